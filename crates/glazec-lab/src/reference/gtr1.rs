//! The GTR1 microsurface of the reference: Burley's GTR1 normal distribution (Burley 2012,
//! App. B, "Generalized-Trowbridge-Reitz" with γ = 1) with its own Smith masking, so a `Gtr1`
//! coat is walked on a microsurface of its own rather than on a GGX substitute.
//!
//! * D(m) = (α² − 1) / (π ln α² (1 + (α² − 1) cos² θm)) (Burley 2012, eq. 4).
//! * Smith's Λ follows from the slope distribution (Heitz 2014, eq. 72: Λ(μ) =
//!   (1/μ)∫_μ^∞ (q − μ) P2(q) dq with μ = cot θ). GTR1's marginal slope density is
//!   P2(q) = (1/L)(1/√(q² + α²) − 1/√(q² + 1)) with L = 2 ln(1/α), so
//!   Λ(μ) = [√(μ² + 1) − √(μ² + α²) + μ ln((μ + √(μ² + α²)) / (μ + √(μ² + 1)))] / (μ L)
//!   (derived in docs/derivations.md, "Smith masking of GTR1"). Burley pairs GTR1 with GGX's
//!   masking at α = 0.25, which belongs to no microsurface and cannot be walked.
//! * Visible normals are sampled by rejection: normals drawn with density ∝ D(m) over solid
//!   angle (closed-form inversion) and kept with probability max(0, w·m) ≤ 1, which leaves the
//!   visible-normal density max(0, w·m) D(m) / A(w) for any `w`, on either hemisphere.
//!
//! Like the rest of the reference, this shares no code with `glazec::math`.

use std::f64::consts::PI;

use glam::DVec3;

use super::rng::Rng;

/// Above this α, α² − 1 and ln α² cancel badly; GTR1 is the uniform D = 1/π at α = 1.
const ALPHA_UNIFORM: f64 = 0.9999;

/// Directions this close to the pole have Λ = 0 (the same cut as the GGX microsurface's).
const POLE: f64 = 0.999_999;

/// Rejection rounds before a visible-normal sample gives up and returns the last proposal; the
/// acceptance rate is the projected area A(w) of the proposal distribution, which only a ray
/// travelling almost straight away from the mean plane makes small, and such rays rarely meet
/// the surface at all.
const MAX_REJECTIONS: u32 = 100_000;

/// The GTR1 distribution D(m), normalised so that ∫ D(m) cos θm dm = 1.
pub fn d(m: DVec3, alpha: f64) -> f64 {
    if m.z <= 0.0 {
        return 0.0;
    }
    if alpha >= ALPHA_UNIFORM {
        return 1.0 / PI;
    }
    let a2 = alpha * alpha;
    (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * m.z * m.z))
}

/// Smith's Λ for GTR1 for a direction on either hemisphere (Λ(w) = −1 − Λ(−w) below the plane).
pub fn lambda(w: DVec3, alpha: f64) -> f64 {
    if w.z < 0.0 {
        return -1.0 - lambda(-w, alpha);
    }
    if w.z > POLE {
        return 0.0;
    }
    let sin = (1.0 - w.z * w.z).max(0.0).sqrt();
    let mu = w.z / sin;
    if alpha >= ALPHA_UNIFORM {
        // D = 1/π: P2(q) = 1/(2(1 + q²)^{3/2}), so Λ = (√(1 + μ²) − μ)/(2μ).
        return ((1.0 + mu * mu).sqrt() - mu) / (2.0 * mu);
    }
    let (root_1, root_a) = ((mu * mu + 1.0).sqrt(), (mu * mu + alpha * alpha).sqrt());
    // √(μ² + 1) − √(μ² + α²) without cancellation, and the logarithm as ln(1 − δ/(μ + √(μ² + 1))).
    let delta = (1.0 - alpha * alpha) / (root_1 + root_a);
    let log = (-delta / (mu + root_1)).ln_1p();
    (delta + mu * log) / (mu * 2.0 * (1.0 / alpha).ln())
}

/// Projected area of the microsurface towards `w`: cos θ (1 + Λ(w)), on either hemisphere.
pub fn projected_area(w: DVec3, alpha: f64) -> f64 {
    (w.z * (1.0 + lambda(w, alpha))).max(0.0)
}

/// Samples a normal with density ∝ D(m) over solid angle: cos θm has density ∝ 1/(1 − b c²),
/// b = 1 − α², whose inverse CDF is c = tanh(u·atanh √b)/√b, with atanh √b = ln((1 + √b)/α).
fn sample_d(alpha: f64, u1: f64, u2: f64) -> DVec3 {
    let c = if alpha >= ALPHA_UNIFORM {
        u1
    } else {
        let sb = (1.0 - alpha * alpha).sqrt();
        ((u1 * ((1.0 + sb) / alpha).ln()).tanh() / sb).min(1.0)
    };
    let sin = (1.0 - c * c).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    DVec3::new(sin * phi.cos(), sin * phi.sin(), c)
}

/// Samples a normal visible from `w` (either hemisphere): density max(0, w·m) D(m) / A(w).
pub fn sample_vndf(w: DVec3, alpha: f64, rng: &mut Rng) -> DVec3 {
    let mut m = DVec3::Z;
    for _ in 0..MAX_REJECTIONS {
        m = sample_d(alpha, rng.uniform(), rng.uniform());
        if rng.uniform() < w.dot(m) {
            return m;
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use glazec::math::sampling::direction as dir;

    /// Quadrature cells per axis, samples per statistical check, and the tolerance in standard
    /// errors.
    const CELLS: usize = 2000;
    const SAMPLES: usize = 200_000;
    const SIGMAS: f64 = 4.0;
    /// Relative tolerance of a midpoint quadrature on `CELLS`² cells of a smooth integrand.
    const QUADRATURE: f64 = 2e-3;
    /// Agreement of glazec's f32 Λ with this f64 one, relative to 1 + Λ (the cosine's own
    /// rounding at grazing angles moves Λ by about 10⁻⁶ of itself).
    const F32_AGREEMENT: f64 = 2e-5;

    /// ∫ g(m) D(m) dm over the upper hemisphere by the midpoint rule in (cos θm, φ); the cells
    /// are finer near the pole, where a narrow GTR1 puts its peak (c = 1 − t²).
    fn integrate(alpha: f64, g: impl Fn(DVec3) -> f64) -> f64 {
        let mut sum = 0.0;
        for i in 0..CELLS {
            let t = (i as f64 + 0.5) / CELLS as f64;
            let c = 1.0 - t * t;
            let dc = 2.0 * t / CELLS as f64;
            let sin = (1.0 - c * c).max(0.0).sqrt();
            for j in 0..CELLS {
                let phi = (j as f64 + 0.5) / CELLS as f64 * 2.0 * PI;
                let m = DVec3::new(sin * phi.cos(), sin * phi.sin(), c);
                sum += g(m) * d(m, alpha) * dc * 2.0 * PI / CELLS as f64;
            }
        }
        sum
    }

    #[test]
    fn d_is_normalised() {
        for alpha in [0.01, 0.04, 0.3, 0.9, 1.0] {
            let total = integrate(alpha, |m| m.z);
            assert!((total - 1.0).abs() < QUADRATURE, "alpha {alpha}: ∫D cos = {total}");
        }
    }

    #[test]
    fn lambda_gives_the_projected_area() {
        // A(w) = ∫ max(0, w·m) D(m) dm = cos θ (1 + Λ) above the plane, and |cos θ| Λ(−w) below.
        for alpha in [0.02, 0.1, 0.5, 1.0] {
            for theta in [0.2, 0.9, 1.3, 1.55, 1.8, 2.6] {
                let w = dir(theta, 0.4);
                let area = integrate(alpha, |m| w.dot(m).max(0.0));
                let closed = projected_area(w, alpha);
                let below = if w.z < 0.0 { -w.z * lambda(-w, alpha) } else { closed };
                assert!((area - closed).abs() < QUADRATURE * area.max(1e-3), "α {alpha} θ {theta}: {area} vs {closed}");
                assert!((closed - below).abs() < 1e-12 * closed.max(1.0));
            }
        }
    }

    #[test]
    fn lambda_is_smooth_towards_the_pole() {
        // The closed form's cancellation is rewritten; near the pole Λ falls off like 1/μ².
        for alpha in [0.01, 0.2, 0.7] {
            let mut previous = f64::INFINITY;
            for k in 1..60 {
                let theta = 1.5 * 0.85f64.powi(k);
                let l = lambda(dir(theta, 0.0), alpha);
                assert!(l.is_finite() && l >= 0.0 && l <= previous, "α {alpha} θ {theta}: {l}");
                previous = l;
            }
        }
    }

    #[test]
    fn the_compilers_lambda_agrees() {
        // glazec's Λ (f32, written in the cosine, `glazec::math::terms::lambda_gtr1`) against this
        // file's (f64, written in the cotangent): two forms of one integral.
        for alpha in [0.001, 0.01, 0.04, 0.2, 0.6, 0.95, 1.0] {
            for degrees in [0.5, 10.0, 30.0, 60.0, 75.0, 85.0, 89.0, 89.9] {
                let w = dir(f64::to_radians(degrees), 0.0);
                let ours = lambda(w, alpha);
                let compiled = f64::from(glazec::math::terms::lambda_gtr1::<f32>(w.z as f32, alpha as f32));
                assert!(
                    (ours - compiled).abs() <= F32_AGREEMENT * (1.0 + ours),
                    "α {alpha} θ {degrees}°: {ours} vs compiled {compiled}"
                );
            }
        }
    }

    #[test]
    fn visible_normals_have_the_right_distribution() {
        // E[m.z] and E[m.x] over the visible normals of w, against quadrature of the density.
        let mut rng = Rng::seeded(5);
        for (alpha, theta) in [(0.04, 0.3), (0.04, 1.4), (0.3, 1.1), (0.6, 2.0), (0.1, 2.8)] {
            let w = dir(theta, 0.7);
            let area = integrate(alpha, |m| w.dot(m).max(0.0));
            for (name, g) in [("m.z", (|m: DVec3| m.z) as fn(DVec3) -> f64), ("m.x", |m: DVec3| m.x)] {
                let expected = integrate(alpha, |m| w.dot(m).max(0.0) * g(m)) / area;
                let values: Vec<f64> = (0..SAMPLES).map(|_| g(sample_vndf(w, alpha, &mut rng))).collect();
                let mean = values.iter().sum::<f64>() / SAMPLES as f64;
                let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / SAMPLES as f64;
                let err = (var / SAMPLES as f64).sqrt();
                assert!(
                    (mean - expected).abs() < SIGMAS * err + QUADRATURE,
                    "α {alpha} θ {theta} {name}: {mean} vs {expected} ± {err}"
                );
            }
        }
    }
}
