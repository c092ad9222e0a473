//! glazec's WGSL through Dawn's Tint, Chrome's WebGPU compiler (npm package `webgpu`, run by
//! `tests/webgpu/check.mjs` under Node): every library, whole module (library + harness), scene
//! variant, textured and random material compiles with no message at all and every entry point
//! builds a pipeline; and `eval_pairs`, executed by Dawn's OpenGL ES backend on llvmpipe, agrees
//! with the CPU. Needs `node` and `npm ci --prefix tests/webgpu` (`scripts/test` does both);
//! without them the tests skip with a message, or fail under `GLAZEC_REQUIRE_TOOLS=1` (CI).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::Vec3;
use glazec::Target;
use glazec::eval::Pair;
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngSeed, TestRunner};

/// Random stacks checked by Tint (quick tier / deep tier).
const RANDOM_STACKS_QUICK: usize = 8;
const RANDOM_STACKS: usize = 40;
const RANDOM_SEED: u64 = 0x7165_6275;

fn script() -> PathBuf {
    common::root().join("tests/webgpu/check.mjs")
}

/// Whether Node and the `webgpu` package are there; a visible skip otherwise (a failure in CI).
fn dawn_available() -> bool {
    let node = Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success());
    let package = common::root().join("tests/webgpu/node_modules/webgpu/package.json").exists();
    if node && package {
        return true;
    }
    let missing = if node {
        "the npm package `webgpu` (npm ci --prefix tests/webgpu)"
    } else {
        "`node` (apt-get install nodejs npm)"
    };
    if std::env::var("GLAZEC_REQUIRE_TOOLS").is_ok_and(|v| v == "1") {
        panic!("{missing} is missing and GLAZEC_REQUIRE_TOOLS=1");
    }
    eprintln!("SKIPPED: {missing} is missing: Tint's checks do not run");
    false
}

/// Runs the script on `job` (with `backend` set) and returns its report.
fn dawn(job: serde_json::Value, dir: &Path) -> serde_json::Value {
    let path = dir.join("job.json");
    std::fs::write(&path, job.to_string()).expect("writes the job");
    let out =
        Command::new("node").arg(script()).arg(&path).env("EGL_PLATFORM", "surfaceless").output().expect("runs node");
    assert!(out.status.success(), "check.mjs failed:\n{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let last = stdout.lines().last().unwrap_or_default();
    serde_json::from_str(last).unwrap_or_else(|e| panic!("{e}: {stdout}\n{}", String::from_utf8_lossy(&out.stderr)))
}

/// A WGSL source to check, and its entry points.
struct Source {
    name: String,
    text: String,
    entries: Vec<(&'static str, &'static str)>,
}

const HARNESS_ENTRIES: [(&str, &str); 3] =
    [("eval_pairs", "compute"), ("preview_fs", "fragment"), ("preview_ibl_fs", "fragment")];

fn library_and_whole(name: &str, compiled: &glazec::Compiled) -> [Source; 2] {
    let library = compiled.emit(&[Target::Wgsl]).expect("emits").remove(0);
    [
        Source {
            name: format!("{name} (library)"),
            text: String::from_utf8_lossy(&library.contents).into(),
            entries: Vec::new(),
        },
        Source {
            name: format!("{name} (library + harness)"),
            text: compiled.whole_wgsl().expect("emits"),
            entries: HARNESS_ENTRIES.to_vec(),
        },
    ]
}

fn random_stacks() -> Vec<String> {
    let count = common::tier("random stacks through Tint", RANDOM_STACKS_QUICK, RANDOM_STACKS);
    let mut runner = TestRunner::new(Config { rng_seed: RngSeed::Fixed(RANDOM_SEED), ..Config::default() });
    (0..count)
        .map(|_| {
            let stack = common::stacks::stack().new_tree(&mut runner).expect("a stack").current();
            common::stacks::Writer { next_param: 0 }.material(&stack)
        })
        .collect()
}

#[test]
fn tint_accepts_every_generated_wgsl_with_no_message() {
    if !dawn_available() {
        return;
    }
    let mut sources = Vec::new();
    let mut libraries = String::new();
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let [library, whole] = library_and_whole(&compiled.material.name, &compiled);
        libraries.push_str(&library.text);
        sources.extend([library, whole]);
    }
    sources.push(Source { name: "every library, concatenated".into(), text: libraries, entries: Vec::new() });
    // The scene variants' libraries, as generated/scenes/ holds them.
    for library in common::files_under(&common::root().join("generated/scenes")) {
        if library.extension().is_none_or(|e| e != "wgsl") {
            continue;
        }
        let text = std::fs::read_to_string(&library).expect("library");
        let name = library.strip_prefix(common::root()).unwrap_or(&library).display().to_string();
        sources.push(Source { name, text, entries: Vec::new() });
    }
    let textured =
        std::fs::read_to_string(common::root().join("examples/textures/textured_clay.ron")).expect("example");
    let textured = glazec::compile(&textured).expect("compiles");
    sources.extend(library_and_whole("textured_clay", &textured));
    for (index, text) in random_stacks().iter().enumerate() {
        let compiled = glazec::compile(text).unwrap_or_else(|e| panic!("{e:?}\n{text}"));
        sources.extend(library_and_whole(&format!("random stack {index}"), &compiled));
    }

    // A negative control: Tint warns about unreachable code (naga says nothing), so a silent
    // run means Tint really looked.
    const CONTROL: &str = "negative control";
    sources.push(Source {
        name: CONTROL.into(),
        text: "fn f() -> f32 {\n    return 1.0;\n    let x = 2.0;\n}\n".into(),
        entries: Vec::new(),
    });
    let dir = tempfile::tempdir().expect("temp dir");
    let check: Vec<serde_json::Value> = sources
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let file = dir.path().join(format!("{i}.wgsl"));
            std::fs::write(&file, &s.text).expect("writes");
            let entries: Vec<serde_json::Value> =
                s.entries.iter().map(|(name, stage)| serde_json::json!({ "name": name, "stage": stage })).collect();
            serde_json::json!({ "name": s.name, "file": file, "entries": entries })
        })
        .collect();
    let report = dawn(serde_json::json!({ "backend": "null", "check": check }), dir.path());
    let mut messages = report["messages"].as_array().cloned().unwrap_or_default();
    let control = messages.iter().filter(|m| m["name"] == CONTROL).count();
    assert_eq!(control, 1, "Tint did not warn about the control's unreachable code: {messages:#?}");
    messages.retain(|m| m["name"] != CONTROL);
    let pipelines: usize = sources.iter().map(|s| s.entries.len()).sum();
    eprintln!("Tint: {} modules, {} pipelines, {} messages", report["modules"], report["pipelines"], messages.len());
    assert!(report["error"].is_null(), "{report}");
    assert_eq!(report["modules"].as_u64(), Some(sources.len() as u64));
    assert_eq!(report["pipelines"].as_u64(), Some(pipelines as u64), "{messages:#?}");
    assert!(messages.is_empty(), "Tint reported:\n{messages:#?}");
    assert!(report["errors"].as_array().is_none_or(Vec::is_empty), "{report}");
}

/// A few pairs over the hemisphere, mirror pairs among them.
fn pairs() -> Vec<Pair> {
    let direction = |theta: f32, phi: f32| glazec::math::sampling::direction_f32(theta.to_radians(), phi.to_radians());
    let mut pairs = Vec::new();
    for (theta_i, theta_o, phi) in
        [(0.0, 0.0, 0.0), (30.0, 45.0, 90.0), (60.0, 60.0, 180.0), (75.0, 20.0, 45.0), (85.0, 85.0, 0.0)]
    {
        let wi = direction(theta_i, 0.0);
        pairs.push(Pair { wi, wo: direction(theta_o, phi) });
        pairs.push(Pair { wi, wo: Vec3::new(-wi.x, -wi.y, wi.z) });
    }
    pairs
}

/// Whether `eval_pairs` reads the resource at `slot`.
fn eval_pairs_uses(compiled: &glazec::Compiled, slot: glazec::lower::bindings::Slot) -> bool {
    let harness = compiled.harness().expect("the harness validates");
    let index = harness.module.entry_points.iter().position(|ep| ep.name == "eval_pairs").expect("eval_pairs");
    let info = harness.info.get_entry_point(index);
    harness.module.global_variables.iter().any(|(handle, var)| {
        var.binding.is_some_and(|b| b.group == slot.group && b.binding == slot.binding) && !info[handle].is_empty()
    })
}

#[test]
fn eval_pairs_through_dawn_agrees_with_the_cpu() {
    if !dawn_available() {
        return;
    }
    let pairs = pairs();
    let pair_bytes: Vec<u8> = pairs
        .iter()
        .flat_map(|p| [p.wi.x, p.wi.y, p.wi.z, 0.0, p.wo.x, p.wo.y, p.wo.z, 0.0])
        .flat_map(f32::to_le_bytes)
        .collect();
    let dir = tempfile::tempdir().expect("temp dir");
    let mut run = Vec::new();
    let mut compiled_all = Vec::new();
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let file = dir.path().join(format!("{}.wgsl", compiled.material.name));
        std::fs::write(&file, compiled.whole_wgsl().expect("emits")).expect("writes");
        let values = compiled.material.default_values();
        let layout = &compiled.harness().expect("the harness validates").layout;
        // 'auto' layouts hold only what the entry point uses (clay's tables serve only its IBL).
        let used = |slot: Option<glazec::lower::bindings::Slot>| {
            slot.filter(|s| eval_pairs_uses(&compiled, *s)).map(|s| s.binding)
        };
        run.push(serde_json::json!({
            "name": compiled.material.name,
            "file": file,
            "count": pairs.len(),
            "pairs": pair_bytes,
            "params": glazec::lower::params_bytes(&compiled.material, &values),
            "tables": compiled.tables_bytes(),
            "bindings": {
                "pairs": layout.pairs,
                "values": layout.values,
                "dispatch": layout.dispatch,
                "params": used(layout.params),
                "tables": used(layout.tables),
            },
        }));
        compiled_all.push(compiled);
    }
    let report = dawn(serde_json::json!({ "backend": "opengles", "run": run }), dir.path());
    if let Some(error) = report["error"].as_str() {
        // No EGL / Mesa GL driver (libegl-mesa0, libgl1-mesa-dri): a visible skip, or a failure in CI.
        if std::env::var("GLAZEC_REQUIRE_TOOLS").is_ok_and(|v| v == "1") {
            panic!("Dawn's OpenGL ES backend: {error} and GLAZEC_REQUIRE_TOOLS=1");
        }
        eprintln!("SKIPPED: Dawn's OpenGL ES backend: {error} (apt-get install libegl-mesa0 libgl1-mesa-dri)");
        return;
    }
    assert!(report["errors"].as_array().is_none_or(Vec::is_empty), "{report}");
    let mut worst = 0.0_f32;
    let mut failures = Vec::new();
    for compiled in &compiled_all {
        let name = &compiled.material.name;
        let gpu: Vec<f32> = report["results"][name]
            .as_array()
            .expect("values")
            .iter()
            .map(|v| v.as_f64().unwrap_or(f64::NAN) as f32)
            .collect();
        let values = compiled.material.default_values();
        let cpu: Vec<Vec3> =
            pairs.iter().map(|p| glazec::eval::brdf(&compiled.material, &values, p.wi, p.wo)).collect();
        let max = cpu.iter().flat_map(|c| [c.x, c.y, c.z]).fold(0.0_f32, |m, x| m.max(x.abs()));
        for (i, c) in cpu.iter().enumerate() {
            for (k, cpu) in [c.x, c.y, c.z].into_iter().enumerate() {
                let dawn = gpu[4 * i + k];
                if !common::agreement::agrees(cpu, dawn, max) {
                    failures.push(format!("{name} pair {i} channel {k}: CPU {cpu}, Dawn {dawn}"));
                }
                if cpu.abs() > common::agreement::SIGNIFICANT * max {
                    worst = worst.max((dawn - cpu).abs() / cpu.abs());
                }
            }
        }
    }
    eprintln!(
        "Dawn (OpenGL ES, llvmpipe) vs CPU: {} materials × {} pairs, worst relative error {worst:.2e}",
        compiled_all.len(),
        pairs.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
