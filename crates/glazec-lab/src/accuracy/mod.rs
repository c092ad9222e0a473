//! Accuracy: the compiled methods measured against the stochastic reference, and the BRDF laws.
//!
//! **Input:** an evaluation set of single-coat materials ([`standard_set`]: coat IOR × coat
//! roughness × base × optical depth; docs/derivations.md, "Accuracy targets"), a direction grid,
//! and the reference's values on it ([`ReferenceData`], computed once by
//! `glazec accuracy --regenerate-reference` and stored in `data/reference/`).
//! **Output:** per method and case, [`Metrics`]: the cosine-weighted relative RMSE of the
//! under-coat lobe (f minus the coat's own reflection), the largest directional-albedo error,
//! the largest reciprocity error and the largest albedo; and per method, the [`Laws`] table.
//!
//! The compiled side is the CPU evaluation of the shared math (`glazec::eval`), which the GPU
//! agreement tests tie to every shader language; the albedos are deterministic quadratures
//! ([`quadrature`]). The reference side is Monte Carlo with a stated standard error.

pub mod full;
pub mod quadrature;
pub mod stated;

use std::io::Read;
use std::path::{Path, PathBuf};

use glam::DVec3;
use glazec::math::sampling::direction_deg;

use crate::reference::{self, InterfaceMode, Stack};
use glazec::model::{Base, Coat, Color, ConductorFresnel, Lobe, Material, Method, Scalar};

/// Polar angles (degrees) of the BRDF grid, for both θi and θo.
pub const GRID_THETAS: [f64; 8] = [5.0, 15.0, 25.0, 35.0, 45.0, 55.0, 65.0, 75.0];
/// Relative azimuths (degrees) of the BRDF grid.
pub const GRID_PHIS: [f64; 5] = [0.0, 45.0, 90.0, 135.0, 180.0];
/// Polar angles (degrees) of the directional albedos.
pub const ALBEDO_THETAS: [f64; 5] = [0.0, 30.0, 60.0, 75.0, 85.0];

/// The bases of the evaluation set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BaseKind {
    Lambert(f32),
    /// EON with ρ = 0.8, r = 1.
    Eon,
    /// Copper (complex IOR at R, G, B), roughness 0.3.
    Copper,
}

/// One material of the evaluation set: a single coat over a base.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub ior: f32,
    pub roughness: f32,
    pub base: BaseKind,
    /// Optical depth τ = σa·d of the coat's slab (grey).
    pub tau: f32,
}

impl Case {
    pub fn label(&self) -> String {
        let base = match self.base {
            BaseKind::Lambert(rho) => format!("Lambert {rho}"),
            BaseKind::Eon => "EON 0.8".to_string(),
            BaseKind::Copper => "copper".to_string(),
        };
        format!("η {} r {} {base} τ {}", self.ior, self.roughness, self.tau)
    }

    /// The case as a material of the given method (`black_base`: the coat alone over black).
    pub fn material(&self, method: Method, black_base: bool) -> Material {
        let lobe =
            if self.roughness == 0.0 { Lobe::Smooth } else { Lobe::Ggx { roughness: Scalar::Lit(self.roughness) } };
        let coat = Coat {
            lobe,
            ior: Scalar::Lit(self.ior),
            absorption: Color::Lit([self.tau; 3]),
            thickness: Scalar::Lit(1.0),
        };
        let base = if black_base {
            Base::Lambert { albedo: Color::Lit([0.0; 3]) }
        } else {
            match self.base {
                BaseKind::Lambert(rho) => Base::Lambert { albedo: Color::Lit([rho; 3]) },
                BaseKind::Eon => Base::Eon { albedo: Color::Lit([0.8; 3]), roughness: Scalar::Lit(1.0) },
                BaseKind::Copper => Base::Conductor {
                    roughness: Scalar::Lit(0.3),
                    fresnel: ConductorFresnel::Complex {
                        eta: Color::Lit([0.27, 0.68, 1.22]),
                        k: Color::Lit([3.61, 2.63, 2.29]),
                    },
                },
            }
        };
        Material { name: "case".into(), method, coats: vec![coat], base, params: vec![], normals: vec![] }
    }

    /// The smallest GGX α among the case's lobes (for the albedo quadrature).
    pub fn sharpest_alpha(&self) -> f64 {
        let coat = if self.roughness > 0.0 { f64::from(self.roughness).powi(2) } else { 1.0 };
        let base = if self.base == BaseKind::Copper { 0.09 } else { 1.0 };
        coat.min(base)
    }
}

/// The standard evaluation set: η ∈ {1.33, 1.5, 2}, roughness ∈ {0, 0.05, 0.2, 0.5}, bases
/// Lambert ρ ∈ {0.2, 0.8, 1}, EON, copper; τ ∈ {0, 0.5}: 120 materials.
pub fn standard_set() -> Vec<Case> {
    let mut cases = Vec::new();
    for ior in [1.33, 1.5, 2.0] {
        for roughness in [0.0, 0.05, 0.2, 0.5] {
            for base in [
                BaseKind::Lambert(0.2),
                BaseKind::Lambert(0.8),
                BaseKind::Lambert(1.0),
                BaseKind::Eon,
                BaseKind::Copper,
            ] {
                for tau in [0.0, 0.5] {
                    cases.push(Case { ior, roughness, base, tau });
                }
            }
        }
    }
    cases
}

/// The BRDF grid: (wi, wo) for every θi, θo and Δφ (320 pairs).
pub fn grid() -> Vec<(DVec3, DVec3)> {
    let mut pairs = Vec::new();
    for ti in GRID_THETAS {
        for to in GRID_THETAS {
            for phi in GRID_PHIS {
                pairs.push((direction_deg(ti, 0.0), direction_deg(to, phi)));
            }
        }
    }
    pairs
}

/// The reference's values on the grid for every case of a set.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceData {
    pub mode: InterfaceMode,
    pub samples: u32,
    pub walks: u32,
    /// Per case: the under-coat lobe on the grid.
    pub under: Vec<Vec<DVec3>>,
    /// Per case: the directional albedo at [`ALBEDO_THETAS`].
    pub albedo: Vec<Vec<DVec3>>,
    /// Per case: the relative standard error of the under-coat lobe (RMS over the grid).
    pub noise: Vec<f64>,
}

/// A stored reference file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    #[error(transparent)]
    Io(#[from] std::io::Error),
    #[error("{0}")]
    Format(String),
}

const MAGIC: &[u8; 8] = b"GLAZREF1";

impl ReferenceData {
    /// Computes the reference for a set, spreading cases over the available cores.
    pub fn compute(
        cases: &[Case],
        mode: InterfaceMode,
        samples: u32,
        walks: u32,
        progress: &(dyn Fn(usize) + Sync),
    ) -> ReferenceData {
        let pairs = grid();
        let compute_case = |i: usize| {
            let stack = Stack::from_material(&cases[i].material(Method::INTERFACED, false), &[]);
            let f_opts = reference::Options { mode, samples, seed: i as u64, ..Default::default() };
            let a_opts = reference::Options { mode, samples: walks, seed: i as u64, ..Default::default() };
            let estimates: Vec<_> = pairs.iter().map(|(wi, wo)| stack.f_under(*wi, *wo, &f_opts)).collect();
            let (mut sq_err, mut sq_val) = (0.0, 0.0);
            for ((wi, wo), e) in pairs.iter().zip(&estimates) {
                let w = wi.z * wo.z;
                sq_err += w * e.std_err.length_squared();
                sq_val += w * e.mean.length_squared();
            }
            let under = estimates.iter().map(|e| e.mean).collect();
            let noise = if sq_val > 0.0 { (sq_err / sq_val).sqrt() } else { 0.0 };
            let albedo = ALBEDO_THETAS.iter().map(|&t| stack.albedo(direction_deg(t, 0.0), &a_opts).mean).collect();
            (under, albedo, noise)
        };
        let results = crate::parallel_map(cases.len(), compute_case, progress);
        let (mut under, mut albedo, mut noise) = (Vec::new(), Vec::new(), Vec::new());
        for (u, a, n) in results {
            under.push(u);
            albedo.push(a);
            noise.push(n);
        }
        ReferenceData { mode, samples, walks, under, albedo, noise }
    }

    /// Little-endian binary: magic, mode, samples, walks, case count, then per case the grid
    /// values, the albedos (f32 RGB) and the noise (f32).
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let mut bytes = Vec::new();
        bytes.extend_from_slice(MAGIC);
        bytes.push(match self.mode {
            InterfaceMode::Single => 0,
            InterfaceMode::Multiple => 1,
        });
        for v in [self.samples, self.walks, self.under.len() as u32] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        for ((under, albedo), noise) in self.under.iter().zip(&self.albedo).zip(&self.noise) {
            for v in under.iter().chain(albedo) {
                for x in v.to_array() {
                    bytes.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            bytes.extend_from_slice(&(*noise as f32).to_le_bytes());
        }
        glazec::output::write_all(&[glazec::output::OutputFile { path: path.to_path_buf(), contents: bytes }])
    }

    /// Reads a file written by [`Self::write`] for a set of `cases` cases.
    ///
    /// # Errors
    /// I/O errors, or a file that does not match the set.
    pub fn read(path: &Path, cases: usize) -> Result<ReferenceData, DataError> {
        let mut bytes = Vec::new();
        std::fs::File::open(path)?.read_to_end(&mut bytes)?;
        let bad = |m: &str| DataError::Format(format!("{}: {m}", path.display()));
        if bytes.len() < 21 || &bytes[..8] != MAGIC {
            return Err(bad("not a glazec reference file"));
        }
        let mode = if bytes[8] == 0 { InterfaceMode::Single } else { InterfaceMode::Multiple };
        let word = |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
        let (samples, walks, count) = (word(9), word(13), word(17) as usize);
        let per_case = (grid().len() + ALBEDO_THETAS.len()) * 12 + 4;
        if count != cases || bytes.len() != 21 + count * per_case {
            return Err(bad("size does not match the evaluation set"));
        }
        let float = |at: usize| f64::from(f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]));
        let (mut under, mut albedo, mut noise) = (Vec::new(), Vec::new(), Vec::new());
        for c in 0..count {
            let start = 21 + c * per_case;
            let rgb =
                |i: usize| DVec3::new(float(start + 12 * i), float(start + 12 * i + 4), float(start + 12 * i + 8));
            let n = grid().len();
            under.push((0..n).map(rgb).collect());
            albedo.push((n..n + ALBEDO_THETAS.len()).map(rgb).collect());
            noise.push(float(start + per_case - 4));
        }
        Ok(ReferenceData { mode, samples, walks, under, albedo, noise })
    }
}

/// One method on one case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Cosine-weighted relative RMSE of the under-coat lobe.
    pub lobe_rmse: f64,
    /// Largest |E_method − E_reference| over the albedo angles and channels.
    pub albedo_error: f64,
    /// Largest |f(i,o) − f(o,i)| / max(f(i,o), f(o,i)) over the grid.
    pub reciprocity: f64,
    /// Largest directional albedo of the method over the albedo angles and channels.
    pub energy_max: f64,
    /// Smallest value of f over the grid (non-negativity).
    pub min_value: f64,
    /// The method's directional albedo at [`ALBEDO_THETAS`].
    pub albedos: [DVec3; ALBEDO_THETAS.len()],
}

/// Which material of a case an evaluator is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// The case as it is.
    Full,
    /// The coat over a black base: subtracted from the full material to get the under-coat lobe.
    CoatOnly,
}

/// Evaluates f (without the cosine) of a case's material at a batch of (wi, wo) pairs: the CPU
/// ([`cpu_evaluator`]) or a shader on a GPU.
pub type Evaluator<'a> = dyn FnMut(Variant, &[(DVec3, DVec3)]) -> Vec<DVec3> + 'a;

/// The CPU evaluation of the shared math for a case and method.
pub fn cpu_evaluator(case: &Case, method: Method) -> impl FnMut(Variant, &[(DVec3, DVec3)]) -> Vec<DVec3> {
    let full = case.material(method, false);
    let coat_only = case.material(method, true);
    move |variant, pairs| {
        let material = if variant == Variant::Full { &full } else { &coat_only };
        pairs.iter().map(|(wi, wo)| glazec::eval::brdf(material, &[], wi.as_vec3(), wo.as_vec3()).as_dvec3()).collect()
    }
}

fn mirror_albedo(case: &Case, method: Method, wo: DVec3) -> DVec3 {
    glazec::eval::mirror_reflectance(&case.material(method, false), &[], wo.as_vec3()).as_dvec3()
}

/// Measures a method on a case against the reference, on the CPU.
pub fn measure(case: &Case, method: Method, under_ref: &[DVec3], albedo_ref: &[DVec3]) -> Metrics {
    measure_with(case, method, under_ref, albedo_ref, &mut cpu_evaluator(case, method))
}

/// Measures a method on a case against the reference, evaluating f with `eval` (in two
/// batches: the full material on the grid, the reversed grid and every albedo node; the coat
/// alone on the grid).
pub fn measure_with(
    case: &Case,
    method: Method,
    under_ref: &[DVec3],
    albedo_ref: &[DVec3],
    eval: &mut Evaluator<'_>,
) -> Metrics {
    let grid = grid();
    let mut full_pairs = grid.clone();
    full_pairs.extend(grid.iter().map(|&(wi, wo)| (wo, wi)));
    let albedo_nodes: Vec<Vec<(DVec3, f64)>> =
        ALBEDO_THETAS.iter().map(|&t| quadrature::albedo_nodes(direction_deg(t, 0.0), case.sharpest_alpha())).collect();
    for (nodes, &theta) in albedo_nodes.iter().zip(&ALBEDO_THETAS) {
        let wo = direction_deg(theta, 0.0);
        full_pairs.extend(nodes.iter().map(|&(wi, _)| (wi, wo)));
    }
    let full = eval(Variant::Full, &full_pairs);
    let coat = eval(Variant::CoatOnly, &grid);
    let (forward, rest) = full.split_at(grid.len());
    let (reversed, mut albedo_values) = rest.split_at(grid.len());

    let (mut sq_err, mut sq_ref, mut reciprocity, mut min_value) = (0.0, 0.0, 0.0_f64, f64::INFINITY);
    for i in 0..grid.len() {
        let (wi, wo) = grid[i];
        let (f, g) = (forward[i], reversed[i]);
        let under = f - coat[i];
        let w = wi.z * wo.z;
        sq_err += w * (under - under_ref[i]).length_squared();
        sq_ref += w * under_ref[i].length_squared();
        for c in 0..3 {
            let m = f[c].abs().max(g[c].abs());
            if m > 0.0 {
                reciprocity = reciprocity.max((f[c] - g[c]).abs() / m);
            }
        }
        min_value = min_value.min(f.min_element());
    }
    let (mut albedo_error, mut energy_max) = (0.0_f64, 0.0_f64);
    let mut albedos = [DVec3::ZERO; ALBEDO_THETAS.len()];
    for (k, nodes) in albedo_nodes.iter().enumerate() {
        let (values, rest) = albedo_values.split_at(nodes.len());
        albedo_values = rest;
        let wo = direction_deg(ALBEDO_THETAS[k], 0.0);
        let e = nodes.iter().zip(values).map(|(&(_, w), &f)| f * w).sum::<DVec3>() + mirror_albedo(case, method, wo);
        albedo_error = albedo_error.max((e - albedo_ref[k]).abs().max_element());
        energy_max = energy_max.max(e.max_element());
        albedos[k] = e;
    }
    let lobe_rmse = if sq_ref > 0.0 { (sq_err / sq_ref).sqrt() } else { 0.0 };
    Metrics { lobe_rmse, albedo_error, reciprocity, energy_max, min_value, albedos }
}

/// The BRDF laws over a set, for one method: the worst case of each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Laws {
    pub min_value: f64,
    pub reciprocity: f64,
    pub energy_max: f64,
    /// Largest |E − 1| over the white, clear cases (Lambert ρ = 1, τ = 0): the white furnace.
    pub furnace: f64,
}

/// Whether a case is a white furnace: a clear coat over a white Lambert base.
pub fn is_white_furnace(case: &Case) -> bool {
    case.base == BaseKind::Lambert(1.0) && case.tau == 0.0
}

/// Laws from a method's metrics on a set.
pub fn laws(cases: &[Case], metrics: &[Metrics]) -> Laws {
    let mut laws = Laws { min_value: f64::INFINITY, reciprocity: 0.0, energy_max: 0.0, furnace: 0.0 };
    for (case, m) in cases.iter().zip(metrics) {
        laws.min_value = laws.min_value.min(m.min_value);
        laws.reciprocity = laws.reciprocity.max(m.reciprocity);
        laws.energy_max = laws.energy_max.max(m.energy_max);
        if is_white_furnace(case) {
            for e in m.albedos {
                laws.furnace = laws.furnace.max((e - DVec3::ONE).abs().max_element());
            }
        }
    }
    laws
}

/// Every method of [`crate::METHODS`] measured on every case against the stored reference.
pub fn measure_methods(cases: &[Case], reference: &ReferenceData) -> Vec<(Method, Vec<Metrics>)> {
    crate::METHODS
        .into_iter()
        .map(|method| {
            let metrics = cases
                .iter()
                .enumerate()
                .map(|(i, case)| measure(case, method, &reference.under[i], &reference.albedo[i]))
                .collect();
            (method, metrics)
        })
        .collect()
}

/// Where the stored reference of an interface mode lives in the lab's source tree.
pub fn stored_reference(mode: InterfaceMode) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/reference").join(format!("standard-{}.bin", mode.name()))
}

/// The accuracy table in Markdown (`docs/results/accuracy.md`, quoted in `docs/accuracy.md`).
pub fn markdown(cases: &[Case], methods: &[(Method, Vec<Metrics>)], reference: &ReferenceData) -> String {
    let mut md = String::new();
    let mode = reference.mode.name();
    md.push_str(&format!(
        "Reference: `{mode}`-scattering interfaces, {} samples per BRDF value, {} walks per albedo \
         (median relative noise of the under-coat lobe {:.2}%).\n\n",
        reference.samples,
        reference.walks,
        100.0 * median(&reference.noise)
    ));
    md.push_str("| method | lobe relRMSE (median) | lobe relRMSE (max) | albedo error (max) | reciprocity (max) | energy (max E) | min f |\n|---|---|---|---|---|---|---|\n");
    for (method, metrics) in methods {
        let rmse: Vec<f64> = metrics.iter().map(|m| m.lobe_rmse).collect();
        let max = |f: fn(&Metrics) -> f64| metrics.iter().map(f).fold(0.0, f64::max);
        md.push_str(&format!(
            "| {} | {:.1}% | {:.1}% | {:.4} | {:.1e} | {:.4} | {:.1e} |\n",
            method_label(*method),
            100.0 * median(&rmse),
            100.0 * max(|m| m.lobe_rmse),
            max(|m| m.albedo_error),
            max(|m| m.reciprocity),
            max(|m| m.energy_max),
            metrics.iter().map(|m| m.min_value).fold(f64::INFINITY, f64::min),
        ));
    }
    md.push_str(&format!(
        "\nPer base, against the targets (lobe relRMSE ≤ {:.0}%, albedo error ≤ {}), worst case:\n\n\
         | method | base | lobe relRMSE (max) | albedo error (max) |\n|---|---|---|---|\n",
        100.0 * LOBE_TARGET,
        ALBEDO_TARGET
    ));
    for (method, metrics) in methods {
        for family in BaseFamily::ALL {
            let of_family: Vec<&Metrics> =
                cases.iter().zip(metrics).filter(|(c, _)| BaseFamily::of(c.base) == family).map(|(_, m)| m).collect();
            let lobe = of_family.iter().map(|m| m.lobe_rmse).fold(0.0, f64::max);
            let albedo = of_family.iter().map(|m| m.albedo_error).fold(0.0, f64::max);
            let mark = |ok: bool| if ok { "✓" } else { "✗" };
            md.push_str(&format!(
                "| {} | {} | {} {:.1}% | {} {:.4} |\n",
                method_label(*method),
                family.label(),
                mark(lobe <= LOBE_TARGET),
                100.0 * lobe,
                mark(albedo <= ALBEDO_TARGET),
                albedo
            ));
        }
    }
    md.push_str("\nLaws (CS184/284A Lecture 14), worst case over the set:\n\n| method | f ≥ 0 | reciprocity ≤ 1e-5 | E ≤ 1 + 1e-3 | white furnace |E − 1| ≤ 5e-3 |\n|---|---|---|---|---|\n");
    for (method, metrics) in methods {
        let l = laws(cases, metrics);
        let mark = |ok: bool| if ok { "✓" } else { "✗" };
        md.push_str(&format!(
            "| {} | {} {:.1e} | {} {:.1e} | {} {:.4} | {} {:.4} |\n",
            method_label(*method),
            mark(l.min_value >= 0.0),
            l.min_value,
            mark(l.reciprocity <= RECIPROCITY_TARGET),
            l.reciprocity,
            mark(l.energy_max <= ENERGY_TARGET),
            l.energy_max,
            mark(l.furnace <= FURNACE_TARGET),
            l.furnace
        ));
    }
    md
}

/// Every case's metrics per method as CSV (`docs/accuracy.csv`).
pub fn csv(cases: &[Case], methods: &[(Method, Vec<Metrics>)]) -> String {
    let mut text = String::from("method,case,lobe_rmse,albedo_error,reciprocity,energy_max,min_f\n");
    for (method, metrics) in methods {
        for (case, m) in cases.iter().zip(metrics) {
            text.push_str(&format!(
                "{},{},{},{},{},{},{}\n",
                method.name(),
                case.label(),
                m.lobe_rmse,
                m.albedo_error,
                m.reciprocity,
                m.energy_max,
                m.min_value
            ));
        }
    }
    text
}

/// The targets of the default method on the standard set (issue 4; docs/derivations.md, "Accuracy
/// targets").
pub const LOBE_TARGET: f64 = 0.10;
pub const ALBEDO_TARGET: f64 = 0.01;
pub const RECIPROCITY_TARGET: f64 = 1e-5;
pub const ENERGY_TARGET: f64 = 1.0 + 1e-3;
pub const FURNACE_TARGET: f64 = 5e-3;

/// The bases of the set, grouped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BaseFamily {
    Lambert,
    Eon,
    Conductor,
}

impl BaseFamily {
    pub const ALL: [BaseFamily; 3] = [BaseFamily::Lambert, BaseFamily::Eon, BaseFamily::Conductor];

    pub fn of(base: BaseKind) -> BaseFamily {
        match base {
            BaseKind::Lambert(_) => BaseFamily::Lambert,
            BaseKind::Eon => BaseFamily::Eon,
            BaseKind::Copper => BaseFamily::Conductor,
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            BaseFamily::Lambert => "Lambert ρ ∈ {0.2, 0.8, 1}",
            BaseFamily::Eon => "EON ρ 0.8, r 1",
            BaseFamily::Conductor => "copper, r 0.3",
        }
    }
}

/// A method's name in the tables, with what it stands for.
pub fn method_label(method: Method) -> String {
    match method {
        Method::INTERFACED => "Interfaced (default)".into(),
        Method::Interfaced(a) => {
            let names: Vec<&str> = a.taken().map(|(_, name)| name).collect();
            format!("Interfaced ({})", names.join(", "))
        }
        Method::WeidlichWilkie => "WeidlichWilkie (Bowsher 2022)".into(),
        Method::Additive => "Additive (Disney clear-coat)".into(),
    }
}

fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
