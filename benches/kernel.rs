//! Throughput of the `eval_pairs` compute kernel on the device (lavapipe here): evaluations per
//! second for each layering method on the same stack (the seed's clay), the median of several
//! dispatches of 1M direction pairs, and the ratio to a baseline measured in the same run (a
//! bare Lambert material: the cost of the dispatch and the memory traffic alone).
//!
//! `cargo bench --bench kernel` (set `LP_NUM_THREADS` to change lavapipe's worker count).

use glam::Vec3;
use glazec::eval::Pair;
use glazec::run::{EvalKernel, Gpu, ShaderPath};

/// Direction pairs per dispatch.
const PAIRS: usize = 1 << 20;
/// Timed dispatches per kernel (after one warm-up).
const REPEATS: usize = 9;

const CLAY_STACK: &str = "layers: [
    Coat(lobe: Ggx(roughness: 0.35), ior: 1.5, absorption: 0.8, thickness: 0.25),
    OrenNayar(albedo: (0.72, 0.42, 0.30), roughness: 0.6),
]";

fn pairs() -> Vec<Pair> {
    // A deterministic spread over the upper hemisphere (golden-ratio sequences).
    (0..PAIRS)
        .map(|i| {
            let u = (i as f32 * 0.618_034).fract();
            let v = (i as f32 * 0.754_877_7).fract();
            let w = (i as f32 * 0.569_840_3).fract();
            let (ti, to, phi) = (u.acos() * 0.99, v.acos() * 0.99, w * std::f32::consts::TAU);
            Pair {
                wi: Vec3::new(ti.sin() * phi.cos(), ti.sin() * phi.sin(), ti.cos()),
                wo: Vec3::new(to.sin(), 0.0, to.cos()),
            }
        })
        .collect()
}

fn median_seconds(gpu: &Gpu, text: &str, pairs: &[Pair]) -> f64 {
    let compiled = glazec::compile(text).expect("compiles");
    let kernel = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).expect("kernel");
    let mut times: Vec<f64> = kernel
        .time_dispatches(gpu, pairs, &compiled.material.default_values(), REPEATS)
        .expect("runs")
        .iter()
        .map(|d| d.as_secs_f64())
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() {
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("skipped: {e}");
            return;
        }
    };
    let pairs = pairs();
    println!("eval_pairs throughput on {}, {} pairs, median of {REPEATS} dispatches", gpu.describe(), pairs.len());
    let baseline = median_seconds(&gpu, "Material(name: \"lambert\", layers: [Lambert(0.5)])", &pairs);
    println!("{:<16} {:>10.1} M evals/s  (baseline)", "Lambert", pairs.len() as f64 / baseline / 1e6);
    for method in ["Additive", "WeidlichWilkie", "Interfaced"] {
        let text = format!("Material(name: \"clay_{}\", method: {method}, {CLAY_STACK})", method.to_lowercase());
        let seconds = median_seconds(&gpu, &text, &pairs);
        println!(
            "{method:<16} {:>10.1} M evals/s  ({:.2}× the baseline's time)",
            pairs.len() as f64 / seconds / 1e6,
            seconds / baseline
        );
    }
}
