//! Where a GTR1 coat's multiply-scattered reflection goes, from the reference's walks on a GTR1
//! microsurface (`glazec_lab::reference::gtr1`), and why the interfaced method does not scale a
//! GTR1 coat's lobe to reflect it (`glazec::math::tables::CoatTables::GTR1`).
//!
//! Per roughness: the albedo of the reflection after two or more events, ⟨E_ms⟩, and per pair
//! of directions what the later events add to the single-scattering lobe (walks from the more
//! grazing direction), beside what a scale c(μl)c(μv) solved to reflect them would add near a
//! narrow lobe's peak, √((1 + E_ms/E_ss)(μl) (1 + E_ms/E_ss)(μv)) − 1 (Turquin 2019's factor,
//! made symmetric).
//!
//! `cargo run --release -p glazec-lab --example gtr1_later_events [-- WALKS]`

use glazec::math::sampling::{direction_at_cosine, direction_deg};
use glazec_lab::reference::microsurface::RoughDielectric;
use glazec_lab::reference::{Ndf, Rng};

/// Cosine nodes of the E_ss, E_ms curves (midpoints of equal steps in μ).
const NODES: usize = 40;

fn main() {
    let walks: u32 = std::env::args().nth(1).and_then(|w| w.parse().ok()).unwrap_or(200_000);
    let eta = 1.5;
    // (θ of l, θ of v, azimuth between them), degrees; 180 is the mirror plane.
    let pairs = [
        (0.0, 0.0, 0.0),
        (20.0, 20.0, 180.0),
        (60.0, 60.0, 180.0),
        (85.0, 85.0, 180.0),
        (5.0, 5.0, 90.0),
        (30.0, 45.0, 90.0),
        (60.0, 60.0, 90.0),
        (80.0, 30.0, 90.0),
        (85.0, 85.0, 0.0),
    ];
    for roughness in [0.14, 0.4] {
        let surface = RoughDielectric { eta, alpha: roughness * roughness, ndf: Ndf::Gtr1 };
        let mut rng = Rng::seeded(3);
        let mus: Vec<f64> = (0..NODES).map(|i| (i as f64 + 0.5) / NODES as f64).collect();
        // (E_ss, E_ms) per node: the shares of walks reflected after one event and after more.
        let shares: Vec<(f64, f64)> = mus
            .iter()
            .map(|&mu| {
                let (mut single, mut multiple) = (0u32, 0u32);
                for _ in 0..walks / 4 {
                    let (out, events) = surface.walk(direction_at_cosine(mu), &mut rng);
                    if out.z > 0.0 {
                        if events >= 2 { multiple += 1 } else { single += 1 }
                    }
                }
                let n = f64::from(walks / 4);
                (f64::from(single) / n, f64::from(multiple) / n)
            })
            .collect();
        let average: f64 = mus.iter().zip(&shares).map(|(mu, (_, ms))| 2.0 * mu * ms / NODES as f64).sum();
        let at = |mu: f64| {
            let x = (mu * NODES as f64 - 0.5).clamp(0.0, (NODES - 1) as f64);
            let i = (x.floor() as usize).min(NODES - 2);
            let t = x - i as f64;
            let (a, b) = (shares[i], shares[i + 1]);
            (a.0 * (1.0 - t) + b.0 * t, a.1 * (1.0 - t) + b.1 * t)
        };
        println!("\nGtr1({roughness}), η {eta}: ⟨E_ms⟩ = {:.2}%\n", 100.0 * average);
        println!("| θl / θv / φ | single-scattering f | later events' f | later / single | a scale's addition |");
        println!("|---|---|---|---|---|");
        for (k, &(tl, tv, phi)) in pairs.iter().enumerate() {
            let (l, v) = (direction_deg(tl, 0.0), direction_deg(tv, phi));
            let (start, toward) = if l.z < v.z { (l, v) } else { (v, l) };
            let (first, later) = surface.first_and_later_events(start, toward, walks, 11 + k as u64);
            let factor = |mu: f64| {
                let (ss, ms) = at(mu);
                1.0 + ms / ss.max(1e-12)
            };
            let scale = (factor(l.z) * factor(v.z)).sqrt() - 1.0;
            println!(
                "| {tl} / {tv} / {phi} | {:.3e} | {:.3e} | {:.2}% | {:.1}% |",
                first / toward.z,
                later / toward.z,
                100.0 * later / first,
                100.0 * scale
            );
        }
    }
}
