//! glazec's layered materials in Bevy 0.19: each material file becomes a Bevy `Material` whose
//! fragment shader lights it with Bevy's own lights — directional lights with cascaded shadows,
//! clustered point and spot lights with shadows, ambient light, the environment map — through
//! glazec's BRDF, then Bevy's fog and tonemapping.
//!
//! ```toml
//! [dependencies]
//! bevy = "0.19"
//! glazec_bevy = "0.1"
//! [build-dependencies]
//! glazec = "0.1"
//! ```
//!
//! ```ignore
//! // build.rs
//! fn main() {
//!     glazec::build::Build::new("materials").bevy().run();
//! }
//!
//! // src/main.rs
//! mod materials {
//!     include!(concat!(env!("OUT_DIR"), "/glazec_bevy_materials.rs"));
//! }
//! App::new().add_plugins((DefaultPlugins, materials::GlazecMaterialsPlugin));
//! commands.spawn((Mesh3d(sphere), MeshMaterial3d(clays.add(materials::clay::Clay::default()))));
//! ```
//!
//! This crate holds what every generated material shares: the lighting module
//! `glazec_bevy::lighting` (`lighting.wgsl`) that the generated fragment shaders import, and
//! [`GlazecPlugin`], which registers it (`GlazecMaterialsPlugin` adds it for you).

use bevy::asset::uuid_handle;
use bevy::prelude::*;

/// The lighting module's shader handle.
pub const LIGHTING_SHADER: Handle<Shader> = uuid_handle!("6c1f4e0a-3b7d-4a52-9e1c-8d2f5b7a9c31");

/// Registers `glazec_bevy::lighting`, the WGSL module the generated fragment shaders import.
pub struct GlazecPlugin;

impl Plugin for GlazecPlugin {
    fn build(&self, app: &mut App) {
        let source = include_str!("lighting.wgsl");
        let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();
        let _ = shaders.insert(&LIGHTING_SHADER, Shader::from_wgsl(source, "glazec_bevy/lighting.wgsl"));
    }
}

/// A material's table uniform (`TABLES`, little-endian 32-bit words) as the `array<vec4<u32>, N>`
/// the library declares. The generated `Default` impls call it.
///
/// # Panics
/// If `bytes` is not 16·N bytes long: the generated code passes the material's own tables.
pub fn table_words<const N: usize>(bytes: &[u8]) -> [UVec4; N] {
    assert_eq!(bytes.len(), 16 * N, "the table uniform is {N} vec4<u32>");
    let word = |i: usize| u32::from_le_bytes([bytes[4 * i], bytes[4 * i + 1], bytes[4 * i + 2], bytes[4 * i + 3]]);
    std::array::from_fn(|k| UVec4::new(word(4 * k), word(4 * k + 1), word(4 * k + 2), word(4 * k + 3)))
}
