//! The glossy level: a conductor directly under a coat, in the interfaced method.
//!
//! Light the conductor reflects under a coat leaves through the coat's escape cone, or is sent
//! back down (total internal reflection beyond the cone, Fresnel reflection inside it) and meets
//! the conductor again; under a smooth coat a glossy conductor may take dozens of events before
//! the light drifts back into the cone. How many events it takes sets the colour (each one
//! multiplies by the conductor's Fresnel factor), and where it leaves sets the shape. The level
//! is split by that count, with statistics `glazec tables` measures by white random walks through
//! the reference's own microsurfaces (`glazec_lab::bake::glossy`):
//!
//! * **near the mirror direction** — a lobe: the conductor's GGX lobe at the refracted
//!   directions, widened by the coat's two crossings (each crossing's σ(μ) along its own plane
//!   of incidence and σ/μ′ across it, `d_ggx_crossed`; Smith's G at α² = α_c² + σ(μᵢ)² + σ(μₒ)²;
//!   σ tabulated: the widening whose peak matches the conductor's peak seen through the coat,
//!   tapered towards grazing) and scaled by s(μᵢ) s(μₒ) (tabulated, solved so that for a white conductor under a
//!   clear coat the lobe reflects exactly T(μ)·(P₁ + (1 − P₁)w₀): the light the walks let out
//!   after one event, and at the second from the trapped light's first return, w₀, which still
//!   leaves near the mirror direction), coloured by √(o(μᵢ) o(μₒ)) (o: that light's colour,
//!   F(μ′) for the first event, F(μ′)·c for the second) and attenuated along the paths that light
//!   really takes (`glossy_path`: its Laplace transform, not e^(−τE[L]), as a factor on the
//!   coat's mean path, `path_cosine`);
//! * **the rest** — a separable lobe M(μᵢ) M(μₒ)/(π⟨M⟩) (Kulla & Conty 2017), spread over the
//!   azimuth by a wrapped Cauchy weight about the forward direction (`forward_azimuth_weight`,
//!   ρ = κ sin θᵢ sin θₒ, κ = √(κ(μᵢ) κ(μₒ)) from `glossy_spread`: a reflection off the
//!   conductor and a total internal reflection both keep a direction's horizontal part, so the
//!   trapped light leaves going on the way it came, not backwards; the weight's mean over the
//!   azimuth is 1, so the lobe's albedo stays M(μₒ)) and tilted further forward per channel
//!   (`forward_azimuth_tilt`, `glossy_spread_colour`: the conductor's colour favours light that
//!   took few events, which has kept going forward more), with
//!   M = T a² F (1 − P₁) Ŷ(c), F the conductor's Fresnel factor at the coat's mean-path cosine
//!   (`path_cosine`: under a rough coat the first event is flatter than Snell's cosine), Ŷ the
//!   generating function of the later events (`glossy_trapped`,
//!   from the walks' event counts, less the second event's share w₀c), c = F(μ*) e^(−2τ/μ*) the
//!   survival of one more event at the trapped light's mean cosine μ*.
//!
//! P₁ is not looked up directly: the level takes it from the lobe's own white albedo,
//! O = s²·K·E(μ′; α)·c(μ′) (`glossy_lobe_albedo` holds K, the analytic GGX albedo E and escape-cone
//! share c carry the steep part), P₁ = (O − w₀)/(1 − w₀), so that the remainder takes T(1 − O),
//! what the lobe does not, even between the nodes where s and P₁ were solved; `glazec tables`
//! fits K where probes of the compiled method still found a gain (or, near grazing, a loss).
//!
//! A white conductor under a clear coat therefore reflects T·O + T(1 − O) = T: all the light
//! the coat lets in (at the nodes; at most that between them). Reciprocal by construction (every factor is symmetric in i and o). The lobe
//! is one GGX evaluation; the coat's own lobe is the other.

use super::base::conductor_fresnel;
use super::geometry::{COS_EPSILON, Geometry, level_name};
use super::inputs::{Depth, Inputs, Stack};
use super::interface::{CoatInterface, interfaced_lobe};
use super::level::{Albedo, Level, Split};
use super::trapped::forward_spread;
use crate::math::Sum;
use crate::math::quadrature::{GAUSS_LEGENDRE_4, gauss_legendre_4_at};
use crate::math::tables::{self, Axis, TableId};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};
use crate::model::{Approximations, Coat, Color, ConductorFresnel, Lobe, Scalar};

/// The smallest outer cosine at which the glossy tables are measured (`glazec tables` evaluates
/// every direction node at μ ≥ this): at grazing incidence itself the light a rough coat lets in
/// (T → 0) takes strange ways, and the share leaving after one event jumps there (0.33 at
/// μ = 10⁻⁴ against 0.25 at μ = 0.02, coat roughness ½); the first node stands for the limit
/// the nodes beside it approach.
pub const GLOSSY_GRAZING: f64 = 0.005;

/// Panels of [`Glossy::hemispherical`]'s quadrature: [0, μ_b] and [μ_b, 1], the wider halved.
const PANELS: u32 = 3;

/// The band of outer cosines [0, μ_b] whose light the conductor sends largely out of the escape
/// cone ends where the refracted mirror direction lies this many GGX α (conductor's plus
/// coat's) inside the cone's edge; the panels' split is kept within
/// [`TRAPPED_BAND_MIN`, 1 − `TRAPPED_BAND_MIN`].
const TRAPPED_BAND_WIDTH: f32 = 2.0;
const TRAPPED_BAND_MIN: f32 = 0.05;

/// The coat directly over a conductor and the conductor, as the glossy level sees them.
struct Glossy<'a, 'i, F: Real> {
    interface: CoatInterface<'i, F>,
    inputs: &'i Inputs<F>,
    /// The coat's relative IOR and its slab's optical depth (RGB).
    eta: F,
    tau: F::Vec,
    /// The conductor's roughness r_c (α = r_c²) and Fresnel, and the absolute IOR of the medium
    /// it sits in.
    conductor_roughness: F,
    fresnel: &'a ConductorFresnel,
    n_medium: Option<F>,
    /// The coat's roughness (0 for a smooth coat).
    roughness: F,
    level: usize,
    /// [`Glossy::roughness_nodes`], worked out on first use.
    roughness_span: std::cell::OnceCell<Option<(usize, usize)>>,
}

/// What the level needs to know about one direction (at outer cosine μ).
#[derive(Clone)]
struct Side<F: Real> {
    transmission: F,
    /// Attenuation along the mean refracted path (diffuse light's, `CoatInterface::path_cosine`)
    /// and along the paths of light that leaves after one event.
    absorb: F::Vec,
    absorb_lobe: F::Vec,
    /// The conductor's Fresnel factor at the first event of the light that does not leave at
    /// once (at the coat's mean-path cosine).
    fresnel: F::Vec,
    single: F,
    /// The lobe's scale s(μ).
    scale: F,
    /// What leaves near the mirror direction (`glossy_once`), and its share of what would for a
    /// white conductor under a clear coat (the lobe's scale is solved for that).
    once: F::Vec,
    once_colour: F::Vec,
    /// What the trapped light's events after the second return (`glossy_later`).
    later: F::Vec,
    /// The weights of `glossy_later`'s event counts from this side: the share that leaves at the
    /// second event (w₀) and the quick and steady geometric counts'; and the slow count's
    /// retention B_s, the pool's (the same from either side).
    next: F,
    quick: F,
    steady: F,
    slow: F,
}

/// A per-direction quantity of the level, as [`Glossy::hemispherical`] averages it.
type PerSide<F> = fn(&Side<F>) -> <F as Real>::Vec;

impl<'a, 'i, F: Real> Glossy<'a, 'i, F> {
    fn name(&self, base: &str) -> String {
        level_name(base, self.level)
    }

    /// The table arguments after the direction: (r_c, r, η).
    fn lookup(&self, id: TableId, mu: F) -> F {
        tables::lookup(id, &[mu, self.conductor_roughness, self.roughness, self.eta])
    }

    fn pool_lookup(&self, id: TableId) -> F {
        tables::lookup(id, &[self.conductor_roughness, self.roughness, self.eta])
    }

    /// σ(μ): how much the coat widens the conductor's lobe from this side (0 when smooth).
    fn blur(&self, mu: F, side: &str) -> Option<F> {
        self.interface.roughness?;
        Some((self.lookup(TableId::GlossyBlur, mu) * self.roughness.sq()).named(&self.name(&format!("blur_{side}"))))
    }

    /// The crossings' blurs (σ(μ_l), σ(μ_v)) at outer cosines; `None` under a smooth coat.
    fn blurs(&self, mu_l: F, mu_v: F) -> Option<(F, F)> {
        Some((self.blur(mu_l, "l")?, self.blur(mu_v, "v")?))
    }

    /// The lobe's α: α² = α_c² + σ_l² + σ_v², plus (linearly) the blur of rough coats above.
    fn alpha(&self, mu_l: F, mu_v: F, blur_above: Option<F>) -> F {
        self.widened_alpha(self.blurs(mu_l, mu_v), blur_above)
    }

    /// [`Self::alpha`] from the crossings' blurs.
    fn widened_alpha(&self, blurs: Option<(F, F)>, blur_above: Option<F>) -> F {
        let alpha_c = self.conductor_roughness.sq();
        let widened = match blurs {
            Some((l, v)) => (alpha_c.sq() + l.sq() + v.sq()).sqrt(),
            None => alpha_c,
        };
        match blur_above {
            Some(b) => (widened + b).named(&self.name("alpha")),
            None => widened.named(&self.name("alpha")),
        }
    }

    /// The lobe's distribution at the directions `below` the coat: the conductor's GGX
    /// (α_c, plus the blur of rough coats above) with each crossing's blur σ spread along its
    /// own direction's plane of incidence and σ²/μ′² across it (`d_ggx_crossed`). A GGX
    /// reflection is μ′ times as wide across its plane as along it, and an isotropic blur of
    /// α² = α_c² + σ_l² + σ_v² (what `alpha` gives Smith's G and the levels above) made the
    /// lobe under a rough coat too narrow across and too high: copper under an η 1.33, r ½ coat
    /// peaked 20% above the reference, 6% with this (docs/accuracy.md, "rough coats (r 0.5)").
    /// Under a smooth coat there is no crossing blur and it is `d_ggx` at `alpha`.
    fn distribution(&self, below: &Geometry<F>, blurs: Option<(F, F)>, alpha: F, blur_above: Option<F>) -> F {
        let half = below.half();
        let name = self.name("d");
        let Some((sigma_l, sigma_v)) = blurs else {
            return d_ggx(half.n_dot_h, half.sin2_h, alpha).named(&name);
        };
        let alpha_c = self.conductor_roughness.sq();
        let base = match blur_above {
            Some(b) => (alpha_c + b).sq(),
            None => alpha_c.sq(),
        };
        let names = (self.name("across_l"), self.name("across_v"));
        below.d_ggx_crossed(base, (sigma_l.sq(), sigma_v.sq()), (&names.0, &names.1)).named(&name)
    }

    /// Attenuation of light that leaves after one event, per crossing: e^(−τ q/μ_eff), μ_eff the
    /// cosine along which the coat's transmitted light is absorbed (`path_cosine`: Snell's
    /// cosine shortened by the coat's mean path factor) and q the one-event light's factor on it.
    fn lobe_absorption(&self, mu: F, path_cosine: F, side: &str) -> F::Vec {
        let tau = self.tau;
        if tau.is_known_zero() {
            return self.inputs.lit(1.0).splat();
        }
        let name = self.name(&format!("absorb_lobe_{side}"));
        if self.interface.roughness.is_none() {
            return absorbed(tau, path_cosine).named(&name);
        }
        let q = |t: F| tables::lookup(TableId::GlossyPath, &[mu, t, self.roughness, self.eta]);
        let paths = F::vec3(q(tau.x()), q(tau.y()), q(tau.z()));
        slab_transmittance(tau * paths, path_cosine).named(&name)
    }

    /// Everything about one direction at outer cosine `mu` (Snell's cosine `mu_refracted`).
    fn side(&self, mu: F, mu_refracted: F, c: F::Vec, side: &str) -> Side<F> {
        let name = |base: &str| self.name(&format!("{base}_{side}"));
        let transmission = self.interface.transmission(mu, side);
        let path_cosine = self.interface.path_cosine(mu, mu_refracted, side);
        let (absorb, absorb_lobe) = if self.tau.is_known_zero() {
            (self.inputs.lit(1.0).splat(), self.inputs.lit(1.0).splat())
        } else {
            let absorb = absorbed(self.tau, path_cosine).named(&name("absorb"));
            (absorb, self.lobe_absorption(mu, path_cosine, side))
        };
        // The conductor's Fresnel factor at the first event of the light that does not leave at
        // once, taken at the coat's mean-path cosine rather than Snell's: under a rough coat that
        // light meets the conductor at flatter angles (white walks under an η 1.5, r ½ coat at
        // 85°: mean cosine 0.526 at the first event, Snell's 0.748), where a conductor reflects
        // more; at Snell's cosine copper under that coat would be 0.0117 too dark in green at
        // 85°, against 0.0033 with this. The lobe itself takes its Fresnel per microfacet
        // (`conductor_lobe`).
        let fresnel =
            conductor_fresnel(self.fresnel, self.inputs, path_cosine, self.n_medium).named(&name("fresnel_cond"));
        let scale = self.lookup(TableId::GlossyScale, mu).named(&name("scale"));
        let next = self.lookup(TableId::GlossyNext, mu).named(&name("next"));
        // The lobe's own white albedo over T, O = s² K E c (`glossy_lobe_albedo`), which sets
        // the share P₁ = (O − w₀)/(1 − w₀) that leaves after one event: the remainder then takes
        // exactly T(1 − O), what the lobe does not.
        let lobe_albedo =
            (scale.sq() * self.lookup(TableId::GlossyLobeAlbedo, mu) * self.normaliser(mu, mu_refracted, side))
                .clamp(0.0, 1.0)
                .named(&name("lobe_albedo"));
        // Guard: 1 − w₀ ≥ 10⁻⁶ (all trapped light leaving at the second event: P₁ is then moot).
        let single = ((lobe_albedo - next) / next.one_minus().at_least(1e-6)).clamp(0.0, 1.0).named(&name("single"));
        let quick = self.lookup(TableId::GlossyQuick, mu);
        let steady = self.lookup(TableId::GlossySteady, mu);
        let slow = self.pool_lookup(TableId::GlossySlowRetention);
        let later = glossy_later(next, quick, steady, slow, c).named(&name("later"));
        let once = glossy_once(single, next, c).named(&name("once"));
        // Guard: the white share ≥ 10⁻⁶ (P₁ = 0 and w₀ = 0 leave no lobe to colour).
        let white = glossy_once(single, next, self.inputs.lit(1.0).splat()).x().at_least(1e-6);
        let once_colour = (once / white).named(&name("once_colour"));
        Side {
            transmission,
            absorb,
            absorb_lobe,
            fresnel,
            single,
            scale,
            once,
            once_colour,
            later,
            next,
            quick,
            steady,
            slow,
        }
    }

    /// E(μ′; α)·c(μ′): the white single-scattering GGX albedo at the lobe's α seen from μ (its
    /// mirror configuration: α² = α_c² + 2σ(μ)², `ggx_albedo`) times the share of that same
    /// lobe inside the escape cone (`cone_share`): what carries the lobe's albedo's steep
    /// dependence on α_c, μ and η, so that `glossy_lobe_albedo` need not. The share is the
    /// widened lobe's, the one the level evaluates: with the conductor's own α_c it would fall by
    /// a quarter from r_c 0.18 to 0.33 under an r 0.5 coat while the lobe's albedo falls by 8%,
    /// and K, interpolated between the two, would miss the lobe's albedo (times T) by up to 0.19
    /// between the nodes, against 0.034 with the widened lobe's share (midpoints of every cell
    /// edge with η ≥ 1.22).
    ///
    /// Guard: μ ≥ [`GLOSSY_GRAZING`], where the table's first direction node was measured. Closer
    /// to grazing the refracted mirror direction of a sharp conductor runs into the escape
    /// cone's edge and c(μ′) falls steeply to ½, while the lobe, scaled by s(μ) held from that
    /// node, does not: K·E·c would then promise the remainder more than the lobe takes (a white
    /// conductor of roughness 10⁻⁴ under an r 0.2 coat would reflect E = 1.043 at 90°).
    fn normaliser(&self, mu: F, mu_refracted: F, side: &str) -> F {
        let mu = mu.at_least(GLOSSY_GRAZING as f32);
        let mu_refracted = mu_refracted.max(self.refracted_cosine(self.inputs.lit(GLOSSY_GRAZING as f32)));
        let alpha = self.alpha(mu, mu, None);
        let white = self.white_albedo(mu_refracted, alpha);
        (white * self.cone_share(mu_refracted, alpha, side)).named(&self.name(&format!("lobe_normaliser_{side}")))
    }

    /// E(μ′; α), `ggx_albedo` at the refracted cosine and the lobe's roughness √α: a lookup in
    /// two arguments that both follow the direction. Where lookups are curves
    /// ([`Real::table_curves`]) and α(μ) is known to stay within a few cells of the table's
    /// roughness axis, it is the same bilinear interpolation written as Σⱼ hatⱼ(√α)·E(μ′; rⱼ)
    /// over the nodes rⱼ it can reach (hatⱼ the tent of node j, 1 − |s − j| at node position
    /// s), each E(μ′; rⱼ) a curve: no table read.
    fn white_albedo(&self, mu_refracted: F, alpha: F) -> F {
        let rho = alpha.sqrt();
        let (axis, n) = TableId::GgxAlbedo.spec().axes[1];
        let span = if F::table_curves(self.inputs.ctx) {
            *self.roughness_span.get_or_init(|| self.roughness_nodes(axis, n))
        } else {
            None
        };
        let Some((first, last)) = span else {
            return tables::lookup(TableId::GgxAlbedo, &[mu_refracted, rho]);
        };
        let position = axis.coordinate(rho) * (n - 1) as f32;
        let mut total = self.inputs.lit(0.0);
        for j in first..=last {
            let tent = (position - j as f32).abs().one_minus().at_least(0.0);
            let at_node = tables::lookup(TableId::GgxAlbedo, &[mu_refracted, self.inputs.lit(axis.node(j, n) as f32)]);
            total = total + tent * at_node;
        }
        total
    }

    /// The first and last roughness nodes (of `n` on `axis`) whose tents √α(μ) can reach, when α
    /// is known at compile time as a function of μ: α grows with the blur, which is piecewise
    /// linear between the blur table's direction nodes, so its extremes are at those nodes or at
    /// the ends of μ ∈ [GLOSSY_GRAZING, 1]. `None` with runtime parameters or beyond four nodes.
    fn roughness_nodes(&self, axis: Axis, n: usize) -> Option<(usize, usize)> {
        let (blur_axis, blur_nodes) = TableId::GlossyBlur.spec().axes[0];
        let grazing = GLOSSY_GRAZING as f32;
        let mus = (0..blur_nodes).map(|k| blur_axis.node(k, blur_nodes) as f32).filter(|&m| m > grazing);
        let mut positions = Vec::new();
        for mu in std::iter::once(grazing).chain(mus) {
            let mu = self.inputs.lit(mu);
            let rho = self.alpha(mu, mu, None).sqrt();
            positions.push(axis.coordinate(rho).known()? * (n - 1) as f32);
        }
        // (A margin of 10⁻³ node against rounding between these values and the shader's.)
        let lowest = positions.iter().copied().fold(f32::INFINITY, f32::min) - 1e-3;
        let highest = positions.iter().copied().fold(f32::NEG_INFINITY, f32::max) + 1e-3;
        let first = lowest.floor().clamp(0.0, (n - 1) as f32) as usize;
        let last = (highest.floor() + 1.0).clamp(0.0, (n - 1) as f32) as usize;
        (last - first < 4).then_some((first, last))
    }

    /// The share of a GGX lobe (α) from Snell's cosine μ′ that stays inside the coat's escape
    /// cone (`CoatInterface::cone_share`). The lobe's tail beyond the cone grows like α², which
    /// no multilinear table in √r_c follows.
    fn cone_share(&self, mu_refracted: F, alpha: F, side: &str) -> F {
        self.interface.cone_share(mu_refracted, alpha).named(&self.name(&format!("cone_share_{side}")))
    }

    /// c: the survival of one more event of trapped light, F(μ*) e^(−2τ/μ*); and F(μ*) alone.
    fn survival(&self) -> (F::Vec, F::Vec) {
        let mu_star = self.pool_lookup(TableId::GlossyPoolCosine).named(&self.name("pool_cosine"));
        let fresnel =
            conductor_fresnel(self.fresnel, self.inputs, mu_star, self.n_medium).named(&self.name("pool_fresnel"));
        if self.tau.is_known_zero() {
            return (fresnel, fresnel);
        }
        let round_trip = absorbed(self.tau * 2.0, mu_star);
        ((fresnel * round_trip).named(&self.name("survival")), fresnel)
    }

    /// Snell's cosine inside the coat for outer cosine μ: √(1 − (1 − μ²)/η²).
    fn refracted_cosine(&self, mu: F) -> F {
        (mu.sq().one_minus() / self.eta.sq()).one_minus().at_least(0.0).sqrt().at_least(COS_EPSILON)
    }

    /// ∫ 2μ x(μ) dμ of per-direction quantities (one total per function in `of`, named
    /// `totals` in generated code) by 4-point Gauss–Legendre on three panels: [0, μ_b] and
    /// [μ_b, 1], split at the edge of the trapped band, the wider of them halved. One rule over
    /// [0, 1] misses the remainder where it lives: for a coat of
    /// IOR just above 1 the escape cone is almost the whole hemisphere and only light entering
    /// near grazing is trapped, so M is concentrated below μ ≈ 0.2, where 6-point Gauss–Legendre
    /// has one node; ⟨M⟩ comes out less than half the truth and the remainder, divided by it,
    /// reflects twice its M (a white conductor of roughness 0.3 under a smooth η 1.003 coat:
    /// E = 1.086 at 89°). Two panels are not enough either: M follows the tables' piecewise
    /// linear interpolation in √μ, and with 4 nodes over [0, 0.95] (a rough coat: the band
    /// covers nearly everything) ⟨M⟩ comes out 0.5% high, which the remainder loses at every
    /// angle (−0.003 of a white conductor's albedo at 85° under an r 0.5 coat), and near η = 1
    /// up to 30% low, a gain the lobe-albedo table would have to be raised against (largest
    /// probe excess 7.5 with two panels, 2.1 with three; `glazec_lab::bake::glossy`).
    ///
    /// The twelve nodes are one loop in a shader ([`Real::sum_over`]): each node looks up seven
    /// 4D tables, and straight-line copies of that make a coat over a conductor with runtime
    /// parameters a shader that lavapipe takes seconds to compile (140 KB of WGSL with eight
    /// nodes). With literal parameters the loop folds to constants when the code is generated.
    fn hemispherical(&self, c: F::Vec, of: &[PerSide<F>], totals: &[&str]) -> Vec<F::Vec> {
        let split = self.trapped_band_edge();
        let fold = [self.eta, self.conductor_roughness, self.roughness].iter().all(|x| x.known().is_some())
            && self.tau.is_known()
            && c.is_known();
        let index = self.name("node_index");
        let key = self.inputs_of_the_nodes(c);
        // The wider of [0, μ_b] and [μ_b, 1] is halved: panels [0, e₁], [e₁, e₂], [e₂, 1].
        let lower_is_wider = split.gt_lit(0.5);
        let first = F::select(lower_is_wider, split * 0.5, split);
        let second = F::select(lower_is_wider, split, (split + 1.0) * 0.5);
        let sum = Sum { count: PANELS * GAUSS_LEGENDRE_4.len() as u32, index: &index, totals, fold, key: &key };
        F::sum_over(self.inputs.ctx, &sum, &|i| {
            // Node i: panel ⌊i/4⌋, Gauss–Legendre node i mod 4.
            let panel = (i * 0.25).floor();
            let (x, w) = gauss_legendre_4_at(i - panel * 4.0);
            let (is_first, is_second) = (panel.lt_lit(0.5), panel.lt_lit(1.5));
            let from = F::select(is_first, self.inputs.lit(0.0), F::select(is_second, first, second));
            let width = F::select(is_first, first, F::select(is_second, second - first, second.one_minus()));
            let mu = (from + width * x).named(&self.name("node"));
            let weight = (mu * width * (w * 2.0)).named(&self.name("weight"));
            let side = self.side(mu, self.refracted_cosine(mu), c, "node");
            of.iter().map(|of| of(&side) * weight).collect()
        })
    }

    /// Everything a node of [`Self::hemispherical`] reads besides its μ, as numbers: the key
    /// under which the CPU keeps the sums (empty when building a shader, which keeps nothing).
    fn inputs_of_the_nodes(&self, c: F::Vec) -> Vec<f32> {
        if !F::IMMEDIATE {
            return Vec::new();
        }
        let number = |x: F| x.known().unwrap_or(f32::NAN);
        let mut key = vec![number(self.eta), number(self.conductor_roughness), number(self.roughness)];
        key.push(if self.interface.roughness.is_some() { 1.0 } else { 0.0 });
        key.push(if self.interface.approx.schlick_fresnel { 1.0 } else { 0.0 });
        key.push(if self.interface.approx.single_scattering { 1.0 } else { 0.0 });
        key.push(self.n_medium.map_or(-1.0, number));
        let mut vectors = vec![self.tau, c];
        match self.fresnel {
            ConductorFresnel::F0(f0) => {
                key.push(0.0);
                vectors.push(self.inputs.color(*f0));
            }
            ConductorFresnel::Complex { eta, k } => {
                key.push(1.0);
                vectors.extend([self.inputs.color(*eta), self.inputs.color(*k)]);
            }
        }
        key.extend(vectors.into_iter().flat_map(|v| [v.x(), v.y(), v.z()].map(number)));
        key
    }

    /// μ_b, the outer cosine whose refracted cosine lies [`TRAPPED_BAND_WIDTH`] α inside the
    /// escape cone's edge μc: μ′_b = min(1, μc + 2(α_c + α)), μ_b = √(1 − η²(1 − μ′_b²)) (Snell's
    /// law backwards), kept within [`TRAPPED_BAND_MIN`], 1 − [`TRAPPED_BAND_MIN`].
    fn trapped_band_edge(&self) -> F {
        let alpha = self.conductor_roughness.sq() + self.roughness.sq();
        let inner = (escape_cone_cosine(self.eta) + alpha * TRAPPED_BAND_WIDTH).clamp(0.0, 1.0);
        let outer = (inner.sq().one_minus() * self.eta.sq()).one_minus().at_least(0.0).sqrt();
        outer.clamp(TRAPPED_BAND_MIN, 1.0 - TRAPPED_BAND_MIN).named(&self.name("band_edge"))
    }
}

fn remainder<F: Real>(side: &Side<F>) -> F::Vec {
    glossy_remainder(side.transmission, side.absorb, side.fresnel, side.single, side.later)
}

/// The part of a side's directional albedo that leaves near the mirror direction as the lobe.
fn albedo_lobe<F: Real>(side: &Side<F>) -> F::Vec {
    glossy_albedo_lobe(side.transmission, side.fresnel, side.absorb_lobe, side.once)
}

fn directional_albedo<F: Real>(side: &Side<F>) -> F::Vec {
    glossy_albedo(side.transmission, albedo_lobe(side), remainder(side))
}

/// The conductor's microfacet lobe (without the cosine) at the level's directions with the
/// distribution `distribution` ([`Glossy::distribution`]) and Smith's G at GGX α `alpha`; white
/// (F = 1) without a Fresnel description.
fn conductor_lobe<F: Real>(
    fresnel: Option<&ConductorFresnel>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    (distribution, alpha): (F, F),
    n_medium: Option<F>,
) -> F::Vec {
    let name = |base| level_name(base, g.level);
    let half = g.half();
    let shadowing = g_smith_ggx_correlated(g.n_dot_v, g.n_dot_l, alpha).named(&name("g"));
    let f = match fresnel {
        Some(fresnel) => conductor_fresnel(fresnel, inputs, half.v_dot_h, n_medium).named(&name("fresnel")),
        None => inputs.lit(1.0).splat(),
    };
    let lobe = f_cook_torrance(distribution, shadowing, f, g.n_dot_v, g.n_dot_l);
    match g.shading_cosine_ratio() {
        Some(ratio) => F::Vec::select(g.raw_n_dot_v.gt_lit(0.0), lobe * ratio, inputs.zero()),
        None => lobe,
    }
}

/// The interfaced method at depth `at` when a conductor lies directly under its coat (see the
/// module essay); `at.blur` is the widening of the rough coats above.
pub(super) fn glossy_level<F: Real>(
    stack: &Stack<'_, F>,
    (roughness, fresnel): (Scalar, &ConductorFresnel),
    g: &Geometry<F>,
    at: Depth<F>,
    want_albedo: bool,
) -> Level<F> {
    let Stack { coats, inputs, approx, .. } = *stack;
    let Depth { k, n_medium, blur, .. } = at;
    let coat = &coats[k];
    let eta = inputs.scalar(coat.ior);
    let tau = inputs.optical_depth(coat).named(&level_name("tau", k));
    let interface = CoatInterface::new(&coat.lobe, eta, inputs, k, approx);
    let coat_roughness = interface.glossy_roughness().unwrap_or(inputs.lit(0.0));
    let glossy = Glossy {
        interface,
        inputs,
        eta,
        tau,
        conductor_roughness: inputs.scalar(roughness),
        fresnel,
        n_medium: Some(n_medium.map_or(eta, |n| n * eta)),
        roughness: coat_roughness,
        level: k + 1,
        roughness_span: std::cell::OnceCell::new(),
    };
    let below = g.refracted(eta);
    let (c, c_fresnel) = glossy.survival();
    let (l, v) = g.sides(
        || glossy.side(g.raw_n_dot_l, below.n_dot_l, c, "l"),
        || glossy.side(g.raw_n_dot_v, below.n_dot_v, c, "v"),
    );
    let blurs = glossy.blurs(g.raw_n_dot_l, g.raw_n_dot_v);
    let alpha = glossy.widened_alpha(blurs, blur.total());
    // The remainder's mean ⟨M⟩ (for f) and the mean albedo (for the levels above), from the same
    // nodes in one loop.
    let mut wanted: Vec<PerSide<F>> = Vec::new();
    let mut totals = Vec::new();
    if !g.albedo_only {
        wanted.push(remainder);
        totals.push(level_name("remainder_total", k));
    }
    if want_albedo {
        wanted.push(directional_albedo);
        totals.push(level_name("albedo_total", k));
    }
    let totals: Vec<&str> = totals.iter().map(String::as_str).collect();
    let mut means = glossy.hemispherical(c, &wanted, &totals).into_iter();
    let f = if g.albedo_only {
        inputs.zero()
    } else {
        let f_top = glossy
            .interface
            .scaled_lobe(interfaced_lobe(&coat.lobe, eta, inputs, g, approx, blur), g)
            .named(&level_name("specular", k));
        // The lobe's colour beyond its Fresnel factor: how much of the light leaving after the
        // second event survives that event, √(o_l o_v) (reciprocal; 1 for a white conductor).
        let colour = (l.once_colour * v.once_colour).sqrt();
        let distribution = glossy.distribution(&below, blurs, alpha, blur.total());
        let lobe = conductor_lobe(Some(fresnel), inputs, &below, (distribution, alpha), glossy.n_medium)
            * colour
            * (l.scale * v.scale);
        let once = interfaced_layer(
            f_top,
            l.transmission,
            v.transmission,
            l.absorb_lobe,
            v.absorb_lobe,
            lobe.named(&level_name("under", k)),
            eta,
        );
        let average = means
            .next()
            .unwrap_or_else(|| unreachable!("the remainder's mean is summed"))
            .named(&level_name("remainder_avg", k));
        // The trapped light keeps travelling on: spread about the forward direction with
        // κ = √(κ(μl) κ(μv)), tilted per channel by the conductor's Fresnel colour
        // (`glossy_spread_colour`, both sides' weights averaged: reciprocal; with the slab's
        // round trip in c too, absorbing copper fits the reference worse, docs/accuracy.md).
        let kappa_l = glossy.lookup(TableId::GlossySpread, g.raw_n_dot_l).named(&level_name("spread_l", k));
        let kappa_v = glossy.lookup(TableId::GlossySpread, g.raw_n_dot_v).named(&level_name("spread_v", k));
        let mean = |of: fn(&Side<F>) -> F| (of(&l) + of(&v)) * 0.5;
        let counts = [mean(|s| s.next), mean(|s| s.quick), mean(|s| s.steady), l.slow];
        let spread = forward_spread(g, (kappa_l, kappa_v), counts, c_fresnel, ("", k));
        let later =
            (glossy_remainder_lobe::<F>(remainder(&l), remainder(&v), average) * spread).named(&level_name("later", k));
        (once + later).named(&level_name("f", k))
    };
    let albedo = want_albedo.then(|| {
        let parts = |side: &Side<F>| (albedo_lobe(side), remainder(side));
        let ((lobe_l, spread_l), (lobe_v, spread_v)) = g.sides(|| parts(&l), || parts(&v));
        let (e_l, e_v) = g.sides(
            || glossy_albedo(l.transmission, lobe_l, spread_l).named(&level_name("albedo_l", k)),
            || glossy_albedo(v.transmission, lobe_v, spread_v).named(&level_name("albedo_v", k)),
        );
        let mean =
            means.next().unwrap_or_else(|| unreachable!("the mean albedo is summed")).named(&level_name("rho", k));
        // Under a coat (a medium above), that coat lets out of each part what its escape cone
        // holds: the coat's own reflection, the lobe and the remainder.
        let split = n_medium.is_some().then(|| {
            let alpha = glossy.interface.ggx_lobe_alpha();
            let part =
                |side: &Side<F>, lobe, spread| Split { specular: side.transmission.one_minus(), alpha, lobe, spread };
            g.sides(|| part(&l, lobe_l, spread_l), || part(&v, lobe_v, spread_v))
        });
        Albedo { e_l, e_v, mean, split }
    });
    Level {
        f,
        albedo,
        glossy: true,
        alpha: Some(alpha),
        boost: inputs.lit(1.0),
        transmission: Some((l.transmission, v.transmission)),
    }
}

/// The glossy level's one-event lobe without its scale s, for a white conductor of roughness
/// `r_c` under a clear coat of roughness `r` and relative IOR `eta`, at unit directions `l`, `v`
/// (the frame's normal is z), on the CPU: T(μl) T(μv)/η² times the widened GGX lobe at the
/// refracted directions. What `glazec tables` normalises the scale against.
pub fn glossy_lobe_white(r_c: f64, r: f64, eta: f64, l: glam::DVec3, v: glam::DVec3) -> f64 {
    if l.z <= 0.0 || v.z <= 0.0 {
        return 0.0;
    }
    let inputs = Inputs::<f32>::new((), Vec::new());
    let coat = clear_coat(r, eta);
    let conductor = ConductorFresnel::F0(Color::Lit([1.0; 3]));
    let material_level = |g: &Geometry<f32>| {
        let glossy = white_level(&inputs, &coat, &conductor, r_c, eta);
        let below = g.refracted(eta as f32);
        let blurs = glossy.blurs(g.raw_n_dot_l, g.raw_n_dot_v);
        let alpha = glossy.widened_alpha(blurs, None);
        let distribution = glossy.distribution(&below, blurs, alpha, None);
        let (t_l, t_v) =
            (glossy.interface.transmission(g.raw_n_dot_l, "l"), glossy.interface.transmission(g.raw_n_dot_v, "v"));
        conductor_lobe(None, &inputs, &below, (distribution, alpha), None).x * t_l * t_v / (eta as f32).powi(2)
    };
    let g = Geometry::new(glam::Vec3::Z, v.as_vec3(), l.as_vec3(), 0);
    f64::from(material_level(&g))
}

/// The glossy level of a white `conductor` of roughness `r_c` under the clear `coat` of relative
/// IOR `eta`, alone in the stack, on the CPU (what `glazec tables` solves against).
fn white_level<'a>(
    inputs: &'a Inputs<f32>,
    coat: &'a Coat,
    conductor: &'a ConductorFresnel,
    r_c: f64,
    eta: f64,
) -> Glossy<'a, 'a, f32> {
    let interface = CoatInterface::new(&coat.lobe, eta as f32, inputs, 0, Approximations::default());
    Glossy {
        roughness: interface.roughness.unwrap_or(0.0),
        interface,
        inputs,
        eta: eta as f32,
        tau: glam::Vec3::ZERO,
        conductor_roughness: r_c as f32,
        fresnel: conductor,
        n_medium: Some(eta as f32),
        level: 1,
        roughness_span: std::cell::OnceCell::new(),
    }
}

/// The normaliser E(μ′; α)·c(μ′) of `glossy_lobe_albedo` for a conductor of roughness `r_c`
/// under a coat of roughness `r` and relative IOR `eta`, at outer cosine `mu`, as the method
/// evaluates it (CPU, with whatever tables `math::tables` evaluates with).
pub fn glossy_lobe_normaliser(r_c: f64, r: f64, eta: f64, mu: f64) -> f64 {
    let inputs = Inputs::<f32>::new((), Vec::new());
    let coat = clear_coat(r, eta);
    let conductor = ConductorFresnel::F0(Color::Lit([1.0; 3]));
    let glossy = white_level(&inputs, &coat, &conductor, r_c, eta);
    let mu = mu as f32;
    let g = Geometry::new(glam::Vec3::Z, glam::Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu), glam::Vec3::Z, 0);
    let below = g.refracted(eta as f32);
    f64::from(glossy.normaliser(mu, below.n_dot_v, "v"))
}

/// The coat's transmission T(μ) as the method evaluates it (CPU), for `glossy_lobe_white`'s
/// normalisation.
pub fn glossy_coat_transmission(r: f64, eta: f64, mu: f64) -> f64 {
    let inputs = Inputs::<f32>::new((), Vec::new());
    let coat = clear_coat(r, eta);
    let interface = CoatInterface::new(&coat.lobe, eta as f32, &inputs, 0, Approximations::default());
    f64::from(interface.transmission(mu as f32, "v"))
}

fn clear_coat(r: f64, eta: f64) -> Coat {
    let lobe = if r == 0.0 { Lobe::Smooth } else { Lobe::Ggx { roughness: Scalar::Lit(r as f32) } };
    Coat { lobe, ior: Scalar::Lit(eta as f32), absorption: Color::Lit([0.0; 3]), thickness: Scalar::Lit(0.0) }
}
