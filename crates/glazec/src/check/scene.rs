//! Checking scene files (see [`crate::scene`]): the same machinery and diagnostics as materials
//! (unknown, missing and duplicate fields, wrong types, `did you mean`), plus the scene's own
//! ranges (`E0301`) and `Range(lo, hi)` order (`E0302`).

use super::checker::Checker;
use super::fields::{FieldSpec, opt, req};
use super::rules::Rule;
use crate::diag::{Code, Diagnostic, Span, Spanned};
use crate::model::{Material, ParamValue};
use crate::parse::Value;
use crate::scene::{DISPLAY_TOLERANCE, Light, ParamDomain, Scene, SceneParam, Tolerance};

const SCENE_FIELDS: &[FieldSpec] = &[
    req("name", "\"studio\""),
    req("lights", "[Directional(irradiance: (2.4, 2.3, 2.1))]"),
    opt("environment", "Uniform(radiance: (0.3, 0.35, 0.45))"),
    opt("view", "(max_angle: 75)"),
    opt("light_directions", "(max_angle: 90)"),
    opt("params", "{\"glaze_ior\": Pinned(1.5)}"),
    opt("tolerance", "Display"),
    opt("exposure", "1.0"),
];
const DIRECTIONAL_FIELDS: &[FieldSpec] = &[req("irradiance", "(2.4, 2.3, 2.1)")];
const POINT_FIELDS: &[FieldSpec] = &[req("intensity", "(4.0, 4.0, 4.0)"), req("min_distance", "2.0")];
const UNIFORM_FIELDS: &[FieldSpec] = &[req("radiance", "(0.3, 0.35, 0.45)")];
const CONE_FIELDS: &[FieldSpec] = &[req("max_angle", "75")];
const PINNED_FIELDS: &[FieldSpec] = &[req("value", "1.5")];
const RANGE_FIELDS: &[FieldSpec] = &[req("lo", "0.1"), req("hi", "0.4")];
const AMOUNT_FIELDS: &[FieldSpec] = &[req("amount", "0.01")];

/// Checks a parsed scene file.
///
/// # Errors
/// Every problem found, in source order.
pub fn check_scene(root: &Spanned<Value>) -> Result<Scene, Vec<Diagnostic>> {
    let mut checker = Checker::default();
    let scene = checker.scene(root);
    checker.errors.sort_by_key(|d| d.primary_span().start);
    match scene {
        Some(scene) if checker.errors.is_empty() => Ok(scene),
        _ => Err(checker.errors),
    }
}

impl Checker {
    fn scene(&mut self, root: &Spanned<Value>) -> Option<Scene> {
        let (ctor, args) = self.constructor(root, "top-level item", &["Scene"])?;
        let f = self.fields(ctor, args, root.span, SCENE_FIELDS);
        let name = f.get(0).and_then(|v| self.identifier(v, "scene"));
        let lights = f.get(1).and_then(|v| self.lights(v));
        let environment = match f.get(2) {
            Some(v) => self.environment(v),
            None => Some(None),
        };
        let view = f.get(3).map_or(Some(90.0), |v| self.cone(v, "view"));
        let light = f.get(4).map_or(Some(90.0), |v| self.cone(v, "light_directions"));
        let params = f.get(5).map_or(Some(Vec::new()), |v| self.scene_params(v));
        let tolerance = f.get(6).map_or(Some(Tolerance::Display(DISPLAY_TOLERANCE)), |v| self.tolerance(v));
        let exposure = f.get(7).map_or(Some(1.0), |v| self.number(v, Rule::Exposure).map(|x| x as f32));
        Some(Scene {
            name: name?,
            lights: lights?,
            environment: environment?,
            view_max_angle: view?,
            light_max_angle: light?,
            params: params?,
            tolerance: tolerance?,
            exposure: exposure?,
        })
    }

    fn lights(&mut self, v: &Spanned<Value>) -> Option<Vec<Light>> {
        let Value::List(items) = &v.node else {
            self.wrong_type(v, "a list of lights", Some("write `lights: [Directional(irradiance: 2.0)]`, or `[]`"));
            return None;
        };
        let lights: Vec<Option<Light>> = items.iter().map(|item| self.light(item)).collect();
        lights.into_iter().collect()
    }

    fn light(&mut self, v: &Spanned<Value>) -> Option<Light> {
        let (ctor, args) = self.constructor(v, "light", &["Directional", "Point"])?;
        if ctor.node == "Directional" {
            let f = self.fields(ctor, args, v.span, DIRECTIONAL_FIELDS);
            let irradiance = f.get(0).and_then(|v| self.rgb(v, Rule::LightAmount));
            return Some(Light::Directional { irradiance: irradiance? });
        }
        let f = self.fields(ctor, args, v.span, POINT_FIELDS);
        let intensity = f.get(0).and_then(|v| self.rgb(v, Rule::LightAmount));
        let distance = f.get(1).and_then(|v| self.number(v, Rule::Distance));
        Some(Light::Point { intensity: intensity?, min_distance: distance? as f32 })
    }

    /// `None` or `Uniform(radiance: …)`.
    fn environment(&mut self, v: &Spanned<Value>) -> Option<Option<[f32; 3]>> {
        let (ctor, args) = self.constructor(v, "environment", &["None", "Uniform"])?;
        if ctor.node == "None" {
            return Some(None);
        }
        let f = self.fields(ctor, args, v.span, UNIFORM_FIELDS);
        f.get(0).and_then(|v| self.rgb(v, Rule::LightAmount)).map(Some)
    }

    /// `(max_angle: degrees)`.
    fn cone(&mut self, v: &Spanned<Value>, what: &str) -> Option<f32> {
        let Value::Call { name: None, args } = &v.node else {
            self.wrong_type(v, "`(max_angle: degrees)`", Some("e.g. `(max_angle: 75)`: up to 75° from the normal"));
            return None;
        };
        let ctor = Spanned::new(what.to_string(), v.span);
        let f = self.fields(&ctor, args.as_deref(), v.span, CONE_FIELDS);
        f.get(0).and_then(|v| self.number(v, Rule::Angle)).map(|x| x as f32)
    }

    fn scene_params(&mut self, v: &Spanned<Value>) -> Option<Vec<SceneParam>> {
        let Value::Map(entries) = &v.node else {
            self.wrong_type(v, "a map of parameters", Some("write `params: {\"glaze_ior\": Pinned(1.5)}`"));
            return None;
        };
        let mut params = Vec::new();
        let mut ok = true;
        for (key, value) in entries {
            let name = self.string(key).map(str::to_string);
            if let Some(previous) = params.iter().find(|p: &&SceneParam| Some(&p.name) == name.as_ref()) {
                let first = previous.span;
                self.error(
                    Diagnostic::error(Code::DuplicateField, "a parameter is set twice", key.span, "set again here")
                        .with_secondary(first, "first set here")
                        .with_help("remove one of them"),
                );
                ok = false;
                continue;
            }
            match (name, self.param_domain(value)) {
                (Some(name), Some(domain)) => params.push(SceneParam { name, domain, span: key.span }),
                _ => ok = false,
            }
        }
        ok.then_some(params)
    }

    /// `Pinned(value)` or `Range(lo, hi)`, each a number or an RGB triple.
    fn param_domain(&mut self, v: &Spanned<Value>) -> Option<ParamDomain> {
        let (ctor, args) = self.constructor(v, "parameter domain", &["Pinned", "Range"])?;
        if ctor.node == "Pinned" {
            let f = self.fields(ctor, args, v.span, PINNED_FIELDS);
            return f.get(0).and_then(|v| self.scene_value(v)).map(ParamDomain::Pinned);
        }
        let f = self.fields(ctor, args, v.span, RANGE_FIELDS);
        let lo = f.get(0).and_then(|v| self.scene_value(v));
        let hi = f.get(1).and_then(|v| self.scene_value(v));
        let (lo, hi) = (lo?, hi?);
        let ordered = match (lo, hi) {
            (ParamValue::Scalar(a), ParamValue::Scalar(b)) => a <= b,
            (ParamValue::Rgb(a), ParamValue::Rgb(b)) => a.iter().zip(&b).all(|(a, b)| a <= b),
            _ => {
                let span = f.get(1).map_or(v.span, |v| v.span);
                self.wrong_type_at(span, "the same kind of value as `lo`", "give both ends as numbers or both as RGB");
                return None;
            }
        };
        if !ordered {
            self.error(
                Diagnostic::error(Code::RangeOrder, "the range's low end is above its high end", v.span, "lo > hi")
                    .with_help("write `Range(lo, hi)` with lo ≤ hi (per channel for colours)"),
            );
            return None;
        }
        Some(ParamDomain::Range(lo, hi))
    }

    fn scene_value(&mut self, v: &Spanned<Value>) -> Option<ParamValue> {
        match &v.node {
            Value::Number(_) => self.number(v, Rule::SceneValue).map(|x| ParamValue::Scalar(x as f32)),
            _ => self.rgb(v, Rule::SceneValue).map(ParamValue::Rgb),
        }
    }

    fn wrong_type_at(&mut self, span: Span, expected: &str, help: &str) {
        self.error(Diagnostic::error(Code::WrongType, format!("expected {expected}"), span, expected).with_help(help));
    }

    /// `Display`, `Display(x)`, `Relative(r)` or `DeltaE(x)`.
    fn tolerance(&mut self, v: &Spanned<Value>) -> Option<Tolerance> {
        let (ctor, args) = self.constructor(v, "tolerance", &["Display", "Relative", "DeltaE"])?;
        if ctor.node == "Display" && args.is_none() {
            return Some(Tolerance::Display(DISPLAY_TOLERANCE));
        }
        let f = self.fields(ctor, args, v.span, AMOUNT_FIELDS);
        let rule = if ctor.node == "DeltaE" { Rule::DeltaE } else { Rule::Tolerance };
        let amount = f.get(0).and_then(|v| self.number(v, rule))? as f32;
        Some(match ctor.node.as_str() {
            "Display" => Tolerance::Display(amount),
            "Relative" => Tolerance::Relative(amount),
            _ => Tolerance::DeltaE(amount),
        })
    }
}

/// `E0303` for each parameter the scene sets that none of `materials` has.
pub fn check_scene_params(scene: &Scene, materials: &[&Material]) -> Vec<Diagnostic> {
    let names: Vec<&str> = materials.iter().flat_map(|m| m.params.iter().map(|p| p.name.as_str())).collect();
    scene
        .params
        .iter()
        .filter(|p| !names.contains(&p.name.as_str()))
        .map(|p| {
            let d = Diagnostic::error(
                Code::UnknownSceneParam,
                format!("no material compiled with this scene has a parameter `{}`", p.name),
                p.span,
                "not a parameter of any material here",
            );
            match crate::check::suggest(&p.name, &names) {
                Some(s) => d.with_help(format!("did you mean `{s}`?")),
                None if names.is_empty() => d.with_help("these materials have no runtime parameters"),
                None => d.with_help(format!("their parameters are {}", names.join(", "))),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_text(text: &str) -> Result<Scene, Vec<Diagnostic>> {
        check_scene(&crate::parse::parse(text).map_err(|d| vec![d])?)
    }

    #[test]
    fn a_full_scene_checks() {
        let scene = check_text(
            r#"Scene(name: "studio", lights: [Directional(irradiance: (2.4, 2.3, 2.1)), Point(intensity: 4.0, min_distance: 2.0)],
               environment: Uniform(radiance: 0.3), view: (max_angle: 75), params: {"ior": Pinned(1.5), "tint": Range(0.1, (0.2, 0.3, 0.4))},
               tolerance: Relative(0.02), exposure: 0.8)"#,
        );
        let errors = scene.expect_err("a scalar and an RGB end");
        assert_eq!(errors.iter().map(|d| d.code).collect::<Vec<_>>(), [Code::WrongType]);
        let scene = check_text(
            r#"Scene(name: "studio", lights: [Directional(irradiance: (2.4, 2.3, 2.1)), Point(intensity: 4.0, min_distance: 2.0)],
               environment: Uniform(radiance: 0.3), view: (max_angle: 75), params: {"ior": Pinned(1.5)}, tolerance: Display)"#,
        )
        .expect("checks");
        assert_eq!(scene.lights[1].max_irradiance(), [1.0; 3]);
        assert_eq!(scene.view_max_angle, 75.0);
        assert_eq!(scene.light_max_angle, 90.0);
        assert_eq!(scene.tolerance, Tolerance::Display(DISPLAY_TOLERANCE));
        assert_eq!(scene.params[0].domain, ParamDomain::Pinned(ParamValue::Scalar(1.5)));
    }

    #[test]
    fn scene_errors_have_codes() {
        let codes = |text: &str| check_text(text).expect_err("bad").iter().map(|d| d.code).collect::<Vec<_>>();
        assert_eq!(codes(r#"Scene(name: "s", lights: [], view: (max_angle: 120))"#), [Code::SceneRange]);
        assert_eq!(codes(r#"Scene(name: "s", lights: [], params: {"r": Range(0.5, 0.2)})"#), [Code::RangeOrder]);
        assert_eq!(codes(r#"Scene(name: "s", lights: [Directional(irradiance: -1)])"#), [Code::SceneRange]);
        assert_eq!(codes(r#"Scene(name: "s", lights: [Spot(cone: 3)])"#), [Code::UnknownVariant]);
        assert_eq!(codes(r#"Scene(name: "s", lights: [], tolerance: Relative(2))"#), [Code::SceneRange]);
        assert_eq!(codes(r#"Scene(name: "s", lights: [], tolerance: DeltaE(0))"#), [Code::SceneRange]);
        let scene = check_text(r#"Scene(name: "s", lights: [], tolerance: DeltaE(2.3))"#).expect("checks");
        assert_eq!(scene.tolerance, Tolerance::DeltaE(2.3));
        assert_eq!(codes(r#"Scene(name: "s", lights: [], exposur: 1)"#), [Code::UnknownField]);
        assert_eq!(codes(r#"Scene(lights: [])"#), [Code::MissingField]);
    }
}
