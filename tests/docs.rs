//! The documentation stays true: the README is a short front door whose commands are what CI
//! runs, the chapters document every diagnostic code, quote real generated code and the
//! published measurement tables verbatim, the headline figures come from those tables, and every
//! relative link resolves.

mod common;

use std::path::Path;

/// The front door's length limit.
const README_MAX_LINES: usize = 200;

fn read(path: &str) -> String {
    std::fs::read_to_string(common::root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The text between `<!-- {marker}:begin -->` and `<!-- {marker}:end -->` of `text`.
fn quoted<'t>(text: &'t str, marker: &str, file: &str) -> &'t str {
    let begin = format!("<!-- {marker}:begin -->\n");
    let start = text.find(&begin).unwrap_or_else(|| panic!("{file} lacks {begin}")) + begin.len();
    let end =
        text.find(&format!("<!-- {marker}:end -->")).unwrap_or_else(|| panic!("{file} lacks the end of {marker}"));
    &text[start..end]
}

#[test]
fn the_readme_is_a_short_front_door_with_the_two_commands() {
    let readme = read("README.md");
    let lines = readme.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines (at most {README_MAX_LINES}); move reference to docs/"
    );
    assert!(readme.contains("cargo run --release -- compile materials/"), "README's main job");
    assert!(readme.contains("\n./scripts/test "), "README's test command");
    let ci = read(".ci/run");
    assert!(ci.lines().any(|l| l.trim() == "./scripts/test"), ".ci/run must run ./scripts/test");
    assert!(
        ci.contains("GLAZEC_REQUIRE_TOOLS=1") && ci.contains("GLAZEC_REQUIRE_GPU=1") && ci.contains("GLAZEC_DEEP=1")
    );
}

#[test]
fn every_diagnostic_code_is_documented() {
    let chapter = read("docs/diagnostics.md");
    for code in glazec::diag::Code::ALL {
        assert!(chapter.contains(&format!("| {} |", code.as_str())), "docs/diagnostics.md lacks a row for {code}");
    }
}

#[test]
fn the_quoted_shader_excerpt_is_real_output() {
    let chapter = read("docs/generated-files.md");
    let start = chapter.find("// Walter et al. 2007").expect("the d_ggx excerpt");
    let end = start + chapter[start..].find("\n}\n").expect("end of d_ggx") + 3;
    let excerpt = &chapter[start..end];
    let wgsl = read("generated/wet_clay/wet_clay.wgsl");
    assert!(wgsl.contains(excerpt), "the d_ggx excerpt differs from generated/wet_clay/wet_clay.wgsl:\n{excerpt}");
}

#[test]
fn the_chapters_quote_the_published_tables() {
    for (chapter, marker, results) in [
        ("docs/accuracy.md", "accuracy", "docs/results/accuracy.md"),
        ("docs/accuracy.md", "accuracy-full", "docs/results/accuracy-full.md"),
        ("docs/accuracy.md", "stated-albedo", "docs/results/stated-albedo.md"),
        ("docs/accuracy.md", "images", "docs/results/images.md"),
        ("docs/speed.md", "bench", "docs/results/bench.md"),
    ] {
        let text = read(chapter);
        assert_eq!(quoted(&text, marker, chapter), read(results), "{chapter} quotes {results} (the lab writes it)");
    }
}

/// Every number of the README's headline figures appears in a published results file, so that
/// the front door cannot drift from what the lab measured.
#[test]
fn the_headline_figures_come_from_the_results() {
    let readme = read("README.md");
    let headline = quoted(&readme, "headline", "README.md");
    let results: String = ["accuracy.md", "bench.md", "stability/summary.md"]
        .iter()
        .map(|f| read(&format!("docs/results/{f}")))
        .collect();
    let numbers: Vec<&str> = headline
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
        .map(|t| t.trim_matches(|c| c == '.' || c == 'e' || c == '-'))
        .filter(|t| t.contains(|c: char| c.is_ascii_digit()) && t.contains('.'))
        .collect();
    assert!(numbers.len() >= 10, "the headline block lost its figures: {numbers:?}");
    for n in numbers {
        assert!(results.contains(n), "README's headline figure {n} is not in docs/results/");
    }
}

/// Relative Markdown links `[text](target)` in `text`, without their `#anchor`.
fn links(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("](") {
        rest = &rest[at + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].split('#').next().unwrap_or_default();
        if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
            out.push(target);
        }
        rest = &rest[end..];
    }
    out
}

#[test]
fn every_relative_link_resolves() {
    let mut files = vec![common::root().join("README.md"), common::root().join("CHANGELOG.md")];
    for entry in std::fs::read_dir(common::root().join("docs")).expect("docs/").flatten() {
        if entry.path().extension().is_some_and(|e| e == "md") {
            files.push(entry.path());
        }
    }
    let mut broken = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).expect("readable");
        let dir = file.parent().unwrap_or(Path::new("."));
        for target in links(&text) {
            if !dir.join(target).exists() {
                broken.push(format!("{}: {target}", file.display()));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}
