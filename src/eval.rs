//! CPU evaluation: a material's BRDF at given direction pairs, through the same [`crate::math`]
//! code that `lower` turns into shaders (here with `F = f32`).
//!
//! **Input:** a [`Material`], parameter values, and pairs (wi, wo) in the local shading frame
//! (z = normal, both directions pointing away from the surface). **Output:** f(wi, wo) per pair,
//! RGB, **without** the cosine. This is `glazec eval --backend cpu`; the direction-pair text
//! format lives here too, so that every backend reads the same input.

use glam::Vec3;

use crate::math::Slot;
use crate::math::layering::{self, Inputs};
use crate::model::{Material, ParamValue};

/// f(wi, wo) of `material` with the given parameter values (one per [`Material::params`]).
pub fn brdf(material: &Material, values: &[ParamValue], wi: Vec3, wo: Vec3) -> Vec3 {
    layering::brdf(material, &inputs(values), Vec3::Z, wo, wi)
}

/// [`brdf`] with shading normals for the layers that have normal maps: (layer, unit normal in
/// the local frame, n = +z); coats are layers 0…, the base is layer `coats.len()`.
pub fn brdf_with_normals(
    material: &Material,
    values: &[ParamValue],
    normals: &[(usize, Vec3)],
    wi: Vec3,
    wo: Vec3,
) -> Vec3 {
    layering::brdf(material, &inputs(values).with_normals(normals.to_vec()), Vec3::Z, wo, wi)
}

/// The lobes of `material` under image-based lighting, seen from `v` at normal `n` (see
/// [`layering::environment`]): the split sum is Σ weight · lookup(direction, roughness).
pub fn environment_lobes(
    material: &Material,
    values: &[ParamValue],
    n: Vec3,
    v: Vec3,
) -> Vec<layering::environment::EnvironmentLobe<f32>> {
    layering::environment::environment_lobes(material, &inputs(values), n, v)
}

/// Independently jittered batches of [`environment_integral`]: each draws `samples / BATCHES`
/// directions per strategy as a square jittered grid; the spread of the batch means gives the
/// standard error.
const BATCHES: u32 = 8;

/// The radiance `material` reflects towards `v` (normal `n`) from an environment of radiance
/// `radiance(direction)`, by brute force: ∫ f(v, l) L(l) n·l dl over the hemisphere, sampled by
/// cosine-weighted directions and by GGX reflections for each rough lobe of the material
/// (one-sample multiple importance sampling, balance heuristic; Veach 1997 §9.2), plus the
/// mirror lobe of a smooth top coat in closed form, R(v)·L(reflect(v)). `samples` directions
/// per strategy, in 8 independently jittered batches; returns the mean and its
/// standard error (the spread of the batch means). Deterministic for a given `seed`.
pub fn environment_integral(
    material: &Material,
    values: &[ParamValue],
    (n, v): (Vec3, Vec3),
    radiance: &dyn Fn(Vec3) -> Vec3,
    samples: u32,
    seed: u64,
) -> (Vec3, Vec3) {
    use layering::environment::Lookup;
    let (t, b) = n.any_orthonormal_pair();
    let to_local = |w: Vec3| Vec3::new(w.dot(t), w.dot(b), w.dot(n));
    let v_local = to_local(v);
    if v_local.z <= 0.0 {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    // GGX strategies: the α of every prefiltered lobe that is not a mirror.
    let alphas: Vec<f32> = environment_lobes(material, values, n, v)
        .iter()
        .filter(|lobe| lobe.lookup == Lookup::Prefiltered && lobe.roughness > 0.0)
        // (No sharper than `d_ggx`'s own floor, so that samples and density agree.)
        .map(|lobe| (lobe.roughness * lobe.roughness).max(crate::math::terms::ALPHA_MIN))
        .collect();
    let strategies = 1 + alphas.len();
    let per_batch = (samples / BATCHES).max(1);
    let side = (f64::from(per_batch).sqrt().ceil() as u32).max(1);
    let mut rng = crate::reference::Rng::seeded(seed);
    let inputs = inputs(values);
    let pdf = |l: Vec3| -> f32 {
        let cosine = l.z.max(0.0) / std::f32::consts::PI;
        let ggx: f32 = alphas.iter().map(|&a| ggx_reflection_pdf(v_local, l, a)).sum();
        (cosine + ggx) / strategies as f32
    };
    let mut batch_means = Vec::with_capacity(BATCHES as usize);
    for _ in 0..BATCHES {
        let (jx, jy) = (rng.uniform() as f32, rng.uniform() as f32);
        let mut sum = Vec3::ZERO;
        let mut count = 0u32;
        for strategy in 0..strategies {
            for k in 0..side * side {
                let u1 = (((k % side) as f32 + jx) / side as f32).fract();
                let u2 = (((k / side) as f32 + jy) / side as f32).fract();
                let l = match strategy {
                    0 => cosine_direction(u1, u2),
                    s => ggx_reflection(v_local, alphas[s - 1], u1, u2),
                };
                count += 1;
                if l.z <= 0.0 {
                    continue;
                }
                let world = t * l.x + b * l.y + n * l.z;
                let f = layering::brdf(material, &inputs, Vec3::Z, v_local, l);
                sum += f * radiance(world) * (l.z / pdf(l));
            }
        }
        batch_means.push(sum / count as f32);
    }
    let mean = batch_means.iter().copied().sum::<Vec3>() / BATCHES as f32;
    let spread = batch_means.iter().map(|m| (*m - mean) * (*m - mean)).sum::<Vec3>() / (BATCHES - 1) as f32;
    let mirror = layering::mirror_reflectance(material, &inputs, Vec3::Z, v_local);
    let reflected = n * (2.0 * n.dot(v)) - v;
    (mean + mirror * radiance(reflected), (spread / BATCHES as f32).max(Vec3::ZERO).sqrt())
}

/// A cosine-weighted direction (Malley's method) in the local frame.
fn cosine_direction(u1: f32, u2: f32) -> Vec3 {
    let r = u1.sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

/// A GGX half vector of roughness α in the local frame (z = normal), sampled in proportion to
/// D(h)(n·h) (Walter et al. 2007, eq. 35–36).
pub(crate) fn ggx_half_vector(alpha: f32, u1: f32, u2: f32) -> Vec3 {
    let a2 = alpha * alpha;
    let cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
    let sin = (1.0 - cos2).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u2;
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos2.sqrt())
}

/// The mirror reflection of `v` about a [`ggx_half_vector`], local frame.
fn ggx_reflection(v: Vec3, alpha: f32, u1: f32, u2: f32) -> Vec3 {
    let h = ggx_half_vector(alpha, u1, u2);
    h * (2.0 * v.dot(h)) - v
}

/// The density of [`ggx_reflection`]'s directions: D(h)(n·h)/(4 v·h) (Walter et al. 2007,
/// eq. 14 and 38; D is the shared `d_ggx`), 0 where v·h ≤ 0.
fn ggx_reflection_pdf(v: Vec3, l: Vec3, alpha: f32) -> f32 {
    let h = (v + l).normalize_or_zero();
    let v_dot_h = v.dot(h);
    if v_dot_h <= 0.0 || h.z <= 0.0 {
        return 0.0;
    }
    crate::math::terms::d_ggx(h.z, h.x * h.x + h.y * h.y, alpha) * h.z / (4.0 * v_dot_h)
}

/// The reflectance of the material's mirror (delta) lobe towards `wo` (see
/// [`layering::mirror_reflectance`]).
pub fn mirror_reflectance(material: &Material, values: &[ParamValue], wo: Vec3) -> Vec3 {
    layering::mirror_reflectance(material, &inputs(values), Vec3::Z, wo)
}

/// The CPU inputs of a material for parameter values (one per [`Material::params`]).
pub(crate) fn inputs(values: &[ParamValue]) -> Inputs<f32> {
    let params = values
        .iter()
        .map(|v| match *v {
            ParamValue::Scalar(x) => Slot::S(x),
            ParamValue::Rgb(c) => Slot::V(Vec3::from_array(c)),
        })
        .collect();
    Inputs::new((), params)
}

/// A direction pair: the light direction `wi` and the view direction `wo`, both unit vectors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pair {
    pub wi: Vec3,
    pub wo: Vec3,
}

/// A malformed line in a pairs file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct PairsError {
    pub line: usize,
    pub message: String,
}

/// Reads lines `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z`. A first line that is not six numbers is a
/// header; blank lines are skipped. Directions are normalised; a zero or non-finite vector is
/// an error.
///
/// # Errors
/// The first malformed line.
pub fn parse_pairs(text: &str) -> Result<Vec<Pair>, PairsError> {
    let mut pairs = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let line_no = index + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        let fields: Vec<&str> = trimmed.split(',').map(str::trim).collect();
        let numbers: Result<Vec<f32>, _> = fields.iter().map(|f| f.parse::<f32>()).collect();
        let numbers = match numbers {
            Ok(n) => n,
            Err(_) if index == 0 => continue, // a header line
            Err(_) => {
                return Err(PairsError { line: line_no, message: format!("expected six numbers, found `{trimmed}`") });
            }
        };
        if numbers.len() != 6 {
            return Err(PairsError {
                line: line_no,
                message: format!("expected 6 values (wi_x,wi_y,wi_z,wo_x,wo_y,wo_z), found {}", numbers.len()),
            });
        }
        let unit = |v: Vec3, what: &str| {
            let len = v.length();
            if len.is_finite() && len > 0.0 {
                Ok(v / len)
            } else {
                Err(PairsError {
                    line: line_no,
                    message: format!("{what} is not a direction (zero length or not finite)"),
                })
            }
        };
        let wi = unit(Vec3::new(numbers[0], numbers[1], numbers[2]), "wi")?;
        let wo = unit(Vec3::new(numbers[3], numbers[4], numbers[5]), "wo")?;
        pairs.push(Pair { wi, wo });
    }
    Ok(pairs)
}

/// One output line `r,g,b`, each value printed with the shortest text that reads back as the
/// same f32 (Rust's `Display`), so no precision is lost.
pub fn format_rgb(rgb: Vec3) -> String {
    format!("{},{},{}", rgb.x, rgb.y, rgb.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_with_header_and_blank_lines() {
        let pairs =
            parse_pairs("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,2, 0,0,1\n\n0.6,0,0.8,-0.6,0,0.8\n").expect("parses");
        assert_eq!(pairs.len(), 2);
        assert_eq!(pairs[0].wi, Vec3::Z);
        assert_eq!(parse_pairs("0,0,1,0,0\n").unwrap_err().line, 1);
        assert_eq!(parse_pairs("0,0,1,0,0,1\n0,0,x,0,0,1\n").unwrap_err().line, 2);
        assert!(parse_pairs("0,0,0,0,0,1\n").is_err());
    }

    #[test]
    fn rgb_round_trips() {
        let v = Vec3::new(0.1, 1.0 / 3.0, 1e-9);
        let text = format_rgb(v);
        let back: Vec<f32> = text.split(',').map(|x| x.parse().expect("number")).collect();
        assert_eq!(back, [v.x, v.y, v.z]);
    }
}
