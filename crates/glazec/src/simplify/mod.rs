//! Stage 2½, `simplify` (between check and lower): the cheapest material a scene cannot tell
//! from the full one.
//!
//! **Input:** a checked [`Material`] and a [`Scene`]. **Output:** a material whose every
//! displayed value, over the scene's view directions, light directions and parameter values,
//! differs from the full material's by no more than the scene's tolerance, with a [`Report`] of
//! each change, its measured error and its cost saving.
//!
//! **The error of a candidate** is measured against the *original* material (never step to step,
//! so errors cannot accumulate unseen), with the CPU evaluator, on a deterministic set of
//! configurations ([`SampleSet::pass`]): view angles θo × light angles θi × azimuth differences
//! Δφ on a grid inside the scene's cones, plus the mirror configuration of every θo (where a
//! glossy lobe peaks), for each of a fixed set of parameter vectors (the scene's pinned values,
//! the ends of its ranges one at a time, and Halton points inside the box). At each
//! configuration the displayed difference is bounded by
//!
//! ```text
//!   ΔL = exposure · ( Σ_lights E_max · |Δf(wi, wo)| cos θi  +  L_env · ∫ |Δf(ω, wo)| cos θ dω )
//! ```
//!
//! per channel — conservative: it lets every light stand at the configuration's direction at once,
//! and the environment at its brightest everywhere (the integral by Gauss–Legendre in cos θ over
//! the light cone × uniform φ). A change is kept when max ΔL / allowed ≤ [`PASS_BUDGET`] of the
//! tolerance: a grid cannot see between its points, so half the tolerance is held back for what
//! it misses; the tests re-measure every result on a denser, different set, on the CPU and on
//! lavapipe, against the whole tolerance.
//!
//! **Changes tried** ([`Change`]), cheapest result first, one accepted per round until none fits:
//! fold parameters the scene pins (exact); cut everything below a coat (an opaque layer hides
//! it); drop a coat; drop a coat's absorption; replace an Oren–Nayar/EON/plastic base by
//! Lambert; use Schlick's Fresnel for a conductor; switch the layering method (`Interfaced`
//! with Schlick's Fresnel or without multiple scattering, `WeidlichWilkie`, `Additive`).
//! Cost is the static size of the shading code ([`crate::lower::static_cost`]: naga expressions
//! in the module's functions); a change is only tried if it lowers it. glazec's shaders carry
//! no environment code (lights are the caller's), so "drop the environment" has nothing to do.

mod domain;
mod report;
mod samples;

pub use domain::{ParameterDomain, natural_range, values_for};
pub use report::{Rejected, Report, Step};
pub use samples::{Evaluated, PASS_BUDGET, SampleSet, cpu_values, error_between};

use report::{base_name, coat_summary, scene_summary};

use glam::Vec3;

use crate::diag::Diagnostic;
use crate::model::{Base, Color, ConductorFresnel, Lobe, Material, Method, ParamId, ParamValue, Scalar};
use crate::scene::Scene;

/// One change of the material.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    FoldPinned(Vec<String>),
    CutBelow(usize),
    DropCoat(usize),
    DropAbsorption(usize),
    BaseToLambert,
    ConductorSchlick,
    Method(Method),
}

impl Change {
    pub fn describe(&self, material: &Material) -> String {
        match self {
            Change::FoldPinned(names) => format!("fold the pinned parameter(s) {}", names.join(", ")),
            Change::CutBelow(i) => format!("cut everything below coat {} (base → black Lambert)", i + 1),
            Change::DropCoat(i) => format!("drop coat {} ({})", i + 1, coat_summary(material, *i)),
            Change::DropAbsorption(i) => format!("drop the absorption of coat {}", i + 1),
            Change::BaseToLambert => format!("replace the {} base by Lambert", base_name(&material.base)),
            Change::ConductorSchlick => "conductor: Schlick's Fresnel with the exact F0".into(),
            Change::Method(m) => format!("layering method {}", m.source()),
        }
    }
}

/// Simplifies `material` for `scene`.
///
/// # Errors
/// Diagnostics against the scene file: a parameter the material does not have, or a value of
/// the wrong kind for it.
pub fn simplify(material: &Material, scene: &Scene) -> Result<(Material, Report), Vec<Diagnostic>> {
    let domain = ParameterDomain::new(material, scene)?;
    let samples = SampleSet::pass(scene, &domain);
    let reference = Evaluated::new(material, scene, &samples);
    let full_cost = cost(material);
    let mut current = material.clone();
    let mut current_cost = full_cost;
    let mut steps: Vec<Step> = Vec::new();
    let mut rejected = Vec::new();
    let pinned = domain.pinned_names();
    if !pinned.is_empty() {
        let folded = fold_pinned(&current, &domain);
        let after = cost(&folded);
        let error = reference.error(&folded, scene, &samples);
        steps.push(Step {
            change: Change::FoldPinned(pinned).describe(&current),
            error,
            cost_before: full_cost,
            cost_after: after,
        });
        current = folded;
        current_cost = after;
    }
    loop {
        let mut candidates: Vec<(usize, Change, Material)> = changes(&current)
            .into_iter()
            .filter_map(|change| apply(&current, &change).map(|m| (cost(&m), change, m)))
            .filter(|(c, _, _)| *c < current_cost)
            .collect();
        candidates.sort_by_key(|(c, _, _)| *c);
        let mut accepted = None;
        for (candidate_cost, change, candidate) in candidates {
            let error = reference.error(&candidate, scene, &samples);
            let text = change.describe(&current);
            if error <= PASS_BUDGET {
                accepted = Some((
                    candidate,
                    Step { change: text, error, cost_before: current_cost, cost_after: candidate_cost },
                ));
                break;
            }
            rejected.push(Rejected { change: text, error, cost: candidate_cost });
        }
        let Some((next, step)) = accepted else { break };
        // A change rejected earlier may fit now; only the last round's rejections are explained.
        rejected.clear();
        current_cost = step.cost_after;
        steps.push(step);
        current = next;
    }
    // Every step's error is measured against the original, so the last one is the result's.
    let final_error = steps.last().map_or(0.0, |s| s.error);
    let report = Report {
        material: material.name.clone(),
        scene: scene.name.clone(),
        scene_summary: scene_summary(scene),
        samples: samples.describe(),
        steps,
        rejected,
        full_cost,
        simplified_cost: current_cost,
        final_error,
    };
    Ok((current, report))
}

/// The static cost of a material's shader: naga expressions in its functions.
pub fn cost(material: &Material) -> usize {
    crate::lower::static_cost(&crate::lower::lower(material).module).0
}

/// The material with every pinned parameter folded to its value.
fn fold_pinned(material: &Material, domain: &ParameterDomain) -> Material {
    let mut m = material.clone();
    let fold_scalar = |s: &mut Scalar, params: &[crate::model::Param]| {
        if let Scalar::Param(id) = *s {
            if let Some(ParamValue::Scalar(x)) = domain.pinned(&params[id.0 as usize].name) {
                *s = Scalar::Lit(x);
            }
        }
    };
    let fold_color = |c: &mut Color, params: &[crate::model::Param]| {
        if let Color::Param(id) = *c {
            match domain.pinned(&params[id.0 as usize].name) {
                Some(ParamValue::Rgb(v)) => *c = Color::Lit(v),
                Some(ParamValue::Scalar(x)) => *c = Color::Lit([x; 3]),
                None => {}
            }
        }
    };
    let params = material.params.clone();
    for_each_slot(&mut m, &mut |slot| match slot {
        Slot::Scalar(s) => fold_scalar(s, &params),
        Slot::Color(c) => fold_color(c, &params),
    });
    prune_params(m)
}

/// A slot of a material, as [`for_each_slot`] visits it.
enum Slot<'a> {
    Scalar(&'a mut Scalar),
    Color(&'a mut Color),
}

/// Visits every scalar and colour slot of a material.
fn for_each_slot(m: &mut Material, visit: &mut dyn FnMut(Slot<'_>)) {
    for coat in &mut m.coats {
        match &mut coat.lobe {
            Lobe::Smooth => {}
            Lobe::Ggx { roughness } | Lobe::Gtr1 { roughness } => visit(Slot::Scalar(roughness)),
        }
        visit(Slot::Scalar(&mut coat.ior));
        visit(Slot::Color(&mut coat.absorption));
        visit(Slot::Scalar(&mut coat.thickness));
    }
    match &mut m.base {
        Base::Lambert { albedo } => visit(Slot::Color(albedo)),
        Base::OrenNayar { albedo, roughness } | Base::Eon { albedo, roughness } => {
            visit(Slot::Color(albedo));
            visit(Slot::Scalar(roughness));
        }
        Base::Conductor { roughness, fresnel } => {
            visit(Slot::Scalar(roughness));
            match fresnel {
                ConductorFresnel::F0(f0) => visit(Slot::Color(f0)),
                ConductorFresnel::Complex { eta, k } => {
                    visit(Slot::Color(eta));
                    visit(Slot::Color(k));
                }
            }
        }
        Base::Plastic { albedo, roughness, ior } => {
            visit(Slot::Color(albedo));
            visit(Slot::Scalar(roughness));
            visit(Slot::Scalar(ior));
        }
    }
}

/// The parameter a slot reads, if any.
fn slot_param(slot: &Slot<'_>) -> Option<ParamId> {
    match slot {
        Slot::Scalar(Scalar::Param(id)) | Slot::Color(Color::Param(id)) => Some(*id),
        _ => None,
    }
}

/// Removes parameters no slot uses any more, renumbering the rest (declaration order kept).
fn prune_params(mut m: Material) -> Material {
    let mut used = vec![false; m.params.len()];
    for_each_slot(&mut m, &mut |slot| {
        if let Some(id) = slot_param(&slot) {
            used[id.0 as usize] = true;
        }
    });
    let mut new_id = vec![None; used.len()];
    let mut next = 0u16;
    for (i, u) in used.iter().enumerate() {
        if *u {
            new_id[i] = Some(ParamId(next));
            next += 1;
        }
    }
    for_each_slot(&mut m, &mut |slot| match slot {
        Slot::Scalar(Scalar::Param(id)) | Slot::Color(Color::Param(id)) => *id = new_id[id.0 as usize].unwrap_or(*id),
        _ => {}
    });
    let mut i = 0;
    m.params.retain(|_| {
        i += 1;
        used[i - 1]
    });
    m
}

// ---------------------------------------------------------------------------------------------
// Changes

/// The changes that apply to `m`.
fn changes(m: &Material) -> Vec<Change> {
    let mut out = Vec::new();
    for i in 0..m.coats.len() {
        if i + 1 < m.coats.len() || !is_black(&m.base) {
            out.push(Change::CutBelow(i));
        }
        out.push(Change::DropCoat(i));
        if m.coats[i].absorption != Color::Lit([0.0; 3]) {
            out.push(Change::DropAbsorption(i));
        }
    }
    if matches!(m.base, Base::OrenNayar { .. } | Base::Eon { .. } | Base::Plastic { .. }) {
        out.push(Change::BaseToLambert);
    }
    if let Base::Conductor { fresnel: ConductorFresnel::Complex { eta: Color::Lit(_), k: Color::Lit(_) }, .. } = m.base
    {
        out.push(Change::ConductorSchlick);
    }
    for method in
        [Method::INTERFACED_SCHLICK, Method::INTERFACED_SINGLE_SCATTERING, Method::WeidlichWilkie, Method::Additive]
    {
        if method != m.method {
            out.push(Change::Method(method));
        }
    }
    out
}

fn is_black(base: &Base) -> bool {
    matches!(base, Base::Lambert { albedo: Color::Lit([0.0, 0.0, 0.0]) })
}

/// `m` with `change` made, or `None` if it does not apply.
fn apply(m: &Material, change: &Change) -> Option<Material> {
    let mut out = m.clone();
    match change {
        Change::FoldPinned(_) => return None,
        Change::CutBelow(i) => {
            out.coats.truncate(i + 1);
            out.base = Base::Lambert { albedo: Color::Lit([0.0; 3]) };
        }
        Change::DropCoat(i) => {
            out.coats.remove(*i);
        }
        Change::DropAbsorption(i) => {
            out.coats[*i].absorption = Color::Lit([0.0; 3]);
        }
        Change::BaseToLambert => {
            let albedo = match m.base {
                Base::OrenNayar { albedo, .. } | Base::Eon { albedo, .. } | Base::Plastic { albedo, .. } => albedo,
                _ => return None,
            };
            out.base = Base::Lambert { albedo };
        }
        Change::ConductorSchlick => {
            let Base::Conductor {
                roughness,
                fresnel: ConductorFresnel::Complex { eta: Color::Lit(eta), k: Color::Lit(k) },
            } = m.base
            else {
                return None;
            };
            // The exact conductor Fresnel at normal incidence (the shared term, on f32).
            let f0 = crate::math::terms::fr_conductor(1.0, Vec3::from(eta), Vec3::from(k)).to_array();
            out.base = Base::Conductor { roughness, fresnel: ConductorFresnel::F0(Color::Lit(f0)) };
        }
        Change::Method(method) => out.method = *method,
    }
    Some(prune_params(out))
}

// ---------------------------------------------------------------------------------------------
// Measuring

#[cfg(test)]
mod tests {
    use super::samples::direction;
    use super::*;
    use crate::diag::Code;

    fn scene(text: &str) -> Scene {
        crate::check::check_scene(&crate::parse::parse(text).expect("parses")).expect("checks")
    }

    fn glaze() -> Material {
        crate::load(
            r#"Material(name: "g", layers: [
                Coat(lobe: Ggx(roughness: Param("rough", 0.2)), ior: Param("ior", 1.5), absorption: Param("tint", (0.1, 0.2, 0.3)), thickness: 0.5),
                Lambert(albedo: Param("body", (0.5, 0.4, 0.3))),
            ])"#,
        )
        .expect("loads")
        .0
    }

    #[test]
    fn folding_pinned_parameters_renumbers_the_rest_and_is_exact() {
        let m = glaze();
        let s = scene(
            r#"Scene(name: "s", lights: [Directional(irradiance: 1)], params: {"ior": Pinned(1.4), "rough": Pinned(0.3)})"#,
        );
        let domain = ParameterDomain::new(&m, &s).expect("domain");
        let folded = fold_pinned(&m, &domain);
        assert_eq!(folded.params.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(), ["tint", "body"]);
        assert_eq!(folded.coats[0].ior, Scalar::Lit(1.4));
        assert_eq!(folded.coats[0].absorption, Color::Param(ParamId(0)));
        assert_eq!(folded.base, Base::Lambert { albedo: Color::Param(ParamId(1)) });
        // Same values as the full material at the pinned values.
        let (wi, wo) = (direction(30.0, 1.0), direction(50.0, 0.0));
        let full_values = [
            ParamValue::Scalar(0.3),
            ParamValue::Scalar(1.4),
            ParamValue::Rgb([0.1, 0.2, 0.3]),
            ParamValue::Rgb([0.5, 0.4, 0.3]),
        ];
        let folded_values = [ParamValue::Rgb([0.1, 0.2, 0.3]), ParamValue::Rgb([0.5, 0.4, 0.3])];
        assert_eq!(crate::eval::brdf(&m, &full_values, wi, wo), crate::eval::brdf(&folded, &folded_values, wi, wo));
    }

    #[test]
    fn a_value_outside_the_slots_range_is_e0305() {
        let m = glaze();
        for params in [r#"{"rough": Pinned(1.5)}"#, r#"{"ior": Range(1.2, 12.0)}"#, r#"{"ior": Pinned(0.05)}"#] {
            let s = scene(&format!(r#"Scene(name: "s", lights: [], params: {params})"#));
            let errors = ParameterDomain::new(&m, &s).expect_err(params);
            assert_eq!(errors.iter().map(|d| d.code).collect::<Vec<_>>(), [Code::SceneParamRange], "{params}");
        }
        let s = scene(r#"Scene(name: "s", lights: [], params: {"rough": Range(0.0, 1.0), "ior": Pinned(10.0)})"#);
        assert!(ParameterDomain::new(&m, &s).is_ok(), "the ends of the accepted ranges are accepted");
    }

    #[test]
    fn a_colour_for_a_scalar_parameter_is_e0304_and_unknown_names_are_e0303() {
        let m = glaze();
        let s =
            scene(r#"Scene(name: "s", lights: [], params: {"ior": Pinned((1.4, 1.5, 1.6)), "roughh": Pinned(0.3)})"#);
        let errors = ParameterDomain::new(&m, &s).expect_err("a colour for the IOR");
        assert_eq!(errors.iter().map(|d| d.code).collect::<Vec<_>>(), [Code::SceneParamType]);
        let unknown = crate::check::check_scene_params(&s, &[&m]);
        assert_eq!(unknown.len(), 1);
        assert_eq!(unknown[0].code, Code::UnknownSceneParam);
        assert!(unknown[0].notes.iter().any(|n| n.contains("did you mean `rough`?")), "{:?}", unknown[0].notes);
    }

    #[test]
    fn free_parameters_span_their_slot_and_vectors_cover_the_ends() {
        let m = glaze();
        assert_eq!(natural_range(&m, ParamId(1)), (1.0, 3.0));
        assert_eq!(natural_range(&m, ParamId(0)), (0.0, 1.0));
        assert_eq!(natural_range(&m, ParamId(2)), (0.0, 2.0));
        let s = scene(r#"Scene(name: "s", lights: [], params: {"rough": Range(0.1, 0.3)})"#);
        let vectors = ParameterDomain::new(&m, &s).expect("domain").vectors(0, 0);
        let roughness: Vec<f32> = vectors
            .iter()
            .map(|v| match v[0].1 {
                ParamValue::Scalar(x) => x,
                ParamValue::Rgb(_) => f32::NAN,
            })
            .collect();
        assert!(
            roughness.contains(&0.1) && roughness.contains(&0.3) && roughness.iter().all(|r| (0.1..=0.3).contains(r))
        );
    }

    #[test]
    fn the_error_sees_a_dropped_coat_and_not_an_unchanged_material() {
        let m = glaze();
        let s = scene(r#"Scene(name: "s", lights: [Directional(irradiance: 1)])"#);
        let domain = ParameterDomain::new(&m, &s).expect("domain");
        let samples = SampleSet::pass(&s, &domain);
        let reference = Evaluated::new(&m, &s, &samples);
        assert_eq!(reference.error(&m, &s, &samples), 0.0);
        let dropped = apply(&m, &Change::DropCoat(0)).expect("applies");
        assert!(reference.error(&dropped, &s, &samples) > 10.0);
    }

    #[test]
    fn a_delta_e_tolerance_measures_colour_differences() {
        let m = glaze();
        let strict = scene(r#"Scene(name: "s", lights: [Directional(irradiance: 1)], tolerance: DeltaE(0.5))"#);
        let loose = scene(r#"Scene(name: "s", lights: [Directional(irradiance: 1)], tolerance: DeltaE(50))"#);
        let dropped = apply(&m, &Change::DropCoat(0)).expect("applies");
        let error = |s: &Scene| {
            let domain = ParameterDomain::new(&m, s).expect("domain");
            let samples = SampleSet::pass(s, &domain);
            Evaluated::new(&m, s, &samples).error(&dropped, s, &samples)
        };
        // The same difference is 100× the share of a 100× stricter ΔE.
        let (e_strict, e_loose) = (error(&strict), error(&loose));
        assert!(e_strict > 1.0 && (e_strict / e_loose - 100.0).abs() < 1e-2, "{e_strict} vs {e_loose}");
        // The pass runs under a ΔE tolerance like under the others: whatever it keeps is within budget.
        let pinned = scene(
            r#"Scene(name: "s", lights: [Directional(irradiance: 1)], tolerance: DeltaE(50),
               params: {"rough": Pinned(0.2), "ior": Pinned(1.5), "tint": Pinned((0.1, 0.2, 0.3)), "body": Pinned((0.5, 0.4, 0.3))})"#,
        );
        let (_, report) = simplify(&m, &pinned).expect("simplifies");
        assert!(report.final_error <= PASS_BUDGET && report.simplified_cost < report.full_cost, "{report:?}");
    }
}
