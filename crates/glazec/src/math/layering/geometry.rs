//! The directions at one level of the stack ([`Geometry`]): the cosines derived from them, the
//! half vector, refraction to the level below, and the shading normals of normal-mapped layers.

use std::cell::OnceCell;

use crate::math::terms::*;
use crate::math::{Named, Real, Vector};

/// Cosines are clamped to at least this before anything divides by them. It keeps f finite at
/// grazing angles and changes nothing above θ = 89.994°.
pub const COS_EPSILON: f32 = 1e-4;

/// Cosine below which a mapped normal is bent towards the viewer (see [`facing`]).
const FACING_EPSILON: f32 = 0.05;

/// A normal-mapped shading normal that faces away from the (refracted) view direction `v` shows
/// a facet the viewer cannot see, which renders as black specks on steep bumps; it is bent
/// towards `v` just enough that n·v = ε: n′ = normalize(n + v (ε − n·v)) when n·v < ε (the usual
/// horizon fix for normal maps, cf. Jimenez et al. 2016 on normal/view mismatch).
pub(super) fn facing<F: Real>(n: F::Vec, v: F::Vec, level: usize) -> F::Vec {
    let deficit = (n.dot(v) * -1.0 + FACING_EPSILON).at_least(0.0);
    (n + v * deficit).normalize().named(&level_name("facing_normal", level))
}

/// Every level's normal and whether it comes from a normal map (see [`brdf`]).
type Levels<F> = std::rc::Rc<[(<F as Real>::Vec, bool)]>;

/// The directions at one level of the stack and the cosines derived from them.
pub(super) struct Geometry<F: Real> {
    pub(super) n: F::Vec,
    pub(super) v: F::Vec,
    pub(super) l: F::Vec,
    pub(super) raw_n_dot_v: F,
    pub(super) raw_n_dot_l: F,
    /// n·v and n·l clamped to ≥ COS_EPSILON, for use in denominators.
    pub(super) n_dot_v: F,
    pub(super) n_dot_l: F,
    pub(super) level: usize,
    pub(super) half: OnceCell<Half<F>>,
    /// Every level's normal, and whether it comes from a normal map (see [`brdf`]).
    pub(super) levels: Option<Levels<F>>,
    /// Whether this level's normal comes from a normal map: its BRDF is then zero for
    /// directions below its own horizon, which the surface's horizon does not exclude.
    pub(super) mapped: bool,
    /// The surface normal (before any normal map), where it differs from `n`.
    pub(super) surface: Option<F::Vec>,
    /// Only the directional albedos are wanted (image-based lighting, [`environment`]): the
    /// methods skip f itself, which would be dead code in the generated function.
    pub(super) albedo_only: bool,
}

/// The half vector h = (v + l)/|v + l| at one level, through the quantities the lobes use.
#[derive(Clone, Copy)]
pub(super) struct Half<F: Real> {
    /// cos θh = n·h.
    pub(super) n_dot_h: F,
    /// sin²θh = |n × h|², computed directly rather than as 1 − (n·h)², which cancels
    /// catastrophically in f32 at the specular peak (n·h → 1) of a sharp lobe.
    pub(super) sin2_h: F,
    /// v·h (= l·h).
    pub(super) v_dot_h: F,
}

/// The name of a value at one level of the stack in generated code: `v` at the top, `layer1_v`
/// under the first coat, and so on (no trailing digits, which naga would suffix with `_`).
pub(super) fn level_name(base: &str, level: usize) -> String {
    if level == 0 { base.to_string() } else { format!("layer{level}_{base}") }
}

impl<F: Real> Geometry<F> {
    pub(super) fn new(n: F::Vec, v: F::Vec, l: F::Vec, level: usize) -> Self {
        let raw_n_dot_v = n.dot(v).named(&level_name("n_dot_v", level));
        let raw_n_dot_l = n.dot(l).named(&level_name("n_dot_l", level));
        Geometry {
            n,
            v,
            l,
            raw_n_dot_v,
            raw_n_dot_l,
            n_dot_v: raw_n_dot_v.at_least(COS_EPSILON).named(&level_name("cos_v", level)),
            n_dot_l: raw_n_dot_l.at_least(COS_EPSILON).named(&level_name("cos_l", level)),
            level,
            half: OnceCell::new(),
            levels: None,
            mapped: false,
            surface: None,
            albedo_only: false,
        }
    }

    /// The geometry of an albedo-only evaluation ([`environment`]): no light direction, so l = v
    /// with the very same values (the generated code computes each cosine once, and term calls
    /// on the light's side are the view's).
    pub(super) fn albedo_only(n: F::Vec, v: F::Vec, level: usize) -> Self {
        let raw_n_dot_v = n.dot(v).named(&level_name("n_dot_v", level));
        let n_dot_v = raw_n_dot_v.at_least(COS_EPSILON).named(&level_name("cos_v", level));
        Geometry {
            n,
            v,
            l: v,
            raw_n_dot_v,
            raw_n_dot_l: raw_n_dot_v,
            n_dot_v,
            n_dot_l: n_dot_v,
            level,
            half: OnceCell::new(),
            levels: None,
            mapped: false,
            surface: None,
            albedo_only: true,
        }
    }

    /// A value towards l and towards v, as `(l(), v())`; where only albedos are wanted (l = v)
    /// it is computed once, towards v, so that the generated code neither repeats it nor names
    /// the view's value after the light.
    pub(super) fn sides<T: Clone>(&self, l: impl FnOnce() -> T, v: impl FnOnce() -> T) -> (T, T) {
        if self.albedo_only {
            let v = v();
            (v.clone(), v)
        } else {
            (l(), v())
        }
    }

    /// For a level whose normal comes from a normal map, the light's cosine to that normal over
    /// its cosine to the surface normal, max(n_s·l, 0)/max(n·l, ε): the mapped facet receives
    /// irradiance by its own cosine while `<material>_eval` multiplies by the surface's. This is
    /// the shading-normal BRDF of Veach 1997 §5.3 (not reciprocal, as no normal map is); it is
    /// what makes a bumpy Lambertian body look bumpy at all (its f alone is constant).
    pub(super) fn shading_cosine_ratio(&self) -> Option<F> {
        if !self.mapped {
            return None;
        }
        let surface = self.surface?;
        Some(
            (self.raw_n_dot_l.at_least(0.0) / surface.dot(self.l).at_least(COS_EPSILON))
                .named(&level_name("shading_ratio", self.level)),
        )
    }

    pub(super) fn with_levels(mut self, levels: std::rc::Rc<[(F::Vec, bool)]>, surface: Option<F::Vec>) -> Self {
        self.mapped = levels.get(self.level).is_some_and(|&(_, mapped)| mapped);
        self.levels = Some(levels);
        self.surface = surface;
        self
    }

    /// The same directions seen by the layer of level `level` (its normal), for methods that
    /// evaluate every layer at the outer directions (`Additive`); `self` if it has no map.
    pub(super) fn facing_level(&self, level: usize) -> Option<Geometry<F>> {
        let &(n, mapped) = self.levels.as_ref()?.get(level)?;
        if !mapped || level == self.level {
            return None;
        }
        let mut g = Geometry::new(n, self.v, self.l, self.level);
        g.mapped = true;
        g.surface = self.surface;
        Some(g)
    }

    pub(super) fn v_dot_l(&self) -> F {
        self.v.dot(self.l)
    }

    /// The half vector's cosines, computed once per level.
    pub(super) fn half(&self) -> Half<F> {
        *self.half.get_or_init(|| {
            let h = half_vector::<F>(self.v, self.l).named(&level_name("h", self.level));
            let n_cross_h = self.n.cross(h).named(&level_name("n_cross_h", self.level));
            Half { n_dot_h: self.n.dot(h), sin2_h: n_cross_h.dot(n_cross_h), v_dot_h: self.v.dot(h) }
        })
    }

    /// A GGX lobe of slope variance `base` (α²) at these directions, each crossing of a rough
    /// coat spreading it by `along` (σ², towards l and towards v) along its direction's plane of
    /// incidence and σ²/μ² across it (`d_ggx_crossed`; μ ≥ CROSSED_COSINE_MIN), the two
    /// across-plane spreads named `names`.
    pub(super) fn d_ggx_crossed(&self, base: F, along: (F, F), names: (&str, &str)) -> F {
        let half = self.half();
        let across = |sigma_sq: F, mu: F, name: &str| (sigma_sq / mu.at_least(CROSSED_COSINE_MIN).sq()).named(name);
        let twist = self.n.dot(self.l.cross(self.v));
        d_ggx_crossed(
            half.n_dot_h,
            half.sin2_h,
            half.v_dot_h,
            self.n_dot_l,
            self.n_dot_v,
            twist.sq(),
            base,
            across(along.0, self.n_dot_l, names.0),
            across(along.1, self.n_dot_v, names.1),
        )
    }

    /// The directions one layer down, under an interface of relative IOR `eta`.
    pub(super) fn refracted(&self, eta: F) -> Geometry<F> {
        let level = self.level + 1;
        let v = refract_down(self.v, self.n, eta).named(&level_name("v", level));
        if self.albedo_only {
            return Geometry::albedo_only(self.n, v, level);
        }
        let l = refract_down(self.l, self.n, eta).named(&level_name("l", level));
        let Some(levels) = &self.levels else { return Geometry::new(self.n, v, l, level) };
        let n = match levels.get(level) {
            Some(&(n, true)) => facing::<F>(n, v, level),
            Some(&(n, false)) => n,
            None => self.n,
        };
        Geometry::new(n, v, l, level).with_levels(levels.clone(), self.surface)
    }
}
