//! Sphere previews: the material's own fragment entry point, run on the device.
//!
//! `preview_fs` shades a unit sphere (seen along −z, orthographic) under one directional light
//! from the `light` uniform. An image is the sum of several such passes, added by the blend
//! unit into a floating-point target: a key light plus an environment sampled as 256 directional
//! lights (a Fibonacci sphere; each carries L_env(ω)·4π/256). On the host, the sphere is laid
//! over a background, multiplied by the exposure, clamped and encoded as sRGB.
//!
//! The environment lights the sphere in one of two ways ([`Lighting`]):
//!
//! * **image-based** (the CLI's default): one more pass, `preview_ibl_fs`, adds
//!   `<material>_ibl` — each lobe's albedo times the environment prefiltered for it
//!   ([`crate::environment`]), so a glossy or smooth coat shows the environment's reflection;
//! * **samples**: the environment sampled as 256 directional lights through `preview_fs`, the
//!   BRDF itself (a brute-force reference on the device, but point lights cannot show a
//!   reflection in a sharp lobe: a very glossy coat reflects them as small dots, and a smooth
//!   coat's delta lobe shows nothing).
//!
//! The analytic environments are `sky` (a blue zenith fading to a pale horizon above, a dark
//! warm ground below) and `studio` (a soft grey dome over a dark floor); `none` leaves the key
//! light alone. Image-based lighting also takes any equirectangular image (a `.hdr` file).

use std::f32::consts::PI;
use std::path::Path;

use glam::Vec3;
use wgpu::util::DeviceExt;

use crate::shader::{self, ShaderPath};
use crate::{Gpu, RunError};
use glazec::Compiled;
use glazec::lower::{bindings, entry_points};
use glazec::model::ParamValue;

/// Environment samples per image.
const ENVIRONMENT_SAMPLES: usize = 256;
/// The render target: blendable floating point.
const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// An analytic lighting environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Environment {
    None,
    Sky,
    Studio,
}

impl Environment {
    pub const ALL: [Environment; 3] = [Environment::None, Environment::Sky, Environment::Studio];

    /// The environment's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Environment::None => "none",
            Environment::Sky => "sky",
            Environment::Studio => "studio",
        }
    }

    pub fn description(self) -> &'static str {
        match self {
            Environment::None => "no environment: the key light alone",
            Environment::Sky => "a blue sky over a dark ground",
            Environment::Studio => "a soft grey dome over a dark floor",
        }
    }
}

/// How the environment lights a preview.
#[derive(Clone, Debug, PartialEq)]
pub enum Lighting {
    /// 256 directional lights sampling the analytic [`Environment`].
    Samples,
    /// Image-based lighting from a prefiltered environment (see [`Environment::image`] and
    /// [`crate::environment::prefilter`]).
    Image(std::sync::Arc<crate::environment::Prefiltered>),
}

impl Environment {
    /// The environment as an equirectangular image `width` texels wide (`None` for
    /// [`Environment::None`]).
    pub fn image(self, width: u32) -> Option<crate::environment::EnvironmentImage> {
        (self != Environment::None).then(|| crate::environment::EnvironmentImage::from_fn(width, |d| self.radiance(d)))
    }

    /// Radiance arriving from direction `d` (view space: y up, z towards the viewer).
    pub fn radiance(self, d: Vec3) -> Vec3 {
        match self {
            Environment::None => Vec3::ZERO,
            Environment::Sky if d.y >= 0.0 => {
                let horizon = Vec3::new(0.75, 0.8, 0.85);
                let zenith = Vec3::new(0.25, 0.45, 0.9);
                horizon.lerp(zenith, d.y.sqrt()) * 0.6
            }
            Environment::Sky => Vec3::new(0.12, 0.1, 0.08),
            Environment::Studio if d.y >= 0.0 => Vec3::splat(0.35 + 0.25 * d.y),
            Environment::Studio => Vec3::splat(0.06),
        }
    }
}

/// How to light and expose a preview.
#[derive(Clone, Debug)]
pub struct PreviewOptions {
    /// Width and height in pixels.
    pub size: u32,
    /// Direction towards the key light, view space (y up, z towards the viewer).
    pub light: Vec3,
    /// Radiance of the key light (it is a directional light: irradiance at normal incidence).
    pub light_radiance: f32,
    /// The analytic environment of [`Lighting::Samples`].
    pub environment: Environment,
    pub lighting: Lighting,
    /// Linear scale applied before sRGB encoding.
    pub exposure: f32,
    /// Images for the material's textures, by name; a texture without one is constant at the
    /// value of its parameters (`crate::textures::constant_textures`).
    pub textures: Vec<(String, crate::textures::TextureImage)>,
}

impl Default for PreviewOptions {
    fn default() -> Self {
        PreviewOptions {
            size: 512,
            light: Vec3::new(-0.5, 0.6, 0.62),
            light_radiance: 2.5,
            environment: Environment::Sky,
            lighting: Lighting::Samples,
            exposure: 1.0,
            textures: Vec::new(),
        }
    }
}

/// An 8-bit sRGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// RGB, 3 bytes per pixel.
    pub rgb: Vec<u8>,
}

/// The lights of one preview: (direction, radiance × solid angle) per pass.
pub fn lights(options: &PreviewOptions) -> Vec<(Vec3, Vec3)> {
    let mut lights = vec![(options.light.normalize_or(Vec3::Z), Vec3::splat(options.light_radiance))];
    if options.environment != Environment::None && options.lighting == Lighting::Samples {
        let weight = 4.0 * PI / ENVIRONMENT_SAMPLES as f32;
        let golden = PI * (3.0 - 5.0_f32.sqrt());
        for i in 0..ENVIRONMENT_SAMPLES {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / ENVIRONMENT_SAMPLES as f32;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f32;
            let d = Vec3::new(r * phi.cos(), y, r * phi.sin());
            lights.push((d, options.environment.radiance(d) * weight));
        }
    }
    lights
}

/// Renders a material's preview; returns linear RGBA (alpha = sphere coverage × passes).
///
/// # Errors
/// A [`RunError`] if the shaders or pipeline are rejected or the image cannot be read back.
pub fn render(
    gpu: &Gpu,
    compiled: &Compiled,
    values: &[ParamValue],
    options: &PreviewOptions,
) -> Result<Vec<[f32; 4]>, RunError> {
    let name = &compiled.material.name;
    let vertex = shader::load(gpu, compiled, ShaderPath::NagaIr, naga::ShaderStage::Vertex, entry_points::PREVIEW_VS)?;
    let fragment =
        shader::load(gpu, compiled, ShaderPath::NagaIr, naga::ShaderStage::Fragment, entry_points::PREVIEW_FS)?;
    let buffer = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    };
    // Group 0 of glazec's default bindings (where `glazec::compile` puts them).
    let optional = &compiled.harness().map_err(glazec::emit::EmitError::from)?.layout;
    // `lower` always adds the preview light; binding 4 is where it lands when absent otherwise.
    let light_binding = optional.light.unwrap_or(bindings::PARAMS + 1);
    let mut entries = Vec::new();
    if let Some(slot) = optional.params {
        entries.push(buffer(slot.binding, wgpu::BufferBindingType::Uniform));
    }
    if let Some(slot) = optional.tables {
        entries.push(buffer(slot.binding, wgpu::BufferBindingType::Uniform));
    }
    entries.push(buffer(light_binding, wgpu::BufferBindingType::Uniform));
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("preview"), entries: &entries });
    let material = &compiled.material;
    let mut images = options.textures.clone();
    for (name, constant) in crate::textures::constant_textures(material, values) {
        if !images.iter().any(|(n, _)| *n == name) {
            images.push((name, constant));
        }
    }
    let filtering = crate::textures::filtered(&images);
    let texture_layout = crate::textures::layout(gpu, material, filtering, wgpu::ShaderStages::FRAGMENT);
    let texture_group =
        texture_layout.as_ref().map(|layout| crate::textures::bind_group(gpu, layout, material, &images, filtering));
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    let corner = [wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x2, offset: 0, shader_location: 0 }];
    let targets = [Some(wgpu::ColorTargetState {
        format: TARGET_FORMAT,
        blend: Some(wgpu::BlendState { color: add, alpha: add }),
        write_mask: wgpu::ColorWrites::ALL,
    })];
    // One pipeline per fragment entry point, all adding into the same target.
    let make_pipeline = |fragment: &shader::Loaded, group_layouts: &[Option<&wgpu::BindGroupLayout>]| {
        let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("preview"),
            bind_group_layouts: group_layouts,
            immediate_size: 0,
        });
        let vertex_layout =
            wgpu::VertexBufferLayout { array_stride: 8, step_mode: wgpu::VertexStepMode::Vertex, attributes: &corner };
        let what = format!("preview pipeline of `{name}` ({})", fragment.entry);
        gpu.checked(&what, || {
            gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&what),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &vertex.module,
                    entry_point: Some(&vertex.entry),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout)],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &fragment.module,
                    entry_point: Some(&fragment.entry),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    };
    let pipeline = make_pipeline(&fragment, &[Some(&layout), texture_layout.as_ref()])?;
    // Image-based lighting: `preview_ibl_fs` with the environment in group 2.
    let ibl = match &options.lighting {
        Lighting::Image(prefiltered) => {
            let fragment = shader::load(
                gpu,
                compiled,
                ShaderPath::NagaIr,
                naga::ShaderStage::Fragment,
                entry_points::PREVIEW_IBL_FS,
            )?;
            let environment_layout = crate::environment::layout(gpu, wgpu::ShaderStages::FRAGMENT);
            let pipeline =
                make_pipeline(&fragment, &[Some(&layout), texture_layout.as_ref(), Some(&environment_layout)])?;
            Some((pipeline, crate::environment::bind_group(gpu, &environment_layout, prefiltered)))
        }
        Lighting::Samples => None,
    };

    let corners: [f32; 6] = [-1.0, -1.0, 3.0, -1.0, -1.0, 3.0];
    let init = |label, contents: &[u8], usage| {
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    };
    let corner_buffer = init("corners", bytemuck::cast_slice(&corners), wgpu::BufferUsages::VERTEX);
    let params = crate::params_bytes(&compiled.material, values)?;
    let params_buffer =
        optional.params.map(|slot| (slot.binding, init("params", &params, wgpu::BufferUsages::UNIFORM)));
    let tables_bytes = compiled.tables_bytes();
    let tables_buffer = optional.tables.map(|slot| (slot.binding, crate::kernel::tables_buffer(gpu, &tables_bytes)));
    let groups: Vec<wgpu::BindGroup> = lights(options)
        .iter()
        .map(|(direction, radiance)| {
            let light: [f32; 8] = [direction.x, direction.y, direction.z, 0.0, radiance.x, radiance.y, radiance.z, 0.0];
            let light_buffer = init("light", bytemuck::cast_slice(&light), wgpu::BufferUsages::UNIFORM);
            let mut entries = Vec::new();
            for (binding, b) in params_buffer.iter().chain(&tables_buffer) {
                entries.push(wgpu::BindGroupEntry { binding: *binding, resource: b.as_entire_binding() });
            }
            entries.push(wgpu::BindGroupEntry { binding: light_binding, resource: light_buffer.as_entire_binding() });
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &layout, entries: &entries })
        })
        .collect();

    let size = options.size.max(1);
    let extent = wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 };
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("preview"),
        size: extent,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: TARGET_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("preview"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_vertex_buffer(0, corner_buffer.slice(..));
        if let Some(textures) = &texture_group {
            pass.set_bind_group(1, textures, &[]);
        }
        for group in &groups {
            pass.set_bind_group(0, group, &[]);
            pass.draw(0..3, 0..1);
        }
        if let (Some((pipeline, environment)), Some(group)) = (&ibl, groups.first()) {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.set_bind_group(2, environment, &[]);
            pass.draw(0..3, 0..1);
        }
    }
    // Rows of the copy are padded to 256 bytes.
    let row = (size * 8).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("preview readback"),
        size: u64::from(row) * u64::from(size),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(size) },
        },
        extent,
    );
    gpu.queue.submit([encoder.finish()]);
    let bytes = gpu.read_buffer(&readback, u64::from(row) * u64::from(size))?;
    let mut pixels = Vec::with_capacity((size * size) as usize);
    for y in 0..size as usize {
        let line = &bytes[y * row as usize..][..size as usize * 8];
        for px in line.chunks_exact(8) {
            let h = |i: usize| half::f16::from_le_bytes([px[i], px[i + 1]]).to_f32();
            pixels.push([h(0), h(2), h(4), h(6)]);
        }
    }
    Ok(pixels)
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
fn srgb(x: f32) -> f32 {
    if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

/// Lays the rendered sphere over a background and encodes it: sRGB(min(1, exposure · linear)).
/// The background is a dark vertical gradient, so the sphere's silhouette reads at any exposure.
pub fn encode(linear: &[[f32; 4]], size: u32, exposure: f32) -> Image {
    let mut rgb = Vec::with_capacity(linear.len() * 3);
    for (i, px) in linear.iter().enumerate() {
        let y = (i as u32 / size.max(1)) as f32 / size.max(1) as f32;
        let color =
            if px[3] > 0.0 { Vec3::new(px[0], px[1], px[2]) * exposure } else { Vec3::splat(0.02 + 0.03 * (1.0 - y)) };
        for c in color.to_array() {
            rgb.push((srgb(c.clamp(0.0, 1.0)) * 255.0).round() as u8);
        }
    }
    Image { width: size, height: size, rgb }
}

/// Height of a tile's label strip, in pixels.
const LABEL_HEIGHT: u32 = 24;
/// Label glyph scale (font8x8 glyphs are 8 × 8).
const LABEL_SCALE: u32 = 2;

/// Tiles images in a grid (`columns` wide) with each name written under its tile.
pub fn contact_sheet(tiles: &[(String, Image)], columns: usize) -> Image {
    use font8x8::UnicodeFonts;
    let Some((_, first)) = tiles.first() else {
        return Image { width: 0, height: 0, rgb: Vec::new() };
    };
    let (tw, th) = (first.width, first.height);
    let columns = columns.clamp(1, tiles.len());
    let rows = tiles.len().div_ceil(columns);
    let width = tw * columns as u32;
    let height = (th + LABEL_HEIGHT) * rows as u32;
    let mut rgb = vec![12u8; (width * height * 3) as usize];
    let mut put = |x: u32, y: u32, c: [u8; 3]| {
        if x < width && y < height {
            let at = ((y * width + x) * 3) as usize;
            rgb[at..at + 3].copy_from_slice(&c);
        }
    };
    for (index, (name, image)) in tiles.iter().enumerate() {
        let (ox, oy) = ((index % columns) as u32 * tw, (index / columns) as u32 * (th + LABEL_HEIGHT));
        for y in 0..image.height.min(th) {
            for x in 0..image.width.min(tw) {
                let at = ((y * image.width + x) * 3) as usize;
                put(ox + x, oy + y, [image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]]);
            }
        }
        let text_width = name.chars().count() as u32 * 8 * LABEL_SCALE;
        let tx = ox + tw.saturating_sub(text_width) / 2;
        let ty = oy + th + (LABEL_HEIGHT - 8 * LABEL_SCALE) / 2;
        for (i, ch) in name.chars().enumerate() {
            let Some(glyph) = font8x8::BASIC_FONTS.get(ch) else { continue };
            for (gy, bits) in glyph.iter().enumerate() {
                for gx in 0..8 {
                    if bits & (1 << gx) != 0 {
                        for sy in 0..LABEL_SCALE {
                            for sx in 0..LABEL_SCALE {
                                let x = tx + (i as u32 * 8 + gx) * LABEL_SCALE + sx;
                                put(x, ty + gy as u32 * LABEL_SCALE + sy, [220, 220, 220]);
                            }
                        }
                    }
                }
            }
        }
    }
    Image { width, height, rgb }
}

/// An image as an 8-bit RGB PNG tagged sRGB.
///
/// # Errors
/// An encoding error.
pub fn encode_png(image: &Image) -> Result<Vec<u8>, RunError> {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, image.width, image.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer.write_image_data(&image.rgb).map_err(std::io::Error::other)?;
    }
    Ok(bytes)
}

/// Writes an image as an 8-bit RGB PNG tagged sRGB.
///
/// # Errors
/// An I/O or encoding error.
pub fn write_png(path: &Path, image: &Image) -> Result<(), RunError> {
    let bytes = encode_png(image)?;
    glazec::output::write_all(&[glazec::output::OutputFile { path: path.to_path_buf(), contents: bytes }])?;
    Ok(())
}
