//! Time per solve of each `glazec::optics` inversion (one channel), and a batch of 1M solves.
//! The clay-optics paper's MMSE solver takes 40 ms per solve; the target is < 1 µs per channel.
//!
//! `cargo bench --bench optics`; docs/optics.md quotes the medians and the ratio to 40 ms.

use std::hint::black_box;

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use glazec::optics::{self, Observation, Slab, SlabModel};

/// The clay-optics paper's time per solve, in seconds.
const SEED_SOLVE_SECONDS: f64 = 0.040;
/// Solves in the batch benchmark.
const BATCH: usize = 1 << 20;

const SLAB: Slab = Slab { f_top: 0.09, f_bottom: 0.0, p_g: 0.5, eta: 1.5 };

/// A spread of observations of one kind, generated from known coefficients.
fn observations(kind: &str, n: usize) -> Vec<Observation> {
    (0..n)
        .map(|i| {
            let t = (i as f64 * 0.618_033_988_75).fract();
            let u = (i as f64 * 0.754_877_666_2).fract();
            let (a, s) = (0.05 + 2.0 * t, 2.0 + 20.0 * u);
            match kind {
                "kubelka_munk" => {
                    let (k, s_km, x) = (2.0 * a, (3.0 * s - a) / 4.0, 0.1);
                    let r_black = optics::km_reflectance(k, s_km, x, 0.0);
                    let r_white = optics::km_reflectance(k, s_km, x, 0.9);
                    Observation::BlackWhite { r_black, r_white, backing: 0.9, thickness: x }
                }
                "two_thicknesses" => {
                    let (d1, d2) = (0.3 / (a + s), 1.2 / (a + s));
                    let model = SlabModel::Exponential;
                    let (r1, r2) = (model.reflectance(SLAB, d1, a, s), model.reflectance(SLAB, d2, a, s));
                    Observation::TwoThicknesses { model, slab: SLAB, d1, r1, d2, r2 }
                }
                "known_scattering_seed" => {
                    let d = 0.1 / (a + s);
                    let r = optics::seed_reflectance(SLAB, d, a, s);
                    Observation::KnownScattering { model: SlabModel::Seed, slab: SLAB, d, r, sigma_s: s }
                }
                "known_scattering_exponential" => {
                    let d = 0.5 / (a + s);
                    let r = optics::exponential_reflectance(SLAB, d, a, s);
                    Observation::KnownScattering { model: SlabModel::Exponential, slab: SLAB, d, r, sigma_s: s }
                }
                _ => {
                    let r = optics::dipole_albedo(s / (a + s), 1.4);
                    Observation::MeanFreePath { r, mfp: 1.0 / (3.0 * a * (a + s)).sqrt(), eta: 1.4 }
                }
            }
        })
        .collect()
}

const KINDS: [&str; 5] =
    ["kubelka_munk", "known_scattering_seed", "known_scattering_exponential", "mean_free_path", "two_thicknesses"];

fn per_solve(c: &mut Criterion) {
    let mut group = c.benchmark_group("optics_solve");
    for kind in KINDS {
        let set = observations(kind, 1024);
        let mut i = 0;
        group.bench_function(kind, |b| {
            b.iter(|| {
                i = (i + 1) % set.len();
                optics::solve(black_box(&set[i])).expect("solves")
            })
        });
    }
    group.finish();
}

fn batch(c: &mut Criterion) {
    let mut group = c.benchmark_group("optics_batch_1M");
    group.sample_size(10);
    let set = observations("kubelka_munk", BATCH);
    group.bench_function("kubelka_munk", |b| {
        b.iter_batched(
            || (),
            |()| set.iter().map(|o| optics::solve(o).map_or(0.0, |s| s.sigma_a)).sum::<f64>(),
            BatchSize::SmallInput,
        )
    });
    group.finish();
    eprintln!("the clay-optics paper's solver: {SEED_SOLVE_SECONDS} s per solve (docs/optics.md)");
}

criterion_group!(benches, per_solve, batch);
criterion_main!(benches);
