//! The top-level items of text that naga's WGSL, GLSL and HLSL backends wrote, and what glazec
//! does with them: the harness file keeps the items the library does not define, and a GLSL or
//! HLSL library guards the items that are not the material's own (naga's helpers, such as
//! `naga_f2u32` or HLSL's sampler heap, written identically by every library) so that two
//! libraries can be included into one shader.
//!
//! An item is what naga writes at column 0: a declaration line and, for a struct, function or
//! block, the lines up to its closing brace at depth 0; `@…` attribute lines and `//` comment
//! lines at column 0 belong to the declaration that follows them, and blank lines end an item.

use super::polish::is_ident_char;

/// One top-level item.
pub(super) struct Item<'t> {
    /// The name it declares (`None` for a preprocessor line or anything unrecognised).
    pub name: Option<&'t str>,
    /// Its lines, without the line ends.
    pub lines: Vec<&'t str>,
    /// Whether a blank line followed it (kept when the item is written again).
    pub spaced: bool,
}

/// Splits backend text into its items, in order. Blank lines between items are dropped.
pub(super) fn items(text: &str) -> Vec<Item<'_>> {
    let mut out: Vec<Item<'_>> = Vec::new();
    let mut current: Vec<&str> = Vec::new();
    let mut declared = false;
    let mut depth: i32 = 0;
    fn flush<'t>(current: &mut Vec<&'t str>, out: &mut Vec<Item<'t>>) {
        if !current.is_empty() {
            let lines = std::mem::take(current);
            let name = lines.iter().find(|l| !is_prefix_line(l)).and_then(|l| declared_name(l));
            out.push(Item { name, lines, spaced: false });
        }
    }
    for line in text.lines() {
        if depth == 0 {
            if line.trim().is_empty() {
                flush(&mut current, &mut out);
                if let Some(last) = out.last_mut() {
                    last.spaced = true;
                }
                declared = false;
                continue;
            }
            // (HLSL opens a function's body on the line after its signature.)
            let starts = !line.starts_with(char::is_whitespace) && !line.starts_with(['{', '}']);
            if starts && declared {
                flush(&mut current, &mut out);
                declared = false;
            }
            if !is_prefix_line(line) {
                declared = true;
            }
        }
        for b in line.bytes() {
            match b {
                b'{' => depth += 1,
                b'}' => depth -= 1,
                _ => {}
            }
        }
        current.push(line);
    }
    flush(&mut current, &mut out);
    out
}

/// A line that belongs to the declaration after it: an attribute (`@group(0) @binding(1)`) or a
/// comment.
fn is_prefix_line(line: &str) -> bool {
    line.starts_with('@') || line.starts_with("//")
}

/// The name a declaration line declares: the word after `struct`, `cbuffer`'s or a GLSL block's
/// name, or the last word before the first `(`, `:`, `=`, `[` or `;`.
fn declared_name(line: &str) -> Option<&str> {
    let word = |s: &str| -> Option<usize> { s.find(|c: char| !is_ident_char(c)).or(Some(s.len())) };
    if line.starts_with('#') {
        return None;
    }
    // GLSL: `layout(…) uniform <block> { … };` or `layout(…) uniform sampler2D <name>;`.
    let line = match line.strip_prefix("layout(") {
        Some(rest) => rest.split_once(')').map_or(rest, |(_, declaration)| declaration.trim_start()),
        None => line,
    };
    let block = line.starts_with("uniform ") && line.contains('{');
    for keyword in ["struct ", "cbuffer ", "uniform "] {
        if let Some(at) = line.find(keyword).filter(|_| keyword != "uniform " || block) {
            let rest = &line[at + keyword.len()..];
            let rest = rest.trim_start();
            let end = word(rest)?;
            return (end > 0).then(|| &rest[..end]);
        }
    }
    let end = line.find(['(', ':', '=', '[', ';'])?;
    let before = line[..end].trim_end();
    let start = before.rfind(|c: char| !is_ident_char(c)).map_or(0, |i| i + 1);
    let name = &before[start..];
    (!name.is_empty()).then_some(name)
}

/// Appends `item`'s lines to `out`, then a blank line if one followed it.
pub(super) fn push(out: &mut String, item: &Item<'_>) {
    for line in &item.lines {
        out.push_str(line);
        out.push('\n');
    }
    if item.spaced {
        out.push('\n');
    }
}

/// Appends `item`, inside an include guard named after it when it is not the material's own
/// (its name does not start with one of `own`): `#ifndef GLAZEC_<NAME>` … `#endif`, so that a
/// second library that writes the same helper skips it.
pub(super) fn push_guarded(out: &mut String, item: &Item<'_>, own: &[&str]) {
    match item.name.filter(|n| !own.iter().any(|p| n.starts_with(p))) {
        Some(name) => {
            let guard = format!("GLAZEC_{}", name.to_ascii_uppercase());
            out.push_str(&format!("#ifndef {guard}\n#define {guard}\n"));
            for line in &item.lines {
                out.push_str(line);
                out.push('\n');
            }
            out.push_str("#endif\n");
            if item.spaced {
                out.push('\n');
            }
        }
        None => push(out, item),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_declarations_in_every_language() {
        for (line, name) in [
            ("struct WetClayParams {", "WetClayParams"),
            ("const wet_clay_tau: vec3<f32> = vec3<f32>(0.3f);", "wet_clay_tau"),
            ("var<storage, read_write> values: array<vec4<f32>>;", "values"),
            ("fn wet_clay_d_ggx(cos_h: f32) -> f32 {", "wet_clay_d_ggx"),
            ("static const float3 wet_clay_tau = float3(0.3, 0.3, 0.3);", "wet_clay_tau"),
            ("cbuffer wet_clay_tables : register(b3) { uint4 wet_clay_tables[4087]; }", "wet_clay_tables"),
            ("SamplerState nagaSamplerHeap[2048]: register(s0, space0);", "nagaSamplerHeap"),
            ("float3 wet_clay_brdf(float3 n, float3 v, float3 l)", "wet_clay_brdf"),
            ("layout(std140, binding = 3) uniform Block_0 { uvec4 x[4]; };", "Block_0"),
            ("const vec3 wet_clay_tau = vec3(0.3);", "wet_clay_tau"),
            ("layout(binding = 33) uniform sampler2D wet_clay_radiance;", "wet_clay_radiance"),
        ] {
            assert_eq!(declared_name(line), Some(name), "{line}");
        }
    }

    #[test]
    fn keeps_an_hlsl_body_with_its_signature() {
        let text = "float f(float x)\n{\n    return x;\n}\n\nfloat g()\n{\n    return 1.0;\n}\n";
        let found = items(text);
        assert_eq!(found.iter().map(|i| i.name).collect::<Vec<_>>(), [Some("f"), Some("g")]);
        assert_eq!(found[0].lines.len(), 4);
    }

    #[test]
    fn splits_items_with_their_attributes_and_comments() {
        let text = "struct A {\n    x: f32,\n}\n\nconst b: f32 = 1f;\nconst c: f32 = 2f;\n\n@group(0) @binding(1) \nvar<uniform> d: A;\n\n// Cited.\nfn e() -> f32 {\n    return 1f;\n}\n";
        let names: Vec<_> = items(text).iter().map(|i| i.name).collect();
        assert_eq!(names, [Some("A"), Some("b"), Some("c"), Some("d"), Some("e")]);
        assert_eq!(items(text)[4].lines.len(), 4);
    }
}
