//! Gauss–Legendre rules on [0, 1]: the one source of quadrature nodes for the shared math (the
//! slab integrals, the glossy level's hemisphere), the simplifier and the lab. Nodes and weights
//! on [−1, 1] are from Abramowitz & Stegun, Table 25.4, mapped to [0, 1].

/// 4-point Gauss–Legendre nodes and weights on [0, 1] in f32, each within one ulp of the exact
/// value (the third node is one ulp below the nearest f32; every shipped shader was generated
/// with these values, so they stay).
pub const GAUSS_LEGENDRE_4: [(f32, f32); 4] = [
    (0.069_431_84, 0.173_927_42),
    (0.330_009_5, 0.326_072_58),
    (0.669_990_5, 0.326_072_58),
    (0.930_568_16, 0.173_927_42),
];

/// The `k`-th node (k = 0…3, a whole number) and weight of [`GAUSS_LEGENDRE_4`], chosen by `k`
/// as a value: the loop counter of a quadrature that [`crate::math::Real::sum_over`] builds once.
pub fn gauss_legendre_4_at<F: crate::math::Real>(k: F) -> (F, F) {
    let pick = |of: fn((f32, f32)) -> f32| {
        let [a, b, c, d] = GAUSS_LEGENDRE_4.map(|node| k.lit(of(node)));
        F::select(k.lt_lit(1.5), F::select(k.lt_lit(0.5), a, b), F::select(k.lt_lit(2.5), c, d))
    };
    (pick(|(x, _)| x), pick(|(_, w)| w))
}

/// 12-point Gauss–Legendre nodes and weights on [0, 1] (rounded to f32 where used in
/// shaders).
pub const GAUSS_LEGENDRE_12: [(f64, f64); 12] = [
    (9.219_682_876_640_378e-3, 2.358_766_819_325_570_6e-2),
    (4.794_137_181_476_26e-2, 5.346_966_299_765_953e-2),
    (1.150_486_629_028_476_5e-1, 8.003_916_427_167_321e-2),
    (2.063_410_228_566_912_6e-1, 1.015_837_133_615_328_6e-1),
    (3.160_842_505_009_099_4e-1, 1.167_462_682_691_773e-1),
    (4.373_832_957_442_655_4e-1, 1.245_735_229_067_013_4e-1),
    (5.626_167_042_557_344e-1, 1.245_735_229_067_013_4e-1),
    (6.839_157_494_990_901e-1, 1.167_462_682_691_773e-1),
    (7.936_589_771_433_087e-1, 1.015_837_133_615_328_6e-1),
    (8.849_513_370_971_523e-1, 8.003_916_427_167_321e-2),
    (9.520_586_281_852_375e-1, 5.346_966_299_765_953e-2),
    (9.907_803_171_233_596e-1, 2.358_766_819_325_570_6e-2),
];

/// 16-point Gauss–Legendre nodes and weights on [0, 1].
pub fn gauss_legendre_16() -> [(f64, f64); 16] {
    // Nodes and weights on [−1, 1] (Abramowitz & Stegun, Table 25.4), mapped to [0, 1].
    const X: [f64; 8] = [
        0.095_012_509_837_637_44,
        0.281_603_550_779_258_9,
        0.458_016_777_657_227_4,
        0.617_876_244_402_643_8,
        0.755_404_408_355_003,
        0.865_631_202_387_831_7,
        0.944_575_023_073_232_6,
        0.989_400_934_991_649_9,
    ];
    const W: [f64; 8] = [
        0.189_450_610_455_068_5,
        0.182_603_415_044_923_6,
        0.169_156_519_395_002_5,
        0.149_595_988_816_576_7,
        0.124_628_971_255_533_9,
        0.095_158_511_682_492_78,
        0.062_253_523_938_647_89,
        0.027_152_459_411_754_09,
    ];
    let mut out = [(0.0, 0.0); 16];
    for i in 0..8 {
        out[2 * i] = ((1.0 - X[i]) / 2.0, W[i] / 2.0);
        out[2 * i + 1] = ((1.0 + X[i]) / 2.0, W[i] / 2.0);
    }
    out
}

#[cfg(test)]
pub mod reference {
    //! Reference integrators for tests, independent of the Gauss–Legendre tables.

    /// Adaptive Simpson in f64 on [a, b] to `eps` (a test-only reference).
    pub fn adaptive_simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, eps: f64, depth: u32) -> f64 {
        fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
            (b - a) / 6.0 * (f(a) + 4.0 * f((a + b) / 2.0) + f(b))
        }
        let m = (a + b) / 2.0;
        let (whole, left, right) = (simpson(f, a, b), simpson(f, a, m), simpson(f, m, b));
        if depth == 0 || (left + right - whole).abs() < 15.0 * eps {
            return left + right + (left + right - whole) / 15.0;
        }
        adaptive_simpson(f, a, m, eps / 2.0, depth - 1) + adaptive_simpson(f, m, b, eps / 2.0, depth - 1)
    }

    /// A composite Simpson rule with `n` (even) intervals on [a, b].
    pub fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut s = f(a) + f(b);
        for i in 1..n {
            s += f(a + h * i as f64) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An n-point rule integrates every polynomial of degree ≤ 2n − 1 exactly.
    fn exact_to_degree(rule: &[(f64, f64)]) {
        for degree in 0..2 * rule.len() as i32 {
            let sum: f64 = rule.iter().map(|&(x, w)| w * x.powi(degree)).sum();
            let exact = 1.0 / f64::from(degree + 1);
            assert!((sum - exact).abs() < 1e-13, "{}-point rule, x^{degree}: {sum} vs {exact}", rule.len());
        }
    }

    #[test]
    fn rules_are_exact_for_their_polynomials() {
        exact_to_degree(&GAUSS_LEGENDRE_12);
        exact_to_degree(&gauss_legendre_16());
        // The 4-point rule in f64, rounded to the stored f32 values.
        let x = [0.5 - 0.430_568_155_797_026_3, 0.5 - 0.169_990_521_792_428_1];
        let w = [0.173_927_422_568_726_9, 0.326_072_577_431_273_1];
        let exact = [(x[0], w[0]), (x[1], w[1]), (1.0 - x[1], w[1]), (1.0 - x[0], w[0])];
        exact_to_degree(&exact);
        let ulp = |x: f32| f32::from_bits(x.to_bits() + 1) - x;
        for ((x, w), (x32, w32)) in exact.iter().zip(GAUSS_LEGENDRE_4) {
            assert!((*x as f32 - x32).abs() <= ulp(x32) && (*w as f32 - w32).abs() <= ulp(w32), "{x32}, {w32}");
        }
    }
}
