//! The reference's random streams: one deterministic stream per estimate, seeded from its
//! inputs.

use rand::{RngExt, SeedableRng};

/// The random stream of one estimate.
pub struct Rng(rand_pcg::Pcg64Mcg);

impl Rng {
    pub fn seeded(seed: u64) -> Rng {
        Rng(rand_pcg::Pcg64Mcg::seed_from_u64(seed))
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0.random::<f64>()
    }
}

/// A 64-bit mix of the inputs of an estimate (splitmix64's finaliser), so each (wi, wo, seed)
/// has its own stream.
pub(super) fn seed_of(values: &[f64], seed: u64) -> u64 {
    let mut h = seed ^ 0x9e37_79b9_7f4a_7c15;
    for v in values {
        h ^= v.to_bits();
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^= h >> 31;
    }
    h
}
