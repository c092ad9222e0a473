//! `glazec tables`, the glossy level: what light does under a coat over a conductor.
//!
//! Light that a conductor reflects under a coat either leaves through the coat's escape cone at
//! once or is sent back down (by total internal reflection, or by the coat's Fresnel
//! reflection) and meets the conductor again, many times for a smooth conductor under a smooth
//! coat. The default method (`layering`'s glossy level) splits what comes back out into the
//! light that left after exactly one conductor event, a lobe, and the rest, a separable
//! remainder whose colour depends on how many events it took. These tables hold what that needs,
//! all measured by **white** walks (the conductor's colour is applied at run time):
//!
//! * per direction μ outside the coat, conductor roughness r_c, coat roughness r and IOR η
//!   (`GLOSSY_SINGLE_GRID`, `GLOSSY_TRAPPED_GRID`): the share P₁ that leaves after one event
//!   (measured here, and stored through the lobe it sets, K below); and the rest, the trapped light,
//!   as a mixture of four geometric event counts: weights w₀…w₃ (w ≥ 0, Σw = 1) on the
//!   retentions B = 0 (it leaves at the next event), ½, 0.8 and a slow B_s. The share leaving
//!   after k events then has the generating function P₁c + (1 − P₁) c Σⱼ wⱼ γ(Bⱼ, c),
//!   γ(B, c) = c(1 − B)/(1 − Bc), for any per-event survival c. B_s is fitted per (r_c, r, η)
//!   over every direction and over c ∈ [0.3, 0.99] (the trapped light forgets where it came
//!   from, so its slowest rate does not depend on μ), the weights per direction by
//!   simplex-constrained least squares. With fixed retentions the weights are linear in the
//!   generating function, so interpolating them between nodes interpolates it (two fitted rates
//!   per node did not: they trade off against each other from node to node);
//! * μ*: the mean cosine at which the trapped light meets the conductor (where the method
//!   evaluates its Fresnel factor for the events after the first);
//! * σ: how much the coat's two crossings widen the conductor's lobe, the GGX width whose peak
//!   matches the conductor's peak seen through the coat's transmission (quadrature of the
//!   conductor's distribution over the walks' transmitted directions), tapered towards grazing,
//!   stored over the coat's α;
//! * s: the per-direction scale that makes the method's widened lobe reflect exactly
//!   T(μ)·(P₁ + (1 − P₁)w₀) of a white conductor under a clear coat (the light that leaves
//!   near the mirror direction: after one event, or at the second from the trapped light's
//!   first return). This one is defined through the compiled lobe itself (the shared math, with
//!   the tables just computed), solved over μ at each node by the symmetric Sinkhorn iteration
//!   s_i ← s_i √(target_i / achieved_i);
//! * K = (P₁ + (1 − P₁)w₀)/(s² E c): that lobe's white albedo over T, over s² and over the
//!   analytic E(μ′; α)·c(μ′) (the GGX albedo at the lobe's α, the share of the conductor's lobe
//!   inside the escape cone), which carry its steep dependence on r_c, μ and η. The method takes
//!   P₁ back from it, so the remainder gets what the lobe does not. Between nodes the two need
//!   not agree, so K is then **fitted to the energy law**: the compiled method is probed (a
//!   white conductor under a clear coat) at every cell's centre, face and edge, at grazing
//!   incidence and at IORs just above 1; K is raised on its η = 1 face for the gains near
//!   η = 1, then changed by the least amount that keeps every probe under the law and, near
//!   grazing, lets none lose more than 3·10⁻³ where it can ([`fit_lobe_albedo`]);
//! * q(μ; τ, r, η) (`GLOSSY_PATH_GRID`): the path factor of light that leaves after one reflection
//!   off a mirror under the coat: the one-event lobe attenuated by e^(−τq/μ_eff) on each side
//!   keeps what the walks' one-event light keeps of itself, E[e^(−τL)] over its path lengths L
//!   (two crossings; solved like the scale). μ_eff is the cosine along which the method absorbs
//!   the coat's transmitted light (Snell's cosine over the `coat_path` factor), so q is a
//!   correction to a path that already follows the coat's roughness and IOR, and interpolates
//!   between the coarse (r, η) nodes where q over Snell's cosine did not: copper under an η 1.33,
//!   r ½, τ ½ coat at 85° came out 0.0122 high with q over Snell's cosine, 0.0080 with this.
//!   Kept at four depths, so that Jensen's gap between E[e^(−τL)] and e^(−τE[L]) (15% at τ = ½
//!   under a coat of roughness ½) is interpolated, not ignored.
//!
//! Walks are the reference's own (Heitz et al. 2016 microsurfaces for rough interfaces and the
//! conductor, exact Fresnel for smooth interfaces), in f64 with deterministic seeds.

use glam::DVec3;
use glazec::math::sampling::direction_at_cosine;

use crate::reference::microsurface::{RoughConductor, RoughDielectric};
use crate::reference::{Rng, fresnel_dielectric};
use glazec::math::layering::GLOSSY_GRAZING;
use glazec::math::tables::{
    Axis, GLOSSY_BLUR_GRID, GLOSSY_PATH_GRID, GLOSSY_SINGLE_GRID, GLOSSY_TRAPPED_GRID, TableId,
};

/// GGX α below which an interface or conductor is smooth (the reference's threshold).
const SMOOTH_ALPHA: f64 = 1e-3;

/// Conductor events after which a walk is ended and counted as leaving then: a light path this
/// long keeps c^EVENT_CAP ≤ 0.99^600 = 0.2% of itself for any conductor that is not white, and a
/// white conductor returns all of it whenever it leaves.
const EVENT_CAP: usize = 600;

/// Per-event survivals over which the retention rates are fitted (the conductor's Fresnel factor
/// times the slab's round trip).
const FIT_SURVIVALS: [f64; 15] = [0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95, 0.99];

/// The blur is tapered towards grazing by 1 − (1 − μ)^GLOSSY_TAPER_POWER: the peak-matched width
/// grows towards grazing (the coat's refraction Jacobian does), but the reference's
/// single-event lobes there are much narrower in azimuth than an isotropic widening makes them.
/// Fitted once against reference single-event lobes (conductor α 0.09 under coats of roughness
/// 0.2 and 0.5, η 1.33, 1.5, 2): the best per-direction widths, divided by the peak-matched ones,
/// follow this curve within 0.05 from 5° to 65°.
pub const GLOSSY_TAPER_POWER: f64 = 1.6;

/// The coat roughness below which the blur's ratio to the coat's α is measured at this roughness
/// instead (the widening of a nearly smooth coat is lost in the walks' noise).
const BLUR_ROUGHNESS_MIN: f64 = 0.16;

/// The smallest conductor α the peak matching uses (a mirror has no peak to match).
const PEAK_ALPHA_MIN: f64 = 0.01;

/// What white walks from one direction show.
#[derive(Clone, Debug, Default)]
pub struct EventCounts {
    /// Walks that entered the coat.
    pub entered: u64,
    /// `events[k]`: walks that entered and left after k + 1 conductor events (the last bin
    /// holds the walks cut at [`EVENT_CAP`]).
    pub events: Vec<u64>,
    /// Σ and count of the incidence cosines of conductor events after the first.
    pub pool_cosine_sum: f64,
    pub pool_events: u64,
}

impl EventCounts {
    /// The share of entering light leaving after exactly k + 1 events.
    fn share(&self, k: usize) -> f64 {
        self.events.get(k).map_or(0.0, |&n| n as f64 / self.entered.max(1) as f64)
    }

    /// Σ_{k ≥ 2} P_k c^(k−1): the trapped light's generating function, exactly.
    fn trapped(&self, c: f64) -> f64 {
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
fn coat_sample(eta: f64, alpha: f64, w: DVec3, rng: &mut Rng) -> (DVec3, bool) {
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
        RoughDielectric { eta, alpha }.sample_multiple(w_up, rng)
    };
    let crossed = out.z < 0.0;
    (if below { DVec3::new(out.x, out.y, -out.z) } else { out }, crossed)
}

/// The conductor reflecting a ray that arrives from `w` (pointing away from it, above it): the
/// direction it leaves in. White (every event keeps all the light); a mirror below SMOOTH_ALPHA.
fn conductor_sample(alpha: f64, w: DVec3, rng: &mut Rng) -> DVec3 {
    if alpha < SMOOTH_ALPHA {
        return DVec3::new(-w.x, -w.y, w.z);
    }
    RoughConductor { alpha }.sample_multiple(w, &|_| DVec3::ONE, rng).0
}

/// One white walk from `wo` (above the coat) into a slab of thickness 1 over the conductor:
/// `None` if the coat reflects it at once, else the cosines of its slab crossings and of its
/// conductor events (in order) until it leaves or is cut.
fn walk(eta: f64, alpha: f64, alpha_c: f64, wo: DVec3, rng: &mut Rng) -> Option<(Vec<f64>, Vec<f64>)> {
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
                return Some((crossings, events));
            }
            w = up;
        } else {
            let (next, crossed) = coat_sample(eta, alpha, -w, rng);
            if crossed {
                return Some((crossings, events));
            }
            w = next;
        }
    }
}

/// Event counts of `walks` white walks from outside cosine `mu`.
pub fn event_counts(mu: f64, r_c: f64, r: f64, eta: f64, walks: u32, seed: u64) -> EventCounts {
    let mut rng = Rng::seeded(seed);
    let wo = direction_at_cosine(mu.max(GLOSSY_GRAZING));
    let mut counts = EventCounts { events: vec![0; EVENT_CAP], ..Default::default() };
    for _ in 0..walks {
        let Some((_, events)) = walk(eta, r * r, r_c * r_c, wo, &mut rng) else { continue };
        counts.entered += 1;
        counts.events[events.len().clamp(1, EVENT_CAP) - 1] += 1;
        for &cosine in events.iter().skip(1) {
            counts.pool_cosine_sum += cosine;
            counts.pool_events += 1;
        }
    }
    counts
}

/// γ(B, c) = c(1 − B)/(1 − Bc): the generating function of a geometric count ≥ 1 with
/// retention B (the share that stays per event).
fn geometric(retention: f64, c: f64) -> f64 {
    c * (1.0 - retention) / (1.0 - retention * c)
}

/// The fixed retentions of the trapped light's basis: leaving at the next event (0), at rate ½
/// and at rate 0.8; a fourth, slow rate is fitted per node ([`fit_trapped`]).
pub const TRAPPED_RETENTIONS: [f64; 3] = [0.0, 0.5, 0.8];

/// The simplex-constrained least-squares weights (w ≥ 0, Σw = 1) of `basis[j][i]` (basis j at
/// survival i) against `target[i]`, by trying every active set (four weights: fifteen sets).
fn simplex_least_squares(basis: &[Vec<f64>], target: &[f64]) -> Vec<f64> {
    let n = basis.len();
    let mut best = (f64::INFINITY, vec![1.0 / n as f64; n]);
    for mask in 1u32..(1 << n) {
        let active: Vec<usize> = (0..n).filter(|j| mask >> j & 1 == 1).collect();
        let m = active.len();
        // The KKT system of min |Bw − t|² subject to Σw = 1: [2BᵀB 1; 1ᵀ 0][w; λ] = [2Bᵀt; 1].
        let mut a = vec![vec![0.0; m + 2]; m + 1];
        for (r, &jr) in active.iter().enumerate() {
            for (q, &jq) in active.iter().enumerate() {
                a[r][q] = 2.0 * basis[jr].iter().zip(&basis[jq]).map(|(x, y)| x * y).sum::<f64>();
            }
            a[r][m] = 1.0;
            a[r][m + 1] = 2.0 * basis[jr].iter().zip(target).map(|(x, y)| x * y).sum::<f64>();
        }
        a[m][..m].iter_mut().for_each(|x| *x = 1.0);
        a[m][m + 1] = 1.0;
        let Some(solution) = solve(a) else { continue };
        if solution[..m].iter().any(|&w| w < -1e-12) {
            continue;
        }
        let mut w = vec![0.0; n];
        for (r, &j) in active.iter().enumerate() {
            w[j] = solution[r].max(0.0);
        }
        let error: f64 =
            (0..target.len()).map(|i| ((0..n).map(|j| w[j] * basis[j][i]).sum::<f64>() - target[i]).powi(2)).sum();
        if error < best.0 {
            best = (error, w);
        }
    }
    best.1
}

/// Gauss–Jordan elimination with partial pivoting of an augmented square system.
fn solve(mut a: Vec<Vec<f64>>) -> Option<Vec<f64>> {
    let size = a.len();
    for col in 0..size {
        let pivot = (col..size).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[pivot][col].abs() < 1e-14 {
            return None;
        }
        a.swap(col, pivot);
        let pivot_row = a[col].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != col {
                let factor = row[col] / pivot_row[col];
                for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    *x -= factor * p;
                }
            }
        }
    }
    Some((0..size).map(|r| a[r][size] / a[r][r]).collect())
}

/// The trapped light of one direction as weights on the basis [`TRAPPED_RETENTIONS`] + `slow`:
/// (weights, largest error of the generating function over [`FIT_SURVIVALS`], in shares of the
/// entering light).
fn trapped_weights(counts: &EventCounts, slow: f64) -> (Vec<f64>, f64) {
    let rest = 1.0 - counts.share(0);
    let retentions: Vec<f64> = TRAPPED_RETENTIONS.iter().copied().chain([slow]).collect();
    if rest < 1e-6 {
        return (vec![0.25; 4], 0.0);
    }
    let basis: Vec<Vec<f64>> =
        retentions.iter().map(|&b| FIT_SURVIVALS.iter().map(|&c| rest * geometric(b, c)).collect()).collect();
    let target: Vec<f64> = FIT_SURVIVALS.iter().map(|&c| counts.trapped(c)).collect();
    let w = simplex_least_squares(&basis, &target);
    let worst = (0..target.len())
        .map(|i| ((0..4).map(|j| w[j] * basis[j][i]).sum::<f64>() - target[i]).abs())
        .fold(0.0, f64::max);
    (w, worst)
}

/// The slow retention that fits every direction's trapped light best (smallest largest error),
/// searched over 1 − B from 0.6 down to 10⁻³ on a geometric grid; and that error.
fn fit_trapped(columns: &[EventCounts]) -> (f64, f64) {
    let mut best = (f64::INFINITY, 0.9);
    for k in 0..48 {
        let slow = 1.0 - 0.6 * (1e-3_f64 / 0.6).powf(f64::from(k) / 47.0);
        let worst = columns.iter().map(|c| trapped_weights(c, slow).1).fold(0.0, f64::max);
        if worst < best.0 {
            best = (worst, slow);
        }
    }
    (best.1, best.0)
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
fn taper(mu: f64) -> f64 {
    1.0 - (1.0 - mu.clamp(0.0, 1.0)).powf(GLOSSY_TAPER_POWER)
}

/// The path lengths L (over the slab's thickness, both crossings) of the light entering at `mu`
/// that leaves after one reflection off a mirror under the coat.
fn mirror_path_lengths(mu: f64, r: f64, eta: f64, walks: u32, seed: u64) -> Vec<f64> {
    let mut rng = Rng::seeded(seed);
    (0..walks)
        .filter_map(|_| {
            let (crossings, events) = walk(eta, r * r, 0.0, direction_at_cosine(mu), &mut rng)?;
            (events.len() == 1).then(|| crossings.iter().map(|c| 1.0 / c.max(1e-6)).sum())
        })
        .collect()
}

/// E[e^(−τL)] over path lengths, summed without underflow: e^(−τ L_min) E[e^(−τ(L − L_min))].
fn mean_attenuation(lengths: &[f64], tau: f64) -> f64 {
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
fn path_depths() -> Vec<f64> {
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
/// over directions whose attenuation differs (set directly, the albedo at 85° came out 10% high).
fn path_column(r: f64, eta: f64, walks: u32, seed: u64) -> Vec<f64> {
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
            super::quadrature::albedo_nodes(v, SMOOTH_ALPHA.max(1e-2))
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

/// The node of `axis` `i` of `n`.
/// The (r_c, r, η) node triples of a glossy grid whose axes after the first are those three, in
/// table order (r_c fastest), with their arguments.
fn node_triples(axes: &[(Axis, usize)]) -> Vec<(f64, f64, f64)> {
    let (rc, r, eta) = (axes[axes.len() - 3], axes[axes.len() - 2], axes[axes.len() - 1]);
    let mut triples = Vec::new();
    for e in 0..eta.1 {
        for j in 0..r.1 {
            for c in 0..rc.1 {
                triples.push((rc.0.node(c, rc.1), r.0.node(j, r.1), eta.0.node(e, eta.1)));
            }
        }
    }
    triples
}

/// The direction nodes of a glossy grid (its first axis), each at least [`GLOSSY_GRAZING`].
fn direction_nodes(axes: &[(Axis, usize)]) -> Vec<f64> {
    let (axis, n) = axes[0];
    (0..n).map(|i| axis.node(i, n).max(GLOSSY_GRAZING)).collect()
}

/// P₁ at every direction of `GLOSSY_SINGLE_GRID` for one (r_c, r, η).
fn single_column((r_c, r, eta): (f64, f64, f64), walks: u32, seed: u64) -> Vec<f64> {
    direction_nodes(&GLOSSY_SINGLE_GRID)
        .iter()
        .enumerate()
        .map(|(i, &mu)| event_counts(mu, r_c, r, eta, walks, seed << 8 | i as u64).share(0))
        .collect()
}

/// The trapped light for one (r_c, r, η) of `GLOSSY_TRAPPED_GRID`: per direction the weights of
/// its first three retentions (the fourth is one minus their sum); the slow retention, the
/// trapped light's mean cosine at the conductor, and the fit's largest error.
struct TrappedColumn {
    weights: Vec<[f64; 3]>,
    slow_retention: f64,
    pool_cosine: f64,
    fit_error: f64,
}

fn trapped_column((r_c, r, eta): (f64, f64, f64), walks: u32, seed: u64) -> TrappedColumn {
    let counts: Vec<EventCounts> = direction_nodes(&GLOSSY_TRAPPED_GRID)
        .iter()
        .enumerate()
        .map(|(i, &mu)| event_counts(mu, r_c, r, eta, walks, seed << 8 | i as u64))
        .collect();
    let (slow_retention, fit_error) = fit_trapped(&counts);
    let weights = counts
        .iter()
        .map(|c| {
            let (w, _) = trapped_weights(c, slow_retention);
            [w[0], w[1], w[2]]
        })
        .collect();
    let (pool_sum, pool_events) =
        counts.iter().fold((0.0, 0u64), |(s, n), c| (s + c.pool_cosine_sum, n + c.pool_events));
    let mu_c = (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt();
    // Without any trapped light (a mirror under a smooth coat), inside the TIR cone.
    let pool_cosine = if pool_events > 0 { pool_sum / pool_events as f64 } else { 0.7 * mu_c.max(0.5) };
    TrappedColumn { weights, slow_retention, pool_cosine, fit_error }
}

/// σ/r² at every direction of `GLOSSY_BLUR_GRID` for one (r_c, r, η): stored over the coat's
/// α = r² (σ grows about linearly with it, which a table in √r does not follow); below
/// r = [`BLUR_ROUGHNESS_MIN`] the ratio is taken at that roughness, where the widening is still
/// large enough to measure.
fn blur_column((r_c, r, eta): (f64, f64, f64), walks: u32, seed: u64) -> Vec<f64> {
    let r_blur = r.max(BLUR_ROUGHNESS_MIN);
    direction_nodes(&GLOSSY_BLUR_GRID)
        .iter()
        .enumerate()
        .map(|(i, &mu)| {
            peak_blur(mu, r_c * r_c, r_blur, eta, walks, seed << 8 | i as u64) * taper(mu) / (r_blur * r_blur)
        })
        .collect()
}

/// What generating the glossy tables measured about itself.
#[derive(Clone, Copy, Debug, Default)]
pub struct GlossyReport {
    /// Largest error of the fitted generating function of trapped light against the walks'
    /// own, over directions and survivals c ∈ [0.3, 0.99] (in shares of the entering light).
    pub max_tail_fit_error: f64,
    /// Largest relative miss of the solved lobe scale at its nodes: |achieved/target − 1|.
    pub max_scale_miss: f64,
    /// Largest energy excess E − 1 of a white conductor under a clear coat found between the
    /// nodes before K was fitted (`fit_lobe_albedo`).
    pub max_energy_excess: f64,
}

/// Fills the glossy tables into `tables` (every other table already computed: the scale is
/// solved through the compiled lobe, which reads the coat's tables).
pub fn generate(tables: &mut [Vec<f32>], walks: u32, progress: &(dyn Fn(usize, usize) + Sync)) -> GlossyReport {
    let single_nodes = node_triples(&GLOSSY_SINGLE_GRID);
    let trapped_nodes = node_triples(&GLOSSY_TRAPPED_GRID);
    let blur_nodes = node_triples(&GLOSSY_BLUR_GRID);
    let [_, _, (_, n_r), (_, n_eta)] = GLOSSY_PATH_GRID;
    let path_nodes: Vec<(f64, f64)> = (0..n_eta)
        .flat_map(|e| (0..n_r).map(move |j| (Axis::Roughness.node(j, n_r), Axis::Ior.node(e, n_eta))))
        .collect();
    let total =
        2 * single_nodes.len() + trapped_nodes.len() + blur_nodes.len() + path_nodes.len() + energy_probes().len();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let tick = || progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1, total);
    // Every job has its own seed, whatever the grids of the others.
    let single = super::parallel_map(
        single_nodes.len(),
        |k| single_column(single_nodes[k], walks, 0x5_0000 | k as u64),
        |_| tick(),
    );
    let trapped = super::parallel_map(
        trapped_nodes.len(),
        |k| trapped_column(trapped_nodes[k], walks, 0x6_0000 | k as u64),
        |_| tick(),
    );
    let blur =
        super::parallel_map(blur_nodes.len(), |k| blur_column(blur_nodes[k], walks, 0x7_0000 | k as u64), |_| tick());
    let mut report = GlossyReport::default();
    let n_single = GLOSSY_SINGLE_GRID[0].1;
    let n_trapped = GLOSSY_TRAPPED_GRID[0].1;
    for (k, column) in trapped.iter().enumerate() {
        for (i, w) in column.weights.iter().enumerate() {
            tables[TableId::GlossyNext as usize][i + n_trapped * k] = w[0] as f32;
            tables[TableId::GlossyQuick as usize][i + n_trapped * k] = w[1] as f32;
            tables[TableId::GlossySteady as usize][i + n_trapped * k] = w[2] as f32;
        }
        tables[TableId::GlossySlowRetention as usize][k] = column.slow_retention as f32;
        tables[TableId::GlossyPoolCosine as usize][k] = column.pool_cosine as f32;
        report.max_tail_fit_error = report.max_tail_fit_error.max(column.fit_error);
    }
    let n_blur = GLOSSY_BLUR_GRID[0].1;
    for (k, column) in blur.iter().enumerate() {
        for (i, &b) in column.iter().enumerate() {
            tables[TableId::GlossyBlur as usize][i + n_blur * k] = b as f32;
        }
    }
    // The scale goes through the compiled lobe, which must read the tables just computed.
    tables[TableId::GlossyScale as usize].iter_mut().for_each(|s| *s = 1.0);
    glazec::math::tables::evaluate_on_cpu_with(tables);
    let scales = super::parallel_map(
        single_nodes.len(),
        |k| {
            let (r_c, r, eta) = single_nodes[k];
            solve_scale(r_c, r, eta, &single[k])
        },
        |_| tick(),
    );
    for (k, (scale, miss)) in scales.into_iter().enumerate() {
        for (i, s) in scale.into_iter().enumerate() {
            tables[TableId::GlossyScale as usize][i + n_single * k] = s as f32;
        }
        report.max_scale_miss = report.max_scale_miss.max(miss);
    }
    // K = O/(s² E c) at every node, O = P₁ + (1 − P₁) w₀ the lobe's white albedo over T (what the
    // scale was solved for).
    glazec::math::tables::evaluate_on_cpu_with(tables);
    for (k, (column, &(r_c, r, eta))) in single.iter().zip(&single_nodes).enumerate() {
        for (i, (&p1, mu)) in column.iter().zip(direction_nodes(&GLOSSY_SINGLE_GRID)).enumerate() {
            let at = [mu as f32, r_c as f32, r as f32, eta as f32];
            let next = f64::from(glazec::math::tables::lookup::<f32>(TableId::GlossyNext, &at));
            let scale = f64::from(tables[TableId::GlossyScale as usize][i + n_single * k]);
            let normaliser = glazec::math::layering::glossy_lobe_normaliser(r_c, r, eta, mu);
            let lobe_albedo = p1 + (1.0 - p1) * next;
            tables[TableId::GlossyLobeAlbedo as usize][i + n_single * k] =
                (lobe_albedo / (scale * scale * normaliser).max(1e-6)) as f32;
        }
    }
    // The path factors go through the scaled lobe.
    glazec::math::tables::evaluate_on_cpu_with(tables);
    let paths = super::parallel_map(
        path_nodes.len(),
        |k| {
            let (r, eta) = path_nodes[k];
            path_column(r, eta, walks, 0x8_0000 | k as u64)
        },
        |_| tick(),
    );
    // Layout (μ, τ, r, η), μ fastest: each column is (μ, τ).
    let column_len = GLOSSY_PATH_GRID[0].1 * GLOSSY_PATH_GRID[1].1;
    for (k, column) in paths.iter().enumerate() {
        tables[TableId::GlossyPath as usize][column_len * k..column_len * (k + 1)]
            .iter_mut()
            .zip(column)
            .for_each(|(t, &q)| *t = q as f32);
    }
    glazec::math::tables::evaluate_on_cpu_with(tables);
    report.max_energy_excess = fit_lobe_albedo(tables, &|| tick());
    glazec::math::tables::evaluate_on_cpu_with(tables);
    report
}

/// A white conductor under a clear coat must reflect what reaches it: the lobe and the remainder
/// T(1 − s²K E c) add up to T(μ) where the interpolated K·E·c follows the lobe's own albedo,
/// exactly at the nodes and nearly between them. Between them a white conductor gains energy
/// where K·E·c falls short of the lobe, and loses it where K·E·c exceeds it. The compiled method
/// itself is probed (a white conductor under a clear coat, by the albedo quadrature) at
/// [`energy_probes`]; K is first raised on its η = 1 face for the probes near η = 1
/// ([`raise_near_one`]), then changed from there by the least amount (in a metric that sends the
/// change of a cell touching η = 1 to its η = 1 face) that
///
/// * takes every probe to at most [`PROBE_ENERGY_CEILING`] (a hard constraint), and
/// * keeps the probes where the method loses energy against the walks within
///   [`PROBE_LOSS_TOLERANCE`] of 1 where it can (a soft one: [`LOSS_MULTIPLIER_CAP`]), so that
///   K is lowered where its interpolation took light from the remainder.
///
/// E at a probe is linear in the looked-up K (K enters the remainder as −T s² E c·K, and the
/// lookup is a weighted sum of corners), so this is a quadratic programme over the corners,
/// solved by Hildreth's dual coordinate ascent ([`least_change`]). Returns the largest excess
/// E − 1 found before the change.
///
/// It replaced a rule that raised each corner by the largest need of the cells around it, which
/// took up to 0.049 from K around η 1.33–1.5 for cells beside them and darkened copper under an
/// η 1.5, r ½ coat by 0.0116 at 30°; and, with the lowering, the light that K's interpolation
/// took from the remainder between the r nodes (a white conductor under that coat reflected 0.993
/// at 85°) is given back.
fn fit_lobe_albedo(tables: &mut [Vec<f32>], tick: &(dyn Fn() + Sync)) -> f64 {
    let probes = energy_probes();
    let measured = super::parallel_map(probes.len(), |k| probe_energy(probes[k]), |_| tick());
    let constraints: Vec<EnergyConstraint> = probes
        .iter()
        .zip(&measured)
        .filter_map(|(&at, &(excess, unit))| EnergyConstraint::new(at, excess, unit))
        .collect();
    let lobe_albedo = &mut tables[TableId::GlossyLobeAlbedo as usize];
    let start = raise_near_one(&constraints, lobe_albedo.len());
    let change = least_change(&constraints, start);
    for (value, delta) in lobe_albedo.iter_mut().zip(&change) {
        *value += *delta as f32;
    }
    measured.iter().map(|&(excess, _)| excess).fold(0.0, f64::max)
}

/// The most a white conductor under a clear coat may reflect at a probe once K is fitted:
/// 8·10⁻⁴ below the law, for the points between the probes (the stability sweeps find no cell
/// over 1 + 10⁻³ away from the known corner near η = 1).
const PROBE_ENERGY_CEILING: f64 = 1.0 - 8e-4;

/// How much less than all of it a white conductor may reflect at a probe before K is lowered
/// there, and which probes ask for it: directions near grazing, μ within
/// [`LOSS_PROBE_COSINES`] (where the loss was measured: a white conductor of roughness 0.3 under
/// an η 1.5, r ½ coat reflected 0.993 at 85°; lowering K for probes at steeper directions too
/// made a white conductor gain at 0° on the table's last r_c and r nodes, E = 1.0015 and
/// 1.0025, corners the probes between the nodes see only in part), coats of
/// η ≥ [`LOSS_PROBE_MIN_IOR`], and a lookup that moves E by at least [`LOSS_PROBE_MIN_UNIT`] per
/// unit of K (elsewhere a loss would need K moved by more than its neighbours can follow). Part
/// of a loss is the coat's own (its reflection and transmission at grazing incidence), which K
/// should not make up for: hence a tolerance, not an equality.
const PROBE_LOSS_TOLERANCE: f64 = 3e-3;
const LOSS_PROBE_COSINES: std::ops::RangeInclusive<f64> = 0.03..=0.2;
const LOSS_PROBE_MIN_IOR: f64 = 1.3;
const LOSS_PROBE_MIN_UNIT: f64 = 0.15;

/// The bound on a loss probe's multiplier: the losses are an exact L1 penalty of this weight (in
/// the metric's units), not a constraint, as neighbouring probes can ask for K raised and
/// lowered at once (multilinear interpolation cannot follow every curvature within a cell).
const LOSS_MULTIPLIER_CAP: f64 = 6.0;

/// The metric's weight of the corners off the η = 1 face (those on it weigh 1): a cell that
/// touches η = 1 is changed on that face. Its gains come from the escape cone closing near
/// η = 1, and changing the face at the next node (η 1.22) for them took energy from every coat
/// up to η 1.5.
const OFF_FACE_WEIGHT: f64 = 0.01;

/// Sweeps of [`least_change`] (it stops earlier once no constraint is violated by more than
/// [`FIT_TOLERANCE`]; with the capped loss probes it usually runs them all).
const FIT_SWEEPS: usize = 1500;
const FIT_TOLERANCE: f64 = 1e-6;

/// A white conductor (F0 = 1) of roughness r_c under a clear coat at a probe (μ, r_c, r, η):
/// E − 1, and what a unit of the looked-up K takes from E there, T s² E c.
fn probe_energy(at: [f64; 4]) -> (f64, f64) {
    let [mu, r_c, r, eta] = at;
    let material = white_conductor_under(r_c, r, eta);
    let wo = direction_at_cosine(mu);
    let f = |wi: DVec3, wo: DVec3| glazec::eval::brdf(&material, &[], wi.as_vec3(), wo.as_vec3()).as_dvec3();
    let sharpest = (r_c * r_c).min(r * r).max(SMOOTH_ALPHA);
    let e = super::quadrature::directional_albedo_f64(&f, wo, sharpest).x
        + f64::from(glazec::eval::mirror_reflectance(&material, &[], wo.as_vec3()).x);
    let at32 = at.map(|x| x as f32);
    let scale = f64::from(glazec::math::tables::lookup::<f32>(TableId::GlossyScale, &at32));
    let t = glazec::math::layering::glossy_coat_transmission(r, eta, mu);
    let normaliser = glazec::math::layering::glossy_lobe_normaliser(r_c, r, eta, mu);
    (e - 1.0, t * scale * scale * normaliser)
}

/// What one probe asks of the change x of K: lower ≤ Σ wᵢ xᵢ ≤ upper over the corners of its
/// cell (upper infinite for a probe that may lose).
struct EnergyConstraint {
    /// Where the probe is, (μ, r_c, r, η).
    at: [f64; 4],
    /// (index into the K table, lookup weight, metric weight) of each corner.
    corners: Vec<(usize, f64, f64)>,
    /// The change of the looked-up K the probe needs to keep under [`PROBE_ENERGY_CEILING`]
    /// (nothing when it is not positive).
    lower: f64,
    upper: f64,
    /// Σ w² m: how far the looked-up change moves per unit of the multiplier.
    norm: f64,
}

impl EnergyConstraint {
    /// The constraint of a probe at `at` whose E is 1 + `excess`, a unit of K taking `unit` from
    /// it; `None` when it asks nothing.
    fn new(at: [f64; 4], excess: f64, unit: f64) -> Option<Self> {
        // Guard: a lookup that barely moves E (T s² E c → 0 at grazing) is taken as 10⁻³.
        let unit_floor = unit.max(1e-3);
        let lower = (1.0 + excess - PROBE_ENERGY_CEILING) / unit_floor;
        let may_lose =
            unit_floor >= LOSS_PROBE_MIN_UNIT && at[3] >= LOSS_PROBE_MIN_IOR && LOSS_PROBE_COSINES.contains(&at[0]);
        let upper = if may_lose { (excess + PROBE_LOSS_TOLERANCE) / unit_floor } else { f64::INFINITY };
        if lower <= 0.0 && upper == f64::INFINITY {
            return None;
        }
        let corners = lookup_corners(at);
        let norm = corners.iter().map(|&(_, w, m)| w * w * m).sum();
        Some(EnergyConstraint { at, corners, lower, upper, norm })
    }

    fn looked_up(&self, change: &[f64]) -> f64 {
        self.corners.iter().map(|&(i, w, _)| w * change[i]).sum()
    }

    /// Moves the change along this constraint's direction (in the metric) by `step`.
    fn step(&self, change: &mut [f64], step: f64) {
        for &(i, w, m) in &self.corners {
            change[i] += step * w * m;
        }
    }
}

/// Where `at` lies in `GLOSSY_SINGLE_GRID`, per axis: the cell's lower node i and the fraction t
/// of the way to node i + 1.
fn single_cell(at: [f64; 4]) -> [(usize, f64); 4] {
    std::array::from_fn(|a| {
        let (axis, n) = GLOSSY_SINGLE_GRID[a];
        let x = f64::from(axis.coordinate(at[a] as f32)) * (n - 1) as f64;
        let i = (x.floor() as usize).min(n - 2);
        (i, x - i as f64)
    })
}

/// The corners spanned by one list of (node, weight) per axis, each with the product of its
/// axes' weights.
fn span(per_axis: &[Vec<(usize, f64)>; 4]) -> Vec<([usize; 4], f64)> {
    let mut corners = vec![([0usize; 4], 1.0)];
    for (a, side) in per_axis.iter().enumerate() {
        corners = corners
            .iter()
            .flat_map(|&(corner, weight)| {
                side.iter().map(move |&(i, w)| {
                    let mut c = corner;
                    c[a] = i;
                    (c, weight * w)
                })
            })
            .collect();
    }
    corners
}

/// A corner's index in the `GLOSSY_SINGLE_GRID` tables (the first axis fastest).
fn single_index(corner: [usize; 4]) -> usize {
    let dims: [usize; 4] = GLOSSY_SINGLE_GRID.map(|(_, n)| n);
    corner[0] + dims[0] * (corner[1] + dims[1] * (corner[2] + dims[2] * corner[3]))
}

/// The corners of the `GLOSSY_SINGLE_GRID` cell holding `at`, as (index of the K table, weight
/// of the multilinear lookup, metric weight: 1 on the η = 1 face, [`OFF_FACE_WEIGHT`] off it).
fn lookup_corners(at: [f64; 4]) -> Vec<(usize, f64, f64)> {
    let per_axis = single_cell(at)
        .map(|(i, t)| [(i, 1.0 - t), (i + 1, t)].into_iter().filter(|&(_, w)| w > 1e-12).collect::<Vec<_>>());
    span(&per_axis)
        .into_iter()
        .map(|(c, w)| (single_index(c), w, if c[3] == 0 { 1.0 } else { OFF_FACE_WEIGHT }))
        .collect()
}

/// The raise of K on the η = 1 face that the least change starts from: every probe inside the
/// first η cell (η 1 … 1.22, within three quarters of it from η = 1) that needs a raise raises
/// the corners of its cell's η = 1 face nearest to it ([`nearest_corners`]) by what it needs,
/// each corner by the largest need among its probes. Near η = 1 the gains come from the escape
/// cone closing (like √(2(η − 1))), steeply in μ and η between the probes: the least change
/// alone, exact at the probes, left a white conductor under a smooth η 1.008 coat gaining
/// E = 1.012 at 85° (1.080 before any change of K); this generous raise leaves none.
fn raise_near_one(constraints: &[EnergyConstraint], len: usize) -> Vec<f64> {
    let mut raise = vec![0.0_f64; len];
    for c in constraints {
        let (ior_cell, ior_fraction) = single_cell(c.at)[3];
        if ior_cell > 0 || ior_fraction >= 0.75 || c.lower <= 0.0 {
            continue;
        }
        for (corner, share) in nearest_corners(c.at) {
            let index = single_index(corner);
            raise[index] = raise[index].max(c.lower / share);
        }
    }
    raise
}

/// The corners of the `GLOSSY_SINGLE_GRID` cell holding `at` (in the first η cell) that
/// [`raise_near_one`] raises for it, with the share of the lookup they carry there (the product
/// over the axes of their weights): the η = 1 face, and along the other axes, where `at` lies
/// within a quarter of the cell from a node only that node's side, else both.
fn nearest_corners(at: [f64; 4]) -> Vec<([usize; 4], f64)> {
    let per_axis: [Vec<(usize, f64)>; 4] = std::array::from_fn(|a| {
        let (i, t) = single_cell(at)[a];
        match t {
            t if t <= 0.25 || GLOSSY_SINGLE_GRID[a].0 == Axis::Ior => vec![(i, 1.0 - t)],
            t if t >= 0.75 => vec![(i + 1, t)],
            t => vec![(i, 1.0 - t), (i + 1, t)],
        }
    });
    let share: f64 = per_axis.iter().map(|side| side.iter().map(|&(_, w)| w).sum::<f64>()).product();
    span(&per_axis).into_iter().map(|(corner, _)| (corner, share)).collect()
}

/// The least change x of the K table (in the metric) from `start` within the constraints:
/// Hildreth's dual coordinate ascent (Hildreth 1957; Censor & Zenios, "Parallel Optimization", 1997, §6.3). Each
/// constraint keeps a multiplier per side, λ ≥ 0 for its lower bound and 0 ≤ μ ≤
/// [`LOSS_MULTIPLIER_CAP`] for its upper one; visiting the constraints in turn, each multiplier
/// moves by the violation over `norm` (projected on its bounds) and x moves with it along the
/// constraint's weights; from multipliers 0 at `start`, it minimises the distance to `start`.
/// Deterministic: the constraints are visited in probe order.
fn least_change(constraints: &[EnergyConstraint], start: Vec<f64>) -> Vec<f64> {
    let mut change = start;
    let mut raise = vec![0.0; constraints.len()];
    let mut lower = vec![0.0; constraints.len()];
    for _ in 0..FIT_SWEEPS {
        let mut worst: f64 = 0.0;
        for (k, c) in constraints.iter().enumerate() {
            let mut looked_up = c.looked_up(&change);
            worst = worst.max(c.lower - looked_up).max(looked_up - c.upper);
            let next = (raise[k] + (c.lower - looked_up) / c.norm).max(0.0);
            c.step(&mut change, next - raise[k]);
            looked_up += (next - raise[k]) * c.norm;
            raise[k] = next;
            if c.upper.is_finite() {
                let next = (lower[k] + (looked_up - c.upper) / c.norm).clamp(0.0, LOSS_MULTIPLIER_CAP);
                c.step(&mut change, -(next - lower[k]));
                lower[k] = next;
            }
        }
        if worst < FIT_TOLERANCE {
            break;
        }
    }
    change
}

/// The points (μ, r_c, r, η) where [`fit_lobe_albedo`] probes the energy: the centre of every
/// cell of `GLOSSY_SINGLE_GRID`, the centres of its faces and edges across (r_c, r, η) (the
/// least change of K, unlike a raise of every corner, leaves the points between probes free to
/// gain: with centres and faces alone a mirror conductor under an r 0.2, η 1.5 coat gained
/// E = 1.0019 at 60°), and the two places where the lookup's terms change
/// fastest within a cell: grazing incidence (μ = 10⁻⁴ and 2·10⁻³, below the first node's
/// [`GLOSSY_GRAZING`], where the lobe's scale is held and the escape cone's edge meets the
/// refracted mirror direction) and a coat IOR just above 1 (η − 1 = 10⁻⁵, 3·10⁻³, 3·10⁻²,
/// where the escape cone closes like √(2(η − 1)) in the first cell of a linear axis), each at
/// the centre of the cell in the other arguments.
fn energy_probes() -> Vec<[f64; 4]> {
    let dims: [usize; 4] = GLOSSY_SINGLE_GRID.map(|(_, n)| n);
    let midpoint = |axis: usize, i: usize| -> f64 {
        let (kind, n) = GLOSSY_SINGLE_GRID[axis];
        kind.argument(i as f64 + 0.5, n)
    };
    let mut probes = Vec::new();
    for e in 0..dims[3] - 1 {
        for r in 0..dims[2] - 1 {
            for c in 0..dims[1] - 1 {
                let (r_c, r, eta) = (midpoint(1, c), midpoint(2, r), midpoint(3, e));
                for m in 0..dims[0] - 1 {
                    probes.push([midpoint(0, m), r_c, r, eta]);
                }
                for mu in GRAZING_PROBES {
                    probes.push([mu, r_c, r, eta]);
                }
                if e == 0 {
                    for m in 0..dims[0] - 1 {
                        probes.extend(NEAR_ONE_PROBES.map(|d| [midpoint(0, m), r_c, r, 1.0 + d]));
                    }
                }
            }
        }
    }
    // The faces and edges of the cells across (r_c, r, η): one or two of them at a node, the
    // others and μ at cell midpoints (edges on η = 1 left out: the coat vanishes there, and the
    // probes just above it look at what closes).
    let node = |axis: usize, i: usize| -> f64 {
        let (kind, n) = GLOSSY_SINGLE_GRID[axis];
        kind.node(i, n)
    };
    for at_node in [
        [true, false, false],
        [false, true, false],
        [false, false, true],
        [true, true, false],
        [true, false, true],
        [false, true, true],
    ] {
        let edge = at_node.iter().filter(|&&b| b).count() == 2;
        let values = |axis: usize| -> Vec<f64> {
            match at_node[axis - 1] {
                true => (usize::from(edge && axis == 3)..dims[axis]).map(|i| node(axis, i)).collect(),
                false => (0..dims[axis] - 1).map(|i| midpoint(axis, i)).collect(),
            }
        };
        for &eta in &values(3) {
            for &r in &values(2) {
                for &r_c in &values(1) {
                    probes.extend((0..dims[0] - 1).map(|m| [midpoint(0, m), r_c, r, eta]));
                }
            }
        }
    }
    probes
}

/// The grazing cosines and the coat IORs (as η − 1) of [`energy_probes`].
const GRAZING_PROBES: [f64; 2] = [1e-4, 2e-3];
const NEAR_ONE_PROBES: [f64; 3] = [1e-5, 3e-3, 3e-2];

/// A white conductor (F0 = 1) of roughness `r_c` under a clear coat of roughness `r` and IOR
/// `eta`, for the energy probes.
fn white_conductor_under(r_c: f64, r: f64, eta: f64) -> glazec::model::Material {
    use glazec::model::{Base, Coat, Color, ConductorFresnel, Lobe, Material, Method, Scalar};
    let lobe = if r * r < SMOOTH_ALPHA { Lobe::Smooth } else { Lobe::Ggx { roughness: Scalar::Lit(r as f32) } };
    Material {
        name: "probe".into(),
        method: Method::INTERFACED,
        coats: vec![Coat {
            lobe,
            ior: Scalar::Lit(eta as f32),
            absorption: Color::Lit([0.0; 3]),
            thickness: Scalar::Lit(1.0),
        }],
        base: Base::Conductor {
            roughness: Scalar::Lit(r_c as f32),
            fresnel: ConductorFresnel::F0(Color::Lit([1.0; 3])),
        },
        params: vec![],
        normals: vec![],
    }
}

/// Sinkhorn iterations of the scale.
const SCALE_ITERATIONS: usize = 30;

/// The scale s at the μ nodes that makes the compiled lobe's albedo (white conductor, clear coat,
/// s interpolated along μ as the lookup does) equal T(μ)·P₁(μ) at every node but μ = 0 (where
/// both vanish; it takes its neighbour's); and the largest relative miss left.
fn solve_scale(r_c: f64, r: f64, eta: f64, single: &[f64]) -> (Vec<f64>, f64) {
    let n_mu = single.len();
    let mus: Vec<f64> = direction_nodes(&GLOSSY_SINGLE_GRID);
    let lobe = |l: DVec3, v: DVec3| glazec::math::layering::glossy_lobe_white(r_c, r, eta, l, v);
    let sharpest = (r_c * r_c).max(SMOOTH_ALPHA);
    // Every node's view direction, its quadrature and the lobe at each quadrature node.
    let columns: Vec<(f64, Vec<(f64, f64)>)> = mus
        .iter()
        .enumerate()
        .map(|(i, &mu)| {
            let v = direction_at_cosine(mu);
            // What leaves near the mirror direction: after one event, or after the second
            // (the trapped light's share w₀, from the table just computed).
            let next = f64::from(glazec::math::tables::lookup::<f32>(
                TableId::GlossyNext,
                &[mu as f32, r_c as f32, r as f32, eta as f32],
            ));
            let target =
                glazec::math::layering::glossy_coat_transmission(r, eta, v.z) * (single[i] + (1.0 - single[i]) * next);
            let nodes = super::quadrature::albedo_nodes(v, sharpest)
                .into_iter()
                .filter_map(|(l, w)| {
                    let f = lobe(l, v);
                    (f > 0.0).then_some((l.z, w * f))
                })
                .collect();
            (target, nodes)
        })
        .collect();
    // Interpolated as the lookup does: linearly in u = √μ.
    let at = |scale: &[f64], mu: f64| -> f64 {
        let x = mu.clamp(0.0, 1.0).sqrt() * (n_mu - 1) as f64;
        let i = (x.floor() as usize).min(n_mu - 2);
        let t = x - i as f64;
        scale[i] * (1.0 - t) + scale[i + 1] * t
    };
    let achieved = |scale: &[f64], i: usize| -> f64 {
        let (_, nodes) = &columns[i];
        scale[i] * nodes.iter().map(|&(mu_l, wf)| at(scale, mu_l) * wf).sum::<f64>()
    };
    let mut scale = vec![1.0; n_mu];
    for _ in 0..SCALE_ITERATIONS {
        let next: Vec<f64> = (0..n_mu)
            .map(|i| {
                let (target, _) = columns[i];
                let got = achieved(&scale, i);
                if i == 0 || target <= 1e-9 || got <= 1e-12 {
                    return scale[i];
                }
                scale[i] * (target / got).sqrt().clamp(0.5, 2.0)
            })
            .collect();
        scale = next;
        scale[0] = scale[1];
    }
    let miss = (1..n_mu)
        .filter(|&i| columns[i].0 > 1e-6)
        .map(|i| (achieved(&scale, i) / columns[i].0 - 1.0).abs())
        .fold(0.0, f64::max);
    (scale, miss)
}
