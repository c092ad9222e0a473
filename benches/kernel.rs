//! Throughput of the `eval_pairs` compute kernel on the device (lavapipe here): evaluations per
//! second for each layering method on the same stack (the seed's clay), the median of several
//! dispatches of 1M direction pairs, and the ratio to a baseline measured in the same run (a
//! bare Lambert material: the cost of the dispatch and the memory traffic alone). Then the
//! generated WeidlichWilkie clay kernel against the same shader written by hand
//! (`crates/glazec-lab/data/clay_by_hand.wgsl`), after checking that both compute the same values.
//!
//! `cargo bench --bench kernel` (set `LP_NUM_THREADS` to change lavapipe's worker count); the
//! same measurements, with more, are `glazec bench`.

use glazec_gpu::throughput::{self, PAIRS};
use glazec_gpu::{EvalKernel, Gpu, ShaderPath};
use glazec_lab::bench::{self, CLAY_STACK};

/// Largest relative difference allowed between the hand-written and the generated clay where
/// |f| is significant (the GPU agreement tests' tolerance).
const SAME_VALUES: f32 = 2e-4;

fn median_seconds(gpu: &Gpu, text: &str, pairs: &[glazec::eval::Pair]) -> f64 {
    let compiled = glazec::compile(text).expect("compiles");
    let kernel = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).expect("kernel");
    throughput::kernel_seconds(gpu, &kernel, pairs).expect("runs")
}

fn main() {
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("skipped: {e}");
            return;
        }
    };
    let pairs = throughput::pairs(PAIRS);
    println!(
        "eval_pairs throughput on {}, {} pairs, median of {} dispatches",
        gpu.describe(),
        pairs.len(),
        throughput::REPEATS
    );
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
    let (generated, hand, worst) = bench::against_hand_written(&gpu, &pairs).expect("runs");
    assert!(worst <= SAME_VALUES, "hand-written clay differs from the generated one by {worst:e}");
    println!(
        "WeidlichWilkie clay: generated {:.1} M evals/s, hand-written {:.1} M evals/s: generated/hand-written time {:.3}× (values agree to {worst:.1e})",
        pairs.len() as f64 / generated / 1e6,
        pairs.len() as f64 / hand / 1e6,
        generated / hand
    );
}
