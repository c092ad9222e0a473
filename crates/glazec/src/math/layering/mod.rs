//! The layering methods: how a stack of coats over a base becomes one BRDF.
//!
//! The stack is known at compile time, so each method is a Rust recursion over the layers that
//! unrolls into straight-line code: the same function produces the CPU value and, run on the
//! naga builder, the body of `<material>_brdf`. Every method goes through [`brdf`], so clay,
//! Disney clear-coat and eight-layer stacks share one code path.
//!
//! * [`Method::Additive`] (Burley 2012; Bowsher 2022, §3.0.2): the base at the outer directions
//!   plus one specular lobe per coat, nothing attenuated.
//! * [`Method::WeidlichWilkie`] (Bowsher 2022, §3.0.3, eq. 12–19), as the seed writes it.
//!   Readings where the seed is ambiguous (also in docs/language.md, "How Bowsher 2022 is
//!   read"):
//!   - eq. 12 evaluates the lower layer at (L′, V) but eq. 13's legend at (L′, V′); we refract
//!     **both** directions (V′), as Weidlich & Wilkie 2007 do, which also keeps f reciprocal;
//!     eq. 15's path length likewise uses n·V′.
//!   - eq. 5 writes Schlick's F with n·V; for a microfacet lobe we use v·h, as the seed's own
//!     source (LearnOpenGL, eq. 2) does; a smooth coat has h = n, so it is n·V there.
//!   - eq. 18–19 multiply "Diffuse × a × f_r" with Diffuse = (1 − F)·OrenNayar: we read them as
//!     eq. 13 with f_r2 = Oren–Nayar, i.e. (1 − F) is T12, applied once, not twice.
//!   - no η² radiance compression and no inter-reflection (faithful; this is why it is measured).
//! * [`Method::Interfaced`] (glazec's default), per coat, top down:
//!   - the interface's own lobe (exact dielectric Fresnel at the microfacet normal,
//!     height-correlated Smith GGX) scaled by c(μi)·c(μo) for the light that scatters more than
//!     once between microfacets (a reciprocal form of Turquin 2019's compensation, c tabulated
//!     so that the lobe reflects exactly what the coat does not transmit), so a rough interface
//!     conserves energy and its multiply-scattered light stays near the mirror direction;
//!   - transmission T(μ) = 1 − F(μ) + G(μ) (G: the deficit of the rough interface's single- and
//!     multiple-scattering reflection against a smooth interface's; tabulated,
//!     `super::tables`); 1 − F(μ) for a smooth coat;
//!   - absorption e^{−τ/μ′} along both refracted paths, μ′ Snell's cosine shortened by the
//!     tabulated path factor of a rough interface; η² radiance compression;
//!   - below the coat, a diffuse body gets f_b + E_b(μi)E_b(μo)R(τ)/(π(1 − ρ̄R(τ))): the series of
//!     internal reflections (TIR included) between the coat and the body, R(τ) and the escape
//!     share E_esc(τ) from slab integrals (smooth) or tables (rough). When the layer below is
//!     itself coated, the series starts from what its first reflection really returns
//!     (`first_pass`): that light leaves concentrated towards the normal; and the light the coat
//!     returns, which meets that layer beyond the escape cone, is sent back up with the layer's
//!     albedo less what its top interface reflects straight back (`returned_albedo`). A conductor directly
//!     under the coat gets the **glossy level** (`glossy`, see its essay): a lobe for the light
//!     that leaves near the mirror direction and a separable remainder for the light trapped
//!     by TIR, split by the number of conductor events with statistics from white random walks
//!     (`glazec tables`). A glossy layer deeper down (a coated conductor under further coats)
//!     keeps its lobe: f_b/(1 − √(E k E k)) for the bounces inside the escape cone, widened by
//!     the refraction through a rough coat above (`BLUR_WIDTH`).
//!
//!   Reciprocal, white furnace within 2·10⁻³, exact for a smooth coat over Lambert with
//!   absorption (docs/derivations.md, "Smooth coat over Lambert"); measured against the
//!   stochastic reference in `glazec_lab::accuracy` (docs/accuracy.md).

mod base;
pub mod environment;
mod geometry;
mod glossy;
mod inputs;
mod interface;
mod interfaced;
mod level;
mod seed;
mod trapped;

pub use geometry::COS_EPSILON;
pub use glossy::{GLOSSY_GRAZING, glossy_coat_transmission, glossy_lobe_normaliser, glossy_lobe_white};
pub use inputs::Inputs;
pub use seed::seed_lobe_white;

use crate::math::terms::*;
use crate::math::{Named, Real, Vector};
use crate::model::{Coat, Lobe, Material, Method};
use geometry::{Geometry, facing, level_name};
use inputs::{Body, Depth, Stack, expand};
use interface::dielectric_fresnel;
use interfaced::interfaced;
use seed::{additive, weidlich_wilkie};

/// The BRDF f(l, v) of a material, **without** the cosine, for unit vectors `n`, `v`, `l`
/// (both directions pointing away from the surface). Zero when either lies below the horizon.
pub fn brdf<F: Real>(material: &Material, inputs: &Inputs<F>, n: F::Vec, v: F::Vec, l: F::Vec) -> F::Vec {
    let (coats, body) = expand(material);
    // Each level's normal: its layer's normal map, or the surface normal. (A plastic base expands
    // to a coat and a body: both take the base's map.)
    // Without normal maps every level has the surface normal: no per-level table (this runs for
    // every evaluation on the CPU).
    if inputs.normals.is_empty() {
        let top = Geometry::new(n, v, l, 0);
        return finish_brdf(material, &coats, &body, inputs, &top, (top.raw_n_dot_v, top.raw_n_dot_l));
    }
    let levels: Vec<(F::Vec, bool)> = (0..=coats.len())
        .map(|level| match inputs.layer_normal(level.min(material.coats.len())) {
            Some(mapped) => (mapped.named(&level_name("shading_normal", level)), true),
            None => (n, false),
        })
        .collect();
    let top_normal = if levels[0].1 { facing::<F>(levels[0].0, v, 0) } else { levels[0].0 };
    let surface = levels.iter().any(|&(_, mapped)| mapped).then_some(n);
    let top = Geometry::new(top_normal, v, l, 0).with_levels(std::rc::Rc::from(levels), surface);
    // (The horizon is the surface normal's: a normal map tilts the shading, not the horizon.)
    finish_brdf(material, &coats, &body, inputs, &top, (n.dot(v), n.dot(l)))
}

/// Runs the material's method from the top level and makes f one-sided: zero unless both
/// cosines to the surface normal, `(n·v, n·l)`, are positive.
fn finish_brdf<F: Real>(
    material: &Material,
    coats: &[Coat],
    body: &Body<'_>,
    inputs: &Inputs<F>,
    top: &Geometry<F>,
    (surface_v, surface_l): (F, F),
) -> F::Vec {
    let f = match material.method {
        Method::Additive => additive(coats, body, inputs, top),
        Method::WeidlichWilkie => weidlich_wilkie(coats, body, inputs, top, 0, None),
        Method::Interfaced(approx) => interfaced(&Stack { coats, body, inputs, approx }, top, Depth::top(), false).f,
    };
    // A one-sided BRDF: nothing is reflected from or towards below the horizon.
    let above = surface_v.gt_lit(0.0) & surface_l.gt_lit(0.0);
    F::Vec::select(above, f.named("f"), inputs.zero())
}

/// The reflectance of the stack's mirror (delta) lobe towards `v`: the part of the light that a
/// smooth top coat reflects specularly, which [`brdf`] (a function of two directions) cannot
/// show. Zero for a rough top coat or a bare base. Each method's own Fresnel: exact for
/// `Interfaced`, Schlick's for the seed's methods. Reflections off deeper smooth interfaces
/// (also deltas) are not included.
pub fn mirror_reflectance<F: Real>(material: &Material, inputs: &Inputs<F>, n: F::Vec, v: F::Vec) -> F::Vec {
    let Some(coat) = material.coats.first() else { return inputs.zero() };
    if !matches!(coat.lobe, Lobe::Smooth) {
        return inputs.zero();
    }
    let eta = inputs.scalar(coat.ior);
    let n_dot_v = n.dot(v);
    let reflectance = match material.method {
        Method::Interfaced(approx) => dielectric_fresnel(n_dot_v, eta, approx).splat(),
        Method::Additive | Method::WeidlichWilkie => {
            f_schlick(f0_dielectric(eta).splat(), n_dot_v.at_least(COS_EPSILON))
        }
    };
    F::Vec::select(n_dot_v.gt_lit(0.0), reflectance, inputs.zero())
}
