//! Texture-read parameters in generated code (`Texture(name, channel, uv_scale)` in a material).
//!
//! A material that reads textures gets, besides its uniform struct:
//!
//! * bind group [`GROUP`](bindings::GROUP): `glazec_sampler: sampler` at binding 0 and one
//!   `texture_2d<f32>` per texture at bindings 1, 2, … in order of first use
//!   ([`Material::textures`]), named after the texture;
//! * a plain struct `<Material>Textures` with one member per texture-read parameter (`f32`, or
//!   `vec3<f32>` for an `Rgb` read), named `<texture>_<channel>`;
//! * `<material>_textures(uv: vec2<f32>) -> <Material>Textures`, which samples every read at
//!   `uv · uv_scale` (mip level 0, so it is valid in every stage) and maps the texel onto the
//!   parameter's range: lo + (hi − lo)·t.
//!
//! HLSL declares textures at `register(t<binding>, space1)`; naga 30 writes samplers for D3D12's
//! sampler heap (`nagaSamplerHeap` plus the index buffer `nagaGroup1SamplerIndexArray`), the
//! layout wgpu's DX12 backend binds. GLSL: see [`bindings::GLSL_OFFSET`].
//!
//! `<material>_brdf` and `<material>_eval` take the struct as their last argument, so the BRDF
//! itself touches no resources: a renderer may fill the struct from its own samplers (with
//! derivatives, anisotropic filtering, …) and call the BRDF anywhere.

use naga::{
    AddressSpace, Expression, FunctionResult, GlobalVariable, Handle, ImageClass, ImageDimension, ResourceBinding,
    SampleLevel, ScalarKind, Span, Statement, StructMember, SwizzleComponent, Type, TypeInner, VectorSize,
};

use super::builder::{Expr, ExprVec, ModuleBuilder, argument, global_in};
use super::layout::member_offsets;
use crate::math::Named;
use crate::math::terms::{normal_from_texel, rnm_blend, tangent_to_world};
use crate::model::{Channel, Material, TextureRead};

/// The resource bindings of texture reads.
pub mod bindings {
    /// Textures and their sampler live in their own bind group by default.
    pub const GROUP: u32 = crate::lower::layout::bindings::TEXTURES_GROUP;
    /// `var glazec_sampler: sampler` (wrap addressing in glazec's renderers).
    pub const SAMPLER: u32 = 0;
    /// The first texture's binding; the others follow in order of first use.
    pub const FIRST_TEXTURE: u32 = 1;
    /// The sampler's name in generated code.
    pub const SAMPLER_NAME: &str = "glazec_sampler";
    /// GLSL has one binding space per descriptor set and naga's GLSL backend writes none, so
    /// group g moves up by g times this much there: a texture at binding b of group 1 is
    /// `layout(binding = 16 + b)`, the environment's (group 2) `32 + b` (combined with the
    /// sampler into a `sampler2D`, which is how naga writes GLSL).
    pub const GLSL_OFFSET: u32 = 16;
}

/// What `lower` needs of a material's texture reads.
pub struct TextureReads {
    /// `<Material>Textures`.
    pub ty: Handle<Type>,
    /// `<material>_textures(uv)`.
    pub sample: Handle<naga::Function>,
}

/// Builds the struct, the resources and the sampling function; `None` without texture reads.
pub fn build(b: &ModuleBuilder, material: &Material) -> Option<TextureReads> {
    let reads: Vec<_> = material.texture_params().collect();
    if reads.is_empty() && material.normals.is_empty() {
        return None;
    }
    let ty = struct_type(b, material);
    let (sampler_ty, image_ty) = sampler_and_image_types(b);
    let sampler = global(b, bindings::SAMPLER_NAME, bindings::SAMPLER, sampler_ty);
    let images: Vec<(String, Handle<GlobalVariable>)> = material
        .textures()
        .iter()
        .enumerate()
        .map(|(i, name)| (name.to_string(), global(b, name, bindings::FIRST_TEXTURE + i as u32, image_ty)))
        .collect();

    let mut arguments = vec![argument("uv", b.types.vec2, None)];
    if !material.normals.is_empty() {
        for frame in ["n", "t", "b"] {
            arguments.push(argument(frame, b.types.vec3, None));
        }
    }
    let name = format!("{}_textures", material.name);
    b.begin_function(&name, arguments, Some(FunctionResult { ty, binding: None }));
    let uv = b.argument(0);
    // One sample per texture and scale: channels of a packed texture share it.
    let mut samples: Vec<((String, u32), Handle<Expression>)> = Vec::new();
    let mut sample = |texture: &str, uv_scale: f32| -> Handle<Expression> {
        let key = (texture.to_string(), uv_scale.to_bits());
        if let Some(&(_, texel)) = samples.iter().find(|(k, _)| *k == key) {
            return texel;
        }
        let Some(&(_, image)) = images.iter().find(|(n, _)| *n == texture) else {
            unreachable!("every texture has a binding")
        };
        let image = b.append(Expression::GlobalVariable(image));
        let sampler = b.append(Expression::GlobalVariable(sampler));
        let coordinate = if uv_scale == 1.0 {
            uv
        } else {
            let scale = b.constant(uv_scale).handle();
            b.append(Expression::Binary { op: naga::BinaryOperator::Multiply, left: uv, right: scale })
        };
        let zero = b.constant(0.0).handle();
        let texel = b.append(Expression::ImageSample {
            image,
            sampler,
            gather: None,
            coordinate,
            array_index: None,
            offset: None,
            level: SampleLevel::Exact(zero),
            depth_ref: None,
            clamp_to_edge: false,
        });
        b.name(texel, &format!("{texture}_texel"));
        samples.push((key, texel));
        texel
    };
    let mut components = Vec::new();
    for (_, param, read) in &reads {
        let texel = sample(&read.texture, read.uv_scale);
        components.push(channel_value(b, texel, read, &param.name));
    }
    if !material.normals.is_empty() {
        let frame: Vec<ExprVec<'_>> = (1..4).map(|i| b.vector(b.argument(i))).collect();
        for (layer, map) in &material.normals {
            let layer_name = material.layer_name(*layer);
            let tangent = |texel: Handle<Expression>| normal_from_texel::<Expr<'_>>(rgb(b, texel));
            let mut m = tangent(sample(&map.texture, map.uv_scale)).named(&format!("{layer_name}_tangent_normal"));
            if let Some((detail, scale)) = &map.detail {
                let d = tangent(sample(detail, *scale)).named(&format!("{layer_name}_detail_normal"));
                m = rnm_blend::<Expr<'_>>(m, d).named(&format!("{layer_name}_blended_normal"));
            }
            let world =
                tangent_to_world::<Expr<'_>>(m, frame[1], frame[2], frame[0]).named(&format!("{layer_name}_normal"));
            components.push(world.handle());
        }
    }
    let result = b.append(Expression::Compose { ty, components });
    b.statement(Statement::Return { value: Some(result) });
    let doc = [
        "The material's texture-read parameters at `uv`: each texture sampled at uv · uv_scale (mip",
        "level 0) and its texel t mapped onto the parameter's range, lo + (hi − lo)·t; and each",
        "normal-mapped layer's shading normal in the frame (t, b, n): the map's tangent-space normal,",
        "blended with its detail map by reoriented normal mapping (Barré-Brisebois & Hill 2012).",
    ];
    let sample = b.add_function(b.end_function(), &doc);
    Some(TextureReads { ty, sample })
}

/// The module's `sampler` and `texture_2d<f32>` types.
pub(super) fn sampler_and_image_types(b: &ModuleBuilder) -> (Handle<Type>, Handle<Type>) {
    let sampler = b.with_module(|m| {
        m.types.insert(Type { name: None, inner: TypeInner::Sampler { comparison: false } }, Span::UNDEFINED)
    });
    let image = b.with_module(|m| {
        let inner = TypeInner::Image {
            dim: ImageDimension::D2,
            arrayed: false,
            class: ImageClass::Sampled { kind: ScalarKind::Float, multi: false },
        };
        m.types.insert(Type { name: None, inner }, Span::UNDEFINED)
    });
    (sampler, image)
}

/// The RGB of a sampled texel.
fn rgb(b: &ModuleBuilder, texel: Handle<Expression>) -> ExprVec<'_> {
    b.vector(b.append(Expression::Swizzle {
        size: VectorSize::Tri,
        vector: texel,
        pattern: [SwizzleComponent::X, SwizzleComponent::Y, SwizzleComponent::Z, SwizzleComponent::X],
    }))
}

/// A read's channel of a sampled texel, mapped onto its range and named after the parameter.
fn channel_value(b: &ModuleBuilder, texel: Handle<Expression>, read: &TextureRead, name: &str) -> Handle<Expression> {
    let value = match read.channel.index() {
        Some(index) => {
            let t = b.scalar(b.append(Expression::AccessIndex { base: texel, index }));
            remap(t, read.range).handle()
        }
        None => remap_vec(b, rgb(b, texel), read.range).handle(),
    };
    b.name(value, name);
    value
}

/// lo + (hi − lo)·t, folded to t for the range [0, 1].
fn remap(t: Expr<'_>, [lo, hi]: [f32; 2]) -> Expr<'_> {
    if lo == 0.0 && hi == 1.0 { t } else { t * (hi - lo) + lo }
}

fn remap_vec<'a>(b: &'a ModuleBuilder, t: ExprVec<'a>, [lo, hi]: [f32; 2]) -> ExprVec<'a> {
    use crate::math::Real;
    if lo == 0.0 && hi == 1.0 { t } else { t * (hi - lo) + b.constant(lo).splat() }
}

/// `<Material>Textures`: one member per texture read, laid out like the uniform struct.
fn struct_type(b: &ModuleBuilder, material: &Material) -> Handle<Type> {
    let reads = material.texture_params().map(|(_, param, read)| (param.name.clone(), read.channel == Channel::Rgb));
    let normals = material.normals.iter().map(|(layer, _)| (format!("{}_normal", material.layer_name(*layer)), true));
    let fields: Vec<(String, bool)> = reads.chain(normals).collect();
    let (offsets, span) = member_offsets(fields.iter().map(|&(_, is_vec3)| is_vec3));
    let members = fields
        .into_iter()
        .zip(offsets)
        .map(|((name, is_vec3), offset)| {
            let ty = if is_vec3 { b.types.vec3 } else { b.types.f32 };
            StructMember { name: Some(name), ty, binding: None, offset }
        })
        .collect();
    let name = material.textures_struct_name();
    b.with_module(|m| {
        m.types.insert(Type { name: Some(name), inner: TypeInner::Struct { members, span } }, Span::UNDEFINED)
    })
}

fn global(b: &ModuleBuilder, name: &str, binding: u32, ty: Handle<Type>) -> Handle<GlobalVariable> {
    global_in(b, name, AddressSpace::Handle, ResourceBinding { group: bindings::GROUP, binding }, ty)
}
