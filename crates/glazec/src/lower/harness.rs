//! glazec's own harness around a material's functions: the `eval_pairs` compute kernel (the
//! tests, `eval` and the benchmarks) and the preview's sphere entry points.

use naga::{
    AddressSpace, Binding, BuiltIn, EntryPoint, Expression, Function, FunctionResult, GlobalVariable, Handle,
    ShaderStage, Statement, StorageAccess, SwizzleComponent, VectorSize,
};

use super::builder::{Expr, ExprVec, ModuleBuilder, argument, runtime_array, struct_type};
use super::layout::{EVAL_WORKGROUP_SIZE, PAIR_STRIDE, bindings, entry_points};
use super::material::{Sampling, global};
use crate::math::{Named, Real, Vector};

/// `eval_pairs`: values[i] = f(pairs[i].wi, pairs[i].wo) for i < dispatch.pair_count.
pub(super) fn eval_pairs_entry(
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
pub(super) fn preview_entries(
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
pub(super) fn preview_ibl_entry(
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
    n: ExprVec<'a>,
    /// The view direction, +z.
    v: ExprVec<'a>,
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
fn return_sphere_color<'a>(b: &'a ModuleBuilder, point: &SpherePoint<'a>, radiance: ExprVec<'a>) {
    let c = |x: f32| b.constant(x);
    let inside = point.r2.lt(c(1.0));
    let color = <ExprVec as Vector>::select(inside, radiance, c(0.0).splat());
    let coverage = Expr::select(inside, c(1.0), c(0.0));
    let color4 =
        b.append(Expression::Compose { ty: b.types.vec4, components: vec![color.handle(), coverage.handle()] });
    b.statement(Statement::Return { value: Some(color4) });
}

/// The sphere's texture coordinates at normal (x, y, z) (y up, z towards the viewer): longitude
/// u = ½ + atan2(x, z)/2π (½ facing the viewer) and latitude v = ½ − asin(y)/π (0 at the top).
fn sphere_uv<'a>(b: &'a ModuleBuilder, x: Expr<'a>, y: Expr<'a>, z: Expr<'a>) -> Handle<Expression> {
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
fn sphere_frame<'a>(b: &'a ModuleBuilder, n: ExprVec<'a>) -> (ExprVec<'a>, ExprVec<'a>) {
    let east = Expr::vec3(n.z(), b.constant(0.0), -n.x());
    let t = (east / east.dot(east).sqrt().at_least(1e-6)).named("tangent");
    let bitangent = n.cross(t).named("bitangent");
    (t, bitangent)
}
