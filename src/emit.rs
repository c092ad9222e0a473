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
//! Text outputs start with a one-line header and carry each term's citation as a `//` comment
//! above its function (naga keeps doc comments in the IR but its backends do not print them).
//! naga's backends also ignore the names of call results (they always print `_e<index>`); the
//! names that `lower` gave them are restored here, inside the calling function only, so that
//! `let d = d_ggx(…)` reads as it does in the Rust source.

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
    pub const TEXT: [Target; 3] = [Target::Wgsl, Target::Glsl, Target::Hlsl];

    pub fn name(self) -> &'static str {
        match self {
            Target::Wgsl => "wgsl",
            Target::Glsl => "glsl",
            Target::Hlsl => "hlsl",
            Target::Spv => "spv",
        }
    }

    pub fn parse(name: &str) -> Option<Target> {
        [Target::Wgsl, Target::Glsl, Target::Hlsl, Target::Spv].into_iter().find(|t| t.name() == name)
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
    #[error("WGSL backend: {0}")]
    Wgsl(#[from] wgsl::Error),
    #[error("GLSL backend ({entry}): {source}")]
    Glsl { entry: String, source: glsl::Error },
    #[error("HLSL backend: {0}")]
    Hlsl(#[from] hlsl::Error),
    #[error("SPIR-V backend: {0}")]
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
pub fn emit(name: &str, module: &Module, info: &ModuleInfo, targets: &[Target]) -> Result<Vec<Artifact>, EmitError> {
    let mut targets = targets.to_vec();
    targets.sort();
    targets.dedup();
    let mut out = Vec::new();
    for target in targets {
        match target {
            Target::Wgsl => {
                let text = wgsl::write_string(module, info, wgsl::WriterFlags::empty())?;
                out.push(text_artifact(format!("{name}.wgsl"), name, module, &text, None));
            }
            Target::Glsl => {
                for ep in &module.entry_points {
                    // naga's GLSL writer includes every function that uses no excluded global,
                    // so a vertex shader would carry the whole BRDF; give it a module that holds
                    // only this entry point and what it reaches.
                    let (single, single_info) = single_entry_point(name, module, &ep.name)?;
                    let text = write_glsl(&single, &single_info, ep.stage, &ep.name)?;
                    let file = format!("{name}.{}.{}.glsl", ep.name, stage_suffix(ep.stage));
                    out.push(text_artifact(file, name, &single, &text, Some((ep.stage, ep.name.clone()))));
                }
            }
            Target::Hlsl => {
                let text = write_hlsl(module, info)?;
                out.push(text_artifact(format!("{name}.hlsl"), name, module, &text, None));
            }
            Target::Spv => {
                let options =
                    spv::Options { lang_version: (1, 0), flags: spv::WriterFlags::empty(), ..Default::default() };
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
    // (research/probe.md §3, gotcha 10) with its WGSL binding number.
    let binding_map =
        module.global_variables.iter().filter_map(|(_, var)| var.binding).map(|rb| (rb, rb.binding as u8)).collect();
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

fn text_artifact(
    file_name: String,
    material: &str,
    module: &Module,
    text: &str,
    stage: Option<(ShaderStage, String)>,
) -> Artifact {
    let mut out = format!(
        "// Generated by glazec from material `{material}`. Do not edit: change the .ron file and recompile.\n"
    );
    let glsl_entry = stage.is_some();
    out.push_str(&with_doc_comments(module, &with_call_result_names(module, text, glsl_entry)));
    Artifact { file_name, contents: out.into_bytes(), stage }
}

/// Inserts each function's doc comment (`// …`) above its definition line. Works for all three
/// text backends: a definition is a line `<type-or-fn> <name>(` at column 0.
fn with_doc_comments(module: &Module, text: &str) -> String {
    let Some(docs) = module.doc_comments.as_deref() else {
        return text.to_string();
    };
    let by_name: Vec<(String, &Vec<String>)> = docs
        .functions
        .iter()
        .filter_map(|(h, lines)| module.functions[*h].name.as_ref().map(|n| (format!("{n}("), lines)))
        .collect();
    let mut out = String::with_capacity(text.len() + 4096);
    for line in text.lines() {
        if !line.starts_with(char::is_whitespace) {
            if let Some((_, rest)) = line.split_once(' ') {
                if let Some((_, lines)) = by_name.iter().find(|(prefix, _)| rest.starts_with(prefix.as_str())) {
                    for doc in lines.iter() {
                        if doc.is_empty() {
                            out.push_str("//\n");
                        } else {
                            out.push_str("// ");
                            out.push_str(doc);
                            out.push('\n');
                        }
                    }
                }
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The printed name of each function whose call results have names, with those names by
/// expression index. In GLSL the (single) entry point is printed as `main`.
fn call_result_names(module: &Module, glsl_entry: bool) -> Vec<(String, Vec<(usize, &str)>)> {
    fn named(f: &naga::Function) -> Vec<(usize, &str)> {
        f.named_expressions
            .iter()
            .filter(|(h, _)| matches!(f.expressions[**h], naga::Expression::CallResult(_)))
            .map(|(h, name)| (h.index(), name.as_str()))
            .collect()
    }
    let functions = module.functions.iter().filter_map(|(_, f)| Some((f.name.clone()?, named(f))));
    let entries = module
        .entry_points
        .iter()
        .map(|ep| (if glsl_entry { "main".to_string() } else { ep.name.clone() }, named(&ep.function)));
    functions.chain(entries).filter(|(_, names)| !names.is_empty()).collect()
}

fn is_ident_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Replaces the identifier `from` by `to` wherever it occurs as a whole word in `line`.
fn replace_word(line: &str, from: &str, to: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut rest = line;
    let mut prev: Option<char> = None;
    while let Some(pos) = rest.find(from) {
        let before = rest[..pos].chars().next_back().or(prev);
        let after = rest[pos + from.len()..].chars().next();
        out.push_str(&rest[..pos]);
        if before.is_some_and(is_ident_char) || after.is_some_and(is_ident_char) {
            out.push_str(from);
        } else {
            out.push_str(to);
        }
        prev = from.chars().next_back();
        rest = &rest[pos + from.len()..];
    }
    out.push_str(rest);
    out
}

/// Renames `_e<N>` call results to the names `lower` chose, function by function. A function's
/// text runs from its definition line (`<type-or-fn> <name>(` at column 0) to the next line
/// that is exactly `}`. A name already used as a word in that function gets a numeric suffix.
fn with_call_result_names(module: &Module, text: &str, glsl_entry: bool) -> String {
    let functions = call_result_names(module, glsl_entry);
    if functions.is_empty() {
        return text.to_string();
    }
    let lines: Vec<&str> = text.lines().collect();
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    for (name, results) in functions {
        let prefix = format!("{name}(");
        let is_definition = |l: &&str| {
            !l.starts_with(char::is_whitespace) && l.split_once(' ').is_some_and(|(_, rest)| rest.starts_with(&prefix))
        };
        let Some(start) = lines.iter().position(is_definition) else { continue };
        let end = lines[start..].iter().position(|l| *l == "}").map_or(lines.len(), |e| start + e);
        let mut used: std::collections::BTreeSet<String> = lines[start..end]
            .iter()
            .flat_map(|l| l.split(|c: char| !is_ident_char(c)))
            .filter(|w| !w.is_empty())
            .map(str::to_string)
            .collect();
        for (index, wanted) in results {
            let mut chosen = wanted.to_string();
            let mut n = 1;
            while used.contains(&chosen) || crate::check::is_reserved(&chosen) {
                chosen = format!("{wanted}_{n}");
                n += 1;
            }
            used.insert(chosen.clone());
            let baked = format!("_e{index}");
            for line in &mut out[start..end] {
                if line.contains(&baked) {
                    *line = replace_word(line, &baked, &chosen);
                }
            }
        }
    }
    let mut joined = out.join("\n");
    if text.ends_with('\n') {
        joined.push('\n');
    }
    joined
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_whole_words_only() {
        assert_eq!(replace_word("let _e1 = f(_e12, _e1);", "_e1", "d"), "let d = f(_e12, d);");
        assert_eq!(replace_word("x_e1 + _e1x", "_e1", "d"), "x_e1 + _e1x");
    }
}
