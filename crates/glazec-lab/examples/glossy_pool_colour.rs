//! How well one Fresnel factor per event colours the glossy level's remainder: white walks
//! through a coat over a conductor of roughness 0.3 (`glazec_lab::bake::glossy::walk_events`,
//! θᵢ 60°), and per channel of copper, gold and aluminium (complex IORs, relative to the coat)
//! the remainder's colour (walks that left after three or more events) with each event's own
//! Fresnel factor, Σ Π F(μⱼ), against the level's model Σ c^(n−1) with c from the events' cosines
//! four ways: F at their mean cosine μ* (what the level takes, `glossy_pool_cosine`), the mean
//! of F, the geometric mean of F, and F at μ* ± one standard deviation (geometric mean); and the
//! mean cosine of the second event (the first return) and of the remainder's last event.
//!
//! `cargo run --release -p glazec-lab --example glossy_pool_colour [-- WALKS]`

use glam::DVec3;
use glazec_lab::bake::glossy::walk_events;
use glazec_lab::reference::fresnel_conductor;

/// (name, η, κ) against air, at about 650, 550 and 450 nm.
const METALS: [(&str, [f64; 3], [f64; 3]); 3] = [
    ("copper", [0.27, 0.68, 1.22], [3.61, 2.63, 2.29]),
    ("gold", [0.17, 0.43, 1.44], [3.5, 2.46, 1.8]),
    ("aluminium", [1.35, 0.96, 0.62], [7.5, 6.69, 5.4]),
];

fn main() {
    let walks: u32 = std::env::args().nth(1).and_then(|w| w.parse().ok()).unwrap_or(500_000);
    println!("model / walks per channel (R, G, B): c = F(μ*) | mean F | geometric mean F | F at μ* ± σ\n");
    for (eta, r, r_c) in
        [(1.33, 0.0, 0.3), (1.5, 0.0, 0.3), (2.0, 0.0, 0.3), (1.5, 0.2, 0.1), (1.5, 0.5, 0.3), (2.0, 0.2, 0.3)]
    {
        let events = walk_events(60.0_f64.to_radians().cos(), r_c, r, eta, walks, 5);
        let remainder: Vec<&Vec<f64>> = events.iter().filter(|e| e.len() >= 3).collect();
        let later: Vec<f64> = events.iter().flat_map(|e| e.iter().skip(1).copied()).collect();
        let n = later.len() as f64;
        let mu_star = later.iter().sum::<f64>() / n;
        let sd = (later.iter().map(|m| (m - mu_star).powi(2)).sum::<f64>() / n).sqrt();
        let second: Vec<f64> = events.iter().filter_map(|e| e.get(1).copied()).collect();
        let mu_second = second.iter().sum::<f64>() / second.len() as f64;
        let last: Vec<f64> = remainder.iter().filter_map(|e| e.last().copied()).collect();
        let mu_last = last.iter().sum::<f64>() / last.len() as f64;
        println!(
            "η {eta}, coat roughness {r}, conductor roughness {r_c}: μ* {mu_star:.3} ± {sd:.3}; the second event's {mu_second:.3}, the remainder's last event's {mu_last:.3}"
        );
        for (name, ior, k) in METALS {
            let (ior, k) = (DVec3::from(ior) / eta, DVec3::from(k) / eta);
            let mut line = format!("  {name:9}");
            for ch in 0..3 {
                let f = |m: f64| fresnel_conductor(m, ior, k)[ch];
                let walked: f64 = remainder.iter().map(|e| e.iter().skip(1).map(|&m| f(m)).product::<f64>()).sum();
                let model = |c: f64| remainder.iter().map(|e| c.powi(e.len() as i32 - 1)).sum::<f64>() / walked;
                let mean = later.iter().map(|&m| f(m)).sum::<f64>() / n;
                let geometric = (later.iter().map(|&m| f(m).ln()).sum::<f64>() / n).exp();
                let spread = ((f((mu_star - sd).max(0.0)).ln() + f((mu_star + sd).min(1.0)).ln()) * 0.5).exp();
                let ends = (f(mu_second) * f(mu_last)) / f(mu_star).powi(2);
                line += &format!(
                    " | {:.3} {:.3} {:.3} {:.3} {:.3}",
                    model(f(mu_star)),
                    model(mean),
                    model(geometric),
                    model(spread),
                    model(f(mu_star)) * ends
                );
            }
            println!("{line}");
        }
    }
}
