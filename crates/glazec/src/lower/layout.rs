//! The contract between a generated module and its host: bind groups and bindings, entry point
//! names, the `eval_pairs` buffers, and the byte layout of the runtime-parameter uniform.

use crate::model::{Material, ParamValue};

/// The resource bindings of generated modules (all in bind group 0).
///
/// They are numbered contiguously from 0 in the order a kernel's layout lists them: wgpu's
/// Vulkan backend renumbers a bind group's entries 0, 1, 2, … in that order, and passthrough
/// SPIR-V (the HLSL path) keeps the numbers glslang gave it, so the two must coincide. The
/// optional resources therefore take the next free number, in this order: `params` (3, when
/// the material has runtime parameters), `glazec_tables` (when a runtime parameter needs whole
/// tables), `light` (the preview's). [`layout`](bindings::layout) reads them back from a module.
pub mod bindings {
    pub const GROUP: u32 = 0;
    /// `var<storage, read> pairs: array<DirectionPair>`: `wi` then `wo`, each a `vec4<f32>` (w unused).
    pub const PAIRS: u32 = 0;
    /// `var<storage, read_write> values: array<vec4<f32>>`: f(wi, wo) in `xyz`, `w` = 0.
    pub const VALUES: u32 = 1;
    /// `var<uniform> dispatch: EvalDispatch`: `pair_count: u32` (padded to 16 bytes).
    pub const DISPATCH: u32 = 2;
    /// `var<uniform> params: <Material>Params` (only when the material has runtime parameters).
    pub const PARAMS: u32 = 3;

    /// Where a module's optional resources are bound.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    pub struct Layout {
        /// `var<uniform> params: <Material>Params`.
        pub params: Option<u32>,
        /// `var<uniform> glazec_tables: array<vec4<u32>, N>` (16-bit codes, two to a word): the contents of
        /// `glazec::math::tables::buffer()` (`glazec_tables.bin` beside the generated folders),
        /// bound when a table lookup has an argument known only at run time (a cosine, or a
        /// runtime parameter).
        pub tables: Option<u32>,
        /// `var<uniform> light: PreviewLight` (the preview's directional light).
        pub light: Option<u32>,
    }

    /// The bindings of a module built by `lower`.
    pub fn layout(module: &naga::Module) -> Layout {
        let binding = |name: &str| {
            module
                .global_variables
                .iter()
                .find(|(_, v)| v.name.as_deref() == Some(name))
                .and_then(|(_, v)| v.binding.as_ref().map(|b| b.binding))
        };
        Layout {
            params: binding("params"),
            tables: binding(crate::lower::builder::TABLES_BUFFER_NAME),
            light: binding("light"),
        }
    }

    /// Numbers the optional resources created without a binding number (`u32::MAX`): the table
    /// buffer, then the light, after `params`.
    pub(in crate::lower) fn assign(module: &mut naga::Module) {
        let mut next = if layout(module).params.is_some() { PARAMS + 1 } else { PARAMS };
        for name in [crate::lower::builder::TABLES_BUFFER_NAME, "light"] {
            for (_, var) in module.global_variables.iter_mut() {
                if var.name.as_deref() == Some(name) {
                    if let Some(b) = var.binding.as_mut() {
                        b.binding = next;
                        next += 1;
                    }
                }
            }
        }
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
        let components: &[f32] = match value {
            ParamValue::Scalar(x) => std::slice::from_ref(x),
            ParamValue::Rgb(c) => c,
        };
        for (i, x) in components.iter().enumerate() {
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
