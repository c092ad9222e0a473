//! Accuracy of the default method against the stochastic reference, on the CPU and on a Vulkan
//! device, and the BRDF laws of every method.
//!
//! The reference values are the stored
//! `crates/glazec-lab/data/reference/standard-multiple.bin` (computed by
//! `glazec accuracy --regenerate-reference`; in the deep tier one test recomputes a few cases and
//! checks they come out the same). The targets are `glazec_lab::accuracy::{LOBE_TARGET, ALBEDO_TARGET, …}`.
//!
//! Every case of the set meets the targets on both. Copper under a coat meets them through the
//! glossy level: its lobe-albedo table is fitted to the energy law (the least change that keeps
//! every probe within the law) and its trapped light's first Fresnel factor is taken at the coat's
//! mean-path cosine (docs/accuracy.md, "The glossy level: a conductor under a coat"). EON under a
//! coat meets them because its first pass out of the body is modelled (docs/accuracy.md, "EON
//! under a coat").

mod common;

use std::path::PathBuf;

use glazec::model::Method;
use glazec_lab::accuracy::{
    self, ALBEDO_TARGET, Case, ENERGY_TARGET, FURNACE_TARGET, LOBE_TARGET, Metrics, RECIPROCITY_TARGET, ReferenceData,
};
use glazec_lab::reference::InterfaceMode;

/// Cases recomputed by the reproducibility test (the first ones of the set).
const RECOMPUTED_CASES: usize = 2;
/// Relative tolerance between recomputed and stored reference values: the file stores f32, and
/// the f64 walk may differ in the last bits between libm builds.
const STORED_REL_TOL: f64 = 1e-6;
/// Largest relative error beyond noise of the stated albedo of a stack of smooth and GGX coats
/// over a diffusing body (measured up to 4.2%, `four ggx` at normal incidence; docs/accuracy.md,
/// "The stated albedo against the reference").
const STATED_ALBEDO_TOLERANCE: f64 = 0.05;
/// The same for every stack over a conductor (measured up to 18.6%, `gtr1 0.1 / smooth / ggx
/// 0.35 over copper` at 30°, 21.8% before the light a coated conductor sends beyond the escape
/// cone of the coat above was trapped part by part; the others within 7.7%).
const STATED_ALBEDO_TOLERANCE_CONDUCTOR: f64 = 0.20;

fn reference() -> (Vec<Case>, ReferenceData) {
    let cases = accuracy::standard_set();
    let path = accuracy::stored_reference(InterfaceMode::Multiple);
    let data = ReferenceData::read(&path, cases.len()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(data.mode, InterfaceMode::Multiple);
    (cases, data)
}

/// Checks the default method's metrics on the set; returns the failures.
fn check_default_method(cases: &[Case], metrics: &[Metrics]) -> Vec<String> {
    let mut failures = Vec::new();
    for (case, m) in cases.iter().zip(metrics) {
        if m.lobe_rmse > LOBE_TARGET || m.albedo_error > ALBEDO_TARGET {
            failures.push(format!(
                "{}: lobe relRMSE {:.4} (≤ {LOBE_TARGET}), albedo error {:.4} (≤ {ALBEDO_TARGET})",
                case.label(),
                m.lobe_rmse,
                m.albedo_error
            ));
        }
        if m.reciprocity > RECIPROCITY_TARGET || m.energy_max > ENERGY_TARGET || m.min_value < 0.0 {
            failures.push(format!(
                "{}: reciprocity {:e}, max E {:.5}, min f {:e}",
                case.label(),
                m.reciprocity,
                m.energy_max,
                m.min_value
            ));
        }
    }
    let laws = accuracy::laws(cases, metrics);
    if laws.furnace > FURNACE_TARGET {
        failures.push(format!("white furnace |E − 1| = {:.5} > {FURNACE_TARGET}", laws.furnace));
    }
    let worst = |f: fn(&Metrics) -> f64| metrics.iter().map(f).fold(0.0, f64::max);
    eprintln!(
        "default method on {} cases: worst lobe relRMSE {:.2}%, albedo error {:.4}, reciprocity {:.1e}, max E {:.5}, furnace {:.4}",
        cases.len(),
        100.0 * worst(|m| m.lobe_rmse),
        worst(|m| m.albedo_error),
        laws.reciprocity,
        laws.energy_max,
        laws.furnace
    );
    failures
}

#[test]
fn default_method_meets_the_targets_on_the_cpu() {
    let (cases, data) = reference();
    let metrics: Vec<Metrics> = cases
        .iter()
        .enumerate()
        .map(|(i, c)| accuracy::measure(c, Method::INTERFACED, &data.under[i], &data.albedo[i]))
        .collect();
    let failures = check_default_method(&cases, &metrics);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn laws_hold_for_the_default_method_and_the_others_are_reported() {
    let (cases, data) = reference();
    let methods = accuracy::measure_methods(&cases, &data);
    let interfaced = accuracy::laws(&cases, &methods[0].1);
    let ww = accuracy::laws(&cases, &methods[1].1);
    let additive = accuracy::laws(&cases, &methods[2].1);
    for (name, l) in [("Interfaced", interfaced), ("WeidlichWilkie", ww), ("Additive", additive)] {
        eprintln!(
            "{name:>14}: min f {:.1e}, reciprocity {:.1e}, max E {:.4}, furnace |E − 1| {:.4}",
            l.min_value, l.reciprocity, l.energy_max, l.furnace
        );
    }
    assert!(interfaced.min_value >= 0.0);
    assert!(interfaced.reciprocity <= RECIPROCITY_TARGET, "{}", interfaced.reciprocity);
    assert!(interfaced.energy_max <= ENERGY_TARGET, "{}", interfaced.energy_max);
    assert!(interfaced.furnace <= FURNACE_TARGET, "{}", interfaced.furnace);
    // The seed's method and Disney clear-coat break laws by design; the table reports it (and
    // this checks the table would show it): WW is neither reciprocal nor energy conserving,
    // Additive creates energy by adding a coat lobe to an unattenuated base.
    assert!(ww.reciprocity > RECIPROCITY_TARGET && ww.energy_max > ENERGY_TARGET);
    assert!(additive.energy_max > ENERGY_TARGET && additive.furnace > FURNACE_TARGET);
    assert!(ww.min_value >= 0.0 && additive.min_value >= 0.0);
    // The published table (docs/results/accuracy.md, quoted in docs/accuracy.md) is what these
    // numbers give.
    let table = accuracy::markdown(&cases, &methods, &data);
    let docs = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/results/accuracy.md"))
        .expect("docs/results/accuracy.md");
    assert_eq!(table, docs, "docs/results/accuracy.md is out of date: run `glazec accuracy`");
    // And so is the per-case file beside it (every digit: the table rounds, the file does not).
    let csv = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/results/accuracy.csv"))
        .expect("docs/results/accuracy.csv");
    assert!(accuracy::csv(&cases, &methods) == csv, "docs/results/accuracy.csv is out of date: run `glazec accuracy`");
}

/// (Deep tier: recomputing even two cases of the reference takes most of a minute.)
#[test]
fn stored_reference_is_reproducible() {
    if !common::deep() {
        eprintln!("the stored reference's reproducibility is checked in the deep tier (GLAZEC_DEEP=1)");
        return;
    }
    let (cases, data) = reference();
    let recomputed = ReferenceData::compute(&cases[..RECOMPUTED_CASES], data.mode, data.samples, data.walks, &|_| {});
    for (c, case) in cases.iter().enumerate().take(RECOMPUTED_CASES) {
        let stored = data.under[c].iter().chain(&data.albedo[c]);
        let fresh = recomputed.under[c].iter().chain(&recomputed.albedo[c]);
        for (s, f) in stored.zip(fresh) {
            let f32_rounded = f.as_vec3().as_dvec3();
            let error = (*s - f32_rounded).abs().max_element();
            assert!(
                error <= STORED_REL_TOL * s.abs().max_element().max(1e-12),
                "{}: stored {s}, recomputed {f}",
                case.label()
            );
        }
    }
}

// ----- the whole BRDF, in bands (issue 31) ------------------------------------------------

/// The published whole-BRDF tables (docs/results/accuracy-full.md, quoted in docs/accuracy.md)
/// are what the stored references and today's math give. (The bands' targets are asserted for
/// the shipped materials, below; in the standard and multi-coat sets the default method still
/// misses them for some stacks over conductors and some GTR1 stacks, and the tables mark each
/// miss.)
#[test]
fn the_whole_brdf_tables_are_current() {
    let table = glazec_lab::accuracy::full::report().unwrap_or_else(|e| panic!("{e}"));
    let docs = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/results/accuracy-full.md"))
        .expect("docs/results/accuracy-full.md");
    assert_eq!(table, docs, "docs/results/accuracy-full.md is out of date: run `glazec accuracy`");
}

/// The stated-albedo table in the docs is what the code and the stored reference albedos give.
#[test]
fn the_stated_albedo_table_is_current() {
    use glazec_lab::accuracy::{full, stated};
    let table = stated::report(&full::sets().unwrap_or_else(|e| panic!("{e}"))).unwrap_or_else(|e| panic!("{e}"));
    let docs = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/results/stated-albedo.md"))
        .expect("docs/results/stated-albedo.md");
    assert_eq!(table, docs, "docs/results/stated-albedo.md is out of date: run `glazec accuracy`");
}

/// Every material of the multi-coat and shipped sets whose coats are smooth or GGX over a
/// diffusing body (Lambert, Oren–Nayar, EON, Plastic) states its directional albedo — what
/// image-based lighting weighs — within [`STATED_ALBEDO_TOLERANCE`] of the reference's beyond
/// noise, at every angle. (Where the first pass let all of a coated GGX layer's lobe out, the
/// part beyond the escape cone of the coat above included, `ggx 0.2 / ggx 0.4 over Lambert 0.8`
/// stated 10% too much; with an Oren–Nayar body's mean albedo in every direction, `wet_clay` 8%.)
/// GTR1 stacks over diffusing bodies are reported in the table, not held to this; conductor
/// stacks are held to their own tolerance (`stacks_over_conductors_state_their_albedo`).
#[test]
fn stacks_over_diffusing_bodies_state_their_albedo() {
    use glazec::model::{Base, Lobe};
    let checked = check_stated_albedo(STATED_ALBEDO_TOLERANCE, &|m| {
        !matches!(m.base, Base::Conductor { .. }) && !m.coats.iter().any(|c| matches!(c.lobe, Lobe::Gtr1 { .. }))
    });
    assert!(checked >= 10, "only {checked} materials checked");
}

/// Every material of the multi-coat and shipped sets over a conductor, GTR1 coats and coats
/// over coated conductors included, states its directional albedo within
/// [`STATED_ALBEDO_TOLERANCE_CONDUCTOR`] of the reference's beyond noise, at every angle.
#[test]
fn stacks_over_conductors_state_their_albedo() {
    use glazec::model::Base;
    let checked = check_stated_albedo(STATED_ALBEDO_TOLERANCE_CONDUCTOR, &|m| matches!(m.base, Base::Conductor { .. }));
    assert!(checked >= 6, "only {checked} materials checked");
}

/// Holds the stated albedo of the multi-coat and shipped materials that `pick` picks within
/// `tolerance` of the stored reference's; returns how many it checked.
fn check_stated_albedo(tolerance: f64, pick: &dyn Fn(&glazec::model::Material) -> bool) -> usize {
    use glazec_lab::accuracy::{full, stated};
    let mut checked = 0;
    for set in full::sets().unwrap_or_else(|e| panic!("{e}")).iter().filter(|s| s.name != "standard") {
        let reference =
            stated::read(&stated::stored_albedo_reference(set.name), &set.subjects).unwrap_or_else(|e| panic!("{e}"));
        for (subject, values) in set.subjects.iter().zip(&reference.values) {
            if !pick(&subject.material) {
                continue;
            }
            checked += 1;
            let errors = stated::errors(subject, values);
            let worst = errors.iter().fold(0.0_f64, |w, e| w.max(e.abs()));
            assert!(worst <= tolerance, "{}: stated albedo off by {errors:?}", subject.label);
        }
    }
    checked
}

/// Every shipped material meets the bands' targets (issue 31: body p90 ≤ 2%, ≤ 10% over a
/// conductor; grazing worst ≤ 25%, beyond the reference's noise) on the CPU; on the device the
/// bands agree with the CPU's (`whole_brdf_bands_hold_on_the_gpu`).
#[test]
fn every_shipped_material_meets_the_whole_brdf_targets() {
    use glazec::model::Method;
    use glazec_lab::accuracy::full::{self, FullReference};
    let sets = full::sets().unwrap_or_else(|e| panic!("{e}"));
    let shipped = sets.iter().find(|s| s.name == "shipped").expect("the shipped set");
    let reference =
        FullReference::read(&full::stored_reference(shipped.name), &shipped.subjects).unwrap_or_else(|e| panic!("{e}"));
    let misses: Vec<String> = shipped
        .subjects
        .iter()
        .zip(&reference.values)
        .filter_map(|(subject, estimates)| {
            let m = full::measure(&subject.probes(), &full::cpu_values(subject, Method::INTERFACED), estimates);
            (!full::meets_targets(subject, &m)).then(|| format!("{}: {m:?}", subject.label))
        })
        .collect();
    assert!(misses.is_empty(), "shipped materials outside the bands' targets:\n{}", misses.join("\n"));
}

/// (Deep tier.) The first material of each whole-BRDF set recomputes to its stored reference.
#[test]
fn stored_whole_brdf_references_are_reproducible() {
    use glazec_lab::accuracy::full::{self, FullReference};
    if !common::deep() {
        eprintln!("the whole-BRDF references' reproducibility is checked in the deep tier (GLAZEC_DEEP=1)");
        return;
    }
    for full::Set { name, subjects, .. } in full::sets().unwrap_or_else(|e| panic!("{e}")) {
        let stored = FullReference::read(&full::stored_reference(name), &subjects).unwrap_or_else(|e| panic!("{e}"));
        let fresh = FullReference::compute(&subjects[..1], stored.samples, &|_| {});
        for (s, f) in stored.values[0].iter().zip(&fresh.values[0]) {
            let error = (s.mean - f.mean.as_vec3().as_dvec3()).abs().max_element();
            assert!(
                error <= STORED_REL_TOL * s.mean.abs().max_element().max(1e-12),
                "{name}, {}: stored {}, recomputed {}",
                subjects[0].label,
                s.mean,
                f.mean
            );
        }
    }
}

// ----- on the device ----------------------------------------------------------------------

mod on_the_device {
    use glam::{DVec3, Vec3};
    use glazec::eval::Pair;
    use glazec::model::{Method, ParamValue};
    use glazec_gpu::{EvalKernel, Gpu, ShaderPath};
    use glazec_lab::accuracy::{self, BaseKind, Case, Variant};

    use super::{check_default_method, common, reference};

    /// The structures of the set as materials with runtime parameters: one shader per lobe kind and
    /// base, every case of that structure is a parameter setting.
    fn structure_text(smooth: bool, base: BaseKind) -> String {
        let lobe = if smooth { "Smooth".to_string() } else { "Ggx(roughness: Param(\"roughness\", 0.2))".to_string() };
        let base = match base {
            BaseKind::Lambert(_) => "Lambert(albedo: Param(\"albedo\", (0.8, 0.8, 0.8)))",
            BaseKind::Eon => "Eon(albedo: (0.8, 0.8, 0.8), roughness: 1.0)",
            BaseKind::Copper => "Conductor(roughness: 0.3, eta: (0.27, 0.68, 1.22), k: (3.61, 2.63, 2.29))",
        };
        format!(
            "Material(name: \"accuracy_case\", layers: [\n    Coat(lobe: {lobe}, ior: Param(\"ior\", 1.5), \
             absorption: Param(\"tau\", (0.5, 0.5, 0.5)), thickness: 1.0),\n    {base},\n])"
        )
    }

    /// Parameter values for a case (`black`: the coat alone, on the Lambert structure).
    fn values(compiled: &glazec::Compiled, case: &Case, black: bool) -> Vec<ParamValue> {
        compiled
            .material
            .params
            .iter()
            .map(|p| match p.name.as_str() {
                "roughness" => ParamValue::Scalar(case.roughness),
                "ior" => ParamValue::Scalar(case.ior),
                "tau" => ParamValue::Rgb([case.tau; 3]),
                "albedo" => ParamValue::Rgb(match case.base {
                    _ if black => [0.0; 3],
                    BaseKind::Lambert(rho) => [rho; 3],
                    _ => unreachable!("only the Lambert structure has an albedo parameter"),
                }),
                other => unreachable!("unknown parameter {other}"),
            })
            .collect()
    }

    struct Shader {
        compiled: glazec::Compiled,
        kernel: EvalKernel,
    }

    fn shader(gpu: &Gpu, smooth: bool, base: BaseKind) -> Shader {
        let compiled = glazec::compile(&structure_text(smooth, base)).unwrap_or_else(|e| panic!("{e:?}"));
        let kernel = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).unwrap_or_else(|e| panic!("{e}"));
        Shader { compiled, kernel }
    }

    #[test]
    fn default_method_meets_the_targets_on_the_gpu() {
        let Some(gpu) = common::open_gpu() else { return };
        let (cases, data) = reference();
        // One shader per structure: (smooth coat?, base).
        const BASES: [BaseKind; 3] = [BaseKind::Lambert(0.0), BaseKind::Eon, BaseKind::Copper];
        let shaders: Vec<Shader> =
            [true, false].iter().flat_map(|&smooth| BASES.map(|base| shader(&gpu, smooth, base))).collect();
        let shader_for = |smooth: bool, base: BaseKind| -> &Shader {
            let b =
                BASES.iter().position(|&k| std::mem::discriminant(&k) == std::mem::discriminant(&base)).unwrap_or(0);
            &shaders[if smooth { b } else { BASES.len() + b }]
        };
        let (mut disagreements, mut values_checked, mut metrics) = (Vec::new(), 0usize, Vec::new());
        for (i, case) in cases.iter().enumerate() {
            let smooth = case.roughness == 0.0;
            let (full, coat_only) = (shader_for(smooth, case.base), shader_for(smooth, BaseKind::Lambert(0.0)));
            let mut eval = |variant: Variant, pairs: &[(DVec3, DVec3)]| -> Vec<DVec3> {
                let (shader, black) = match variant {
                    Variant::Full => (full, false),
                    Variant::CoatOnly => (coat_only, true),
                };
                let values = values(&shader.compiled, case, black);
                let pairs: Vec<Pair> =
                    pairs.iter().map(|(wi, wo)| Pair { wi: wi.as_vec3(), wo: wo.as_vec3() }).collect();
                let on_gpu = shader.kernel.eval(&gpu, &pairs, &values).unwrap_or_else(|e| panic!("{e}"));
                let on_cpu: Vec<Vec3> =
                    pairs.iter().map(|p| glazec::eval::brdf(&shader.compiled.material, &values, p.wi, p.wo)).collect();
                let max = on_cpu.iter().map(|f| f.max_element()).fold(0.0_f32, f32::max);
                for ((p, c), g) in pairs.iter().zip(&on_cpu).zip(&on_gpu) {
                    for k in 0..3 {
                        values_checked += 1;
                        if !common::agreement::agrees(c[k], g[k], max) && disagreements.len() < 10 {
                            disagreements.push(format!(
                                "{} {variant:?}: wi {} wo {}: cpu {} gpu {}",
                                case.label(),
                                p.wi,
                                p.wo,
                                c[k],
                                g[k]
                            ));
                        }
                    }
                }
                on_gpu.iter().map(|v| v.as_dvec3()).collect()
            };
            metrics.push(accuracy::measure_with(case, Method::INTERFACED, &data.under[i], &data.albedo[i], &mut eval));
        }
        eprintln!(
            "GPU cases executed: {} materials, {} shaders, {values_checked} values compared with the CPU",
            cases.len(),
            shaders.len()
        );
        assert!(disagreements.is_empty(), "GPU and CPU disagree:\n{}", disagreements.join("\n"));
        let failures = check_default_method(&cases, &metrics);
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
    /// The whole-BRDF bands of the multi-coat set and the shipped materials on lavapipe: every
    /// probe agrees with the CPU, and the bands measured from the device's values are the
    /// published ones (the CPU's) within [`BAND_TOL`].
    #[test]
    fn whole_brdf_bands_hold_on_the_gpu() {
        use glazec_lab::accuracy::full::{self, FullReference};
        /// How far a band's figure from the device's values may lie from the CPU's (absolute,
        /// relative error): what the shaders' f32 rounding moves at the sharpest peaks.
        const BAND_TOL: f64 = 1e-3;
        let Some(gpu) = common::open_gpu() else { return };
        let (mut disagreements, mut values_checked, mut bands_checked) = (Vec::new(), 0usize, 0usize);
        for set in full::sets().unwrap_or_else(|e| panic!("{e}")).into_iter().filter(|s| s.name != "standard") {
            let reference =
                FullReference::read(&full::stored_reference(set.name), &set.subjects).unwrap_or_else(|e| panic!("{e}"));
            for (subject, estimates) in set.subjects.iter().zip(&reference.values) {
                let compiled = glazec::compile_material(subject.with_method(Method::INTERFACED), Default::default())
                    .unwrap_or_else(|e| panic!("{}: {e}", subject.label));
                let kernel = EvalKernel::new(&gpu, &compiled, ShaderPath::NagaIr).unwrap_or_else(|e| panic!("{e}"));
                let probes = subject.probes();
                let pairs: Vec<Pair> = probes.iter().map(|p| Pair { wi: p.wi.as_vec3(), wo: p.wo.as_vec3() }).collect();
                let on_gpu = kernel.eval(&gpu, &pairs, &subject.values).unwrap_or_else(|e| panic!("{e}"));
                let on_cpu = full::cpu_values(subject, Method::INTERFACED);
                let max = on_cpu.iter().map(|f| f.max_element()).fold(0.0, f64::max) as f32;
                for ((p, c), g) in pairs.iter().zip(&on_cpu).zip(&on_gpu) {
                    for k in 0..3 {
                        values_checked += 1;
                        if !common::agreement::agrees(c[k] as f32, g[k], max) && disagreements.len() < 10 {
                            disagreements
                                .push(format!("{}: wi {} wo {}: cpu {} gpu {}", subject.label, p.wi, p.wo, c[k], g[k]));
                        }
                    }
                }
                let gpu_values: Vec<DVec3> = on_gpu.iter().map(|v| v.as_dvec3()).collect();
                let (a, b) =
                    (full::measure(&probes, &on_cpu, estimates), full::measure(&probes, &gpu_values, estimates));
                for (x, y) in [
                    (a.body_p90, b.body_p90),
                    (a.body_max, b.body_max),
                    (a.grazing_p90, b.grazing_p90),
                    (a.grazing_max, b.grazing_max),
                    (a.peak_height, b.peak_height),
                    (a.peak_width, b.peak_width),
                ] {
                    bands_checked += 1;
                    assert!((x - y).abs() <= BAND_TOL * x.abs().max(1.0), "{}: CPU {a:?}, GPU {b:?}", subject.label);
                }
            }
        }
        eprintln!(
            "whole-BRDF probes on the device: {values_checked} values compared with the CPU, {bands_checked} band figures"
        );
        assert!(disagreements.is_empty(), "GPU and CPU disagree:\n{}", disagreements.join("\n"));
    }
}
