//! How the glossy level's remainder spreads over the azimuth by event count, from white walks
//! through a coat over a conductor (`glazec_lab::bake::glossy::event_counts`): per count n the
//! mean resultant length E[cos φf]/E[sin θᵢ sin θₒ] (κₙ), and for light whose every event
//! keeps a share c of it, the walks' κ_c = Σ cⁿ Σcos / Σ cⁿ Σsines against what
//! `glossy_spread_colour`'s random-walk model makes of the white κ (here with the walks' own
//! event counts and their mean sin θᵢ sin θₒ; the shader takes both from its tables). The model
//! overstates the walks' ratio κ_c/κ; docs/accuracy.md says why it is kept.
//!
//! `cargo run --release -p glazec-lab --example glossy_colour_spread [-- WALKS]`

use glazec_lab::bake::glossy::event_counts;

fn main() {
    let walks: u32 = std::env::args().nth(1).and_then(|w| w.parse().ok()).unwrap_or(200_000);
    for (r, eta) in [(0.0, 1.5), (0.05, 1.5), (0.2, 1.5), (0.5, 1.5), (0.2, 1.33)] {
        for theta in [30.0_f64, 60.0, 80.0] {
            let counts = event_counts(theta.to_radians().cos(), 0.3, r, eta, walks, 7);
            let by = &counts.forward_by_events;
            let share = |k: usize| counts.share(k);
            // Remainder: n ≥ 3 events (index ≥ 2); later count m = n − 2.
            let kappa_c = |c: f64| {
                let (mut num, mut den) = (0.0, 0.0);
                for (k, &(cos, w)) in by.iter().enumerate().skip(2) {
                    num += c.powi(k as i32 + 1) * cos;
                    den += c.powi(k as i32 + 1) * w;
                }
                num / den.max(1e-300)
            };
            let mean_sines = {
                let (w, n): (f64, f64) = by
                    .iter()
                    .enumerate()
                    .skip(2)
                    .map(|(k, &(_, w))| (w, share(k)))
                    .fold((0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
                w / (n * counts.entered as f64).max(1e-300)
            };
            let later = |z: f64| (2..by.len()).map(|k| share(k) * z.powi(k as i32 - 1)).sum::<f64>();
            let mean_m = (2..by.len()).map(|k| share(k) * (k as f64 - 1.0)).sum::<f64>() / later(1.0).max(1e-300);
            let rho_w = kappa_c(1.0) * mean_sines;
            let rho1 = rho_w.max(1e-6).powf(1.0 / mean_m);
            let model = |c: f64| rho_w * (later(c * rho1) / later(c)) / (later(rho1) / later(1.0)) / mean_sines;
            let per_n: Vec<String> =
                [2usize, 3, 4, 6, 9, 14, 20].iter().map(|&k| format!("{:.2}", by[k].0 / by[k].1.max(1e-300))).collect();
            println!("r {r} η {eta} θ {theta}: n̄ later {mean_m:.1}, κ by n (3,4,5,7,10,15,21) [{}]", per_n.join(" "));
            for c in [0.9, 0.7, 0.5, 0.3] {
                println!(
                    "    c {c}: walks κ_c/κ {:.3}, model {:.3}",
                    kappa_c(c) / kappa_c(1.0),
                    model(c) / kappa_c(1.0)
                );
            }
        }
    }
}
