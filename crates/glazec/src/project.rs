//! A set of material files compiled together: what the CLI's `compile`, the [`crate::build`] API
//! and the [`crate::snapshot`] helper share.
//!
//! **Input:** a [`Project`]: paths (files or directories of `*.ron`), an optional scene, an
//! output directory and targets. **Output:** an [`Outcome`] holding every material compiled (and
//! simplified for the scene), the notes and reports to show, and the planned output files
//! (shaders per material folder plus the table file when a shader binds it), ready for
//! [`crate::output::write_all`] or [`crate::output::drift`]; or every file's diagnostics. A front
//! end renders either once.
//!
//! Beyond what one file can check, a set checks that material names are unique: a name is a
//! folder and a shader symbol, so two files declaring one name would overwrite each other.

use std::collections::BTreeMap;

use rayon::prelude::*;
use std::path::{Path, PathBuf};

use crate::diag::{Code, Diagnostic, Source};
use crate::lower::bindings::Choice;
use crate::output::{self, OutputFile};
use crate::{CompileError, Compiled, Target};

/// A material file and its text.
#[derive(Clone, Debug)]
pub struct SourceFile {
    pub path: PathBuf,
    pub text: String,
}

impl SourceFile {
    /// The path as diagnostics name it.
    pub fn name(&self) -> String {
        self.path.display().to_string()
    }

    /// The file name that generated headers record (no directory).
    pub fn file_name(&self) -> String {
        self.path.file_name().map_or_else(|| self.name(), |n| n.to_string_lossy().into_owned())
    }
}

/// A path could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("cannot read {}", .path.display())]
    Io { path: PathBuf, source: std::io::Error },
    #[error("no .ron files in {}", .0.display())]
    Empty(PathBuf),
    #[error("{} is {size} bytes; sources of at most {} bytes are read", .path.display(), crate::parse::MAX_SOURCE_BYTES)]
    TooLarge { path: PathBuf, size: u64 },
}

/// The `*.ron` files directly inside `dir` (materials or scenes), sorted by name.
///
/// # Errors
/// The directory cannot be listed, or holds no `.ron` file.
pub fn material_files(dir: &Path) -> Result<Vec<PathBuf>, ReadError> {
    let io = |source| ReadError::Io { path: dir.to_path_buf(), source };
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        if path.extension().is_some_and(|e| e == "ron") && path.is_file() {
            files.push(path);
        }
    }
    if files.is_empty() {
        return Err(ReadError::Empty(dir.to_path_buf()));
    }
    files.sort();
    Ok(files)
}

/// Reads `paths`, expanding each directory to its [`material_files`].
///
/// # Errors
/// The first path that cannot be read.
pub fn read(paths: &[PathBuf]) -> Result<Vec<SourceFile>, ReadError> {
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() { files.extend(material_files(path)?) } else { files.push(path.clone()) }
    }
    files.into_iter().map(|path| read_file(&path)).collect()
}

/// Reads one source file, refusing one larger than [`crate::parse::MAX_SOURCE_BYTES`] before
/// reading it.
fn read_file(path: &Path) -> Result<SourceFile, ReadError> {
    let io = |source| ReadError::Io { path: path.to_path_buf(), source };
    let size = std::fs::metadata(path).map_err(io)?.len();
    if size > crate::parse::MAX_SOURCE_BYTES as u64 {
        return Err(ReadError::TooLarge { path: path.to_path_buf(), size });
    }
    let text = std::fs::read_to_string(path).map_err(io)?;
    Ok(SourceFile { path: path.to_path_buf(), text })
}

/// One file's diagnostics (errors, or notes), with the file they point into.
#[derive(Clone, Debug)]
pub struct FileDiagnostics {
    pub file: SourceFile,
    pub diagnostics: Vec<Diagnostic>,
}

impl FileDiagnostics {
    /// Rendered as plain text (codespan-reporting, no colour).
    pub fn render_plain(&self) -> String {
        crate::diag::render_plain(Source { name: &self.file.name(), text: &self.file.text }, &self.diagnostics)
    }
}

/// Why a set of files produced nothing.
#[derive(Debug, thiserror::Error)]
pub enum ProjectError {
    #[error(transparent)]
    Read(#[from] ReadError),
    /// Problems in the files' text (materials, then the scene), per file in input order.
    #[error("{} file(s) with errors", .0.len())]
    Diagnostics(Vec<FileDiagnostics>),
    /// A bug in glazec: naga rejected IR that `lower` built.
    #[error("glazec internal error: naga rejected the generated IR")]
    Validate(#[from] crate::validate::ValidateError),
    /// A bug in glazec or naga: a backend failed on a validated module.
    #[error("glazec internal error: a backend failed")]
    Emit(#[from] crate::emit::EmitError),
    /// The chosen bindings put two of a material's resources in one place.
    #[error("material `{material}`")]
    Bind { material: String, source: crate::lower::bindings::Clash },
    /// The outputs could not be written ([`Project::write`]); nothing was.
    #[error("cannot write to {}", .path.display())]
    Write { path: PathBuf, source: std::io::Error },
}

/// Compiles every file; fails with every file's diagnostics if any has errors (including a
/// material name declared by two files).
///
/// # Errors
/// See [`ProjectError`].
pub fn compile(files: &[SourceFile]) -> Result<Vec<Compiled>, ProjectError> {
    let results: Vec<Result<Compiled, CompileError>> =
        files.par_iter().map(|file| crate::compile_source(Some(&file.file_name()), &file.text)).collect();
    let mut compiled: Vec<(usize, Compiled)> = Vec::new();
    let mut failed: BTreeMap<usize, Vec<Diagnostic>> = BTreeMap::new();
    for (index, result) in results.into_iter().enumerate() {
        match result {
            Ok(c) => compiled.push((index, c)),
            Err(CompileError::Diagnostics(diagnostics)) => {
                failed.insert(index, diagnostics);
            }
            Err(CompileError::Internal(e)) => return Err(ProjectError::Validate(e)),
        }
    }
    let names: Vec<(usize, &str, crate::diag::Span)> = compiled
        .iter()
        .map(|(index, c)| (*index, c.material.name.as_str(), c.source_map.name.unwrap_or_default()))
        .collect();
    for (index, d) in duplicate_names(files, &names) {
        failed.entry(index).or_default().push(d);
    }
    if failed.is_empty() { Ok(compiled.into_iter().map(|(_, c)| c).collect()) } else { Err(failures(files, failed)) }
}

/// `E0105` for every material (file index, name, the name's span) whose name an earlier file
/// already declared.
fn duplicate_names(files: &[SourceFile], names: &[(usize, &str, crate::diag::Span)]) -> Vec<(usize, Diagnostic)> {
    let mut first_by_name: BTreeMap<&str, usize> = BTreeMap::new();
    let mut found = Vec::new();
    for &(index, name, span) in names {
        if let Some(first) = first_by_name.insert(name, index) {
            let d = Diagnostic::error(
                Code::DuplicateMaterial,
                format!("material `{name}` is also defined in {}", files[first].name()),
                span,
                "a second material with this name",
            )
            .with_help("material names must be unique: they name the output directory and shader symbols");
            found.push((index, d));
        }
    }
    found
}

fn failures(files: &[SourceFile], failed: BTreeMap<usize, Vec<Diagnostic>>) -> ProjectError {
    ProjectError::Diagnostics(
        failed
            .into_iter()
            .map(|(index, diagnostics)| FileDiagnostics { file: files[index].clone(), diagnostics })
            .collect(),
    )
}

/// The files `compiled` materials produce under `out_dir`: `<material>/<artifact>` for each
/// target (with the material's table file when its library reads tables, and glazec's harness
/// files with `harness`), their resources where `bindings` puts them.
///
/// # Errors
/// Two resources would share a binding, or a backend error (a bug: validated modules are
/// expected to emit).
pub fn plan(
    out_dir: &Path,
    compiled: &[&Compiled],
    targets: &[Target],
    bindings: &Choice,
    harness: bool,
) -> Result<Vec<OutputFile>, ProjectError> {
    let planned: Vec<Vec<OutputFile>> =
        compiled.par_iter().map(|c| plan_one(out_dir, c, targets, bindings, harness)).collect::<Result<_, _>>()?;
    Ok(planned.into_iter().flatten().collect())
}

/// [`plan`] for one material.
fn plan_one(
    out_dir: &Path,
    c: &Compiled,
    targets: &[Target],
    bindings: &Choice,
    harness: bool,
) -> Result<Vec<OutputFile>, ProjectError> {
    let artifacts = if *bindings == Choice::default() {
        c.emit_files(targets, harness)?
    } else {
        let rebound = c.with_bindings(bindings).map_err(|e| match e {
            crate::BindError::Clash(source) => ProjectError::Bind { material: c.material.name.clone(), source },
            crate::BindError::Internal(e) => ProjectError::Validate(e),
        })?;
        rebound.emit_files(targets, harness)?
    };
    Ok(output::plan(out_dir, &c.material.name, artifacts))
}

/// Every file's diagnostics rendered as plain text (codespan-reporting, no colour).
pub fn render_plain(failed: &[FileDiagnostics]) -> String {
    failed.iter().map(FileDiagnostics::render_plain).collect()
}

/// A scene file, read and checked.
#[derive(Clone, Debug)]
pub struct SceneFile {
    pub source: SourceFile,
    pub scene: crate::scene::Scene,
}

/// Reads and checks a scene file.
///
/// # Errors
/// [`ProjectError::Read`] if it cannot be read; [`ProjectError::Diagnostics`] with the scene's.
pub fn read_scene(path: &Path) -> Result<SceneFile, ProjectError> {
    let source = read_file(path)?;
    let checked = crate::parse::parse(&source.text).map_err(|d| vec![d]).and_then(|v| crate::check::check_scene(&v));
    match checked {
        Ok(scene) => Ok(SceneFile { source, scene }),
        Err(diagnostics) => Err(ProjectError::Diagnostics(vec![FileDiagnostics { file: source, diagnostics }])),
    }
}

/// `compiled` materials simplified for a scene, each with its report; every output header
/// names the scene file.
///
/// # Errors
/// Diagnostics against the scene file (`E0303`, `E0304`), or a compiler bug.
pub fn simplify_all(
    compiled: &[Compiled],
    scene: &SceneFile,
) -> Result<Vec<(Compiled, crate::simplify::Report)>, ProjectError> {
    let materials: Vec<&crate::Material> = compiled.iter().map(|c| &c.material).collect();
    let mut diagnostics = crate::check::check_scene_params(&scene.scene, &materials);
    let mut out = Vec::new();
    for c in compiled {
        match crate::simplify::simplify(&c.material, &scene.scene) {
            Ok((material, report)) => {
                let mut simplified = crate::compile_material(material, c.source_map.clone())?;
                simplified.origin = c.origin.clone();
                simplified.origin.scene =
                    Some((scene.source.file_name(), crate::source_hash(scene.source.text.as_bytes())));
                out.push((simplified, report));
            }
            Err(d) => diagnostics.extend(d),
        }
    }
    if diagnostics.is_empty() {
        Ok(out)
    } else {
        diagnostics.sort_by_key(|d| d.primary_span().start);
        Err(ProjectError::Diagnostics(vec![FileDiagnostics { file: scene.source.clone(), diagnostics }]))
    }
}

/// The report file of a simplified material: `<out_dir>/<material>/<material>.simplify.md`
/// (with the explanation of what was kept).
pub fn report_file(out_dir: &Path, report: &crate::simplify::Report) -> OutputFile {
    OutputFile {
        path: out_dir.join(&report.material).join(format!("{}.simplify.md", report.material)),
        contents: report.markdown(true).into_bytes(),
    }
}

/// A set of material files to compile together, optionally simplified for a scene: what
/// `glazec compile`, `glazec preview` and [`crate::snapshot`] ask for.
#[derive(Clone, Debug)]
pub struct Project {
    /// Material files or directories of them.
    pub inputs: Vec<PathBuf>,
    /// A scene to simplify every material for (`compile --scene`).
    pub scene: Option<PathBuf>,
    /// Where [`Outcome::files`] are planned.
    pub out_dir: PathBuf,
    pub targets: Vec<Target>,
    /// Where the libraries' resources are bound (`compile --bind`).
    pub bindings: Choice,
    /// Whether glazec's harness files are written beside the libraries (`compile --harness`).
    pub harness: bool,
}

/// What a [`Project`] produced, for a front end to render and write.
pub struct Outcome {
    /// Every material as compiled from its file, in input order.
    pub compiled: Vec<Compiled>,
    /// With a scene: each material simplified for it, with its report (else empty).
    pub simplified: Vec<(Compiled, crate::simplify::Report)>,
    /// Notes that never fail a compilation (the coefficients a `Measured` layer derived).
    pub notes: Vec<FileDiagnostics>,
    /// The files to write or compare: the shaders (of the simplified materials, with a scene),
    /// each material's table file when its library reads tables, and the simplification reports.
    pub files: Vec<OutputFile>,
}

impl Outcome {
    /// The materials the files were generated from: simplified with a scene, else as compiled.
    pub fn generated(&self) -> Vec<&Compiled> {
        if self.simplified.is_empty() {
            self.compiled.iter().collect()
        } else {
            self.simplified.iter().map(|(c, _)| c).collect()
        }
    }
}

impl Project {
    /// Reads, compiles, simplifies (with a scene) and plans every output file.
    ///
    /// # Errors
    /// An unreadable path, every file's diagnostics (materials first, then the scene's), or a
    /// compiler bug.
    pub fn compile(&self) -> Result<Outcome, ProjectError> {
        let files = read(&self.inputs)?;
        let compiled = compile(&files)?;
        let notes = files
            .iter()
            .zip(&compiled)
            .filter(|(_, c)| !c.source_map.notes.is_empty())
            .map(|(file, c)| FileDiagnostics { file: file.clone(), diagnostics: c.source_map.notes.clone() })
            .collect();
        let simplified = match &self.scene {
            Some(path) => simplify_all(&compiled, &read_scene(path)?)?,
            None => Vec::new(),
        };
        let mut outcome = Outcome { compiled, simplified, notes, files: Vec::new() };
        let mut files = plan(&self.out_dir, &outcome.generated(), &self.targets, &self.bindings, self.harness)?;
        files.extend(outcome.simplified.iter().map(|(_, report)| report_file(&self.out_dir, report)));
        outcome.files = files;
        Ok(outcome)
    }
}

/// What [`Project::write`] wrote.
#[derive(Debug)]
pub struct Written {
    pub materials: usize,
    pub files: usize,
    /// Notes that never fail a compilation, per file with any.
    pub notes: Vec<FileDiagnostics>,
}

/// One file's part of [`Project::write`]: its material's name (and the name's span) and staged
/// outputs, or its diagnostics.
enum Streamed {
    Staged { name: String, span: crate::diag::Span, staged: Vec<output::Staged>, notes: Vec<Diagnostic> },
    Failed(Vec<Diagnostic>),
}

impl Project {
    /// Compiles every material and writes its outputs, all or nothing, without a scene: each
    /// file is compiled, emitted and its outputs staged on disk ([`output::stage`]) on every
    /// core, one material per core in memory at a time, and only when every file has compiled
    /// are the outputs renamed into place. Memory does not grow with the number of files
    /// (beyond their texts and the staged files' names).
    ///
    /// # Errors
    /// As [`Project::compile`]; [`ProjectError::Write`] if an output cannot be staged or renamed.
    pub fn write(&self) -> Result<Written, ProjectError> {
        let files = read(&self.inputs)?;
        let written = |path: &Path| {
            let path = path.to_path_buf();
            move |source| ProjectError::Write { path, source }
        };
        let streamed: Vec<Result<Streamed, ProjectError>> = files
            .par_iter()
            .map(|file| {
                let c = match crate::compile_source(Some(&file.file_name()), &file.text) {
                    Ok(c) => c,
                    Err(CompileError::Diagnostics(d)) => return Ok(Streamed::Failed(d)),
                    Err(CompileError::Internal(e)) => return Err(ProjectError::Validate(e)),
                };
                let planned = plan_one(&self.out_dir, &c, &self.targets, &self.bindings, self.harness)?;
                let mut staged = Vec::with_capacity(planned.len());
                for f in &planned {
                    match output::stage(f) {
                        Ok(s) => staged.push(s),
                        Err(e) => {
                            output::abandon(staged);
                            return Err(written(&f.path)(e));
                        }
                    }
                }
                let span = c.source_map.name.unwrap_or_default();
                Ok(Streamed::Staged { name: c.material.name, span, staged, notes: c.source_map.notes })
            })
            .collect();
        let (mut ok, mut error) = (Vec::with_capacity(streamed.len()), None);
        for result in streamed {
            match result {
                Ok(s) => ok.push(s),
                Err(e) => error = error.or(Some(e)),
            }
        }
        let streamed = ok;
        if let Some(e) = error {
            abandon(streamed);
            return Err(e);
        }
        let mut failed: BTreeMap<usize, Vec<Diagnostic>> = BTreeMap::new();
        let mut names = Vec::new();
        for (index, s) in streamed.iter().enumerate() {
            match s {
                Streamed::Staged { name, span, .. } => names.push((index, name.as_str(), *span)),
                Streamed::Failed(d) => {
                    failed.insert(index, d.clone());
                }
            }
        }
        for (index, d) in duplicate_names(&files, &names) {
            failed.entry(index).or_default().push(d);
        }
        if !failed.is_empty() {
            abandon(streamed);
            return Err(failures(&files, failed));
        }
        let mut written_files = 0;
        let mut notes = Vec::new();
        for (file, s) in files.iter().zip(streamed) {
            if let Streamed::Staged { staged, notes: n, .. } = s {
                written_files += staged.len();
                for f in staged {
                    let path = f.path().to_path_buf();
                    f.persist().map_err(written(&path))?;
                }
                if !n.is_empty() {
                    notes.push(FileDiagnostics { file: file.clone(), diagnostics: n });
                }
            }
        }
        Ok(Written { materials: files.len(), files: written_files, notes })
    }
}

/// Removes what [`Project::write`] staged for `streamed` (see [`output::abandon`]).
fn abandon(streamed: Vec<Streamed>) {
    let staged = streamed.into_iter().flat_map(|s| match s {
        Streamed::Staged { staged, .. } => staged,
        Streamed::Failed(_) => Vec::new(),
    });
    output::abandon(staged.collect());
}
