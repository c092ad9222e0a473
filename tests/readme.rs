//! README.md stays true: it documents every diagnostic code, its test command is what CI runs,
//! and the shader excerpt it quotes is what glazec emits.

mod common;

fn readme() -> String {
    std::fs::read_to_string(common::root().join("README.md")).expect("README.md")
}

#[test]
fn every_diagnostic_code_is_documented() {
    let readme = readme();
    for code in glazec::diag::Code::ALL {
        assert!(readme.contains(&format!("| {} |", code.as_str())), "README lacks a row for {code}");
    }
}

#[test]
fn ci_runs_the_readme_test_command() {
    let readme = readme();
    let ci = std::fs::read_to_string(common::root().join(".ci/run")).expect(".ci/run");
    assert!(readme.contains("\n./scripts/test "), "README's test command");
    assert!(ci.lines().any(|l| l.trim() == "./scripts/test"), ".ci/run must run ./scripts/test");
    assert!(ci.contains("GLAZEC_REQUIRE_TOOLS=1") && ci.contains("GLAZEC_REQUIRE_GPU=1"));
    assert!(readme.contains("cargo run --release -- compile materials/"));
}

#[test]
fn quoted_shader_excerpt_is_real_output() {
    let readme = readme();
    let start = readme.find("// Walter et al. 2007").expect("the d_ggx excerpt");
    let end = start + readme[start..].find("\n}\n").expect("end of d_ggx") + 3;
    let excerpt = &readme[start..end];
    let wgsl = std::fs::read_to_string(common::root().join("generated/wet_clay/wet_clay.wgsl")).expect("generated");
    assert!(wgsl.contains(excerpt), "README's d_ggx excerpt differs from generated/wet_clay/wet_clay.wgsl:\n{excerpt}");
}

/// The text between `<!-- {marker}:begin -->` and `<!-- {marker}:end -->` in the README, and the
/// docs file it quotes.
fn quoted(marker: &str, docs: &str) -> (String, String) {
    let readme = readme();
    let begin = format!("<!-- {marker}:begin -->\n");
    let start = readme.find(&begin).unwrap_or_else(|| panic!("README lacks {begin}")) + begin.len();
    let end =
        readme.find(&format!("<!-- {marker}:end -->")).unwrap_or_else(|| panic!("README lacks the end of {marker}"));
    let docs = std::fs::read_to_string(common::root().join(docs)).unwrap_or_else(|e| panic!("{docs}: {e}"));
    (readme[start..end].to_string(), docs)
}

#[test]
fn accuracy_table_in_the_readme_is_the_one_in_docs() {
    let (quoted, docs) = quoted("accuracy", "docs/accuracy.md");
    assert_eq!(quoted, docs, "README's accuracy table differs from docs/accuracy.md (glazec accuracy writes it)");
}

#[test]
fn bench_tables_in_the_readme_are_the_ones_in_docs() {
    let (quoted, docs) = quoted("bench", "docs/bench.md");
    assert_eq!(quoted, docs, "README's bench tables differ from docs/bench.md (glazec bench writes it)");
}
