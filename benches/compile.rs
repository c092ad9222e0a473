//! In-process compile time of the seed's clay to all three text targets (the libraries a host
//! imports), and a baseline measured in the same run: naga alone translating the equivalent
//! hand-written WGSL (glazec's own library for clay) — WGSL front end, validation, and the same
//! three backends. The ratio says what going through a material costs over writing the shader
//! by hand. glazec's harness, which only its own runs ask for, is timed apart.
//!
//! `cargo bench --bench compile` prints both and their ratio at the end.

use std::hint::black_box;

use criterion::{Criterion, criterion_group};
use glazec::Target;

const CLAY: &str = include_str!("../materials/clay.ron");

const GROUP: &str = "compile";
const MATERIAL: &str = "clay_to_wgsl_glsl_hlsl";
const BASELINE: &str = "naga_baseline_from_wgsl";

fn compile_clay() -> usize {
    let compiled = glazec::compile(black_box(CLAY)).expect("clay compiles");
    let artifacts = compiled.emit(&Target::TEXT).expect("emits");
    artifacts.iter().map(|a| a.contents.len()).sum()
}

fn naga_from_wgsl(wgsl: &str) -> usize {
    let module = naga::front::wgsl::parse_str(black_box(wgsl)).expect("parses");
    let info = glazec::validate::validate("clay", &module).expect("validates");
    // The parsed module stands for both the library and the whole module.
    let layout = glazec::lower::bindings::Layout::default();
    let modules = glazec::emit::Modules { library: &module, library_info: &info, layout: &layout, harness: None };
    let artifacts =
        glazec::emit::emit("clay", &glazec::Origin::new(None, wgsl), modules, &Target::TEXT).expect("emits");
    artifacts.iter().map(|a| a.contents.len()).sum()
}

/// WGSL and HLSL of `library`, GLSL of `module`'s `eval_pairs`: bytes written.
fn naga_backends(
    library: &naga::Module,
    library_info: &naga::valid::ModuleInfo,
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
) -> usize {
    use naga::back::{glsl, hlsl, wgsl};
    let wgsl = wgsl::write_string(library, library_info, wgsl::WriterFlags::empty()).expect("WGSL");
    let mut hlsl = String::new();
    let options = hlsl::Options { shader_model: hlsl::ShaderModel::V6_0, ..Default::default() };
    hlsl::Writer::new(&mut hlsl, &options, &hlsl::PipelineOptions { entry_point: None })
        .write(library, library_info, None)
        .expect("HLSL");
    let mut glsl = String::new();
    let options = glsl::Options { version: glsl::Version::Desktop(450), ..Default::default() };
    let pipeline = glsl::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: "eval_pairs".to_string(),
        multiview: None,
    };
    glsl::Writer::new(&mut glsl, module, info, &options, &pipeline, naga::proc::BoundsCheckPolicies::default())
        .expect("GLSL writer")
        .write()
        .expect("GLSL");
    wgsl.len() + hlsl.len() + glsl.len()
}

fn stages(c: &mut Criterion) {
    let mut group = c.benchmark_group(GROUP);
    group.bench_function(MATERIAL, |b| b.iter(compile_clay));
    let wgsl = {
        let compiled = glazec::compile(CLAY).expect("clay compiles");
        let files = compiled.emit(&[Target::Wgsl]).expect("emits");
        String::from_utf8(files[0].contents.clone()).expect("utf-8")
    };
    group.bench_function(BASELINE, |b| b.iter(|| naga_from_wgsl(&wgsl)));
    // glazec's own runs: the libraries and the harness files beside them.
    group.bench_function("clay_with_harness", |b| {
        b.iter(|| {
            let compiled = glazec::compile(black_box(CLAY)).expect("clay compiles");
            compiled.emit_with_harness(&Target::TEXT).expect("emits").len()
        })
    });
    group.finish();

    let mut group = c.benchmark_group("stages");
    group.bench_function("parse_and_check", |b| b.iter(|| glazec::load(black_box(CLAY)).expect("valid")));
    let (material, _) = glazec::load(CLAY).expect("valid");
    let choice = glazec::lower::bindings::Choice::default();
    group.bench_function("lower_library", |b| {
        b.iter(|| glazec::lower::lower_library(black_box(&material), &choice).expect("lowers"))
    });
    group.bench_function("lower_with_harness", |b| b.iter(|| glazec::lower::lower(black_box(&material))));
    let lowered = glazec::lower::lower(&material);
    group.bench_function("validate_library", |b| {
        b.iter(|| glazec::validate::validate("clay", black_box(&lowered.library)).expect("valid"))
    });
    let info = glazec::validate::validate("clay", &lowered.module).expect("valid");
    let library_info = glazec::validate::validate("clay", &lowered.library).expect("valid");
    let modules = glazec::emit::Modules {
        library: &lowered.library,
        library_info: &library_info,
        layout: &lowered.layout,
        harness: None,
    };
    // The floor under emit: naga's three backends writing the library once each, with none of
    // glazec's text passes (GLSL needs an entry point: the whole module's `eval_pairs`).
    group.bench_function("naga_backends_library_only", |b| {
        b.iter(|| naga_backends(black_box(&lowered.library), &library_info, &lowered.module, &info))
    });
    let origin = glazec::Origin::new(Some("clay.ron"), CLAY);
    // The two halves of `compile/clay_to_wgsl_glsl_hlsl`.
    group.bench_function("compile_library", |b| b.iter(|| glazec::compile(black_box(CLAY)).expect("compiles")));
    let compiled = glazec::compile(CLAY).expect("clay compiles");
    group.bench_function("emit_text_targets", |b| b.iter(|| compiled.emit(black_box(&Target::TEXT)).expect("emits")));
    for target in Target::TEXT {
        group.bench_function(format!("emit_{}", target.name()), |b| {
            b.iter(|| glazec::emit::emit("clay", &origin, black_box(modules), &[target]).expect("emits"))
        });
    }
    group.finish();
}

criterion_group!(benches, stages);

/// Mean time in nanoseconds of a finished benchmark, from criterion's report.
fn mean_ns(id: &str) -> Option<f64> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("target/criterion/{GROUP}/{id}/new/estimates.json"));
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    json["mean"]["point_estimate"].as_f64()
}

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    if let (Some(material), Some(baseline)) = (mean_ns(MATERIAL), mean_ns(BASELINE)) {
        println!(
            "\nclay → WGSL+GLSL+HLSL: {:.1} µs; naga alone from hand-written WGSL: {:.1} µs; ratio {:.2}",
            material / 1e3,
            baseline / 1e3,
            material / baseline
        );
    }
}
