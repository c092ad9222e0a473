//! The `build.rs` API: compile a directory of materials into `OUT_DIR` as part of a cargo build.
//!
//! Depend on `glazec` (the core crate has no features, and no wgpu or CLI in its tree):
//!
//! ```toml
//! [build-dependencies]
//! glazec = "0.1"
//! [dependencies]
//! bytemuck = "1"   # the generated parameter structs are `Pod`
//! ```
//!
//! ```no_run
//! // build.rs, in `fn main`:
//! glazec::build::Build::new("materials").run();
//! ```
//!
//! ```ignore
//! // src/main.rs
//! mod materials {
//!     include!(concat!(env!("OUT_DIR"), "/glazec_materials.rs"));
//! }
//! let params = materials::tunable_glaze::Params { glaze_roughness: 0.3, ..Default::default() };
//! queue.write_buffer(&buffer, 0, bytemuck::bytes_of(&params));
//! ```
//!
//! [`Build::run`] does what a build script must: it prints `cargo:rerun-if-changed` for the
//! directory and every material file (before compiling, so that fixing a broken file reruns
//! it), writes the shaders to `OUT_DIR/glazec/<material>/` and the Rust module
//! `OUT_DIR/glazec_materials.rs` (see `rust_module` for what it holds), and reports each
//! diagnostic as one `cargo:warning` line; on errors it prints the full rendered report to
//! stderr (which cargo shows for a failed build script) and exits with status 1. Nothing is
//! written unless every material compiles. [`Build::generate`] is the same without the cargo
//! protocol, for tools and tests.

mod bevy;
#[allow(dead_code, clippy::all)]
pub(crate) mod prelude;
mod rust_module;

use std::path::{Path, PathBuf};

use crate::Target;
use crate::diag::Source;
use crate::lower::bindings::{Choice, Resource, Slot};
use crate::output::{self, OutputFile};
use crate::project::{self, FileDiagnostics, ProjectError};

/// The generated Rust module's file name in the output directory.
pub const MODULE_FILE: &str = "glazec_materials.rs";
/// The folder of the generated shaders in the output directory.
pub const SHADER_DIR: &str = "glazec";

/// What to compile, and where.
#[derive(Clone, Debug)]
pub struct Build {
    materials: PathBuf,
    out_dir: Option<PathBuf>,
    targets: Vec<Target>,
    bytemuck: bool,
    bindings: Choice,
    /// Per material: choices that override `bindings`.
    material_bindings: Vec<(String, Resource, Slot)>,
    /// Bevy materials instead of the plain module (`Build::bevy`).
    bevy: bool,
    /// glazec's harness beside the libraries (`Build::harness`).
    harness: bool,
}

/// What [`Build::generate`] wrote.
#[derive(Clone, Debug)]
pub struct Generated {
    /// `OUT_DIR/glazec_materials.rs`.
    pub module: PathBuf,
    /// The material names, in file order.
    pub materials: Vec<String>,
    /// Every file written (shaders, table files, the module).
    pub files: Vec<PathBuf>,
}

/// Why nothing was generated.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    #[error(transparent)]
    Read(#[from] project::ReadError),
    /// Problems in the materials: one summary line per diagnostic (for `cargo:warning`) and the
    /// full rendered report.
    #[error("{report}")]
    Diagnostics { summaries: Vec<String>, report: String },
    /// The chosen bindings put two of a material's resources in one place.
    #[error("material `{material}`")]
    Bind { material: String, source: crate::lower::bindings::Clash },
    /// `Build::bind_material` named a material that no file declares.
    #[error("Build::bind_material names `{0}`, which no material file declares")]
    UnknownMaterial(String),
    #[error("OUT_DIR is not set: call Build::out_dir outside a build script")]
    NoOutDir,
    #[error("glazec internal error: {0}")]
    Internal(String),
    #[error("cannot write the generated files")]
    Write(#[from] std::io::Error),
}

impl Build {
    /// Compiles every `*.ron` in `materials` (relative to the package root in a build script)
    /// to WGSL, GLSL and HLSL, with `bytemuck` impls on the generated structs.
    pub fn new(materials: impl Into<PathBuf>) -> Self {
        Build {
            materials: materials.into(),
            out_dir: None,
            targets: Target::TEXT.to_vec(),
            bytemuck: true,
            bindings: Choice::default(),
            material_bindings: Vec::new(),
            bevy: false,
            harness: false,
        }
    }

    /// Bevy materials (Bevy 0.19): per material a type implementing Bevy's `Material` and a
    /// fragment shader that lights it with Bevy's own lights, in `OUT_DIR/glazec_bevy_materials.rs`
    /// (instead of `glazec_materials.rs`; see the `glazec_bevy` crate). The libraries' resources
    /// go to Bevy's material bind group (parameters at 0, tables at 1, sampler at 2, textures from
    /// 3) and only WGSL and its naga_oil flavour are generated.
    #[must_use]
    pub fn bevy(mut self) -> Self {
        self.bevy = true;
        self.bindings = bevy::choice();
        self.targets = vec![Target::Wgsl, Target::NagaOil];
        self
    }

    /// Binds `resource` of material `material`'s library at `slot`, over [`Build::bind`]: for a
    /// program that puts several materials' libraries into one shader, each material's
    /// parameters and tables at bindings of their own.
    #[must_use]
    pub fn bind_material(mut self, material: &str, resource: Resource, slot: Slot) -> Self {
        self.material_bindings.push((material.to_string(), resource, slot));
        self
    }

    /// The bindings of material `name`: [`Build::bind`]'s, then its own.
    fn choice_for(&self, name: &str) -> Choice {
        self.material_bindings
            .iter()
            .filter(|(m, ..)| m == name)
            .fold(self.bindings, |choice, &(_, resource, slot)| choice.with(resource, slot))
    }

    /// Binds `resource` of every material's library at `slot` (group, binding) instead of
    /// glazec's default; the module's `LIBRARY_BINDINGS` follow. E.g. a renderer that owns
    /// groups 0 and 1 puts the parameters (and the tables after them) in group 2:
    /// `.bind(Resource::Params, Slot::new(2, 0))`. Placing [`Resource::Environment`] also adds
    /// glazec's environment lookup, `<m>_ibl`, to the libraries.
    #[must_use]
    pub fn bind(mut self, resource: Resource, slot: Slot) -> Self {
        self.bindings = self.bindings.with(resource, slot);
        self
    }

    /// Which shader languages to generate (SPIR-V becomes a `&[u8]` constant).
    #[must_use]
    pub fn targets(mut self, targets: &[Target]) -> Self {
        self.targets = targets.to_vec();
        self
    }

    /// Whether to write glazec's harness beside each library (its `eval_pairs` kernel and
    /// preview pipelines, as `glazec compile --harness` does) and describe its pipelines in the
    /// Rust module (`WGSL_HARNESS`, `EVAL_PAIRS_BINDINGS`, `PREVIEW_BINDINGS`, …). Off by
    /// default: a host imports the libraries.
    #[must_use]
    pub fn harness(mut self, on: bool) -> Self {
        self.harness = on;
        self
    }

    /// Where to write (default: `$OUT_DIR`).
    #[must_use]
    pub fn out_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.out_dir = Some(dir.into());
        self
    }

    /// Whether the parameter structs implement `bytemuck::Pod` (needs `bytemuck` as a dependency
    /// of the crate that includes the module). On by default.
    #[must_use]
    pub fn bytemuck(mut self, on: bool) -> Self {
        self.bytemuck = on;
        self
    }

    /// For `build.rs`: generates, speaking cargo's build-script protocol (see the module docs).
    /// Exits the process with status 1 after printing the report if anything fails.
    pub fn run(&self) -> Generated {
        for line in self.rerun_if_changed() {
            println!("{line}");
        }
        match self.generate() {
            Ok(generated) => generated,
            Err(e) => {
                for line in cargo_warnings(&e) {
                    println!("{line}");
                }
                eprintln!("{e}");
                std::process::exit(1);
            }
        }
    }

    /// `cargo:rerun-if-changed` for the materials folder (cargo then watches everything in it,
    /// including files added later) and for each material file in it.
    pub fn rerun_if_changed(&self) -> Vec<String> {
        let mut lines = vec![format!("cargo:rerun-if-changed={}", self.materials.display())];
        if let Ok(files) = project::material_files(&self.materials) {
            lines.extend(files.iter().map(|f| format!("cargo:rerun-if-changed={}", f.display())));
        }
        lines
    }

    /// Compiles every material and writes the shaders and the Rust module, all or nothing.
    ///
    /// # Errors
    /// See [`BuildError`].
    pub fn generate(&self) -> Result<Generated, BuildError> {
        let out_dir = match &self.out_dir {
            Some(dir) => dir.clone(),
            None => std::env::var_os("OUT_DIR").map(PathBuf::from).ok_or(BuildError::NoOutDir)?,
        };
        let files = project::read(std::slice::from_ref(&self.materials))?;
        let compiled = project::compile(&files).map_err(|e| match e {
            ProjectError::Read(e) => BuildError::Read(e),
            ProjectError::Diagnostics(failed) => diagnostics_error(&failed),
            e => BuildError::Internal(crate::error_chain(&e)),
        })?;
        let out_dir = absolute(&out_dir)?;
        let shader_dir = out_dir.join(SHADER_DIR);
        let mut outputs: Vec<OutputFile> = Vec::new();
        if let Some((name, ..)) =
            self.material_bindings.iter().find(|(m, ..)| !compiled.iter().any(|c| c.material.name == *m))
        {
            return Err(BuildError::UnknownMaterial(name.clone()));
        }
        let mut rebound = Vec::new();
        for c in &compiled {
            rebound.push(c.with_bindings(&self.choice_for(&c.material.name)).map_err(|e| match e {
                crate::BindError::Clash(source) => BuildError::Bind { material: c.material.name.clone(), source },
                e => BuildError::Internal(crate::error_chain(&e)),
            })?);
        }
        let mut inputs = Vec::new();
        for (file, c) in files.iter().zip(&rebound) {
            let artifacts =
                c.emit_files(&self.targets, self.harness).map_err(|e| BuildError::Internal(crate::error_chain(&e)))?;
            let planned = output::plan(&shader_dir, &c.material.name, artifacts.clone());
            let written: Vec<_> = artifacts.into_iter().zip(planned.iter().map(|f| f.path.clone())).collect();
            outputs.extend(planned);
            inputs.push((std::fs::canonicalize(&file.path)?, c, written));
        }
        if self.bevy {
            return self.write_bevy(&out_dir, &shader_dir, outputs, &inputs);
        }
        let mut materials = Vec::new();
        for (source, compiled, artifacts) in &inputs {
            let harness = if self.harness {
                Some(compiled.harness().map_err(|e| BuildError::Internal(crate::error_chain(&e)))?)
            } else {
                None
            };
            materials.push(rust_module::MaterialInput { compiled, harness, source, artifacts: artifacts.clone() });
        }
        let module_path = out_dir.join(MODULE_FILE);
        let text = rust_module::module_text(&materials, self.bytemuck);
        outputs.push(OutputFile { path: module_path.clone(), contents: text.into_bytes() });
        output::write_all(&outputs)?;
        Ok(Generated {
            module: module_path,
            materials: compiled.iter().map(|c| c.material.name.clone()).collect(),
            files: outputs.into_iter().map(|f| f.path).collect(),
        })
    }
}

type Written<'a> = (PathBuf, &'a crate::Compiled, Vec<(crate::emit::Artifact, PathBuf)>);

impl Build {
    /// The Bevy flavour's files: each material's fragment shader and the Bevy module.
    fn write_bevy(
        &self,
        out_dir: &Path,
        shader_dir: &Path,
        mut outputs: Vec<OutputFile>,
        inputs: &[Written<'_>],
    ) -> Result<Generated, BuildError> {
        let mut materials = Vec::new();
        for (_, c, written) in inputs {
            let name = &c.material.name;
            let path_of = |suffix: &str| {
                written
                    .iter()
                    .find(|(a, _)| a.file_name == format!("{name}{suffix}"))
                    .map(|(_, p)| p.to_string_lossy().into_owned())
            };
            let library = path_of(".naga_oil.wgsl")
                .ok_or_else(|| BuildError::Internal(format!("no naga_oil library for `{name}`")))?;
            let fragment = shader_dir.join(name).join(bevy::fragment_file(name));
            outputs.push(OutputFile { path: fragment.clone(), contents: bevy::fragment_shader(c).into_bytes() });
            let tables = if c.uses_tables() { path_of(".tables.bin") } else { None };
            materials.push(bevy::BevyMaterial {
                compiled: c,
                library,
                fragment: fragment.to_string_lossy().into_owned(),
                tables,
            });
        }
        let module_path = out_dir.join(bevy::MODULE_FILE);
        outputs.push(OutputFile { path: module_path.clone(), contents: bevy::module_text(&materials).into_bytes() });
        output::write_all(&outputs)?;
        Ok(Generated {
            module: module_path,
            materials: inputs.iter().map(|(_, c, _)| c.material.name.clone()).collect(),
            files: outputs.into_iter().map(|f| f.path).collect(),
        })
    }
}

/// The `cargo:warning` lines for a failure: one per diagnostic, or one for anything else.
pub fn cargo_warnings(e: &BuildError) -> Vec<String> {
    match e {
        BuildError::Diagnostics { summaries, .. } => summaries.iter().map(|l| format!("cargo:warning={l}")).collect(),
        other => vec![format!("cargo:warning=glazec: {}", crate::error_chain(other).replace('\n', " "))],
    }
}

fn absolute(path: &Path) -> std::io::Result<PathBuf> {
    std::path::absolute(path)
}

/// One `file:line:col: error[code]: message` line per diagnostic, and the rendered report.
fn diagnostics_error(failed: &[FileDiagnostics]) -> BuildError {
    let mut summaries = Vec::new();
    for f in failed {
        let file = &f.file;
        let name = file.name();
        let source = Source { name: &name, text: &file.text };
        for d in &f.diagnostics {
            let (line, column) = source.line_col(d.primary_span().start);
            let severity = match d.severity {
                crate::diag::Severity::Error => "error",
                crate::diag::Severity::Warning => "warning",
                crate::diag::Severity::Note => "note",
            };
            summaries.push(format!("{name}:{line}:{column}: {severity}[{}]: {}", d.code, d.message));
        }
    }
    BuildError::Diagnostics { summaries, report: project::render_plain(failed) }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLAZE: &str = r#"Material(name: "glaze", layers: [
    Coat(lobe: Ggx(roughness: Param("glaze_roughness", 0.2)), ior: 1.5, absorption: Param("tint", (0.1, 0.2, 0.3))),
    Lambert(albedo: (0.5, 0.4, 0.3)),
])"#;
    const BAD: &str = "Material(name: \"bad\", layers: [Lambert(albedo: 7)])";

    fn materials(files: &[(&str, &str)]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().expect("temp dir");
        for (name, text) in files {
            std::fs::write(dir.path().join(name), text).expect("writes a material");
        }
        dir
    }

    #[test]
    fn generates_shaders_and_a_module_deterministically() {
        let sources = materials(&[("glaze.ron", GLAZE)]);
        let out = tempfile::tempdir().expect("temp dir");
        let build = Build::new(sources.path()).out_dir(out.path());
        let generated = build.generate().expect("generates");
        assert_eq!(generated.materials, ["glaze"]);
        let module = std::fs::read_to_string(&generated.module).expect("module written");
        for expected in [
            "pub mod glaze {",
            "pub struct GlazeParams {",
            "pub _pad0: [u32; 3],",
            // Each member says what its slots accept.
            "/// `f32` at byte 0; accepts [0, 1].",
            "/// `vec3<f32>` at byte 16; accepts [0, 1000000] per component.",
            "assert!(core::mem::offset_of!(GlazeParams, tint) == 16",
            "assert!(core::mem::size_of::<GlazeParams>() == 32",
            "unsafe impl bytemuck::Pod for GlazeParams {}",
            "pub const PREVIEW_BINDINGS: &[Binding] = &[",
            "glazec_source_hash(include_bytes!(",
        ] {
            assert!(module.contains(expected), "missing `{expected}` in\n{module}");
        }
        for file in &generated.files {
            assert!(file.is_absolute() && file.exists(), "{}", file.display());
        }
        let first: Vec<Vec<u8>> = generated.files.iter().map(|f| std::fs::read(f).expect("readable")).collect();
        let again = build.generate().expect("generates again");
        let second: Vec<Vec<u8>> = again.files.iter().map(|f| std::fs::read(f).expect("readable")).collect();
        assert_eq!(first, second, "byte-identical on a second run");
        let without = Build::new(sources.path()).out_dir(out.path()).bytemuck(false).generate().expect("generates");
        assert!(!std::fs::read_to_string(without.module).expect("written").contains("bytemuck"));
    }

    #[test]
    fn errors_become_one_warning_per_diagnostic_and_nothing_is_written() {
        let sources = materials(&[("glaze.ron", GLAZE), ("bad.ron", BAD)]);
        let out = tempfile::tempdir().expect("temp dir");
        let target = out.path().join("out");
        let error = Build::new(sources.path()).out_dir(&target).generate().expect_err("bad.ron has an error");
        let warnings = cargo_warnings(&error);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let bad = sources.path().join("bad.ron");
        assert!(warnings[0].starts_with(&format!("cargo:warning={}:1:", bad.display())), "{}", warnings[0]);
        assert!(warnings[0].contains("error[E0213]"), "{}", warnings[0]);
        let report = error.to_string();
        assert!(report.contains("error[E0213]") && report.contains("┌─"), "the full codespan report:\n{report}");
        assert!(!target.exists(), "nothing is written when a material has errors");
    }

    #[test]
    fn reruns_when_the_folder_or_any_material_changes() {
        let sources = materials(&[("glaze.ron", GLAZE), ("notes.txt", "not a material")]);
        let lines = Build::new(sources.path()).rerun_if_changed();
        let dir = sources.path().display();
        assert_eq!(lines, [format!("cargo:rerun-if-changed={dir}"), format!("cargo:rerun-if-changed={dir}/glaze.ron")]);
    }
}
