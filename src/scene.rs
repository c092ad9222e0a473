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
//!   `Display(x)`, or `Relative(r)` (|ΔL| ≤ r·L of the full material, per channel);
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
}

impl Tolerance {
    /// The allowed difference at a point where the full material's display value is `value`.
    pub fn allowed(self, value: f32) -> f32 {
        match self {
            Tolerance::Display(t) => t,
            Tolerance::Relative(r) => (r * value.abs()).max(DISPLAY_TOLERANCE),
        }
    }

    pub fn describe(self) -> String {
        match self {
            Tolerance::Display(t) if (t - DISPLAY_TOLERANCE).abs() < 1e-9 => "1/255 of display value".into(),
            Tolerance::Display(t) => format!("{t} of display value"),
            Tolerance::Relative(r) => format!("{:.3}% of the full material's value (at least 1/255)", r * 100.0),
        }
    }
}
