//! A coat's interface in the interfaced method ([`CoatInterface`]): transmission, the path
//! factor, the slab's return and escape, the multiple-scattering lobe, and its own reflection.

use super::geometry::{Geometry, level_name};
use super::inputs::Inputs;
use super::level::{Blur, coat_blur};
use crate::math::tables::{self, CoatTables, TableId};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};
use crate::model::{Approximations, Lobe, Scalar};

/// The GGX roughness a GTR1 coat stands for in the glossy level's tables, r′ = A·r^B: the
/// tables are measured by walks through GGX coats, and GTR1 of α = r² is a log-uniform mixture
/// of GGX distributions of α′ from α to 1 (docs/derivations.md, "GTR1 is a mixture of GGX"),
/// whose widest members spread what the conductor reflects far more than r says. Fitted against
/// the reference for conductors under GTR1 coats of r 0.05–0.4 and η 1.33–2 (`glazec-lab`
/// example `gtr1_over_conductor`): taking r itself left the body 0.3–0.6× the reference and the
/// mirror peak up to 2.4× it; with r′ the RMS log error over its probes falls from 0.45–0.95 to
/// 0.12–0.35, and what remains is grazing light to the side (0.4–0.9× the reference).
const GTR1_GLOSSY_SCALE: f32 = 0.7;
/// See [`GTR1_GLOSSY_SCALE`].
const GTR1_GLOSSY_POWER: f32 = 0.15;

/// A coat's interface as the interfaced method sees it: smooth (exact Fresnel, slab integrals by
/// quadrature) or rough (tabulated: `crate::math::tables`).
pub(super) struct CoatInterface<'i, F: Real> {
    pub(super) eta: F,
    /// `None` for a smooth coat.
    pub(super) roughness: Option<F>,
    /// The tables of its microfacet distribution (GGX or GTR1).
    pub(super) tables: CoatTables,
    pub(super) inputs: &'i Inputs<F>,
    pub(super) level: usize,
    pub(super) approx: Approximations,
}

impl<'i, F: Real> CoatInterface<'i, F> {
    pub(super) fn new(lobe: &Lobe, eta: F, inputs: &'i Inputs<F>, k: usize, approx: Approximations) -> Self {
        // A literal roughness of 0 is a smooth interface. (A runtime roughness always takes the
        // tabulated path, whose r = 0 nodes are the smooth interface, so the CPU and the shader
        // evaluate the same formula.)
        let roughness = match lobe {
            Lobe::Smooth | Lobe::Ggx { roughness: Scalar::Lit(0.0) } | Lobe::Gtr1 { roughness: Scalar::Lit(0.0) } => {
                None
            }
            Lobe::Ggx { roughness } | Lobe::Gtr1 { roughness } => Some(inputs.scalar(*roughness)),
        };
        let tables = if matches!(lobe, Lobe::Gtr1 { .. }) { CoatTables::GTR1 } else { CoatTables::GGX };
        CoatInterface { eta, roughness, tables, inputs, level: k + 1, approx }
    }

    /// The blur of the coats above, `above`, with this coat's added (`level::coat_blur`), from
    /// the median slope of its microfacet normals: GGX's α = r², GTR1's √α = r (none for a
    /// smooth coat).
    pub(super) fn blur_below(&self, above: Blur<F>, k: usize, cosines: Option<((F, F), (F, F))>) -> Blur<F> {
        let gtr1 = self.tables == CoatTables::GTR1;
        let median_slope = self.roughness.map(|r| if gtr1 { r } else { r * r });
        coat_blur(median_slope, gtr1, self.eta, above, k, cosines)
    }

    /// The GGX α of a GGX coat's reflection lobe, r² (`None` for a smooth or a GTR1 coat).
    pub(super) fn ggx_lobe_alpha(&self) -> Option<F> {
        let r = self.roughness?;
        (self.tables == CoatTables::GGX).then(|| r.sq())
    }

    /// The share of a GGX reflection lobe (α) about the mirror direction of Snell's cosine μ′
    /// under this coat that stays inside its escape cone: 1 − `glossy_trapped_share` (1 without
    /// total internal reflection, η ≤ 1).
    pub(super) fn cone_share(&self, mu_refracted: F, alpha: F) -> F {
        let mu_c = escape_cone_cosine(self.eta);
        let trapped = glossy_trapped_share(mu_refracted, mu_c, alpha);
        F::select(mu_c.gt_lit(0.0), trapped.one_minus(), self.inputs.lit(1.0))
    }

    /// The roughness the glossy level looks its tables up at (`None` for a smooth coat): a GGX
    /// coat's own, a GTR1 coat's [`GTR1_GLOSSY_SCALE`]·r^[`GTR1_GLOSSY_POWER`], at most 1.
    /// Guard: r ≥ 10⁻⁶ under the logarithm (a rough coat's r is above 0).
    pub(super) fn glossy_roughness(&self) -> Option<F> {
        let r = self.roughness?;
        if self.tables != CoatTables::GTR1 {
            return Some(r);
        }
        Some(((r.at_least(1e-6).ln() * GTR1_GLOSSY_POWER).exp() * GTR1_GLOSSY_SCALE).min(r.lit(1.0)))
    }

    pub(super) fn name(&self, base: &str) -> String {
        level_name(base, self.level)
    }

    /// The mean cosine of the escape cone seen from inside, weighted by projected solid angle:
    /// (2/3)(1 − μc³)/(1 − μc²) with μc = √(1 − 1/η²) (2/3 without TIR). Guard: 1 − μc² ≥ 10⁻⁶.
    pub(super) fn escape_cone_mean_cosine(&self) -> F {
        let mu_c = escape_cone_cosine(self.eta);
        ((mu_c * mu_c * mu_c).one_minus() / mu_c.sq().one_minus().at_least(1e-6) * (2.0 / 3.0)).clamp(0.0, 1.0)
    }

    /// The coat's transmission T̄ out of its escape cone, at the cone's mean cosine inside
    /// ([`Self::escape_cone_mean_cosine`]), i.e. at the outside cosine √(1 − η²(1 − μ̄c²)).
    pub(super) fn transmission_from_cone(&self) -> F {
        let mu_mean = self.escape_cone_mean_cosine();
        let mu_outside = (self.eta.sq() * mu_mean.sq().one_minus()).one_minus().at_least(0.0).sqrt();
        self.transmission(mu_outside, "cone")
    }

    /// The tables cover η ∈ [1, 3]. A rough coat of lower relative IOR (optically thinner than
    /// the medium above it) uses the smooth interface's transmission, path and slab terms
    /// instead (its own lobe stays rough): outside their range the tables would give a
    /// hemispherical transmittance above η², i.e. a negative internal reflection. A runtime η
    /// selects between both.
    pub(super) fn unless_below_one<T>(
        &self,
        smooth: impl FnOnce() -> T,
        rough: T,
        select: fn(F::Bool, T, T) -> T,
    ) -> T {
        match self.eta.known() {
            Some(eta) if eta < 1.0 => smooth(),
            Some(_) => rough,
            None => select(self.eta.lt_lit(1.0), smooth(), rough),
        }
    }

    /// T(μ): the share of light from above at cosine μ that enters the coat. Rough:
    /// T = 1 − F + G, G the tabulated deficit of the single- and multiple-scattering reflection
    /// against a smooth interface's.
    pub(super) fn transmission(&self, mu: F, side: &str) -> F {
        let name = self.name(&format!("transmit_{side}"));
        let smooth =
            dielectric_fresnel(mu, self.eta, self.approx).named(&self.name(&format!("fresnel_{side}"))).one_minus();
        match self.roughness {
            None => smooth.named(&name),
            Some(r) => {
                let deficit = tables::lookup(self.tables.deficit, &[mu, r, self.eta])
                    .named(&self.name(&format!("deficit_{side}")));
                let rough = (smooth + deficit).clamp(0.0, 1.0);
                self.unless_below_one(|| smooth, rough, F::select).named(&name)
            }
        }
    }

    /// ⟨T⟩ for either kind of interface.
    pub(super) fn transmission_hemispherical(&self) -> F {
        match self.roughness {
            None => self.smooth_transmission_avg(),
            Some(r) => self.transmission_avg(r),
        }
    }

    /// ⟨T⟩ of the smooth interface from above. The table covers η ≥ 1; a coat optically thinner
    /// than the medium above (η < 1) takes it by the reciprocity of étendue, n₁²⟨T⟩↓ = n₂²⟨T⟩↑
    /// (what enters from above is what would leave upwards, seen from the other side):
    /// ⟨T⟩(η) = η²⟨T⟩(1/η), at most η², since light beyond the critical angle above cannot enter.
    /// (The clamped lookup gave ⟨T⟩(1) = 1 there, and the first pass out of such a coat, which
    /// divides by it, let 13% too little of the light it reflects escape under a coat of η 2:
    /// `glazec_lab::reference::smooth_stack`.)
    fn smooth_transmission_avg(&self) -> F {
        let from_above = |eta: F| tables::lookup(TableId::FresnelTransmitAvg, &[eta]);
        let thinner = || self.eta.sq() * from_above(self.inputs.lit(1.0) / self.eta);
        self.unless_below_one(thinner, from_above(self.eta), F::select)
    }

    /// ⟨T⟩: the coat's hemispherical transmittance from above, consistent with
    /// [`Self::transmission`] (the average of the same interpolated curve; the smooth
    /// interface's for η < 1, as there).
    pub(super) fn transmission_avg(&self, r: F) -> F {
        let smooth = self.smooth_transmission_avg();
        let rough = || smooth + tables::lookup(self.tables.deficit_avg, &[r, self.eta]);
        self.unless_below_one(|| smooth, rough(), F::select).named(&self.name("transmit_avg"))
    }

    /// The cosine along which light entering at outer cosine `mu` (refracted cosine
    /// `mu_refracted`) is absorbed: Snell's for a smooth coat, shortened by the tabulated path
    /// factor for a rough one.
    pub(super) fn path_cosine(&self, mu: F, mu_refracted: F, side: &str) -> F {
        match self.path_factor(mu) {
            None => mu_refracted,
            Some(q) => {
                let q = q.named(&self.name(&format!("path_factor_{side}")));
                (mu_refracted / q).named(&self.name(&format!("path_cos_{side}")))
            }
        }
    }

    /// The tabulated path factor q(μ; r, η) ≥ 1 of a rough coat (1 for η < 1, where the smooth
    /// interface's path is taken); `None` for a smooth coat.
    fn path_factor(&self, mu: F) -> Option<F> {
        let r = self.roughness?;
        let q = tables::lookup(self.tables.path, &[mu, r, self.eta]);
        Some(self.unless_below_one(|| q.lit(1.0), q, F::select))
    }

    /// The spread of Snell's invariant p = n sin θ that this coat's roughness gives the light it
    /// transmits, |n_below − n_above|·m with `n_above` the absolute IOR above it (`None`: air)
    /// and m the median slope of its microfacet normals (as [`Self::blur_below`]); `None` for a
    /// smooth coat. A facet tilted by δ turns a transmitted ray by about (1 − 1/η)δ, which is a
    /// change of p by (n_below − n_above)δ; smooth interfaces below keep p, so spreads in p
    /// from coats at different depths add up without regard to the IORs between them.
    pub(super) fn p_spread(&self, n_above: Option<F>) -> Option<F> {
        let r = self.roughness?;
        let median_slope = if self.tables == CoatTables::GTR1 { r } else { r * r };
        let n_below = n_above.map_or(self.eta, |n| n * self.eta);
        let contrast = n_above.map_or(n_below.lit(1.0) - n_below, |n| n - n_below).abs();
        Some(contrast * median_slope)
    }

    /// [`Self::path_cosine`] for a slab under rough coats, which have spread the light's Snell
    /// invariant by `spread_above` (see [`Self::p_spread`]) before this coat spreads it again.
    /// The path factor grows with the variance of the directions in the slab, and variances of
    /// independent spreads add, so the factors' excesses add: q = q_own + q_above − 1. q_above
    /// is that of one GGX interface from air into the slab's absolute IOR n = `n_above`·η that
    /// spreads p as much: median slope α = spread/(n − 1), looked up at roughness √α and the
    /// outside cosine μ₀ = √(1 − n_above²(1 − μ²)) (Snell's invariant). Guards: n − 1 ≥ 0.05 (a
    /// slab of nearly the outside IOR would need an infinitely rough interface; the roughness is
    /// at most 1 either way), and no excess for n < 1. Without it a rough coat over an
    /// index-matched absorbing slab came out 1.06–1.26× the reference at 60°/60° (GGX 0.3 and
    /// 0.6, GTR1 0.2); with it 0.97–1.03× (the same coat with the absorption in its own slab:
    /// 0.92–0.99×). Adding the spreads instead of the excesses made two GGX 0.6
    /// coats over an absorbing slab 0.90× the reference there (this: 0.97×).
    pub(super) fn path_cosine_spread(&self, mu: F, mu_refracted: F, n_above: F, spread_above: F, side: &str) -> F {
        let n = n_above * self.eta;
        let mu_outside = (n_above.sq() * mu.sq().one_minus()).one_minus().at_least(0.0).sqrt();
        let roughness = (spread_above / (n - 1.0).at_least(0.05)).sqrt().min(n.lit(1.0));
        let q_above = tables::lookup(TableId::CoatPath, &[mu_outside, roughness, n]);
        let excess = F::select(n.lt_lit(1.0), n.lit(0.0), q_above - 1.0);
        let q = self
            .path_factor(mu)
            .map_or(excess + 1.0, |q_own| q_own.named(&self.name(&format!("path_factor_{side}"))) + excess);
        (mu_refracted / q).named(&self.name(&format!("path_cos_{side}")))
    }

    /// The coat's reflection lobe with the light it reflects after more than one microfacet event:
    /// the single-scattering lobe `single` scaled by c(μl)·c(μv) (Turquin 2019, "Practical
    /// multiple scattering compensation for microfacet models", scales the single-scattering lobe
    /// by 1 + E_ms/E_ss at the view; a symmetric product keeps f reciprocal, and `glazec tables`
    /// solves c so that the scaled lobe reflects exactly what the coat does not transmit, F − G).
    /// Multiply-scattered light stays where the single-scattering lobe puts it, near the mirror
    /// direction for a smooth-ish coat, as the reference's microsurface walks show; a separable
    /// Kulla–Conty lobe spread it over every direction, most towards grazing pairs (5× the
    /// reference at 85°). Unscaled for a smooth coat, for an optically thinner one (η < 1: no
    /// tables), for a GTR1 coat (whose later events leave far from its peak: `CoatTables::GTR1`)
    /// and under [`Approximations::single_scattering`].
    pub(super) fn scaled_lobe(&self, single: F::Vec, g: &Geometry<F>) -> F::Vec {
        let Some(r) = self.roughness.filter(|_| !self.approx.single_scattering) else { return single };
        // A GTR1 coat's lobe is not scaled (`CoatTables::GTR1`).
        let Some(scale) = self.tables.scale else { return single };
        let c_l = tables::lookup(scale, &[g.raw_n_dot_l, r, self.eta]).named(&self.name("scale_l"));
        let c_v = tables::lookup(scale, &[g.raw_n_dot_v, r, self.eta]).named(&self.name("scale_v"));
        let second = self.second_event(r * r, g);
        let scaled = (single + second.splat()) * (c_l * c_v);
        self.unless_below_one(|| single, scaled, F::Vec::select)
    }

    /// The light the coat's microsurface reflects in two events when one direction grazes:
    /// arriving at elevation ε and reflected near the mirror direction, it meets the
    /// microsurface again at a facet steeper than ε, which sends it on as if it had arrived from
    /// its direction mirrored in the mean plane. The tail of a single-scattering lobe at that
    /// mirrored direction, weighted by the first event's Fresnel factor and
    /// `second_event_share`, both at the more grazing of l and v (so reciprocal):
    ///
    ///   f₂ = F(μg)·s(Λ(μg)) · D_tail(h̄) F(h̄·l) G₂ / (4 μl μv),  μg = min(μl, μv),
    ///
    /// h̄ the half vector with the lower direction mirrored (`d_ggx_mirrored_tail`), whose
    /// cosine with either direction is |l + v̄|/2. Derived here from the Smith microsurface of
    /// Heitz et al. 2016 ("Multiple-Scattering Microfacet BSDFs with the Smith Model") and
    /// checked against its walks (docs/accuracy.md, "Multiple scattering in a rough coat's lobe"):
    /// it puts the second event where the walks do, in the lobe's tail beside a grazing
    /// direction (α 0.0025 at 89°: 0.65 times the single-scattering lobe 14° from the mirror
    /// direction), where scaling the lobe by c cannot. Its energy is part of E_ms:
    /// `glazec tables` solves c for the single-scattering lobe plus this one.
    fn second_event(&self, alpha: F, g: &Geometry<F>) -> F {
        let along = g.n.cross(g.v + g.l).named(&self.name("mirrored_along"));
        let across = along.dot(along).named(&self.name("mirrored_across"));
        let z = (g.n_dot_l - g.n_dot_v).named(&self.name("mirrored_z"));
        let distribution = d_ggx_mirrored_tail(z, across, alpha).named(&self.name("mirrored_d"));
        let facet_cosine = ((z * z + across).sqrt() * 0.5).named(&self.name("mirrored_cos"));
        let fresnel = dielectric_fresnel(facet_cosine, self.eta, self.approx).named(&self.name("mirrored_fresnel"));
        // At the more grazing direction: F and Λ fall as μ rises (η ≥ 1, the only case with
        // tables), so there they are the larger of the two directions' values, which the
        // transmission and G₂ compute anyway (a shader compiler merges the repeated terms).
        let fresnel_at = |mu: F| dielectric_fresnel(mu, self.eta, self.approx);
        let first_fresnel = fresnel_at(g.raw_n_dot_l).max(fresnel_at(g.raw_n_dot_v));
        let clamped = alpha.at_least(ALPHA_MIN);
        let lambda_l = lambda_ggx(g.n_dot_l, clamped).named(&self.name("lambda_l"));
        let lambda_v = lambda_ggx(g.n_dot_v, clamped).named(&self.name("lambda_v"));
        let lambda = lambda_l.max(lambda_v);
        let share = second_event_share(lambda).named(&self.name("second_share"));
        let first = (first_fresnel * share).named(&self.name("first_event"));
        // The same call as a GGX coat's single-scattering lobe makes (it clamps α itself): the
        // module shares it for a literal α, and a shader compiler merges it for a runtime one.
        let shadowing = g_smith_ggx_correlated(g.n_dot_v, g.n_dot_l, alpha);
        (first * distribution * fresnel * shadowing / (g.n_dot_v * g.n_dot_l * 4.0)).named(&self.name("second_event"))
    }

    /// (R(τ), E_esc(τ)) of the coat's slab.
    pub(super) fn slab(&self, tau: F::Vec) -> (F::Vec, F::Vec) {
        let smooth = || (slab_return(self.eta, tau), slab_escape(self.eta, tau));
        let (r_return, e_escape) = match self.roughness {
            None => smooth(),
            Some(r) => {
                // Both tables are normalised by the internal transmittance ⟨T_int⟩ = ⟨T⟩/η²,
                // so both are exactly 1 for a clear slab (τ = 0): no lookup needed then.
                let scale = self.transmission_avg(r) / self.eta.sq();
                let per_channel = |id: TableId| {
                    if tau.is_known_zero() {
                        return scale.splat();
                    }
                    let at = |t: F| tables::lookup(id, &[t, r, self.eta]);
                    F::vec3(at(tau.x()), at(tau.y()), at(tau.z())) * scale
                };
                // Guard: R(τ) → 0 for a thick slab, where 1 − (interpolated ratio) may round to
                // −10⁻⁸; a reflectance is ≥ 0.
                let zero = self.inputs.zero();
                let r_return = per_channel(self.tables.slab_return).one_minus().max(zero);
                let rough = (r_return, per_channel(self.tables.slab_escape));
                let pick = |c: F::Bool, a: (F::Vec, F::Vec), b: (F::Vec, F::Vec)| {
                    (F::Vec::select(c, a.0, b.0), F::Vec::select(c, a.1, b.1))
                };
                self.unless_below_one(smooth, rough, pick)
            }
        };
        (r_return.named(&self.name("r_return")), e_escape)
    }
}

/// A GGX lobe of its own α `own` seen through rough coats that widen it to `alpha_l` at the
/// light's direction and `alpha_v` at the view's (`Blur::widen`), spread as the glossy level
/// spreads a conductor's lobe (`d_ggx_crossed`): each crossing's share of the widening, half
/// the slope variance α² − α_own² at its direction, along that direction's plane of incidence
/// and 1/μ² as much across it. To first order a crossing spreads the ray isotropically
/// (`coat_blur`), but this fits the reference better: under a `Gtr1(0.15)` coat over
/// `Ggx(0.25)` over Plastic the body p90 is 2.7% against 3.9% for the isotropic GGX of
/// α² = (α_l² + α_v²)/2 (3.6% with the blur along the normal); that lobe at 55° is 0.90× the
/// reference at its peak and 1.1–1.3× it 9°–20° across the plane, where the isotropic one is
/// 1.03× at the peak and 1.13–1.34× 10°–20° off it in the plane.
fn crossed_lobe<F: Real>(g: &Geometry<F>, own: F, (alpha_l, alpha_v): (F, F), name: &str) -> F {
    let per_crossing = |alpha: F| ((alpha.sq() - own.sq()) * 0.5).at_least(0.0);
    let names = (format!("{name}_l"), format!("{name}_v"));
    g.d_ggx_crossed(own.sq(), (per_crossing(alpha_l), per_crossing(alpha_v)), (&names.0, &names.1))
}

/// A coat's own reflection lobe in the interfaced method: exact dielectric Fresnel at the
/// microfacet normal and the exact height-correlated Smith term of its distribution (GGX's, or
/// GTR1's own for a `Gtr1` coat: the reference walks a GTR1 microsurface, and Burley's GGX term
/// at α = 0.25 shadowed its lobe 4% less per direction at 60° and 60% less at 85° for α 0.04).
/// Seen through rough coats above, whose refraction spreads it, the lobe is widened by their
/// `blur` ([`Blur::widen`] of its median slope: GGX's α, GTR1's √α). (The coat's transmission
/// and multiple-scattering scale stay those of its own roughness: the widened lobe reflects what
/// the narrower one does, less what its wider masking takes near grazing, so no energy is
/// gained.) Zero for a smooth coat (a delta lobe that point lights cannot see; one seen through
/// a rough coat would be that coat's transmission lobe, which the method leaves out).
pub(super) fn interfaced_lobe<F: Real>(
    lobe: &Lobe,
    eta: F,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    approx: Approximations,
    blur: Blur<F>,
) -> F::Vec {
    let name = |base| level_name(base, g.level);
    let (distribution, shadowing) = match lobe {
        Lobe::Smooth => return inputs.zero(),
        Lobe::Ggx { roughness } => {
            let r = inputs.scalar(*roughness);
            let own = r * r;
            let (alpha, distribution) = match blur.widen(own, &name("lobe_alpha")) {
                Some((alpha_l, alpha_v)) => (
                    ((alpha_l.sq() + alpha_v.sq()) * 0.5).sqrt().named(&name("lobe_alpha")),
                    crossed_lobe(g, own, (alpha_l, alpha_v), &name("crossing")),
                ),
                None => {
                    // Named where it is computed at run time (a literal α stays inline).
                    let own = if own.known().is_some() { own } else { own.named(&name("lobe_alpha")) };
                    (own, d_ggx(g.half().n_dot_h, g.half().sin2_h, own))
                }
            };
            (distribution, g_smith_ggx_correlated(g.n_dot_v, g.n_dot_l, alpha))
        }
        Lobe::Gtr1 { roughness } => {
            let r = inputs.scalar(*roughness);
            let alpha = match blur.widen(r, &name("lobe_slope")) {
                Some((slope_l, slope_v)) => (slope_l * slope_v).named(&name("lobe_alpha")),
                None => r.sq(),
            };
            (d_gtr1(g.half().n_dot_h, g.half().sin2_h, alpha), g_smith_gtr1_correlated(g.n_dot_v, g.n_dot_l, alpha))
        }
    };
    let distribution = distribution.named(&name("d"));
    let shadowing = shadowing.named(&name("g"));
    let microfacet = || dielectric_fresnel(g.half().v_dot_h, eta, approx);
    // A coat optically thinner than the medium above (η < 1) keeps its rough lobe but takes the
    // smooth interface's transmission 1 − F(μ) (the tables stop at η = 1; see
    // `CoatInterface::unless_below_one`). Near the critical angle, facets tilted past it reflect
    // totally, so a lobe with the microfacet Fresnel F(v·h) reflects more than F(μ) and the two
    // together gained up to 14% energy. With min(F(n·v), F(n·l)) instead (symmetric, so
    // reciprocal) the lobe's albedo is at most F(μ) times the white lobe's, ≤ F(μ): no gain.
    let macro_surface = || {
        let f_v = dielectric_fresnel(g.n_dot_v, eta, approx);
        let f_l = dielectric_fresnel(g.n_dot_l, eta, approx);
        f_v.min(f_l)
    };
    let fresnel = match eta.known() {
        Some(e) if e >= 1.0 => microfacet(),
        Some(_) => macro_surface(),
        None => F::select(eta.lt_lit(1.0), macro_surface(), microfacet()),
    }
    .named(&name("fresnel"));
    f_cook_torrance(distribution, shadowing, fresnel.splat(), g.n_dot_v, g.n_dot_l).named(&name("single_event"))
}

/// A coat's dielectric Fresnel reflectance at cosine `cos_i` from above: exact, or Schlick's
/// approximation when asked for ([`Approximations::schlick_fresnel`]). Schlick's needs the
/// cosine on the optically thinner side, which for η < 1 is the refracted one, with total
/// internal reflection where it does not exist (`fr_dielectric_schlick`); a literal η ≥ 1
/// skips that.
pub(super) fn dielectric_fresnel<F: Real>(cos_i: F, eta: F, approx: Approximations) -> F {
    if !approx.schlick_fresnel {
        return fr_dielectric(cos_i, eta);
    }
    match eta.known() {
        Some(e) if e >= 1.0 => f_schlick_scalar(f0_dielectric(eta), cos_i.clamp(0.0, 1.0)),
        _ => fr_dielectric_schlick(cos_i, eta),
    }
}
