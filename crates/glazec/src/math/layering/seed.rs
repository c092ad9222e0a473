//! The seed's two methods (Bowsher 2022): Disney clear-coat layering, each coat adding its
//! Cook–Torrance lobe ([`additive`]), and the Weidlich–Wilkie recurrence ([`weidlich_wilkie`]).

use super::base::base_brdf;
use super::geometry::{Geometry, level_name};
use super::inputs::{Body, Inputs};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};
use crate::model::{Coat, Lobe};

pub(super) fn additive<F: Real>(coats: &[Coat], body: &Body<'_>, inputs: &Inputs<F>, g: &Geometry<F>) -> F::Vec {
    // Every layer at the outer directions, each with its own normal where it has a map.
    let base_g = g.facing_level(coats.len());
    let mut f = base_brdf(body, inputs, base_g.as_ref().unwrap_or(g), None, None).named("f_base");
    for (k, coat) in coats.iter().enumerate() {
        let coat_g = g.facing_level(k);
        if let Some(lobe) = seed_lobe(&coat.lobe, inputs.scalar(coat.ior), inputs, coat_g.as_ref().unwrap_or(g)) {
            f = f + lobe.specular;
        }
    }
    f
}

/// A coat's specular lobe as the seed computes it (Schlick F, Schlick-GGX G).
struct SeedSpecular<F: Real> {
    pub(super) specular: F::Vec,
    pub(super) fresnel: F::Vec,
    pub(super) distribution: F,
    pub(super) shadowing: F,
}

/// The seed's Cook–Torrance coat lobe (Bowsher 2022, §3.0.1–3.0.2), `None` for a smooth coat.
fn seed_lobe<F: Real>(lobe: &Lobe, eta: F, inputs: &Inputs<F>, g: &Geometry<F>) -> Option<SeedSpecular<F>> {
    let name = |base| level_name(base, g.level);
    let (roughness, distribution) = match lobe {
        Lobe::Smooth => return None,
        Lobe::Ggx { roughness } => {
            let r = inputs.scalar(*roughness);
            (r, d_ggx(g.half().n_dot_h, g.half().sin2_h, r * r))
        }
        Lobe::Gtr1 { roughness } => {
            let r = inputs.scalar(*roughness);
            (inputs.lit(GTR1_SMITH_ROUGHNESS), d_gtr1(g.half().n_dot_h, g.half().sin2_h, r * r))
        }
    };
    let distribution = distribution.named(&name("d"));
    let shadowing = g_smith_schlick_ggx(g.n_dot_v, g.n_dot_l, roughness).named(&name("g"));
    let fresnel = f_schlick(f0_dielectric(eta).splat(), g.half().v_dot_h).named(&name("fresnel"));
    let specular = f_cook_torrance(distribution, shadowing, fresnel, g.n_dot_v, g.n_dot_l).named(&name("specular"));
    Some(SeedSpecular { specular, fresnel, distribution, shadowing })
}

/// The seed's coat lobe without its Fresnel factor, D·G/(4 μv μl), for unit directions in the
/// frame of `n` (zero below the horizon and for a smooth coat): what `glazec tables` integrates
/// into the seed lobes' split-sum DFG (`environment`), so that image-based lighting weighs the
/// lobe the shaders evaluate.
pub fn seed_lobe_white(lobe: &Lobe, n: glam::Vec3, v: glam::Vec3, l: glam::Vec3) -> f32 {
    if n.dot(v) <= 0.0 || n.dot(l) <= 0.0 {
        return 0.0;
    }
    let inputs = Inputs::<f32>::new((), Vec::new());
    let g = Geometry::new(n, v, l, 0);
    // (The IOR only sets the Fresnel factor, which is left out.)
    seed_lobe(lobe, 1.5, &inputs, &g)
        .map_or(0.0, |seed| f_cook_torrance(seed.distribution, seed.shadowing, glam::Vec3::ONE, g.n_dot_v, g.n_dot_l).x)
}

pub(super) fn weidlich_wilkie<F: Real>(
    coats: &[Coat],
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    k: usize,
    n_medium: Option<F>,
) -> F::Vec {
    let Some(coat) = coats.get(k) else {
        return base_brdf(body, inputs, g, n_medium, None).named(&level_name("f_base", g.level));
    };
    let eta = inputs.scalar(coat.ior);
    let (f_top, fresnel, shadowing) = match seed_lobe(&coat.lobe, eta, inputs, g) {
        Some(lobe) => (lobe.specular, lobe.fresnel, lobe.shadowing),
        // A smooth interface: its mirror lobe is a delta (zero for point lights), h = n, G = 1.
        None => (inputs.zero(), f_schlick(f0_dielectric(eta).splat(), g.n_dot_v), inputs.lit(1.0)),
    };
    let name = |base| level_name(base, k);
    let t12 = fresnel.one_minus().named(&name("transmission"));
    let below = g.refracted(eta);
    let sigma_a = inputs.color(coat.absorption);
    let thickness = inputs.scalar(coat.thickness);
    // No absorption (σa = 0 or d = 0) is e^0 = 1: skip the call.
    let absorption = if sigma_a.is_known_zero() || thickness.splat().is_known_zero() {
        inputs.lit(1.0).splat()
    } else if sigma_a.is_known_grey() {
        absorption_ww_grey(sigma_a.x(), thickness, below.n_dot_l, below.n_dot_v).splat().named(&name("absorption"))
    } else {
        absorption_ww(sigma_a, thickness, below.n_dot_l, below.n_dot_v).named(&name("absorption"))
    };
    let inner = ww_inner_reflection(shadowing, t12).named(&name("inner"));
    let n_below = Some(n_medium.map_or(eta, |n| n * eta));
    let f_below = weidlich_wilkie(coats, body, inputs, &below, k + 1, n_below);
    ww_layer::<F>(f_top, t12, absorption, inner, f_below).named(&name("f"))
}
