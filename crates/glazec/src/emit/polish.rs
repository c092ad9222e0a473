//! Finishing touches on backend text, in one pass over the lines:
//!
//! * each function's doc comment (its citation) becomes `// …` lines above its definition;
//! * call results get back the names `lower` gave them. naga's backends always print a call
//!   result as `_e<index>`, ignoring `named_expressions`; inside the calling function each
//!   `_e<index>` of a call result is replaced by its name, or, where `lower` gave it none, by
//!   the name of the function called without the material's prefix (`let coat_path_curve =
//!   wet_clay_coat_path_curve(…)`, as a person names a value after what computes it), with a
//!   numeric suffix if that word is already used in the function, or reserved.
//!
//! A function definition is recognised in all three languages as a line at column 0 of the form
//! `<type-or-fn> <name>(`; its body ends at the next line that is exactly `}` (how naga's
//! backends format functions).

use std::collections::HashMap;

use naga::{Expression, Function, Module};

/// What to do for one function.
struct Edits<'m> {
    doc: Option<&'m [String]>,
    /// (expression index, wanted name) of named call results.
    results: Vec<(usize, &'m str)>,
}

/// The call results of `f` and the names they are to get: their own, else the called
/// function's without `prefix` (`<material>_`).
fn call_results<'m>(module: &'m Module, f: &'m Function, prefix: &str) -> Vec<(usize, &'m str)> {
    let mut results: Vec<(usize, &str)> = f
        .expressions
        .iter()
        .filter_map(|(h, e)| {
            let Expression::CallResult(callee) = *e else { return None };
            let own = f.named_expressions.get(&h).map(String::as_str);
            let callee = module.functions[callee].name.as_deref().map(|n| n.strip_prefix(prefix).unwrap_or(n));
            own.or(callee).filter(|n| !n.is_empty()).map(|name| (h.index(), name))
        })
        .collect();
    results.sort_unstable();
    results
}

/// The edits per printed function name. In GLSL the (single) entry point is printed as `main`.
fn edits<'m>(module: &'m Module, material: &str, glsl_entry: bool) -> HashMap<String, Edits<'m>> {
    let docs = module.doc_comments.as_deref();
    let prefix = format!("{material}_");
    let mut map = HashMap::new();
    for (handle, f) in module.functions.iter() {
        let Some(name) = &f.name else { continue };
        let doc = docs.and_then(|d| d.functions.get(&handle)).map(Vec::as_slice);
        map.insert(name.clone(), Edits { doc, results: call_results(module, f, &prefix) });
    }
    for ep in &module.entry_points {
        let name = if glsl_entry { "main".to_string() } else { ep.name.clone() };
        map.insert(name, Edits { doc: None, results: call_results(module, &ep.function, &prefix) });
    }
    map
}

/// Whether `c` can be part of an identifier in WGSL, GLSL and HLSL as naga writes them.
pub(super) fn is_ident_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The function name if `line` starts a function definition.
fn defined_function(line: &str) -> Option<&str> {
    if line.starts_with(char::is_whitespace) {
        return None;
    }
    let (_, rest) = line.split_once(' ')?;
    let end = rest.find('(')?;
    let name = &rest[..end];
    (!name.is_empty() && name.chars().all(is_ident_char)).then_some(name)
}

/// Appends `line` to `out` with every whole-word `_e<N>` found in `renames` replaced.
fn push_renamed(out: &mut String, line: &str, renames: &HashMap<usize, String>) {
    if renames.is_empty() {
        out.push_str(line);
        return;
    }
    let bytes = line.as_bytes();
    let mut copied = 0;
    for (i, _) in line.match_indices('_') {
        let starts_word = i == 0 || !is_ident_char(bytes[i - 1] as char);
        if i < copied || !starts_word || bytes.get(i + 1) != Some(&b'e') {
            continue;
        }
        let digits_end = (i + 2..bytes.len()).find(|&j| !bytes[j].is_ascii_digit()).unwrap_or(bytes.len());
        let ends_word = digits_end == bytes.len() || !is_ident_char(bytes[digits_end] as char);
        if digits_end == i + 2 || !ends_word {
            continue;
        }
        if let Some(name) = line[i + 2..digits_end].parse::<usize>().ok().and_then(|n| renames.get(&n)) {
            out.push_str(&line[copied..i]);
            out.push_str(name);
            copied = digits_end;
        }
    }
    out.push_str(&line[copied..]);
}

/// The identifiers in `body` that start with one of `prefixes` (the only ones that can collide
/// with a wanted name or its `_N` variants).
fn words_with_prefix<'t>(body: &[&'t str], prefixes: &[&str]) -> Vec<&'t str> {
    let mut found = Vec::new();
    for line in body {
        let bytes = line.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            if !is_ident_char(bytes[i] as char) {
                i += 1;
                continue;
            }
            let start = i;
            while i < bytes.len() && is_ident_char(bytes[i] as char) {
                i += 1;
            }
            let word = &line[start..i];
            if prefixes.iter().any(|p| word.starts_with(p)) {
                found.push(word);
            }
        }
    }
    found
}

/// Chooses the final names of a function's call results: the wanted name, or the first
/// `name_N` not already a word of the function and not reserved.
fn choose_names(body: &[&str], results: &[(usize, &str)]) -> HashMap<usize, String> {
    let mut prefixes: Vec<&str> = results.iter().map(|&(_, w)| w).collect();
    prefixes.sort_unstable();
    prefixes.dedup();
    let used = words_with_prefix(body, &prefixes);
    let mut renames: HashMap<usize, String> = HashMap::with_capacity(results.len());
    for &(index, wanted) in results {
        let mut chosen = wanted.to_string();
        let mut n = 1;
        while used.contains(&chosen.as_str())
            || renames.values().any(|c| *c == chosen)
            || crate::names::is_reserved(&chosen)
        {
            chosen = format!("{wanted}_{n}");
            n += 1;
        }
        renames.insert(index, chosen);
    }
    renames
}

/// Appends the polished `text` (of material `material`'s `module`) to `out`.
pub fn polish(module: &Module, material: &str, text: &str, glsl_entry: bool, out: &mut String) {
    let edits = edits(module, material, glsl_entry);
    let lines: Vec<&str> = text.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let Some(edit) = defined_function(lines[i]).and_then(|name| edits.get(name)) else {
            out.push_str(lines[i]);
            out.push('\n');
            i += 1;
            continue;
        };
        for doc in edit.doc.unwrap_or_default() {
            out.push_str(if doc.is_empty() { "//" } else { "// " });
            out.push_str(doc);
            out.push('\n');
        }
        let end = lines[i..].iter().position(|l| *l == "}").map_or(lines.len(), |e| i + e + 1);
        let renames =
            if edit.results.is_empty() { HashMap::new() } else { choose_names(&lines[i..end], &edit.results) };
        for line in &lines[i..end] {
            push_renamed(out, line, &renames);
            out.push('\n');
        }
        i = end;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renames_whole_words_only() {
        let renames = HashMap::from([(1, "d".to_string())]);
        let mut out = String::new();
        push_renamed(&mut out, "let _e1 = f(_e12, _e1);", &renames);
        assert_eq!(out, "let d = f(_e12, d);");
        out.clear();
        push_renamed(&mut out, "x_e1 + _e1x", &renames);
        assert_eq!(out, "x_e1 + _e1x");
    }

    #[test]
    fn recognises_definitions_in_every_language() {
        assert_eq!(defined_function("fn d_ggx(n_dot_h: f32) -> f32 {"), Some("d_ggx"));
        assert_eq!(defined_function("float3 f_schlick(float3 f0_, float c)"), Some("f_schlick"));
        assert_eq!(defined_function("    let x = d_ggx(a);"), None);
        assert_eq!(defined_function("struct Foo {"), None);
    }

    #[test]
    fn avoids_names_in_use() {
        let renames = choose_names(&["fn f(d: f32) {", "  let _e3 = g(d);", "}"], &[(3, "d")]);
        assert_eq!(renames[&3], "d_1");
    }
}
