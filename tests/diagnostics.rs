//! The bad-input corpus: every `tests/bad/X.ron` is an invalid material, and
//! `tests/bad/X.stderr` is exactly what `glazec check tests/bad/X.ron` prints on stderr.
//!
//! For every file this test checks that
//! - `glazec check` exits with 1 and prints the expected diagnostics (human format; stderr is
//!   not a terminal here, so there is no colour);
//! - `glazec check --message-format json` prints one well-formed JSON object per diagnostic,
//!   each with a code, a 1-based position and a primary label;
//! - `glazec compile -o DIR` exits with 1 and writes nothing.
//!
//! To regenerate the expected output after an intended change in wording, run
//! `GLAZEC_BLESS=1 cargo test --test diagnostics` and review the diff before committing.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use glazec::diag::Code;
use similar::{ChangeTag, TextDiff};

/// The corpus may grow, never shrink below this many files.
const MIN_CORPUS_SIZE: usize = 30;

/// Codes that the single-file corpus cannot exercise (they are tested separately below).
/// E03xx belong to scene files (`src/check/scene.rs` unit tests, `tests/simplify.rs`).
/// N0401 is a note on a material that compiles.
/// E0108 needs a file over 1 MiB (tests/robustness.rs).
const CODES_NOT_IN_CORPUS: &[&str] = &["E0108", "E0218", "E0301", "E0302", "E0303", "E0304", "E0305", "N0401"];

/// The corpus folder, relative to the project root.
const CORPUS_DIR: &str = "tests/bad";

/// Set to `1` to rewrite the `.stderr` files instead of comparing them.
const BLESS_VAR: &str = "GLAZEC_BLESS";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn blessing() -> bool {
    std::env::var(BLESS_VAR).is_ok_and(|v| v == "1")
}

/// The corpus files as `tests/bad/X.ron` paths relative to the project root, sorted.
fn corpus() -> Vec<String> {
    let dir = root().join(CORPUS_DIR);
    let mut files: Vec<String> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .map(|p| format!("{CORPUS_DIR}/{}", p.file_name().expect("file name").to_string_lossy()))
        .collect();
    files.sort();
    files
}

fn expected_path(ron: &str) -> PathBuf {
    root().join(Path::new(ron).with_extension("stderr"))
}

/// Runs glazec from the project root.
fn glazec<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_glazec")).current_dir(root()).args(args).output().expect("cannot run glazec")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A line diff, `-` for expected and `+` for actual.
fn line_diff(expected: &str, actual: &str) -> String {
    let mut out = String::new();
    for change in TextDiff::from_lines(expected, actual).iter_all_changes() {
        let sign = match change.tag() {
            ChangeTag::Delete => '-',
            ChangeTag::Insert => '+',
            ChangeTag::Equal => ' ',
        };
        out.push(sign);
        out.push_str(change.value());
        if change.missing_newline() {
            out.push_str("\n\\ no newline at end\n");
        }
    }
    out
}

/// Writes through a temporary file so that a concurrent reader never sees a half-written file.
fn write_atomically(path: &Path, contents: &str) {
    let dir = path.parent().expect("parent directory");
    let mut temp = tempfile::NamedTempFile::new_in(dir).expect("temporary file");
    std::io::Write::write_all(&mut temp, contents.as_bytes()).expect("write");
    temp.persist(path).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
}

/// The codes in human-format output, in order (`error[E0206]: …` headers).
fn human_codes(stderr: &str) -> Vec<String> {
    stderr
        .lines()
        .filter_map(|line| line.strip_prefix("error[").or_else(|| line.strip_prefix("warning[")))
        .filter_map(|rest| rest.split_once(']').map(|(code, _)| code.to_string()))
        .collect()
}

fn is_code(s: &str) -> bool {
    s.len() == 5 && s.starts_with("E0") && s[2..].bytes().all(|b| b.is_ascii_digit())
}

/// Checks the JSON rendering of one file's diagnostics; returns the problems found.
fn check_json(ron: &str, human: &str) -> Vec<String> {
    let output = glazec(["check", ron, "--message-format", "json"]);
    let mut problems = Vec::new();
    if output.status.code() != Some(1) {
        problems.push(format!("--message-format json: exit status {:?}, expected 1", output.status.code()));
    }
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    let mut codes = Vec::new();
    for line in stdout.lines().chain(stderr.lines()).filter(|l| !l.trim().is_empty()) {
        let json: serde_json::Value = match serde_json::from_str(line) {
            Ok(v) => v,
            Err(e) => {
                problems.push(format!("not a JSON line ({e}): {line}"));
                continue;
            }
        };
        let code = json["code"].as_str().unwrap_or("");
        if !is_code(code) {
            problems.push(format!("bad or missing `code`: {line}"));
        }
        codes.push(code.to_string());
        if json["file"].as_str() != Some(ron) {
            problems.push(format!("`file` is not `{ron}`: {line}"));
        }
        for key in ["line", "column"] {
            if json[key].as_u64().is_none_or(|n| n < 1) {
                problems.push(format!("`{key}` missing or below 1: {line}"));
            }
        }
        let labels = json["labels"].as_array().map(Vec::as_slice).unwrap_or(&[]);
        if !labels.iter().any(|l| l["primary"].as_bool() == Some(true)) {
            problems.push(format!("no primary label: {line}"));
        }
    }
    if codes.is_empty() {
        problems.push("--message-format json printed no diagnostics".into());
    }
    let expected_codes = human_codes(human);
    if codes != expected_codes {
        problems.push(format!("JSON codes {codes:?} differ from the human output's {expected_codes:?}"));
    }
    problems
}

/// Checks that `glazec compile` fails and writes nothing; returns the problems found.
fn check_compile_writes_nothing(ron: &str) -> Vec<String> {
    let out = tempfile::tempdir().expect("temporary directory");
    let output = glazec(["compile".as_ref(), ron.as_ref(), "-o".as_ref(), out.path().as_os_str()]);
    let mut problems = Vec::new();
    if output.status.code() != Some(1) {
        problems.push(format!("compile: exit status {:?}, expected 1", output.status.code()));
    }
    let written: Vec<_> = fs::read_dir(out.path()).expect("read temporary directory").collect();
    if !written.is_empty() {
        problems.push(format!("compile wrote {} entries into the output directory", written.len()));
    }
    problems
}

#[test]
fn bad_inputs_produce_the_expected_diagnostics() {
    let files = corpus();
    assert!(!files.is_empty(), "no files in {CORPUS_DIR}");
    let bless = blessing();
    let mut failures: Vec<String> = Vec::new();
    for ron in &files {
        let mut problems = Vec::new();
        let output = glazec(["check", ron.as_str()]);
        if output.status.code() != Some(1) {
            problems.push(format!("check: exit status {:?}, expected 1", output.status.code()));
        }
        let stderr = text(&output.stderr);
        if !output.stdout.is_empty() {
            problems.push(format!("check printed on stdout:\n{}", text(&output.stdout)));
        }
        let expected_file = expected_path(ron);
        if bless {
            write_atomically(&expected_file, &stderr);
        } else {
            match fs::read_to_string(&expected_file) {
                Ok(expected) if expected == stderr => {}
                Ok(expected) => problems.push(format!(
                    "stderr differs from {} (- expected, + actual):\n{}",
                    expected_file.display(),
                    line_diff(&expected, &stderr)
                )),
                Err(e) => problems.push(format!(
                    "cannot read {} ({e}); run with {BLESS_VAR}=1 to create it. Actual stderr:\n{stderr}",
                    expected_file.display()
                )),
            }
        }
        problems.extend(check_json(ron, &stderr));
        problems.extend(check_compile_writes_nothing(ron));
        if !problems.is_empty() {
            eprintln!("---- {ron}");
            for p in &problems {
                eprintln!("{p}");
            }
            failures.push(ron.clone());
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} corpus files failed:\n  {}",
        failures.len(),
        files.len(),
        failures.join("\n  ")
    );
}

#[test]
fn corpus_covers_every_code() {
    let files = corpus();
    assert!(
        files.len() >= MIN_CORPUS_SIZE,
        "{CORPUS_DIR} has {} files; it must keep at least {MIN_CORPUS_SIZE}",
        files.len()
    );
    let bless = blessing();
    let mut seen = std::collections::BTreeSet::new();
    for ron in &files {
        if bless {
            // The other test is rewriting the .stderr files right now; use what it will write.
            seen.extend(human_codes(&text(&glazec(["check", ron.as_str()]).stderr)));
        } else if let Ok(expected) = fs::read_to_string(expected_path(ron)) {
            // A missing file is reported by the comparison test; here it just covers nothing.
            seen.extend(human_codes(&expected));
        }
    }
    let missing: Vec<&str> = Code::ALL
        .iter()
        .map(|c| c.as_str())
        .filter(|c| !CODES_NOT_IN_CORPUS.contains(c) && !seen.contains(*c))
        .collect();
    assert!(missing.is_empty(), "no file in {CORPUS_DIR} exercises {missing:?}; add one");
    // Every .stderr belongs to a .ron (a renamed or deleted test leaves none behind).
    let dir = root().join(CORPUS_DIR);
    for entry in fs::read_dir(&dir).expect("corpus directory") {
        let path = entry.expect("directory entry").path();
        if path.extension().is_some_and(|e| e == "stderr") {
            assert!(path.with_extension("ron").is_file(), "{} has no .ron file", path.display());
        }
    }
}

const TWIN: &str = "// One of two files that declare the same material.
Material(
    name: \"twin\",
    layers: [Lambert(albedo: 0.5)],
)
";

#[test]
fn duplicate_material_names_across_files_are_rejected() {
    let inputs = tempfile::tempdir().expect("temporary directory");
    let first = inputs.path().join("first.ron");
    let second = inputs.path().join("second.ron");
    fs::write(&first, TWIN).expect("write first.ron");
    fs::write(&second, TWIN.replace("0.5", "0.4")).expect("write second.ron");
    let out = tempfile::tempdir().expect("temporary directory");
    let output =
        glazec(["compile".as_ref(), first.as_os_str(), second.as_os_str(), "-o".as_ref(), out.path().as_os_str()]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "stderr:\n{stderr}");
    assert_eq!(human_codes(&stderr), ["E0218"], "stderr:\n{stderr}");
    assert!(stderr.contains("material `twin` is also defined in"), "stderr:\n{stderr}");
    for path in [&first, &second] {
        assert!(stderr.contains(&path.display().to_string()), "{} not mentioned:\n{stderr}", path.display());
    }
    let written: Vec<_> = fs::read_dir(out.path()).expect("read output directory").collect();
    assert!(written.is_empty(), "compile wrote {} entries", written.len());
}

/// Regression test for a known bug in `compile_all` (src/main.rs): it zips *all* inputs with the
/// *successfully compiled* ones, so once an earlier file has failed, E0218 is printed against
/// the wrong file, names the wrong "other" file and applies the span to the wrong text.
#[test]
fn duplicate_material_after_a_failing_file_names_the_right_files() {
    let inputs = tempfile::tempdir().expect("temporary directory");
    let broken = inputs.path().join("a_broken.ron");
    let first = inputs.path().join("b_first.ron");
    let second = inputs.path().join("c_second.ron");
    fs::write(&broken, "Material(name: \"broken\", layers: [])\n").expect("write");
    fs::write(&first, TWIN).expect("write");
    fs::write(&second, TWIN.replace("0.5", "0.4")).expect("write");
    let output = glazec(["check".as_ref(), broken.as_os_str(), first.as_os_str(), second.as_os_str()]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "stderr:\n{stderr}");
    let e0218 = &stderr[stderr.find("error[E0218]").expect("an E0218 diagnostic")..];
    let header = e0218.lines().nth(1).unwrap_or("");
    assert!(header.contains(&second.display().to_string()), "E0218 should point into c_second.ron:\n{e0218}");
    assert!(
        e0218.lines().next().unwrap_or("").contains(&first.display().to_string()),
        "should name b_first.ron:\n{e0218}"
    );
}
