//! The `glazec` binary: what it writes, its exit codes, and its determinism.

mod common;

use common::glazec;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

fn code(out: &Output) -> i32 {
    out.status.code().expect("exited normally")
}

/// Every file under `dir`, by path relative to it.
fn tree(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    common::files_under(dir)
        .into_iter()
        .map(|path| {
            let rel = path.strip_prefix(dir).expect("inside").display().to_string();
            (rel, std::fs::read(&path).expect("readable file"))
        })
        .collect()
}

#[test]
fn compile_writes_every_target_for_every_material_identically_twice() {
    let (a, b) = (tempfile::tempdir().expect("tmp"), tempfile::tempdir().expect("tmp"));
    for dir in [&a, &b] {
        let out = glazec(&["compile", "materials/", "-o", dir.path().to_str().expect("utf-8")]);
        assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    }
    let (first, second) = (tree(a.path()), tree(b.path()));
    assert_eq!(first, second, "two runs differ");
    // generated/scenes/ holds the `--scene` outputs (tests/golden.rs).
    let mut golden = tree(&common::root().join("generated"));
    golden.retain(|path, _| !path.starts_with("scenes/"));
    assert!(first == golden, "the CLI's output differs from generated/");
    let materials = common::material_files().len();
    // The libraries alone: glazec's harness only with --harness.
    for ext in [".naga_oil.wgsl", ".hlsli"] {
        assert_eq!(first.keys().filter(|k| k.ends_with(ext)).count(), materials, "{ext}");
    }
    for ext in ["wgsl", "glsl"] {
        let libraries = first
            .keys()
            .filter(|k| k.split('/').next_back().is_some_and(|f| f.matches('.').count() == 1 && f.ends_with(ext)));
        assert_eq!(libraries.count(), materials, "{ext} libraries");
    }
    let harness =
        [".harness.wgsl", ".hlsl", ".comp.glsl", ".vert.glsl", ".preview_fs.frag.glsl", ".preview_ibl_fs.frag.glsl"];
    assert!(first.keys().all(|k| !harness.iter().any(|ext| k.ends_with(ext))), "a harness file without --harness");
    let with = tempfile::tempdir().expect("tmp");
    let out = glazec(&["compile", "materials/", "--harness", "-o", with.path().to_str().expect("utf-8")]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let with = tree(with.path());
    for ext in harness {
        assert_eq!(with.keys().filter(|k| k.ends_with(ext)).count(), materials, "{ext} with --harness");
    }
    // The libraries are the same bytes with or without the harness beside them.
    assert!(first.iter().all(|(path, bytes)| with.get(path) == Some(bytes)), "--harness changed a library");
}

#[test]
fn spirv_on_request() {
    let dir = tempfile::tempdir().expect("tmp");
    let out =
        glazec(&["compile", "materials/clay.ron", "--target", "spv,wgsl", "-o", dir.path().to_str().expect("utf-8")]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let files = tree(dir.path());
    // (clay's literal coat reads no table: no table file.)
    assert_eq!(files.keys().cloned().collect::<Vec<_>>(), ["clay/clay.spv", "clay/clay.wgsl"]);
    let spv = &files["clay/clay.spv"];
    assert_eq!(&spv[..4], &0x0723_0203_u32.to_le_bytes(), "SPIR-V magic number");
}

#[test]
fn check_mode_reports_drift_and_writes_nothing() {
    let out = glazec(&["compile", "--check", "materials/", "-o", "generated"]);
    assert_eq!(code(&out), 0, "generated/ is current: {}", String::from_utf8_lossy(&out.stderr));
    let dir = tempfile::tempdir().expect("tmp");
    let target = dir.path().to_str().expect("utf-8");
    let out = glazec(&["compile", "--check", "materials/clay.ron", "-o", target]);
    assert_eq!(code(&out), 1);
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing:"));
    assert!(tree(dir.path()).is_empty(), "--check wrote files");
}

#[test]
fn check_mode_prints_a_unified_diff_of_what_changed() {
    let dir = tempfile::tempdir().expect("tmp");
    let target = dir.path().to_str().expect("utf-8");
    assert_eq!(code(&glazec(&["compile", "materials/clay.ron", "--target", "wgsl", "-o", target])), 0);
    let wgsl = dir.path().join("clay/clay.wgsl");
    let original = std::fs::read_to_string(&wgsl).expect("written");
    let line = original.lines().find(|l| l.starts_with("fn clay_d_ggx")).expect("d_ggx is emitted").to_string();
    std::fs::write(&wgsl, original.replace(&line, "fn d_ggx_edited_by_hand() {")).expect("edits");
    let out = glazec(&["compile", "--check", "materials/clay.ron", "--target", "wgsl", "-o", target]);
    assert_eq!(code(&out), 1);
    let diff = String::from_utf8_lossy(&out.stdout);
    assert!(diff.contains("(on disk)") && diff.contains("(generated)") && diff.contains("@@"), "{diff}");
    assert!(diff.contains("-fn d_ggx_edited_by_hand() {") && diff.contains(&format!("+{line}")), "{diff}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("out of date:"));
    assert_eq!(
        std::fs::read_to_string(&wgsl).expect("still there"),
        original.replace(&line, "fn d_ggx_edited_by_hand() {")
    );
}

#[test]
fn one_bad_file_means_nothing_is_written() {
    let dir = tempfile::tempdir().expect("tmp");
    let bad = dir.path().join("bad.ron");
    std::fs::write(&bad, "Material(name: \"bad\", layers: [Lambert(albedo: 7)])").expect("writes");
    let out_dir = dir.path().join("out");
    let out = glazec(&[
        "compile",
        "materials/clay.ron",
        bad.to_str().expect("utf-8"),
        "-o",
        out_dir.to_str().expect("utf-8"),
    ]);
    assert_eq!(code(&out), 1);
    assert!(String::from_utf8_lossy(&out.stderr).contains("E0213"));
    assert!(!out_dir.exists(), "outputs were written despite an error");
}

#[test]
fn usage_errors_exit_with_2() {
    assert_eq!(code(&glazec(&[])), 2);
    assert_eq!(code(&glazec(&["compile"])), 2);
    assert_eq!(code(&glazec(&["compile", "--target", "msl", "materials/"])), 2);
    let out = glazec(&["check", "does/not/exist.ron"]);
    assert_eq!(code(&out), 2);
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read"));
}

/// An unreadable input is reported with its cause once, not once per layer of error wrapping.
#[test]
fn unreadable_inputs_name_their_cause_once() {
    let out = glazec(&["compile", "does/not/exist.ron"]);
    assert_eq!(code(&out), 2);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.matches("No such file or directory").count(), 1, "{stderr}");
    let dir = tempfile::tempdir().expect("tmp");
    let binary = dir.path().join("binary.ron");
    std::fs::write(&binary, [0xff, 0xfe, 0x00]).expect("writes");
    let out = glazec(&["check", binary.to_str().expect("utf-8")]);
    assert_eq!(code(&out), 2);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim(), format!("error: cannot read {}: stream did not contain valid UTF-8", binary.display()));
}

#[test]
fn check_accepts_every_shipped_material() {
    let out = glazec(&["check", "materials/"]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn eval_prints_one_line_per_pair_and_honours_overrides() {
    let dir = tempfile::tempdir().expect("tmp");
    let pairs = dir.path().join("pairs.csv");
    std::fs::write(&pairs, "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n0.6,0,0.8,-0.6,0,0.8\n0,0,-1,0,0,1\n")
        .expect("writes");
    let pairs = pairs.to_str().expect("utf-8");
    let out = glazec(&["eval", "materials/tunable_glaze.ron", "--pairs", pairs]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let lines: Vec<Vec<f32>> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect())
        .collect();
    assert_eq!(lines.len(), 3);
    assert!(lines[0].iter().all(|&x| x > 0.0));
    assert_eq!(lines[2], [0.0, 0.0, 0.0], "below the horizon");

    let darker = glazec(&["eval", "materials/tunable_glaze.ron", "--pairs", pairs, "--set", "body_albedo=0.1"]);
    assert_eq!(code(&darker), 0, "{}", String::from_utf8_lossy(&darker.stderr));
    let first: f32 = String::from_utf8_lossy(&darker.stdout).split(',').next().expect("value").parse().expect("number");
    assert!(first < lines[0][0], "a darker body gives a darker BRDF");

    assert_eq!(code(&glazec(&["eval", "materials/tunable_glaze.ron", "--pairs", pairs, "--set", "nope=1"])), 2);
    assert_eq!(code(&glazec(&["eval", "materials/tunable_glaze.ron", "--pairs", pairs, "--set", "glaze_ior=1,2"])), 2);
    // Values the parameter's slots would refuse as literals: a roughness of 5, a negative albedo.
    for set in ["glaze_roughness=5", "body_albedo=0.5,-0.1,0.5", "glaze_ior=0.05"] {
        let out = glazec(&["eval", "materials/tunable_glaze.ron", "--pairs", pairs, "--set", set]);
        assert_eq!(code(&out), 2, "{set}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("is outside ["),
            "{set}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let bad_pairs = dir.path().join("bad.csv");
    std::fs::write(&bad_pairs, "0,0,1,0,0\n").expect("writes");
    assert_eq!(code(&glazec(&["eval", "materials/clay.ron", "--pairs", bad_pairs.to_str().expect("utf-8")])), 2);
}
