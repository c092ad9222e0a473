//! `light_loop [OUT.png]`: renders the light-loop scene (two glazec material libraries in the
//! program's own shader, two spheres, two lights) and writes it as a PNG; `docs/light-loop.png`
//! is `cargo run -p glazec-spheres --release --bin light_loop -- docs/light-loop.png`.

use glazec_spheres::light_loop::LightLoop;
use glazec_spheres::render::{Renderer, encode_srgb, write_png};

/// Pixels across (the frame is half as high).
const WIDTH: u32 = 640;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "light-loop.png".into()));
    let renderer = Renderer::new()?;
    let frame = LightLoop::new(&renderer)?.render(&renderer, WIDTH)?;
    write_png(&path, frame.width, frame.height, &encode_srgb(&frame.radiance))?;
    eprintln!("wrote {} ({} × {}, on {})", path.display(), frame.width, frame.height, renderer.adapter_name);
    Ok(())
}
