//! The rough dielectric interface as the tables see it: the reference's single-scattering
//! reflection lobe (GGX D, height-correlated Smith G2, exact Fresnel with total internal
//! reflection) and its albedo by quadrature. Shared by the coat's tables and its lobe's scale.

use glam::DVec3;
use glazec::math::sampling::direction_at_cosine;

use crate::accuracy::quadrature::directional_albedo_f64;
use crate::reference::{fresnel_dielectric, microsurface};

/// GGX α below which an interface or a conductor is smooth (the reference's threshold).
pub(super) const SMOOTH_ALPHA: f64 = 1e-3;

/// The single-scattering reflection lobe of a rough dielectric seen from the side where the
/// relative IOR is `eta` (TIR included): D G2 F / (4 μi μo).
pub(super) fn dielectric_lobe(wi: DVec3, wo: DVec3, eta: f64, alpha: f64) -> f64 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = (wi + wo).normalize();
    microsurface::ggx_d(h, alpha) * microsurface::g2(wi, wo, alpha) * fresnel_dielectric(wo.dot(h), eta)
        / (4.0 * wi.z * wo.z)
}

/// E_ss(μ): the single-scattering reflection albedo, by quadrature.
pub(super) fn single_scattering_albedo(mu: f64, eta: f64, alpha: f64) -> f64 {
    let lobe = |wi: DVec3, wo: DVec3| DVec3::splat(dielectric_lobe(wi, wo, eta, alpha));
    directional_albedo_f64(&lobe, direction_at_cosine(mu), alpha).x
}
