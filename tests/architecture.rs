//! The layout stays what docs/architecture.md describes: within each crate no module imports
//! another that imports it back (directly or around a longer loop), and no source file grows
//! past [`MAX_LINES`] unless it is listed in [`LONG_FILES`] with the reason it is one concern.
//!
//! Dependencies are read from the source text: every path in a `use` item and every
//! `crate::…`/`super::…`/`self::…`/`module::…` path in code, resolved to the longest module
//! prefix. A parent's `pub use` of its children (its facade) and `mod` declarations are not
//! dependencies; unit tests (`#[cfg(test)] mod tests`) are left out.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The longest a source file may be without a reason.
const MAX_LINES: usize = 700;

/// Files allowed to be longer, each with why it is one concern.
const LONG_FILES: &[(&str, &str)] = &[(
    "crates/glazec/src/lower/builder/values.rs",
    "the builder's folding value types and their Real/Vector/Logic impls: one impl per op",
)];

/// The source roots checked: each crate's `src/`.
const ROOTS: &[&str] = &[
    "crates/glazec/src",
    "crates/glazec-gpu/src",
    "crates/glazec-lab/src",
    "crates/glazec-web/src",
    "crates/glazec_bevy/src",
    "crates/glazec_bevy/scene/src",
    "src",
];

type Module = Vec<String>;

/// Every `.rs` file under `root` by module path (`lib.rs`, `main.rs` and `mod.rs` name their
/// folder's module).
fn modules(root: &Path) -> BTreeMap<Module, PathBuf> {
    common::files_under(root)
        .into_iter()
        .filter(|path| path.extension().is_some_and(|e| e == "rs"))
        .map(|path| {
            let relative = path.strip_prefix(root).expect("under the root").with_extension("");
            let mut parts: Module = relative.iter().map(|p| p.to_string_lossy().into_owned()).collect();
            if matches!(parts.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                parts.pop();
            }
            (parts, path)
        })
        .collect()
}

/// The text with comments, string and char literals, unit tests, visibility paths and
/// re-exports removed: what is left names dependencies.
fn code_of(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' && chars.get(i + 2) == Some(&'\'') {
            i += 3;
        } else if c == '\'' && next == Some('\\') {
            i += 2;
            while i < chars.len() && chars[i] != '\'' {
                i += 1;
            }
            i += 1;
        } else {
            out.push(c);
            i += 1;
        }
    }
    let out = match out.find("#[cfg(test)]\nmod tests") {
        Some(at) => out[..at].to_string(),
        None => out,
    };
    let mut kept = String::new();
    let mut rest = out.as_str();
    // `pub use …;` (a facade) and `pub(in …)` (a visibility) are not dependencies.
    while let Some(at) = rest.find("pub") {
        kept.push_str(&rest[..at]);
        let tail = &rest[at..];
        if let Some(after) = tail.strip_prefix("pub use ").or_else(|| tail.strip_prefix("pub(crate) use ")) {
            rest = after.find(';').map_or("", |end| &after[end + 1..]);
        } else if tail.starts_with("pub(in ") {
            rest = tail.find(')').map_or("", |end| &tail[end + 1..]);
        } else {
            kept.push_str("pub");
            rest = &tail[3..];
        }
    }
    kept.push_str(rest);
    kept
}

/// The paths a `use` tree names: `a::{b, c::{d, e}}` → `a::b`, `a::c::d`, `a::c::e`.
fn expand(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else { return vec![tree.split(" as ").next().unwrap_or(tree).trim().into()] };
    let prefix = &tree[..open];
    let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .flat_map(|p| {
            if p == "self" { vec![prefix.trim_end_matches(':').to_string()] } else { expand(&format!("{prefix}{p}")) }
        })
        .collect()
}

/// Every `a::b::c` path in `code` (identifiers joined by `::`).
fn inline_paths(code: &str) -> Vec<String> {
    let mut paths = Vec::new();
    let bytes = code.as_bytes();
    let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let mut i = 0;
    while i < bytes.len() {
        if ident(bytes[i]) && (i == 0 || !(ident(bytes[i - 1]) || bytes[i - 1] == b':')) {
            let start = i;
            let mut end = i;
            loop {
                while end < bytes.len() && ident(bytes[end]) {
                    end += 1;
                }
                if code[end..].starts_with("::") && bytes.get(end + 2).is_some_and(|&b| ident(b)) {
                    end += 2;
                } else {
                    break;
                }
            }
            if code[start..end].contains("::") {
                paths.push(code[start..end].to_string());
            }
            i = end.max(i + 1);
        } else {
            i += 1;
        }
    }
    paths
}

/// The module a path in module `current` refers to (its longest module prefix), if any.
fn resolve(current: &Module, path: &str, all: &BTreeMap<Module, PathBuf>) -> Option<Module> {
    let mut segments: Vec<&str> = path.split("::").map(str::trim).collect();
    let mut base: Module = match segments.first().copied() {
        Some("crate") => {
            segments.remove(0);
            Vec::new()
        }
        Some("super") => {
            let mut base = current.clone();
            while segments.first() == Some(&"super") {
                base.pop();
                segments.remove(0);
            }
            base
        }
        Some("self") => {
            segments.remove(0);
            current.clone()
        }
        Some(first) => {
            let mut child = current.clone();
            child.push(first.to_string());
            if !all.contains_key(&child) {
                return None;
            }
            current.clone()
        }
        None => return None,
    };
    let mut best = all.contains_key(&base).then(|| base.clone());
    for s in segments {
        base.push(s.to_string());
        if all.contains_key(&base) {
            best = Some(base.clone());
        }
    }
    best
}

/// Each module's dependencies on other modules of the same crate.
fn graph(root: &Path) -> BTreeMap<Module, BTreeSet<Module>> {
    let all = modules(root);
    let mut edges = BTreeMap::new();
    for (module, file) in &all {
        let code = code_of(&std::fs::read_to_string(file).expect("readable source"));
        let mut paths = inline_paths(&code);
        let mut rest = code.as_str();
        while let Some(at) = rest.find("use ") {
            let before_ok = at == 0 || !rest.as_bytes()[at - 1].is_ascii_alphanumeric();
            let tail = &rest[at + 4..];
            let end = tail.find(';').unwrap_or(tail.len());
            if before_ok {
                paths.extend(expand(&tail[..end].split_whitespace().collect::<Vec<_>>().join(" ")));
            }
            rest = &tail[end.min(tail.len())..];
        }
        let targets: BTreeSet<Module> =
            paths.iter().filter_map(|p| resolve(module, p, &all)).filter(|target| target != module).collect();
        edges.insert(module.clone(), targets);
    }
    edges
}

/// The strongly connected components with more than one module (Tarjan).
fn cycles(graph: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    struct State<'g> {
        graph: &'g BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'g Module, usize>,
        low: BTreeMap<&'g Module, usize>,
        stack: Vec<&'g Module>,
        on_stack: BTreeSet<&'g Module>,
        found: Vec<Vec<Module>>,
    }
    fn visit<'g>(s: &mut State<'g>, v: &'g Module) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.graph.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[w].min(s.low[v]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.index[w].min(s.low[v]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.clone());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                s.found.push(component);
            }
        }
    }
    let mut state = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !state.index.contains_key(v) {
            visit(&mut state, v);
        }
    }
    state.found
}

fn name(module: &Module) -> String {
    if module.is_empty() { "(root)".into() } else { module.join("::") }
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let mut loops = Vec::new();
    for root in ROOTS {
        let graph = graph(&common::root().join(root));
        assert!(!graph.is_empty(), "{root}: no modules found");
        for component in cycles(&graph) {
            let members: BTreeSet<&Module> = component.iter().collect();
            let edges: Vec<String> = component
                .iter()
                .flat_map(|a| graph[a].iter().filter(|b| members.contains(b)).map(move |b| (a, b)))
                .map(|(a, b)| format!("{} -> {}", name(a), name(b)))
                .collect();
            loops.push(format!("{root}: {}", edges.join(", ")));
        }
    }
    assert!(loops.is_empty(), "import loops:\n{}", loops.join("\n"));
}

#[test]
fn the_checker_sees_a_loop() {
    // Two modules that name each other, as the test above would see them in a crate.
    let all: BTreeMap<Module, PathBuf> =
        [vec![], vec!["a".to_string()], vec!["b".to_string()]].into_iter().map(|m| (m, PathBuf::new())).collect();
    let a = vec!["a".to_string()];
    let b = vec!["b".to_string()];
    assert_eq!(resolve(&a, "super::b::Thing", &all), Some(b.clone()));
    assert_eq!(resolve(&b, "crate::a::{self, Other}", &all), Some(a.clone()));
    let graph: BTreeMap<Module, BTreeSet<Module>> =
        [(a.clone(), BTreeSet::from([b.clone()])), (b.clone(), BTreeSet::from([a.clone()])), (vec![], BTreeSet::new())]
            .into_iter()
            .collect();
    assert_eq!(cycles(&graph).len(), 1);
    assert_eq!(expand("x::{y, z::{p, q as r}}"), ["x::y", "x::z::p", "x::z::q"]);
    assert_eq!(code_of("pub use a::b;\nuse c::d; // e::f\nlet s = \"g::h\";"), "\nuse c::d; \nlet s = \"\";");
}

#[test]
fn no_source_file_is_longer_than_the_limit_without_a_reason() {
    let mut long = Vec::new();
    for root in ROOTS.iter().chain(&["tests"]) {
        for (_, file) in modules(&common::root().join(root)) {
            let lines = std::fs::read_to_string(&file).expect("readable").lines().count();
            let relative = file.strip_prefix(common::root()).expect("in the project").to_string_lossy().into_owned();
            let allowed = LONG_FILES.iter().any(|(path, _)| *path == relative);
            if lines > MAX_LINES && !allowed {
                long.push(format!("{relative}: {lines} lines"));
            }
        }
    }
    assert!(
        long.is_empty(),
        "files over {MAX_LINES} lines (split them, or list them with a reason):\n{}",
        long.join("\n")
    );
}
