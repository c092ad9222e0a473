//! Image-based lighting in generated code: `<material>_ibl` and the environment it reads.
//!
//! Every library gets `<material>_ibl_lobes`; the library (where the host placed the
//! environment) or else the harness gets the rest:
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
//! * `<material>_ibl_lobes(n, v[, params][, textures]) -> <Material>IblLobes`: the lobes of
//!   [`crate::math::layering::environment`] as data (each lobe's direction, roughness and
//!   weight), for a host that samples its own prefiltered environment (Bevy's
//!   `EnvironmentMapLight`, an engine's probes); `<material>_ibl_specular_lobes` is their count;
//! * `<material>_ibl(n, v[, params][, textures]) -> vec3<f32>`: the radiance the material
//!   reflects towards `v` from the whole environment, Σ weight · lookup over those lobes;
//! * the fragment entry point `preview_ibl_fs`, the preview sphere lit by it.
//!
//! `glazec_gpu::environment` prefilters images for these bindings (and documents the sampler:
//! repeat in u, clamp in v, linear filtering between texels and levels).

use naga::{
    AddressSpace, ArraySize, Expression, FunctionResult, GlobalVariable, Handle, ImageQuery, Literal, ResourceBinding,
    SampleLevel, ScalarKind, Span, Statement, SwizzleComponent, Type, TypeInner, VectorSize,
};

use super::builder::{Expr, ExprVec, ModuleBuilder, argument, global_in, struct_type};
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

/// The structs `<material>_ibl_lobes` returns.
#[derive(Clone, Copy)]
pub struct LobeTypes {
    /// `<Material>IblLobe { direction: vec3<f32>, roughness: f32, weight: vec3<f32> }`.
    pub lobe: Handle<Type>,
    /// `<Material>IblLobes { specular: array<<Material>IblLobe, K>, irradiance: <Material>IblLobe }`.
    pub lobes: Handle<Type>,
    /// K, the length of `specular` (at least 1; unused entries weigh 0).
    pub specular: u32,
    /// How many of them the material has (0 or K).
    pub used_specular: u32,
    /// Whether the material has an irradiance lobe (else `irradiance` weighs 0).
    pub irradiance: bool,
}

/// The byte size of `<Material>IblLobe` (WGSL layout: direction at 0, roughness at 12, weight
/// at 16).
const LOBE_SPAN: u32 = 32;

/// The lobes of `material` seen from `v` at normal `n` as one `<Material>IblLobes` value: its
/// prefiltered lobes in `specular` (in the order of [`environment_lobes`], padded with lobes of
/// weight 0 around `n`), its irradiance lobe in `irradiance` (weight 0 when the material has
/// none; its roughness is 1, the irradiance being the cosine lobe's average).
pub fn composed_lobes<'a>(
    b: &'a ModuleBuilder,
    material: &Material,
    inputs: &Inputs<Expr<'a>>,
    n: ExprVec<'a>,
    v: ExprVec<'a>,
) -> (Handle<Expression>, LobeTypes) {
    let lobes = environment_lobes(material, inputs, n, v);
    let (specular, irradiance): (Vec<_>, Vec<_>) = lobes.into_iter().partition(|l| l.lookup == Lookup::Prefiltered);
    debug_assert!(irradiance.len() <= 1, "the body is the only diffuse lobe");
    let count = specular.len().max(1) as u32;
    let (lobe, array, lobes) = lobe_types(b, material, count);
    let types = LobeTypes {
        lobe,
        lobes,
        specular: count,
        used_specular: specular.len() as u32,
        irradiance: !irradiance.is_empty(),
    };
    let zero = b.constant(0.0).splat();
    let compose = |direction: ExprVec<'a>, roughness: Expr<'a>, weight: ExprVec<'a>| {
        let components = vec![direction.handle(), roughness.handle(), weight.handle()];
        b.append(Expression::Compose { ty: types.lobe, components })
    };
    let mut entries: Vec<_> = specular.into_iter().map(|l| compose(l.direction, l.roughness, l.weight)).collect();
    while entries.len() < count as usize {
        entries.push(compose(n, b.constant(0.0), zero));
    }
    let specular = b.append(Expression::Compose { ty: array, components: entries });
    let irradiance = match irradiance.into_iter().next() {
        Some(l) => compose(l.direction, b.constant(1.0), l.weight),
        None => compose(n, b.constant(1.0), zero),
    };
    (b.append(Expression::Compose { ty: types.lobes, components: vec![specular, irradiance] }), types)
}

/// Declares `<Material>IblLobe`, the array of `count` of them and `<Material>IblLobes`, and the
/// constant `<material>_ibl_specular_lobes` = `count`.
fn lobe_types(b: &ModuleBuilder, material: &Material, count: u32) -> (Handle<Type>, Handle<Type>, Handle<Type>) {
    let prefix = crate::model::camel_case(&material.name);
    let lobe = struct_type(
        b,
        &format!("{prefix}IblLobe"),
        &[
            ("direction", b.types.vec3, 0, None),
            ("roughness", b.types.f32, 12, None),
            ("weight", b.types.vec3, 16, None),
        ],
        LOBE_SPAN,
    );
    let size = std::num::NonZeroU32::new(count).unwrap_or(std::num::NonZeroU32::MIN);
    let array = b.with_module(|m| {
        m.types.insert(
            Type {
                name: None,
                inner: TypeInner::Array { base: lobe, size: ArraySize::Constant(size), stride: LOBE_SPAN },
            },
            Span::UNDEFINED,
        )
    });
    let lobes = struct_type(
        b,
        &format!("{prefix}IblLobes"),
        &[("specular", array, 0, None), ("irradiance", lobe, count * LOBE_SPAN, None)],
        (count + 1) * LOBE_SPAN,
    );
    // `<material>_ibl_specular_lobes`: K, for a host's loop over `specular`.
    b.with_module(|m| {
        let init = m.global_expressions.append(Expression::Literal(Literal::U32(count)), Span::UNDEFINED);
        let name = Some("glazec_ibl_specular_lobes".to_string());
        m.constants.append(naga::Constant { name, ty: b.types.u32, init }, Span::UNDEFINED);
    });
    (lobe, array, lobes)
}

/// The radiance reflected towards `v` from the environment: Σ weight · lookup over the lobes
/// `lobes` (a `<Material>IblLobes` value), looked up in glazec's own environment images.
pub fn reflected<'a>(
    b: &'a ModuleBuilder,
    lookups: Lookups,
    lobes: Handle<Expression>,
    types: LobeTypes,
) -> ExprVec<'a> {
    let field = |base: Handle<Expression>, index: u32| b.append(Expression::AccessIndex { base, index });
    let specular = field(lobes, 0);
    let mut total: Option<ExprVec<'a>> = None;
    // The lookups of lobes the material has: padding and a missing irradiance lobe weigh 0.
    let used = (0..types.used_specular).chain(types.irradiance.then_some(types.specular));
    for k in used {
        let (lobe, light) = if k < types.specular {
            let lobe = field(specular, k);
            (lobe, b.call(lookups.prefiltered, vec![field(lobe, 0), field(lobe, 1)]))
        } else {
            let lobe = field(lobes, 1);
            (lobe, b.call(lookups.irradiance, vec![field(lobe, 0)]))
        };
        b.name(light, &format!("light{}", letter(k as usize)));
        let term = b.vector(field(lobe, 2)) * b.vector(light);
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
