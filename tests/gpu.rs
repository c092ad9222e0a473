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
use glazec_gpu::{EvalKernel, Gpu, ShaderPath};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngSeed, TestRunner};
use rayon::prelude::*;

use common::agreement::{ABS_TOL, REL_TOL, SIGNIFICANT};

/// Random stacks checked in every language (fixed seed): the quick tier's sample and the deep
/// tier's sweep.
const RANDOM_STACKS_QUICK: usize = 16;
const RANDOM_STACKS: usize = 200;
const RANDOM_SEED: u64 = 0x0bad_5eed;
/// Polar-angle and azimuth resolution of the direction grid (16 × 16 × 16 = 4096 pairs), before
/// the mirror, grazing and below-horizon pairs are added.
const GRID: usize = 16;

/// The device, opened once per test binary. `None` means "skip" (only without GLAZEC_REQUIRE_GPU).
fn gpu() -> Option<&'static Gpu> {
    static GPU: OnceLock<Option<Gpu>> = OnceLock::new();
    GPU.get_or_init(common::open_gpu).as_ref()
}

fn direction(theta_deg: f32, phi_deg: f32) -> Vec3 {
    glazec::math::sampling::direction_f32(theta_deg.to_radians(), phi_deg.to_radians())
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

impl Worst {
    /// Takes in what another thread saw.
    fn merge(&mut self, other: Worst) {
        if other.relative > self.relative {
            self.relative = other.relative;
            self.detail = other.detail;
        }
        self.values += other.values;
        self.insignificant_by_relative += other.insignificant_by_relative;
    }
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
            let ok = common::agreement::agrees(c, g, max);
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

/// Checks random stacks on every core: lavapipe compiles each pipeline on the thread that
/// creates it, and a deep stack's four shaders take seconds to compile.
#[test]
fn random_stacks_agree_with_the_cpu_in_every_language() {
    let Some(gpu) = gpu() else { return };
    let pairs = pairs();
    let count = common::tier("random stacks", RANDOM_STACKS_QUICK, RANDOM_STACKS);
    let mut runner = TestRunner::new(Config { rng_seed: RngSeed::Fixed(RANDOM_SEED), ..Config::default() });
    let stacks: Vec<String> = (0..count)
        .map(|_| {
            let stack = common::stacks::stack().new_tree(&mut runner).expect("a stack").current();
            common::stacks::Writer { next_param: 0 }.material(&stack)
        })
        .collect();
    // rayon hands stacks out as threads come free: their shaders take very different times to
    // compile on lavapipe.
    // `None`: refused with E0222 (more tables than a uniform holds), the right answer for it.
    let results: Vec<Option<([Worst; 4], Option<String>)>> = stacks
        .par_iter()
        .enumerate()
        .map(|(index, text)| {
            let mut worst: [Worst; 4] = Default::default();
            let compiled = match glazec::compile(text) {
                Ok(compiled) => compiled,
                Err(e) if common::stacks::refused_for_table_budget(&e) => return None,
                Err(e) => panic!("{e:?}\n{text}"),
            };
            let values = compiled.material.default_values();
            let found = check_material(gpu, &format!("random stack {index}"), &compiled, &values, &pairs, &mut worst);
            Some((worst, (!found.is_empty()).then(|| format!("{}\n{text}", found.join("\n")))))
        })
        .collect();
    let refused = results.iter().filter(|r| r.is_none()).count();
    let mut worst: [Worst; 4] = Default::default();
    let mut failures = Vec::new();
    for (found_worst, found) in results.into_iter().flatten() {
        for (total, part) in worst.iter_mut().zip(found_worst) {
            total.merge(part);
        }
        failures.extend(found);
    }
    report("random stacks", &worst);
    eprintln!(
        "GPU cases executed: {} stacks × {} paths × {} pairs ({refused} of {count} refused with E0222)",
        count - refused,
        ShaderPath::ALL.len(),
        pairs.len()
    );
    // Nearly all stacks must run: a refusal is for stacks with many runtime parameters.
    assert!(refused * 10 <= count, "{refused} of {count} random stacks were refused with E0222");
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

/// Size of the previews rendered by the tests.
const PREVIEW_SIZE: u32 = 96;

/// Mean and peak luminance over the sphere, and the share of sphere pixels brighter than half
/// the peak (how wide the highlight is), of a preview under the key light alone.
fn preview_stats(gpu: &Gpu, name: &str) -> (f32, f32, f32) {
    use glazec_gpu::preview;
    let compiled = common::compile_file(&common::root().join(format!("materials/{name}.ron")));
    let options =
        preview::PreviewOptions { size: PREVIEW_SIZE, environment: preview::Environment::None, ..Default::default() };
    let pixels = preview::render(gpu, &compiled, &compiled.material.default_values(), &options).expect("renders");
    let luminance: Vec<f32> =
        pixels.iter().filter(|p| p[3] > 0.0).map(|p| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]).collect();
    let mean = luminance.iter().sum::<f32>() / luminance.len() as f32;
    let peak = luminance.iter().copied().fold(0.0, f32::max);
    let bright = luminance.iter().filter(|&&l| l > 0.5 * peak).count() as f32 / luminance.len() as f32;
    (mean, peak, bright)
}

#[test]
fn previews_show_the_differences_bowsher_2022_describes() {
    let Some(gpu) = gpu() else { return };
    let (clay_mean, clay_peak, clay_bright) = preview_stats(gpu, "clay");
    let (wet_mean, wet_peak, _) = preview_stats(gpu, "wet_clay");
    let (coat_mean, coat_peak, coat_bright) = preview_stats(gpu, "disney_clay");
    eprintln!("clay: mean {clay_mean:.4}, peak {clay_peak:.3}, highlight share {clay_bright:.4}");
    eprintln!("wet_clay: mean {wet_mean:.4}, peak {wet_peak:.3}");
    eprintln!("disney_clay: mean {coat_mean:.4}, peak {coat_peak:.3}, highlight share {coat_bright:.4}");
    // Wet clay is darker and glossier (Bowsher 2022, §2.4, Figure 3).
    assert!(wet_mean < clay_mean, "wet clay is not darker");
    assert!(wet_peak > clay_peak, "wet clay is not glossier");
    // The clear coat's highlight is brighter and sharper, and nothing darkens its body (Bowsher 2022, §4).
    assert!(coat_peak > clay_peak, "the clear-coat highlight is not brighter");
    assert!(coat_bright < clay_bright, "the clear-coat highlight is not sharper");
    assert!(coat_mean > clay_mean, "the clear coat darkens the body although it only adds a lobe");
}

#[test]
fn preview_covers_a_disk_and_writes_a_png() {
    use glazec_gpu::preview;
    let Some(gpu) = gpu() else { return };
    let compiled = common::compile_file(&common::root().join("materials/tunable_glaze.ron"));
    let options = preview::PreviewOptions { size: PREVIEW_SIZE, ..Default::default() };
    let pixels = preview::render(gpu, &compiled, &compiled.material.default_values(), &options).expect("renders");
    let at = |x: u32, y: u32| pixels[(y * PREVIEW_SIZE + x) as usize];
    assert!(at(PREVIEW_SIZE / 2, PREVIEW_SIZE / 2)[3] > 0.0, "the centre is on the sphere");
    assert_eq!(at(0, 0)[3], 0.0, "the corner is background");
    assert!(at(PREVIEW_SIZE / 2, PREVIEW_SIZE / 2)[0] > 0.0, "the sphere is lit");
    let covered = pixels.iter().filter(|p| p[3] > 0.0).count() as f32 / pixels.len() as f32;
    assert!((covered - std::f32::consts::FRAC_PI_4).abs() < 0.03, "the sphere covers π/4 of the square: {covered}");
    let image = preview::encode(&pixels, PREVIEW_SIZE, 1.0);
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join("glaze.png");
    preview::write_png(&path, &image).expect("writes");
    let bytes = std::fs::read(&path).expect("written");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
}

/// (The CLI's GPU backends are in builds with the `gpu` feature.)
#[cfg(feature = "gpu")]
#[test]
fn eval_command_runs_every_backend() {
    if gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("tmp");
    let csv = dir.path().join("pairs.csv");
    let mut text = String::from("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n");
    for p in pairs().iter().step_by(37) {
        text.push_str(&format!("{},{},{},{},{},{}\n", p.wi.x, p.wi.y, p.wi.z, p.wo.x, p.wo.y, p.wo.z));
    }
    std::fs::write(&csv, text).expect("writes");
    let run = |backend: &str| -> Vec<f32> {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_glazec"))
            .args([
                "eval",
                "materials/tunable_glaze.ron",
                "--pairs",
                csv.to_str().expect("utf-8"),
                "--backend",
                backend,
            ])
            .current_dir(common::root())
            .output()
            .expect("runs glazec");
        assert!(out.status.success(), "{backend}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout)
            .split([',', '\n'])
            .filter(|s| !s.is_empty())
            .map(|x| x.parse().expect("a number"))
            .collect()
    };
    let cpu = run("cpu");
    assert!(cpu.len() > 300);
    for backend in ["naga-ir", "wgsl", "glsl", "hlsl"] {
        let gpu = run(backend);
        assert_eq!(gpu.len(), cpu.len(), "{backend}");
        for (g, c) in gpu.iter().zip(&cpu) {
            assert!((g - c).abs() <= REL_TOL * c.abs() + ABS_TOL, "{backend}: {g} vs cpu {c}");
        }
    }
}
