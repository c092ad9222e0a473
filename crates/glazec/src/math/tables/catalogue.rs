//! The table catalogue: which tables exist ([`TableId`]), their axes and grids ([`Axis`],
//! [`TableSpec`]), and the shader function that looks each one up.

use crate::math::{Kind, Real, TermDef};

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
    /// A cosine μ ∈ [0, 1]: u = √μ. For the statistics of light under a coat over a conductor,
    /// which change over the whole range of μ, fastest (but not as fast as a rough interface's
    /// albedo) towards grazing.
    RootCosine,
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
            Axis::RootCosine => x.clamp(0.0, 1.0).sqrt(),
        }
    }

    /// The coordinate of an argument in node units, u·(n − 1) ∈ [0, n − 1] for an axis of `n`
    /// nodes (node i at i): what a table's curve is written in, so that its knots are whole
    /// numbers. The cosine axis folds the scale into its own.
    pub fn position<F: Real>(self, x: F, n: usize) -> F {
        let scale = (n - 1) as f32;
        match self {
            Axis::Cosine => {
                (x.clamp(COSINE_FLOOR as f32, 1.0).sqrt().sqrt() - COSINE_FLOOR_ROOT)
                    * (scale / (1.0 - COSINE_FLOOR_ROOT))
            }
            _ => self.coordinate(x) * scale,
        }
    }

    /// The argument at node `i` of `n` (the inverse of [`Self::coordinate`]); `f64::INFINITY`
    /// for the last node of a depth axis.
    pub fn node(self, i: usize, n: usize) -> f64 {
        self.argument(i as f64, n)
    }

    /// The argument at the fractional node position `x` of `n` nodes (`x = i + ½` is the middle
    /// of cell `i`): the inverse of [`Self::coordinate`] at u = x/(n − 1).
    pub fn argument(self, x: f64, n: usize) -> f64 {
        let u = x / (n - 1) as f64;
        match self {
            Axis::Cosine => {
                let root = f64::from(COSINE_FLOOR_ROOT);
                (root + (1.0 - root) * u).powi(4)
            }
            Axis::Roughness => u * u,
            Axis::Ior => (2.0 + u) / (2.0 - u),
            // u = 1 (the last node) is τ = ∞.
            Axis::Depth => u / (1.0 - u),
            Axis::RootCosine => u * u,
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
    /// How its values round to 16 bits.
    pub rounding: Rounding,
}

/// How a table's values round to 16 bits when the table file is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rounding {
    /// To the nearest step.
    Nearest,
    /// To the nearest step at or below the value (a table whose lookup must not overshoot).
    Down,
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
    CoatScale,
    CoatPath,
    CoatDeficitAvg,
    FresnelTransmitAvg,
    CoatReturn,
    CoatEscape,
    Gtr1CoatDeficit,
    Gtr1CoatPath,
    Gtr1CoatDeficitAvg,
    Gtr1CoatReturn,
    Gtr1CoatEscape,
    GgxAlbedo,
    GgxAlbedoAvg,
    EonEscapeShape,
    SeedGgxDfgScale,
    SeedGgxDfgBias,
    ClearcoatDfgScale,
    ClearcoatDfgBias,
    GlossyBlur,
    GlossyScale,
    GlossyLobeAlbedo,
    GlossyNext,
    GlossyQuick,
    GlossySteady,
    GlossySlowRetention,
    GlossyPoolCosine,
    GlossyPath,
    GlossySpread,
}

/// The deficit decides the energy balance and switches on sharply near grazing incidence (where
/// α ≈ μ): it gets 32 × 32 (μ, r) nodes. The lobe's scale is solved against its interpolated
/// values (`glazec_lab::bake`), so that what the coat transmits and what its lobe reflects add up
/// to 1 between the nodes too. The smoother terms share coarser grids.
const DEFICIT_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 32), (Axis::Roughness, 32), (Axis::Ior, 8)];

/// The lobe's scale is smooth in μ except near grazing incidence, where the cosine axis is dense.
const SCALE_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 16), (Axis::Roughness, 16), (Axis::Ior, 8)];

const PATH_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 12), (Axis::Roughness, 12), (Axis::Ior, 8)];

const SLAB_GRID: [(Axis, usize); 3] = [(Axis::Depth, 16), (Axis::Roughness, 16), (Axis::Ior, 8)];

/// A `Gtr1` coat's tables: the same terms on coarser roughness axes (GTR1 is the clear coat's
/// lobe, and its tables share the uniform budget with GGX's in a material that has both), and
/// no lobe scale: the walks put GTR1's multiply-scattered reflection far from its lobe's peak
/// (at most 0.4% of the single-scattering lobe there, where a scale that reflects it adds
/// 2–9%), and there is little of it (⟨E_ms⟩ 0.29% at r 0.14, 0.37% at r 0.4), so it is left to
/// the transmission.
const GTR1_DEFICIT_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 32), (Axis::Roughness, 16), (Axis::Ior, 8)];
const GTR1_PATH_GRID: [(Axis, usize); 3] = [(Axis::Cosine, 12), (Axis::Roughness, 8), (Axis::Ior, 8)];
const GTR1_SLAB_GRID: [(Axis, usize); 3] = [(Axis::Depth, 16), (Axis::Roughness, 12), (Axis::Ior, 8)];

/// The split-sum DFG of the seed's coat lobes (image-based lighting): smooth in both arguments.
const DFG_GRID: [(Axis, usize); 2] = [(Axis::Cosine, 32), (Axis::Roughness, 32)];

/// A conductor under a coat (`layering`'s glossy level): per direction μ (outside the coat),
/// the conductor's roughness, the coat's roughness and its IOR. What these tables hold changes
/// over the whole range of μ (the share of the conductor's lobe that the escape cone cuts), so
/// μ is spaced in √μ rather than μ^¼. The share P₁ that leaves after one event, and the lobe's
/// scale solved against it, get the finest grid (P₁ is not monotonic in the coat's roughness at
/// grazing incidence); the composition of the trapped light, which only matters in proportion to
/// 1 − P₁, and the blur, which is smooth, coarser ones.
pub const GLOSSY_SINGLE_GRID: [(Axis, usize); 4] =
    [(Axis::RootCosine, 9), (Axis::Roughness, 8), (Axis::Roughness, 7), (Axis::Ior, 6)];

pub const GLOSSY_TRAPPED_GRID: [(Axis, usize); 4] =
    [(Axis::RootCosine, 5), (Axis::Roughness, 8), (Axis::Roughness, 6), (Axis::Ior, 6)];

pub const GLOSSY_BLUR_GRID: [(Axis, usize); 4] =
    [(Axis::RootCosine, 6), (Axis::Roughness, 4), (Axis::Roughness, 6), (Axis::Ior, 4)];

/// The pool of light trapped under a coat over a conductor: no direction (it has forgotten it).
pub const GLOSSY_POOL_GRID: [(Axis, usize); 3] = [(Axis::Roughness, 8), (Axis::Roughness, 6), (Axis::Ior, 6)];

/// The path of light that leaves a coat over a mirror after one reflection: per direction, per
/// optical depth (the Laplace transform of its path length), coat roughness and IOR.
pub const GLOSSY_PATH_GRID: [(Axis, usize); 4] =
    [(Axis::RootCosine, 7), (Axis::Depth, 4), (Axis::Roughness, 6), (Axis::Ior, 5)];

const S: Kind = Kind::Scalar;

/// Parameter lists of the lookup functions, one parameter per axis.
const COAT_PARAMS: &[(&str, Kind)] = &[("cos_theta", S), ("roughness", S), ("eta", S)];

const SLAB_PARAMS: &[(&str, Kind)] = &[("tau", S), ("roughness", S), ("eta", S)];

const COAT_AVG_PARAMS: &[(&str, Kind)] = &[("roughness", S), ("eta", S)];

const DFG_PARAMS: &[(&str, Kind)] = &[("cos_theta", S), ("roughness", S)];

const GLOSSY_PARAMS: &[(&str, Kind)] = &[("cos_theta", S), ("conductor_roughness", S), ("roughness", S), ("eta", S)];

const GLOSSY_POOL_PARAMS: &[(&str, Kind)] = &[("conductor_roughness", S), ("roughness", S), ("eta", S)];

const GLOSSY_PATH_PARAMS: &[(&str, Kind)] = &[("cos_theta", S), ("tau", S), ("roughness", S), ("eta", S)];

/// A coat table's lookup doc: what it holds (its first paragraph, the generated code's comment,
/// ends with where the table comes from), then how it is sampled.
macro_rules! table_doc {
    ($($line:literal),* $(,)?) => {
        &[
            $($line,)*
            "Tabulated by `glazec tables` from Heitz et al. 2016 microsurface walks and quadrature (f64).",
            "",
            "Multilinear in u ∝ μ^¼ (from μ = 1e-4), √r, 2(η − 1)/(η + 1), τ/(1 + τ), clamped to the range.",
        ]
    };
}

/// A glossy level's lookup doc, as [`table_doc`].
macro_rules! glossy_doc {
    ($($line:literal),* $(,)?) => {
        &[
            $($line,)*
            "Tabulated by `glazec tables` from white random walks through the reference's coat and",
            "conductor microsurfaces (Heitz et al. 2016; f64).",
            "",
            "Multilinear in μ, √r_c, √r, 2(η − 1)/(η + 1).",
        ]
    };
}

/// A seed lobe's DFG lookup doc, as [`table_doc`].
macro_rules! dfg_doc {
    ($($line:literal),* $(,)?) => {
        &[
            $($line,)*
            "Tabulated by `glazec tables` by deterministic quadrature of Bowsher 2022's lobe.",
            "",
            "The shared terms, Schlick's Fresnel split as F0·(1 − (1 − v·h)⁵) + (1 − v·h)⁵;",
            "multilinear in u ∝ μ^¼, √r.",
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
    TableSpec {
        name,
        axes,
        term: TermDef { name: function, params, ret: Kind::Scalar, doc },
        rounding: Rounding::Nearest,
    }
}

/// [`table`] for a table whose lookup must not overshoot ([`Rounding::Down`]).
const fn rounded_down(spec: TableSpec) -> TableSpec {
    TableSpec { rounding: Rounding::Down, ..spec }
}

/// The most table bytes one material's method can read: WebGPU's guaranteed uniform binding
/// size (`maxUniformBufferBindingSize`), so that a material's table uniform, which never holds
/// more than the tables it reads, always fits.
pub const TABLE_BUDGET: usize = 65_536;

/// Every table's layout. Changing one invalidates `crates/glazec/data/tables.bin` (regenerate it
/// with `glazec tables`).
pub const SPECS: [TableSpec; 29] = [
    rounded_down(table(
        "coat_deficit_table",
        &DEFICIT_GRID,
        "coat_deficit",
        COAT_PARAMS,
        &[
            "G(μ; r, η) = F(μ) − A(μ): how much less the rough interface reflects than a smooth one, A",
            "the albedo of its scaled lobe (`coat_scale`); T = 1 − F + G; 0 when smooth.",
            "Tabulated by `glazec tables` from Heitz et al. 2016 microsurface walks and quadrature (f64).",
            "",
            "A is E_ss + E_ms, single and multiple microfacet scattering, by quadrature; nodes are",
            "lowered until the lookup never overshoots it between them. G is negative where multiple",
            "scattering or Fresnel's convexity win. Multilinear in u ∝ μ^¼ (from μ = 1e-4), √r,",
            "2(η − 1)/(η + 1), clamped to the range.",
        ],
    )),
    table(
        "coat_scale_table",
        &SCALE_GRID,
        "coat_scale",
        COAT_PARAMS,
        table_doc![
            "c(μ; r, η): the scale of the rough interface's lobe, f_ss(l, v)·c(μl)·c(μv), for it to reflect",
            "E_ss + E_ms, single and multiple scattering (Turquin 2019, made reciprocal); 1 when smooth.",
        ],
    ),
    table(
        "coat_path_table",
        &PATH_GRID,
        "coat_path",
        COAT_PARAMS,
        table_doc![
            "q(μ; r, η) = μ′/μ_eff ≥ 1: how much longer the path through the slab is than along Snell's",
            "μ′, μ_eff the geometric-mean cosine of the directions the rough interface refracts into.",
        ],
    ),
    rounded_down(table(
        "coat_deficit_avg_table",
        &[DEFICIT_GRID[1], DEFICIT_GRID[2]],
        "coat_deficit_avg",
        COAT_AVG_PARAMS,
        table_doc!["⟨G⟩(r, η) = ∫ 2μ G(μ) dμ.",],
    )),
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
    rounded_down(table(
        "gtr1_coat_deficit_table",
        &GTR1_DEFICIT_GRID,
        "gtr1_coat_deficit",
        COAT_PARAMS,
        table_doc![
            "`coat_deficit` of a GTR1 microsurface (GTR1 normals, GTR1's own Smith masking) for its",
            "unscaled single-scattering lobe: G = F − E_ss, so T = 1 − E_ss carries the light GTR1",
            "reflects after more than one event (⟨E_ms⟩ ≤ 0.4%) into the coat (no `coat_scale`).",
        ],
    )),
    table(
        "gtr1_coat_path_table",
        &GTR1_PATH_GRID,
        "gtr1_coat_path",
        COAT_PARAMS,
        table_doc!["`coat_path` of a GTR1 microsurface.",],
    ),
    rounded_down(table(
        "gtr1_coat_deficit_avg_table",
        &[GTR1_DEFICIT_GRID[1], GTR1_DEFICIT_GRID[2]],
        "gtr1_coat_deficit_avg",
        COAT_AVG_PARAMS,
        table_doc!["⟨G⟩(r, η) = ∫ 2μ G(μ) dμ of `gtr1_coat_deficit`.",],
    )),
    table(
        "gtr1_coat_return_table",
        &GTR1_SLAB_GRID,
        "gtr1_coat_return",
        SLAB_PARAMS,
        table_doc!["`coat_return` of a GTR1 microsurface.",],
    ),
    table(
        "gtr1_coat_escape_table",
        &GTR1_SLAB_GRID,
        "gtr1_coat_escape",
        SLAB_PARAMS,
        table_doc!["`coat_escape` of a GTR1 microsurface.",],
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
    table(
        "seed_ggx_dfg_scale_table",
        &DFG_GRID,
        "seed_ggx_dfg_scale",
        DFG_PARAMS,
        dfg_doc![
            "A(μ; r) of Bowsher 2022's GGX coat lobe (Schlick-GGX Smith, k = (r + 1)²/8): its directional",
            "albedo is F0·A + B (the split-sum DFG of Karis 2013, for this lobe).",
        ],
    ),
    table(
        "seed_ggx_dfg_bias_table",
        &DFG_GRID,
        "seed_ggx_dfg_bias",
        DFG_PARAMS,
        dfg_doc!["B(μ; r) of Bowsher 2022's GGX coat lobe (see `seed_ggx_dfg_scale`).",],
    ),
    table(
        "clearcoat_dfg_scale_table",
        &DFG_GRID,
        "clearcoat_dfg_scale",
        DFG_PARAMS,
        dfg_doc![
            "A(μ; r) of the Disney clear-coat lobe (GTR1 of α = r², Smith at α = 0.25): its directional",
            "albedo is F0·A + B (the split-sum DFG of Karis 2013, for this lobe).",
        ],
    ),
    table(
        "clearcoat_dfg_bias_table",
        &DFG_GRID,
        "clearcoat_dfg_bias",
        DFG_PARAMS,
        dfg_doc!["B(μ; r) of the Disney clear-coat lobe (see `clearcoat_dfg_scale`).",],
    ),
    table(
        "glossy_blur_table",
        &GLOSSY_BLUR_GRID,
        "glossy_blur",
        GLOSSY_PARAMS,
        glossy_doc![
            "σ(μ; r_c, r, η)/r²: how much a rough coat (α = r²) widens the conductor's lobe under it,",
            "per crossing (α² = α_c² + σ_l² + σ_v²): the GGX width whose peak matches the conductor's",
            "peak seen through the coat's transmission from μ, tapered towards grazing.",
        ],
    ),
    table(
        "glossy_scale_table",
        &GLOSSY_SINGLE_GRID,
        "glossy_scale",
        GLOSSY_PARAMS,
        glossy_doc![
            "s(μ; r_c, r, η): the per-direction scale that makes the widened lobe s_l s_v f(l′, v′)",
            "reflect what leaves near the mirror direction (after one conductor event, or at the",
            "second from the trapped light's first return), for a white conductor under a clear coat",
            "(solved over μ at each node).",
        ],
    ),
    table(
        "glossy_lobe_albedo_table",
        &GLOSSY_SINGLE_GRID,
        "glossy_lobe_albedo",
        GLOSSY_PARAMS,
        glossy_doc![
            "K(μ; r_c, r, η): the white albedo of the level's lobe (scaled, `glossy_scale`) over T(μ),",
            "over its scale s(μ)² and over E(μ′; α)·c(μ′) (the white GGX albedo at the lobe's α and the",
            "share of the lobe inside the escape cone), so that the remainder, T(1 − s²K·E·c), takes",
            "what the lobe does not (fitted where probes between the nodes found a gain or a loss).",
        ],
    ),
    table(
        "glossy_next_table",
        &GLOSSY_TRAPPED_GRID,
        "glossy_next",
        GLOSSY_PARAMS,
        glossy_doc!["w₀(μ; r_c, r, η): the share of the trapped light that leaves at the next (second) event.",],
    ),
    table(
        "glossy_quick_table",
        &GLOSSY_TRAPPED_GRID,
        "glossy_quick",
        GLOSSY_PARAMS,
        glossy_doc!["w₁(μ; r_c, r, η): the share of the trapped light that leaves at the rate B = ½.",],
    ),
    table(
        "glossy_steady_table",
        &GLOSSY_TRAPPED_GRID,
        "glossy_steady",
        GLOSSY_PARAMS,
        glossy_doc![
            "w₂(μ; r_c, r, η): the share of the trapped light that leaves at the rate B = 0.8 (the",
            "rest, 1 − w₀ − w₁ − w₂, leaves at the slow rate `glossy_slow_retention`).",
        ],
    ),
    table(
        "glossy_slow_retention_table",
        &GLOSSY_POOL_GRID,
        "glossy_slow_retention",
        GLOSSY_POOL_PARAMS,
        glossy_doc!["B_s(r_c, r, η): the share of the slowest part of the trapped light that stays per event.",],
    ),
    table(
        "glossy_pool_cosine_table",
        &GLOSSY_POOL_GRID,
        "glossy_pool_cosine",
        GLOSSY_POOL_PARAMS,
        glossy_doc!["μ*(r_c, r, η): the mean cosine at which trapped light meets the conductor.",],
    ),
    table(
        "glossy_path_table",
        &GLOSSY_PATH_GRID,
        "glossy_path",
        GLOSSY_PATH_PARAMS,
        &[
            "q(μ; τ, r, η) ≥ 0: the light that enters at μ and leaves after one reflection keeps",
            "e^(−τ q/μ_eff) of itself per crossing (μ_eff: the cosine along which the coat's transmitted",
            "light is absorbed, Snell's over `coat_path`; q = 1 for a smooth coat).",
            "Tabulated by `glazec tables` from random walks through the reference's coat over a mirror (f64).",
            "",
            "Multilinear in √μ, τ/(1 + τ), √r, 2(η − 1)/(η + 1).",
        ],
    ),
    table(
        "glossy_spread_table",
        &GLOSSY_TRAPPED_GRID,
        "glossy_spread",
        GLOSSY_PARAMS,
        glossy_doc![
            "κ(μ; r_c, r, η): how much of its direction of travel the light entering at μ keeps when it",
            "leaves as the level's remainder (after three or more conductor events, or at the second",
            "after total internal reflection): the mean cosine of its azimuth about the forward",
            "direction is κ sin θ sin θₒ (each reflection off the conductor and each total internal",
            "reflection keeps the direction's horizontal part).",
        ],
    ),
];

/// The tables of a rough coat's interface, one set per microfacet distribution: GGX (`Ggx`
/// coats, and `Plastic`'s interface) and GTR1 (`Gtr1` coats).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CoatTables {
    pub deficit: TableId,
    /// The lobe's scale c(μ); `None`: the lobe is not scaled.
    pub scale: Option<TableId>,
    pub path: TableId,
    pub deficit_avg: TableId,
    pub slab_return: TableId,
    pub slab_escape: TableId,
}

impl CoatTables {
    pub const GGX: CoatTables = CoatTables {
        deficit: TableId::CoatDeficit,
        scale: Some(TableId::CoatScale),
        path: TableId::CoatPath,
        deficit_avg: TableId::CoatDeficitAvg,
        slab_return: TableId::CoatReturn,
        slab_escape: TableId::CoatEscape,
    };
    pub const GTR1: CoatTables = CoatTables {
        deficit: TableId::Gtr1CoatDeficit,
        scale: None,
        path: TableId::Gtr1CoatPath,
        deficit_avg: TableId::Gtr1CoatDeficitAvg,
        slab_return: TableId::Gtr1CoatReturn,
        slab_escape: TableId::Gtr1CoatEscape,
    };

    /// Both sets, GGX first.
    pub const ALL: [CoatTables; 2] = [CoatTables::GGX, CoatTables::GTR1];

    /// The set's tables.
    pub fn ids(self) -> Vec<TableId> {
        [Some(self.deficit), self.scale, Some(self.path), Some(self.deficit_avg)]
            .into_iter()
            .chain([Some(self.slab_return), Some(self.slab_escape)])
            .flatten()
            .collect()
    }
}

impl TableId {
    pub const ALL: [TableId; 29] = [
        TableId::CoatDeficit,
        TableId::CoatScale,
        TableId::CoatPath,
        TableId::CoatDeficitAvg,
        TableId::FresnelTransmitAvg,
        TableId::CoatReturn,
        TableId::CoatEscape,
        TableId::Gtr1CoatDeficit,
        TableId::Gtr1CoatPath,
        TableId::Gtr1CoatDeficitAvg,
        TableId::Gtr1CoatReturn,
        TableId::Gtr1CoatEscape,
        TableId::GgxAlbedo,
        TableId::GgxAlbedoAvg,
        TableId::EonEscapeShape,
        TableId::SeedGgxDfgScale,
        TableId::SeedGgxDfgBias,
        TableId::ClearcoatDfgScale,
        TableId::ClearcoatDfgBias,
        TableId::GlossyBlur,
        TableId::GlossyScale,
        TableId::GlossyLobeAlbedo,
        TableId::GlossyNext,
        TableId::GlossyQuick,
        TableId::GlossySteady,
        TableId::GlossySlowRetention,
        TableId::GlossyPoolCosine,
        TableId::GlossyPath,
        TableId::GlossySpread,
    ];

    /// Whether only the seed's methods (`Additive`, `WeidlichWilkie`) read the table: their coat
    /// lobes' split-sum DFG. The default method never does, so a material's tables come from
    /// one side of this split or the other, each within [`TABLE_BUDGET`].
    pub fn is_seed_only(self) -> bool {
        matches!(
            self,
            TableId::SeedGgxDfgScale | TableId::SeedGgxDfgBias | TableId::ClearcoatDfgScale | TableId::ClearcoatDfgBias
        )
    }

    /// Whether the table belongs to the glossy level (a conductor under a coat;
    /// `glazec_lab::bake::glossy`).
    pub fn is_glossy(self) -> bool {
        self.spec().name.starts_with("glossy_")
    }

    pub fn spec(self) -> &'static TableSpec {
        &SPECS[self as usize]
    }
}
