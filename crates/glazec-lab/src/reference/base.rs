//! The opaque bases the reference walks under its coats: Lambert, Oren–Nayar, energy-preserving
//! Oren–Nayar and a GGX conductor, each evaluated and sampled from above.

use std::f64::consts::PI;

use glam::DVec3;

use super::microsurface::{self, RoughConductor, fresnel_conductor};
use super::{InterfaceMode, Rng, SMOOTH_ALPHA, walk_from_the_more_grazing};

/// An opaque base (directions above it, z > 0).
#[derive(Clone, Debug)]
pub enum BaseBsdf {
    Lambert {
        albedo: DVec3,
    },
    /// The qualitative Oren–Nayar model with σ in radians (Oren & Nayar 1994).
    OrenNayar {
        albedo: DVec3,
        sigma: f64,
    },
    /// Energy-preserving Oren–Nayar (Portsmouth, Kutz & Hill 2025), with the exact E_FON.
    Eon {
        albedo: DVec3,
        roughness: f64,
    },
    /// A GGX conductor, its Fresnel factor relative to the medium above.
    Conductor {
        alpha: f64,
        optics: ConductorOptics,
    },
}

/// A conductor's Fresnel factor, relative to the medium above it.
#[derive(Clone, Copy, Debug)]
pub enum ConductorOptics {
    /// The exact conductor Fresnel factor of complex IOR η + iκ ([`fresnel_conductor`]).
    Complex { eta: DVec3, k: DVec3 },
    /// Schlick 1994: F0 + (1 − F0)(1 − cos)⁵, what the material language means by `f0`.
    Schlick { f0: DVec3 },
}

impl ConductorOptics {
    /// The Fresnel factor at cosine `c` (clamped to [0, 1]).
    pub fn fresnel(&self, c: f64) -> DVec3 {
        match *self {
            ConductorOptics::Complex { eta, k } => fresnel_conductor(c, eta, k),
            ConductorOptics::Schlick { f0 } => f0 + (DVec3::ONE - f0) * (1.0 - c.clamp(0.0, 1.0)).powi(5),
        }
    }
}

pub(super) fn cosine_sample(rng: &mut Rng) -> DVec3 {
    let (u1, u2) = (rng.uniform(), rng.uniform());
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

/// The exact directional albedo of Fujii's Oren–Nayar lobe at ρ = 1 (EON paper, eq. 25).
fn e_fon_exact(mu: f64, r: f64) -> f64 {
    let a_f = 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * PI)) * r);
    let b_f = r * a_f;
    let s = (1.0 - mu * mu).max(0.0).sqrt();
    let g = s * (mu.clamp(-1.0, 1.0).acos() - s * mu) + (2.0 / 3.0) * ((s / mu.max(1e-12)) * (1.0 - s * s * s) - s);
    a_f + b_f / PI * g
}

impl BaseBsdf {
    pub(super) fn f(&self, wo: DVec3, wi: DVec3, mode: InterfaceMode, rng: &mut Rng) -> DVec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return DVec3::ZERO;
        }
        match self {
            BaseBsdf::Lambert { albedo } => *albedo / PI,
            BaseBsdf::OrenNayar { albedo, sigma } => {
                let s2 = sigma * sigma;
                let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
                let b = 0.45 * s2 / (s2 + 0.09);
                // cos(φi − φo) sin α tan β, computed from angles.
                let (ti, to) = (wi.z.acos(), wo.z.acos());
                let (alpha, beta) = (ti.max(to), ti.min(to));
                let (si, so) = (wi.truncate().length(), wo.truncate().length());
                let cos_dphi =
                    if si > 1e-12 && so > 1e-12 { wi.truncate().dot(wo.truncate()) / (si * so) } else { 0.0 };
                *albedo / PI * (a + b * cos_dphi.max(0.0) * alpha.sin() * beta.tan())
            }
            BaseBsdf::Eon { albedo, roughness: r } => {
                let c1 = 0.5 - 2.0 / (3.0 * PI);
                let c2 = 2.0 / 3.0 - 28.0 / (15.0 * PI);
                let s = wi.dot(wo) - wi.z * wo.z;
                let st = if s > 0.0 { s / wi.z.max(wo.z) } else { s };
                let a_f = 1.0 / (1.0 + c1 * r);
                let f_ss = *albedo / PI * a_f * (1.0 + r * st);
                let (eo, ei) = (e_fon_exact(wo.z, *r), e_fon_exact(wi.z, *r));
                let e_avg = a_f * (1.0 + c2 * r);
                let rho_ms = *albedo * *albedo * e_avg / (DVec3::ONE - *albedo * (1.0 - e_avg));
                f_ss + rho_ms / PI * ((1.0 - eo) * (1.0 - ei) / (1.0 - e_avg))
            }
            BaseBsdf::Conductor { alpha, optics } => {
                if *alpha < SMOOTH_ALPHA {
                    return DVec3::ZERO;
                }
                let fresnel = |c: f64| optics.fresnel(c);
                match mode {
                    InterfaceMode::Single => {
                        let m = (wo + wi).normalize();
                        fresnel(wo.dot(m))
                            * (microsurface::ggx_d(m, *alpha) * microsurface::g2(wo, wi, *alpha) / (4.0 * wo.z * wi.z))
                    }
                    InterfaceMode::Multiple => walk_from_the_more_grazing(wo, wi, |start, toward| {
                        RoughConductor { alpha: *alpha }.eval_multiple(start, toward, &fresnel, rng)
                    }),
                }
            }
        }
    }

    /// Samples a reflected direction from `wo` (above): (direction, f·cos/pdf).
    pub(super) fn sample(&self, wo: DVec3, mode: InterfaceMode, rng: &mut Rng) -> Option<(DVec3, DVec3)> {
        match self {
            BaseBsdf::Conductor { alpha, optics } => {
                let fresnel = |c: f64| optics.fresnel(c);
                if *alpha < SMOOTH_ALPHA {
                    return Some((DVec3::new(-wo.x, -wo.y, wo.z), fresnel(wo.z)));
                }
                match mode {
                    InterfaceMode::Single => {
                        let m = microsurface::sample_vndf(wo, *alpha, rng.uniform(), rng.uniform());
                        let wi = microsurface::reflect(wo, m);
                        if wi.z <= 0.0 {
                            return None;
                        }
                        let weight = microsurface::g2(wo, wi, *alpha) / microsurface::g1(wo, *alpha);
                        Some((wi, fresnel(wo.dot(m)) * weight))
                    }
                    InterfaceMode::Multiple => {
                        let (wi, weight) = RoughConductor { alpha: *alpha }.sample_multiple(wo, &fresnel, rng);
                        (wi.z > 0.0).then_some((wi, weight))
                    }
                }
            }
            _ => {
                let wi = cosine_sample(rng);
                if wi.z <= 0.0 {
                    return None;
                }
                // f·cos/pdf with pdf = cos/π.
                Some((wi, self.f(wo, wi, mode, rng) * PI))
            }
        }
    }
}
