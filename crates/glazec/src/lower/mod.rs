//! Stage 3, `lower`: the material model → a `naga::Module`, built programmatically.
//!
//! **Input:** a checked [`Material`]. **Output:** a `naga::Module` holding
//!
//! * one function per BRDF term the material uses (`d_ggx`, `fr_dielectric`, …; built by
//!   running [`crate::math`] on the [`builder`]), each carrying its citation as a doc comment;
//! * `<material>_brdf(n, v, l[, params]) -> vec3<f32>`: f(l, v) **without** the cosine;
//! * `<material>_eval(n, v, l[, params]) -> vec3<f32>`: f · max(n·l, 0), for users' light loops;
//! * a uniform struct `<Material>Params` with one member per runtime parameter (declaration
//!   order, `f32` or `vec3<f32>`), when the material has any;
//! * the entry points `eval_pairs` (compute: f(wi, wo) for a buffer of direction pairs, used by
//!   the tests, `eval` and benchmarks) and `preview_vs`/`preview_fs` (a full-screen triangle
//!   that shades a sphere under one directional light, given by the `light` uniform; the
//!   preview renderer adds several such passes to light the sphere by an environment).
//!
//! The binding layout is fixed and the same in every backend (group 0): see [`bindings`]. The
//! kernel reads its element count from a uniform rather than from `arrayLength`, because
//! glslang's HLSL front end lowers `GetDimensions` on byte-address buffers to a dword count
//! (research/probe.md §4), which would cover only a quarter of the buffer.
//!
//! **Invariants:** the module validates with all of naga's validation flags (checked by
//! `validate`); output is a pure function of the material (no hash-map iteration order, no
//! addresses), so emitted files are byte-identical across runs.

pub mod builder;
pub mod environment;
pub mod textures;

use naga::{
    AddressSpace, Binding, BuiltIn, EntryPoint, Expression, Function, FunctionArgument, FunctionResult, GlobalVariable,
    Handle, MemoryDecorations, Module, ResourceBinding, ShaderStage, Span, Statement, StorageAccess, StructMember,
    SwizzleComponent, Type, TypeInner, VectorSize,
};

use crate::math::layering::{self, Inputs};
use crate::math::{Named, Real, Slot, Vector};
use crate::model::{Material, ParamSource, ParamValue};
use builder::{Expr, ModuleBuilder};

/// The resource bindings of generated modules (all in bind group 0).
///
/// They are numbered contiguously from 0 in the order a kernel's layout lists them: wgpu's
/// Vulkan backend renumbers a bind group's entries 0, 1, 2, … in that order, and passthrough
/// SPIR-V (the HLSL path) keeps the numbers glslang gave it, so the two must coincide. The
/// optional resources therefore take the next free number, in this order: `params` (3, when
/// the material has runtime parameters), `glazec_tables` (when a runtime parameter needs whole
/// tables), `light` (the preview's). [`layout`](bindings::layout) reads them back from a module.
pub mod bindings {
    pub const GROUP: u32 = 0;
    /// `var<storage, read> pairs: array<DirectionPair>`: `wi` then `wo`, each a `vec4<f32>` (w unused).
    pub const PAIRS: u32 = 0;
    /// `var<storage, read_write> values: array<vec4<f32>>`: f(wi, wo) in `xyz`, `w` = 0.
    pub const VALUES: u32 = 1;
    /// `var<uniform> dispatch: EvalDispatch`: `pair_count: u32` (padded to 16 bytes).
    pub const DISPATCH: u32 = 2;
    /// `var<uniform> params: <Material>Params` (only when the material has runtime parameters).
    pub const PARAMS: u32 = 3;

    /// Where a module's optional resources are bound.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    pub struct Layout {
        /// `var<uniform> params: <Material>Params`.
        pub params: Option<u32>,
        /// `var<uniform> glazec_tables: array<vec4<u32>, N>` (16-bit codes, two to a word): the contents of
        /// `glazec::math::tables::buffer()` (`glazec_tables.bin` beside the generated folders),
        /// bound when a table lookup has an argument known only at run time (a cosine, or a
        /// runtime parameter).
        pub tables: Option<u32>,
        /// `var<uniform> light: PreviewLight` (the preview's directional light).
        pub light: Option<u32>,
    }

    /// The bindings of a module built by `lower`.
    pub fn layout(module: &naga::Module) -> Layout {
        let binding = |name: &str| {
            module
                .global_variables
                .iter()
                .find(|(_, v)| v.name.as_deref() == Some(name))
                .and_then(|(_, v)| v.binding.as_ref().map(|b| b.binding))
        };
        Layout {
            params: binding("params"),
            tables: binding(super::builder::TABLES_BUFFER_NAME),
            light: binding("light"),
        }
    }

    /// Numbers the optional resources created without a binding number (`u32::MAX`): the table
    /// buffer, then the light, after `params`.
    pub(super) fn assign(module: &mut naga::Module) {
        let mut next = if layout(module).params.is_some() { PARAMS + 1 } else { PARAMS };
        for name in [super::builder::TABLES_BUFFER_NAME, "light"] {
            for (_, var) in module.global_variables.iter_mut() {
                if var.name.as_deref() == Some(name) {
                    if let Some(b) = var.binding.as_mut() {
                        b.binding = next;
                        next += 1;
                    }
                }
            }
        }
    }
}

/// Entry point names.
pub mod entry_points {
    pub const EVAL_PAIRS: &str = "eval_pairs";
    pub const PREVIEW_VS: &str = "preview_vs";
    pub const PREVIEW_FS: &str = "preview_fs";
    /// The preview sphere lit by the environment (`<material>_ibl`).
    pub const PREVIEW_IBL_FS: &str = "preview_ibl_fs";
}

/// Workgroup size of `eval_pairs`.
pub const EVAL_WORKGROUP_SIZE: u32 = 64;

/// Byte size of one direction pair in the `pairs` buffer.
pub const PAIR_STRIDE: u32 = 32;

/// The layout of one runtime parameter inside the uniform struct.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParamLayout {
    pub name: String,
    /// `"f32"` or `"vec3<f32>"`.
    pub wgsl_type: &'static str,
    pub offset: u32,
    pub size: u32,
}

/// The uniform block of a material's runtime parameters for `values` (one per parameter, in
/// declaration order; texture reads are skipped): little-endian f32 at [`params_layout`]'s
/// offsets, padding zeroed.
/// Extra or missing values are the caller's to check.
pub fn params_bytes(material: &Material, values: &[ParamValue]) -> Vec<u8> {
    let (layout, size) = params_layout(material);
    let mut bytes = vec![0u8; size as usize];
    let uniform_values = material.uniform_params().filter_map(|(i, _)| values.get(i));
    for (slot, value) in layout.iter().zip(uniform_values) {
        let components: &[f32] = match value {
            ParamValue::Scalar(x) => std::slice::from_ref(x),
            ParamValue::Rgb(c) => c,
        };
        for (i, x) in components.iter().enumerate() {
            let at = slot.offset as usize + 4 * i;
            bytes[at..at + 4].copy_from_slice(&x.to_le_bytes());
        }
    }
    bytes
}

/// The uniform struct's layout (WGSL uniform rules; naga reproduces it in every backend).
pub fn params_layout(material: &Material) -> (Vec<ParamLayout>, u32) {
    let params: Vec<_> = material.uniform_params().map(|(_, p)| p).collect();
    let (offsets, span) = member_offsets(params.iter().map(|p| matches!(p.default, ParamValue::Rgb(_))));
    let layout = params
        .iter()
        .zip(offsets)
        .map(|(p, offset)| {
            let (size, wgsl_type) = match p.default {
                ParamValue::Scalar(_) => (4, "f32"),
                ParamValue::Rgb(_) => (12, "vec3<f32>"),
            };
            ParamLayout { name: p.name.clone(), wgsl_type, offset, size }
        })
        .collect();
    (layout, span)
}

/// Offsets of a struct's `f32` (false) and `vec3<f32>` (true) members under WGSL's uniform
/// rules (vec3 aligned to 16), and its size padded to 16 bytes so that it can be bound in
/// every backend.
pub(crate) fn member_offsets(vec3: impl IntoIterator<Item = bool>) -> (Vec<u32>, u32) {
    let mut offset: u32 = 0;
    let mut offsets = Vec::new();
    for is_vec3 in vec3 {
        let (align, size) = if is_vec3 { (16, 12) } else { (4, 4) };
        offset = offset.next_multiple_of(align);
        offsets.push(offset);
        offset += size;
    }
    (offsets, offset.next_multiple_of(16))
}

/// Expressions and transcendental calls (exp, log, pow, sqrt, trigonometry) over the module's
/// functions: the static size of the shading code.
pub fn static_cost(module: &naga::Module) -> (usize, usize) {
    use naga::{Expression, MathFunction as M};
    let mut expressions = 0;
    let mut transcendental = 0;
    for (_, f) in module.functions.iter() {
        expressions += f.expressions.len();
        transcendental += f
            .expressions
            .iter()
            .filter(|(_, e)| {
                matches!(
                    e,
                    Expression::Math {
                        fun: M::Exp
                            | M::Exp2
                            | M::Log
                            | M::Log2
                            | M::Pow
                            | M::Sqrt
                            | M::InverseSqrt
                            | M::Sin
                            | M::Cos
                            | M::Tan
                            | M::Asin
                            | M::Acos
                            | M::Atan
                            | M::Atan2,
                        ..
                    }
                )
            })
            .count();
    }
    (expressions, transcendental)
}

/// Lowers a material to a naga module (see the module docs for what it contains).
pub fn lower(material: &Material) -> Module {
    let b = ModuleBuilder::new();
    let params_ty = params_type(&b, material);
    let reads = textures::build(&b, material);
    let inputs = InputTypes { params: params_ty, textures: reads.as_ref().map(|r| r.ty) };
    let brdf = brdf_function(&b, material, inputs);
    let eval = eval_function(&b, material, inputs, brdf);
    let lookups = environment::build_lookups(&b);
    let ibl = ibl_function(&b, material, inputs, lookups);
    let params_var = params_ty.map(|ty| global(&b, "params", AddressSpace::Uniform, bindings::PARAMS, ty));
    let sample = reads.as_ref().map(|r| Sampling { function: r.sample, frame: !material.normals.is_empty() });
    eval_pairs_entry(&b, brdf, params_var, sample);
    preview_entries(&b, eval, params_var, sample);
    preview_ibl_entry(&b, ibl, params_var, sample);
    let mut module = b.finish();
    bindings::assign(&mut module);
    module
}

/// `<material>_textures` and whether it takes the surface frame (n, t, b) after `uv`.
#[derive(Clone, Copy)]
struct Sampling {
    function: Handle<Function>,
    frame: bool,
}

/// The optional struct arguments of `<material>_brdf` and `<material>_eval`.
#[derive(Clone, Copy)]
struct InputTypes {
    params: Option<Handle<Type>>,
    textures: Option<Handle<Type>>,
}

fn params_type(b: &ModuleBuilder, material: &Material) -> Option<Handle<Type>> {
    material.uniform_params().next()?;
    let (layout, span) = params_layout(material);
    let members = layout
        .iter()
        .map(|p| StructMember {
            name: Some(p.name.clone()),
            ty: if p.size == 4 { b.types.f32 } else { b.types.vec3 },
            binding: None,
            offset: p.offset,
        })
        .collect();
    let name = material.params_struct_name();
    Some(b.with_module(|m| {
        m.types.insert(Type { name: Some(name), inner: TypeInner::Struct { members, span } }, Span::UNDEFINED)
    }))
}

fn global(
    b: &ModuleBuilder,
    name: &str,
    space: AddressSpace,
    binding: u32,
    ty: Handle<Type>,
) -> Handle<GlobalVariable> {
    global_in(b, name, space, ResourceBinding { group: bindings::GROUP, binding }, ty)
}

/// A module-scope resource at `binding` (any group).
fn global_in(
    b: &ModuleBuilder,
    name: &str,
    space: AddressSpace,
    binding: ResourceBinding,
    ty: Handle<Type>,
) -> Handle<GlobalVariable> {
    b.with_module(|m| {
        m.global_variables.append(
            GlobalVariable {
                name: Some(name.to_string()),
                space,
                binding: Some(binding),
                ty,
                init: None,
                memory_decorations: MemoryDecorations::empty(),
            },
            Span::UNDEFINED,
        )
    })
}

fn argument(name: &str, ty: Handle<Type>, binding: Option<Binding>) -> FunctionArgument {
    FunctionArgument { name: Some(name.to_string()), ty, binding }
}

/// The `n`, `v`, `l` (and `params`, `textures`) arguments shared by `<material>_brdf` and
/// `<material>_eval`.
fn direction_arguments(b: &ModuleBuilder, inputs: InputTypes) -> Vec<FunctionArgument> {
    let mut arguments =
        vec![argument("n", b.types.vec3, None), argument("v", b.types.vec3, None), argument("l", b.types.vec3, None)];
    if let Some(ty) = inputs.params {
        arguments.push(argument("params", ty, None));
    }
    if let Some(ty) = inputs.textures {
        arguments.push(argument("textures", ty, None));
    }
    arguments
}

fn add(b: &ModuleBuilder, function: Function) -> Handle<Function> {
    b.add_function(function, &[])
}

/// `<material>_brdf(n, v, l[, params])`: the layering method run on the IR builder.
fn brdf_function(b: &ModuleBuilder, material: &Material, inputs: InputTypes) -> Handle<Function> {
    let result = FunctionResult { ty: b.types.vec3, binding: None };
    b.begin_function(&format!("{}_brdf", material.name), direction_arguments(b, inputs), Some(result));
    let n = b.vector(b.argument(0));
    let v = b.vector(b.argument(1));
    let l = b.vector(b.argument(2));
    let inputs = function_inputs(b, material, inputs, 3);
    let f = layering::brdf(material, &inputs, n, v, l);
    let value = f.handle();
    b.statement(Statement::Return { value: Some(value) });
    add(b, b.end_function())
}

/// The material's inputs inside a generated function whose optional `params` and `textures`
/// arguments start at argument `first`: the parameters (uniform members, texture reads) and the
/// normal-mapped layers' shading normals.
fn function_inputs<'a>(b: &'a ModuleBuilder, material: &Material, inputs: InputTypes, first: u32) -> Inputs<Expr<'a>> {
    let params_arg = inputs.params.map(|_| b.argument(first));
    let textures_arg = inputs.textures.map(|_| b.argument(first + u32::from(inputs.params.is_some())));
    // Members of each struct in declaration order: the uniform ones, the texture reads.
    let (mut next_uniform, mut next_read) = (0, 0);
    let params = material
        .params
        .iter()
        .map(|p| {
            let (base, counter) = match p.source {
                ParamSource::Uniform => (params_arg, &mut next_uniform),
                ParamSource::Texture(_) => (textures_arg, &mut next_read),
            };
            let Some(base) = base else { unreachable!("a parameter's struct is an argument") };
            let h = b.append(Expression::AccessIndex { base, index: *counter });
            *counter += 1;
            match p.default {
                ParamValue::Scalar(_) => Slot::S(b.scalar(h)),
                ParamValue::Rgb(_) => Slot::V(b.vector(h)),
            }
        })
        .collect();
    // Normal-mapped layers' shading normals: the textures struct's members after the reads.
    let reads = material.texture_params().count() as u32;
    let normals = material
        .normals
        .iter()
        .enumerate()
        .map(|(i, (layer, _))| {
            let Some(base) = textures_arg else { unreachable!("normal maps come with the textures struct") };
            (*layer, b.vector(b.append(Expression::AccessIndex { base, index: reads + i as u32 })))
        })
        .collect();
    Inputs::new(b, params).with_normals(normals)
}

/// `<material>_ibl(n, v[, params][, textures])`: the radiance reflected towards `v` from the
/// environment (see [`environment`]).
fn ibl_function(
    b: &ModuleBuilder,
    material: &Material,
    inputs: InputTypes,
    lookups: environment::Lookups,
) -> Handle<Function> {
    let result = FunctionResult { ty: b.types.vec3, binding: None };
    let mut arguments = direction_arguments(b, inputs);
    arguments.remove(2);
    b.begin_function(&format!("{}_ibl", material.name), arguments, Some(result));
    let n = b.vector(b.argument(0));
    let v = b.vector(b.argument(1));
    let material_inputs = function_inputs(b, material, inputs, 2);
    let value = environment::reflected(b, lookups, material, &material_inputs, n, v).handle();
    b.statement(Statement::Return { value: Some(value) });
    let doc = [
        "The radiance reflected towards v from the environment (image-based lighting, split-sum): each lobe's",
        "directional albedo times the environment prefiltered for it (glazec_environment) or the irradiance",
        "over π (glazec_irradiance_at). n, v: unit vectors, v pointing away from the surface.",
    ];
    b.add_function(b.end_function(), &doc)
}

/// `<material>_eval(n, v, l[, params])` = brdf · max(n·l, 0).
fn eval_function(
    b: &ModuleBuilder,
    material: &Material,
    inputs: InputTypes,
    brdf: Handle<Function>,
) -> Handle<Function> {
    let result = FunctionResult { ty: b.types.vec3, binding: None };
    let arguments = direction_arguments(b, inputs);
    let count = arguments.len() as u32;
    b.begin_function(&format!("{}_eval", material.name), arguments, Some(result));
    let handles: Vec<_> = (0..count).map(|i| b.argument(i)).collect();
    let f = b.call(brdf, handles.clone());
    b.name(f, "f");
    let f = b.vector(f);
    let n = b.vector(handles[0]);
    let l = b.vector(handles[2]);
    let cosine = n.dot(l).at_least(0.0);
    let value = (f * cosine).handle();
    b.statement(Statement::Return { value: Some(value) });
    let eval = add(b, b.end_function());
    b.with_module(|m| {
        let docs = m.doc_comments.get_or_insert_with(Default::default);
        docs.functions.insert(eval, vec![format!(
            "The reflected radiance factor f(l, v) · max(n·l, 0) of material `{}`: multiply by a light's radiance.",
            material.name
        )]);
        docs.functions.insert(brdf, vec![format!(
            "The BRDF f(l, v) of material `{}` ({} layering), without the cosine. n, v, l: unit vectors, v and l pointing away from the surface.",
            material.name,
            material.method.name()
        )]);
    });
    eval
}

fn struct_type(
    b: &ModuleBuilder,
    name: &str,
    members: &[(&str, Handle<Type>, u32, Option<Binding>)],
    span: u32,
) -> Handle<Type> {
    let members = members
        .iter()
        .map(|(name, ty, offset, binding)| StructMember {
            name: Some((*name).to_string()),
            ty: *ty,
            binding: binding.clone(),
            offset: *offset,
        })
        .collect();
    b.with_module(|m| {
        m.types
            .insert(Type { name: Some(name.to_string()), inner: TypeInner::Struct { members, span } }, Span::UNDEFINED)
    })
}

fn runtime_array(b: &ModuleBuilder, base: Handle<Type>, stride: u32) -> Handle<Type> {
    b.with_module(|m| {
        m.types.insert(
            Type { name: None, inner: TypeInner::Array { base, size: naga::ArraySize::Dynamic, stride } },
            Span::UNDEFINED,
        )
    })
}

/// `eval_pairs`: values[i] = f(pairs[i].wi, pairs[i].wo) for i < dispatch.pair_count.
fn eval_pairs_entry(
    b: &ModuleBuilder,
    brdf: Handle<Function>,
    params_var: Option<Handle<GlobalVariable>>,
    sample: Option<Sampling>,
) {
    let pair_ty =
        struct_type(b, "DirectionPair", &[("wi", b.types.vec4, 0, None), ("wo", b.types.vec4, 16, None)], PAIR_STRIDE);
    let pairs_ty = runtime_array(b, pair_ty, PAIR_STRIDE);
    let values_ty = runtime_array(b, b.types.vec4, 16);
    let dispatch_ty = struct_type(b, "EvalDispatch", &[("pair_count", b.types.u32, 0, None)], 16);
    let pairs = global(b, "pairs", AddressSpace::Storage { access: StorageAccess::LOAD }, bindings::PAIRS, pairs_ty);
    let values = global(
        b,
        "values",
        AddressSpace::Storage { access: StorageAccess::LOAD | StorageAccess::STORE },
        bindings::VALUES,
        values_ty,
    );
    let dispatch = global(b, "dispatch", AddressSpace::Uniform, bindings::DISPATCH, dispatch_ty);

    let id = argument("id", b.types.uvec3, Some(Binding::BuiltIn(BuiltIn::GlobalInvocationId)));
    b.begin_function(entry_points::EVAL_PAIRS, vec![id], None);
    let id = b.argument(0);
    let index = b.append(Expression::AccessIndex { base: id, index: 0 });
    b.name(index, "index");
    let dispatch_ptr = b.append(Expression::GlobalVariable(dispatch));
    let count_ptr = b.append(Expression::AccessIndex { base: dispatch_ptr, index: 0 });
    let count = b.append(Expression::Load { pointer: count_ptr });
    let outside = b.append(Expression::Binary { op: naga::BinaryOperator::GreaterEqual, left: index, right: count });
    b.return_if(outside);

    let pairs_ptr = b.append(Expression::GlobalVariable(pairs));
    let pair_ptr = b.append(Expression::Access { base: pairs_ptr, index });
    let pair = b.append(Expression::Load { pointer: pair_ptr });
    b.name(pair, "pair");
    let xyz = |b: &ModuleBuilder, member: u32| {
        let v4 = b.append(Expression::AccessIndex { base: pair, index: member });
        b.append(Expression::Swizzle {
            size: VectorSize::Tri,
            vector: v4,
            pattern: [SwizzleComponent::X, SwizzleComponent::Y, SwizzleComponent::Z, SwizzleComponent::X],
        })
    };
    let wi = xyz(b, 0);
    let wo = xyz(b, 1);
    let normal = b.constant(0.0);
    let normal = Expr::vec3(normal, normal, b.constant(1.0)).handle();
    let mut arguments = vec![normal, wo, wi];
    if let Some(var) = params_var {
        let ptr = b.append(Expression::GlobalVariable(var));
        arguments.push(b.append(Expression::Load { pointer: ptr }));
    }
    if let Some(sample) = sample {
        // The texture coordinates ride in the pairs' spare fourth components: (wi.w, wo.w).
        let w = |member: u32| {
            let v4 = b.append(Expression::AccessIndex { base: pair, index: member });
            b.append(Expression::AccessIndex { base: v4, index: 3 })
        };
        let (u, v) = (w(0), w(1));
        let uv = b.append(Expression::Compose { ty: b.types.vec2, components: vec![u, v] });
        b.name(uv, "uv");
        let mut sample_arguments = vec![uv];
        if sample.frame {
            // The local frame: n = +z, tangent +x, bitangent +y.
            let c = |x: f32| b.constant(x);
            for (x, y, z) in [(0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)] {
                sample_arguments.push(Expr::vec3(c(x), c(y), c(z)).handle());
            }
        }
        let textures = b.call(sample.function, sample_arguments);
        b.name(textures, "textures");
        arguments.push(textures);
    }
    let f = b.call(brdf, arguments);
    b.name(f, "f");
    let zero = b.constant(0.0).handle();
    let value = b.append(Expression::Compose { ty: b.types.vec4, components: vec![f, zero] });
    let values_ptr = b.append(Expression::GlobalVariable(values));
    let out_ptr = b.append(Expression::Access { base: values_ptr, index });
    b.statement(Statement::Store { pointer: out_ptr, value });
    b.statement(Statement::Return { value: None });
    let function = b.end_function();
    b.with_module(|m| {
        m.entry_points.push(EntryPoint {
            name: entry_points::EVAL_PAIRS.to_string(),
            stage: ShaderStage::Compute,
            early_depth_test: None,
            workgroup_size: [EVAL_WORKGROUP_SIZE, 1, 1],
            workgroup_size_overrides: None,
            function,
            mesh_info: None,
            task_payload: None,
            incoming_ray_payload: None,
        })
    });
}

fn push_entry(b: &ModuleBuilder, name: &str, stage: ShaderStage, function: Function) {
    b.with_module(|m| {
        m.entry_points.push(EntryPoint {
            name: name.to_string(),
            stage,
            early_depth_test: None,
            workgroup_size: [0, 0, 0],
            workgroup_size_overrides: None,
            function,
            mesh_info: None,
            task_payload: None,
            incoming_ray_payload: None,
        })
    });
}

fn location(location: u32) -> Binding {
    Binding::Location { location, interpolation: None, sampling: None, blend_src: None, per_primitive: false }
}

/// A perspective-interpolated varying at `location`.
fn varying(location: u32) -> Binding {
    Binding::Location {
        location,
        interpolation: Some(naga::Interpolation::Perspective),
        sampling: Some(naga::Sampling::Center),
        blend_src: None,
        per_primitive: false,
    }
}

/// `preview_vs` (a full-screen triangle passing its clip-space position on) and `preview_fs` (a
/// unit sphere seen along −z, shaded by `<material>_eval` under the directional light in the
/// `light` uniform; alpha is the sphere's coverage, and outside it the output is 0).
fn preview_entries(
    b: &ModuleBuilder,
    eval: Handle<Function>,
    params_var: Option<Handle<GlobalVariable>>,
    sample: Option<Sampling>,
) {
    let light_ty = struct_type(
        b,
        "PreviewLight",
        &[("direction", b.types.vec4, 0, None), ("radiance", b.types.vec4, 16, None)],
        32,
    );
    // Numbered by `bindings::assign` once the module is complete.
    let light = global(b, "light", AddressSpace::Uniform, u32::MAX, light_ty);
    let varying_ty = struct_type(
        b,
        "PreviewVarying",
        &[
            ("position", b.types.vec4, 0, Some(Binding::BuiltIn(BuiltIn::Position { invariant: false }))),
            ("p", b.types.vec2, 16, Some(varying(0))),
        ],
        24,
    );

    // Vertex: a full-screen triangle from a vertex buffer of clip-space corners, e.g.
    // (−1, −1), (3, −1), (−1, 3). (An index-generated triangle would need `vertex_index`, which
    // naga's GLSL backend writes as GL's `gl_VertexID`, not Vulkan's `gl_VertexIndex`.)
    let corner = argument("corner", b.types.vec2, Some(location(0)));
    b.begin_function(entry_points::PREVIEW_VS, vec![corner], Some(FunctionResult { ty: varying_ty, binding: None }));
    let corner = b.argument(0);
    let x = b.append(Expression::AccessIndex { base: corner, index: 0 });
    let y = b.append(Expression::AccessIndex { base: corner, index: 1 });
    let zero = b.constant(0.0).handle();
    let w = b.constant(1.0).handle();
    let position = b.append(Expression::Compose { ty: b.types.vec4, components: vec![x, y, zero, w] });
    let out = b.append(Expression::Compose { ty: varying_ty, components: vec![position, corner] });
    b.statement(Statement::Return { value: Some(out) });
    push_entry(b, entry_points::PREVIEW_VS, ShaderStage::Vertex, b.end_function());

    // Fragment: the sphere under the light.
    begin_sphere_fragment(b, entry_points::PREVIEW_FS);
    let point = sphere_point(b, params_var, sample);
    let light_ptr = b.append(Expression::GlobalVariable(light));
    let member = |index: u32| {
        let ptr = b.append(Expression::AccessIndex { base: light_ptr, index });
        let v4 = b.append(Expression::Load { pointer: ptr });
        b.vector(b.append(Expression::Swizzle {
            size: VectorSize::Tri,
            vector: v4,
            pattern: [SwizzleComponent::X, SwizzleComponent::Y, SwizzleComponent::Z, SwizzleComponent::X],
        }))
    };
    let l = member(0).named("l");
    let light_radiance = member(1);
    let mut arguments = vec![point.n.handle(), point.v.handle(), l.handle()];
    arguments.extend(point.material_arguments.iter().copied());
    let reflected = b.call(eval, arguments);
    b.name(reflected, "reflected");
    let radiance = b.vector(reflected) * light_radiance;
    return_sphere_color(b, &point, radiance);
    push_entry(b, entry_points::PREVIEW_FS, ShaderStage::Fragment, b.end_function());
}

/// `preview_ibl_fs`: the preview sphere lit by the environment through `<material>_ibl`.
fn preview_ibl_entry(
    b: &ModuleBuilder,
    ibl: Handle<Function>,
    params_var: Option<Handle<GlobalVariable>>,
    sample: Option<Sampling>,
) {
    begin_sphere_fragment(b, entry_points::PREVIEW_IBL_FS);
    let point = sphere_point(b, params_var, sample);
    let mut arguments = vec![point.n.handle(), point.v.handle()];
    arguments.extend(point.material_arguments.iter().copied());
    let reflected = b.call(ibl, arguments);
    b.name(reflected, "reflected");
    return_sphere_color(b, &point, b.vector(reflected));
    push_entry(b, entry_points::PREVIEW_IBL_FS, ShaderStage::Fragment, b.end_function());
}

/// Starts a preview fragment entry point: clip-space position `p` in, colour out.
fn begin_sphere_fragment(b: &ModuleBuilder, name: &str) {
    let p_arg = argument("p", b.types.vec2, Some(varying(0)));
    let output = FunctionResult { ty: b.types.vec4, binding: Some(location(0)) };
    b.begin_function(name, vec![p_arg], Some(output));
}

/// The preview sphere's point under the fragment (unit sphere seen along −z, orthographic).
struct SpherePoint<'a> {
    /// |p|²: the point is on the sphere where it is below 1.
    r2: Expr<'a>,
    n: builder::ExprVec<'a>,
    /// The view direction, +z.
    v: builder::ExprVec<'a>,
    /// The material's `params` and `textures` arguments (those it has).
    material_arguments: Vec<Handle<Expression>>,
}

/// At clip-space position p, on the disk |p| ≤ 1, the normal is (p, √(1 − |p|²)); the material's
/// arguments are loaded (params) and sampled (textures at the sphere's uv, normal maps in its
/// tangent frame).
fn sphere_point<'a>(
    b: &'a ModuleBuilder,
    params_var: Option<Handle<GlobalVariable>>,
    sample: Option<Sampling>,
) -> SpherePoint<'a> {
    let p = b.argument(0);
    let px = b.scalar(b.append(Expression::AccessIndex { base: p, index: 0 }));
    let py = b.scalar(b.append(Expression::AccessIndex { base: p, index: 1 }));
    let r2 = (px * px + py * py).named("r2");
    // Guard: outside the disk the square root would be of a negative number; the select in
    // `return_sphere_color` discards those pixels anyway.
    let nz = r2.one_minus().at_least(0.0).sqrt();
    let n = Expr::vec3(px, py, nz).named("n");
    let c = |x: f32| b.constant(x);
    let v = Expr::vec3(c(0.0), c(0.0), c(1.0));
    let mut material_arguments = Vec::new();
    if let Some(var) = params_var {
        let ptr = b.append(Expression::GlobalVariable(var));
        material_arguments.push(b.append(Expression::Load { pointer: ptr }));
    }
    if let Some(sample) = sample {
        let uv = sphere_uv(b, px, py, nz);
        b.name(uv, "uv");
        let mut sample_arguments = vec![uv];
        if sample.frame {
            let (t, bitangent) = sphere_frame(b, n);
            sample_arguments.extend([n.handle(), t.handle(), bitangent.handle()]);
        }
        let textures = b.call(sample.function, sample_arguments);
        b.name(textures, "textures");
        material_arguments.push(textures);
    }
    SpherePoint { r2, n, v, material_arguments }
}

/// Returns (radiance, coverage) on the sphere and transparent black outside it, so that passes
/// add up and the host can put a background behind the sphere.
fn return_sphere_color<'a>(b: &'a ModuleBuilder, point: &SpherePoint<'a>, radiance: builder::ExprVec<'a>) {
    let c = |x: f32| b.constant(x);
    let inside = point.r2.lt(c(1.0));
    let color = <builder::ExprVec as Vector>::select(inside, radiance, c(0.0).splat());
    let coverage = Expr::select(inside, c(1.0), c(0.0));
    let color4 =
        b.append(Expression::Compose { ty: b.types.vec4, components: vec![color.handle(), coverage.handle()] });
    b.statement(Statement::Return { value: Some(color4) });
}

/// The sphere's texture coordinates at normal (x, y, z) (y up, z towards the viewer): longitude
/// u = ½ + atan2(x, z)/2π (½ facing the viewer) and latitude v = ½ − asin(y)/π (0 at the top).
fn sphere_uv<'a>(
    b: &'a ModuleBuilder,
    x: builder::Expr<'a>,
    y: builder::Expr<'a>,
    z: builder::Expr<'a>,
) -> Handle<Expression> {
    use std::f32::consts::PI;
    // Guard: asin of |y| ≤ 1 only; on the disk's rim rounding can put y a hair outside.
    let y = y.clamp(-1.0, 1.0);
    let longitude = b.scalar(b.math(naga::MathFunction::Atan2, &[x.handle(), z.handle()]));
    let latitude = b.scalar(b.math(naga::MathFunction::Asin, &[y.handle()]));
    let u = (longitude * (0.5 / PI) + 0.5).handle();
    let v = (latitude * (-1.0 / PI) + 0.5).handle();
    b.append(Expression::Compose { ty: b.types.vec2, components: vec![u, v] })
}

/// The sphere's tangent frame at normal `n` along its uv: t = ∂P/∂u ∝ (n.z, 0, −n.x) (east), and
/// b = n × t (north, texture +y up, the OpenGL normal-map convention). Guard: |(n.z, 0, −n.x)|
/// ≥ 10⁻⁶ at the poles, where longitude has no direction.
fn sphere_frame<'a>(b: &'a ModuleBuilder, n: builder::ExprVec<'a>) -> (builder::ExprVec<'a>, builder::ExprVec<'a>) {
    let east = Expr::vec3(n.z(), b.constant(0.0), -n.x());
    let t = (east / east.dot(east).sqrt().at_least(1e-6)).named("tangent");
    let bitangent = n.cross(t).named("bitangent");
    (t, bitangent)
}
