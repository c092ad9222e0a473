//! The BRDF terms, each written once (see the [module essay](super)).
//!
//! Every term cites its source on the first line of its doc comment (which is also copied above
//! the function in the generated shaders), and documents its numerical guards where they sit.
//! Cosine arguments are expected to be clamped by the caller where they divide (see
//! [`super::layering::COS_EPSILON`]); terms clamp only what they introduce themselves.

use std::f32::consts::PI;

use super::Vector;

use crate::shading_fn;

/// Smallest GGX / GTR1 α. Below it a microfacet lobe is a mirror for all practical purposes
/// (pbrt-v4's `EffectivelySmooth` threshold); clamping keeps D finite at n·h = 1, where its peak
/// value 1/(πα²) ≈ 3.2·10⁵ is still representable in f32.
pub const ALPHA_MIN: f32 = 1e-3;

/// Roughness above which GTR1's α²−1 → 0 and ln α² → 0 cancel badly; the limit there is D = 1/π.
const GTR1_ALPHA_MAX: f32 = 0.9999;

/// Largest Schlick F0 accepted when converting F0 back to an IOR (η = (1+√F0)/(1−√F0) → ∞ at 1).
const F0_MAX: f32 = 0.9999;

/// Smallest argument of a square root or reciprocal that would otherwise hit 0 at grazing angles.
const TINY: f32 = 1e-12;

shading_fn! {
    /// Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 33
    /// (seed 000 eq. 6): the GGX / Trowbridge–Reitz normal distribution
    /// D(h) = α² / (π ((n·h)²(α² − 1) + 1)²), with the denominator written as
    /// α² cos²θh + sin²θh and sin²θh = |n × h|² passed in (Filament's `D_GGX` does the same):
    /// 1 − (n·h)² cancels catastrophically in f32 at the peak of a sharp lobe.
    /// Guards: α ≥ ALPHA_MIN = 10⁻³ keeps the peak finite; the denominator ≥ TINY covers a
    /// zero half vector (two zero directions under total internal reflection), where it would
    /// be 0 — for a unit h it is never below α² ≥ 10⁻⁶.
    pub fn d_ggx(cos_h: S, sin2_h: S, alpha: S) -> S {
        let a = alpha.at_least(ALPHA_MIN);
        let a_sq = a * a;
        let denom = (cos_h * cos_h * a_sq + sin2_h).at_least(TINY);
        a_sq / (denom * denom * PI)
    }
}

shading_fn! {
    /// Burley 2012, "Physically-Based Shading at Disney", App. B, GTR with γ = 1 (seed 000
    /// eq. 10): the clear-coat distribution D = (α² − 1) / (π ln α² (1 + (α² − 1) cos²θh)), with
    /// 1 + (α² − 1) cos²θh written as α² cos²θh + sin²θh (as in `d_ggx`).
    /// Guards: α ≥ ALPHA_MIN = 10⁻³ (ln 0); at α → 1 the 0/0 limit 1/π is taken directly; the
    /// bracket ≥ TINY for a zero half vector, as in `d_ggx`.
    pub fn d_gtr1(cos_h: S, sin2_h: S, alpha: S) -> S {
        let a = alpha.clamp(ALPHA_MIN, GTR1_ALPHA_MAX);
        let a_sq = a * a;
        let d = (a_sq - 1.0) / (a_sq.ln() * (cos_h * cos_h * a_sq + sin2_h).at_least(TINY) * PI);
        F::select(alpha.gt_lit(GTR1_ALPHA_MAX), alpha.lit(1.0 / PI), d)
    }
}

shading_fn! {
    /// Schlick 1994 as used by Karis 2013, "Real Shading in Unreal Engine 4" (seed 000 eq. 7):
    /// the Schlick-GGX masking term G1 = n·x / ((n·x)(1 − k) + k).
    pub fn g1_schlick_ggx(n_dot_x: S, k: S) -> S {
        n_dot_x / (n_dot_x * k.one_minus() + k)
    }
}

shading_fn! {
    /// Karis 2013 with Burley's remapping (seed 000 eq. 8–9): Smith's separable product of two
    /// Schlick-GGX terms with k = (roughness + 1)² / 8.
    pub fn g_smith_schlick_ggx(n_dot_v: S, n_dot_l: S, roughness: S) -> S {
        let k = (roughness + 1.0).sq() / 8.0;
        g1_schlick_ggx(n_dot_v, k) * g1_schlick_ggx(n_dot_l, k)
    }
}

shading_fn! {
    /// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
    /// eq. 72: the GGX Smith auxiliary function Λ(μ) = (√(1 + α² tan²θ) − 1) / 2.
    /// Guard: μ² ≥ TINY (the caller clamps μ; this keeps the division defined at μ = 0).
    pub fn lambda_ggx(n_dot_x: S, alpha: S) -> S {
        let mu_sq = (n_dot_x * n_dot_x).at_least(TINY);
        let tan_sq = mu_sq.one_minus() / mu_sq;
        ((alpha * alpha * tan_sq + 1.0).sqrt() - 1.0) * 0.5
    }
}

shading_fn! {
    /// Heitz 2014, eq. 99: the exact height-correlated Smith masking-shadowing for GGX,
    /// G2 = 1 / (1 + Λ(v) + Λ(l)).
    pub fn g_smith_ggx_correlated(n_dot_v: S, n_dot_l: S, alpha: S) -> S {
        let alpha = alpha.at_least(ALPHA_MIN);
        (lambda_ggx(n_dot_v, alpha) + lambda_ggx(n_dot_l, alpha) + 1.0).recip()
    }
}

shading_fn! {
    /// Cook & Torrance 1982 (seed 000 eq. 4): the microfacet reflection f = D G F / (4 (n·l)(n·v)).
    /// The caller passes cosines clamped to ≥ COS_EPSILON.
    pub fn f_cook_torrance(d: S, g: S, fresnel: V, n_dot_v: S, n_dot_l: S) -> V {
        fresnel * (d * g / (n_dot_v * n_dot_l * 4.0))
    }
}

shading_fn! {
    /// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering" (seed 000 eq. 5):
    /// F(θ) = F0 + (1 − F0)(1 − cos θ)⁵.
    pub fn f_schlick(f0: V, cos_theta: S) -> V {
        let m = cos_theta.clamp(0.0, 1.0).one_minus();
        let m_sq = m * m;
        f0 + f0.one_minus() * (m_sq * m_sq * m)
    }
}

shading_fn! {
    /// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 15, for one
    /// scalar reflectance (a dielectric's): F = F0 + (1 − F0)(1 − cos θ)⁵.
    pub fn f_schlick_scalar(f0: S, cos_theta: S) -> S {
        let m = cos_theta.one_minus();
        let m_sq = m * m;
        f0 + f0.one_minus() * (m_sq * m_sq * m)
    }
}

shading_fn! {
    /// Schlick 1994 eq. 15 for a dielectric interface of relative IOR η from either side: the
    /// cosine in the power term must be the one in the optically thinner medium, so for η < 1
    /// it is the refracted cosine √(1 − (1 − cos²θ)/η²), and beyond the critical angle the
    /// reflectance is 1 (total internal reflection; the rejected branch is then NaN).
    pub fn fr_dielectric_schlick(cos_i: S, eta: S) -> S {
        let cos_i = cos_i.clamp(0.0, 1.0);
        let sin2_t = cos_i.sq().one_minus() / (eta * eta);
        let cos_t = sin2_t.one_minus().at_least(0.0).sqrt();
        let cos_thin = F::select(eta.lt_lit(1.0), cos_t, cos_i);
        let f0 = ((eta - 1.0) / (eta + 1.0)).sq();
        let m = cos_thin.one_minus();
        let m_sq = m * m;
        let schlick = f0 + f0.one_minus() * (m_sq * m_sq * m);
        F::select(sin2_t.lt_lit(1.0), schlick, cos_i.lit(1.0))
    }
}

shading_fn! {
    /// The normal-incidence reflectance of a dielectric interface, F0 = ((η − 1)/(η + 1))².
    pub fn f0_dielectric(eta: S) -> S {
        ((eta - 1.0) / (eta + 1.0)).sq()
    }
}

shading_fn! {
    /// Fresnel equations for an unpolarised dielectric interface (Born & Wolf 1999; pbrt-v4
    /// `FrDielectric`). `cos_i` ≥ 0 on the incident side; `eta` = n_transmitted / n_incident.
    /// Total internal reflection (sin²θt ≥ 1) returns 1; the other branch is then NaN and
    /// rejected by the select.
    pub fn fr_dielectric(cos_i: S, eta: S) -> S {
        let cos_i = cos_i.clamp(0.0, 1.0);
        let sin2_t = cos_i.sq().one_minus() / (eta * eta);
        let cos_t = sin2_t.one_minus().at_least(0.0).sqrt();
        let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
        let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
        let fresnel = (r_parl * r_parl + r_perp * r_perp) * 0.5;
        F::select(sin2_t.lt_lit(1.0), fresnel, cos_i.lit(1.0))
    }
}

shading_fn! {
    /// Fresnel reflectance of a conductor with complex IOR η + iκ, unpolarised, per channel
    /// (Born & Wolf 1999; the closed form of pbrt-v3 `FrConductor`). `eta`, `k` are relative to
    /// the medium above.
    pub fn fr_conductor(cos_i: S, eta: V, k: V) -> V {
        let cos2 = cos_i.clamp(0.0, 1.0).sq();
        let sin2 = cos2.one_minus();
        let eta2 = eta * eta;
        let k2 = k * k;
        let t0 = eta2 - k2 - sin2.splat();
        let a2_plus_b2 = (t0 * t0 + eta2 * k2 * 4.0).sqrt();
        let t1 = a2_plus_b2 + cos2.splat();
        let a = ((a2_plus_b2 + t0) * 0.5).sqrt();
        let t2 = a * (cos2.sqrt() * 2.0);
        let r_s = (t1 - t2) / (t1 + t2);
        let t3 = a2_plus_b2 * cos2 + (sin2 * sin2).splat();
        let t4 = t2 * sin2;
        let r_p = r_s * (t3 - t4) / (t3 + t4);
        (r_p + r_s) * 0.5
    }
}

shading_fn! {
    /// Re-expresses a conductor's F0 (given against air) for a base that sits in a medium of
    /// absolute index `n_medium`: F0 → η = (1+√F0)/(1−√F0) → η/n → F0′ (the approach of
    /// Filament's `f0ClearCoatToSurface`, generalised from n = 1.5). Guard: F0 ≤ F0_MAX.
    pub fn f0_under_medium(f0: V, n_medium: S) -> V {
        let s = f0.min(n_medium.lit(F0_MAX).splat()).sqrt();
        let eta = (s + n_medium.lit(1.0).splat()) / s.one_minus() / n_medium;
        let r = (eta - n_medium.lit(1.0).splat()) / (eta + n_medium.lit(1.0).splat());
        r * r
    }
}

shading_fn! {
    /// Lambert 1760: the ideal diffuse BRDF f = ρ/π.
    pub fn fd_lambert(albedo: V) -> V {
        albedo * (1.0 / PI)
    }
}

shading_fn! {
    /// Oren & Nayar 1994, "Generalization of Lambert's Reflectance Model", the qualitative model
    /// (seed 000 eq. 17): f = ρ/π (A + B max(0, cos Δφ) sin α tan β), α = max(θi, θr),
    /// β = min(θi, θr). Written without trigonometry: since sin θi sin θo cos Δφ = l·v − μi μo
    /// and sin α tan β = sin θi sin θo / max(μi, μo), the B term is B max(0, s) / max(μi, μo)
    /// with s = l·v − μi μo (the form of Fujii 2013). σ is in radians.
    pub fn fd_oren_nayar(albedo: V, sigma: S, n_dot_v: S, n_dot_l: S, v_dot_l: S) -> V {
        let sigma_sq = sigma * sigma;
        let a = (sigma_sq / (sigma_sq + 0.33) * 0.5).one_minus();
        let b = sigma_sq / (sigma_sq + 0.09) * 0.45;
        let s = v_dot_l - n_dot_v * n_dot_l;
        let s_over_t = s.at_least(0.0) / n_dot_v.max(n_dot_l);
        albedo * ((b * s_over_t + a) / PI)
    }
}

/// Fujii's FON constant c1 = 1/2 − 2/(3π) (EON listing, `constant1_FON`).
const FON_C1: f32 = 0.5 - 2.0 / (3.0 * PI);
/// Average FON albedo coefficient c2 = 2/3 − 28/(15π) (EON listing, `constant2_FON`).
const FON_C2: f32 = 2.0 / 3.0 - 28.0 / (15.0 * PI);
/// Average albedo coefficient of the qualitative Oren–Nayar B term: ⟨E⟩ = ρ(A + c B) with
/// c = 2/3 − 64/(45π). It is FON's c2 plus 4/(9π), the share of the s < 0 half that QON clamps
/// to zero; checked against numerical quadrature (0.213959273) in the tests.
pub const QON_AVG_B: f32 = 2.0 / 3.0 - 64.0 / (45.0 * PI);

shading_fn! {
    /// Portsmouth, Kutz & Hill 2025, "EON: A practical energy-preserving rough diffuse BRDF"
    /// (JCGT 14(1); arXiv 2410.18026), Listing 1 `E_FON_approx`: the directional albedo of the
    /// Fujii Oren–Nayar lobe at ρ = 1, a quartic in 1 − μ (max error 4.7·10⁻⁴).
    pub fn e_fon(mu: S, r: S) -> S {
        let x = mu.clamp(0.0, 1.0).one_minus();
        let g_over_pi = x * (x * (x * (x * 0.071_442_99 - 0.332_181_44) + 0.491_881_87) + 0.057_108_53);
        (r * g_over_pi + 1.0) / (r * FON_C1 + 1.0)
    }
}

shading_fn! {
    /// Portsmouth, Kutz & Hill 2025, Listing 1 `f_EON`: Fujii's Oren–Nayar single-scattering lobe
    /// plus the analytic multiple-scattering compensation that makes it energy-preserving.
    /// Guard: the ε = 10⁻⁷ of the listing on 1 − E terms.
    pub fn fd_eon(albedo: V, r: S, n_dot_v: S, n_dot_l: S, v_dot_l: S) -> V {
        let s = v_dot_l - n_dot_v * n_dot_l;
        let s_over_t = F::select(s.gt_lit(0.0), s / n_dot_v.max(n_dot_l), s);
        let a_f = (r * FON_C1 + 1.0).recip();
        let f_ss = albedo * (a_f * (r * s_over_t + 1.0) / PI);
        let e_o = e_fon(n_dot_v, r);
        let e_i = e_fon(n_dot_l, r);
        let e_avg = a_f * (r * FON_C2 + 1.0);
        let rho_ms = eon_rho_ms(albedo, r);
        let f_ms = rho_ms * (e_o.one_minus().at_least(1e-7) * e_i.one_minus().at_least(1e-7)
            / (e_avg.one_minus().at_least(1e-7) * PI));
        f_ss + f_ms
    }
}

shading_fn! {
    /// Hemispherical-average albedo ⟨E⟩ of the qualitative Oren–Nayar lobe (Oren & Nayar 1994):
    /// ρ (A + c B), c = 2/3 − 64/(45π), from integrating the B term over both hemispheres.
    pub fn albedo_avg_oren_nayar(albedo: V, sigma: S) -> V {
        let sigma_sq = sigma * sigma;
        let a = (sigma_sq / (sigma_sq + 0.33) * 0.5).one_minus();
        let b = sigma_sq / (sigma_sq + 0.09) * 0.45;
        albedo * (b * QON_AVG_B + a)
    }
}

shading_fn! {
    /// Portsmouth, Kutz & Hill 2025, Listing 1 `E_EON` averaged over the hemisphere:
    /// ⟨E⟩ = ρ⟨E_F⟩ + ρ_ms (1 − ⟨E_F⟩) with ⟨E_F⟩ = A_F (1 + c2 r).
    pub fn albedo_avg_eon(albedo: V, r: S) -> V {
        let e_avg = (r * FON_C2 + 1.0) / (r * FON_C1 + 1.0);
        let rho_ms = eon_rho_ms(albedo, r);
        albedo * e_avg + rho_ms * e_avg.one_minus()
    }
}

shading_fn! {
    /// Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks": the hemispherical
    /// average of Schlick's Fresnel, F_avg = F0 + (1 − F0)/21. Used as a conductor's mean albedo
    /// (an approximation that ignores the lobe's single-scattering loss).
    pub fn albedo_avg_conductor(f0: V) -> V {
        f0 + f0.one_minus() * (1.0 / 21.0)
    }
}

shading_fn! {
    /// Snell's law at a horizontal interface: the direction `w` (pointing away from the surface,
    /// above it) continued into a layer of relative IOR `eta` below, again pointing up and away:
    /// −refract(−w, n, 1/η). On total internal reflection (only possible for η < 1) it is the
    /// zero vector, whose cosine 0 makes every transmission factor 0.
    pub fn refract_down(w: V, n: V, eta: S) -> V {
        -((-w).refract(n, eta.recip()))
    }
}

shading_fn! {
    /// The microfacet half vector h = (v + l)/|v + l| (Torrance & Sparrow 1967).
    /// Guard: |v + l|² ≥ TINY. Under total internal reflection a refracted direction is the zero
    /// vector, and both can be; h is then 0 rather than NaN (its lobe is multiplied by zero
    /// transmission anyway).
    pub fn half_vector(v: V, l: V) -> V {
        let sum = v + l;
        sum / sum.dot(sum).at_least(TINY).sqrt()
    }
}

shading_fn! {
    /// Beer–Lambert transmittance of a slab with optical depth τ (per channel) along a direction
    /// with cosine μ: e^{−τ/μ}. Guard: μ ≥ COS_EPSILON (the caller's clamp) keeps τ/μ finite.
    pub fn slab_transmittance(tau: V, mu: S) -> V {
        (-(tau / mu)).exp()
    }
}

shading_fn! {
    /// Weidlich & Wilkie 2007 (seed 000 eq. 14–15): the absorption a = e^{−α l} along the path
    /// l = d (1/(n·l′) + 1/(n·v′)) through a layer of density `thickness`.
    pub fn absorption_ww(sigma_a: V, thickness: S, n_dot_l1: S, n_dot_v1: S) -> V {
        let path = thickness * (n_dot_l1.recip() + n_dot_v1.recip());
        (-(sigma_a * path)).exp()
    }
}

shading_fn! {
    /// Weidlich & Wilkie 2007 via seed 000 §3.0.3: the internal-reflection term
    /// t = (1 − G) + T21·G, with T21 = T12.
    pub fn ww_inner_reflection(g: S, t21: V) -> V {
        t21 * g + g.one_minus().splat()
    }
}

shading_fn! {
    /// Weidlich & Wilkie 2007 (seed 000 eq. 13): one step of the recurrence,
    /// f = f_r1(L, V) + T12 · f_r2(L′, V′) · a · t.
    pub fn ww_layer(f_top: V, t12: V, absorption: V, inner: V, f_below: V) -> V {
        f_top + f_below * t12 * absorption * inner
    }
}

shading_fn! {
    /// glazec's interfaced layering (research/accuracy.md §1.4 and §3.3 "M4"): the light under a
    /// coat of relative IOR η enters with transmittance Tᵢ, is attenuated on its way down and up
    /// (aᵢ, aₒ), is reflected by what lies below (`f_under`, at refracted directions), leaves
    /// with Tₒ and is compressed by 1/η² (étendue). Symmetric in i and o, so reciprocal.
    pub fn interfaced_layer(f_top: V, t_i: S, t_o: S, a_i: V, a_o: V, f_under: V, eta: S) -> V {
        f_top + f_under * a_i * a_o * (t_i * t_o / (eta * eta))
    }
}

shading_fn! {
    /// glazec's interfaced layering, a diffusing layer below a coat: the single reflection
    /// `f_below`, plus the light it reflects (directional albedos Eᵢ, Eₒ) that the coat sends
    /// back down (R, the slab's diffuse return reflectance) and that then bounces between body
    /// and coat (mean albedo ρ̄): Eᵢ Eₒ R / (π (1 − ρ̄ R)). For a Lambertian body (E = ρ̄ = ρ) the
    /// sum is ρ/(π(1 − ρR)), the exact series (research/accuracy.md §1.4).
    pub fn interfaced_diffuse_under(f_below: V, e_i: V, e_o: V, rho_below: V, r_return: V) -> V {
        f_below + e_i * e_o * r_return / ((rho_below * r_return).one_minus() * PI)
    }
}

shading_fn! {
    /// glazec's interfaced layering, a glossy body (a conductor) below a coat: light it reflects
    /// stays near the mirror direction, inside the coat's escape cone, so it returns with the
    /// coat's directional internal reflectance kᵢ = (1 − Tᵢ) aᵢ² (reciprocity of the interface)
    /// rather than the diffuse R, and the bounces keep the lobe's shape: f / (1 − √(Eᵢkᵢ Eₒkₒ)),
    /// symmetric in i and o.
    pub fn interfaced_glossy_under(f_below: V, e_i: V, k_i: V, e_o: V, k_o: V) -> V {
        f_below / (e_i * k_i * e_o * k_o).sqrt().one_minus()
    }
}

shading_fn! {
    /// glazec: the share of a GGX reflection lobe (α) around the mirror direction of a ray at
    /// cosine μ that leaves the coat's escape cone (cosine μc) and is trapped by total internal
    /// reflection. The reflected ray stays in the cone for half vectors whose in-plane tilt lies
    /// between (θ − θc)/2 and (θ + θc)/2, taken as a disc in slope space with those slopes
    /// t₁ = tan((θ − θc)/2), t₂ = tan((θ + θc)/2) as its diameter. GGX's slope density
    /// α²/(π(α² + |s|²)²) (Walter et al. 2007 eq. 33; Heitz 2014 §5.2) is the stereographic
    /// image of the uniform measure on the sphere (slopes scaled by 1/α), and stereographic
    /// projection maps discs to spherical caps, so the disc holds exactly (1 − cos β)/2 of it,
    /// β = atan(t₂/α) − atan(t₁/α): the share trapped is
    /// (1 + (α² + t₁t₂)/√((α² + t₁²)(α² + t₂²)))/2. Exact at normal incidence (ρ²/(α² + ρ²) stays
    /// in a cone of slope radius ρ); the disc is the approximation elsewhere. The tangents are
    /// written without trigonometric calls, tan(x/2) = sin x/(1 + cos x).
    /// Guards: 1 + cos(θ + θc) ≥ 10⁻⁶ (both angles at 90°), the root's argument ≥ 10⁻²⁴.
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
    /// cosine μ that lands between the coat's escape cone (cosine μc) and the horizon, trapped by
    /// total internal reflection: `trapped_share` beyond the cone minus `trapped_share` beyond
    /// the horizon (μc = 0), which the lobe loses below the horizon whatever the coat. So the
    /// share goes to 0 with the cone's width as η → 1, continuously (beyond the cone alone, it
    /// jumped from 0 at η = 1 to a third of a grazing lobe at η = 1 + 10⁻⁵).
    /// Guard: ≥ 0 (the disc approximation is not monotonic in μc to the last bit).
    pub fn glossy_trapped_share(mu: S, mu_c: S, alpha: S) -> S {
        let beyond_cone = trapped_share(mu, mu_c, alpha);
        let below_horizon = trapped_share(mu, mu_c.lit(0.0), alpha);
        (beyond_cone - below_horizon).at_least(0.0)
    }
}

shading_fn! {
    /// glazec: the share q of a pool of trapped light (uniform radiance over the trapped
    /// directions, projected solid angle π μc²) that a body reflects into the escape cone at each
    /// bounce, per unit albedo. By reciprocity the body sends light from the pool towards a cone
    /// direction o in proportion to its trapped share p(μₒ) (`trapped_share`), so
    /// q = (1/μc²) ∫ p du over the cone, u = μ² from μc² to 1 (projected solid angle). For a
    /// sharp lobe p falls from ½ to 0 within a sliver of the cone's edge that no fixed quadrature
    /// resolves, and a q too small would let a white body return more than it trapped. So the
    /// edge's half-plane profile h(d) = ½(1 − d/√(w² + d²)) (d = u − μc², w = 4 μc sin θc α: the
    /// slope x ≈ d/(4 μc sin θc) of `trapped_share` near the edge) is integrated exactly,
    /// ∫₀ᴰ h = ½(D + w − √(w² + D²)), D = 1 − μc², and only the smooth rest p − h by 4-point
    /// Gauss–Legendre quadrature.
    /// Guards: μc² ≥ 10⁻⁴; q ≤ 1.
    pub fn trapped_escape(mu_c: S, alpha: S) -> S {
        let c2 = mu_c.sq();
        let width = c2.one_minus();
        let w = mu_c * width.at_least(0.0).sqrt() * alpha * 4.0;
        let rest = super::layering::trapped_rest(mu_c, alpha, w);
        let edge = (width + w - (w.sq() + width.sq()).sqrt()) * 0.5;
        let q = (rest + edge) / c2.at_least(1e-4);
        q.min(q.lit(1.0))
    }
}

shading_fn! {
    /// glazec's interfaced layering, the light a glossy body sends outside the coat's escape
    /// cone (shares pᵢ, pₒ of its albedos Eᵢ, Eₒ): trapped by total internal reflection, it comes
    /// back with the slab's round-trip transmittance g and meets the body again, which (mean
    /// albedo ρ̄) sends a share q of it into the cone (`trapped_escape`) and keeps the rest
    /// trapped. By reciprocity the body sends Eₒpₒ/(π μc²) of trapped light (projected solid
    /// angle π μc²) towards o: Eᵢpᵢ Eₒpₒ g / (π μc² (1 − ρ̄ g (1 − q))), symmetric in i and o. Its
    /// albedo is Eᵢpᵢ g ρ̄ q/(1 − ρ̄ g (1 − q)) (taking Eₒ ≈ ρ̄ over the cone): a white body returns
    /// all trapped light.
    /// Guard: μc² ≥ 10⁻⁴ (without a cone nothing is trapped; the caller zeroes that case).
    pub fn trapped_lobe(e_i: V, p_i: S, e_o: V, p_o: S, mu_c: S, round_trip: V, rho: V, q: S) -> V {
        e_i * e_o * round_trip * (p_i * p_o / (mu_c.sq().at_least(1e-4) * PI)) / (rho * round_trip * q.one_minus()).one_minus()
    }
}

shading_fn! {
    /// glazec's glossy level (a conductor under a coat), the light trapped after the first
    /// conductor event, per unit of it, that does not leave at the second: the generating
    /// function of its events w₁γ(½, c) + w₂γ(0.8, c) + (1 − w₀ − w₁ − w₂)γ(B_s, c), γ(B, c) =
    /// c(1 − B)/(1 − Bc), for a per-event survival c (the conductor's Fresnel factor times the
    /// slab's round trip): a mixture of geometric event counts (B: the share that stays per
    /// event; w₀ the share that leaves at the second event, `glossy_once`) fitted by
    /// `glazec tables` to white walks through the reference's microsurfaces. At c = 1 it is
    /// 1 − w₀: a white conductor under a clear coat returns all of it.
    /// Guard: 1 − B_s c ≥ 10⁻⁶ (B_s < 1 by construction; c ≤ 1).
    pub fn glossy_later(next: S, quick: S, steady: S, slow: S, c: V) -> V {
        let one = c.x().lit(1.0).splat();
        let quick_rate = c * 0.5 / (one - c * 0.5);
        let steady_rate = c * 0.2 / (one - c * 0.8);
        let slow_rate = c * slow.one_minus() / (c * slow).one_minus().max(c.x().lit(1e-6).splat());
        let rest = (next + quick + steady).one_minus().at_least(0.0);
        quick_rate * quick + steady_rate * steady + slow_rate * rest
    }
}

shading_fn! {
    /// glazec's glossy level, the light that leaves near the conductor's mirror direction, per
    /// unit entering: after one event (P₁) or, trapped, after the second (share w₀ of the
    /// trapped light, one more event's survival c): P₁ + (1 − P₁) w₀ c.
    pub fn glossy_once(single: S, next: S, c: V) -> V {
        c * (single.one_minus() * next) + single.splat()
    }
}

shading_fn! {
    /// glazec's glossy level, the directional albedo of what leaves after three or more conductor
    /// events: M(μ) = T a² F (1 − P₁) Ŷ, light that enters (T), is attenuated down and up once (a²)
    /// and reflected by the conductor (F, at the refracted direction), but not let out at once
    /// (1 − P₁) or at the second event, and that its further events return (`glossy_later`).
    pub fn glossy_remainder(t: S, a: V, fresnel: V, single: S, later: V) -> V {
        a * a * fresnel * later * (t * single.one_minus())
    }
}

shading_fn! {
    /// Kulla & Conty 2017's reciprocal separable lobe for the glossy level's remainder: the light
    /// that leaves after several conductor events has forgotten where it entered, so
    /// f = M(μᵢ) M(μₒ)/(π ⟨M⟩), whose albedo is M(μₒ) exactly (⟨M⟩ = ∫ 2μ M(μ) dμ).
    /// Guard: ⟨M⟩ ≥ 10⁻⁶ (M ≡ 0 gives 0).
    pub fn glossy_remainder_lobe(m_i: V, m_o: V, m_avg: V) -> V {
        m_i * m_o / (m_avg.max(m_avg.x().lit(1e-6).splat()) * PI)
    }
}

shading_fn! {
    /// The directional albedo seen above a coat over a conductor (glazec's glossy level):
    /// (1 − T) + T F (a₁² O + a² (1 − P₁) Ŷ): the coat's reflection, the lobe of light that
    /// leaves after one or two conductor events (O, `glossy_once`; attenuated by a₁² along its
    /// own paths) and the remainder (`glossy_remainder`).
    pub fn glossy_albedo(t: S, fresnel: V, a_lobe: V, a: V, once: V, single: S, later: V) -> V {
        let near = a_lobe * a_lobe * once;
        let far = a * a * later * single.one_minus();
        fresnel * (near + far) * t + t.one_minus().splat()
    }
}

shading_fn! {
    /// The directional albedo seen above a coat over a diffusing layer (same model as
    /// `interfaced_diffuse_under`): (1 − T) + T a E_below E_esc (x + c ρ̄ R / (1 − ρ̄ R)), where x
    /// and c scale the first reflection's escape and return against diffuse light's (both 1 for
    /// a diffusing body, which gives (1 − T) + T a E_below E_esc / (1 − ρ̄ R)).
    pub fn interfaced_albedo_dir(t: S, a: V, e_below: V, rho_below: V, r_return: V, e_escape: V, first_escape: V, first_return: V) -> V {
        let series = first_return * rho_below * r_return / (rho_below * r_return).one_minus();
        a * e_below * e_escape * (first_escape + series) * t + t.one_minus().splat()
    }
}

shading_fn! {
    /// The directional albedo seen above a coat over a glossy body (same model as
    /// `interfaced_glossy_under`): (1 − T) + T² a² E_below / (1 − E_below k), k = (1 − T) a².
    pub fn interfaced_albedo_glossy(t: S, a: V, e_below: V) -> V {
        let k = a * a * t.one_minus();
        a * a * e_below * (t * t) / (e_below * k).one_minus() + t.one_minus().splat()
    }
}

shading_fn! {
    /// Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks": a reciprocal
    /// lobe carrying energy E_ms(μ) lost by a single-scattering microfacet lobe,
    /// E_ms(μᵢ) E_ms(μₒ) / (π ⟨E_ms⟩), so that its albedo at μₒ is exactly E_ms(μₒ).
    /// Guard: ⟨E_ms⟩ ≥ 10⁻⁶ (a smooth interface has none to restore).
    pub fn multiple_scattering_lobe(e_i: S, e_o: S, e_avg: S) -> S {
        e_i * e_o / (e_avg.at_least(1e-6) * PI)
    }
}

shading_fn! {
    /// The directional albedo of the energy-preserving Oren–Nayar lobe (Portsmouth, Kutz & Hill
    /// 2025, Listing 1 `E_EON`): ρ E_FON(μ) + ρ_ms (1 − E_FON(μ)).
    pub fn albedo_eon(albedo: V, r: S, mu: S) -> V {
        let e_f = e_fon(mu, r);
        let rho_ms = eon_rho_ms(albedo, r);
        albedo * e_f + rho_ms * e_f.one_minus()
    }
}

shading_fn! {
    /// The hemispherical-average albedo seen above a coat (same model as `interfaced_layer`):
    /// ⟨E⟩ = E_F + η² E_esc(τ)² ρ̄ / (1 − ρ̄ R(τ)), where E_F = 1 − η² E_esc(0) is the coat's
    /// own average Fresnel reflectance (the flux identity 1 − E_F = η²(1 − K)).
    pub fn interfaced_albedo(eta: S, e_escape_clear: S, e_escape: V, r_return: V, rho_below: V) -> V {
        let eta_sq = eta * eta;
        let e_fresnel = (eta_sq * e_escape_clear).one_minus();
        e_escape * e_escape * rho_below * eta_sq / (rho_below * r_return).one_minus() + e_fresnel.splat()
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
    /// Portsmouth, Kutz & Hill 2025, Listing 1: the albedo of EON's multiple-scattering lobe,
    /// ρ_ms = ρ² E_avg / (1 − ρ (1 − E_avg)), E_avg = (1 + c₂ r)/(1 + c₁ r).
    pub fn eon_rho_ms(albedo: V, r: S) -> V {
        let e_avg = (r * FON_C2 + 1.0) / (r * FON_C1 + 1.0);
        albedo * albedo * e_avg / (albedo * e_avg.one_minus()).one_minus()
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
    /// glazec: how much more of EON's multiple-scattering lobe leaves a smooth coat (relative
    /// IOR η) through the escape cone than of diffuse light. That lobe sends light in
    /// proportion to 1 − E_FON(μ) = r (c₁ − q(1 − μ))/(1 + c₁ r), so the ratio
    /// s = ∫ 2μ (1 − F_int)(1 − E_FON) dμ / ((1 − E_avg) E_esc(0)) = (c₁ E_esc(0) − Q)/((c₁ − c₂) E_esc(0))
    /// does not depend on r; Q and E_esc(0) by 12-point Gauss–Legendre quadrature over the cone.
    /// `glazec tables` tabulates it over η (`eon_escape_shape` looks it up). Guard: E_esc(0) ≥ 10⁻⁶.
    pub fn eon_escape_shape_exact(eta: S) -> S {
        let q = super::layering::eon_escape_q(eta);
        let escape = slab_escape(eta, eta.lit(0.0).splat()).x();
        (escape * FON_C1 - q) / (escape.at_least(1e-6) * (FON_C1 - FON_C2))
    }
}

shading_fn! {
    /// The slab's internal return reflectance R(τ) = ∫₀¹ 2μ e^{−2τ/μ} F_int(μ) dμ: the share of
    /// diffuse light going up inside a coat (η, optical depth τ) that comes back down, through
    /// absorption twice and Fresnel (with TIR) at the top (research/accuracy.md §1.4). Computed
    /// by 24-point Gauss–Legendre quadrature; folded to a constant when η and τ are literals.
    pub fn slab_return(eta: S, tau: V) -> V {
        super::layering::slab_integral(eta, tau, super::layering::SlabIntegral::Return)
    }
}

shading_fn! {
    /// The slab's escape albedo E_esc(τ) = ∫₀¹ 2μ e^{−τ/μ} (1 − F_int(μ)) dμ: the share of
    /// diffuse light leaving the base that escapes through the coat (research/accuracy.md §1.4).
    /// Gauss–Legendre quadrature; folded to a constant when η and τ are literals.
    pub fn slab_escape(eta: S, tau: V) -> V {
        super::layering::slab_integral(eta, tau, super::layering::SlabIntegral::Escape)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::reference::simpson;
    use glam::Vec3;

    #[test]
    fn ggx_d_is_normalised() {
        // ∫ D(h) (n·h) dω_h = 1 (Walter et al. 2007, eq. 4).
        for alpha in [0.05_f32, 0.2, 0.5, 1.0] {
            let integral = simpson(
                |mu| 2.0 * std::f64::consts::PI * d_ggx(mu as f32, (1.0 - mu * mu) as f32, alpha) as f64 * mu,
                0.0,
                1.0,
                20_000,
            );
            assert!((integral - 1.0).abs() < 2e-3, "alpha {alpha}: {integral}");
        }
    }

    #[test]
    fn gtr1_is_normalised_and_continuous_at_one() {
        for alpha in [0.01_f32, 0.1, 0.5] {
            let integral = simpson(
                |mu| 2.0 * std::f64::consts::PI * d_gtr1(mu as f32, (1.0 - mu * mu) as f32, alpha) as f64 * mu,
                0.0,
                1.0,
                20_000,
            );
            assert!((integral - 1.0).abs() < 2e-3, "alpha {alpha}: {integral}");
        }
        assert!((d_gtr1(0.5, 0.75, 1.0) - 1.0 / PI).abs() < 1e-6);
        assert!((d_gtr1(0.5, 0.75, 0.9998) - 1.0 / PI).abs() < 1e-3);
    }

    #[test]
    fn smith_limits() {
        // E(μ=1, α=1) = 1 − ln 2 needs the full lobe; here: G2 = 1 at normal incidence, and
        // Λ = 0 for a smooth surface.
        assert!((g_smith_ggx_correlated(1.0, 1.0, 0.5) - 1.0).abs() < 1e-6);
        assert!(lambda_ggx(0.3, 0.0).abs() < 1e-6);
        assert!((g1_schlick_ggx(1.0, 0.3) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn dielectric_fresnel() {
        assert!((fr_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((f0_dielectric(1.5) - 0.04).abs() < 1e-7);
        // Total internal reflection beyond the critical angle (sin θc = 1/1.5 from inside).
        let cos_c = (1.0_f32 - 1.0 / 2.25).sqrt();
        assert_eq!(fr_dielectric(cos_c - 0.01, 1.0 / 1.5), 1.0);
        assert!(fr_dielectric(cos_c + 0.01, 1.0 / 1.5) < 1.0);
        // Reciprocity of the interface: F(θi, η) = F(θt, 1/η).
        let cos_t = (1.0_f32 - (1.0 - 0.6 * 0.6) / 2.25).sqrt();
        assert!((fr_dielectric(0.6, 1.5) - fr_dielectric(cos_t, 1.0 / 1.5)).abs() < 1e-6);
        assert_eq!(fr_dielectric(0.0, 1.5), 1.0);
    }

    #[test]
    fn conductor_fresnel_matches_dielectric_without_extinction() {
        for cos in [0.1_f32, 0.5, 0.9, 1.0] {
            let c = fr_conductor(cos, Vec3::splat(1.5), Vec3::ZERO);
            assert!((c.x - fr_dielectric(cos, 1.5)).abs() < 1e-5, "{cos}: {c}");
        }
        // Normal incidence: ((η−1)² + κ²) / ((η+1)² + κ²).
        let c = fr_conductor(1.0, Vec3::splat(0.2), Vec3::splat(3.9));
        let expected = (0.64 + 15.21) / (1.44 + 15.21);
        assert!((c.x - expected).abs() < 1e-5);
    }

    #[test]
    fn f0_under_medium_matches_ior_ratio() {
        let f0 = Vec3::splat(crate::model::f0_from_ior(3.0));
        let got = f0_under_medium(f0, 1.5);
        assert!((got.x - crate::model::f0_from_ior(2.0)).abs() < 1e-5);
        assert!((f0_under_medium(f0, 1.0).x - f0.x).abs() < 1e-6);
    }

    #[test]
    fn qon_average_albedo_constant() {
        assert!((QON_AVG_B - 0.213_959_27).abs() < 1e-6);
    }

    #[test]
    fn eon_white_furnace() {
        // EON conserves energy: E(μ) = 1 for ρ = 1 (to the accuracy of E_FON_approx).
        let r = 1.0_f32;
        for mu_o in [0.2_f32, 0.6, 1.0] {
            let n = 256;
            let mut e = 0.0_f64;
            for a in 0..n {
                let mu_i = (a as f32 + 0.5) / n as f32;
                for b in 0..n {
                    let phi = (b as f32 + 0.5) / n as f32 * std::f32::consts::TAU;
                    let s_i = (1.0 - mu_i * mu_i).sqrt();
                    let s_o = (1.0 - mu_o * mu_o).sqrt();
                    let v_dot_l = s_i * s_o * phi.cos() + mu_i * mu_o;
                    let f = fd_eon(Vec3::ONE, r, mu_o, mu_i, v_dot_l).x as f64;
                    e += f * mu_i as f64 / (n * n) as f64 * std::f64::consts::TAU;
                }
            }
            assert!((e - 1.0).abs() < 2e-3, "mu_o {mu_o}: {e}");
        }
    }
}

shading_fn! {
    /// A normal-map texel (RGB in [0, 1], as normal maps store n·½ + ½) back to the tangent-space
    /// vector it encodes: 2t − 1 (Kilgard 2000; every normal-map tool's convention).
    pub fn normal_from_texel(texel: V) -> V {
        texel * 2.0 - texel.x().lit(1.0).splat()
    }
}

shading_fn! {
    /// Reoriented normal mapping (Barré-Brisebois & Hill 2012, "Blending in Detail", listing
    /// "RNM"): the detail normal `detail` is rotated by the rotation that takes +z to `base`, so
    /// the detail follows the base's slopes instead of being added to them (UDN/whiteout
    /// flatten strong details). t = base + (0, 0, 1), u = detail·(−1, −1, 1),
    /// r = t (t·u)/t.z − u. A flat detail (0, 0, 1) returns `base`; a flat base returns
    /// `detail`. Guard: t.z = base.z + 1 ≥ 10⁻⁶ (a base pointing straight down, which no normal
    /// map stores).
    pub fn rnm_blend(base: V, detail: V) -> V {
        let one = base.x().lit(1.0);
        let t = base + F::vec3(one.lit(0.0), one.lit(0.0), one);
        let u = detail * F::vec3(-one, -one, one);
        let tz = t.z().at_least(1e-6);
        (t * (t.dot(u) / tz) - u).normalize()
    }
}

shading_fn! {
    /// A tangent-space normal `m` in the surface frame (tangent `t`, bitangent `b`, normal `n`):
    /// normalize(t·m.x + b·m.y + n·m.z) (Mikkelsen 2008's convention for per-pixel frames).
    pub fn tangent_to_world(m: V, t: V, b: V, n: V) -> V {
        (t * m.x() + b * m.y() + n * m.z()).normalize()
    }
}

shading_fn! {
    /// Lagarde & de Rousiers 2014, "Moving Frostbite to Physically Based Rendering", listing 22:
    /// the direction a GGX lobe of roughness α around the mirror direction r = 2(n·v)n − v
    /// reflects most light from, pulled towards n as α grows: normalize(mix(n, r, s(√s + α))),
    /// s = 1 − α. Guards: n·v ≥ 0 (a view below the horizon reflects nothing; its weight is zero)
    /// and |mix| ≥ TINY.
    pub fn specular_dominant_direction(n: V, v: V, alpha: S) -> V {
        let r = n * (n.dot(v).at_least(0.0) * 2.0) - v;
        let smoothness = alpha.one_minus().clamp(0.0, 1.0);
        let t = smoothness * (smoothness.sqrt() + alpha);
        let d = n * t.one_minus() + r * t;
        d / d.dot(d).at_least(TINY).sqrt()
    }
}
