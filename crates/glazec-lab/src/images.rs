//! Rendered images against the reference, compared with ꟻLIP (issue 31): what a user sees of a
//! material's accuracy.
//!
//! Every shipped material and every stack of the multi-coat set
//! ([`crate::accuracy::full`]) is rendered as the preview sphere (unit sphere, orthographic along
//! −z; `glazec_gpu::preview`) twice: under the preview's key light alone, and under the `sky`
//! environment alone. The glazec image is the generated shaders on the device: `preview_fs`
//! under the key light, `preview_ibl_fs` (split-sum image-based lighting) under the sky. The
//! reference image is the stochastic reference at the same pixels: f from [`Stack::f`] times
//! n·l under the key light, and under the sky the radiance its analog walks carry from the
//! environment ([`Stack::reflected`]), which includes a smooth coat's mirror reflection. Both
//! are encoded alike (`preview::encode`, exposure 1) and compared with ꟻLIP (Andersson et al.
//! 2020, NVIDIA's implementation through `nv-flip`) at its default 67 pixels per degree; the
//! mean and 99th percentile are over the sphere's pixels. A second reference rendered with
//! other seeds gives the reference's own noise floor in the same units.

use glam::{DVec3, Vec3};
use glazec_gpu::environment::{BASE_WIDTH, Prefiltered, prefilter};
use glazec_gpu::preview::{self, Environment, Image, Lighting, PreviewOptions};
use glazec_gpu::{Gpu, RunError};

use crate::accuracy::full::Subject;
use crate::reference::{InterfaceMode, Options, Stack};

/// Width and height of each image, in pixels.
pub const SIZE: u32 = 128;
/// Reference samples per pixel under the key light: Monte Carlo samples of f.
pub const KEY_SAMPLES: u32 = 1024;
/// Reference samples per pixel under the sky: analog walks (noisier per sample than f's
/// estimator, whose light direction is fixed).
pub const SKY_SAMPLES: u32 = 2048;
/// Seed offset of the second reference (the noise floor).
const SECOND_SEED: u64 = 1 << 32;

/// The two lightings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Light {
    /// The preview's key light, alone.
    Key,
    /// The `sky` environment, alone.
    Sky,
}

impl Light {
    pub const ALL: [Light; 2] = [Light::Key, Light::Sky];

    pub fn name(self) -> &'static str {
        match self {
            Light::Key => "key light",
            Light::Sky => "sky",
        }
    }
}

/// The preview options of a lighting (the sky prefiltered once, by the caller).
fn options(light: Light, sky: &std::sync::Arc<Prefiltered>) -> PreviewOptions {
    let base = PreviewOptions { size: SIZE, ..PreviewOptions::default() };
    match light {
        Light::Key => PreviewOptions { environment: Environment::None, lighting: Lighting::Samples, ..base },
        Light::Sky => PreviewOptions {
            light_radiance: 0.0,
            environment: Environment::Sky,
            lighting: Lighting::Image(sky.clone()),
            ..base
        },
    }
}

/// The sky, prefiltered for image-based lighting as `glazec preview` does.
pub fn prefiltered_sky() -> std::sync::Arc<Prefiltered> {
    let image = Environment::Sky.image(2 * BASE_WIDTH).unwrap_or_else(|| unreachable!("the sky is an environment"));
    std::sync::Arc::new(prefilter(&image))
}

/// The glazec image of a subject: its generated preview shaders on the device (linear RGBA).
///
/// # Errors
/// A device failure, or a material that does not compile.
pub fn glazec_image(
    gpu: &Gpu,
    subject: &Subject,
    light: Light,
    sky: &std::sync::Arc<Prefiltered>,
) -> Result<Vec<[f32; 4]>, RunError> {
    let compiled = glazec::compile_material(subject.material.clone(), Default::default())
        .map_err(|e| RunError::Rejected { what: format!("material {}", subject.label), message: e.to_string() })?;
    preview::render(gpu, &compiled, &subject.values, &options(light, sky))
}

/// The reference image of a subject (linear RGBA, alpha 1 on the sphere), with seeds from
/// `seed`.
pub fn reference_image(subject: &Subject, light: Light, seed: u64) -> Vec<[f32; 4]> {
    let stack = Stack::from_material(&subject.material, &subject.values);
    let key = PreviewOptions::default();
    let (key_direction, key_radiance) = (key.light.normalize_or(Vec3::Z).as_dvec3(), f64::from(key.light_radiance));
    let size = SIZE as usize;
    let rows = crate::parallel_map(
        size,
        |j| {
            (0..size)
                .map(|i| {
                    // The fragment's clip-space position at the pixel's centre (row 0 at the top).
                    let x = (i as f64 + 0.5) / SIZE as f64 * 2.0 - 1.0;
                    let y = 1.0 - (j as f64 + 0.5) / SIZE as f64 * 2.0;
                    let r2 = x * x + y * y;
                    if r2 >= 1.0 {
                        return [0.0; 4];
                    }
                    let n = DVec3::new(x, y, (1.0 - r2).sqrt());
                    let (t, b) = n.any_orthonormal_pair();
                    let local = |w: DVec3| DVec3::new(w.dot(t), w.dot(b), w.dot(n));
                    let v = local(DVec3::Z);
                    let opts = Options {
                        mode: InterfaceMode::Multiple,
                        samples: if light == Light::Key { KEY_SAMPLES } else { SKY_SAMPLES },
                        seed: seed + (j * size + i) as u64,
                        ..Default::default()
                    };
                    let radiance = match light {
                        Light::Key => {
                            let l = local(key_direction);
                            if l.z <= 0.0 { DVec3::ZERO } else { stack.f(l, v, &opts).mean * l.z * key_radiance }
                        }
                        Light::Sky => {
                            let world = |w: DVec3| t * w.x + b * w.y + n * w.z;
                            let sky = |w: DVec3| Environment::Sky.radiance(world(w).as_vec3()).as_dvec3();
                            stack.reflected(v, &sky, &opts).mean
                        }
                    };
                    [radiance.x as f32, radiance.y as f32, radiance.z as f32, 1.0]
                })
                .collect::<Vec<_>>()
        },
        |_| {},
    );
    rows.into_iter().flatten().collect()
}

/// ꟻLIP of `test` against `reference` (both [`SIZE`]², sRGB): the error map in ꟻLIP's magma
/// colours, and its mean and 99th percentile over the pixels where `mask` holds.
pub fn flip(reference: &Image, test: &Image, mask: &[bool]) -> (Image, f64, f64) {
    let as_flip = |image: &Image| nv_flip::FlipImageRgb8::with_data(image.width, image.height, &image.rgb);
    let error = nv_flip::flip(as_flip(reference), as_flip(test), nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let map = error.apply_color_lut(&nv_flip::magma_lut());
    let mut values: Vec<f64> =
        error.to_vec().iter().zip(mask).filter(|(_, m)| **m).map(|(&e, _)| f64::from(e)).collect();
    values.sort_by(f64::total_cmp);
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    let p99 = values.get(((values.len().max(1) - 1) as f64 * 0.99).round() as usize).copied().unwrap_or(0.0);
    (Image { width: map.width(), height: map.height(), rgb: map.to_vec() }, mean, p99)
}

/// One subject under one lighting: the three images and the figures.
pub struct Comparison {
    pub glazec: Image,
    pub reference: Image,
    pub error_map: Image,
    pub mean: f64,
    pub p99: f64,
    /// ꟻLIP between two references of different seeds: the noise floor.
    pub noise_mean: f64,
    pub noise_p99: f64,
}

/// Renders and compares one subject under one lighting.
///
/// # Errors
/// A device failure.
pub fn compare(
    gpu: &Gpu,
    subject: &Subject,
    light: Light,
    sky: &std::sync::Arc<Prefiltered>,
) -> Result<Comparison, RunError> {
    let linear = glazec_image(gpu, subject, light, sky)?;
    let mask: Vec<bool> = linear.iter().map(|p| p[3] > 0.0).collect();
    let glazec = preview::encode(&linear, SIZE, 1.0);
    let reference = preview::encode(&reference_image(subject, light, 0), SIZE, 1.0);
    let second = preview::encode(&reference_image(subject, light, SECOND_SEED), SIZE, 1.0);
    let (error_map, mean, p99) = flip(&reference, &glazec, &mask);
    let (_, noise_mean, noise_p99) = flip(&reference, &second, &mask);
    Ok(Comparison { glazec, reference, error_map, mean, p99, noise_mean, noise_p99 })
}

/// Every comparison of one set, and its contact sheet.
pub struct SetImages {
    /// The set's name (`shipped`, `multi-coat`): the sheet is `images-<name>.png`.
    pub name: &'static str,
    pub title: &'static str,
    /// Per subject: its label and its comparisons under [`Light::ALL`].
    pub rows: Vec<(String, Vec<Comparison>)>,
}

impl SetImages {
    /// The contact sheet: a row per material, `#k` its row in the table; per lighting the glazec
    /// image, the reference and the ꟻLIP error map.
    pub fn sheet(&self) -> Image {
        let mut tiles = Vec::new();
        for (k, (_, comparisons)) in self.rows.iter().enumerate() {
            for (light, c) in Light::ALL.iter().zip(comparisons) {
                let short = if *light == Light::Key { "key" } else { "sky" };
                tiles.push((format!("#{} {short}", k + 1), c.glazec.clone()));
                tiles.push((format!("#{} ref", k + 1), c.reference.clone()));
                tiles.push((format!("#{} FLIP", k + 1), c.error_map.clone()));
            }
        }
        preview::contact_sheet(&tiles, 3 * Light::ALL.len())
    }

    /// The set's table in Markdown.
    pub fn markdown(&self) -> String {
        let mut md = format!(
            "**{}** (`images-{}.png`; ꟻLIP over the sphere's pixels, mean / 99th percentile; in \
             brackets the reference against itself with other seeds, its noise floor):\n\n\
             | # | material | key light | sky |\n|---|---|---|---|\n",
            self.title, self.name
        );
        for (k, (label, comparisons)) in self.rows.iter().enumerate() {
            let cells: Vec<String> = comparisons
                .iter()
                .map(|c| format!("{:.3} / {:.3} ({:.3} / {:.3})", c.mean, c.p99, c.noise_mean, c.noise_p99))
                .collect();
            md.push_str(&format!("| {} | {label} | {} |\n", k + 1, cells.join(" | ")));
        }
        md
    }
}

/// Renders and compares the shipped materials and the multi-coat set under both lightings (with
/// `only`, the materials whose label contains it).
///
/// # Errors
/// A device failure, or a shipped material that does not compile.
pub fn run(gpu: &Gpu, only: Option<&str>, progress: &dyn Fn(&str)) -> Result<Vec<SetImages>, String> {
    let sky = prefiltered_sky();
    let sets = [
        (
            "shipped",
            "The shipped materials",
            crate::accuracy::full::shipped_subjects(&crate::accuracy::full::shipped_dir())?,
        ),
        ("multi-coat", "The multi-coat set", crate::accuracy::full::multi_coat_set()),
    ];
    let mut out = Vec::new();
    for (name, title, subjects) in sets {
        let mut rows = Vec::new();
        for subject in subjects.iter().filter(|s| only.is_none_or(|o| s.label.contains(o))) {
            progress(&subject.label);
            let comparisons = Light::ALL
                .iter()
                .map(|&light| compare(gpu, subject, light, &sky))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| format!("{}: {e}", subject.label))?;
            rows.push((subject.label.clone(), comparisons));
        }
        if !rows.is_empty() {
            out.push(SetImages { name, title, rows });
        }
    }
    Ok(out)
}
