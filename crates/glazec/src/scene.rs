//! Scenes: what a material will be seen under, so that `simplify` can drop what cannot be seen.
//!
//! A scene file (RON, checked by [`crate::check::check_scene`] with the same diagnostics as
//! materials) gives
//!
//! * `lights`: directional lights (`Directional(irradiance: (r, g, b))`, the irradiance at normal
//!   incidence) and point lights (`Point(intensity: (r, g, b), min_distance: d)`, whose
//!   irradiance is at most intensity/d²);
//! * `environment`: `None` or `Uniform(radiance: (r, g, b))`, an upper bound on the radiance
//!   arriving from any direction;
//! * `view` and `light_directions`: `(max_angle: degrees)`, the largest angle from the surface
//!   normal at which the camera sees a surface and at which light arrives (a camera that never
//!   sees grazing angles, a top light);
//! * `params`: `{ "name": Pinned(value), "name": Range(lo, hi) }` for the material's runtime
//!   parameters (a parameter the scene does not name stays free over `[0, 1]` per channel for
//!   reflectances and roughness, and over [1, 3] for an IOR: see `simplify::parameter_domain`);
//! * `tolerance`: `Display` (1/255 of display-referred value: invisible on an 8-bit display),
//!   `Display(x)`, `Relative(r)` (|ΔL| ≤ r·L of the full material, per channel), or `DeltaE(x)`
//!   (CIE76 ΔE*ab between the full and the simplified display colour ≤ x; 2.3 is about one
//!   just-noticeable difference);
//! * `exposure`: the scale from radiance to display-referred value (default 1).
//!
//! Every light direction and view direction is taken relative to the surface normal: a scene says
//! which *local* configurations occur, which is what a BRDF can be simplified for.

use crate::diag::Span;
use crate::model::ParamValue;

/// The display tolerance of an 8-bit display: one code value.
pub const DISPLAY_TOLERANCE: f32 = 1.0 / 255.0;

#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub name: String,
    pub lights: Vec<Light>,
    /// Upper bound of the environment's radiance, per channel; `None` for no environment.
    pub environment: Option<[f32; 3]>,
    /// Largest angle between the normal and the direction to the camera, in degrees.
    pub view_max_angle: f32,
    /// Largest angle between the normal and the direction to a light, in degrees.
    pub light_max_angle: f32,
    pub params: Vec<SceneParam>,
    pub tolerance: Tolerance,
    pub exposure: f32,
}

/// A light source, as far as the error bound needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Irradiance at normal incidence, per channel.
    Directional { irradiance: [f32; 3] },
    /// Intensity per channel; irradiance at most intensity / min_distance².
    Point { intensity: [f32; 3], min_distance: f32 },
}

impl Light {
    /// The largest irradiance the light delivers at normal incidence.
    pub fn max_irradiance(self) -> [f32; 3] {
        match self {
            Light::Directional { irradiance } => irradiance,
            Light::Point { intensity, min_distance } => intensity.map(|i| i / (min_distance * min_distance)),
        }
    }
}

/// What the scene says about one runtime parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneParam {
    pub name: String,
    pub domain: ParamDomain,
    /// Where the scene names it (for diagnostics about the material).
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamDomain {
    /// The value is fixed: it can be folded into the shader.
    Pinned(ParamValue),
    /// Every value between the two (per channel for colours) occurs.
    Range(ParamValue, ParamValue),
}

/// How large a difference may be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tolerance {
    /// Absolute, in display-referred units (exposure × radiance; 1 = white).
    Display(f32),
    /// Relative to the full material's value at the same configuration, per channel, with the
    /// display tolerance as a floor (so that black stays black to the eye, not to 0).
    Relative(f32),
    /// CIE 1976 ΔE*ab between the display colours (linear sRGB primaries, D65, display value 1
    /// = white), bounded over every sign of the per-channel difference.
    DeltaE(f32),
}

impl Tolerance {
    /// The allowed difference in one channel where the full material's display value is
    /// `value` (for `DeltaE`, see [`Tolerance::share`]).
    pub fn allowed(self, value: f32) -> f32 {
        match self {
            Tolerance::Display(t) => t,
            Tolerance::Relative(r) => (r * value.abs()).max(DISPLAY_TOLERANCE),
            Tolerance::DeltaE(_) => f32::INFINITY,
        }
    }

    /// How much of the tolerance a difference of at most `delta` per channel uses, where the full
    /// material's display colour is `value`: the largest share over the channels, or for `DeltaE`
    /// the largest ΔE*ab over the eight corners value ± delta, divided by the allowed ΔE.
    pub fn share(self, value: [f32; 3], delta: [f32; 3]) -> f32 {
        match self {
            Tolerance::DeltaE(allowed) => {
                let reference = lab(value);
                let mut worst = 0.0_f32;
                for corner in 0..8 {
                    let other = [0, 1, 2].map(|c| {
                        let sign = if corner >> c & 1 == 1 { 1.0 } else { -1.0 };
                        (value[c] + sign * delta[c]).max(0.0)
                    });
                    let l = lab(other);
                    let d =
                        ((l[0] - reference[0]).powi(2) + (l[1] - reference[1]).powi(2) + (l[2] - reference[2]).powi(2))
                            .sqrt();
                    worst = worst.max(d);
                }
                worst / allowed
            }
            t => (0..3).map(|c| delta[c] / t.allowed(value[c])).fold(0.0, f32::max),
        }
    }

    pub fn describe(self) -> String {
        match self {
            Tolerance::Display(t) if (t - DISPLAY_TOLERANCE).abs() < 1e-9 => "1/255 of display value".into(),
            Tolerance::Display(t) => format!("{t} of display value"),
            Tolerance::Relative(r) => format!("{:.3}% of the full material's value (at least 1/255)", r * 100.0),
            Tolerance::DeltaE(x) => format!("ΔE*ab ≤ {x} (CIE 1976)"),
        }
    }
}

/// CIE 1976 L*a*b* of a linear sRGB colour (IEC 61966-2-1 primaries, D65 white; display value 1
/// is white, L* = 100). Values above 1 are extrapolated by the same formulas.
pub fn lab(rgb: [f32; 3]) -> [f32; 3] {
    let [r, g, b] = rgb.map(f64::from);
    let x = 0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b;
    let y = 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175_0 * b;
    let z = 0.019_333_9 * r + 0.119_192_0 * g + 0.950_304_1 * b;
    // CIE's f(t): cube root above (6/29)³, linear below (continuous at the joint).
    let f = |t: f64| {
        let delta: f64 = 6.0 / 29.0;
        if t > delta.powi(3) { t.cbrt() } else { t / (3.0 * delta * delta) + 4.0 / 29.0 }
    };
    let (fx, fy, fz) = (f(x / 0.950_47), f(y), f(z / 1.088_83));
    [(116.0 * fy - 16.0) as f32, (500.0 * (fx - fy)) as f32, (200.0 * (fy - fz)) as f32]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lab_of_white_black_and_a_known_colour() {
        let white = lab([1.0; 3]);
        assert!((white[0] - 100.0).abs() < 1e-3 && white[1].abs() < 1e-2 && white[2].abs() < 1e-2, "{white:?}");
        assert_eq!(lab([0.0; 3]), [0.0, 0.0, 0.0]);
        // Linear sRGB (1, 0, 0) is L* 53.24, a* 80.09, b* 67.20.
        let red = lab([1.0, 0.0, 0.0]);
        assert!(
            (red[0] - 53.24).abs() < 0.02 && (red[1] - 80.09).abs() < 0.05 && (red[2] - 67.20).abs() < 0.05,
            "{red:?}"
        );
    }

    #[test]
    fn delta_e_share_bounds_every_sign_of_the_difference() {
        let t = Tolerance::DeltaE(1.0);
        assert_eq!(t.share([0.5; 3], [0.0; 3]), 0.0);
        // A grey step of 0.01 at mid-grey moves L* by about 0.55.
        let share = t.share([0.2; 3], [0.01, 0.0, 0.0]);
        let direct = {
            let (a, b) = (lab([0.2; 3]), lab([0.21, 0.2, 0.2]));
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        assert!(share >= direct && share < 2.0 * direct, "{share} vs {direct}");
        assert_eq!(Tolerance::Display(DISPLAY_TOLERANCE).share([0.5; 3], [DISPLAY_TOLERANCE, 0.0, 0.0]), 1.0);
    }
}
