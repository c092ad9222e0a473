//! Environments for image-based lighting: the images `lower::environment` binds (group 2).
//!
//! An environment is an equirectangular radiance image (linear RGB; direction d ↦
//! u = ½ + atan2(d.x, d.z)/2π, v = acos(d.y)/π, y up): a Radiance `.hdr` file
//! ([`EnvironmentImage::read_hdr`]) or an analytic one ([`EnvironmentImage::from_fn`]).
//! [`prefilter`] turns it into what `<material>_ibl` samples:
//!
//! * **radiance levels**: level 0 is the image resampled to [`BASE_WIDTH`] × [`BASE_WIDTH`]/2;
//!   level k of N = [`LEVELS`] is the environment convolved with a GGX lobe of roughness
//!   r = k/(N − 1) (α = r²) around each texel's direction, with n = v = r (Karis 2013, "Real
//!   Shading in Unreal Engine 4": the split sum's first factor), estimated with
//!   [`PREFILTER_SAMPLES`] Hammersley samples of the GGX normal distribution, each read from a
//!   box-filtered pyramid of the image at the level whose texels match the sample's solid angle
//!   (filtered importance sampling, Křivánek & Colbert 2008). The weights are normalised, so a
//!   constant environment stays exactly constant.
//! * **irradiance**: E(d)/π on a [`IRRADIANCE_WIDTH`] × [`IRRADIANCE_WIDTH`]/2 image, the
//!   cosine-weighted mean of the pyramid level of that size over the hemisphere around d, summed
//!   texel by texel (a constant environment again stays exactly constant).
//!
//! On the device both are `Rgba16Float` with linear filtering within and between levels,
//! repeating in u and clamped in v (half floats: 11 significant bits, a relative rounding of
//! 2⁻¹¹ ≈ 4.9·10⁻⁴).

use std::f32::consts::PI;

use glam::Vec3;
use rayon::prelude::*;
use wgpu::util::DeviceExt;

use crate::{Gpu, RunError};
use glazec::lower::environment::bindings;
use glazec::math::layering::environment::{EnvironmentLobe, Lookup};
use glazec::math::sampling::{ggx_half_vector, radical_inverse};

/// Width of the prefiltered level 0 (height: half of it).
pub const BASE_WIDTH: u32 = 512;
/// Number of prefiltered levels: 512 × 256 down to 8 × 4.
pub const LEVELS: u32 = 7;
/// GGX samples per texel of a prefiltered level.
pub const PREFILTER_SAMPLES: u32 = 256;
/// Width of the irradiance image (height: half of it).
pub const IRRADIANCE_WIDTH: u32 = 64;
/// The device format of both images.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// An equirectangular radiance image, rows top (+y) to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Vec3>,
}

/// The direction at equirectangular coordinates (u, v) (inverse of [`equirect_uv`]).
pub fn direction(u: f32, v: f32) -> Vec3 {
    let (phi, theta) = ((u - 0.5) * 2.0 * PI, v * PI);
    Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos())
}

/// The equirectangular coordinates of unit direction `d`, as the generated
/// `glazec_equirect_uv` computes them.
pub fn equirect_uv(d: Vec3) -> (f32, f32) {
    (0.5 + d.x.atan2(d.z) / (2.0 * PI), d.y.clamp(-1.0, 1.0).acos() / PI)
}

impl EnvironmentImage {
    /// An image of `width` × `width/2` texels holding `radiance` at each texel's centre.
    pub fn from_fn(width: u32, radiance: impl Fn(Vec3) -> Vec3) -> EnvironmentImage {
        let height = (width / 2).max(1);
        let texels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| radiance(direction((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32)))
            .collect();
        EnvironmentImage { width, height, texels }
    }

    /// A Radiance RGBE (`.hdr`) file, equirectangular (any size; twice as wide as high is the
    /// convention).
    ///
    /// # Errors
    /// The file cannot be read or is not a Radiance HDR image.
    pub fn read_hdr(path: &std::path::Path) -> Result<EnvironmentImage, RunError> {
        let bad = |m: String| RunError::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, m));
        let file = std::io::BufReader::new(std::fs::File::open(path)?);
        let decoder = image::codecs::hdr::HdrDecoder::new(file).map_err(|e| bad(format!("{}: {e}", path.display())))?;
        let meta = decoder.metadata();
        let pixels = decoder.read_image_hdr().map_err(|e| bad(format!("{}: {e}", path.display())))?;
        let texels = pixels.iter().map(|p| Vec3::from_array(p.0).max(Vec3::ZERO)).collect();
        Ok(EnvironmentImage { width: meta.width, height: meta.height, texels })
    }

    /// Bilinear lookup at (u, v): repeating in u, clamped in v.
    pub fn bilinear(&self, u: f32, v: f32) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = u * w as f32 - 0.5;
        let y = (v * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |dx: i64, dy: i64| {
            let xi = (x0 as i64 + dx).rem_euclid(w);
            let yi = (y0 as i64 + dy).clamp(0, h - 1);
            self.texels[(yi * w + xi) as usize]
        };
        let top = texel(0, 0).lerp(texel(1, 0), fx);
        let bottom = texel(0, 1).lerp(texel(1, 1), fx);
        top.lerp(bottom, fy)
    }

    /// The radiance arriving from direction `d` (bilinear).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (u, v) = equirect_uv(d);
        self.bilinear(u, v)
    }

    /// Half the width and height, each texel the solid-angle-weighted mean of the four it covers
    /// (an odd last column or row is dropped).
    fn half(&self) -> EnvironmentImage {
        let (width, height) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let weight = |y: u32| (((y as f32 + 0.5) / self.height as f32) * PI).sin();
        let texels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let mut sum = Vec3::ZERO;
                let mut total = 0.0;
                for (sx, sy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (xs, ys) = ((2 * x + sx).min(self.width - 1), (2 * y + sy).min(self.height - 1));
                    let w = weight(ys);
                    sum += self.texels[(ys * self.width + xs) as usize] * w;
                    total += w;
                }
                sum / total
            })
            .collect();
        EnvironmentImage { width, height, texels }
    }

    /// The image resampled to `width` × `width/2`: each new texel averages 4 × 4 bilinear
    /// samples of the source per source texel it spans (at least one).
    fn resampled(&self, width: u32) -> EnvironmentImage {
        let ratio = (self.width as f32 / width as f32).ceil().max(1.0) as u32;
        let grid = (ratio * 2).min(8);
        let height = (width / 2).max(1);
        let texels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let mut sum = Vec3::ZERO;
                for j in 0..grid {
                    for i in 0..grid {
                        let u = (x as f32 + (i as f32 + 0.5) / grid as f32) / width as f32;
                        let v = (y as f32 + (j as f32 + 0.5) / grid as f32) / height as f32;
                        sum += self.bilinear(u, v);
                    }
                }
                sum / (grid * grid) as f32
            })
            .collect();
        EnvironmentImage { width, height, texels }
    }
}

/// What `<material>_ibl` samples: the prefiltered radiance levels and the irradiance.
#[derive(Clone, Debug, PartialEq)]
pub struct Prefiltered {
    /// [`LEVELS`] images, [`BASE_WIDTH`] wide and halving.
    pub levels: Vec<EnvironmentImage>,
    /// E/π, [`IRRADIANCE_WIDTH`] wide.
    pub irradiance: EnvironmentImage,
}

impl Prefiltered {
    /// The prefiltered radiance around `d` for roughness `r`, as the shader's trilinear lookup
    /// reads it (lod = r·(N − 1)).
    pub fn radiance(&self, d: Vec3, r: f32) -> Vec3 {
        let (u, v) = equirect_uv(d);
        lookup(&self.levels, u, v, r.clamp(0.0, 1.0) * (self.levels.len() - 1) as f32)
    }

    /// E(d)/π.
    pub fn irradiance(&self, d: Vec3) -> Vec3 {
        self.irradiance.radiance(d)
    }

    /// The split sum on the CPU: Σ weight · lookup over a material's lobes
    /// ([`glazec::eval::environment_lobes`]), the value `<material>_ibl` computes on the device.
    pub fn shade(&self, lobes: &[EnvironmentLobe<f32>]) -> Vec3 {
        lobes
            .iter()
            .map(|lobe| {
                lobe.weight
                    * match lobe.lookup {
                        Lookup::Prefiltered => self.radiance(lobe.direction, lobe.roughness),
                        Lookup::Irradiance => self.irradiance(lobe.direction),
                    }
            })
            .sum()
    }
}

/// Trilinear lookup in a pyramid at fractional level `lod`.
fn lookup(pyramid: &[EnvironmentImage], u: f32, v: f32, lod: f32) -> Vec3 {
    let top = (pyramid.len() - 1) as f32;
    let lod = lod.clamp(0.0, top);
    let below = lod.floor() as usize;
    let above = (below + 1).min(pyramid.len() - 1);
    pyramid[below].bilinear(u, v).lerp(pyramid[above].bilinear(u, v), lod - below as f32)
}

/// Prefilters `image` for image-based lighting (see the module docs).
pub fn prefilter(image: &EnvironmentImage) -> Prefiltered {
    let mut pyramid = vec![image.resampled(BASE_WIDTH)];
    while pyramid.last().is_some_and(|level| level.height > 1) {
        let next = pyramid[pyramid.len() - 1].half();
        pyramid.push(next);
    }
    let levels = (0..LEVELS as usize)
        .map(|k| match k {
            0 => pyramid[0].clone(),
            _ => prefiltered_level(&pyramid, k, k as f32 / (LEVELS - 1) as f32),
        })
        .collect();
    let irradiance_source = pyramid.iter().find(|level| level.width <= IRRADIANCE_WIDTH).unwrap_or(&pyramid[0]);
    Prefiltered { levels, irradiance: irradiance(irradiance_source) }
}

/// Level `k` (the pyramid's size at k) convolved with a GGX lobe of roughness `r`.
fn prefiltered_level(pyramid: &[EnvironmentImage], k: usize, r: f32) -> EnvironmentImage {
    let (width, height) = (pyramid[k].width, pyramid[k].height);
    let alpha = r * r;
    // Solid angle of a texel of the pyramid's level 0, on average over the sphere.
    let texel_solid_angle = 4.0 * PI / (pyramid[0].width * pyramid[0].height) as f32;
    let rows: Vec<Vec<Vec3>> = (0..height)
        .into_par_iter()
        .map(|y| {
            (0..width)
                .map(|x| {
                    let (u, v) = ((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
                    convolve(pyramid, direction(u, v), alpha, texel_solid_angle)
                })
                .collect()
        })
        .collect();
    EnvironmentImage { width, height, texels: rows.into_iter().flatten().collect() }
}

/// The GGX-weighted mean radiance around `r` (n = v = r), Σ L(l) n·l / Σ n·l over GGX samples.
fn convolve(pyramid: &[EnvironmentImage], r: Vec3, alpha: f32, texel_solid_angle: f32) -> Vec3 {
    let (t, b) = r.any_orthonormal_pair();
    let mut sum = Vec3::ZERO;
    let mut total = 0.0;
    for i in 0..PREFILTER_SAMPLES {
        let (xi1, xi2) = ((i as f32 + 0.5) / PREFILTER_SAMPLES as f32, radical_inverse(2, i));
        let local = ggx_half_vector(alpha, xi1, xi2);
        let h = t * local.x + b * local.y + r * local.z;
        let l = h * (2.0 * r.dot(h)) - r;
        let n_dot_l = r.dot(l);
        if n_dot_l <= 0.0 {
            continue;
        }
        // pdf(l) = D(h) (n·h) / (4 v·h) = D(h)/4 with n = v (D: the shared `d_ggx`).
        let d = glazec::math::terms::d_ggx(local.z, local.x * local.x + local.y * local.y, alpha);
        let sample_solid_angle = 4.0 / (PREFILTER_SAMPLES as f32 * d.max(1e-12));
        // Filtered importance sampling: the level whose texels cover the sample's solid angle
        // (+1: Křivánek & Colbert's bias towards smoother, less noisy reads).
        let lod = 0.5 * (sample_solid_angle / texel_solid_angle).log2() + 1.0;
        let (u, v) = equirect_uv(l);
        sum += lookup(pyramid, u, v, lod) * n_dot_l;
        total += n_dot_l;
    }
    if total > 0.0 { sum / total } else { Vec3::ZERO }
}

/// E(d)/π for every texel direction d of an image of `source`'s size, by direct summation.
fn irradiance(source: &EnvironmentImage) -> EnvironmentImage {
    let (width, height) = (source.width, source.height);
    let texel_direction = |x: u32, y: u32| direction((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
    // Each texel's direction and solid angle (2π/W)(π/H) sin θ.
    let texels: Vec<(Vec3, f32, Vec3)> = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let theta = (y as f32 + 0.5) / height as f32 * PI;
            let solid_angle = 2.0 * PI * PI / (width * height) as f32 * theta.sin();
            (texel_direction(x, y), solid_angle, source.texels[(y * width + x) as usize])
        })
        .collect();
    let rows: Vec<Vec<Vec3>> = (0..height)
        .into_par_iter()
        .map(|y| {
            (0..width)
                .map(|x| {
                    let d = texel_direction(x, y);
                    let (mut sum, mut total) = (Vec3::ZERO, 0.0);
                    for &(w, solid_angle, radiance) in &texels {
                        let weight = d.dot(w).max(0.0) * solid_angle;
                        sum += radiance * weight;
                        total += weight;
                    }
                    sum / total
                })
                .collect()
        })
        .collect();
    EnvironmentImage { width, height, texels: rows.into_iter().flatten().collect() }
}

/// The layout of bind group [`bindings::GROUP`] for `stages`.
pub fn layout(gpu: &Gpu, stages: wgpu::ShaderStages) -> wgpu::BindGroupLayout {
    let texture = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let entries = [
        wgpu::BindGroupLayoutEntry {
            binding: bindings::SAMPLER,
            visibility: stages,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        },
        texture(bindings::RADIANCE),
        texture(bindings::IRRADIANCE),
    ];
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("environment"), entries: &entries })
}

/// Uploads `prefiltered` and binds it for `layout`.
pub fn bind_group(gpu: &Gpu, layout: &wgpu::BindGroupLayout, prefiltered: &Prefiltered) -> wgpu::BindGroup {
    let radiance = upload(gpu, "environment radiance", &prefiltered.levels);
    let irradiance = upload(gpu, "environment irradiance", std::slice::from_ref(&prefiltered.irradiance));
    let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(bindings::SAMPLER_NAME),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    });
    let view = |texture: &wgpu::Texture| texture.create_view(&Default::default());
    let (radiance_view, irradiance_view) = (view(&radiance), view(&irradiance));
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("environment"),
        layout,
        entries: &[
            wgpu::BindGroupEntry { binding: bindings::SAMPLER, resource: wgpu::BindingResource::Sampler(&sampler) },
            wgpu::BindGroupEntry {
                binding: bindings::RADIANCE,
                resource: wgpu::BindingResource::TextureView(&radiance_view),
            },
            wgpu::BindGroupEntry {
                binding: bindings::IRRADIANCE,
                resource: wgpu::BindingResource::TextureView(&irradiance_view),
            },
        ],
    })
}

/// One texture whose mip levels are `levels` (each half the previous one's size).
fn upload(gpu: &Gpu, label: &str, levels: &[EnvironmentImage]) -> wgpu::Texture {
    let size = wgpu::Extent3d { width: levels[0].width, height: levels[0].height, depth_or_array_layers: 1 };
    let data: Vec<u8> = levels
        .iter()
        .flat_map(|level| level.texels.iter())
        .flat_map(|t| [t.x, t.y, t.z, 1.0])
        .flat_map(|x| half::f16::from_f32(x).to_le_bytes())
        .collect();
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size,
            mip_level_count: levels.len() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &data,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_and_coordinates_are_inverse() {
        for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.8), (0.25, 0.01)] {
            let (u2, v2) = equirect_uv(direction(u, v));
            assert!((u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5, "{u} {v}: {u2} {v2}");
        }
        // +z (towards a preview's viewer) is the image's centre, +y its top row.
        assert_eq!(equirect_uv(Vec3::Z), (0.5, 0.0_f32.acos() / PI));
        assert!(equirect_uv(Vec3::Y).1.abs() < 1e-6);
    }

    /// A constant environment stays constant through every level and the irradiance (the
    /// weights are normalised): the white furnace of the lookups themselves.
    #[test]
    fn a_constant_environment_stays_constant() {
        let white = EnvironmentImage::from_fn(64, |_| Vec3::splat(0.75));
        let p = prefilter(&white);
        assert_eq!(p.levels.len(), LEVELS as usize);
        for (k, level) in p.levels.iter().enumerate() {
            assert_eq!(level.width, BASE_WIDTH >> k);
            for t in &level.texels {
                assert!((*t - Vec3::splat(0.75)).abs().max_element() < 1e-5, "level {k}: {t}");
            }
        }
        for t in &p.irradiance.texels {
            assert!((*t - Vec3::splat(0.75)).abs().max_element() < 1e-5, "irradiance: {t}");
        }
    }

    /// The irradiance of a sky that is 1 above the horizon and 0 below, seen by a surface facing
    /// up, is π (E/π = 1); facing sideways, π/2 (E/π = ½).
    #[test]
    fn irradiance_of_a_half_sky() {
        let sky = EnvironmentImage::from_fn(256, |d| if d.y > 0.0 { Vec3::ONE } else { Vec3::ZERO });
        let p = prefilter(&sky);
        let up = p.irradiance(Vec3::Y).x;
        let side = p.irradiance(Vec3::X).x;
        assert!((up - 1.0).abs() < 0.02, "{up}");
        assert!((side - 0.5).abs() < 0.02, "{side}");
    }
}
