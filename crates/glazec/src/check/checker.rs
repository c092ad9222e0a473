//! The [`Checker`]: it walks the value tree once, converting what it can and collecting a
//! diagnostic for everything it cannot; the generic conversions (fields, names, numbers,
//! colours, scalars) live here, the layers and the parameters beside it.

use std::collections::HashMap;

use super::fields::{
    FRESNEL_NAMES, FieldSpec, Fields, INTERFACED_FIELDS, MATERIAL_FIELDS, as_param, as_texture, one_of, show_number,
    suggest,
};
use super::rules::Rule;
use crate::diag::{Code, Diagnostic, Span, Spanned};
use crate::model::*;
use crate::names::name_problem;
use crate::parse::{Arg, Value};

#[derive(Default)]
pub(super) struct Checker {
    pub(super) errors: Vec<Diagnostic>,
    pub(super) params: Vec<Param>,
    /// Normal maps by layer, and the span of each `NormalMap(…)`.
    pub(super) normals: Vec<(usize, NormalMap, Span)>,
    /// The normal map of the layer being checked, until `layers` knows its index.
    pub(super) layer_normal: Option<(NormalMap, Span)>,
    pub(super) param_spans: Vec<Span>,
    pub(super) param_ids: HashMap<String, ParamId>,
    pub(super) name_span: Option<Span>,
    pub(super) layer_spans: Vec<Span>,
    pub(super) notes: Vec<Diagnostic>,
}

impl Checker {
    pub(super) fn error(&mut self, d: Diagnostic) {
        self.errors.push(d);
    }

    pub(super) fn wrong_type(&mut self, v: &Spanned<Value>, expected: &str, help: Option<&str>) {
        let mut d = Diagnostic::error(
            Code::WrongType,
            format!("expected {expected}, found {}", v.node.describe()),
            v.span,
            format!("expected {expected}"),
        );
        if let Some(help) = help {
            d = d.with_help(help);
        }
        self.error(d);
    }

    /// Maps a constructor's arguments onto `spec`, reporting unknown, duplicate and missing
    /// fields and bad positional use. Returns what could be mapped.
    pub(super) fn fields<'v>(
        &mut self,
        ctor: &Spanned<String>,
        args: Option<&'v [Arg]>,
        whole: Span,
        spec: &[FieldSpec],
    ) -> Fields<'v> {
        let mut values: Vec<Option<&'v Spanned<Value>>> = vec![None; spec.len()];
        let mut first_span: Vec<Option<Span>> = vec![None; spec.len()];
        // Fields already named in a "did you mean" help are not reported missing a second time.
        let mut suggested: Vec<&str> = Vec::new();
        let args = args.unwrap_or(&[]);
        let named = args.iter().any(|a| a.name.is_some());
        let positional = args.iter().any(|a| a.name.is_none());
        if named && positional {
            let first_positional = args.iter().find(|a| a.name.is_none()).map_or(whole, |a| a.value.span);
            self.error(
                Diagnostic::error(
                    Code::BadArguments,
                    format!("`{}` mixes positional and named arguments", ctor.node),
                    first_positional,
                    "positional argument",
                )
                .with_help(format!("name every argument, e.g. `{}: {}`", spec[0].name, spec[0].example)),
            );
            return Fields { values };
        }
        for (i, arg) in args.iter().enumerate() {
            let index = match &arg.name {
                None if i < spec.len() => i,
                None => {
                    let names: Vec<&str> = spec.iter().map(|f| f.name).collect();
                    self.error(
                        Diagnostic::error(
                            Code::BadArguments,
                            format!("`{}` takes at most {} positional argument(s)", ctor.node, spec.len()),
                            arg.value.span,
                            "unexpected argument",
                        )
                        .with_help(format!("the arguments are, in order: {}", one_of(&names))),
                    );
                    continue;
                }
                Some(name) => match spec.iter().position(|f| f.name == name.node) {
                    Some(index) => index,
                    None => {
                        let names: Vec<&str> = spec.iter().map(|f| f.name).collect();
                        let mut d = Diagnostic::error(
                            Code::UnknownField,
                            format!("unknown field `{}` in `{}`", name.node, ctor.node),
                            name.span,
                            "unknown field",
                        );
                        if let Some(s) = suggest(&name.node, &names) {
                            d = d.with_help(format!("did you mean `{s}`?"));
                            suggested.push(s);
                        }
                        d = d.with_help(format!("`{}` has the fields {}", ctor.node, one_of(&names)));
                        self.error(d);
                        continue;
                    }
                },
            };
            let this_span = arg.name.as_ref().map_or(arg.value.span, |n| n.span);
            if let Some(first) = first_span[index] {
                self.error(
                    Diagnostic::error(
                        Code::DuplicateField,
                        format!("field `{}` is given twice in `{}`", spec[index].name, ctor.node),
                        this_span,
                        "given again here",
                    )
                    .with_secondary(first, "first given here")
                    .with_help("remove one of them"),
                );
                continue;
            }
            first_span[index] = Some(this_span);
            values[index] = Some(&arg.value);
        }
        let missing: Vec<&FieldSpec> = spec
            .iter()
            .zip(&values)
            .filter(|(f, v)| f.required && v.is_none() && !suggested.contains(&f.name))
            .map(|(f, _)| f)
            .collect();
        for f in missing {
            self.error(
                Diagnostic::error(
                    Code::MissingField,
                    format!("missing field `{}` in `{}`", f.name, ctor.node),
                    ctor.span,
                    format!("`{}` needs `{}`", ctor.node, f.name),
                )
                .with_help(format!("add `{}: {}`", f.name, f.example)),
            );
        }
        Fields { values }
    }

    /// Splits a value into a constructor name and its arguments, or reports `expected`.
    pub(super) fn constructor<'v>(
        &mut self,
        v: &'v Spanned<Value>,
        expected: &str,
        names: &[&str],
    ) -> Option<(&'v Spanned<String>, Option<&'v [Arg]>)> {
        match &v.node {
            Value::Call { name: Some(name), args } => {
                if names.contains(&name.node.as_str()) {
                    return Some((name, args.as_deref()));
                }
                let mut d = Diagnostic::error(
                    Code::UnknownVariant,
                    format!("unknown {expected} `{}`", name.node),
                    name.span,
                    format!("not a known {expected}"),
                );
                if let Some(s) = suggest(&name.node, names) {
                    d = d.with_help(format!("did you mean `{s}`?"));
                }
                self.error(d.with_help(format!("a {expected} is one of {}", one_of(names))));
                None
            }
            _ => {
                self.wrong_type(
                    v,
                    &format!("a {expected}"),
                    Some(&format!("a {expected} is one of {}", one_of(names))),
                );
                None
            }
        }
    }

    pub(super) fn material(&mut self, root: &Spanned<Value>) -> Option<Material> {
        let (ctor, args) = self.constructor(root, "top-level item", &["Material"])?;
        let f = self.fields(ctor, args, root.span, MATERIAL_FIELDS);
        let name = f.get(0).and_then(|v| self.material_name(v));
        let method = match f.get(1) {
            Some(v) => self.method(v),
            None => Some(Method::default()),
        };
        let stack = f.get(2).and_then(|v| self.layers(v));
        let (coats, base) = stack?;
        let normals: Vec<(usize, NormalMap)> = self.normals.iter().map(|(l, m, _)| (*l, m.clone())).collect();
        let material =
            Material { name: name?, method: method?, coats, base, params: std::mem::take(&mut self.params), normals };
        self.texture_count(&material)?;
        Some(material)
    }

    pub(super) fn string<'v>(&mut self, v: &'v Spanned<Value>) -> Option<&'v str> {
        match &v.node {
            Value::Str(s) => Some(s),
            _ => {
                self.wrong_type(v, "a string", None);
                None
            }
        }
    }

    pub(super) fn identifier(&mut self, v: &Spanned<Value>, what: &str) -> Option<String> {
        let s = self.string(v)?;
        if let Some(problem) = name_problem(s) {
            self.error(
                Diagnostic::error(Code::BadName, format!("`{s}` cannot be a {what} name"), v.span, problem).with_help(
                    "use a lowercase snake_case identifier such as `wet_clay`; it names files and shader symbols",
                ),
            );
            return None;
        }
        Some(s.to_string())
    }

    pub(super) fn material_name(&mut self, v: &Spanned<Value>) -> Option<String> {
        self.name_span = Some(v.span);
        self.identifier(v, "material")
    }

    pub(super) fn method(&mut self, v: &Spanned<Value>) -> Option<Method> {
        let (name, args) = self.constructor(v, "method", Method::NAMES)?;
        match name.node.as_str() {
            "Additive" => {
                self.no_arguments(name, args, v.span);
                Some(Method::Additive)
            }
            "WeidlichWilkie" => {
                self.no_arguments(name, args, v.span);
                Some(Method::WeidlichWilkie)
            }
            _ => self.approximations(name, args, v.span).map(Method::Interfaced),
        }
    }

    /// `Interfaced(fresnel: Exact | Schlick, multiple_scattering: true | false)`.
    pub(super) fn approximations(
        &mut self,
        name: &Spanned<String>,
        args: Option<&[Arg]>,
        whole: Span,
    ) -> Option<Approximations> {
        let f = self.fields(name, args, whole, INTERFACED_FIELDS);
        let schlick_fresnel = match f.get(0) {
            Some(v) => self.constructor(v, "Fresnel model", FRESNEL_NAMES).map(|(n, a)| {
                self.no_arguments(n, a, v.span);
                n.node == "Schlick"
            }),
            None => Some(false),
        };
        let single_scattering = match f.get(1) {
            Some(v) => self.boolean(v).map(|multiple| !multiple),
            None => Some(false),
        };
        Some(Approximations { schlick_fresnel: schlick_fresnel?, single_scattering: single_scattering? })
    }

    pub(super) fn boolean(&mut self, v: &Spanned<Value>) -> Option<bool> {
        match v.node {
            Value::Bool(b) => Some(b),
            _ => {
                self.wrong_type(v, "`true` or `false`", None);
                None
            }
        }
    }

    pub(super) fn no_arguments(&mut self, name: &Spanned<String>, args: Option<&[Arg]>, whole: Span) {
        if args.is_some_and(|a| !a.is_empty()) {
            self.error(
                Diagnostic::error(
                    Code::BadArguments,
                    format!("`{}` takes no arguments", name.node),
                    whole,
                    "unexpected arguments",
                )
                .with_help(format!("write just `{}`", name.node)),
            );
        }
    }

    /// A finite number from a literal, with its span.
    pub(super) fn number(&mut self, v: &Spanned<Value>, rule: Rule) -> Option<f64> {
        let Value::Number(x) = v.node else {
            self.wrong_type(v, "a number", Some(rule.help()));
            return None;
        };
        if !x.is_finite() {
            self.error(
                Diagnostic::error(
                    Code::NotFinite,
                    format!("the {} must be a finite number", rule.what()),
                    v.span,
                    "not finite",
                )
                .with_help(rule.help()),
            );
            return None;
        }
        if !(x as f32).is_finite() {
            self.error(
                Diagnostic::error(
                    Code::NotFinite,
                    format!("the {} {} does not fit in a 32-bit float", rule.what(), show_number(x)),
                    v.span,
                    "too large for f32 (about ±3.4e38)",
                )
                .with_help(rule.help()),
            );
            return None;
        }
        if !rule.accepts(x) {
            self.error(
                Diagnostic::error(
                    rule.code(),
                    format!("{} {} is out of range", rule.what(), show_number(x)),
                    v.span,
                    rule.label(),
                )
                .with_help(rule.help()),
            );
            return None;
        }
        Some(x)
    }

    /// `(r, g, b)` or a single grey number.
    pub(super) fn rgb(&mut self, v: &Spanned<Value>, rule: Rule) -> Option<[f32; 3]> {
        match &v.node {
            Value::Number(_) => self.number(v, rule).map(|x| [x as f32; 3]),
            Value::Call { name: None, args: Some(items) }
                if items.len() == 3 && items.iter().all(|a| a.name.is_none()) =>
            {
                let c: Vec<Option<f64>> = items.iter().map(|a| self.number(&a.value, rule)).collect();
                Some([c[0]? as f32, c[1]? as f32, c[2]? as f32])
            }
            _ => {
                self.wrong_type(
                    v,
                    "an RGB triple `(r, g, b)` or a number",
                    Some("write a colour as three numbers `(0.8, 0.5, 0.3)`, or one number for grey"),
                );
                None
            }
        }
    }

    pub(super) fn scalar(&mut self, v: Option<&Spanned<Value>>, rule: Rule) -> Option<Scalar> {
        let v = v?;
        if let Some((name, args)) = as_texture(v) {
            return self.texture(name, args, v.span, rule, false).map(Scalar::Param);
        }
        if let Some((name, args)) = as_param(v) {
            let (id, default) = self.param(name, args, v.span, rule)?;
            return match default {
                ParamValue::Scalar(_) => Some(Scalar::Param(id)),
                ParamValue::Rgb(_) => {
                    self.wrong_type(
                        v,
                        "a scalar parameter",
                        Some("this slot takes one number; give the parameter a number as default"),
                    );
                    None
                }
            };
        }
        self.number(v, rule).map(|x| Scalar::Lit(x as f32))
    }

    pub(super) fn color(&mut self, v: Option<&Spanned<Value>>, rule: Rule) -> Option<Color> {
        let v = v?;
        if let Some((name, args)) = as_texture(v) {
            return self.texture(name, args, v.span, rule, true).map(Color::Param);
        }
        if let Some((name, args)) = as_param(v) {
            return self.param(name, args, v.span, rule).map(|(id, _)| Color::Param(id));
        }
        self.rgb(v, rule).map(Color::Lit)
    }
}
