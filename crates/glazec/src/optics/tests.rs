use super::*;

/// Round trips must recover the coefficients to this relative error.
const ROUND_TRIP: f64 = 1e-9;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1e-300)
}

/// (σa, σs′) pairs per unit thickness: weakly to strongly absorbing, weakly to strongly scattering.
fn coefficient_grid() -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for a in [0.01, 0.05, 0.2, 0.8, 2.0] {
        for s in [0.1, 0.5, 2.0, 8.0, 30.0] {
            out.push((a, s));
        }
    }
    out
}

const SLAB: Slab = Slab { f_top: 0.06, f_bottom: 0.4, p_g: 0.5, eta: 1.5 };

#[test]
fn kubelka_munk_black_white_round_trips() {
    let mut cases = 0;
    for (sigma_a, sigma_s) in coefficient_grid() {
        let (k, s) = (2.0 * sigma_a, (3.0 * sigma_s - sigma_a) / 4.0);
        if s <= 0.0 {
            continue;
        }
        for x in [0.05, 0.3, 1.0] {
            let r0 = km_reflectance(k, s, x, 0.0);
            let rw = km_reflectance(k, s, x, 0.9);
            if rw - r0 < 1e-6 {
                continue; // so thick that the backing does not show: the closed form cannot resolve it
            }
            let sol = solve(&Observation::BlackWhite { r_black: r0, r_white: rw, backing: 0.9, thickness: x })
                .unwrap_or_else(|e| panic!("σa {sigma_a} σs′ {sigma_s} x {x}: {e}"));
            assert!(close(sol.sigma_a, sigma_a, ROUND_TRIP), "σa {} vs {sigma_a}", sol.sigma_a);
            assert!(close(sol.sigma_s, sigma_s, ROUND_TRIP), "σs′ {} vs {sigma_s}", sol.sigma_s);
            assert!(close(sol.albedo, km_r_infinity(k / s), 1e-12));
            cases += 1;
        }
    }
    assert!(cases > 40, "{cases} cases");
}

#[test]
fn kubelka_munk_round_trips_to_1e9_where_the_backing_shows() {
    for (k, s, x) in [(0.1, 1.0, 0.5), (0.4, 3.0, 0.2), (1.0, 0.5, 1.0), (0.02, 10.0, 0.1)] {
        let (r0, rw) = (km_reflectance(k, s, x, 0.0), km_reflectance(k, s, x, 0.85));
        let (k2, s2) = km_from_black_white(r0, rw, 0.85, x).expect("solves");
        assert!(close(k2, k, ROUND_TRIP) && close(s2, s, ROUND_TRIP), "K {k2} vs {k}, S {s2} vs {s}");
    }
}

#[test]
fn two_thicknesses_round_trip_for_both_slab_models() {
    for model in [SlabModel::Seed, SlabModel::Exponential] {
        let mut cases = 0;
        for (sigma_a, sigma_s) in coefficient_grid() {
            // The seed model is only monotone (and meaningful) at small optical depth.
            let (d1, d2) = match model {
                SlabModel::Seed => (0.05 / (sigma_a + sigma_s), 0.15 / (sigma_a + sigma_s)),
                SlabModel::Exponential => (0.3 / (sigma_a + sigma_s), 1.2 / (sigma_a + sigma_s)),
            };
            let r1 = model.reflectance(SLAB, d1, sigma_a, sigma_s);
            let r2 = model.reflectance(SLAB, d2, sigma_a, sigma_s);
            let sol = solve(&Observation::TwoThicknesses { model, slab: SLAB, d1, r1, d2, r2 })
                .unwrap_or_else(|e| panic!("{model:?} σa {sigma_a} σs′ {sigma_s}: {e}"));
            assert!(
                close(sol.sigma_a, sigma_a, ROUND_TRIP),
                "{model:?}: σa {} vs {sigma_a} (σs′ {sigma_s})",
                sol.sigma_a
            );
            assert!(
                close(sol.sigma_s, sigma_s, ROUND_TRIP),
                "{model:?}: σs′ {} vs {sigma_s} (σa {sigma_a})",
                sol.sigma_s
            );
            cases += 1;
        }
        assert_eq!(cases, 25);
    }
}

#[test]
fn one_reflectance_with_known_scattering_round_trips_and_the_quadratic_matches_bisection() {
    for model in [SlabModel::Seed, SlabModel::Exponential] {
        for (sigma_a, sigma_s) in coefficient_grid() {
            let d = 0.1 / (sigma_a + sigma_s);
            let r = model.reflectance(SLAB, d, sigma_a, sigma_s);
            let sol = solve(&Observation::KnownScattering { model, slab: SLAB, d, r, sigma_s }).expect("solves");
            assert!(close(sol.sigma_a, sigma_a, ROUND_TRIP), "{model:?}: {} vs {sigma_a}", sol.sigma_a);
            if model == SlabModel::Seed {
                // The closed form against a plain bisection of the forward model.
                let (mut lo, mut hi) = (0.0, (1.0 - sigma_s * SLAB.p_g * d) / d);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if seed_reflectance(SLAB, d, mid, sigma_s) > r { lo = mid } else { hi = mid }
                }
                assert!(close(sol.sigma_a, 0.5 * (lo + hi), 1e-12), "quadratic {} vs bisection {}", sol.sigma_a, lo);
            }
        }
    }
}

#[test]
fn one_reflectance_with_a_known_ratio_round_trips_where_the_root_is_unique() {
    let mut solved = 0;
    for (sigma_a, sigma_s) in coefficient_grid() {
        let d = 0.5 / (sigma_a + sigma_s);
        let slab = Slab { f_bottom: 0.0, ..SLAB };
        let r = exponential_reflectance(slab, d, sigma_a, sigma_s);
        let observation =
            Observation::KnownRatio { model: SlabModel::Exponential, slab, d, r, ratio: sigma_s / sigma_a };
        if let Ok(sol) = solve(&observation) {
            assert!(close(sol.sigma_a, sigma_a, ROUND_TRIP), "{} vs {sigma_a}", sol.sigma_a);
            assert!(close(sol.sigma_s, sigma_s, ROUND_TRIP));
            solved += 1;
        }
    }
    assert!(solved >= 20, "{solved} of 25 solved");
}

#[test]
fn dipole_round_trips_through_the_mean_free_path() {
    for (sigma_a, sigma_s) in coefficient_grid() {
        let alpha = sigma_s / (sigma_a + sigma_s);
        let r = dipole_albedo(alpha, 1.4);
        let mfp = 1.0 / (3.0 * sigma_a * (sigma_a + sigma_s)).sqrt();
        let sol = solve(&Observation::MeanFreePath { r, mfp, eta: 1.4 }).expect("solves");
        assert!(close(sol.sigma_a, sigma_a, ROUND_TRIP), "σa {} vs {sigma_a}", sol.sigma_a);
        assert!(close(sol.sigma_s, sigma_s, ROUND_TRIP), "σs′ {} vs {sigma_s}", sol.sigma_s);
    }
}

#[test]
fn closed_forms_agree_with_limits_and_numerical_derivatives() {
    // R∞ is the limit of a thick layer over any backing.
    for (k, s) in [(0.1, 1.0), (1.0, 0.3), (0.01, 5.0)] {
        for rg in [0.0, 0.5, 0.95] {
            assert!(close(km_reflectance(k, s, 200.0 / s, rg), km_r_infinity(k / s), 1e-10));
        }
    }
    // The seed model is the exponential one to first order in σt·d.
    let (a, s, d) = (0.3, 2.0, 1e-4);
    assert!(close(seed_reflectance(SLAB, d, a, s), exponential_reflectance(SLAB, d, a, s), 1e-4));
    // Analytic derivatives against central differences.
    for model in [SlabModel::Seed, SlabModel::Exponential] {
        let (ga, gs) = model.gradient(SLAB, 0.1, 0.7, 3.0);
        let h = 1e-6;
        let na = (model.reflectance(SLAB, 0.1, 0.7 + h, 3.0) - model.reflectance(SLAB, 0.1, 0.7 - h, 3.0)) / (2.0 * h);
        let ns = (model.reflectance(SLAB, 0.1, 0.7, 3.0 + h) - model.reflectance(SLAB, 0.1, 0.7, 3.0 - h)) / (2.0 * h);
        assert!(close(ga, na, 1e-6) && close(gs, ns, 1e-6), "{model:?}: ({ga}, {gs}) vs ({na}, {ns})");
    }
    for alpha in [0.1, 0.5, 0.9, 0.99] {
        let h = 1e-7;
        let numeric = (dipole_albedo(alpha + h, 1.3) - dipole_albedo(alpha - h, 1.3)) / (2.0 * h);
        assert!(close(dipole_albedo_derivative(alpha, 1.3), numeric, 1e-6));
    }
    // Egan & Hilgeman at η = 1.5: internal ≈ 0.6, external ≈ 0.09.
    assert!((diffuse_fresnel_internal(1.5) - 0.596).abs() < 0.01);
    assert!((diffuse_fresnel_external(1.5) - 0.092).abs() < 0.01, "{}", diffuse_fresnel_external(1.5));
}

#[test]
fn impossible_or_insufficient_observations_are_rejected_with_reasons() {
    assert_eq!(solve(&Observation::Single { r: 0.4 }), Err(OpticsError::SingleReflectance));
    assert!(OpticsError::SingleReflectance.to_string().contains("black and a white backing"));
    for r in [1.0, 1.2, 0.0, -0.1, f64::NAN] {
        assert!(matches!(solve(&Observation::Single { r }), Err(OpticsError::OutOfRange { .. })), "{r}");
    }
    let white_below_black = Observation::BlackWhite { r_black: 0.5, r_white: 0.4, backing: 0.9, thickness: 1.0 };
    assert!(matches!(solve(&white_below_black), Err(OpticsError::Inconsistent(m)) if m.contains("must exceed")));
    let equal =
        Observation::TwoThicknesses { model: SlabModel::Exponential, slab: SLAB, d1: 1.0, r1: 0.3, d2: 1.0, r2: 0.4 };
    assert!(matches!(solve(&equal), Err(OpticsError::Inconsistent(m)) if m.contains("equal")));
    let too_bright =
        Observation::KnownScattering { model: SlabModel::Exponential, slab: SLAB, d: 0.1, r: 0.9, sigma_s: 0.5 };
    assert!(matches!(solve(&too_bright), Err(OpticsError::Inconsistent(m)) if m.contains("σs′ is too small")));
}

#[test]
fn the_seed_model_past_its_regime_warns() {
    let (sigma_a, sigma_s) = (0.5, 2.0);
    let (d1, d2) = (0.2, 0.3); // σt·d up to 0.45
    let r1 = seed_reflectance(SLAB, d1, sigma_a, sigma_s);
    let r2 = seed_reflectance(SLAB, d2, sigma_a, sigma_s);
    let sol =
        solve(&Observation::TwoThicknesses { model: SlabModel::Seed, slab: SLAB, d1, r1, d2, r2 }).expect("solves");
    assert_eq!(sol.warnings.len(), 1);
    assert!(sol.warnings[0].contains("use the exponential model"), "{:?}", sol.warnings);
}
