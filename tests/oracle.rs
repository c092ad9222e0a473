//! Oracle test: `glazec eval` on a smooth absorbing dielectric coat over a Lambertian base, with
//! the default `Interfaced` method, against an independent f64 implementation of the closed form
//!
//! ```text
//! f(ωi, ωo) = ρ (1 − F(μi)) (1 − F(μo)) e^{−τ (1/μti + 1/μto)} / (π η² (1 − ρ R_ret(τ)))
//! R_ret(τ)  = ∫₀¹ 2μ e^{−2τ/μ} F_int(μ) dμ
//! ```
//!
//! η: coat IOR relative to the medium above; ρ: base albedo; τ = σa·d; μ: cosines above the coat;
//! μt = sqrt(1 − (1 − μ²)/η²): refracted cosines inside; F: exact unpolarised dielectric Fresnel
//! from outside; F_int: the same from inside (relative IOR 1/η, 1 under total internal
//! reflection). The smooth coat's mirror reflection is a delta, so exact mirror pairs are left out
//! of the grid. Directions below or on the horizon (z ≤ 0) give f = 0.
//!
//! Nothing here calls glazec's math: Fresnel, the quadrature of R_ret and f are written afresh.
//! The reference is evaluated at exactly the inputs glazec reads: the f32 values of the material
//! numbers and of the direction components written to the pairs file (then normalised in f64).

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

// ---------------------------------------------------------------------------------------------
// Tolerances and grid sizes.
// ---------------------------------------------------------------------------------------------

/// Relative tolerance of glazec's (f32) value against the f64 closed form. (Measured worst
/// on this grid: about 4.4e-6, at η = 2.5, ρ = 1, τ = 0.01. It comes from the fixed 12 + 12-node
/// quadrature of R_ret in f32: an error in R_ret of a few 1e-7 that varies in sign with τ, scaled by
/// ρ/(1 − ρ R_ret), which is largest for ρ = 1, high η and small τ > 0.)
const REL_TOL: f64 = 1e-5;
/// Absolute floor added to the tolerance, so that exact zeros (below-horizon pairs) compare.
const ABS_FLOOR: f64 = 1e-12;
/// Absolute error target of the adaptive Gauss–Kronrod quadrature of R_ret (whose value is in
/// [0, 1]); far below anything REL_TOL can see.
const QUAD_TOL: f64 = 1e-14;
/// Maximum bisection depth of the adaptive quadrature (never reached for these smooth integrands).
const QUAD_MAX_DEPTH: u32 = 40;
/// Polar angles (degrees) used for both θi and θo: normal incidence, the bulk, near-grazing
/// 85°–88°; every η in `ETAS` has its critical angle asin(1/η) ≤ 65.4°, so 65°–88° (and more
/// for larger η) lie beyond it.
const THETAS_DEG: [f64; 14] = [0.0, 5.0, 15.0, 25.0, 35.0, 45.0, 55.0, 65.0, 75.0, 80.0, 85.0, 86.0, 87.0, 88.0];
/// Number of relative azimuths Δφ = φo − φi, evenly spaced over [0°, 360°).
const N_DPHI: usize = 8;
/// Azimuth φi (degrees) of the incident direction is `PHI_I_STEP_DEG · (index of θi)`, so the
/// pairs are not all in one frame orientation (f depends only on Δφ here).
const PHI_I_STEP_DEG: f64 = 23.0;
/// Minimum number of direction pairs demanded of the grid.
const MIN_PAIRS: usize = 500;
/// Coat IORs.
const ETAS: [f64; 5] = [1.1, 1.33, 1.5, 2.0, 2.5];
/// Base albedos.
const ALBEDOS: [[f64; 3]; 2] = [[0.8, 0.5, 0.2], [1.0, 1.0, 1.0]];
/// (absorption σa per channel, thickness d): τ = σa·d covers 0, small, moderate and large.
const ABSORPTIONS: [([f64; 3], f64); 3] = [
    ([0.0, 0.3, 3.0], 1.0),     // τ = (0, 0.3, 3)
    ([1.0, 30.0, 300.0], 0.01), // τ = (0.01, 0.3, 3), through a thin slab
    ([1.0, 0.0, 0.3], 0.01),    // τ = (0.01, 0, 0.003)
];

// ---------------------------------------------------------------------------------------------
// Independent reference.
// ---------------------------------------------------------------------------------------------

/// Exact unpolarised Fresnel reflectance for light arriving at cosine `cos_i` (≥ 0) on an
/// interface of relative IOR `eta` = n_transmitted / n_incident. 1 under total internal reflection.
fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let c = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - c * c) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - sin2_t).sqrt();
    let rs = (c - eta * ct) / (c + eta * ct);
    let rp = (eta * c - ct) / (eta * c + ct);
    0.5 * (rs * rs + rp * rp)
}

/// 15-point Kronrod nodes (non-negative half, descending) and weights, with the weights of the
/// embedded 7-point Gauss rule (on the odd-indexed Kronrod nodes). Digits as tabulated (QUADPACK).
#[allow(clippy::excessive_precision)]
const XGK: [f64; 8] = [
    0.991455371120812639206854697526329,
    0.949107912342758524526189684047851,
    0.864864423359769072789712788640926,
    0.741531185599394439863864773280788,
    0.586087235467691130294144845693013,
    0.405845151377397166906606412076961,
    0.207784955007898467600689403773245,
    0.0,
];
#[allow(clippy::excessive_precision)]
const WGK: [f64; 8] = [
    0.022935322010529224963732008058970,
    0.063092092629978553290700663189204,
    0.104790010322250183839876322541518,
    0.140653259715525918745189590510238,
    0.169004726639267902826583426598550,
    0.190350578064785409913256402421014,
    0.204432940075298892414161999234649,
    0.209482141084727828012999174891714,
];
#[allow(clippy::excessive_precision)]
const WG: [f64; 4] = [
    0.129484966168869693270611432679082,
    0.279705391489276667901467771423780,
    0.381830050505118944950369775488975,
    0.417959183673469387755102040816327,
];

/// (Kronrod estimate, |Kronrod − Gauss|) of ∫_a^b g.
fn gk15(g: &dyn Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = g(c);
    let mut k = WGK[7] * fc;
    let mut gauss = WG[3] * fc;
    for j in 0..7 {
        let x = h * XGK[j];
        let s = g(c - x) + g(c + x);
        k += WGK[j] * s;
        if j % 2 == 1 {
            gauss += WG[j / 2] * s;
        }
    }
    (k * h, (k - gauss).abs() * h)
}

/// Adaptive Gauss–Kronrod quadrature of ∫_a^b g to absolute error `tol`.
fn integrate(g: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    fn rec(g: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, depth: u32) -> f64 {
        let (value, err) = gk15(g, a, b);
        if err <= tol || depth >= QUAD_MAX_DEPTH {
            return value;
        }
        let m = 0.5 * (a + b);
        rec(g, a, m, 0.5 * tol, depth + 1) + rec(g, m, b, 0.5 * tol, depth + 1)
    }
    if b <= a { 0.0 } else { rec(g, a, b, tol, 0) }
}

/// R_ret(τ) = ∫₀¹ 2μ e^{−2τ/μ} F_int(μ) dμ for a coat of relative IOR `eta` (> 1).
///
/// Split at the critical cosine μc = sqrt(1 − 1/η²): below it F_int = 1 (TIR). Above it the
/// substitution μ² = μc² + u² (so 2μ dμ = 2u du, u ∈ [0, 1/η]) removes the square-root kink of
/// F_int at μc: the cosine outside is η·u, and the Fresnel amplitudes (from index η to 1) become
/// rs = (μ − u)/(μ + u), rp = (μ − η²u)/(μ + η²u), smooth in u.
fn r_ret(tau: f64, eta: f64) -> f64 {
    assert!(eta > 1.0);
    let mu_c2 = 1.0 - 1.0 / (eta * eta);
    let atten = |mu: f64| {
        if tau == 0.0 {
            1.0
        } else if mu <= 0.0 {
            0.0
        } else {
            (-2.0 * tau / mu).exp()
        }
    };
    let tir = integrate(&|mu: f64| 2.0 * mu * atten(mu), 0.0, mu_c2.sqrt(), QUAD_TOL);
    let refr = integrate(
        &|u: f64| {
            let mu = (mu_c2 + u * u).sqrt();
            let rs = (mu - u) / (mu + u);
            let rp = (mu - eta * eta * u) / (mu + eta * eta * u);
            2.0 * u * atten(mu) * 0.5 * (rs * rs + rp * rp)
        },
        0.0,
        1.0 / eta,
        QUAD_TOL,
    );
    tir + refr
}

/// The coat-over-Lambert parameters of one channel.
#[derive(Clone, Copy, Debug)]
struct Channel {
    eta: f64,
    rho: f64,
    tau: f64,
    /// R_ret(τ), precomputed.
    r_ret: f64,
}

impl Channel {
    fn new(eta: f64, rho: f64, tau: f64) -> Self {
        Channel { eta, rho, tau, r_ret: r_ret(tau, eta) }
    }

    /// f(ωi, ωo) without the cosine; `wi`, `wo` need not be normalised.
    fn f(&self, wi: [f64; 3], wo: [f64; 3]) -> f64 {
        let cos = |w: [f64; 3]| w[2] / (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        let (mi, mo) = (cos(wi), cos(wo));
        if mi <= 0.0 || mo <= 0.0 {
            return 0.0;
        }
        let eta = self.eta;
        let mu_t = |mu: f64| (1.0 - (1.0 - mu * mu) / (eta * eta)).sqrt();
        let trans = (1.0 - fresnel(mi, eta)) * (1.0 - fresnel(mo, eta));
        let atten = (-self.tau * (1.0 / mu_t(mi) + 1.0 / mu_t(mo))).exp();
        self.rho * trans * atten / (std::f64::consts::PI * eta * eta * (1.0 - self.rho * self.r_ret))
    }
}

// ---------------------------------------------------------------------------------------------
// The direction pairs.
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug)]
struct PairSpec {
    /// Angles for the report (degrees); NaN for the hand-written below-horizon pairs.
    theta_i: f64,
    theta_o: f64,
    dphi: f64,
    /// The components as written (f32), widened to f64: what glazec reads.
    wi: [f64; 3],
    wo: [f64; 3],
}

fn to_f32_vec(v: [f64; 3]) -> [f64; 3] {
    v.map(|x| x as f32 as f64)
}

fn dir(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]
}

fn pair_grid() -> Vec<PairSpec> {
    let mut pairs = Vec::new();
    for (ii, &ti) in THETAS_DEG.iter().enumerate() {
        let phi_i = PHI_I_STEP_DEG * ii as f64;
        for &to in &THETAS_DEG {
            for k in 0..N_DPHI {
                let dphi = 360.0 * k as f64 / N_DPHI as f64;
                // At θ = 0 the azimuth means nothing: one Δφ is enough.
                if (ti == 0.0 || to == 0.0) && k > 0 {
                    continue;
                }
                // The exact mirror pair carries the coat's delta lobe: not a BRDF value.
                let mirror = ti == to && (ti == 0.0 || dphi == 180.0);
                if mirror {
                    continue;
                }
                pairs.push(PairSpec {
                    theta_i: ti,
                    theta_o: to,
                    dphi,
                    wi: to_f32_vec(dir(ti, phi_i)),
                    wo: to_f32_vec(dir(to, phi_i + dphi)),
                });
            }
        }
    }
    // Below (and on) the horizon: f must be exactly 0.
    let up = dir(30.0, 10.0);
    let below: [([f64; 3], [f64; 3]); 6] = [
        ([0.3, 0.2, -0.5], up),
        (up, [0.1, -0.4, -0.8]),
        ([0.0, 0.0, -1.0], [0.0, 0.0, -1.0]),
        ([0.6, 0.0, -0.01], [-0.5, 0.5, 0.7]),
        ([1.0, 0.0, 0.0], up),
        (up, [0.0, 1.0, 0.0]),
    ];
    for (wi, wo) in below {
        pairs.push(PairSpec {
            theta_i: f64::NAN,
            theta_o: f64::NAN,
            dphi: f64::NAN,
            wi: to_f32_vec(wi),
            wo: to_f32_vec(wo),
        });
    }
    pairs
}

fn write_pairs_csv(path: &Path, pairs: &[PairSpec]) {
    let mut text = String::from("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n");
    for p in pairs {
        // f32 Display is the shortest text reading back as the same f32: exactly `p.wi`, `p.wo`.
        let c: Vec<String> = p.wi.iter().chain(&p.wo).map(|&x| format!("{}", x as f32)).collect();
        writeln!(text, "{}", c.join(",")).unwrap();
    }
    std::fs::write(path, text).expect("write pairs csv");
}

// ---------------------------------------------------------------------------------------------
// Running glazec.
// ---------------------------------------------------------------------------------------------

fn run_eval(material: &Path, pairs: &Path) -> Vec<[f64; 3]> {
    let out = Command::new(env!("CARGO_BIN_EXE_glazec"))
        .arg("eval")
        .arg(material)
        .arg("--pairs")
        .arg(pairs)
        .args(["--backend", "cpu"])
        .output()
        .expect("run glazec");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "glazec eval failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr),
        stdout
    );
    stdout
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> =
                l.split(',').map(|x| x.trim().parse::<f64>().unwrap_or_else(|_| panic!("bad line `{l}`"))).collect();
            assert_eq!(v.len(), 3, "bad line `{l}`");
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// One (value, reference) comparison, kept for the report.
#[derive(Clone, Debug)]
struct Sample {
    eta: f64,
    rho: f64,
    tau: f64,
    channel: usize,
    pair: PairSpec,
    glazec: f64,
    reference: f64,
}

impl Sample {
    fn rel_err(&self) -> f64 {
        let d = (self.glazec - self.reference).abs();
        if self.reference == 0.0 { if d == 0.0 { 0.0 } else { f64::INFINITY } } else { d / self.reference.abs() }
    }
    fn ok(&self) -> bool {
        (self.glazec - self.reference).abs() <= REL_TOL * self.reference.abs() + ABS_FLOOR
    }
    fn describe(&self) -> String {
        format!(
            "η = {}, ρ = {}, τ = {} (channel {}), θi = {}°, θo = {}°, Δφ = {}°, wi = {:?}, wo = {:?}: \
             glazec = {:e}, reference = {:e}, relative error = {:e}",
            self.eta,
            self.rho,
            self.tau,
            self.channel,
            self.pair.theta_i,
            self.pair.theta_o,
            self.pair.dphi,
            self.pair.wi,
            self.pair.wo,
            self.glazec,
            self.reference,
            self.rel_err()
        )
    }
}

#[test]
fn interfaced_smooth_coat_over_lambert_matches_closed_form() {
    let dir = tempfile::tempdir().expect("temp dir");
    let pairs = pair_grid();
    assert!(pairs.len() >= MIN_PAIRS, "only {} pairs", pairs.len());
    let pairs_path = dir.path().join("pairs.csv");
    write_pairs_csv(&pairs_path, &pairs);

    let mut samples: Vec<Sample> = Vec::new();
    for (ie, &eta) in ETAS.iter().enumerate() {
        for (ia, albedo) in ALBEDOS.iter().enumerate() {
            for (ib, (sigma, thickness)) in ABSORPTIONS.iter().enumerate() {
                let text = format!(
                    "Material(name: \"oracle\", layers: [Coat(lobe: Smooth, ior: {:?}, absorption: ({:?}, {:?}, {:?}), \
                     thickness: {:?}), Lambert(albedo: ({:?}, {:?}, {:?}))])\n",
                    eta, sigma[0], sigma[1], sigma[2], thickness, albedo[0], albedo[1], albedo[2]
                );
                let path = dir.path().join(format!("oracle_{ie}_{ia}_{ib}.ron"));
                std::fs::write(&path, &text).expect("write material");
                let values = run_eval(&path, &pairs_path);
                assert_eq!(
                    values.len(),
                    pairs.len(),
                    "glazec printed {} lines for {} pairs",
                    values.len(),
                    pairs.len()
                );

                // The reference at the f32 inputs glazec reads.
                let f32v = |x: f64| x as f32 as f64;
                let channels: Vec<Channel> = (0..3)
                    .map(|c| Channel::new(f32v(eta), f32v(albedo[c]), f32v(sigma[c]) * f32v(*thickness)))
                    .collect();
                for (p, v) in pairs.iter().zip(&values) {
                    for (c, ch) in channels.iter().enumerate() {
                        samples.push(Sample {
                            eta,
                            rho: albedo[c],
                            tau: sigma[c] * thickness,
                            channel: c,
                            pair: *p,
                            glazec: v[c],
                            reference: ch.f(p.wi, p.wo),
                        });
                    }
                }
            }
        }
    }

    let worst = samples.iter().max_by(|a, b| a.rel_err().total_cmp(&b.rel_err())).expect("samples");
    let failures: Vec<&Sample> = samples.iter().filter(|s| !s.ok()).collect();
    eprintln!(
        "oracle: {} comparisons ({} pairs × {} materials × 3 channels); worst relative error {:e}",
        samples.len(),
        pairs.len(),
        ETAS.len() * ALBEDOS.len() * ABSORPTIONS.len(),
        worst.rel_err()
    );
    eprintln!("oracle: worst case: {}", worst.describe());
    if !failures.is_empty() {
        let worst_fail = failures.iter().max_by(|a, b| a.rel_err().total_cmp(&b.rel_err())).unwrap();
        panic!(
            "{} of {} values exceed REL_TOL = {:e}; worst: {}",
            failures.len(),
            samples.len(),
            REL_TOL,
            worst_fail.describe()
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The reference itself.
// ---------------------------------------------------------------------------------------------

#[test]
fn reference_is_sane() {
    // Fresnel at normal incidence: ((η − 1)/(η + 1))² = 0.04 for η = 1.5, either side.
    assert!((fresnel(1.0, 1.5) - 0.04).abs() < 1e-15);
    assert!((fresnel(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-15);
    // Total internal reflection beyond the critical angle, and grazing incidence.
    assert_eq!(fresnel(0.5, 1.0 / 1.5), 1.0);
    assert!((fresnel(0.0, 1.5) - 1.0).abs() < 1e-15);

    // The Kronrod rule integrates polynomials to degree 22 exactly, the Gauss rule to 13.
    for k in 0..=22 {
        let (v, _) = gk15(&|x: f64| x.powi(k), 0.0, 1.0);
        assert!((v - 1.0 / (k as f64 + 1.0)).abs() < 1e-15, "K15 x^{k}: {v}");
    }
    let (_, err) = gk15(&|x: f64| x.powi(13), 0.0, 1.0);
    assert!(err < 1e-15, "G7 should be exact for x^13 (err {err})");

    // R_ret(0) for η = 1.5 (the internal diffuse reflectance of glass).
    let r0 = r_ret(0.0, 1.5);
    assert!((r0 - 0.59635).abs() < 1e-4, "R_ret(0) = {r0}");

    // The inside/outside reciprocity 1 − R_ret(0) = (1 − F̄)/η², with F̄ = ∫₀¹ 2μ F(μ) dμ from
    // outside — computed by a different route (the plain Fresnel function, no substitution).
    for eta in ETAS {
        let f_bar = integrate(&|mu: f64| 2.0 * mu * fresnel(mu, eta), 0.0, 1.0, QUAD_TOL);
        let lhs = 1.0 - r_ret(0.0, eta);
        let rhs = (1.0 - f_bar) / (eta * eta);
        assert!((lhs - rhs).abs() < 1e-12, "η = {eta}: 1 − R_ret(0) = {lhs}, (1 − F̄)/η² = {rhs}");

        // R_ret(τ) computed the plain way (F_int through `fresnel`, split at μc) agrees.
        for tau in [0.01, 0.3, 3.0] {
            let mu_c = (1.0 - 1.0 / (eta * eta)).sqrt();
            let g = |mu: f64| {
                if mu <= 0.0 { 0.0 } else { 2.0 * mu * (-2.0 * tau / mu).exp() * fresnel(mu, 1.0 / eta) }
            };
            let plain = integrate(&g, 0.0, mu_c, 1e-15) + integrate(&g, mu_c, 1.0, 1e-15);
            let r = r_ret(tau, eta);
            assert!((plain - r).abs() < 1e-10, "η = {eta}, τ = {tau}: {plain} vs {r}");
        }

        // Energy: with τ = 0 and ρ = 1 nothing is absorbed, so the directional albedo
        // ∫ f μi dωi plus the mirror reflection F(μo) is 1 for every μo.
        let ch = Channel::new(eta, 1.0, 0.0);
        for mo in [1.0_f64, 0.7, 0.3, 0.05] {
            let wo = [(1.0 - mo * mo).sqrt(), 0.0, mo];
            // f does not depend on φ here: ∫ f μi dωi = 2π ∫₀¹ f(μi) μi dμi.
            let diffuse = 2.0
                * std::f64::consts::PI
                * integrate(&|mi: f64| ch.f([(1.0 - mi * mi).sqrt(), 0.0, mi], wo) * mi, 0.0, 1.0, QUAD_TOL);
            let total = diffuse + fresnel(mo, eta);
            assert!((total - 1.0).abs() < 1e-10, "η = {eta}, μo = {mo}: albedo {total}");
        }
    }
}
