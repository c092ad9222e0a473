//! Kernel throughput on the device: how many BRDF evaluations per second a material's
//! `eval_pairs` kernel runs (`glazec compile --scene --throughput`, `glazec bench`).
//!
//! Timings are wall-clock medians of dispatches on whatever device runs them; compare them only
//! as ratios between kernels timed in the same run.

use glam::Vec3;
use glazec::eval::Pair;
use glazec::model::ParamValue;

use crate::{EvalKernel, Gpu, RunError, ShaderPath};

/// Direction pairs per timed dispatch.
pub const PAIRS: usize = 1 << 20;
/// Timed dispatches per kernel and round (after one warm-up).
pub const REPEATS: usize = 7;
/// Interleaved rounds in which the methods' kernels and the Lambert baseline are timed.
pub const ROUNDS: usize = 3;
/// A deterministic spread of pairs over the upper hemisphere (golden-ratio sequences).
pub fn pairs(n: usize) -> Vec<Pair> {
    (0..n)
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

/// The median of `v` (the upper one of an even count).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Median seconds per dispatch of each kernel, timed in [`ROUNDS`] interleaved rounds of
/// [`REPEATS`] dispatches each (after a warm-up), so that a slow spell of the machine falls on
/// every kernel alike rather than on one of them.
pub fn interleaved_seconds(gpu: &Gpu, kernels: &[&EvalKernel], pairs: &[Pair]) -> Result<Vec<f64>, RunError> {
    let with_values: Vec<(&EvalKernel, &[ParamValue])> = kernels.iter().map(|k| (*k, &[][..])).collect();
    interleaved_seconds_with(gpu, &with_values, pairs)
}

/// [`interleaved_seconds`] for kernels with runtime parameters (one value per parameter each).
pub fn interleaved_seconds_with(
    gpu: &Gpu,
    kernels: &[(&EvalKernel, &[ParamValue])],
    pairs: &[Pair],
) -> Result<Vec<f64>, RunError> {
    let mut times = vec![Vec::new(); kernels.len()];
    for _ in 0..ROUNDS {
        for ((kernel, values), t) in kernels.iter().zip(&mut times) {
            t.extend(kernel.time_dispatches(gpu, pairs, values, REPEATS)?.iter().map(|d| d.as_secs_f64()));
        }
    }
    Ok(times.into_iter().map(median).collect())
}

/// Evaluations per second of each material's `eval_pairs` kernel on the device (naga-IR path,
/// default parameter values, [`PAIRS`] pairs), timed in interleaved rounds.
///
/// # Errors
/// A device failure.
pub fn throughputs(gpu: &Gpu, compiled: &[&glazec::Compiled]) -> Result<Vec<f64>, RunError> {
    let kernels: Vec<EvalKernel> =
        compiled.iter().map(|c| EvalKernel::new(gpu, c, ShaderPath::NagaIr)).collect::<Result<_, _>>()?;
    let values: Vec<Vec<ParamValue>> = compiled.iter().map(|c| c.material.default_values()).collect();
    let with_values: Vec<(&EvalKernel, &[ParamValue])> =
        kernels.iter().zip(&values).map(|(k, v)| (k, v.as_slice())).collect();
    let pairs = pairs(PAIRS);
    let seconds = interleaved_seconds_with(gpu, &with_values, &pairs)?;
    Ok(seconds.iter().map(|s| PAIRS as f64 / s).collect())
}

/// Median seconds per dispatch of a kernel.
pub fn kernel_seconds(gpu: &Gpu, kernel: &EvalKernel, pairs: &[Pair]) -> Result<f64, RunError> {
    let times = kernel.time_dispatches(gpu, pairs, &[], REPEATS)?;
    Ok(median(times.iter().map(|d| d.as_secs_f64()).collect()))
}
