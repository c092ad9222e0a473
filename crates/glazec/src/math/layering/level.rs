//! What the interfaced method hands up from one level to the coat above it: the level's BRDF
//! and albedos ([`Level`], [`Albedo`]), and the blur rough coats add to a conductor's lobe.

use super::geometry::level_name;
use crate::math::Real;

/// What the interfaced method knows about the layer under a coat, at that layer's directions.
pub(super) struct Level<F: Real> {
    /// f at the level's (refracted) directions.
    pub(super) f: F::Vec,
    /// Its directional and mean albedos, when the coat above needs them.
    pub(super) albedo: Option<Albedo<F>>,
    /// A bare conductor: its reflection stays a lobe (see `interfaced_glossy_under`).
    pub(super) glossy: bool,
    /// The GGX α of that lobe (a bare conductor only).
    pub(super) alpha: Option<F>,
    /// How much more easily than diffuse light the light this level sends up escapes the coats
    /// above it (see [`first_pass`]); 1 for the body.
    pub(super) boost: F,
    /// Its top coat's transmission T(μ) towards l and v (`None` for the body).
    pub(super) transmission: Option<(F, F)>,
}

/// Directional albedos towards l and v, and the hemispherical mean.
#[derive(Clone, Copy)]
pub(super) struct Albedo<F: Real> {
    pub(super) e_l: F::Vec,
    pub(super) e_v: F::Vec,
    pub(super) mean: F::Vec,
}

/// How much a rough coat widens a conductor's lobe under it: α += BLUR_WIDTH · |1 − 1/η| α_coat.
/// A facet tilted by θm refracts a ray by about (1 − 1/η) θm (Walter et al. 2007, the
/// refraction Jacobian at normal incidence). The light crosses the coat twice, through
/// independent facets, so the two deviations add in quadrature: √2 (1 − 1/η) α_coat in
/// direction. A GGX lobe of width α in half-vector slope reflects into 2α in direction, so that
/// spread is (1/√2)(1 − 1/η) α_coat in the conductor's α. GGX slopes are heavy-tailed, so the
/// added width adds to the conductor's own linearly rather than in quadrature (Belcour 2018 adds
/// variances). Against the reference (standard set, copper under coats of roughness 0.5) this
/// gives a lobe error of 9–14%.
pub(super) const BLUR_WIDTH: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The blur a coat of roughness `roughness` (α = r²) and relative IOR `eta` adds to the `blur`
/// of the coats above it (see [`BLUR_WIDTH`]); a smooth coat adds none.
pub(super) fn coat_blur<F: Real>(roughness: Option<F>, eta: F, blur: Option<F>, k: usize) -> Option<F> {
    let Some(r) = roughness else { return blur };
    // |1 − 1/η|: a coat optically thinner than the medium above (η < 1) spreads rays too (and a
    // negative width would make α negative).
    let spread = eta.recip().one_minus().abs();
    let added = (spread * r.sq() * BLUR_WIDTH).named(&level_name("blur", k));
    Some(blur.map_or(added, |b| b + added))
}
