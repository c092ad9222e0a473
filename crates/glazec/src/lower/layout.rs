//! The contract between a generated module and its host: bind groups and bindings, entry point
//! names, the `eval_pairs` buffers, and the byte layout of the runtime-parameter uniform.

use crate::model::{Material, ParamValue};

/// The resource bindings of generated modules: glazec's defaults, the host's choice, and where
/// a lowered module's resources ended up.
///
/// A material's **library** binds at most four kinds of resource, each where the host chooses
/// ([`Choice`]; CLI `--bind`, `Build::bindings`): the runtime-parameter uniform, the table
/// uniform, the texture sampler with its textures (sampler at the chosen binding, textures at
/// the next ones in order of first use) and glazec's environment (sampler, radiance, irradiance
/// at the chosen binding and the two after it; in the library only where the host places it).
/// By default they sit where they always have: `params` at group 0 binding 3, the tables right
/// after the parameters (3 without them), textures in group 1 and, in the harness, the
/// environment in group 2, from binding 0.
///
/// glazec's **harness** (`eval_pairs`, the previews) adds `pairs`, `values`, `dispatch` and the
/// preview's `light`, in group 0 at the lowest bindings the library leaves free: with the
/// defaults 0, 1, 2 and the binding after the library's last in group 0. The numbers are then
/// contiguous from 0, which glazec's own runner needs: wgpu's Vulkan backend renumbers a bind
/// group's entries 0, 1, 2, … in the order a kernel's layout lists them, and passthrough SPIR-V
/// (the HLSL path) keeps the numbers glslang gave it, so the two must coincide.
pub mod bindings {
    /// The default group of the parameters, the tables and the harness.
    pub const GROUP: u32 = 0;
    /// `var<storage, read> pairs: array<DirectionPair>`: `wi` then `wo`, each a `vec4<f32>` (w unused).
    pub const PAIRS: u32 = 0;
    /// `var<storage, read_write> values: array<vec4<f32>>`: f(wi, wo) in `xyz`, `w` = 0.
    pub const VALUES: u32 = 1;
    /// `var<uniform> dispatch: EvalDispatch`: `pair_count: u32` (padded to 16 bytes).
    pub const DISPATCH: u32 = 2;
    /// `var<uniform> <material>_params: <Material>Params` by default (when the material has runtime parameters).
    pub const PARAMS: u32 = 3;
    /// The default group of the texture sampler and the textures (their own, so that group 0's
    /// numbering, which depends on the optional uniforms, does not move them).
    pub const TEXTURES_GROUP: u32 = 1;
    /// The default group of the environment, after the textures'.
    pub const ENVIRONMENT_GROUP: u32 = 2;

    /// A resource's place in a pipeline layout: bind group and binding (`@group(g) @binding(b)`;
    /// `register(…, space g)` in HLSL; `layout(binding = 16·g + b)` in GLSL).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
    pub struct Slot {
        pub group: u32,
        pub binding: u32,
    }

    impl Slot {
        pub const fn new(group: u32, binding: u32) -> Slot {
            Slot { group, binding }
        }

        /// The slot `n` bindings further on in the same group.
        pub const fn after(self, n: u32) -> Slot {
            Slot { group: self.group, binding: self.binding + n }
        }
    }

    impl std::fmt::Display for Slot {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "{}:{}", self.group, self.binding)
        }
    }

    impl std::str::FromStr for Slot {
        type Err = String;
        /// `"group:binding"`, e.g. `"2:0"`.
        fn from_str(s: &str) -> Result<Slot, String> {
            let (g, b) = s.split_once(':').ok_or_else(|| format!("`{s}` is not GROUP:BINDING (e.g. 2:0)"))?;
            let number = |t: &str| t.trim().parse::<u32>().map_err(|_| format!("`{t}` in `{s}` is not a number"));
            let slot = Slot::new(number(g)?, number(b)?);
            // naga's GLSL backend flattens group g to bindings 16·g + b, into a u8.
            if slot.group > 7 || slot.binding > 15 {
                return Err(format!("`{s}`: the group must be at most 7 and the binding at most 15"));
            }
            Ok(slot)
        }
    }

    /// What a library binds, one kind of resource each.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
    pub enum Resource {
        /// The runtime-parameter uniform.
        Params,
        /// The table uniform.
        Tables,
        /// The texture sampler, then the textures.
        Textures,
        /// The environment's sampler, radiance and irradiance.
        Environment,
    }

    impl Resource {
        pub const ALL: [Resource; 4] = [Resource::Params, Resource::Tables, Resource::Textures, Resource::Environment];

        /// The name on the command line (`--bind params=0:3`).
        pub fn name(self) -> &'static str {
            match self {
                Resource::Params => "params",
                Resource::Tables => "tables",
                Resource::Textures => "textures",
                Resource::Environment => "environment",
            }
        }
    }

    /// The host's choice of where a library's resources are bound; `None` keeps the default.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
    pub struct Choice {
        pub params: Option<Slot>,
        pub tables: Option<Slot>,
        /// The sampler; the textures follow it.
        pub textures: Option<Slot>,
        /// The sampler; radiance and irradiance follow it. `Some` also puts glazec's environment
        /// lookup, `<material>_ibl`, and these bindings in the library; `None` leaves both to the
        /// harness, at the default place.
        pub environment: Option<Slot>,
    }

    impl Choice {
        /// The choice with `resource` at `slot`.
        pub fn with(mut self, resource: Resource, slot: Slot) -> Choice {
            *match resource {
                Resource::Params => &mut self.params,
                Resource::Tables => &mut self.tables,
                Resource::Textures => &mut self.textures,
                Resource::Environment => &mut self.environment,
            } = Some(slot);
            self
        }

        /// Where the parameters go.
        pub fn params(&self) -> Slot {
            self.params.unwrap_or(Slot::new(GROUP, PARAMS))
        }

        /// Where the tables go: right after the parameters unless chosen.
        pub fn tables(&self, has_params: bool) -> Slot {
            self.tables.unwrap_or_else(|| self.params().after(u32::from(has_params)))
        }

        /// Where the texture sampler goes.
        pub fn textures(&self) -> Slot {
            self.textures.unwrap_or(Slot::new(TEXTURES_GROUP, 0))
        }

        /// Where the environment sampler goes.
        pub fn environment(&self) -> Slot {
            self.environment.unwrap_or(Slot::new(ENVIRONMENT_GROUP, 0))
        }
    }

    /// Two of a library's resources were given one slot.
    #[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
    #[error(
        "`{first}` and `{second}` would both be bound at {slot} (group:binding); choose other bindings with --bind"
    )]
    pub struct Clash {
        pub first: String,
        pub second: String,
        pub slot: Slot,
    }

    /// Where a lowered module's resources are bound, by role: the library's, then the harness's.
    #[derive(Clone, Debug, Default, PartialEq, Eq)]
    pub struct Layout {
        /// `var<uniform> <material>_params: <Material>Params`.
        pub params: Option<Slot>,
        /// `var<uniform> <material>_tables: array<vec4<u32>, N>` (16-bit codes, two to a word): the
        /// contents of `Compiled::tables_bytes` (`<material>.tables.bin` beside the shaders), bound
        /// when a table lookup has an argument known only at run time (a cosine, or a runtime
        /// parameter). Only the tables the material reads.
        pub tables: Option<Slot>,
        /// The texture sampler and each texture, as (name in generated code, slot), sampler first.
        pub textures: Vec<(String, Slot)>,
        /// The environment's sampler, radiance and irradiance, with their names in generated code
        /// (the library's where the host placed them, else the harness's).
        pub environment: Vec<(String, Slot)>,
        /// The harness's `pairs`, `values` and `dispatch` (group 0).
        pub pairs: u32,
        pub values: u32,
        pub dispatch: u32,
        /// The harness's `light: PreviewLight` (the preview's directional light), in group 0.
        pub light: Option<u32>,
    }
}

/// Entry point names.
pub mod entry_points {
    pub const EVAL_PAIRS: &str = "eval_pairs";
    pub const PREVIEW_VS: &str = "preview_vs";
    pub const PREVIEW_FS: &str = "preview_fs";
    /// The preview sphere lit by the environment (`<material>_ibl`).
    pub const PREVIEW_IBL_FS: &str = "preview_ibl_fs";
}

/// Workgroup size of `eval_pairs`.
pub const EVAL_WORKGROUP_SIZE: u32 = 64;

/// Byte size of one direction pair in the `pairs` buffer.
pub const PAIR_STRIDE: u32 = 32;

/// The layout of one runtime parameter inside the uniform struct.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParamLayout {
    pub name: String,
    /// `"f32"` or `"vec3<f32>"`.
    pub wgsl_type: &'static str,
    pub offset: u32,
    pub size: u32,
}

/// The uniform block of a material's runtime parameters for `values` (one per parameter, in
/// declaration order; texture reads are skipped): little-endian f32 at [`params_layout`]'s
/// offsets, padding zeroed.
/// Extra or missing values are the caller's to check.
pub fn params_bytes(material: &Material, values: &[ParamValue]) -> Vec<u8> {
    let (layout, size) = params_layout(material);
    let mut bytes = vec![0u8; size as usize];
    let uniform_values = material.uniform_params().filter_map(|(i, _)| values.get(i));
    for (slot, value) in layout.iter().zip(uniform_values) {
        for (i, x) in value.components().iter().enumerate() {
            let at = slot.offset as usize + 4 * i;
            bytes[at..at + 4].copy_from_slice(&x.to_le_bytes());
        }
    }
    bytes
}

/// The uniform struct's layout (WGSL uniform rules; naga reproduces it in every backend).
pub fn params_layout(material: &Material) -> (Vec<ParamLayout>, u32) {
    let params: Vec<_> = material.uniform_params().map(|(_, p)| p).collect();
    let (offsets, span) = member_offsets(params.iter().map(|p| matches!(p.default, ParamValue::Rgb(_))));
    let layout = params
        .iter()
        .zip(offsets)
        .map(|(p, offset)| {
            let (size, wgsl_type) = match p.default {
                ParamValue::Scalar(_) => (4, "f32"),
                ParamValue::Rgb(_) => (12, "vec3<f32>"),
            };
            ParamLayout { name: p.name.clone(), wgsl_type, offset, size }
        })
        .collect();
    (layout, span)
}

/// Offsets of a struct's `f32` (false) and `vec3<f32>` (true) members under WGSL's uniform
/// rules (vec3 aligned to 16), and its size padded to 16 bytes so that it can be bound in
/// every backend.
pub(crate) fn member_offsets(vec3: impl IntoIterator<Item = bool>) -> (Vec<u32>, u32) {
    let mut offset: u32 = 0;
    let mut offsets = Vec::new();
    for is_vec3 in vec3 {
        let (align, size) = if is_vec3 { (16, 12) } else { (4, 4) };
        offset = offset.next_multiple_of(align);
        offsets.push(offset);
        offset += size;
    }
    (offsets, offset.next_multiple_of(16))
}
