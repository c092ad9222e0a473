//! The error measure: a deterministic set of view and light configurations inside the scene's
//! cones, and the largest displayed difference between two materials over it.

use glam::Vec3;

use super::domain::{ParameterDomain, values_for};
use crate::math::sampling::{direction_f32, radical_inverse};
use crate::model::{Material, ParamValue};
use crate::scene::Scene;

/// The share of the tolerance a change may spend on the pass's own sample set.
pub const PASS_BUDGET: f32 = 0.5;

/// View angles of the pass's grid (from 0 to the scene's largest).
const PASS_VIEW_ANGLES: usize = 10;
/// Light angles of the pass's grid.
const PASS_LIGHT_ANGLES: usize = 12;
/// Azimuth differences of the pass's grid, over [0, π] (every BRDF here is isotropic).
const PASS_AZIMUTHS: usize = 9;
/// Halton points in the parameter box, besides the pinned values and range ends.
const PASS_PARAM_POINTS: usize = 6;
/// Environment quadrature: Gauss–Legendre nodes in cos θ, uniform nodes in φ.
const ENV_COS_NODES: usize = 16;
const ENV_AZIMUTHS: usize = 24;
/// The largest angle evaluated: f · cos θ vanishes at 90°, and directions exactly in the tangent
/// plane are outside every BRDF's domain.
const MAX_ANGLE_DEG: f32 = 89.5;

/// The configurations an error is measured on.
#[derive(Clone, Debug)]
pub struct SampleSet {
    /// (wi, wo) pairs in the local frame (n = +z).
    pub pairs: Vec<(Vec3, Vec3)>,
    /// View directions at which the environment term is integrated.
    pub views: Vec<Vec3>,
    /// Parameter vectors (by name).
    pub params: Vec<Vec<(String, ParamValue)>>,
    /// Environment quadrature: (direction, weight) over the light cone, Σ weight·cos θ = ∫ cos dω.
    pub env: Vec<(Vec3, f32)>,
    description: String,
}

pub(super) fn direction(theta_deg: f32, phi: f32) -> Vec3 {
    direction_f32(theta_deg.min(MAX_ANGLE_DEG).to_radians(), phi)
}

impl SampleSet {
    /// The pass's own grid (see the module docs).
    pub fn pass(scene: &Scene, domain: &ParameterDomain) -> Self {
        let grid = |n: usize, max: f32| (0..n).map(move |i| max * i as f32 / (n - 1) as f32);
        let views: Vec<Vec3> = grid(PASS_VIEW_ANGLES, scene.view_max_angle).map(|t| direction(t, 0.0)).collect();
        let mut pairs = Vec::new();
        for (j, theta_o) in grid(PASS_VIEW_ANGLES, scene.view_max_angle).enumerate() {
            let wo = views[j];
            for theta_i in grid(PASS_LIGHT_ANGLES, scene.light_max_angle) {
                for k in 0..PASS_AZIMUTHS {
                    let phi = std::f32::consts::PI * k as f32 / (PASS_AZIMUTHS - 1) as f32;
                    pairs.push((direction(theta_i, phi), wo));
                }
            }
            if theta_o <= scene.light_max_angle {
                pairs.push((direction(theta_o, std::f32::consts::PI), wo));
            }
        }
        let params = domain.vectors(PASS_PARAM_POINTS, 0);
        let environment = if scene.environment.is_some() {
            format!(", the environment integrated by {ENV_COS_NODES} × {ENV_AZIMUTHS} nodes at each view angle")
        } else {
            String::new()
        };
        let description = format!(
            "{} (wi, wo) pairs ({PASS_VIEW_ANGLES} view angles × {PASS_LIGHT_ANGLES} light angles × {PASS_AZIMUTHS} \
             azimuths, plus each view's mirror direction) × {} parameter vector(s){environment}; a change may use \
             {PASS_BUDGET} of the tolerance",
            pairs.len(),
            params.len()
        );
        SampleSet { pairs, views, params, env: env_quadrature(scene.light_max_angle), description }
    }

    /// An independent, denser set for checking a result: Halton directions (bases 2, 3, 5, 7)
    /// inside the cones, mirror configurations at Halton angles, and Halton parameter vectors
    /// away from the pass's.
    pub fn check(scene: &Scene, domain: &ParameterDomain, pairs: usize, param_points: usize) -> Self {
        let mut out = Vec::with_capacity(pairs);
        let cos_cap = |max: f32, u: f32| {
            // Uniform in cos θ over the cone: its directions where they occur.
            let c_min = max.min(MAX_ANGLE_DEG).to_radians().cos();
            (1.0 - u * (1.0 - c_min)).acos().to_degrees()
        };
        for i in 0..pairs {
            let n = (i + 1) as u32;
            let theta_o = cos_cap(scene.view_max_angle, radical_inverse(2, n));
            let wo = direction(theta_o, 0.0);
            if i % 8 == 7 && theta_o <= scene.light_max_angle {
                out.push((direction(theta_o, std::f32::consts::PI), wo));
                continue;
            }
            let theta_i = cos_cap(scene.light_max_angle, radical_inverse(3, n));
            let phi = std::f32::consts::PI * radical_inverse(5, n);
            out.push((direction(theta_i, phi), wo));
        }
        let views = (0..16).map(|i| direction(cos_cap(scene.view_max_angle, radical_inverse(7, i + 1)), 0.0)).collect();
        let params = domain.vectors(param_points, 97);
        let description = format!("{} Halton pairs × {} parameter vector(s)", out.len(), params.len());
        SampleSet { pairs: out, views, params, env: env_quadrature(scene.light_max_angle), description }
    }

    pub fn describe(&self) -> String {
        self.description.clone()
    }
}

impl SampleSet {
    /// Every (wi, wo) at which a material is evaluated, per parameter vector: the pairs, then
    /// (with an environment) each view with each environment node.
    pub fn evaluation_pairs(&self, with_env: bool) -> Vec<(Vec3, Vec3)> {
        let mut out = self.pairs.clone();
        if with_env {
            for wo in &self.views {
                out.extend(self.env.iter().map(|(wi, _)| (*wi, *wo)));
            }
        }
        out
    }
}

/// Gauss–Legendre (16 nodes) in cos θ over [cos θmax, 1] × uniform φ over [0, 2π): weights sum to the
/// cone's solid angle.
fn env_quadrature(max_angle: f32) -> Vec<(Vec3, f32)> {
    let c_min = max_angle.min(MAX_ANGLE_DEG).to_radians().cos();
    let mut out = Vec::new();
    for (x, w) in crate::math::quadrature::gauss_legendre_16() {
        let mu = c_min + (1.0 - c_min) * x as f32;
        let w_mu = w as f32 * (1.0 - c_min);
        let sin = (1.0 - mu * mu).max(0.0).sqrt();
        for k in 0..ENV_AZIMUTHS {
            let phi = std::f32::consts::TAU * (k as f32 + 0.5) / ENV_AZIMUTHS as f32;
            out.push((
                Vec3::new(sin * phi.cos(), sin * phi.sin(), mu),
                w_mu * std::f32::consts::TAU / ENV_AZIMUTHS as f32,
            ));
        }
    }
    out
}

/// f (without the cosine) at [`SampleSet::evaluation_pairs`], per parameter vector, on the CPU.
pub fn cpu_values(material: &Material, samples: &SampleSet, with_env: bool) -> Vec<Vec<Vec3>> {
    let pairs = samples.evaluation_pairs(with_env);
    samples
        .params
        .iter()
        .map(|named| {
            let values = values_for(material, named);
            pairs.iter().map(|(wi, wo)| crate::eval::brdf(material, &values, *wi, *wo)).collect()
        })
        .collect()
}

/// The reference material's values on a sample set, kept for comparing candidates.
pub struct Evaluated {
    full: Vec<Vec<Vec3>>,
}

impl Evaluated {
    pub fn new(material: &Material, scene: &Scene, samples: &SampleSet) -> Self {
        Evaluated { full: cpu_values(material, samples, scene.environment.is_some()) }
    }

    /// max over the set of ΔL / allowed for `candidate`, evaluated on the CPU.
    pub fn error(&self, candidate: &Material, scene: &Scene, samples: &SampleSet) -> f32 {
        error_between(&self.full, &cpu_values(candidate, samples, scene.environment.is_some()), scene, samples)
    }
}

/// max over the set of ΔL / allowed between two materials' values at
/// [`SampleSet::evaluation_pairs`] (see the module docs for ΔL).
pub fn error_between(full: &[Vec<Vec3>], candidate: &[Vec<Vec3>], scene: &Scene, samples: &SampleSet) -> f32 {
    let light = scene.lights.iter().fold(Vec3::ZERO, |acc, l| acc + Vec3::from(l.max_irradiance())) * scene.exposure;
    let environment = Vec3::from(scene.environment.unwrap_or([0.0; 3])) * scene.exposure;
    let n_pairs = samples.pairs.len();
    let n_env = samples.env.len();
    let mut worst = 0.0_f32;
    let mut worse = |delta: Vec3, value: Vec3| {
        worst = worst.max(scene.tolerance.share(value.to_array(), delta.to_array()));
    };
    for (full, cand) in full.iter().zip(candidate) {
        // The environment's share at each view: L_env · ∫ |Δf| cos, and L_env · ∫ f cos; the
        // largest over the views is added at every pair (conservative).
        let mut env_delta = Vec3::ZERO;
        if scene.environment.is_some() {
            for v in 0..samples.views.len() {
                let range = n_pairs + v * n_env..n_pairs + (v + 1) * n_env;
                let mut delta = Vec3::ZERO;
                let mut value = Vec3::ZERO;
                for ((a, b), (dir, w)) in full[range.clone()].iter().zip(&cand[range]).zip(&samples.env) {
                    delta += (*a - *b).abs() * dir.z * *w;
                    value += *a * dir.z * *w;
                }
                worse(delta * environment, value * environment);
                env_delta = env_delta.max(delta * environment);
            }
        }
        for ((a, b), (wi, _)) in full[..n_pairs].iter().zip(&cand[..n_pairs]).zip(&samples.pairs) {
            worse((*a - *b).abs() * wi.z * light + env_delta, *a * wi.z * light);
        }
    }
    worst
}
