//! The example renders every shipped material on lavapipe and writes PNGs (in CI, where
//! `GLAZEC_REQUIRE_GPU=1` turns a missing adapter into a failure; elsewhere it skips visibly).

use glazec_spheres::materials::{self, tunable_glaze};
use glazec_spheres::render::{Renderer, SpherePipeline, encode_srgb, write_png};

/// Pixels per side.
const SIZE: u32 = 96;
/// The sphere fills a disc of radius 1 in a 2 × 2 view: π/4 of the pixels, up to the pixels
/// cut by its edge (≈ 4·SIZE·π/4 of them, 3% at 96 pixels).
const COVERAGE: f64 = std::f64::consts::FRAC_PI_4;
const COVERAGE_TOL: f64 = 0.03;

fn luminance(px: &[f32; 4]) -> f32 {
    0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2]
}

#[test]
fn every_shipped_material_renders_a_lit_sphere_and_writes_a_png() {
    let Some(renderer) = Renderer::or_skip() else { return };
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("spheres");
    std::fs::create_dir_all(&out).expect("creates the output folder");
    for material in materials::MATERIALS {
        let pipeline = SpherePipeline::new(&renderer, material).unwrap_or_else(|e| panic!("{}: {e}", material.name));
        let pixels = pipeline.render(&renderer, SIZE).unwrap_or_else(|e| panic!("{}: {e}", material.name));
        let covered = pixels.iter().filter(|p| p[3] > 0.0).count() as f64 / pixels.len() as f64;
        assert!((covered - COVERAGE).abs() < COVERAGE_TOL, "{}: sphere covers {covered:.3}", material.name);
        assert!(
            pixels.iter().all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0)),
            "{}: a pixel is negative or not finite",
            material.name
        );
        let lit = pixels.iter().filter(|p| p[3] > 0.0 && luminance(p) > 0.01).count();
        assert!(lit * 4 > pixels.len(), "{}: only {lit} lit pixels", material.name);
        let path = out.join(format!("{}.png", material.name));
        write_png(&path, SIZE, SIZE, &encode_srgb(&pixels)).expect("writes the PNG");
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).expect("exists")));
        let info = decoder.read_info().expect("a PNG").info().clone();
        assert_eq!((info.width, info.height), (SIZE, SIZE));
    }
    eprintln!("wrote {} PNGs to {}", materials::MATERIALS.len(), out.display());
}

#[test]
fn writing_the_typed_parameter_struct_changes_the_next_frame() {
    let Some(renderer) = Renderer::or_skip() else { return };
    let pipeline = SpherePipeline::new(&renderer, &tunable_glaze::INFO).expect("pipeline");
    let buffer = pipeline.params_buffer.as_ref().expect("tunable_glaze has parameters");
    let mut peaks = Vec::new();
    for roughness in [0.05, 0.6] {
        let params = tunable_glaze::Params { glaze_roughness: roughness, ..Default::default() };
        renderer.queue.write_buffer(buffer, 0, bytemuck::bytes_of(&params));
        let pixels = pipeline.render(&renderer, SIZE).expect("renders");
        peaks.push(pixels.iter().map(luminance).fold(0.0_f32, f32::max));
    }
    // A sharper glaze concentrates the key light's highlight: a brighter peak.
    assert!(peaks[0] > 2.0 * peaks[1], "peak luminance at roughness 0.05 vs 0.6: {peaks:?}");
}
