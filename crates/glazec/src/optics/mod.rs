//! Measured optics (the clay-optics paper): absorption σa and reduced scattering σs′ of a turbid
//! layer (clay) from measured diffuse reflectance, and the diffuse albedo a renderer needs.
//!
//! The clay-optics paper recovers (σa, σs′) from one spectrophotometer reading with an MMSE fit
//! (40 ms per solve). One reflectance cannot fix two unknowns (docs/derivations.md, "The
//! clay-optics forward model"): every inversion here takes a second observation or a prior, and
//! says which when it is missing. All arithmetic is f64; every solve is closed form or a
//! safeguarded Newton iteration of a few steps.
//!
//! | observation | model | solver |
//! |---|---|---|
//! | over black and over white backing (one thickness) | Kubelka–Munk | closed form |
//! | two thicknesses | paper's eq. 1, or its exponential form | 2×2 Newton in log σ, analytic Jacobian |
//! | one reflectance + known σs′ | paper's eq. 1 (quadratic, closed form) or exponential (1-D Newton) | |
//! | one reflectance + known ratio σs′/σa | paper's eq. 1 or exponential | bracketed 1-D solve |
//! | one reflectance + diffuse mean free path | diffusion dipole (Jensen et al. 2001) | 1-D Newton |
//!
//! The diffuse albedo of the material (what a Lambert or EON base uses) is Kubelka–Munk's R∞ for
//! Kubelka–Munk inversions, and otherwise the dipole's R_d(α′) with α′ = σs′/(σa + σs′).

/// The seed model is only sound while its linearisation (1 − x)² ≈ e^(−2x) holds: −4.5% at
/// x = σt·d = 0.2 (docs/derivations.md, "The clay-optics forward model").
pub const SEED_MODEL_MAX_OPTICAL_DEPTH: f64 = 0.2;
/// Newton iterations before a solve gives up.
const MAX_ITERATIONS: usize = 100;
/// Relative change at which Newton has converged.
const CONVERGED: f64 = 1e-14;

/// Why no coefficients came out.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OpticsError {
    #[error(
        "one reflectance cannot fix two unknowns (σa and σs′): measure the sample over a black and a white \
         backing, or at a second thickness, or give σs′, the ratio σs′/σa or the diffuse mean free path"
    )]
    SingleReflectance,
    #[error("{what} = {} is outside {range}", show(*.value))]
    OutOfRange { what: &'static str, value: f64, range: &'static str },
    #[error("{0}")]
    Inconsistent(String),
    #[error("the solve did not converge: {0}")]
    NoConvergence(String),
    #[error("missing `{0}`: {1}")]
    Missing(&'static str, &'static str),
}

/// A reading as a person wrote it: at most six decimals, trailing zeros dropped (inputs often
/// come from f32 and would otherwise print as 0.44999998807907104).
pub fn show(x: f64) -> String {
    let text = format!("{x:.6}");
    let trimmed = text.trim_end_matches('0').trim_end_matches('.');
    if trimmed.is_empty() || trimmed == "-" { "0".into() } else { trimmed.to_string() }
}

fn check_range(what: &'static str, value: f64, lo: f64, hi: f64, range: &'static str) -> Result<(), OpticsError> {
    if value.is_finite() && value > lo && value < hi {
        Ok(())
    } else {
        Err(OpticsError::OutOfRange { what, value, range })
    }
}

fn reflectance(what: &'static str, value: f64) -> Result<(), OpticsError> {
    check_range(what, value, 0.0, 1.0, "(0, 1)")
}

fn positive(what: &'static str, value: f64) -> Result<(), OpticsError> {
    check_range(what, value, 0.0, f64::INFINITY, "(0, ∞)")
}

// ---------------------------------------------------------------------------------------------
// Boundaries

/// Egan & Hilgeman 1979 fit of the internal diffuse Fresnel reflectance of a boundary of relative
/// index η (light inside the medium): F_dr(η) = −1.440/η² + 0.710/η + 0.668 + 0.0636η. Within
/// 5·10⁻⁴ of 1 − (1 − E_F)/η² for η ∈ [1.3, 2] (docs/derivations.md, "Diffuse reflectance
/// relations").
pub fn diffuse_fresnel_internal(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

/// The external diffuse Fresnel reflectance (light from outside, averaged over a cosine-weighted
/// hemisphere), from the internal one by energy balance across the boundary:
/// E_F = 1 − η²(1 − F_dr) (docs/derivations.md, "Diffuse reflectance relations"). About 0.09
/// for η = 1.5.
pub fn diffuse_fresnel_external(eta: f64) -> f64 {
    1.0 - eta * eta * (1.0 - diffuse_fresnel_internal(eta))
}

/// The boundaries of a slab in the clay-optics paper's eq. 1: transmission loss at the top
/// (F_dr,t) and reflection at the bottom (F_dr,b), and P(g), the share of the phase function
/// scattering backwards.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    pub f_top: f64,
    pub f_bottom: f64,
    pub p_g: f64,
    /// The boundary's relative index, for the diffuse albedo of the result (dipole).
    pub eta: f64,
}

impl Default for Slab {
    /// An index-matched top (no loss), a black bottom, isotropic scattering (P = ½).
    fn default() -> Self {
        Slab { f_top: 0.0, f_bottom: 0.0, p_g: 0.5, eta: 1.5 }
    }
}

// ---------------------------------------------------------------------------------------------
// Forward models

/// The clay-optics paper, eq. 1 (after its ref. 4):
/// R_d = (1 − F_dr,t)·[s(d − σa d² + σa² d³/3) + F_dr,b (1 − σa d − s d)²] with s = σs′·P(g):
/// single scattering with the two-way attenuation e^(−2σa z) linearised to (1 − σa z)², plus the
/// bottom's reflection, attenuation linearised too.
/// Sound only for σt·d ≲ [`SEED_MODEL_MAX_OPTICAL_DEPTH`].
pub fn seed_reflectance(slab: Slab, d: f64, sigma_a: f64, sigma_s: f64) -> f64 {
    let s = sigma_s * slab.p_g;
    let single = s * (d - sigma_a * d * d + sigma_a * sigma_a * d * d * d / 3.0);
    let bottom = slab.f_bottom * (1.0 - sigma_a * d - s * d).powi(2);
    (1.0 - slab.f_top) * (single + bottom)
}

/// The exact exponential counterpart of the clay-optics paper's eq. 1 (docs/derivations.md, "The
/// clay-optics forward model"): R_d = (1 − F_dr,t)·[s(1 − e^(−2σa d))/(2σa) + F_dr,b e^(−2σt d)],
/// σt = σa + s, s = σs′·P(g).
pub fn exponential_reflectance(slab: Slab, d: f64, sigma_a: f64, sigma_s: f64) -> f64 {
    let s = sigma_s * slab.p_g;
    (1.0 - slab.f_top) * (s * single_path(sigma_a, d) + slab.f_bottom * (-2.0 * (sigma_a + s) * d).exp())
}

/// ∫₀^d e^(−2σa z) dz = (1 − e^(−2σa d))/(2σa), with its σa → 0 limit d.
fn single_path(sigma_a: f64, d: f64) -> f64 {
    let x = 2.0 * sigma_a * d;
    // Guard: for x → 0 the quotient cancels; −expm1(−x)/x is accurate everywhere.
    if x == 0.0 { d } else { -(-x).exp_m1() / x * d }
}

/// Kubelka & Munk 1931: the reflectance of an infinitely thick layer,
/// R∞ = 1 + K/S − √((K/S)² + 2K/S).
pub fn km_r_infinity(k_over_s: f64) -> f64 {
    1.0 + k_over_s - (k_over_s * k_over_s + 2.0 * k_over_s).sqrt()
}

/// Kubelka & Munk 1931: a layer of thickness x over a background of reflectance R_g:
/// R = [1 − R_g(a − b coth(bSx))]/[a − R_g + b coth(bSx)], a = 1 + K/S, b = √(a² − 1).
pub fn km_reflectance(k: f64, s: f64, x: f64, r_g: f64) -> f64 {
    let a = 1.0 + k / s;
    let b = (a * a - 1.0).sqrt();
    let coth = 1.0 / (b * s * x).tanh();
    (1.0 - r_g * (a - b * coth)) / (a - r_g + b * coth)
}

/// Kubelka–Munk coefficients → transport coefficients by the common diffusion correspondence
/// K = 2σa, S = (3σs′ − σa)/4 (several conventions exist; docs/derivations.md, "Diffuse
/// reflectance relations").
pub fn km_to_transport(k: f64, s: f64) -> (f64, f64) {
    let sigma_a = k / 2.0;
    (sigma_a, (4.0 * s + sigma_a) / 3.0)
}

/// Jensen, Marschner, Levoy & Hanrahan 2001 (after Farrell, Patterson & Wilson 1992), the
/// diffusion dipole's total diffuse reflectance: R_d = (α′/2)(1 + e^(−(4/3)A√(3(1−α′))))
/// e^(−√(3(1−α′))), A = (1 + F_dr)/(1 − F_dr), F_dr the internal diffuse Fresnel reflectance.
pub fn dipole_albedo(alpha: f64, eta: f64) -> f64 {
    let f_dr = diffuse_fresnel_internal(eta);
    let a = (1.0 + f_dr) / (1.0 - f_dr);
    let root = (3.0 * (1.0 - alpha)).max(0.0).sqrt();
    alpha / 2.0 * (1.0 + (-4.0 / 3.0 * a * root).exp()) * (-root).exp()
}

/// d R_d / d α′ of [`dipole_albedo`].
fn dipole_albedo_derivative(alpha: f64, eta: f64) -> f64 {
    let f_dr = diffuse_fresnel_internal(eta);
    let a = (1.0 + f_dr) / (1.0 - f_dr);
    let root = (3.0 * (1.0 - alpha)).max(1e-300).sqrt();
    let droot = -1.5 / root;
    let e1 = (-4.0 / 3.0 * a * root).exp();
    let e2 = (-root).exp();
    0.5 * (1.0 + e1) * e2 + alpha / 2.0 * (e1 * (-4.0 / 3.0 * a * droot) * e2 + (1.0 + e1) * e2 * (-droot))
}

// ---------------------------------------------------------------------------------------------
// Inversions

/// Which slab formula an inversion uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlabModel {
    /// The clay-optics paper's eq. 1 as published (linearised attenuation).
    Seed,
    /// Its exact exponential form.
    Exponential,
}

impl SlabModel {
    pub fn reflectance(self, slab: Slab, d: f64, sigma_a: f64, sigma_s: f64) -> f64 {
        match self {
            SlabModel::Seed => seed_reflectance(slab, d, sigma_a, sigma_s),
            SlabModel::Exponential => exponential_reflectance(slab, d, sigma_a, sigma_s),
        }
    }

    /// ∂R/∂σa and ∂R/∂σs′.
    fn gradient(self, slab: Slab, d: f64, sigma_a: f64, sigma_s: f64) -> (f64, f64) {
        let (_, d_a, d_s) = self.value_and_gradient(slab, d, sigma_a, sigma_s);
        (d_a, d_s)
    }

    /// R, ∂R/∂σa and ∂R/∂σs′ together (two exponentials for the exponential model).
    fn value_and_gradient(self, slab: Slab, d: f64, sigma_a: f64, sigma_s: f64) -> (f64, f64, f64) {
        let t = 1.0 - slab.f_top;
        let p = slab.p_g;
        let s = sigma_s * p;
        match self {
            SlabModel::Seed => {
                let lin = 1.0 - sigma_a * d - s * d;
                let path = d - sigma_a * d * d + sigma_a * sigma_a * d * d * d / 3.0;
                let value = t * (s * path + slab.f_bottom * lin * lin);
                let d_a = t * (s * (-d * d + 2.0 * sigma_a * d * d * d / 3.0) - 2.0 * slab.f_bottom * lin * d);
                let d_s = t * p * (path - 2.0 * slab.f_bottom * lin * d);
                (value, d_a, d_s)
            }
            SlabModel::Exponential => {
                let x = 2.0 * sigma_a * d;
                let e_a = (-x).exp();
                let bottom = slab.f_bottom * e_a * (-2.0 * s * d).exp();
                // ∫₀^d e^(−2σa z) dz = −expm1(−x)/x · d (accurate as x → 0), and its σa-derivative
                // d²·[x e^(−x) + expm1(−x)]·2/x² (→ −d² as x → 0).
                let (path, d_path) = if x < 1e-6 {
                    (d * (1.0 - 0.5 * x), -d * d)
                } else {
                    let em1 = (-x).exp_m1();
                    (-em1 / x * d, 2.0 * d * d * (x * e_a + em1) / (x * x))
                };
                let value = t * (s * path + bottom);
                let d_a = t * (s * d_path - 2.0 * d * bottom);
                let d_s = t * p * (path - 2.0 * d * bottom);
                (value, d_a, d_s)
            }
        }
    }
}

/// What a user measured (per channel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Observation {
    /// One reflectance and nothing else: rejected ([`OpticsError::SingleReflectance`]).
    Single { r: f64 },
    /// Kubelka–Munk: reflectance over a black backing and over a backing of reflectance
    /// `backing`, of a layer of thickness `thickness`.
    BlackWhite { r_black: f64, r_white: f64, backing: f64, thickness: f64 },
    /// The same material at two thicknesses, through a slab model.
    TwoThicknesses { model: SlabModel, slab: Slab, d1: f64, r1: f64, d2: f64, r2: f64 },
    /// One reflectance at thickness `d` and a known σs′.
    KnownScattering { model: SlabModel, slab: Slab, d: f64, r: f64, sigma_s: f64 },
    /// One reflectance at thickness `d` and a known ratio σs′/σa.
    KnownRatio { model: SlabModel, slab: Slab, d: f64, r: f64, ratio: f64 },
    /// A semi-infinite sample's diffuse reflectance and its diffuse mean free path ℓ_d = 1/σtr,
    /// through the diffusion dipole with boundary index η (Jensen & Buhler 2002).
    MeanFreePath { r: f64, mfp: f64, eta: f64 },
}

/// Coefficients recovered from an observation.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    pub sigma_a: f64,
    pub sigma_s: f64,
    /// The diffuse albedo of a thick layer of the material (see the module docs).
    pub albedo: f64,
    /// Things the user should know (a model pushed past its regime).
    pub warnings: Vec<String>,
}

/// Solves one channel.
///
/// # Errors
/// Inputs outside their ranges, inconsistent observations, or a single reflectance.
pub fn solve(observation: &Observation) -> Result<Solution, OpticsError> {
    match *observation {
        Observation::Single { r } => {
            reflectance("reflectance", r)?;
            Err(OpticsError::SingleReflectance)
        }
        Observation::BlackWhite { r_black, r_white, backing, thickness } => {
            let (k, s) = km_from_black_white(r_black, r_white, backing, thickness)?;
            let (sigma_a, sigma_s) = km_to_transport(k, s);
            Ok(Solution { sigma_a, sigma_s, albedo: km_r_infinity(k / s), warnings: Vec::new() })
        }
        Observation::TwoThicknesses { model, slab, d1, r1, d2, r2 } => {
            let (sigma_a, sigma_s) = two_thicknesses(model, slab, (d1, r1), (d2, r2))?;
            let warnings = regime_warnings(model, sigma_a, sigma_s, slab, d1.max(d2));
            Ok(with_dipole_albedo(sigma_a, sigma_s, slab.eta, warnings))
        }
        Observation::KnownScattering { model, slab, d, r, sigma_s } => {
            let sigma_a = known_scattering(model, slab, d, r, sigma_s)?;
            let warnings = regime_warnings(model, sigma_a, sigma_s, slab, d);
            Ok(with_dipole_albedo(sigma_a, sigma_s, slab.eta, warnings))
        }
        Observation::KnownRatio { model, slab, d, r, ratio } => {
            let sigma_a = known_ratio(model, slab, d, r, ratio)?;
            let warnings = regime_warnings(model, sigma_a, ratio * sigma_a, slab, d);
            Ok(with_dipole_albedo(sigma_a, ratio * sigma_a, slab.eta, warnings))
        }
        Observation::MeanFreePath { r, mfp, eta } => {
            reflectance("reflectance", r)?;
            positive("mean free path", mfp)?;
            check_range("η", eta, 1.0 - 1e-12, 3.0 + 1e-12, "[1, 3]")?;
            let alpha = dipole_alpha(r, eta)?;
            // Jensen & Buhler 2002: σt′ = 1/(ℓ_d √(3(1 − α′))), σa = (1 − α′)σt′, σs′ = α′σt′.
            let sigma_t = 1.0 / (mfp * (3.0 * (1.0 - alpha)).sqrt());
            Ok(Solution { sigma_a: (1.0 - alpha) * sigma_t, sigma_s: alpha * sigma_t, albedo: r, warnings: Vec::new() })
        }
    }
}

fn with_dipole_albedo(sigma_a: f64, sigma_s: f64, eta: f64, warnings: Vec<String>) -> Solution {
    let alpha = sigma_s / (sigma_a + sigma_s);
    Solution { sigma_a, sigma_s, albedo: dipole_albedo(alpha, eta), warnings }
}

fn regime_warnings(model: SlabModel, sigma_a: f64, sigma_s: f64, slab: Slab, d: f64) -> Vec<String> {
    let depth = (sigma_a + sigma_s * slab.p_g) * d;
    if model == SlabModel::Seed && depth > SEED_MODEL_MAX_OPTICAL_DEPTH {
        vec![format!(
            "σt·d = {depth:.3} exceeds {SEED_MODEL_MAX_OPTICAL_DEPTH}: eq. 1 of the clay-optics paper linearises e^(−2x) as (1 − x)², \
             {:.0}% off here; use the exponential model",
            100.0 * (1.0 - (1.0 - depth).powi(2) / (-2.0 * depth).exp()).abs()
        )]
    } else {
        Vec::new()
    }
}

/// Kubelka–Munk from the reflectance R₀ over black and R_g′ over a backing R_g (Kubelka 1948):
/// a = ½[R_g′ + (R₀ − R_g′ + R_g)/(R₀R_g)], b = √(a² − 1), S = arcoth((1 − aR₀)/(bR₀))/(b x),
/// K = S(a − 1).
///
/// # Errors
/// Reflectances outside (0, 1), a white reading not above the black one, or readings no
/// Kubelka–Munk layer produces.
pub fn km_from_black_white(r0: f64, r_white: f64, r_g: f64, x: f64) -> Result<(f64, f64), OpticsError> {
    reflectance("reflectance over black", r0)?;
    reflectance("reflectance over white", r_white)?;
    reflectance("backing reflectance", r_g)?;
    positive("thickness", x)?;
    if r_white <= r0 {
        return Err(OpticsError::Inconsistent(format!(
            "the reflectance over white ({}) must exceed the one over black ({}): a backing can only add light",
            show(r_white),
            show(r0)
        )));
    }
    let a = 0.5 * (r_white + (r0 - r_white + r_g) / (r0 * r_g));
    let y = (1.0 - a * r0) / ((a * a - 1.0).max(0.0).sqrt() * r0);
    // (NaN fails both comparisons and lands here too.)
    let resolvable = a > 1.0 && y > 1.0;
    if !resolvable {
        return Err(OpticsError::Inconsistent(format!(
            "no Kubelka–Munk layer gives {} over black and {} over a backing of {}: the sample may be thicker than \
             the measurement can resolve (over black and white alike), or the backing's reflectance wrong",
            show(r0),
            show(r_white),
            show(r_g)
        )));
    }
    let b = (a * a - 1.0).sqrt();
    let s = 0.5 * ((y + 1.0) / (y - 1.0)).ln() / (b * x);
    Ok((s * (a - 1.0), s))
}

/// σa for a known σs′ and one reflectance.
fn known_scattering(model: SlabModel, slab: Slab, d: f64, r: f64, sigma_s: f64) -> Result<f64, OpticsError> {
    reflectance("reflectance", r)?;
    positive("thickness", d)?;
    check_range("σs′", sigma_s, -1e-300, f64::INFINITY, "[0, ∞)")?;
    let at_zero = model.reflectance(slab, d, 0.0, sigma_s);
    if r > at_zero {
        return Err(OpticsError::Inconsistent(format!(
            "{} is above the most this σs′ can reflect without absorption ({}): σs′ is too small",
            show(r),
            show(at_zero)
        )));
    }
    match model {
        SlabModel::Seed => seed_sigma_a(slab, d, r, sigma_s),
        SlabModel::Exponential => {
            // R decreases monotonically in σa: bracket [0, hi], then safeguarded Newton.
            let f = |a: f64| model.reflectance(slab, d, a, sigma_s) - r;
            let df = |a: f64| model.gradient(slab, d, a, sigma_s).0;
            let mut hi = 1.0 / d;
            while f(hi) > 0.0 {
                hi *= 4.0;
                if hi > 1e12 / d {
                    return Err(OpticsError::Inconsistent(format!("no σa ≥ 0 gives {r}")));
                }
            }
            safeguarded_newton(f, df, 0.0, hi)
        }
    }
}

/// The clay-optics paper's eq. 1 is quadratic in σa for fixed s (docs/derivations.md, "Solving
/// for σa and σs′"): A σa² + B σa + C = 0 with A = s d³/3 + F_b d², B = −s d² − 2F_b(1 − s d)d,
/// C = s d + F_b(1 − s d)² − R/(1 − F_t).
/// The root on the model's monotone branch (1 − σa d − s d ≥ 0 side, the smaller one) is taken,
/// by the cancellation-free formula q = −(B + sign(B)√Δ)/2, roots q/A and C/q.
fn seed_sigma_a(slab: Slab, d: f64, r: f64, sigma_s: f64) -> Result<f64, OpticsError> {
    let s = sigma_s * slab.p_g;
    let fb = slab.f_bottom;
    let a = s * d * d * d / 3.0 + fb * d * d;
    let b = -s * d * d - 2.0 * fb * (1.0 - s * d) * d;
    let c = s * d + fb * (1.0 - s * d).powi(2) - r / (1.0 - slab.f_top);
    if a == 0.0 {
        return if b == 0.0 {
            Err(OpticsError::Inconsistent("σs′ = 0 and a black bottom reflect nothing".into()))
        } else {
            Ok(-c / b)
        };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return Err(OpticsError::Inconsistent(format!("the clay-optics paper's eq. 1 reaches no {r} with this σs′")));
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (r1, r2) = (q / a, c / q);
    let root = [r1, r2].into_iter().filter(|x| *x >= 0.0).fold(f64::INFINITY, f64::min);
    if root.is_finite() { Ok(root) } else { Err(OpticsError::Inconsistent(format!("no σa ≥ 0 gives {r}"))) }
}

/// σa for a known ratio σs′ = ratio·σa: the root of R(σa, ratio·σa) = r, bracketed by a scan over
/// σa·d from 10⁻⁶ to 10³ (log-spaced) and refined by bisection-safeguarded Newton. Two roots
/// (the model is not monotone along the ray) are an error that names both.
fn known_ratio(model: SlabModel, slab: Slab, d: f64, r: f64, ratio: f64) -> Result<f64, OpticsError> {
    reflectance("reflectance", r)?;
    positive("thickness", d)?;
    positive("ratio σs′/σa", ratio)?;
    let f = |a: f64| model.reflectance(slab, d, a, ratio * a) - r;
    let df = |a: f64| {
        let (ga, gs) = model.gradient(slab, d, a, ratio * a);
        ga + ratio * gs
    };
    const SCAN: usize = 240;
    let at = |i: usize| 1e-6 * 1e9_f64.powf(i as f64 / SCAN as f64) / d;
    let mut roots = Vec::new();
    for i in 0..SCAN {
        let (lo, hi) = (at(i), at(i + 1));
        if f(lo) * f(hi) <= 0.0 {
            roots.push(safeguarded_newton(f, df, lo, hi)?);
        }
    }
    roots.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    match roots.as_slice() {
        [root] => Ok(*root),
        [] => Err(OpticsError::Inconsistent(format!("no σa with σs′ = {ratio}·σa gives {r}"))),
        many => Err(OpticsError::Inconsistent(format!(
            "{} values of σa give {r} with σs′ = {ratio}·σa ({}): measure a second thickness or backing",
            many.len(),
            many.iter().map(|x| format!("{x:.6}")).collect::<Vec<_>>().join(", ")
        ))),
    }
}

/// The dipole's α′ for a diffuse reflectance (R_d increases monotonically from 0 at α′ = 0 to 1
/// at α′ = 1).
fn dipole_alpha(r: f64, eta: f64) -> Result<f64, OpticsError> {
    safeguarded_newton(|a| dipole_albedo(a, eta) - r, |a| dipole_albedo_derivative(a, eta), 0.0, 1.0)
}

/// (σa, σs′) from two thicknesses: Newton on (ln σa, ln σs′) (positivity for free) with the
/// analytic Jacobian and a backtracking line search on the residual.
fn two_thicknesses(
    model: SlabModel,
    slab: Slab,
    first: (f64, f64),
    second: (f64, f64),
) -> Result<(f64, f64), OpticsError> {
    let ((d1, r1), (d2, r2)) = (first, second);
    reflectance("first reflectance", r1)?;
    reflectance("second reflectance", r2)?;
    positive("first thickness", d1)?;
    positive("second thickness", d2)?;
    if (d1 - d2).abs() <= 1e-12 * d1.max(d2) {
        return Err(OpticsError::Inconsistent(
            "the two thicknesses are equal: they give one observation, not two".into(),
        ));
    }
    // Residuals and their Jacobian in (u, v) = (ln σa, ln σs′), where ∂R/∂u = σa ∂R/∂σa: one
    // evaluation per Newton step, reused by the line search's accepted point.
    let evaluate = |u: f64, v: f64| {
        let (a, s) = (u.exp(), v.exp());
        let (f1, g1a, g1s) = model.value_and_gradient(slab, d1, a, s);
        let (f2, g2a, g2s) = model.value_and_gradient(slab, d2, a, s);
        ([f1 - r1, f2 - r2], [g1a * a, g1s * s, g2a * a, g2s * s])
    };
    let norm = |v: [f64; 2]| v[0].hypot(v[1]);
    // Start at σa·d̄ = ½ and the σs′ that explains the mean reading by single scattering alone.
    let mean_d = 0.5 * (d1 + d2);
    let (mut u, mut v) =
        ((0.5 / mean_d).ln(), ((0.5 * (r1 + r2)) / ((1.0 - slab.f_top) * slab.p_g * mean_d)).max(1e-9).ln());
    let (mut res, mut jac) = evaluate(u, v);
    for _ in 0..MAX_ITERATIONS {
        let [j11, j12, j21, j22] = jac;
        let det = j11 * j22 - j12 * j21;
        if det == 0.0 || !det.is_finite() {
            return Err(OpticsError::NoConvergence(
                "singular Jacobian: the two readings do not separate σa from σs′".into(),
            ));
        }
        let du = -(j22 * res[0] - j12 * res[1]) / det;
        let dv = -(-j21 * res[0] + j11 * res[1]) / det;
        // Backtracking: halve the step until the residual does not grow.
        let mut step = 1.0;
        let mut trial = evaluate(u + du, v + dv);
        while step > 1e-6 && norm(trial.0) > norm(res) {
            step *= 0.5;
            trial = evaluate(u + step * du, v + step * dv);
        }
        u += step * du;
        v += step * dv;
        (res, jac) = trial;
        if (step * du).abs().max((step * dv).abs()) < CONVERGED {
            if norm(res) > 1e-9 {
                break;
            }
            return Ok((u.exp(), v.exp()));
        }
    }
    let (a, s) = (u.exp(), v.exp());
    if norm(res) <= 1e-12 {
        return Ok((a, s));
    }
    Err(OpticsError::Inconsistent(format!(
        "no (σa, σs′) reproduces {r1} at thickness {d1} and {r2} at {d2} with this model (closest: σa = {a:.4}, \
         σs′ = {s:.4})"
    )))
}

/// Newton's method kept inside a bracket [lo, hi] with f(lo)·f(hi) ≤ 0, bisecting whenever a
/// step would leave it or not shrink the residual fast enough.
fn safeguarded_newton(
    f: impl Fn(f64) -> f64,
    df: impl Fn(f64) -> f64,
    mut lo: f64,
    mut hi: f64,
) -> Result<f64, OpticsError> {
    let (mut f_lo, f_hi) = (f(lo), f(hi));
    if f_lo == 0.0 {
        return Ok(lo);
    }
    if f_hi == 0.0 {
        return Ok(hi);
    }
    if f_lo * f_hi > 0.0 {
        return Err(OpticsError::Inconsistent("the reading lies outside what the model can produce".into()));
    }
    let mut x = 0.5 * (lo + hi);
    for _ in 0..MAX_ITERATIONS * 2 {
        let fx = f(x);
        if fx == 0.0 {
            return Ok(x);
        }
        if fx * f_lo < 0.0 {
            hi = x;
        } else {
            lo = x;
            f_lo = fx;
        }
        let newton = x - fx / df(x);
        let next = if newton.is_finite() && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        if (next - x).abs() <= CONVERGED * x.abs().max(1e-300) || hi - lo <= CONVERGED * hi.abs() {
            return Ok(next);
        }
        x = next;
    }
    Err(OpticsError::NoConvergence(format!("bracket [{lo}, {hi}] after {} steps", MAX_ITERATIONS * 2)))
}

mod inputs;

pub use inputs::{Batch, BatchError, BatchRow, INPUT_NAMES, Inputs};

#[cfg(test)]
mod tests;
