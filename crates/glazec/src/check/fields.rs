//! What a constructor accepts: each one's fields ([`FieldSpec`]), the names of enum-like values,
//! and the help texts built from them ("did you mean …", the valid names).

use crate::diag::Spanned;
use crate::parse::{Arg, Value};

/// One field of a constructor: its name, whether it must be present, and an example value for
/// the "missing field" help line.
pub(super) struct FieldSpec {
    pub(super) name: &'static str,
    pub(super) required: bool,
    pub(super) example: &'static str,
}

pub(super) const fn req(name: &'static str, example: &'static str) -> FieldSpec {
    FieldSpec { name, required: true, example }
}

pub(super) const fn opt(name: &'static str, example: &'static str) -> FieldSpec {
    FieldSpec { name, required: false, example }
}

pub(super) const MATERIAL_FIELDS: &[FieldSpec] =
    &[req("name", "\"clay\""), opt("method", "Interfaced"), req("layers", "[Lambert(albedo: 0.5)]")];

pub(super) const COAT_FIELDS: &[FieldSpec] = &[
    req("lobe", "Ggx(roughness: 0.2)"),
    req("ior", "1.5"),
    opt("absorption", "(0.1, 0.2, 0.4)"),
    opt("thickness", "0.5"),
    opt("normal", "NormalMap(\"clay_normal\", 1.0)"),
];

pub(super) const ROUGH_LOBE_FIELDS: &[FieldSpec] = &[req("roughness", "0.2")];

pub(super) const LAMBERT_FIELDS: &[FieldSpec] =
    &[req("albedo", "(0.8, 0.5, 0.3)"), opt("normal", "NormalMap(\"clay_normal\", 1.0)")];

pub(super) const ROUGH_DIFFUSE_FIELDS: &[FieldSpec] =
    &[req("albedo", "(0.8, 0.5, 0.3)"), req("roughness", "0.5"), opt("normal", "NormalMap(\"clay_normal\", 1.0)")];

pub(super) const CONDUCTOR_FIELDS: &[FieldSpec] = &[
    req("roughness", "0.3"),
    opt("f0", "(0.95, 0.64, 0.54)"),
    opt("eta", "(0.2, 0.92, 1.1)"),
    opt("k", "(3.9, 2.45, 2.14)"),
    opt("normal", "NormalMap(\"clay_normal\", 1.0)"),
];

pub(super) const PLASTIC_FIELDS: &[FieldSpec] = &[
    req("albedo", "(0.8, 0.1, 0.1)"),
    req("roughness", "0.3"),
    req("ior", "1.5"),
    opt("normal", "NormalMap(\"clay_normal\", 1.0)"),
];

pub(super) const NORMAL_MAP_FIELDS: &[FieldSpec] = &[
    req("texture", "\"clay_normal\""),
    opt("uv_scale", "1.0"),
    opt("detail", "\"clay_pores\""),
    opt("detail_scale", "8.0"),
];

pub(super) const INTERFACED_FIELDS: &[FieldSpec] = &[opt("fresnel", "Schlick"), opt("multiple_scattering", "false")];

pub(super) const FRESNEL_NAMES: &[&str] = &["Exact", "Schlick"];

pub(super) const PARAM_FIELDS: &[FieldSpec] = &[req("name", "\"roughness\""), req("default", "0.5")];

pub(super) const TEXTURE_FIELDS: &[FieldSpec] =
    &[req("name", "\"clay_maps\""), req("channel", "R"), opt("uv_scale", "1.0"), opt("range", "(0.0, 1.0)")];

pub(super) const LAYER_NAMES: &[&str] = &["Coat", "Lambert", "OrenNayar", "Eon", "Conductor", "Plastic", "Measured"];

/// The arguments of one constructor call, mapped onto its field list.
pub(super) struct Fields<'v> {
    pub(super) values: Vec<Option<&'v Spanned<Value>>>,
}

impl<'v> Fields<'v> {
    pub(super) fn get(&self, index: usize) -> Option<&'v Spanned<Value>> {
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

pub(super) fn one_of(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// A number as a message shows it: plain for everyday magnitudes, scientific otherwise.
pub(super) fn show_number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") }
}

pub(super) fn as_texture(v: &Spanned<Value>) -> Option<(&Spanned<String>, Option<&[Arg]>)> {
    match &v.node {
        Value::Call { name: Some(name), args } if name.node == "Texture" => Some((name, args.as_deref())),
        _ => None,
    }
}

pub(super) fn as_param(v: &Spanned<Value>) -> Option<(&Spanned<String>, Option<&[Arg]>)> {
    match &v.node {
        Value::Call { name: Some(name), args } if name.node == "Param" => Some((name, args.as_deref())),
        _ => None,
    }
}
