//! How far a coloured conductor's remainder under a coat moves forward, the walks against the
//! glossy level's model: white walks (`walk_returns`) weighed by cⁿ (a constant per-event
//! survival c), over the walks the remainder holds (three or more events; at the second after
//! total internal reflection), at θᵢ and exits within ±5° of θₒ; the mean resultant length of
//! their azimuth about the forward direction, white and coloured, and the coloured light's
//! share per bin of φf (0° forward; [`BINS`]) over white's, each over its mean; against the
//! level's ρ (κ from `GlossySpread`), ρ_c (`glossy_spread_colour` over the tables' event
//! counts), the share its tilt (`forward_azimuth_tilt`, averaged over each bin under the white
//! weight) gives per bin, and what the random-walk model behind ρ_c gives to the side
//! (φf = 90°) and behind (φf = 165°) when summed over the event counts (a wrapped Cauchy of
//! A·ρ₁ⁿ after n events) instead of tilted.
//!
//! `cargo run --release -p glazec-lab --example spread_colour [-- WALKS]`

use glam::Vec3;
use glazec::math::tables::{TableId, lookup};
use glazec::math::terms::{forward_azimuth_tilt, forward_azimuth_weight, glossy_spread_colour};
use glazec_lab::bake::glossy::{escape_cone_cosine, walk_returns};

/// Bins of φf about the forward direction, degrees.
const BINS: [(f64, f64); 6] = [(0.0, 20.0), (20.0, 45.0), (45.0, 75.0), (75.0, 105.0), (105.0, 135.0), (135.0, 180.0)];

fn main() {
    let walks: u32 = std::env::args().nth(1).and_then(|w| w.parse().ok()).unwrap_or(1_000_000);
    println!(
        "| r_c, r, η | θi/θo | c | walks ρ white / coloured | walks: share per bin of φf | model ρ / ρ_c | tilt: share per bin | random walk: side, back |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (r_c, r, eta) in
        [(0.25_f64, 0.1_f64, 1.5_f64), (0.3, 0.0, 1.5), (0.3, 0.0, 2.0), (0.3, 0.2, 1.33), (0.3, 0.5, 1.5)]
    {
        let cone = escape_cone_cosine(eta);
        for (theta_i, theta_o) in [(85.0_f64, 75.0_f64), (75.0, 75.0), (60.0, 60.0)] {
            let mu_i = theta_i.to_radians().cos();
            let returns = walk_returns(mu_i, r_c, r, eta, walks, 11);
            let kept: Vec<_> = returns
                .iter()
                .filter(|w| w.events >= 3 || (w.events == 2 && w.first_return <= cone))
                .filter_map(|w| {
                    let (cos_phi, sines) = w.forward?;
                    let exit = (sines / theta_i.to_radians().sin()).clamp(0.0, 1.0).asin().to_degrees();
                    ((exit - theta_o).abs() < 5.0).then_some((cos_phi.clamp(-1.0, 1.0), w.events))
                })
                .collect();
            let at = |mu: f64| [mu as f32, r_c as f32, r as f32, eta as f32];
            let mu_o = theta_o.to_radians().cos();
            let mean = |id: TableId| 0.5 * (lookup::<f32>(id, &at(mu_i)) + lookup::<f32>(id, &at(mu_o)));
            let slow = lookup::<f32>(TableId::GlossySlowRetention, &[r_c as f32, r as f32, eta as f32]);
            let kappa = (lookup::<f32>(TableId::GlossySpread, &at(mu_i))
                * lookup::<f32>(TableId::GlossySpread, &at(mu_o)))
            .sqrt();
            let rho = (kappa * (theta_i.to_radians().sin() * theta_o.to_radians().sin()) as f32).min(0.95);
            for c in [0.9_f64, 0.6] {
                let weigh = |coloured: bool, keep: &dyn Fn(f64) -> bool| -> (f64, f64) {
                    kept.iter()
                        .filter(|(p, _)| keep(*p))
                        .map(|&(p, n)| (if coloured { c.powi(n as i32) } else { 1.0 }, p))
                        .fold((0.0, 0.0), |(s, m), (w, p)| (s + w, m + w * p))
                };
                let (white, white_cos) = weigh(false, &|_| true);
                let (coloured, coloured_cos) = weigh(true, &|_| true);
                let share =
                    |keep: &dyn Fn(f64) -> bool| (weigh(true, keep).0 / coloured) / (weigh(false, keep).0 / white);
                let walk_shares: Vec<String> = BINS
                    .iter()
                    .map(|&(lo, hi)| format!("{:.2}", share(&|p: f64| (lo..hi).contains(&p.acos().to_degrees()))))
                    .collect();
                let rho_c = glossy_spread_colour::<f32>(
                    rho,
                    mean(TableId::GlossyNext),
                    mean(TableId::GlossyQuick),
                    mean(TableId::GlossySteady),
                    slow,
                    Vec3::splat(c as f32),
                )
                .x;
                // The random-walk model itself, not its tilt: light that took n more events
                // leaves with a wrapped Cauchy of mean resultant length A·ρ₁ⁿ (ρ₁ = ρ^(1/n̄) as
                // `glossy_spread_colour` takes it, A so that white light's is ρ), summed over
                // the event counts of the tables' geometric mixture, weighed by cⁿ.
                let (next, quick, steady) = (
                    f64::from(mean(TableId::GlossyNext)),
                    f64::from(mean(TableId::GlossyQuick)),
                    f64::from(mean(TableId::GlossySteady)),
                );
                let rest = (1.0 - next - quick - steady).max(0.0);
                let components = [(quick, 0.5), (steady, 0.8), (rest, f64::from(slow))];
                let weight_of =
                    |n: i32| -> f64 { components.iter().map(|&(w, b)| w * (1.0 - b) * b.powi(n - 1)).sum::<f64>() };
                let total: f64 = components.iter().map(|c| c.0).sum::<f64>().max(1e-6);
                let events = (quick * 2.0 + steady * 5.0 + rest / (1.0 - f64::from(slow)).max(1e-6)) / total;
                let step = f64::from(rho).powf(1.0 / events);
                let scale = f64::from(rho) / ((1..400).map(|n| weight_of(n) * step.powi(n)).sum::<f64>() / total);
                let mixture = |survival: f64, cos_phi: f64| {
                    let (mut sum, mut norm) = (0.0, 0.0);
                    for n in 1..400 {
                        let (w, r) = (weight_of(n) * survival.powi(n), (scale * step.powi(n)).min(0.999));
                        sum += w * (1.0 - r * r) / (1.0 + r * r - 2.0 * r * cos_phi);
                        norm += w;
                    }
                    sum / norm
                };
                let random_walk = |cos_phi: f64| mixture(c, cos_phi) / mixture(1.0, cos_phi);
                // The tilt's share per bin: its mean over the bin under the white weight W.
                let tilt_shares: Vec<String> = BINS
                    .iter()
                    .map(|&(lo, hi)| {
                        let (mut tilted, mut plain) = (0.0, 0.0);
                        for k in 0..60 {
                            let cos_phi = (lo + (f64::from(k) + 0.5) / 60.0 * (hi - lo)).to_radians().cos() as f32;
                            let w = forward_azimuth_weight::<f32>(rho, cos_phi);
                            tilted += w * forward_azimuth_tilt::<f32>(rho, Vec3::splat(rho_c), cos_phi).x;
                            plain += w;
                        }
                        format!("{:.2}", tilted / plain)
                    })
                    .collect();
                println!(
                    "| {r_c}, {r}, {eta} | {theta_i}/{theta_o} | {c} | {:.3} / {:.3} | {} | {rho:.3} / {rho_c:.3} | {} | {:.2}, {:.2} |",
                    white_cos / white,
                    coloured_cos / coloured,
                    walk_shares.join(" "),
                    tilt_shares.join(" "),
                    random_walk(0.0),
                    random_walk(-0.966)
                );
            }
        }
    }
}
