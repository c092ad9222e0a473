//! Texture reads on the device: the bind group that `lower::textures` declares (group 1) —
//! the sampler and one `texture_2d<f32>` per texture the material reads.
//!
//! Two kinds of texture reach it. **Constant** textures (1 × 1, `Rgba32Float`, nearest
//! sampling) hold exactly the texels that make every read equal given parameter values
//! ([`constant_textures`]): the kernels and the agreement tests use them, so a textured
//! material evaluates the same values as the CPU. **Images** (a PNG per texture, `glazec
//! preview --texture name=file.png`) are uploaded as `Rgba16Float` with bilinear filtering and
//! wrap addressing; their 8-bit values are taken as linear data (no sRGB decoding: maps hold
//! roughness, thickness, albedo as numbers).

use wgpu::util::DeviceExt;

use crate::{Gpu, RunError};
use glazec::lower::textures::bindings;
use glazec::model::{Material, ParamValue};

/// One texture's texels, RGBA in [0, 1], rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
}

impl TextureImage {
    /// A 1 × 1 texture.
    pub fn uniform(texel: [f32; 4]) -> TextureImage {
        TextureImage { width: 1, height: 1, texels: vec![texel] }
    }

    /// An 8- or 16-bit PNG (grey, grey + alpha, RGB or RGBA), values taken as linear.
    ///
    /// # Errors
    /// The file cannot be read or is not a PNG glazec understands.
    pub fn read_png(path: &std::path::Path) -> Result<TextureImage, RunError> {
        let bad = |m: String| RunError::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, m));
        let file = std::io::BufReader::new(std::fs::File::open(path)?);
        let mut decoder = png::Decoder::new(file);
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().map_err(|e| bad(format!("{}: {e}", path.display())))?;
        let size = reader.output_buffer_size().ok_or_else(|| bad(format!("{}: image too large", path.display())))?;
        let mut buffer = vec![0; size];
        let info = reader.next_frame(&mut buffer).map_err(|e| bad(format!("{}: {e}", path.display())))?;
        let channels = info.color_type.samples();
        let wide = info.bit_depth == png::BitDepth::Sixteen;
        let sample = |i: usize| -> f32 {
            if wide {
                f32::from(u16::from_be_bytes([buffer[2 * i], buffer[2 * i + 1]])) / 65535.0
            } else {
                f32::from(buffer[i]) / 255.0
            }
        };
        let pixels = (info.width * info.height) as usize;
        let texels = (0..pixels)
            .map(|p| {
                let c = |k: usize| sample(p * channels + k);
                match channels {
                    1 => [c(0), c(0), c(0), 1.0],
                    2 => [c(0), c(0), c(0), c(1)],
                    3 => [c(0), c(1), c(2), 1.0],
                    _ => [c(0), c(1), c(2), c(3)],
                }
            })
            .collect();
        Ok(TextureImage { width: info.width, height: info.height, texels })
    }
}

/// 1 × 1 textures that make each texture read of `material` equal its value in `values` (one
/// per parameter, in order); channels no read uses hold 0.5, and a normal map a flat normal.
pub fn constant_textures(material: &Material, values: &[ParamValue]) -> Vec<(String, TextureImage)> {
    material
        .textures()
        .iter()
        .map(|&name| {
            let mut texel = neutral_texel(material, name);
            for (i, _, read) in material.texture_params().filter(|(_, _, r)| r.texture == name) {
                let value = values.get(i).copied().unwrap_or(material.params[i].default);
                match (read.channel.index(), value) {
                    (Some(c), ParamValue::Scalar(x)) => texel[c as usize] = read.texel(x),
                    (Some(c), ParamValue::Rgb(rgb)) => texel[c as usize] = read.texel(rgb[0]),
                    (None, ParamValue::Rgb(rgb)) => {
                        for (k, x) in rgb.iter().enumerate() {
                            texel[k] = read.texel(*x);
                        }
                    }
                    (None, ParamValue::Scalar(x)) => texel[..3].fill(read.texel(x)),
                }
            }
            (name.to_string(), TextureImage::uniform(texel))
        })
        .collect()
}

/// The texel a texture holds when nothing is said about it: a flat normal (0, 0, 1) for a
/// normal map, mid-grey otherwise.
fn neutral_texel(material: &Material, name: &str) -> [f32; 4] {
    let normal_map = material.normals.iter().any(|(_, m)| m.textures().any(|t| t == name));
    if normal_map { [0.5, 0.5, 1.0, 1.0] } else { [0.5; 4] }
}

/// Whether a set of textures needs filtering (any larger than one texel): glazec's preview
/// filters images and reads constants exactly.
pub(crate) fn filtered(images: &[(String, TextureImage)]) -> bool {
    images.iter().any(|(_, i)| i.width * i.height > 1)
}

/// The group-1 layout for a material's textures, or `None` if it reads none.
/// `filtering`: bilinear `Rgba16Float` textures and a filtering sampler, or exact
/// `Rgba32Float` texels read by nearest sampling.
pub(crate) fn layout(
    gpu: &Gpu,
    material: &Material,
    filtering: bool,
    visibility: wgpu::ShaderStages,
) -> Option<wgpu::BindGroupLayout> {
    let names = material.textures();
    if names.is_empty() {
        return None;
    }
    let mut entries = vec![wgpu::BindGroupLayoutEntry {
        binding: bindings::SAMPLER,
        visibility,
        ty: wgpu::BindingType::Sampler(if filtering {
            wgpu::SamplerBindingType::Filtering
        } else {
            wgpu::SamplerBindingType::NonFiltering
        }),
        count: None,
    }];
    for i in 0..names.len() {
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: bindings::FIRST_TEXTURE + i as u32,
            visibility,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: filtering },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        });
    }
    Some(
        gpu.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("textures"), entries: &entries }),
    )
}

/// The group-1 bind group: `images` holds one image per texture of `material` (by name; a
/// missing one is a mid-grey texel).
pub(crate) fn bind_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    material: &Material,
    images: &[(String, TextureImage)],
    filtering: bool,
) -> wgpu::BindGroup {
    let views: Vec<wgpu::TextureView> = material
        .textures()
        .iter()
        .map(|name| {
            let neutral = TextureImage::uniform(neutral_texel(material, name));
            let image = images.iter().find(|(n, _)| n == name).map_or(&neutral, |(_, i)| i);
            upload(gpu, name, image, filtering).create_view(&Default::default())
        })
        .collect();
    let filter = if filtering { wgpu::FilterMode::Linear } else { wgpu::FilterMode::Nearest };
    let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(bindings::SAMPLER_NAME),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: filter,
        min_filter: filter,
        ..Default::default()
    });
    let mut entries =
        vec![wgpu::BindGroupEntry { binding: bindings::SAMPLER, resource: wgpu::BindingResource::Sampler(&sampler) }];
    for (i, view) in views.iter().enumerate() {
        entries.push(wgpu::BindGroupEntry {
            binding: bindings::FIRST_TEXTURE + i as u32,
            resource: wgpu::BindingResource::TextureView(view),
        });
    }
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("textures"), layout, entries: &entries })
}

/// Uploads an image: `Rgba16Float` (filterable) or exact `Rgba32Float`.
fn upload(gpu: &Gpu, name: &str, image: &TextureImage, filtering: bool) -> wgpu::Texture {
    let (format, bytes): (wgpu::TextureFormat, Vec<u8>) = if filtering {
        let halves: Vec<u16> = image.texels.iter().flatten().map(|&x| half::f16::from_f32(x).to_bits()).collect();
        (wgpu::TextureFormat::Rgba16Float, bytemuck::cast_slice(&halves).to_vec())
    } else {
        (wgpu::TextureFormat::Rgba32Float, bytemuck::cast_slice(&image.texels).to_vec())
    };
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some(name),
            size: wgpu::Extent3d { width: image.width, height: image.height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &bytes,
    )
}
