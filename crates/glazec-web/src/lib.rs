//! glazec's compiler core for the browser: what the playground calls, as functions from the
//! material's text to JSON strings (so that the JavaScript side needs no generated bindings
//! beyond two functions).
//!
//! * [`check`]: the diagnostics of a material, each with its code, severity, message, 1-based
//!   line and column, and its labels' byte spans (the JSON lines of `glazec check
//!   --message-format json`, as one array);
//! * [`compile`]: on success the material's library and glazec's harness in WGSL, GLSL and
//!   HLSL, the table uniform's bytes, the runtime parameters' uniform layout with their defaults
//!   and ranges, and where the library binds its resources; on failure the diagnostics.
//!
//! Built for `wasm32-unknown-unknown` both are exported to JavaScript by `wasm-bindgen`
//! (`scripts/web`); natively they are ordinary functions, tested below.

use glazec::diag::{Diagnostic, Source};
use glazec::lower::bindings::Slot;
use glazec::{CompileError, Target};
use serde::Serialize;

/// The file name diagnostics are reported against.
const FILE: &str = "material.ron";

/// The material's diagnostics as a JSON array (empty for a material that compiles).
pub fn check(text: &str) -> String {
    match glazec::load(text) {
        Ok(_) => "[]".to_string(),
        Err(diagnostics) => diagnostics_json(text, &diagnostics),
    }
}

fn diagnostics_json(text: &str, diagnostics: &[Diagnostic]) -> String {
    let source = Source { name: FILE, text };
    let items: Vec<String> = diagnostics.iter().map(|d| glazec::diag::to_json(source, d)).collect();
    format!("[{}]", items.join(","))
}

/// One runtime parameter of the uniform block.
#[derive(Serialize)]
struct Param {
    name: String,
    /// `"f32"` or `"vec3<f32>"`.
    wgsl_type: &'static str,
    offset: u32,
    size: u32,
    /// Its default: one number, or three.
    default: Vec<f32>,
    /// The values its slots accept (per component).
    range: [f32; 2],
}

/// A texture the library samples.
#[derive(Serialize)]
struct Texture {
    /// Its name in the material (`clay_maps`).
    name: String,
    slot: Slot,
    /// Whether a layer reads it as a normal map (a host without the image binds a flat normal,
    /// (½, ½, 1); any other texture a mid-grey texel, as `glazec eval` assumes).
    normal_map: bool,
}

/// What a host needs to call the library (docs/generated-files.md, "What a library contains"):
/// `<m>_eval(n, v, l[, <m>_params][, textures])` with `textures = <m>_textures(uv[, n, t, b])`,
/// and where its resources are bound.
#[derive(Serialize)]
struct Interface {
    /// The uniform `<m>_params` exists (and is passed to `<m>_eval` and `<m>_ibl_lobes`).
    params: Option<Slot>,
    /// The table uniform, holding `tables`.
    tables: Option<Slot>,
    /// The texture sampler (`<m>_textures` exists when it does).
    sampler: Option<Slot>,
    textures: Vec<Texture>,
    /// `<m>_textures` takes the tangent frame (n, t, b) after the uv: a layer has a normal map.
    framed: bool,
}

#[derive(Serialize)]
struct Output {
    ok: bool,
    name: String,
    /// The library (`<m>.wgsl`) and glazec's harness after it (`<m>.harness.wgsl`).
    wgsl: String,
    wgsl_harness: String,
    /// The GLSL library (`<m>.glsl`), and the harness's entry points, one shader each (GLSL
    /// has one entry point a file), by file name (`<m>.eval_pairs.comp.glsl`, …).
    glsl: String,
    glsl_harness: std::collections::BTreeMap<String, String>,
    /// The HLSL library (`<m>.hlsli`) and the harness that includes it (`<m>.hlsl`).
    hlsl: String,
    hlsl_harness: String,
    /// The table uniform's bytes (empty when the library reads no table).
    tables: Vec<u8>,
    /// The runtime parameters' uniform block: its members and its size in bytes.
    params: Vec<Param>,
    params_size: u32,
    interface: Interface,
}

#[derive(Serialize)]
struct Failure {
    ok: bool,
    /// The diagnostics, as [`check`] gives them (parsed JSON objects).
    diagnostics: serde_json::Value,
    /// A compiler bug's message (naga rejected what glazec built), else empty.
    internal: String,
}

/// Compiles the material: a JSON object with `ok: true` and the outputs, or `ok: false` with
/// its `diagnostics`.
pub fn compile(text: &str) -> String {
    let failure = |diagnostics: serde_json::Value, internal: String| {
        serde_json::to_string(&Failure { ok: false, diagnostics, internal }).unwrap_or_default()
    };
    let compiled = match glazec::compile_source(Some(FILE), text) {
        Ok(c) => c,
        Err(CompileError::Diagnostics(d)) => {
            let parsed = serde_json::from_str(&diagnostics_json(text, &d)).unwrap_or_default();
            return failure(parsed, String::new());
        }
        Err(e) => return failure(serde_json::Value::Array(Vec::new()), e.to_string()),
    };
    let artifacts = match compiled.emit_with_harness(&[Target::Wgsl, Target::Glsl, Target::Hlsl]) {
        Ok(a) => a,
        Err(e) => return failure(serde_json::Value::Array(Vec::new()), e.to_string()),
    };
    let name = compiled.material.name.clone();
    let text = |a: &glazec::Artifact| String::from_utf8_lossy(&a.contents).into_owned();
    let file = |suffix: &str| {
        artifacts.iter().find(|a| a.file_name == format!("{name}{suffix}")).map(text).unwrap_or_default()
    };
    let glsl_harness = artifacts
        .iter()
        .filter(|a| a.harness && a.file_name.ends_with(".glsl"))
        .map(|a| (a.file_name.clone(), text(a)))
        .collect();
    let (layout, params_size) = glazec::lower::params_layout(&compiled.material);
    let declared = compiled.material.uniform_params().map(|(_, p)| p);
    let params = layout
        .into_iter()
        .zip(declared)
        .map(|(p, declared)| Param {
            name: p.name,
            wgsl_type: p.wgsl_type,
            offset: p.offset,
            size: p.size,
            default: declared.default.components().to_vec(),
            range: declared.range,
        })
        .collect();
    let interface = interface(&compiled);
    let output = Output {
        ok: true,
        wgsl: file(".wgsl"),
        wgsl_harness: file(".harness.wgsl"),
        glsl: file(".glsl"),
        glsl_harness,
        hlsl: file(".hlsli"),
        hlsl_harness: file(".hlsl"),
        tables: compiled.tables_bytes(),
        params,
        params_size,
        interface,
        name,
    };
    serde_json::to_string(&output).unwrap_or_default()
}

fn interface(compiled: &glazec::Compiled) -> Interface {
    let (material, layout) = (&compiled.material, &compiled.layout);
    let normal_maps: Vec<&str> = material.normals.iter().flat_map(|(_, map)| map.textures()).collect();
    // `layout.textures` lists the sampler, then the textures in `Material::textures` order.
    let textures = material
        .textures()
        .into_iter()
        .zip(layout.textures.iter().skip(1))
        .map(|(name, (_, slot))| Texture {
            name: name.to_string(),
            slot: *slot,
            normal_map: normal_maps.contains(&name),
        })
        .collect();
    Interface {
        params: layout.params,
        tables: layout.tables,
        sampler: layout.textures.first().map(|(_, slot)| *slot),
        textures,
        framed: !material.normals.is_empty(),
    }
}

/// The JavaScript bindings of the WebAssembly build.
#[cfg(target_arch = "wasm32")]
mod js {
    use wasm_bindgen::prelude::wasm_bindgen;

    /// `check(text)`: the diagnostics as a JSON array.
    #[wasm_bindgen]
    pub fn check(text: &str) -> String {
        super::check(text)
    }

    /// `compile(text)`: the outputs, or the diagnostics, as a JSON object.
    #[wasm_bindgen]
    pub fn compile(text: &str) -> String {
        super::compile(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped(name: &str) -> String {
        let path = format!("{}/../../materials/{name}.ron", env!("CARGO_MANIFEST_DIR"));
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
    }

    fn json(text: &str) -> serde_json::Value {
        serde_json::from_str(text).unwrap_or_else(|e| panic!("not JSON ({e}): {text}"))
    }

    #[test]
    fn a_shipped_material_checks_clean_and_compiles_to_every_language() {
        let text = shipped("tunable_glaze");
        assert_eq!(check(&text), "[]");
        let out = json(&compile(&text));
        assert_eq!(out["ok"], true);
        assert_eq!(out["name"], "tunable_glaze");
        for key in ["wgsl", "wgsl_harness", "glsl", "hlsl"] {
            let source = out[key].as_str().unwrap_or_default();
            assert!(source.contains("tunable_glaze_"), "{key} holds the library's names");
        }
        assert!(out["wgsl"].as_str().unwrap_or_default().contains("fn tunable_glaze_eval("));
        assert!(out["wgsl_harness"].as_str().unwrap_or_default().contains("@fragment"));
        // glazec's harness in GLSL (one file an entry point) and HLSL (including the library).
        let glsl_harness = out["glsl_harness"].as_object().cloned().unwrap_or_default();
        let files: Vec<&str> = glsl_harness.keys().map(String::as_str).collect();
        assert_eq!(
            files,
            [
                "tunable_glaze.eval_pairs.comp.glsl",
                "tunable_glaze.preview_fs.frag.glsl",
                "tunable_glaze.preview_ibl_fs.frag.glsl",
                "tunable_glaze.preview_vs.vert.glsl"
            ]
        );
        assert!(out["hlsl_harness"].as_str().unwrap_or_default().contains("#include \"tunable_glaze.hlsli\""));
        // Its uniform block, as the shader declares it.
        let params = out["params"].as_array().cloned().unwrap_or_default();
        let names: Vec<_> = params.iter().map(|p| p["name"].as_str().unwrap_or_default().to_string()).collect();
        assert_eq!(
            names,
            ["glaze_roughness", "glaze_ior", "glaze_absorption", "glaze_thickness", "body_albedo", "body_roughness"]
        );
        assert_eq!(params[2]["wgsl_type"], "vec3<f32>");
        assert_eq!(params[2]["offset"], 16);
        assert_eq!(params[1]["default"][0].as_f64().map(|x| (x * 100.0).round()), Some(152.0));
        // WGSL's uniform layout: an f32 after a vec3 fills its last four bytes.
        assert_eq!(params[3]["offset"], 28);
        assert_eq!(out["params_size"], 48);
        // The slots' ranges: a roughness in [0, 1], a coat's IOR in [0.1, 10].
        assert_eq!(params[0]["range"], serde_json::json!([0.0, 1.0]));
        let ior = params[1]["range"].as_array().cloned().unwrap_or_default();
        assert_eq!((ior[0].as_f64().map(|x| (x * 10.0).round()), ior[1].as_f64()), (Some(1.0), Some(10.0)));
        // A runtime roughness needs the tables at run time; where both uniforms are bound.
        assert!(!out["tables"].as_array().cloned().unwrap_or_default().is_empty());
        let interface = &out["interface"];
        assert_eq!(interface["params"], serde_json::json!({"group": 0, "binding": 3}));
        assert_eq!(interface["tables"], serde_json::json!({"group": 0, "binding": 4}));
        assert_eq!(interface["sampler"], serde_json::Value::Null);
        assert_eq!(interface["framed"], false);
    }

    #[test]
    fn a_textured_material_says_where_its_textures_go_and_which_are_normal_maps() {
        let path = format!("{}/../../examples/textures/textured_clay.ron", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let out = json(&compile(&text));
        let interface = &out["interface"];
        assert_eq!(interface["sampler"], serde_json::json!({"group": 1, "binding": 0}));
        assert_eq!(interface["framed"], true);
        let textures: Vec<(String, u64, bool)> = interface["textures"]
            .as_array()
            .cloned()
            .unwrap_or_default()
            .iter()
            .map(|t| {
                let name = t["name"].as_str().unwrap_or_default().to_string();
                (name, t["slot"]["binding"].as_u64().unwrap_or(0), t["normal_map"] == true)
            })
            .collect();
        let expected =
            [("clay_maps", 1, false), ("clay_albedo", 2, false), ("clay_bumps", 3, true), ("clay_pores", 4, true)];
        let expected: Vec<_> = expected.iter().map(|(n, b, m)| (n.to_string(), *b, *m)).collect();
        assert_eq!(textures, expected);
        // Every binding the library declares is in the interface.
        for t in &textures {
            assert!(out["wgsl"].as_str().unwrap_or_default().contains(&format!("@group(1) @binding({})", t.1)));
        }
    }

    #[test]
    fn a_broken_material_gives_its_diagnostic_at_its_line_and_span() {
        let text = shipped("clay").replace("roughness: 0.6", "roughness: 1.6");
        let diagnostics = json(&check(&text));
        let first = &diagnostics[0];
        assert_eq!(first["severity"], "error");
        assert!(first["code"].as_str().unwrap_or_default().starts_with("E02"), "{first}");
        let line = text.lines().position(|l| l.contains("roughness: 1.6")).map(|i| i + 1);
        assert_eq!(first["line"].as_u64().map(|l| l as usize), line);
        let label = &first["labels"][0];
        let (start, end) =
            (label["byte_start"].as_u64().unwrap_or(0) as usize, label["byte_end"].as_u64().unwrap_or(0) as usize);
        assert_eq!(&text[start..end], "1.6");
        let out = json(&compile(&text));
        assert_eq!(out["ok"], false);
        assert_eq!(out["diagnostics"], diagnostics);
    }

    #[test]
    fn text_that_is_not_a_material_is_a_syntax_error_not_a_panic() {
        for text in ["", "Material(", "not ron at all {{{", "Material(name: \"x\", layers: [])"] {
            let diagnostics = json(&check(text));
            assert!(!diagnostics.as_array().cloned().unwrap_or_default().is_empty(), "{text:?}");
            assert_eq!(json(&compile(text))["ok"], false, "{text:?}");
        }
    }
}
