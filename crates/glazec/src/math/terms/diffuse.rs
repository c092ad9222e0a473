//! Diffuse bases: Lambert, Oren–Nayar (the qualitative model), and the energy-preserving
//! Oren–Nayar (EON) of Portsmouth et al. 2025 with its albedos.

use std::f32::consts::PI;

use crate::math::Vector;
use crate::math::shading_fn;

shading_fn! {
    /// Lambert 1760: the ideal diffuse BRDF f = ρ/π.
    pub fn fd_lambert(albedo: V) -> V {
        albedo * (1.0 / PI)
    }
}

shading_fn! {
    /// Oren & Nayar 1994, "Generalization of Lambert's Reflectance Model", the qualitative model
    /// (Bowsher 2022, eq. 17): f = ρ/π (A + B max(0, cos Δφ) sin α tan β), α = max(θi, θr),
    /// β = min(θi, θr), written as B max(0, s) / max(μi, μo), s = l·v − μi μo (Fujii 2013).
    ///
    /// Without trigonometry: sin θi sin θo cos Δφ = l·v − μi μo and sin α tan β = sin θi sin θo /
    /// max(μi, μo). σ is in radians.
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
pub(super) const FON_C1: f32 = 0.5 - 2.0 / (3.0 * PI);

/// Average FON albedo coefficient c2 = 2/3 − 28/(15π) (EON listing, `constant2_FON`).
pub(super) const FON_C2: f32 = 2.0 / 3.0 - 28.0 / (15.0 * PI);

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
    /// Directional albedo E(θ) of the qualitative Oren–Nayar lobe (Oren & Nayar 1994; the lobe of
    /// [`fd_oren_nayar`]) towards a direction at cosine μ = cos θ:
    /// E = ρ [A + (2B/π) (sin θ (θ/2 − sin 2θ/4) + tan θ (1 − sin³θ)/3)], θ = acos μ by Abramowitz &
    /// Stegun 1964, eq. 4.4.45. Guard: μ ≥ 10⁻⁴ (tan θ; the second term tends to cos θ/2 → 0 at
    /// grazing).
    ///
    /// The closed form integrates the B term over the azimuth (∫ max(0, cos Δφ) dφ = 2) and over θi
    /// on both sides of θ. Its hemispherical average is [`albedo_avg_oren_nayar`]'s (checked in the
    /// tests). The arccosine √(1 − μ)(1.5707288 − 0.2121144μ + 0.0742610μ² − 0.0187293μ³) is within
    /// 5·10⁻⁵ rad (E within 10⁻⁵ of ρ): a square root and three multiply-adds where `acos` is a
    /// transcendental call (the directional albedo is in the kernel of every coated Oren–Nayar body).
    pub fn albedo_oren_nayar(albedo: V, sigma: S, mu: S) -> V {
        let sigma_sq = sigma * sigma;
        let a = (sigma_sq / (sigma_sq + 0.33) * 0.5).one_minus();
        let b = sigma_sq / (sigma_sq + 0.09) * 0.45;
        let cos_t = mu.clamp(1e-4, 1.0);
        let theta = cos_t.one_minus().sqrt()
            * (((cos_t * -0.0187293 + 0.074261) * cos_t - 0.2121144) * cos_t + 1.5707288);
        let sin_t = cos_t.sq().one_minus().at_least(0.0).sqrt();
        let below = sin_t * (theta * 0.5 - sin_t * cos_t * 0.5);
        let above = sin_t / cos_t * (sin_t * sin_t * sin_t).one_minus() * (1.0 / 3.0);
        albedo * (b * (below + above) * (2.0 / PI) + a)
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
    /// The directional albedo of the energy-preserving Oren–Nayar lobe (Portsmouth, Kutz & Hill
    /// 2025, Listing 1 `E_EON`): ρ E_FON(μ) + ρ_ms (1 − E_FON(μ)).
    pub fn albedo_eon(albedo: V, r: S, mu: S) -> V {
        let e_f = e_fon(mu, r);
        let rho_ms = eon_rho_ms(albedo, r);
        albedo * e_f + rho_ms * e_f.one_minus()
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
