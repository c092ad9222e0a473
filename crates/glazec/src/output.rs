//! Writing outputs: all or nothing, each file atomically.
//!
//! Every file is first written to a temporary file in its destination directory ([`stage`]);
//! only when all of them exist are they renamed into place ([`Staged::persist`]; a rename within
//! one directory is atomic on POSIX). If anything fails before the renames, the temporary files
//! are removed and nothing changes. Files are not flushed to the disk (`fsync`), as compilers
//! do not: outputs are regenerated from their sources, and a flush per file was half the time
//! of `glazec compile materials/`. [`drift`] compares planned outputs with what is on disk (for
//! `compile --check` and the golden tests) without writing anything.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

/// A file to be written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputFile {
    pub path: PathBuf,
    pub contents: Vec<u8>,
}

/// Writes every file, or none of them (staged on every core, then renamed).
///
/// # Errors
/// The first I/O error; files already staged are removed.
pub fn write_all(files: &[OutputFile]) -> io::Result<()> {
    let (mut staged, mut error) = (Vec::with_capacity(files.len()), None);
    for result in files.par_iter().map(stage).collect::<Vec<_>>() {
        match result {
            Ok(s) => staged.push(s),
            Err(e) => error = error.or(Some(e)),
        }
    }
    if let Some(e) = error {
        abandon(staged);
        return Err(e);
    }
    staged.into_iter().try_for_each(Staged::persist)
}

/// A file written under a temporary name beside its destination, removed when dropped unless
/// persisted. Holds no open file, so that a folder of thousands of outputs can be staged.
#[derive(Debug)]
pub struct Staged {
    temp: tempfile::TempPath,
    path: PathBuf,
    /// The directories staging created for it, outermost first.
    created: Vec<PathBuf>,
}

/// Removes staged files that will not be written, and the directories staging created for them
/// (those left empty), so that a failed write leaves the disk as it found it.
pub fn abandon(staged: Vec<Staged>) {
    let mut created: Vec<PathBuf> = staged.iter().flat_map(|s| s.created.iter().cloned()).collect();
    drop(staged);
    // Innermost first: a directory is empty once its staged files and sub-directories are gone.
    created.sort_by_key(|d| std::cmp::Reverse(d.components().count()));
    created.dedup();
    for dir in created {
        let _ = fs::remove_dir(dir);
    }
}

/// Creates `dir` and its missing ancestors: the ones this call created, outermost first (one
/// that another thread creates meanwhile is not counted).
fn create_dirs(dir: &Path) -> io::Result<Vec<PathBuf>> {
    let missing: Vec<&Path> = dir.ancestors().take_while(|d| !d.as_os_str().is_empty() && !d.is_dir()).collect();
    let mut created = Vec::new();
    for d in missing.into_iter().rev() {
        match fs::create_dir(d) {
            Ok(()) => created.push(d.to_path_buf()),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && d.is_dir() => {}
            Err(e) => return Err(e),
        }
    }
    Ok(created)
}

impl Staged {
    /// Where the file goes.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the file into place.
    ///
    /// # Errors
    /// The rename failed (the temporary file is then removed).
    pub fn persist(self) -> io::Result<()> {
        self.temp.persist(&self.path).map_err(|e| e.error)
    }
}

/// Writes `file` under a temporary name in its destination directory (created if missing).
///
/// # Errors
/// The directory or the file cannot be written.
pub fn stage(file: &OutputFile) -> io::Result<Staged> {
    let dir = file.path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let created = create_dirs(dir)?;
    let mut builder = tempfile::Builder::new();
    builder.prefix(".glazec-");
    // Temporary files are private (0600) by default; outputs are ordinary files.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let mut temp = builder.tempfile_in(dir)?;
    temp.write_all(&file.contents)?;
    Ok(Staged { temp: temp.into_temp_path(), path: file.path.clone(), created })
}

/// The files for one compiled material: `<out_dir>/<material>/<artifact>`.
pub fn plan(out_dir: &Path, material: &str, artifacts: Vec<crate::Artifact>) -> Vec<OutputFile> {
    artifacts
        .into_iter()
        .map(|a| OutputFile { path: out_dir.join(material).join(a.file_name), contents: a.contents })
        .collect()
}

/// How a planned output differs from the file on disk.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Drift {
    Missing(PathBuf),
    Different(PathBuf),
}

impl std::fmt::Display for Drift {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Drift::Missing(p) => write!(f, "missing: {}", p.display()),
            Drift::Different(p) => write!(f, "out of date: {}", p.display()),
        }
    }
}

/// The planned files that are missing or differ on disk.
pub fn drift(files: &[OutputFile]) -> Vec<Drift> {
    files
        .iter()
        .filter_map(|file| match fs::read(&file.path) {
            Ok(existing) if existing == file.contents => None,
            Ok(_) => Some(Drift::Different(file.path.clone())),
            Err(_) => Some(Drift::Missing(file.path.clone())),
        })
        .collect()
}

/// A unified diff (3 lines of context) from the file on disk to the planned contents, headed
/// `--- <path> (on disk)` / `+++ <path> (generated)`; a missing file diffs against nothing, and
/// a file that is not UTF-8 on either side gets a one-line note instead. Empty when they agree.
pub fn unified_diff(file: &OutputFile) -> String {
    let on_disk = fs::read(&file.path).ok();
    if on_disk.as_deref() == Some(file.contents.as_slice()) {
        return String::new();
    }
    let path = file.path.display();
    let old = on_disk.as_deref().map_or(Ok(""), std::str::from_utf8);
    let (Ok(old), Ok(new)) = (old, std::str::from_utf8(&file.contents)) else {
        return format!("Binary files {path} (on disk) and {path} (generated) differ\n");
    };
    let old_header = if on_disk.is_some() { format!("{path} (on disk)") } else { "/dev/null".to_string() };
    similar::TextDiff::from_lines(old, new)
        .unified_diff()
        .context_radius(3)
        .header(&old_header, &format!("{path} (generated)"))
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failure_while_staging_writes_nothing_at_all() {
        let dir = tempfile::tempdir().expect("temp dir");
        // The second file's folder cannot be created: a file stands where it should be.
        fs::write(dir.path().join("blocked"), "a file").expect("writes");
        let files = vec![
            OutputFile { path: dir.path().join("ok/first.wgsl"), contents: b"first".to_vec() },
            OutputFile { path: dir.path().join("blocked/second.wgsl"), contents: b"second".to_vec() },
        ];
        assert!(write_all(&files).is_err());
        assert!(!dir.path().join("ok/first.wgsl").exists(), "the first file was written although the second failed");
        let leftovers: Vec<_> = fs::read_dir(dir.path().join("ok")).map(|d| d.flatten().collect()).unwrap_or_default();
        assert!(leftovers.is_empty(), "temporary files left behind: {leftovers:?}");
    }

    #[test]
    fn writes_all_files_and_reports_drift() {
        let dir = tempfile::tempdir().expect("temp dir");
        let files = vec![
            OutputFile { path: dir.path().join("a/x.txt"), contents: b"one".to_vec() },
            OutputFile { path: dir.path().join("b/y.txt"), contents: b"two".to_vec() },
        ];
        assert_eq!(drift(&files).len(), 2);
        write_all(&files).expect("writes");
        assert!(drift(&files).is_empty());
        let changed = vec![OutputFile { path: dir.path().join("a/x.txt"), contents: b"three".to_vec() }];
        assert_eq!(drift(&changed), vec![Drift::Different(dir.path().join("a/x.txt"))]);
        let diff = unified_diff(&changed[0]);
        assert!(diff.contains("-one") && diff.contains("+three") && diff.contains("(on disk)"), "{diff}");
        assert!(unified_diff(&files[1]).is_empty());
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = fs::metadata(dir.path().join("a/x.txt")).expect("written").permissions().mode();
            assert_eq!(mode & 0o777, 0o644, "outputs are ordinary files, not private temporaries");
        }
        // No temporary files are left behind.
        let leftovers: Vec<_> = fs::read_dir(dir.path().join("a")).expect("dir").collect();
        assert_eq!(leftovers.len(), 1);
    }
}
