//! GPU-vs-CPU agreement: every generated shader runs on a Vulkan device (lavapipe in CI) through
//! each language — the naga module, WGSL text, GLSL via glslang, HLSL via glslang as passthrough
//! SPIR-V — and must give the numbers the CPU gives for the same material.
//!
//! Without an adapter the tests skip with a visible message; with `GLAZEC_REQUIRE_GPU=1` (set by
//! `.ci/run`) they fail instead. Each test prints how many GPU cases it executed.

mod common;

use std::sync::OnceLock;

use glam::Vec3;
use glazec::eval::Pair;
use glazec::model::ParamValue;
use glazec::run::{EvalKernel, Gpu, RunError, ShaderPath};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngSeed, TestRunner};

/// Relative tolerance where |f| is significant.
const REL_TOL: f32 = 2e-4;
/// A value is significant when |f| > SIGNIFICANT · max|f| (over the material's pairs and channels).
const SIGNIFICANT: f32 = 1e-4;
/// Absolute tolerance for values that are not significant. Such a value also passes if it meets
/// REL_TOL: for a material with a very sharp peak (car_paint: max|f| ≈ 4·10⁸ at a grazing mirror
/// pair) "not significant" reaches values of 10⁴, where 10⁻⁶ is far below one f32 ulp, so the
/// absolute bound alone would demand more than f32 can represent. Significant values get no
/// such alternative.
const ABS_TOL: f32 = 1e-6;
/// Random stacks checked (fixed seed).
const RANDOM_STACKS: usize = 200;
const RANDOM_SEED: u64 = 0x0bad_5eed;
/// Polar-angle and azimuth resolution of the direction grid (16 × 16 × 16 = 4096 pairs), before
/// the mirror, grazing and below-horizon pairs are added.
const GRID: usize = 16;

/// The device, opened once per test binary. `None` means "skip" (only without GLAZEC_REQUIRE_GPU).
fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Option<Gpu>> = OnceLock::new();
    GPU.get_or_init(|| match Gpu::new() {
        Ok(gpu) => {
            eprintln!("GPU tests run on {}", gpu.describe());
            Some(gpu)
        }
        Err(e @ RunError::NoAdapter { .. }) => {
            if std::env::var("GLAZEC_REQUIRE_GPU").is_ok_and(|v| v == "1") {
                panic!("GLAZEC_REQUIRE_GPU=1 but {e}");
            }
            eprintln!("SKIPPED: {e}");
            None
        }
        Err(e) => panic!("{e}"),
    })
    .as_ref()
}

fn direction(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// ≥ 4096 pairs: a θi × θo × Δφ grid up to 89.5°, exact mirror pairs, exactly grazing pairs
/// (z = 0) and pairs below the horizon (expected 0).
fn pairs() -> Vec<Pair> {
    let theta = |i: usize| 89.5 * (i as f32 / (GRID - 1) as f32).sqrt();
    let mut pairs = Vec::new();
    for a in 0..GRID {
        for b in 0..GRID {
            for c in 0..GRID {
                let phi = 360.0 * c as f32 / GRID as f32;
                pairs.push(Pair {
                    wi: direction(theta(a), 17.0 * a as f32),
                    wo: direction(theta(b), 17.0 * a as f32 + phi),
                });
            }
        }
    }
    for a in 0..GRID {
        let wi = direction(theta(a), 31.0 * a as f32);
        pairs.push(Pair { wi, wo: Vec3::new(-wi.x, -wi.y, wi.z) }); // the mirror direction
        pairs.push(Pair { wi: direction(90.0, 40.0 * a as f32), wo: direction(theta(a), 0.0) }); // grazing
        pairs.push(Pair { wi: direction(theta(a), 0.0), wo: direction(90.0, 40.0 * a as f32) });
        pairs.push(Pair { wi: direction(95.0 + a as f32, 10.0), wo: direction(theta(a), 0.0) }); // below
        pairs.push(Pair { wi: direction(30.0, 0.0), wo: direction(100.0 + 4.0 * a as f32, 50.0) });
    }
    pairs
}

/// The worst disagreement seen on one path.
#[derive(Default)]
struct Worst {
    relative: f32,
    detail: String,
    values: usize,
    /// Values below the significance threshold that missed ABS_TOL but met REL_TOL.
    insignificant_by_relative: usize,
}

/// Compares GPU values with CPU values; returns the failures (at most a few, described).
fn compare(
    label: &str,
    path: ShaderPath,
    pairs: &[Pair],
    cpu: &[Vec3],
    gpu: &[Vec3],
    worst: &mut Worst,
) -> Vec<String> {
    let max = cpu.iter().map(|f| f.max_element()).fold(0.0_f32, f32::max);
    let mut failures = Vec::new();
    for ((pair, c), g) in pairs.iter().zip(cpu).zip(gpu) {
        for k in 0..3 {
            worst.values += 1;
            let (c, g) = (c[k], g[k]);
            let significant = c.abs() > SIGNIFICANT * max;
            let error = (g - c).abs();
            let within_relative = error <= REL_TOL * c.abs();
            let ok = g.is_finite() && g >= 0.0 && (within_relative || (!significant && error <= ABS_TOL));
            if !significant && error > ABS_TOL && within_relative {
                worst.insignificant_by_relative += 1;
            }
            if significant && error / c.abs() > worst.relative {
                worst.relative = error / c.abs();
                worst.detail = format!("{label}: wi {} wo {} channel {k}: cpu {c:e} gpu {g:e}", pair.wi, pair.wo);
            }
            if !ok && failures.len() < 5 {
                failures.push(format!(
                    "{label} via {path}: wi {} wo {} channel {k}: cpu {c:e}, gpu {g:e} ({} error {:e}, max|f| {max:e})",
                    pair.wi,
                    pair.wo,
                    if significant { "relative" } else { "absolute" },
                    if significant { error / c.abs() } else { error }
                ));
            }
        }
    }
    failures
}

/// Runs one compiled material through every path; returns failures.
fn check_material(
    gpu: &Gpu,
    label: &str,
    compiled: &glazec::Compiled,
    values: &[ParamValue],
    pairs: &[Pair],
    worst: &mut [Worst; 4],
) -> Vec<String> {
    let cpu: Vec<Vec3> = pairs.iter().map(|p| glazec::eval::brdf(&compiled.material, values, p.wi, p.wo)).collect();
    let mut failures = Vec::new();
    for (i, path) in ShaderPath::ALL.into_iter().enumerate() {
        let result = EvalKernel::new(gpu, compiled, path).and_then(|k| k.eval(gpu, pairs, values));
        match result {
            Ok(values) => failures.extend(compare(label, path, pairs, &cpu, &values, &mut worst[i])),
            Err(e) => failures.push(format!("{label} via {path}: {e}")),
        }
    }
    failures
}

fn report(what: &str, worst: &[Worst; 4]) {
    for (path, w) in ShaderPath::ALL.iter().zip(worst) {
        eprintln!(
            "{what} via {path}: {} values compared, worst relative error {:.2e} ({}); {} insignificant values passed by the relative bound",
            w.values, w.relative, w.detail, w.insignificant_by_relative
        );
    }
}

#[test]
fn shipped_materials_agree_with_the_cpu_in_every_language() {
    let Some(gpu) = gpu() else { return };
    let pairs = pairs();
    assert!(pairs.len() >= 4096);
    let mut worst: [Worst; 4] = Default::default();
    let mut failures = Vec::new();
    let files = common::material_files();
    for path in &files {
        let compiled = common::compile_file(path);
        let values = compiled.material.default_values();
        failures.extend(check_material(gpu, &compiled.material.name, &compiled, &values, &pairs, &mut worst));
    }
    report("materials", &worst);
    eprintln!(
        "GPU cases executed: {} materials × {} paths × {} pairs",
        files.len(),
        ShaderPath::ALL.len(),
        pairs.len()
    );
    assert!(failures.is_empty(), "{} disagreements:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn random_stacks_agree_with_the_cpu_in_every_language() {
    let Some(gpu) = gpu() else { return };
    let pairs = pairs();
    let mut runner = TestRunner::new(Config { rng_seed: RngSeed::Fixed(RANDOM_SEED), ..Config::default() });
    let mut worst: [Worst; 4] = Default::default();
    let mut failures = Vec::new();
    for index in 0..RANDOM_STACKS {
        let stack = common::stacks::stack().new_tree(&mut runner).expect("a stack").current();
        let text = common::stacks::Writer { next_param: 0 }.material(&stack);
        let compiled = glazec::compile(&text).unwrap_or_else(|e| panic!("{e:?}\n{text}"));
        let values = compiled.material.default_values();
        let found = check_material(gpu, &format!("random stack {index}"), &compiled, &values, &pairs, &mut worst);
        if !found.is_empty() {
            failures.push(format!("{}\n{text}", found.join("\n")));
        }
    }
    report("random stacks", &worst);
    eprintln!("GPU cases executed: {RANDOM_STACKS} stacks × {} paths × {} pairs", ShaderPath::ALL.len(), pairs.len());
    assert!(failures.is_empty(), "{} stacks disagree:\n{}", failures.len(), failures.join("\n\n"));
}

#[test]
fn runtime_parameters_are_read_from_the_uniform_buffer() {
    let Some(gpu) = gpu() else { return };
    let compiled = common::compile_file(&common::root().join("materials/tunable_glaze.ron"));
    let pairs = pairs();
    let defaults = compiled.material.default_values();
    // Every parameter moved away from its default.
    let changed: Vec<ParamValue> = defaults
        .iter()
        .map(|v| match *v {
            ParamValue::Scalar(x) => ParamValue::Scalar(if x > 1.0 { x * 1.3 } else { 1.0 - x }),
            ParamValue::Rgb([r, g, b]) => ParamValue::Rgb([b, r, g]),
        })
        .collect();
    let mut worst: [Worst; 4] = Default::default();
    let failures = check_material(gpu, "tunable_glaze (changed parameters)", &compiled, &changed, &pairs, &mut worst);
    report("changed parameters", &worst);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // And the parameters do change the result.
    let kernel = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).expect("kernel");
    let a = kernel.eval(gpu, &pairs[..64], &defaults).expect("runs");
    let b = kernel.eval(gpu, &pairs[..64], &changed).expect("runs");
    assert!(a.iter().zip(&b).any(|(x, y)| (*x - *y).abs().max_element() > 1e-3), "parameters had no effect");
}
