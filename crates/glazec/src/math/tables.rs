//! Tabulated terms: the functions of the default method that have no closed form.
//!
//! A rough dielectric coat transmits T(μ) = 1 − R(μ), where R includes light that scatters more
//! than once between the microfacets (Heitz et al. 2016); seen from inside, its internal
//! reflection sets how much diffuse light comes back down (R(τ)) or escapes (E_esc(τ)) through
//! an absorbing slab. None of these has a closed form, so `glazec tables` samples them (the
//! stochastic reference's microsurface walks plus deterministic quadrature, in f64) on the grids
//! below and stores them in `data/tables.bin`, which is compiled into the crate. A GGX
//! conductor's single-scattering albedo is tabulated the same way, and so is the split-sum DFG of
//! the seed's two coat lobes, which image-based lighting needs for the seed's methods
//! (`layering::environment`; by quadrature of the seed's lobe itself).
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
//!
//! **Precision.** Every table is stored as 16-bit fixed point over its own range, value =
//! offset + scale·u for u ∈ [0, 65535] (a step of range/65535: 1.5·10⁻⁵ for a table within
//! [0, 1], far below the tables' own sampling and interpolation errors), in the table file and in
//! the buffer, two entries per 32-bit word. The CPU decodes the same 16-bit values with the same
//! f32 arithmetic as a shader, so a shader and the CPU still evaluate the same numbers (a GPU may
//! fuse the multiply-add: half an ulp). The single-scattering deficit rounds down
//! ([`Rounding::Down`]) so that its lookup stays at or below the truth (`accuracy::tables`);
//! everything else to nearest. Sixteen bits halve what the tables spend of the 64 KiB a uniform
//! binding guarantees. (Half floats would need `unpack2x16float`, which naga validates only with
//! the `SHADER_FLOAT16_IN_FLOAT32` capability, and which llvmpipe supports only with native f16.)

use std::sync::{Arc, OnceLock};

use super::{Codes, Kind, Real, Slot, TermDef};

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

/// A table's 16-bit encoding: value = offset + scale·u.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantization {
    pub offset: f32,
    pub scale: f32,
}

impl Quantization {
    /// The encoding that spans `values` (a constant table gets scale 1).
    pub fn spanning(values: &[f32]) -> Quantization {
        let lo = values.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        let scale = if hi > lo { (hi - lo) / 65_535.0 } else { 1.0 };
        Quantization { offset: lo, scale }
    }

    /// The value of code `u`, in the f32 arithmetic a shader uses.
    pub fn decode(self, u: u16) -> f32 {
        f32::from(u) * self.scale + self.offset
    }

    /// The code of `value`, rounded as asked and clamped to the codes: the code whose decoded
    /// value is nearest, or the largest whose decoded value is not above `value` (judged by
    /// [`Self::decode`] itself, so that decoding and encoding again gives the same code).
    pub fn encode(self, value: f32, rounding: Rounding) -> u16 {
        let guess = ((value - self.offset) / self.scale).floor().clamp(0.0, 65_535.0) as u16;
        let candidates = [guess.saturating_sub(1), guess, guess.saturating_add(1)];
        match rounding {
            Rounding::Nearest => candidates
                .into_iter()
                .min_by(|&a, &b| (self.decode(a) - value).abs().total_cmp(&(self.decode(b) - value).abs()))
                .unwrap_or(guess),
            Rounding::Down => candidates.into_iter().rev().find(|&c| self.decode(c) <= value).unwrap_or(candidates[0]),
        }
    }
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

/// The first doc lines of the glossy level's lookup functions.
macro_rules! glossy_doc {
    ($($line:literal),* $(,)?) => {
        &[
            "Tabulated by `glazec tables` from white random walks through the reference's coat and",
            "conductor microsurfaces (Heitz et al. 2016; f64); multilinear in μ, √r_c, √r, 2(η − 1)/(η + 1).",
            $($line),*
        ]
    };
}

/// The first doc lines of the seed lobes' DFG lookup functions.
macro_rules! dfg_doc {
    ($($line:literal),* $(,)?) => {
        &[
            "Tabulated by `glazec tables` by deterministic quadrature of the seed's lobe (the shared terms,",
            "Schlick's Fresnel split as F0·(1 − (1 − v·h)⁵) + (1 − v·h)⁵); multilinear in u ∝ μ^¼, √r.",
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

/// Every table's layout. Changing one invalidates `data/tables.bin` (regenerate it with
/// `glazec tables`).
pub const SPECS: [TableSpec; 24] = [
    rounded_down(table(
        "coat_deficit_table",
        &DEFICIT_GRID,
        "coat_deficit",
        COAT_PARAMS,
        table_doc![
            "G(μ; r, η) = F(μ) − E_ss(μ): how much less the rough interface's single-scattering",
            "reflection lobe reflects than a smooth interface (masking, shadowing, light sent below",
            "the horizon; slightly negative where Fresnel's convexity wins); 0 when smooth.",
        ],
    )),
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
    rounded_down(table(
        "coat_deficit_avg_table",
        &[DEFICIT_GRID[1], DEFICIT_GRID[2]],
        "coat_deficit_avg",
        COAT_AVG_PARAMS,
        table_doc!["⟨G⟩(r, η) = ∫ 2μ G(μ) dμ.",],
    )),
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
    table(
        "seed_ggx_dfg_scale_table",
        &DFG_GRID,
        "seed_ggx_dfg_scale",
        DFG_PARAMS,
        dfg_doc![
            "A(μ; r) of the seed's GGX coat lobe (Schlick-GGX Smith, k = (r + 1)²/8): its directional",
            "albedo is F0·A + B (the split-sum DFG of Karis 2013, for this lobe).",
        ],
    ),
    table(
        "seed_ggx_dfg_bias_table",
        &DFG_GRID,
        "seed_ggx_dfg_bias",
        DFG_PARAMS,
        dfg_doc!["B(μ; r) of the seed's GGX coat lobe (see `seed_ggx_dfg_scale`).",],
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
            "Tabulated by `glazec tables` from random walks through the reference's coat over a mirror",
            "(f64); multilinear in √μ, τ/(1 + τ), √r, 2(η − 1)/(η + 1).",
            "q(μ; τ, r, η) ≥ 0: the light that enters at μ and leaves after one reflection keeps",
            "e^(−τ q/μ_eff) of itself per crossing (μ_eff: the cosine along which the coat's transmitted",
            "light is absorbed, Snell's over `coat_path`; q = 1 for a smooth coat).",
        ],
    ),
];

impl TableId {
    pub const ALL: [TableId; 24] = [
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
    ];

    /// Whether the table belongs to the glossy level (a conductor under a coat;
    /// `accuracy::glossy`).
    pub fn is_glossy(self) -> bool {
        self.spec().name.starts_with("glossy_")
    }

    pub fn spec(self) -> &'static TableSpec {
        &SPECS[self as usize]
    }

    /// The table's values (compiled into the crate from `data/tables.bin`), decoded.
    pub fn values(self) -> &'static Arc<[f32]> {
        &stored()[self as usize].values
    }

    /// The table's 16-bit codes, as stored.
    pub fn codes(self) -> &'static [u16] {
        &stored()[self as usize].codes
    }

    /// The table's encoding.
    pub fn quantization(self) -> Quantization {
        stored()[self as usize].quantization
    }
}

impl TableId {
    /// Where the table starts in [`buffer`], in entries (16-bit codes).
    pub fn buffer_offset(self) -> u32 {
        TableId::ALL.iter().take_while(|&&id| id != self).map(|id| id.spec().len() as u32).sum()
    }
}

/// Every table's 16-bit codes, concatenated in [`SPECS`] order, two to a 32-bit word (entry i in
/// the low half of word i / 2 when i is even, the high half when odd), padded with zeros to whole
/// `vec4<u32>` elements: the contents of the table buffer a shader binds when a lookup has an
/// argument known only at run time (`crate::lower::bindings`). A shader decodes entry i of table
/// t as offset_t + scale_t·u ([`TableId::quantization`], literals in its lookup function).
pub fn buffer() -> Vec<u32> {
    let codes: Vec<u16> = TableId::ALL.iter().flat_map(|id| id.codes().iter().copied()).collect();
    let mut words: Vec<u32> =
        codes.chunks(2).map(|pair| u32::from(pair[0]) | u32::from(pair.get(1).copied().unwrap_or(0)) << 16).collect();
    words.resize(4 * buffer_vec4s(), 0);
    words
}

/// Entries (16-bit codes) of [`buffer`], without its padding.
pub fn buffer_len() -> usize {
    SPECS.iter().map(TableSpec::len).sum()
}

/// `vec4<u32>` elements of [`buffer`] (eight entries each).
pub fn buffer_vec4s() -> usize {
    buffer_len().div_ceil(8)
}

/// The table file, compiled in.
const TABLE_FILE: &[u8] = include_bytes!("../../data/tables.bin");
const MAGIC: &[u8; 8] = b"GLAZTAB2";

/// One stored table.
struct Stored {
    codes: Vec<u16>,
    quantization: Quantization,
    values: Arc<[f32]>,
}

/// Tables that replace the compiled-in ones on the CPU ([`evaluate_on_cpu_with`]); null: none.
static OVERRIDE: std::sync::atomic::AtomicPtr<Vec<Stored>> = std::sync::atomic::AtomicPtr::new(std::ptr::null_mut());

/// Makes every CPU evaluation in this process read `tables` (values per table, in [`SPECS`]
/// order, stored as [`encode`] would store them) instead of the compiled-in file. For
/// `glazec tables`, whose later tables are defined through the compiled math evaluated with the
/// tables it has just computed (`accuracy::tables`); shaders are not affected. Each call leaks
/// its tables (a few tens of kilobytes, a handful of times per generation).
pub fn evaluate_on_cpu_with(tables: &[Vec<f32>]) {
    let stored: Vec<Stored> = SPECS
        .iter()
        .zip(tables)
        .map(|(spec, values)| {
            let quantization = Quantization::spanning(values);
            let codes: Vec<u16> = values.iter().map(|&v| quantization.encode(v, spec.rounding)).collect();
            let values = codes.iter().map(|&u| quantization.decode(u)).collect();
            Stored { codes, quantization, values }
        })
        .collect();
    OVERRIDE.store(Box::into_raw(Box::new(stored)), std::sync::atomic::Ordering::Release);
}

fn stored() -> &'static [Stored] {
    let replaced = OVERRIDE.load(std::sync::atomic::Ordering::Acquire);
    if !replaced.is_null() {
        // SAFETY: set only by `evaluate_on_cpu_with` from a leaked box, never freed.
        return unsafe { &*replaced };
    }
    static TABLES: OnceLock<Vec<Stored>> = OnceLock::new();
    TABLES.get_or_init(|| match decode_codes(TABLE_FILE) {
        Ok(tables) => tables
            .into_iter()
            .map(|(quantization, codes)| {
                let values = codes.iter().map(|&u| quantization.decode(u)).collect();
                Stored { codes, quantization, values }
            })
            .collect(),
        // The file ships with the crate and a test decodes it; a mismatch is a build of
        // inconsistent sources, not bad user input.
        Err(e) => panic!("data/tables.bin does not match the table layout ({e}); run `glazec tables`"),
    })
}

/// The table file: magic, table count, then per table its name (u8 length + UTF-8), its entry
/// count (u32), its encoding's offset and scale (f32) and its codes (u16, rounded as its spec
/// says), all little-endian, in [`SPECS`] order.
pub fn encode(tables: &[Vec<f32>]) -> Vec<u8> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&(tables.len() as u32).to_le_bytes());
    for (spec, values) in SPECS.iter().zip(tables) {
        let q = Quantization::spanning(values);
        bytes.push(spec.name.len() as u8);
        bytes.extend_from_slice(spec.name.as_bytes());
        bytes.extend_from_slice(&(values.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&q.offset.to_le_bytes());
        bytes.extend_from_slice(&q.scale.to_le_bytes());
        for &v in values {
            bytes.extend_from_slice(&q.encode(v, spec.rounding).to_le_bytes());
        }
    }
    bytes
}

/// Reads a table file, checking it against [`SPECS`]: the decoded values.
pub fn decode(bytes: &[u8]) -> Result<Vec<Vec<f32>>, String> {
    Ok(decode_codes(bytes)?.into_iter().map(|(q, codes)| codes.iter().map(|&u| q.decode(u)).collect()).collect())
}

/// Reads the tables a table file holds by name, whatever its layout: for every table of [`SPECS`],
/// its decoded values if the file has a table of that name and size (`glazec tables
/// --glossy-only` keeps the others of an existing file).
pub fn decode_by_name(bytes: &[u8]) -> Vec<Option<Vec<f32>>> {
    let mut found: Vec<Option<Vec<f32>>> = vec![None; SPECS.len()];
    let mut at = 12;
    let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    if bytes.get(..8) != Some(MAGIC.as_slice()) {
        return found;
    }
    while at < bytes.len() {
        let Some(&name_len) = bytes.get(at) else { break };
        let Some(name) = bytes.get(at + 1..at + 1 + name_len as usize) else { break };
        at += 1 + name_len as usize;
        let Some(header) = bytes.get(at..at + 12) else { break };
        let (len, offset, scale) =
            (word(header) as usize, f32::from_bits(word(&header[4..])), f32::from_bits(word(&header[8..])));
        at += 12;
        let Some(codes) = bytes.get(at..at + 2 * len) else { break };
        at += 2 * len;
        let q = Quantization { offset, scale };
        let values: Vec<f32> = codes.chunks_exact(2).map(|c| q.decode(u16::from_le_bytes([c[0], c[1]]))).collect();
        if let Some(i) = SPECS.iter().position(|spec| spec.name.as_bytes() == name && spec.len() == len) {
            found[i] = Some(values);
        }
    }
    found
}

/// Reads a table file: each table's encoding and codes.
fn decode_codes(bytes: &[u8]) -> Result<Vec<(Quantization, Vec<u16>)>, String> {
    let mut at = 0;
    let mut take = |n: usize| -> Result<&[u8], String> {
        let s = bytes.get(at..at + n).ok_or("truncated")?;
        at += n;
        Ok(s)
    };
    if take(8)? != MAGIC {
        return Err("not a glazec table file (of this version)".into());
    }
    let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    if word(take(4)?) as usize != SPECS.len() {
        return Err("wrong table count".into());
    }
    let mut tables = Vec::new();
    for spec in &SPECS {
        let name_len = take(1)?[0] as usize;
        if take(name_len)? != spec.name.as_bytes() {
            return Err(format!("expected table {}", spec.name));
        }
        if word(take(4)?) as usize != spec.len() {
            return Err(format!("{} has the wrong size", spec.name));
        }
        let offset = f32::from_bits(word(take(4)?));
        let scale = f32::from_bits(word(take(4)?));
        let codes = take(2 * spec.len())?.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
        tables.push((Quantization { offset, scale }, codes));
    }
    if at != bytes.len() {
        return Err("trailing bytes".into());
    }
    Ok(tables)
}

/// Bytes of table data compiled into the crate (two per entry).
pub fn total_bytes() -> usize {
    SPECS.iter().map(|s| 2 * s.len()).sum()
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
        // The entry's value: offset + scale·code, the stored encoding.
        let quantization = id.quantization();
        let mut code = F::fetch(Codes { codes: id.codes(), buffer_offset: id.buffer_offset() }, index);
        // Corner names list the lower (l) or upper (u) node per axis, first axis first: `at_lul`.
        let corner_name =
            || -> String { (0..cells.len()).map(|a| if corner >> a & 1 == 1 { 'u' } else { 'l' }).collect() };
        if !names.is_empty() {
            code = code.named(&format!("code_{}", corner_name()));
        }
        let mut value = code * quantization.scale + quantization.offset;
        if !names.is_empty() {
            value = value.named(&format!("at_{}", corner_name()));
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
        // Decoding and encoding again gives the stored codes (with the stored encodings).
        for (id, values) in TableId::ALL.iter().zip(&tables) {
            let (q, rounding) = (id.quantization(), id.spec().rounding);
            assert!(values.iter().zip(id.codes()).all(|(&v, &u)| q.encode(v, rounding) == u), "{id:?}");
        }
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
    fn rounding_down_never_rounds_up() {
        let q = Quantization::spanning(&[-0.01, 0.7]);
        for x in [0.3_f32, -0.003, 1e-7, 0.0, 0.123_456, 0.699_99, -0.01, 0.7] {
            let down = q.decode(q.encode(x, Rounding::Down));
            let nearest = q.decode(q.encode(x, Rounding::Nearest));
            assert!(down <= x, "{x}: {down}");
            assert!(x - down <= 1.01 * q.scale, "{x}: {down} is more than a step below");
            assert!((x - nearest).abs() <= 0.51 * q.scale, "{x}: nearest {nearest}");
        }
    }

    #[test]
    fn buffer_packs_two_codes_per_word() {
        let words = buffer();
        assert_eq!(words.len(), 4 * buffer_vec4s());
        for id in [TableId::CoatDeficit, TableId::GgxAlbedo, TableId::EonEscapeShape] {
            let q = id.quantization();
            for (i, &v) in id.values().iter().enumerate().step_by(7) {
                let at = id.buffer_offset() as usize + i;
                let code = (words[at / 2] >> (16 * (at % 2))) as u16;
                assert_eq!(q.decode(code), v, "{id:?} {i}");
            }
        }
    }

    #[test]
    fn axis_nodes_invert_coordinates() {
        for axis in [Axis::Cosine, Axis::Roughness, Axis::Ior, Axis::Depth, Axis::RootCosine] {
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
