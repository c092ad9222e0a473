//! Where a white conductor's light leaves a coat, by conductor events, against the glossy
//! level's parts: white walks (`glazec_lab::bake::glossy::walk_exits`) per bin of the exit's
//! azimuth φf about the forward direction (0° forward) and band of exit angles, as f averaged
//! over the bin; the walks that left after one event against the level's lobe (`glossy_lobe_white`
//! times the scales s(μᵢ) s(μₒ)), and the rest against the level's f less that lobe and less the
//! coat's own reflection (the same coat over a black base). The lobe also holds w₀ of the light
//! that leaves at the second event, which the walks count in the rest. Then the mean resultant
//! length ρ of the rest's azimuth per pair of angles against the level's,
//! √(κ(μᵢ) κ(μₒ)) sin θᵢ sin θₒ (`glossy_spread`).
//!
//! `cargo run --release -p glazec-lab --example glossy_lobe_events [-- WALKS R ETA]`
//! (a conductor of roughness 0.3 under a GGX coat of roughness R, relative IOR ETA; defaults
//! 1,000,000 walks, 0.5, 1.5).

use glam::DVec3;
use glazec::math::layering::glossy_lobe_white;
use glazec::math::sampling::direction_deg;
use glazec::math::tables::{TableId, lookup};
use glazec::model::Material;
use glazec_lab::bake::glossy::walk_exits;

/// The conductor's roughness.
const R_C: f64 = 0.3;
/// Bins of φf, degrees.
const BINS: [(f64, f64); 4] = [(0.0, 30.0), (30.0, 60.0), (60.0, 120.0), (120.0, 180.0)];
/// Azimuths per bin the level is averaged over.
const STEPS: usize = 24;

/// The unit directions at polar angles `ti`, `to` (degrees) and azimuth φf (radians) about the
/// forward direction (`direction_deg`'s φ = 180° − φf).
fn directions(ti: f64, to: f64, phi_f: f64) -> (DVec3, DVec3) {
    (direction_deg(ti, 0.0), direction_deg(to, 180.0 - phi_f.to_degrees()))
}

/// `f` averaged over the bin's azimuths.
fn bin_mean(bin: (f64, f64), f: impl Fn(f64) -> f64) -> f64 {
    (0..STEPS).map(|k| f((bin.0 + (k as f64 + 0.5) / STEPS as f64 * (bin.1 - bin.0)).to_radians())).sum::<f64>()
        / STEPS as f64
}

fn material(r: f64, eta: f64, base: &str) -> Result<Material, String> {
    let text = format!("Material(name: \"m\", layers: [Coat(lobe: Ggx(roughness: {r}), ior: {eta}), {base}])");
    glazec::load(&text).map(|(m, _)| m).map_err(|e| format!("{e:?}"))
}

fn main() -> Result<(), String> {
    let arg = |i: usize, default: f64| std::env::args().nth(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (walks, r, eta) = (arg(1, 1e6) as u32, arg(2, 0.5), arg(3, 1.5));
    let white = material(r, eta, "Conductor(roughness: 0.3, f0: (1.0, 1.0, 1.0))")?;
    let black = material(r, eta, "Lambert(albedo: (0.0, 0.0, 0.0))")?;
    let below = |wi: DVec3, wo: DVec3| {
        let (wi, wo) = (wi.as_vec3(), wo.as_vec3());
        f64::from(glazec::eval::brdf(&white, &[], wi, wo).x - glazec::eval::brdf(&black, &[], wi, wo).x)
    };
    let scale =
        |mu: f64| f64::from(lookup::<f32>(TableId::GlossyScale, &[mu as f32, R_C as f32, r as f32, eta as f32]));
    let lobe = |wi: DVec3, wo: DVec3| glossy_lobe_white(R_C, r, eta, wi, wo) * scale(wi.z) * scale(wo.z);
    println!(
        "Conductor r {R_C} under a GGX coat r {r}, η {eta}; f per bin of φf: walks' one event / level's lobe; walks' rest / level's rest\n"
    );
    println!("| θi | θo band | 0°–30° | 30°–60° | 60°–120° | 120°–180° |");
    println!("|---|---|---|---|---|---|");
    for (ti, lo, hi) in [
        (20.0_f64, 45.0, 55.0),
        (35.0, 30.0, 40.0),
        (35.0, 45.0, 55.0),
        (75.0, 55.0, 65.0),
        (89.0, 55.0, 65.0),
        (89.0, 70.0, 80.0),
        (85.0, 80.0, 88.0_f64),
    ] {
        let exits = walk_exits(ti.to_radians().cos(), R_C, r, eta, walks, 9);
        let (a, b) = (f64::to_radians(hi).cos(), f64::to_radians(lo).cos());
        let centre = (lo + hi) / 2.0;
        let cells: Vec<String> = BINS
            .iter()
            .map(|&(p0, p1)| {
                let in_bin = |&&(mu, phi, _): &&(f64, f64, usize)| {
                    mu >= a && mu < b && phi.to_degrees() >= p0 && phi.to_degrees() < p1
                };
                // f over the bin: exits per walk over ∫ μ dω of the bin (both sides of the plane).
                let per =
                    |n: usize| n as f64 / f64::from(walks) / ((b * b - a * a) / 2.0 * 2.0 * (p1 - p0).to_radians());
                let all = per(exits.iter().filter(in_bin).count());
                let one = per(exits.iter().filter(in_bin).filter(|e| e.2 == 1).count());
                let level_lobe = bin_mean((p0, p1), |p| {
                    let (wi, wo) = directions(ti, centre, p);
                    lobe(wi, wo)
                });
                let level = bin_mean((p0, p1), |p| {
                    let (wi, wo) = directions(ti, centre, p);
                    below(wi, wo)
                });
                format!("{one:.3} / {level_lobe:.3}; {:.3} / {:.3}", all - one, level - level_lobe)
            })
            .collect();
        println!("| {ti}° | {lo}°–{hi}° | {} |", cells.join(" | "));
    }
    let kappa =
        |mu: f64| f64::from(lookup::<f32>(TableId::GlossySpread, &[mu as f32, R_C as f32, r as f32, eta as f32]));
    let bands = [(15.0, 25.0), (30.0, 40.0), (45.0, 55.0), (55.0, 65.0), (70.0, 80.0), (80.0, 88.0_f64)];
    println!("\nρ of the walks that left after two or more events / the level's, θo bands {bands:?}\n");
    for ti in [20.0_f64, 35.0, 50.0, 60.0, 75.0, 89.0] {
        let exits = walk_exits(ti.to_radians().cos(), R_C, r, eta, walks, 5);
        let row: Vec<String> = bands
            .iter()
            .map(|&(lo, hi)| {
                let (a, b) = (f64::to_radians(hi).cos(), f64::to_radians(lo).cos());
                let rest: Vec<f64> =
                    exits.iter().filter(|e| e.2 >= 2 && e.0 >= a && e.0 < b).map(|e| e.1.cos()).collect();
                let walks_rho = rest.iter().sum::<f64>() / rest.len().max(1) as f64;
                let to = ((lo + hi) / 2.0_f64).to_radians();
                let ti = ti.to_radians();
                let level = (kappa(ti.cos()) * kappa(to.cos())).sqrt() * ti.sin() * to.sin();
                format!("{walks_rho:.2} / {level:.2}")
            })
            .collect();
        println!("θi {ti}°: {}", row.join(", "));
    }
    Ok(())
}
