//! The scale c(μ; r, η) of a rough coat's reflection lobe (`coat_scale`): the interfaced method
//! reflects f_ss(l, v)·c(μl)·c(μv), c solved so that this reflects what the reference's
//! microsurface reflects, E_ss + E_ms; the coat's deficit is then taken from the scaled lobe
//! itself ([`scaled_albedo`]), so that what the coat transmits and what its lobe reflects add up
//! to 1 whatever the noise of the walks.
//!
//! Turquin 2019 ("Practical multiple scattering compensation for microfacet models") scales the
//! single-scattering lobe by 1 + E_ms/E_ss at the view direction, which puts the multiply
//! scattered light where the single-scattering lobe is, but is not reciprocal. A product of one
//! factor per direction is; its albedo at μo is
//!
//!   A(μo) = c(μo) ∫ f_ss(ωi, ωo) c(μi) μi dωi,
//!
//! and A = E_ss + E_ms at every node is a symmetric matrix scaling (Sinkhorn & Knopp 1967; the
//! symmetric iteration of Knight 2008, "The Sinkhorn–Knopp algorithm: convergence and
//! applications"): with c interpolated linearly between the nodes as the lookups do, the integral
//! is a matrix M over the nodes, A = c ∘ (M c), and c ← √(c ∘ b / (M c)) converges for the
//! positive kernels of GGX lobes. The plain √(1 + E_ms/E_ss) per direction solves it only for a
//! lobe much narrower than c's variation: for broad lobes it gained up to 1.6% energy near
//! grazing incidence (docs/accuracy.md, "Multiple scattering in the coat's lobe").

use glazec::math::sampling::direction_at_cosine;
use glazec::math::tables::Axis;

use super::interface::{Family, SMOOTH_ALPHA, coat_lobe};
use crate::accuracy::quadrature::albedo_nodes;
use crate::reference::Ndf;

/// Iterations of the scaling at most (it converges geometrically; the tolerance ends it first).
const MAX_ITERATIONS: usize = 5_000;
/// |A/b − 1| at every node at which the scaling stops.
const NODE_TOLERANCE: f64 = 1e-9;

/// The albedo integral of the single-scattering lobe from one outgoing cosine, as weights on
/// c's nodes (`n_mu` on the cosine axis): the quadrature's f_ss·weight spread over the two nodes
/// around each light direction's coordinate, as linear interpolation spreads c.
fn kernel_row(mu: f64, eta: f64, alpha: f64, n_mu: usize, ndf: Ndf) -> Vec<f64> {
    let wo = direction_at_cosine(mu);
    let mut row = vec![0.0; n_mu];
    for (wi, weight) in albedo_nodes(wo, alpha) {
        let f = coat_lobe(wi, wo, eta, alpha, ndf) * weight;
        let (i, t) = cell(wi.z, n_mu);
        row[i] += f * (1.0 - t);
        if t > 0.0 {
            row[i + 1] += f * t;
        }
    }
    row
}

/// The cell and the fraction within it of a cosine on a cosine axis of `n_mu` nodes (clamped
/// into its range, as the lookups clamp it).
fn cell(mu: f64, n_mu: usize) -> (usize, f64) {
    let u = f64::from(Axis::Cosine.coordinate(mu as f32)).clamp(0.0, 1.0) * (n_mu - 1) as f64;
    let i = (u.floor() as usize).min(n_mu - 2);
    (i, (u - i as f64).clamp(0.0, 1.0))
}

/// c at the nodes `cosines` of one column (r, η) of the scale table, solved so that the scaled
/// lobe reflects `targets` there (E_ss + E_ms); 1 for a smooth interface. Returns c and the
/// largest |A/b − 1| left at a node.
pub(super) fn scale_column(roughness: f64, eta: f64, cosines: &[f64], targets: &[f64], ndf: Ndf) -> (Vec<f64>, f64) {
    let n_mu = cosines.len();
    let alpha = roughness * roughness;
    if alpha < SMOOTH_ALPHA || eta == 1.0 {
        return (vec![1.0; n_mu], 0.0);
    }
    let rows: Vec<Vec<f64>> = cosines.iter().map(|&mu| kernel_row(mu, eta, alpha, n_mu, ndf)).collect();
    let gathered = |k: usize, c: &[f64]| -> f64 { rows[k].iter().zip(c).map(|(m, c)| m * c).sum() };
    let worst_miss = |c: &[f64]| -> f64 {
        (0..n_mu)
            .filter(|&k| targets[k] > 0.0)
            .map(|k| (c[k] * gathered(k, c) / targets[k] - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let mut c = vec![1.0; n_mu];
    for _ in 0..MAX_ITERATIONS {
        c = (0..n_mu)
            .map(|k| {
                let m = gathered(k, &c);
                // Guard: a direction whose lobe reflects nothing, or should not, keeps its factor.
                if m > 1e-300 && targets[k] > 0.0 { (c[k] * targets[k] / m).sqrt() } else { c[k] }
            })
            .collect();
        if worst_miss(&c) < NODE_TOLERANCE {
            break;
        }
    }
    let miss = worst_miss(&c);
    (c, miss)
}

/// The albedo of the scaled lobe f_ss·c(μl)·c(μv) at outer cosine `mu`, c read through the
/// compiled lookup (the tables `glazec::math::tables::evaluate_on_cpu_with` set), by quadrature.
pub(super) fn scaled_albedo(mu: f64, roughness: f64, eta: f64, family: Family) -> f64 {
    let alpha = roughness * roughness;
    // A family without a scale table has an unscaled lobe.
    let c = |mu: f64| {
        let args = [mu as f32, roughness as f32, eta as f32];
        family.tables.scale.map_or(1.0, |id| f64::from(glazec::math::tables::lookup::<f32>(id, &args)))
    };
    let wo = direction_at_cosine(mu);
    let gathered: f64 = albedo_nodes(wo, alpha)
        .into_iter()
        .map(|(wi, weight)| coat_lobe(wi, wo, eta, alpha, family.ndf) * weight * c(wi.z))
        .sum();
    c(mu) * gathered
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// The albedo of the unscaled lobe (single scattering and the second event) at `mu`.
    fn lobe_albedo(mu: f64, eta: f64, alpha: f64) -> f64 {
        let lobe = |wi: DVec3, wo: DVec3| DVec3::splat(coat_lobe(wi, wo, eta, alpha, Ndf::Ggx));
        crate::accuracy::quadrature::directional_albedo_f64(&lobe, direction_at_cosine(mu), alpha).x
    }

    #[test]
    fn kernel_rows_sum_to_the_lobes_albedo_which_the_second_event_only_adds_to() {
        // With c = 1 a row's sum is the lobe's albedo: the quadrature's, spread over the nodes.
        for (mu, eta, alpha) in [(0.5, 1.5, 0.04), (0.05, 1.33, 0.25), (0.9, 2.0, 1.0), (0.02, 1.5, 0.0025)] {
            let row = kernel_row(mu, eta, alpha, 16, Ndf::Ggx);
            let sum: f64 = row.iter().sum();
            let albedo = lobe_albedo(mu, eta, alpha);
            assert!((sum - albedo).abs() < 1e-12, "μ {mu}, η {eta}, α {alpha}: {sum} vs {albedo}");
            let e_ss = super::super::interface::single_scattering_albedo(mu, eta, alpha, Ndf::Ggx);
            assert!(albedo >= e_ss, "μ {mu}, η {eta}, α {alpha}: {albedo} below single scattering {e_ss}");
        }
    }

    #[test]
    fn the_scaling_meets_its_targets_and_a_narrow_lobe_takes_turquins_factor() {
        let cosines: Vec<f64> =
            (0..16).map(|i| Axis::Cosine.node(i, 16).max(glazec::math::tables::COSINE_FLOOR)).collect();
        for (roughness, eta) in [(0.2, 1.5), (1.0, 1.33), (0.6, 2.5)] {
            let alpha: f64 = roughness * roughness;
            let e_ss: Vec<f64> = cosines
                .iter()
                .map(|&mu| super::super::interface::single_scattering_albedo(mu, eta, alpha, Ndf::Ggx))
                .collect();
            // Ten per cent more than single scattering, more towards grazing incidence.
            let targets: Vec<f64> = e_ss.iter().zip(&cosines).map(|(e, mu)| e * (1.1 + 0.2 * (1.0 - mu))).collect();
            let (c, miss) = scale_column(roughness, eta, &cosines, &targets, Ndf::Ggx);
            assert!(miss < 1e-8, "r {roughness}, η {eta}: {miss}");
            assert!(c.iter().all(|&c| c > 0.9 && c < 1.3), "{c:?}");
            if roughness == 0.2 {
                // A narrow lobe: c ≈ √(b/E) at each node away from grazing, E the unscaled lobe's
                // albedo (Turquin's factor, with the second event in the lobe). Nearer grazing
                // (μ < 0.05 here) the second event's tail reaches other nodes' c: not narrow.
                for k in 6..16 {
                    let turquin = (targets[k] / lobe_albedo(cosines[k], eta, alpha)).sqrt();
                    assert!((c[k] / turquin - 1.0).abs() < 0.01, "node {k}: {} vs {turquin}", c[k]);
                }
            }
        }
    }
}
