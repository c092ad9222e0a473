//! Multilinear interpolation of a table, written once over the shading ops: it folds literal
//! lookups at compile time, evaluates on the CPU, gives a curve its nodes, and is the body of the
//! interpolation helper that a shader's lookup functions call.

use super::catalogue::TableId;
use crate::math::{Real, TableCodes};

/// The lower node index and the weight of the upper node at fractional node position `s`
/// = u·(n − 1) on `n` nodes.
fn cell<F: Real>(s: F, n: usize) -> (F, F) {
    let i = s.floor().min(s.lit((n - 2) as f32));
    (i, s - i)
}

/// Multilinear interpolation of table `id` at coordinates u ∈ [0, 1] (`coordinate(axis)`, asked
/// for once per axis, in order): the cell and weight on every axis, then the corners, summed by
/// [`corners`] where every cell is known now (always on the CPU; literal lookups in a shader) and
/// otherwise by a call of the shader's interpolation helper ([`Real::interpolate_at_runtime`]),
/// whose body is [`corner_sum`] too. `names` (one per axis, or none at all) name the generated
/// `let`s.
pub(super) fn multilinear<F: Real>(id: TableId, coordinate: impl Fn(usize) -> F, names: &[&str]) -> F {
    let spec = id.spec();
    let cell_on = |a: usize| {
        let n = spec.axes[a].1;
        let node = coordinate(a) * (n - 1) as f32;
        match names.get(a) {
            Some(name) => {
                let (i, w) = cell(node.named(&format!("node_{name}")), n);
                (i.named(&format!("cell_{name}")), w.named(&format!("weight_{name}")))
            }
            // (No names: no strings built on the CPU's hot path.)
            None => cell(node, n),
        }
    };
    // (Tables have at most four axes: no allocation on the CPU's hot path.)
    let first = cell_on(0);
    let mut cells = [first; 4];
    for (a, c) in cells.iter_mut().enumerate().take(spec.axes.len()).skip(1) {
        *c = cell_on(a);
    }
    let cells = &cells[..spec.axes.len()];
    // (Checked first: the CPU's hot path builds no table description.)
    if cells.iter().all(|(i, w)| i.known().is_some() && w.known().is_some()) {
        return corners(id, cells);
    }
    let quantization = id.quantization();
    let mut nodes = [0u32; 4];
    for (n, &(_, axis_nodes)) in nodes.iter_mut().zip(spec.axes) {
        *n = axis_nodes as u32;
    }
    let table = TableCodes {
        codes: id.codes(),
        buffer_offset: id.buffer_offset(),
        nodes,
        scale: quantization.scale,
        offset: quantization.offset,
    };
    F::interpolate_at_runtime(&table, cells).unwrap_or_else(|| corners(id, cells))
}

/// Σ over the 2^k corners of a k-axis cell of (scale·code + offset)·Π weight, the corners in
/// order (axis 0 changing fastest) and added from zero, each weight the product over the axes
/// of w (upper node) or 1 − w (lower node), first axis first. `code(corner)` is the 16-bit code
/// at the corner (bit `a` of `corner` set: the upper node on axis `a`). The one copy of the
/// arithmetic: the CPU, the compile-time fold, and the shader's interpolation helper all sum
/// exactly this, in this order, so that they agree to rounding.
pub(crate) fn corner_sum<F: Real>(weights: &[F], scale: F, offset: F, code: impl Fn(usize) -> F) -> F {
    let zero = scale.lit(0.0);
    let mut total = zero;
    for corner in 0..1usize << weights.len() {
        let mut weight = zero.lit(1.0);
        for (axis, &w) in weights.iter().enumerate() {
            weight = weight * if corner >> axis & 1 == 1 { w } else { w.one_minus() };
        }
        total = total + (code(corner) * scale + offset) * weight;
    }
    total
}

/// [`corner_sum`] at cells (lower node index, upper node weight) known now: the CPU's lookup and
/// a shader's lookup at literal arguments, folded. The codes are read here, from the tables
/// compiled into the crate.
fn corners<F: Real>(id: TableId, cells: &[(F, F)]) -> F {
    let spec = id.spec();
    let mut weights = [cells[0].1; 4];
    for (w, &(_, cell_weight)) in weights.iter_mut().zip(cells) {
        *w = cell_weight;
    }
    let quantization = id.quantization();
    let ctx = cells[0].0.ctx();
    let codes = id.codes();
    corner_sum(
        &weights[..cells.len()],
        F::constant(ctx, quantization.scale),
        F::constant(ctx, quantization.offset),
        |corner| {
            // The corner's entry: Σ (cell + upper)·stride over the axes (every cell is known).
            let (mut entry, mut stride) = (0usize, 1usize);
            for (axis, &(i, _)) in cells.iter().enumerate() {
                let upper = usize::from(corner >> axis & 1 == 1);
                // (`as` saturates: a cell is never negative, its coordinate being clamped.)
                entry += (i.known().unwrap_or(0.0) as usize + upper) * stride;
                stride *= spec.axes[axis].1;
            }
            F::constant(ctx, f32::from(codes[entry.min(codes.len() - 1)]))
        },
    )
}
