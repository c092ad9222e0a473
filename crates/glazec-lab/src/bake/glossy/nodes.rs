//! The nodes the glossy tables are measured at, and the constants every measurement shares.

use glazec::math::layering::GLOSSY_GRAZING;
use glazec::math::tables::Axis;

pub(super) use crate::bake::interface::SMOOTH_ALPHA;

/// Sinkhorn iterations of the scale.
pub(super) const SCALE_ITERATIONS: usize = 30;

/// The node of `axis` `i` of `n`.
/// The (r_c, r, η) node triples of a glossy grid whose axes after the first are those three, in
/// table order (r_c fastest), with their arguments.
pub(super) fn node_triples(axes: &[(Axis, usize)]) -> Vec<(f64, f64, f64)> {
    let (rc, r, eta) = (axes[axes.len() - 3], axes[axes.len() - 2], axes[axes.len() - 1]);
    let mut triples = Vec::new();
    for e in 0..eta.1 {
        for j in 0..r.1 {
            for c in 0..rc.1 {
                triples.push((rc.0.node(c, rc.1), r.0.node(j, r.1), eta.0.node(e, eta.1)));
            }
        }
    }
    triples
}

/// The direction nodes of a glossy grid (its first axis), each at least [`GLOSSY_GRAZING`].
pub(super) fn direction_nodes(axes: &[(Axis, usize)]) -> Vec<f64> {
    let (axis, n) = axes[0];
    (0..n).map(|i| axis.node(i, n).max(GLOSSY_GRAZING)).collect()
}
