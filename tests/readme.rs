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

#[test]
fn accuracy_table_in_the_readme_is_the_one_in_docs() {
    let readme = readme();
    let begin = "<!-- accuracy:begin -->\n";
    let start = readme.find(begin).expect("the accuracy table's start marker") + begin.len();
    let end = readme.find("<!-- accuracy:end -->").expect("the accuracy table's end marker");
    let docs = std::fs::read_to_string(common::root().join("docs/accuracy.md")).expect("docs/accuracy.md");
    assert_eq!(
        &readme[start..end],
        docs,
        "README's accuracy table differs from docs/accuracy.md (glazec accuracy writes it)"
    );
}
