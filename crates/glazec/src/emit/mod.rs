//! Stage 5, `emit`: validated modules → shader files (thin adapters over `naga::back`).
//!
//! **Input:** a material's library and harness modules ([`Modules`]) and the requested
//! [`Target`]s. **Output:** [`Artifact`]s (file name + bytes), in a fixed order. Nothing is
//! written here; writing (atomically, all or nothing) is the caller's job.
//!
//! Every target writes the material's **library** — what a host imports: its structs,
//! constants, functions and resources, no entry point, every module-scope name prefixed with
//! `<m>_` — and glazec's **harness** on it (`eval_pairs`, the previews: glazec's tests, `eval`,
//! `bench` and `preview` run it):
//!
//! | target | library | harness | notes |
//! |---|---|---|---|
//! | WGSL | `<m>.wgsl` | `<m>.harness.wgsl` | the harness holds only its own items: read it after the library (concatenated) |
//! | naga_oil | `<m>.naga_oil.wgsl` | — | `#define_import_path glazec::<m>`; the material's group is `#{MATERIAL_BIND_GROUP}` |
//! | GLSL 450 | `<m>.glsl` | `<m>.<entry>.<stage>.glsl` | the library has no `#version` and no `main` (for `#include` or concatenation); each harness file is a whole shader |
//! | HLSL SM 6.0 | `<m>.hlsli` | `<m>.hlsl` | the harness `#include`s the library; registers `b`/`t`/`u` N = binding N, space = group |
//! | SPIR-V 1.0 | — | `<m>.spv` | on request; library and harness in one module |
//!
//! In the GLSL and HLSL libraries, what naga writes for every module alike (helpers such as
//! `naga_f2u32`, HLSL's sampler heap) sits inside `#ifndef GLAZEC_<NAME>` guards, so that two
//! libraries can be included into one shader.
//!
//! **Invariant:** the output is a pure function of the modules: the same material gives the
//! same bytes on every run and machine (tested on every shipped material).
//!
//! Text outputs start with a one-line [`header`] (glazec version, source file, source hash) and carry each term's citation as a `//` comment
//! above its function (naga keeps doc comments in the IR but its backends do not print them).
//! naga's backends also ignore the names of call results (they always print `_e<index>`); the
//! names that `lower` gave them are restored here, inside the calling function only, so that
//! `let d = d_ggx(…)` reads as it does in the Rust source.

mod items;
mod library;
mod polish;

use naga::back::{glsl, hlsl, spv, wgsl};
use naga::valid::ModuleInfo;
use naga::{Module, ShaderStage};

/// An output language.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Target {
    Wgsl,
    NagaOil,
    Glsl,
    Hlsl,
    Spv,
}

impl Target {
    pub const ALL: [Target; 5] = [Target::Wgsl, Target::NagaOil, Target::Glsl, Target::Hlsl, Target::Spv];
    pub const TEXT: [Target; 4] = [Target::Wgsl, Target::NagaOil, Target::Glsl, Target::Hlsl];

    /// The target's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::NagaOil => "naga-oil",
            Target::Glsl => "glsl",
            Target::Hlsl => "hlsl",
            Target::Spv => "spv",
        }
    }

    /// What the target writes, in a few words.
    pub fn description(self) -> &'static str {
        match self {
            Target::Wgsl => "WGSL: the library (.wgsl) and glazec's harness (.harness.wgsl)",
            Target::NagaOil => "the WGSL library as a naga_oil module (.naga_oil.wgsl), for Bevy and wgsl_bindgen",
            Target::Glsl => {
                "GLSL 4.50: the library (.glsl) and one harness file per entry point (.<entry>.<stage>.glsl)"
            }
            Target::Hlsl => "HLSL, shader model 6.0: the library (.hlsli) and the harness (.hlsl)",
            Target::Spv => "one SPIR-V 1.0 module with the harness's entry points (.spv)",
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
    /// Whether the file is glazec's harness (else the material's library).
    pub harness: bool,
}

/// What [`emit`] writes from: a material's library, validated, where its resources are bound,
/// and glazec's harness when it is wanted.
#[derive(Clone, Copy)]
pub struct Modules<'a> {
    pub library: &'a Module,
    pub library_info: &'a ModuleInfo,
    pub layout: &'a crate::lower::bindings::Layout,
    pub harness: Option<HarnessModule<'a>>,
}

/// The library followed by glazec's harness, validated.
#[derive(Clone, Copy)]
pub struct HarnessModule<'a> {
    pub module: &'a Module,
    pub info: &'a ModuleInfo,
    /// Whether to write the harness files beside the libraries (SPIR-V, which holds the
    /// harness's entry points, is written from `module` either way).
    pub files: bool,
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
    /// SPIR-V was asked for without the harness module it is written from (a bug in the caller).
    #[error("SPIR-V is written from glazec's harness, which was not given")]
    NoHarness,
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

/// Emits `targets` for material `name`, in target order.
///
/// # Errors
/// A backend error (never expected for a module that passed validation).
pub fn emit(
    name: &str,
    origin: &crate::origin::Origin,
    modules: Modules<'_>,
    targets: &[Target],
) -> Result<Vec<Artifact>, EmitError> {
    let Modules { library, library_info, layout, harness } = modules;
    let header = header(name, origin);
    let harness_header = |library_file: &str, how: &str| {
        format!(
            "{header}// glazec's harness for `{name}` (its tests, `glazec eval`, `bench` and `preview`), {how} {library_file}.\n"
        )
    };
    let mut targets = targets.to_vec();
    targets.sort();
    targets.dedup();
    let mut out = Vec::new();
    // The WGSL library, written once for the WGSL and naga_oil targets.
    let wgsl_library = if targets.iter().any(|t| matches!(t, Target::Wgsl | Target::NagaOil)) {
        polished(name, library, &wgsl::write_string(library, library_info, wgsl::WriterFlags::empty())?, false)
    } else {
        String::new()
    };
    // The harness files are written from the whole module with the library's function bodies
    // left out (`library::harness_view`): the backends then write the library once, not again
    // for every harness file.
    let view = match harness {
        Some(h) if h.files && targets.iter().any(|t| matches!(t, Target::Wgsl | Target::Glsl | Target::Hlsl)) => {
            let view = library::harness_view(library, h.module);
            let view_info = crate::validate::validate(name, &view)?;
            Some((view, view_info, h.module))
        }
        _ => None,
    };
    for target in targets {
        match target {
            Target::Wgsl => {
                out.push(artifact(format!("{name}.wgsl"), &header, &wgsl_library, None, false));
                if let Some((view, view_info, _)) = &view {
                    let full = wgsl::write_string(view, view_info, wgsl::WriterFlags::empty())?;
                    let harness = polished(name, view, &library::harness_items(&full, &wgsl_library), false);
                    let harness_header = harness_header(&format!("{name}.wgsl"), "to be read after");
                    out.push(artifact(format!("{name}.harness.wgsl"), &harness_header, &harness, None, true));
                }
            }
            Target::NagaOil => {
                let text = library::naga_oil(name, &wgsl_library, layout);
                out.push(artifact(format!("{name}.naga_oil.wgsl"), &header, &text, None, false));
            }
            Target::Glsl => {
                let probe = library::glsl_probe(library);
                let probe_info = crate::validate::analyse(name, &probe)?;
                let probe_text = write_glsl(&probe, &probe_info, ShaderStage::Fragment, "main")?;
                let text = library::glsl_library(name, library, polished(name, library, &probe_text, false));
                let library_file = format!("{name}.glsl");
                out.push(artifact(library_file.clone(), &header, &text, None, false));
                if let Some((view, _, module)) = &view {
                    let declared = library::declared_names(&text);
                    for ep in &module.entry_points {
                        let (single, single_info) = single_entry_point(name, view, &ep.name)?;
                        let entry = write_glsl(&single, &single_info, ep.stage, &ep.name)?;
                        let whole = library::glsl_entry(&entry, &library_file, &declared, |harness| {
                            polished(name, &single, harness, true)
                        });
                        let file = format!("{name}.{}.{}.glsl", ep.name, stage_suffix(ep.stage));
                        out.push(artifact(file, &header, &whole, Some((ep.stage, ep.name.clone())), true));
                    }
                }
            }
            Target::Hlsl => {
                let library_text = polished(name, library, &write_hlsl(library, library_info)?, false);
                let harness_text = match &view {
                    Some((view, view_info, _)) => Some(polished(
                        name,
                        view,
                        &library::harness_items(&write_hlsl(view, view_info)?, &library_text),
                        false,
                    )),
                    None => None,
                };
                let library_text = library::guarded(&library_text, name);
                out.push(artifact(format!("{name}.hlsli"), &header, &library_text, None, false));
                if let Some(harness) = harness_text {
                    let harness = format!("#include \"{name}.hlsli\"\n\n{harness}");
                    let harness_header = harness_header(&format!("{name}.hlsli"), "which includes");
                    out.push(artifact(format!("{name}.hlsl"), &harness_header, &harness, None, true));
                }
            }
            Target::Spv => {
                let h = harness.ok_or(EmitError::NoHarness)?;
                // Fixed flags (naga's default adds DEBUG only in debug builds, which would make
                // the bytes depend on the build profile): debug names for tools and reflection,
                // and WGSL's clip-space convention (no Y flip), as in the other outputs.
                let flags = spv::WriterFlags::DEBUG | spv::WriterFlags::LABEL_VARYINGS;
                let options = spv::Options { lang_version: (1, 0), flags, ..Default::default() };
                let words = spv::write_vec(h.module, h.info, &options, None)?;
                let contents = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                out.push(Artifact { file_name: format!("{name}.spv"), contents, stage: None, harness: true });
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

/// Backend text with the doc comments and call-result names restored ([`polish`]).
fn polished(material: &str, module: &Module, text: &str, glsl_entry: bool) -> String {
    // Room for the comments the polish adds (about a third of a library's text).
    let mut out = String::with_capacity(text.len() * 3 / 2);
    polish::polish(module, material, text, glsl_entry, &mut out);
    out
}

fn artifact(
    file_name: String,
    header: &str,
    text: &str,
    stage: Option<(ShaderStage, String)>,
    harness: bool,
) -> Artifact {
    let mut out = header.to_string();
    out.push_str(text);
    if !out.ends_with('\n') {
        out.push('\n');
    }
    Artifact { file_name, contents: out.into_bytes(), stage, harness }
}
