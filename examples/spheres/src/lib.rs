//! An example consumer of glazec: every shipped material rendered on a sphere with wgpu.
//!
//! glazec is used only through `build.rs` (see `build.rs`): the generated module below holds,
//! per material, the WGSL source, a `#[repr(C)]` struct for the runtime parameters and the
//! bind-group layout of the preview pipeline. [`render`] turns those descriptions into wgpu
//! objects without knowing any material by name; `main.rs` also animates one material's
//! parameter through its typed struct.

/// What glazec generated for `../../materials` (`OUT_DIR/glazec_materials.rs`).
pub mod materials {
    include!(concat!(env!("OUT_DIR"), "/glazec_materials.rs"));
}

pub mod render;
