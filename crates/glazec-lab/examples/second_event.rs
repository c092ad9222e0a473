//! The second microfacet event of a rough coat when one direction grazes, from the reference's
//! microsurface walks (Heitz et al. 2016) against the model the default method adds to the coat's
//! lobe (`second_event`: the tail of the lobe at the half vector with the lower direction
//! mirrored, weighted by the first event's Fresnel factor and 1.1/(1 + 4Λ + 2Λ²) there).
//! Per pair: what the walks' later events add to the single-scattering lobe, and what the model
//! adds (`glazec_lab::bake::coat_lobe` over `dielectric_lobe`). Walks start at the more grazing
//! direction, where they see the second event (docs/accuracy.md, "The stochastic reference").
//!
//! `cargo run --release -p glazec-lab --example second_event [-- WALKS]`

use glazec::math::sampling::direction_deg;
use glazec_lab::bake::{coat_lobe, dielectric_lobe};
use glazec_lab::reference::Ndf;
use glazec_lab::reference::microsurface::RoughDielectric;

fn main() {
    let walks: u32 = std::env::args().nth(1).and_then(|w| w.parse().ok()).unwrap_or(200_000);
    let eta = 1.5;
    let alphas = [0.0025, 0.01, 0.04, 0.25];
    // (more grazing θ, other θ, azimuth between them), degrees; 180 is the mirror plane.
    let pairs = [
        (89.0, 30.0, 180.0),
        (89.0, 75.0, 180.0),
        (89.0, 85.0, 180.0),
        (88.0, 60.0, 150.0),
        (85.0, 80.0, 180.0),
        (80.0, 78.0, 180.0),
        (85.0, 85.0, 160.0),
    ];
    let header: Vec<String> = alphas.iter().map(|a| format!("α {a}: walks / f₂")).collect();
    println!("| θ grazing / θ other / φ | {} |", header.join(" | "));
    println!("|---|{}", "---|".repeat(alphas.len()));
    for (k, &(grazing, other, phi)) in pairs.iter().enumerate() {
        let (wg, wo) = (direction_deg(grazing, 0.0), direction_deg(other, phi));
        let cells: Vec<String> = alphas
            .iter()
            .map(|&alpha| {
                let (first, later) =
                    RoughDielectric::ggx(eta, alpha).first_and_later_events(wg, wo, walks, 11 + k as u64);
                let model =
                    coat_lobe(wg, wo, eta, alpha, Ndf::Ggx) / dielectric_lobe(wg, wo, eta, alpha, Ndf::Ggx) - 1.0;
                format!("{:.3} / {model:.3}", later / first)
            })
            .collect();
        println!("| {grazing} / {other} / {phi} | {} |", cells.join(" | "));
    }
}
