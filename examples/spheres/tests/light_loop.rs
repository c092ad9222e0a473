//! The program's own shader (`src/light_loop.wgsl`: two glazec libraries, two meshes, two
//! lights, its own light loop) renders on lavapipe, and its pixels are what glazec's CPU
//! evaluation gives for the same normal, view and lights.

use glam::Vec3;
use glazec_spheres::light_loop::{HALF_WIDTH, LIGHTS, LightLoop, SPHERES, TO_VIEWER};
use glazec_spheres::render::Renderer;

/// Pixels across the frame.
const WIDTH: u32 = 192;
/// Pixels compared per sphere: a grid of GRID × GRID over its disc.
const GRID: usize = 7;
/// Only where the normal faces the viewer by at least this much (away from the silhouette, where
/// the mesh's interpolated normal turns fastest).
const MIN_FACING: f32 = 0.25;
/// The agreement tolerance of glazec's GPU tests (tests/common/mod.rs): relative where a value
/// is significant (above SIGNIFICANT × the largest), absolute below.
const REL_TOL: f32 = 2e-4;
const SIGNIFICANT: f32 = 1e-4;
const ABS_TOL: f32 = 1e-6;

/// Σ over the lights of f(l, v)·max(n·l, 0)·radiance, on the CPU, in the local frame of `n`.
fn expected(material: &glazec::Material, n: Vec3) -> Vec3 {
    let helper = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let t = helper.cross(n).normalize();
    let b = n.cross(t);
    let local = |x: Vec3| Vec3::new(x.dot(t), x.dot(b), x.dot(n));
    let v = Vec3::from(TO_VIEWER);
    let values = material.default_values();
    LIGHTS
        .iter()
        .map(|(l, radiance)| {
            let l = Vec3::from(*l);
            glazec::eval::brdf(material, &values, local(l), local(v)) * n.dot(l).max(0.0) * Vec3::from(*radiance)
        })
        .sum()
}

#[test]
fn the_programs_own_light_loop_agrees_with_the_cpu() {
    let Some(renderer) = Renderer::or_skip() else { return };
    let scene = LightLoop::new(&renderer).expect("builds the scene");
    let frame = scene.render(&renderer, WIDTH).expect("renders");
    let height = frame.height;
    let covered = frame.radiance.iter().filter(|p| p[3] > 0.0).count() as f32 / frame.radiance.len() as f32;
    // Two unit discs in a 2·HALF_WIDTH × HALF_WIDTH view.
    let discs = 2.0 * std::f32::consts::PI / (2.0 * HALF_WIDTH * HALF_WIDTH);
    assert!((covered - discs).abs() < 0.02, "the spheres cover {covered:.3} of the frame, expected {discs:.3}");
    let mut compared = 0;
    let mut worst = 0.0_f32;
    let mut failures = Vec::new();
    for (name, centre) in SPHERES {
        let text = std::fs::read_to_string(format!("{}/../../materials/{name}.ron", env!("CARGO_MANIFEST_DIR")))
            .expect("the material file");
        let material = glazec::compile(&text).expect("compiles").material;
        let mut cases = Vec::new();
        for i in 0..GRID {
            for j in 0..GRID {
                // A point of the disc, to a pixel.
                let (dx, dy) = (-0.9 + 1.8 * i as f32 / (GRID - 1) as f32, -0.9 + 1.8 * j as f32 / (GRID - 1) as f32);
                let x = ((centre[0] + dx) / HALF_WIDTH * 0.5 + 0.5) * WIDTH as f32;
                let y = (0.5 - (centre[1] + dy) / HALF_WIDTH) * height as f32;
                let index = y as usize * WIDTH as usize + x as usize;
                let normal = frame.normal[index];
                if normal[3] == 0.0 || normal[2] < MIN_FACING {
                    continue;
                }
                let n = Vec3::new(normal[0], normal[1], normal[2]);
                let gpu = Vec3::new(frame.radiance[index][0], frame.radiance[index][1], frame.radiance[index][2]);
                cases.push((index, expected(&material, n), gpu));
            }
        }
        assert!(cases.len() >= GRID * GRID / 2, "{name}: only {} pixels on the sphere", cases.len());
        let max = cases.iter().map(|(_, c, _)| c.max_element()).fold(0.0_f32, f32::max);
        for (index, cpu, gpu) in &cases {
            for (c, g) in cpu.to_array().into_iter().zip(gpu.to_array()) {
                let error = (g - c).abs();
                let significant = c.abs() > SIGNIFICANT * max;
                if significant {
                    worst = worst.max(error / c.abs());
                }
                if !(g.is_finite() && (error <= REL_TOL * c.abs() || (!significant && error <= ABS_TOL))) {
                    failures.push(format!("{name}, pixel {index}: CPU {cpu}, GPU {gpu}"));
                }
            }
        }
        compared += cases.len();
    }
    eprintln!("light loop on {}: {compared} pixels, worst relative error {worst:.2e}", renderer.adapter_name);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
