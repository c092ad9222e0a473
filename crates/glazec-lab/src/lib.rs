//! # glazec-lab — the measurement lab beside the compiler
//!
//! Everything here measures or produces what the compiler uses; none of it is in the compiler
//! that `build.rs` users get:
//!
//! * [`reference`](mod@reference): the ground truth, an independent f64 Monte Carlo random walk through the
//!   layer stack (position-free, in the style of pbrt-v4's `LayeredBxDF`), with the exact
//!   closed forms that exist.
//! * [`accuracy`]: every layering method against the reference on an evaluation set, and the
//!   BRDF laws (reciprocity, energy) — `glazec accuracy`.
//! * [`bake`] (and [`bake::glossy`]): baking the tabulated terms of the default method from the
//!   reference's microsurfaces into `crates/glazec/data/tables.bin` — `glazec tables`.
//! * [`stability`]: sweeps to the limits where layering breaks — `glazec stability`.
//! * [`bench`](mod@bench) and [`chart`] (feature `gpu`): speed against accuracy — `glazec bench`.
//! * [`fuzzing`]: the harnesses of the fuzz targets and of the tests that replay their corpus.

pub mod accuracy;
pub mod bake;
#[cfg(feature = "gpu")]
pub mod bench;
#[cfg(feature = "gpu")]
pub mod chart;
pub mod fuzzing;
#[cfg(feature = "gpu")]
pub mod images;
pub mod reference;
pub mod stability;

use glazec::model::Method;
use rayon::prelude::*;

/// The layering methods the lab compares, the default first.
pub const METHODS: [Method; 3] = [Method::INTERFACED, Method::WeidlichWilkie, Method::Additive];

/// `f(0)`, …, `f(count − 1)` computed on every available core, in index order (each result
/// depends only on its index, so the output does not depend on scheduling); `progress(i)` after
/// each.
pub(crate) fn parallel_map<R: Send>(
    count: usize,
    f: impl Fn(usize) -> R + Sync,
    progress: impl Fn(usize) + Sync,
) -> Vec<R> {
    (0..count)
        .into_par_iter()
        .map(|i| {
            let r = f(i);
            progress(i);
            r
        })
        .collect()
}
