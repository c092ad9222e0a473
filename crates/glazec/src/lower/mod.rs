//! Stage 3, `lower`: the material model → a `naga::Module`, built programmatically.
//!
//! **Input:** a checked [`Material`]. **Output:** a `naga::Module` holding
//!
//! * one function per BRDF term the material uses (`d_ggx`, `fr_dielectric`, …; built by
//!   running [`crate::math`] on the [`builder`]), each carrying its citation as a doc comment;
//! * `<material>_brdf(n, v, l[, params]) -> vec3<f32>`: f(l, v) **without** the cosine;
//! * `<material>_eval(n, v, l[, params]) -> vec3<f32>`: f · max(n·l, 0), for users' light loops;
//! * `<material>_ibl_lobes(n, v[, params]) -> <Material>IblLobes`: image-based lighting as lobes
//!   for the host's environment; and, where the host placed glazec's environment
//!   ([`Choice::environment`]), `<material>_ibl(n, v[, params])`, the lobes looked up in it;
//! * a uniform struct `<Material>Params` with one member per runtime parameter (declaration
//!   order, `f32` or `vec3<f32>`), when the material has any;
//! * the resources they read, each at the binding the host chose ([`bindings::Choice`]): the
//!   parameter uniform `<material>_params`, the table uniform `<material>_tables` (only the
//!   tables the material reads), the textures and the environment;
//!
//! all of it the material's **library** ([`Lowered::library`]): no entry point, and every
//! module-scope name but the structs' (already `<Material>…`) prefixed with `<material>_`, so
//! that several materials' libraries concatenate into one shader. After the library come the
//! entry points of glazec's own **harness** ([`Lowered::module`]): `eval_pairs` (compute: f(wi,
//! wo) for a buffer of direction pairs, used by the tests, `eval` and benchmarks) and
//! `preview_vs`/`preview_fs`/`preview_ibl_fs` (a full-screen triangle that shades a sphere under
//! one directional light, given by the `light` uniform, or under the environment, through
//! `<material>_ibl` and glazec's environment, which the harness adds at their default place
//! when the library has not got them).
//!
//! See [`bindings`] for where each resource goes. The kernel reads its element count from a
//! uniform rather than from `arrayLength`, because glslang's HLSL front end lowers
//! `GetDimensions` on byte-address buffers to a dword count (docs/derivations.md, "glslang and
//! the HLSL path"), which would cover only a quarter of the buffer.
//!
//! **Invariants:** both modules validate with all of naga's validation flags (checked by
//! `validate`); the library's arenas are a prefix of the harness module's; output is a pure
//! function of the material and the choice of bindings (no hash-map iteration order, no
//! addresses), so emitted files are byte-identical across runs.

pub mod builder;
mod cost;
pub mod environment;
mod harness;
mod layout;
mod material;
mod namespace;
pub mod textures;

pub use cost::{CallCost, call_cost, static_cost};
pub use layout::{EVAL_WORKGROUP_SIZE, PAIR_STRIDE, ParamLayout, bindings, entry_points, params_bytes, params_layout};

use crate::model::Material;
use bindings::{Choice, Clash, Layout};
use builder::ModuleBuilder;
use harness::{eval_pairs_entry, preview_entries, preview_ibl_entry};
use material::{
    InputTypes, Sampling, brdf_function, eval_function, global, ibl_function, ibl_lobes_function, params_type,
};
use naga::{AddressSpace, Module};

/// A lowered material.
#[derive(Clone, Debug)]
pub struct Lowered {
    /// The material's library: its functions and the resources they read; no entry point.
    pub library: Module,
    /// The library followed by glazec's harness (its arenas extend the library's).
    pub module: Module,
    /// Where both modules' resources are bound.
    pub layout: Layout,
    /// The contents of the table uniform: the 16-bit codes of the tables the library reads,
    /// concatenated (empty when it reads none). [`builder::table_bytes`] packs them.
    pub tables: Vec<u16>,
}

/// Lowers a material with glazec's default bindings (see the module docs for what it contains).
pub fn lower(material: &Material) -> Lowered {
    lower_with(material, &Choice::default())
        .unwrap_or_else(|clash| unreachable!("the default bindings are apart by construction: {clash}"))
}

/// Lowers a material with its resources where `choice` puts them: the library and glazec's
/// harness on it.
///
/// # Errors
/// Two resources of the library would share a binding.
pub fn lower_with(material: &Material, choice: &Choice) -> Result<Lowered, Clash> {
    let (library, module, layout, tables) = lower_parts(material, choice, true)?;
    let module = module.unwrap_or_else(|| unreachable!("the harness was asked for"));
    Ok(Lowered { library, module, layout, tables })
}

/// A material's library alone: what a host imports, without glazec's harness (which
/// [`lower_with`] adds, for glazec's own runs).
#[derive(Clone, Debug)]
pub struct Library {
    pub library: Module,
    /// Where the library's resources are bound (the harness's fields keep their defaults).
    pub layout: Layout,
    /// As [`Lowered::tables`].
    pub tables: Vec<u16>,
}

/// Lowers a material's library alone, with its resources where `choice` puts them: the same
/// library as [`lower_with`]'s, without building the harness.
///
/// # Errors
/// Two resources of the library would share a binding.
pub fn lower_library(material: &Material, choice: &Choice) -> Result<Library, Clash> {
    let (library, _, layout, tables) = lower_parts(material, choice, false)?;
    Ok(Library { library, layout, tables })
}

type Parts = (Module, Option<Module>, Layout, Vec<u16>);

fn lower_parts(material: &Material, choice: &Choice, with_harness: bool) -> Result<Parts, Clash> {
    let b = ModuleBuilder::new();
    b.curves.set(crate::math::tables::curves_for(material));
    let params_ty = params_type(&b, material);
    let reads = textures::build(&b, material);
    let inputs = InputTypes { params: params_ty, textures: reads.as_ref().map(|r| r.ty) };
    let brdf = brdf_function(&b, material, inputs);
    let eval = eval_function(&b, material, inputs, brdf);
    let lobes = ibl_lobes_function(&b, material, inputs);
    // glazec's own environment lookup is the library's only where the host placed it.
    let ibl_in_library = choice.environment.is_some();
    let build_ibl = || ibl_function(&b, material, inputs, environment::build_lookups(&b), lobes);
    let library_ibl = ibl_in_library.then(&build_ibl);
    let params_var = params_ty.map(|ty| global(&b, "params", AddressSpace::Uniform, bindings::PARAMS, ty));
    let tables = b.finish_tables();
    let public = [Some(brdf), Some(eval), Some(lobes.function), library_ibl, reads.as_ref().map(|r| r.sample)];
    let tables_var = b.tables_global();
    let mut layout = b.with_module(|m| {
        namespace::prefix(m, &material.name, &public, namespace::Start::default());
        namespace::place(m, choice, params_var, tables_var)
    })?;
    if !with_harness {
        return Ok((b.finish(), None, layout, tables));
    }
    let library = b.snapshot();
    let ibl = library_ibl.unwrap_or_else(|| {
        let start = b.with_module(|m| namespace::Start::of(m));
        let ibl = build_ibl();
        b.with_module(|m| namespace::prefix(m, &material.name, &[Some(ibl)], start));
        ibl
    });

    let sample = reads.as_ref().map(|r| Sampling { function: r.sample, frame: !material.normals.is_empty() });
    eval_pairs_entry(&b, brdf, params_var, sample);
    preview_entries(&b, eval, params_var, sample);
    preview_ibl_entry(&b, ibl, params_var, sample);
    let mut module = b.finish();
    namespace::place_harness(&mut module, library.global_variables.len(), &mut layout);
    Ok((library, Some(module), layout, tables))
}
