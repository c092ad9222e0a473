//! The directional albedo a material's method states (what the split sum weighs and a white
//! furnace returns: the sum of `glazec::eval::environment_lobes`' weights) against the integral
//! of its own f under a white environment (`environment_integral`, multiple importance
//! sampling), per channel and view angle. Where the first exceeds the second, image-based
//! lighting is too bright by that much. The last columns are the reference's directional
//! albedo (`glazec_lab::reference::Stack::albedo`, analog walks) and the stated albedo against it:
//! what the split sum weighs against the truth.
//!
//! `cargo run --release -p glazec-lab --example albedo_gap -- materials/car_paint.ron`

use glam::Vec3;
use glazec_lab::reference::environment::environment_integral;

/// View angles (degrees) and samples per strategy.
const ANGLES: [f32; 10] = [0.0, 20.0, 40.0, 50.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];
const SAMPLES: u32 = 1 << 16;
/// Walks per view angle of the reference's albedo.
const WALKS: u32 = 1 << 18;

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: albedo_gap <material.ron>");
        std::process::exit(2);
    };
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let compiled = glazec::compile(&text).unwrap_or_else(|e| panic!("{e:?}"));
    let material = &compiled.material;
    let values = material.default_values();
    let stack = glazec_lab::reference::Stack::from_material(material, &values);
    let opts = glazec_lab::reference::Options { samples: WALKS, ..Default::default() };
    println!(
        "θ      stated E (r, g, b)        ∫f (r, g, b)              stated/∫f − 1         reference E (r, g, b)     stated/reference − 1"
    );
    for degrees in ANGLES {
        let t = degrees.to_radians();
        let v = Vec3::new(t.sin(), 0.0, t.cos());
        let stated: Vec3 =
            glazec::eval::environment_lobes(material, &values, Vec3::Z, v).iter().map(|lobe| lobe.weight).sum();
        let (integral, _) = environment_integral(material, &values, (Vec3::Z, v), &|_| Vec3::ONE, SAMPLES, 7);
        let gap = stated / integral - Vec3::ONE;
        let truth = stack.albedo(v.as_dvec3(), &opts).mean.as_vec3();
        let off = stated / truth - Vec3::ONE;
        println!(
            "{degrees:>4}°  {:.4} {:.4} {:.4}   {:.4} {:.4} {:.4}   {:+.3} {:+.3} {:+.3}   {:.4} {:.4} {:.4}   {:+.3} {:+.3} {:+.3}",
            stated.x,
            stated.y,
            stated.z,
            integral.x,
            integral.y,
            integral.z,
            gap.x,
            gap.y,
            gap.z,
            truth.x,
            truth.y,
            truth.z,
            off.x,
            off.y,
            off.z
        );
    }
}
