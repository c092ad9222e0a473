//! Golden-shader snapshot tests for users' own materials.
//!
//! A project keeps the shaders glazec generates for its materials in a directory under version
//! control; a test asserts that they are still exactly what the materials produce, so a changed
//! material (or a new glazec) shows up in review as a shader diff:
//!
//! ```no_run
//! #[test]
//! fn shaders_are_current() {
//!     glazec::snapshot::Snapshot::new("materials", "shaders").assert_current();
//! }
//! ```
//!
//! On a mismatch the test fails with a unified diff per file (and lists files no material
//! produces any more); with `GLAZEC_BLESS=1` in the environment it rewrites the directory
//! instead, atomically, and removes those stale files. glazec's own `generated/` is tested this
//! way (`tests/golden.rs`).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::Target;
use crate::output::{self, OutputFile};
use crate::project::{self, ProjectError};

/// The environment variable that turns [`Snapshot::assert_current`] into [`Snapshot::bless`].
pub const BLESS_VAR: &str = "GLAZEC_BLESS";

/// A materials directory and the directory holding its expected shaders.
#[derive(Clone, Debug)]
pub struct Snapshot {
    materials: PathBuf,
    expected: PathBuf,
    targets: Vec<Target>,
    scene: Option<PathBuf>,
}

/// Why a snapshot is not current.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    /// A material does not compile: the rendered diagnostics.
    #[error("the materials do not compile:\n{0}")]
    Diagnostics(String),
    /// Files differ, are missing, or are stale: a unified diff per file.
    #[error("{count} file(s) differ from what the materials generate (set {BLESS_VAR}=1 to update):\n{report}")]
    Drift { count: usize, report: String },
    #[error(transparent)]
    Read(#[from] project::ReadError),
    #[error("{0}")]
    Internal(String),
    #[error("cannot update the snapshot: {0}")]
    Write(#[from] std::io::Error),
}

impl Snapshot {
    /// Compares `expected` with what every `materials/*.ron` generates, in WGSL, GLSL and HLSL.
    pub fn new(materials: impl Into<PathBuf>, expected: impl Into<PathBuf>) -> Self {
        Snapshot { materials: materials.into(), expected: expected.into(), targets: Target::TEXT.to_vec(), scene: None }
    }

    /// Snapshots the materials simplified for a scene (`compile --scene`), with each material's
    /// `.simplify.md` report.
    #[must_use]
    pub fn scene(mut self, scene: impl Into<PathBuf>) -> Self {
        self.scene = Some(scene.into());
        self
    }

    /// Which targets the snapshot holds.
    #[must_use]
    pub fn targets(mut self, targets: &[Target]) -> Self {
        self.targets = targets.to_vec();
        self
    }

    /// The files the materials generate, under the expected directory.
    ///
    /// # Errors
    /// Unreadable materials, diagnostics, or a compiler bug.
    pub fn planned(&self) -> Result<Vec<OutputFile>, SnapshotError> {
        let files = project::read(std::slice::from_ref(&self.materials))?;
        let compiled = project::compile(&files).map_err(|e| match e {
            ProjectError::Diagnostics(failed) => SnapshotError::Diagnostics(project::render_plain(&files, &failed)),
            ProjectError::Internal(e) => SnapshotError::Internal(e.to_string()),
        })?;
        let Some(scene_path) = &self.scene else {
            return project::plan(&self.expected, &compiled, &self.targets)
                .map_err(|e| SnapshotError::Internal(e.to_string()));
        };
        let scene = project::read_scene(scene_path)?.map_err(|(source, d)| {
            SnapshotError::Diagnostics(crate::diag::render_plain(
                crate::diag::Source { name: &source.name(), text: &source.text },
                &d,
            ))
        })?;
        let simplified = project::simplify_all(&compiled, &scene).map_err(|e| match e {
            project::SceneError::Diagnostics(d) => SnapshotError::Diagnostics(crate::diag::render_plain(
                crate::diag::Source { name: &scene.source.name(), text: &scene.source.text },
                &d,
            )),
            project::SceneError::Internal(e) => SnapshotError::Internal(e.to_string()),
        })?;
        let (compiled, reports): (Vec<_>, Vec<_>) = simplified.into_iter().unzip();
        let mut files = project::plan(&self.expected, &compiled, &self.targets)
            .map_err(|e| SnapshotError::Internal(e.to_string()))?;
        files.extend(reports.iter().map(|r| project::report_file(&self.expected, r)));
        Ok(files)
    }

    /// Whether the expected directory holds exactly the generated files.
    ///
    /// # Errors
    /// [`SnapshotError::Drift`] with a diff per file, or why nothing could be generated.
    pub fn check(&self) -> Result<(), SnapshotError> {
        let planned = self.planned()?;
        let mut report = String::new();
        let mut count = 0;
        for file in &planned {
            let diff = output::unified_diff(file);
            if !diff.is_empty() {
                count += 1;
                report.push_str(&diff);
            }
        }
        for path in stale(&self.expected, &planned) {
            count += 1;
            report.push_str(&format!("stale: {} is not generated by any material\n", path.display()));
        }
        if count == 0 { Ok(()) } else { Err(SnapshotError::Drift { count, report }) }
    }

    /// Rewrites the expected directory (all files or none) and removes stale files; returns how
    /// many files it holds.
    ///
    /// # Errors
    /// Why nothing could be generated, or an I/O error.
    pub fn bless(&self) -> Result<usize, SnapshotError> {
        let planned = self.planned()?;
        output::write_all(&planned)?;
        for path in stale(&self.expected, &planned) {
            std::fs::remove_file(path)?;
        }
        Ok(planned.len())
    }

    /// For tests: [`Snapshot::bless`] when `GLAZEC_BLESS=1`, otherwise [`Snapshot::check`].
    ///
    /// # Panics
    /// When the snapshot is not current (with the diff), or cannot be updated.
    pub fn assert_current(&self) {
        let blessing = std::env::var(BLESS_VAR).is_ok_and(|v| v == "1");
        let result = if blessing { self.bless().map(|_| ()) } else { self.check() };
        if let Err(e) = result {
            panic!("snapshot {} of {}: {e}", self.expected.display(), self.materials.display());
        }
    }
}

/// Files in `dir` (and its material folders, one level down) that `planned` does not include.
/// Folders one level down are not looked into.
fn stale(dir: &Path, planned: &[OutputFile]) -> Vec<PathBuf> {
    let planned: BTreeSet<&Path> = planned.iter().map(|f| f.path.as_path()).collect();
    let mut found = BTreeSet::new();
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_dir() {
            // Files only: a folder here (`generated/scenes/<scene>/`) is another snapshot's.
            found.extend(
                std::fs::read_dir(&path).into_iter().flatten().flatten().map(|e| e.path()).filter(|p| p.is_file()),
            );
        } else {
            found.insert(path);
        }
    }
    found.into_iter().filter(|p| !planned.contains(p.as_path()) && !is_hidden(p)).collect()
}

/// Dot files (`.gitignore`, editors' files) are not outputs.
fn is_hidden(path: &Path) -> bool {
    path.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.'))
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLAZE: &str = r#"Material(name: "glaze", layers: [Coat(lobe: Ggx(roughness: 0.2), ior: 1.5), Lambert(albedo: (0.5, 0.4, 0.3))])"#;

    #[test]
    fn detects_edits_missing_and_stale_files_and_blesses_them_away() {
        let dir = tempfile::tempdir().expect("temp dir");
        let materials = dir.path().join("materials");
        std::fs::create_dir_all(&materials).expect("mkdir");
        std::fs::write(materials.join("glaze.ron"), GLAZE).expect("writes");
        let snapshot = Snapshot::new(&materials, dir.path().join("shaders")).targets(&[Target::Wgsl]);
        // glaze.wgsl and the table file it binds.
        assert!(matches!(snapshot.check(), Err(SnapshotError::Drift { count: 2, .. })), "missing files");
        assert_eq!(snapshot.bless().expect("blesses"), 2);
        snapshot.check().expect("current after blessing");

        let wgsl = dir.path().join("shaders/glaze/glaze.wgsl");
        let text = std::fs::read_to_string(&wgsl).expect("written");
        std::fs::write(&wgsl, text.replacen("fn ", "fn edited_", 1)).expect("edits");
        std::fs::write(dir.path().join("shaders/glaze/old.wgsl"), "stale").expect("writes");
        match snapshot.check() {
            Err(SnapshotError::Drift { count: 2, report }) => {
                assert!(report.contains("-fn edited_") && report.contains("stale:"), "{report}");
            }
            other => panic!("expected drift in two files, got {other:?}"),
        }
        snapshot.bless().expect("blesses");
        snapshot.check().expect("current again");
        assert!(!dir.path().join("shaders/glaze/old.wgsl").exists(), "stale file removed");
    }

    #[test]
    fn a_bad_material_is_reported_with_its_diagnostics() {
        let dir = tempfile::tempdir().expect("temp dir");
        std::fs::write(dir.path().join("bad.ron"), "Material(name: \"bad\", layers: [Lambert(albedo: 7)])").expect("w");
        match Snapshot::new(dir.path(), dir.path().join("out")).check() {
            Err(SnapshotError::Diagnostics(text)) => assert!(text.contains("E0213"), "{text}"),
            other => panic!("expected diagnostics, got {other:?}"),
        }
    }
}
