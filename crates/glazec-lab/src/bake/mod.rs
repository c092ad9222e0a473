//! `glazec tables`: generates `crates/glazec/data/tables.bin`, the tabulated terms of the default
//! method (layout and meaning in `glazec::math::tables`).
//!
//! Every value is computed in f64 from the reference's microsurface (Heitz et al. 2016), never
//! from the compiled math it will feed:
//!
//! * the share E_ms(μ) that a rough dielectric interface (GGX D, or GTR1 D for a `Gtr1` coat's
//!   own set of tables, with the height-correlated Smith G2 of either; exact Fresnel with total
//!   internal reflection) reflects after two or more microfacet events,
//!   by counting analog microsurface random walks (`walks` per entry: standard error at most
//!   √(E_ms/walks)), and the single-scattering albedo E_ss by deterministic quadrature over half
//!   vectors (the walk's single-event share equals it in this model; the generator checks it);
//! * the scale c(μ) of the interface's reflection lobe ([`scale`]), so that f_ss·c(μi)·c(μo)
//!   reflects E_ss + E_ms at the nodes, and the deficit G(μ) = F(μ) − A(μ), A that scaled lobe's
//!   albedo by quadrature through the lookups of c: so T(μ) = 1 − F + G = 1 − A exactly at the
//!   deficit's nodes, and at most that between them (the nodes are lowered until the lookup
//!   never overshoots the quadrature inside a cell);
//! * the geometric-mean cosine of the directions the walks transmit into (the path factor);
//! * seen from inside (relative IOR 1/η), R_int(μ) = E_ss + E_ms likewise, at 32 Gauss–Legendre
//!   nodes split at the critical cosine, integrated into R(τ) and E_esc(τ) at each depth node and
//!   normalised by ⟨T_int⟩ (see the table docs for why).
//!
//! Smooth columns (α < 10⁻³, as in the reference) and η = 1 (no interface) are exact: Fresnel's
//! equations. Cosine axes start at μ = [`GRAZING_COSINE`], where the lobes clamp their cosines.

pub mod glossy;
mod interface;
pub use interface::{Family, coat_lobe, dielectric_lobe};
mod scale;

use glam::DVec3;
use glazec::math::sampling::direction_at_cosine;
use rayon::prelude::*;

use crate::accuracy::quadrature::directional_albedo_f64;
use crate::reference::microsurface::{self, RoughDielectric};
use crate::reference::{Ndf, Rng, fresnel_dielectric};
use glazec::math::quadrature::gauss_legendre_16;
use glazec::math::tables::{Axis, TableId, TableSpec};
use interface::{SMOOTH_ALPHA, single_scattering_albedo};

/// The smallest cosine any node is evaluated at (the first node of a cosine axis; μ = 0 itself
/// is degenerate): the lobes' clamp.
pub const GRAZING_COSINE: f64 = glazec::math::tables::COSINE_FLOOR;

/// What generation measured about its own consistency.
#[derive(Clone, Copy, Debug, Default)]
pub struct Report {
    /// Largest |η²⟨T_int⟩ − ⟨T⟩| over rough columns: the flux identity between the walks from
    /// inside and the external transmittance (a check of the walks; the normalised slab tables
    /// do not depend on it).
    pub max_flux_identity_error: f64,
    /// Largest deviation of the walks' single-event reflection share from the quadrature E_ss,
    /// in standard errors (a check of both).
    pub max_single_event_sigma: f64,
    /// Largest |A/(E_ss + E_ms) − 1| of the scaled coat lobe at the scale table's nodes once
    /// solved, and the range of c.
    pub max_scale_miss: f64,
    pub scale_range: (f64, f64),
    /// Largest amount by which the interpolated deficit exceeded the true one (of the scaled
    /// lobe) between its nodes before generation lowered them.
    pub max_deficit_excess: f64,
    /// What the glossy level's tables measured about themselves.
    pub glossy: glossy::GlossyReport,
}

/// One column of a table (every node along its first axis) at an (r, η) node pair.
enum Column {
    /// `scale` is `None` for a family without a scale table.
    ScaleAndSlab {
        scale: Option<Vec<f64>>,
        miss: f64,
        returned: Vec<f64>,
        escape: Vec<f64>,
        identity_error: f64,
        sigma: f64,
    },
    Path {
        values: Vec<f64>,
    },
}

/// A column to compute: the family (its place in [`Family::ALL`]) and the (r, η) node.
#[derive(Clone, Copy)]
enum Job {
    ScaleAndSlab(usize, usize, usize),
    Path(usize, usize, usize),
}

/// Computes every table. `walks` microsurface walks per rough entry, `glossy_walks` white walks
/// per node of the glossy level's tables; `progress(done, total)`.
pub fn generate(walks: u32, glossy_walks: u32, progress: &(dyn Fn(usize, usize) + Sync)) -> (Vec<Vec<f32>>, Report) {
    let dims = |id: TableId| -> Vec<usize> { id.spec().axes.iter().map(|&(_, n)| n).collect() };
    // GGX's jobs first, in the order they had before GTR1 had tables, so that their seeds (the
    // job's index) and so their tables are unchanged.
    let mut jobs = Vec::new();
    let mut deficit_columns = 0;
    for (f, family) in Family::ALL.iter().enumerate() {
        let (path, slab) = (dims(family.tables.path), dims(family.tables.slab_return));
        if let Some(scale) = family.tables.scale.map(dims) {
            assert_eq!(
                (scale[1], scale[2]),
                (slab[1], slab[2]),
                "the scale and the slab tables share their (r, η) nodes"
            );
        }
        for e in 0..slab[2] {
            jobs.extend((0..slab[1]).map(|r| Job::ScaleAndSlab(f, r, e)));
        }
        for e in 0..path[2] {
            jobs.extend((0..path[1]).map(|r| Job::Path(f, r, e)));
        }
        let deficit = dims(family.tables.deficit);
        deficit_columns += deficit[1] * deficit[2];
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    let total = jobs.len() + deficit_columns;
    let tick = || progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1, total);
    let run = |k: usize| {
        let seed = k as u64;
        match jobs[k] {
            Job::ScaleAndSlab(f, r, e) => {
                let family = Family::ALL[f];
                let slab = dims(family.tables.slab_return);
                let (roughness, eta) = (Axis::Roughness.node(r, slab[1]), Axis::Ior.node(e, slab[2]));
                // Without a scale table the walks from outside only check the flux identity, at
                // as many cosines as GGX's scale has.
                let (n_mu, scaled) = match family.tables.scale {
                    Some(id) => (dims(id)[0], true),
                    None => (dims(TableId::CoatScale)[0], false),
                };
                scale_and_slab_column(roughness, eta, n_mu, scaled, slab[0], walks, seed, family.ndf)
            }
            Job::Path(f, r, e) => {
                let family = Family::ALL[f];
                let path = dims(family.tables.path);
                let (roughness, eta) = (Axis::Roughness.node(r, path[1]), Axis::Ior.node(e, path[2]));
                path_column(roughness, eta, path[0], walks, seed, family.ndf)
            }
        }
    };
    let results = crate::parallel_map(jobs.len(), run, |_| tick());
    let mut tables: Vec<Vec<f32>> = TableId::ALL.iter().map(|id| vec![0.0; id.spec().len()]).collect();
    let mut report = Report { scale_range: (f64::INFINITY, 0.0), ..Report::default() };
    for (job, column) in jobs.iter().zip(results) {
        match (*job, column) {
            (
                Job::ScaleAndSlab(f, r, e),
                Column::ScaleAndSlab { scale: values, miss, returned, escape, identity_error, sigma },
            ) => {
                let family = Family::ALL[f];
                let col = r + dims(family.tables.slab_return)[1] * e;
                put(&mut tables, family.tables.slab_return, col, &returned);
                put(&mut tables, family.tables.slab_escape, col, &escape);
                if let (Some(id), Some(values)) = (family.tables.scale, values) {
                    put(&mut tables, id, col, &values);
                    report.max_scale_miss = report.max_scale_miss.max(miss);
                    let (lo, hi) = report.scale_range;
                    report.scale_range = values.iter().fold((lo, hi), |(lo, hi), &c| (lo.min(c), hi.max(c)));
                }
                report.max_flux_identity_error = report.max_flux_identity_error.max(identity_error);
                report.max_single_event_sigma = report.max_single_event_sigma.max(sigma);
            }
            (Job::Path(f, r, e), Column::Path { values }) => {
                let family = Family::ALL[f];
                put(&mut tables, family.tables.path, r + dims(family.tables.path)[1] * e, &values);
            }
            _ => unreachable!("each job yields its own kind of column"),
        }
    }
    let n_eta = TableId::FresnelTransmitAvg.spec().axes[0].1;
    let fresnel: Vec<f64> = (0..n_eta).map(|e| smooth_transmission_average(Axis::Ior.node(e, n_eta))).collect();
    put(&mut tables, TableId::FresnelTransmitAvg, 0, &fresnel);
    let n_eta = TableId::EonEscapeShape.spec().axes[0].1;
    let shape: Vec<f64> = (0..n_eta)
        .map(|e| f64::from(glazec::math::terms::eon_escape_shape_exact::<f32>(Axis::Ior.node(e, n_eta) as f32)))
        .collect();
    put(&mut tables, TableId::EonEscapeShape, 0, &shape);
    // The deficit of the scaled lobe, through the lookups of c as stored.
    glazec::math::tables::evaluate_on_cpu_with(&tables);
    for family in Family::ALL {
        let deficit = dims(family.tables.deficit);
        let columns = crate::parallel_map(
            deficit[1] * deficit[2],
            |k| {
                let (roughness, eta) =
                    (Axis::Roughness.node(k % deficit[1], deficit[1]), Axis::Ior.node(k / deficit[1], deficit[2]));
                (0..deficit[0])
                    .map(|i| deficit_at(Axis::Cosine.node(i, deficit[0]), roughness, eta, family).unwrap_or(0.0))
                    .collect::<Vec<_>>()
            },
            |_| tick(),
        );
        for (k, values) in columns.iter().enumerate() {
            put(&mut tables, family.tables.deficit, k, values);
        }
        let excess = make_deficit_conservative(&mut tables[family.tables.deficit as usize], &deficit, family);
        report.max_deficit_excess = report.max_deficit_excess.max(excess);
        let columns = tables[family.tables.deficit as usize].chunks(deficit[0]);
        let averages: Vec<f32> =
            columns.map(|c| curve_average(&c.iter().map(|&v| f64::from(v)).collect::<Vec<_>>()) as f32).collect();
        tables[family.tables.deficit_avg as usize] = averages;
    }
    let (albedo, average) = ggx_albedo(TableId::GgxAlbedo.spec());
    tables[TableId::GgxAlbedo as usize] = albedo;
    tables[TableId::GgxAlbedoAvg as usize] = average;
    for (lobe, scale, bias) in [
        (SeedLobe::Ggx, TableId::SeedGgxDfgScale, TableId::SeedGgxDfgBias),
        (SeedLobe::Clearcoat, TableId::ClearcoatDfgScale, TableId::ClearcoatDfgBias),
    ] {
        let (a, b) = seed_dfg(lobe, scale.spec());
        tables[scale as usize] = a;
        tables[bias as usize] = b;
    }
    report.glossy = glossy::generate(&mut tables, glossy_walks, progress);
    (tables, report)
}

/// Stores `values` as column `column` of table `id` (columns of `values.len()` entries).
fn put(tables: &mut [Vec<f32>], id: TableId, column: usize, values: &[f64]) {
    let n = values.len();
    for (i, v) in values.iter().enumerate() {
        tables[id as usize][i + n * column] = *v as f32;
    }
}

/// Only the glossy level's tables, every other table taken from `existing` (values per table
/// in `SPECS` order, as `math::tables::decode_by_name` reads them from a table file; a full
/// generation reproduces them exactly, its walks being seeded by their nodes).
///
/// # Errors
/// A table other than the glossy level's is missing from `existing`.
pub fn generate_glossy_only(
    existing: Vec<Option<Vec<f32>>>,
    glossy_walks: u32,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(Vec<Vec<f32>>, Report), String> {
    let mut tables = Vec::new();
    for (id, values) in TableId::ALL.iter().zip(existing) {
        match values {
            Some(values) => tables.push(values),
            None if id.is_glossy() => tables.push(vec![0.0; id.spec().len()]),
            None => return Err(format!("the table file has no {} table; run a full `glazec tables`", id.spec().name)),
        }
    }
    let glossy = glossy::generate(&mut tables, glossy_walks, progress);
    Ok((tables, Report { glossy, ..Report::default() }))
}

/// The seed's coat lobes (`Lobe::Ggx` and the Disney clear coat's `Lobe::Gtr1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeedLobe {
    Ggx,
    Clearcoat,
}

impl SeedLobe {
    fn at(self, roughness: f64) -> glazec::model::Lobe {
        let roughness = glazec::model::Scalar::Lit(roughness as f32);
        match self {
            SeedLobe::Ggx => glazec::model::Lobe::Ggx { roughness },
            SeedLobe::Clearcoat => glazec::model::Lobe::Gtr1 { roughness },
        }
    }
}

/// The split-sum DFG (Karis 2013) of a seed coat lobe at cosine `mu` and roughness `roughness`:
/// (A, B) with the lobe's directional albedo F0·A + B under Schlick's Fresnel, by quadrature of
/// the lobe itself as the shaders evaluate it (`layering::seed_lobe_white`, the shared terms):
/// A = ∫ f (1 − (1 − v·h)⁵) cos θl, B = ∫ f (1 − v·h)⁵ cos θl. Not the reference's: these tables
/// describe the seed's lobe, whatever its physics, so that image-based lighting weighs it by its
/// own albedo.
pub fn seed_dfg_at(lobe: SeedLobe, mu: f64, roughness: f64) -> (f64, f64) {
    let model = lobe.at(roughness);
    let wo = direction_at_cosine(mu.max(GRAZING_COSINE));
    let alpha = (roughness * roughness).max(SMOOTH_ALPHA);
    let (mut a, mut b) = (0.0, 0.0);
    for (wi, weight) in crate::accuracy::quadrature::albedo_nodes(wo, alpha) {
        let (v, l) = (wo.as_vec3(), wi.as_vec3());
        let f = f64::from(glazec::math::layering::seed_lobe_white(&model, glam::Vec3::Z, v, l));
        let h = (v + l).normalize();
        // Schlick's (1 − v·h)⁵: the shared term at F0 = 0.
        let bias = f64::from(glazec::math::terms::f_schlick::<f32>(glam::Vec3::ZERO, v.dot(h)).x);
        a += weight * f * (1.0 - bias);
        b += weight * f * bias;
    }
    (a, b)
}

/// Both DFG tables of a seed lobe on the grid of `spec` (μ fastest, then r).
fn seed_dfg(lobe: SeedLobe, spec: &TableSpec) -> (Vec<f32>, Vec<f32>) {
    let (n_mu, n_r) = (spec.axes[0].1, spec.axes[1].1);
    let nodes: Vec<(f64, f64)> = (0..n_r)
        .flat_map(|j| (0..n_mu).map(move |i| (Axis::Cosine.node(i, n_mu), Axis::Roughness.node(j, n_r))))
        .collect();
    let values: Vec<_> = nodes.par_iter().map(|&(mu, r)| seed_dfg_at(lobe, mu, r)).collect();
    values.into_iter().map(|(a, b)| (a as f32, b as f32)).unzip()
}

/// What a microsurface's walks from one direction show.
struct Walks {
    /// Share reflected after a single event.
    single: f64,
    /// Share reflected after two or more events.
    multiple: f64,
    /// Geometric mean cosine of the transmitted directions (0 if none crossed).
    transmitted_cosine: f64,
}

fn walk(mu: f64, eta: f64, alpha: f64, walks: u32, seed: u64, ndf: Ndf) -> Walks {
    let surface = RoughDielectric { eta, alpha, ndf };
    let mut rng = Rng::seeded(seed);
    let (mut multiple, mut first, mut crossed, mut log_cosine) = (0u64, 0u64, 0u64, 0.0);
    for _ in 0..walks {
        let (out, events) = surface.walk(direction_at_cosine(mu), &mut rng);
        if out.z > 0.0 {
            if events >= 2 {
                multiple += 1;
            } else {
                first += 1;
            }
        } else {
            crossed += 1;
            log_cosine += (-out.z).max(1e-9).ln();
        }
    }
    let n = f64::from(walks.max(1));
    let transmitted_cosine = if crossed > 0 { (log_cosine / crossed as f64).exp() } else { 0.0 };
    Walks { single: first as f64 / n, multiple: multiple as f64 / n, transmitted_cosine }
}

/// |walk single-event share − quadrature| in standard errors.
fn sigma(walks: &Walks, single: f64, n: u32) -> f64 {
    let std_err = (single * (1.0 - single) / f64::from(n.max(1))).sqrt().max(1e-12);
    (walks.single - single).abs() / std_err
}

/// The scale column at the nodes of its cosine axis (`n_mu`) and the slab column at the nodes
/// of its depth axis (`n_tau`), at one (r, η) node: the walks from outside give E_ms (the
/// scale's target, with E_ss) and the transmitted share (the flux identity's check), those from
/// inside the slab's internal reflection.
#[allow(clippy::too_many_arguments)]
fn scale_and_slab_column(
    roughness: f64,
    eta: f64,
    n_mu: usize,
    scaled: bool,
    n_tau: usize,
    walks: u32,
    seed: u64,
    ndf: Ndf,
) -> Column {
    let alpha = roughness * roughness;
    // Below α = 10⁻³ the reference treats an interface as smooth (pbrt's `EffectivelySmooth`),
    // and so do the tables.
    let smooth = alpha < SMOOTH_ALPHA || eta == 1.0;
    let mut worst_sigma = 0.0_f64;
    let cosines: Vec<f64> = (0..n_mu).map(|i| Axis::Cosine.node(i, n_mu).max(GRAZING_COSINE)).collect();
    let (mut targets, mut outer_transmit) = (Vec::new(), Vec::new());
    if !smooth {
        for (i, &mu) in cosines.iter().enumerate() {
            let single = single_scattering_albedo(mu, eta, alpha, ndf);
            let w = walk(mu, eta, alpha, walks, seed << 20 | i as u64, ndf);
            worst_sigma = worst_sigma.max(sigma(&w, single, walks));
            targets.push(single + w.multiple);
            outer_transmit.push(1.0 - w.single - w.multiple);
        }
    }
    let (scale, miss) = match (scaled, smooth) {
        (false, _) => (None, 0.0),
        (true, true) => (Some(vec![1.0; n_mu]), 0.0),
        (true, false) => {
            let (scale, miss) = scale::scale_column(roughness, eta, &cosines, &targets, ndf);
            (Some(scale), miss)
        }
    };
    // Inside: relative IOR 1/η, 32 Gauss–Legendre nodes split at the critical cosine.
    let mu_c = (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt();
    let gl = gauss_legendre_16();
    let mut nodes = Vec::new(); // (μ, weight of ∫ … dμ)
    if mu_c > 0.0 {
        nodes.extend(gl.iter().map(|&(t, w)| (mu_c * t * t, w * 2.0 * mu_c * t)));
    }
    nodes.extend(gl.iter().map(|&(s, w)| (mu_c + (1.0 - mu_c) * s * s, w * 2.0 * (1.0 - mu_c) * s)));
    let inner_reflect: Vec<f64> = nodes
        .iter()
        .enumerate()
        .map(|(k, &(mu, _))| {
            if smooth {
                return fresnel_dielectric(mu, 1.0 / eta);
            }
            let single = single_scattering_albedo(mu, 1.0 / eta, alpha, ndf);
            let w = walk(mu, 1.0 / eta, alpha, walks, seed << 20 | 1 << 19 | k as u64, ndf);
            worst_sigma = worst_sigma.max(sigma(&w, single, walks));
            (single + w.multiple).min(1.0)
        })
        .collect();
    let integral = |f: &dyn Fn(f64, f64) -> f64| -> f64 {
        nodes.iter().zip(&inner_reflect).map(|(&(mu, w), &r)| w * 2.0 * mu * f(mu, r)).sum()
    };
    let inner_transmit = integral(&|_, r| 1.0 - r);
    let mut returned = Vec::new();
    let mut escape = Vec::new();
    for i in 0..n_tau {
        let tau = Axis::Depth.node(i, n_tau);
        let (r, e) = if tau.is_finite() {
            (integral(&|mu, r| (-2.0 * tau / mu).exp() * r), integral(&|mu, r| (-tau / mu).exp() * (1.0 - r)))
        } else {
            (0.0, 0.0)
        };
        returned.push((1.0 - r) / inner_transmit);
        escape.push(e / inner_transmit);
    }
    // The flux identity η²⟨T_int⟩ = ⟨T⟩ checks the walks from inside against those from outside.
    let identity_error = if smooth { 0.0 } else { (eta * eta * inner_transmit - curve_average(&outer_transmit)).abs() };
    Column::ScaleAndSlab { scale, miss, returned, escape, identity_error, sigma: worst_sigma }
}

fn path_column(roughness: f64, eta: f64, n_mu: usize, walks: u32, seed: u64, ndf: Ndf) -> Column {
    let alpha = roughness * roughness;
    let values = (0..n_mu)
        .map(|i| {
            if alpha < SMOOTH_ALPHA || eta == 1.0 {
                return 1.0;
            }
            let mu = Axis::Cosine.node(i, n_mu).max(GRAZING_COSINE);
            let w = walk(mu, eta, alpha, walks, seed << 20 | 1 << 18 | i as u64, ndf);
            // Paths through the slab are longer by μ′/μ_eff than along Snell's direction.
            if w.transmitted_cosine > 0.0 { refracted_cosine(mu, eta) / w.transmitted_cosine } else { 1.0 }
        })
        .collect();
    Column::Path { values }
}

/// Snell's cosine inside a coat of relative IOR η for light arriving at cosine μ.
fn refracted_cosine(mu: f64, eta: f64) -> f64 {
    (1.0 - (1.0 - mu * mu) / (eta * eta)).max(0.0).sqrt()
}

/// ∫₀¹ 2μ (1 − F(μ)) dμ for a smooth interface seen from outside (Gauss–Legendre on 16 cells in
/// u = √μ; the integrand is smooth there).
fn smooth_transmission_average(eta: f64) -> f64 {
    let gl = gauss_legendre_16();
    let cells = 16;
    let mut total = 0.0;
    for c in 0..cells {
        for &(x, w) in &gl {
            let u = (c as f64 + x) / cells as f64;
            let mu = u * u;
            total += w / cells as f64 * 4.0 * u * u * u * (1.0 - fresnel_dielectric(mu, eta));
        }
    }
    total
}

/// Where [`make_deficit_conservative`] compares the table with the true deficit inside each
/// cell, in node units along the cosine and roughness axes, and along the IOR axis.
const DEFICIT_PROBES: [f64; 3] = [0.25, 0.5, 0.75];
const DEFICIT_PROBES_IOR: [f64; 4] = [0.0, 0.25, 0.5, 0.75];

/// The deficit G(μ) = F(μ) − A(μ) at any argument, A the scaled lobe's albedo through the
/// lookups of c (0 for η = 1, no interface); `None` below [`SMOOTH_ALPHA`], where the nodes hold
/// the smooth interface's 0 and the quadrature does not resolve the lobe.
fn deficit_at(mu: f64, roughness: f64, eta: f64, family: Family) -> Option<f64> {
    let alpha = roughness * roughness;
    if alpha < SMOOTH_ALPHA {
        return None;
    }
    if eta == 1.0 {
        return Some(0.0);
    }
    let mu = mu.max(GRAZING_COSINE);
    Some(fresnel_dielectric(mu, eta) - scale::scaled_albedo(mu, roughness, eta, family))
}

/// Makes the deficit table never overestimate: the transmission T = 1 − F + G must not exceed
/// what the scaled lobe beside it leaves (1 − A), or a white stack reflects more than it
/// receives. Near grazing incidence, where α ≈ μ, G bends sharply between nodes and the
/// multilinear lookup overshoots it by up to 3·10⁻³ (the energy gains in docs/stability.md).
/// Each cell is probed at [`DEFICIT_PROBES`] ×
fn make_deficit_conservative(table: &mut [f32], dims: &[usize], family: Family) -> f64 {
    let (n_mu, n_r, n_eta) = (dims[0], dims[1], dims[2]);
    let index = |i: usize, j: usize, k: usize| i + n_mu * (j + n_r * k);
    let cells: Vec<(usize, usize, usize)> =
        (0..n_eta - 1).flat_map(|k| (0..n_r - 1).flat_map(move |j| (0..n_mu - 1).map(move |i| (i, j, k)))).collect();
    let snapshot: Vec<f64> = table.iter().map(|&v| f64::from(v)).collect();
    let overshoot_of = |&(i, j, k): &(usize, usize, usize)| -> f64 {
        let mut worst: f64 = 0.0;
        for &se in &DEFICIT_PROBES_IOR {
            for &sr in &DEFICIT_PROBES {
                for &sm in &DEFICIT_PROBES {
                    let mut interpolated = 0.0;
                    for corner in 0..8 {
                        let (di, dj, dk) = (corner & 1, (corner >> 1) & 1, corner >> 2);
                        let w = (if di == 1 { sm } else { 1.0 - sm })
                            * (if dj == 1 { sr } else { 1.0 - sr })
                            * (if dk == 1 { se } else { 1.0 - se });
                        interpolated += w * snapshot[index(i + di, j + dj, k + dk)];
                    }
                    let truth = deficit_at(
                        Axis::Cosine.argument(i as f64 + sm, n_mu),
                        Axis::Roughness.argument(j as f64 + sr, n_r),
                        Axis::Ior.argument(k as f64 + se, n_eta),
                        family,
                    );
                    if let Some(truth) = truth {
                        worst = worst.max(interpolated - truth);
                    }
                }
            }
        }
        worst
    };
    let overshoots: Vec<_> = cells.par_iter().map(overshoot_of).collect();
    let mut lower = vec![0.0_f64; table.len()];
    for (&(i, j, k), &o) in cells.iter().zip(&overshoots) {
        for corner in 0..8 {
            let at = index(i + (corner & 1), j + ((corner >> 1) & 1), k + (corner >> 2));
            lower[at] = lower[at].max(o);
        }
    }
    for (value, l) in table.iter_mut().zip(&lower) {
        // Rounded down to f32, so that the stored node stays at or below the lowered value.
        let lowered = f64::from(*value) - l;
        let mut stored = lowered as f32;
        if f64::from(stored) > lowered {
            stored = f32::from_bits(if stored > 0.0 { stored.to_bits() - 1 } else { stored.to_bits() + 1 });
        }
        *value = stored;
    }
    overshoots.into_iter().fold(0.0, f64::max)
}

/// ∫₀¹ 2μ c(μ) dμ for a curve stored at the nodes of a cosine axis and interpolated linearly
/// in its coordinate u, as the lookups do. With μ^¼ = a + b u (a = μ₀^¼, b = 1 − a; see
/// [`Axis::Cosine`]) the integral over the nodes is ∫₀¹ 8b (a + bu)⁷ c(u) du, a polynomial of
/// degree 8 per cell, so 16-point Gauss–Legendre is exact; below μ₀ the lookups hold the first
/// node's value, which adds μ₀² c₀.
fn curve_average(values: &[f64]) -> f64 {
    let a = f64::from(glazec::math::tables::COSINE_FLOOR_ROOT);
    let b = 1.0 - a;
    let n = values.len();
    let h = 1.0 / (n - 1) as f64;
    let mut total = GRAZING_COSINE * GRAZING_COSINE * values[0];
    for i in 0..n - 1 {
        for (x, w) in gauss_legendre_16() {
            let root = a + b * (i as f64 + x) * h;
            let c = values[i] + (values[i + 1] - values[i]) * x;
            total += w * h * 8.0 * b * root.powi(7) * c;
        }
    }
    total
}

/// The white single-scattering GGX albedo E(μ; r) and its average ⟨E⟩(r).
fn ggx_albedo(spec: &TableSpec) -> (Vec<f32>, Vec<f32>) {
    let (n_mu, n_r) = (spec.axes[0].1, spec.axes[1].1);
    // Layout: μ fastest, then r.
    let mut table = Vec::new();
    let mut average = Vec::new();
    let mut columns = vec![Vec::new(); n_r];
    for (j, column) in columns.iter_mut().enumerate() {
        let roughness = Axis::Roughness.node(j, n_r);
        let alpha = roughness * roughness;
        for i in 0..n_mu {
            let mu = Axis::Cosine.node(i, n_mu);
            let e = if alpha < SMOOTH_ALPHA {
                1.0
            } else {
                let lobe = |wi: DVec3, wo: DVec3| {
                    if wi.z <= 0.0 || wo.z <= 0.0 {
                        return DVec3::ZERO;
                    }
                    let h = (wi + wo).normalize();
                    DVec3::splat(microsurface::ggx_d(h, alpha) * microsurface::g2(wi, wo, alpha) / (4.0 * wi.z * wo.z))
                };
                directional_albedo_f64(&lobe, direction_at_cosine(mu.max(GRAZING_COSINE)), alpha).x.min(1.0)
            };
            column.push(e);
        }
    }
    for column in &columns {
        average.push(curve_average(column) as f32);
        table.extend(column.iter().map(|&e| e as f32));
    }
    (table, average)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glazec::math::tables::lookup;

    /// Largest error of a seed lobe's DFG lookup against its quadrature between nodes (A and B
    /// of an albedo within [0, 1.9]; multilinear interpolation of a 32 × 32 grid). Measured:
    /// 4.6·10⁻³ for the clear coat's A at r = 0.03 near grazing, ≤ 1.3·10⁻³ for the GGX lobe.
    const DFG_TOLERANCE: f32 = 5e-3;

    #[test]
    fn seed_dfg_tables_match_their_quadrature_between_nodes() {
        let mut worst = 0.0_f32;
        for (lobe, scale, bias) in [
            (SeedLobe::Ggx, TableId::SeedGgxDfgScale, TableId::SeedGgxDfgBias),
            (SeedLobe::Clearcoat, TableId::ClearcoatDfgScale, TableId::ClearcoatDfgBias),
        ] {
            for mu in [0.013_f32, 0.07, 0.23, 0.5, 0.81, 0.97] {
                for r in [0.03_f32, 0.14, 0.33, 0.6, 0.9] {
                    let (a, b) = seed_dfg_at(lobe, f64::from(mu), f64::from(r));
                    let (ta, tb) = (lookup::<f32>(scale, &[mu, r]), lookup::<f32>(bias, &[mu, r]));
                    worst = worst.max((ta - a as f32).abs()).max((tb - b as f32).abs());
                    assert!((ta - a as f32).abs() < DFG_TOLERANCE, "{lobe:?} A at μ {mu}, r {r}: {ta} vs {a}");
                    assert!((tb - b as f32).abs() < DFG_TOLERANCE, "{lobe:?} B at μ {mu}, r {r}: {tb} vs {b}");
                }
            }
        }
        eprintln!("seed DFG tables: largest error between nodes {worst:.1e}");
    }
}
