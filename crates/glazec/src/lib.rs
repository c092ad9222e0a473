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

/// A material that went through every stage up to validation: its library, and glazec's
/// harness on it when asked for ([`Compiled::harness`]).
pub struct Compiled {
    pub material: Material,
    /// Where the text came from; named in the header of every generated file.
    pub origin: Origin,
    pub source_map: SourceMap,
    /// The material's library (no entry points): what a host imports.
    pub library: naga::Module,
    pub library_info: naga::valid::ModuleInfo,
    /// Where the library's resources are bound (the harness's are in [`Harness::layout`]).
    pub layout: lower::bindings::Layout,
    /// The contents of the table uniform (see [`lower::Lowered::tables`]).
    pub tables: Vec<u16>,
    /// The bindings the library was lowered with (the harness is lowered with them too).
    choice: lower::bindings::Choice,
    /// glazec's harness, built on first use: a host never needs it.
    harness: std::sync::OnceLock<Harness>,
}

/// The library followed by glazec's harness (`eval_pairs` and the previews): what glazec's
/// tests, `eval`, `bench` and `preview` run.
pub struct Harness {
    pub module: naga::Module,
    pub info: naga::valid::ModuleInfo,
    /// Where the resources of the library and of the harness are bound.
    pub layout: lower::bindings::Layout,
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
    if let Some(diagnostic) = table_budget(&compiled) {
        return Err(CompileError::Diagnostics(vec![diagnostic]));
    }
    compiled.origin = Origin::new(file, text);
    Ok(compiled)
}

/// `E0222` when the tables the library looks up at runtime do not fit the uniform binding they
/// live in ([`lower::builder::MAX_UNIFORM_BYTES`], what WebGPU guarantees). A lookup whose
/// arguments are all literal is baked into the shader and reads nothing; only runtime
/// parameters make a material read tables, and only one with Gtr1 and Ggx coats over a
/// conductor, with runtime parameters on each, can read more than fits. Reported at its first
/// runtime parameter.
fn table_budget(compiled: &Compiled) -> Option<Diagnostic> {
    let bytes = 2 * compiled.tables.len();
    if bytes <= lower::builder::MAX_UNIFORM_BYTES {
        return None;
    }
    let map = &compiled.source_map;
    let span = map.params.first().or(map.layers.first()).or(map.name.as_ref()).copied().unwrap_or_default();
    let mut diagnostic = Diagnostic::error(
        diag::Code::TableBudget,
        format!(
            "the shader would look up {bytes} bytes of tables, more than the {} a uniform binding holds",
            lower::builder::MAX_UNIFORM_BYTES
        ),
        span,
        "runtime parameters make the shader read tables",
    );
    diagnostic.notes.push(
        "help: make some parameters literal: a table lookup whose arguments are all literal is baked into \
         the shader and reads no table"
            .to_string(),
    );
    Some(diagnostic)
}

/// Lowers and validates an already-checked material's library (for programs that build
/// [`Material`]s), with glazec's default bindings. Unlike [`compile_source`], it does not refuse a
/// material whose runtime table lookups exceed the uniform binding (`E0222`): a program that
/// builds such a material compares `2 * tables.len()` with [`lower::builder::MAX_UNIFORM_BYTES`].
///
/// # Errors
/// Only for a compiler bug (naga rejecting the generated IR).
pub fn compile_material(material: Material, source_map: SourceMap) -> Result<Compiled, validate::ValidateError> {
    compile_material_with(material, source_map, &lower::bindings::Choice::default()).map_err(|e| match e {
        BindError::Internal(e) => e,
        BindError::Clash(clash) => unreachable!("the default bindings are apart by construction: {clash}"),
    })
}

/// Why a material with chosen bindings produced nothing.
#[derive(Debug, thiserror::Error)]
pub enum BindError {
    #[error(transparent)]
    Clash(#[from] lower::bindings::Clash),
    #[error(transparent)]
    Internal(#[from] validate::ValidateError),
}

/// [`compile_material`] with the library's resources where `choice` puts them.
///
/// # Errors
/// Two resources would share a binding, or a compiler bug.
pub fn compile_material_with(
    material: Material,
    source_map: SourceMap,
    choice: &lower::bindings::Choice,
) -> Result<Compiled, BindError> {
    let lower::Library { library, layout, tables } = lower::lower_library(&material, choice)?;
    let library_info = validate::validate(&material.name, &library)?;
    // A material built by a program has no text; its model (whose `Debug` form prints every
    // field, floats exactly) stands in for it.
    let origin = Origin { file: None, hash: source_hash(format!("{material:?}").as_bytes()), scene: None };
    Ok(Compiled {
        material,
        origin,
        source_map,
        library,
        library_info,
        layout,
        tables,
        choice: *choice,
        harness: std::sync::OnceLock::new(),
    })
}

impl Compiled {
    /// Whether the library reads its table uniform (then bind [`Compiled::tables_bytes`] at
    /// `layout.tables`).
    pub fn uses_tables(&self) -> bool {
        self.layout.tables.is_some()
    }

    /// The bytes of the table uniform: the tables this material reads (empty when none).
    pub fn tables_bytes(&self) -> Vec<u8> {
        if self.uses_tables() { lower::builder::table_bytes(&self.tables) } else { Vec::new() }
    }

    /// The same material with its library's resources where `choice` puts them (the origin is
    /// kept). With the default choice, a copy.
    ///
    /// # Errors
    /// Two resources would share a binding, or a compiler bug.
    pub fn with_bindings(&self, choice: &lower::bindings::Choice) -> Result<Compiled, BindError> {
        let mut rebound = compile_material_with(self.material.clone(), self.source_map.clone(), choice)?;
        rebound.origin = self.origin.clone();
        Ok(rebound)
    }

    /// glazec's harness on the library, lowered and validated on first use.
    ///
    /// # Errors
    /// Only for a compiler bug (naga rejecting the generated IR).
    pub fn harness(&self) -> Result<&Harness, validate::ValidateError> {
        if let Some(harness) = self.harness.get() {
            return Ok(harness);
        }
        let lowered = lower::lower_with(&self.material, &self.choice)
            .unwrap_or_else(|clash| unreachable!("the library was lowered with these bindings: {clash}"));
        let info = validate::validate(&self.material.name, &lowered.module)?;
        let harness = Harness { module: lowered.module, info, layout: lowered.layout };
        Ok(self.harness.get_or_init(|| harness))
    }

    /// The library and glazec's harness in WGSL, concatenated: the whole module as one source
    /// (what glazec's runner compiles on the WGSL path).
    ///
    /// # Errors
    /// Only for a compiler bug.
    pub fn whole_wgsl(&self) -> Result<String, emit::EmitError> {
        let files = self.emit_with_harness(&[Target::Wgsl])?;
        Ok(files
            .iter()
            .filter(|a| a.file_name.ends_with(".wgsl"))
            .map(|a| String::from_utf8_lossy(&a.contents).into_owned())
            .collect::<Vec<_>>()
            .join("\n"))
    }

    /// Emits the library's files for `targets` (what a host imports), and the table uniform's
    /// contents (`<m>.tables.bin`) when the library reads it. SPIR-V, which holds entry points,
    /// is the one target written from glazec's harness.
    ///
    /// # Errors
    /// Only for a compiler bug; a validated module is expected to emit.
    pub fn emit(&self, targets: &[Target]) -> Result<Vec<Artifact>, emit::EmitError> {
        self.emit_files(targets, false)
    }

    /// [`Compiled::emit`] and glazec's harness files beside the libraries (see [`emit`] for
    /// which).
    ///
    /// # Errors
    /// Only for a compiler bug.
    pub fn emit_with_harness(&self, targets: &[Target]) -> Result<Vec<Artifact>, emit::EmitError> {
        self.emit_files(targets, true)
    }

    /// [`Compiled::emit_with_harness`] when `with_harness`, else [`Compiled::emit`] (for callers
    /// that take the choice as an option: `--harness`, `Build::harness`).
    ///
    /// # Errors
    /// Only for a compiler bug.
    pub fn emit_files(&self, targets: &[Target], with_harness: bool) -> Result<Vec<Artifact>, emit::EmitError> {
        let harness = if with_harness || targets.contains(&Target::Spv) {
            let harness = self.harness()?;
            Some(emit::HarnessModule { module: &harness.module, info: &harness.info, files: with_harness })
        } else {
            None
        };
        let modules =
            emit::Modules { library: &self.library, library_info: &self.library_info, layout: &self.layout, harness };
        let mut artifacts = emit::emit(&self.material.name, &self.origin, modules, targets)?;
        if self.uses_tables() {
            artifacts.push(Artifact {
                file_name: format!("{}.tables.bin", self.material.name),
                contents: self.tables_bytes(),
                stage: None,
                harness: false,
            });
        }
        Ok(artifacts)
    }
}
