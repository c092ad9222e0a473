//! Stacks of smooth coats over Lambert: glazec's CPU evaluation over the exact answer
//! (`glazec_lab::reference::smooth_stack`), at body and grazing pairs 90° of azimuth apart (off
//! the mirror directions), in the red channel; then the directional albedo glazec states (what
//! image-based lighting weighs: the sum of `<m>_ibl_lobes`' weights) over the exact one. Each
//! coat's IOR is relative to the medium above.
//!
//! `cargo run --release -p glazec-lab --example smooth_stack`

use glazec::math::sampling::direction_deg;
use glazec::model::{Material, ParamValue};
use glazec_lab::reference::Stack;
use glazec_lab::reference::smooth_stack::SmoothStack;

/// A stack: its label, its coats as (IOR, absorption) at thickness 1, and the Lambert albedo.
type Probe = (&'static str, &'static [(f64, f64)], f64);

const STACKS: [Probe; 17] = [
    ("one coat 1.5", &[(1.5, 0.0)], 0.8),
    ("one coat 0.8", &[(0.8, 0.0)], 0.8),
    ("two coats 2.0 / 0.8, white", &[(2.0, 0.0), (0.8, 0.0)], 1.0),
    ("two coats 2.0 / 0.8", &[(2.0, 0.0), (0.8, 0.0)], 0.8),
    ("two coats 1.5 / 0.9", &[(1.5, 0.0), (0.9, 0.0)], 0.8),
    ("two coats 1.5 / 1.4", &[(1.5, 0.0), (1.4, 0.0)], 0.8),
    ("two coats 1.5 / 1.5", &[(1.5, 0.0), (1.5, 0.0)], 0.8),
    ("two coats 1.5 / 1.5, white", &[(1.5, 0.0), (1.5, 0.0)], 1.0),
    ("three coats 1.5 / 1.5 / 1.5", &[(1.5, 0.0), (1.5, 0.0), (1.5, 0.0)], 0.8),
    ("three coats 1.5 / 1.5 / 1.5, white", &[(1.5, 0.0), (1.5, 0.0), (1.5, 0.0)], 1.0),
    ("three coats 1.5 / 1.4 / 1.5", &[(1.5, 0.0), (1.4, 0.0), (1.5, 0.0)], 0.8),
    ("three coats 1.3 / 1.4 / 1.5", &[(1.3, 0.0), (1.4, 0.0), (1.5, 0.0)], 0.8),
    ("three coats 1.5 / 1.4 / 1.3", &[(1.5, 0.0), (1.4, 0.0), (1.3, 0.0)], 0.8),
    ("two coats 1.5 / 1.0 absorbing 0.3", &[(1.5, 0.0), (1.0, 0.3)], 0.8),
    ("two coats 1.5 / 1.1 absorbing 0.3", &[(1.5, 0.0), (1.1, 0.3)], 0.8),
    ("three coats 1.5 / 1.4 absorbing 0.3 / 1.5", &[(1.5, 0.0), (1.4, 0.3), (1.5, 0.0)], 0.8),
    ("four coats 1.5 / 1.5 / 1.5 / 1.5", &[(1.5, 0.0), (1.5, 0.0), (1.5, 0.0), (1.5, 0.0)], 0.8),
];

/// (θl, θv) in degrees.
const PAIRS: [(f64, f64); 5] = [(0.0, 30.0), (30.0, 60.0), (60.0, 60.0), (45.0, 80.0), (85.0, 85.0)];
/// View angles of the albedo table, degrees.
const VIEWS: [f64; 4] = [0.0, 30.0, 60.0, 80.0];

/// A stack's material, its default parameter values and its exact answer.
fn probe((_, coats, rho): Probe) -> Result<(Material, Vec<ParamValue>, SmoothStack), String> {
    let layers: Vec<String> = coats
        .iter()
        .map(|(ior, absorption)| format!("Coat(lobe: Smooth, ior: {ior}, absorption: {absorption}, thickness: 1.0)"))
        .collect();
    let source = format!("Material(name: \"probe\", layers: [{}, Lambert({rho})])", layers.join(", "));
    let material = glazec::compile(&source).map_err(|e| format!("{e:?}"))?.material;
    let values = material.default_values();
    let exact = SmoothStack::of(&Stack::from_material(&material, &values)).ok_or("not a smooth stack")?;
    Ok((material, values, exact))
}

/// One cell of a table: the stack's material, values and exact answer, and the column.
type Cell = dyn Fn(&Material, &[ParamValue], &SmoothStack, usize) -> String;

/// Prints one table: a row per stack, a cell per column.
fn table(title: &str, columns: &[String], cell: &Cell) -> Result<(), String> {
    println!("| {title} | {} |", columns.join(" | "));
    println!("|---|{}", "---|".repeat(columns.len()));
    for stack in STACKS {
        let (material, values, exact) = probe(stack)?;
        let cells: Vec<String> = (0..columns.len()).map(|i| cell(&material, &values, &exact, i)).collect();
        println!("| {} | {} |", stack.0, cells.join(" | "));
    }
    Ok(())
}

fn main() -> Result<(), String> {
    let pairs: Vec<String> = PAIRS.iter().map(|(a, b)| format!("{a}°/{b}°")).collect();
    table("stack over Lambert", &pairs, &|material, values, exact, i| {
        let (theta_l, theta_v) = PAIRS[i];
        let (wi, wo) = (direction_deg(theta_l, 0.0), direction_deg(theta_v, 90.0));
        let f = glazec::eval::brdf(material, values, wi.as_vec3(), wo.as_vec3()).x as f64;
        let e = exact.f(wi, wo).x;
        // Light that cannot enter the stack (a coat thinner than air beyond its critical angle).
        if e == 0.0 { format!("{f} / 0") } else { format!("{:.3}", f / e) }
    })?;
    println!();
    let views: Vec<String> = VIEWS.iter().map(|v| format!("{v}°")).collect();
    table("stated directional albedo over the exact one", &views, &|material, values, exact, i| {
        let wo = direction_deg(VIEWS[i], 0.0);
        let lobes = glazec::eval::environment_lobes(material, values, glam::Vec3::Z, wo.as_vec3());
        let stated: f32 = lobes.iter().map(|lobe| lobe.weight.x).sum();
        format!("{:.3}", f64::from(stated) / exact.directional_albedo(wo).x)
    })
}
