//! Multilinear interpolation of a table, written once over the shading ops: it folds literal
//! lookups at compile time, evaluates on the CPU, is the body of a shader's lookup function, and
//! gives a curve its nodes.

use super::catalogue::TableId;
use crate::math::{Codes, Real};

/// The lower node index and the weight of the upper node at fractional node position `s`
/// = u·(n − 1) on `n` nodes.
fn cell<F: Real>(s: F, n: usize) -> (F, F) {
    let i = s.floor().min(s.lit((n - 2) as f32));
    (i, s - i)
}

/// Multilinear interpolation of table `id` at coordinates u ∈ [0, 1] (`coordinate(axis)`, asked
/// for once per axis, in order), written once over the shading ops: it folds literal lookups at
/// compile time, evaluates on the CPU, and is the body of the shader's lookup function. `names`
/// (one per axis, or none at all) name the generated `let`s.
pub(super) fn multilinear<F: Real>(id: TableId, coordinate: impl Fn(usize) -> F, names: &[&str]) -> F {
    let spec = id.spec();
    let cells: Vec<(F, F)> = spec
        .axes
        .iter()
        .enumerate()
        .map(|(a, &(_, n))| {
            let node = coordinate(a) * (n - 1) as f32;
            match names.get(a) {
                Some(name) => {
                    let (i, w) = cell(node.named(&format!("node_{name}")), n);
                    (i.named(&format!("cell_{name}")), w.named(&format!("weight_{name}")))
                }
                // (No names: no strings built on the CPU's hot path.)
                None => cell(node, n),
            }
        })
        .collect();
    let zero = cells[0].0.lit(0.0);
    let mut total = zero;
    for corner in 0..1usize << cells.len() {
        // The corner's entry is start + index: a known cell (every one on the CPU) adds its
        // axis' part to `start`; an axis known only at run time adds to `index`, over its cells
        // i ∈ [0, n − 2] plus one on the upper side, so the corner reaches the window
        // [start, start + span].
        let (mut index, mut weight, mut stride) = (zero, zero.lit(1.0), 1u32);
        let (mut start, mut span) = (0u32, 0u32);
        for (axis, &(i, w)) in cells.iter().enumerate() {
            let upper = corner >> axis & 1 == 1;
            weight = weight * if upper { w } else { w.one_minus() };
            let n = spec.axes[axis].1 as u32;
            match i.known() {
                Some(cell) => start += (cell as u32 + u32::from(upper)) * stride,
                None => {
                    index = index + (if upper { i + 1.0 } else { i }) * stride as f32;
                    span += (n - 1) * stride;
                }
            }
            stride *= n;
        }
        // The entry's value: offset + scale·code, the stored encoding.
        let quantization = id.quantization();
        let codes = Codes { codes: id.codes(), buffer_offset: id.buffer_offset(), start, len: span + 1 };
        let mut code = F::fetch(codes, index);
        // Corner names list the lower (l) or upper (u) node per axis, first axis first: `at_lul`.
        let corner_name =
            || -> String { (0..cells.len()).map(|a| if corner >> a & 1 == 1 { 'u' } else { 'l' }).collect() };
        if !names.is_empty() {
            code = code.named(&format!("code_{}", corner_name()));
        }
        let mut value = code * quantization.scale + quantization.offset;
        if !names.is_empty() {
            value = value.named(&format!("at_{}", corner_name()));
        }
        total = total + value * weight;
    }
    total
}
