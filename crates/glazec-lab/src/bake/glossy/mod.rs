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
//!   per node would not: they trade off against each other from node to node);
//! * κ: how the light of the remainder keeps going forward (what leaves after three or more
//!   events, and what leaves at the second but not in the lobe: the walks whose first return
//!   total internal reflection sent back, and of those the coat's Fresnel reflection sent back
//!   inside the cone what exceeds w₀; `EventCounts::forward_spread`): the mean cosine of its
//!   azimuth about the forward direction is
//!   about κ sin θᵢ sin θₒ (measured: κ within ±15% over θₒ and θᵢ for a conductor of roughness
//!   0.3 under a smooth coat, while E[cos φf] itself runs from 0.13 to 0.68), the ρ of the
//!   wrapped Cauchy weight that spreads the remainder over the azimuth;
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
//!   grazing, lets none lose more than 3·10⁻³ where it can (`fit_lobe_albedo`);
//! * q(μ; τ, r, η) (`GLOSSY_PATH_GRID`): the path factor of light that leaves after one reflection
//!   off a mirror under the coat: the one-event lobe attenuated by e^(−τq/μ_eff) on each side
//!   keeps what the walks' one-event light keeps of itself, E[e^(−τL)] over its path lengths L
//!   (two crossings; solved like the scale). μ_eff is the cosine along which the method absorbs
//!   the coat's transmitted light (Snell's cosine over the `coat_path` factor), so q is a
//!   correction to a path that already follows the coat's roughness and IOR, and interpolates
//!   between the coarse (r, η) nodes, which a q over Snell's cosine does not (it leaves copper
//!   under an η 1.33, r ½, τ ½ coat too bright at 85°). Kept at four depths, so that Jensen's
//!   gap between E\[e^(−τL)\] and e^(−τE\[L\]) (15% at τ = ½ under a coat of roughness ½) is
//!   interpolated, not ignored.
//!
//! Walks are the reference's own (Heitz et al. 2016 microsurfaces for rough interfaces and the
//! conductor, exact Fresnel for smooth interfaces), in f64 with deterministic seeds.

mod energy;
mod nodes;
mod solve;
mod walk;

pub use solve::TRAPPED_RETENTIONS;
pub use walk::{
    EventCounts, GLOSSY_TAPER_POWER, WalkReturn, escape_cone_cosine, event_counts, peak_blur, walk_events, walk_exits,
    walk_returns,
};

use energy::{energy_probes, fit_lobe_albedo};
use glazec::math::tables::{
    Axis, GLOSSY_BLUR_GRID, GLOSSY_PATH_GRID, GLOSSY_SINGLE_GRID, GLOSSY_TRAPPED_GRID, TableId,
};
use nodes::{direction_nodes, node_triples};
use solve::{fit_trapped, solve_scale, trapped_weights};
use walk::{BLUR_ROUGHNESS_MIN, path_column, taper};

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
    /// Per direction, the remainder's forward spread κ (`glossy_spread`).
    spread: Vec<f64>,
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
    let weights: Vec<[f64; 3]> = counts
        .iter()
        .map(|c| {
            let (w, _) = trapped_weights(c, slow_retention);
            [w[0], w[1], w[2]]
        })
        .collect();
    let (pool_sum, pool_events) =
        counts.iter().fold((0.0, 0u64), |(s, n), c| (s + c.pool_cosine_sum, n + c.pool_events));
    let mu_c = escape_cone_cosine(eta);
    // Without any trapped light (a mirror under a smooth coat), inside the TIR cone.
    let pool_cosine = if pool_events > 0 { pool_sum / pool_events as f64 } else { 0.7 * mu_c.max(0.5) };
    // Along the normal (the last node) light has no azimuth: the node takes its neighbour's κ.
    let spread: Vec<Option<f64>> = counts.iter().zip(&weights).map(|(c, w)| c.forward_spread(w[0])).collect();
    let spread = (0..spread.len())
        .map(|i| spread[i].or_else(|| spread[..i].iter().rev().find_map(|&k| k)).unwrap_or(0.0).min(SPREAD_MAX))
        .collect();
    TrappedColumn { weights, spread, slow_retention, pool_cosine, fit_error }
}

/// The largest κ stored: past it the spread is ρ = κ sin θᵢ sin θₒ clamped anyway
/// (`forward_azimuth_weight`); a mirror-like conductor under a rough coat measures up to 1.6.
const SPREAD_MAX: f64 = 2.0;

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
    /// nodes before K was fitted (`fit_lobe_albedo`), and what the fit left at a probe (as the
    /// lookup's linear model predicts it; the fit's ceiling, −2·10⁻³, where it met every probe).
    pub max_energy_excess: f64,
    pub max_energy_after_fit: f64,
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
    let single = crate::parallel_map(
        single_nodes.len(),
        |k| single_column(single_nodes[k], walks, 0x5_0000 | k as u64),
        |_| tick(),
    );
    let trapped = crate::parallel_map(
        trapped_nodes.len(),
        |k| trapped_column(trapped_nodes[k], walks, 0x6_0000 | k as u64),
        |_| tick(),
    );
    let blur =
        crate::parallel_map(blur_nodes.len(), |k| blur_column(blur_nodes[k], walks, 0x7_0000 | k as u64), |_| tick());
    let mut report = GlossyReport::default();
    let n_single = GLOSSY_SINGLE_GRID[0].1;
    let n_trapped = GLOSSY_TRAPPED_GRID[0].1;
    for (k, column) in trapped.iter().enumerate() {
        for (i, w) in column.weights.iter().enumerate() {
            tables[TableId::GlossyNext as usize][i + n_trapped * k] = w[0] as f32;
            tables[TableId::GlossyQuick as usize][i + n_trapped * k] = w[1] as f32;
            tables[TableId::GlossySteady as usize][i + n_trapped * k] = w[2] as f32;
        }
        for (i, &rho) in column.spread.iter().enumerate() {
            tables[TableId::GlossySpread as usize][i + n_trapped * k] = rho as f32;
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
    let scales = crate::parallel_map(
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
    let paths = crate::parallel_map(
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
    (report.max_energy_excess, report.max_energy_after_fit) = fit_lobe_albedo(tables, &|| tick());
    glazec::math::tables::evaluate_on_cpu_with(tables);
    report
}
