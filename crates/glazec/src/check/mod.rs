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

mod checker;
mod fields;
mod layers;
mod measured;
mod params;
mod rules;
mod scene;

pub use fields::suggest;
pub use scene::{check_scene, check_scene_params};

use crate::diag::{Diagnostic, Spanned};
use crate::model::*;
use crate::parse::Value;
use checker::Checker;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Code;

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

    #[test]
    fn a_parameter_knows_the_range_of_every_slot_it_fills() {
        let m = check_text(
            r#"Material(name: "m", layers: [
                Coat(lobe: Ggx(Param("r", 0.3)), ior: Param("eta", 1.5), absorption: Param("s", 0.2), thickness: Param("eta", 1.5)),
                Lambert(Param("tint", (0.3, 0.3, 0.3))),
            ])"#,
        )
        .expect("valid");
        let range = |name: &str| m.params.iter().find(|p| p.name == name).map(|p| p.range);
        assert_eq!(range("r"), Some([0.0, 1.0]));
        assert_eq!(range("tint"), Some([0.0, 1.0]));
        assert_eq!(range("s"), Some([0.0, 1e6]));
        // An IOR that is also a thickness: [0.1, 10] ∩ [0, 10⁶].
        assert_eq!(range("eta"), Some([0.1, 10.0]));
    }
}
