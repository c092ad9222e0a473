//! Golden outputs: `generated/` must be exactly what `glazec compile materials/` produces.
//!
//! On mismatch the test prints a line diff per file and fails; `GLAZEC_BLESS=1 cargo test
//! --test golden` rewrites `generated/` (and removes files no material produces any more).

mod common;

use std::collections::BTreeSet;
use std::path::PathBuf;

use glazec::output::{self, OutputFile};

fn planned_outputs() -> Vec<OutputFile> {
    let out_dir = common::root().join("generated");
    let compiled: Vec<glazec::Compiled> = common::material_files().iter().map(|p| common::compile_file(p)).collect();
    let mut files: Vec<OutputFile> = compiled
        .iter()
        .flat_map(|c| output::plan(&out_dir, &c.material.name, c.emit(&glazec::Target::TEXT).expect("emits")))
        .collect();
    if compiled.iter().any(glazec::Compiled::uses_tables) {
        files.push(output::tables_file(&out_dir));
    }
    files
}

fn files_on_disk() -> BTreeSet<PathBuf> {
    let mut found = BTreeSet::new();
    let Ok(dirs) = std::fs::read_dir(common::root().join("generated")) else { return found };
    for dir in dirs.flatten() {
        if let Ok(files) = std::fs::read_dir(dir.path()) {
            found.extend(files.flatten().map(|f| f.path()));
        } else {
            found.insert(dir.path());
        }
    }
    found
}

#[test]
fn generated_matches_materials() {
    let planned = planned_outputs();
    let planned_paths: BTreeSet<PathBuf> = planned.iter().map(|f| f.path.clone()).collect();
    let stale: Vec<PathBuf> = files_on_disk().difference(&planned_paths).cloned().collect();
    if common::blessing() {
        output::write_all(&planned).expect("writes generated/");
        for path in &stale {
            std::fs::remove_file(path).expect("removes a stale file");
        }
        return;
    }
    let mut report = String::new();
    for file in &planned {
        let expected_bytes = std::fs::read(&file.path).unwrap_or_default();
        if expected_bytes != file.contents {
            let expected = String::from_utf8_lossy(&expected_bytes);
            let actual = String::from_utf8_lossy(&file.contents);
            report.push_str(&format!("\n=== {} ===\n{}", file.path.display(), common::diff(&expected, &actual)));
        }
    }
    for path in &stale {
        report.push_str(&format!("\n=== {} is not produced by any material ===\n", path.display()));
    }
    assert!(report.is_empty(), "generated/ is out of date (GLAZEC_BLESS=1 to update):{report}");
}

#[test]
fn every_material_produces_every_text_target() {
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let artifacts = compiled.emit(&glazec::Target::TEXT).expect("emits");
        let name = &compiled.material.name;
        let names: Vec<&str> = artifacts.iter().map(|a| a.file_name.as_str()).collect();
        for expected in [
            format!("{name}.wgsl"),
            format!("{name}.hlsl"),
            format!("{name}.eval_pairs.comp.glsl"),
            format!("{name}.preview_vs.vert.glsl"),
            format!("{name}.preview_fs.frag.glsl"),
        ] {
            assert!(names.contains(&expected.as_str()), "{}: missing {expected} in {names:?}", path.display());
        }
        // The material file is named after the material (so generated/<name>/ maps back to it).
        assert_eq!(path.file_stem().and_then(|s| s.to_str()), Some(name.as_str()));
    }
}

#[test]
fn compiling_twice_is_byte_identical() {
    for path in common::material_files() {
        let first = common::compile_file(&path).emit(&[
            glazec::Target::Wgsl,
            glazec::Target::Glsl,
            glazec::Target::Hlsl,
            glazec::Target::Spv,
        ]);
        let second = common::compile_file(&path).emit(&[
            glazec::Target::Wgsl,
            glazec::Target::Glsl,
            glazec::Target::Hlsl,
            glazec::Target::Spv,
        ]);
        assert_eq!(first.expect("emits"), second.expect("emits"), "{}", path.display());
    }
}
