//! The brute-force reference of image-based lighting: the radiance a material reflects from an
//! environment, integrated by multiple importance sampling over the hemisphere. The split-sum
//! lobes that `<material>_ibl` evaluates (`glazec::eval::environment_lobes`) are measured
//! against it (`tests/ibl.rs`).

use glam::Vec3;

use crate::reference::Rng;
use glazec::math::layering::{self, environment::Lookup};
use glazec::math::sampling::{cosine_direction, ggx_half_vector};
use glazec::model::{Material, ParamValue};

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
    let (t, b) = n.any_orthonormal_pair();
    let to_local = |w: Vec3| Vec3::new(w.dot(t), w.dot(b), w.dot(n));
    let v_local = to_local(v);
    if v_local.z <= 0.0 {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    // GGX strategies: the α of every prefiltered lobe that is not a mirror.
    let alphas: Vec<f32> = glazec::eval::environment_lobes(material, values, n, v)
        .iter()
        .filter(|lobe| lobe.lookup == Lookup::Prefiltered && lobe.lobe_roughness > 0.0)
        // (No sharper than `d_ggx`'s own floor, so that samples and density agree.)
        .map(|lobe| (lobe.lobe_roughness * lobe.lobe_roughness).max(glazec::math::terms::ALPHA_MIN))
        .collect();
    let strategies = 1 + alphas.len();
    let per_batch = (samples / BATCHES).max(1);
    let side = (f64::from(per_batch).sqrt().ceil() as u32).max(1);
    let mut rng = Rng::seeded(seed);
    let inputs = glazec::eval::inputs(values);
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
    glazec::math::terms::d_ggx(h.z, h.x * h.x + h.y * h.y, alpha) * h.z / (4.0 * v_dot_h)
}
