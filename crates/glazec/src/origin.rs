//! Where a compiled material came from, as the header of every generated file states it: the
//! source file's name and hash, the scene it was simplified for, and the glazec version.

/// The source a material was compiled from, as every generated file's header names it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Origin {
    /// The source file's name (no directory, so that headers do not depend on where a project
    /// lives), or `None` for text compiled from memory.
    pub file: Option<String>,
    /// [`source_hash`] of the text.
    pub hash: u64,
    /// The scene the material was simplified for (`compile --scene`): its file name and hash.
    pub scene: Option<(String, u64)>,
}

impl Origin {
    /// The origin of `text`, read from a file named `file` (its directory is dropped).
    pub fn new(file: Option<&str>, text: &str) -> Self {
        let file = file.map(|f| std::path::Path::new(f).file_name().map_or(f.into(), |n| n.to_string_lossy().into()));
        Origin { file, hash: source_hash(text.as_bytes()), scene: None }
    }
}

/// The hash that generated files record of their source: 64-bit FNV-1a (Fowler, Noll & Vo).
/// Chosen because the Rust module written by [`build`](crate::build) recomputes it in a `const fn` at compile
/// time, which rules out cryptographic hashes from crates; it detects changes, not attacks.
pub const fn source_hash(bytes: &[u8]) -> u64 {
    crate::build::prelude::glazec_source_hash(bytes)
}

/// The glazec version that generated files name in their header.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
