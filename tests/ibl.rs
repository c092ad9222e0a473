//! Image-based lighting on lavapipe: the generated `<material>_ibl` (through `preview_ibl_fs`)
//! under a white furnace, against the CPU split sum (same lobes, same prefiltered images), and
//! against a brute-force CPU integration of the material's own BRDF under the analytic
//! environment the images were made from.

mod common;

use std::sync::Arc;

use glam::Vec3;
use glazec::Compiled;
use glazec_gpu::environment::{EnvironmentImage, Prefiltered, prefilter};
use glazec_gpu::preview::{self, Environment, Lighting, PreviewOptions};
use rayon::prelude::*;

/// Preview size in pixels.
const SIZE: u32 = 64;
/// Every `STRIDE`-th pixel in each direction is compared.
const STRIDE: usize = 4;
/// Pixels whose |p|² exceeds this are left out: at the silhouette the sphere's normal changes
/// faster than a pixel, and views graze the surface.
const MAX_R2: f32 = 0.9;
/// A white stack under a white environment reflects at most 1 + this. The half-float images and
/// target round by 2⁻¹¹ ≈ 4.9·10⁻⁴; the method's own white furnace is within 2·10⁻³
/// (docs/accuracy.md).
const FURNACE_TOLERANCE: f32 = 2.5e-3;
/// Largest difference between lavapipe and the CPU split sum, relative to the CPU value (the
/// same lobes and images: half-float storage and the device's 8-bit filtering weights).
const SPLIT_SUM_AGREEMENT: f32 = 0.02;
/// Brute-force samples per strategy and point (cosine-weighted plus one GGX strategy per rough
/// lobe).
const BRUTE_FORCE_SAMPLES: u32 = 4096;
/// Largest root-mean-square luminance error of the split sum against the brute-force integral,
/// relative to the mean brute-force luminance, over the compared points of one material: the
/// stated error of glazec's image-based lighting (docs/accuracy.md, "Image-based lighting against
/// brute force"; measured 0.010–0.051 on the seven materials below, largest for clay; issue 31's
/// target).
const SPLIT_SUM_RMS: f32 = 0.06;
/// Largest luminance error of the split sum against the brute-force integral at one point,
/// relative to the same mean: issue 31's target (measured 0.039–0.107 on the seven materials,
/// largest for wet_clay and lacquered_wood, since a coat's own reflection is looked up at its lobe's width across the
/// plane of incidence; 0.046–0.276 before).
const SPLIT_SUM_WORST: f32 = 0.15;

fn material(name: &str) -> Compiled {
    let path = common::root().join("materials").join(format!("{name}.ron"));
    glazec::compile(&std::fs::read_to_string(path).expect("material")).expect("compiles")
}

fn compile(text: &str) -> Compiled {
    glazec::compile(text).expect("compiles")
}

/// The preview under image-based lighting alone (the key light is off).
fn render_ibl(gpu: &glazec_gpu::Gpu, compiled: &Compiled, prefiltered: &Arc<Prefiltered>) -> Vec<[f32; 4]> {
    let options = PreviewOptions {
        size: SIZE,
        light_radiance: 0.0,
        environment: Environment::None,
        lighting: Lighting::Image(prefiltered.clone()),
        ..Default::default()
    };
    let values = compiled.material.default_values();
    preview::render(gpu, compiled, &values, &options).expect("renders")
}

/// The compared pixels: (index into the image, normal). The fragment at pixel (x, y) has
/// clip-space p = (2(x + ½)/S − 1, 1 − 2(y + ½)/S) and normal (p, √(1 − |p|²)).
fn points() -> Vec<(usize, Vec3)> {
    let mut out = Vec::new();
    for y in (STRIDE / 2..SIZE as usize).step_by(STRIDE) {
        for x in (STRIDE / 2..SIZE as usize).step_by(STRIDE) {
            let px = 2.0 * (x as f32 + 0.5) / SIZE as f32 - 1.0;
            let py = 1.0 - 2.0 * (y as f32 + 0.5) / SIZE as f32;
            let r2 = px * px + py * py;
            if r2 < MAX_R2 {
                out.push((y * SIZE as usize + x, Vec3::new(px, py, (1.0 - r2).sqrt())));
            }
        }
    }
    out
}

/// Rec. 709 luminance of linear RGB.
fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

fn rgb(p: [f32; 4]) -> Vec3 {
    Vec3::new(p[0], p[1], p[2])
}

#[test]
fn a_white_stack_in_a_white_furnace_reflects_at_most_its_albedo() {
    let Some(gpu) = common::open_gpu() else { return };
    let white = Arc::new(prefilter(&EnvironmentImage::from_fn(64, |_| Vec3::ONE)));
    let stacks = [
        ("smooth_coat", "Coat(lobe: Smooth, ior: 1.5), Lambert(albedo: 1.0)"),
        ("rough_coat", "Coat(lobe: Ggx(roughness: 0.3), ior: 1.5), Lambert(albedo: 1.0)"),
        (
            "two_coats",
            "Coat(lobe: Ggx(roughness: 0.1), ior: 1.33), Coat(lobe: Ggx(roughness: 0.5), ior: 1.5), Lambert(albedo: 1.0)",
        ),
        ("white_plastic", "Plastic(albedo: 1.0, roughness: 0.4, ior: 1.5)"),
        ("coated_eon", "Coat(lobe: Ggx(roughness: 0.2), ior: 1.5), Eon(albedo: 1.0, roughness: 0.8)"),
    ];
    for (name, layers) in stacks {
        let compiled = compile(&format!("Material(name: \"{name}\", layers: [{layers}])"));
        let image = render_ibl(&gpu, &compiled, &white);
        let (mut worst, mut lowest) = (0.0_f32, f32::MAX);
        for (index, n) in points() {
            let value = rgb(image[index]);
            let lobes = glazec::eval::environment_lobes(&compiled.material, &[], n, Vec3::Z);
            let albedo: Vec3 = lobes.iter().map(|l| l.weight).sum();
            assert!(value.max_element() <= 1.0 + FURNACE_TOLERANCE, "{name} at {n}: {value}");
            // A white environment returns exactly the method's directional albedo.
            let difference = (value - albedo).abs().max_element();
            assert!(difference <= FURNACE_TOLERANCE, "{name} at {n}: {value} against the albedo {albedo}");
            worst = worst.max(value.max_element());
            lowest = lowest.min(value.min_element());
        }
        println!("white furnace, {name}: reflected {lowest:.4} … {worst:.4}");
    }
}

/// The materials compared against the brute force: every method, smooth and rough coats,
/// diffusing and conductor bases (the deep tier); the quick tier takes the first four, one per
/// method and a conductor under a coat.
const COMPARED: [&str; 7] =
    ["clay", "disney_clay", "wet_clay", "coated_gold", "car_paint", "red_plastic", "lacquered_wood"];
const COMPARED_QUICK: usize = 4;

#[test]
fn image_based_lighting_matches_the_cpu_split_sum_and_a_brute_force_integral() {
    let Some(gpu) = common::open_gpu() else { return };
    let environment = Environment::Sky;
    let image = environment.image(1024).expect("an analytic environment");
    let prefiltered = Arc::new(prefilter(&image));
    let points = points();
    println!(
        "{} points per material, {} brute-force samples per strategy and point; luminance errors relative to the mean luminance",
        points.len(),
        BRUTE_FORCE_SAMPLES
    );
    println!(
        "material        | GPU vs CPU split sum (max) | split sum vs brute force (RMS, max) | brute-force std. error"
    );
    let mut failures = Vec::new();
    let compared = common::tier("materials compared with the brute force", COMPARED_QUICK, COMPARED.len());
    for name in &COMPARED[..compared] {
        let compiled = material(name);
        let m = &compiled.material;
        let values = m.default_values();
        let gpu_image = render_ibl(&gpu, &compiled, &prefiltered);
        let (mut agreement, mut squared, mut worst, mut error) = (0.0_f32, 0.0, 0.0_f32, 0.0_f32);
        let row = |i: usize, &(index, n): &(usize, Vec3)| {
            let device = rgb(gpu_image[index]);
            let cpu = prefiltered.shade(&glazec::eval::environment_lobes(m, &values, n, Vec3::Z));
            let radiance = |d: Vec3| environment.radiance(d);
            let (truth, std_error) = glazec_lab::reference::environment::environment_integral(
                m,
                &values,
                (n, Vec3::Z),
                &radiance,
                BRUTE_FORCE_SAMPLES,
                i as u64,
            );
            (device, cpu, truth, std_error)
        };
        // The brute force on every core (each point seeded by its index, so the result does not
        // depend on the number of threads).
        let rows: Vec<(Vec3, Vec3, Vec3, Vec3)> = points.par_iter().enumerate().map(|(i, p)| row(i, p)).collect();
        let scale = rows.iter().map(|r| luminance(r.2)).sum::<f32>() / rows.len() as f32;
        for (device, cpu, truth, std_error) in &rows {
            agreement = agreement.max((*device - *cpu).abs().max_element() / cpu.max_element().max(scale * 0.1));
            let e = (luminance(*device) - luminance(*truth)).abs() / scale;
            squared += e * e;
            worst = worst.max(e);
            error = error.max(luminance(*std_error) / scale);
        }
        let rms = (squared / rows.len() as f32).sqrt();
        println!("{name:<15} | {agreement:>26.4} | {rms:>13.4}, {worst:>19.4} | {error:>10.5}");
        if agreement > SPLIT_SUM_AGREEMENT {
            failures.push(format!("{name}: GPU and CPU split sums differ by {agreement}"));
        }
        if rms > SPLIT_SUM_RMS {
            failures.push(format!("{name}: split sum RMS error {rms} against the brute force"));
        }
        if worst > SPLIT_SUM_WORST {
            failures.push(format!("{name}: split sum error {worst} at one point against the brute force"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
