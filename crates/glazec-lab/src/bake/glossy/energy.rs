//! The lobe albedo K fitted to the energy law: the compiled method probed at every cell's
//! centre, faces and edges (and at grazing incidence and IORs just above 1), then K changed by
//! the least amount that keeps every probe under the law (Hildreth's dual coordinate ascent).

use super::nodes::SMOOTH_ALPHA;
use super::solve::white_conductor_under;
use glam::DVec3;
use glazec::math::sampling::direction_at_cosine;
use glazec::math::tables::{Axis, GLOSSY_SINGLE_GRID, TableId};

/// A white conductor under a clear coat must reflect what reaches it: the lobe and the remainder
/// T(1 − s²K E c) add up to T(μ) where the interpolated K·E·c follows the lobe's own albedo,
/// exactly at the nodes and nearly between them. Between them a white conductor gains energy
/// where K·E·c falls short of the lobe, and loses it where K·E·c exceeds it. The compiled method
/// itself is probed (a white conductor under a clear coat, by the albedo quadrature) at
/// [`energy_probes`]; K is first raised on its η = 1 face for the probes near η = 1
/// ([`raise_near_one`]), then changed from there by the least amount (in a metric that sends the
/// change of a cell touching η = 1 to its η = 1 face) that
///
/// * takes every probe to at most [`PROBE_ENERGY_CEILING`] (a hard constraint), and
/// * keeps the probes where the method loses energy against the walks within
///   [`PROBE_LOSS_TOLERANCE`] of 1 where it can (a soft one: [`LOSS_MULTIPLIER_CAP`]), so that
///   K is lowered where its interpolation took light from the remainder.
///
/// E at a probe is linear in the looked-up K (K enters the remainder as −T s² E c·K, and the
/// lookup is a weighted sum of corners), so this is a quadratic programme over the corners,
/// solved by Hildreth's dual coordinate ascent ([`least_change`]). Returns the largest excess
/// E − 1 found before the change.
///
/// A simpler rule, raising each corner by the largest need of the cells around it, takes up to
/// 0.049 from K around η 1.33–1.5 for cells beside them and darkens copper under an η 1.5, r ½
/// coat by 0.0116 at 30°; and the lowering gives back the light that K's interpolation takes from
/// the remainder between the r nodes (without it a white conductor under that coat reflects 0.993
/// at 85°).
pub(super) fn fit_lobe_albedo(tables: &mut [Vec<f32>], tick: &(dyn Fn() + Sync)) -> (f64, f64) {
    let probes = energy_probes();
    let measured = crate::parallel_map(probes.len(), |k| probe_energy(probes[k]), |_| tick());
    let constraints: Vec<EnergyConstraint> = probes
        .iter()
        .zip(&measured)
        .filter_map(|(&at, &(excess, unit))| EnergyConstraint::new(at, excess, unit))
        .collect();
    let lobe_albedo = &mut tables[TableId::GlossyLobeAlbedo as usize];
    let start = raise_near_one(&constraints, lobe_albedo.len());
    let change = least_change(&constraints, start);
    for (value, delta) in lobe_albedo.iter_mut().zip(&change) {
        *value += *delta as f32;
    }
    // What the fit left over the ceiling at a probe, as the lookup's linear model predicts it.
    let left = constraints.iter().map(|c| (c.lower - c.looked_up(&change)).max(0.0) * c.unit).fold(0.0, f64::max);
    (measured.iter().map(|&(excess, _)| excess).fold(0.0, f64::max), PROBE_ENERGY_CEILING - 1.0 + left)
}

/// The most a white conductor under a clear coat may reflect at a probe once K is fitted:
/// 2·10⁻³ below the law, for the points between the probes. With the anisotropic lobe
/// (`d_ggx_crossed`) and 8·10⁻⁴, the roughness sweep over a conductor found E = 1.00145 at
/// r 0.464 and 85°, between probes whose E the fit had taken to 1 − 8·10⁻⁴.
pub(super) const PROBE_ENERGY_CEILING: f64 = 1.0 - 2e-3;

/// How much less than all of it a white conductor may reflect at a probe before K is lowered
/// there, and which probes ask for it: directions near grazing, μ within
/// [`LOSS_PROBE_COSINES`] (where the loss is: a white conductor of roughness 0.3 under an η 1.5,
/// r ½ coat reflects 0.993 at 85° without the lowering; lowering K for probes at steeper
/// directions too makes a white conductor gain at 0° on the table's last r_c and r nodes,
/// E = 1.0015 and 1.0025, corners the probes between the nodes see only in part), coats of
/// η ≥ [`LOSS_PROBE_MIN_IOR`], and a lookup that moves E by at least [`LOSS_PROBE_MIN_UNIT`] per
/// unit of K (elsewhere a loss would need K moved by more than its neighbours can follow). Part
/// of a loss is the coat's own (its reflection and transmission at grazing incidence), which K
/// should not make up for: hence a tolerance, not an equality.
pub(super) const PROBE_LOSS_TOLERANCE: f64 = 3e-3;

pub(super) const LOSS_PROBE_COSINES: std::ops::RangeInclusive<f64> = 0.03..=0.2;

pub(super) const LOSS_PROBE_MIN_IOR: f64 = 1.3;

pub(super) const LOSS_PROBE_MIN_UNIT: f64 = 0.15;

/// The bound on a loss probe's multiplier: the losses are an exact L1 penalty of this weight (in
/// the metric's units), not a constraint, as neighbouring probes can ask for K raised and
/// lowered at once (multilinear interpolation cannot follow every curvature within a cell).
pub(super) const LOSS_MULTIPLIER_CAP: f64 = 6.0;

/// The metric's weight of the corners off the η = 1 face (those on it weigh 1): a cell that
/// touches η = 1 is changed on that face. Its gains come from the escape cone closing near
/// η = 1, and changing the face at the next node (η 1.22) for them would take energy from every
/// coat up to η 1.5.
pub(super) const OFF_FACE_WEIGHT: f64 = 0.01;

/// Sweeps of [`least_change`] (it stops earlier once no constraint is violated by more than
/// [`FIT_TOLERANCE`]; with the capped loss probes it usually runs them all).
pub(super) const FIT_SWEEPS: usize = 20_000;

pub(super) const FIT_TOLERANCE: f64 = 1e-6;

/// A white conductor (F0 = 1) of roughness r_c under a clear coat at a probe (μ, r_c, r, η):
/// E − 1, and what a unit of the looked-up K takes from E there, T s² E c.
pub(super) fn probe_energy(at: [f64; 4]) -> (f64, f64) {
    let [mu, r_c, r, eta] = at;
    let material = white_conductor_under(r_c, r, eta);
    let wo = direction_at_cosine(mu);
    let f = |wi: DVec3, wo: DVec3| glazec::eval::brdf(&material, &[], wi.as_vec3(), wo.as_vec3()).as_dvec3();
    let sharpest = (r_c * r_c).min(r * r).max(SMOOTH_ALPHA);
    let e = crate::accuracy::quadrature::directional_albedo_f64(&f, wo, sharpest).x
        + f64::from(glazec::eval::mirror_reflectance(&material, &[], wo.as_vec3()).x);
    let at32 = at.map(|x| x as f32);
    let scale = f64::from(glazec::math::tables::lookup::<f32>(TableId::GlossyScale, &at32));
    let t = glazec::math::layering::glossy_coat_transmission(r, eta, mu);
    let normaliser = glazec::math::layering::glossy_lobe_normaliser(r_c, r, eta, mu);
    (e - 1.0, t * scale * scale * normaliser)
}

/// What one probe asks of the change x of K: lower ≤ Σ wᵢ xᵢ ≤ upper over the corners of its
/// cell (upper infinite for a probe that may lose).
pub(super) struct EnergyConstraint {
    /// Where the probe is, (μ, r_c, r, η).
    at: [f64; 4],
    /// (index into the K table, lookup weight, metric weight) of each corner.
    corners: Vec<(usize, f64, f64)>,
    /// The change of the looked-up K the probe needs to keep under [`PROBE_ENERGY_CEILING`]
    /// (nothing when it is not positive).
    lower: f64,
    upper: f64,
    /// Σ w² m: how far the looked-up change moves per unit of the multiplier.
    norm: f64,
    /// What a unit of the looked-up K takes from E (floored, as `lower` and `upper` use it).
    unit: f64,
}

impl EnergyConstraint {
    /// The constraint of a probe at `at` whose E is 1 + `excess`, a unit of K taking `unit` from
    /// it; `None` when it asks nothing.
    pub(super) fn new(at: [f64; 4], excess: f64, unit: f64) -> Option<Self> {
        // Guard: a lookup that barely moves E (T s² E c → 0 at grazing) is taken as 10⁻³.
        let unit_floor = unit.max(1e-3);
        let lower = (1.0 + excess - PROBE_ENERGY_CEILING) / unit_floor;
        let may_lose =
            unit_floor >= LOSS_PROBE_MIN_UNIT && at[3] >= LOSS_PROBE_MIN_IOR && LOSS_PROBE_COSINES.contains(&at[0]);
        let upper = if may_lose { (excess + PROBE_LOSS_TOLERANCE) / unit_floor } else { f64::INFINITY };
        if lower <= 0.0 && upper == f64::INFINITY {
            return None;
        }
        let corners = lookup_corners(at);
        let norm = corners.iter().map(|&(_, w, m)| w * w * m).sum();
        Some(EnergyConstraint { at, corners, lower, upper, norm, unit: unit_floor })
    }

    pub(super) fn looked_up(&self, change: &[f64]) -> f64 {
        self.corners.iter().map(|&(i, w, _)| w * change[i]).sum()
    }

    /// Moves the change along this constraint's direction (in the metric) by `step`.
    pub(super) fn step(&self, change: &mut [f64], step: f64) {
        for &(i, w, m) in &self.corners {
            change[i] += step * w * m;
        }
    }
}

/// Where `at` lies in `GLOSSY_SINGLE_GRID`, per axis: the cell's lower node i and the fraction t
/// of the way to node i + 1.
pub(super) fn single_cell(at: [f64; 4]) -> [(usize, f64); 4] {
    std::array::from_fn(|a| {
        let (axis, n) = GLOSSY_SINGLE_GRID[a];
        let x = f64::from(axis.coordinate(at[a] as f32)) * (n - 1) as f64;
        let i = (x.floor() as usize).min(n - 2);
        (i, x - i as f64)
    })
}

/// The corners spanned by one list of (node, weight) per axis, each with the product of its
/// axes' weights.
pub(super) fn span(per_axis: &[Vec<(usize, f64)>; 4]) -> Vec<([usize; 4], f64)> {
    let mut corners = vec![([0usize; 4], 1.0)];
    for (a, side) in per_axis.iter().enumerate() {
        corners = corners
            .iter()
            .flat_map(|&(corner, weight)| {
                side.iter().map(move |&(i, w)| {
                    let mut c = corner;
                    c[a] = i;
                    (c, weight * w)
                })
            })
            .collect();
    }
    corners
}

/// A corner's index in the `GLOSSY_SINGLE_GRID` tables (the first axis fastest).
pub(super) fn single_index(corner: [usize; 4]) -> usize {
    let dims: [usize; 4] = GLOSSY_SINGLE_GRID.map(|(_, n)| n);
    corner[0] + dims[0] * (corner[1] + dims[1] * (corner[2] + dims[2] * corner[3]))
}

/// The corners of the `GLOSSY_SINGLE_GRID` cell holding `at`, as (index of the K table, weight
/// of the multilinear lookup, metric weight: 1 on the η = 1 face, [`OFF_FACE_WEIGHT`] off it).
pub(super) fn lookup_corners(at: [f64; 4]) -> Vec<(usize, f64, f64)> {
    let per_axis = single_cell(at)
        .map(|(i, t)| [(i, 1.0 - t), (i + 1, t)].into_iter().filter(|&(_, w)| w > 1e-12).collect::<Vec<_>>());
    span(&per_axis)
        .into_iter()
        .map(|(c, w)| (single_index(c), w, if c[3] == 0 { 1.0 } else { OFF_FACE_WEIGHT }))
        .collect()
}

/// The raise of K on the η = 1 face that the least change starts from: every probe inside the
/// first η cell (η 1 … 1.22, within three quarters of it from η = 1) that needs a raise raises
/// the corners of its cell's η = 1 face nearest to it ([`nearest_corners`]) by what it needs,
/// each corner by the largest need among its probes. Near η = 1 the gains come from the escape
/// cone closing (like √(2(η − 1))), steeply in μ and η between the probes: the least change
/// alone, exact at the probes, leaves a white conductor under a smooth η 1.008 coat gaining
/// E = 1.012 at 85° (1.080 with K unchanged); this generous raise leaves none.
pub(super) fn raise_near_one(constraints: &[EnergyConstraint], len: usize) -> Vec<f64> {
    let mut raise = vec![0.0_f64; len];
    for c in constraints {
        let (ior_cell, ior_fraction) = single_cell(c.at)[3];
        if ior_cell > 0 || ior_fraction >= 0.75 || c.lower <= 0.0 {
            continue;
        }
        for (corner, share) in nearest_corners(c.at) {
            let index = single_index(corner);
            raise[index] = raise[index].max(c.lower / share);
        }
    }
    raise
}

/// The corners of the `GLOSSY_SINGLE_GRID` cell holding `at` (in the first η cell) that
/// [`raise_near_one`] raises for it, with the share of the lookup they carry there (the product
/// over the axes of their weights): the η = 1 face, and along the other axes, where `at` lies
/// within a quarter of the cell from a node only that node's side, else both.
pub(super) fn nearest_corners(at: [f64; 4]) -> Vec<([usize; 4], f64)> {
    let per_axis: [Vec<(usize, f64)>; 4] = std::array::from_fn(|a| {
        let (i, t) = single_cell(at)[a];
        match t {
            t if t <= 0.25 || GLOSSY_SINGLE_GRID[a].0 == Axis::Ior => vec![(i, 1.0 - t)],
            t if t >= 0.75 => vec![(i + 1, t)],
            t => vec![(i, 1.0 - t), (i + 1, t)],
        }
    });
    let share: f64 = per_axis.iter().map(|side| side.iter().map(|&(_, w)| w).sum::<f64>()).product();
    span(&per_axis).into_iter().map(|(corner, _)| (corner, share)).collect()
}

/// The least change x of the K table (in the metric) from `start` within the constraints:
/// Hildreth's dual coordinate ascent (Hildreth 1957; Censor & Zenios, "Parallel Optimization", 1997, §6.3). Each
/// constraint keeps a multiplier per side, λ ≥ 0 for its lower bound and 0 ≤ μ ≤
/// [`LOSS_MULTIPLIER_CAP`] for its upper one; visiting the constraints in turn, each multiplier
/// moves by the violation over `norm` (projected on its bounds) and x moves with it along the
/// constraint's weights; from multipliers 0 at `start`, it minimises the distance to `start`.
/// Deterministic: the constraints are visited in probe order.
pub(super) fn least_change(constraints: &[EnergyConstraint], start: Vec<f64>) -> Vec<f64> {
    let mut change = start;
    let mut raise = vec![0.0; constraints.len()];
    let mut lower = vec![0.0; constraints.len()];
    for _ in 0..FIT_SWEEPS {
        let mut worst: f64 = 0.0;
        for (k, c) in constraints.iter().enumerate() {
            let mut looked_up = c.looked_up(&change);
            worst = worst.max(c.lower - looked_up).max(looked_up - c.upper);
            let next = (raise[k] + (c.lower - looked_up) / c.norm).max(0.0);
            c.step(&mut change, next - raise[k]);
            looked_up += (next - raise[k]) * c.norm;
            raise[k] = next;
            if c.upper.is_finite() {
                let next = (lower[k] + (looked_up - c.upper) / c.norm).clamp(0.0, LOSS_MULTIPLIER_CAP);
                c.step(&mut change, -(next - lower[k]));
                lower[k] = next;
            }
        }
        if worst < FIT_TOLERANCE {
            break;
        }
    }
    change
}

/// The points (μ, r_c, r, η) where [`fit_lobe_albedo`] probes the energy: the centre of every
/// cell of `GLOSSY_SINGLE_GRID`, the centres of its faces and edges across (r_c, r, η) (the
/// least change of K, unlike a raise of every corner, leaves the points between probes free to
/// gain: with centres and faces alone a mirror conductor under an r 0.2, η 1.5 coat gained
/// E = 1.0019 at 60°), and the two places where the lookup's terms change
/// fastest within a cell: grazing incidence (μ = 10⁻⁴ and 2·10⁻³, below the first node's
/// [`GLOSSY_GRAZING`], where the lobe's scale is held and the escape cone's edge meets the
/// refracted mirror direction) and a coat IOR just above 1 (η − 1 = 10⁻⁵, 3·10⁻³, 3·10⁻²,
/// where the escape cone closes like √(2(η − 1)) in the first cell of a linear axis), each at
/// the centre of the cell in the other arguments.
pub(super) fn energy_probes() -> Vec<[f64; 4]> {
    let dims: [usize; 4] = GLOSSY_SINGLE_GRID.map(|(_, n)| n);
    let midpoint = |axis: usize, i: usize| -> f64 {
        let (kind, n) = GLOSSY_SINGLE_GRID[axis];
        kind.argument(i as f64 + 0.5, n)
    };
    let mut probes = Vec::new();
    for e in 0..dims[3] - 1 {
        for r in 0..dims[2] - 1 {
            for c in 0..dims[1] - 1 {
                let (r_c, r, eta) = (midpoint(1, c), midpoint(2, r), midpoint(3, e));
                for m in 0..dims[0] - 1 {
                    probes.push([midpoint(0, m), r_c, r, eta]);
                }
                for mu in GRAZING_PROBES {
                    probes.push([mu, r_c, r, eta]);
                }
                if e == 0 {
                    for m in 0..dims[0] - 1 {
                        probes.extend(NEAR_ONE_PROBES.map(|d| [midpoint(0, m), r_c, r, 1.0 + d]));
                    }
                }
            }
        }
    }
    // The faces and edges of the cells across (r_c, r, η): one or two of them at a node, the
    // others and μ at cell midpoints (edges on η = 1 left out: the coat vanishes there, and the
    // probes just above it look at what closes).
    let node = |axis: usize, i: usize| -> f64 {
        let (kind, n) = GLOSSY_SINGLE_GRID[axis];
        kind.node(i, n)
    };
    for at_node in [
        [true, false, false],
        [false, true, false],
        [false, false, true],
        [true, true, false],
        [true, false, true],
        [false, true, true],
    ] {
        let edge = at_node.iter().filter(|&&b| b).count() == 2;
        let values = |axis: usize| -> Vec<f64> {
            match at_node[axis - 1] {
                true => (usize::from(edge && axis == 3)..dims[axis]).map(|i| node(axis, i)).collect(),
                false => (0..dims[axis] - 1).map(|i| midpoint(axis, i)).collect(),
            }
        };
        for &eta in &values(3) {
            for &r in &values(2) {
                for &r_c in &values(1) {
                    probes.extend((0..dims[0] - 1).map(|m| [midpoint(0, m), r_c, r, eta]));
                }
            }
        }
    }
    probes
}

/// The grazing cosines and the coat IORs (as η − 1) of [`energy_probes`].
pub(super) const GRAZING_PROBES: [f64; 2] = [1e-4, 2e-3];

pub(super) const NEAR_ONE_PROBES: [f64; 3] = [1e-5, 3e-3, 3e-2];
