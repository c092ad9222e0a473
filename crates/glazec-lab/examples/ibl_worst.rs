//! Where the split sum of image-based lighting misses most against brute force, on the CPU: the
//! points of `tests/ibl.rs` (the sky, or the studio, a 64 × 64 sphere, every 4th pixel inside |p|² < 0.9), each
//! split-sum lobe's share there (weight, direction, roughness, what it looks up), and the brute
//! force of the material's own f (`environment_integral`).
//!
//! `cargo run --release -p glazec-lab --features gpu --example ibl_worst -- materials/red_plastic.ron [COUNT [sky|studio]]`

use glam::Vec3;
use glazec_gpu::environment::prefilter;
use glazec_gpu::preview::Environment;
use glazec_lab::reference::environment::environment_integral;

const SIZE: usize = 64;
const STRIDE: usize = 4;
const MAX_R2: f32 = 0.9;
const SAMPLES: u32 = 4096;

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: ibl_worst <material.ron> [COUNT [sky|studio]]");
        std::process::exit(2);
    };
    let count: usize = std::env::args().nth(2).and_then(|c| c.parse().ok()).unwrap_or(8);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let compiled = glazec::compile(&text).unwrap_or_else(|e| panic!("{e:?}"));
    let material = &compiled.material;
    let values = material.default_values();
    let environment = match std::env::args().nth(3).as_deref() {
        Some("studio") => Environment::Studio,
        _ => Environment::Sky,
    };
    let prefiltered = prefilter(&environment.image(1024).expect("the sky is analytic"));
    let mut rows = Vec::new();
    for y in (STRIDE / 2..SIZE).step_by(STRIDE) {
        for x in (STRIDE / 2..SIZE).step_by(STRIDE) {
            let px = 2.0 * (x as f32 + 0.5) / SIZE as f32 - 1.0;
            let py = 1.0 - 2.0 * (y as f32 + 0.5) / SIZE as f32;
            let r2 = px * px + py * py;
            if r2 >= MAX_R2 {
                continue;
            }
            let n = Vec3::new(px, py, (1.0 - r2).sqrt());
            let lobes = glazec::eval::environment_lobes(material, &values, n, Vec3::Z);
            let split = prefiltered.shade(&lobes);
            let (truth, _) = environment_integral(
                material,
                &values,
                (n, Vec3::Z),
                &|d| environment.radiance(d),
                SAMPLES,
                rows.len() as u64,
            );
            rows.push((n, lobes, split, truth));
        }
    }
    let scale = rows.iter().map(|r| luminance(r.3)).sum::<f32>() / rows.len() as f32;
    let error = |r: &(Vec3, Vec<glazec::math::layering::environment::EnvironmentLobe<f32>>, Vec3, Vec3)| {
        (luminance(r.2) - luminance(r.3)) / scale
    };
    rows.sort_by(|a, b| error(b).abs().total_cmp(&error(a).abs()));
    let rms = (rows.iter().map(|r| error(r).powi(2)).sum::<f32>() / rows.len() as f32).sqrt();
    println!(
        "{} points, mean luminance {scale:.4}: split sum against brute force RMS {:.3}, worst {:.3}",
        rows.len(),
        rms,
        error(&rows[0]).abs()
    );
    for row in rows.iter().take(count) {
        let (n, lobes, split, truth) = row;
        println!(
            "n {n:.3}: split sum {:.4}, brute force {:.4}: {:+.1}% of the mean",
            luminance(*split),
            luminance(*truth),
            100.0 * error(row)
        );
        for lobe in lobes {
            let looked = prefiltered.shade(std::slice::from_ref(lobe));
            println!(
                "    {:?} weight {:.3} direction {:.3} roughness {:.3}: {:.4}",
                lobe.lookup,
                lobe.weight,
                lobe.direction,
                lobe.roughness,
                luminance(looked)
            );
        }
    }
}
