//! The fits of the glossy level's statistics: the trapped light's event counts as a mixture of
//! geometric laws (simplex-constrained least squares, the slow rate per node), and the lobe's
//! per-direction scale (symmetric Sinkhorn iteration against the compiled lobe).

use super::nodes::{SCALE_ITERATIONS, SMOOTH_ALPHA, direction_nodes};
use super::walk::EventCounts;
use glam::DVec3;
use glazec::math::sampling::direction_at_cosine;
use glazec::math::tables::{GLOSSY_SINGLE_GRID, TableId};

/// γ(B, c) = c(1 − B)/(1 − Bc): the generating function of a geometric count ≥ 1 with
/// retention B (the share that stays per event).
pub(super) fn geometric(retention: f64, c: f64) -> f64 {
    c * (1.0 - retention) / (1.0 - retention * c)
}

/// The fixed retentions of the trapped light's basis: leaving at the next event (0), at rate ½
/// and at rate 0.8; a fourth, slow rate is fitted per node (`fit_trapped`).
pub const TRAPPED_RETENTIONS: [f64; 3] = [0.0, 0.5, 0.8];

/// Per-event survivals over which the retention rates are fitted (the conductor's Fresnel factor
/// times the slab's round trip).
pub(super) const FIT_SURVIVALS: [f64; 15] =
    [0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95, 0.99];

/// The simplex-constrained least-squares weights (w ≥ 0, Σw = 1) of `basis[j][i]` (basis j at
/// survival i) against `target[i]`, by trying every active set (four weights: fifteen sets).
pub(super) fn simplex_least_squares(basis: &[Vec<f64>], target: &[f64]) -> Vec<f64> {
    let n = basis.len();
    let mut best = (f64::INFINITY, vec![1.0 / n as f64; n]);
    for mask in 1u32..(1 << n) {
        let active: Vec<usize> = (0..n).filter(|j| mask >> j & 1 == 1).collect();
        let m = active.len();
        // The KKT system of min |Bw − t|² subject to Σw = 1: [2BᵀB 1; 1ᵀ 0][w; λ] = [2Bᵀt; 1].
        let mut a = vec![vec![0.0; m + 2]; m + 1];
        for (r, &jr) in active.iter().enumerate() {
            for (q, &jq) in active.iter().enumerate() {
                a[r][q] = 2.0 * basis[jr].iter().zip(&basis[jq]).map(|(x, y)| x * y).sum::<f64>();
            }
            a[r][m] = 1.0;
            a[r][m + 1] = 2.0 * basis[jr].iter().zip(target).map(|(x, y)| x * y).sum::<f64>();
        }
        a[m][..m].iter_mut().for_each(|x| *x = 1.0);
        a[m][m + 1] = 1.0;
        let Some(solution) = solve(a) else { continue };
        if solution[..m].iter().any(|&w| w < -1e-12) {
            continue;
        }
        let mut w = vec![0.0; n];
        for (r, &j) in active.iter().enumerate() {
            w[j] = solution[r].max(0.0);
        }
        let error: f64 =
            (0..target.len()).map(|i| ((0..n).map(|j| w[j] * basis[j][i]).sum::<f64>() - target[i]).powi(2)).sum();
        if error < best.0 {
            best = (error, w);
        }
    }
    best.1
}

/// Gauss–Jordan elimination with partial pivoting of an augmented square system.
pub(super) fn solve(mut a: Vec<Vec<f64>>) -> Option<Vec<f64>> {
    let size = a.len();
    for col in 0..size {
        let pivot = (col..size).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[pivot][col].abs() < 1e-14 {
            return None;
        }
        a.swap(col, pivot);
        let pivot_row = a[col].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != col {
                let factor = row[col] / pivot_row[col];
                for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    *x -= factor * p;
                }
            }
        }
    }
    Some((0..size).map(|r| a[r][size] / a[r][r]).collect())
}

/// The trapped light of one direction as weights on the basis [`TRAPPED_RETENTIONS`] + `slow`:
/// (weights, largest error of the generating function over [`FIT_SURVIVALS`], in shares of the
/// entering light).
pub(super) fn trapped_weights(counts: &EventCounts, slow: f64) -> (Vec<f64>, f64) {
    let rest = 1.0 - counts.share(0);
    let retentions: Vec<f64> = TRAPPED_RETENTIONS.iter().copied().chain([slow]).collect();
    if rest < 1e-6 {
        return (vec![0.25; 4], 0.0);
    }
    let basis: Vec<Vec<f64>> =
        retentions.iter().map(|&b| FIT_SURVIVALS.iter().map(|&c| rest * geometric(b, c)).collect()).collect();
    let target: Vec<f64> = FIT_SURVIVALS.iter().map(|&c| counts.trapped(c)).collect();
    let w = simplex_least_squares(&basis, &target);
    let worst = (0..target.len())
        .map(|i| ((0..4).map(|j| w[j] * basis[j][i]).sum::<f64>() - target[i]).abs())
        .fold(0.0, f64::max);
    (w, worst)
}

/// The slow retention that fits every direction's trapped light best (smallest largest error),
/// searched over 1 − B from 0.6 down to 10⁻³ on a geometric grid; and that error.
pub(super) fn fit_trapped(columns: &[EventCounts]) -> (f64, f64) {
    let mut best = (f64::INFINITY, 0.9);
    for k in 0..48 {
        let slow = 1.0 - 0.6 * (1e-3_f64 / 0.6).powf(f64::from(k) / 47.0);
        let worst = columns.iter().map(|c| trapped_weights(c, slow).1).fold(0.0, f64::max);
        if worst < best.0 {
            best = (worst, slow);
        }
    }
    (best.1, best.0)
}

/// A white conductor (F0 = 1) of roughness `r_c` under a clear coat of roughness `r` and IOR
/// `eta`, for the energy probes.
pub(super) fn white_conductor_under(r_c: f64, r: f64, eta: f64) -> glazec::model::Material {
    use glazec::model::{Base, Coat, Color, ConductorFresnel, Lobe, Material, Method, Scalar};
    let lobe = if r * r < SMOOTH_ALPHA { Lobe::Smooth } else { Lobe::Ggx { roughness: Scalar::Lit(r as f32) } };
    Material {
        name: "probe".into(),
        method: Method::INTERFACED,
        coats: vec![Coat {
            lobe,
            ior: Scalar::Lit(eta as f32),
            absorption: Color::Lit([0.0; 3]),
            thickness: Scalar::Lit(1.0),
        }],
        base: Base::Conductor {
            roughness: Scalar::Lit(r_c as f32),
            fresnel: ConductorFresnel::F0(Color::Lit([1.0; 3])),
        },
        params: vec![],
        normals: vec![],
    }
}

/// The scale s at the μ nodes that makes the compiled lobe's albedo (white conductor, clear coat,
/// s interpolated along μ as the lookup does) equal T(μ)·P₁(μ) at every node but μ = 0 (where
/// both vanish; it takes its neighbour's); and the largest relative miss left.
pub(super) fn solve_scale(r_c: f64, r: f64, eta: f64, single: &[f64]) -> (Vec<f64>, f64) {
    let n_mu = single.len();
    let mus: Vec<f64> = direction_nodes(&GLOSSY_SINGLE_GRID);
    let lobe = |l: DVec3, v: DVec3| glazec::math::layering::glossy_lobe_white(r_c, r, eta, l, v);
    let sharpest = (r_c * r_c).max(SMOOTH_ALPHA);
    // Every node's view direction, its quadrature and the lobe at each quadrature node.
    let columns: Vec<(f64, Vec<(f64, f64)>)> = mus
        .iter()
        .enumerate()
        .map(|(i, &mu)| {
            let v = direction_at_cosine(mu);
            // What leaves near the mirror direction: after one event, or after the second
            // (the trapped light's share w₀, from the table just computed).
            let next = f64::from(glazec::math::tables::lookup::<f32>(
                TableId::GlossyNext,
                &[mu as f32, r_c as f32, r as f32, eta as f32],
            ));
            let target =
                glazec::math::layering::glossy_coat_transmission(r, eta, v.z) * (single[i] + (1.0 - single[i]) * next);
            let nodes = crate::accuracy::quadrature::albedo_nodes(v, sharpest)
                .into_iter()
                .filter_map(|(l, w)| {
                    let f = lobe(l, v);
                    (f > 0.0).then_some((l.z, w * f))
                })
                .collect();
            (target, nodes)
        })
        .collect();
    // Interpolated as the lookup does: linearly in u = √μ.
    let at = |scale: &[f64], mu: f64| -> f64 {
        let x = mu.clamp(0.0, 1.0).sqrt() * (n_mu - 1) as f64;
        let i = (x.floor() as usize).min(n_mu - 2);
        let t = x - i as f64;
        scale[i] * (1.0 - t) + scale[i + 1] * t
    };
    let achieved = |scale: &[f64], i: usize| -> f64 {
        let (_, nodes) = &columns[i];
        scale[i] * nodes.iter().map(|&(mu_l, wf)| at(scale, mu_l) * wf).sum::<f64>()
    };
    let mut scale = vec![1.0; n_mu];
    for _ in 0..SCALE_ITERATIONS {
        let next: Vec<f64> = (0..n_mu)
            .map(|i| {
                let (target, _) = columns[i];
                let got = achieved(&scale, i);
                if i == 0 || target <= 1e-9 || got <= 1e-12 {
                    return scale[i];
                }
                scale[i] * (target / got).sqrt().clamp(0.5, 2.0)
            })
            .collect();
        scale = next;
        scale[0] = scale[1];
    }
    let miss = (1..n_mu)
        .filter(|&i| columns[i].0 > 1e-6)
        .map(|i| (achieved(&scale, i) / columns[i].0 - 1.0).abs())
        .fold(0.0, f64::max);
    (scale, miss)
}
