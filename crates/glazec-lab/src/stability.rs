//! Stability: where the layering methods break numerically, swept to the limits.
//!
//! **Input:** [`sweeps`]: families of *white* materials (white bases, clear coats, so that any
//! directional albedo above 1 is an energy gain, not a colour) that vary one parameter towards a
//! limit where methods fail — coat roughness → 10⁻⁴ and → 1, coat IOR → 1 and up to 3, a coat
//! optically thinner than the medium above (total internal reflection from inside), optical
//! depth 0 … 10⁴ (an opaque coat), 1 … 16 coats, a conductor's roughness → 10⁻⁴, and denormal
//! parameters — and per parameter value a row of direction configurations at polar angles up to
//! exactly 90°, plus a denormal cosine ([`ANGLES`]).
//! **Output:** per method and sweep a [`Map`] of [`Cell`]s (parameter × angle): non-finite
//! values, negative values, the directional albedo E(θ) (an energy gain when E > 1 + 10⁻³,
//! [`ENERGY_BOUND`]), and discontinuities along the parameter axis ([`discontinuities`]); a
//! Markdown summary ([`summary`]) and heat-map pixels ([`heat_map`]).
//!
//! f is evaluated through a callback: `glazec::eval` on the CPU (`glazec stability`), the
//! `eval_pairs` kernel on a GPU (`glazec stability --gpu`, and the tests on lavapipe).

use glam::{DVec3, Vec3};
use glazec::math::sampling::direction_f32;

use crate::accuracy::quadrature;
use glazec::model::{Base, Coat, Color, ConductorFresnel, Lobe, Material, Method, Scalar};

/// An albedo above this is an energy gain (the accuracy issue's law, with its quadrature error).
pub const ENERGY_BOUND: f64 = 1.0 + 1e-3;
/// A jump between neighbouring parameter samples is examined when it exceeds this share of the
/// largest |f| along the sweep (per direction pair and channel).
pub const JUMP_FLOOR: f32 = 0.05;
/// Bisections of a suspicious interval, each keeping the half with the larger jump.
pub const JUMP_BISECTIONS: u32 = 4;
/// A jump is a discontinuity when, after [`JUMP_BISECTIONS`] halvings (1/16 of the step), one
/// sub-interval still carries this share of it: a continuous function's jump shrinks with the
/// step, a discontinuous one's does not.
pub const JUMP_KEPT: f32 = 0.5;

/// The polar angles (degrees) of the map's columns; the last column is a denormal cosine.
pub const ANGLES: [f32; 9] = [0.0, 30.0, 60.0, 80.0, 85.0, 89.0, 89.9, 89.99, 90.0];
/// The cosine of the extra, denormal column (f32 denormals start below 1.18·10⁻³⁸).
pub const DENORMAL_COSINE: f32 = 1e-40;

/// One sweep: a parameter, its values, and the material at each value.
pub struct Sweep {
    pub name: &'static str,
    /// What varies, for the tables.
    pub parameter: &'static str,
    pub values: Vec<f32>,
    /// Whether the parameter is continuous (discontinuities are sought along it) and how to
    /// bisect: geometrically for a log-spaced one.
    pub spacing: Spacing,
    build: fn(Method, f32) -> Material,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spacing {
    Linear,
    Log,
    /// A whole number (layer count): no values in between.
    Discrete,
}

impl Sweep {
    pub fn material(&self, method: Method, value: f32) -> Material {
        (self.build)(method, value)
    }

    fn midpoint(&self, a: f32, b: f32) -> f32 {
        match self.spacing {
            Spacing::Log if a > 0.0 && b > 0.0 => (a * b).sqrt(),
            _ => 0.5 * (a + b),
        }
    }
}

fn log_range(from: f32, to: f32, n: usize) -> Vec<f32> {
    (0..n).map(|i| from * (to / from).powf(i as f32 / (n - 1) as f32)).collect()
}

fn white() -> Color {
    Color::Lit([1.0; 3])
}

fn coat(lobe: Lobe, ior: f32, tau: f32) -> Coat {
    Coat { lobe, ior: Scalar::Lit(ior), absorption: Color::Lit([tau; 3]), thickness: Scalar::Lit(1.0) }
}

fn ggx(roughness: f32) -> Lobe {
    Lobe::Ggx { roughness: Scalar::Lit(roughness) }
}

fn over_white(method: Method, coats: Vec<Coat>) -> Material {
    Material {
        name: "sweep".into(),
        method,
        coats,
        base: Base::Lambert { albedo: white() },
        params: vec![],
        normals: vec![],
    }
}

/// `coats` over a white conductor (F0 = 1) of roughness `roughness`.
fn over_white_conductor(method: Method, roughness: f32, coats: Vec<Coat>) -> Material {
    Material {
        base: Base::Conductor { roughness: Scalar::Lit(roughness), fresnel: ConductorFresnel::F0(white()) },
        ..over_white(method, coats)
    }
}

/// The sweeps; `reduced` takes fewer values per sweep (for the tests).
pub fn sweeps(reduced: bool) -> Vec<Sweep> {
    let n = if reduced { 5 } else { 13 };
    let mut ior_to_one: Vec<f32> = (0..n).map(|i| 1.0 + 10f32.powf(-5.0 + 5.0 * i as f32 / (n - 1) as f32)).collect();
    ior_to_one.retain(|&x| x <= 3.0);
    ior_to_one.push(3.0);
    let layers: Vec<f32> = if reduced { vec![1.0, 4.0, 16.0] } else { (1..=16).map(|k| k as f32).collect() };
    let mut depth = vec![0.0];
    depth.extend(log_range(1e-6, 1e4, n));
    vec![
        Sweep {
            name: "coat roughness",
            parameter: "GGX roughness of a clear η 1.5 coat over white Lambert",
            values: log_range(1e-4, 1.0, n),
            spacing: Spacing::Log,
            build: |m, r| over_white(m, vec![coat(ggx(r), 1.5, 0.0)]),
        },
        Sweep {
            name: "coat IOR",
            parameter: "IOR 1 + 10⁻⁵ … 3 of a clear r 0.2 coat over white Lambert",
            values: ior_to_one.clone(),
            spacing: Spacing::Linear,
            build: |m, eta| over_white(m, vec![coat(ggx(0.2), eta, 0.0)]),
        },
        Sweep {
            name: "IOR below the medium",
            parameter: "IOR 0.3 … 0.999 of a clear r 0.2 coat (TIR from inside) over white Lambert",
            values: (0..n).map(|i| 0.3 + 0.699 * i as f32 / (n - 1) as f32).collect(),
            spacing: Spacing::Linear,
            build: |m, eta| over_white(m, vec![coat(ggx(0.2), eta, 0.0)]),
        },
        Sweep {
            name: "optical depth",
            parameter: "τ = 0, 10⁻⁶ … 10⁴ of an r 0.2, η 1.5 coat over white Lambert",
            values: depth,
            spacing: Spacing::Log,
            build: |m, tau| over_white(m, vec![coat(ggx(0.2), 1.5, tau)]),
        },
        Sweep {
            name: "layers",
            parameter: "1 … 16 clear coats (r 0.2, η 1.5 and 1.3 alternating) over white Lambert",
            values: layers,
            spacing: Spacing::Discrete,
            build: |m, k| {
                let coats = (0..k as usize).map(|i| coat(ggx(0.2), if i % 2 == 0 { 1.5 } else { 1.3 }, 0.0)).collect();
                over_white(m, coats)
            },
        },
        Sweep {
            name: "conductor roughness",
            parameter: "roughness of a white conductor (F0 = 1) under a clear r 0.2, η 1.5 coat",
            values: log_range(1e-4, 1.0, n),
            spacing: Spacing::Log,
            build: |m, r| over_white_conductor(m, r, vec![coat(ggx(0.2), 1.5, 0.0)]),
        },
        Sweep {
            name: "IOR over a conductor",
            parameter: "IOR 1 + 10⁻⁵ … 3 of a smooth clear coat over a white conductor of roughness 0.3",
            values: ior_to_one,
            spacing: Spacing::Linear,
            build: |m, eta| over_white_conductor(m, 0.3, vec![coat(Lobe::Smooth, eta, 0.0)]),
        },
        Sweep {
            name: "roughness over a conductor",
            parameter: "GGX roughness of a clear η 1.5 coat over a white conductor of roughness 0.3",
            values: log_range(1e-4, 1.0, n),
            spacing: Spacing::Log,
            build: |m, r| over_white_conductor(m, 0.3, vec![coat(ggx(r), 1.5, 0.0)]),
        },
        Sweep {
            name: "denormal parameters",
            parameter: "x = 0, 10⁻⁴⁵ … 10⁻³⁰ as coat roughness, absorption and EON roughness",
            values: vec![0.0, 1e-45, 1e-42, 1e-40, 1e-38, 1e-30],
            spacing: Spacing::Discrete,
            build: |m, x| Material {
                base: Base::Eon { albedo: white(), roughness: Scalar::Lit(x) },
                ..over_white(m, vec![coat(ggx(x), 1.5, x)])
            },
        },
    ]
}

/// A direction at polar angle `theta` (degrees) and azimuth `phi` (degrees).
fn direction(theta: f32, phi: f32) -> Vec3 {
    let d = direction_f32(theta.to_radians(), phi.to_radians());
    // θ = 90° exactly: cos(π/2) in f32 is −4.4·10⁻⁸; the column means "exactly grazing".
    if theta == 90.0 { Vec3::new(d.x, d.y, 0.0) } else { d }
}

/// The outgoing direction of column `column` ([`ANGLES`], then the denormal cosine).
fn column_direction(column: usize) -> Vec3 {
    match ANGLES.get(column) {
        Some(&theta) => direction(theta, 0.0),
        None => Vec3::new((1.0 - DENORMAL_COSINE * DENORMAL_COSINE).sqrt(), 0.0, DENORMAL_COSINE),
    }
}

/// Columns of a map: the angles and the denormal cosine.
pub const COLUMNS: usize = ANGLES.len() + 1;

/// The direction pairs of a column: mirror, retro-reflection and normal-to-angle in both
/// orders, and an oblique pair.
fn column_pairs(column: usize) -> Vec<(Vec3, Vec3)> {
    let w = column_direction(column);
    let mirror = Vec3::new(-w.x, -w.y, w.z);
    vec![(w, mirror), (w, w), (w, Vec3::Z), (Vec3::Z, w), (w, direction(60.0, 90.0))]
}

/// Where f jumps in the light direction's cosine: a top coat optically thinner than the medium
/// above (literal η < 1) transmits nothing beyond its critical angle, cos θc = √(1 − η²) (the
/// albedo quadrature refines its cells there, `quadrature::albedo_nodes_with_jump`).
fn critical_cosine(material: &Material) -> Option<f64> {
    match material.coats.first().map(|c| c.ior) {
        Some(Scalar::Lit(eta)) if eta < 1.0 => Some((1.0 - f64::from(eta).powi(2)).sqrt()),
        _ => None,
    }
}

/// The smallest GGX α of a material's lobes (for the albedo quadrature).
fn sharpest_alpha(material: &Material) -> f64 {
    // (The sweeps use literals; a runtime roughness would count as rough.)
    let roughness = |s: &Scalar| match s {
        Scalar::Lit(r) => f64::from(*r),
        Scalar::Param(_) => 1.0,
    };
    let mut alpha: f64 = 1.0;
    for c in &material.coats {
        if let Lobe::Ggx { roughness: r } | Lobe::Gtr1 { roughness: r } = &c.lobe {
            alpha = alpha.min(roughness(r).powi(2));
        }
    }
    if let Base::Conductor { roughness: r, .. } | Base::Plastic { roughness: r, .. } = &material.base {
        alpha = alpha.min(roughness(r).powi(2));
    }
    alpha
}

/// One (parameter, angle) cell.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cell {
    /// Non-finite channel values among the column's pairs and the albedo quadrature's.
    pub non_finite: u32,
    /// Negative channel values among them.
    pub negative: u32,
    /// The largest channel of the directional albedo E(θ) (quadrature of f plus a smooth coat's
    /// mirror reflection); NaN if f was not finite.
    pub albedo: f64,
    /// A discontinuity between this parameter value and the next.
    pub jump: bool,
}

impl Cell {
    pub fn energy_gain(&self) -> bool {
        self.albedo > ENERGY_BOUND
    }

    pub fn fails(&self) -> bool {
        self.non_finite > 0 || self.negative > 0 || self.energy_gain() || self.jump || self.albedo.is_nan()
    }
}

/// A method on a sweep: `cells[parameter][column]`.
pub struct Map {
    pub method: Method,
    pub sweep: &'static str,
    pub cells: Vec<Vec<Cell>>,
}

/// Evaluates f (without the cosine) of a material at direction pairs.
pub type Evaluator<'a> = dyn FnMut(&Material, &[(Vec3, Vec3)]) -> Vec<Vec3> + 'a;

/// The CPU evaluation of the shared math.
pub fn cpu_evaluator(material: &Material, pairs: &[(Vec3, Vec3)]) -> Vec<Vec3> {
    pairs.iter().map(|&(wi, wo)| glazec::eval::brdf(material, &material.default_values(), wi, wo)).collect()
}

/// f of a material at direction pairs on a GPU: the material's own `eval_pairs` kernel, reached
/// as the naga module (one shader per material).
///
/// # Errors
/// The module does not validate, or the device rejects or fails to run it.
#[cfg(feature = "gpu")]
pub fn gpu_evaluation(gpu: &glazec_gpu::Gpu, material: &Material, pairs: &[(Vec3, Vec3)]) -> Result<Vec<Vec3>, String> {
    use glazec_gpu::{EvalKernel, ShaderPath};
    let compiled = glazec::compile_material(material.clone(), Default::default()).map_err(|e| e.to_string())?;
    let kernel = EvalKernel::new(gpu, &compiled, ShaderPath::NagaIr).map_err(|e| e.to_string())?;
    let pairs: Vec<glazec::eval::Pair> = pairs.iter().map(|&(wi, wo)| glazec::eval::Pair { wi, wo }).collect();
    kernel.eval(gpu, &pairs, &material.default_values()).map_err(|e| e.to_string())
}

fn count(values: &[Vec3], cell: &mut Cell) {
    for v in values {
        for c in 0..3 {
            if !v[c].is_finite() {
                cell.non_finite += 1;
            } else if v[c] < 0.0 {
                cell.negative += 1;
            }
        }
    }
}

/// Runs one method over one sweep. `refine` looks for discontinuities (it evaluates materials at
/// parameter values between the sweep's).
pub fn run(sweep: &Sweep, method: Method, eval: &mut Evaluator<'_>, refine: bool) -> Map {
    let mut cells = Vec::with_capacity(sweep.values.len());
    let mut samples = Vec::with_capacity(sweep.values.len());
    for &value in &sweep.values {
        let material = sweep.material(method, value);
        let alpha = sharpest_alpha(&material);
        let jump = critical_cosine(&material);
        // One batch per material: every column's pairs, then every column's albedo nodes.
        let mut pairs: Vec<(Vec3, Vec3)> = (0..COLUMNS).flat_map(column_pairs).collect();
        let nodes: Vec<Vec<(DVec3, f64)>> = (0..COLUMNS)
            .map(|c| quadrature::albedo_nodes_with_jump(column_direction(c).as_dvec3(), alpha, jump))
            .collect();
        for (c, column_nodes) in nodes.iter().enumerate() {
            let wo = column_direction(c);
            pairs.extend(column_nodes.iter().map(|&(wi, _)| (wi.as_vec3(), wo)));
        }
        let values = eval(&material, &pairs);
        let per_column = column_pairs(0).len();
        let (direct, mut rest) = values.split_at(COLUMNS * per_column);
        let mut row = Vec::with_capacity(COLUMNS);
        for (c, column_nodes) in nodes.iter().enumerate() {
            let mut cell = Cell::default();
            count(&direct[c * per_column..(c + 1) * per_column], &mut cell);
            let (node_values, tail) = rest.split_at(column_nodes.len());
            rest = tail;
            count(node_values, &mut cell);
            let mirror = glazec::eval::mirror_reflectance(&material, &[], column_direction(c)).as_dvec3();
            let e: DVec3 =
                column_nodes.iter().zip(node_values).map(|(&(_, w), f)| f.as_dvec3() * w).sum::<DVec3>() + mirror;
            cell.albedo = if e.is_finite() { e.max_element() } else { f64::NAN };
            row.push(cell);
        }
        cells.push(row);
        samples.push(direct.to_vec());
    }
    if refine && sweep.spacing != Spacing::Discrete {
        for (p, column) in discontinuities(sweep, method, &samples, eval) {
            cells[p][column].jump = true;
        }
    }
    Map { method, sweep: sweep.name, cells }
}

/// The (parameter index, column) of every discontinuity between neighbouring parameter values:
/// a jump above [`JUMP_FLOOR`] of the sweep's largest |f| that, bisected [`JUMP_BISECTIONS`]
/// times, stays concentrated in one sub-interval ([`JUMP_KEPT`]).
pub fn discontinuities(
    sweep: &Sweep,
    method: Method,
    samples: &[Vec<Vec3>],
    eval: &mut Evaluator<'_>,
) -> Vec<(usize, usize)> {
    let per_column = column_pairs(0).len();
    let scale = samples.iter().flatten().filter(|v| v.is_finite()).map(|v| v.abs().max_element()).fold(0.0, f32::max);
    let mut found = Vec::new();
    for p in 0..samples.len().saturating_sub(1) {
        for column in 0..COLUMNS {
            let range = column * per_column..(column + 1) * per_column;
            let pairs = column_pairs(column);
            let (a, b) = (&samples[p][range.clone()], &samples[p + 1][range]);
            let suspicious = a.iter().zip(b).any(|(x, y)| (*x - *y).abs().max_element() > JUMP_FLOOR * scale);
            if suspicious && is_discontinuous(sweep, method, &pairs, sweep.values[p], sweep.values[p + 1], a, b, eval) {
                found.push((p, column));
            }
        }
    }
    found
}

#[allow(clippy::too_many_arguments)]
fn is_discontinuous(
    sweep: &Sweep,
    method: Method,
    pairs: &[(Vec3, Vec3)],
    lo: f32,
    hi: f32,
    f_lo: &[Vec3],
    f_hi: &[Vec3],
    eval: &mut Evaluator<'_>,
) -> bool {
    let jump = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f32::max);
    let total = jump(f_lo, f_hi);
    let (mut lo, mut hi, mut f_lo, mut f_hi) = (lo, hi, f_lo.to_vec(), f_hi.to_vec());
    for _ in 0..JUMP_BISECTIONS {
        let mid = sweep.midpoint(lo, hi);
        let f_mid = eval(&sweep.material(method, mid), pairs);
        if jump(&f_lo, &f_mid) >= jump(&f_mid, &f_hi) {
            (hi, f_hi) = (mid, f_mid);
        } else {
            (lo, f_lo) = (mid, f_mid);
        }
    }
    jump(&f_lo, &f_hi) >= JUMP_KEPT * total
}

/// Failure counts of one map.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Failures {
    pub non_finite: u32,
    pub negative: u32,
    /// Cells whose albedo exceeds [`ENERGY_BOUND`].
    pub energy_gain: u32,
    pub largest_albedo: f64,
    pub jumps: u32,
}

impl Failures {
    pub fn of(map: &Map) -> Failures {
        let mut f = Failures::default();
        for cell in map.cells.iter().flatten() {
            f.non_finite += cell.non_finite + u32::from(cell.albedo.is_nan());
            f.negative += cell.negative;
            f.energy_gain += u32::from(cell.energy_gain());
            f.jumps += u32::from(cell.jump);
            if cell.albedo.is_finite() {
                f.largest_albedo = f.largest_albedo.max(cell.albedo);
            }
        }
        f
    }

    pub fn none(&self) -> bool {
        self.non_finite == 0 && self.negative == 0 && self.energy_gain == 0 && self.jumps == 0
    }
}

/// The published page (`docs/results/stability/summary.md`): where f was evaluated, then the
/// [`summary`].
pub fn summary_page(maps: &[Map], sweeps: &[Sweep], on_gpu: bool) -> String {
    let backend = if on_gpu { "the GPU (naga-IR kernel)" } else { "the CPU" };
    format!("Evaluated on {backend}.\n\n{}", summary(maps, sweeps))
}

/// The Markdown summary: one row per method and sweep.
pub fn summary(maps: &[Map], sweeps: &[Sweep]) -> String {
    let mut md = String::from(
        "| method | sweep | non-finite values | negative values | cells with E > 1 + 10⁻³ (largest E) | discontinuities |\n|---|---|---|---|---|---|\n",
    );
    for map in maps {
        let f = Failures::of(map);
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} ({:.4}) | {} |\n",
            crate::accuracy::method_label(map.method),
            map.sweep,
            f.non_finite,
            f.negative,
            f.energy_gain,
            f.largest_albedo,
            f.jumps
        ));
    }
    md.push_str("\nSweeps (each over polar angles ");
    md.push_str(&ANGLES.map(|a| format!("{a}°")).join(", "));
    md.push_str(&format!(", and cos θ = {DENORMAL_COSINE:e}):\n\n"));
    for s in sweeps {
        md.push_str(&format!("* **{}**: {}.\n", s.name, s.parameter));
    }
    md
}

/// A map's heat map, `scale` pixels per cell, padded to `rows` rows: rows are parameter values
/// (top: the first), columns the angles (left: 0°; right: the denormal cosine). Colours: red
/// non-finite, orange negative, magenta energy gain, yellow a discontinuity to the next row;
/// otherwise green, brighter with the albedo (brightest at E = 1). Returns (width, height, RGB8).
pub fn heat_map(map: &Map, scale: u32, rows: u32) -> (u32, u32, Vec<u8>) {
    let (width, height) = (COLUMNS as u32 * scale, rows.max(map.cells.len() as u32) * scale);
    let mut rgb = vec![12u8; (width * height * 3) as usize];
    for (r, row) in map.cells.iter().enumerate() {
        for (c, cell) in row.iter().enumerate() {
            let colour = if cell.non_finite > 0 || cell.albedo.is_nan() {
                [230, 30, 30]
            } else if cell.negative > 0 {
                [250, 140, 20]
            } else if cell.energy_gain() {
                [220, 40, 220]
            } else if cell.jump {
                [240, 230, 40]
            } else {
                let g = (40.0 + 215.0 * cell.albedo.clamp(0.0, 1.0)) as u8;
                [g / 3, g, g / 3]
            };
            // A one-pixel gap between cells.
            for y in 0..scale - 1 {
                for x in 0..scale - 1 {
                    let (px, py) = (c as u32 * scale + x, r as u32 * scale + y);
                    let at = ((py * width + px) * 3) as usize;
                    rgb[at..at + 3].copy_from_slice(&colour);
                }
            }
        }
    }
    (width, height, rgb)
}

/// Each method's heat maps as one PNG contact sheet, `<out>/<method>.png` (one tile per sweep).
///
/// # Errors
/// A PNG that cannot be encoded.
#[cfg(feature = "gpu")]
pub fn heat_map_files(
    maps: &[Map],
    out: &std::path::Path,
) -> Result<Vec<glazec::output::OutputFile>, glazec_gpu::RunError> {
    use glazec_gpu::preview::{Image, contact_sheet, encode_png};
    const CELL: u32 = 32;
    let rows = maps.iter().map(|m| m.cells.len() as u32).max().unwrap_or(1);
    crate::METHODS
        .iter()
        .map(|&method| {
            let tiles: Vec<(String, Image)> = maps
                .iter()
                .filter(|m| m.method == method)
                .map(|m| {
                    let (width, height, rgb) = heat_map(m, CELL, rows);
                    (m.sweep.to_string(), Image { width, height, rgb })
                })
                .collect();
            let contents = encode_png(&contact_sheet(&tiles, 4))?;
            Ok(glazec::output::OutputFile { path: out.join(format!("{}.png", method.name())), contents })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_is_a_discontinuity_and_a_steep_ramp_is_not() {
        // A fake sweep whose "material" only carries the parameter in its base albedo; the
        // evaluator turns it into a step or a ramp.
        let sweep = Sweep {
            name: "test",
            parameter: "x",
            values: vec![0.0, 0.5, 1.0],
            spacing: Spacing::Linear,
            build: |m, x| Material { base: Base::Lambert { albedo: Color::Lit([x; 3]) }, ..over_white(m, vec![]) },
        };
        let x_of = |m: &Material| match m.base {
            Base::Lambert { albedo: Color::Lit([x, _, _]) } => x,
            _ => unreachable!(),
        };
        let mut step = |m: &Material, pairs: &[(Vec3, Vec3)]| {
            vec![Vec3::splat(if x_of(m) > 0.3 { 1.0 } else { 0.0 }); pairs.len()]
        };
        let samples: Vec<Vec<Vec3>> = sweep
            .values
            .iter()
            .map(|&x| step(&sweep.material(Method::INTERFACED, x), &column_pairs(0).repeat(COLUMNS)))
            .collect();
        assert_eq!(discontinuities(&sweep, Method::INTERFACED, &samples, &mut step).len(), COLUMNS);
        let mut ramp = |m: &Material, pairs: &[(Vec3, Vec3)]| vec![Vec3::splat(3.0 * x_of(m)); pairs.len()];
        let samples: Vec<Vec<Vec3>> = sweep
            .values
            .iter()
            .map(|&x| ramp(&sweep.material(Method::INTERFACED, x), &column_pairs(0).repeat(COLUMNS)))
            .collect();
        assert!(discontinuities(&sweep, Method::INTERFACED, &samples, &mut ramp).is_empty());
    }
}
