//! Directions and sample points shared by every stage that samples a hemisphere: the
//! simplifier's error measure, the GPU runner's environment prefilter and the lab.
//!
//! Directions are in the local shading frame (z = normal). Angles are in radians unless a
//! name says degrees.

use glam::{DVec3, Vec3};

/// The unit vector at polar angle `theta` and azimuth `phi` (radians), f64.
pub fn direction(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
}

/// [`direction`] with both angles in degrees.
pub fn direction_deg(theta_deg: f64, phi_deg: f64) -> DVec3 {
    direction(theta_deg.to_radians(), phi_deg.to_radians())
}

/// [`direction`] in f32 arithmetic (what f32 evaluations sample with, so that their directions
/// are the ones f32 code computes).
pub fn direction_f32(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
}

/// The direction in the xz-plane whose cosine to the normal is `mu` (φ = 0), f64.
pub fn direction_at_cosine(mu: f64) -> DVec3 {
    DVec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu)
}

/// The van der Corput radical inverse of `i` in `base` (Halton 1960): the digits of `i` in
/// `base` mirrored about the radix point. Base 2 gives Hammersley's second coordinate.
pub fn radical_inverse(base: u32, mut i: u32) -> f32 {
    let mut inverse = 0.0_f64;
    let mut scale = 1.0 / f64::from(base);
    while i > 0 {
        inverse += f64::from(i % base) * scale;
        i /= base;
        scale /= f64::from(base);
    }
    inverse as f32
}

/// A cosine-weighted direction (Malley's method) in the local frame.
pub fn cosine_direction(u1: f32, u2: f32) -> Vec3 {
    let r = u1.sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

/// A GGX half vector of roughness α in the local frame (z = normal), sampled in proportion to
/// D(h)(n·h) (Walter et al. 2007, eq. 35–36).
pub fn ggx_half_vector(alpha: f32, u1: f32, u2: f32) -> Vec3 {
    let a2 = alpha * alpha;
    let cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
    let sin = (1.0 - cos2).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos2.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_radical_inverse() {
        assert_eq!([1, 2, 3, 4].map(|i| radical_inverse(2, i)), [0.5, 0.25, 0.75, 0.125]);
        assert!((radical_inverse(3, 1) - 1.0 / 3.0).abs() < 1e-7);
    }

    #[test]
    fn base_two_is_the_bit_reversal() {
        // Hammersley's form, i.reverse_bits() / 2³², is the same number for every i < 2²⁴.
        for i in [0_u32, 1, 2, 3, 7, 100, 255, 65_535, (1 << 24) - 1] {
            let reversed = i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0);
            assert_eq!(radical_inverse(2, i), reversed, "{i}");
        }
    }
}
