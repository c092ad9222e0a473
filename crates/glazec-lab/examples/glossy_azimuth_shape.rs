//! The shape of the glossy level's remainder (light leaving a coat over a white conductor after
//! three or more conductor events), from white walks (`glazec_lab::bake::glossy::walk_exits`),
//! against what the level assumes:
//!
//! * over the azimuth: the histogram of φf (about the forward direction) per band of exit angles
//!   against the wrapped Cauchy distribution of the walks' own mean resultant length ρ, and that
//!   ρ against the level's, √(κ(μᵢ) κ(μₒ)) sin θᵢ sin θₒ (`glossy_spread`);
//! * over the polar angles: the remainder averaged over the azimuth, g(θᵢ, θₒ), as the ratio
//!   g(θᵢ, θₒ) g(30°, 30°)/(g(θᵢ, 30°) g(30°, θₒ)), which is 1 where it is separable, as the
//!   level's M(μᵢ) M(μₒ)/(π⟨M⟩) is.
//!
//! `cargo run --release -p glazec-lab --example glossy_azimuth_shape [-- WALKS]`

use std::f64::consts::PI;

use glazec::math::tables::{self, TableId};
use glazec_lab::bake::glossy::walk_exits;

/// Azimuth bins over [0°, 180°].
const BINS: usize = 12;
/// The conductor's roughness.
const R_C: f64 = 0.3;

/// (exit cosine, φf) of the walks that left after three or more events.
fn remainder(theta_i: f64, r: f64, eta: f64, walks: u32) -> Vec<(f64, f64)> {
    let exits = walk_exits(theta_i.to_radians().cos(), R_C, r, eta, walks, 11);
    exits.into_iter().filter(|&(_, _, n)| n >= 3).map(|(mu, phi, _)| (mu, phi)).collect()
}

/// The exits whose polar angle lies in [lo°, hi°].
fn in_band(exits: &[(f64, f64)], (lo, hi): (f64, f64)) -> Vec<(f64, f64)> {
    let cosines = hi.to_radians().cos()..lo.to_radians().cos();
    exits.iter().copied().filter(|(mu, _)| cosines.contains(mu)).collect()
}

fn main() {
    let walks: u32 = std::env::args().nth(1).and_then(|w| w.parse().ok()).unwrap_or(1_000_000);
    let coats = [(0.0, 1.5), (0.2, 1.33)];
    println!("Over the azimuth: walks / wrapped Cauchy of the walks' ρ, per bin of φf (0° forward)\n");
    for (r, eta) in coats {
        for theta_i in [60.0_f64, 80.0] {
            let exits = remainder(theta_i, r, eta, walks);
            for band in [(55.0, 65.0), (75.0, 85.0)] {
                let band_exits = in_band(&exits, band);
                let n = band_exits.len() as f64;
                let rho = band_exits.iter().map(|(_, p)| p.cos()).sum::<f64>() / n;
                let rho2 = band_exits.iter().map(|(_, p)| (2.0 * p).cos()).sum::<f64>() / n;
                let sines = band_exits.iter().map(|(mu, _)| (1.0 - mu * mu).sqrt()).sum::<f64>() / n
                    * theta_i.to_radians().sin();
                let kappa = |theta: f64| {
                    let args = [theta.to_radians().cos() as f32, R_C as f32, r as f32, eta as f32];
                    f64::from(tables::lookup::<f32>(TableId::GlossySpread, &args))
                };
                let level = (kappa(theta_i) * kappa((band.0 + band.1) / 2.0)).sqrt() * sines;
                println!(
                    "r {r}, η {eta}, θi {theta_i}°, θo {}–{}°: {} exits; ρ {rho:.3} (the level's {level:.3}), E[cos 2φf] {rho2:.3} (the wrapped Cauchy's {:.3})",
                    band.0,
                    band.1,
                    band_exits.len(),
                    rho * rho
                );
                let mut hist = [0.0; BINS];
                for &(_, p) in &band_exits {
                    hist[((p / PI * BINS as f64) as usize).min(BINS - 1)] += 1.0;
                }
                let cauchy = |phi: f64| (1.0 - rho * rho) / (1.0 + rho * rho - 2.0 * rho * phi.cos());
                let cells: Vec<String> = (0..BINS)
                    .map(|b| {
                        // The Cauchy density averaged over the bin, against the bin's share.
                        let model = (0..16)
                            .map(|k| cauchy((b as f64 + (k as f64 + 0.5) / 16.0) * PI / BINS as f64))
                            .sum::<f64>()
                            / 16.0;
                        format!(
                            "{:.0}°: {:.2}",
                            (b as f64 + 0.5) * 180.0 / BINS as f64,
                            hist[b] / n * BINS as f64 / model
                        )
                    })
                    .collect();
                println!("  {}", cells.join("  "));
            }
        }
    }
    println!("\nOver the polar angles: g(θi, θo) g(30°, 30°) / (g(θi, 30°) g(30°, θo)), 1 where separable\n");
    let bands: [(f64, f64); 6] = [(25.0, 35.0), (55.0, 65.0), (70.0, 75.0), (75.0, 80.0), (80.0, 85.0), (85.0, 88.0)];
    for (r, eta) in coats {
        let g: Vec<Vec<f64>> = [30.0, 60.0, 75.0, 80.0, 85.0, 89.0]
            .iter()
            .map(|&theta_i| {
                let exits = remainder(theta_i, r, eta, walks);
                bands
                    .iter()
                    .map(|&band| {
                        let (c_hi, c_lo) = (band.0.to_radians().cos(), band.1.to_radians().cos());
                        in_band(&exits, band).len() as f64 / (c_hi - c_lo) / ((c_hi + c_lo) / 2.0)
                    })
                    .collect()
            })
            .collect();
        println!("r {r}, η {eta} (θo bands {bands:?}):");
        for (theta_i, row) in [30.0, 60.0, 75.0, 80.0, 85.0, 89.0].iter().zip(&g) {
            let ratios: Vec<String> =
                row.iter().zip(&g[0]).map(|(x, at_30)| format!("{:.2}", x * g[0][0] / (row[0] * at_30))).collect();
            println!("  θi {theta_i}°: {}", ratios.join(" "));
        }
    }
}
