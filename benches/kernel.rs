//! Throughput of the `eval_pairs` compute kernel on the device (lavapipe here): evaluations per
//! second for each layering method on the same stack (the seed's clay), the median of several
//! dispatches of 1M direction pairs, and the ratio to a baseline measured in the same run (a
//! bare Lambert material: the cost of the dispatch and the memory traffic alone). Then the
//! generated WeidlichWilkie clay kernel against the same shader written by hand
//! (`benches/clay_by_hand.wgsl`), after checking that both compute the same values.
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

/// Largest relative difference allowed between the hand-written and the generated clay where
/// |f| is significant (the GPU agreement tests' tolerance).
const SAME_VALUES: f32 = 2e-4;

fn median_seconds(gpu: &Gpu, text: &str, pairs: &[Pair]) -> f64 {
    let compiled = glazec::compile(text).expect("compiles");
    let kernel = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).expect("kernel");
    median_of(&kernel, gpu, pairs, &compiled.material.default_values())
}

fn median_of(kernel: &EvalKernel, gpu: &Gpu, pairs: &[Pair], params: &[glazec::model::ParamValue]) -> f64 {
    let mut times: Vec<f64> =
        kernel.time_dispatches(gpu, pairs, params, REPEATS).expect("runs").iter().map(|d| d.as_secs_f64()).collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The generated WeidlichWilkie clay against `benches/clay_by_hand.wgsl`, interleaved so that
/// both see the same machine state.
fn against_hand_written(gpu: &Gpu, pairs: &[Pair]) {
    let text = format!("Material(name: \"clay_ww\", method: WeidlichWilkie, {CLAY_STACK})");
    let compiled = glazec::compile(&text).expect("compiles");
    let generated = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).expect("kernel");
    let hand =
        EvalKernel::from_wgsl(gpu, "clay_by_hand", include_str!("clay_by_hand.wgsl")).expect("hand-written kernel");
    let check = &pairs[..4096];
    let (a, b) = (generated.eval(gpu, check, &[]).expect("runs"), hand.eval(gpu, check, &[]).expect("runs"));
    let max = a.iter().map(|f| f.max_element()).fold(0.0_f32, f32::max);
    let worst = a
        .iter()
        .zip(&b)
        .flat_map(|(x, y)| (0..3).map(move |c| (x[c], y[c])))
        .filter(|(x, _)| x.abs() > 1e-4 * max)
        .map(|(x, y)| (x - y).abs() / x.abs())
        .fold(0.0_f32, f32::max);
    assert!(worst <= SAME_VALUES, "hand-written clay differs from the generated one by {worst:e}");
    let (mut generated_times, mut hand_times) = (Vec::new(), Vec::new());
    for _ in 0..3 {
        generated_times.push(median_of(&generated, gpu, pairs, &[]));
        hand_times.push(median_of(&hand, gpu, pairs, &[]));
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (g, h) = (median(generated_times), median(hand_times));
    println!(
        "WeidlichWilkie clay: generated {:.1} M evals/s, hand-written {:.1} M evals/s: generated/hand-written time {:.3}× (values agree to {worst:.1e})",
        pairs.len() as f64 / g / 1e6,
        pairs.len() as f64 / h / 1e6,
        g / h
    );
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
    against_hand_written(&gpu, &pairs);
}
