//! The directional albedo E(θ) of a material by brute force: a midpoint rule over u = cos²θ and
//! φ (cos θ dω = ½ du dφ), 1500 × 600 light directions per view angle. Slow (about a second per
//! angle) but blind to where f is discontinuous, which the half-vector quadrature of
//! `glazec stability` is not: a coat optically thinner than the medium above (η < 1) cuts its
//! transmission off at the critical angle, and there that quadrature errs by up to 3%.
//!
//! `cargo run --release --example brute_albedo -- 'Material(name: "m", layers: [Coat(lobe: Ggx(0.2), ior: 0.3), Lambert(1.0)])'`

use glam::Vec3;

/// Steps in u = cos²θ and in φ.
const U_STEPS: usize = 1500;
const PHI_STEPS: usize = 600;
/// View angles (degrees).
const ANGLES: [f32; 9] = [0.0, 30.0, 45.0, 60.0, 70.0, 75.0, 80.0, 85.0, 89.0];

fn main() {
    let Some(text) = std::env::args().nth(1) else {
        eprintln!("usage: brute_albedo '<material text>'");
        std::process::exit(2);
    };
    let compiled = match glazec::compile(&text) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("{e:?}");
            std::process::exit(1);
        }
    };
    let material = &compiled.material;
    let values = material.default_values();
    for degrees in ANGLES {
        let t = degrees.to_radians();
        let wo = Vec3::new(t.sin(), 0.0, t.cos());
        let mut sum = 0.0_f64;
        for i in 0..U_STEPS {
            let u = (i as f64 + 0.5) / U_STEPS as f64;
            let (cos, sin) = (u.sqrt(), (1.0 - u).sqrt());
            for j in 0..PHI_STEPS {
                let phi = std::f64::consts::TAU * (j as f64 + 0.5) / PHI_STEPS as f64;
                let wi = Vec3::new((sin * phi.cos()) as f32, (sin * phi.sin()) as f32, cos as f32);
                sum += f64::from(glazec::eval::brdf(material, &values, wi, wo).max_element());
            }
        }
        let e = sum * std::f64::consts::PI / (U_STEPS * PHI_STEPS) as f64
            + f64::from(glazec::eval::mirror_reflectance(material, &values, wo).max_element());
        println!("θ {degrees:>4}°: E = {e:.4} (largest channel)");
    }
}
