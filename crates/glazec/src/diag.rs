//! Diagnostics: spans, codes, and the one place that renders them.
//!
//! Every user-facing problem — a syntax error in the RON text, a roughness outside `[0, 1]`,
//! two runtime parameters that share a name but not a type — becomes a [`Diagnostic`]: a code
//! (`E0206`), a lowercase message, one primary [`Label`] on the offending value's byte span,
//! optional secondary labels that say *why* ("first declared here"), and notes (`help: …`).
//! Diagnostics are plain data; rendering is a function of them. This file is the only one that
//! talks to `codespan-reporting`, so a version bump of that crate touches one place.
//!
//! Codes are stable and grouped by stage: `E01xx` syntax (parse), `E02xx` semantics (check),
//! `E03xx` scenes (check and simplify), `E04xx` measured optics; `N04xx` are notes.
//! The full list, with one line each, is [`Code`].

use std::fmt;
use std::ops::Range;

use codespan_reporting::diagnostic as cs;
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term;
use serde::Serialize;

/// A half-open byte range `start..end` into one source file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct Span {
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(start: usize, end: usize) -> Span {
        Span { start: start as u32, end: end as u32 }
    }

    /// The smallest span that covers both.
    pub fn to(self, other: Span) -> Span {
        Span { start: self.start.min(other.start), end: self.end.max(other.end) }
    }

    pub fn range(self) -> Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// A value together with the span of source text it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Spanned<T> {
    pub node: T,
    pub span: Span,
}

impl<T> Spanned<T> {
    pub fn new(node: T, span: Span) -> Self {
        Spanned { node, span }
    }
}

macro_rules! codes {
    ($( $(#[$doc:meta])* $name:ident = $text:literal, )*) => {
        /// Stable diagnostic codes. `E01xx`: syntax; `E02xx`: material semantics.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Code { $( $(#[$doc])* $name, )* }
        impl Code {
            /// The code as printed, e.g. `E0206`.
            pub fn as_str(self) -> &'static str {
                match self { $( Code::$name => $text, )* }
            }
            /// Every code, in numeric order (used by docs/diagnostics.md's table and its test).
            pub const ALL: &'static [Code] = &[ $( Code::$name, )* ];
        }
    };
}

codes! {
    /// A character that cannot start any RON token.
    UnexpectedChar = "E0101",
    /// A token where another was expected (`expected `,` or `)`, found `:``).
    UnexpectedToken = "E0102",
    /// The file ended inside a value, string or comment.
    UnexpectedEof = "E0103",
    /// A string literal with no closing quote, or an invalid escape.
    BadString = "E0104",
    /// A number literal that does not parse.
    BadNumber = "E0105",
    /// Text after the material's closing parenthesis.
    TrailingInput = "E0106",
    /// Values nested deeper than the parser allows.
    TooDeep = "E0107",
    /// A source larger than `parse::MAX_SOURCE_BYTES`.
    FileTooLarge = "E0108",
    /// A field name that the constructor does not have.
    UnknownField = "E0201",
    /// A required field is absent.
    MissingField = "E0202",
    /// The same field given twice.
    DuplicateField = "E0203",
    /// A value of the wrong shape (a string where a number belongs, …).
    WrongType = "E0204",
    /// An unknown method, lobe or base name.
    UnknownVariant = "E0205",
    /// A roughness outside `[0, 1]`.
    RoughnessRange = "E0206",
    /// An index of refraction (or a conductor's η) that is not above zero.
    IorRange = "E0207",
    /// A negative absorption, thickness or extinction coefficient.
    NegativeMedium = "E0208",
    /// A layer stack with no layers.
    EmptyStack = "E0209",
    /// The opaque base is not the last layer, or the last layer is not a base.
    BaseNotLast = "E0210",
    /// Two runtime parameters with one name but different types or defaults.
    ParamConflict = "E0211",
    /// A material or parameter name that is not a valid identifier and file name.
    BadName = "E0212",
    /// An albedo or reflectance (F0) outside `[0, 1]`.
    AlbedoRange = "E0213",
    /// Positional and named arguments mixed, or too many positional arguments.
    BadArguments = "E0214",
    /// A conductor given both, or neither, of `f0` and `eta`/`k`.
    ConductorFresnel = "E0215",
    /// More coat layers than the compiler supports.
    TooManyLayers = "E0216",
    /// A number that is NaN, infinite, or too large for 32-bit floats.
    NotFinite = "E0217",
    /// Two input files declare materials with the same name (their outputs would collide).
    DuplicateMaterial = "E0218",
    /// More runtime parameters than `model::MAX_PARAMS`.
    TooManyParams = "E0219",
    /// More textures than `model::MAX_TEXTURES`.
    TooManyTextures = "E0220",
    /// A texture read without the `range` its slot needs, or with a `uv_scale` that is not a
    /// positive number.
    TextureRange = "E0221",
    /// The tables the shader looks up at runtime exceed the uniform binding they live in
    /// (`lower::builder::MAX_UNIFORM_BYTES`).
    TableBudget = "E0222",
    /// A scene's number outside its range (angle, tolerance, exposure, light, distance).
    SceneRange = "E0301",
    /// `Range(lo, hi)` with lo > hi.
    RangeOrder = "E0302",
    /// A scene sets a parameter that the material does not have.
    UnknownSceneParam = "E0303",
    /// A scene gives an RGB value for a scalar parameter, or the reverse.
    SceneParamType = "E0304",
    /// A scene gives a parameter a value that the material's slots would refuse as a literal.
    SceneParamRange = "E0305",
    /// `Measured` with one reflectance and nothing that fixes the second unknown.
    SingleReflectance = "E0401",
    /// `Measured` readings that no layer produces (white below black, out of range, …).
    ImpossibleMeasurement = "E0402",
    /// A note with the optical coefficients `Measured` derived (not an error).
    DerivedOptics = "N0401",
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
    /// Information (derived values); never fails a build.
    Note,
}

/// A span with a message. The primary label marks the offending value; secondary labels say why.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub span: Span,
    pub message: String,
    pub primary: bool,
}

/// One problem found in one source file.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    pub code: Code,
    pub message: String,
    pub labels: Vec<Label>,
    /// Help lines (`help: …`) and notes, rendered below the source excerpt.
    pub notes: Vec<String>,
}

impl Diagnostic {
    /// An error with a primary label on `span`.
    pub fn error(code: Code, message: impl Into<String>, span: Span, label: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            code,
            message: message.into(),
            labels: vec![Label { span, message: label.into(), primary: true }],
            notes: Vec::new(),
        }
    }

    /// Adds a `help:` line.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.notes.push(format!("help: {}", help.into()));
        self
    }

    /// Adds a secondary label ("first declared here").
    pub fn with_secondary(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label { span, message: message.into(), primary: false });
        self
    }

    /// The primary label's span (every diagnostic has one).
    pub fn primary_span(&self) -> Span {
        self.labels.iter().find(|l| l.primary).map(|l| l.span).unwrap_or_default()
    }

    fn to_codespan(&self) -> cs::Diagnostic<()> {
        let severity = match self.severity {
            Severity::Error => cs::Severity::Error,
            Severity::Warning => cs::Severity::Warning,
            Severity::Note => cs::Severity::Note,
        };
        cs::Diagnostic::new(severity)
            .with_code(self.code.as_str())
            .with_message(&self.message)
            .with_labels(
                self.labels
                    .iter()
                    .map(|l| {
                        let label = if l.primary {
                            cs::Label::primary((), l.span.range())
                        } else {
                            cs::Label::secondary((), l.span.range())
                        };
                        label.with_message(&l.message)
                    })
                    .collect(),
            )
            .with_notes(self.notes.clone())
    }
}

/// A source file as diagnostics see it: the name to print and the text that spans index.
#[derive(Clone, Copy, Debug)]
pub struct Source<'a> {
    pub name: &'a str,
    pub text: &'a str,
}

impl Source<'_> {
    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, byte: u32) -> (usize, usize) {
        let byte = (byte as usize).min(self.text.len());
        let before = &self.text[..floor_char_boundary(self.text, byte)];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        (line, column)
    }
}

fn floor_char_boundary(text: &str, mut byte: usize) -> usize {
    while !text.is_char_boundary(byte) {
        byte -= 1;
    }
    byte
}

/// How the CLI prints diagnostics.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// codespan-reporting's rich terminal rendering.
    Human { color: bool },
    /// One JSON object per diagnostic per line (for editors and CI).
    Json,
}

/// Renders diagnostics as human-readable text without colour (what the golden tests compare).
pub fn render_plain(source: Source<'_>, diagnostics: &[Diagnostic]) -> String {
    let file = SimpleFile::new(source.name, source.text);
    let config = term::Config::default();
    let mut out = String::new();
    for d in diagnostics {
        // Rendering into a String can only fail if a span lies outside the file, which would be
        // a bug in the parser; fall back to the bare message rather than lose the diagnostic.
        match term::emit_into_string(&config, &file, &d.to_codespan()) {
            Ok(text) => out.push_str(&text),
            Err(_) => out.push_str(&format!("error[{}]: {}\n", d.code, d.message)),
        }
    }
    out
}

/// Writes diagnostics to a terminal-like stream in the requested format.
pub fn emit(
    out: &mut dyn term::termcolor::WriteColor,
    source: Source<'_>,
    diagnostics: &[Diagnostic],
    format: Format,
) -> std::io::Result<()> {
    match format {
        Format::Json => {
            for d in diagnostics {
                writeln!(out, "{}", to_json(source, d))?;
            }
        }
        Format::Human { color } => {
            if !color {
                write!(out, "{}", render_plain(source, diagnostics))?;
                return Ok(());
            }
            let file = SimpleFile::new(source.name, source.text);
            let config = term::Config::default();
            for d in diagnostics {
                term::emit_to_write_style(out, &config, &file, &d.to_codespan()).map_err(std::io::Error::other)?;
            }
        }
    }
    Ok(())
}

#[derive(Serialize)]
struct JsonPosition {
    line: usize,
    column: usize,
}

#[derive(Serialize)]
struct JsonLabel<'a> {
    primary: bool,
    message: &'a str,
    byte_start: u32,
    byte_end: u32,
    start: JsonPosition,
    end: JsonPosition,
}

#[derive(Serialize)]
struct JsonDiagnostic<'a> {
    file: &'a str,
    severity: Severity,
    code: &'static str,
    message: &'a str,
    line: usize,
    column: usize,
    labels: Vec<JsonLabel<'a>>,
    notes: &'a [String],
}

/// One diagnostic as a single-line JSON object (`--message-format json`).
pub fn to_json(source: Source<'_>, d: &Diagnostic) -> String {
    let position = |byte| {
        let (line, column) = source.line_col(byte);
        JsonPosition { line, column }
    };
    let (line, column) = source.line_col(d.primary_span().start);
    let json = JsonDiagnostic {
        file: source.name,
        severity: d.severity,
        code: d.code.as_str(),
        message: &d.message,
        line,
        column,
        labels: d
            .labels
            .iter()
            .map(|l| JsonLabel {
                primary: l.primary,
                message: &l.message,
                byte_start: l.span.start,
                byte_end: l.span.end,
                start: position(l.span.start),
                end: position(l.span.end),
            })
            .collect(),
        notes: &d.notes,
    };
    // Serialising plain strings and integers cannot fail.
    serde_json::to_string(&json).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_characters_not_bytes() {
        let src = Source { name: "m.ron", text: "a\n\u{3b7} = x" };
        assert_eq!(src.line_col(0), (1, 1));
        assert_eq!(src.line_col(2), (2, 1));
        // 'η' is two bytes; the space after it is column 2.
        assert_eq!(src.line_col(4), (2, 2));
    }

    #[test]
    fn codes_are_unique_and_sorted() {
        let texts: Vec<_> = Code::ALL.iter().map(|c| c.as_str()).collect();
        let mut sorted = texts.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(texts, sorted);
    }
}
