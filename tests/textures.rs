//! Texture reads (`Texture(name, channel, uv_scale, range)`): the language's checks, the
//! resources every backend declares, and on lavapipe (naga IR and WGSL paths) that a material
//! reading uniform textures computes exactly what the same material with constants does.

mod common;

use glam::Vec3;
use glazec::Target;
use glazec::diag::Code;
use glazec::eval::Pair;
use glazec::model::ParamValue;
use glazec_gpu::ShaderPath;
use glazec_gpu::textures::TextureImage;

/// The example material: two textures, three reads (a packed map's G and B, an albedo map).
fn textured_clay() -> String {
    std::fs::read_to_string(common::root().join("examples/textures/textured_clay.ron")).expect("example material")
}

/// The same stack with the texture reads replaced by constants (the values below).
const CONSTANT_CLAY: &str = r#"Material(
    name: "constant_clay",
    layers: [
        Coat(lobe: Ggx(roughness: 0.3), ior: 1.33, absorption: (0.3, 0.2, 0.1), thickness: 0.45),
        Eon(albedo: (0.7, 0.5, 0.4), roughness: 0.6),
    ],
)"#;

/// The texture-read values that make `textured_clay` equal `CONSTANT_CLAY`, in parameter order
/// (clay_maps G → roughness, clay_maps B → thickness, clay_albedo RGB → albedo).
fn constant_values() -> Vec<ParamValue> {
    vec![ParamValue::Scalar(0.3), ParamValue::Scalar(0.45), ParamValue::Rgb([0.7, 0.5, 0.4])]
}

fn codes(text: &str) -> Vec<Code> {
    match glazec::load(text) {
        Ok(_) => Vec::new(),
        Err(diagnostics) => diagnostics.iter().map(|d| d.code).collect(),
    }
}

fn material(layers: &str) -> String {
    format!("Material(name: \"m\", layers: [{layers}])")
}

/// The relative step of a half float (10 fraction bits): the previews' precision.
const HALF_STEP: f32 = 1.0 / 1024.0;
#[test]
fn texture_reads_become_parameters_with_their_ranges() {
    let (m, _) = glazec::load(&textured_clay()).expect("checks");
    let names: Vec<&str> = m.params.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["clay_maps_g", "clay_maps_b", "clay_albedo_rgb"]);
    assert_eq!(m.textures(), ["clay_maps", "clay_albedo", "clay_bumps", "clay_pores"]);
    // Defaults: a mid-grey texel, the middle of each range.
    assert_eq!(m.default_values()[0], ParamValue::Scalar(0.3));
    assert_eq!(m.default_values()[2], ParamValue::Rgb([0.5; 3]));
    // No uniform struct: every parameter is a texture read.
    assert_eq!(glazec::lower::params_layout(&m).0.len(), 0);
}

#[test]
fn bad_texture_reads_are_diagnosed() {
    // An IOR needs a range: a texel value of 0 lies outside the IOR's [0.1, 10].
    assert_eq!(
        codes(&material(r#"Coat(lobe: Smooth, ior: Texture("m", R, 1.0)), Lambert(0.5)"#)),
        [Code::TextureRange]
    );
    // A range outside the slot's own range.
    assert_eq!(
        codes(&material(r#"Coat(lobe: Ggx(Texture("m", R, 1.0, (0.2, 1.5))), ior: 1.5), Lambert(0.5)"#)),
        [Code::RoughnessRange]
    );
    // uv_scale must be positive.
    assert_eq!(codes(&material(r#"Lambert(Texture("m", Rgb, 0.0))"#)), [Code::TextureRange]);
    // Three channels in a slot that takes one number.
    assert_eq!(
        codes(&material(r#"Coat(lobe: Ggx(Texture("m", Rgb, 1.0)), ior: 1.5), Lambert(0.5)"#)),
        [Code::WrongType]
    );
    // An unknown channel (with a suggestion).
    assert_eq!(codes(&material(r#"Lambert(Texture("m", Rbg, 1.0))"#)), [Code::UnknownVariant]);
    // One channel read two ways.
    assert_eq!(
        codes(&material(
            r#"Coat(lobe: Ggx(Texture("m", R, 1.0)), ior: 1.5), Eon(albedo: 0.5, roughness: Texture("m", R, 2.0))"#
        )),
        [Code::ParamConflict]
    );
    // A uniform parameter cannot take a texture read's name.
    assert_eq!(
        codes(&material(
            r#"Coat(lobe: Ggx(Texture("m", R, 1.0)), ior: 1.5), Eon(albedo: 0.5, roughness: Param("m_r", 0.5))"#
        )),
        [Code::ParamConflict]
    );
    // Nine textures.
    let coats: Vec<String> = (0..9).map(|i| format!(r#"Coat(lobe: Ggx(Texture("t{i}", R, 1.0)), ior: 1.5)"#)).collect();
    assert_eq!(codes(&material(&format!("{}, Lambert(0.5)", coats.join(", ")))), [Code::TooManyTextures]);
}

#[test]
fn every_backend_declares_the_documented_bindings() {
    let compiled = glazec::compile(&textured_clay()).expect("compiles");
    assert_eq!(
        compiled.layout.textures,
        ["sampler", "clay_maps", "clay_albedo", "clay_bumps", "clay_pores"]
            .iter()
            .enumerate()
            .map(|(i, n)| (format!("textured_clay_{n}"), glazec::lower::bindings::Slot::new(1, i as u32)))
            .collect::<Vec<_>>()
    );
    let artifacts = compiled.emit(&[Target::Wgsl, Target::Glsl, Target::Hlsl]).expect("emits");
    let text = |suffix: &str| {
        let a = artifacts.iter().find(|a| a.file_name.ends_with(suffix)).expect("artifact");
        String::from_utf8(a.contents.clone()).expect("utf-8")
    };
    let wgsl = text(".wgsl");
    for line in [
        "@group(1) @binding(0) \nvar textured_clay_sampler: sampler;",
        "@group(1) @binding(1) \nvar textured_clay_clay_maps: texture_2d<f32>;",
    ] {
        assert!(wgsl.contains(line), "WGSL lacks {line:?}");
    }
    let signature = wgsl.lines().find(|l| l.starts_with("fn textured_clay_brdf(")).expect("the BRDF function");
    assert!(signature.ends_with("textures: TexturedClayTextures) -> vec3<f32> {"), "{signature}");
    // One sample per texture: the packed map's G and B share it.
    assert_eq!(wgsl.matches("textureSampleLevel(textured_clay_clay_maps").count(), 1);
    let glsl = text("textured_clay.glsl");
    assert!(glsl.contains("layout(binding = 17) uniform sampler2D"), "GLSL: textures at 16 + binding");
    let hlsl = text(".hlsli");
    assert!(hlsl.contains("Texture2D<float4> textured_clay_clay_maps : register(t1, space1);"));
}

/// glslang on every GLSL stage and every HLSL entry point, spirv-val on the SPIR-V.
#[test]
fn textured_shaders_pass_the_external_validators() {
    if !common::tool_available("glslangValidator") {
        return;
    }
    let compiled = glazec::compile(&textured_clay()).expect("compiles");
    let dir = tempfile::tempdir().expect("temp dir");
    let mut runs: Vec<(String, Vec<String>)> = Vec::new();
    for artifact in compiled.emit_with_harness(&[Target::Glsl, Target::Hlsl]).expect("emits") {
        let path = dir.path().join(&artifact.file_name);
        std::fs::write(&path, &artifact.contents).expect("write");
        let file = path.to_string_lossy().to_string();
        match &artifact.stage {
            Some((stage, _)) => {
                runs.push((file, vec!["-V".into(), "-S".into(), glazec::emit::stage_suffix(*stage).into()]))
            }
            // The GLSL library: inside a fragment shader.
            None if artifact.file_name.ends_with(".glsl") => {
                let wrapped = dir.path().join("library.frag");
                let text =
                    format!("#version 450 core\n{}\nvoid main() {{}}\n", String::from_utf8_lossy(&artifact.contents));
                std::fs::write(&wrapped, text).expect("write");
                runs.push((wrapped.to_string_lossy().to_string(), vec!["-V".into(), "-S".into(), "frag".into()]));
            }
            // The HLSL harness (which includes the library): every entry point.
            None if artifact.file_name.ends_with(".hlsl") => {
                for (stage, entry) in
                    [("comp", "eval_pairs"), ("vert", "preview_vs"), ("frag", "preview_fs"), ("frag", "preview_ibl_fs")]
                {
                    let args = ["-D", "-V", "-S", stage, "-e", entry].map(String::from).to_vec();
                    runs.push((file.clone(), args));
                }
            }
            // The HLSL library (checked through the harness) and the table file.
            None => {}
        }
    }
    assert_eq!(runs.len(), 9, "the GLSL library, four GLSL entry points and four HLSL entry points");
    if common::tool_available("spirv-val") {
        let spv = compiled.emit(&[Target::Spv]).expect("emits").remove(0);
        let path = dir.path().join(&spv.file_name);
        std::fs::write(&path, &spv.contents).expect("write");
        let out = std::process::Command::new("spirv-val").arg(&path).output().expect("runs");
        assert!(out.status.success(), "spirv-val: {}", String::from_utf8_lossy(&out.stderr));
    }
    for (file, args) in runs {
        let out = std::process::Command::new("glslangValidator")
            .args(&args)
            .arg(&file)
            .arg("-o")
            .arg(dir.path().join("out.spv"))
            .output()
            .expect("runs");
        assert!(out.status.success(), "{file} {args:?}: {}", String::from_utf8_lossy(&out.stdout));
    }
}

fn pairs() -> Vec<Pair> {
    let dir = |t: f32, p: f32| {
        let (t, p) = (t.to_radians(), p.to_radians());
        Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
    };
    let mut pairs = Vec::new();
    for ti in [0.0, 20.0, 45.0, 70.0, 85.0] {
        for to in [5.0, 30.0, 60.0, 80.0] {
            for phi in [0.0, 90.0, 180.0] {
                pairs.push(Pair { wi: dir(ti, 0.0), wo: dir(to, phi) });
            }
        }
    }
    pairs
}

#[test]
fn uniform_textures_equal_the_constant_case_on_the_gpu() {
    let Some(gpu) = common::open_gpu() else { return };
    let gpu = &gpu;
    let textured = glazec::compile(&textured_clay()).expect("compiles");
    let constant = glazec::compile(CONSTANT_CLAY).expect("compiles");
    let pairs = pairs();
    let expected: Vec<Vec3> = pairs.iter().map(|p| glazec::eval::brdf(&constant.material, &[], p.wi, p.wo)).collect();
    let max = expected.iter().map(|v| v.max_element()).fold(0.0, f32::max);
    // The texture-read parameters evaluate on the CPU like literals.
    for (p, e) in pairs.iter().zip(&expected) {
        let cpu = glazec::eval::brdf(&textured.material, &constant_values(), p.wi, p.wo);
        for c in 0..3 {
            assert!(common::agreement::agrees(e[c], cpu[c], max), "CPU: {cpu} against {e}");
        }
    }
    // GLSL and HLSL bind textures differently (a combined `sampler2D`; D3D12's sampler heap):
    // they are validated above, not run here.
    for path in [ShaderPath::NagaIr, ShaderPath::Wgsl] {
        let kernel = glazec_gpu::EvalKernel::new(gpu, &textured, path).expect("kernel");
        let values = kernel.eval(gpu, &pairs, &constant_values()).expect("runs");
        for (v, e) in values.iter().zip(&expected) {
            for c in 0..3 {
                assert!(common::agreement::agrees(e[c], v[c], max), "{path}: {v} against {e}");
            }
        }
        // And the textures do drive the result: other texels, other values.
        let other = vec![ParamValue::Scalar(0.12), ParamValue::Scalar(0.0), ParamValue::Rgb([0.1, 0.2, 0.9])];
        let changed = kernel.eval(gpu, &pairs, &other).expect("runs");
        assert!(changed.iter().zip(&values).any(|(a, b)| (*a - *b).abs().max_element() > 1e-3), "{path}");
    }
    eprintln!("texture reads: {} pairs × 2 paths agree with the constant material", pairs.len());
}

#[test]
fn previews_sample_the_images_at_the_sphere_uv() {
    use glazec_gpu::preview::{self, Environment, PreviewOptions};
    let Some(gpu) = common::open_gpu() else { return };
    let gpu = &gpu;
    let textured = glazec::compile(&textured_clay()).expect("compiles");
    let constant = glazec::compile(CONSTANT_CLAY).expect("compiles");
    let options = PreviewOptions { size: 64, environment: Environment::None, ..Default::default() };
    let a = preview::render(gpu, &constant, &[], &options).expect("renders");
    let b = preview::render(gpu, &textured, &constant_values(), &options).expect("renders");
    // The previews are half floats (Rgba16Float). The constant clay's table lookups are curves
    // summed in its code and the textured clay's (runtime roughness) are lookups: the same
    // numbers up to f32 rounding, which may round to neighbouring half floats: one step apart.
    let worst = a
        .iter()
        .zip(&b)
        .flat_map(|(x, y)| {
            (0..4).map(move |c| (x[c] - y[c]).abs() / (HALF_STEP * x[c].abs().max(y[c].abs()).max(1e-3)))
        })
        .fold(0.0, f32::max);
    assert!(worst <= 1.0, "uniform textures: previews differ by {worst} half-float steps");
    // An albedo image whose left half (u < ½, the sphere's left side) is black darkens that side.
    // (64 texels wide, so that bilinear filtering blends only a sliver around u = ½.)
    let texels = (0..64).map(|i| if i < 32 { [0.0, 0.0, 0.0, 1.0] } else { [0.7, 0.5, 0.4, 1.0] }).collect();
    let half_black = TextureImage { width: 64, height: 1, texels };
    let options = PreviewOptions { textures: vec![("clay_albedo".into(), half_black)], ..options };
    let c = preview::render(gpu, &textured, &constant_values(), &options).expect("renders");
    let side_mean = |image: &[[f32; 4]], left: bool| -> f32 {
        let size = 64;
        let (mut sum, mut n) = (0.0, 0);
        for y in 20..44 {
            for x in if left { 12..24 } else { 40..52 } {
                let p = image[y * size + x];
                sum += p[0] + p[1] + p[2];
                n += 1;
            }
        }
        sum / n as f32
    };
    assert!(side_mean(&c, true) < 0.8 * side_mean(&b, true), "left side not darkened");
    assert!((side_mean(&c, false) - side_mean(&b, false)).abs() < 0.1 * side_mean(&b, false), "right side changed");
}

/// (`preview` is in builds with the `gpu` feature.)
#[cfg(feature = "gpu")]
#[test]
fn preview_rejects_an_image_for_a_texture_no_material_reads() {
    let out = tempfile::tempdir().expect("temp dir");
    let output = common::glazec(&[
        "preview",
        "examples/textures/textured_clay.ron",
        "-o",
        &out.path().join("p.png").to_string_lossy(),
        "--texture",
        "clay_map=examples/textures/clay_maps.png",
    ]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains(
            "no material reads a texture of that name (they read: clay_maps, clay_albedo, clay_bumps, clay_pores)"
        ),
        "{stderr}"
    );
    assert!(!out.path().join("p.png").exists(), "nothing is written");
}

// ---- normal maps ---------------------------------------------------------------------------

/// Reoriented normal mapping written from the paper (Barré-Brisebois & Hill 2012, listing
/// "RNM"), in f64: independent of `glazec::math::terms::rnm_blend`.
fn rnm_f64(base: glam::DVec3, detail: glam::DVec3) -> glam::DVec3 {
    let t = base + glam::DVec3::Z;
    let u = detail * glam::DVec3::new(-1.0, -1.0, 1.0);
    (t * t.dot(u) / t.z - u).normalize()
}

/// A unit normal within 50° of +z, from a seed.
fn tilted(seed: u32) -> glam::DVec3 {
    let a = f64::from(seed).mul_add(2.399_963, 0.3);
    let tilt = (0.1 + 0.8 * f64::from(seed % 7) / 7.0).min(0.87);
    glam::DVec3::new(tilt * a.cos(), tilt * a.sin(), 1.0).normalize()
}

/// Blending tolerance against the f64 formula (f32 arithmetic on unit vectors).
const BLEND_TOLERANCE: f32 = 2e-6;

#[test]
fn rnm_blending_matches_the_papers_formula_and_its_identities() {
    use glazec::math::terms::rnm_blend;
    for i in 0..64 {
        let (base, detail) = (tilted(i), tilted(i * 31 + 5));
        let ours = rnm_blend::<f32>(base.as_vec3(), detail.as_vec3());
        let theirs = rnm_f64(base, detail).as_vec3();
        assert!((ours - theirs).abs().max_element() < BLEND_TOLERANCE, "{ours} against {theirs}");
        // A flat detail leaves the base; a flat base takes the detail.
        let flat = rnm_blend::<f32>(base.as_vec3(), Vec3::Z);
        assert!((flat - base.as_vec3()).abs().max_element() < BLEND_TOLERANCE);
        let onto_flat = rnm_blend::<f32>(Vec3::Z, detail.as_vec3());
        assert!((onto_flat - detail.as_vec3()).abs().max_element() < BLEND_TOLERANCE);
    }
}

#[test]
fn normal_maps_are_read_per_layer() {
    let (m, _) = glazec::load(&textured_clay()).expect("checks");
    assert_eq!(m.normals.len(), 1);
    let (layer, map) = &m.normals[0];
    assert_eq!(*layer, 1, "the base (the film has none)");
    assert_eq!(map.texture, "clay_bumps");
    assert_eq!(map.detail, Some(("clay_pores".to_string(), 4.0)));
    assert_eq!(codes(&material(r#"Lambert(albedo: 0.5, normal: Bump("x"))"#)), [Code::UnknownVariant]);
    assert_eq!(codes(&material(r#"Lambert(albedo: 0.5, normal: NormalMap("x", 0.0))"#)), [Code::TextureRange]);
    assert_eq!(codes(&material(r#"Lambert(albedo: 0.5, normal: NormalMap("X y"))"#)), [Code::BadName]);
    let coats: Vec<String> =
        (0..8).map(|i| format!(r#"Coat(lobe: Ggx(0.2), ior: 1.5, normal: NormalMap("n{i}", 1.0))"#)).collect();
    let nine = format!(r#"{}, Lambert(albedo: 0.5, normal: NormalMap("n8"))"#, coats.join(", "));
    assert_eq!(codes(&material(&nine)), [Code::TooManyTextures]);
}

/// A 4 × 4 normal map of tilted normals (texels exact in f32).
fn normal_image(seed: u32) -> (TextureImage, Vec<glam::DVec3>) {
    let normals: Vec<glam::DVec3> = (0..16).map(|i| tilted(seed + i)).collect();
    let texels = normals
        .iter()
        .map(|n| {
            let t = n.as_vec3() * 0.5 + Vec3::splat(0.5);
            [t.x, t.y, t.z, 1.0]
        })
        .collect();
    (TextureImage { width: 4, height: 4, texels }, normals)
}

#[test]
fn normal_mapped_shading_matches_the_cpu_on_the_gpu() {
    let Some(gpu) = common::open_gpu() else { return };
    let gpu = &gpu;
    let text = r#"Material(
        name: "bumpy",
        layers: [
            Coat(lobe: Ggx(0.25), ior: 1.5, absorption: 0.2, thickness: 0.5),
            Eon(albedo: (0.7, 0.5, 0.4), roughness: 0.5, normal: NormalMap(texture: "bumps", uv_scale: 1.0, detail: "pores", detail_scale: 1.0)),
        ],
    )"#;
    let compiled = glazec::compile(text).expect("compiles");
    let (bumps, bump_normals) = normal_image(3);
    let (pores, pore_normals) = normal_image(101);
    let images = vec![("bumps".to_string(), bumps), ("pores".to_string(), pores)];
    // Every texel centre, each with several direction pairs.
    let all = pairs();
    let (mut pairs_at, mut uvs, mut expected) = (Vec::new(), Vec::new(), Vec::new());
    for texel in 0..16 {
        let uv = [((texel % 4) as f32 + 0.5) / 4.0, ((texel / 4) as f32 + 0.5) / 4.0];
        // The local frame is the identity (t = x, b = y, n = z): the blended normal as it is.
        let decoded = |n: glam::DVec3| (n.as_vec3() * 0.5 + Vec3::splat(0.5)) * 2.0 - Vec3::ONE;
        let normal = rnm_f64(decoded(bump_normals[texel]).as_dvec3(), decoded(pore_normals[texel]).as_dvec3());
        for p in all.iter().skip(texel % 3).step_by(3) {
            pairs_at.push(*p);
            uvs.push(uv);
            expected.push(glazec::eval::brdf_with_normals(
                &compiled.material,
                &[],
                &[(1, normal.as_vec3())],
                p.wi,
                p.wo,
            ));
        }
    }
    let max = expected.iter().map(|v| v.max_element()).fold(0.0, f32::max);
    let flat: Vec<Vec3> = pairs_at.iter().map(|p| glazec::eval::brdf(&compiled.material, &[], p.wi, p.wo)).collect();
    let changed =
        expected.iter().zip(&flat).filter(|(a, b)| (**a - **b).abs().max_element() > 0.02 * b.max_element()).count();
    eprintln!("normal maps change {changed} of {} values by more than 2%", expected.len());
    assert!(changed > expected.len() / 4, "the normal maps should change the BRDF");
    for path in [ShaderPath::NagaIr, ShaderPath::Wgsl] {
        let kernel = glazec_gpu::EvalKernel::new(gpu, &compiled, path).expect("kernel");
        let values = kernel.eval_textured(gpu, &pairs_at, &uvs, &[], &images).expect("runs");
        for ((v, e), uv) in values.iter().zip(&expected).zip(&uvs) {
            for c in 0..3 {
                assert!(common::agreement::agrees(e[c], v[c], max), "{path} at uv {uv:?}: {v} against {e}");
            }
        }
    }
    eprintln!("normal maps: {} pairs over 16 texels × 2 paths agree with the CPU", pairs_at.len());
}
