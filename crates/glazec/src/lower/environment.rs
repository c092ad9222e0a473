//! Image-based lighting in generated code: `<material>_ibl` and the environment it reads.
//!
//! Every module gets
//!
//! * bind group [`GROUP`](bindings::GROUP): `glazec_environment_sampler` at 0, and two
//!   equirectangular `texture_2d<f32>` images (direction d ↦ u = ½ + atan2(d.x, d.z)/2π,
//!   v = acos(d.y)/π: y up, +z at the image's centre):
//!   - `glazec_radiance` at 1: mip level k of N holds the environment prefiltered by a GGX lobe
//!     of roughness r = k/(N − 1) (α = r²) around each texel's direction (Karis 2013's
//!     prefiltered environment, with n = v = r); level 0 is the environment itself;
//!   - `glazec_irradiance` at 2: the cosine-weighted mean of the environment over the
//!     hemisphere around each texel's direction, E(d)/π (1 under a white environment);
//! * `glazec_environment(direction, roughness)` and `glazec_irradiance_at(direction)`, the two
//!   lookups (trilinear between the prefiltered levels: lod = r·(N − 1));
//! * `<material>_ibl(n, v[, params][, textures]) -> vec3<f32>`: the radiance the material
//!   reflects towards `v` from the whole environment, Σ weight · lookup over the lobes of
//!   [`crate::math::layering::environment`];
//! * the fragment entry point `preview_ibl_fs`, the preview sphere lit by it.
//!
//! `glazec_gpu::environment` prefilters images for these bindings (and documents the sampler:
//! repeat in u, clamp in v, linear filtering between texels and levels).

use naga::{
    AddressSpace, Expression, FunctionResult, GlobalVariable, Handle, ImageQuery, ResourceBinding, SampleLevel,
    ScalarKind, Statement, SwizzleComponent, Type, VectorSize,
};

use super::builder::{Expr, ExprVec, ModuleBuilder, argument, global_in};
use crate::math::layering::Inputs;
use crate::math::layering::environment::{Lookup, environment_lobes};
use crate::math::{Named, Real, Vector};
use crate::model::Material;

/// The resource bindings of the environment.
pub mod bindings {
    /// The environment has its own bind group by default, after the textures'.
    pub const GROUP: u32 = crate::lower::layout::bindings::ENVIRONMENT_GROUP;
    /// `var glazec_environment_sampler: sampler`.
    pub const SAMPLER: u32 = 0;
    /// `var glazec_radiance: texture_2d<f32>`: the prefiltered levels.
    pub const RADIANCE: u32 = 1;
    /// `var glazec_irradiance: texture_2d<f32>`: irradiance / π.
    pub const IRRADIANCE: u32 = 2;
    pub const SAMPLER_NAME: &str = "glazec_environment_sampler";
    pub const RADIANCE_NAME: &str = "glazec_radiance";
    pub const IRRADIANCE_NAME: &str = "glazec_irradiance";
}

/// The two lookups, built once per module.
#[derive(Clone, Copy)]
pub struct Lookups {
    /// `glazec_environment(direction, roughness) -> vec3<f32>`.
    pub prefiltered: Handle<naga::Function>,
    /// `glazec_irradiance_at(direction) -> vec3<f32>`.
    pub irradiance: Handle<naga::Function>,
}

/// Declares the resources and builds the lookup functions.
pub fn build_lookups(b: &ModuleBuilder) -> Lookups {
    let (sampler_ty, image_ty) = super::textures::sampler_and_image_types(b);
    let sampler = global(b, bindings::SAMPLER_NAME, bindings::SAMPLER, sampler_ty);
    let radiance = global(b, bindings::RADIANCE_NAME, bindings::RADIANCE, image_ty);
    let irradiance = global(b, bindings::IRRADIANCE_NAME, bindings::IRRADIANCE, image_ty);
    let uv_function = equirect_uv_function(b);

    let direction_arg = || argument("direction", b.types.vec3, None);
    let result = || Some(FunctionResult { ty: b.types.vec3, binding: None });

    b.begin_function("glazec_environment", vec![direction_arg(), argument("roughness", b.types.f32, None)], result());
    let uv = b.call(uv_function, vec![b.argument(0)]);
    b.name(uv, "uv");
    let image = b.append(Expression::GlobalVariable(radiance));
    let levels = b.append(Expression::ImageQuery { image, query: ImageQuery::NumLevels });
    let levels = b.scalar(b.append(Expression::As { expr: levels, kind: ScalarKind::Float, convert: Some(4) }));
    let lod = (b.scalar(b.argument(1)) * (levels - 1.0)).named("lod");
    let texel = sample(b, radiance, sampler, uv, lod.handle());
    b.statement(Statement::Return { value: Some(texel) });
    let doc = [
        "The environment prefiltered by a GGX lobe of roughness `roughness` (α = r²) around `direction`:",
        "trilinear between the levels of `glazec_radiance`, level k of N prefiltered at r = k/(N − 1).",
    ];
    let prefiltered = b.add_function(b.end_function(), &doc);

    b.begin_function("glazec_irradiance_at", vec![direction_arg()], result());
    let uv = b.call(uv_function, vec![b.argument(0)]);
    b.name(uv, "uv");
    let texel = sample(b, irradiance, sampler, uv, b.constant(0.0).handle());
    b.statement(Statement::Return { value: Some(texel) });
    let doc =
        ["The irradiance around `direction` divided by π (1 under a white environment), from `glazec_irradiance`."];
    let irradiance = b.add_function(b.end_function(), &doc);
    Lookups { prefiltered, irradiance }
}

/// `glazec_equirect_uv(d)`: the equirectangular coordinates of unit direction `d`.
fn equirect_uv_function(b: &ModuleBuilder) -> Handle<naga::Function> {
    use std::f32::consts::PI;
    let result = Some(FunctionResult { ty: b.types.vec2, binding: None });
    b.begin_function("glazec_equirect_uv", vec![argument("d", b.types.vec3, None)], result);
    let d = b.vector(b.argument(0));
    let longitude = b.scalar(b.math(naga::MathFunction::Atan2, &[d.x().handle(), d.z().handle()]));
    // Guard: acos of |y| ≤ 1 only; a normalised vector can exceed it by rounding.
    let y = d.y().clamp(-1.0, 1.0);
    let polar = b.scalar(b.math(naga::MathFunction::Acos, &[y.handle()]));
    let u = (longitude * (0.5 / PI) + 0.5).handle();
    let v = (polar * (1.0 / PI)).handle();
    let uv = b.append(Expression::Compose { ty: b.types.vec2, components: vec![u, v] });
    b.statement(Statement::Return { value: Some(uv) });
    let doc =
        ["Equirectangular coordinates of unit direction `d` (y up): u = ½ + atan2(d.x, d.z)/2π, v = acos(d.y)/π."];
    b.add_function(b.end_function(), &doc)
}

/// The RGB of `image` sampled at `uv`, level `lod`.
fn sample(
    b: &ModuleBuilder,
    image: Handle<GlobalVariable>,
    sampler: Handle<GlobalVariable>,
    uv: Handle<Expression>,
    lod: Handle<Expression>,
) -> Handle<Expression> {
    let image = b.append(Expression::GlobalVariable(image));
    let sampler = b.append(Expression::GlobalVariable(sampler));
    let texel = b.append(Expression::ImageSample {
        image,
        sampler,
        gather: None,
        coordinate: uv,
        array_index: None,
        offset: None,
        level: SampleLevel::Exact(lod),
        depth_ref: None,
        clamp_to_edge: false,
    });
    b.append(Expression::Swizzle {
        size: VectorSize::Tri,
        vector: texel,
        pattern: [SwizzleComponent::X, SwizzleComponent::Y, SwizzleComponent::Z, SwizzleComponent::X],
    })
}

fn global(b: &ModuleBuilder, name: &str, binding: u32, ty: Handle<Type>) -> Handle<GlobalVariable> {
    global_in(b, name, AddressSpace::Handle, ResourceBinding { group: bindings::GROUP, binding }, ty)
}

/// The radiance `material` reflects towards `v` from the environment: Σ weight · lookup.
pub fn reflected<'a>(
    b: &'a ModuleBuilder,
    lookups: Lookups,
    material: &Material,
    inputs: &Inputs<Expr<'a>>,
    n: ExprVec<'a>,
    v: ExprVec<'a>,
) -> ExprVec<'a> {
    let mut total: Option<ExprVec<'a>> = None;
    for (i, lobe) in environment_lobes(material, inputs, n, v).into_iter().enumerate() {
        let light = match lobe.lookup {
            Lookup::Prefiltered => b.call(lookups.prefiltered, vec![lobe.direction.handle(), lobe.roughness.handle()]),
            Lookup::Irradiance => b.call(lookups.irradiance, vec![lobe.direction.handle()]),
        };
        b.name(light, &format!("light{}", letter(i)));
        let term = lobe.weight * b.vector(light);
        total = Some(match total {
            Some(sum) => sum + term,
            None => term,
        });
    }
    total.unwrap_or_else(|| b.constant(0.0).splat())
}

/// Lobe names without trailing digits (which naga would suffix with `_`): `light_a`, `light_b`, ….
fn letter(i: usize) -> String {
    format!("_{}", (b'a' + (i % 26) as u8) as char)
}
