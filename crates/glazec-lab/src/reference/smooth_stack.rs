//! An exact reference for stacks of smooth coats over a Lambertian base, deterministic and
//! without noise: the walks' answer where they need no walks.
//!
//! Smooth interfaces keep Snell's invariant p = n sin θ (n the absolute index of the medium the
//! light crosses), so light of one p never mixes with another until it reaches the base. Per p,
//! the adding equations of the interfaces (unpolarised Fresnel at every event, as the walks take
//! it; Born & Wolf 1999) and the slabs' one-way attenuation e^(−τ/μ) give the stack's
//! transmittance T(p) from outside down to the base and its reflectance R(p) seen from the base.
//! The base's diffuse light then reflects, off the mirror directions (the coats' own reflection
//! being a delta),
//!
//!   f(l, v) = T(pₗ) T(pᵥ) ρ / (π n² (1 − ρ R̄)),   R̄ = 2 ∫₀¹ R(p(μ)) μ dμ,
//!
//! μ the cosine and n the absolute index in the base's medium: light the base scatters is
//! diffuse, and each of its bounces reaches the base again with the share R̄. For one coat this is
//! the closed form of `tests/oracle.rs` (docs/derivations.md, "Smooth coat over Lambert").
//! Independent of `glazec::math`, like the rest of this module.

use std::f64::consts::PI;

use glam::DVec3;

use super::{BaseBsdf, Below, SMOOTH_ALPHA, Stack};

/// Midpoint steps in μ² for R̄ and ⟨T⟩ (computed once per stack): the integrands are smooth but for square-root kinks at
/// the critical angles, where the midpoint rule's error is about 10⁻⁶ at this count (a white
/// clear stack's albedo comes out 1 + 1.1·10⁻⁶).
const MEAN_STEPS: usize = 20_000;

/// A stack of smooth, non-scattering coats over Lambert, per channel.
#[derive(Clone, Debug)]
pub struct SmoothStack {
    /// (IOR relative to the medium above, optical depth per channel) per coat, from the top.
    coats: Vec<(f64, DVec3)>,
    albedo: DVec3,
    /// Absolute indices: outside (1) first, the base's medium last.
    indices: Vec<f64>,
    /// R̄ per channel: the share of the base's diffuse light that comes back to it.
    base_return: DVec3,
    /// ⟨T⟩ per channel: the outside hemisphere's mean transmittance down to the base.
    mean_transmission: DVec3,
}

/// Unpolarised Fresnel reflectance between media of absolute index `n1` (cosine `c1`) and `n2`
/// (cosine `c2`), both propagating at one invariant p.
fn fresnel(n1: f64, c1: f64, n2: f64, c2: f64) -> f64 {
    let rs = (n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2);
    let rp = (n2 * c1 - n1 * c2) / (n2 * c1 + n1 * c2);
    0.5 * (rs * rs + rp * rp)
}

/// One step of the adding equations: (T, R seen from below, R seen from above) of the layers
/// added so far, then a slab of one-way attenuation `a` and an interface of reflectance `r_j`.
fn add_interface((t, r_up, r_down): (f64, f64, f64), a: f64, r_j: f64) -> (f64, f64, f64) {
    let t_j = 1.0 - r_j;
    let round = 1.0 - r_up * a * a * r_j;
    (t * a * t_j / round, r_j + t_j * t_j * a * a * r_up / round, r_down + t * t * a * a * r_j / round)
}

/// The midpoint-rule mean of `g(μ²)` over μ² ∈ [0, 1] (projected solid angle).
fn hemispherical_mean(g: impl Fn(f64) -> f64) -> f64 {
    (0..MEAN_STEPS).map(|i| g((i as f64 + 0.5) / MEAN_STEPS as f64)).sum::<f64>() / MEAN_STEPS as f64
}

impl SmoothStack {
    /// The stack of `stack`, if every coat is smooth (α below the walks' own smooth limit) and
    /// clear of scattering, over a Lambertian base; `None` otherwise.
    pub fn of(stack: &Stack) -> Option<SmoothStack> {
        let mut coats = Vec::new();
        let mut at = stack;
        let albedo = loop {
            let (interface, medium) = at.coat.as_ref()?;
            if interface.alpha >= SMOOTH_ALPHA || medium.scattering != 0.0 {
                return None;
            }
            coats.push((interface.eta, medium.absorption * medium.thickness));
            match &at.below {
                Below::Stack(next) => at = next,
                Below::Base(BaseBsdf::Lambert { albedo }) => break *albedo,
                Below::Base(_) => return None,
            }
        };
        let mut indices = vec![1.0];
        for &(eta, _) in &coats {
            indices.push(indices[indices.len() - 1] * eta);
        }
        let mut stack =
            SmoothStack { coats, albedo, indices, base_return: DVec3::ZERO, mean_transmission: DVec3::ZERO };
        let n_base = stack.n_base();
        for c in 0..3 {
            stack.base_return[c] = hemispherical_mean(|mu_sq| stack.adding(n_base * (1.0 - mu_sq).sqrt(), c).1);
            stack.mean_transmission[c] = hemispherical_mean(|mu_sq| stack.adding((1.0 - mu_sq).sqrt(), c).0);
        }
        Some(stack)
    }

    /// The absolute index of the base's medium.
    fn n_base(&self) -> f64 {
        self.indices[self.indices.len() - 1]
    }

    /// (T, R) of one channel at invariant `p`: T from outside down to the base, R of everything
    /// above seen from the base.
    fn adding(&self, p: f64, channel: usize) -> (f64, f64) {
        let n = &self.indices;
        // Light of this p does not propagate in the base's medium: none reaches it.
        if p >= self.n_base() {
            return (0.0, 1.0);
        }
        // Below the lowest medium where p does not propagate everything is reflected.
        let (start, mut sums) = match (0..n.len()).rev().find(|&k| p >= n[k]) {
            None => (1, (1.0, 0.0, 0.0)),
            Some(k) => (k + 2, (0.0, 1.0, 1.0)),
        };
        for j in start..n.len() {
            let (a, r_j) = self.interface(p, j, channel);
            sums = add_interface(sums, a, r_j);
        }
        let a = self.attenuation(p, n.len() - 1, channel);
        (sums.0 * a, sums.1 * a * a)
    }

    /// The interfaces' own (specular) reflectance seen from outside at invariant `p` < 1, one
    /// channel: the adding equations from the top, down to the base or to the first medium `p`
    /// does not propagate in, which reflects everything.
    fn mirror_reflectance(&self, p: f64, channel: usize) -> f64 {
        let mut sums = (1.0, 0.0, 0.0);
        for j in 1..self.indices.len() {
            if p >= self.indices[j] {
                return add_interface(sums, self.attenuation(p, j - 1, channel), 1.0).2;
            }
            let (a, r_j) = self.interface(p, j, channel);
            sums = add_interface(sums, a, r_j);
        }
        sums.2
    }

    /// One-way attenuation e^(−τ/μ) through the slab of medium `k` (none outside, k = 0).
    fn attenuation(&self, p: f64, k: usize, channel: usize) -> f64 {
        if k == 0 {
            return 1.0;
        }
        let cosine = (1.0 - (p / self.indices[k]).powi(2)).max(0.0).sqrt();
        (-self.coats[k - 1].1[channel] / cosine).exp()
    }

    /// (attenuation through the slab above interface `j`, the interface's Fresnel reflectance),
    /// both media propagating.
    fn interface(&self, p: f64, j: usize, channel: usize) -> (f64, f64) {
        let n = &self.indices;
        let cosine = |k: usize| (1.0 - (p / n[k]).powi(2)).max(0.0).sqrt();
        (self.attenuation(p, j - 1, channel), fresnel(n[j - 1], cosine(j - 1), n[j], cosine(j)))
    }

    /// What the base's diffuse light gives per unit transmittance on each side, one channel:
    /// ρ / (n² (1 − ρ R̄)).
    fn diffuse(&self, channel: usize) -> f64 {
        let rho = self.albedo[channel];
        rho / (self.n_base() * self.n_base() * (1.0 - rho * self.base_return[channel]))
    }

    /// The directional albedo towards `wo` (the mirror reflection included):
    /// R_s(p) + T(p) ρ ⟨T⟩ / (n² (1 − ρ R̄)), ⟨T⟩ the outside hemisphere's mean transmittance.
    pub fn directional_albedo(&self, wo: DVec3) -> DVec3 {
        let p = (1.0 - wo.normalize().z.powi(2)).max(0.0).sqrt();
        DVec3::from_array(std::array::from_fn(|c| {
            self.mirror_reflectance(p, c) + self.adding(p, c).0 * self.mean_transmission[c] * self.diffuse(c)
        }))
    }

    /// f(wi, wo) without the cosine, off the mirror directions (directions need not be unit).
    pub fn f(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        let (wi, wo) = (wi.normalize(), wo.normalize());
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return DVec3::ZERO;
        }
        let sine = |w: DVec3| (1.0 - w.z * w.z).max(0.0).sqrt();
        DVec3::from_array(std::array::from_fn(|c| {
            self.adding(sine(wi), c).0 * self.adding(sine(wo), c).0 * self.diffuse(c) / PI
        }))
    }
}

#[cfg(test)]
mod tests {
    use glazec::math::sampling::direction_deg;

    use super::*;
    use crate::reference::{InterfaceMode, Options};

    /// Walks per probe of the stochastic reference (standard errors of 0.3–0.5% here).
    const WALKS: u32 = 40_000;
    /// The walks agree with the exact answer within this many standard errors.
    const SIGMAS: f64 = 4.0;
    /// The default method's body target of issue 31 (docs/accuracy.md, "The whole BRDF, in
    /// bands"), which these smooth stacks meet against the exact answer.
    const BODY_TARGET: f64 = 0.02;
    /// How far the exact directional albedo of a white clear stack may lie from 1 (the midpoint
    /// rule's error in R̄ and ⟨T⟩, about 10⁻⁶; see `MEAN_STEPS`).
    const ENERGY_TOL: f64 = 1e-5;
    /// How far glazec's stated albedo of a white clear stack may lie from 1 (f32 rounding).
    const STATED_ENERGY_TOL: f64 = 1e-5;
    /// (θl, θv, azimuth between them) of the probes, degrees: body pairs off the mirror plane.
    const BODY_PAIRS: [(f64, f64, f64); 4] =
        [(0.0, 30.0, 90.0), (30.0, 60.0, 90.0), (60.0, 60.0, 45.0), (45.0, 20.0, 0.0)];

    fn material(layers: &str) -> (glazec::model::Material, Vec<glazec::model::ParamValue>) {
        let source = format!("Material(name: \"probe\", layers: [{layers}])");
        let material = glazec::compile(&source).expect("a valid material").material;
        let values = material.default_values();
        (material, values)
    }

    #[test]
    fn one_coat_is_the_closed_form() {
        // ρ(1 − F(μi))(1 − F(μo)) e^(−τ(1/μti + 1/μto)) / (π η² (1 − ρ R_ret)) at normal incidence
        // on both sides (μt = 1, F = ((η − 1)/(η + 1))²), with R_ret of a clear η 1.5 coat:
        // 1 − (1 − R̄ext)/η², R̄ext = 0.0918 (the hemispherical reflectance from outside).
        let (m, values) = material("Coat(lobe: Smooth, ior: 1.5), Lambert(0.8)");
        let exact = SmoothStack::of(&Stack::from_material(&m, &values)).expect("a smooth stack");
        let f0 = 0.04;
        let r_ret = 1.0 - (1.0 - 0.091_752) / 2.25;
        let expected = 0.8 * (1.0 - f0) * (1.0 - f0) / (PI * 2.25 * (1.0 - 0.8 * r_ret));
        let f = exact.f(DVec3::Z, DVec3::Z).x;
        assert!((f / expected - 1.0).abs() < 1e-4, "{f} against {expected}");
    }

    #[test]
    fn a_white_clear_stack_reflects_everything() {
        for (layers, stated_too) in [
            (
                "Coat(lobe: Smooth, ior: 1.5), Coat(lobe: Smooth, ior: 0.8), Coat(lobe: Smooth, ior: 2.0), Lambert(1.0)",
                true,
            ),
            // A coat thinner than air (absolute index 0.75) reflects whatever arrives beyond
            // 48.6°. glazec states 0.994 at 85° and 0.971 at 89° there (docs/limitations.md).
            ("Coat(lobe: Smooth, ior: 1.5), Coat(lobe: Smooth, ior: 0.5), Lambert(1.0)", false),
        ] {
            white_stack_reflects_everything(layers, stated_too);
        }
    }

    fn white_stack_reflects_everything(layers: &str, stated_too: bool) {
        let (m, values) = material(layers);
        let exact = SmoothStack::of(&Stack::from_material(&m, &values)).expect("a smooth stack");
        for theta in [0.0, 40.0, 80.0, 89.0] {
            let wo = direction_deg(theta, 0.0);
            let albedo = exact.directional_albedo(wo);
            assert!((albedo - DVec3::ONE).abs().max_element() < ENERGY_TOL, "at {theta}°: {albedo}");
            // What glazec states for image-based lighting (its lobes' weights) is the same.
            let lobes = glazec::eval::environment_lobes(&m, &values, glam::Vec3::Z, wo.as_vec3());
            let stated: f32 = lobes.iter().map(|lobe| lobe.weight.x).sum();
            assert!(!stated_too || (f64::from(stated) - 1.0).abs() < STATED_ENERGY_TOL, "stated at {theta}°: {stated}");
        }
    }

    #[test]
    fn stacks_agree_with_the_walks() {
        for layers in [
            "Coat(lobe: Smooth, ior: 1.5), Coat(lobe: Smooth, ior: 1.4, absorption: (0.1, 0.3, 0.6), thickness: 1.0), \
             Coat(lobe: Smooth, ior: 1.5), Lambert(0.8)",
            // A coat optically thinner than the one above it: light beyond the critical angle
            // between them never reaches the base.
            "Coat(lobe: Smooth, ior: 2.0), Coat(lobe: Smooth, ior: 0.8), Lambert((1.0, 0.8, 0.3))",
        ] {
            let (m, values) = material(layers);
            let stack = Stack::from_material(&m, &values);
            let exact = SmoothStack::of(&stack).expect("a smooth stack");
            let options = Options { mode: InterfaceMode::Multiple, samples: WALKS, seed: 3, ..Default::default() };
            for (theta_l, theta_v, phi) in [BODY_PAIRS[1], (80.0, 40.0, 90.0)] {
                let (wi, wo) = (direction_deg(theta_l, 0.0), direction_deg(theta_v, phi));
                let walks = stack.f(wi, wo, &options);
                let f = exact.f(wi, wo);
                for c in 0..3 {
                    let off = (f[c] - walks.mean[c]).abs() / walks.std_err[c];
                    assert!(off <= SIGMAS, "{layers} at {theta_l}/{theta_v}: {} against the walks' {walks:?}", f[c]);
                }
            }
        }
    }

    #[test]
    fn smooth_stacks_meet_the_body_target() {
        for layers in [
            "Coat(lobe: Smooth, ior: 1.5), Coat(lobe: Smooth, ior: 1.5), Lambert(0.8)",
            "Coat(lobe: Smooth, ior: 1.33), Coat(lobe: Smooth, ior: 1.6, absorption: 0.5, thickness: 1.0), Lambert((0.9, 0.5, 0.2))",
            "Coat(lobe: Smooth, ior: 2.0), Coat(lobe: Smooth, ior: 0.8), Lambert(1.0)",
            // Three: the light the top coat returns to the two below is what their top interface
            // reflects back, not their mean albedo (`returned_albedo`; 5.6% too bright before).
            "Coat(lobe: Smooth, ior: 1.5), Coat(lobe: Smooth, ior: 1.5), Coat(lobe: Smooth, ior: 1.5), Lambert(0.8)",
        ] {
            let (m, values) = material(layers);
            let exact = SmoothStack::of(&Stack::from_material(&m, &values)).expect("a smooth stack");
            for (theta_l, theta_v, phi) in BODY_PAIRS {
                let (wi, wo) = (direction_deg(theta_l, 0.0), direction_deg(theta_v, phi));
                let f = glazec::eval::brdf(&m, &values, wi.as_vec3(), wo.as_vec3()).as_dvec3();
                let error = (f / exact.f(wi, wo) - 1.0).abs().max_element();
                assert!(error <= BODY_TARGET, "{layers} at {theta_l}/{theta_v}/{phi}: {error}");
            }
        }
    }
}
