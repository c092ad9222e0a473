//! Harnesses shared by the fuzz targets (`fuzz/`, cargo-fuzz) and the tests that replay their
//! corpus and run the same checks under proptest.
//!
//! Each harness panics exactly when glazec misbehaves: a panic inside glazec, a diagnostic whose
//! span lies outside the text or off a character boundary, an empty error list, IR that naga
//! rejects, or a validated module that a backend cannot emit.

use glazec::diag::Diagnostic;
use glazec::{CompileError, Target};

/// The shipped materials, the seeds of [`mutate_shipped`].
pub const SHIPPED: &[&str] = &[
    include_str!("../../../materials/car_paint.ron"),
    include_str!("../../../materials/clay.ron"),
    include_str!("../../../materials/coated_gold.ron"),
    include_str!("../../../materials/color_clay.ron"),
    include_str!("../../../materials/cork_clay.ron"),
    include_str!("../../../materials/disney_clay.ron"),
    include_str!("../../../materials/four_layer.ron"),
    include_str!("../../../materials/lacquered_wood.ron"),
    include_str!("../../../materials/mud_clay.ron"),
    include_str!("../../../materials/paper_clay.ron"),
    include_str!("../../../materials/red_plastic.ron"),
    include_str!("../../../materials/tunable_glaze.ron"),
    include_str!("../../../materials/wet_clay.ron"),
];

/// Examples outside `materials/` that [`mutate_shipped`] also starts from: the one that reads
/// textures and normal maps.
pub const EXAMPLES: &[&str] = &[include_str!("../../../examples/textures/textured_clay.ron")];

/// Parses and checks `text` as a material and as a scene.
///
/// # Panics
/// When a diagnostic is malformed (see the module docs).
pub fn parse_and_check(text: &str) {
    if let Err(diagnostics) = glazec::load(text) {
        assert_well_formed(text, &diagnostics);
    }
    if let Ok(value) = glazec::parse::parse(text) {
        if let Err(diagnostics) = glazec::check::check_scene(&value) {
            assert_well_formed(text, &diagnostics);
        }
    }
}

/// Compiles `text` and emits every target.
///
/// # Panics
/// When glazec misbehaves (see the module docs).
pub fn whole_pipeline(text: &str) {
    match glazec::compile_source(Some("fuzz.ron"), text) {
        Ok(compiled) => {
            let targets = [Target::Wgsl, Target::Glsl, Target::Hlsl, Target::Spv];
            if let Err(e) = compiled.emit(&targets) {
                panic!("a validated module did not emit: {e}\n{text}");
            }
        }
        Err(CompileError::Diagnostics(diagnostics)) => assert_well_formed(text, &diagnostics),
        Err(CompileError::Internal(e)) => panic!("naga rejected the lowered IR: {e}\n{text}"),
    }
}

/// Every failure has at least one diagnostic, and every label lies inside the text on character
/// boundaries.
pub fn assert_well_formed(text: &str, diagnostics: &[Diagnostic]) {
    assert!(!diagnostics.is_empty(), "an error without diagnostics:\n{text}");
    for d in diagnostics {
        assert!(!d.labels.is_empty(), "{}: a diagnostic without a label", d.code);
        for label in &d.labels {
            let (start, end) = (label.span.start as usize, label.span.end as usize);
            assert!(
                start <= end && end <= text.len() && text.is_char_boundary(start) && text.is_char_boundary(end),
                "{}: span {start}..{end} outside the text ({} bytes) or off a character boundary",
                d.code,
                text.len()
            );
        }
    }
}

/// Values that stress number handling: zero and negative zero, the ends of f32, subnormals,
/// non-finite spellings, out-of-range reflectances and roughnesses.
const EXTREME_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "1e38",
    "3.4028235e38",
    "3.5e38",
    "1e400",
    "-1e400",
    "1e-45",
    "1e-40",
    "NaN",
    "inf",
    "-inf",
    "16777217",
    "0.9999999",
    "1.0000001",
    "1e-7",
    "99999999999999999999",
];

/// A shipped material or example ([`SHIPPED`], [`EXAMPLES`]) chosen by `data[0]`, changed by the rest of `data`, two bytes per change.
pub fn mutate_shipped(data: &[u8]) -> String {
    let Some((&pick, rest)) = data.split_first() else { return SHIPPED[0].to_string() };
    let pick = pick as usize % (SHIPPED.len() + EXAMPLES.len());
    let mut text = SHIPPED.get(pick).unwrap_or_else(|| &EXAMPLES[pick - SHIPPED.len()]).to_string();
    for pair in rest.chunks(2) {
        let (op, arg) = (pair[0], pair.get(1).copied().unwrap_or(0) as usize);
        match op % 7 {
            0 => replace_number(&mut text, arg, EXTREME_NUMBERS[arg % EXTREME_NUMBERS.len()]),
            1 => delete_token(&mut text, arg),
            2 => duplicate_first_coat(&mut text, 1 + arg % 8),
            3 => deepen(&mut text, arg),
            4 => insert_byte(&mut text, arg, op),
            5 => truncate(&mut text, arg),
            _ => swap_identifier(&mut text, arg),
        }
    }
    text
}

/// Byte ranges of number tokens.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts =
            bytes[i].is_ascii_digit() && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
        if starts {
            let start = if i > 0 && bytes[i - 1] == b'-' { i - 1 } else { i };
            let mut end = i;
            while end < bytes.len() && (bytes[end].is_ascii_digit() || matches!(bytes[end], b'.' | b'e' | b'E')) {
                end += 1;
            }
            out.push((start, end));
            i = end;
        } else {
            i += 1;
        }
    }
    out
}

fn replace_number(text: &mut String, which: usize, with: &str) {
    let found = numbers(text);
    if let Some(&(start, end)) = found.get(which % found.len().max(1)) {
        text.replace_range(start..end, with);
    }
}

/// Token boundaries: runs of identifier characters, or single punctuation characters.
fn tokens(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices() {
        let word = c.is_alphanumeric() || c == '_' || c == '.';
        match (word, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push((s, i));
                start = None;
            }
            _ => {}
        }
        if !word && !c.is_whitespace() {
            out.push((i, i + c.len_utf8()));
        }
    }
    if let Some(s) = start {
        out.push((s, text.len()));
    }
    out
}

fn delete_token(text: &mut String, which: usize) {
    let found = tokens(text);
    if let Some(&(start, end)) = found.get(which % found.len().max(1)) {
        text.replace_range(start..end, "");
    }
}

/// Repeats the first `Coat(…)` (balanced parentheses) `times` more times: deep stacks, and past
/// the layer limit.
fn duplicate_first_coat(text: &mut String, times: usize) {
    let Some(start) = text.find("Coat(") else { return };
    let mut depth = 0;
    let mut end = None;
    for (i, c) in text[start..].char_indices() {
        match c {
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    end = Some(start + i + 1);
                    break;
                }
            }
            _ => {}
        }
    }
    let Some(end) = end else { return };
    let coat = format!("{}, ", &text[start..end]);
    text.insert_str(start, &coat.repeat(times * 3));
}

/// Wraps a number in up to 100 list brackets (past the nesting limit at 64).
fn deepen(text: &mut String, arg: usize) {
    let found = numbers(text);
    if let Some(&(start, end)) = found.get(arg % found.len().max(1)) {
        let depth = arg % 101;
        let wrapped = format!("{}{}{}", "[".repeat(depth), &text[start..end], "]".repeat(depth));
        text.replace_range(start..end, &wrapped);
    }
}

fn insert_byte(text: &mut String, at: usize, byte: u8) {
    let mut at = at * 7 % (text.len() + 1);
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    const BYTES: &[u8] = b"(){}[],:\"\\/*0e-_#r\n\t\x00";
    let c = char::from(BYTES[byte as usize % BYTES.len()]);
    text.insert(at, c);
}

fn truncate(text: &mut String, at: usize) {
    let mut at = at * 11 % (text.len() + 1);
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    text.truncate(at);
}

/// Replaces an identifier by a near miss, a reserved word or a long name.
fn swap_identifier(text: &mut String, which: usize) {
    const SWAPS: &[&str] = &["Lambrt", "coat", "Ggx2", "main", "Param", "Measured", "Smooth", "x", "Eon", "Conductor"];
    let found: Vec<(usize, usize)> =
        tokens(text).into_iter().filter(|&(s, e)| text[s..e].starts_with(|c: char| c.is_ascii_alphabetic())).collect();
    if let Some(&(start, end)) = found.get(which % found.len().max(1)) {
        text.replace_range(start..end, SWAPS[which % SWAPS.len()]);
    }
}
