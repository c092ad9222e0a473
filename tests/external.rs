//! Every generated shader passes the external validators, not only naga's:
//!
//! * WGSL: re-parsed by naga's own WGSL front end and validated again (a text round trip);
//! * GLSL: `glslangValidator -V` (Vulkan GLSL → SPIR-V), then `spirv-val`;
//! * HLSL: `glslangValidator -D -V -S <stage> -e <entry>` (glslang's HLSL front end), then
//!   `spirv-val` (there is no dxc on Linux here; see docs/limitations.md);
//! * SPIR-V from naga's own backend: `spirv-val`.
//!
//! The tools come from Debian's `glslang-tools` and `spirv-tools`. Without them the test skips
//! with a visible message; `.ci/run` sets `GLAZEC_REQUIRE_TOOLS=1`, which makes that a failure.

mod common;

use std::path::Path;
use std::process::Command;

use glazec::Target;
use naga::valid::{Capabilities, ValidationFlags, Validator};

fn run(cmd: &mut Command) -> Result<(), String> {
    let out = cmd.output().map_err(|e| format!("{cmd:?}: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{cmd:?} failed ({}):\n{}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

fn glslang_stage(stage: naga::ShaderStage) -> &'static str {
    glazec::emit::stage_suffix(stage)
}

/// Compiles with glslang and validates the result; returns a failure description.
fn check_with_glslang(file: &Path, args: &[&str], spv: &Path) -> Result<(), String> {
    let mut cmd = Command::new("glslangValidator");
    cmd.args(args).arg(file).arg("-o").arg(spv);
    run(&mut cmd)?;
    run(Command::new("spirv-val").arg("--target-env").arg("vulkan1.0").arg(spv))
}

#[test]
fn wgsl_round_trips_through_naga() {
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let parse = |text: &str| {
            let module = naga::front::wgsl::parse_str(text).unwrap_or_else(|e| {
                panic!("{}: naga cannot re-parse its WGSL:\n{}", path.display(), e.emit_to_string(text))
            });
            Validator::new(ValidationFlags::all(), Capabilities::default()).validate(&module).unwrap_or_else(|e| {
                panic!("{}: re-parsed WGSL does not validate:\n{}", path.display(), e.emit_to_string(text))
            });
            module
        };
        // The library alone, and with the harness after it: every entry point and function kept.
        let library = compiled.emit(&[Target::Wgsl]).expect("emits").remove(0);
        let library = parse(&String::from_utf8(library.contents).expect("utf-8"));
        assert!(library.entry_points.is_empty(), "{}: the library has entry points", path.display());
        assert_eq!(library.functions.len(), compiled.library.functions.len());
        let module = parse(&compiled.whole_wgsl().expect("emits"));
        let harness = compiled.harness().expect("the harness validates");
        assert_eq!(module.entry_points.len(), harness.module.entry_points.len());
        assert_eq!(module.functions.len(), harness.module.functions.len());
    }
}

#[test]
fn glsl_hlsl_and_spirv_pass_glslang_and_spirv_val() {
    if !common::tool_available("glslangValidator") || !common::tool_available("spirv-val") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let mut failures = Vec::new();
    let mut checked = 0;
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let artifacts =
            compiled.emit_with_harness(&[Target::Wgsl, Target::Glsl, Target::Hlsl, Target::Spv]).expect("emits");
        for artifact in &artifacts {
            let file = dir.path().join(&artifact.file_name);
            std::fs::write(&file, &artifact.contents).expect("writes");
        }
        for artifact in &artifacts {
            let file = dir.path().join(&artifact.file_name);
            let result = if let Some((stage, _)) = &artifact.stage {
                checked += 1;
                let spv = file.with_extension("glsl.spv");
                check_with_glslang(&file, &["-V", "--target-env", "vulkan1.0", "-S", glslang_stage(*stage)], &spv)
            } else if artifact.file_name.ends_with(".hlsl") {
                let mut result = Ok(());
                for ep in &compiled.harness().expect("the harness validates").module.entry_points {
                    checked += 1;
                    let spv = dir.path().join(format!("{}.{}.hlsl.spv", compiled.material.name, ep.name));
                    let stage = glslang_stage(ep.stage);
                    let r = check_with_glslang(&file, &["-D", "-V", "-S", stage, "-e", &ep.name], &spv);
                    result = result.and(r);
                }
                result
            } else if artifact.file_name.ends_with(".glsl") {
                // The library: a fragment shader around it.
                checked += 1;
                let wrapped = dir.path().join(format!("{}.library.frag", compiled.material.name));
                let text =
                    format!("#version 450 core\n{}\nvoid main() {{}}\n", String::from_utf8_lossy(&artifact.contents));
                std::fs::write(&wrapped, text).expect("writes");
                let spv = wrapped.with_extension("frag.spv");
                check_with_glslang(&wrapped, &["-V", "--target-env", "vulkan1.0", "-S", "frag"], &spv)
            } else if artifact.file_name.ends_with(".spv") {
                checked += 1;
                run(Command::new("spirv-val").arg("--target-env").arg("vulkan1.0").arg(&file))
            } else {
                Ok(())
            };
            if let Err(e) = result {
                failures.push(format!("{} ({}): {e}", artifact.file_name, path.display()));
            }
        }
    }
    assert!(failures.is_empty(), "{} of {checked} checks failed:\n{}", failures.len(), failures.join("\n"));
    eprintln!("{checked} external validations passed");
}

/// Member name → byte offset of every struct named `struct_name` that carries offsets in a
/// SPIR-V module (as `spirv-dis` prints it).
fn struct_offsets(spv: &Path, struct_name: &str) -> Vec<std::collections::BTreeMap<String, u32>> {
    use std::collections::BTreeMap;
    let out = Command::new("spirv-dis").arg(spv).output().expect("runs spirv-dis");
    let text = String::from_utf8_lossy(&out.stdout);
    let mut ids = Vec::new();
    let mut members: BTreeMap<(String, u32), String> = BTreeMap::new();
    let mut offsets: BTreeMap<(String, u32), u32> = BTreeMap::new();
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["OpName", id, name] if name.trim_matches('"') == struct_name => ids.push(id.to_string()),
            ["OpMemberName", id, index, name] => {
                members.insert((id.to_string(), index.parse().expect("index")), name.trim_matches('"').to_string());
            }
            ["OpMemberDecorate", id, index, "Offset", offset] => {
                offsets.insert((id.to_string(), index.parse().expect("index")), offset.parse().expect("offset"));
            }
            _ => {}
        }
    }
    ids.iter()
        .map(|id| {
            members
                .iter()
                .filter(|((owner, _), name)| owner == id && !name.starts_with("_pad"))
                .filter_map(|(key, name)| offsets.get(key).map(|&o| (name.clone(), o)))
                .collect::<BTreeMap<_, _>>()
        })
        .filter(|m| !m.is_empty())
        .collect()
}

#[test]
fn runtime_parameters_have_one_layout_in_every_backend() {
    if !common::tool_available("glslangValidator") || !common::tool_available("spirv-dis") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let mut checked = 0;
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        if compiled.material.params.is_empty() {
            continue;
        }
        let struct_name = compiled.material.params_struct_name();
        let (layout, _) = glazec::lower::params_layout(&compiled.material);
        let expected: std::collections::BTreeMap<String, u32> =
            layout.iter().map(|p| (p.name.clone(), p.offset)).collect();
        let artifacts = compiled.emit_with_harness(&[Target::Glsl, Target::Hlsl, Target::Spv]).expect("emits");
        let mut spirv_files = Vec::new();
        for artifact in &artifacts {
            let file = dir.path().join(&artifact.file_name);
            std::fs::write(&file, &artifact.contents).expect("writes");
            if artifact.file_name.ends_with(".spv") {
                spirv_files.push(("naga SPIR-V", file));
            } else if artifact.file_name.ends_with(".eval_pairs.comp.glsl") {
                let spv = file.with_extension("spv");
                check_with_glslang(&file, &["-V", "-S", "comp"], &spv).expect("GLSL compiles");
                spirv_files.push(("GLSL via glslang", spv));
            } else if artifact.file_name.ends_with(".hlsl") {
                let spv = file.with_extension("spv");
                check_with_glslang(&file, &["-D", "-V", "-S", "comp", "-e", "eval_pairs"], &spv)
                    .expect("HLSL compiles");
                spirv_files.push(("HLSL via glslang", spv));
            }
        }
        assert_eq!(spirv_files.len(), 3, "{}", path.display());
        for (what, spv) in spirv_files {
            let found = struct_offsets(&spv, &struct_name);
            assert!(!found.is_empty(), "{}: no laid-out `{struct_name}` in the {what} module", path.display());
            for layout in found {
                assert_eq!(layout, expected, "{}: {what} lays out `{struct_name}` differently", path.display());
                checked += 1;
            }
        }
    }
    assert!(checked >= 3, "at least one material with runtime parameters is checked in three backends");
}
