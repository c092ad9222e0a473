//! Image-based lighting: a layered material lit by a whole environment, as a few lobes.
//!
//! The radiance a material reflects towards `v` from an environment L is ∫ f(v, l) L(l) n·l dl.
//! The split-sum approximation (Karis 2013, "Real Shading in Unreal Engine 4") writes each lobe
//! of f as its directional albedo E(v) times the environment averaged over the lobe's shape:
//!
//! L_o(v) ≈ Σ_lobes E_k(v) · L̄_k(d_k, r_k)
//!
//! where L̄ is either the environment **prefiltered** with a GGX lobe of roughness r_k around the
//! direction d_k (for specular lobes), or the **irradiance** around the normal divided by π (for
//! lobes that leave the surface diffusely). Both are lookups into images that the renderer
//! prepares (`glazec_gpu::environment`, or the user's own); this module only says which lobes a
//! material has and how much each weighs.
//!
//! The weights come from the method's own albedos, so the lighting conserves exactly what the
//! BRDF conserves (a white furnace returns the method's directional albedo):
//!
//! * [`Method::Interfaced`]: the top coat's lobe (its single- and multiple-scattering
//!   reflection) weighs 1 − T(μv), the coat's transmission from the tables `glazec tables`
//!   generates (CoatDeficit; for a smooth coat the exact Fresnel F(μv): the mirror
//!   lobe). Everything under it weighs E(μv) − (1 − T(μv)), E the stack's directional albedo the
//!   method itself computes for its inter-reflections; it leaves diffusely (irradiance) over a
//!   diffusing body, and as a GGX lobe of the conductor's α widened by the rough coats above
//!   (the method's blur) over a conductor. Light reflected by deeper coats is counted in that
//!   second part (as diffuse or as the conductor's lobe), not as sharp reflections of its own.
//! * The seed's methods (Additive, WeidlichWilkie) weigh their Schlick-Fresnel coat lobes by
//!   the split-sum DFG of the seed's own lobe, E(μ) = F0·A(μ; r) + B(μ; r), which `glazec tables`
//!   generates by quadrature of that lobe (GGX with Burley's Smith remap k = (r + 1)²/8; GTR1 with
//!   Smith at α = 0.25); a smooth coat's mirror weighs Schlick's F(μ). The base weighs its
//!   directional albedo, unattenuated (Additive) or through each coat's 1 − E and absorption
//!   (WeidlichWilkie, absorption along the refracted view path both ways).
//!
//! Specular lobes look up their reflection direction pulled towards the normal as roughness
//! grows (the lobe's dominant direction, Lagarde & de Rousiers 2014), and a coat's own
//! reflection at the width its lobe has across the plane of incidence, which narrows as the view
//! grazes (`grazing_lookup_roughness`); normal maps bend the coat's lobe by the top layer's normal
//! and the irradiance by the base's.

use super::base::{body_albedo, conductor_alpha};
use super::geometry::{Geometry, facing, level_name};
use super::inputs::{Body, Depth, Inputs, Stack, expand};
use super::interfaced::interfaced;
use crate::math::tables::{self, TableId};
use crate::math::terms::*;
use crate::math::{Named, Real, Vector};
use crate::model::{Approximations, Coat, Lobe, Material, Method};

/// How a lobe samples the environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// The environment prefiltered by a GGX lobe of the lobe's roughness, around its direction.
    Prefiltered,
    /// The irradiance around the direction, divided by π (a white environment gives 1).
    Irradiance,
}

/// One lobe of a material under image-based lighting.
pub struct EnvironmentLobe<F: Real> {
    /// Its directional albedo towards `v` (RGB).
    pub weight: F::Vec,
    /// Where it looks up the environment (unit vector, same frame as `n` and `v`).
    pub direction: F::Vec,
    /// The GGX roughness r (α = r²) of the prefiltering; 0 for irradiance lobes.
    pub roughness: F,
    /// The GGX roughness of the lobe itself, what a brute-force integral samples by: `roughness`
    /// except for a coat's reflection, whose lookup is narrower at grazing views
    /// (`grazing_lookup_roughness`). Not part of the generated `<Material>IblLobe`.
    pub lobe_roughness: F,
    pub lookup: Lookup,
}

/// The lobes of `material` seen from `v` at surface normal `n` (unit vectors; `v` points away
/// from the surface). The reflected radiance is Σ weight · lookup(direction, roughness); it is
/// zero for a view below the horizon.
pub fn environment_lobes<F: Real>(
    material: &Material,
    inputs: &Inputs<F>,
    n: F::Vec,
    v: F::Vec,
) -> Vec<EnvironmentLobe<F>> {
    let (coats, body) = expand(material);
    let top_normal = match inputs.layer_normal(0) {
        Some(mapped) if !coats.is_empty() => facing::<F>(mapped, v, 0),
        _ => n,
    };
    let base_normal = match inputs.layer_normal(material.coats.len()) {
        Some(mapped) => facing::<F>(mapped, v, coats.len()),
        None => n,
    };
    let mut lobes = match material.method {
        Method::Interfaced(approx) => interfaced_lobes(&coats, &body, inputs, (top_normal, base_normal), v, approx),
        Method::Additive => seed_lobes(&coats, &body, inputs, (top_normal, base_normal), v, false),
        Method::WeidlichWilkie => seed_lobes(&coats, &body, inputs, (top_normal, base_normal), v, true),
    };
    // One-sided, as the BRDF: nothing is reflected towards a viewer below the horizon.
    let above = n.dot(v).gt_lit(0.0).named("above");
    for lobe in &mut lobes {
        lobe.weight = F::Vec::select(above, lobe.weight, inputs.zero());
    }
    lobes
}

/// The interfaced method's two lobes: the top coat's reflection and what comes from below it.
fn interfaced_lobes<F: Real>(
    coats: &[Coat],
    body: &Body<'_>,
    inputs: &Inputs<F>,
    (top_normal, base_normal): (F::Vec, F::Vec),
    v: F::Vec,
    approx: Approximations,
) -> Vec<EnvironmentLobe<F>> {
    let g = Geometry::albedo_only(top_normal, v, 0);
    let level = interfaced(&Stack { coats, body, inputs, approx }, &g, Depth::top(), true);
    let Some(albedo) = level.albedo else { unreachable!("the albedo was asked for") };
    let total = albedo.e_v.named("stack_albedo");
    let Some(coat) = coats.first() else {
        return vec![body_lobe(body, inputs, base_normal, v, level.alpha, total, inputs.lit(1.0))];
    };
    let Some((_, t_v)) = level.transmission else { unreachable!("a coated level reports its transmission") };
    let coat_weight = t_v.one_minus().named("coat_albedo");
    let coat_roughness = lobe_roughness(&coat.lobe, inputs);
    let under = (total - coat_weight.splat()).max(inputs.zero()).named("under_albedo");
    let coat_lobe = coat_lobe(coat_weight.splat(), coat_roughness, top_normal, v);
    // The stack's relative IOR over the body. (A conductor's α, widened by every rough coat as
    // the method widens it, comes with the level.)
    let eta_body = coats.iter().fold(inputs.lit(1.0), |eta, coat| eta * inputs.scalar(coat.ior));
    vec![coat_lobe, body_lobe(body, inputs, base_normal, v, level.alpha, under, eta_body)]
}

/// The seed's methods: one Schlick lobe per coat (DFG fit), then the base.
fn seed_lobes<F: Real>(
    coats: &[Coat],
    body: &Body<'_>,
    inputs: &Inputs<F>,
    (top_normal, base_normal): (F::Vec, F::Vec),
    v: F::Vec,
    attenuated: bool,
) -> Vec<EnvironmentLobe<F>> {
    let mut lobes = Vec::new();
    let mut g = Geometry::albedo_only(top_normal, v, 0);
    let mut through = inputs.lit(1.0).splat();
    for coat in coats {
        let eta = inputs.scalar(coat.ior);
        let f0 = f0_dielectric(eta).splat();
        let r = lobe_roughness(&coat.lobe, inputs);
        let albedo = seed_coat_albedo(&coat.lobe, f0, r, g.n_dot_v).named(&level_name("coat_albedo", g.level));
        lobes.push(coat_lobe(through * albedo, r, g.n, g.v));
        if attenuated {
            let below = g.refracted(eta);
            let absorption = absorption_ww(
                inputs.color(coat.absorption),
                inputs.scalar(coat.thickness),
                below.n_dot_v,
                below.n_dot_v,
            );
            through = through * albedo.one_minus() * absorption;
            g = below;
        }
    }
    // The body's directional albedo towards the view (an Oren–Nayar body's own, not its mean: it
    // is most of the seed's clay under an environment, whose split sum missed the brute force by
    // 10% RMS with the mean).
    let base = body_albedo(body, inputs, &g, None, None, None).e_v.named("base_albedo");
    // The seed's methods evaluate the base at the outer directions (Additive) or refract both
    // (WeidlichWilkie) without η² compression: no widening is applied to their lobes.
    let alpha = match body {
        Body::Conductor(roughness, _) => Some(conductor_alpha(inputs.scalar(*roughness), None, 0)),
        _ => None,
    };
    lobes.push(body_lobe(body, inputs, base_normal, v, alpha, through * base, inputs.lit(1.0)));
    lobes
}

/// The directional albedo of a seed coat lobe (Schlick's Fresnel from F0) towards a view at cosine
/// `mu`: F0·A(μ; r) + B(μ; r) from the split-sum DFG tables `glazec tables` generates for the
/// seed's own lobe (Karis 2013's decomposition; GGX with Burley's Smith remap, or GTR1 with the
/// fixed Smith α of 0.25), or Schlick's F(μ) itself for a smooth coat's mirror (as
/// `mirror_reflectance` has it).
fn seed_coat_albedo<F: Real>(lobe: &Lobe, f0: F::Vec, r: F, mu: F) -> F::Vec {
    let (scale, bias) = match lobe {
        Lobe::Smooth => return f_schlick(f0, mu),
        Lobe::Ggx { .. } => (TableId::SeedGgxDfgScale, TableId::SeedGgxDfgBias),
        Lobe::Gtr1 { .. } => (TableId::ClearcoatDfgScale, TableId::ClearcoatDfgBias),
    };
    let a = tables::lookup(scale, &[mu, r]);
    let b = tables::lookup(bias, &[mu, r]);
    f0 * a + b.splat()
}

/// The lobe of the body: irradiance for a diffusing one, a GGX lobe of α `alpha` for a conductor
/// (as the method widens it under rough coats). Seen from outside a stack of relative IOR η over
/// the body, the conductor's lobe is wider by η: refraction out of the denser medium multiplies small angles from the normal by η
/// (Snell's law near normal incidence; the refraction operator of Belcour 2018, §5.2, scales a
/// lobe's angular spread the same way), so α_outside = min(η α, 1).
fn body_lobe<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    n: F::Vec,
    v: F::Vec,
    alpha: Option<F>,
    weight: F::Vec,
    eta: F,
) -> EnvironmentLobe<F> {
    match (body, alpha) {
        (Body::Conductor(..), Some(alpha)) => {
            let outside = (alpha * eta).min(inputs.lit(1.0));
            specular_lobe(weight, outside.sqrt().named("base_roughness"), n, v)
        }
        _ => {
            let zero = inputs.lit(0.0);
            EnvironmentLobe { weight, direction: n, roughness: zero, lobe_roughness: zero, lookup: Lookup::Irradiance }
        }
    }
}

/// A prefiltered lobe around the dominant direction of a GGX lobe of roughness `r` (a body
/// seen through the coats: looked up at `r`).
fn specular_lobe<F: Real>(weight: F::Vec, r: F, n: F::Vec, v: F::Vec) -> EnvironmentLobe<F> {
    let direction = specular_dominant_direction(n, v, r * r).named("reflected");
    EnvironmentLobe { weight, direction, roughness: r, lobe_roughness: r, lookup: Lookup::Prefiltered }
}

/// A coat's own reflection: [`specular_lobe`] looked up at the width its lobe has across the
/// plane of incidence (`grazing_lookup_roughness`). Measured against brute force under the sky
/// (`examples/ibl_worst.rs`), the largest error of `red_plastic` fell from 28% to 4% of the mean
/// luminance; the conductor's lobe seen through a coat, looked up the same way, got worse
/// (`coated_gold` 4.6% → 17%), so the body keeps its own width.
fn coat_lobe<F: Real>(weight: F::Vec, r: F, n: F::Vec, v: F::Vec) -> EnvironmentLobe<F> {
    let lobe = specular_lobe(weight, r, n, v);
    let roughness = grazing_lookup_roughness(r, n.dot(v)).named("lookup_roughness");
    EnvironmentLobe { roughness, ..lobe }
}

/// A coat lobe's roughness r (0 for a smooth coat).
fn lobe_roughness<F: Real>(lobe: &Lobe, inputs: &Inputs<F>) -> F {
    match lobe {
        Lobe::Smooth => inputs.lit(0.0),
        Lobe::Ggx { roughness } | Lobe::Gtr1 { roughness } => inputs.scalar(*roughness),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn lobes(source: &str, v: Vec3) -> Vec<EnvironmentLobe<f32>> {
        let compiled = match crate::compile(source) {
            Ok(c) => c,
            Err(e) => panic!("{e:?}"),
        };
        let m = &compiled.material;
        let values: Vec<_> = m.params.iter().map(|p| p.default).collect();
        environment_lobes(m, &crate::eval::inputs(&values), Vec3::Z, v)
    }

    /// The weights add up to the method's directional albedo; for a clear smooth coat over
    /// white Lambert that is exactly 1 (docs/derivations.md, "Smooth coat over Lambert").
    #[test]
    fn weights_of_a_white_stack_add_to_one() {
        let source = r#"Material(name: "white", layers: [Coat(lobe: Smooth, ior: 1.5), Lambert(albedo: 1.0)])"#;
        for cos in [1.0_f32, 0.7, 0.3, 0.05] {
            let v = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            let total: Vec3 = lobes(source, v).iter().map(|l| l.weight).sum();
            assert!((total - Vec3::ONE).abs().max_element() < 2e-3, "{cos}: {total}");
        }
    }

    #[test]
    fn a_smooth_coat_reflects_by_fresnel_along_the_mirror_direction() {
        let source = r#"Material(name: "coated", layers: [Coat(lobe: Smooth, ior: 1.5), Lambert(albedo: 0.5)])"#;
        let v = Vec3::new(0.6, 0.0, 0.8);
        let found = lobes(source, v);
        assert_eq!(found[0].lookup, Lookup::Prefiltered);
        let fresnel = fr_dielectric(0.8_f32, 1.5);
        assert!((found[0].weight.x - fresnel).abs() < 1e-6);
        assert!((found[0].direction - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
        assert_eq!(found[1].lookup, Lookup::Irradiance);
        assert!(lobes(source, Vec3::new(0.6, 0.0, -0.8)).iter().all(|l| l.weight == Vec3::ZERO));
    }
}
