//! A coat's slab seen from inside: transmittance along a path, the hemispherical integrals of
//! return and escape through the top interface (with total internal reflection) by
//! Gauss–Legendre quadrature, and the share of a glossy lobe trapped outside the escape cone.

use crate::math::shading_fn;
use crate::math::{Named, Real, Sum, Vector};

use super::diffuse::{FON_C1, FON_C2};
use super::microfacet::*;
use crate::math::quadrature::{GAUSS_LEGENDRE_4, GAUSS_LEGENDRE_12, gauss_legendre_4_at};

shading_fn! {
    /// Beer–Lambert transmittance of a slab with optical depth τ (per channel) along a direction
    /// with cosine μ: e^{−τ/μ}. Guard: μ ≥ COS_EPSILON (the caller's clamp) keeps τ/μ finite.
    pub fn slab_transmittance(tau: V, mu: S) -> V {
        (-(tau / mu)).exp()
    }
}

shading_fn! {
    /// Beer–Lambert transmittance of a grey slab (the same optical depth τ in every channel)
    /// along a direction with cosine μ: e^{−τ/μ}, one exponential instead of three. Guard: μ ≥
    /// COS_EPSILON (the caller's clamp) keeps τ/μ finite.
    pub fn slab_transmittance_grey(tau: S, mu: S) -> S {
        (-(tau / mu)).exp()
    }
}

/// [`slab_transmittance`], through [`slab_transmittance_grey`] when τ is known to be grey (a
/// literal absorption with equal channels): the same numbers.
pub fn absorbed<F: Real>(tau: F::Vec, mu: F) -> F::Vec {
    if tau.is_known_grey() { slab_transmittance_grey(tau.x(), mu).splat() } else { slab_transmittance(tau, mu) }
}

shading_fn! {
    /// glazec: the share of a GGX reflection lobe (α) around the mirror direction of a ray at cosine μ
    /// that leaves the coat's escape cone (cosine μc), trapped by total internal reflection:
    /// (1 + (α² + t₁t₂)/√((α² + t₁²)(α² + t₂²)))/2, t₁ = tan((θ − θc)/2), t₂ = tan((θ + θc)/2)
    /// (Walter et al. 2007 eq. 33; Heitz 2014 §5.2). Guards: 1 + cos(θ + θc) ≥ 10⁻⁶ (both angles at
    /// 90°), the root's argument ≥ 10⁻²⁴.
    ///
    /// The reflected ray stays in the cone for half vectors whose in-plane tilt lies between t₁ and
    /// t₂, taken as a disc in slope space with those slopes as its diameter. GGX's slope density
    /// α²/(π(α² + |s|²)²) is the stereographic image of the uniform measure on the sphere (slopes
    /// scaled by 1/α), and stereographic projection maps discs to spherical caps, so the disc holds
    /// exactly (1 − cos β)/2 of it, β = atan(t₂/α) − atan(t₁/α). Exact at normal incidence
    /// (ρ²/(α² + ρ²) stays in a cone of slope radius ρ); the disc is the approximation elsewhere. The
    /// tangents are written without trigonometric calls, tan(x/2) = sin x/(1 + cos x).
    pub fn trapped_share(mu: S, mu_c: S, alpha: S) -> S {
        let sin_t = mu.sq().one_minus().at_least(0.0).sqrt();
        let sin_c = mu_c.sq().one_minus().at_least(0.0).sqrt();
        let near = (sin_t * mu_c - mu * sin_c) / (mu * mu_c + sin_t * sin_c + 1.0);
        let far = (sin_t * mu_c + mu * sin_c) / (mu * mu_c - sin_t * sin_c + 1.0).at_least(1e-6);
        let a2 = alpha.sq();
        let cos_beta = (a2 + near * far) / ((a2 + near.sq()) * (a2 + far.sq())).at_least(1e-24).sqrt();
        (cos_beta + 1.0) * 0.5
    }
}

shading_fn! {
    /// glazec's glossy level: the share of a GGX lobe (α) around the mirror direction of a ray at
    /// cosine μ that lands between the coat's escape cone (cosine μc) and the horizon:
    /// `trapped_share` beyond the cone minus `trapped_share` beyond the horizon (μc = 0). Guard: ≥ 0
    /// (the disc approximation is not monotonic in μc to the last bit).
    ///
    /// That light is trapped by total internal reflection; the lobe loses what lies below the horizon
    /// whatever the coat. So the share goes to 0 with the cone's width as η → 1, continuously (beyond
    /// the cone alone, it would jump from 0 at η = 1 to a third of a grazing lobe at η = 1 + 10⁻⁵).
    pub fn glossy_trapped_share(mu: S, mu_c: S, alpha: S) -> S {
        let beyond_cone = trapped_share(mu, mu_c, alpha);
        let below_horizon = trapped_share(mu, mu_c.lit(0.0), alpha);
        (beyond_cone - below_horizon).at_least(0.0)
    }
}

shading_fn! {
    /// glazec: the share q of a pool of trapped light (uniform radiance over the trapped directions,
    /// projected solid angle π μc²) that a body reflects into the escape cone at each bounce, per unit
    /// albedo: q = (1/μc²) ∫ p du over the cone, u = μ², the edge's profile integrated exactly and the
    /// rest by 4-point Gauss–Legendre quadrature. Guards: μc² ≥ 10⁻⁴; q ≤ 1.
    ///
    /// By reciprocity the body sends light from the pool towards a cone direction o in proportion to
    /// its trapped share p(μₒ) (`trapped_share`), integrated from μc² to 1 (projected solid angle).
    /// For a sharp lobe p falls from ½ to 0 within a sliver of the cone's edge that no fixed
    /// quadrature resolves, and a q too small would let a white body return more than it trapped. So
    /// the edge's half-plane profile h(d) = ½(1 − d/√(w² + d²)) (d = u − μc², w = 4 μc sin θc α: the
    /// slope x ≈ d/(4 μc sin θc) of `trapped_share` near the edge) is integrated exactly,
    /// ∫₀ᴰ h = ½(D + w − √(w² + D²)), D = 1 − μc², and only the smooth rest p − h by quadrature.
    pub fn trapped_escape(mu_c: S, alpha: S) -> S {
        let c2 = mu_c.sq();
        let width = c2.one_minus();
        let w = mu_c * width.at_least(0.0).sqrt() * alpha * 4.0;
        let rest = trapped_rest(mu_c, alpha, w);
        let edge = (width + w - (w.sq() + width.sq()).sqrt()) * 0.5;
        let q = (rest + edge) / c2.at_least(1e-4);
        q.min(q.lit(1.0))
    }
}

shading_fn! {
    /// One Gauss–Legendre node of R(τ) inside the TIR cone μ ∈ [0, μc], where F_int = 1, with
    /// the substitution μ = μc t² (dμ = 2μc t dt): 2μ e^{−2τ/μ} · 2μc t · w.
    /// Guard: μ ≥ 10⁻²⁰ keeps τ/μ defined when μc = 0 (no TIR cone; the weight is then 0).
    pub fn slab_tir_node(mu_c: S, tau: V, t: S, weight: S) -> V {
        let mu = (mu_c * t * t).at_least(1e-20);
        (-(tau * 2.0 / mu)).exp() * (mu * mu_c * t * weight * 4.0)
    }
}

shading_fn! {
    /// One Gauss–Legendre node of R(τ) on μ ∈ [μc, 1] with μ = μc + (1 − μc) s²
    /// (dμ = 2(1 − μc) s ds): 2μ e^{−2τ/μ} F_int(μ) · 2(1 − μc) s · w.
    pub fn slab_return_node(mu_c: S, inv_eta: S, tau: V, s: S, weight: S) -> V {
        let mu = mu_c + mu_c.one_minus() * s * s;
        let fresnel = fr_dielectric(mu, inv_eta);
        (-(tau * 2.0 / mu)).exp() * (mu * mu_c.one_minus() * s * fresnel * weight * 4.0)
    }
}

shading_fn! {
    /// One Gauss–Legendre node of E_esc(τ) on μ ∈ [μc, 1] with μ = μc + (1 − μc) s²:
    /// 2μ e^{−τ/μ} (1 − F_int(μ)) · 2(1 − μc) s · w.
    pub fn slab_escape_node(mu_c: S, inv_eta: S, tau: V, s: S, weight: S) -> V {
        let mu = mu_c + mu_c.one_minus() * s * s;
        let fresnel = fr_dielectric(mu, inv_eta);
        (-(tau / mu)).exp() * (mu * mu_c.one_minus() * s * fresnel.one_minus() * weight * 4.0)
    }
}

shading_fn! {
    /// One Gauss–Legendre node (μ = μc + (1 − μc) s², as in `slab_escape_node`) of
    /// Q = ∫ 2μ (1 − F_int(μ)) q(1 − μ) dμ over the escape cone, q the quartic of `e_fon`
    /// (E_FON = (1 + r q)/(1 + c₁ r)).
    pub fn eon_escape_node(mu_c: S, inv_eta: S, s: S, weight: S) -> S {
        let mu = mu_c + mu_c.one_minus() * s * s;
        let x = mu.one_minus();
        let q = x * (x * (x * (x * 0.071_442_99 - 0.332_181_44) + 0.491_881_87) + 0.057_108_53);
        mu * mu_c.one_minus() * s * fr_dielectric(mu, inv_eta).one_minus() * weight * q * 4.0
    }
}

shading_fn! {
    /// glazec: how much more of EON's multiple-scattering lobe leaves a smooth coat (relative IOR η)
    /// through the escape cone than of diffuse light,
    /// s = (c₁ E_esc(0) − Q)/((c₁ − c₂) E_esc(0)), Q and E_esc(0) by 12-point Gauss–Legendre
    /// quadrature over the cone. Guard: E_esc(0) ≥ 10⁻⁶.
    ///
    /// That lobe sends light in proportion to 1 − E_FON(μ) = r (c₁ − q(1 − μ))/(1 + c₁ r), so the
    /// ratio s = ∫ 2μ (1 − F_int)(1 − E_FON) dμ / ((1 − E_avg) E_esc(0)) does not depend on r.
    /// `glazec tables` tabulates it over η (`eon_escape_shape` looks it up).
    pub fn eon_escape_shape_exact(eta: S) -> S {
        let q = eon_escape_q(eta);
        let escape = slab_escape(eta, eta.lit(0.0).splat()).x();
        (escape * FON_C1 - q) / (escape.at_least(1e-6) * (FON_C1 - FON_C2))
    }
}

shading_fn! {
    /// The slab's internal return reflectance R(τ) = ∫₀¹ 2μ e^{−2τ/μ} F_int(μ) dμ (docs/derivations.md,
    /// "Smooth coat over Lambert"), by 24-point Gauss–Legendre quadrature.
    ///
    /// The share of diffuse light going up inside a coat (η, optical depth τ) that comes back down,
    /// through absorption twice and Fresnel (with TIR) at the top. Folded to a constant when η and τ
    /// are literals.
    pub fn slab_return(eta: S, tau: V) -> V {
        slab_integral(eta, tau, SlabIntegral::Return)
    }
}

shading_fn! {
    /// The slab's escape albedo E_esc(τ) = ∫₀¹ 2μ e^{−τ/μ} (1 − F_int(μ)) dμ: the share of
    /// diffuse light leaving the base that escapes through the coat (docs/derivations.md, "Smooth
    /// coat over Lambert"). Gauss–Legendre quadrature; folded to a constant when η and τ are
    /// literals.
    pub fn slab_escape(eta: S, tau: V) -> V {
        slab_integral(eta, tau, SlabIntegral::Escape)
    }
}

/// The cosine μc = √(1 − 1/η²) of a coat's escape cone seen from inside (0 without TIR, η ≤ 1).
pub fn escape_cone_cosine<F: Real>(eta: F) -> F {
    eta.sq().recip().one_minus().at_least(0.0).sqrt()
}

/// Which slab integral [`slab_integral`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlabIntegral {
    /// R(τ) = ∫₀¹ 2μ e^{−2τ/μ} F_int(μ) dμ.
    Return,
    /// E_esc(τ) = ∫₀¹ 2μ e^{−τ/μ} (1 − F_int(μ)) dμ.
    Escape,
}

/// The hemispherical integrals of a coat's slab seen from inside (docs/derivations.md, "Smooth
/// coat over Lambert"), by Gauss–Legendre quadrature in two pieces (one node per call of
/// [`slab_tir_node`], [`slab_return_node`] or [`slab_escape_node`]), each with a substitution that
/// makes its integrand smooth:
///
/// * the TIR cone μ ∈ [0, μc] (μc = √(1 − 1/η²), where F_int = 1), with μ = μc t²: it clusters
///   nodes near μ = 0, where e^{−2τ/μ} rises steeply for small τ;
/// * μ ∈ [μc, 1] with μ = μc + (1 − μc) s²: Fresnel behaves like √(μ − μc) at the critical
///   angle, which is linear in s.
///
/// 12 + 12 nodes give an absolute error below 10⁻⁶ for η ∈ (1, 3] and all τ ≥ 0 (measured
/// against adaptive quadrature in the tests). For η ≤ 1 there is no TIR cone (μc = 0).
pub fn slab_integral<F: Real>(eta: F, tau: F::Vec, which: SlabIntegral) -> F::Vec {
    let mu_c = escape_cone_cosine(eta).named("mu_c");
    let inv_eta = eta.recip().named("inv_eta");
    let mut sum = eta.lit(0.0).splat();
    if which == SlabIntegral::Return {
        for (t, w) in GAUSS_LEGENDRE_12 {
            sum = sum + slab_tir_node(mu_c, tau, mu_c.lit(t as f32), mu_c.lit(w as f32)).named("node");
        }
    }
    for (s, w) in GAUSS_LEGENDRE_12 {
        let (s, w) = (mu_c.lit(s as f32), mu_c.lit(w as f32));
        let node = match which {
            SlabIntegral::Return => slab_return_node(mu_c, inv_eta, tau, s, w),
            SlabIntegral::Escape => slab_escape_node(mu_c, inv_eta, tau, s, w),
        };
        sum = sum + node.named("node");
    }
    sum
}

/// How the absorbing slabs under a coat (relative IOR `eta`) treat the light the coat returns
/// and the light that escapes through it, against diffuse light: (c_r, c_e) =
/// ((N/M)/(P/Q)², (N_e/M_e)/(P/Q)). N/M is the mean of a(μ)² over the light the coat returns
/// (weighted by its internal reflectance F(μ), total beyond its escape cone), N_e/M_e the mean
/// of a(μ) over the light it lets out (1 − F(μ)), and P/Q the mean of a(μ) over diffuse light;
/// a(μ) = e^{−Σ τⱼ/μⱼ} along the refracted cosines μⱼ in the slabs `below` (each its relative
/// IOR and optical depth, from the top; a slab beyond a critical angle is not reached), all
/// weighted by the transmission T′(μ) of the first interface below. The coat returns light
/// mostly beyond its escape cone, which crosses the slabs below obliquely, and lets out light
/// near the normal, which crosses them steeply; the light the layer below sends up was chosen
/// by the same obliquity on its way. The series of the coat above takes the layer's albedo,
/// whose absorption is that of diffuse light, so its return is scaled by c_r ≤ 1 and what
/// escapes by c_e ≥ 1 (both 1 for clear slabs). Under an index-matched layer (η′ = 1) over a
/// body both are exact: c_r·R(0)·E_esc′(τ)² is the absorbing slab's own return R(τ), and
/// c_e·E_esc(0)·E_esc′(τ) its own escape E_esc(τ). Rough interfaces take the smooth ones'
/// Fresnel factors and Snell's directions here (checked against the reference on `four_layer`
/// and the multi-coat set, not derived for them). By [`slab_integral`]'s substitutions on the
/// coat's cone and beyond it, three panels of 4-point Gauss–Legendre on each, as one loop in a
/// shader ([`Real::sum_over`], folded to constants for literal arguments, and on the CPU summed
/// once per material: unrolled, the deep tier's random stacks with runtime parameters ran for
/// over 20 minutes instead of 2). Its sums are named by `name` (`selection_node`,
/// `selection_returned`, …). Guards: the sums ≥ 10⁻⁶, μⱼ ≥ 10⁻⁴.
pub fn selected_absorption<F: Real>(eta: F, below: &[(F, F::Vec)], name: &dyn Fn(&str) -> String) -> (F::Vec, F::Vec) {
    let mu_c = escape_cone_cosine(eta);
    let inv_eta = eta.recip();
    let zero = eta.lit(0.0);
    let Some(&(eta_first, _)) = below.first() else { return (eta.lit(1.0).splat(), eta.lit(1.0).splat()) };
    let fold = eta.known().is_some() && below.iter().all(|(e, tau)| e.known().is_some() && tau.is_known());
    let index = name("selection_node");
    let totals =
        [name("selection_returned"), name("selection_escaped"), name("selection_diffuse"), name("selection_weights")];
    let totals: Vec<&str> = totals.iter().map(String::as_str).collect();
    // On the CPU the sums are kept under their inputs, as numbers: one material's are summed once.
    let number = |x: F| x.known().unwrap_or(f32::NAN);
    let key: Vec<f32> = if F::IMMEDIATE {
        std::iter::once(number(eta))
            .chain(below.iter().flat_map(|&(e, tau)| [number(e), number(tau.x()), number(tau.y()), number(tau.z())]))
            .collect()
    } else {
        Vec::new()
    };
    let count = 2 * SELECTION_PANELS * GAUSS_LEGENDRE_4.len() as u32;
    let sum = Sum { count, index: &index, totals: &totals, fold, key: &key };
    let sums = F::sum_over(eta.ctx(), &sum, &|i| {
        // Node i: the part beyond the escape cone (μ = μc t²) for i < 12, else the cone
        // (μ = μc + (1 − μc) s²); in each, panel ⌊j/4⌋ of three and Gauss–Legendre node j mod 4.
        let in_cone = (i * (1.0 / 12.0)).floor();
        let j = i - in_cone * 12.0;
        let panel = (j * 0.25).floor();
        let (x, w) = gauss_legendre_4_at(j - panel * 4.0);
        let x = (panel + x) * (1.0 / 3.0);
        let beyond = in_cone.lt_lit(0.5);
        let mu = F::select(beyond, mu_c * x * x, mu_c + mu_c.one_minus() * x * x);
        let fresnel = F::select(beyond, eta.lit(1.0), fr_dielectric(mu, inv_eta));
        let weight = F::select(beyond, mu_c, mu_c.one_minus()) * x * w * mu * fr_dielectric(mu, eta_first).one_minus();
        // Σ τⱼ/μⱼ down the slabs the light reaches: sin²θ falls by the relative IOR at each.
        let (mut sin2, mut depth, mut reached) = (mu.sq().one_minus(), zero.splat(), mu.lit(1.0));
        for &(eta_j, tau_j) in below {
            sin2 = sin2 / eta_j.sq();
            reached = F::select(sin2.lt_lit(1.0), reached, zero);
            let mu_j = sin2.one_minus().at_least(1e-8).sqrt().at_least(1e-4);
            depth = depth + tau_j * (reached / mu_j);
        }
        let a = (-depth).exp();
        let (returned, escaped) = (weight * fresnel, weight * fresnel.one_minus());
        vec![a * a * returned, a * escaped, a * weight, F::vec3(returned, escaped, weight)]
    });
    let [n, n_e, p, weights] = [sums[0], sums[1], sums[2], sums[3]];
    let diffuse = (p / weights.z().at_least(1e-6)).max(eta.lit(1e-6).splat());
    let returned = n / weights.x().at_least(1e-6) / (diffuse * diffuse);
    let escaped = n_e / weights.y().at_least(1e-6) / diffuse;
    (returned, escaped)
}

/// Panels of [`selected_absorption`]'s quadrature on each of its two parts.
const SELECTION_PANELS: u32 = 3;

/// The smooth rest ∫ (p − h) du of `trapped_escape` over the cone, u = μc² + d, d ∈ [0, 1 − μc²]:
/// the trapped share p (`trapped_share`) minus its edge profile h(d) = ½(1 − d/√(w² + d²)),
/// by 4-point Gauss–Legendre quadrature.
pub fn trapped_rest<F: Real>(mu_c: F, alpha: F, w: F) -> F {
    let c2 = mu_c.sq();
    let width = c2.one_minus();
    let mut sum = mu_c.lit(0.0);
    for (x, weight) in GAUSS_LEGENDRE_4 {
        let d = width * x;
        let p = trapped_share((c2 + d).sqrt(), mu_c, alpha);
        let h = (d / (w.sq() + d.sq()).sqrt()).one_minus() * 0.5;
        sum = sum + (p - h).named("node") * weight;
    }
    sum * width
}

/// Q of `eon_escape_shape`: the integral over the escape cone of a smooth interface of
/// relative IOR `eta`, with the nodes of [`slab_integral`] (no TIR part: nothing escapes there).
pub fn eon_escape_q<F: Real>(eta: F) -> F {
    let mu_c = escape_cone_cosine(eta).named("mu_c");
    let inv_eta = eta.recip().named("inv_eta");
    let mut q = eta.lit(0.0);
    for (s, w) in GAUSS_LEGENDRE_12 {
        q = q + eon_escape_node(mu_c, inv_eta, mu_c.lit(s as f32), mu_c.lit(w as f32)).named("node");
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::reference::adaptive_simpson;
    use glam::Vec3;

    fn fresnel_inside(mu: f64, eta: f64) -> f64 {
        let e = 1.0 / eta;
        let sin2_t = (1.0 - mu * mu) / (e * e);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        let ct = (1.0 - sin2_t).sqrt();
        let rs = (mu - e * ct) / (mu + e * ct);
        let rp = (e * mu - ct) / (e * mu + ct);
        0.5 * (rs * rs + rp * rp)
    }

    /// Largest absolute quadrature error tolerated for the slab integrals.
    const SLAB_ABS_TOLERANCE: f64 = 2e-6;

    #[test]
    fn slab_integrals_match_adaptive_quadrature() {
        for eta in [0.8_f64, 1.2, 1.33, 1.5, 2.0, 3.0] {
            for tau in [0.0_f64, 1e-3, 0.01, 0.05, 0.25, 1.0, 4.0] {
                let mu_c = (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt();
                let ret = |mu: f64| 2.0 * mu * (-2.0 * tau / mu.max(1e-300)).exp() * fresnel_inside(mu, eta);
                let esc = |mu: f64| 2.0 * mu * (-tau / mu.max(1e-300)).exp() * (1.0 - fresnel_inside(mu, eta));
                let r_ref = adaptive_simpson(&ret, 0.0, mu_c, 1e-12, 40) + adaptive_simpson(&ret, mu_c, 1.0, 1e-12, 40);
                let e_ref = adaptive_simpson(&esc, mu_c, 1.0, 1e-12, 40);
                let r = slab_integral(eta as f32, Vec3::splat(tau as f32), SlabIntegral::Return).x as f64;
                let e = slab_integral(eta as f32, Vec3::splat(tau as f32), SlabIntegral::Escape).x as f64;
                assert!((r - r_ref).abs() < SLAB_ABS_TOLERANCE, "R eta {eta} tau {tau}: {r} vs {r_ref}");
                assert!((e - e_ref).abs() < SLAB_ABS_TOLERANCE, "E eta {eta} tau {tau}: {e} vs {e_ref}");
            }
        }
    }

    /// Largest relative difference tolerated between the same integral by two quadrature rules
    /// (`selected_absorption`'s panels against `slab_integral`'s 12-point rule), in f32.
    const RULES_REL_TOLERANCE: f32 = 1e-4;

    #[test]
    fn selected_absorption_is_exact_under_an_index_matched_layer() {
        for eta in [1.2_f32, 1.5, 2.0] {
            let r_clear = slab_integral(eta, Vec3::ZERO, SlabIntegral::Return).x;
            let e_clear = slab_integral(eta, Vec3::ZERO, SlabIntegral::Escape).x;
            for tau in [0.0_f32, 0.05, 0.36, 1.0, 3.0] {
                let tau = Vec3::splat(tau);
                let (c_r, c_e) = selected_absorption(eta, &[(1.0, tau)], &|b: &str| b.to_string());
                let r = slab_integral(eta, tau, SlabIntegral::Return).x;
                let e = slab_integral(eta, tau, SlabIntegral::Escape).x;
                let e_below = slab_integral(1.0, tau, SlabIntegral::Escape).x;
                let series = c_r.x * r_clear * e_below * e_below;
                let escape = c_e.x * e_clear * e_below;
                assert!(
                    (series - r).abs() <= RULES_REL_TOLERANCE * r.max(1e-6),
                    "η {eta} τ {tau}: {series} vs R(τ) {r}"
                );
                assert!(
                    (escape - e).abs() <= RULES_REL_TOLERANCE * e.max(1e-6),
                    "η {eta} τ {tau}: {escape} vs E(τ) {e}"
                );
                assert!(c_r.x <= 1.0 + RULES_REL_TOLERANCE && c_e.x >= 1.0 - RULES_REL_TOLERANCE, "η {eta} τ {tau}");
            }
        }
        // Clear slabs below: no change; absorbing ones under a real interface: less returned.
        let (c_r, c_e) =
            selected_absorption(1.5_f32, &[(1.3, Vec3::ZERO), (1.2, Vec3::ZERO)], &|b: &str| b.to_string());
        assert!((c_r.x - 1.0).abs() < 1e-6 && (c_e.x - 1.0).abs() < 1e-6);
        let (c_r, c_e) =
            selected_absorption(1.5_f32, &[(1.3, Vec3::ZERO), (1.2, Vec3::splat(0.5))], &|b: &str| b.to_string());
        assert!(c_r.x < 1.0 && c_r.x > 0.5 && c_e.x > 1.0, "{c_r} {c_e}");
    }

    #[test]
    fn clear_slab_identity() {
        // 1 − E_F = η²(1 − K): with τ = 0, η² E_esc + (1 − η² E_esc) = 1 and K = 1 − E_esc.
        let e = slab_integral(1.5_f32, Vec3::ZERO, SlabIntegral::Escape).x;
        let r = slab_integral(1.5_f32, Vec3::ZERO, SlabIntegral::Return).x;
        assert!((e + r - 1.0).abs() < 1e-6, "E_esc + K = {}", e + r);
        // K(1.5) = 0.59635 (docs/derivations.md, "Invariants").
        assert!((r - 0.596_35).abs() < 1e-4, "K = {r}");
    }
}
