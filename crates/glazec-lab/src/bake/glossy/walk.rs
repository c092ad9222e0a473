//! White random walks through a coat over a conductor (the reference's microsurfaces): how many
//! conductor events light takes to leave, how the coat widens the conductor's lobe, and the
//! path lengths of light that leaves after one reflection.

use super::nodes::{SCALE_ITERATIONS, SMOOTH_ALPHA, direction_nodes};
use crate::reference::microsurface::{RoughConductor, RoughDielectric};
use crate::reference::{Rng, fresnel_dielectric};
use glam::DVec3;
use glazec::math::layering::GLOSSY_GRAZING;
use glazec::math::sampling::direction_at_cosine;
use glazec::math::tables::{Axis, GLOSSY_PATH_GRID, TableId};

/// What white walks from one direction show.
#[derive(Clone, Debug, Default)]
pub struct EventCounts {
    /// Walks that entered the coat.
    pub entered: u64,
    /// `events[k]`: walks that entered and left after k + 1 conductor events (the last bin
    /// holds the walks cut at `EVENT_CAP`).
    pub events: Vec<u64>,
    /// Σ and count of the incidence cosines of conductor events after the first.
    pub pool_cosine_sum: f64,
    pub pool_events: u64,
    /// Over the walks that left after three or more conductor events (the level's remainder:
    /// the first two events are its lobe): Σ cos φf, φf their azimuth about the forward
    /// direction (where a mirror sends the light on), and Σ sin θᵢ sin θₒ.
    pub forward_cosine_sum: f64,
    pub forward_weight: f64,
    /// The same two sums split by the walk's event count (index k: k + 1 events), for research
    /// into how the spread depends on the count (`examples/glossy_colour_spread.rs`).
    pub forward_by_events: Vec<(f64, f64)>,
    /// The same two sums over the walks that left at the second event, split by where their
    /// first return went: inside the escape cone (the coat's Fresnel reflection sent them back,
    /// about the mirror direction) or beyond it (total internal reflection); and the count of
    /// the first.
    pub second_inside: (f64, f64),
    pub second_beyond: (f64, f64),
    pub second_inside_walks: u64,
}

impl EventCounts {
    /// The share of entering light leaving after exactly k + 1 events.
    pub fn share(&self, k: usize) -> f64 {
        self.events.get(k).map_or(0.0, |&n| n as f64 / self.entered.max(1) as f64)
    }

    /// κ of the remainder's azimuth about the forward direction, E[cos φf] = κ sin θᵢ sin θₒ (the
    /// wrapped Cauchy distribution's ρ is its mean resultant length E[cos φf]), by the moments:
    /// Σ cos φf / Σ sin θᵢ sin θₒ over the light the remainder holds; `None` without any
    /// remainder that has an azimuth. The remainder holds every walk that left after three or
    /// more events and, of those that left at the second, all but the share `next` of the trapped
    /// light that the level's lobe takes (w₀). That share is taken from the walks whose first
    /// return the coat's Fresnel reflection sent back inside the escape cone, which leave about
    /// the mirror direction like the lobe (for coats of roughness ≤ 0.2 they leave w₀ within
    /// 0.03 of the fitted weight at 40°–85°; `examples/second_return.rs`); what total internal
    /// reflection returned leaves anywhere in the cone, and further forward than the later
    /// events (κ 1.02–1.35 against 0.75–0.99 for a conductor of roughness 0.25–0.3 under η 1.5
    /// coats of roughness ≤ 0.2 at 40°–85°). Counted from three events only, the remainder's
    /// spread put too much of it to the side and behind.
    pub(super) fn forward_spread(&self, next: f64) -> Option<f64> {
        let trapped = self.entered as f64 * (1.0 - self.share(0));
        let inside = self.second_inside_walks as f64;
        let kept = if inside > 0.0 { (1.0 - next * trapped / inside).clamp(0.0, 1.0) } else { 0.0 };
        let cosines = self.forward_cosine_sum + self.second_beyond.0 + kept * self.second_inside.0;
        let weight = self.forward_weight + self.second_beyond.1 + kept * self.second_inside.1;
        (weight > 0.0).then(|| (cosines / weight).max(0.0))
    }

    /// Σ_{k ≥ 2} P_k c^(k−1): the trapped light's generating function, exactly.
    pub(super) fn trapped(&self, c: f64) -> f64 {
        let mut total = 0.0;
        let mut power = c;
        for k in 1..self.events.len() {
            total += self.share(k) * power;
            power *= c;
        }
        total
    }
}

/// Samples a coat interface of relative IOR `eta` (below / above) and GGX α from direction `w`
/// (pointing away from it, on either side): the new direction and whether it crossed. The
/// reference's interface in its `multiple` mode (exact Fresnel when smooth).
pub(super) fn coat_sample(eta: f64, alpha: f64, w: DVec3, rng: &mut Rng) -> (DVec3, bool) {
    let below = w.z < 0.0;
    let (w_up, eta) = if below { (DVec3::new(w.x, w.y, -w.z), 1.0 / eta) } else { (w, eta) };
    let out = if alpha < SMOOTH_ALPHA {
        if rng.uniform() < fresnel_dielectric(w_up.z, eta) {
            DVec3::new(-w_up.x, -w_up.y, w_up.z)
        } else {
            let sin2 = (1.0 - w_up.z * w_up.z) / (eta * eta);
            DVec3::new(-w_up.x / eta, -w_up.y / eta, -(1.0 - sin2).max(0.0).sqrt()).normalize()
        }
    } else {
        RoughDielectric::ggx(eta, alpha).sample_multiple(w_up, rng)
    };
    let crossed = out.z < 0.0;
    (if below { DVec3::new(out.x, out.y, -out.z) } else { out }, crossed)
}

/// The conductor reflecting a ray that arrives from `w` (pointing away from it, above it): the
/// direction it leaves in. White (every event keeps all the light); a mirror below SMOOTH_ALPHA.
pub(super) fn conductor_sample(alpha: f64, w: DVec3, rng: &mut Rng) -> DVec3 {
    if alpha < SMOOTH_ALPHA {
        return DVec3::new(-w.x, -w.y, w.z);
    }
    RoughConductor { alpha }.sample_multiple(w, &|_| DVec3::ONE, rng).0
}

/// One white walk through the coat over the conductor ([`walk`]).
pub(super) struct Walk {
    /// The cosines of its slab crossings and of its conductor events, in order.
    pub(super) crossings: Vec<f64>,
    pub(super) events: Vec<f64>,
    /// The direction it left the coat in (above it); `None` for a walk cut at `EVENT_CAP`.
    pub(super) exit: Option<DVec3>,
}

/// One white walk from `wo` (above the coat) into a slab of thickness 1 over the conductor:
/// `None` if the coat reflects it at once, else its crossings and conductor events until it
/// leaves or is cut.
pub(super) fn walk(eta: f64, alpha: f64, alpha_c: f64, wo: DVec3, rng: &mut Rng) -> Option<Walk> {
    let (mut w, crossed) = coat_sample(eta, alpha, wo, rng);
    if !crossed {
        return None;
    }
    let (mut crossings, mut events) = (Vec::new(), Vec::new());
    loop {
        crossings.push(w.z.abs());
        if w.z < 0.0 {
            events.push(-w.z);
            let up = conductor_sample(alpha_c, -w, rng);
            if up.z <= 0.0 || events.len() >= EVENT_CAP {
                // (A conductor walk never leaves below; a cut walk counts as leaving now.)
                return Some(Walk { crossings, events, exit: None });
            }
            w = up;
        } else {
            let (next, crossed) = coat_sample(eta, alpha, -w, rng);
            if crossed {
                return Some(Walk { crossings, events, exit: Some(next) });
            }
            w = next;
        }
    }
}

/// (cos φf, sin θᵢ sin θₒ) of light that arrived from `wo` and left along `exit`: φf the
/// azimuth of `exit` about the forward direction (the one a mirror sends the light on to, the
/// tangential component reversed); cos φf = 0 for a direction along the normal.
fn forward_cosine(wo: DVec3, exit: DVec3) -> (f64, f64) {
    let (a, b) = (DVec3::new(wo.x, wo.y, 0.0), DVec3::new(exit.x, exit.y, 0.0));
    let lengths = (a.length_squared() * b.length_squared()).sqrt();
    (if lengths < 1e-12 { 0.0 } else { -a.dot(b) / lengths }, lengths)
}

/// The cosine of the coat's escape cone inside it, √(1 − 1/η²) (0 without total internal
/// reflection, η ≤ 1).
pub fn escape_cone_cosine(eta: f64) -> f64 {
    (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt()
}

/// Event counts of `walks` white walks from outside cosine `mu`.
pub fn event_counts(mu: f64, r_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> EventCounts {
    let mut rng = Rng::seeded(seed);
    let wo = direction_at_cosine(mu.max(GLOSSY_GRAZING));
    let cone = escape_cone_cosine(eta);
    let mut counts = EventCounts {
        events: vec![0; EVENT_CAP],
        forward_by_events: vec![(0.0, 0.0); EVENT_CAP],
        ..Default::default()
    };
    for _ in 0..walks {
        let Some(Walk { crossings, events, exit }) = walk(eta, r * r, r_c * r_c, wo, &mut rng) else { continue };
        counts.entered += 1;
        counts.events[events.len().clamp(1, EVENT_CAP) - 1] += 1;
        for &cosine in events.iter().skip(1) {
            counts.pool_cosine_sum += cosine;
            counts.pool_events += 1;
        }
        let Some(exit) = exit else { continue };
        let (cosine, weight) = forward_cosine(wo, exit);
        if events.len() == 2 {
            if crossings.get(1).is_some_and(|&up| up > cone) {
                counts.second_inside.0 += cosine;
                counts.second_inside.1 += weight;
                counts.second_inside_walks += 1;
            } else {
                counts.second_beyond.0 += cosine;
                counts.second_beyond.1 += weight;
            }
        } else if events.len() >= 3 {
            counts.forward_cosine_sum += cosine;
            counts.forward_weight += weight;
            let by = &mut counts.forward_by_events[events.len().clamp(1, EVENT_CAP) - 1];
            by.0 += cosine;
            by.1 += weight;
        }
    }
    counts
}

/// Of `walks` white walks from outside cosine `mu`, those that entered the coat; and the
/// direction they came from.
fn walks_that_entered(mu: f64, r_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> (DVec3, Vec<Walk>) {
    let mut rng = Rng::seeded(seed);
    let wo = direction_at_cosine(mu.max(GLOSSY_GRAZING));
    (wo, (0..walks).filter_map(|_| walk(eta, r * r, r_c * r_c, wo, &mut rng)).collect())
}

/// The `walks` white walks from outside cosine `mu` that left the coat (not cut at
/// `EVENT_CAP`): per walk, its conductor events' incidence cosines and the direction it left in;
/// and the direction they came from.
fn walks_that_left(mu: f64, r_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> (DVec3, Vec<(Vec<f64>, DVec3)>) {
    let (wo, entered) = walks_that_entered(mu, r_c, r, eta, walks, seed);
    (wo, entered.into_iter().filter_map(|w| Some((w.events, w.exit?))).collect())
}

/// Where `walks` white walks from outside cosine `mu` leave the coat: per walk that left, the
/// exit's cosine, its azimuth φf about the forward direction (radians) and its count of
/// conductor events; for research into the remainder's shape (`examples/glossy_azimuth_shape.rs`).
pub fn walk_exits(mu: f64, r_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> Vec<(f64, f64, usize)> {
    let (wo, left) = walks_that_left(mu, r_c, r, eta, walks, seed);
    left.into_iter()
        .map(|(events, exit)| {
            let (cosine, _) = forward_cosine(wo, exit);
            (exit.z, cosine.clamp(-1.0, 1.0).acos(), events.len())
        })
        .collect()
}

/// The conductor events of `walks` white walks from outside cosine `mu`: per walk that left, the
/// incidence cosine of each of its events, in order; for research into the trapped light's colour
/// (`examples/glossy_pool_colour.rs`).
pub fn walk_events(mu: f64, r_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> Vec<Vec<f64>> {
    walks_that_left(mu, r_c, r, eta, walks, seed).1.into_iter().map(|(events, _)| events).collect()
}

/// How one white walk that entered the coat left ([`walk_returns`]).
#[derive(Clone, Copy, Debug)]
pub struct WalkReturn {
    /// The cosine of its first upward direction (after the first conductor event).
    pub first_return: f64,
    /// Its count of conductor events (`EVENT_CAP` for a cut walk).
    pub events: usize,
    /// For a walk that left: cos φf and sin θᵢ sin θₒ of its exit about the forward direction.
    pub forward: Option<(f64, f64)>,
}

/// How `walks` white walks from outside cosine `mu` leave, per walk that entered the coat; for
/// research into where the light that leaves at the second event came from (the coat's Fresnel
/// reflection inside the escape cone, or total internal reflection beyond it;
/// `examples/second_return.rs`).
pub fn walk_returns(mu: f64, r_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> Vec<WalkReturn> {
    let (wo, entered) = walks_that_entered(mu, r_c, r, eta, walks, seed);
    entered
        .into_iter()
        .map(|w| WalkReturn {
            first_return: w.crossings.get(1).copied().unwrap_or(1.0),
            events: w.events.len(),
            forward: w.exit.map(|e| forward_cosine(wo, e)),
        })
        .collect()
}

/// The peak-matched widening of a conductor lobe (α = `alpha_c`) seen through the coat from
/// outside cosine `mu`: light refracted into u instead of Snell's direction s′ moves the half
/// vector between u and the mirror image of s′ off the normal by the slope t; the conductor's
/// distribution seen through the coat peaks at E[D(t)] = E[α²/(π(α² + |t|²)²)], which a GGX
/// lobe of α₁² = α² + σ² has: σ² = 1/E[α²/(α² + |t|²)²] − α².
pub fn peak_blur(mu: f64, alpha_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> f64 {
    let alpha = r * r;
    if eta == 1.0 {
        return 0.0;
    }
    let a2 = alpha_c.max(PEAK_ALPHA_MIN).powi(2);
    let wo = direction_at_cosine(mu.max(GLOSSY_GRAZING));
    // Snell's direction of the refracted ray, reversed to point up (away from the conductor),
    // and its mirror image: the conductor's lobe peaks at the half vector between u and it.
    let snell = DVec3::new(wo.x / eta, 0.0, (1.0 - wo.x * wo.x / (eta * eta)).max(0.0).sqrt());
    let mirror = DVec3::new(-snell.x, -snell.y, snell.z);
    let mut rng = Rng::seeded(seed);
    let (mut sum, mut count) = (0.0, 0u64);
    for _ in 0..walks {
        let (w, crossed) = coat_sample(eta, alpha, wo, &mut rng);
        if !crossed {
            continue;
        }
        let h = (-w + mirror).normalize();
        if h.z <= 1e-9 {
            count += 1;
            continue;
        }
        let t2 = (h.x * h.x + h.y * h.y) / (h.z * h.z);
        sum += a2 / (a2 + t2).powi(2);
        count += 1;
    }
    if sum <= 0.0 {
        return 0.0;
    }
    (count as f64 / sum - a2).max(0.0).sqrt()
}

/// The taper of the blur towards grazing (see [`GLOSSY_TAPER_POWER`]).
pub(super) fn taper(mu: f64) -> f64 {
    1.0 - (1.0 - mu.clamp(0.0, 1.0)).powf(GLOSSY_TAPER_POWER)
}

/// The path lengths L (over the slab's thickness, both crossings) of the light entering at `mu`
/// that leaves after one reflection off a mirror under the coat.
pub(super) fn mirror_path_lengths(mu: f64, r: f64, eta: f64, walks: u32, seed: u64) -> Vec<f64> {
    let mut rng = Rng::seeded(seed);
    (0..walks)
        .filter_map(|_| {
            let Walk { crossings, events, .. } = walk(eta, r * r, 0.0, direction_at_cosine(mu), &mut rng)?;
            (events.len() == 1).then(|| crossings.iter().map(|c| 1.0 / c.max(1e-6)).sum())
        })
        .collect()
}

/// E[e^(−τL)] over path lengths, summed without underflow: e^(−τ L_min) E[e^(−τ(L − L_min))].
pub(super) fn mean_attenuation(lengths: &[f64], tau: f64) -> f64 {
    if lengths.is_empty() {
        return 1.0;
    }
    let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    let mean = lengths.iter().map(|l| (-tau * (l - shortest)).exp()).sum::<f64>() / lengths.len() as f64;
    (-tau * shortest).exp() * mean
}

/// The optical depths at which the path factors are solved, one per depth node: the first
/// (τ = 0, where any factor attenuates nothing) stands for small depths, the last (τ = ∞) for
/// τ = 20, where e^(−τL) keeps only the shortest paths.
pub(super) fn path_depths() -> Vec<f64> {
    let n_tau = GLOSSY_PATH_GRID[1].1;
    (0..n_tau)
        .map(|i| match Axis::Depth.node(i, n_tau) {
            0.0 => 0.05,
            tau if tau.is_finite() => tau,
            _ => 20.0,
        })
        .collect()
}

/// The path factors q(μ, τ) of one (r, η) node of `GLOSSY_PATH_GRID` (μ fastest): solved so that
/// the method's one-event lobe over a mirror (the compiled lobe at r_c = 0 with its scale),
/// attenuated by e^(−τ q/μ_eff) on each side, keeps of its white albedo what the walks' one-event
/// light keeps, E[e^(−τL)]: the symmetric iteration of the scale's, on the attenuation. Solving
/// rather than setting e^(−2τq/μ_eff) = E[e^(−τL)] matters under rough coats, where the lobe spreads
/// over directions whose attenuation differs (set directly, the albedo at 85° comes out 10% high).
pub(super) fn path_column(r: f64, eta: f64, walks: u32, seed: u64) -> Vec<f64> {
    let mus = direction_nodes(&GLOSSY_PATH_GRID);
    let depths = path_depths();
    let (n_mu, n_tau) = (mus.len(), depths.len());
    if r * r < SMOOTH_ALPHA || eta == 1.0 {
        return vec![1.0; n_mu * n_tau];
    }
    let lengths: Vec<Vec<f64>> =
        mus.iter().enumerate().map(|(i, &mu)| mirror_path_lengths(mu, r, eta, walks, seed << 8 | i as u64)).collect();
    // The cosine the method's lobe is attenuated along: Snell's, shortened by the coat's mean
    // path factor (`coat_path`, what its `path_cosine` reads).
    let path_cosine = |mu: f64| {
        let snell = (1.0 - (1.0 - mu * mu) / (eta * eta)).max(0.0).sqrt().max(1e-4);
        let mean_path = glazec::math::tables::lookup::<f32>(TableId::CoatPath, &[mu as f32, r as f32, eta as f32]);
        snell / f64::from(mean_path)
    };
    let scale = |mu: f64| {
        f64::from(glazec::math::tables::lookup::<f32>(TableId::GlossyScale, &[mu as f32, 0.0, r as f32, eta as f32]))
    };
    // The white lobe s_l s_v f at every quadrature node of every direction node.
    let columns: Vec<Vec<(f64, f64)>> = mus
        .iter()
        .map(|&mu| {
            let v = direction_at_cosine(mu);
            crate::accuracy::quadrature::albedo_nodes(v, SMOOTH_ALPHA.max(1e-2))
                .into_iter()
                .filter_map(|(l, w)| {
                    let f = glazec::math::layering::glossy_lobe_white(0.0, r, eta, l, v) * scale(l.z) * scale(v.z);
                    (f > 0.0).then_some((l.z, w * f))
                })
                .collect()
        })
        .collect();
    let at = |q: &[f64], mu: f64| -> f64 {
        let x = mu.clamp(0.0, 1.0).sqrt() * (n_mu - 1) as f64;
        let i = (x.floor() as usize).min(n_mu - 2);
        let t = x - i as f64;
        q[i] * (1.0 - t) + q[i + 1] * t
    };
    let mut factors = vec![0.0; n_mu * n_tau];
    for (t, &tau) in depths.iter().enumerate() {
        let attenuation = |q: &[f64], mu: f64| (-tau * at(q, mu) / path_cosine(mu)).exp();
        let mut q = vec![1.0; n_mu];
        for _ in 0..SCALE_ITERATIONS {
            let next: Vec<f64> = (0..n_mu)
                .map(|i| {
                    let white: f64 = columns[i].iter().map(|&(_, wf)| wf).sum();
                    let kept: f64 = columns[i].iter().map(|&(mu_l, wf)| wf * attenuation(&q, mu_l)).sum::<f64>()
                        * attenuation(&q, mus[i]);
                    let target = white * mean_attenuation(&lengths[i], tau);
                    if i == 0 || white <= 1e-12 || kept <= 1e-300 || target <= 1e-300 {
                        return q[i];
                    }
                    (q[i] - path_cosine(mus[i]) / (2.0 * tau) * (target / kept).ln()).max(0.0)
                })
                .collect();
            q = next;
            q[0] = q[1];
        }
        for (i, &value) in q.iter().enumerate() {
            factors[i + n_mu * t] = value;
        }
    }
    factors
}

/// Conductor events after which a walk is ended and counted as leaving then: a light path this
/// long keeps c^EVENT_CAP ≤ 0.99^600 = 0.2% of itself for any conductor that is not white, and a
/// white conductor returns all of it whenever it leaves.
pub(super) const EVENT_CAP: usize = 600;

/// The coat roughness below which the blur's ratio to the coat's α is measured at this roughness
/// instead (the widening of a nearly smooth coat is lost in the walks' noise).
pub(super) const BLUR_ROUGHNESS_MIN: f64 = 0.16;

/// The smallest conductor α the peak matching uses (a mirror has no peak to match).
pub(super) const PEAK_ALPHA_MIN: f64 = 0.01;

/// The blur is tapered towards grazing by 1 − (1 − μ)^GLOSSY_TAPER_POWER: the peak-matched width
/// grows towards grazing (the coat's refraction Jacobian does), but the reference's
/// single-event lobes there are much narrower in azimuth than an isotropic widening makes them.
/// Fitted once against reference single-event lobes (conductor α 0.09 under coats of roughness
/// 0.2 and 0.5, η 1.33, 1.5, 2): the best per-direction widths, divided by the peak-matched ones,
/// follow this curve within 0.05 from 5° to 65°.
pub const GLOSSY_TAPER_POWER: f64 = 1.6;
