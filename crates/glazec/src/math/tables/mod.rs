//! Tabulated terms: the functions of the default method that have no closed form.
//!
//! A rough dielectric coat transmits T(μ) = 1 − R(μ), where R includes light that scatters more
//! than once between the microfacets (Heitz et al. 2016); seen from inside, its internal
//! reflection sets how much diffuse light comes back down (R(τ)) or escapes (E_esc(τ)) through
//! an absorbing slab. None of these has a closed form, so `glazec tables` samples them (the
//! stochastic reference's microsurface walks plus deterministic quadrature, in f64) on the grids
//! below and stores them in `crates/glazec/data/tables.bin`, which is compiled into the crate. A
//! GGX conductor's single-scattering albedo is tabulated the same way, and so is the split-sum
//! DFG of the seed's two coat lobes, which image-based lighting needs for the seed's methods
//! (`layering::environment`; by quadrature of that lobe itself).
//!
//! **Axes.** Every axis maps its argument to a coordinate u ∈ [0, 1] sampled at n uniform nodes:
//! [`Axis::Cosine`] u = (μ^¼ − μ₀^¼)/(1 − μ₀^¼) from μ₀ = 10⁻⁴ (dense near grazing, where a rough
//! interface's albedo changes fastest), [`Axis::Roughness`]
//! u = √r (α = r²), [`Axis::Ior`] u = 2(η − 1)/(η + 1) (η ∈ [1, 3]; u² = 4·F0), [`Axis::Depth`]
//! u = τ/(1 + τ) (τ ∈ [0, ∞]). Arguments outside the range clamp to its ends.
//!
//! **Lookups** are multilinear ([`lookup`]). They are written once over the shading ops, like
//! every term: on the CPU they interpolate directly; in a shader a lookup whose arguments are
//! all compile-time constants folds to a number; for a material without runtime parameters, one
//! whose arguments are constants but for one is that table's [`Curve`] along the free axis, a
//! closed form in the code (which the CPU then sums too); any other becomes a call of the
//! table's lookup function (`coat_deficit`, `coat_escape`, …), which reads the material's table
//! uniform (the entries its lookups can reach; its binding is in `crate::lower::bindings`).
//! Tables are not emitted as constant arrays: see [`Curve`] and `lower::builder`'s
//! `tables_buffer` for what that cost on lavapipe.
//!
//! **Precision.** Every table is stored as 16-bit fixed point over its own range, value =
//! offset + scale·u for u ∈ [0, 65535] (a step of range/65535: 1.5·10⁻⁵ for a table within
//! [0, 1], far below the tables' own sampling and interpolation errors), in the table file and in
//! the buffer, two entries per 32-bit word. The CPU decodes the same 16-bit values with the same
//! f32 arithmetic as a shader, so a shader and the CPU still evaluate the same numbers (a GPU may
//! fuse the multiply-add: half an ulp). The single-scattering deficit rounds down
//! ([`Rounding::Down`]) so that its lookup stays at or below the truth (`glazec_lab::bake`);
//! everything else to nearest. Sixteen bits halve what the tables spend of the 64 KiB a uniform
//! binding guarantees. (Half floats would need `unpack2x16float`, which naga validates only with
//! the `SHADER_FLOAT16_IN_FLOAT32` capability, and which llvmpipe supports only with native f16.)

mod catalogue;
mod curve;
mod multilinear;
mod storage;

pub use catalogue::{
    Axis, COSINE_FLOOR, COSINE_FLOOR_ROOT, CoatTables, GLOSSY_BLUR_GRID, GLOSSY_PATH_GRID, GLOSSY_POOL_GRID,
    GLOSSY_SINGLE_GRID, GLOSSY_TRAPPED_GRID, Rounding, SPECS, TABLE_BUDGET, TableId, TableSpec,
};
pub use curve::{Curve, Form, KNOT_TOLERANCE, curves_for, curves_on_cpu, keep_knots, with_curves};
pub use storage::{
    Quantization, buffer, buffer_len, buffer_vec4s, decode, decode_by_name, encode, evaluate_on_cpu_with, total_bytes,
};

use super::{Real, Slot};
pub(crate) use multilinear::corner_sum;
use multilinear::multilinear;

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
        // On the CPU, for a material whose shader sums curves ([`with_curves`]), a lookup along a
        // direction is the same curve, summed in the same order, so that the two agree to
        // rounding even where a lobe divides by a tiny table value (a sharp coat's
        // multiple-scattering share).
        if F::IMMEDIATE
            && F::table_curves(args[0].ctx())
            && spec.axes.len() > 1
            && matches!(spec.axes[0].0, Axis::Cosine | Axis::RootCosine)
        {
            // (No allocation: this is the CPU's hot path. Tables have at most four axes.)
            let mut fixed = [0.0_f32; 4];
            for (f, x) in fixed.iter_mut().zip(args) {
                *f = x.known().unwrap_or(0.0);
            }
            return curve::on_cpu(id, &fixed[..args.len()], |curve| curve.evaluate(args[0]));
        }
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

#[cfg(test)]
mod tests {
    use super::storage::TABLE_FILE;
    use super::*;

    #[test]
    fn stored_tables_decode_and_fit_the_budget() {
        let tables = decode(TABLE_FILE).expect("crates/glazec/data/tables.bin decodes");
        assert_eq!(tables.len(), SPECS.len());
        // The default method reads every table but the seed's DFG; the seed's methods those and
        // at most the shared GGX albedo. Without a Gtr1 coat, or without a coated conductor (the
        // glossy level), a material's tables always fit; with both, and runtime parameters
        // enough to read most of them, `compile` says so (E0222).
        let bytes = |keep: fn(&TableId) -> bool| -> usize {
            TableId::ALL.iter().filter(|id| keep(id)).map(|id| 2 * id.spec().len()).sum()
        };
        let without_gtr1 = bytes(|id| !id.is_seed_only() && !CoatTables::GTR1.ids().contains(id));
        let without_glossy = bytes(|id| !id.is_seed_only() && !id.is_glossy());
        let seed_methods = bytes(|id| id.is_seed_only() || matches!(id, TableId::GgxAlbedo | TableId::GgxAlbedoAvg));
        assert!(without_gtr1 <= TABLE_BUDGET, "the default method's tables but GTR1's: {without_gtr1} bytes");
        assert!(without_glossy <= TABLE_BUDGET, "the default method's tables but the glossy level's: {without_glossy}");
        assert!(seed_methods <= TABLE_BUDGET, "the seed's tables: {seed_methods} bytes");
        assert_eq!(total_bytes(), bytes(|_| true));
        for (spec, values) in SPECS.iter().zip(&tables) {
            // The deficit (and so its average) may be slightly negative: the table is lowered
            // until its lookup never overshoots (`glazec_lab::bake`). The normalised slab tables
            // exceed 1.
            let range = if spec.name.contains("coat_deficit") { -1.0..=1.0 } else { 0.0..=100.0 };
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
