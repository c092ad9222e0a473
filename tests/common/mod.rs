//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

pub mod stacks;

/// Opens the Vulkan device for a test binary. Without an adapter: `None` and a visible
/// "SKIPPED" line — or, with `GLAZEC_REQUIRE_GPU=1` (set by `.ci/run`), a panic.
pub fn open_gpu() -> Option<glazec_gpu::Gpu> {
    match glazec_gpu::Gpu::new() {
        Ok(gpu) => {
            eprintln!("GPU tests run on {}", gpu.describe());
            Some(gpu)
        }
        Err(e @ glazec_gpu::RunError::NoAdapter { .. }) => {
            if std::env::var("GLAZEC_REQUIRE_GPU").is_ok_and(|v| v == "1") {
                panic!("GLAZEC_REQUIRE_GPU=1 but {e}");
            }
            eprintln!("SKIPPED: {e}");
            None
        }
        Err(e) => panic!("{e}"),
    }
}

/// GPU-vs-CPU agreement tolerances, shared by every test that runs shaders on a device.
pub mod agreement {
    /// Relative tolerance where |f| is significant.
    pub const REL_TOL: f32 = 2e-4;
    /// A value is significant when |f| > SIGNIFICANT · max|f| (over the material's pairs and
    /// channels).
    pub const SIGNIFICANT: f32 = 1e-4;
    /// Absolute tolerance for values that are not significant. Such a value also passes if it
    /// meets REL_TOL: for a material with a very sharp peak (car_paint: max|f| ≈ 4·10⁸ at a
    /// grazing mirror pair) "not significant" reaches values of 10⁴, where 10⁻⁶ is far below
    /// one f32 ulp, so the absolute bound alone would demand more than f32 can represent.
    /// Significant values get no such alternative.
    pub const ABS_TOL: f32 = 1e-6;

    /// Whether a GPU value agrees with the CPU value `cpu`, given the largest |f| of the set.
    pub fn agrees(cpu: f32, gpu: f32, max: f32) -> bool {
        let error = (gpu - cpu).abs();
        let significant = cpu.abs() > SIGNIFICANT * max;
        gpu.is_finite() && gpu >= 0.0 && (error <= REL_TOL * cpu.abs() || (!significant && error <= ABS_TOL))
    }
}

/// Runs the `glazec` binary from the project root.
pub fn glazec(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_glazec"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("runs glazec")
}

/// The project root (where `materials/` and `generated/` live).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every file under `dir` (recursively), sorted.
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())).flatten() {
            let path = entry.path();
            if path.is_dir() { stack.push(path) } else { files.push(path) }
        }
    }
    files.sort();
    files
}

/// Every `materials/*.ron`, sorted.
pub fn material_files() -> Vec<PathBuf> {
    glazec::project::material_files(&root().join("materials")).expect("materials/ holds .ron files")
}

/// Every `scenes/*.ron`, sorted.
pub fn scene_files() -> Vec<PathBuf> {
    glazec::project::material_files(&root().join("scenes")).expect("scenes/ holds .ron files")
}

/// Compiles one material file, panicking with rendered diagnostics if it does not compile.
pub fn compile_file(path: &Path) -> glazec::Compiled {
    let text = std::fs::read_to_string(path).expect("readable material");
    let file_name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    match glazec::compile_source(file_name.as_deref(), &text) {
        Ok(c) => c,
        Err(glazec::CompileError::Diagnostics(d)) => {
            let source = glazec::diag::Source { name: &path.display().to_string(), text: &text };
            panic!("{}", glazec::diag::render_plain(source, &d))
        }
        Err(e) => panic!("{e}"),
    }
}

/// Whether an external tool is on PATH. When it is not, tests skip visibly — unless
/// `GLAZEC_REQUIRE_TOOLS=1` (set by `.ci/run`), which turns the skip into a failure.
pub fn tool_available(tool: &str) -> bool {
    let found = std::process::Command::new(tool).arg("--version").output().is_ok();
    if !found {
        if std::env::var("GLAZEC_REQUIRE_TOOLS").is_ok_and(|v| v == "1") {
            panic!("`{tool}` is not installed and GLAZEC_REQUIRE_TOOLS=1");
        }
        eprintln!("SKIPPED: `{tool}` is not installed (apt-get install glslang-tools spirv-tools)");
    }
    found
}

/// Whether the deep tier runs (`GLAZEC_DEEP=1`, set by `.ci/run`): the exhaustive sweeps that
/// the quick tier samples. See docs/tests.md for what each tier covers and costs.
pub fn deep() -> bool {
    std::env::var("GLAZEC_DEEP").is_ok_and(|v| v == "1")
}

/// `quick` in the quick tier, `deep` in the deep tier, and a line saying which.
pub fn tier<T: std::fmt::Debug>(what: &str, quick: T, deep: T) -> T {
    let (tier, value) = if self::deep() { ("deep", deep) } else { ("quick", quick) };
    eprintln!("{what}: {value:?} ({tier} tier; GLAZEC_DEEP=1 runs the deep tier)");
    value
}

/// `GLAZEC_BLESS=1` rewrites expected files instead of comparing.
pub fn blessing() -> bool {
    std::env::var("GLAZEC_BLESS").is_ok_and(|v| v == "1")
}

/// A readable line diff between an expected and an actual text.
pub fn diff(expected: &str, actual: &str) -> String {
    similar::TextDiff::from_lines(expected, actual)
        .unified_diff()
        .context_radius(3)
        .header("expected", "actual")
        .to_string()
}
