//! The physical range of every number a material or scene gives ([`Rule`]), with the code,
//! label and help of the diagnostic for a number outside it.

use crate::diag::Code;

/// The physical range a number must lie in, with its code and help text.
#[derive(Clone, Copy)]
pub(super) enum Rule {
    /// Perceptual roughness, [0, 1].
    Roughness,
    /// Oren–Nayar σ in radians, [0, 1].
    Sigma,
    /// IOR or real part of a complex IOR: finite and > 0.
    Ior,
    /// Absorption σa ≥ 0.
    Absorption,
    /// Thickness d ≥ 0.
    Thickness,
    /// Conductor extinction κ ≥ 0.
    Extinction,
    /// A reflectance in [0, 1].
    Albedo,
    /// A conductor's normal-incidence reflectance F0 in [0, 1].
    Reflectance,
    /// The real part η of a conductor's complex IOR (relative to vacuum), > 0.
    ConductorEta,
    /// A scene's angle from the normal, in degrees: [0, 90].
    Angle,
    /// A light's irradiance, intensity or radiance: ≥ 0.
    LightAmount,
    /// A point light's closest distance: > 0.
    Distance,
    /// A tolerance: (0, 1].
    Tolerance,
    /// A scene's exposure: > 0.
    Exposure,
    /// A ΔE*ab tolerance: (0, 100].
    DeltaE,
    /// A value a scene gives a runtime parameter: ≥ 0 (the material's slot bounds it further).
    SceneValue,
}

/// A coat's relative IOR: physical interfaces lie well inside (diamond in air 2.42, air under
/// water 0.75); far outside, η² and 1/η² leave f32's range in the shader's constants (fuzzing
/// found η = 10⁻⁴⁵ folding to NaN).
const IOR_MIN: f64 = 0.1;

const IOR_MAX: f64 = 10.0;

/// A conductor's η can be small (silver ≈ 0.05 in the visible).
const CONDUCTOR_ETA_MIN: f64 = 0.01;

/// Absorption, thickness and extinction: beyond 10⁶ a layer is opaque anyway, and products of
/// such values overflow f32.
const MEDIUM_MAX: f64 = 1e6;

impl Rule {
    /// The range a number must lie in: [lo, hi], or (lo, hi] where [`Self::excludes_lower`];
    /// hi = ∞ where only the lower end is bounded.
    fn range(self) -> (f64, f64) {
        match self {
            Rule::Roughness | Rule::Sigma | Rule::Albedo | Rule::Reflectance | Rule::Tolerance => (0.0, 1.0),
            Rule::Ior => (IOR_MIN, IOR_MAX),
            Rule::ConductorEta => (CONDUCTOR_ETA_MIN, IOR_MAX),
            Rule::Absorption | Rule::Thickness | Rule::Extinction => (0.0, MEDIUM_MAX),
            Rule::Angle => (0.0, 90.0),
            Rule::DeltaE => (0.0, 100.0),
            Rule::LightAmount | Rule::SceneValue | Rule::Distance | Rule::Exposure => (0.0, f64::INFINITY),
        }
    }

    /// Whether the lower end itself is refused (a distance, exposure or tolerance of 0).
    fn excludes_lower(self) -> bool {
        matches!(self, Rule::Distance | Rule::Exposure | Rule::Tolerance | Rule::DeltaE)
    }

    /// The closed range a material's slot accepts, for the [`Param`](crate::model::Param)s
    /// that fill it (every such rule includes its lower end).
    pub(super) fn bounds(self) -> [f32; 2] {
        let (lo, hi) = self.range();
        [lo as f32, hi as f32]
    }

    pub(super) fn accepts(self, x: f64) -> bool {
        let (lo, hi) = self.range();
        (if self.excludes_lower() { x > lo } else { x >= lo }) && x <= hi
    }

    pub(super) fn code(self) -> Code {
        match self {
            Rule::Roughness | Rule::Sigma => Code::RoughnessRange,
            Rule::Ior | Rule::ConductorEta => Code::IorRange,
            Rule::Absorption | Rule::Thickness | Rule::Extinction => Code::NegativeMedium,
            Rule::Albedo | Rule::Reflectance => Code::AlbedoRange,
            Rule::Angle
            | Rule::LightAmount
            | Rule::Distance
            | Rule::Tolerance
            | Rule::Exposure
            | Rule::DeltaE
            | Rule::SceneValue => Code::SceneRange,
        }
    }

    pub(super) fn what(self) -> &'static str {
        match self {
            Rule::Roughness => "roughness",
            Rule::Sigma => "Oren–Nayar roughness",
            Rule::Ior => "index of refraction",
            Rule::Absorption => "absorption",
            Rule::Thickness => "thickness",
            Rule::Extinction => "extinction coefficient",
            Rule::Albedo => "albedo",
            Rule::Reflectance => "reflectance F0",
            Rule::ConductorEta => "conductor IOR η",
            Rule::Angle => "angle",
            Rule::LightAmount => "light amount",
            Rule::Distance => "distance",
            Rule::Tolerance => "tolerance",
            Rule::Exposure => "exposure",
            Rule::DeltaE => "ΔE tolerance",
            Rule::SceneValue => "parameter value",
        }
    }

    pub(super) fn label(self) -> &'static str {
        match self {
            Rule::Roughness | Rule::Sigma | Rule::Albedo | Rule::Reflectance => "must lie in [0, 1]",
            Rule::Ior => "must lie in [0.1, 10]",
            Rule::ConductorEta => "must lie in [0.01, 10]",
            Rule::Absorption | Rule::Thickness | Rule::Extinction => "must lie in [0, 10⁶]",
            Rule::Angle => "must lie in [0, 90] degrees",
            Rule::LightAmount | Rule::SceneValue => "must not be negative",
            Rule::Distance | Rule::Exposure => "must be greater than 0",
            Rule::Tolerance => "must lie in (0, 1]",
            Rule::DeltaE => "must lie in (0, 100]",
        }
    }

    pub(super) fn help(self) -> &'static str {
        match self {
            Rule::Roughness => "roughness is perceptual (α = roughness²): 0 is a mirror, 1 is fully rough",
            Rule::Sigma => "Oren–Nayar roughness is the facet-slope deviation σ in radians, from 0 (Lambert) to 1",
            Rule::Ior => {
                "an index of refraction relative to the medium above lies in [0.1, 10] \
                          (water 1.33, glass 1.5, diamond 2.42)"
            }
            Rule::Absorption => "absorption σa is per unit length; 0 means a clear coat",
            Rule::Thickness => "thickness is a length (Bowsher 2022's density d); 0 means an interface with no slab",
            Rule::Extinction => {
                "the imaginary part κ of a conductor's IOR is 0 or more (gold: (0.2, 0.92, 1.1) + i(3.9, 2.45, 2.14))"
            }
            Rule::Albedo => "albedo is a reflectance in [0, 1]; a value above 1 creates energy",
            Rule::Reflectance => {
                "F0 is the conductor's reflectance at normal incidence, in [0, 1] \
                                  (silver (0.97, 0.96, 0.91), gold (1.0, 0.78, 0.34))"
            }
            Rule::ConductorEta => {
                "η is the real part of the conductor's complex IOR relative to vacuum, above 0 \
                                   (gold: η = (0.17, 0.43, 1.44), κ = (3.5, 2.46, 1.8))"
            }
            Rule::Angle => "an angle from the surface normal in degrees: 0 is head-on, 90 is grazing",
            Rule::LightAmount => "irradiance, intensity and radiance are 0 or more, per channel",
            Rule::Distance => "the closest a point light comes to a lit surface, in scene units, above 0",
            Rule::Tolerance => "a tolerance is a fraction: `Display` is 1/255, `Relative(0.01)` is 1%",
            Rule::Exposure => "exposure scales radiance to display value; 1 shows radiance 1 as white",
            Rule::DeltaE => "a CIE 1976 ΔE*ab: about 2.3 is one just-noticeable difference",
            Rule::SceneValue => "a parameter's value in a scene is 0 or more (the material's slot bounds it)",
        }
    }
}
