//! Speed against accuracy, measured in one run (`glazec bench`).
//!
//! **Input:** a Vulkan device (lavapipe in CI), the stored accuracy reference, `materials/`.
//! **Output:** a Markdown report ([`Report::markdown`]) with, per layering method on the seed's
//! clay stack, the kernel's throughput (median of `REPEATS` dispatches of `PAIRS` pairs after
//! a warm-up) as a ratio to a bare Lambert kernel timed in the same run, its static cost (naga
//! expressions and transcendental calls in the module's functions) and its error on the accuracy
//! set; the generated WeidlichWilkie clay against the same shader written by hand; compile times
//! per material and target; and cost growth with the number of coats (1, 2, 4, 8, 16) with a
//! least-squares line and its R² for compile time, code size and kernel time.
//!
//! Timings are wall-clock medians on whatever machine runs it; the report prints the device and
//! the ratios, which are what compare across machines.

use std::time::Instant;

use glazec::eval::Pair;
use glazec::model::Method;
use glazec_gpu::throughput::{PAIRS, REPEATS, ROUNDS, interleaved_seconds, kernel_seconds, median, pairs};
use glazec_gpu::{EvalKernel, Gpu, ShaderPath};

/// In-process compiles timed per material.
const COMPILES: usize = 15;
/// Coat counts of the scaling sweep.
pub const LAYER_COUNTS: [usize; 5] = [1, 2, 4, 8, 16];

/// The seed's clay stack (materials/clay.ron) under any method.
pub const CLAY_STACK: &str = "layers: [
    Coat(lobe: Ggx(roughness: 0.35), ior: 1.5, absorption: 0.8, thickness: 0.25),
    OrenNayar(albedo: (0.72, 0.42, 0.30), roughness: 0.6),
]";

/// The seed's clay written by hand (`crates/glazec-lab/data/clay_by_hand.wgsl`).
pub const CLAY_BY_HAND: &str = include_str!("../data/clay_by_hand.wgsl");

fn compile(text: &str) -> Result<glazec::Compiled, String> {
    glazec::compile(text).map_err(|e| format!("{e:?}"))
}

/// One method on the clay stack.
pub struct MethodRow {
    pub method: Method,
    pub evals_per_second: f64,
    /// Kernel time over the Lambert kernel's.
    pub time_ratio: f64,
    pub expressions: usize,
    pub transcendental: usize,
    /// Median and largest under-coat lobe relRMSE, largest albedo error on the accuracy set.
    pub lobe_median: f64,
    pub lobe_max: f64,
    pub albedo_max: f64,
}

/// One coat count of the scaling sweep.
pub struct ScaleRow {
    pub coats: usize,
    pub compile_ms: f64,
    pub wgsl_bytes: usize,
    pub expressions: usize,
    pub kernel_ns: f64,
}

/// A least-squares line y = a + b·x and its R².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    pub slope: f64,
    pub intercept: f64,
    pub r2: f64,
}

pub fn linear_fit(xs: &[f64], ys: &[f64]) -> Fit {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let intercept = my - slope * mx;
    let ss_res: f64 = xs.iter().zip(ys).map(|(x, y)| (y - intercept - slope * x).powi(2)).sum();
    let ss_tot: f64 = ys.iter().map(|y| (y - my).powi(2)).sum();
    Fit { slope, intercept, r2: if ss_tot > 0.0 { 1.0 - ss_res / ss_tot } else { 1.0 } }
}

/// Everything `glazec bench` measures.
pub struct Report {
    pub device: String,
    pub lambert_evals_per_second: f64,
    pub methods: Vec<MethodRow>,
    /// (generated, hand-written) seconds per dispatch, and the largest relative difference of
    /// their values.
    pub hand_written: (f64, f64, f32),
    /// (material, target, median µs of compiling it from text to that target).
    pub compile_times: Vec<(String, &'static str, f64)>,
    pub scale: Vec<ScaleRow>,
    /// Median ms of the whole process `glazec compile materials/` (filled in by the CLI).
    pub process_ms: Option<f64>,
    /// (material, one evaluation of its `<m>_brdf`, bytes of its WGSL library).
    pub eval_costs: Vec<(String, glazec::lower::CallCost, usize)>,
}

/// Runs every measurement. `materials`: (name, text) of the materials to time compiling.
///
/// # Errors
/// A device error, or a material that does not compile.
pub fn run(gpu: &Gpu, materials: &[(String, String)], progress: &dyn Fn(&str)) -> Result<Report, String> {
    let pairs = pairs(PAIRS);
    let kernel_of = |text: &str| -> Result<(glazec::Compiled, EvalKernel), String> {
        let compiled = compile(text)?;
        let kernel = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).map_err(|e| e.to_string())?;
        Ok((compiled, kernel))
    };
    let timed = |text: &str| -> Result<(glazec::Compiled, f64), String> {
        let (compiled, kernel) = kernel_of(text)?;
        let seconds = kernel_seconds(gpu, &kernel, &pairs).map_err(|e| e.to_string())?;
        Ok((compiled, seconds))
    };
    progress("accuracy of each method");
    let errors = method_errors();
    progress("kernels of the Lambert baseline and every method, interleaved");
    let (_, lambert_kernel) = kernel_of("Material(name: \"lambert\", layers: [Lambert(0.5)])")?;
    let method_kernels = Method::MEASURED
        .iter()
        .map(|m| kernel_of(&format!("Material(name: \"clay\", method: {}, {CLAY_STACK})", m.source())))
        .collect::<Result<Vec<_>, _>>()?;
    let all: Vec<&EvalKernel> = std::iter::once(&lambert_kernel).chain(method_kernels.iter().map(|(_, k)| k)).collect();
    let seconds = interleaved_seconds(gpu, &all, &pairs).map_err(|e| e.to_string())?;
    let lambert = seconds[0];
    let mut methods = Vec::new();
    for (((method, (lobe_median, lobe_max, albedo_max)), (compiled, _)), &seconds) in
        Method::MEASURED.into_iter().zip(errors).zip(&method_kernels).zip(&seconds[1..])
    {
        let harness = compiled.harness().map_err(|e| e.to_string())?;
        let (expressions, transcendental) = glazec::lower::static_cost(&harness.module);
        methods.push(MethodRow {
            method,
            evals_per_second: PAIRS as f64 / seconds,
            time_ratio: seconds / lambert,
            expressions,
            transcendental,
            lobe_median,
            lobe_max,
            albedo_max,
        });
    }

    progress("hand-written clay");
    let hand_written = against_hand_written(gpu, &pairs)?;

    progress("compile times");
    let mut eval_costs = Vec::new();
    for (name, text) in materials {
        let compiled = compile(text)?;
        let function = format!("{}_brdf", compiled.material.name);
        let cost = glazec::lower::call_cost(&compiled.library, &function).ok_or(format!("no {function}"))?;
        let wgsl = compiled.emit(&[glazec::Target::Wgsl]).map_err(|e| e.to_string())?[0].contents.len();
        eval_costs.push((name.clone(), cost, wgsl));
    }
    let mut compile_times = Vec::new();
    for (name, text) in materials {
        for target in glazec::Target::TEXT {
            let seconds = median(
                (0..COMPILES)
                    .map(|_| {
                        let start = Instant::now();
                        let compiled = compile(text).and_then(|c| c.emit(&[target]).map_err(|e| e.to_string()));
                        std::hint::black_box(compiled).ok();
                        start.elapsed().as_secs_f64()
                    })
                    .collect(),
            );
            compile_times.push((name.clone(), target.name(), seconds * 1e6));
        }
    }

    let mut scale = Vec::new();
    for coats in LAYER_COUNTS {
        progress(&format!("{coats} coats"));
        let text = stack_of(coats);
        let compile_s = median(
            (0..5)
                .map(|_| {
                    let start = Instant::now();
                    let out = compile(&text).and_then(|c| c.emit(&glazec::Target::TEXT).map_err(|e| e.to_string()));
                    std::hint::black_box(out).ok();
                    start.elapsed().as_secs_f64()
                })
                .collect(),
        );
        let (compiled, seconds) = timed(&text)?;
        let wgsl_bytes = compiled.emit(&[glazec::Target::Wgsl]).map_err(|e| e.to_string())?[0].contents.len();
        scale.push(ScaleRow {
            coats,
            compile_ms: compile_s * 1e3,
            wgsl_bytes,
            expressions: glazec::lower::static_cost(&compiled.harness().map_err(|e| e.to_string())?.module).0,
            kernel_ns: seconds / PAIRS as f64 * 1e9,
        });
    }
    Ok(Report {
        device: gpu.describe(),
        lambert_evals_per_second: PAIRS as f64 / lambert,
        methods,
        hand_written,
        compile_times,
        scale,
        process_ms: None,
        eval_costs,
    })
}

/// A stack of `coats` rough coats (r 0.2, η 1.5 and 1.3 alternating, light absorption) over a
/// grey Lambert base.
pub fn stack_of(coats: usize) -> String {
    let layers: Vec<String> = (0..coats)
        .map(|i| {
            let ior = if i % 2 == 0 { 1.5 } else { 1.3 };
            format!("Coat(lobe: Ggx(0.2), ior: {ior}, absorption: 0.1, thickness: 0.5)")
        })
        .collect();
    format!("Material(name: \"stack{coats}\", layers: [{}, Lambert(0.5)])", layers.join(", "))
}

/// (median lobe relRMSE, largest lobe relRMSE, largest albedo error) per method of
/// [`Method::MEASURED`], in that order; NaN if the stored reference is missing.
fn method_errors() -> Vec<(f64, f64, f64)> {
    use crate::accuracy;
    let cases = accuracy::standard_set();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/reference/standard-multiple.bin");
    let Ok(data) = accuracy::ReferenceData::read(&path, cases.len()) else {
        return vec![(f64::NAN, f64::NAN, f64::NAN); Method::MEASURED.len()];
    };
    Method::MEASURED
        .into_iter()
        .map(|method| {
            let metrics: Vec<accuracy::Metrics> = cases
                .iter()
                .enumerate()
                .map(|(i, c)| accuracy::measure(c, method, &data.under[i], &data.albedo[i]))
                .collect();
            let lobes: Vec<f64> = metrics.iter().map(|m| m.lobe_rmse).collect();
            let lobe_max = lobes.iter().copied().fold(0.0, f64::max);
            let albedo_max = metrics.iter().map(|m| m.albedo_error).fold(0.0, f64::max);
            (median(lobes), lobe_max, albedo_max)
        })
        .collect()
}

/// The generated WeidlichWilkie clay against [`CLAY_BY_HAND`], after checking their values
/// agree: (generated, hand-written) seconds per dispatch, timed interleaved (the median of three
/// medians each), and the largest relative difference of their values where |f| is significant.
pub fn against_hand_written(gpu: &Gpu, pairs: &[Pair]) -> Result<(f64, f64, f32), String> {
    let compiled = compile(&format!("Material(name: \"clay_ww\", method: WeidlichWilkie, {CLAY_STACK})"))?;
    let generated = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).map_err(|e| e.to_string())?;
    let hand = EvalKernel::from_wgsl(gpu, "clay_by_hand", CLAY_BY_HAND).map_err(|e| e.to_string())?;
    let check = &pairs[..4096.min(pairs.len())];
    let a = generated.eval(gpu, check, &[]).map_err(|e| e.to_string())?;
    let b = hand.eval(gpu, check, &[]).map_err(|e| e.to_string())?;
    let max = a.iter().map(|f| f.max_element()).fold(0.0_f32, f32::max);
    let worst = a
        .iter()
        .zip(&b)
        .flat_map(|(x, y)| (0..3).map(move |c| (x[c], y[c])))
        .filter(|(x, _)| x.abs() > 1e-4 * max)
        .map(|(x, y)| (x - y).abs() / x.abs())
        .fold(0.0_f32, f32::max);
    let (mut g, mut h) = (Vec::new(), Vec::new());
    for _ in 0..3 {
        g.push(kernel_seconds(gpu, &generated, pairs).map_err(|e| e.to_string())?);
        h.push(kernel_seconds(gpu, &hand, pairs).map_err(|e| e.to_string())?);
    }
    Ok((median(g), median(h), worst))
}

impl Report {
    pub fn markdown(&self) -> String {
        let mut md = format!(
            "Device: {}. Kernels: median of {} dispatches of {PAIRS} pairs ({ROUNDS} interleaved rounds of {REPEATS}, each after a warm-up), against a bare Lambert kernel timed in the same rounds ({:.1} M evaluations/s).\n\n",
            self.device,
            ROUNDS * REPEATS,
            self.lambert_evals_per_second / 1e6
        );
        md.push_str("| method (seed's clay stack) | M evaluations/s | time vs Lambert | time vs WeidlichWilkie | naga expressions | transcendental calls | lobe relRMSE median / max | albedo error max |\n|---|---|---|---|---|---|---|---|\n");
        let ww = self.methods.iter().find(|m| m.method == Method::WeidlichWilkie).map_or(f64::NAN, |m| m.time_ratio);
        for m in &self.methods {
            md.push_str(&format!(
                "| {} | {:.1} | {:.2}× | {:.2}× | {} | {} | {:.1}% / {:.1}% | {:.4} |\n",
                crate::accuracy::method_label(m.method),
                m.evals_per_second / 1e6,
                m.time_ratio,
                m.time_ratio / ww,
                m.expressions,
                m.transcendental,
                100.0 * m.lobe_median,
                100.0 * m.lobe_max,
                m.albedo_max
            ));
        }
        let (g, h, worst) = self.hand_written;
        md.push_str(&format!(
            "\nGenerated WeidlichWilkie clay against the same shader written by hand (`crates/glazec-lab/data/clay_by_hand.wgsl`; values agree to {worst:.1e}): generated/hand-written time **{:.2}×** (target ≤ 1.10×).\n",
            g / h
        ));
        md.push_str("\nCompile time from text, median µs (parse, check, lower, validate, emit one target's library):\n\n| material | WGSL | GLSL | HLSL |\n|---|---|---|---|\n");
        let mut names: Vec<&String> = self.compile_times.iter().map(|(n, _, _)| n).collect();
        names.dedup();
        for name in names {
            let of =
                |t: &str| self.compile_times.iter().find(|(n, tt, _)| n == name && *tt == t).map_or(f64::NAN, |x| x.2);
            md.push_str(&format!("| {name} | {:.0} | {:.0} | {:.0} |\n", of("wgsl"), of("glsl"), of("hlsl")));
        }
        md.push_str("\nOne evaluation of each material's `<m>_brdf`, every call counted as if inlined: naga expressions, loads from a resource (a uniform, storage buffer or texture) and transcendental calls; and the bytes of its WGSL library:\n\n| material | expressions | resource loads | transcendental calls | WGSL library bytes |\n|---|---|---|---|---|\n");
        for (name, c, bytes) in &self.eval_costs {
            md.push_str(&format!("| {name} | {} | {} | {} | {bytes} |\n", c.expressions, c.loads, c.transcendental));
        }
        if let Some(ms) = self.process_ms {
            md.push_str(&format!(
                "\nThe whole process `glazec compile materials/` (every material's libraries, WGSL + naga_oil + GLSL + HLSL, files written): {ms:.1} ms (median of 5).\n"
            ));
        }
        md.push_str("\nGrowth with the number of coats (rough coats over Lambert, default method):\n\n| coats | compile to all targets (ms) | WGSL bytes | naga expressions | kernel ns/evaluation |\n|---|---|---|---|---|\n");
        for r in &self.scale {
            md.push_str(&format!(
                "| {} | {:.2} | {} | {} | {:.2} |\n",
                r.coats, r.compile_ms, r.wgsl_bytes, r.expressions, r.kernel_ns
            ));
        }
        let xs: Vec<f64> = self.scale.iter().map(|r| r.coats as f64).collect();
        let fit = |ys: Vec<f64>| linear_fit(&xs, &ys);
        let rows = [
            ("compile (ms)", fit(self.scale.iter().map(|r| r.compile_ms).collect())),
            ("WGSL bytes", fit(self.scale.iter().map(|r| r.wgsl_bytes as f64).collect())),
            ("naga expressions", fit(self.scale.iter().map(|r| r.expressions as f64).collect())),
            ("kernel ns/evaluation", fit(self.scale.iter().map(|r| r.kernel_ns).collect())),
        ];
        md.push_str("\n| least-squares line over coats | slope per coat | intercept | R² |\n|---|---|---|---|\n");
        for (what, f) in rows {
            md.push_str(&format!("| {what} | {:.4} | {:.4} | {:.4} |\n", f.slope, f.intercept, f.r2));
        }
        md
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_fit_recovers_a_line_and_scores_a_curve_lower() {
        let xs = [1.0, 2.0, 4.0, 8.0, 16.0];
        let line: Vec<f64> = xs.iter().map(|x| 3.0 + 2.0 * x).collect();
        let fit = linear_fit(&xs, &line);
        assert!((fit.slope - 2.0).abs() < 1e-12 && (fit.intercept - 3.0).abs() < 1e-12 && (fit.r2 - 1.0).abs() < 1e-12);
        let square: Vec<f64> = xs.iter().map(|x| x * x).collect();
        assert!(linear_fit(&xs, &square).r2 < 0.95);
    }
}
