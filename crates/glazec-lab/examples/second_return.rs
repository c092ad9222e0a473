//! Where the glossy level's light that leaves at the second conductor event came from: the
//! coat's Fresnel reflection inside the escape cone (which returns it about the mirror direction)
//! or total internal reflection beyond the cone (which the conductor then scatters into the cone
//! anywhere). Per (r_c, r, η) and direction: the share P₁ leaving after one event; of the trapped
//! rest, q₂ leaving at the second event, G the part of q₂ whose first return was inside the
//! cone, F the share of trapped light whose first return was inside the cone; the fitted
//! weight w₀ the level's lobe takes today (`GlossyNext`); and κ = Σ cos φf / Σ sin θᵢ sin θₒ of
//! the walks that left after three or more events, of those that left at the second after
//! total internal reflection, and of both together.
//!
//! `cargo run --release -p glazec-lab --example second_return [-- WALKS]`

use glazec::math::tables::{TableId, lookup};
use glazec_lab::bake::glossy::{WalkReturn, escape_cone_cosine, walk_returns};

fn main() {
    let walks: u32 = std::env::args().nth(1).and_then(|w| w.parse().ok()).unwrap_or(200_000);
    let configs: [(f64, f64, f64); 6] =
        [(0.25, 0.1, 1.5), (0.3, 0.0, 1.5), (0.3, 0.2, 1.5), (0.3, 0.5, 1.5), (0.3, 0.2, 2.0), (0.3, 0.0, 1.33)];
    println!("| r_c, r, η | θ | P₁ | q₂ | G | F | w₀ | κ ≥ 3 | κ 2, TIR | κ both |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (r_c, r, eta) in configs {
        let mu_c = escape_cone_cosine(eta);
        for theta in [85.0_f64, 75.0, 60.0, 40.0] {
            let mu = theta.to_radians().cos();
            let returns = walk_returns(mu, r_c, r, eta, walks, 7);
            let n = returns.len() as f64;
            let count = |keep: &dyn Fn(&WalkReturn) -> bool| returns.iter().filter(|r| keep(r)).count() as f64;
            let kappa = |keep: &dyn Fn(&WalkReturn) -> bool| {
                let (c, w) = returns
                    .iter()
                    .filter(|r| keep(r))
                    .filter_map(|r| r.forward)
                    .fold((0.0, 0.0), |(c, w), (x, y)| (c + x, w + y));
                c / w
            };
            let once = count(&|r| r.events == 1);
            let trapped = n - once;
            let w0 = lookup::<f32>(TableId::GlossyNext, &[mu as f32, r_c as f32, r as f32, eta as f32]);
            println!(
                "| {r_c}, {r}, {eta} | {theta} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} | {:.2} |",
                once / n,
                count(&|r| r.events == 2) / trapped,
                count(&|r| r.events == 2 && r.first_return > mu_c) / trapped,
                count(&|r| r.events >= 2 && r.first_return > mu_c) / trapped,
                w0,
                kappa(&|r| r.events >= 3),
                kappa(&|r| r.events == 2 && r.first_return <= mu_c),
                kappa(&|r| r.events >= 3 || (r.events == 2 && r.first_return <= mu_c)),
            );
        }
    }
}
