//! Rough interfaces of the reference: isotropic GGX microsurfaces, in f64 (dielectric ones may
//! have GTR1 normals instead: [`Ndf`], [`super::gtr1`]).
//!
//! * Single scattering (pbrt-v4's `DielectricBxDF`/`ConductorBxDF`): one microfacet event, the
//!   height-correlated Smith term; energy that would need a second event is lost.
//! * Multiple scattering (Heitz, Hanika, d'Eon & Dachsbacher 2016, "Multiple-Scattering
//!   Microfacet BSDFs with the Smith Model"): a random walk on the microsurface (uniform height
//!   distribution, GGX slopes) until the ray leaves it. Sampling is analog (every sample carries
//!   weight 1 for a dielectric: reflection and transmission together conserve energy); the BSDF
//!   value is estimated by next-event estimation at each vertex of such a walk.
//!
//! Visible normals are sampled by spherical caps (Dupuy & Benyoub 2023, "Sampling Visible GGX
//! Normals with Spherical Caps"), which is valid for directions on both hemispheres, as the walk
//! needs. This file shares no code with `glazec::math`: it is the independent side of every
//! accuracy measurement.

use std::f64::consts::PI;

use glam::DVec3;

use super::gtr1;
use super::rng::Rng;

/// Directions this close to the pole are treated as exactly normal (Λ = 0).
const POLE: f64 = 0.999_999;

/// The normal distribution of a dielectric microsurface: GGX (the free functions of this file)
/// or GTR1 ([`super::gtr1`]). The walk only asks it for Λ, D and visible normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ndf {
    Ggx,
    Gtr1,
}

impl Ndf {
    pub fn lambda(self, w: DVec3, alpha: f64) -> f64 {
        match self {
            Ndf::Ggx => lambda(w, alpha),
            Ndf::Gtr1 => gtr1::lambda(w, alpha),
        }
    }

    pub fn d(self, m: DVec3, alpha: f64) -> f64 {
        match self {
            Ndf::Ggx => ggx_d(m, alpha),
            Ndf::Gtr1 => gtr1::d(m, alpha),
        }
    }

    /// G1 for a direction on the upper hemisphere: 1/(1 + Λ).
    pub fn g1(self, w: DVec3, alpha: f64) -> f64 {
        if w.z <= 0.0 { 0.0 } else { 1.0 / (1.0 + self.lambda(w, alpha)) }
    }

    /// Height-correlated G2 for two directions measured on their own sides (|z| is used).
    pub fn g2(self, a: DVec3, b: DVec3, alpha: f64) -> f64 {
        let up = |w: DVec3| DVec3::new(w.x, w.y, w.z.abs());
        1.0 / (1.0 + self.lambda(up(a), alpha) + self.lambda(up(b), alpha))
    }

    /// The distribution of normals visible from `w`: max(0, w·m) D(m) / A(w).
    pub fn vndf(self, w: DVec3, m: DVec3, alpha: f64) -> f64 {
        match self {
            Ndf::Ggx => vndf(w, m, alpha),
            Ndf::Gtr1 => {
                let area = gtr1::projected_area(w, alpha);
                if area <= 0.0 { 0.0 } else { w.dot(m).max(0.0) * gtr1::d(m, alpha) / area }
            }
        }
    }

    /// Samples a normal visible from `w` (any hemisphere). GGX draws two uniforms, as
    /// [`sample_vndf`] always has, so its random streams are unchanged.
    pub fn sample_vndf(self, w: DVec3, alpha: f64, rng: &mut Rng) -> DVec3 {
        match self {
            Ndf::Ggx => sample_vndf(w, alpha, rng.uniform(), rng.uniform()),
            Ndf::Gtr1 => gtr1::sample_vndf(w, alpha, rng),
        }
    }
}

/// Smith's Λ for isotropic GGX (Heitz 2014, eq. 72), for a direction on either hemisphere:
/// (−1 + sign(a)·√(1 + 1/a²))/2 with a = cot θ / α.
pub fn lambda(w: DVec3, alpha: f64) -> f64 {
    if w.z > POLE {
        return 0.0;
    }
    if w.z < -POLE {
        return -1.0;
    }
    let sin = (1.0 - w.z * w.z).max(0.0).sqrt();
    let a = w.z / (alpha * sin);
    0.5 * (-1.0 + a.signum() * (1.0 + 1.0 / (a * a)).sqrt())
}

/// G1 for a direction on the upper hemisphere: 1/(1 + Λ).
pub fn g1(w: DVec3, alpha: f64) -> f64 {
    if w.z <= 0.0 { 0.0 } else { 1.0 / (1.0 + lambda(w, alpha)) }
}

/// Height-correlated G2 for two directions measured on their own sides (|z| is used).
pub fn g2(a: DVec3, b: DVec3, alpha: f64) -> f64 {
    let up = |w: DVec3| DVec3::new(w.x, w.y, w.z.abs());
    1.0 / (1.0 + lambda(up(a), alpha) + lambda(up(b), alpha))
}

/// The GGX normal distribution D(m) (Walter et al. 2007, eq. 33).
pub fn ggx_d(m: DVec3, alpha: f64) -> f64 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = m.z * m.z * a2 + (m.x * m.x + m.y * m.y);
    a2 / (PI * t * t)
}

/// Projected area of the microsurface towards `w` (Heitz 2014): (cos + √(cos² + α² sin²))/2.
pub fn projected_area(w: DVec3, alpha: f64) -> f64 {
    let c = w.z;
    0.5 * (c + (c * c + alpha * alpha * (1.0 - c * c)).max(0.0).sqrt())
}

/// The distribution of normals visible from `w`: max(0, w·m) D(m) / A(w).
pub fn vndf(w: DVec3, m: DVec3, alpha: f64) -> f64 {
    let area = projected_area(w, alpha);
    if area <= 0.0 { 0.0 } else { w.dot(m).max(0.0) * ggx_d(m, alpha) / area }
}

/// Samples a normal visible from `w` (any hemisphere), by spherical caps.
pub fn sample_vndf(w: DVec3, alpha: f64, u1: f64, u2: f64) -> DVec3 {
    let ws = DVec3::new(w.x * alpha, w.y * alpha, w.z).normalize();
    let phi = 2.0 * PI * u1;
    let z = (1.0 - u2) * (1.0 + ws.z) - ws.z;
    let sin = (1.0 - z * z).max(0.0).sqrt();
    let h = DVec3::new(sin * phi.cos(), sin * phi.sin(), z) + ws;
    DVec3::new(h.x * alpha, h.y * alpha, h.z).normalize()
}

/// Exact unpolarised Fresnel reflectance for cosine `c` (> 0 on the incident side) into a
/// medium of relative IOR `eta` (transmitted / incident); 1 under total internal reflection.
pub fn fresnel_dielectric(c: f64, eta: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    let s2t = (1.0 - c * c) / (eta * eta);
    if s2t >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - s2t).sqrt();
    let rs = (c - eta * ct) / (c + eta * ct);
    let rp = (eta * c - ct) / (eta * c + ct);
    0.5 * (rs * rs + rp * rp)
}

/// Exact unpolarised Fresnel reflectance of a conductor with complex IOR η + iκ (per channel).
pub fn fresnel_conductor(c: f64, eta: DVec3, k: DVec3) -> DVec3 {
    let channel = |eta: f64, k: f64| {
        // |r_s|² and |r_p|² with the complex cosine of refraction (Born & Wolf 1999).
        let c = c.clamp(0.0, 1.0);
        let s2 = 1.0 - c * c;
        let (n2r, n2i) = (eta * eta - k * k, 2.0 * eta * k); // (η + iκ)²
        // cos_t·(η+iκ) = √((η+iκ)² − sin²θ)
        let (ar, ai) = complex_sqrt(n2r - s2, n2i);
        let rs = complex_abs2(c - ar, -ai) / complex_abs2(c + ar, ai);
        // r_p = ((η+iκ)² c − a) / ((η+iκ)² c + a)
        let (pr, pi) = (n2r * c - ar, n2i * c - ai);
        let (qr, qi) = (n2r * c + ar, n2i * c + ai);
        let rp = complex_abs2(pr, pi) / complex_abs2(qr, qi);
        0.5 * (rs + rp)
    };
    DVec3::new(channel(eta.x, k.x), channel(eta.y, k.y), channel(eta.z, k.z))
}

fn complex_abs2(re: f64, im: f64) -> f64 {
    re * re + im * im
}

fn complex_sqrt(re: f64, im: f64) -> (f64, f64) {
    let r = (re * re + im * im).sqrt();
    let a = ((r + re) * 0.5).max(0.0).sqrt();
    let b = ((r - re) * 0.5).max(0.0).sqrt();
    (a, if im < 0.0 { -b } else { b })
}

/// Reflection of `w` about `m` (both pointing away from the surface).
pub fn reflect(w: DVec3, m: DVec3) -> DVec3 {
    2.0 * w.dot(m) * m - w
}

/// Refraction of `w` (pointing away, on the side `m` points to) through a facet with normal `m`
/// into relative IOR `eta`; `None` on total internal reflection.
pub fn refract(w: DVec3, m: DVec3, eta: f64) -> Option<DVec3> {
    let c = w.dot(m);
    let s2t = (1.0 - c * c) / (eta * eta);
    if s2t >= 1.0 {
        return None;
    }
    let ct = (1.0 - s2t).sqrt();
    Some((m * (c / eta - ct) - w / eta).normalize())
}

/// Uniform heights in [−1, 1]: CDF and its inverse (the results do not depend on the choice;
/// Heitz et al. 2016, §3.1).
fn height_cdf(h: f64) -> f64 {
    (0.5 * (h + 1.0)).clamp(0.0, 1.0)
}

fn height_inv_cdf(u: f64) -> f64 {
    (2.0 * u - 1.0).clamp(-1.0, 1.0)
}

/// Masking at height `h` towards `w` (upper hemisphere): C1(h)^Λ(w).
fn g1_at(w: DVec3, h: f64, ndf: Ndf, alpha: f64) -> f64 {
    if w.z > POLE {
        return 1.0;
    }
    if w.z <= 0.0 {
        return 0.0;
    }
    height_cdf(h).powf(ndf.lambda(w, alpha))
}

/// The next height along a ray travelling in direction `w` from height `h` on the upper side,
/// or `None` if the ray leaves the microsurface.
fn next_height(w: DVec3, h: f64, ndf: Ndf, alpha: f64, u: f64) -> Option<f64> {
    if w.z > POLE {
        return None;
    }
    if w.z < -POLE {
        return Some(height_inv_cdf(u * height_cdf(h)));
    }
    if w.z.abs() < 1e-6 {
        return Some(h);
    }
    let g = g1_at(w, h, ndf, alpha);
    if u > 1.0 - g {
        return None;
    }
    Some(height_inv_cdf(height_cdf(h) / (1.0 - u).powf(1.0 / ndf.lambda(w, alpha))))
}

/// A microsurface side: above (`outside`) or below the mean plane. The surface seen from below
/// is the mirrored surface with the inverse IOR, so every local computation is done "from
/// above" in a frame flipped when inside.
fn flip(w: DVec3) -> DVec3 {
    DVec3::new(w.x, w.y, -w.z)
}

/// A rough dielectric interface with relative IOR `eta` (below / above).
#[derive(Clone, Copy, Debug)]
pub struct RoughDielectric {
    pub eta: f64,
    pub alpha: f64,
    pub ndf: Ndf,
}

impl RoughDielectric {
    /// A GGX interface, what every rough dielectric is but a `Gtr1` coat.
    pub fn ggx(eta: f64, alpha: f64) -> Self {
        RoughDielectric { eta, alpha, ndf: Ndf::Ggx }
    }

    /// The local phase function of a microfacet event (energy form: reflection + transmission
    /// integrate to 1), for `wi` and `wo` pointing away from the event, `wi` on the upper side
    /// of a surface of relative IOR `eta`.
    fn phase(wi: DVec3, wo: DVec3, eta: f64, ndf: Ndf, alpha: f64) -> f64 {
        if wo.z > 0.0 {
            let wh = (wi + wo).normalize();
            let c = wi.dot(wh);
            if c <= 0.0 {
                return 0.0;
            }
            0.25 * ndf.vndf(wi, wh, alpha) / c * fresnel_dielectric(c, eta)
        } else {
            let mut wh = -(wi + wo * eta).normalize();
            if wh.z < 0.0 {
                wh = -wh;
            }
            let (ci, co) = (wi.dot(wh), wo.dot(wh));
            if ci <= 0.0 || co >= 0.0 {
                return 0.0;
            }
            let denom = ci + eta * co;
            eta * eta * (1.0 - fresnel_dielectric(ci, eta)) * ndf.vndf(wi, wh, alpha) * (-co) / (denom * denom)
        }
    }

    /// Samples the local phase function from `wi` (upper side): returns the new direction
    /// (pointing away) and whether it crossed to the other side.
    fn sample_phase(wi: DVec3, eta: f64, ndf: Ndf, alpha: f64, rng: &mut Rng) -> (DVec3, bool) {
        let m = ndf.sample_vndf(wi, alpha, rng);
        let f = fresnel_dielectric(wi.dot(m), eta);
        if rng.uniform() < f {
            (reflect(wi, m), false)
        } else {
            match refract(wi, m, eta) {
                Some(t) => (t, true),
                None => (reflect(wi, m), false),
            }
        }
    }

    /// One analog random walk from `wi` (pointing away from the surface, on either side):
    /// the direction it leaves in (pointing away). Weight 1: the walk conserves energy.
    pub fn sample_multiple(&self, wi: DVec3, rng: &mut Rng) -> DVec3 {
        self.walk(wi, rng).0
    }

    /// [`Self::sample_multiple`], also returning the number of microfacet events of the walk.
    pub fn walk(&self, wi: DVec3, rng: &mut Rng) -> (DVec3, u32) {
        let mut outside = wi.z > 0.0;
        // The ray arrives travelling along −wi.
        let mut wr = -wi;
        let mut h = if outside { 1.0 + height_inv_cdf(0.999) } else { -1.0 - height_inv_cdf(0.999) };
        for events in 0..MAX_MICROSURFACE_BOUNCES {
            let (w_local, h_local) = if outside { (wr, h) } else { (flip(wr), -h) };
            match next_height(w_local, h_local, self.ndf, self.alpha, rng.uniform()) {
                // The ray leaves the microsurface travelling along `wr`.
                None => return (wr, events),
                Some(hn) => h = if outside { hn } else { -hn },
            }
            let eta = if outside { self.eta } else { 1.0 / self.eta };
            let incoming = if outside { -wr } else { flip(-wr) };
            let (out, crossed) = Self::sample_phase(incoming, eta, self.ndf, self.alpha, rng);
            let out = if outside { out } else { flip(out) };
            if crossed {
                outside = !outside;
            }
            // The ray now travels along the direction it left the event in.
            wr = out;
        }
        // A walk this long is vanishingly rare; end it where it is.
        (wr, MAX_MICROSURFACE_BOUNCES)
    }

    /// Estimate of f(wi, wo)·|cos θo| (energy form) by next-event estimation along one walk.
    pub fn eval_multiple(&self, wi: DVec3, wo: DVec3, rng: &mut Rng) -> f64 {
        let (first, later) = self.eval_by_event(wi, wo, rng);
        first + later
    }

    /// The mean over `walks` walks from `wi` of [`Self::eval_multiple`]'s two parts: what the
    /// first microfacet event sends towards `wo` (single scattering) and what the later ones do.
    pub fn first_and_later_events(&self, wi: DVec3, wo: DVec3, walks: u32, seed: u64) -> (f64, f64) {
        let mut rng = Rng::seeded(seed);
        let (mut first, mut later) = (0.0, 0.0);
        for _ in 0..walks {
            let (a, b) = self.eval_by_event(wi, wo, &mut rng);
            first += a;
            later += b;
        }
        (first / f64::from(walks), later / f64::from(walks))
    }

    /// One walk's next-event estimate of f(wi, wo)·|cos θo|, split into the first event's and the
    /// later events' contributions.
    fn eval_by_event(&self, wi: DVec3, wo: DVec3, rng: &mut Rng) -> (f64, f64) {
        let mut outside = wi.z > 0.0;
        let wo_outside = wo.z > 0.0;
        let mut wr = -wi;
        let mut h = if outside { 1.0 + height_inv_cdf(0.999) } else { -1.0 - height_inv_cdf(0.999) };
        let (mut first, mut later) = (0.0, 0.0);
        for event in 0..MAX_MICROSURFACE_BOUNCES {
            let (w_local, h_local) = if outside { (wr, h) } else { (flip(wr), -h) };
            match next_height(w_local, h_local, self.ndf, self.alpha, rng.uniform()) {
                None => break,
                Some(hn) => h = if outside { hn } else { -hn },
            }
            let eta = if outside { self.eta } else { 1.0 / self.eta };
            // Next-event estimation towards wo from this vertex.
            let incoming = if outside { -wr } else { flip(-wr) };
            let towards = if outside { wo } else { flip(wo) };
            let phase = Self::phase(incoming, towards, eta, self.ndf, self.alpha);
            let shadowing =
                if wo_outside { g1_at(wo, h, self.ndf, self.alpha) } else { g1_at(flip(wo), -h, self.ndf, self.alpha) };
            let value = phase * shadowing;
            if value.is_finite() {
                if event == 0 {
                    first += value;
                } else {
                    later += value;
                }
            }
            let (out, crossed) = Self::sample_phase(incoming, eta, self.ndf, self.alpha, rng);
            let out = if outside { out } else { flip(out) };
            if crossed {
                outside = !outside;
            }
            wr = out;
        }
        (first, later)
    }
}

/// Longest walk on a microsurface; the probability of reaching it is negligible for α ≤ 1.
const MAX_MICROSURFACE_BOUNCES: u32 = 256;

/// Conductor microsurface walk (Heitz et al. 2016) with a coloured Fresnel factor per event.
#[derive(Clone, Copy, Debug)]
pub struct RoughConductor {
    pub alpha: f64,
}

impl RoughConductor {
    /// One analog walk from `wi` (upper side): the leaving direction and the product of the
    /// Fresnel factors of its events.
    pub fn sample_multiple(&self, wi: DVec3, fresnel: &dyn Fn(f64) -> DVec3, rng: &mut Rng) -> (DVec3, DVec3) {
        let mut wr = -wi;
        let mut h = 1.0 + height_inv_cdf(0.999);
        let mut weight = DVec3::ONE;
        for _ in 0..MAX_MICROSURFACE_BOUNCES {
            match next_height(wr, h, Ndf::Ggx, self.alpha, rng.uniform()) {
                None => return (wr, weight),
                Some(hn) => h = hn,
            }
            let incoming = -wr;
            let m = sample_vndf(incoming, self.alpha, rng.uniform(), rng.uniform());
            weight *= fresnel(incoming.dot(m));
            wr = reflect(incoming, m);
        }
        (wr, weight)
    }

    /// Estimate of f(wi, wo)·cos θo by next-event estimation along one walk.
    pub fn eval_multiple(&self, wi: DVec3, wo: DVec3, fresnel: &dyn Fn(f64) -> DVec3, rng: &mut Rng) -> DVec3 {
        if wo.z <= 0.0 {
            return DVec3::ZERO;
        }
        let mut wr = -wi;
        let mut h = 1.0 + height_inv_cdf(0.999);
        let mut weight = DVec3::ONE;
        let mut sum = DVec3::ZERO;
        for _ in 0..MAX_MICROSURFACE_BOUNCES {
            match next_height(wr, h, Ndf::Ggx, self.alpha, rng.uniform()) {
                None => break,
                Some(hn) => h = hn,
            }
            let incoming = -wr;
            let wh = (incoming + wo).normalize();
            let c = incoming.dot(wh);
            if wh.z > 0.0 && c > 0.0 {
                let phase = 0.25 * vndf(incoming, wh, self.alpha) / c;
                let value = weight * fresnel(c) * (phase * g1_at(wo, h, Ndf::Ggx, self.alpha));
                if value.is_finite() {
                    sum += value;
                }
            }
            let m = sample_vndf(incoming, self.alpha, rng.uniform(), rng.uniform());
            weight *= fresnel(incoming.dot(m));
            wr = reflect(incoming, m);
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples per statistical check, and the tolerance in standard errors.
    const SAMPLES: usize = 200_000;
    const SIGMAS: f64 = 4.0;

    use glazec::math::sampling::direction as dir;

    #[test]
    fn visible_normals_have_the_right_distribution() {
        // E[m.z / (w·m)] over the VNDF of w is ∫_{w·m>0} m.z D(m) dm / A(w). In slope space,
        // with tan θm = α tan ψ, the numerator is ∫∫ [w·m > 0] sin ψ cos ψ / π dψ dφ.
        let mut rng = Rng::seeded(7);
        for (alpha, theta) in [(0.3, 0.4), (0.8, 1.2), (0.5, 1.9), (0.2, 2.6)] {
            let w = dir(theta, 0.3);
            let cells = 3000;
            let mut numerator = 0.0;
            for i in 0..cells {
                let psi = (i as f64 + 0.5) / cells as f64 * PI / 2.0;
                for j in 0..cells {
                    let phi = (j as f64 + 0.5) / cells as f64 * 2.0 * PI;
                    let m = DVec3::new(-alpha * psi.tan() * phi.cos(), -alpha * psi.tan() * phi.sin(), 1.0).normalize();
                    if w.dot(m) > 0.0 {
                        numerator += psi.sin() * psi.cos() / PI;
                    }
                }
            }
            numerator *= (PI / 2.0 / cells as f64) * (2.0 * PI / cells as f64);
            let expected = numerator / projected_area(w, alpha);
            let values: Vec<f64> = (0..SAMPLES)
                .map(|_| {
                    let m = sample_vndf(w, alpha, rng.uniform(), rng.uniform());
                    assert!(m.z >= 0.0 && w.dot(m) >= -1e-12);
                    m.z / w.dot(m).max(1e-300)
                })
                .collect();
            let mean = values.iter().sum::<f64>() / SAMPLES as f64;
            let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / SAMPLES as f64;
            let err = (var / SAMPLES as f64).sqrt();
            // The quadrature of an indicator converges as 1/cells.
            let quadrature = expected * 2.0 / cells as f64;
            assert!(
                (mean - expected).abs() < SIGMAS * err + quadrature,
                "alpha {alpha} theta {theta}: {mean} vs {expected} ± {err}"
            );
        }
    }

    #[test]
    fn fresnel_limits() {
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-12);
        let k0 = fresnel_conductor(0.6, DVec3::splat(1.5), DVec3::ZERO);
        assert!((k0.x - fresnel_dielectric(0.6, 1.5)).abs() < 1e-12);
        let n = fresnel_conductor(1.0, DVec3::splat(0.2), DVec3::splat(3.9));
        assert!((n.x - (0.64 + 15.21) / (1.44 + 15.21)).abs() < 1e-12);
    }

    #[test]
    fn multiple_scattering_walk_matches_its_own_evaluation() {
        // The share of walks leaving on the upper side (reflectance) equals the integral of the
        // evaluated reflection over the hemisphere (checked by uniform hemisphere sampling).
        // Both distributions: GTR1's own Λ, D and visible normals must agree with each other
        // as GGX's do.
        for (ndf, alpha, theta) in [(Ndf::Ggx, 0.6, 0.7), (Ndf::Gtr1, 0.3, 0.7), (Ndf::Gtr1, 0.05, 1.35)] {
            let interface = RoughDielectric { eta: 1.5, alpha, ndf };
            let wi = dir(theta, 0.0);
            let mut rng = Rng::seeded(11);
            let reflected = (0..SAMPLES).filter(|_| interface.sample_multiple(wi, &mut rng).z > 0.0).count() as f64
                / SAMPLES as f64;
            let mut values = Vec::with_capacity(SAMPLES);
            for _ in 0..SAMPLES {
                let (u, v) = (rng.uniform(), rng.uniform());
                let wo = dir(u.acos(), 2.0 * PI * v); // uniform on the hemisphere, pdf 1/(2π)
                values.push(interface.eval_multiple(wi, wo, &mut rng) * 2.0 * PI);
            }
            let mean = values.iter().sum::<f64>() / SAMPLES as f64;
            let var = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / SAMPLES as f64;
            let err = (var / SAMPLES as f64).sqrt() + (reflected * (1.0 - reflected) / SAMPLES as f64).sqrt();
            assert!(
                (mean - reflected).abs() < SIGMAS * err,
                "{ndf:?} α {alpha}: eval {mean} vs sampled {reflected} ± {err}"
            );
        }
    }
}
