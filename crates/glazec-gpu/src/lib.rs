//! Stage 6, `run`: executing the generated shaders on a Vulkan device through wgpu
//! (feature `gpu`; lavapipe, Mesa's CPU driver, in the tests).
//!
//! **Input:** a [`Compiled`](glazec::Compiled) material, direction pairs and parameter values.
//! **Output:** f(wi, wo) per pair as computed by the device ([`EvalKernel`]), or an image of a
//! shaded sphere ([`preview`]).
//!
//! * [`Gpu`] gets a device; it is separate from the kernels. A missing adapter is the typed
//!   error [`RunError::NoAdapter`]: this library never decides whether that means skip or fail
//!   (the tests do, by `GLAZEC_REQUIRE_GPU`).
//! * [`ShaderPath`] is how a shader reaches the device. Every language runs, not only WGSL:
//!   the naga module itself, WGSL text through wgpu's front end, GLSL compiled by
//!   `glslangValidator -V`, and HLSL compiled by glslang's HLSL front end (`-D`), the last as
//!   passthrough SPIR-V because naga's SPIR-V reader rejects glslang's HLSL output.
//! * [`environment`] prefilters environment images for image-based lighting (`<material>_ibl`),
//!   which [`preview`] renders with.
//!
//! **Invariant:** all paths use one explicit bind-group layout (the one in
//! [`glazec::lower::bindings`]), so a kernel behaves the same whichever language it came from.

mod device;
pub mod environment;
mod kernel;
pub mod preview;
mod shader;
pub mod textures;
pub mod throughput;

pub use device::{ADAPTER_ENV, Gpu};
pub use kernel::{EvalKernel, pairs_bytes, params_bytes};
pub use shader::ShaderPath;

/// Why the device could not run something.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// No Vulkan adapter (or none matching `GLAZEC_ADAPTER`).
    #[error("no Vulkan adapter{}{}", wanted.as_ref().map(|w| format!(" matching `{w}`")).unwrap_or_default(),
        if available.is_empty() { String::from(" is available (install mesa-vulkan-drivers and libvulkan1 for lavapipe)") }
        else { format!("; available: {}", available.join(", ")) })]
    NoAdapter { wanted: Option<String>, available: Vec<String> },
    /// The adapter refused to create a device.
    #[error("cannot create a device on {adapter}: {message}")]
    Device { adapter: String, message: String },
    /// An external compiler is not on PATH.
    #[error("`{tool}` is not installed (apt-get install glslang-tools)")]
    ToolMissing { tool: &'static str },
    /// An external compiler rejected a generated shader.
    #[error("{tool} failed on the {what}:\n{output}")]
    Tool { tool: &'static str, what: String, output: String },
    /// The device (or wgpu's validation) rejected a shader or pipeline.
    #[error("the device rejected the {what}: {message}")]
    Rejected { what: String, message: String },
    /// Passthrough SPIR-V is needed but the device does not offer it.
    #[error("the {path} path needs passthrough SPIR-V, which this device does not support")]
    NoPassthrough { path: &'static str },
    /// Mapping a buffer for reading failed.
    #[error("reading results back from the device failed: {0}")]
    Readback(String),
    /// The number of parameter values does not match the material.
    #[error("expected {expected} parameter values, got {got}")]
    ParamCount { expected: usize, got: usize },
    /// `EvalKernel::eval_textured` needs one uv per direction pair.
    #[error("expected one uv per direction pair ({pairs}), got {uvs}")]
    UvCount { pairs: usize, uvs: usize },
    #[error(transparent)]
    Emit(#[from] glazec::emit::EmitError),
    #[error(transparent)]
    Io(#[from] std::io::Error),
}
