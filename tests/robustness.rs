//! Robustness: the fuzz corpus and every crash fuzzing found replay as ordinary tests; random
//! mutations of valid materials and random text never panic and always explain themselves;
//! every documented limit and output-safety rule holds.

mod common;

use common::glazec;

use std::path::{Path, PathBuf};

use glazec_lab::fuzzing;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// Mutated materials and random texts per run (fixed seed; `GLAZEC_PROPTEST_CASES` asks for more).
const CASES: u32 = 300;
const SEED: u64 = 0x0b57_ac1e;
/// Invalid mutations also run through the binary (slower: one process each).
const CLI_CASES: usize = 12;

fn cases() -> u32 {
    std::env::var("GLAZEC_PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(CASES)
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.flatten().map(|e| e.path()).filter(|p| p.is_file()).collect())
        .unwrap_or_default();
    files.sort();
    files
}

#[test]
fn the_fuzzers_seed_from_every_shipped_material() {
    // `fuzzing::SHIPPED` lists the files by hand (include_str! needs literal paths).
    let on_disk: Vec<String> =
        common::material_files().iter().map(|p| std::fs::read_to_string(p).expect("readable")).collect();
    assert_eq!(
        fuzzing::SHIPPED.len(),
        on_disk.len(),
        "a material was added or removed: update glazec_lab::fuzzing::SHIPPED"
    );
    assert!(on_disk.iter().all(|text| fuzzing::SHIPPED.contains(&text.as_str())));
}

#[test]
fn the_fuzz_corpus_and_every_crash_found_replay_without_panics() {
    let fuzz = common::root().join("fuzz");
    let mut replayed = 0;
    for target in ["parse_check", "pipeline", "mutate_valid"] {
        for dir in [fuzz.join("corpus").join(target), fuzz.join("regressions").join(target)] {
            for file in files_in(&dir) {
                let Ok(data) = std::fs::read(&file) else { continue }; // a fuzzer running beside us may reduce it away
                match target {
                    "mutate_valid" => fuzzing::whole_pipeline(&fuzzing::mutate_shipped(&data)),
                    _ => {
                        let Ok(text) = std::str::from_utf8(&data) else { continue };
                        if target == "parse_check" {
                            fuzzing::parse_and_check(text)
                        } else {
                            fuzzing::whole_pipeline(text)
                        }
                    }
                }
                replayed += 1;
            }
        }
    }
    assert!(replayed >= 40, "only {replayed} corpus files");
    eprintln!("replayed {replayed} corpus and regression inputs");
}

proptest! {
    #![proptest_config(Config { cases: cases(), rng_seed: RngSeed::Fixed(SEED), failure_persistence: None, ..Config::default() })]

    #[test]
    fn mutated_shipped_materials_compile_or_explain_themselves(data in prop::collection::vec(any::<u8>(), 1..24)) {
        fuzzing::whole_pipeline(&fuzzing::mutate_shipped(&data));
    }

    #[test]
    fn random_text_is_diagnosed_without_panics(text in "[ -~\\n\\u{e9}\\u{2212}]{0,200}") {
        fuzzing::parse_and_check(&text);
        fuzzing::whole_pipeline(&text);
    }
}

#[test]
fn invalid_mutations_exit_1_with_a_located_diagnostic_and_write_nothing() {
    let dir = tempfile::tempdir().expect("tmp");
    let mut checked = 0;
    let mut seed = 0x5eed_u32;
    while checked < CLI_CASES {
        seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
        let data: Vec<u8> = (0..8).map(|i| (seed >> (i * 3)) as u8).collect();
        let text = fuzzing::mutate_shipped(&data);
        if glazec::load(&text).is_ok() {
            continue; // a mutation that stayed valid
        }
        let input = dir.path().join(format!("case{checked}.ron"));
        std::fs::write(&input, &text).expect("writes");
        let out_dir = dir.path().join(format!("out{checked}"));
        let out = glazec(&["compile", input.to_str().expect("utf-8"), "-o", out_dir.to_str().expect("utf-8")]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}\n{text}");
        assert!(stderr.contains("error[E") && stderr.contains(&format!("case{checked}.ron:")), "{stderr}");
        assert!(!out_dir.exists(), "outputs written despite an error");
        checked += 1;
    }
}

#[test]
fn every_limit_is_enforced_with_a_clear_error() {
    // File size: the library refuses with E0108; the CLI does not even read the file.
    let huge = format!(
        "// {}\nMaterial(name: \"big\", layers: [Lambert(albedo: 0.5)])",
        "x".repeat(glazec::parse::MAX_SOURCE_BYTES)
    );
    let errors = glazec::load(&huge).expect_err("too large");
    assert_eq!(errors[0].code.as_str(), "E0108");
    let dir = tempfile::tempdir().expect("tmp");
    let big = dir.path().join("big.ron");
    std::fs::write(&big, &huge).expect("writes");
    let out = glazec(&["check", big.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("sources of at most 1048576 bytes are read"));
    // Nesting depth: no stack overflow on 100,000 brackets.
    let deep = format!("Material(name: \"d\", layers: {}{})", "[".repeat(100_000), "]".repeat(100_000));
    assert_eq!(glazec::load(&deep).expect_err("too deep")[0].code.as_str(), "E0107");
    // Layers, parameters and identifier length (the corpus shows their messages).
    let coat = "Coat(lobe: Smooth, ior: 1.5)";
    let seventeen = format!("Material(name: \"m\", layers: [{}, Lambert(albedo: 0.5)])", [coat; 17].join(", "));
    assert_eq!(glazec::load(&seventeen).expect_err("17 coats")[0].code.as_str(), "E0216");
    let long = format!("Material(name: \"{}\", layers: [Lambert(albedo: 0.5)])", "a".repeat(49));
    assert_eq!(glazec::load(&long).expect_err("49 characters")[0].code.as_str(), "E0212");
    let params: Vec<String> = (0..16)
        .map(|i| format!("Coat(lobe: Ggx(Param(\"r{i}\", 0.2)), ior: Param(\"n{i}\", 1.5), absorption: Param(\"a{i}\", 0.1), thickness: Param(\"d{i}\", 0.5))"))
        .collect();
    let many = format!(
        "Material(name: \"m\", layers: [{}, Eon(albedo: Param(\"x\", 0.5), roughness: Param(\"y\", 0.5))])",
        params.join(", ")
    );
    assert!(glazec::load(&many).expect_err("67 parameters").iter().any(|d| d.code.as_str() == "E0219"));
}

#[test]
fn names_cannot_leave_the_output_directory() {
    for name in ["../escape", "/abs", "a/b", "con", "nul", "com1", "..", "a\\\\b"] {
        let text = format!("Material(name: \"{name}\", layers: [Lambert(albedo: 0.5)])");
        let errors = glazec::load(&text).expect_err(name);
        assert_eq!(errors[0].code.as_str(), "E0212", "{name}");
    }
}

#[test]
fn an_output_directory_that_cannot_be_written_is_a_clear_error() {
    let dir = tempfile::tempdir().expect("tmp");
    let blocker = dir.path().join("not_a_directory");
    std::fs::write(&blocker, "a file where the output folder should go").expect("writes");
    let out = glazec(&["compile", "materials/clay.ron", "-o", blocker.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("cannot write to") && stderr.contains("not_a_directory"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&blocker).expect("untouched"), "a file where the output folder should go");
}

#[test]
fn compiling_in_parallel_gives_the_bytes_of_compiling_serially() {
    let files = common::material_files();
    let serial: Vec<Vec<glazec::Artifact>> =
        files.iter().map(|p| common::compile_file(p).emit(&glazec::Target::TEXT).expect("emits")).collect();
    let parallel: Vec<Vec<glazec::Artifact>> = std::thread::scope(|scope| {
        let handles: Vec<_> = files
            .iter()
            .map(|p| scope.spawn(move || common::compile_file(p).emit(&glazec::Target::TEXT).expect("emits")))
            .collect();
        handles.into_iter().map(|h| h.join().expect("no panic")).collect()
    });
    assert!(serial == parallel, "parallel compilation changed the output");
}
