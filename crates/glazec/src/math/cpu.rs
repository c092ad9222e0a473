//! The immediate implementation of the shading ops: `f32` scalars, `glam::Vec3` vectors.
//!
//! Every operation follows the WGSL definition of the corresponding builtin, so that a term run
//! here and the same term run as a shader differ only by the rounding of the hardware (e.g.
//! `refract` returns the zero vector on total internal reflection, exactly as WGSL does).

use glam::Vec3;

use super::{Logic, Named, Real, Slot, Sum, TermDef, Vector};

impl Named for f32 {
    fn named(self, _: &str) -> Self {
        self
    }
}

impl Named for Vec3 {
    fn named(self, _: &str) -> Self {
        self
    }
}

impl Named for bool {
    fn named(self, _: &str) -> Self {
        self
    }
}

impl Logic for bool {}

impl Real for f32 {
    type Vec = Vec3;
    type Bool = bool;
    type Ctx = ();
    const IMMEDIATE: bool = true;

    fn ctx(self) {}
    fn constant((): (), x: f32) -> f32 {
        x
    }
    fn sqrt(self) -> f32 {
        f32::sqrt(self)
    }
    fn acos(self) -> f32 {
        f32::acos(self)
    }
    fn exp(self) -> f32 {
        f32::exp(self)
    }
    fn ln(self) -> f32 {
        f32::ln(self)
    }
    fn powf(self, exponent: f32) -> f32 {
        f32::powf(self, exponent)
    }
    fn abs(self) -> f32 {
        f32::abs(self)
    }
    fn floor(self) -> f32 {
        f32::floor(self)
    }
    fn min(self, other: f32) -> f32 {
        f32::min(self, other)
    }
    fn max(self, other: f32) -> f32 {
        f32::max(self, other)
    }
    fn lt(self, other: f32) -> bool {
        self < other
    }
    fn gt(self, other: f32) -> bool {
        self > other
    }
    fn select(condition: bool, accept: f32, reject: f32) -> f32 {
        if condition { accept } else { reject }
    }
    fn splat(self) -> Vec3 {
        Vec3::splat(self)
    }
    fn vec3(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }
    fn known(self) -> Option<f32> {
        Some(self)
    }
    fn table_curves((): ()) -> bool {
        super::tables::curves_on_cpu()
    }
    fn call(_: &'static TermDef, args: &[Slot<f32>], body: &dyn Fn(&[Slot<f32>]) -> Slot<f32>) -> Slot<f32> {
        body(args)
    }
    fn sum_over((): (), sum: &Sum, body: &dyn Fn(f32) -> Vec<Vec3>) -> Vec<Vec3> {
        let key = (!sum.key.is_empty()).then(|| SumKey::of(sum));
        if let Some(totals) = key.as_ref().and_then(|key| SUMS.with_borrow(|sums| sums.find(key))) {
            return totals;
        }
        let mut totals = vec![Vec3::ZERO; sum.totals.len()];
        for i in 0..sum.count {
            for (total, term) in totals.iter_mut().zip(body(i as f32)) {
                *total += term;
            }
        }
        if let Some(key) = key {
            SUMS.with_borrow_mut(|sums| sums.keep(key, totals.clone()));
        }
        totals
    }
}

/// What identifies a sum of [`Real::sum_over`]: its length, what it returns, and its inputs'
/// bits.
#[derive(PartialEq)]
struct SumKey {
    count: u32,
    totals: Vec<String>,
    inputs: Vec<u32>,
}

impl SumKey {
    fn of(sum: &Sum) -> Self {
        SumKey {
            count: sum.count,
            totals: sum.totals.iter().map(|t| t.to_string()).collect(),
            inputs: sum.key.iter().map(|x| x.to_bits()).collect(),
        }
    }
}

/// The last few sums on this thread, newest last.
#[derive(Default)]
struct Sums(Vec<(SumKey, Vec<Vec3>)>);

impl Sums {
    /// Sums kept per thread: a material's f, its albedo-only pass and a few materials in turn
    /// (a stack's glossy level and each coat over an absorbing coated layer keep their own).
    const KEPT: usize = 16;

    fn find(&self, key: &SumKey) -> Option<Vec<Vec3>> {
        self.0.iter().rev().find(|(k, _)| k == key).map(|(_, totals)| totals.clone())
    }

    fn keep(&mut self, key: SumKey, totals: Vec<Vec3>) {
        if self.0.len() == Self::KEPT {
            self.0.remove(0);
        }
        self.0.push((key, totals));
    }
}

thread_local! {
    static SUMS: std::cell::RefCell<Sums> = std::cell::RefCell::new(Sums::default());
}

impl Vector for Vec3 {
    type Real = f32;

    fn dot(self, other: Vec3) -> f32 {
        Vec3::dot(self, other)
    }
    fn cross(self, other: Vec3) -> Vec3 {
        Vec3::cross(self, other)
    }
    fn normalize(self) -> Vec3 {
        self / self.length()
    }
    fn x(self) -> f32 {
        self.x
    }
    fn y(self) -> f32 {
        self.y
    }
    fn z(self) -> f32 {
        self.z
    }
    fn exp(self) -> Vec3 {
        Vec3::new(self.x.exp(), self.y.exp(), self.z.exp())
    }
    fn sqrt(self) -> Vec3 {
        Vec3::new(self.x.sqrt(), self.y.sqrt(), self.z.sqrt())
    }
    fn min(self, other: Vec3) -> Vec3 {
        Vec3::min(self, other)
    }
    fn max(self, other: Vec3) -> Vec3 {
        Vec3::max(self, other)
    }
    fn select(condition: bool, accept: Vec3, reject: Vec3) -> Vec3 {
        if condition { accept } else { reject }
    }
    fn is_known_zero(self) -> bool {
        self == Vec3::ZERO
    }
    fn is_known(self) -> bool {
        true
    }
    fn refract(self, normal: Vec3, eta: f32) -> Vec3 {
        // WGSL §17.5 refract(e1, e2, e3): k = 1 − e3²(1 − dot(e2, e1)²);
        // 0 if k < 0, else e3·e1 − (e3·dot(e2, e1) + √k)·e2.
        let d = normal.dot(self);
        let k = 1.0 - eta * eta * (1.0 - d * d);
        if k < 0.0 { Vec3::ZERO } else { self * eta - normal * (eta * d + k.sqrt()) }
    }
}
