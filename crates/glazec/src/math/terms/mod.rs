//! The BRDF terms, each written once (see the [module essay](super)).
//!
//! Every term cites its source on the first line of its doc comment (which is also copied above
//! the function in the generated shaders), and documents its numerical guards where they sit.
//! Cosine arguments are expected to be clamped by the caller where they divide (see
//! [`super::layering::COS_EPSILON`]); terms clamp only what they introduce themselves.

mod diffuse;
mod layer;
mod microfacet;
mod normal;
mod slab;

pub use diffuse::*;
pub use layer::*;
pub use microfacet::*;
pub use normal::*;
pub use slab::*;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::reference::simpson;
    use glam::Vec3;
    use std::f32::consts::PI;

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
    fn crossed_ggx_is_ggx_with_the_crossings_covariance() {
        // d_ggx_crossed, written without a frame, against GGX with the slope covariance
        // A = α² I + Σ_l + Σ_v built in the frame n = z (Σ = β(I − x_t x_tᵀ)), at the half
        // vectors of pairs all round the hemisphere; and plain d_ggx where nothing is crossed.
        let direction = |theta: f32, phi: f32| Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
        let (base, beta_l, beta_v) = (0.01_f32, 0.03_f32, 0.11_f32);
        for (theta_l, theta_v) in [(0.2_f32, 0.5_f32), (1.0, 1.3), (1.45, 0.1), (0.7, 0.7)] {
            for phi in [0.0_f32, 0.8, 2.0, 3.1, 4.4] {
                let (l, v) = (direction(theta_l, 0.3), direction(theta_v, 0.3 + phi));
                let h = (l + v).normalize();
                let covariance = |x: Vec3, beta: f32| {
                    let (x, y) = (f64::from(x.x), f64::from(x.y));
                    let b = f64::from(beta);
                    [b * (1.0 - x * x), -b * x * y, b * (1.0 - y * y)]
                };
                let (cl, cv) = (covariance(l, beta_l), covariance(v, beta_v));
                let a = [f64::from(base) + cl[0] + cv[0], cl[1] + cv[1], f64::from(base) + cl[2] + cv[2]];
                let det = a[0] * a[2] - a[1] * a[1];
                let (sx, sy) = (f64::from(h.x / h.z), f64::from(h.y / h.z));
                let q = (a[2] * sx * sx - 2.0 * a[1] * sx * sy + a[0] * sy * sy) / det;
                let expected = 1.0 / (std::f64::consts::PI * det.sqrt() * (1.0 + q).powi(2) * f64::from(h.z).powi(4));
                let twist = Vec3::Z.dot(l.cross(v));
                let sin2_h = Vec3::Z.cross(h).length_squared();
                let got = d_ggx_crossed(h.z, sin2_h, l.dot(h), l.z, v.z, twist * twist, base, beta_l, beta_v);
                let error = (f64::from(got) / expected - 1.0).abs();
                assert!(error < 1e-4, "θ {theta_l}/{theta_v}, φ {phi}: {got} against {expected}");
                let plain = d_ggx_crossed(h.z, sin2_h, l.dot(h), l.z, v.z, twist * twist, base, 0.0, 0.0);
                assert!((plain / d_ggx(h.z, sin2_h, base.sqrt()) - 1.0).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn forward_tilt_keeps_the_albedo_and_reaches_its_mean_resultant_length() {
        // Over the azimuth, W(ρ)·tilt has mean 1 and is positive, and its first Fourier
        // coefficient is ρ_c (clamped to what the tilt reaches) where ρ_c ≥ ρ, as a coloured
        // conductor's is (a ρ_c below ρ moves it only as far as 1 + aV > 0 allows); the
        // channels are independent.
        const N: usize = 20_000;
        for rho in [0.05_f32, 0.2, 0.45, 0.7, 0.84, 0.95] {
            for rho_c in [rho * 0.8, rho, rho + 0.5 * (1.0 - rho) * 0.3, rho + (1.0 - rho) * 0.6, 0.99] {
                let top = (rho + 0.95) / (0.95 * rho + 1.0) - 1e-3;
                let wanted = rho_c.min(top);
                let (mut mean, mut first, mut least) = (0.0_f64, 0.0_f64, f32::MAX);
                for k in 0..N {
                    let phi = (k as f32 + 0.5) / N as f32 * 2.0 * PI;
                    let w = forward_azimuth_weight(rho, phi.cos());
                    let tilt = forward_azimuth_tilt(rho, Vec3::new(rho_c, rho, wanted), phi.cos());
                    least = least.min(tilt.min_element());
                    mean += f64::from(w * tilt.x) / N as f64;
                    first += f64::from(w * tilt.x * phi.cos()) / N as f64;
                    assert!((tilt.y - 1.0).abs() < 1e-5, "white stays untilted: ρ {rho}: {}", tilt.y);
                }
                assert!(least > 0.0, "ρ {rho}, ρ_c {rho_c}: {least}");
                assert!((mean - 1.0).abs() < 1e-3, "ρ {rho}, ρ_c {rho_c}: mean {mean}");
                if rho_c >= rho {
                    assert!((first - f64::from(wanted)).abs() < 2e-3, "ρ {rho}, ρ_c {rho_c}: {first} against {wanted}");
                }
            }
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

    /// The closed-form directional albedo of the qualitative Oren–Nayar lobe against a midpoint
    /// rule over the lobe itself, and its hemispherical average against the constant.
    #[test]
    fn qon_directional_albedo_matches_its_integral() {
        // Largest difference from the 512 × 512 midpoint rule (its own error is ~1e-5).
        const TOLERANCE: f32 = 2e-4;
        let sigma = 0.6_f32;
        let mut average = 0.0_f64;
        for mu_o in [0.05_f32, 0.3, 0.6, 0.9, 1.0] {
            let n = 512;
            let mut e = 0.0_f64;
            for a in 0..n {
                let mu_i = (a as f32 + 0.5) / n as f32;
                for b in 0..n {
                    let phi = (b as f32 + 0.5) / n as f32 * std::f32::consts::TAU;
                    let (s_i, s_o) = ((1.0 - mu_i * mu_i).sqrt(), (1.0 - mu_o * mu_o).sqrt());
                    let v_dot_l = s_i * s_o * phi.cos() + mu_i * mu_o;
                    let f = fd_oren_nayar(Vec3::ONE, sigma, mu_o, mu_i, v_dot_l).x as f64;
                    e += f * mu_i as f64 / (n * n) as f64 * std::f64::consts::TAU;
                }
            }
            let closed = albedo_oren_nayar(Vec3::ONE, sigma, mu_o).x;
            assert!((closed - e as f32).abs() < TOLERANCE, "μ {mu_o}: {closed} against {e}");
        }
        let n = 4096;
        for k in 0..n {
            let mu = (k as f32 + 0.5) / n as f32;
            average += 2.0 * f64::from(mu * albedo_oren_nayar(Vec3::ONE, sigma, mu).x) / n as f64;
        }
        let expected = albedo_avg_oren_nayar(Vec3::ONE, sigma).x;
        assert!((average as f32 - expected).abs() < 1e-4, "{average} against {expected}");
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
