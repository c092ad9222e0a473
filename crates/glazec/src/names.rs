//! Which names generated code cannot use: the reserved words of WGSL, GLSL, HLSL and naga's
//! own prefixes, and names Windows refuses as file names. `check` refuses them in materials;
//! `emit` keeps the names it chooses clear of them.

/// Reserved words of GLSL and HLSL that naga would rename if used as a struct member; a
/// parameter's name must survive unchanged in every backend (naga's WGSL list is checked too).
const RESERVED_NAMES: &[&str] = &[
    "active",
    "asm",
    "attribute",
    "bool",
    "break",
    "buffer",
    "case",
    "cast",
    "centroid",
    "cbuffer",
    "class",
    "coherent",
    "column_major",
    "common",
    "compile",
    "const",
    "continue",
    "default",
    "discard",
    "do",
    "double",
    "else",
    "enum",
    "export",
    "extern",
    "external",
    "false",
    "filter",
    "fixed",
    "flat",
    "float",
    "for",
    "goto",
    "groupshared",
    "half",
    "highp",
    "if",
    "in",
    "inline",
    "inout",
    "input",
    "int",
    "interface",
    "invariant",
    "layout",
    "line",
    "linear",
    "long",
    "lowp",
    "matrix",
    "mediump",
    "namespace",
    "noinline",
    "nointerpolation",
    "noperspective",
    "out",
    "output",
    "packed",
    "packoffset",
    "partition",
    "pass",
    "patch",
    "point",
    "precise",
    "precision",
    "readonly",
    "register",
    "resource",
    "restrict",
    "return",
    "row_major",
    "sample",
    "sampler",
    "shared",
    "short",
    "signed",
    "sizeof",
    "smooth",
    "static",
    "string",
    "struct",
    "subroutine",
    "superp",
    "switch",
    "technique",
    "template",
    "texture",
    "this",
    "triangle",
    "true",
    "typedef",
    "uint",
    "uniform",
    "union",
    "unsigned",
    "using",
    "vector",
    "void",
    "volatile",
    "while",
    "writeonly",
    "main",
    "params",
];

/// Whether `word` is reserved in one of the target languages (or by glazec's generated code).
pub fn is_reserved(word: &str) -> bool {
    static RESERVED: std::sync::OnceLock<std::collections::HashSet<&'static str>> = std::sync::OnceLock::new();
    RESERVED
        .get_or_init(|| RESERVED_NAMES.iter().chain(naga::keywords::wgsl::RESERVED).copied().collect())
        .contains(word)
}

/// Device names Windows reserves in every folder (`con`, `nul`, `com1`, …): a folder so named
/// cannot be created there.
pub(crate) fn is_reserved_file_name(name: &str) -> bool {
    matches!(name, "con" | "prn" | "aux" | "nul")
        || (name.len() == 4
            && (name.starts_with("com") || name.starts_with("lpt"))
            && name.as_bytes()[3].is_ascii_digit()
            && name.as_bytes()[3] != b'0')
}

/// Whether `name` can name a material (files, shader functions) or a parameter (struct member).
pub(crate) fn name_problem(name: &str) -> Option<&'static str> {
    if name.is_empty() {
        return Some("a name cannot be empty");
    }
    if name.len() > 48 {
        return Some("a name has at most 48 characters");
    }
    if !name.starts_with(|c: char| c.is_ascii_lowercase()) {
        return Some("a name starts with a lowercase ASCII letter");
    }
    if !name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_') {
        return Some("a name uses only lowercase ASCII letters, digits and `_`");
    }
    if name.contains("__") {
        return Some("`__` is reserved in GLSL");
    }
    if is_reserved(name) {
        return Some("this word is reserved in WGSL, GLSL or HLSL");
    }
    if is_reserved_file_name(name) {
        return Some("this is a reserved file name on Windows, and a material's name names its output folder");
    }
    None
}
