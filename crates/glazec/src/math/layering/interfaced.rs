//! glazec's interfaced layering, coat by coat from the top (see the [module essay](super)): the
//! coat's lobe, transmission and absorption, the level below, and the series of internal
//! reflections between them, started from what the first pass out of the level below returns.

use std::cell::OnceCell;

use super::base::{base_brdf, body_albedo, conductor_alpha};
use super::geometry::{Geometry, level_name};
use super::glossy::glossy_level;
use super::inputs::{Body, Depth, Inputs, Stack};
use super::interface::{CoatInterface, interfaced_lobe};
use super::level::{Albedo, Level, Split};
use super::trapped::{trapped, trapped_shares};
use crate::math::tables::{self, TableId};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};
use crate::model::{Color, Lobe, Scalar};

/// The interfaced method from depth `at` down, at the directions `g` of that level; the level's
/// albedos too when `want_albedo`.
pub(super) fn interfaced<F: Real>(stack: &Stack<'_, F>, g: &Geometry<F>, at: Depth<F>, want_albedo: bool) -> Level<F> {
    let Stack { coats, body, inputs, approx } = *stack;
    let Depth { k, n_medium, blur, spread, incidence } = at;
    let Some(coat) = coats.get(k) else {
        // A body's lobe takes the whole blur (`Blur::total`), summed once.
        let blur = blur.total();
        let f = if g.albedo_only {
            inputs.zero()
        } else {
            base_brdf(body, inputs, g, n_medium, blur).named(&level_name("f_base", g.level))
        };
        let albedo = want_albedo.then(|| body_albedo(body, inputs, g, n_medium, blur, incidence));
        let alpha = match body {
            Body::Conductor(roughness, _) => Some(conductor_alpha(inputs.scalar(*roughness), blur, g.level)),
            _ => None,
        };
        return Level { f, albedo, glossy: alpha.is_some(), alpha, boost: inputs.lit(1.0), transmission: None };
    };
    // A conductor directly under this coat: the glossy level.
    if let (None, Body::Conductor(roughness, fresnel)) = (coats.get(k + 1), body) {
        return glossy_level(stack, (*roughness, *fresnel), g, at, want_albedo);
    }
    let name = |base| level_name(base, k);
    let eta = inputs.scalar(coat.ior);
    let tau = inputs.optical_depth(coat).named(&name("tau"));
    let interface = CoatInterface::new(&coat.lobe, eta, inputs, k, approx);
    let f_top = if g.albedo_only {
        inputs.zero()
    } else {
        interface.scaled_lobe(interfaced_lobe(&coat.lobe, eta, inputs, g, approx, blur), g).named(&name("specular"))
    };
    let (t_l, t_v) =
        g.sides(|| interface.transmission(g.raw_n_dot_l, "l"), || interface.transmission(g.raw_n_dot_v, "v"));
    let below = g.refracted(eta);
    // The spread of the light under this coat, which only coats further down ask for: its own
    // and that of the rough coats above, added as independent spreads (in quadrature: their
    // variances add, as in `CoatInterface::path_cosine_spread`).
    let spread_below = match (spread, coats.get(k + 1).and_then(|_| interface.p_spread(n_medium))) {
        (Some(above), Some(own)) => Some((above.sq() + own.sq()).sqrt()),
        (above, own) => above.or(own),
    };
    // The coat's own path cosines towards l and v (`CoatInterface::path_cosine`), built once when
    // first asked for: the slab's absorption takes them (without rough coats above) and so does
    // an Oren–Nayar body right under the coat.
    let own_paths = OnceCell::new();
    let own_path = || {
        *own_paths.get_or_init(|| {
            g.sides(
                || interface.path_cosine(g.raw_n_dot_l, below.n_dot_l, "l"),
                || interface.path_cosine(g.raw_n_dot_v, below.n_dot_v, "v"),
            )
        })
    };
    // A clear slab (τ = 0) transmits everything: e^0 = 1, so the calls are skipped.
    let (a_l, a_v) = if tau.is_known_zero() {
        (inputs.lit(1.0).splat(), inputs.lit(1.0).splat())
    } else {
        let (path_l, path_v) = match (spread, n_medium) {
            (Some(above), Some(n_above)) => g.sides(
                || interface.path_cosine_spread(g.raw_n_dot_l, below.n_dot_l, n_above, above, "l"),
                || interface.path_cosine_spread(g.raw_n_dot_v, below.n_dot_v, n_above, above, "v"),
            ),
            _ => own_path(),
        };
        g.sides(|| absorbed(tau, path_l).named(&name("absorb_l")), || absorbed(tau, path_v).named(&name("absorb_v")))
    };
    // An Oren–Nayar body right under this coat: the cosines its directional albedo is taken at.
    let incidence = match (coats.get(k + 1), body) {
        (None, Body::OrenNayar(..)) => Some(own_path()),
        _ => None,
    };
    // The blur at the directions is built only for the lobe of a rough coat further down.
    let rough_below = coats[k + 1..].iter().any(|c| !matches!(c.lobe, Lobe::Smooth));
    let deeper = Depth {
        k: k + 1,
        n_medium: Some(n_medium.map_or(eta, |n| n * eta)),
        blur: interface.blur_below(
            blur,
            k,
            rough_below.then_some(((g.n_dot_l, below.n_dot_l), (g.n_dot_v, below.n_dot_v))),
        ),
        spread: spread_below,
        incidence,
    };
    let lower = interfaced(stack, &below, deeper, true);
    let albedo = lower.albedo.unwrap_or_else(|| Albedo {
        e_l: inputs.zero(),
        e_v: inputs.zero(),
        mean: inputs.zero(),
        split: None,
    });
    let (r_return, e_escape) = interface.slab(tau);
    // The clear slab's (R(0), E_esc(0)), built when first needed.
    let clear = OnceCell::new();
    let clear = || *clear.get_or_init(|| interface.slab(inputs.zero()));
    let first = (!lower.glossy).then(|| match (coats.get(k + 1), body) {
        (None, Body::Eon(rho, r)) => eon_first_pass(&interface, (*rho, *r), g, &below, &clear, inputs),
        _ => first_pass(stack, k, &interface, &lower, &albedo, (&below, (t_l, t_v)), &clear),
    });
    let boost = first.as_ref().map_or(inputs.lit(1.0), |p| p.boost);
    // The albedo for the light this coat returns, less what the layer's top interface sends
    // straight back (none for a body directly under the coat). Guard: R(0) ≥ 10⁻⁴.
    let returned = match &first {
        Some(FirstPass { recirculated: Some(s), .. }) => {
            let again = r_return / clear().0.x().at_least(1e-4);
            returned_albedo(albedo.mean, *s, again).named(&name("rho_returned"))
        }
        _ => albedo.mean,
    };
    // The coat's return and escape as the series over a coated layer takes them: scaled for the
    // obliquity of the light through the absorbing slabs below (`selected_absorption`).
    let (r_series, e_series) = match &first {
        Some(FirstPass { recirculated: Some(_), .. }) => {
            let below: Vec<(F, F::Vec)> =
                coats[k + 1..].iter().map(|c| (inputs.scalar(c.ior), inputs.optical_depth(c))).collect();
            if below.iter().all(|(_, tau)| tau.is_known_zero()) {
                (r_return, e_escape)
            } else {
                let (c_r, c_e) = selected_absorption(eta, &below, &|base| level_name(base, k));
                ((r_return * c_r).named(&name("r_series")), (e_escape * c_e).named(&name("e_series")))
            }
        }
        _ => (r_return, e_escape),
    };
    // Over a glossy body: the light of its reflections towards l and v that leaves the escape
    // cone, trapped (none without total internal reflection, η ≤ 1), and what becomes of it.
    let trapped_at = match (lower.glossy, lower.alpha) {
        (true, Some(alpha)) => {
            Some((alpha, trapped_shares(&interface, &below, (alpha, &albedo), (r_return, clear().0), inputs)))
        }
        _ => None,
    };
    let f_under: F::Vec = if g.albedo_only {
        inputs.zero()
    } else if let Some((alpha, shares)) = &trapped_at {
        let k_l = (a_l * a_l * t_l.one_minus()).named(&name("inner_l"));
        let k_v = (a_v * a_v * t_v.one_minus()).named(&name("inner_v"));
        // Only what the body keeps inside the escape cone comes back up to the coat; what it
        // sends beyond is the trapped lobe's.
        let (kept_l, kept_v) = (shares.near_l + shares.spread_l, shares.near_v + shares.spread_v);
        let glossy = interfaced_glossy_under::<F>(lower.f, kept_l, k_l, kept_v, k_v);
        glossy + trapped(&interface, g, &below, &albedo, *alpha, shares, inputs).named(&name("trapped"))
    } else if let Some(first) = &first {
        // The series starts from what the first pass returns, E·c (c = 1 for a diffusing body),
        // and on the viewer's side is divided by the return factor of diffuse light through the
        // escape cone, so that what returns eventually escapes (reciprocal: symmetric in l, v).
        let e_v = albedo.e_v * first.return_v / first.return_mean.max(first.return_l.min(first.return_v));
        interfaced_diffuse_under::<F>(lower.f, albedo.e_l * first.return_l, e_v, returned, r_series)
    } else {
        unreachable!("a layer that is not glossy has its first pass")
    };
    let f = if g.albedo_only {
        inputs.zero()
    } else {
        interfaced_layer(f_top, t_l, t_v, a_l, a_v, f_under.named(&name("under")), eta).named(&name("f"))
    };
    let albedo = want_albedo.then(|| {
        let (first_l, first_v) = first.as_ref().map(|p| ((p.escape_l, p.return_l), (p.escape_v, p.return_v))).unzip();
        let e_escape_clear = clear().1.x();
        let mean =
            interfaced_albedo(eta, e_escape_clear, e_series, r_series, albedo.mean, returned).named(&name("rho"));
        let Some((_, shares)) = &trapped_at else {
            let directional = |t: F, a: F::Vec, e: F::Vec, (escape, back): (F::Vec, F::Vec)| {
                interfaced_albedo_dir(t, a, e, returned, r_series, e_series, escape, back)
            };
            let (Some(first_l), Some(first_v)) = (first_l, first_v) else {
                unreachable!("a layer that is not glossy has its first pass")
            };
            let (e_l, e_v) = g.sides(
                || directional(t_l, a_l, albedo.e_l, first_l).named(&name("albedo_l")),
                || directional(t_v, a_v, albedo.e_v, first_v).named(&name("albedo_v")),
            );
            return Albedo { e_l, e_v, mean, split: None };
        };
        // Over a glossy body: of what it keeps inside the escape cone, what leaves with T, and
        // of what it traps, what leaves after all (`trapped_return`).
        let t_cone = interface.transmission_from_cone();
        let out = trapped_return(shares.round_trip, albedo.mean, shares.q, t_cone).named(&name("trapped_out"));
        let directional = |t: F, a: F::Vec, (near, spread, trapped): (F::Vec, F::Vec, F::Vec)| {
            interfaced_albedo_glossy::<F>(t, t_cone, a, near, spread, trapped, out)
        };
        let side_l = (shares.near_l, shares.spread_l, shares.trapped_l);
        let side_v = (shares.near_v, shares.spread_v, shares.trapped_v);
        let (e_l, e_v) = g.sides(
            || directional(t_l, a_l, side_l).named(&name("albedo_l")),
            || directional(t_v, a_v, side_v).named(&name("albedo_v")),
        );
        // Under a coat, this level's light splits as the glossy level's does: this coat's own
        // reflection, what leaves near the mirror direction, and the rest (the trapped light
        // let out, and the spread light kept in the cone).
        let split = n_medium.is_some().then(|| {
            let part = |t: F, a: F::Vec, (near, spread, trapped): (F::Vec, F::Vec, F::Vec)| {
                let through = |leaving: F::Vec| a * a * interfaced_glossy_bounced(t, a, near + spread, leaving) * t;
                let lobe = through(near * t);
                let spread = through(spread * t_cone + trapped * out);
                Split { specular: t.one_minus(), alpha: interface.ggx_lobe_alpha(), lobe, spread }
            };
            (part(t_l, a_l, side_l), part(t_v, a_v, side_v))
        });
        Albedo { e_l, e_v, mean, split }
    });
    Level { f, albedo, glossy: lower.glossy, alpha: lower.alpha, boost, transmission: Some((t_l, t_v)) }
}

/// How the first reflection off the layer under coat `k` differs from a diffusing body's, per
/// light and view direction: `escape_*` scales the share of it that leaves through the coat at
/// once, `return_*` the share the coat sends back down (both 1 for a diffusing body, whose light
/// leaves the way [`interfaced_diffuse_under`]'s series assumes).
struct FirstPass<F: Real> {
    pub(super) escape_l: F::Vec,
    pub(super) escape_v: F::Vec,
    pub(super) return_l: F::Vec,
    pub(super) return_v: F::Vec,
    /// The return factor of diffuse light seen through the escape cone (at its mean cosine,
    /// with the layer's mean albedo); ≥ 10⁻³.
    pub(super) return_mean: F::Vec,
    /// S: the share of the light this coat returns that the layer's top interface reflects
    /// back (`returned_albedo`); none for a body directly under the coat.
    pub(super) recirculated: Option<F>,
    /// T′(μ̄c)/⟨T′⟩ times the layer's own boost: how concentrated towards the normal the light
    /// leaving this coat's level is (handed to the coat above).
    pub(super) boost: F,
}

/// glazec's interfaced layering, the first pass out of a coated layer. A coated layer below (coat
/// `k + 1` over something) reflects part of the light specularly (1 − T′(μ′), which leaves
/// through coat `k` with its transmission T(μ); of a rough GGX coat's lobe only the share C inside
/// coat `k`'s escape cone, `CoatInterface::cone_share`, leaves) and sends the rest up through coat `k + 1` with a
/// distribution ∝ T′(w) — concentrated towards the normal, so more of it escapes coat `k` than of
/// diffuse light: the share Y ≈ E_esc(0)·b, b = T′(μ̄c)/⟨T′⟩ times the same factor of the coats
/// further down, μ̄c the mean cosine of coat `k`'s escape cone. The first pass then escapes
/// ξ = [(1 − T′)C T + (E − (1 − T′))Y]/E and returns 1 − ξ, against E_esc(0) and R(0) = 1 − E_esc(0)
/// for diffuse light. Treating that light as diffuse would count part of it twice (energy gains
/// of up to 16% for sixteen coats; docs/stability.md, "What keeps the default method stable");
/// compounding b down the stack over-corrects deep stacks instead (a white stack of sixteen coats
/// reflects 0.47–0.76).
/// Guards: the return factor is clamped to [0, 1] (never more than a diffusing body returns),
/// ξ to [0, 1], E ≥ 10⁻⁶, R(0) ≥ 10⁻⁴, E_esc(0) ≥ 10⁻⁴.
fn first_pass<F: Real>(
    stack: &Stack<'_, F>,
    k: usize,
    interface: &CoatInterface<'_, F>,
    lower_level: &Level<F>,
    albedo: &Albedo<F>,
    // The directions under coat `k`, and its transmissions towards l and v.
    (below, (t_l, t_v)): (&Geometry<F>, (F, F)),
    clear: &dyn Fn() -> (F::Vec, F::Vec),
) -> FirstPass<F> {
    let Stack { coats, inputs, .. } = *stack;
    let one = inputs.lit(1.0).splat();
    let (Some(next), Some((t_below_l, t_below_v))) = (coats.get(k + 1), lower_level.transmission) else {
        return FirstPass {
            escape_l: one,
            escape_v: one,
            return_l: one,
            return_v: one,
            return_mean: one,
            recirculated: None,
            boost: inputs.lit(1.0),
        };
    };
    let name = |base: &str| level_name(base, k);
    let lower = CoatInterface::new(&next.lobe, inputs.scalar(next.ior), inputs, k + 1, interface.approx);
    let (r_clear, e_clear) = clear();
    let (r_clear, e_clear) = (r_clear.x(), e_clear.x());
    let mu_mean = interface.escape_cone_mean_cosine();
    let t_cone_below = lower.transmission(mu_mean, "cone");
    // Coats further down concentrate the light further (their boost, handed up).
    let t_avg_below = lower.transmission_hemispherical();
    let boost = (t_cone_below / t_avg_below.at_least(1e-4) * lower_level.boost).named(&name("boost"));
    let shaped = (e_clear * boost).clamp(0.0, 1.0).named(&name("first_escape_diffuse"));
    // ξ for light reflected with albedo `e`, of which 1 − T′ (`below_transmission`) specularly
    // about the mirror direction of Snell's cosine `mu`, escaping coat k with transmission `t`
    // there; of a rough GGX coat's lobe only its share inside the escape cone (`cone_share`),
    // the rest returns like the light beyond the cone that it is. (A GTR1 coat's lobe leaves
    // whole: with the GGX α of its median slope, r, `four mixed`'s body p90 rose from 6.8% to
    // 9.1%; its long tails' light is not where a GGX lobe's is.)
    let lobe_alpha = lower.ggx_lobe_alpha();
    let shares = |e: F::Vec, below_transmission: F, t: F, mu: F, side: &str| {
        let specular = below_transmission.one_minus();
        let leaving = match lobe_alpha {
            Some(alpha) => {
                let kept = interface.cone_share(mu, alpha).named(&name(&format!("first_cone_share_{side}")));
                specular * kept
            }
            None => specular,
        };
        let e_safe = e.max(inputs.lit(1e-6).splat());
        let escaped = (leaving * t).splat() + (e - specular.splat()).max(inputs.zero()) * shaped;
        let xi = (escaped / e_safe).max(inputs.zero()).min(one);
        let escape = (xi / e_clear.at_least(1e-4)).named(&name(&format!("first_escape_{side}")));
        let back = first_return(xi, r_clear, inputs).named(&name(&format!("first_return_{side}")));
        (escape, back)
    };
    let ((escape_l, return_l), (escape_v, return_v)) = below.sides(
        || shares(albedo.e_l, t_below_l, t_l, below.n_dot_l, "l"),
        || shares(albedo.e_v, t_below_v, t_v, below.n_dot_v, "v"),
    );
    // At the cone's mean cosine.
    let (_, return_mean) = shares(albedo.mean, t_cone_below, interface.transmission_from_cone(), mu_mean, "cone");
    let return_mean = return_mean.max(inputs.lit(1e-3).splat());
    // S = 1 − ⟨T′⟩ of the coat below; for a coat optically thinner than this one (η′ < 1) only
    // over the directions it accepts, ⟨T′⟩/η′² (light beyond them never reaches this coat from
    // below, so this coat returns none there).
    let accepted = lower.eta.sq().min(inputs.lit(1.0));
    let recirculated = (t_avg_below / accepted).one_minus().clamp(0.0, 1.0);
    let recirculated = Some(recirculated.named(&name("recirculated")));
    FirstPass { escape_l, escape_v, return_l, return_v, return_mean, recirculated, boost }
}

/// The first pass out of an EON body (Portsmouth et al. 2025) under coat `k`. EON's
/// multiple-scattering lobe sends light in proportion to 1 − E_FON(μₒ), which is largest
/// towards the normal, so more of the first reflection leaves through the escape cone than of
/// diffuse light (treated as diffuse, a water-coated EON comes out 0.011 too bright at normal
/// incidence; docs/accuracy.md, "EON under a coat"). Of the body's albedo
/// E(μ) = ρE_FON(μ) + ρ_ms(1 − E_FON(μ)), the FON part is taken to leave like diffuse light and
/// the multiple-scattering part with the cone's weight for its shape, `eon_escape_shape_exact` s
/// (of the smooth interface, tabulated over η; for a rough coat an approximation): escape factor
/// x(μ) = 1 + ρ_ms(1 − E_FON(μ))(s − 1)/E(μ), return factor (1 − x E_esc(0))/R(0) clamped to
/// [0, 1] (R(0) = 1 − E_esc(0): a white body still returns everything, E = 1). The return factor
/// at the cone's mean cosine normalises the viewer's side as in [`first_pass`]. Guards:
/// E ≥ 10⁻⁶, R(0) ≥ 10⁻⁴, the return at the mean ≥ 10⁻³.
fn eon_first_pass<F: Real>(
    interface: &CoatInterface<'_, F>,
    (albedo_color, roughness): (Color, Scalar),
    above: &Geometry<F>,
    below: &Geometry<F>,
    clear: &dyn Fn() -> (F::Vec, F::Vec),
    inputs: &Inputs<F>,
) -> FirstPass<F> {
    let name = |base: &str| level_name(base, below.level);
    let (rho, r) = (inputs.color(albedo_color), inputs.scalar(roughness));
    let (r_clear, e_clear) = clear();
    let (r_clear, e_clear) = (r_clear.x(), e_clear.x());
    let one = inputs.lit(1.0).splat();
    let shape = tables::lookup(TableId::EonEscapeShape, &[interface.eta]).named(&name("eon_escape_shape"));
    let rho_ms = eon_rho_ms(rho, r).named(&name("rho_ms"));
    let factors = |mu: F, side: &str| {
        let e = albedo_eon(rho, r, mu);
        let spread = rho_ms * e_fon(mu, r).one_minus();
        let escape = (one + spread * (shape - 1.0) / e.max(inputs.lit(1e-6).splat()))
            .named(&name(&format!("first_escape_{side}")));
        let back = first_return(escape * e_clear, r_clear, inputs).named(&name(&format!("first_return_{side}")));
        (escape, back)
    };
    // A rough coat spreads the refracted light: its effective cosine (the path factor's) stands
    // for the direction of incidence on the body. (The spread of rough coats further up,
    // `CoatInterface::path_cosine_spread`, changed `four_layer`'s bands by 0.1 point at most
    // here, for two more curves per direction: left out.)
    let ((escape_l, return_l), (escape_v, return_v)) = above.sides(
        || factors(interface.path_cosine(above.raw_n_dot_l, below.n_dot_l, "l"), "l"),
        || factors(interface.path_cosine(above.raw_n_dot_v, below.n_dot_v, "v"), "v"),
    );
    let mu_mean = interface.escape_cone_mean_cosine();
    let (_, return_mean) = factors(mu_mean, "cone");
    let return_mean = return_mean.max(inputs.lit(1e-3).splat());
    FirstPass { escape_l, escape_v, return_l, return_v, return_mean, recirculated: None, boost: inputs.lit(1.0) }
}

/// The return factor of a first pass (see [`FirstPass`]): the share 1 − ξ of the first
/// reflection that does not escape, against the clear slab's R(0), clamped to [0, 1] (never more
/// than a diffusing body returns). Guard: R(0) ≥ 10⁻⁴.
fn first_return<F: Real>(escaped: F::Vec, r_clear: F, inputs: &Inputs<F>) -> F::Vec {
    let one = inputs.lit(1.0).splat();
    ((one - escaped) / r_clear.at_least(1e-4)).max(inputs.zero()).min(one)
}
