//! A conductor directly under a GTR1 coat: glazec's CPU evaluation against the stochastic
//! reference (which walks GTR1's own microsurface), for coats of roughness r and IOR η over
//! copper of roughness 0.3, at the mirror peak, in the body and at grazing pairs (φ = 180° is
//! forward, the mirror plane); per material the ratio in green and the RMS of its logarithm.
//! What the glossy level's GGX roughness for a GTR1 coat (`CoatInterface::glossy_roughness`) is
//! fitted on.
//!
//! `cargo run --release -p glazec-lab --example gtr1_over_conductor [-- SAMPLES]`

use glazec::math::sampling::direction_deg;
use glazec_lab::reference::{self, InterfaceMode, Stack};

/// Probe pairs (θi, θo, φ), degrees.
const PAIRS: [(f64, f64, f64); 11] = [
    (5.0, 5.0, 180.0),
    (35.0, 35.0, 180.0),
    (60.0, 60.0, 180.0),
    (35.0, 20.0, 180.0),
    (60.0, 60.0, 90.0),
    (35.0, 50.0, 45.0),
    (20.0, 50.0, 0.0),
    (75.0, 75.0, 90.0),
    (89.0, 60.0, 90.0),
    (80.0, 80.0, 180.0),
    (85.0, 30.0, 180.0),
];

fn main() -> Result<(), String> {
    let samples: u32 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(65_536);
    let header: Vec<String> = PAIRS.iter().map(|(i, o, p)| format!("{i}/{o}/{p}")).collect();
    println!("| r, η | RMS log | {} |", header.join(" | "));
    println!("|---|---|{}", "---|".repeat(PAIRS.len()));
    for (r, eta) in
        [(0.05, 1.5), (0.1, 1.33), (0.1, 1.5), (0.1, 2.0), (0.2, 1.5), (0.3, 1.33), (0.3, 1.5), (0.3, 2.0), (0.4, 1.5)]
    {
        let source = format!(
            "Material(name: \"probe\", layers: [Coat(lobe: Gtr1({r}), ior: {eta}), \
             Conductor(roughness: 0.3, eta: (0.27, 0.68, 1.22), k: (3.61, 2.63, 2.29))])"
        );
        let material = glazec::compile(&source).map_err(|e| format!("{e:?}"))?.material;
        let values = material.default_values();
        let stack = Stack::from_material(&material, &values);
        let options = reference::Options { mode: InterfaceMode::Multiple, samples, seed: 1, ..Default::default() };
        let ratios: Vec<f64> = PAIRS
            .iter()
            .map(|&(theta_i, theta_o, phi)| {
                let (wi, wo) = (direction_deg(theta_i, 0.0), direction_deg(theta_o, phi));
                let f = glazec::eval::brdf(&material, &values, wi.as_vec3(), wo.as_vec3()).as_dvec3();
                f.y / stack.f(wi, wo, &options).mean.y.max(1e-12)
            })
            .collect();
        let rms = (ratios.iter().map(|q| q.ln().powi(2)).sum::<f64>() / ratios.len() as f64).sqrt();
        let cells: Vec<String> = ratios.iter().map(|q| format!("{q:.2}")).collect();
        println!("| {r}, {eta} | {rms:.3} | {} |", cells.join(" | "));
    }
    Ok(())
}
