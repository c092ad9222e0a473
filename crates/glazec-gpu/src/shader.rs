//! How a generated shader reaches the device, in each of its languages.

use std::borrow::Cow;
use std::path::Path;
use std::process::Command;

use naga::ShaderStage;

use crate::{Gpu, RunError};
use glazec::{Compiled, Target};

/// The route from a compiled material to a `wgpu::ShaderModule`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ShaderPath {
    /// The naga module itself (`ShaderSource::Naga`): no text at all.
    NagaIr,
    /// The emitted WGSL, through wgpu's WGSL front end.
    Wgsl,
    /// The emitted GLSL, compiled by `glslangValidator -V` to SPIR-V (then read by naga).
    Glsl,
    /// The emitted HLSL, compiled by glslang's HLSL front end (`-D -V`) to SPIR-V, run as
    /// passthrough SPIR-V (naga's SPIR-V reader rejects glslang's HLSL output).
    Hlsl,
}

impl ShaderPath {
    pub const ALL: [ShaderPath; 4] = [ShaderPath::NagaIr, ShaderPath::Wgsl, ShaderPath::Glsl, ShaderPath::Hlsl];

    pub fn name(self) -> &'static str {
        match self {
            ShaderPath::NagaIr => "naga-ir",
            ShaderPath::Wgsl => "wgsl",
            ShaderPath::Glsl => "glsl",
            ShaderPath::Hlsl => "hlsl",
        }
    }
}

impl std::fmt::Display for ShaderPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A shader module on the device and the name of the entry point to use in it.
pub(crate) struct Loaded {
    pub module: wgpu::ShaderModule,
    pub entry: String,
}

/// Loads the entry point `entry` (of `stage`) of a compiled material by `path`.
pub(crate) fn load(
    gpu: &Gpu,
    compiled: &Compiled,
    path: ShaderPath,
    stage: ShaderStage,
    entry: &str,
) -> Result<Loaded, RunError> {
    let name = &compiled.material.name;
    let what = format!("{path} module of `{name}`");
    let create = |source: wgpu::ShaderSource<'_>| {
        gpu.checked(&what, || {
            gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(name), source })
        })
    };
    match path {
        ShaderPath::NagaIr => {
            let harness = compiled.harness().map_err(glazec::emit::EmitError::from)?;
            let module = create(wgpu::ShaderSource::Naga(Cow::Owned(harness.module.clone())))?;
            Ok(Loaded { module, entry: entry.to_string() })
        }
        ShaderPath::Wgsl => {
            let text = compiled.whole_wgsl()?;
            let module = create(wgpu::ShaderSource::Wgsl(Cow::Owned(text)))?;
            Ok(Loaded { module, entry: entry.to_string() })
        }
        ShaderPath::Glsl => {
            // The entry point's file `#include`s the library: all go to glslang's folder.
            let files = compiled.emit_with_harness(&[Target::Glsl])?;
            let artifact = files
                .iter()
                .find(|a| a.stage.as_ref().is_some_and(|(s, e)| *s == stage && e == entry))
                .ok_or_else(|| RunError::Rejected { what: what.clone(), message: format!("no GLSL for `{entry}`") })?;
            let stage_name = glazec::emit::stage_suffix(stage);
            let words = glslang(&files, &artifact.file_name, &["-V", "--target-env", "vulkan1.0", "-S", stage_name])?;
            let entry = spirv_entry_point(&words).unwrap_or_else(|| "main".to_string());
            let module = create(wgpu::ShaderSource::SpirV(Cow::Owned(words)))?;
            Ok(Loaded { module, entry })
        }
        ShaderPath::Hlsl => {
            if !gpu.passthrough {
                return Err(RunError::NoPassthrough { path: "hlsl" });
            }
            // The harness `#include`s the library: both go to glslang's folder.
            let files = compiled.emit_with_harness(&[Target::Hlsl])?;
            let harness = files.iter().find(|a| a.harness).map(|a| a.file_name.clone()).unwrap_or_default();
            let stage_name = glazec::emit::stage_suffix(stage);
            let words = glslang(&files, &harness, &["-D", "-V", "-S", stage_name, "-e", entry])?;
            let entry = spirv_entry_point(&words).unwrap_or_else(|| entry.to_string());
            let entry_points = [wgpu::PassthroughShaderEntryPoint {
                name: Cow::Owned(entry.clone()),
                workgroup_size: (glazec::lower::EVAL_WORKGROUP_SIZE, 1, 1),
            }];
            let descriptor = wgpu::ShaderModuleDescriptorPassthrough {
                label: Some(name),
                entry_points: Cow::Borrowed(&entry_points),
                spirv: Some(Cow::Owned(words)),
                ..Default::default()
            };
            // SAFETY: the SPIR-V comes from glslang compiling HLSL that naga emitted from a
            // validated module, for the same bind-group layout the pipeline uses; the test
            // suite runs spirv-val on exactly these binaries (tests/external.rs).
            let module = gpu.checked(&what, || unsafe { gpu.device.create_shader_module_passthrough(descriptor) })?;
            Ok(Loaded { module, entry })
        }
    }
}

/// Runs `glslangValidator` on `file_name`, one of `files` (all written to a temporary folder,
/// so that includes resolve), and returns the SPIR-V words.
fn glslang(files: &[glazec::Artifact], file_name: &str, args: &[&str]) -> Result<Vec<u32>, RunError> {
    let dir = tempfile::tempdir()?;
    for file in files {
        std::fs::write(dir.path().join(&file.file_name), &file.contents)?;
    }
    let input = dir.path().join(file_name);
    let output = dir.path().join("out.spv");
    let result = Command::new("glslangValidator").args(args).arg(&input).arg("-o").arg(&output).output();
    let result = match result {
        Ok(r) => r,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(RunError::ToolMissing { tool: "glslangValidator" });
        }
        Err(e) => return Err(e.into()),
    };
    if !result.status.success() {
        return Err(RunError::Tool {
            tool: "glslangValidator",
            what: file_name.to_string(),
            output: format!("{}{}", String::from_utf8_lossy(&result.stdout), String::from_utf8_lossy(&result.stderr)),
        });
    }
    read_spirv(&output)
}

fn read_spirv(path: &Path) -> Result<Vec<u32>, RunError> {
    let bytes = std::fs::read(path)?;
    Ok(bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect())
}

/// The name of the first `OpEntryPoint` in a SPIR-V module.
fn spirv_entry_point(words: &[u32]) -> Option<String> {
    const OP_ENTRY_POINT: u32 = 15;
    let mut i = 5; // after the header
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        let opcode = words[i] & 0xffff;
        if count == 0 {
            return None;
        }
        if opcode == OP_ENTRY_POINT && i + 3 < words.len() {
            let bytes: Vec<u8> =
                words[i + 3..(i + count).min(words.len())].iter().flat_map(|w| w.to_le_bytes()).collect();
            let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
            return String::from_utf8(bytes[..end].to_vec()).ok();
        }
        i += count;
    }
    None
}
