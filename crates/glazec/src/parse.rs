//! Stage 1, `parse`: RON text → a spanned syntax tree.
//!
//! **Input:** the text of one `.ron` file. **Output:** a [`Value`] tree in which every node
//! carries the byte [`Span`] it came from, or the first syntax error as a [`Diagnostic`]
//! (`E01xx`).
//!
//! This stage knows RON, not materials: it accepts any well-formed value in the subset below and
//! leaves meaning to `check`. It exists because the `ron` crate reports a position only for its
//! own syntax errors and none for values that parse; our semantic diagnostics must point at the
//! value itself (`roughness: 1.7` underlines `1.7`). The `ron` crate stays a test oracle: the
//! test suite checks that both parsers accept the shipped materials.
//!
//! The subset (a superset of what materials use):
//!
//! ```text
//! document := value EOF
//! value    := number | string | "true" | "false"
//!           | IDENT [ "(" args ")" ]            unit variant, struct or tuple struct
//!           | "(" args ")"                       tuple or anonymous struct
//!           | "[" [ value { "," value } [","] ] "]"
//!           | "{" [ value ":" value { "," value ":" value } [","] ] "}"
//! args     := [ arg { "," arg } [","] ]
//! arg      := IDENT ":" value | value
//! number   := ["+"|"-"] ( DIGITS ["." DIGITS] [("e"|"E") ["+"|"-"] DIGITS] | "inf" | "NaN" )
//! string   := '"' chars-and-escapes '"' | raw string r#"…"#
//! ```
//!
//! Comments `// …` and (nested) `/* … */` count as whitespace. **Invariant:** every span lies
//! inside the source and on UTF-8 character boundaries.

use crate::diag::{Code, Diagnostic, Span, Spanned};

/// A parsed RON value with spans on every node.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Number(f64),
    Str(String),
    Bool(bool),
    /// `Name`, `Name(…)` or `(…)`. `name` is `None` for a bare parenthesised group;
    /// `args` is `None` for a unit variant written without parentheses.
    Call {
        name: Option<Spanned<String>>,
        args: Option<Vec<Arg>>,
    },
    List(Vec<Spanned<Value>>),
    Map(Vec<(Spanned<Value>, Spanned<Value>)>),
}

/// One argument inside parentheses: `name: value` or a positional `value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Arg {
    pub name: Option<Spanned<String>>,
    pub value: Spanned<Value>,
}

impl Value {
    /// A short description of the value's shape, for "expected X, found Y" messages.
    pub fn describe(&self) -> String {
        match self {
            Value::Number(_) => "a number".into(),
            Value::Str(_) => "a string".into(),
            Value::Bool(_) => "a boolean".into(),
            Value::Call { name: Some(n), .. } => format!("`{}`", n.node),
            Value::Call { name: None, args } => match args {
                Some(a) if a.iter().all(|a| a.name.is_none()) => format!("a {}-tuple", a.len()),
                _ => "a parenthesised struct".into(),
            },
            Value::List(_) => "a list".into(),
            Value::Map(_) => "a map".into(),
        }
    }
}

/// Parses one RON document.
///
/// # Errors
/// The first syntax error, as a diagnostic with a span and an `E01xx` code.
pub fn parse(text: &str) -> Result<Spanned<Value>, Diagnostic> {
    if text.len() > MAX_SOURCE_BYTES {
        return Err(Diagnostic::error(
            Code::FileTooLarge,
            format!("the file is {} bytes; at most {MAX_SOURCE_BYTES} are read", text.len()),
            Span::new(0, 0),
            "this file",
        )
        .with_help("a material is a few hundred bytes; this is probably not a material file"));
    }
    // A UTF-8 byte-order mark is not part of the document.
    let start = if text.starts_with('\u{feff}') { '\u{feff}'.len_utf8() } else { 0 };
    let mut parser = Parser { text, pos: start, open: Vec::new() };
    parser.skip_trivia()?;
    let value = parser.value()?;
    parser.skip_trivia()?;
    if parser.pos < text.len() {
        let span = parser.token_span();
        return Err(Diagnostic::error(
            Code::TrailingInput,
            "unexpected text after the material",
            span,
            "nothing may follow the closing parenthesis",
        )
        .with_help("a file holds exactly one material"));
    }
    Ok(value)
}

/// Largest source accepted (1 MiB): materials and scenes are a few hundred bytes.
pub const MAX_SOURCE_BYTES: usize = 1 << 20;

/// Deepest nesting of `(`, `[` and `{` accepted. Materials nest about five deep; the limit keeps
/// hostile input from exhausting the stack.
pub const MAX_DEPTH: usize = 64;

struct Parser<'a> {
    text: &'a str,
    pos: usize,
    /// The delimiters opened and not yet closed (innermost last), for "never closed" errors.
    open: Vec<(char, Span)>,
}

/// How a character is shown in a message: itself, or its code point if it is invisible.
fn show_char(c: char) -> String {
    if c.is_control() || c.is_whitespace() || matches!(c, '\u{200b}'..='\u{200f}' | '\u{feff}' | '\u{2060}') {
        format!("U+{:04X}", c as u32)
    } else {
        c.to_string()
    }
}

fn is_ident_start(c: char) -> bool {
    c.is_ascii_alphabetic() || c == '_'
}

fn is_ident_continue(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

impl<'a> Parser<'a> {
    fn peek(&self) -> Option<char> {
        self.text[self.pos..].chars().next()
    }

    fn peek_at(&self, offset: usize) -> Option<char> {
        self.text[self.pos..].chars().nth(offset)
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += c.len_utf8();
        Some(c)
    }

    fn here(&self) -> Span {
        let len = self.peek().map_or(0, char::len_utf8);
        Span::new(self.pos, self.pos + len)
    }

    fn eof_error(&self, expected: &str) -> Diagnostic {
        // Point just after the last visible character, not at trailing blank lines.
        let end = self.text.trim_end().len();
        let Some(&(open, open_span)) = self.open.last() else {
            return Diagnostic::error(
                Code::UnexpectedEof,
                format!("unexpected end of file, expected {expected}"),
                Span::new(end, end),
                "the file ends here",
            );
        };
        let close = match open {
            '(' => ')',
            '[' => ']',
            _ => '}',
        };
        Diagnostic::error(
            Code::UnexpectedEof,
            format!("unexpected end of file: `{open}` is never closed"),
            Span::new(end, end),
            format!("expected {expected} or `{close}`"),
        )
        .with_secondary(open_span, "opened here")
        .with_help(format!("close it with `{close}`"))
    }

    /// The span of the token starting here: a whole identifier or number, or one character.
    fn token_span(&self) -> Span {
        let rest = &self.text[self.pos..];
        let len = match rest.chars().next() {
            Some(c) if is_ident_continue(c) || c == '.' => {
                rest.find(|c: char| !(is_ident_continue(c) || c == '.')).unwrap_or(rest.len())
            }
            Some(c) => c.len_utf8(),
            None => 0,
        };
        Span::new(self.pos, self.pos + len)
    }

    fn unexpected(&self, expected: &str) -> Diagnostic {
        match self.peek() {
            None => self.eof_error(expected),
            Some(c) => {
                let span = self.token_span();
                let found = if span.end as usize - span.start as usize > c.len_utf8() {
                    self.text[span.range()].to_string()
                } else {
                    show_char(c)
                };
                let mut d = Diagnostic::error(
                    Code::UnexpectedToken,
                    format!("expected {expected}, found `{found}`"),
                    span,
                    format!("expected {expected}"),
                );
                if expected.contains("`,`") && (is_ident_continue(c) || matches!(c, '"' | '(' | '[' | '-' | '+')) {
                    d = d.with_help("is a `,` missing before this?");
                }
                d
            }
        }
    }

    /// Opens a delimiter at the current position, enforcing [`MAX_DEPTH`].
    fn open(&mut self, c: char) -> Result<(), Diagnostic> {
        let span = self.here();
        if self.open.len() >= MAX_DEPTH {
            return Err(Diagnostic::error(
                Code::TooDeep,
                format!("values are nested more than {MAX_DEPTH} levels deep"),
                span,
                "too deep",
            )
            .with_help("a material nests about five levels; check for unbalanced brackets"));
        }
        self.open.push((c, span));
        self.bump();
        Ok(())
    }

    fn close(&mut self) {
        self.open.pop();
        self.bump();
    }

    /// Skips whitespace and comments (block comments nest, as in RON).
    fn skip_trivia(&mut self) -> Result<(), Diagnostic> {
        loop {
            match self.peek() {
                Some(c) if c.is_whitespace() => {
                    self.bump();
                }
                Some('/') if self.peek_at(1) == Some('/') => {
                    while let Some(c) = self.bump() {
                        if c == '\n' {
                            break;
                        }
                    }
                }
                Some('/') if self.peek_at(1) == Some('*') => {
                    let start = self.pos;
                    self.pos += 2;
                    let mut depth = 1;
                    while depth > 0 {
                        match self.bump() {
                            None => {
                                return Err(Diagnostic::error(
                                    Code::UnexpectedEof,
                                    "unterminated block comment",
                                    Span::new(start, start + 2),
                                    "this comment is never closed",
                                )
                                .with_help("close it with `*/`"));
                            }
                            Some('*') if self.peek() == Some('/') => {
                                self.bump();
                                depth -= 1;
                            }
                            Some('/') if self.peek() == Some('*') => {
                                self.bump();
                                depth += 1;
                            }
                            Some(_) => {}
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    fn expect(&mut self, c: char, expected: &str) -> Result<Span, Diagnostic> {
        self.skip_trivia()?;
        if self.peek() == Some(c) {
            let span = self.here();
            self.bump();
            Ok(span)
        } else {
            Err(self.unexpected(expected))
        }
    }

    fn value(&mut self) -> Result<Spanned<Value>, Diagnostic> {
        self.skip_trivia()?;
        let start = self.pos;
        let Some(c) = self.peek() else {
            return Err(self.eof_error("a value"));
        };
        match c {
            '0'..='9' | '+' | '-' | '.' => self.number(),
            '"' => self.string(),
            'r' if matches!(self.peek_at(1), Some('"') | Some('#')) => self.raw_string(),
            '(' => {
                let args = self.args()?;
                Ok(Spanned::new(Value::Call { name: None, args: Some(args) }, Span::new(start, self.pos)))
            }
            '[' => self.list(),
            '{' => self.map(),
            c if is_ident_start(c) => self.ident_led(),
            _ => Err(Diagnostic::error(
                Code::UnexpectedChar,
                format!("unexpected character `{}`", show_char(c)),
                self.here(),
                "this cannot start a value",
            )
            .with_help("a value is a number, a string, a name like `Lambert(…)`, a tuple `(…)` or a list `[…]`")),
        }
    }

    fn ident(&mut self) -> Spanned<String> {
        let start = self.pos;
        while self.peek().is_some_and(is_ident_continue) {
            self.bump();
        }
        Spanned::new(self.text[start..self.pos].to_string(), Span::new(start, self.pos))
    }

    fn ident_led(&mut self) -> Result<Spanned<Value>, Diagnostic> {
        let name = self.ident();
        let value = match name.node.as_str() {
            "true" => Value::Bool(true),
            "false" => Value::Bool(false),
            "inf" => Value::Number(f64::INFINITY),
            "NaN" => Value::Number(f64::NAN),
            _ => {
                // A `(` directly after the name (whitespace allowed) opens its arguments.
                let save = self.pos;
                self.skip_trivia()?;
                if self.peek() == Some('(') {
                    let args = self.args()?;
                    let span = name.span.to(Span::new(save, self.pos));
                    return Ok(Spanned::new(Value::Call { name: Some(name), args: Some(args) }, span));
                }
                self.pos = save;
                let span = name.span;
                return Ok(Spanned::new(Value::Call { name: Some(name), args: None }, span));
            }
        };
        Ok(Spanned::new(value, name.span))
    }

    /// `( args )`, the opening parenthesis being next.
    fn args(&mut self) -> Result<Vec<Arg>, Diagnostic> {
        self.skip_trivia()?;
        if self.peek() != Some('(') {
            return Err(self.unexpected("`(`"));
        }
        self.open('(')?;
        let mut args = Vec::new();
        loop {
            self.skip_trivia()?;
            if self.peek() == Some(')') {
                self.close();
                return Ok(args);
            }
            args.push(self.arg()?);
            self.skip_trivia()?;
            match self.peek() {
                Some(',') => {
                    self.bump();
                }
                Some(')') => {
                    self.close();
                    return Ok(args);
                }
                _ => return Err(self.unexpected("`,` or `)`")),
            }
        }
    }

    fn arg(&mut self) -> Result<Arg, Diagnostic> {
        // `name: value` if an identifier is followed by a colon; otherwise a positional value.
        let save = self.pos;
        if self.peek().is_some_and(is_ident_start) {
            let name = self.ident();
            self.skip_trivia()?;
            if self.peek() == Some(':') {
                self.bump();
                let value = self.value()?;
                return Ok(Arg { name: Some(name), value });
            }
            self.pos = save;
        }
        Ok(Arg { name: None, value: self.value()? })
    }

    fn list(&mut self) -> Result<Spanned<Value>, Diagnostic> {
        let start = self.pos;
        self.open('[')?;
        let mut items = Vec::new();
        loop {
            self.skip_trivia()?;
            if self.peek() == Some(']') {
                self.close();
                break;
            }
            items.push(self.value()?);
            self.skip_trivia()?;
            match self.peek() {
                Some(',') => {
                    self.bump();
                }
                Some(']') => {
                    self.close();
                    break;
                }
                _ => return Err(self.unexpected("`,` or `]`")),
            }
        }
        Ok(Spanned::new(Value::List(items), Span::new(start, self.pos)))
    }

    fn map(&mut self) -> Result<Spanned<Value>, Diagnostic> {
        let start = self.pos;
        self.open('{')?;
        let mut entries = Vec::new();
        loop {
            self.skip_trivia()?;
            if self.peek() == Some('}') {
                self.close();
                break;
            }
            let key = self.value()?;
            self.expect(':', "`:`")?;
            let value = self.value()?;
            entries.push((key, value));
            self.skip_trivia()?;
            match self.peek() {
                Some(',') => {
                    self.bump();
                }
                Some('}') => {
                    self.close();
                    break;
                }
                _ => return Err(self.unexpected("`,` or `}`")),
            }
        }
        Ok(Spanned::new(Value::Map(entries), Span::new(start, self.pos)))
    }

    fn number(&mut self) -> Result<Spanned<Value>, Diagnostic> {
        let start = self.pos;
        let negative = self.peek() == Some('-');
        if matches!(self.peek(), Some('+') | Some('-')) {
            self.bump();
        }
        // `-inf`, `+inf`, `-NaN`
        if self.peek().is_some_and(is_ident_start) {
            let word = self.ident();
            let value = match word.node.as_str() {
                "inf" if negative => f64::NEG_INFINITY,
                "inf" => f64::INFINITY,
                "NaN" => f64::NAN,
                _ => {
                    return Err(Diagnostic::error(
                        Code::BadNumber,
                        format!("invalid number `{}`", &self.text[start..self.pos]),
                        Span::new(start, self.pos),
                        "not a number",
                    ));
                }
            };
            return Ok(Spanned::new(Value::Number(value), Span::new(start, self.pos)));
        }
        while self.peek().is_some_and(|c| c.is_ascii_alphanumeric() || c == '.' || c == '_' || c == '+' || c == '-') {
            // A sign continues a number only right after an exponent marker.
            let c = self.peek().unwrap_or(' ');
            if (c == '+' || c == '-') && !matches!(self.text[..self.pos].chars().last(), Some('e') | Some('E')) {
                break;
            }
            self.bump();
        }
        let text = &self.text[start..self.pos];
        let span = Span::new(start, self.pos);
        let cleaned: String = text.chars().filter(|&c| c != '_').collect();
        let digits_ok = cleaned.trim_start_matches(['+', '-']).starts_with(|c: char| c.is_ascii_digit() || c == '.');
        match cleaned.parse::<f64>() {
            Ok(v) if digits_ok && !cleaned.contains("inf") && !cleaned.to_lowercase().contains("nan") => {
                Ok(Spanned::new(Value::Number(v), span))
            }
            _ => Err(Diagnostic::error(Code::BadNumber, format!("invalid number `{text}`"), span, "not a number")
                .with_help("write numbers like `0.5`, `-2`, `1e-3`")),
        }
    }

    fn string(&mut self) -> Result<Spanned<Value>, Diagnostic> {
        let start = self.pos;
        self.bump(); // opening quote
        let mut out = String::new();
        loop {
            let Some(c) = self.bump() else {
                return Err(Diagnostic::error(
                    Code::BadString,
                    "unterminated string",
                    Span::new(start, start + 1),
                    "this string is never closed",
                )
                .with_help("close it with `\"`"));
            };
            match c {
                '"' => break,
                '\\' => {
                    let esc_start = self.pos - 1;
                    let escaped = match self.bump() {
                        Some('"') => '"',
                        Some('\\') => '\\',
                        Some('/') => '/',
                        Some('n') => '\n',
                        Some('t') => '\t',
                        Some('r') => '\r',
                        Some('0') => '\0',
                        Some('u') => self.unicode_escape(esc_start)?,
                        _ => {
                            return Err(Diagnostic::error(
                                Code::BadString,
                                "invalid escape in string",
                                Span::new(esc_start, self.pos),
                                "unknown escape",
                            )
                            .with_help("valid escapes: \\\" \\\\ \\n \\t \\r \\0 \\u{…}"));
                        }
                    };
                    out.push(escaped);
                }
                c => out.push(c),
            }
        }
        Ok(Spanned::new(Value::Str(out), Span::new(start, self.pos)))
    }

    fn unicode_escape(&mut self, esc_start: usize) -> Result<char, Diagnostic> {
        let bad = |p: &Self| {
            Diagnostic::error(
                Code::BadString,
                "invalid unicode escape",
                Span::new(esc_start, p.pos),
                "expected `\\u{HEX}`",
            )
        };
        if self.bump() != Some('{') {
            return Err(bad(self));
        }
        let hex_start = self.pos;
        while self.peek().is_some_and(|c| c.is_ascii_hexdigit()) {
            self.bump();
        }
        let hex = &self.text[hex_start..self.pos];
        if self.bump() != Some('}') {
            return Err(bad(self));
        }
        u32::from_str_radix(hex, 16).ok().and_then(char::from_u32).ok_or_else(|| bad(self))
    }

    fn raw_string(&mut self) -> Result<Spanned<Value>, Diagnostic> {
        let start = self.pos;
        self.bump(); // 'r'
        let mut hashes = 0;
        while self.peek() == Some('#') {
            self.bump();
            hashes += 1;
        }
        if self.bump() != Some('"') {
            return Err(Diagnostic::error(
                Code::BadString,
                "invalid raw string",
                Span::new(start, self.pos),
                "expected `\"` after `r#…`",
            ));
        }
        let body_start = self.pos;
        let closing: String = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
        match self.text[body_start..].find(&closing) {
            Some(offset) => {
                let body = self.text[body_start..body_start + offset].to_string();
                self.pos = body_start + offset + closing.len();
                Ok(Spanned::new(Value::Str(body), Span::new(start, self.pos)))
            }
            None => Err(Diagnostic::error(
                Code::BadString,
                "unterminated raw string",
                Span::new(start, body_start),
                "this string is never closed",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_ok(text: &str) -> Value {
        parse(text).map(|v| v.node).unwrap_or_else(|d| panic!("{text}: {d:?}"))
    }

    #[test]
    fn struct_with_named_and_positional_args() {
        let v = parse_ok("Coat(lobe: Ggx(0.3), ior: 1.5, /* c */ absorption: (0.1, 0.2, 0.3)) // end");
        let Value::Call { name: Some(name), args: Some(args) } = v else { panic!() };
        assert_eq!(name.node, "Coat");
        assert_eq!(args.len(), 3);
        assert_eq!(args[0].name.as_ref().map(|n| n.node.as_str()), Some("lobe"));
        let Value::Call { args: Some(inner), .. } = &args[0].value.node else { panic!() };
        assert!(inner[0].name.is_none());
        assert_eq!(inner[0].value.node, Value::Number(0.3));
    }

    #[test]
    fn spans_cover_values() {
        let text = "Lambert(albedo: (0.5, 0.25, 1e-1))";
        let v = parse(text).expect("parses");
        let Value::Call { args: Some(args), .. } = v.node else { panic!() };
        assert_eq!(&text[args[0].value.span.range()], "(0.5, 0.25, 1e-1)");
        let Value::Call { args: Some(tuple), .. } = &args[0].value.node else { panic!() };
        assert_eq!(&text[tuple[2].value.span.range()], "1e-1");
    }

    #[test]
    fn numbers() {
        assert_eq!(parse_ok("-1.5e2"), Value::Number(-150.0));
        assert_eq!(parse_ok("1_000"), Value::Number(1000.0));
        assert_eq!(parse_ok("-inf"), Value::Number(f64::NEG_INFINITY));
        assert!(matches!(parse_ok("NaN"), Value::Number(x) if x.is_nan()));
        assert_eq!(parse("1.2.3").unwrap_err().code, Code::BadNumber);
    }

    #[test]
    fn strings_and_escapes() {
        assert_eq!(parse_ok(r#""a\"b\u{3b7}""#), Value::Str("a\"b\u{3b7}".into()));
        assert_eq!(parse_ok(r###"r#"x"y"#"###), Value::Str("x\"y".into()));
        assert_eq!(parse("\"abc").unwrap_err().code, Code::BadString);
    }

    #[test]
    fn errors_point_at_the_problem() {
        let text = "Material(name: \"x\" layers: [])";
        let d = parse(text).unwrap_err();
        assert_eq!(d.code, Code::UnexpectedToken);
        assert_eq!(&text[d.primary_span().range()], "layers");
        let d = parse("Material(name: \"x\"").unwrap_err();
        assert_eq!(d.code, Code::UnexpectedEof);
        let d = parse("Lambert(0.5) extra").unwrap_err();
        assert_eq!(d.code, Code::TrailingInput);
        let d = parse("/* open").unwrap_err();
        assert_eq!(d.code, Code::UnexpectedEof);
    }

    #[test]
    fn eof_names_the_unclosed_delimiter() {
        let text = "Material(name: \"x\", layers: [Lambert(0.5)\n\n";
        let d = parse(text).unwrap_err();
        assert_eq!(d.code, Code::UnexpectedEof);
        assert!(d.message.contains("`[` is never closed"), "{}", d.message);
        let secondary = d.labels.iter().find(|l| !l.primary).expect("points at the opening bracket");
        assert_eq!(&text[secondary.span.range()], "[");
        assert_eq!(d.primary_span().start as usize, text.trim_end().len());
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let text = "[".repeat(200_000);
        assert_eq!(parse(&text).unwrap_err().code, Code::TooDeep);
        let ok = format!("{}1{}", "[".repeat(MAX_DEPTH), "]".repeat(MAX_DEPTH));
        assert!(parse(&ok).is_ok());
    }

    #[test]
    fn byte_order_mark_is_skipped() {
        assert_eq!(parse("\u{feff}true").map(|v| v.node), Ok(Value::Bool(true)));
        let d = parse("\u{200b}").unwrap_err();
        assert!(d.message.contains("U+200B"), "{}", d.message);
    }

    #[test]
    fn found_token_is_the_whole_word() {
        let d = parse("Material(name: \"x\" layers: [])").unwrap_err();
        assert!(d.message.ends_with("found `layers`"), "{}", d.message);
        assert!(d.notes.iter().any(|n| n.contains("`,` missing")));
    }
}
