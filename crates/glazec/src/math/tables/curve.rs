//! A table's curve: a lookup with every argument but one fixed at compile time, baked into a
//! closed form that a shader evaluates without reading any resource.
//!
//! Multilinear interpolation is separable, so with every axis but one fixed, a lookup is the
//! piecewise-linear function through the table's nodes along the free axis, each node's value
//! interpolated across the fixed axes (exactly what [`super::lookup`] computes for those cells).
//! A piecewise-linear function with knots k₁ < k₂ < … on u ∈ [0, n − 1] (the free argument's
//! coordinate in node units, [`Axis::position`], so that every knot is a node's whole number) is
//!
//!   f(u) = a + s₀·u + Σⱼ cⱼ·max(u, kⱼ),   cⱼ = sⱼ − sⱼ₋₁ (the change of slope at kⱼ),
//!
//! (a absorbs −Σ cⱼkⱼ), which costs a max and a multiply-add per knot and no memory at all. The
//! shader groups the knots by three: `dot(max(vec3(u), vec3(1f, 2f, 3f)), slope_changes)`. Its terms are as
//! large as the slopes, so where that would lose a curve's small values to rounding (more than
//! an eighth of the table's 16-bit step) the curve is summed piece by piece instead, each term
//! at most its piece's change of value ([`Form`]).
//!
//! **Why not a constant array.** On lavapipe a dynamically indexed `const` array of the clay's
//! three curves made the `eval_pairs` pipeline take 0.84 s to build and the kernel run at 8.9 M
//! evaluations/s, against 70 M/s for these hinge sums and 35 M/s for today's lookups in the
//! table uniform (naga's SPIR-V writer spills the array into a local variable at every access,
//! which llvmpipe lowers to a chain of selects). A fitted polynomial does not work either: the
//! lookup has a kink at every node, and a degree-12 fit still misses it by 4·10⁻⁴ to 2·10⁻² on
//! the coat tables.
//!
//! **Knots.** The curve keeps the free axis' nodes that it needs: starting from the two ends, it
//! adds the node where the piecewise-linear function through the kept nodes is furthest from the
//! lookup until that distance is at most [`KNOT_TOLERANCE`] (rounding) everywhere. Both are
//! piecewise linear with knots at nodes, so the largest distance is at a node and the check is
//! exact.

use super::catalogue::{Axis, TableId};
use super::multilinear::multilinear;
use crate::math::{Real, Vector};

/// How far a curve may lie from the multilinear lookup it replaces at a dropped node
/// (absolute): none but rounding. A curve drops only the nodes that lie on the line through
/// their neighbours (a flat or straight stretch, such as a smooth interface's zero deficit), so
/// that it is the lookup itself up to rounding: the CPU, which looks the tables up, and a shader,
/// which sums the curve, agree as closely as before. Any real tolerance is too much somewhere:
/// at 10⁻⁶ a sharp coat's (r 0.04) multiple-scattering share, itself about 10⁻⁶ and divided by
/// its hemispherical average in the lobe, became a straight line and `car_paint`'s lobe rose by
/// 5·10⁻⁵ at grazing; at 5·10⁻⁵ rough coats gained up to 0.45% energy, the deficit's curve
/// overshooting the table that is rounded down so that its lookup does not. Even at 10⁻⁴, a
/// deficit curve keeps 25–32 of its 32 nodes: the tables are sampled as coarsely as their shapes
/// allow.
pub const KNOT_TOLERANCE: f64 = 1e-12;

/// A function of one argument, piecewise linear in that argument's coordinate in node units,
/// u ∈ [0, n − 1] ([`Axis::position`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// How the argument maps to u.
    pub mapping: Axis,
    pub form: Form,
    /// The smallest value at its nodes, and how far the sum may round away from the exact
    /// piecewise-linear value (f32 ε times the sum of its terms' sizes). Where the smallest value
    /// is a share of zero or within rounding of it, the sum is held at or above it, so that a
    /// share never rounds below zero (a lobe divides by one); elsewhere rounding stays inside.
    pub floor: f32,
    pub rounding: f32,
    /// The nodes the curve was built on (u = 0, 1, …, n − 1).
    pub nodes: usize,
}

/// How a [`Curve`] is summed.
#[derive(Clone, Debug, PartialEq)]
pub enum Form {
    /// a + s₀·u + Σⱼ cⱼ·max(u, kⱼ): a max and a multiply-add per knot. Its terms are as large
    /// as the slopes, so a curve that falls steeply to nearly nothing loses the small values
    /// to rounding.
    Hinges { constant: f32, slope: f32, knots: Vec<(f32, f32)> },
    /// v₀ + Σⱼ sⱼ·(clamp(u, uⱼ, uⱼ₊₁) − uⱼ): twice the work per knot, but each term is at most
    /// the change of value across its piece, so small values keep their precision.
    Pieces { start: f32, pieces: Vec<(f32, f32, f32)> },
}

impl Curve {
    /// The lookup of `table` along axis `axis`, with the other arguments `fixed` (one per axis,
    /// in order; the free axis' entry is ignored).
    pub fn of_table(table: TableId, axis: usize, fixed: &[f32]) -> Curve {
        let spec = table.spec();
        let (mapping, n) = spec.axes[axis];
        let coordinates: Vec<f32> = fixed.iter().zip(spec.axes).map(|(&x, &(a, _))| a.coordinate(x)).collect();
        let points: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let u = i as f32 / (n - 1) as f32;
                (i as f64, f64::from(multilinear::<f32>(table, |a| if a == axis { u } else { coordinates[a] }, &[])))
            })
            .collect();
        Curve::through_points(mapping, &points, f64::from(table.quantization().scale))
    }

    /// The piecewise-linear function through `points` (u, value), u the node positions 0, 1, …,
    /// n − 1, keeping the points it needs to stay within [`KNOT_TOLERANCE`] of all of them. `step` is
    /// the precision of the values (a table's 16-bit step): the hinge form is used where its
    /// rounding (f32 ε times the sum of its terms' sizes) stays within an eighth of it, the
    /// piece form elsewhere.
    pub fn through_points(mapping: Axis, points: &[(f64, f64)], step: f64) -> Curve {
        let kept = keep_knots(points, KNOT_TOLERANCE);
        let slope = |a: usize, b: usize| (points[b].1 - points[a].1) / (points[b].0 - points[a].0);
        let slopes: Vec<f64> = kept.windows(2).map(|w| slope(w[0], w[1])).collect();
        let mut constant = points[0].1 - slopes[0] * points[0].0;
        let mut knots = Vec::new();
        for (j, &knot) in kept.iter().enumerate().take(kept.len() - 1).skip(1) {
            let change = slopes[j] - slopes[j - 1];
            constant -= change * points[knot].0;
            knots.push((points[knot].0 as f32, change as f32));
        }
        // Each term is at most its factor times the largest u.
        let u_max = points[points.len() - 1].0;
        let size =
            constant.abs() + u_max * (slopes[0].abs() + knots.iter().map(|&(_, c)| f64::from(c.abs())).sum::<f64>());
        let mut rounding = f64::from(f32::EPSILON) * size;
        let form = if rounding <= step / 8.0 {
            Form::Hinges { constant: constant as f32, slope: slopes[0] as f32, knots }
        } else {
            let changes = kept.windows(2).map(|w| (points[w[1]].1 - points[w[0]].1).abs()).sum::<f64>();
            rounding = f64::from(f32::EPSILON) * (points[0].1.abs() + changes);
            let pieces = kept
                .windows(2)
                .zip(&slopes)
                .map(|(w, &s)| (points[w[0]].0 as f32, points[w[1]].0 as f32, s as f32))
                .collect();
            Form::Pieces { start: points[0].1 as f32, pieces }
        };
        let floor = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min) as f32;
        Curve { mapping, form, floor, rounding: rounding as f32, nodes: points.len() }
    }

    /// How many of its nodes the curve keeps.
    pub fn kept(&self) -> usize {
        match &self.form {
            Form::Hinges { knots, .. } => knots.len() + 2,
            Form::Pieces { pieces, .. } => pieces.len() + 1,
        }
    }

    /// The curve at argument `x` (mapped to u and clamped like the lookup's axis), written once
    /// over the shading ops: the body of the shader's curve function, and the CPU's lookup.
    pub fn evaluate<F: Real>(&self, x: F) -> F {
        let sum = self.sum(x);
        if self.floor >= 0.0 && self.floor <= 4.0 * self.rounding { sum.at_least(self.floor) } else { sum }
    }

    /// The curve's sum, before the floor.
    fn sum<F: Real>(&self, x: F) -> F {
        let u = self.mapping.position(x, self.nodes).named("u");
        // (A partial sum that folds to a number, as on the CPU, stays unnamed.)
        let partial = |v: F| if v.known().is_some() { v } else { v.named("f") };
        let triple = |a: f32, b: f32, c: f32| F::vec3(u.lit(a), u.lit(b), u.lit(c));
        match &self.form {
            Form::Hinges { constant, slope, knots } => {
                let mut total = partial(u * *slope + *constant);
                let groups = knots.chunks_exact(3);
                let rest = groups.remainder();
                for g in groups {
                    let at = triple(g[0].0, g[1].0, g[2].0);
                    total = partial(total + u.splat().max(at).dot(triple(g[0].1, g[1].1, g[2].1)));
                }
                for &(knot, change) in rest {
                    total = partial(total + u.max(u.lit(knot)) * change);
                }
                total
            }
            Form::Pieces { start, pieces } => {
                let mut total = u.lit(*start);
                let groups = pieces.chunks_exact(3);
                let rest = groups.remainder();
                for g in groups {
                    let (lo, hi) = (triple(g[0].0, g[1].0, g[2].0), triple(g[0].1, g[1].1, g[2].1));
                    let along = u.splat().max(lo).min(hi) - lo;
                    total = partial(total + along.dot(triple(g[0].2, g[1].2, g[2].2)));
                }
                for &(lo, hi, s) in rest {
                    total = partial(total + (u.clamp(lo, hi) - lo) * s);
                }
                total
            }
        }
    }
}

/// Whether `material`'s lookups along a direction are curves, in its shader and on the CPU: when
/// it has no runtime parameters. (With runtime parameters most lookups have several runtime
/// arguments and read the table uniform; the CPU then looks every table up, exactly as the
/// shader does, rather than summing curves for the few lookups whose other arguments are
/// literals: a sharp coat's multiple-scattering lobe divides by its tiny hemispherical average
/// and turns the two forms' different rounding into visible differences.)
pub fn curves_for(material: &crate::model::Material) -> bool {
    material.params.is_empty()
}

thread_local! {
    static CURVES_ON_CPU: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f` with the CPU's table lookups along a direction summing curves (`on`) or looking the
/// tables up: what a CPU evaluation of a material does around its math, per [`curves_for`].
pub fn with_curves<R>(on: bool, f: impl FnOnce() -> R) -> R {
    let before = CURVES_ON_CPU.replace(on);
    let result = f();
    CURVES_ON_CPU.set(before);
    result
}

/// Whether the CPU sums curves now (see [`with_curves`]).
pub fn curves_on_cpu() -> bool {
    CURVES_ON_CPU.get()
}

/// Curves the CPU evaluates, most recent first, per thread: evaluating one material at many
/// directions builds each of its curves once.
const CPU_CURVES: usize = 32;

/// A cached curve: its table, its fixed arguments' bits (tables have at most four axes), the
/// tables' generation, the curve.
type Cached = (TableId, [u32; 3], usize, std::rc::Rc<Curve>);

thread_local! {
    static CACHE: std::cell::RefCell<Vec<Cached>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// `with` the curve of `table` along its first axis with the other arguments of `args` fixed,
/// from this thread's cache.
pub(super) fn on_cpu<R>(table: TableId, args: &[f32], with: impl FnOnce(&Curve) -> R) -> R {
    let mut key = [0_u32; 3];
    for (k, x) in key.iter_mut().zip(&args[1..]) {
        *k = x.to_bits();
    }
    let generation = super::storage::generation();
    let curve = CACHE.with_borrow_mut(|cache| {
        let found = cache.iter().position(|(t, k, g, _)| *t == table && *k == key && *g == generation);
        match found {
            Some(0) => {}
            Some(at) => {
                let entry = cache.remove(at);
                cache.insert(0, entry);
            }
            None => {
                cache.insert(0, (table, key, generation, std::rc::Rc::new(Curve::of_table(table, 0, args))));
                cache.truncate(CPU_CURVES);
            }
        }
        cache[0].3.clone()
    });
    with(&curve)
}

/// The points a piecewise-linear interpolant of `points` (u, value) must keep to stay within
/// `tolerance` of all of them: the two ends, then greedily the point furthest away. (Also what
/// the lab's `kernel_breakdown` example asks of a curve at issue 30's bound.)
pub fn keep_knots(points: &[(f64, f64)], tolerance: f64) -> Vec<usize> {
    let n = points.len();
    let mut kept = vec![0, n - 1];
    loop {
        let mut worst = (0, 0.0);
        for pair in kept.windows(2) {
            let ((ua, va), (ub, vb)) = (points[pair[0]], points[pair[1]]);
            for (i, &(u, v)) in points.iter().enumerate().take(pair[1]).skip(pair[0] + 1) {
                let error = (va + (u - ua) / (ub - ua) * (vb - va) - v).abs();
                if error > worst.1 {
                    worst = (i, error);
                }
            }
        }
        if worst.1 <= tolerance {
            return kept;
        }
        let at = kept.partition_point(|&k| k < worst.0);
        kept.insert(at, worst.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::tables::SPECS;

    /// Every curve stays this close to the lookup it replaces (absolute, relative above 1), at
    /// any argument: f32 rounding (issue 30 asked for 10⁻⁴ absolute).
    const CURVE_BOUND: f32 = 5e-6;

    /// Arguments along an axis: its nodes, the middles of its cells, and its ends' outsides.
    fn arguments(axis: Axis, n: usize) -> Vec<f32> {
        let mut xs: Vec<f32> = (0..4 * (n - 1) + 1).map(|k| axis.argument(k as f64 / 4.0, n) as f32).collect();
        xs.retain(|x| x.is_finite());
        xs
    }

    #[test]
    fn every_table_curve_stays_within_the_bound_of_its_lookup() {
        let mut worst = 0.0_f32;
        for (t, spec) in SPECS.iter().enumerate() {
            let table = TableId::ALL[t];
            for axis in 0..spec.axes.len() {
                // Fixed arguments: a spread of cells of every other axis (nodes and middles).
                let others: Vec<Vec<f32>> = spec
                    .axes
                    .iter()
                    .map(|&(a, n)| {
                        (0..2 * (n - 1)).step_by(3).map(|k| a.argument(k as f64 / 2.0 + 0.25, n) as f32).collect()
                    })
                    .collect();
                let combinations: usize =
                    others.iter().enumerate().filter(|(a, _)| *a != axis).map(|(_, v)| v.len()).product();
                for c in 0..combinations {
                    let mut rest = c;
                    let fixed: Vec<f32> = others
                        .iter()
                        .enumerate()
                        .map(|(a, v)| {
                            if a == axis {
                                return 0.0;
                            }
                            let x = v[rest % v.len()];
                            rest /= v.len();
                            x
                        })
                        .collect();
                    let curve = Curve::of_table(table, axis, &fixed);
                    for x in arguments(spec.axes[axis].0, spec.axes[axis].1) {
                        let mut args = fixed.clone();
                        args[axis] = x;
                        // Against the multilinear lookup itself (the CPU's `lookup` sums the curve).
                        let coordinates: Vec<f32> =
                            args.iter().zip(spec.axes).map(|(&x, &(a, _))| a.coordinate(x)).collect();
                        let exact = multilinear::<f32>(table, |a| coordinates[a], &[]);
                        let error = (curve.evaluate(x) - exact).abs() / exact.abs().max(1.0);
                        worst = worst.max(error);
                        assert!(error <= CURVE_BOUND, "{} along axis {axis} at {args:?}: off by {error:e}", spec.name);
                    }
                }
            }
        }
        eprintln!("largest difference of a curve from its lookup: {worst:.2e}");
        assert!(worst > 0.0, "the curves were compared");
    }

    #[test]
    fn knots_are_kept_where_needed() {
        // A straight line needs no interior knot; a kink needs its node.
        let uniform = |v: &[f64]| -> Vec<(f64, f64)> { v.iter().enumerate().map(|(i, &v)| (i as f64, v)).collect() };
        assert_eq!(keep_knots(&uniform(&[0.0, 1.0, 2.0, 3.0]), 1e-9), vec![0, 3]);
        assert_eq!(keep_knots(&uniform(&[0.0, 1.0, 2.0, 2.0, 2.0]), 1e-9), vec![0, 2, 4]);
    }
}
