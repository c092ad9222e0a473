//! The glossy level's remainder over the azimuth: glazec's CPU evaluation against the
//! stochastic reference for a conductor under a coat, at polar pairs away from the mirror peak
//! and six azimuths (φ = 180° forward, the mirror plane). Where the conductor's lobe is
//! negligible (backwards and sideways) f is the remainder, whose azimuthal spread the walks
//! measure for `glossy_spread` (docs/accuracy.md, "Where the default method misses").
//!
//! `cargo run --release -p glazec-lab --example glossy_azimuth [-- "LAYERS"]`, LAYERS a
//! material's layer list (default: a white conductor of roughness 0.3 under a smooth η 1.5 coat).

use glazec::math::sampling::direction_deg;
use glazec_lab::reference::{self, InterfaceMode, Stack};

/// Samples per reference value (standard errors of about 1–4% here).
const SAMPLES: u32 = 16_384;

fn main() -> Result<(), String> {
    let layers = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "Coat(lobe: Smooth, ior: 1.5), Conductor(roughness: 0.3, f0: 1.0)".to_string());
    let source = format!("Material(name: \"probe\", layers: [{layers}])");
    let material = glazec::compile(&source).map_err(|e| format!("{e:?}"))?.material;
    let values = material.default_values();
    let stack = Stack::from_material(&material, &values);
    let options = reference::Options { mode: InterfaceMode::Multiple, samples: SAMPLES, seed: 1, ..Default::default() };
    println!("| θi | θo | φ | glazec (R, G, B) | reference ± std. error (R, G, B) | ratio (R, G, B) |");
    println!("|---|---|---|---|---|---|");
    for theta_i in [30.0, 60.0, 80.0] {
        for theta_o in [30.0, 60.0, 80.0, 89.0] {
            for phi in [0.0, 45.0, 90.0, 135.0, 160.0, 180.0] {
                let (wi, wo) = (direction_deg(theta_i, 0.0), direction_deg(theta_o, phi));
                let f = glazec::eval::brdf(&material, &values, wi.as_vec3(), wo.as_vec3()).as_dvec3();
                let r = stack.f(wi, wo, &options);
                let ratio = f / r.mean.max(glam::DVec3::splat(1e-12));
                println!(
                    "| {theta_i} | {theta_o} | {phi} | {:.3e}, {:.3e}, {:.3e} | {:.3e}, {:.3e}, {:.3e} ± {:.0e} | {:.2}, {:.2}, {:.2} |",
                    f.x,
                    f.y,
                    f.z,
                    r.mean.x,
                    r.mean.y,
                    r.mean.z,
                    r.std_err.max_element(),
                    ratio.x,
                    ratio.y,
                    ratio.z
                );
            }
        }
    }
    Ok(())
}
