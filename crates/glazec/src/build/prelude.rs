// The part of every generated `glazec_materials.rs` that does not depend on the materials
// (`build::rust_module` copies this file's text into the module). glazec compiles it too, as
// `build::prelude`: the text is checked by rustc, and `glazec::source_hash` is this hash.

/// Plain descriptions of the generated shaders' resources (no graphics-API types, so that they
/// serve wgpu, Vulkan or anything else).
#[allow(dead_code)]
pub mod glazec_layout {
    /// What a binding holds.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Role {
        /// `pairs`: the direction pairs `eval_pairs` reads (storage, read-only).
        Pairs,
        /// `values`: what `eval_pairs` writes (storage, read-write).
        Values,
        /// `dispatch`: the pair count (uniform `EvalDispatch`).
        Dispatch,
        /// `<material>_params`: the material's runtime parameters (uniform, the material's `Params`).
        Params,
        /// `<material>_tables`: the table uniform (bind the material's `TABLES`).
        Tables,
        /// `light`: the preview's directional light (uniform `PreviewLight`).
        Light,
        /// `<material>_sampler`: the sampler of the material's texture reads.
        Sampler,
        /// A texture the material reads (`texture_2d<f32>`, `<material>_<texture>`).
        Texture,
        /// `<material>_environment_sampler`: the environment's sampler (repeat in u, clamp in v, linear).
        EnvironmentSampler,
        /// `<material>_radiance`: the prefiltered equirectangular environment (`texture_2d<f32>`, mip k = roughness k/(N − 1)).
        Radiance,
        /// `<material>_irradiance`: the environment's irradiance / π (`texture_2d<f32>`).
        Irradiance,
    }

    /// How a binding is accessed.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Access {
        Uniform,
        StorageReadOnly,
        StorageReadWrite,
        /// A sampler or a sampled texture (no buffer).
        Handle,
    }

    /// The shader stages that use a binding.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct Stages {
        pub vertex: bool,
        pub fragment: bool,
        pub compute: bool,
    }

    /// One entry of a bind-group layout.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct Binding {
        /// The variable's name in the WGSL source.
        pub name: &'static str,
        pub role: Role,
        pub group: u32,
        pub binding: u32,
        pub access: Access,
        /// The smallest buffer that may be bound, in bytes (one element for a runtime-sized array).
        pub min_size: u64,
        pub stages: Stages,
    }

    /// One member of a uniform struct, as naga laid it out.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct Member {
        pub name: &'static str,
        /// `"f32"` or `"vec3<f32>"`.
        pub wgsl_type: &'static str,
        pub offset: usize,
        pub size: usize,
    }

    /// A material's runtime-parameter struct: naga's layout and the Rust struct's.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct ParamsInfo {
        /// The struct's name in the shaders and in Rust.
        pub struct_name: &'static str,
        /// The members as the shader's uniform struct lays them out.
        pub members: &'static [Member],
        /// The uniform struct's size.
        pub size: usize,
        /// `offset_of!` of each member in the Rust struct, in member order.
        pub rust_offsets: &'static [usize],
        /// `size_of` the Rust struct.
        pub rust_size: usize,
        /// The material's default values laid out as the uniform buffer holds them
        /// (little-endian, padding zeroed): what to upload when nothing is overridden.
        pub default_bytes: &'static [u8],
    }

    /// Everything generated for one material.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct MaterialInfo {
        pub name: &'static str,
        /// The `.ron` file's name.
        pub source: &'static str,
        pub source_hash: u64,
        /// The WGSL library (empty if WGSL was not generated).
        pub wgsl: &'static str,
        /// glazec's WGSL harness, to be read after `wgsl` (empty if WGSL was not generated).
        pub wgsl_harness: &'static str,
        /// `<name>_brdf(n, v, l[, params]) -> vec3<f32>`: f without the cosine.
        pub brdf_function: &'static str,
        /// `<name>_eval(n, v, l[, params]) -> vec3<f32>`: f · max(n·l, 0).
        pub eval_function: &'static str,
        pub params: Option<ParamsInfo>,
        /// Whether the library binds its table uniform.
        pub uses_tables: bool,
        /// The table uniform's contents (empty without tables).
        pub tables: &'static [u8],
        /// The library's resources, where the build put them.
        pub library_bindings: &'static [Binding],
        /// The compute pipeline of `eval_pairs`.
        pub eval_pairs_bindings: &'static [Binding],
        /// The render pipeline of `preview_vs` + `preview_fs`.
        pub preview_bindings: &'static [Binding],
    }
}

/// 64-bit FNV-1a, the hash that shader headers record of their `.ron` source.
#[allow(dead_code)]
pub const fn glazec_source_hash(bytes: &[u8]) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut i = 0;
    while i < bytes.len() {
        hash ^= bytes[i] as u64;
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        i += 1;
    }
    hash
}

/// Whether `text` starts with `prefix` (usable in `const` assertions).
#[allow(dead_code)]
pub const fn glazec_starts_with(text: &str, prefix: &str) -> bool {
    let (text, prefix) = (text.as_bytes(), prefix.as_bytes());
    if text.len() < prefix.len() {
        return false;
    }
    let mut i = 0;
    while i < prefix.len() {
        if text[i] != prefix[i] {
            return false;
        }
        i += 1;
    }
    true
}
