//! One source for the math: every BRDF term and layering method, written once.
//!
//! The formulas in [`terms`] and [`layering`] are ordinary Rust functions, generic over the
//! shading-ops trait [`Real`] (a scalar) and its [`Vector`] (a `vec3`). Two types implement it:
//!
//! * `f32` with `glam::Vec3` ([`cpu`]) evaluates immediately — this is `glazec eval --backend
//!   cpu`, the tests' CPU side, and constant folding;
//! * `lower::builder::Expr` builds naga IR: each operation appends an expression to the function
//!   being built, folding literal arithmetic on the way.
//!
//! So the generated shader and the CPU evaluation of a material are the same formula by
//! construction; GPU-vs-CPU agreement tests measure float differences only.
//!
//! Terms are declared with `shading_fn!`. On the CPU a term is a plain call; in naga it becomes
//! one shader function with the same name (`d_ggx`, `fr_dielectric`, …), its doc comment is
//! carried into the emitted code, and each `let` inside it becomes a named `let` in the output.
//! A term whose arguments are all literals is folded at compile time instead of being called.
//!
//! Conventions (docs/derivations.md, "One source for the math"): directions in the local shading
//! frame with z the normal; `wi`/`l` and `wo`/`v` both point away from the surface; `f` is the
//! BRDF **without** the cosine; RGB is linear radiometric.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

pub mod cpu;
pub mod layering;
pub mod quadrature;
pub mod sampling;
pub mod tables;
pub mod terms;

/// The shape of a term argument or result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Scalar,
    Vec3,
}

/// A term's static description: its shader-visible name, parameters, result and doc text.
#[derive(Debug)]
pub struct TermDef {
    pub name: &'static str,
    pub params: &'static [(&'static str, Kind)],
    pub ret: Kind,
    /// The term's doc comment, line by line; the first line cites the paper.
    pub doc: &'static [&'static str],
}

impl TermDef {
    /// The doc comment's first paragraph, the comment above the term in generated code: the
    /// citation, the formula and its guards. The paragraphs after it (why the term has this
    /// form, what was measured) stay in the Rust docs.
    pub fn summary(&self) -> &'static [&'static str] {
        let end = self.doc.iter().position(|line| line.trim().is_empty()).unwrap_or(self.doc.len());
        &self.doc[..end]
    }
}

/// A table as a shader's interpolation helper reads it ([`Real::interpolate_at_runtime`]): its
/// 16-bit codes, where they start in the catalogue's buffer (the table's identity), its nodes per
/// axis (first axis fastest in memory) and its quantisation, value = scale·code + offset.
#[derive(Clone, Copy, Debug)]
pub struct TableCodes {
    pub codes: &'static [u16],
    pub buffer_offset: u32,
    /// Nodes per axis (as many axes as the lookup has cells; at most four).
    pub nodes: [u32; 4],
    pub scale: f32,
    pub offset: f32,
}

/// A term argument or result of either shape.
pub enum Slot<F: Real> {
    S(F),
    V(F::Vec),
}

impl<F: Real> Clone for Slot<F> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<F: Real> Copy for Slot<F> {}

/// Values that can be given a readable name in generated code (`let a2 = …`). No-op on the CPU.
pub trait Named: Sized {
    fn named(self, name: &str) -> Self;
}

/// Boolean values of a [`Real`] family (`bool` on the CPU, a naga `bool` expression otherwise).
pub trait Logic: Copy + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> + Named {}

/// The scalar of the shading-ops family: `f32`, or a naga expression of type `f32`.
///
/// Arithmetic uses the standard operators, with `f32` literals on the right (`x * 2.0`); a literal
/// on the left is written `x.lit(2.0) - x`, or with the helpers below.
pub trait Real:
    Copy
    + Named
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f32, Output = Self>
    + Sub<f32, Output = Self>
    + Mul<f32, Output = Self>
    + Div<f32, Output = Self>
{
    type Vec: Vector<Real = Self> + Mul<Self, Output = Self::Vec> + Div<Self, Output = Self::Vec>;
    type Bool: Logic;
    /// What a constant needs to be created: `()` on the CPU, the module builder in naga.
    type Ctx: Copy;
    /// Whether operations compute their values at once (the CPU) rather than build code.
    const IMMEDIATE: bool;

    fn ctx(self) -> Self::Ctx;
    fn constant(ctx: Self::Ctx, x: f32) -> Self;

    fn sqrt(self) -> Self;
    /// The arc cosine, in radians (of an argument within [−1, 1]).
    fn acos(self) -> Self;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
    fn powf(self, exponent: Self) -> Self;
    fn abs(self) -> Self;
    fn floor(self) -> Self;
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    fn lt(self, other: Self) -> Self::Bool;
    fn gt(self, other: Self) -> Self::Bool;
    /// `accept` where `condition` holds, else `reject`. Both sides are evaluated (as on a GPU),
    /// so a rejected side may be NaN or infinite without harm.
    fn select(condition: Self::Bool, accept: Self, reject: Self) -> Self;
    fn splat(self) -> Self::Vec;
    fn vec3(x: Self, y: Self, z: Self) -> Self::Vec;

    /// The value, if it is known now (always on the CPU; a folded constant in naga).
    fn known(self) -> Option<f32>;
    /// Whether table lookups along one runtime argument are curves here (`tables::Curve`): in
    /// the shader of a material without runtime parameters, and in its CPU evaluation.
    fn table_curves(ctx: Self::Ctx) -> bool;
    /// Multilinear interpolation of `table` in `cells` (per axis, the lower node's index and the
    /// upper node's weight), asked for only where a cell is known only at run time: in a shader,
    /// a call of the module's interpolation helper, whose body sums the corners as `tables` does.
    /// `None` where there is no such helper (the CPU, whose cells are always known): `tables`
    /// then sums the corners itself.
    fn interpolate_at_runtime(table: &TableCodes, cells: &[(Self, Self)]) -> Option<Self> {
        let _ = (table, cells);
        None
    }

    /// Calls (or, on the CPU, simply evaluates) a term. Use `shading_fn!` rather than this.
    fn call(def: &'static TermDef, args: &[Slot<Self>], body: &dyn Fn(&[Slot<Self>]) -> Slot<Self>) -> Slot<Self>;

    /// The sums over i = 0, 1, …, `sum.count` − 1 of the vectors `body(i)` returns (i as a
    /// number; `body` returns as many vectors every time), added in order from zero. In a shader
    /// this is a loop whose body is built once (`sum.index` names its counter, `sum.totals` its
    /// accumulators), so that a quadrature over many nodes costs one node's code; with
    /// `sum.fold` the iterations are instead built one after another with i a literal, for
    /// bodies whose other inputs are all literals and which therefore fold to constants. On the
    /// CPU the last few sums are kept, by `sum.key` (every input the body reads besides i, as
    /// numbers, with `sum.totals` naming what it returns): evaluating one material at many
    /// directions sums its hemisphere once. An empty key keeps nothing.
    fn sum_over(ctx: Self::Ctx, sum: &Sum, body: &dyn Fn(Self) -> Vec<Self::Vec>) -> Vec<Self::Vec>;

    /// A literal in the same context as `self`.
    fn lit(self, x: f32) -> Self {
        Self::constant(self.ctx(), x)
    }
    /// `1 − self`.
    fn one_minus(self) -> Self {
        self.lit(1.0) - self
    }
    /// `1 / self`.
    fn recip(self) -> Self {
        self.lit(1.0) / self
    }
    /// `self²`.
    fn sq(self) -> Self {
        self * self
    }
    /// `max(self, x)`: the usual guard against a cosine or denominator reaching zero.
    fn at_least(self, x: f32) -> Self {
        self.max(self.lit(x))
    }
    fn clamp(self, lo: f32, hi: f32) -> Self {
        self.max(self.lit(lo)).min(self.lit(hi))
    }
    fn lt_lit(self, x: f32) -> Self::Bool {
        self.lt(self.lit(x))
    }
    fn gt_lit(self, x: f32) -> Self::Bool {
        self.gt(self.lit(x))
    }
}

/// A loop of [`Real::sum_over`]: how many iterations, what the generated code calls its
/// counter and accumulators, and whether to unroll it at compile time instead.
#[derive(Clone, Copy, Debug)]
pub struct Sum<'n> {
    pub count: u32,
    pub index: &'n str,
    pub totals: &'n [&'n str],
    pub fold: bool,
    pub key: &'n [f32],
}

/// A three-component vector of a [`Real`] family: a direction or an RGB colour.
pub trait Vector:
    Copy
    + Named
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Mul<f32, Output = Self>
{
    type Real: Real<Vec = Self>;

    fn dot(self, other: Self) -> Self::Real;
    fn cross(self, other: Self) -> Self;
    fn normalize(self) -> Self;
    fn x(self) -> Self::Real;
    fn y(self) -> Self::Real;
    fn z(self) -> Self::Real;
    /// Component-wise `e^x`.
    fn exp(self) -> Self;
    /// Component-wise square root.
    fn sqrt(self) -> Self;
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    fn select(condition: <Self::Real as Real>::Bool, accept: Self, reject: Self) -> Self;
    /// GLSL/WGSL `refract(self, n, eta)`: the refracted direction for incident direction `self`
    /// (pointing *towards* the surface), or the zero vector on total internal reflection.
    fn refract(self, normal: Self, eta: Self::Real) -> Self;

    /// Whether the value is known to be exactly zero when the code is generated (on the CPU:
    /// whether it is zero). Lets a method skip work that would multiply by one, e.g. the
    /// absorption of a clear coat; the result is the same either way.
    fn is_known_zero(self) -> bool;

    /// Whether the value is known when the code is generated (always on the CPU; a folded
    /// constant in naga).
    fn is_known(self) -> bool;

    /// Whether the value is known when the code is generated, with three equal components (a
    /// grey colour: one scalar computation can then stand for three).
    fn is_known_grey(self) -> bool {
        // (Checked first, so that no component of a runtime vector is extracted into the code.)
        if !self.is_known() {
            return false;
        }
        match (self.x().known(), self.y().known(), self.z().known()) {
            (Some(x), Some(y), Some(z)) => x == y && y == z,
            _ => false,
        }
    }

    /// `1 − self`, component-wise.
    fn one_minus(self) -> Self {
        self.x().lit(1.0).splat() - self
    }
}

/// Declares a BRDF term once for every [`Real`] implementation.
///
/// ```ignore
/// shading_fn! {
///     /// Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 33.
///     pub fn d_ggx(n_dot_h: S, alpha: S) -> S {
///         let a2 = alpha * alpha;
///         let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
///         a2 / (d * d * PI)
///     }
/// }
/// ```
///
/// Argument and result kinds are `S` (scalar) or `V` (`vec3`). The body is a sequence of
/// `let name = expr;` followed by the result expression; each `let` becomes a named `let` in
/// the generated shader.
macro_rules! shading_fn {
    (
        $(#[doc = $doc:literal])*
        $vis:vis fn $name:ident ( $( $arg:ident : $kind:ident ),* $(,)? ) -> $ret:ident { $($body:tt)* }
    ) => {
        $(#[doc = $doc])*
        #[allow(clippy::too_many_arguments)]
        $vis fn $name<F: $crate::math::Real>( $( $arg: $crate::math::shading_fn!(@ty F $kind) ),* )
            -> $crate::math::shading_fn!(@ty F $ret)
        {
            static DEF: $crate::math::TermDef = $crate::math::TermDef {
                name: stringify!($name),
                params: &[ $( (stringify!($arg), $crate::math::shading_fn!(@kind $kind)) ),* ],
                ret: $crate::math::shading_fn!(@kind $ret),
                doc: &[ $( $doc ),* ],
            };
            let args = [ $( $crate::math::shading_fn!(@slot $kind $arg) ),* ];
            let result = F::call(&DEF, &args, &|slots: &[$crate::math::Slot<F>]| {
                let mut slots = slots.iter().copied();
                $( let $arg = $crate::math::shading_fn!(@unslot $kind slots.next()); )*
                let result = $crate::math::shading_fn!(@body [] $($body)*);
                $crate::math::shading_fn!(@slot $ret result)
            });
            $crate::math::shading_fn!(@unslot $ret Some(result))
        }
    };
    (@ty $f:ident S) => { $f };
    (@ty $f:ident V) => { <$f as $crate::math::Real>::Vec };
    (@kind S) => { $crate::math::Kind::Scalar };
    (@kind V) => { $crate::math::Kind::Vec3 };
    (@slot S $e:expr) => { $crate::math::Slot::S($e) };
    (@slot V $e:expr) => { $crate::math::Slot::V($e) };
    (@unslot S $e:expr) => {
        match $e {
            Some($crate::math::Slot::S(x)) => x,
            // The macro fixes every slot's kind; a mismatch is a bug in `Real::call`.
            _ => unreachable!("term slot kind mismatch"),
        }
    };
    (@unslot V $e:expr) => {
        match $e {
            Some($crate::math::Slot::V(x)) => x,
            _ => unreachable!("term slot kind mismatch"),
        }
    };
    (@body [$($done:tt)*] let $n:ident = $e:expr; $($rest:tt)*) => {
        $crate::math::shading_fn!(@body [$($done)* let $n = $crate::math::Named::named($e, stringify!($n));] $($rest)*)
    };
    (@body [$($done:tt)*] $e:expr) => { { $($done)* $e } };
}
pub(crate) use shading_fn;
