//! Where the default method's clay kernel spends its time: the generated `eval_pairs` kernel of
//! the seed's clay stack under the default method, as generated and with parts of its library
//! replaced (its WGSL edited), timed on the device in interleaved rounds against the
//! WeidlichWilkie clay written by hand (`glazec_lab::bench::CLAY_BY_HAND`). The edited kernels
//! compute a wrong BRDF; only their time means something:
//!
//! * curves as constants: each `*_curve` (a table lookup baked along the direction, summed as
//!   hinges) returns a constant, so its hinges and its argument's μ^¼ are gone;
//! * no second event: the coat lobe's second microfacet event is left out;
//! * both.
//!
//! And, for each of the clay coat's three curves, the nodes it keeps against the knots a
//! piecewise-linear function within 10⁻⁴ of it (issue 30's bound) needs, chosen through 2,001
//! points uniform in the table's coordinate by the curves' own knot selection
//! (`tables::keep_knots`): how much smaller a curve within that bound could be.
//!
//! `cargo run --release -p glazec-lab --example kernel_breakdown` (docs/speed.md quotes it).

use glazec::math::tables::{Curve, TableId, keep_knots};
use glazec_gpu::throughput::{PAIRS, interleaved_seconds, pairs};
use glazec_gpu::{EvalKernel, Gpu};
use glazec_lab::bench::{CLAY_BY_HAND, CLAY_STACK};

/// `wgsl` with the body of every function whose name ends in `_curve` replaced by
/// `return <argument> * 1e-4 + 1;`.
fn curves_as_constants(wgsl: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = wgsl;
    let mut replaced = 0;
    while let Some(start) = rest.find("\nfn ") {
        let (before, from) = rest.split_at(start + 1);
        out.push_str(before);
        let header_end = from.find('{').ok_or("a function without a body")?;
        let header = &from[..header_end];
        let body_end = from.find("\n}\n").ok_or("a function without its closing brace")? + 3;
        let name = header.trim_start_matches("fn ").split('(').next().unwrap_or_default();
        if name.ends_with("_curve") {
            let argument = header.split('(').nth(1).and_then(|a| a.split(':').next()).ok_or("no argument")?;
            out.push_str(&format!("{header}{{\n    return {argument} * 0.0001f + 1f;\n}}\n"));
            replaced += 1;
        } else {
            out.push_str(&from[..body_end]);
        }
        rest = &from[body_end..];
    }
    out.push_str(rest);
    if replaced == 0 { Err("no curves in the kernel".into()) } else { Ok(out) }
}

/// `wgsl` without the coat's second microfacet event (its term replaced by zero).
fn without_second_event(wgsl: &str) -> Result<String, String> {
    let term = "vec3(layer1_second_event)";
    if !wgsl.contains(term) {
        return Err(format!("`{term}` not in the kernel"));
    }
    Ok(wgsl.replace(term, "vec3(0f)"))
}

/// The clay coat's roughness and IOR (`CLAY_STACK`).
const CLAY_COAT: [f32; 2] = [0.35, 1.5];
/// Issue 30's bound on a specialised curve against the lookup it replaces.
const BOUND: f64 = 1e-4;
/// Points the knots are chosen among.
const POINTS: usize = 2001;

fn knot_counts() {
    println!("| curve (clay's coat) | nodes kept | knots within {BOUND:e} (interior) |\n|---|---|---|");
    for table in [TableId::CoatScale, TableId::CoatDeficit, TableId::CoatPath] {
        let curve = Curve::of_table(table, 0, &[0.0, CLAY_COAT[0], CLAY_COAT[1]]);
        let points: Vec<(f64, f64)> = (0..POINTS)
            .map(|i| {
                let u = i as f64 / (POINTS - 1) as f64;
                (u, f64::from(curve.evaluate::<f32>(curve.mapping.node(i, POINTS) as f32)))
            })
            .collect();
        // (Interior knots: the two ends are always kept.)
        println!("| {table:?} | {} of {} | {} |", curve.kept(), curve.nodes, keep_knots(&points, BOUND).len() - 2);
    }
    println!();
}

fn main() -> Result<(), String> {
    knot_counts();
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    let compiled =
        glazec::compile(&format!("Material(name: \"clay_default\", {CLAY_STACK})")).map_err(|e| format!("{e:?}"))?;
    let generated = compiled.whole_wgsl().map_err(|e| e.to_string())?;
    let variants = [
        ("WeidlichWilkie, written by hand", CLAY_BY_HAND.to_string()),
        ("default method, as generated", generated.clone()),
        ("curves as constants", curves_as_constants(&generated)?),
        ("no second event", without_second_event(&generated)?),
        ("curves as constants, no second event", without_second_event(&curves_as_constants(&generated)?)?),
    ];
    let kernels: Vec<EvalKernel> = variants
        .iter()
        .map(|(label, wgsl)| EvalKernel::from_wgsl(&gpu, label, wgsl).map_err(|e| e.to_string()))
        .collect::<Result<_, _>>()?;
    let refs: Vec<&EvalKernel> = kernels.iter().collect();
    let seconds = interleaved_seconds(&gpu, &refs, &pairs(PAIRS)).map_err(|e| e.to_string())?;
    println!("Device: {}. Median of interleaved dispatches of {PAIRS} pairs.\n", gpu.describe());
    println!("| kernel | M evaluations/s | time vs WeidlichWilkie by hand | time vs as generated |\n|---|---|---|---|");
    for ((label, _), s) in variants.iter().zip(&seconds) {
        println!("| {label} | {:.1} | {:.2}× | {:.2}× |", PAIRS as f64 / s / 1e6, s / seconds[0], s / seconds[1]);
    }
    Ok(())
}
