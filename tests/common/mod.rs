//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

pub mod stacks;

/// The project root (where `materials/` and `generated/` live).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `materials/*.ron`, sorted.
pub fn material_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("materials"))
        .expect("materials/ exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    files
}

/// Compiles one material file, panicking with rendered diagnostics if it does not compile.
pub fn compile_file(path: &Path) -> glazec::Compiled {
    let text = std::fs::read_to_string(path).expect("readable material");
    match glazec::compile(&text) {
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
