//! The rough dielectric interface as the tables see it: the reference's single-scattering
//! reflection lobe (GGX or GTR1 D, their height-correlated Smith G2, exact Fresnel with total
//! internal reflection) and its albedo by quadrature. Shared by the coat's tables and its lobe's scale.

use glam::DVec3;
use glazec::math::sampling::direction_at_cosine;
use glazec::math::terms::SECOND_EVENT_LATER;

use crate::accuracy::quadrature::directional_albedo_f64;
use crate::reference::{Ndf, fresnel_dielectric, microsurface};
use glazec::math::tables::CoatTables;

/// A rough coat's microfacet distribution and the tables `glazec tables` bakes for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Family {
    pub ndf: Ndf,
    pub tables: CoatTables,
}

impl Family {
    pub const GGX: Family = Family { ndf: Ndf::Ggx, tables: CoatTables::GGX };
    pub const GTR1: Family = Family { ndf: Ndf::Gtr1, tables: CoatTables::GTR1 };
    /// GGX first: its jobs keep the seeds they had before GTR1 had tables.
    pub const ALL: [Family; 2] = [Family::GGX, Family::GTR1];
}

/// GGX α below which an interface or a conductor is smooth (the reference's threshold).
pub(super) const SMOOTH_ALPHA: f64 = 1e-3;

/// The single-scattering reflection lobe of a rough dielectric seen from the side where the
/// relative IOR is `eta` (TIR included): D G2 F / (4 μi μo), D and G2 of `ndf`.
pub fn dielectric_lobe(wi: DVec3, wo: DVec3, eta: f64, alpha: f64, ndf: Ndf) -> f64 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = (wi + wo).normalize();
    ndf.d(h, alpha) * ndf.g2(wi, wo, alpha) * fresnel_dielectric(wo.dot(h), eta) / (4.0 * wi.z * wo.z)
}

/// The lobe whose scale c the tables solve: the single-scattering lobe plus the second event of
/// light arriving or leaving at a grazing angle, `glazec::math`'s `CoatInterface::second_event`
/// written again in f64 from its formula: 1.1 F(μg)/(1 + 4Λg + 2Λg²) · D(h̄) tan²θh̄/(tan²θh̄ + α²)
/// F(|wi + w̄o|/2) G2 / (4 μi μo), μg the lower cosine, h̄ the half vector of wi and wo with the
/// lower one mirrored in the mean plane (none when they mirror into each other). A GTR1 coat's
/// lobe is its single-scattering lobe alone (the second event is fitted to GGX walks).
pub fn coat_lobe(wi: DVec3, wo: DVec3, eta: f64, alpha: f64, ndf: Ndf) -> f64 {
    let single = dielectric_lobe(wi, wo, eta, alpha, ndf);
    if ndf != Ndf::Ggx || wi.z <= 0.0 || wo.z <= 0.0 {
        return single;
    }
    let mirrored = DVec3::new(wi.x + wo.x, wi.y + wo.y, wi.z - wo.z);
    let (across, z2) = (mirrored.x * mirrored.x + mirrored.y * mirrored.y, mirrored.z * mirrored.z);
    if across < 1e-24 {
        return single;
    }
    let h = DVec3::new(mirrored.x, mirrored.y, mirrored.z.abs()).normalize();
    let tail = across / (across + alpha * alpha * z2);
    let grazing = if wi.z < wo.z { wi } else { wo };
    let lambda = microsurface::lambda(grazing, alpha);
    let first = SECOND_EVENT_LATER * fresnel_dielectric(grazing.z, eta) / (1.0 + 4.0 * lambda + 2.0 * lambda * lambda);
    let second = first
        * microsurface::ggx_d(h, alpha)
        * tail
        // The facet's cosine with either direction, the mirrored one included: |wi + w̄o|/2.
        * fresnel_dielectric(0.5 * mirrored.length(), eta)
        * microsurface::g2(wi, wo, alpha)
        / (4.0 * wi.z * wo.z);
    single + second
}

/// E_ss(μ): the single-scattering reflection albedo, by quadrature.
pub(super) fn single_scattering_albedo(mu: f64, eta: f64, alpha: f64, ndf: Ndf) -> f64 {
    let lobe = |wi: DVec3, wo: DVec3| DVec3::splat(dielectric_lobe(wi, wo, eta, alpha, ndf));
    directional_albedo_f64(&lobe, direction_at_cosine(mu), alpha).x
}
