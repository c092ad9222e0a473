//! A set of material files compiled together: what the CLI's `compile`, the [`crate::build`] API
//! and the [`crate::snapshot`] helper share.
//!
//! **Input:** paths (files or directories of `*.ron`). **Output:** every material compiled, or
//! every file's diagnostics; then the planned output files (shaders per material folder plus the
//! table file when a shader binds it), ready for [`crate::output::write_all`] or
//! [`crate::output::drift`].
//!
//! Beyond what one file can check, a set checks that material names are unique: a name is a
//! folder and a shader symbol, so two files declaring one name would overwrite each other.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::diag::{Code, Diagnostic, Source};
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
    #[error("cannot read {}: {source}", .path.display())]
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

/// One file's problems.
#[derive(Clone, Debug)]
pub struct FileDiagnostics {
    /// Index into the files given to [`compile`].
    pub file: usize,
    pub diagnostics: Vec<Diagnostic>,
}

/// Why a set of files produced nothing.
#[derive(Debug, thiserror::Error)]
pub enum ProjectError {
    /// Problems in the files' text, per file in input order.
    #[error("{} file(s) with errors", .0.len())]
    Diagnostics(Vec<FileDiagnostics>),
    /// A bug in glazec: naga rejected IR that `lower` built.
    #[error(transparent)]
    Internal(#[from] crate::validate::ValidateError),
}

/// Compiles every file; fails with every file's diagnostics if any has errors (including a
/// material name declared by two files).
///
/// # Errors
/// See [`ProjectError`].
pub fn compile(files: &[SourceFile]) -> Result<Vec<Compiled>, ProjectError> {
    let mut compiled: Vec<(usize, Compiled)> = Vec::new();
    let mut failed: BTreeMap<usize, Vec<Diagnostic>> = BTreeMap::new();
    for (index, file) in files.iter().enumerate() {
        match crate::compile_source(Some(&file.file_name()), &file.text) {
            Ok(c) => compiled.push((index, c)),
            Err(CompileError::Diagnostics(diagnostics)) => {
                failed.insert(index, diagnostics);
            }
            Err(CompileError::Internal(e)) => return Err(ProjectError::Internal(e)),
        }
    }
    let mut first_by_name: BTreeMap<&str, usize> = BTreeMap::new();
    for (index, c) in &compiled {
        if let Some(first) = first_by_name.insert(&c.material.name, *index) {
            let span = c.source_map.name.unwrap_or_default();
            let d = Diagnostic::error(
                Code::DuplicateMaterial,
                format!("material `{}` is also defined in {}", c.material.name, files[first].name()),
                span,
                "a second material with this name",
            )
            .with_help("material names must be unique: they name the output directory and shader symbols");
            failed.entry(*index).or_default().push(d);
        }
    }
    if failed.is_empty() {
        Ok(compiled.into_iter().map(|(_, c)| c).collect())
    } else {
        Err(ProjectError::Diagnostics(
            failed.into_iter().map(|(file, diagnostics)| FileDiagnostics { file, diagnostics }).collect(),
        ))
    }
}

/// The files `compiled` materials produce under `out_dir`: `<material>/<artifact>` for each
/// target, plus [`output::TABLES_FILE`] when any shader binds the table buffer.
///
/// # Errors
/// A backend error (a bug: validated modules are expected to emit).
pub fn plan(
    out_dir: &Path,
    compiled: &[Compiled],
    targets: &[Target],
) -> Result<Vec<OutputFile>, crate::emit::EmitError> {
    let mut files = Vec::new();
    for c in compiled {
        files.extend(output::plan(out_dir, &c.material.name, c.emit(targets)?));
    }
    if compiled.iter().any(Compiled::uses_tables) {
        files.push(output::tables_file(out_dir));
    }
    Ok(files)
}

/// Every file's diagnostics rendered as plain text (codespan-reporting, no colour).
pub fn render_plain(files: &[SourceFile], failed: &[FileDiagnostics]) -> String {
    failed
        .iter()
        .map(|f| {
            let file = &files[f.file];
            crate::diag::render_plain(Source { name: &file.name(), text: &file.text }, &f.diagnostics)
        })
        .collect()
}

/// A scene file, read and checked.
#[derive(Clone, Debug)]
pub struct SceneFile {
    pub source: SourceFile,
    pub scene: crate::scene::Scene,
}

/// Reads and checks a scene file; diagnostics come back with the file for rendering.
///
/// # Errors
/// [`ReadError`] if it cannot be read; otherwise the file and its diagnostics.
pub fn read_scene(path: &Path) -> Result<Result<SceneFile, (SourceFile, Vec<Diagnostic>)>, ReadError> {
    let source = read_file(path)?;
    let checked = crate::parse::parse(&source.text).map_err(|d| vec![d]).and_then(|v| crate::check::check_scene(&v));
    Ok(match checked {
        Ok(scene) => Ok(SceneFile { source, scene }),
        Err(diagnostics) => Err((source, diagnostics)),
    })
}

/// Why materials could not be simplified for a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Problems in the scene file, for these materials.
    #[error("{} error(s) in the scene", .0.len())]
    Diagnostics(Vec<Diagnostic>),
    #[error(transparent)]
    Internal(#[from] crate::validate::ValidateError),
}

/// `compiled` materials simplified for a scene, each with its report; every output header
/// names the scene file.
///
/// # Errors
/// Diagnostics against the scene file (`E0303`, `E0304`), or a compiler bug.
pub fn simplify_all(
    compiled: &[Compiled],
    scene: &SceneFile,
) -> Result<Vec<(Compiled, crate::simplify::Report)>, SceneError> {
    let materials: Vec<&crate::Material> = compiled.iter().map(|c| &c.material).collect();
    let mut diagnostics = crate::simplify::check_scene_params(&scene.scene, &materials);
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
        Err(SceneError::Diagnostics(diagnostics))
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
