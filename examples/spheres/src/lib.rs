//! An example consumer of glazec: every shipped material rendered on a sphere with wgpu.
//!
//! glazec is used only through `build.rs` (see `build.rs`): the generated module below holds,
//! per material, the WGSL source, a `#[repr(C)]` struct for the runtime parameters and the
//! bind-group layout of the preview pipeline. [`render`] turns those descriptions into wgpu
//! objects without knowing any material by name; `main.rs` also animates one material's
//! parameter through its typed struct. [`light_loop`] is a program's own shader: two material
//! libraries, two meshes and two lights in its own light loop.

/// What glazec generated for `../../materials` (`OUT_DIR/glazec_materials.rs`).
pub mod materials {
    include!(concat!(env!("OUT_DIR"), "/glazec_materials.rs"));
}

/// What glazec generated for the light-loop scene: the same materials with the bindings the
/// program chose for them (`OUT_DIR/light_loop/glazec_materials.rs`; see `build.rs`).
pub mod light_materials {
    include!(concat!(env!("OUT_DIR"), "/light_loop/glazec_materials.rs"));
}

pub mod light_loop;
pub mod render;
