//! Stage 5, `emit`: a validated module → shader files (thin adapters over `naga::back`).
//!
//! **Input:** a `naga::Module`, its `ModuleInfo`, and the requested [`Target`]s.
//! **Output:** [`Artifact`]s (file name + bytes), in a fixed order. Nothing is written here;
//! writing (atomically, all or nothing) is the caller's job.
//!
//! | target | files | notes |
//! |---|---|---|
//! | WGSL | `<m>.wgsl` | all entry points |
//! | GLSL 450 | `<m>.<entry>.<stage>.glsl` | one per entry point (naga's GLSL backend writes one); every binding in set 0 |
//! | HLSL SM 6.0 | `<m>.hlsl` | all entry points; registers `b`/`t`/`u` N = binding N, `space0` |
//! | SPIR-V 1.0 | `<m>.spv` | on request; all entry points |
//!
//! **Invariant:** the output is a pure function of the module: the same material gives the same
//! bytes on every run and machine (tested on every shipped material).
//!
//! Text outputs start with a one-line [`header`] (glazec version, source file, source hash) and carry each term's citation as a `//` comment
//! above its function (naga keeps doc comments in the IR but its backends do not print them).
//! naga's backends also ignore the names of call results (they always print `_e<index>`); the
//! names that `lower` gave them are restored here, inside the calling function only, so that
//! `let d = d_ggx(…)` reads as it does in the Rust source.

mod polish;

use naga::back::{glsl, hlsl, spv, wgsl};
use naga::valid::ModuleInfo;
use naga::{Module, ShaderStage};

/// An output language.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Target {
    Wgsl,
    Glsl,
    Hlsl,
    Spv,
}

impl Target {
    pub const ALL: [Target; 4] = [Target::Wgsl, Target::Glsl, Target::Hlsl, Target::Spv];
    pub const TEXT: [Target; 3] = [Target::Wgsl, Target::Glsl, Target::Hlsl];

    /// The target's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::Glsl => "glsl",
            Target::Hlsl => "hlsl",
            Target::Spv => "spv",
        }
    }

    /// What the target writes, in a few words.
    pub fn description(self) -> &'static str {
        match self {
            Target::Wgsl => "one WGSL module (.wgsl)",
            Target::Glsl => "GLSL 4.50, one file per entry point (.<entry>.<stage>.glsl)",
            Target::Hlsl => "one HLSL file, shader model 6.0 (.hlsl)",
            Target::Spv => "one SPIR-V 1.0 module (.spv)",
        }
    }
}

/// One emitted file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Artifact {
    /// File name (no directory), e.g. `clay.eval_pairs.comp.glsl`.
    pub file_name: String,
    pub contents: Vec<u8>,
    /// For GLSL files: the stage and entry point they contain (what `glslangValidator -S` needs).
    pub stage: Option<(ShaderStage, String)>,
}

/// A naga backend failed on a validated module (a bug in glazec or naga).
#[derive(Debug, thiserror::Error)]
pub enum EmitError {
    #[error("the WGSL backend failed")]
    Wgsl(#[from] wgsl::Error),
    #[error("the GLSL backend failed on entry point `{entry}`")]
    Glsl { entry: String, source: glsl::Error },
    #[error("the HLSL backend failed")]
    Hlsl(#[from] hlsl::Error),
    #[error("the SPIR-V backend failed")]
    Spv(#[from] spv::Error),
    /// A single-entry-point copy of the module failed validation.
    #[error(transparent)]
    Validate(#[from] crate::validate::ValidateError),
}

/// The file-name suffix glslang understands for a stage.
pub fn stage_suffix(stage: ShaderStage) -> &'static str {
    match stage {
        ShaderStage::Vertex => "vert",
        ShaderStage::Fragment => "frag",
        _ => "comp",
    }
}

/// Emits `targets` for the module of material `name`, in target order.
///
/// # Errors
/// A backend error (never expected for a module that passed validation).
pub fn emit(
    name: &str,
    origin: &crate::origin::Origin,
    module: &Module,
    info: &ModuleInfo,
    targets: &[Target],
) -> Result<Vec<Artifact>, EmitError> {
    let header = header(name, origin);
    let mut targets = targets.to_vec();
    targets.sort();
    targets.dedup();
    let mut out = Vec::new();
    for target in targets {
        match target {
            Target::Wgsl => {
                let text = wgsl::write_string(module, info, wgsl::WriterFlags::empty())?;
                out.push(text_artifact(format!("{name}.wgsl"), &header, module, &text, None));
            }
            Target::Glsl => {
                for ep in &module.entry_points {
                    // naga's GLSL writer includes every function that uses no excluded global,
                    // so a vertex shader would carry the whole BRDF; give it a module that holds
                    // only this entry point and what it reaches.
                    let (single, single_info) = single_entry_point(name, module, &ep.name)?;
                    let text = write_glsl(&single, &single_info, ep.stage, &ep.name)?;
                    let file = format!("{name}.{}.{}.glsl", ep.name, stage_suffix(ep.stage));
                    out.push(text_artifact(file, &header, &single, &text, Some((ep.stage, ep.name.clone()))));
                }
            }
            Target::Hlsl => {
                let text = write_hlsl(module, info)?;
                out.push(text_artifact(format!("{name}.hlsl"), &header, module, &text, None));
            }
            Target::Spv => {
                // Fixed flags (naga's default adds DEBUG only in debug builds, which would make
                // the bytes depend on the build profile): debug names for tools and reflection,
                // and WGSL's clip-space convention (no Y flip), as in the other outputs.
                let flags = spv::WriterFlags::DEBUG | spv::WriterFlags::LABEL_VARYINGS;
                let options = spv::Options { lang_version: (1, 0), flags, ..Default::default() };
                let words = spv::write_vec(module, info, &options, None)?;
                let contents = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                out.push(Artifact { file_name: format!("{name}.spv"), contents, stage: None });
            }
        }
    }
    Ok(out)
}

/// A copy of `module` with one entry point and only the functions, globals and types it uses.
fn single_entry_point(material: &str, module: &Module, entry: &str) -> Result<(Module, ModuleInfo), EmitError> {
    let mut single = module.clone();
    single.entry_points.retain(|ep| ep.name == entry);
    naga::compact::compact(&mut single, naga::compact::KeepUnused::No);
    let info = crate::validate::validate(material, &single)?;
    Ok((single, info))
}

fn write_glsl(module: &Module, info: &ModuleInfo, stage: ShaderStage, entry: &str) -> Result<String, EmitError> {
    let glsl_error = |source| EmitError::Glsl { entry: entry.to_string(), source };
    // Vulkan GLSL: naga's GLSL backend never writes `set =`, so every resource lives in set 0
    // (docs/derivations.md, "Building a naga module by hand") with its WGSL binding number.
    use crate::lower::textures::bindings::GLSL_OFFSET;
    let glsl_binding = |rb: naga::ResourceBinding| GLSL_OFFSET * rb.group + rb.binding;
    let binding_map = module
        .global_variables
        .iter()
        .filter_map(|(_, var)| var.binding)
        .map(|rb| (rb, glsl_binding(rb) as u8))
        .collect();
    let options = glsl::Options {
        version: glsl::Version::Desktop(450),
        writer_flags: glsl::WriterFlags::empty(),
        binding_map,
        zero_initialize_workgroup_memory: false,
    };
    let pipeline = glsl::PipelineOptions { shader_stage: stage, entry_point: entry.to_string(), multiview: None };
    let mut text = String::new();
    let mut writer =
        glsl::Writer::new(&mut text, module, info, &options, &pipeline, naga::proc::BoundsCheckPolicies::default())
            .map_err(glsl_error)?;
    writer.write().map_err(glsl_error)?;
    Ok(text)
}

fn write_hlsl(module: &Module, info: &ModuleInfo) -> Result<String, EmitError> {
    let options = hlsl::Options { shader_model: hlsl::ShaderModel::V6_0, ..Default::default() };
    let mut text = String::new();
    hlsl::Writer::new(&mut text, &options, &hlsl::PipelineOptions { entry_point: None }).write(module, info, None)?;
    Ok(text)
}

/// The first line of every text output: the glazec version, the source file and the hash of
/// its text (which the `build` module's generated Rust checks at compile time).
pub fn header(material: &str, origin: &crate::origin::Origin) -> String {
    let version = crate::origin::VERSION;
    let hash = origin.hash;
    let source = origin.file.as_deref().map_or_else(|| format!("material `{material}`"), |f| format!("`{f}`"));
    let scene = origin
        .scene
        .as_ref()
        .map_or_else(String::new, |(file, hash)| format!(", simplified for scene `{file}` (fnv1a64 {hash:016x})"));
    format!(
        "// Generated by glazec {version} from {source} (fnv1a64 {hash:016x}){scene}. Do not edit: change the .ron \
         file and recompile.\n"
    )
}

fn text_artifact(
    file_name: String,
    header: &str,
    module: &Module,
    text: &str,
    stage: Option<(ShaderStage, String)>,
) -> Artifact {
    let glsl_entry = stage.is_some();
    let mut out = header.to_string();
    polish::polish(module, text, glsl_entry, &mut out);
    Artifact { file_name, contents: out.into_bytes(), stage }
}
