//! Deterministic directional albedo: E(wo) = ∫ f(wi, wo) cos θi dωi of a compiled method.
//!
//! The integral is taken over half vectors h (wi = reflect(wo, h), dωi = 4|wo·h| dωh), where
//! every microfacet lobe peaks at h = n whatever wo is. θh is split at geometric breakpoints
//! a, 3a, 10a, 30a, … from the sharpest lobe's α = a up to π/2, with Gauss–Legendre nodes in each
//! piece, and φh uses the trapezoid rule (exact for a periodic integrand's low harmonics). So a
//! lobe with α = 10⁻³ and a Lambertian body are integrated by the same rule.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use glazec::math::quadrature::gauss_legendre_16;

/// Azimuth steps of the trapezoid rule.
const PHI_STEPS: usize = 96;

/// E(wo) for a BRDF `f(wi, wo)` (without the cosine). `sharpest_alpha` is the smallest GGX α
/// among the material's lobes (1 if it has none).
pub fn directional_albedo(f: &dyn Fn(Vec3, Vec3) -> Vec3, wo: DVec3, sharpest_alpha: f64) -> DVec3 {
    let f64_f = |wi: DVec3, wo: DVec3| f(wi.as_vec3(), wo.as_vec3()).as_dvec3();
    directional_albedo_f64(&f64_f, wo, sharpest_alpha)
}

/// [`directional_albedo`] for a BRDF evaluated in f64.
pub fn directional_albedo_f64(f: &dyn Fn(DVec3, DVec3) -> DVec3, wo: DVec3, sharpest_alpha: f64) -> DVec3 {
    albedo_nodes(wo, sharpest_alpha).iter().map(|&(wi, weight)| f(wi, wo) * weight).sum()
}

/// The quadrature's nodes for E(wo): light directions `wi` (above the horizon) and weights, so
/// that E(wo) ≈ Σ weight · f(wi, wo). (For evaluating f elsewhere, e.g. on a GPU.)
pub fn albedo_nodes(wo: DVec3, sharpest_alpha: f64) -> Vec<(DVec3, f64)> {
    albedo_nodes_with_jump(wo, sharpest_alpha, None)
}

/// Probes per θh panel when looking for where f jumps ([`albedo_nodes_with_jump`]).
pub const JUMP_PROBES: usize = 8;

/// [`albedo_nodes`] for an f that jumps where the light direction's cosine crosses `jump`: a
/// coat optically thinner than the medium above (η < 1) cuts its transmission off at its
/// critical angle. Gauss–Legendre nodes across a jump err by the jump times the panel's width,
/// and the jump's curve in half-vector space depends on wo and φh, so no fixed breakpoint lies
/// on it. Instead, at each φh step, the θh panels are split where wi·n = `jump` (sign changes
/// of wi·n − jump between [`JUMP_PROBES`] + 1 probes per panel, then bisection), and each piece
/// gets the full Gauss–Legendre rule: the inner integral over θh is then of a smooth function,
/// and the outer one over φh of a continuous one.
pub fn albedo_nodes_with_jump(wo: DVec3, sharpest_alpha: f64, jump: Option<f64>) -> Vec<(DVec3, f64)> {
    let a = sharpest_alpha.clamp(1e-3, 1.0);
    let mut edges = vec![0.0];
    let mut edge = a;
    let mut factor = 3.0;
    while edge.atan() < PI / 2.0 - 1e-9 && edges.len() < 40 {
        edges.push(edge.atan());
        edge *= factor;
        factor = if factor == 3.0 { 10.0 / 3.0 } else { 3.0 };
    }
    edges.push(PI / 2.0);
    let gauss = gauss_legendre_16();
    let d_phi = 2.0 * PI / PHI_STEPS as f64;
    let mut nodes = Vec::new();
    for k in 0..PHI_STEPS {
        let phi = 2.0 * PI * (k as f64 + 0.5) / PHI_STEPS as f64;
        for pair in edges.windows(2) {
            let mut pieces = vec![pair[0]];
            if let Some(mu) = jump {
                pieces.extend(jumps_in(wo, phi, (pair[0], pair[1]), mu));
            }
            pieces.push(pair[1]);
            for piece in pieces.windows(2) {
                let (lo, hi) = (piece[0], piece[1]);
                for &(x, w) in &gauss {
                    push_node(wo, lo + (hi - lo) * x, phi, w * (hi - lo) * d_phi, &mut nodes);
                }
            }
        }
    }
    nodes
}

/// The light direction's cosine minus `mu`, for the half vector at (θh, φh).
fn light_cosine_minus(wo: DVec3, theta: f64, phi: f64, mu: f64) -> f64 {
    let h = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
    2.0 * wo.dot(h) * h.z - wo.z - mu
}

/// The θh in (lo, hi) where the light direction's cosine crosses `mu` at azimuth φh.
fn jumps_in(wo: DVec3, phi: f64, (lo, hi): (f64, f64), mu: f64) -> Vec<f64> {
    let g = |theta: f64| light_cosine_minus(wo, theta, phi, mu);
    let mut roots = Vec::new();
    let step = (hi - lo) / JUMP_PROBES as f64;
    for i in 0..JUMP_PROBES {
        let (mut a, mut b) = (lo + step * i as f64, lo + step * (i + 1) as f64);
        let (ga, gb) = (g(a), g(b));
        if (ga < 0.0) == (gb < 0.0) {
            continue;
        }
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if (g(m) < 0.0) == (ga < 0.0) { a = m } else { b = m }
        }
        roots.push(0.5 * (a + b));
    }
    roots
}

/// The light direction reflected about the half vector at (θh, φh), with its weight (the
/// quadrature weight `w` in θh·φh times sin θh and the Jacobian 4|wo·h|, times wi·n), or
/// nothing when it lies below the horizon.
fn push_node(wo: DVec3, theta: f64, phi: f64, w: f64, nodes: &mut Vec<(DVec3, f64)>) {
    let h = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
    let c = wo.dot(h);
    if c <= 0.0 {
        return;
    }
    let wi = 2.0 * c * h - wo;
    if wi.z <= 0.0 {
        return;
    }
    nodes.push((wi, wi.z * 4.0 * c * w * theta.sin()));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How close the refined rule comes to a cut-off Lambert lobe's exact albedo.
    const JUMP_TOLERANCE: f64 = 2e-4;

    #[test]
    fn refining_at_a_jump_makes_it_accurate_at_every_view() {
        // Lambert cut off beyond θc (a coat with η < 1): E = sin²θc whatever wo is.
        let mu_c = (1.0 - 0.824_f64 * 0.824).sqrt();
        let f = |wi: DVec3, _: DVec3| DVec3::splat(if wi.z > mu_c { 1.0 / PI } else { 0.0 });
        let exact = 1.0 - mu_c * mu_c;
        for theta in [0.0_f64, 0.3, 0.55, 1.0, 1.4] {
            let wo = DVec3::new(theta.sin(), 0.0, theta.cos());
            let integrate = |jump: Option<f64>| -> f64 {
                albedo_nodes_with_jump(wo, 0.04, jump).iter().map(|&(wi, w)| f(wi, wo).x * w).sum()
            };
            let refined = integrate(Some(mu_c));
            assert!((refined - exact).abs() < JUMP_TOLERANCE, "θ {theta}: {refined} against {exact}");
            if theta > 0.0 {
                let plain = integrate(None);
                assert!((plain - exact).abs() > (refined - exact).abs(), "θ {theta}: refining should help");
            }
        }
    }

    #[test]
    fn lambert_integrates_to_its_albedo() {
        let f = |_: Vec3, _: Vec3| Vec3::splat(0.7 / std::f32::consts::PI);
        for theta in [0.0_f64, 0.5, 1.2, 1.5] {
            let wo = DVec3::new(theta.sin(), 0.0, theta.cos());
            let e = directional_albedo(&f, wo, 1.0);
            assert!((e.x - 0.7).abs() < 2e-4, "theta {theta}: {}", e.x);
        }
    }

    #[test]
    fn sharp_ggx_lobe_integrates_to_its_albedo() {
        // A white GGX conductor: E(μ = 1, α) is known from the reference's own quadrature; here
        // the check is that a sharp lobe (α = 10⁻³) and a rough one both give E ≤ 1 and the
        // sharp one ≈ 1 (no masking at normal incidence to speak of).
        for alpha in [1e-3_f64, 0.2] {
            let f = move |wi: DVec3, wo: DVec3| {
                let h = (wi + wo).normalize();
                let a2 = alpha * alpha;
                let sin2 = h.x * h.x + h.y * h.y;
                let d = a2 / (std::f64::consts::PI * (h.z * h.z * a2 + sin2).powi(2));
                let lambda = |w: DVec3| ((1.0 + a2 * (1.0 - w.z * w.z) / (w.z * w.z)).sqrt() - 1.0) / 2.0;
                let g = 1.0 / (1.0 + lambda(wi) + lambda(wo));
                DVec3::splat(d * g / (4.0 * wi.z * wo.z))
            };
            let e = directional_albedo_f64(&f, DVec3::Z, alpha);
            assert!(e.x <= 1.0 + 1e-4 && e.x > 0.94, "alpha {alpha}: {}", e.x);
        }
    }
}
