//! The stability map on a reduced sweep (`glazec stability --reduced`): on the CPU for every
//! method and on lavapipe for the default one.
//!
//! The default method must show no non-finite values, no negative values and no discontinuities
//! anywhere in the sweep. It does gain energy in two places today (README "Stability"; the
//! speed-and-stability issue stays open on them), which are held to the values measured when this
//! test was last changed so that they cannot grow or spread unseen:
//! * rough coats seen within 1° of grazing: the tabulated transmission and the analytic lobe
//!   disagree by up to 0.2% where the single-scattering albedo changes fastest (α ≈ μ). (It was
//!   up to 4.9% before the cosine axes got their first node at the lobes' clamp, 10⁻⁴, and a
//!   μ^¼ spacing; the same change let the τ and layer sweeps reach 1.0014 at 89°–89.99°, where
//!   they had stayed below 1.001.)
//! * a rough coat optically thinner than the medium above (η < 1), outside the tables, where the
//!   smooth-interface transmission is paired with a rough lobe (its Fresnel taken at the macro
//!   normal, which removed a real gain of up to 14%). What the sweep still reports there is the
//!   quadrature's error at the transmission's cut-off at the critical angle, which a breakpoint
//!   removes at normal incidence but not for oblique views: a brute-force integration
//!   (`examples/brute_albedo.rs`) gives E = 0.9997 where the sweep gives 1.0012 (η 0.824, 30°).
//!
//! Stacks of several coats gained up to 16% before the first pass out of a coated layer was
//! modelled (`first_pass` in `math::layering`); they are held to the plain bound.
//!
//! The other methods' failures are printed, not asserted (they break energy conservation by
//! design).

mod common;

use glazec::model::Method;
use glazec::stability::{self, ANGLES, Failures, Map, Sweep};

/// Largest albedo measured for the default method's known energy gains (CPU and lavapipe agree).
const GRAZING_MEASURED: f64 = 1.0021;
const IOR_BELOW_ONE_MEASURED: f64 = 1.0013;
/// The grazing gain appears only this close to 90° (degrees).
const GRAZING_FROM: f32 = 89.0;

/// Checks the default method's map of one sweep; returns what is wrong.
fn check_default(map: &Map, sweep: &Sweep) -> Vec<String> {
    let mut problems = Vec::new();
    let f = Failures::of(map);
    if f.non_finite > 0 || f.negative > 0 || f.jumps > 0 {
        problems.push(format!(
            "{}: {} non-finite, {} negative, {} discontinuities",
            sweep.name, f.non_finite, f.negative, f.jumps
        ));
    }
    for (p, row) in map.cells.iter().enumerate() {
        for (column, cell) in row.iter().enumerate() {
            if !cell.energy_gain() {
                continue;
            }
            let angle = ANGLES.get(column).copied().unwrap_or(90.0); // the last column: denormal cosine
            let bound = match sweep.name {
                "IOR below the medium" => IOR_BELOW_ONE_MEASURED,
                _ if angle >= GRAZING_FROM => GRAZING_MEASURED,
                _ => stability::ENERGY_BOUND,
            };
            if cell.albedo > bound {
                problems.push(format!(
                    "{} = {} at {angle}°: E = {:.5} > {bound}",
                    sweep.name, sweep.values[p], cell.albedo
                ));
            }
        }
    }
    problems
}

fn report(label: &str, maps: &[Map], sweeps: &[Sweep]) {
    eprintln!("{label}:\n{}", stability::summary(maps, sweeps));
}

#[test]
fn default_method_is_stable_on_the_cpu_and_the_others_are_reported() {
    let sweeps = stability::sweeps(true);
    let mut maps = Vec::new();
    let mut problems = Vec::new();
    for method in [Method::INTERFACED, Method::WeidlichWilkie, Method::Additive] {
        for sweep in &sweeps {
            let map = stability::run(sweep, method, &mut stability::cpu_evaluator, true);
            if method == Method::INTERFACED {
                problems.extend(check_default(&map, sweep));
            }
            maps.push(map);
        }
    }
    report("CPU, reduced sweep", &maps, &sweeps);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // The seed's method and Disney clear-coat gain energy in every sweep (reported above).
    for map in maps.iter().filter(|m| m.method != Method::INTERFACED) {
        assert!(Failures::of(map).energy_gain > 0, "{:?} on {} shows no energy gain", map.method, map.sweep);
    }
}

#[cfg(feature = "gpu")]
#[test]
fn default_method_is_stable_on_the_gpu() {
    use glam::Vec3;

    let Some(gpu) = common::open_gpu() else { return };
    let sweeps = stability::sweeps(true);
    let (mut maps, mut problems, mut shaders) = (Vec::new(), Vec::new(), 0);
    let mut on_gpu = |material: &glazec::model::Material, pairs: &[(Vec3, Vec3)]| -> Vec<Vec3> {
        shaders += 1;
        stability::gpu_evaluation(&gpu, material, pairs).unwrap_or_else(|e| panic!("{e}"))
    };
    for sweep in &sweeps {
        // Discontinuities are sought on the CPU (the refinement compiles a shader per bisection);
        // the agreement tests tie the GPU's values to the CPU's.
        let map = stability::run(sweep, Method::INTERFACED, &mut on_gpu, false);
        problems.extend(check_default(&map, sweep));
        maps.push(map);
    }
    report(&format!("lavapipe, reduced sweep ({shaders} shaders)"), &maps, &sweeps);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
