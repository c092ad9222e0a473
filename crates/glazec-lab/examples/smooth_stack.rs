//! Stacks of smooth coats over Lambert: glazec's CPU evaluation over the exact answer
//! (`glazec_lab::reference::smooth_stack`), at body and grazing pairs 90° of azimuth apart (off
//! the mirror directions), in the red channel. Each coat's IOR is relative to the medium above.
//!
//! `cargo run --release -p glazec-lab --example smooth_stack`

use glazec::math::sampling::direction_deg;
use glazec_lab::reference::Stack;
use glazec_lab::reference::smooth_stack::SmoothStack;

/// A stack: its label, its coats as (IOR, absorption) at thickness 1, and the Lambert albedo.
type Probe = (&'static str, &'static [(f64, f64)], f64);

const STACKS: [Probe; 15] = [
    ("one coat 1.5", &[(1.5, 0.0)], 0.8),
    ("one coat 0.8", &[(0.8, 0.0)], 0.8),
    ("two coats 2.0 / 0.8, white", &[(2.0, 0.0), (0.8, 0.0)], 1.0),
    ("two coats 2.0 / 0.8", &[(2.0, 0.0), (0.8, 0.0)], 0.8),
    ("two coats 1.5 / 0.9", &[(1.5, 0.0), (0.9, 0.0)], 0.8),
    ("two coats 1.5 / 1.4", &[(1.5, 0.0), (1.4, 0.0)], 0.8),
    ("two coats 1.5 / 1.5", &[(1.5, 0.0), (1.5, 0.0)], 0.8),
    ("two coats 1.5 / 1.5, white", &[(1.5, 0.0), (1.5, 0.0)], 1.0),
    ("three coats 1.5 / 1.5 / 1.5", &[(1.5, 0.0), (1.5, 0.0), (1.5, 0.0)], 0.8),
    ("three coats 1.5 / 1.5 / 1.5, white", &[(1.5, 0.0), (1.5, 0.0), (1.5, 0.0)], 1.0),
    ("three coats 1.5 / 1.4 / 1.5", &[(1.5, 0.0), (1.4, 0.0), (1.5, 0.0)], 0.8),
    ("three coats 1.3 / 1.4 / 1.5", &[(1.3, 0.0), (1.4, 0.0), (1.5, 0.0)], 0.8),
    ("three coats 1.5 / 1.4 / 1.3", &[(1.5, 0.0), (1.4, 0.0), (1.3, 0.0)], 0.8),
    ("three coats 1.5 / 1.4 absorbing 0.3 / 1.5", &[(1.5, 0.0), (1.4, 0.3), (1.5, 0.0)], 0.8),
    ("four coats 1.5 / 1.5 / 1.5 / 1.5", &[(1.5, 0.0), (1.5, 0.0), (1.5, 0.0), (1.5, 0.0)], 0.8),
];

/// (θl, θv) in degrees.
const PAIRS: [(f64, f64); 5] = [(0.0, 30.0), (30.0, 60.0), (60.0, 60.0), (45.0, 80.0), (85.0, 85.0)];

fn main() -> Result<(), String> {
    let header: Vec<String> = PAIRS.iter().map(|(a, b)| format!("{a}°/{b}°")).collect();
    println!("| stack over Lambert | {} |", header.join(" | "));
    println!("|---|{}", "---|".repeat(PAIRS.len()));
    for (label, coats, rho) in STACKS {
        let layers: Vec<String> = coats
            .iter()
            .map(|(ior, absorption)| {
                format!("Coat(lobe: Smooth, ior: {ior}, absorption: {absorption}, thickness: 1.0)")
            })
            .collect();
        let source = format!("Material(name: \"probe\", layers: [{}, Lambert({rho})])", layers.join(", "));
        let material = glazec::compile(&source).map_err(|e| format!("{e:?}"))?.material;
        let values = material.default_values();
        let exact = SmoothStack::of(&Stack::from_material(&material, &values)).ok_or("not a smooth stack")?;
        let cells: Vec<String> = PAIRS
            .iter()
            .map(|&(theta_l, theta_v)| {
                let (wi, wo) = (direction_deg(theta_l, 0.0), direction_deg(theta_v, 90.0));
                let f = glazec::eval::brdf(&material, &values, wi.as_vec3(), wo.as_vec3()).x as f64;
                let e = exact.f(wi, wo).x;
                // Light that cannot enter the stack (a coat thinner than air beyond its critical angle).
                if e == 0.0 { format!("{f} / 0") } else { format!("{:.3}", f / e) }
            })
            .collect();
        println!("| {label} | {} |", cells.join(" | "));
    }
    Ok(())
}
