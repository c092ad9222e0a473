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
//! (docs/derivations.md, "glslang and the HLSL path"), which would cover only a quarter of the
//! buffer.
//!
//! **Invariants:** the module validates with all of naga's validation flags (checked by
//! `validate`); output is a pure function of the material (no hash-map iteration order, no
//! addresses), so emitted files are byte-identical across runs.

pub mod builder;
mod cost;
pub mod environment;
mod harness;
mod layout;
mod material;
pub mod textures;

pub use cost::static_cost;
pub use layout::{EVAL_WORKGROUP_SIZE, PAIR_STRIDE, ParamLayout, bindings, entry_points, params_bytes, params_layout};

use crate::model::Material;
use builder::ModuleBuilder;
use harness::{eval_pairs_entry, preview_entries, preview_ibl_entry};
use material::{InputTypes, Sampling, brdf_function, eval_function, global, ibl_function, params_type};
use naga::{AddressSpace, Module};

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
