//! `glazec-spheres [OUT_DIR]`: renders every shipped material on a sphere (one PNG each), and
//! animates `tunable_glaze` by writing its typed parameter struct every frame (a film strip).
//!
//! Everything material-specific comes from the module glazec's build script API generated;
//! the only material named here is the animated one, whose `Params` struct is used directly.

use std::path::PathBuf;

use glazec_spheres::materials::{self, tunable_glaze};
use glazec_spheres::render::{Renderer, SpherePipeline, encode_srgb, write_png};

/// Pixels per side of each image.
const SIZE: u32 = 256;
/// Frames of the animation.
const FRAMES: u32 = 6;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "spheres".into()));
    std::fs::create_dir_all(&out)?;
    let renderer = Renderer::new()?;
    eprintln!("rendering on {} with glazec {} shaders", renderer.adapter_name, materials::GLAZEC_VERSION);
    for material in materials::MATERIALS {
        let pipeline = SpherePipeline::new(&renderer, material)?;
        let image = encode_srgb(&pipeline.render(&renderer, SIZE)?);
        let path = out.join(format!("{}.png", material.name));
        write_png(&path, SIZE, SIZE, &image)?;
        eprintln!("wrote {}", path.display());
    }
    let strip = animate_glaze(&renderer)?;
    let path = out.join("tunable_glaze_frames.png");
    write_png(&path, SIZE * FRAMES, SIZE, &strip)?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// Renders `tunable_glaze` with its glaze roughening from 0.05 to 0.6, one frame per value, and
/// lays the frames side by side.
fn animate_glaze(renderer: &Renderer) -> Result<Vec<u8>, Box<dyn std::error::Error>> {
    let pipeline = SpherePipeline::new(renderer, &tunable_glaze::INFO)?;
    let buffer = pipeline.params_buffer.as_ref().ok_or("tunable_glaze has runtime parameters")?;
    let mut frames = Vec::new();
    for frame in 0..FRAMES {
        let t = frame as f32 / (FRAMES - 1) as f32;
        // The typed struct: its layout is the shader's uniform struct, checked at compile time.
        let params = tunable_glaze::Params { glaze_roughness: 0.05 + 0.55 * t, ..Default::default() };
        renderer.queue.write_buffer(buffer, 0, bytemuck::bytes_of(&params));
        frames.push(encode_srgb(&pipeline.render(renderer, SIZE)?));
    }
    let mut strip = Vec::with_capacity(frames.len() * frames[0].len());
    for y in 0..SIZE as usize {
        for frame in &frames {
            strip.extend_from_slice(&frame[y * SIZE as usize * 3..][..SIZE as usize * 3]);
        }
    }
    Ok(strip)
}
