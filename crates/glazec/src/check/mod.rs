//! Stage 2, `check`: spanned syntax → the typed [`Material`] model, or every error at once.
//!
//! **Input:** the [`Value`] tree from `parse`. **Output:** a [`Material`] plus its
//! [`SourceMap`], or *all* semantic problems as [`Diagnostic`]s (`E02xx`), each pointing at the
//! offending value's own span, with a help line: the valid names of an enum (and "did you mean"),
//! the physical range of a number, or a fix.
//!
//! Checking is table-driven: each constructor (`Material`, `Coat`, `Ggx`, `Lambert`, …) has a
//! list of `FieldSpec`s, and one routine maps named or positional arguments onto it, reporting
//! unknown, duplicate and missing fields. Values are then converted slot by slot; a slot that
//! fails is reported and skipped, so one run finds every error.
//!
//! **Invariants of the output:** those listed in [`crate::model`].

use std::collections::HashMap;

use crate::diag::{Code, Diagnostic, Span, Spanned};
mod measured;
mod scene;
pub use scene::check_scene;

use crate::model::*;
use crate::parse::{Arg, Value};

/// Checks a parsed material.
///
/// # Errors
/// Every semantic problem found, in source order.
pub fn check(root: &Spanned<Value>) -> Result<(Material, SourceMap), Vec<Diagnostic>> {
    let mut checker = Checker::default();
    let material = checker.material(root);
    checker.errors.sort_by_key(|d| d.primary_span().start);
    match material {
        Some(material) if checker.errors.is_empty() => {
            let map = SourceMap {
                name: checker.name_span,
                layers: checker.layer_spans,
                params: checker.param_spans,
                notes: checker.notes,
            };
            Ok((material, map))
        }
        _ => Err(checker.errors),
    }
}

/// One field of a constructor: its name, whether it must be present, and an example value for
/// the "missing field" help line.
struct FieldSpec {
    name: &'static str,
    required: bool,
    example: &'static str,
}

const fn req(name: &'static str, example: &'static str) -> FieldSpec {
    FieldSpec { name, required: true, example }
}

const fn opt(name: &'static str, example: &'static str) -> FieldSpec {
    FieldSpec { name, required: false, example }
}

const MATERIAL_FIELDS: &[FieldSpec] =
    &[req("name", "\"clay\""), opt("method", "Interfaced"), req("layers", "[Lambert(albedo: 0.5)]")];
const COAT_FIELDS: &[FieldSpec] = &[
    req("lobe", "Ggx(roughness: 0.2)"),
    req("ior", "1.5"),
    opt("absorption", "(0.1, 0.2, 0.4)"),
    opt("thickness", "0.5"),
    opt("normal", "NormalMap(\"clay_normal\", 1.0)"),
];
const ROUGH_LOBE_FIELDS: &[FieldSpec] = &[req("roughness", "0.2")];
const LAMBERT_FIELDS: &[FieldSpec] =
    &[req("albedo", "(0.8, 0.5, 0.3)"), opt("normal", "NormalMap(\"clay_normal\", 1.0)")];
const ROUGH_DIFFUSE_FIELDS: &[FieldSpec] =
    &[req("albedo", "(0.8, 0.5, 0.3)"), req("roughness", "0.5"), opt("normal", "NormalMap(\"clay_normal\", 1.0)")];
const CONDUCTOR_FIELDS: &[FieldSpec] = &[
    req("roughness", "0.3"),
    opt("f0", "(0.95, 0.64, 0.54)"),
    opt("eta", "(0.2, 0.92, 1.1)"),
    opt("k", "(3.9, 2.45, 2.14)"),
    opt("normal", "NormalMap(\"clay_normal\", 1.0)"),
];
const PLASTIC_FIELDS: &[FieldSpec] = &[
    req("albedo", "(0.8, 0.1, 0.1)"),
    req("roughness", "0.3"),
    req("ior", "1.5"),
    opt("normal", "NormalMap(\"clay_normal\", 1.0)"),
];
const NORMAL_MAP_FIELDS: &[FieldSpec] = &[
    req("texture", "\"clay_normal\""),
    opt("uv_scale", "1.0"),
    opt("detail", "\"clay_pores\""),
    opt("detail_scale", "8.0"),
];
const INTERFACED_FIELDS: &[FieldSpec] = &[opt("fresnel", "Schlick"), opt("multiple_scattering", "false")];
const FRESNEL_NAMES: &[&str] = &["Exact", "Schlick"];
const PARAM_FIELDS: &[FieldSpec] = &[req("name", "\"roughness\""), req("default", "0.5")];
const TEXTURE_FIELDS: &[FieldSpec] =
    &[req("name", "\"clay_maps\""), req("channel", "R"), opt("uv_scale", "1.0"), opt("range", "(0.0, 1.0)")];

const LAYER_NAMES: &[&str] = &["Coat", "Lambert", "OrenNayar", "Eon", "Conductor", "Plastic", "Measured"];

/// The physical range a number must lie in, with its code and help text.
#[derive(Clone, Copy)]
enum Rule {
    /// Perceptual roughness, [0, 1].
    Roughness,
    /// Oren–Nayar σ in radians, [0, 1].
    Sigma,
    /// IOR or real part of a complex IOR: finite and > 0.
    Ior,
    /// Absorption σa ≥ 0.
    Absorption,
    /// Thickness d ≥ 0.
    Thickness,
    /// Conductor extinction κ ≥ 0.
    Extinction,
    /// A reflectance in [0, 1].
    Albedo,
    /// A conductor's normal-incidence reflectance F0 in [0, 1].
    Reflectance,
    /// The real part η of a conductor's complex IOR (relative to vacuum), > 0.
    ConductorEta,
    /// A scene's angle from the normal, in degrees: [0, 90].
    Angle,
    /// A light's irradiance, intensity or radiance: ≥ 0.
    LightAmount,
    /// A point light's closest distance: > 0.
    Distance,
    /// A tolerance: (0, 1].
    Tolerance,
    /// A scene's exposure: > 0.
    Exposure,
    /// A ΔE*ab tolerance: (0, 100].
    DeltaE,
    /// A value a scene gives a runtime parameter: ≥ 0 (the material's slot bounds it further).
    SceneValue,
}

/// A coat's relative IOR: physical interfaces lie well inside (diamond in air 2.42, air under
/// water 0.75); far outside, η² and 1/η² leave f32's range in the shader's constants (fuzzing
/// found η = 10⁻⁴⁵ folding to NaN).
const IOR_MIN: f64 = 0.1;
const IOR_MAX: f64 = 10.0;
/// A conductor's η can be small (silver ≈ 0.05 in the visible).
const CONDUCTOR_ETA_MIN: f64 = 0.01;
/// Absorption, thickness and extinction: beyond 10⁶ a layer is opaque anyway, and products of
/// such values overflow f32.
const MEDIUM_MAX: f64 = 1e6;

impl Rule {
    fn accepts(self, x: f64) -> bool {
        match self {
            Rule::Roughness | Rule::Sigma | Rule::Albedo | Rule::Reflectance => (0.0..=1.0).contains(&x),
            Rule::Ior => (IOR_MIN..=IOR_MAX).contains(&x),
            Rule::ConductorEta => (CONDUCTOR_ETA_MIN..=IOR_MAX).contains(&x),
            Rule::Absorption | Rule::Thickness | Rule::Extinction => (0.0..=MEDIUM_MAX).contains(&x),
            Rule::Angle => (0.0..=90.0).contains(&x),
            Rule::LightAmount | Rule::SceneValue => x >= 0.0,
            Rule::Distance | Rule::Exposure => x > 0.0,
            Rule::Tolerance => x > 0.0 && x <= 1.0,
            Rule::DeltaE => x > 0.0 && x <= 100.0,
        }
    }

    fn code(self) -> Code {
        match self {
            Rule::Roughness | Rule::Sigma => Code::RoughnessRange,
            Rule::Ior | Rule::ConductorEta => Code::IorRange,
            Rule::Absorption | Rule::Thickness | Rule::Extinction => Code::NegativeMedium,
            Rule::Albedo | Rule::Reflectance => Code::AlbedoRange,
            Rule::Angle
            | Rule::LightAmount
            | Rule::Distance
            | Rule::Tolerance
            | Rule::Exposure
            | Rule::DeltaE
            | Rule::SceneValue => Code::SceneRange,
        }
    }

    fn what(self) -> &'static str {
        match self {
            Rule::Roughness => "roughness",
            Rule::Sigma => "Oren–Nayar roughness",
            Rule::Ior => "index of refraction",
            Rule::Absorption => "absorption",
            Rule::Thickness => "thickness",
            Rule::Extinction => "extinction coefficient",
            Rule::Albedo => "albedo",
            Rule::Reflectance => "reflectance F0",
            Rule::ConductorEta => "conductor IOR η",
            Rule::Angle => "angle",
            Rule::LightAmount => "light amount",
            Rule::Distance => "distance",
            Rule::Tolerance => "tolerance",
            Rule::Exposure => "exposure",
            Rule::DeltaE => "ΔE tolerance",
            Rule::SceneValue => "parameter value",
        }
    }

    fn label(self) -> &'static str {
        match self {
            Rule::Roughness | Rule::Sigma | Rule::Albedo | Rule::Reflectance => "must lie in [0, 1]",
            Rule::Ior => "must lie in [0.1, 10]",
            Rule::ConductorEta => "must lie in [0.01, 10]",
            Rule::Absorption | Rule::Thickness | Rule::Extinction => "must lie in [0, 10⁶]",
            Rule::Angle => "must lie in [0, 90] degrees",
            Rule::LightAmount | Rule::SceneValue => "must not be negative",
            Rule::Distance | Rule::Exposure => "must be greater than 0",
            Rule::Tolerance => "must lie in (0, 1]",
            Rule::DeltaE => "must lie in (0, 100]",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Rule::Roughness => "roughness is perceptual (α = roughness²): 0 is a mirror, 1 is fully rough",
            Rule::Sigma => "Oren–Nayar roughness is the facet-slope deviation σ in radians, from 0 (Lambert) to 1",
            Rule::Ior => {
                "an index of refraction relative to the medium above lies in [0.1, 10] \
                          (water 1.33, glass 1.5, diamond 2.42)"
            }
            Rule::Absorption => "absorption σa is per unit length; 0 means a clear coat",
            Rule::Thickness => "thickness is a length (the seed's density d); 0 means an interface with no slab",
            Rule::Extinction => {
                "the imaginary part κ of a conductor's IOR is 0 or more (gold: (0.2, 0.92, 1.1) + i(3.9, 2.45, 2.14))"
            }
            Rule::Albedo => "albedo is a reflectance in [0, 1]; a value above 1 creates energy",
            Rule::Reflectance => {
                "F0 is the conductor's reflectance at normal incidence, in [0, 1] \
                                  (silver (0.97, 0.96, 0.91), gold (1.0, 0.78, 0.34))"
            }
            Rule::ConductorEta => {
                "η is the real part of the conductor's complex IOR relative to vacuum, above 0 \
                                   (gold: η = (0.17, 0.43, 1.44), κ = (3.5, 2.46, 1.8))"
            }
            Rule::Angle => "an angle from the surface normal in degrees: 0 is head-on, 90 is grazing",
            Rule::LightAmount => "irradiance, intensity and radiance are 0 or more, per channel",
            Rule::Distance => "the closest a point light comes to a lit surface, in scene units, above 0",
            Rule::Tolerance => "a tolerance is a fraction: `Display` is 1/255, `Relative(0.01)` is 1%",
            Rule::Exposure => "exposure scales radiance to display value; 1 shows radiance 1 as white",
            Rule::DeltaE => "a CIE 1976 ΔE*ab: about 2.3 is one just-noticeable difference",
            Rule::SceneValue => "a parameter's value in a scene is 0 or more (the material's slot bounds it)",
        }
    }
}

#[derive(Default)]
struct Checker {
    errors: Vec<Diagnostic>,
    params: Vec<Param>,
    /// Normal maps by layer, and the span of each `NormalMap(…)`.
    normals: Vec<(usize, NormalMap, Span)>,
    /// The normal map of the layer being checked, until `layers` knows its index.
    layer_normal: Option<(NormalMap, Span)>,
    param_spans: Vec<Span>,
    param_ids: HashMap<String, ParamId>,
    name_span: Option<Span>,
    layer_spans: Vec<Span>,
    notes: Vec<Diagnostic>,
}

/// The arguments of one constructor call, mapped onto its field list.
struct Fields<'v> {
    values: Vec<Option<&'v Spanned<Value>>>,
}

impl<'v> Fields<'v> {
    fn get(&self, index: usize) -> Option<&'v Spanned<Value>> {
        self.values.get(index).copied().flatten()
    }
}

/// "did you mean `x`?" over a list of valid names: the closest by edit distance, if close enough.
pub fn suggest<'a>(word: &str, candidates: &[&'a str]) -> Option<&'a str> {
    let lower = word.to_lowercase();
    candidates
        .iter()
        .map(|&c| (strsim::damerau_levenshtein(&lower, &c.to_lowercase()), c))
        .filter(|&(d, c)| d <= (c.len().max(word.len()) / 3).max(1))
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

fn one_of(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// A number as a message shows it: plain for everyday magnitudes, scientific otherwise.
fn show_number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") }
}

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
fn is_reserved_file_name(name: &str) -> bool {
    matches!(name, "con" | "prn" | "aux" | "nul")
        || (name.len() == 4
            && (name.starts_with("com") || name.starts_with("lpt"))
            && name.as_bytes()[3].is_ascii_digit()
            && name.as_bytes()[3] != b'0')
}

/// Whether `name` can name a material (files, shader functions) or a parameter (struct member).
fn name_problem(name: &str) -> Option<&'static str> {
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

impl Checker {
    fn error(&mut self, d: Diagnostic) {
        self.errors.push(d);
    }

    fn wrong_type(&mut self, v: &Spanned<Value>, expected: &str, help: Option<&str>) {
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
    fn fields<'v>(
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
    fn constructor<'v>(
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

    fn material(&mut self, root: &Spanned<Value>) -> Option<Material> {
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

    fn string<'v>(&mut self, v: &'v Spanned<Value>) -> Option<&'v str> {
        match &v.node {
            Value::Str(s) => Some(s),
            _ => {
                self.wrong_type(v, "a string", None);
                None
            }
        }
    }

    fn identifier(&mut self, v: &Spanned<Value>, what: &str) -> Option<String> {
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

    fn material_name(&mut self, v: &Spanned<Value>) -> Option<String> {
        self.name_span = Some(v.span);
        self.identifier(v, "material")
    }

    fn method(&mut self, v: &Spanned<Value>) -> Option<Method> {
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
    fn approximations(&mut self, name: &Spanned<String>, args: Option<&[Arg]>, whole: Span) -> Option<Approximations> {
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

    fn boolean(&mut self, v: &Spanned<Value>) -> Option<bool> {
        match v.node {
            Value::Bool(b) => Some(b),
            _ => {
                self.wrong_type(v, "`true` or `false`", None);
                None
            }
        }
    }

    fn no_arguments(&mut self, name: &Spanned<String>, args: Option<&[Arg]>, whole: Span) {
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

    fn layers(&mut self, v: &Spanned<Value>) -> Option<(Vec<Coat>, Base)> {
        let Value::List(items) = &v.node else {
            self.wrong_type(
                v,
                "a list of layers",
                Some("write the stack top to bottom: `layers: [Coat(…), Lambert(…)]`"),
            );
            return None;
        };
        let Some((last, coats)) = items.split_last() else {
            self.error(
                Diagnostic::error(Code::EmptyStack, "the layer stack is empty", v.span, "no layers")
                    .with_help("a material needs at least an opaque base, e.g. `layers: [Lambert(albedo: 0.5)]`"),
            );
            return None;
        };
        self.layer_spans = items.iter().map(|i| i.span).collect();
        let mut ok = true;
        let mut checked_coats = Vec::new();
        for item in coats {
            let layer = self.layer(item);
            if let Some((map, span)) = self.layer_normal.take() {
                self.normals.push((checked_coats.len(), map, span));
            }
            match layer {
                Some(Layer::Coat(c)) => checked_coats.push(c),
                Some(Layer::Base(_)) => {
                    ok = false;
                    self.error(
                        Diagnostic::error(
                            Code::BaseNotLast,
                            "an opaque base must be the last layer",
                            item.span,
                            "this base hides every layer below it",
                        )
                        .with_help("list the stack top to bottom: coats first, then exactly one base"),
                    );
                }
                None => ok = false,
            }
        }
        let base_layer = self.layer(last);
        if let Some((map, span)) = self.layer_normal.take() {
            self.normals.push((checked_coats.len(), map, span));
        }
        let base = match base_layer {
            Some(Layer::Base(b)) => Some(b),
            Some(Layer::Coat(_)) => {
                self.error(
                    Diagnostic::error(
                        Code::BaseNotLast,
                        "the last layer must be an opaque base",
                        last.span,
                        "a coat cannot end the stack",
                    )
                    .with_help(format!("add a base below it: {}", one_of(&LAYER_NAMES[1..]))),
                );
                None
            }
            None => None,
        };
        if checked_coats.len() > MAX_COATS {
            self.error(
                Diagnostic::error(
                    Code::TooManyLayers,
                    format!("{} coat layers; at most {MAX_COATS} are supported", checked_coats.len()),
                    coats[MAX_COATS].span,
                    format!("coat {} is one too many", MAX_COATS + 1),
                )
                .with_help("merge layers with identical interfaces, or drop the ones that cannot be seen"),
            );
            ok = false;
        }
        if !ok {
            return None;
        }
        Some((checked_coats, base?))
    }

    fn layer(&mut self, v: &Spanned<Value>) -> Option<Layer> {
        let (name, args) = self.constructor(v, "layer", LAYER_NAMES)?;
        let layer = match name.node.as_str() {
            "Coat" => Layer::Coat(self.coat(name, args, v.span)?),
            "Lambert" => {
                let f = self.fields(name, args, v.span, LAMBERT_FIELDS);
                self.normal_map(f.get(1))?;
                Layer::Base(Base::Lambert { albedo: self.color(f.get(0), Rule::Albedo)? })
            }
            "OrenNayar" | "Eon" => {
                let f = self.fields(name, args, v.span, ROUGH_DIFFUSE_FIELDS);
                self.normal_map(f.get(2))?;
                let sigma_rule = if name.node == "OrenNayar" { Rule::Sigma } else { Rule::Roughness };
                let albedo = self.color(f.get(0), Rule::Albedo);
                let roughness = self.scalar(f.get(1), sigma_rule);
                let (albedo, roughness) = (albedo?, roughness?);
                Layer::Base(if name.node == "OrenNayar" {
                    Base::OrenNayar { albedo, roughness }
                } else {
                    Base::Eon { albedo, roughness }
                })
            }
            "Conductor" => Layer::Base(self.conductor(name, args, v.span)?),
            "Measured" => Layer::Base(self.measured(name, args, v.span)?),
            _ => {
                let f = self.fields(name, args, v.span, PLASTIC_FIELDS);
                self.normal_map(f.get(3))?;
                let albedo = self.color(f.get(0), Rule::Albedo);
                let roughness = self.scalar(f.get(1), Rule::Roughness);
                let ior = self.scalar(f.get(2), Rule::Ior);
                Layer::Base(Base::Plastic { albedo: albedo?, roughness: roughness?, ior: ior? })
            }
        };
        Some(layer)
    }

    fn coat(&mut self, name: &Spanned<String>, args: Option<&[Arg]>, whole: Span) -> Option<Coat> {
        let f = self.fields(name, args, whole, COAT_FIELDS);
        self.normal_map(f.get(4))?;
        let lobe = f.get(0).and_then(|v| self.lobe(v));
        let ior = self.scalar(f.get(1), Rule::Ior);
        let absorption = match f.get(2) {
            Some(v) => self.color(Some(v), Rule::Absorption),
            None => Some(Color::Lit([0.0; 3])),
        };
        let thickness = match f.get(3) {
            Some(v) => self.scalar(Some(v), Rule::Thickness),
            None => Some(Scalar::Lit(0.0)),
        };
        Some(Coat { lobe: lobe?, ior: ior?, absorption: absorption?, thickness: thickness? })
    }

    fn lobe(&mut self, v: &Spanned<Value>) -> Option<Lobe> {
        let (name, args) = self.constructor(v, "lobe", Lobe::NAMES)?;
        if name.node == "Smooth" {
            self.no_arguments(name, args, v.span);
            return Some(Lobe::Smooth);
        }
        let f = self.fields(name, args, v.span, ROUGH_LOBE_FIELDS);
        let roughness = self.scalar(f.get(0), Rule::Roughness)?;
        Some(if name.node == "Ggx" { Lobe::Ggx { roughness } } else { Lobe::Gtr1 { roughness } })
    }

    fn conductor(&mut self, name: &Spanned<String>, args: Option<&[Arg]>, whole: Span) -> Option<Base> {
        let f = self.fields(name, args, whole, CONDUCTOR_FIELDS);
        self.normal_map(f.get(4))?;
        let roughness = self.scalar(f.get(0), Rule::Roughness);
        let fresnel = match (f.get(1), f.get(2), f.get(3)) {
            (Some(f0), None, None) => self.color(Some(f0), Rule::Reflectance).map(ConductorFresnel::F0),
            (None, Some(eta), Some(k)) => {
                let eta = self.color(Some(eta), Rule::ConductorEta);
                let k = self.color(Some(k), Rule::Extinction);
                Some(ConductorFresnel::Complex { eta: eta?, k: k? })
            }
            (f0, eta, k) => {
                const HELP: &str = "write `f0: (1.0, 0.78, 0.34)` (Schlick's approximation) or \
                                    `eta: (0.17, 0.43, 1.44), k: (3.5, 2.46, 1.8)` (the exact conductor Fresnel)";
                let d = match (f0, eta, k) {
                    (Some(f0), ..) => {
                        let mut d = Diagnostic::error(
                            Code::ConductorFresnel,
                            "a conductor takes either `f0` or `eta` and `k`, not both",
                            f0.span,
                            "`f0` given here",
                        );
                        for (other, what) in [(eta, "`eta`"), (k, "`k`")] {
                            if let Some(other) = other {
                                d = d.with_secondary(other.span, format!("and {what} here"));
                            }
                        }
                        d
                    }
                    (None, Some(eta), None) => Diagnostic::error(
                        Code::ConductorFresnel,
                        "a conductor given `eta` also needs `k`",
                        eta.span,
                        "the real part of the complex IOR; the imaginary part `k` is missing",
                    ),
                    (None, None, Some(k)) => Diagnostic::error(
                        Code::ConductorFresnel,
                        "a conductor given `k` also needs `eta`",
                        k.span,
                        "the imaginary part of the complex IOR; the real part `eta` is missing",
                    ),
                    _ => Diagnostic::error(
                        Code::ConductorFresnel,
                        "a conductor needs its Fresnel reflectance: `f0`, or `eta` and `k`",
                        name.span,
                        "no `f0`, `eta` or `k`",
                    ),
                };
                self.error(d.with_help(HELP));
                None
            }
        };
        Some(Base::Conductor { roughness: roughness?, fresnel: fresnel? })
    }

    /// A finite number from a literal, with its span.
    fn number(&mut self, v: &Spanned<Value>, rule: Rule) -> Option<f64> {
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
    fn rgb(&mut self, v: &Spanned<Value>, rule: Rule) -> Option<[f32; 3]> {
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

    fn scalar(&mut self, v: Option<&Spanned<Value>>, rule: Rule) -> Option<Scalar> {
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

    fn color(&mut self, v: Option<&Spanned<Value>>, rule: Rule) -> Option<Color> {
        let v = v?;
        if let Some((name, args)) = as_texture(v) {
            return self.texture(name, args, v.span, rule, true).map(Color::Param);
        }
        if let Some((name, args)) = as_param(v) {
            return self.param(name, args, v.span, rule).map(|(id, _)| Color::Param(id));
        }
        self.rgb(v, rule).map(Color::Lit)
    }

    /// Declares (or re-uses) a runtime parameter `Param("name", default)`.
    fn param(
        &mut self,
        ctor: &Spanned<String>,
        args: Option<&[Arg]>,
        whole: Span,
        rule: Rule,
    ) -> Option<(ParamId, ParamValue)> {
        let f = self.fields(ctor, args, whole, PARAM_FIELDS);
        let name = f.get(0).and_then(|v| self.identifier(v, "parameter"));
        let default = f.get(1).and_then(|v| match &v.node {
            Value::Number(_) => self.number(v, rule).map(|x| ParamValue::Scalar(x as f32)),
            _ => self.rgb(v, rule).map(ParamValue::Rgb),
        });
        let (name, default) = (name?, default?);
        if let Some(&id) = self.param_ids.get(&name) {
            let first = self.params[id.0 as usize].default;
            let first_span = self.param_spans[id.0 as usize];
            if self.params[id.0 as usize].source != ParamSource::Uniform {
                self.error(
                    Diagnostic::error(
                        Code::ParamConflict,
                        format!("`{name}` is the name of a texture read"),
                        whole,
                        "declared as a uniform parameter here",
                    )
                    .with_secondary(first_span, "read from a texture here")
                    .with_help("rename the parameter"),
                );
                return None;
            }
            if first.type_name() != default.type_name() {
                self.error(
                    Diagnostic::error(
                        Code::ParamConflict,
                        format!("parameter `{name}` is declared with two types"),
                        whole,
                        format!("declared here as {}", default.type_name()),
                    )
                    .with_secondary(first_span, format!("first declared here as {}", first.type_name()))
                    .with_help("rename one of them, or give both defaults the same shape"),
                );
                return None;
            }
            if first != default {
                self.error(
                    Diagnostic::error(
                        Code::ParamConflict,
                        format!("parameter `{name}` is declared with two different defaults"),
                        whole,
                        "declared again here",
                    )
                    .with_secondary(first_span, "first declared here")
                    .with_help("a parameter has one default; repeat the same value or rename one"),
                );
                return None;
            }
            return Some((id, first));
        }
        let id = self.declare(Param { name, default, source: ParamSource::Uniform }, whole)?;
        Some((id, default))
    }

    /// Declares (or re-uses) a parameter read from a texture,
    /// `Texture("name", channel, uv_scale, range: (lo, hi))`. Its name is the texture's with the
    /// channel's suffix (`clay_maps_g`); `color_slot`: the slot takes a colour.
    fn texture(
        &mut self,
        ctor: &Spanned<String>,
        args: Option<&[Arg]>,
        whole: Span,
        rule: Rule,
        color_slot: bool,
    ) -> Option<ParamId> {
        let f = self.fields(ctor, args, whole, TEXTURE_FIELDS);
        let texture = f.get(0).and_then(|v| self.identifier(v, "texture"));
        let channel = f.get(1).and_then(|v| self.channel(v, color_slot));
        let uv_scale = match f.get(2) {
            Some(v) => self.uv_scale(v),
            None => Some(1.0),
        };
        let range = match f.get(3) {
            Some(v) => self.texture_range(v, rule),
            None => self.default_texture_range(whole, rule),
        };
        let (texture, channel, uv_scale, range) = (texture?, channel?, uv_scale?, range?);
        let mid = 0.5 * (range[0] + range[1]);
        let default = if channel == Channel::Rgb { ParamValue::Rgb([mid; 3]) } else { ParamValue::Scalar(mid) };
        let name = format!("{texture}_{}", channel.suffix());
        let read = TextureRead { texture, channel, uv_scale, range };
        let source = ParamSource::Texture(read.clone());
        if let Some(&id) = self.param_ids.get(&name) {
            let first = &self.params[id.0 as usize];
            if first.source == source {
                return Some(id);
            }
            let first_span = self.param_spans[id.0 as usize];
            self.error(
                Diagnostic::error(
                    Code::ParamConflict,
                    format!("`{name}` is read twice in different ways"),
                    whole,
                    "read again here",
                )
                .with_secondary(first_span, "first read here")
                .with_help(
                    "a texture channel is one parameter: give every read of it the same uv_scale and range, or \
                     use another channel",
                ),
            );
            return None;
        }
        let textures = distinct_textures(&self.params, &[]);
        if !textures.contains(&read.texture.as_str()) && textures.len() == MAX_TEXTURES {
            self.error(
                Diagnostic::error(
                    Code::TooManyTextures,
                    format!("more than {MAX_TEXTURES} textures"),
                    whole,
                    format!("texture `{}` is one too many", read.texture),
                )
                .with_help("pack scalar maps into the channels of one texture (R, G, B, A)"),
            );
            return None;
        }
        self.declare(Param { name, default, source }, whole)
    }

    /// Adds a new parameter, unless there are [`MAX_PARAMS`] already (`E0219`).
    fn declare(&mut self, param: Param, whole: Span) -> Option<ParamId> {
        if self.params.len() == MAX_PARAMS {
            self.error(
                Diagnostic::error(
                    Code::TooManyParams,
                    format!("more than {MAX_PARAMS} runtime parameters"),
                    whole,
                    format!("parameter {} is one too many", MAX_PARAMS + 1),
                )
                .with_help("fold the values that never change into literals"),
            );
            return None;
        }
        let id = ParamId(self.params.len() as u16);
        self.param_ids.insert(param.name.clone(), id);
        self.params.push(param);
        self.param_spans.push(whole);
        Some(id)
    }

    /// A layer's `normal: NormalMap("texture", uv_scale, detail: "texture", detail_scale)`;
    /// `None` if it is malformed (reported), else remembered for `layers`.
    fn normal_map(&mut self, v: Option<&Spanned<Value>>) -> Option<()> {
        let Some(v) = v else { return Some(()) };
        let (name, args) = self.constructor(v, "normal map", &["NormalMap"])?;
        let f = self.fields(name, args, v.span, NORMAL_MAP_FIELDS);
        let texture = f.get(0).and_then(|t| self.identifier(t, "texture"));
        let uv_scale = f.get(1).map_or(Some(1.0), |x| self.uv_scale(x));
        let detail = f.get(2).map(|t| self.identifier(t, "texture"));
        let detail_scale = f.get(3).map_or(Some(1.0), |x| self.uv_scale(x));
        let detail = match detail {
            Some(t) => Some((t?, detail_scale?)),
            None => None,
        };
        self.layer_normal = Some((NormalMap { texture: texture?, uv_scale: uv_scale?, detail }, v.span));
        Some(())
    }

    /// At most [`MAX_TEXTURES`] textures, counting normal maps (E0220 at the first one too many).
    fn texture_count(&mut self, material: &Material) -> Option<()> {
        let textures = material.textures();
        if textures.len() <= MAX_TEXTURES {
            return Some(());
        }
        let extra = textures[MAX_TEXTURES];
        let span = self.normals.iter().find(|(_, m, _)| m.textures().any(|t| t == extra)).map(|(_, _, s)| *s);
        let Some(span) = span else { return Some(()) }; // (texture reads are counted as they are read)
        self.error(
            Diagnostic::error(
                Code::TooManyTextures,
                format!("more than {MAX_TEXTURES} textures"),
                span,
                format!("texture `{extra}` is one too many"),
            )
            .with_help("pack scalar maps into the channels of one texture (R, G, B, A)"),
        );
        None
    }

    /// A channel `R`, `G`, `B`, `A` or (in a colour slot) `Rgb`.
    fn channel(&mut self, v: &Spanned<Value>, color_slot: bool) -> Option<Channel> {
        let (name, args) = self.constructor(v, "texture channel", Channel::NAMES)?;
        self.no_arguments(name, args, v.span);
        let channel = Channel::ALL.into_iter().find(|c| Channel::NAMES[*c as usize] == name.node)?;
        if channel == Channel::Rgb && !color_slot {
            self.wrong_type(
                v,
                "one channel (R, G, B or A)",
                Some("this slot takes one number; read one channel of the texture"),
            );
            return None;
        }
        Some(channel)
    }

    /// `uv_scale`: a positive number of repeats.
    fn uv_scale(&mut self, v: &Spanned<Value>) -> Option<f32> {
        let x = match v.node {
            Value::Number(x) => x,
            _ => {
                self.wrong_type(v, "a number", Some("uv_scale is how often the texture repeats across the surface"));
                return None;
            }
        };
        if !(x.is_finite() && x > 0.0 && x <= 1e6) {
            self.error(
                Diagnostic::error(
                    Code::TextureRange,
                    "uv_scale must be a positive number",
                    v.span,
                    "must lie in (0, 10⁶]",
                )
                .with_help("uv_scale is how often the texture repeats across uv ∈ [0, 1]; 1 maps it once"),
            );
            return None;
        }
        Some(x as f32)
    }

    /// `range: (lo, hi)`: the slot's values at texel values 0 and 1; both inside the slot's range.
    fn texture_range(&mut self, v: &Spanned<Value>, rule: Rule) -> Option<[f32; 2]> {
        match &v.node {
            Value::Call { name: None, args: Some(items) }
                if items.len() == 2 && items.iter().all(|a| a.name.is_none()) =>
            {
                let lo = self.number(&items[0].value, rule);
                let hi = self.number(&items[1].value, rule);
                Some([lo? as f32, hi? as f32])
            }
            _ => {
                self.wrong_type(
                    v,
                    "a pair `(lo, hi)`",
                    Some("range gives the slot's values at texel values 0 and 1, e.g. `range: (0.1, 0.6)`"),
                );
                None
            }
        }
    }

    /// A texel lies in [0, 1]: that is the range when the slot's own range is [0, 1]; any other
    /// slot must say how texels map onto it.
    fn default_texture_range(&mut self, whole: Span, rule: Rule) -> Option<[f32; 2]> {
        if rule.accepts(0.0) && rule.accepts(1.0) {
            return Some([0.0, 1.0]);
        }
        self.error(
            Diagnostic::error(
                Code::TextureRange,
                format!("a texture for the {} needs a `range`", rule.what()),
                whole,
                format!("texels lie in [0, 1]; the {} {}", rule.what(), rule.label()),
            )
            .with_help("map texel values onto the slot with `range: (lo, hi)`, e.g. `range: (1.3, 1.6)`"),
        );
        None
    }
}

enum Layer {
    Coat(Coat),
    Base(Base),
}

fn as_texture(v: &Spanned<Value>) -> Option<(&Spanned<String>, Option<&[Arg]>)> {
    match &v.node {
        Value::Call { name: Some(name), args } if name.node == "Texture" => Some((name, args.as_deref())),
        _ => None,
    }
}

fn as_param(v: &Spanned<Value>) -> Option<(&Spanned<String>, Option<&[Arg]>)> {
    match &v.node {
        Value::Call { name: Some(name), args } if name.node == "Param" => Some((name, args.as_deref())),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_text(text: &str) -> Result<Material, Vec<Diagnostic>> {
        let root = crate::parse::parse(text).map_err(|d| vec![d])?;
        check(&root).map(|(m, _)| m)
    }

    #[test]
    fn suggestions() {
        assert_eq!(suggest("rougness", &["roughness", "ior"]), Some("roughness"));
        assert_eq!(suggest("ggx", Lobe::NAMES), Some("Ggx"));
        assert_eq!(suggest("zzz", Lobe::NAMES), None);
    }

    #[test]
    fn a_full_material() {
        let m = check_text(
            r#"Material(name: "clay", method: WeidlichWilkie, layers: [
                Coat(lobe: Ggx(Param("coat_roughness", 0.3)), ior: 1.5, absorption: 0.8, thickness: 0.1),
                OrenNayar(albedo: Param("tint", (0.8, 0.5, 0.3)), roughness: 0.5),
            ])"#,
        )
        .expect("valid");
        assert_eq!(m.method, Method::WeidlichWilkie);
        assert_eq!(m.params.len(), 2);
        assert_eq!(m.coats[0].absorption, Color::Lit([0.8; 3]));
        assert_eq!(m.coats[0].lobe, Lobe::Ggx { roughness: Scalar::Param(ParamId(0)) });
    }

    #[test]
    fn interfaced_approximations() {
        let method = |m: &str| check_text(&format!(r#"Material(name: "m", method: {m}, layers: [Lambert(0.5)])"#));
        assert_eq!(method("Interfaced").expect("valid").method, Method::INTERFACED);
        assert_eq!(method("Interfaced()").expect("valid").method, Method::INTERFACED);
        assert_eq!(method("Interfaced(fresnel: Schlick)").expect("valid").method, Method::INTERFACED_SCHLICK);
        assert_eq!(
            method("Interfaced(multiple_scattering: false)").expect("valid").method,
            Method::INTERFACED_SINGLE_SCATTERING
        );
        for m in Method::MEASURED {
            assert_eq!(method(&m.source()).expect("valid").method, m, "{}", m.source());
        }
        let codes = |m: &str| method(m).unwrap_err().iter().map(|d| d.code).collect::<Vec<_>>();
        assert_eq!(codes("Interfaced(fresnel: Schlik)"), [Code::UnknownVariant]);
        assert_eq!(codes("Interfaced(multiple_scattering: 0)"), [Code::WrongType]);
        assert_eq!(codes("Interfaced(fresnell: Exact)"), [Code::UnknownField]);
        assert_eq!(codes("Additive(fresnel: Schlick)"), [Code::BadArguments]);
    }

    #[test]
    fn all_errors_are_reported() {
        let errors = check_text(
            r#"Material(name: "Bad Name", layers: [
                Coat(lobe: Ggx(roughness: 1.5), ior: -1, absorption: -0.1),
                Lambert(albedo: 2),
            ])"#,
        )
        .unwrap_err();
        let codes: Vec<Code> = errors.iter().map(|d| d.code).collect();
        assert_eq!(
            codes,
            [Code::BadName, Code::RoughnessRange, Code::IorRange, Code::NegativeMedium, Code::AlbedoRange]
        );
    }

    #[test]
    fn shared_parameters() {
        let m = check_text(
            r#"Material(name: "m", layers: [
                Coat(lobe: Ggx(Param("r", 0.3)), ior: 1.5),
                Conductor(roughness: Param("r", 0.3), f0: 0.9),
            ])"#,
        )
        .expect("same name, type and default is one parameter");
        assert_eq!(m.params.len(), 1);
        let errors = check_text(
            r#"Material(name: "m", layers: [
                Coat(lobe: Ggx(Param("r", 0.3)), ior: 1.5),
                Lambert(Param("r", (0.3, 0.3, 0.3))),
            ])"#,
        )
        .unwrap_err();
        assert_eq!(errors[0].code, Code::ParamConflict);
        assert_eq!(errors[0].labels.len(), 2);
    }
}
