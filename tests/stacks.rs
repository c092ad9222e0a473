//! Random layer stacks (1..=8 coats, every lobe, base and method, literal or runtime
//! parameters) go through the whole pipeline: the generated RON parses and checks, the module
//! validates with all of naga's checks, every backend emits, and the CPU evaluation of the same
//! math is finite, non-negative and reciprocal.

mod common;

use common::stacks::{Stack, WEIDLICH_WILKIE, Writer, refused_for_table_budget, stack, stack_of};
use glam::Vec3;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// Stacks tried per run (fixed seed: the same stacks every run); `GLAZEC_PROPTEST_CASES` asks
/// for more.
const CASES: u32 = 200;
/// Deep stacks (9..=16 coats, up to the layer limit) tried per run.
const DEEP_CASES: u32 = 24;
const SEED: u64 = 0x91a2_e5c0;
/// Direction pairs evaluated per stack.
const PAIRS: usize = 48;
/// Reciprocity tolerance: f32 rounding of a symmetric formula evaluated in two orders.
const RECIPROCITY_REL: f32 = 2e-4;
const RECIPROCITY_ABS: f32 = 1e-6;

/// Deterministic directions on the upper hemisphere, grazing ones included.
fn directions() -> Vec<(Vec3, Vec3)> {
    (0..PAIRS)
        .map(|i| {
            let t = i as f32 / PAIRS as f32;
            let theta_i = (t * 89.5_f32).to_radians();
            let theta_o = ((1.0 - t) * 89.0_f32).to_radians();
            let phi = t * 17.0;
            let wi = Vec3::new(theta_i.sin() * phi.cos(), theta_i.sin() * phi.sin(), theta_i.cos());
            let wo = Vec3::new(theta_o.sin(), 0.0, theta_o.cos());
            (wi, wo)
        })
        .collect()
}

fn cases(default: u32) -> u32 {
    std::env::var("GLAZEC_PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

proptest! {
    #![proptest_config(Config { cases: cases(CASES), rng_seed: RngSeed::Fixed(SEED), failure_persistence: None, ..Config::default() })]

    #[test]
    fn random_stacks_compile_validate_and_evaluate(s in stack()) {
        check_stack(&s)?;
    }
}

proptest! {
    #![proptest_config(Config { cases: cases(DEEP_CASES), rng_seed: RngSeed::Fixed(SEED + 1), failure_persistence: None, ..Config::default() })]

    #[test]
    fn deep_random_stacks_up_to_the_layer_limit_compile_validate_and_evaluate(s in stack_of(9..=16)) {
        check_stack(&s)?;
    }
}

/// The whole pipeline on one stack: compiles, validates, emits every target deterministically,
/// and evaluates finite, non-negative and (where the method is) reciprocal.
fn check_stack(s: &Stack) -> Result<(), TestCaseError> {
    {
        let text = Writer { next_param: 0 }.material(s);
        let compiled = match glazec::compile(&text) {
            Ok(c) => c,
            // A stack whose runtime lookups need more tables than a uniform holds is refused
            // with E0222 (`tests/bad/table_budget.ron`): a right answer, not a case to check.
            Err(e) if refused_for_table_budget(&e) => return Err(TestCaseError::reject("over the table budget")),
            Err(e) => return Err(TestCaseError::fail(format!("{e}: {e:?}\n{text}"))),
        };
        let targets = [glazec::Target::Wgsl, glazec::Target::Glsl, glazec::Target::Hlsl, glazec::Target::Spv];
        let artifacts =
            compiled.emit_with_harness(&targets).map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        // WGSL library and harness, the GLSL library and four harness files, the HLSL library
        // and harness, SPIR-V; and the table file when the library reads tables.
        prop_assert_eq!(artifacts.len(), 10 + usize::from(compiled.uses_tables()));
        let again = glazec::compile(&text).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        let again = again.emit_with_harness(&targets).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert!(artifacts == again, "output is not deterministic\n{}", text);

        // Every method is reciprocal except the seed's Weidlich–Wilkie over a smooth coat, whose
        // T12 = 1 − F(n·v) depends on the view direction only (Bowsher 2022, eq. 5;
        // docs/language.md, "How Bowsher 2022 is read").
        let reciprocal = s.method != WEIDLICH_WILKIE || s.coats.iter().all(|c| c.lobe != 0);
        let values = compiled.material.default_values();
        for (wi, wo) in directions() {
            let f = glazec::eval::brdf(&compiled.material, &values, wi, wo);
            let g = glazec::eval::brdf(&compiled.material, &values, wo, wi);
            prop_assert!(f.is_finite() && f.min_element() >= 0.0, "f = {f} at wi {wi} wo {wo}\n{text}");
            for c in (0..3).filter(|_| reciprocal) {
                let tolerance = RECIPROCITY_REL * f[c].abs().max(g[c].abs()) + RECIPROCITY_ABS;
                prop_assert!((f[c] - g[c]).abs() <= tolerance, "not reciprocal: {f} vs {g} at wi {wi} wo {wo}\n{text}");
            }
        }
    }
    Ok(())
}

#[test]
fn eight_coats_compile() {
    let coat = "Coat(lobe: Ggx(0.3), ior: 1.2, absorption: 0.1, thickness: 0.5)";
    let text = format!("Material(name: \"eight\", layers: [{}, Lambert(0.5)])", [coat; 8].join(", "));
    let compiled = glazec::compile(&text).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(compiled.material.coats.len(), 8);
    compiled.emit(&glazec::Target::TEXT).expect("emits");
}

/// Coats optically thinner than the medium above them over a conductor: beyond their critical
/// angles no light enters (T = 0), the coat reflects all of it from below (k = 1) and the level
/// under it can be white (E = 1), where the glossy inter-reflection's 1 − E k was 0/0: NaN at
/// 21 of 25 direction pairs (found by shrinking a deep-tier random stack).
#[test]
fn coats_thinner_than_the_medium_above_a_conductor_stay_finite() {
    for iors in [[1.0, 0.7, 0.7], [0.7, 0.7, 1.5], [0.7, 1.5, 0.7], [0.7, 0.7, 0.7]] {
        let coats: Vec<String> = iors.iter().map(|n| format!("Coat(lobe: Smooth, ior: {n:?})")).collect();
        let text =
            format!("Material(name: \"thin\", layers: [{}, Conductor(roughness: 0.05, f0: 0.9)])", coats.join(", "));
        let compiled = glazec::compile(&text).unwrap_or_else(|e| panic!("{e:?}"));
        let values = compiled.material.default_values();
        for (wi, wo) in directions() {
            let f = glazec::eval::brdf(&compiled.material, &values, wi, wo);
            assert!(f.is_finite() && f.min_element() >= 0.0, "f = {f} at wi {wi} wo {wo}\n{text}");
        }
    }
}

/// A stack whose lookups at literal roughnesses and runtime IORs, depths and a runtime conductor
/// roughness would take 72,368 bytes of table uniform as compact per-lookup blocks (found by the
/// deep tier's random stacks, which wgpu then refused: over WebGPU's 64 KiB) fits: the buffer
/// falls back to the tables' own windows, merged, never more than the tables themselves.
#[test]
fn many_slices_fit_the_table_uniform() {
    let text = r#"Material(name: "random", method: Interfaced(multiple_scattering: false), layers: [
    Coat(lobe: Ggx(roughness: Param("p1", 0.13390031)), ior: 1.2035459, absorption: Param("p2", (1.1395423, 0.56253743, 0.82903504)), thickness: 0.18741773),
    Coat(lobe: Ggx(roughness: Param("p3", 0.8260229)), ior: 2.5485573, absorption: (0.09027628, 4.310355, 4.281066), thickness: 0.4810426),
    Coat(lobe: Ggx(roughness: 0.12954053), ior: 2.9184213, absorption: (1.201069, 0.2354038, 4.3134212), thickness: 0.8504063),
    Coat(lobe: Ggx(roughness: Param("p4", 0.45693025)), ior: 1.4478294, absorption: (0.45201188, 0.14726332, 0.28869337), thickness: 0.43310073),
    Coat(lobe: Ggx(roughness: Param("p5", 0.98685557)), ior: 2.0829754, absorption: (4.511372, 4.28169, 3.325157), thickness: 1.8258964),
    Plastic(albedo: (0.46454486, 0.258839, 0.25338265), roughness: 0.49807295, ior: Param("p6", 2.432246))
])"#;
    let compiled = glazec::compile(text).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(compiled.uses_tables(), "the lookups read the table uniform");
    let bytes = compiled.tables_bytes().len();
    assert!(bytes <= glazec::lower::builder::MAX_UNIFORM_BYTES, "{bytes} bytes of tables");
}

/// The WGSL of a material, as text.
fn wgsl(text: &str) -> String {
    let compiled = glazec::compile(text).unwrap_or_else(|e| panic!("{e:?}"));
    let artifact = compiled.emit(&[glazec::Target::Wgsl]).expect("emits").remove(0);
    String::from_utf8(artifact.contents).expect("WGSL is UTF-8")
}

/// The glossy level's hemisphere (twelve nodes, each with seven 4D lookups) is one loop per
/// function in a shader when the material has runtime parameters, and folds to constants when it
/// has none (unrolled, eight nodes call the lookup functions 20 times and make 140 KB of WGSL).
#[test]
fn a_conductor_under_a_coat_sums_its_hemisphere_in_one_loop_or_folds_it() {
    let conductor = "Conductor(roughness: Param(\"cr\", 0.2), eta: (0.27, 0.68, 1.22), k: (3.61, 2.63, 2.29))";
    let coat = "Coat(lobe: Ggx(roughness: Param(\"rough\", 0.3)), ior: Param(\"ior\", 1.5))";
    let tunable = wgsl(&format!("Material(name: \"tunable_copper\", layers: [{coat}, {conductor}])"));
    // One loop in `_brdf` and one in `_ibl_lobes`.
    assert_eq!(tunable.matches("loop {").count(), 2, "{tunable}");
    // glossy_scale: its definition, the light's and the view's side and the loop in `_brdf`,
    // the view's side and the loop in `_ibl_lobes`.
    assert_eq!(tunable.matches("glossy_scale(").count(), 6);

    let literal = wgsl(&std::fs::read_to_string(common::root().join("materials/coated_gold.ron")).expect("material"));
    assert!(!literal.contains("loop {"), "coated_gold's hemisphere folds");
    assert!(literal.contains("const coated_gold_remainder_avg"), "coated_gold's remainder mean is a constant");
}
