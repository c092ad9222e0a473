//! Cargo's fingerprinting sees the materials: touching a `.ron` file reruns the build script
//! (glazec's `Build::run` printed `cargo:rerun-if-changed` for it), and an untouched tree does not.
//!
//! This runs cargo itself, on the same target directory (the build is already up to date, so the
//! runs are incremental) and restores the material's modification time afterwards.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

/// `cargo build -v -p glazec-spheres --lib`; returns whether the package's build script ran.
fn build_script_ran(workspace: &Path) -> bool {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args(["build", "-v", "-p", "glazec-spheres", "--lib"])
        .current_dir(workspace)
        .output()
        .expect("cargo runs");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "cargo build failed:\n{log}");
    log.lines().any(|l| {
        l.trim_start().starts_with("Running") && l.contains("glazec-spheres-") && l.contains("build-script-build")
    })
}

#[test]
fn touching_a_material_reruns_the_build_script_and_nothing_else_does() {
    let workspace = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let material = workspace.join("materials/clay.ron");
    let _ = build_script_ran(&workspace); // settle whatever this build's flags differ in
    assert!(!build_script_ran(&workspace), "the build script reran although nothing changed");

    let file = std::fs::File::options().append(true).open(&material).expect("materials/clay.ron");
    let before = file.metadata().and_then(|m| m.modified()).expect("mtime");
    file.set_modified(SystemTime::now()).expect("touches the material");
    let reran = build_script_ran(&workspace);
    file.set_modified(before).expect("restores the mtime");
    assert!(reran, "touching materials/clay.ron did not rerun the build script");
}
