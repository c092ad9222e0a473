//! Light a glossy body sends outside a coat's escape cone: total internal reflection traps it
//! between body and coat until the body scatters it back into the cone. Used where a glossy
//! body is not directly under its coat's glossy level (`interfaced`).

use super::geometry::{Geometry, level_name};
use super::inputs::Inputs;
use super::interface::CoatInterface;
use super::level::{Albedo, Split};
use crate::math::tables::{self, TableId};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};

/// What a glossy body under a coat sends outside the coat's escape cone, at the directions
/// `below` (under the coat): the light of its reflections towards l and v that is trapped, and
/// what becomes of trapped light.
#[derive(Clone, Copy)]
pub(super) struct Trapped<F: Real> {
    /// μc, the escape cone's cosine inside (0 without total internal reflection).
    pub(super) mu_c: F,
    /// P: the light of the body's directional albedos towards l and v that leaves the cone.
    pub(super) trapped_l: F::Vec,
    pub(super) trapped_v: F::Vec,
    /// What stays inside the cone, towards l and v, in two parts: near the mirror direction (the
    /// body's coat's reflection and its lobe) and spread over the cone. Each is a sum of
    /// non-negative terms, not the albedo less what is trapped: where nearly all of a dark
    /// channel is trapped that difference lost its digits in f32 (a random stack's blue at
    /// 10⁻¹¹ differed by 2·10⁻⁴ between the CPU and lavapipe).
    pub(super) near_l: F::Vec,
    pub(super) near_v: F::Vec,
    pub(super) spread_l: F::Vec,
    pub(super) spread_v: F::Vec,
    /// The slab's round trip for trapped light, R(τ)/R(0).
    pub(super) round_trip: F::Vec,
    /// q, the share of trapped light the body sends into the cone at each bounce.
    pub(super) q: F,
}

/// The light the glossy body of GGX α and albedos `albedo` under `interface` sends beyond the
/// escape cone (see [`Trapped`]); `r_clear` is the clear slab's return R(0). Each part of the
/// body's reflection (`Albedo::split`) is trapped by its own share: of its coat's GGX lobe
/// `glossy_trapped_share` (a mirror's stays in the cone), of the conductor's lobe
/// `trapped_share`, and of the light spread like diffuse light the share of projected solid
/// angle beyond the cone, μc². Without the split all of the albedo counts as the lobe, which
/// had let a coat over a coated conductor state 4–22% more albedo than the reference and its f
/// lose what the body's coat and remainder send beyond the cone (docs/accuracy.md, "The stated
/// albedo against the reference").
pub(super) fn trapped_shares<F: Real>(
    interface: &CoatInterface<'_, F>,
    below: &Geometry<F>,
    (alpha, albedo): (F, &Albedo<F>),
    (r_return, r_clear): (F::Vec, F::Vec),
    inputs: &Inputs<F>,
) -> Trapped<F> {
    let name = |base: &str| level_name(base, below.level);
    let mu_c = escape_cone_cosine(interface.eta).named(&name("mu_c"));
    let side = |mu: F, e: F::Vec, split: Option<Split<F>>, s: &str| {
        // Without total internal reflection (μc = 0) nothing is trapped; `trapped_share` alone
        // would give the lobe's share below the horizon there.
        let p = trapped_share(mu, mu_c, alpha);
        let p = F::select(mu_c.gt_lit(0.0), p, inputs.lit(0.0)).named(&name(&format!("trapped_share_{s}")));
        match split {
            Some(Split { specular, alpha: specular_alpha, lobe, spread }) => {
                let (specular_trapped, specular_kept) = match specular_alpha {
                    Some(a) => {
                        let share = glossy_trapped_share(mu, mu_c, a);
                        (specular * share, specular * share.one_minus())
                    }
                    None => (inputs.lit(0.0), specular),
                };
                let trapped = lobe * p + spread * mu_c.sq() + specular_trapped.splat();
                let near = lobe * p.one_minus() + specular_kept.splat();
                let spread = spread * mu_c.sq().one_minus();
                (
                    trapped.named(&name(&format!("trapped_{s}"))),
                    near.named(&name(&format!("near_{s}"))),
                    spread.named(&name(&format!("spread_kept_{s}"))),
                )
            }
            None => ((e * p).named(&name(&format!("trapped_{s}"))), e * p.one_minus(), inputs.zero()),
        }
    };
    let (split_l, split_v) = albedo.split.unzip();
    let ((trapped_l, near_l, spread_l), (trapped_v, near_v, spread_v)) =
        below.sides(|| side(below.n_dot_l, albedo.e_l, split_l, "l"), || side(below.n_dot_v, albedo.e_v, split_v, "v"));
    // The round trip of trapped light: R(τ)/R(0), the absorption of the slab's diffuse return.
    let round_trip = r_return / r_clear.max(inputs.lit(1e-4).splat());
    let q = trapped_escape(mu_c, alpha).named(&name("trapped_escape"));
    Trapped { mu_c, trapped_l, trapped_v, near_l, near_v, spread_l, spread_v, round_trip, q }
}

/// The light a glossy body of GGX α under a coat sends outside the escape cone (`trapped_lobe`,
/// from its `shares`, [`trapped_shares`]), spread over the azimuth about the forward direction
/// like the glossy level's own remainder (`forward_azimuth_weight`, κ from `glossy_spread` at
/// the body's α and the coat's IOR and roughness, a GTR1 coat's equivalent one as the level
/// looks it up (`CoatInterface::glossy_roughness`): total internal reflection and a glossy
/// reflection both keep the light going on) and tilted per channel like it
/// (`forward_azimuth_tilt`); `above` the directions above the coat.
pub(super) fn trapped<F: Real>(
    interface: &CoatInterface<'_, F>,
    above: &Geometry<F>,
    below: &Geometry<F>,
    albedo: &Albedo<F>,
    alpha: F,
    shares: &Trapped<F>,
    inputs: &Inputs<F>,
) -> F::Vec {
    let eta = interface.eta;
    let Trapped { mu_c, trapped_l, trapped_v, round_trip, q, .. } = *shares;
    let lobe = trapped_lobe(trapped_l, trapped_v, mu_c, round_trip, albedo.mean, q);
    let roughness = interface.glossy_roughness().unwrap_or(inputs.lit(0.0));
    let kappa = |mu: F| tables::lookup(TableId::GlossySpread, &[mu, alpha.sqrt(), roughness, eta]);
    // Over the event counts this lobe assumes: a geometric count of retention 1 − q.
    let none = inputs.lit(0.0);
    let counts = [none, none, none, q.one_minus()];
    let kappas = (kappa(above.raw_n_dot_l), kappa(above.raw_n_dot_v));
    let lobe = lobe * forward_spread(above, kappas, counts, albedo.mean, ("trapped_", below.level));
    // Without total internal reflection (η ≤ 1) nothing is trapped.
    F::Vec::select(mu_c.gt_lit(0.0), lobe, inputs.zero())
}

/// How light trapped between a coat and a glossy body leaves over the azimuth, at the directions
/// `g` above the coat: the glossy level's remainder and what a coat traps over a coated conductor
/// alike. A reflection off the body and a total internal reflection both keep a direction's
/// horizontal part, so it leaves about the forward direction: the wrapped Cauchy weight W of
/// ρ = √(κ_l κ_v) sin θl sin θv (`forward_azimuth_weight`; κ per side from `glossy_spread`),
/// tilted per channel (`forward_azimuth_tilt`) to the mean resultant length
/// `glossy_spread_colour` gives the event counts `counts` (w₀, w₁, w₂ and the slow retention B_s,
/// as `glossy_later` takes them) under a per-event survival `colour`: light that took few events,
/// which a coloured body darkens least, kept going forward more. Each channel's mean over the
/// azimuth is 1, and it is symmetric in l and v. Guard: ρ ≤ 0.95 (as `forward_azimuth_weight`).
/// Its values are named `<prefix>sines`, `<prefix>spread_rho`, `<prefix>spread_weight` and
/// `<prefix>spread` at `level` in generated code.
pub(super) fn forward_spread<F: Real>(
    g: &Geometry<F>,
    (kappa_l, kappa_v): (F, F),
    [next, quick, steady, slow]: [F; 4],
    colour: F::Vec,
    (prefix, level): (&str, usize),
) -> F::Vec {
    let name = |base: &str| level_name(&format!("{prefix}{base}"), level);
    let sines = forward_sines::<F>(g.n, g.v, g.l).named(&name("sines"));
    let rho = ((kappa_l * kappa_v).at_least(0.0).sqrt() * sines).min(sines.lit(0.95)).named(&name("spread_rho"));
    let rho_c = glossy_spread_colour(rho, next, quick, steady, slow, colour);
    let cos_phi = forward_cosine(g.n, g.v, g.l, sines);
    let weight = forward_azimuth_weight(rho, cos_phi).named(&name("spread_weight"));
    (forward_azimuth_tilt(rho, rho_c, cos_phi) * weight).named(&name("spread"))
}
