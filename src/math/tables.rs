//! Tabulated terms: the functions of the default method that have no closed form.
//!
//! A rough dielectric coat transmits T(μ) = 1 − R(μ), where R includes light that scatters more
//! than once between the microfacets (Heitz et al. 2016); seen from inside, its internal
//! reflection sets how much diffuse light comes back down (R(τ)) or escapes (E_esc(τ)) through
//! an absorbing slab. None of these has a closed form, so `glazec tables` samples them (the
//! stochastic reference's microsurface walks plus deterministic quadrature, in f64) on the grids
//! below and stores them in `data/tables.bin`, which is compiled into the crate. A GGX
//! conductor's single-scattering albedo is tabulated the same way.
//!
//! **Axes.** Every axis maps its argument to a coordinate u ∈ [0, 1] sampled at n uniform nodes:
//! [`Axis::Cosine`] u = (μ^¼ − μ₀^¼)/(1 − μ₀^¼) from μ₀ = 10⁻⁴ (dense near grazing, where a rough
//! interface's albedo changes fastest), [`Axis::Roughness`]
//! u = √r (α = r²), [`Axis::Ior`] u = 2(η − 1)/(η + 1) (η ∈ [1, 3]; u² = 4·F0), [`Axis::Depth`]
//! u = τ/(1 + τ) (τ ∈ [0, ∞]). Arguments outside the range clamp to its ends.
//!
//! **Lookups** are multilinear ([`lookup`]). They are written once over the shading ops, like
//! every term: on the CPU they interpolate directly; in a shader a lookup whose arguments are
//! all compile-time constants folds to a number, and any other becomes a call of the table's
//! lookup function (`coat_deficit`, `coat_escape`, …), which reads the table from the table
//! uniform buffer `glazec_tables` (all tables concatenated, [`buffer`]; its binding is in
//! `crate::lower::bindings`). Tables are not emitted as constant arrays: see
//! `lower::builder`'s `tables_buffer` for what that cost on lavapipe.

use std::sync::{Arc, OnceLock};

use super::{Kind, Real, Slot, TermDef};

/// The smallest cosine a cosine axis resolves: the lobes' clamp, `layering::COS_EPSILON`.
pub const COSINE_FLOOR: f64 = 1e-4;
/// [`COSINE_FLOOR`]^¼.
pub const COSINE_FLOOR_ROOT: f32 = 0.1;

/// How an axis maps its argument to the table coordinate u ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// A cosine μ ∈ [μ₀, 1]: u = (μ^¼ − μ₀^¼)/(1 − μ₀^¼), μ₀ = [`COSINE_FLOOR`]. Dense towards
    /// grazing incidence, where the single-scattering albedo changes fastest (α ≈ μ); the first
    /// node sits at μ₀, where the lobes clamp their cosines, so that a table and the analytic lobe
    /// it complements agree down to grazing (with u = √μ and a node at μ = 10⁻³ standing for
    /// μ = 0, a rough coat gained 4% energy at 89.99°).
    Cosine,
    /// A roughness r ∈ [0, 1] (GGX α = r²): u = √r, dense for glossy lobes (a rough
    /// interface's effect at grazing angles switches on where α ≈ μ).
    Roughness,
    /// A relative IOR η ∈ [1, 3]: u = 2(η − 1)/(η + 1).
    Ior,
    /// An optical depth τ ∈ [0, ∞]: u = τ/(1 + τ).
    Depth,
}

impl Axis {
    /// The coordinate of an argument (clamped into the axis range).
    pub fn coordinate<F: Real>(self, x: F) -> F {
        match self {
            Axis::Cosine => {
                (x.clamp(COSINE_FLOOR as f32, 1.0).sqrt().sqrt() - COSINE_FLOOR_ROOT)
                    * (1.0 / (1.0 - COSINE_FLOOR_ROOT))
            }
            Axis::Roughness => x.clamp(0.0, 1.0).sqrt(),
            Axis::Ior => ((x - 1.0) * 2.0 / (x + 1.0)).clamp(0.0, 1.0),
            Axis::Depth => {
                let tau = x.at_least(0.0);
                tau / (tau + 1.0)
            }
        }
    }

    /// The argument at node `i` of `n` (the inverse of [`Self::coordinate`]); `f64::INFINITY`
    /// for the last node of a depth axis.
    pub fn node(self, i: usize, n: usize) -> f64 {
        let u = i as f64 / (n - 1) as f64;
        match self {
            Axis::Cosine => {
                let root = f64::from(COSINE_FLOOR_ROOT);
                (root + (1.0 - root) * u).powi(4)
            }
            Axis::Roughness => u * u,
            Axis::Ior => (2.0 + u) / (2.0 - u),
            Axis::Depth if i + 1 == n => f64::INFINITY,
            Axis::Depth => u / (1.0 - u),
        }
    }
}

/// One table: its name in the table file, its axes (first varies fastest), and the shader
/// function that looks it up when an argument is known only at run time (`term`: its name,
/// one parameter per axis, and its doc comment saying what the table holds).
#[derive(Debug)]
pub struct TableSpec {
    pub name: &'static str,
    pub axes: &'static [(Axis, usize)],
    pub term: TermDef,
}

impl TableSpec {
    /// Number of entries.
    pub fn len(&self) -> usize {
        self.axes.iter().map(|&(_, n)| n).product()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The tables, in file order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableId {
    CoatDeficit,
    CoatExtra,
    CoatPath,
    CoatDeficitAvg,
    CoatExtraAvg,
    FresnelTransmitAvg,
    CoatReturn,
    CoatEscape,
    GgxAlbedo,
    GgxAlbedoAvg,
    EonEscapeShape,
}

/// The single-scattering deficit decides the energy balance and switches on sharply near
/// grazing incidence (where α ≈ μ): it gets 32 × 32 (μ, r) nodes, and its nodes are lowered
/// until the lookup never overshoots the quadrature between them (up to 7·10⁻³ before;
/// `accuracy::tables`), so that a rough coat never transmits more than its lobe leaves. The
/// smoother terms share a coarser grid.
const DEFICIT_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 32), (Axis::Roughness, 32), (Axis::Ior, 8)];
const EXTRA_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 16), (Axis::Roughness, 16), (Axis::Ior, 8)];
const PATH_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 12), (Axis::Roughness, 12), (Axis::Ior, 8)];
const SLAB_GRID: [(Axis, usize); 3] = [(Axis::Depth, 16), (Axis::Roughness, 16), (Axis::Ior, 8)];

const S: Kind = Kind::Scalar;
/// Parameter lists of the lookup functions, one parameter per axis.
const COAT_PARAMS: &[(&str, Kind)] = &[("cos_theta", S), ("roughness", S), ("eta", S)];
const SLAB_PARAMS: &[(&str, Kind)] = &[("tau", S), ("roughness", S), ("eta", S)];
const COAT_AVG_PARAMS: &[(&str, Kind)] = &[("roughness", S), ("eta", S)];

/// The first doc line of every lookup function.
macro_rules! table_doc {
    ($($line:literal),* $(,)?) => {
        &[
            "Tabulated by `glazec tables` from Heitz et al. 2016 microsurface walks and quadrature (f64);",
            "multilinear in u ∝ μ^¼ (from μ = 1e-4), √r, 2(η − 1)/(η + 1), τ/(1 + τ), clamped to the range.",
            $($line),*
        ]
    };
}

const fn table(
    name: &'static str,
    axes: &'static [(Axis, usize)],
    function: &'static str,
    params: &'static [(&'static str, Kind)],
    doc: &'static [&'static str],
) -> TableSpec {
    TableSpec { name, axes, term: TermDef { name: function, params, ret: Kind::Scalar, doc } }
}

/// Every table's layout. Changing one invalidates `data/tables.bin` (regenerate it with
/// `glazec tables`).
pub const SPECS: [TableSpec; 11] = [
    table(
        "coat_deficit_table",
        &DEFICIT_GRID,
        "coat_deficit",
        COAT_PARAMS,
        table_doc![
            "G(μ; r, η) = F(μ) − E_ss(μ): how much less the rough interface's single-scattering",
            "reflection lobe reflects than a smooth interface (masking, shadowing, light sent below",
            "the horizon; slightly negative where Fresnel's convexity wins); 0 when smooth.",
        ],
    ),
    table(
        "coat_extra_table",
        &EXTRA_GRID,
        "coat_extra",
        COAT_PARAMS,
        table_doc![
            "E_ms(μ; r, η): the share reflected after two or more microfacet events, which the",
            "single-scattering lobe misses. The transmittance is T = 1 − F + G − E_ms.",
        ],
    ),
    table(
        "coat_path_table",
        &PATH_GRID,
        "coat_path",
        COAT_PARAMS,
        table_doc![
            "q(μ; r, η) = μ′/μ_eff ≥ 1: how much longer the transmitted light's path through the slab",
            "is than along Snell's direction μ′ (μ_eff: the geometric-mean cosine of the directions a",
            "rough interface refracts into; 1 when smooth).",
        ],
    ),
    table(
        "coat_deficit_avg_table",
        &[DEFICIT_GRID[1], DEFICIT_GRID[2]],
        "coat_deficit_avg",
        COAT_AVG_PARAMS,
        table_doc!["⟨G⟩(r, η) = ∫ 2μ G(μ) dμ.",],
    ),
    table(
        "coat_extra_avg_table",
        &[EXTRA_GRID[1], EXTRA_GRID[2]],
        "coat_extra_avg",
        COAT_AVG_PARAMS,
        table_doc!["⟨E_ms⟩(r, η) = ∫ 2μ E_ms(μ) dμ.",],
    ),
    table(
        "fresnel_transmit_avg_table",
        &[(Axis::Ior, 64)],
        "fresnel_transmit_avg",
        &[("eta", S)],
        table_doc!["⟨1 − F⟩(η) = ∫ 2μ (1 − F(μ)) dμ: a smooth interface's hemispherical transmittance.",],
    ),
    table(
        "coat_return_table",
        &SLAB_GRID,
        "coat_return",
        SLAB_PARAMS,
        table_doc![
            "(1 − R(τ; r, η))/⟨T_int⟩, R(τ) = ∫ 2μ e^(−2τ/μ) R_int(μ) dμ: the share of diffuse light",
            "going up inside the coat that comes back down (internal reflection incl. TIR, absorbed",
            "both ways). Normalised by ⟨T_int⟩ = E_esc(0) (1 at τ = 0): the caller multiplies by its",
            "own ⟨T⟩/η², so a white body keeps E_esc(0) = 1 − R(0) exactly.",
        ],
    ),
    table(
        "coat_escape_table",
        &SLAB_GRID,
        "coat_escape",
        SLAB_PARAMS,
        table_doc![
            "E_esc(τ; r, η)/⟨T_int⟩, E_esc(τ) = ∫ 2μ e^(−τ/μ) T_int(μ) dμ: the share of diffuse light",
            "leaving the body that escapes through the coat (normalised like coat_return).",
        ],
    ),
    table(
        "ggx_albedo_table",
        &[(Axis::Cosine, 16), (Axis::Roughness, 16)],
        "ggx_albedo",
        &[("cos_theta", S), ("roughness", S)],
        table_doc!["E(μ; r): the directional albedo of a white single-scattering GGX reflector.",],
    ),
    table(
        "ggx_albedo_avg_table",
        &[(Axis::Roughness, 16)],
        "ggx_albedo_avg",
        &[("roughness", S)],
        table_doc!["⟨E⟩(r) = ∫ 2μ E(μ; r) dμ.",],
    ),
    table(
        "eon_escape_shape_table",
        &[(Axis::Ior, 32)],
        "eon_escape_shape",
        &[("eta", S)],
        table_doc![
            "s(η): how much more of EON's multiple-scattering lobe than of diffuse light leaves a",
            "smooth coat through its escape cone (`eon_escape_shape_exact`); 1 at η = 1.",
        ],
    ),
];

impl TableId {
    pub const ALL: [TableId; 11] = [
        TableId::CoatDeficit,
        TableId::CoatExtra,
        TableId::CoatPath,
        TableId::CoatDeficitAvg,
        TableId::CoatExtraAvg,
        TableId::FresnelTransmitAvg,
        TableId::CoatReturn,
        TableId::CoatEscape,
        TableId::GgxAlbedo,
        TableId::GgxAlbedoAvg,
        TableId::EonEscapeShape,
    ];

    pub fn spec(self) -> &'static TableSpec {
        &SPECS[self as usize]
    }

    /// The table's values (compiled into the crate from `data/tables.bin`).
    pub fn values(self) -> &'static Arc<[f32]> {
        &stored()[self as usize]
    }
}

impl TableId {
    /// Where the table starts in [`buffer`], in f32 elements.
    pub fn buffer_offset(self) -> u32 {
        TableId::ALL.iter().take_while(|&&id| id != self).map(|id| id.spec().len() as u32).sum()
    }
}

/// Every table, concatenated in [`SPECS`] order: the contents of the table buffer a shader
/// binds when a lookup has an argument known only at run time (`crate::lower::bindings`).
pub fn buffer() -> Vec<f32> {
    TableId::ALL.iter().flat_map(|id| id.values().iter().copied()).collect()
}

/// Entries (f32) of [`buffer`].
pub fn buffer_len() -> usize {
    SPECS.iter().map(TableSpec::len).sum()
}

/// The table file, compiled in.
const TABLE_FILE: &[u8] = include_bytes!("../../data/tables.bin");
const MAGIC: &[u8; 8] = b"GLAZTAB1";

fn stored() -> &'static [Arc<[f32]>] {
    static TABLES: OnceLock<Vec<Arc<[f32]>>> = OnceLock::new();
    TABLES.get_or_init(|| match decode(TABLE_FILE) {
        Ok(tables) => tables.into_iter().map(Arc::from).collect(),
        // The file ships with the crate and a test decodes it; a mismatch is a build of
        // inconsistent sources, not bad user input.
        Err(e) => panic!("data/tables.bin does not match the table layout ({e}); run `glazec tables`"),
    })
}

/// The table file: magic, table count, then per table its name (u8 length + UTF-8), its
/// entry count (u32) and its values (f32), all little-endian, in [`SPECS`] order.
pub fn encode(tables: &[Vec<f32>]) -> Vec<u8> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&(tables.len() as u32).to_le_bytes());
    for (spec, values) in SPECS.iter().zip(tables) {
        bytes.push(spec.name.len() as u8);
        bytes.extend_from_slice(spec.name.as_bytes());
        bytes.extend_from_slice(&(values.len() as u32).to_le_bytes());
        for v in values {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

/// Reads a table file, checking it against [`SPECS`].
pub fn decode(bytes: &[u8]) -> Result<Vec<Vec<f32>>, String> {
    let mut at = 0;
    let mut take = |n: usize| -> Result<&[u8], String> {
        let s = bytes.get(at..at + n).ok_or("truncated")?;
        at += n;
        Ok(s)
    };
    if take(8)? != MAGIC {
        return Err("not a glazec table file".into());
    }
    let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize;
    if word(take(4)?) != SPECS.len() {
        return Err("wrong table count".into());
    }
    let mut tables = Vec::new();
    for spec in &SPECS {
        let name_len = take(1)?[0] as usize;
        if take(name_len)? != spec.name.as_bytes() {
            return Err(format!("expected table {}", spec.name));
        }
        if word(take(4)?) != spec.len() {
            return Err(format!("{} has the wrong size", spec.name));
        }
        let data = take(4 * spec.len())?;
        tables.push(data.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect());
    }
    if at != bytes.len() {
        return Err("trailing bytes".into());
    }
    Ok(tables)
}

/// Bytes of table data compiled into the crate.
pub fn total_bytes() -> usize {
    SPECS.iter().map(|s| 4 * s.len()).sum()
}

/// The lower node index and the weight of the upper node at fractional node position `s`
/// = u·(n − 1) on `n` nodes.
fn cell<F: Real>(s: F, n: usize) -> (F, F) {
    let i = s.floor().min(s.lit((n - 2) as f32));
    (i, s - i)
}

/// Multilinear interpolation of table `id` at `args` (one argument per axis, in the table's
/// order). With every argument known (always on the CPU; literal parameters in a shader) the
/// value is interpolated now; otherwise the result is a call of the table's lookup function
/// (`coat_deficit(n_dot_l, 0.2, 1.5)`), emitted once per module.
pub fn lookup<F: Real>(id: TableId, args: &[F]) -> F {
    let spec = id.spec();
    debug_assert_eq!(args.len(), spec.axes.len());
    // (The argument is checked first so that no code is emitted for a runtime one here.)
    let known: Option<Vec<f32>> =
        args.iter().zip(spec.axes).map(|(&x, &(axis, _))| x.known().and_then(|_| axis.coordinate(x).known())).collect();
    if let Some(known) = known {
        return args[0].lit(multilinear::<f32>(id, |a| known[a], &[]));
    }
    let slots: Vec<Slot<F>> = args.iter().map(|&x| Slot::S(x)).collect();
    match F::call(&spec.term, &slots, &|slots| Slot::S(interpolate_in_buffer(id, slots))) {
        Slot::S(x) => x,
        Slot::V(_) => unreachable!("table lookups return scalars"),
    }
}

/// The body of a table's lookup function: [`multilinear`] at the arguments' coordinates.
fn interpolate_in_buffer<F: Real>(id: TableId, args: &[Slot<F>]) -> F {
    let spec = id.spec();
    let params: Vec<&str> = spec.term.params.iter().map(|&(p, _)| p).collect();
    let coordinate = |a: usize| match args[a] {
        Slot::S(x) => spec.axes[a].0.coordinate(x).named(&format!("u_{}", params[a])),
        Slot::V(_) => unreachable!("table arguments are scalars"),
    };
    multilinear(id, coordinate, &params)
}

/// Multilinear interpolation of table `id` at coordinates u ∈ [0, 1] (`coordinate(axis)`, asked
/// for once per axis, in order), written once over the shading ops: it folds literal lookups at
/// compile time, evaluates on the CPU, and is the body of the shader's lookup function. `names`
/// (one per axis, or none at all) name the generated `let`s.
fn multilinear<F: Real>(id: TableId, coordinate: impl Fn(usize) -> F, names: &[&str]) -> F {
    let spec = id.spec();
    let cells: Vec<(F, F)> = spec
        .axes
        .iter()
        .enumerate()
        .map(|(a, &(_, n))| {
            let node = coordinate(a) * (n - 1) as f32;
            match names.get(a) {
                Some(name) => {
                    let (i, w) = cell(node.named(&format!("node_{name}")), n);
                    (i.named(&format!("cell_{name}")), w.named(&format!("weight_{name}")))
                }
                // (No names: no strings built on the CPU's hot path.)
                None => cell(node, n),
            }
        })
        .collect();
    let zero = cells[0].0.lit(0.0);
    let mut total = zero;
    for corner in 0..1usize << cells.len() {
        let (mut index, mut weight, mut stride) = (zero, zero.lit(1.0), 1.0);
        for (axis, &(i, w)) in cells.iter().enumerate() {
            let upper = corner >> axis & 1 == 1;
            index = index + (if upper { i + 1.0 } else { i }) * stride;
            weight = weight * if upper { w } else { w.one_minus() };
            stride *= spec.axes[axis].1 as f32;
        }
        let mut value = F::fetch(id, index);
        if !names.is_empty() {
            // Corner names list the lower (l) or upper (u) node per axis, first axis first: `at_lul`.
            let corner_name: String = (0..cells.len()).map(|a| if corner >> a & 1 == 1 { 'u' } else { 'l' }).collect();
            value = value.named(&format!("at_{corner_name}"));
        }
        total = total + value * weight;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stored_tables_decode_and_fit_the_budget() {
        let tables = decode(TABLE_FILE).expect("data/tables.bin decodes");
        assert_eq!(tables.len(), SPECS.len());
        assert!(total_bytes() <= 64 * 1024, "{} bytes", total_bytes());
        for (spec, values) in SPECS.iter().zip(&tables) {
            // The deficit (and so its average) may be slightly negative: the table is lowered
            // until its lookup never overshoots (`accuracy::tables`). The normalised slab tables
            // exceed 1.
            let range = if spec.name.starts_with("coat_deficit") { -1.0..=1.0 } else { 0.0..=100.0 };
            assert!(values.iter().all(|v| v.is_finite() && range.contains(v)), "{}", spec.name);
        }
        assert_eq!(encode(&tables), TABLE_FILE);
    }

    #[test]
    fn eon_escape_shape_table_matches_its_quadrature() {
        for eta in [1.0_f32, 1.1, 1.33, 1.5, 1.7, 2.0, 2.5, 3.0] {
            let table = lookup::<f32>(TableId::EonEscapeShape, &[eta]);
            let exact = crate::math::terms::eon_escape_shape_exact::<f32>(eta);
            assert!((table - exact).abs() < 2e-3, "η {eta}: table {table}, quadrature {exact}");
        }
        // Without a cone every direction escapes, so s = 1 up to the quartic fit of E_FON that
        // `e_fon` uses (Portsmouth et al.: max error 4.7·10⁻⁴), which the constants c₁, c₂ do not share.
        let at_one = crate::math::terms::eon_escape_shape_exact::<f32>(1.0);
        assert!((at_one - 1.0).abs() < 1e-3, "no cone, no preference: {at_one}");
    }

    #[test]
    fn axis_nodes_invert_coordinates() {
        for axis in [Axis::Cosine, Axis::Roughness, Axis::Ior, Axis::Depth] {
            for i in 0..11 {
                let x = axis.node(i, 12);
                let u = axis.coordinate(x as f32);
                assert!((u - i as f32 / 11.0).abs() < 1e-6, "{axis:?} {i}: {u}");
            }
        }
    }

    #[test]
    fn interpolation_reproduces_nodes_and_is_linear_between() {
        let values = TableId::GgxAlbedo.values();
        let at = |i: usize, j: usize| values[i + 16 * j];
        assert_eq!(multilinear::<f32>(TableId::GgxAlbedo, |a| [3.0 / 15.0, 7.0 / 15.0][a], &[]), at(3, 7));
        let mid = multilinear::<f32>(TableId::GgxAlbedo, |a| [3.5 / 15.0, 7.0 / 15.0][a], &[]);
        assert!((mid - (at(3, 7) + at(4, 7)) / 2.0).abs() < 1e-6);
    }
}
