//! # glazec — a layered-material compiler
//!
//! A material is a small RON file that declares a stack of layers (each coat with its
//! interface lobe, IOR, absorption and thickness) over an opaque base. glazec checks it with
//! precise diagnostics, lowers it **through naga IR** to WGSL, GLSL and HLSL (and SPIR-V), and
//! evaluates the very same formulas on the CPU.
//!
//! ```text
//!   .ron text ──parse──▶ spanned syntax ──check──▶ Material model
//!      ──lower──▶ naga::Module ──validate──▶ ModuleInfo ──emit──▶ WGSL / GLSL / HLSL / SPIR-V
//!                     ▲
//!        math (one source: terms + layering, generic over Real) ──▶ eval (CPU, f32)
//! ```
//!
//! One module per stage, data flowing one way: [`parse`] knows RON, [`check`] knows materials
//! and reports every error with a span and a code ([`diag`]), [`model`] is plain data,
//! [`lower`] builds IR by running [`math`] on a naga builder, [`validate`] is naga's validator,
//! [`emit`] wraps naga's backends, [`eval`] runs [`math`] on `f32`, and [`output`] writes files
//! atomically. [`compile`] chains the stages; the `glazec` command line (package `glazec-cli`
//! at the workspace root) is a thin layer over it and [`project`].
//! Around them: [`project`] compiles a set of files, [`build`] is the `build.rs` API,
//! [`snapshot`] the golden-shader helper for users' tests, and [`simplify`] (between check and
//! lower) drops what a [`scene`] cannot see, within its tolerance.
//!
//! `build.rs` users depend on `glazec`: the whole compiler (naga, codespan-reporting), without
//! the CLI or a GPU. The GPU runner (`glazec-gpu`) and the measurement lab (`glazec-lab`) are
//! crates beside it in the workspace, and depend on it, not the other way round.

pub mod build;
pub mod check;
pub mod diag;
pub mod emit;
pub mod eval;
pub mod lower;
pub mod math;
pub mod model;
pub mod names;
pub mod optics;
mod origin;
pub mod output;
pub mod parse;
pub mod project;
pub mod scene;
pub mod simplify;
pub mod snapshot;
pub mod validate;

use diag::Diagnostic;
pub use emit::{Artifact, Target};
pub use model::{Material, SourceMap};
pub use origin::{Origin, VERSION, source_hash};

/// A material that went through every stage up to validation.
pub struct Compiled {
    pub material: Material,
    /// Where the text came from; named in the header of every generated file.
    pub origin: Origin,
    pub source_map: SourceMap,
    pub module: naga::Module,
    pub info: naga::valid::ModuleInfo,
}

/// An error and its causes, each once, joined by ": " (what `{:#}` prints for an `anyhow` error):
/// glazec's errors name their cause through [`std::error::Error::source`], not in their own text.
pub fn error_chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut cause = error.source();
    while let Some(e) = cause {
        text.push_str(": ");
        text.push_str(&e.to_string());
        cause = e.source();
    }
    text
}

/// Why a compilation produced nothing.
#[derive(Debug, thiserror::Error)]
pub enum CompileError {
    /// Problems in the material's text, all of them, in source order.
    #[error("{} error(s) in the material", .0.len())]
    Diagnostics(Vec<Diagnostic>),
    /// A bug in glazec: naga rejected IR that `lower` built.
    #[error(transparent)]
    Internal(#[from] validate::ValidateError),
}

/// Parses and checks a material's text.
///
/// # Errors
/// The first syntax error, or every semantic error.
pub fn load(text: &str) -> Result<(Material, SourceMap), Vec<Diagnostic>> {
    let syntax = parse::parse(text).map_err(|d| vec![d])?;
    check::check(&syntax)
}

/// Compiles a material's text up to a validated naga module.
///
/// # Errors
/// [`CompileError::Diagnostics`] for bad input; [`CompileError::Internal`] for a compiler bug.
pub fn compile(text: &str) -> Result<Compiled, CompileError> {
    compile_source(None, text)
}

/// Compiles the text of the file `file` (named in generated headers without its directory).
///
/// # Errors
/// As [`compile`].
pub fn compile_source(file: Option<&str>, text: &str) -> Result<Compiled, CompileError> {
    let (material, source_map) = load(text).map_err(CompileError::Diagnostics)?;
    let mut compiled = compile_material(material, source_map)?;
    compiled.origin = Origin::new(file, text);
    Ok(compiled)
}

/// Lowers and validates an already-checked material (for programs that build [`Material`]s).
///
/// # Errors
/// Only for a compiler bug (naga rejecting the generated IR).
pub fn compile_material(material: Material, source_map: SourceMap) -> Result<Compiled, validate::ValidateError> {
    let module = lower::lower(&material);
    let info = validate::validate(&material.name, &module)?;
    // A material built by a program has no text; its model (whose `Debug` form prints every
    // field, floats exactly) stands in for it.
    let origin = Origin { file: None, hash: source_hash(format!("{material:?}").as_bytes()), scene: None };
    Ok(Compiled { material, origin, source_map, module, info })
}

impl Compiled {
    /// Whether the shaders read the table buffer `glazec_tables` (then bind the contents of
    /// [`output::tables_file`]; see `lower::bindings`).
    pub fn uses_tables(&self) -> bool {
        lower::bindings::layout(&self.module).tables.is_some()
    }

    /// Emits shader files for `targets`.
    ///
    /// # Errors
    /// Only for a backend bug; a validated module is expected to emit.
    pub fn emit(&self, targets: &[Target]) -> Result<Vec<Artifact>, emit::EmitError> {
        emit::emit(&self.material.name, &self.origin, &self.module, &self.info, targets)
    }
}
