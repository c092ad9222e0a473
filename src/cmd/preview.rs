//! `glazec preview`: a sphere per material rendered on the GPU to a PNG (a labelled contact
//! sheet for several), optionally beside each material simplified for a scene.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, bail};
use clap::ValueEnum;
use glam::Vec3;
use glazec::project::Project;
use glazec_gpu::environment::{BASE_WIDTH, EnvironmentImage, prefilter};
use glazec_gpu::preview::{self, Environment, Lighting, PreviewOptions};
use glazec_gpu::textures::TextureImage;

use crate::choice;
use crate::report::{Failure, MessageFormat, gpu_failure, print_diagnostics, project_failure};

/// Render a sphere with the material on the GPU and write a PNG.
///
/// Several inputs (or a directory) give a labelled contact sheet.
#[derive(clap::Args)]
pub struct Args {
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// The PNG to write.
    #[arg(short, long)]
    out: PathBuf,
    /// Image (or tile) size in pixels.
    #[arg(long, default_value_t = 512)]
    size: u32,
    /// Direction towards the key light, `x,y,z` in view space (y up, z towards the viewer).
    #[arg(long, value_name = "X,Y,Z", default_value = "-0.5,0.6,0.62")]
    light: String,
    /// Radiance of the key light.
    #[arg(long, default_value_t = 2.5)]
    light_radiance: f32,
    #[arg(long, value_parser = choice::parser::<Environment>(), default_value = "sky")]
    env: Environment,
    /// An equirectangular Radiance `.hdr` image to light with instead of `--env` (image-based
    /// lighting; y up, the image's centre behind the viewer).
    #[arg(long, value_name = "FILE.hdr")]
    env_image: Option<PathBuf>,
    /// How the environment lights the sphere.
    #[arg(long, value_enum, default_value = "ibl")]
    lighting: LightingArg,
    /// Linear scale before sRGB encoding.
    #[arg(long, default_value_t = 1.0)]
    exposure: f32,
    /// Tiles per row of a contact sheet.
    #[arg(long, default_value_t = 3)]
    columns: usize,
    /// Before/after: each material beside its simplification for this scene.
    #[arg(long, value_name = "SCENE.ron")]
    scene: Option<PathBuf>,
    /// An image for a texture the materials read (`Texture("name", …)`), as linear data;
    /// repeatable. A texture without one is constant at its parameters' default values.
    #[arg(long = "texture", value_name = "NAME=FILE.png")]
    textures: Vec<String>,
    #[arg(long, value_enum, default_value = "human")]
    message_format: MessageFormat,
}

/// How the environment lights a preview (`Lighting` holds the prefiltered image itself).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum LightingArg {
    /// Image-based lighting: each lobe reads the environment prefiltered for it (reflections).
    Ibl,
    /// The environment as 256 directional lights through the BRDF (no sharp reflections).
    Samples,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let options = PreviewOptions {
        size: args.size,
        light: parse_direction(&args.light)?,
        light_radiance: args.light_radiance,
        environment: args.env,
        lighting: lighting(args.env, args.env_image.as_deref(), args.lighting)?,
        exposure: args.exposure,
        textures: read_textures(&args.textures)?,
    };
    let single = args.inputs.len() == 1 && !args.inputs[0].is_dir() && args.scene.is_none();
    let project = Project {
        inputs: args.inputs,
        scene: args.scene,
        out_dir: PathBuf::new(),
        targets: Vec::new(),
        bindings: Default::default(),
        harness: false,
    };
    let outcome = project.compile().map_err(|e| project_failure(e, args.message_format))?;
    for file in &outcome.notes {
        print_diagnostics(file, args.message_format);
    }
    for (name, _) in &options.textures {
        if !outcome.compiled.iter().any(|c| c.material.textures().contains(&name.as_str())) {
            let read: Vec<&str> = outcome.compiled.iter().flat_map(|c| c.material.textures()).collect();
            return Err(Failure::usage(format!(
                "--texture {name}: no material reads a texture of that name (they read: {})",
                if read.is_empty() { "none".to_string() } else { read.join(", ") }
            )));
        }
    }
    let gpu = glazec_gpu::Gpu::new().map_err(gpu_failure)?;
    let mut tiles = Vec::new();
    for (i, c) in outcome.compiled.iter().enumerate() {
        let linear = preview::render(&gpu, c, &c.material.default_values(), &options).map_err(gpu_failure)?;
        tiles.push((c.material.name.clone(), preview::encode(&linear, options.size, options.exposure)));
        if let Some((s, _)) = outcome.simplified.get(i) {
            let scene_name = s.origin.scene.as_ref().map_or("scene", |(file, _)| file.trim_end_matches(".ron"));
            let linear = preview::render(&gpu, s, &s.material.default_values(), &options).map_err(gpu_failure)?;
            tiles.push((scene_name.to_string(), preview::encode(&linear, options.size, options.exposure)));
        }
    }
    let image = if single { tiles.remove(0).1 } else { preview::contact_sheet(&tiles, args.columns) };
    preview::write_png(&args.out, &image).map_err(gpu_failure)?;
    eprintln!(
        "wrote {} ({}×{}, {} on {})",
        args.out.display(),
        image.width,
        image.height,
        outcome.compiled.len(),
        gpu.describe()
    );
    Ok(())
}

/// The preview's lighting: the environment (an `.hdr` image, or the analytic one rasterised)
/// prefiltered for image-based lighting, or the analytic one's samples.
fn lighting(environment: Environment, image: Option<&Path>, lighting: LightingArg) -> Result<Lighting, Failure> {
    let image = match (image, lighting) {
        (Some(_), LightingArg::Samples) => return Err(Failure::usage("--env-image needs --lighting ibl")),
        (Some(path), LightingArg::Ibl) => {
            Some(EnvironmentImage::read_hdr(path).context("cannot read the environment image")?)
        }
        (None, LightingArg::Ibl) => environment.image(2 * BASE_WIDTH),
        (None, LightingArg::Samples) => None,
    };
    Ok(match image {
        Some(image) => Lighting::Image(Arc::new(prefilter(&image))),
        None => Lighting::Samples,
    })
}

/// `NAME=FILE.png` arguments of `--texture`.
fn read_textures(args: &[String]) -> Result<Vec<(String, TextureImage)>, Failure> {
    args.iter()
        .map(|arg| {
            let Some((name, file)) = arg.split_once('=') else {
                return Err(Failure::usage(format!("--texture takes NAME=FILE.png, got `{arg}`")));
            };
            let image =
                TextureImage::read_png(Path::new(file)).with_context(|| format!("cannot read texture `{name}`"))?;
            Ok((name.trim().to_string(), image))
        })
        .collect()
}

/// `--light x,y,z`: a non-zero direction.
fn parse_direction(text: &str) -> anyhow::Result<Vec3> {
    let numbers: Vec<f32> = text
        .split(',')
        .map(|x| x.trim().parse::<f32>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .with_context(|| format!("--light: `{text}` is not three numbers x,y,z"))?;
    match numbers.as_slice() {
        [x, y, z] if (x * x + y * y + z * z) > 0.0 => Ok(Vec3::new(*x, *y, *z)),
        _ => bail!("--light: `{text}` is not a non-zero direction x,y,z"),
    }
}
