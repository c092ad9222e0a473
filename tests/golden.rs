//! Golden outputs: `generated/` must be exactly what `glazec compile materials/` produces.
//!
//! The comparison is the library's snapshot helper (`glazec::snapshot`), which users run on their
//! own materials: on mismatch it prints a unified diff per file and fails; `GLAZEC_BLESS=1 cargo
//! test --test golden` rewrites `generated/` (and removes files no material produces any more).

mod common;

use glazec::snapshot::Snapshot;

#[test]
fn generated_matches_materials() {
    Snapshot::new(common::root().join("materials"), common::root().join("generated")).assert_current();
}

/// `generated/scenes/<scene>/`: every material simplified for every shipped scene (WGSL and the
/// `.simplify.md` report), as `glazec compile --scene scenes/<scene>.ron --target wgsl` writes it.
#[test]
fn scene_outputs_match_materials_and_scenes() {
    let scenes = common::scene_files();
    assert!(scenes.len() >= 4, "studio, overcast, turntable, top-down");
    for scene in scenes {
        let name = scene.file_stem().expect("file name").to_string_lossy().into_owned();
        Snapshot::new(common::root().join("materials"), common::root().join("generated/scenes").join(name))
            .scene(&scene)
            .targets(&[glazec::Target::Wgsl])
            .assert_current();
    }
}

/// `emit` writes the libraries alone; `emit_with_harness` adds glazec's harness files.
#[test]
fn every_material_produces_every_text_target() {
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let name = &compiled.material.name;
        let libraries =
            [format!("{name}.wgsl"), format!("{name}.naga_oil.wgsl"), format!("{name}.glsl"), format!("{name}.hlsli")];
        let tables = compiled.uses_tables().then(|| format!("{name}.tables.bin"));
        let artifacts = compiled.emit(&glazec::Target::TEXT).expect("emits");
        let names: Vec<String> = artifacts.iter().map(|a| a.file_name.clone()).collect();
        let expected: Vec<String> = libraries.iter().cloned().chain(tables.clone()).collect();
        assert_eq!(names, expected, "{}: the libraries alone", path.display());
        assert!(artifacts.iter().all(|a| !a.harness));
        let artifacts = compiled.emit_with_harness(&glazec::Target::TEXT).expect("emits");
        let names: Vec<&str> = artifacts.iter().map(|a| a.file_name.as_str()).collect();
        for expected in libraries.iter().cloned().chain([
            format!("{name}.harness.wgsl"),
            format!("{name}.hlsl"),
            format!("{name}.eval_pairs.comp.glsl"),
            format!("{name}.preview_vs.vert.glsl"),
            format!("{name}.preview_fs.frag.glsl"),
            format!("{name}.preview_ibl_fs.frag.glsl"),
        ]) {
            assert!(names.contains(&expected.as_str()), "{}: missing {expected} in {names:?}", path.display());
        }
        assert_eq!(artifacts.iter().filter(|a| a.harness).count(), 6);
        // The material file is named after the material (so generated/<name>/ maps back to it).
        assert_eq!(path.file_stem().and_then(|s| s.to_str()), Some(name.as_str()));
    }
}

#[test]
fn compiling_twice_is_byte_identical() {
    for path in common::material_files() {
        let first = common::compile_file(&path).emit_with_harness(&[
            glazec::Target::Wgsl,
            glazec::Target::Glsl,
            glazec::Target::Hlsl,
            glazec::Target::Spv,
        ]);
        let second = common::compile_file(&path).emit_with_harness(&[
            glazec::Target::Wgsl,
            glazec::Target::Glsl,
            glazec::Target::Hlsl,
            glazec::Target::Spv,
        ]);
        assert_eq!(first.expect("emits"), second.expect("emits"), "{}", path.display());
    }
}
