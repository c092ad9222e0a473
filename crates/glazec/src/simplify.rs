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

use std::fmt::Write as _;

use glam::Vec3;

use crate::diag::{Code, Diagnostic};
use crate::math::sampling::radical_inverse;
use crate::model::{Base, Color, ConductorFresnel, Lobe, Material, Method, ParamId, ParamValue, Scalar};
use crate::scene::{ParamDomain, Scene};

/// The share of the tolerance a change may spend on the pass's own sample set.
pub const PASS_BUDGET: f32 = 0.5;

/// View angles of the pass's grid (from 0 to the scene's largest).
const PASS_VIEW_ANGLES: usize = 10;
/// Light angles of the pass's grid.
const PASS_LIGHT_ANGLES: usize = 12;
/// Azimuth differences of the pass's grid, over [0, π] (every BRDF here is isotropic).
const PASS_AZIMUTHS: usize = 9;
/// Halton points in the parameter box, besides the pinned values and range ends.
const PASS_PARAM_POINTS: usize = 6;
/// Environment quadrature: Gauss–Legendre nodes in cos θ, uniform nodes in φ.
const ENV_COS_NODES: usize = 16;
const ENV_AZIMUTHS: usize = 24;
/// The largest angle evaluated: f · cos θ vanishes at 90°, and directions exactly in the tangent
/// plane are outside every BRDF's domain.
const MAX_ANGLE_DEG: f32 = 89.5;

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

fn coat_summary(material: &Material, i: usize) -> String {
    let coat = &material.coats[i];
    let lobe = match coat.lobe {
        Lobe::Smooth => "smooth".to_string(),
        Lobe::Ggx { roughness } => format!("GGX {}", scalar_text(material, roughness)),
        Lobe::Gtr1 { roughness } => format!("GTR1 {}", scalar_text(material, roughness)),
    };
    format!("{lobe}, IOR {}", scalar_text(material, coat.ior))
}

fn scalar_text(material: &Material, s: Scalar) -> String {
    match s {
        Scalar::Lit(x) => format!("{x}"),
        Scalar::Param(id) => format!("`{}`", material.params[id.0 as usize].name),
    }
}

fn base_name(base: &Base) -> &'static str {
    match base {
        Base::Lambert { .. } => "Lambert",
        Base::OrenNayar { .. } => "Oren–Nayar",
        Base::Eon { .. } => "EON",
        Base::Conductor { .. } => "conductor",
        Base::Plastic { .. } => "plastic",
    }
}

/// One accepted change.
#[derive(Clone, Debug)]
pub struct Step {
    pub change: String,
    /// max ΔL / allowed against the original material, on the pass's sample set.
    pub error: f32,
    pub cost_before: usize,
    pub cost_after: usize,
}

/// A change that was tried and not kept.
#[derive(Clone, Debug)]
pub struct Rejected {
    pub change: String,
    pub error: f32,
    pub cost: usize,
}

/// What `simplify` did, and why.
#[derive(Clone, Debug)]
pub struct Report {
    pub material: String,
    pub scene: String,
    pub scene_summary: String,
    pub samples: String,
    pub steps: Vec<Step>,
    pub rejected: Vec<Rejected>,
    pub full_cost: usize,
    pub simplified_cost: usize,
    /// max ΔL / allowed of the result, on the pass's sample set.
    pub final_error: f32,
}

impl Report {
    /// The report as Markdown; `explain` adds the changes that were tried and not kept.
    pub fn markdown(&self, explain: bool) -> String {
        let mut out = format!("# `{}` simplified for scene `{}`\n\n", self.material, self.scene);
        let _ = writeln!(out, "Scene: {}.\n", self.scene_summary);
        let _ = writeln!(out, "Error measure: {}.\n", self.samples);
        if self.steps.is_empty() {
            out.push_str("No change fits the tolerance: the material is compiled as written.\n\n");
        } else {
            out.push_str("| step | change | error (share of tolerance) | cost (expressions) |\n|---|---|---|---|\n");
            for (i, s) in self.steps.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} → {} ({}) |",
                    i + 1,
                    s.change,
                    share(s.error),
                    s.cost_before,
                    s.cost_after,
                    percent(s.cost_before, s.cost_after)
                );
            }
            out.push('\n');
        }
        let _ = writeln!(
            out,
            "Result: cost {} → {} expressions ({}); error {} of the tolerance against the full material.\n",
            self.full_cost,
            self.simplified_cost,
            percent(self.full_cost, self.simplified_cost),
            share(self.final_error)
        );
        if explain {
            if self.rejected.is_empty() {
                out.push_str("Nothing else was tried: no other change lowers the cost.\n");
            } else {
                out.push_str("Kept, because removing it shows (error above the pass's budget of ");
                let _ = writeln!(out, "{PASS_BUDGET} of the tolerance):\n");
                out.push_str("| change | error (share of tolerance) | cost it would have |\n|---|---|---|\n");
                for r in &self.rejected {
                    let _ = writeln!(out, "| {} | {} | {} |", r.change, share(r.error), r.cost);
                }
            }
        }
        out
    }
}

fn percent(before: usize, after: usize) -> String {
    if before == 0 {
        return "—".into();
    }
    format!("{:+.0}%", 100.0 * (after as f64 - before as f64) / before as f64)
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
    crate::lower::static_cost(&crate::lower::lower(material)).0
}

fn scene_summary(scene: &Scene) -> String {
    let total = scene.lights.iter().fold([0.0_f32; 3], |acc, l| {
        let e = l.max_irradiance();
        [acc[0] + e[0], acc[1] + e[1], acc[2] + e[2]]
    });
    let env = scene.environment.map_or("no environment".to_string(), |l| format!("environment ≤ {}", rgb_text(l)));
    format!(
        "{} light(s), Σ irradiance ≤ {}; {env}; view ≤ {}°, light ≤ {}° from the normal; exposure {}; tolerance {}",
        scene.lights.len(),
        rgb_text(total),
        scene.view_max_angle,
        scene.light_max_angle,
        scene.exposure,
        scene.tolerance.describe()
    )
}

fn rgb_text(c: [f32; 3]) -> String {
    let short = |x: f32| format!("{}", (x * 1000.0).round() / 1000.0);
    format!("({}, {}, {})", short(c[0]), short(c[1]), short(c[2]))
}

/// A share of the tolerance: three decimals, or scientific notation when it is huge.
fn share(x: f32) -> String {
    if x < 1000.0 { format!("{x:.3}") } else { format!("{x:.2e}") }
}

// ---------------------------------------------------------------------------------------------
// Parameters

/// Where each of the material's parameters may lie in the scene.
#[derive(Clone, Debug)]
pub struct ParameterDomain {
    /// Per material parameter: (name, low, high); equal ends for a pinned value.
    bounds: Vec<(String, ParamValue, ParamValue, bool)>,
}

impl ParameterDomain {
    /// The scene's statements about `material`'s parameters; a parameter the scene does not
    /// name is free over its slot's natural range ([`natural_range`]). Names the material does
    /// not have are ignored here (a scene serves many materials; [`check_scene_params`] reports
    /// a name that no material of a set has).
    ///
    /// # Errors
    /// `E0304` for a colour given to a scalar parameter.
    pub fn new(material: &Material, scene: &Scene) -> Result<Self, Vec<Diagnostic>> {
        let mut errors = Vec::new();
        for p in &scene.params {
            let Some(param) = material.params.iter().find(|m| m.name == p.name) else { continue };
            let kinds_match = |v: ParamValue| {
                matches!((v, param.default), (ParamValue::Scalar(_), _) | (ParamValue::Rgb(_), ParamValue::Rgb(_)))
            };
            let ok = match p.domain {
                ParamDomain::Pinned(v) => kinds_match(v),
                ParamDomain::Range(lo, hi) => kinds_match(lo) && kinds_match(hi),
            };
            if !ok {
                errors.push(
                    Diagnostic::error(
                        Code::SceneParamType,
                        format!(
                            "`{}` is a scalar parameter of `{}`, but the scene gives it a colour",
                            p.name, material.name
                        ),
                        p.span,
                        "a scalar parameter",
                    )
                    .with_help("give it one number"),
                );
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        let bounds = material
            .params
            .iter()
            .enumerate()
            .map(|(i, param)| {
                let stated = scene.params.iter().find(|p| p.name == param.name);
                let widen = |v: ParamValue| match (v, param.default) {
                    (ParamValue::Scalar(x), ParamValue::Rgb(_)) => ParamValue::Rgb([x; 3]),
                    _ => v,
                };
                match stated.map(|p| p.domain) {
                    Some(ParamDomain::Pinned(v)) => (param.name.clone(), widen(v), widen(v), true),
                    Some(ParamDomain::Range(lo, hi)) => (param.name.clone(), widen(lo), widen(hi), false),
                    None => {
                        let (lo, hi) = natural_range(material, ParamId(i as u16));
                        let (lo, hi) = match param.default {
                            ParamValue::Scalar(_) => (ParamValue::Scalar(lo), ParamValue::Scalar(hi)),
                            ParamValue::Rgb(_) => (ParamValue::Rgb([lo; 3]), ParamValue::Rgb([hi; 3])),
                        };
                        (param.name.clone(), lo, hi, false)
                    }
                }
            })
            .collect();
        Ok(ParameterDomain { bounds })
    }

    fn pinned_names(&self) -> Vec<String> {
        self.bounds.iter().filter(|b| b.3).map(|b| b.0.clone()).collect()
    }

    fn pinned(&self, name: &str) -> Option<ParamValue> {
        self.bounds.iter().find(|b| b.0 == name && b.3).map(|b| b.1)
    }

    /// A point of the box: `t` ∈ [0, 1] per parameter (per channel of a colour).
    fn point(&self, t: &dyn Fn(usize) -> f32) -> Vec<(String, ParamValue)> {
        let mut axis = 0;
        self.bounds
            .iter()
            .map(|(name, lo, hi, _)| {
                let value = match (lo, hi) {
                    (ParamValue::Scalar(a), ParamValue::Scalar(b)) => {
                        axis += 1;
                        ParamValue::Scalar(a + (b - a) * t(axis - 1))
                    }
                    (ParamValue::Rgb(a), ParamValue::Rgb(b)) => {
                        let mut c = [0.0; 3];
                        for k in 0..3 {
                            c[k] = a[k] + (b[k] - a[k]) * t(axis + k);
                        }
                        axis += 3;
                        ParamValue::Rgb(c)
                    }
                    _ => *lo,
                };
                (name.clone(), value)
            })
            .collect()
    }

    fn axes(&self) -> usize {
        self.bounds.iter().map(|(_, lo, _, _)| if matches!(lo, ParamValue::Scalar(_)) { 1 } else { 3 }).sum()
    }

    /// The parameter vectors a sample set uses: the box's centre, each axis's two ends with the
    /// others at the centre, and `halton` points of the Halton sequence (bases 2, 3, 5, …)
    /// starting at `offset`.
    pub fn vectors(&self, halton: usize, offset: usize) -> Vec<Vec<(String, ParamValue)>> {
        if self.bounds.is_empty() {
            return vec![Vec::new()];
        }
        let axes = self.axes();
        let mut out = vec![self.point(&|_| 0.5)];
        for axis in 0..axes {
            for end in [0.0, 1.0] {
                out.push(self.point(&|a| if a == axis { end } else { 0.5 }));
            }
        }
        for i in 0..halton {
            out.push(self.point(&|a| radical_inverse(PRIMES[a % PRIMES.len()], (i + offset + 1) as u32)));
        }
        out.dedup();
        out
    }
}

const PRIMES: [u32; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

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

/// The range a free parameter is taken over, from the slot it feeds: roughness, albedo,
/// reflectance and σ [0, 1]; IOR [1, 3] (the tables' range); absorption and thickness from 0 to
/// twice the default (at least 2: what a material author tunes around).
pub fn natural_range(material: &Material, id: ParamId) -> (f32, f32) {
    let default = match material.params[id.0 as usize].default {
        ParamValue::Scalar(x) => x,
        ParamValue::Rgb(c) => c.iter().copied().fold(0.0, f32::max),
    };
    let is = |s: &Scalar| *s == Scalar::Param(id);
    let open = (0.0, (2.0 * default).max(2.0));
    for coat in &material.coats {
        if is(&coat.ior) {
            return (1.0, 3.0);
        }
        if is(&coat.thickness) || coat.absorption == Color::Param(id) {
            return open;
        }
    }
    (0.0, 1.0)
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

/// The configurations an error is measured on.
#[derive(Clone, Debug)]
pub struct SampleSet {
    /// (wi, wo) pairs in the local frame (n = +z).
    pub pairs: Vec<(Vec3, Vec3)>,
    /// View directions at which the environment term is integrated.
    pub views: Vec<Vec3>,
    /// Parameter vectors (by name).
    pub params: Vec<Vec<(String, ParamValue)>>,
    /// Environment quadrature: (direction, weight) over the light cone, Σ weight·cos θ = ∫ cos dω.
    pub env: Vec<(Vec3, f32)>,
    description: String,
}

fn direction(theta_deg: f32, phi: f32) -> Vec3 {
    let theta = theta_deg.min(MAX_ANGLE_DEG).to_radians();
    Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
}

impl SampleSet {
    /// The pass's own grid (see the module docs).
    pub fn pass(scene: &Scene, domain: &ParameterDomain) -> Self {
        let grid = |n: usize, max: f32| (0..n).map(move |i| max * i as f32 / (n - 1) as f32);
        let views: Vec<Vec3> = grid(PASS_VIEW_ANGLES, scene.view_max_angle).map(|t| direction(t, 0.0)).collect();
        let mut pairs = Vec::new();
        for (j, theta_o) in grid(PASS_VIEW_ANGLES, scene.view_max_angle).enumerate() {
            let wo = views[j];
            for theta_i in grid(PASS_LIGHT_ANGLES, scene.light_max_angle) {
                for k in 0..PASS_AZIMUTHS {
                    let phi = std::f32::consts::PI * k as f32 / (PASS_AZIMUTHS - 1) as f32;
                    pairs.push((direction(theta_i, phi), wo));
                }
            }
            if theta_o <= scene.light_max_angle {
                pairs.push((direction(theta_o, std::f32::consts::PI), wo));
            }
        }
        let params = domain.vectors(PASS_PARAM_POINTS, 0);
        let environment = if scene.environment.is_some() {
            format!(", the environment integrated by {ENV_COS_NODES} × {ENV_AZIMUTHS} nodes at each view angle")
        } else {
            String::new()
        };
        let description = format!(
            "{} (wi, wo) pairs ({PASS_VIEW_ANGLES} view angles × {PASS_LIGHT_ANGLES} light angles × {PASS_AZIMUTHS} \
             azimuths, plus each view's mirror direction) × {} parameter vector(s){environment}; a change may use \
             {PASS_BUDGET} of the tolerance",
            pairs.len(),
            params.len()
        );
        SampleSet { pairs, views, params, env: env_quadrature(scene.light_max_angle), description }
    }

    /// An independent, denser set for checking a result: Halton directions (bases 2, 3, 5, 7)
    /// inside the cones, mirror configurations at Halton angles, and Halton parameter vectors
    /// away from the pass's.
    pub fn check(scene: &Scene, domain: &ParameterDomain, pairs: usize, param_points: usize) -> Self {
        let mut out = Vec::with_capacity(pairs);
        let cos_cap = |max: f32, u: f32| {
            // Uniform in cos θ over the cone: its directions where they occur.
            let c_min = max.min(MAX_ANGLE_DEG).to_radians().cos();
            (1.0 - u * (1.0 - c_min)).acos().to_degrees()
        };
        for i in 0..pairs {
            let n = (i + 1) as u32;
            let theta_o = cos_cap(scene.view_max_angle, radical_inverse(2, n));
            let wo = direction(theta_o, 0.0);
            if i % 8 == 7 && theta_o <= scene.light_max_angle {
                out.push((direction(theta_o, std::f32::consts::PI), wo));
                continue;
            }
            let theta_i = cos_cap(scene.light_max_angle, radical_inverse(3, n));
            let phi = std::f32::consts::PI * radical_inverse(5, n);
            out.push((direction(theta_i, phi), wo));
        }
        let views = (0..16).map(|i| direction(cos_cap(scene.view_max_angle, radical_inverse(7, i + 1)), 0.0)).collect();
        let params = domain.vectors(param_points, 97);
        let description = format!("{} Halton pairs × {} parameter vector(s)", out.len(), params.len());
        SampleSet { pairs: out, views, params, env: env_quadrature(scene.light_max_angle), description }
    }

    pub fn describe(&self) -> String {
        self.description.clone()
    }
}

/// Gauss–Legendre (16 nodes) in cos θ over [cos θmax, 1] × uniform φ over [0, 2π): weights sum to the
/// cone's solid angle.
fn env_quadrature(max_angle: f32) -> Vec<(Vec3, f32)> {
    let c_min = max_angle.min(MAX_ANGLE_DEG).to_radians().cos();
    let mut out = Vec::new();
    for (x, w) in crate::math::quadrature::gauss_legendre_16() {
        let mu = c_min + (1.0 - c_min) * x as f32;
        let w_mu = w as f32 * (1.0 - c_min);
        let sin = (1.0 - mu * mu).max(0.0).sqrt();
        for k in 0..ENV_AZIMUTHS {
            let phi = std::f32::consts::TAU * (k as f32 + 0.5) / ENV_AZIMUTHS as f32;
            out.push((
                Vec3::new(sin * phi.cos(), sin * phi.sin(), mu),
                w_mu * std::f32::consts::TAU / ENV_AZIMUTHS as f32,
            ));
        }
    }
    out
}

/// The values of `material` for a named parameter vector (defaults for names it lacks).
pub fn values_for(material: &Material, named: &[(String, ParamValue)]) -> Vec<ParamValue> {
    material.params.iter().map(|p| named.iter().find(|(n, _)| *n == p.name).map_or(p.default, |(_, v)| *v)).collect()
}

impl SampleSet {
    /// Every (wi, wo) at which a material is evaluated, per parameter vector: the pairs, then
    /// (with an environment) each view with each environment node.
    pub fn evaluation_pairs(&self, with_env: bool) -> Vec<(Vec3, Vec3)> {
        let mut out = self.pairs.clone();
        if with_env {
            for wo in &self.views {
                out.extend(self.env.iter().map(|(wi, _)| (*wi, *wo)));
            }
        }
        out
    }
}

/// f (without the cosine) at [`SampleSet::evaluation_pairs`], per parameter vector, on the CPU.
pub fn cpu_values(material: &Material, samples: &SampleSet, with_env: bool) -> Vec<Vec<Vec3>> {
    let pairs = samples.evaluation_pairs(with_env);
    samples
        .params
        .iter()
        .map(|named| {
            let values = values_for(material, named);
            pairs.iter().map(|(wi, wo)| crate::eval::brdf(material, &values, *wi, *wo)).collect()
        })
        .collect()
}

/// The reference material's values on a sample set, kept for comparing candidates.
pub struct Evaluated {
    full: Vec<Vec<Vec3>>,
}

impl Evaluated {
    pub fn new(material: &Material, scene: &Scene, samples: &SampleSet) -> Self {
        Evaluated { full: cpu_values(material, samples, scene.environment.is_some()) }
    }

    /// max over the set of ΔL / allowed for `candidate`, evaluated on the CPU.
    pub fn error(&self, candidate: &Material, scene: &Scene, samples: &SampleSet) -> f32 {
        error_between(&self.full, &cpu_values(candidate, samples, scene.environment.is_some()), scene, samples)
    }
}

/// max over the set of ΔL / allowed between two materials' values at
/// [`SampleSet::evaluation_pairs`] (see the module docs for ΔL).
pub fn error_between(full: &[Vec<Vec3>], candidate: &[Vec<Vec3>], scene: &Scene, samples: &SampleSet) -> f32 {
    let light = scene.lights.iter().fold(Vec3::ZERO, |acc, l| acc + Vec3::from(l.max_irradiance())) * scene.exposure;
    let environment = Vec3::from(scene.environment.unwrap_or([0.0; 3])) * scene.exposure;
    let n_pairs = samples.pairs.len();
    let n_env = samples.env.len();
    let mut worst = 0.0_f32;
    let mut worse = |delta: Vec3, value: Vec3| {
        worst = worst.max(scene.tolerance.share(value.to_array(), delta.to_array()));
    };
    for (full, cand) in full.iter().zip(candidate) {
        // The environment's share at each view: L_env · ∫ |Δf| cos, and L_env · ∫ f cos; the
        // largest over the views is added at every pair (conservative).
        let mut env_delta = Vec3::ZERO;
        if scene.environment.is_some() {
            for v in 0..samples.views.len() {
                let range = n_pairs + v * n_env..n_pairs + (v + 1) * n_env;
                let mut delta = Vec3::ZERO;
                let mut value = Vec3::ZERO;
                for ((a, b), (dir, w)) in full[range.clone()].iter().zip(&cand[range]).zip(&samples.env) {
                    delta += (*a - *b).abs() * dir.z * *w;
                    value += *a * dir.z * *w;
                }
                worse(delta * environment, value * environment);
                env_delta = env_delta.max(delta * environment);
            }
        }
        for ((a, b), (wi, _)) in full[..n_pairs].iter().zip(&cand[..n_pairs]).zip(&samples.pairs) {
            worse((*a - *b).abs() * wi.z * light + env_delta, *a * wi.z * light);
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn a_colour_for_a_scalar_parameter_is_e0304_and_unknown_names_are_e0303() {
        let m = glaze();
        let s =
            scene(r#"Scene(name: "s", lights: [], params: {"ior": Pinned((1.4, 1.5, 1.6)), "roughh": Pinned(0.3)})"#);
        let errors = ParameterDomain::new(&m, &s).expect_err("a colour for the IOR");
        assert_eq!(errors.iter().map(|d| d.code).collect::<Vec<_>>(), [Code::SceneParamType]);
        let unknown = check_scene_params(&s, &[&m]);
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
