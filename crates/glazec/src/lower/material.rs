//! The material's own functions: `<material>_brdf`, `<material>_eval`, `<material>_ibl_lobes`,
//! `<material>_ibl` and the runtime-parameter struct, built by running the shared math on the IR
//! builder.

use naga::{
    AddressSpace, Expression, Function, FunctionArgument, FunctionResult, GlobalVariable, Handle, ResourceBinding,
    Span, Statement, StructMember, Type, TypeInner,
};

use super::builder::{Expr, ModuleBuilder, argument, global_in};
use super::environment::{self};
use super::layout::{bindings, params_layout};
use crate::math::layering::{self, Inputs};
use crate::math::{Real, Slot, Vector};
use crate::model::{Material, ParamSource, ParamValue};

/// `<material>_textures` and whether it takes the surface frame (n, t, b) after `uv`.
#[derive(Clone, Copy)]
pub(super) struct Sampling {
    pub(super) function: Handle<Function>,
    pub(super) frame: bool,
}

/// The optional struct arguments of `<material>_brdf` and `<material>_eval`.
#[derive(Clone, Copy)]
pub(super) struct InputTypes {
    pub(super) params: Option<Handle<Type>>,
    pub(super) textures: Option<Handle<Type>>,
}

pub(super) fn params_type(b: &ModuleBuilder, material: &Material) -> Option<Handle<Type>> {
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

pub(super) fn global(
    b: &ModuleBuilder,
    name: &str,
    space: AddressSpace,
    binding: u32,
    ty: Handle<Type>,
) -> Handle<GlobalVariable> {
    global_in(b, name, space, ResourceBinding { group: bindings::GROUP, binding }, ty)
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

pub(super) fn add(b: &ModuleBuilder, function: Function) -> Handle<Function> {
    b.add_function(function, &[])
}

/// `<material>_brdf(n, v, l[, params])`: the layering method run on the IR builder.
pub(super) fn brdf_function(b: &ModuleBuilder, material: &Material, inputs: InputTypes) -> Handle<Function> {
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

/// `<material>_ibl_lobes(n, v[, params][, textures]) -> <Material>IblLobes`: the material's
/// lobes under image-based lighting (see [`environment`]), for hosts with their own environment.
pub(super) fn ibl_lobes_function(b: &ModuleBuilder, material: &Material, inputs: InputTypes) -> IblLobes {
    let mut arguments = direction_arguments(b, inputs);
    arguments.remove(2);
    let name = format!("{}_ibl_lobes", material.name);
    // The result type exists only once the lobes are known: it is set after the body.
    b.begin_function(&name, arguments, None);
    let n = b.vector(b.argument(0));
    let v = b.vector(b.argument(1));
    let material_inputs = function_inputs(b, material, inputs, 2);
    let (value, types) = environment::composed_lobes(b, material, &material_inputs, n, v);
    b.statement(Statement::Return { value: Some(value) });
    let mut function = b.end_function();
    function.result = Some(FunctionResult { ty: types.lobes, binding: None });
    let m = &material.name;
    let doc = [
        "The material's lobes under image-based lighting (split sum), for a host's own prefiltered environment:"
            .to_string(),
        "the reflected radiance is Σ_k specular[k].weight · (environment prefiltered by GGX of roughness".to_string(),
        "specular[k].roughness around specular[k].direction) + irradiance.weight · (irradiance around".to_string(),
        format!(
            "irradiance.direction, over π), k < {m}_ibl_specular_lobes. n, v: unit vectors, v pointing away from the surface."
        ),
    ];
    let doc: Vec<&str> = doc.iter().map(String::as_str).collect();
    IblLobes { function: b.add_function(function, &doc), types }
}

/// `<material>_ibl_lobes` and the structs it returns.
#[derive(Clone, Copy)]
pub(super) struct IblLobes {
    pub(super) function: Handle<Function>,
    pub(super) types: environment::LobeTypes,
}

/// `<material>_ibl(n, v[, params][, textures])`: the radiance reflected towards `v` from the
/// environment (see [`environment`]): `<material>_ibl_lobes` looked up in glazec's images.
pub(super) fn ibl_function(
    b: &ModuleBuilder,
    material: &Material,
    inputs: InputTypes,
    lookups: environment::Lookups,
    lobes: IblLobes,
) -> Handle<Function> {
    let result = FunctionResult { ty: b.types.vec3, binding: None };
    let mut arguments = direction_arguments(b, inputs);
    arguments.remove(2);
    let count = arguments.len() as u32;
    b.begin_function(&format!("{}_ibl", material.name), arguments, Some(result));
    let found = b.call(lobes.function, (0..count).map(|i| b.argument(i)).collect());
    b.name(found, "lobes");
    let value = environment::reflected(b, lookups, found, lobes.types).handle();
    b.statement(Statement::Return { value: Some(value) });
    let m = &material.name;
    let doc = [
        "The radiance reflected towards v from the environment (image-based lighting, split-sum): each lobe of"
            .to_string(),
        format!("{m}_ibl_lobes times the environment prefiltered for it ({m}_environment) or the irradiance"),
        format!("over π ({m}_irradiance_at). n, v: unit vectors, v pointing away from the surface."),
    ];
    let doc: Vec<&str> = doc.iter().map(String::as_str).collect();
    b.add_function(b.end_function(), &doc)
}

/// `<material>_eval(n, v, l[, params])` = brdf · max(n·l, 0).
pub(super) fn eval_function(
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
