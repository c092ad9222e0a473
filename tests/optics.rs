//! `glazec optics`: round trips through the command line (per channel and as a CSV batch) and
//! the rejections a user meets.

mod common;

use common::glazec;

use std::process::Output;

use glazec::optics::{self, Slab, SlabModel};

/// Round trips through the CLI's printed values (shortest f64 text reads back exactly).
const ROUND_TRIP: f64 = 1e-9;

fn rows(out: &Output) -> Vec<Vec<String>> {
    String::from_utf8_lossy(&out.stdout).lines().skip(1).map(|l| l.split(',').map(str::to_string).collect()).collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= ROUND_TRIP * b.abs()
}

#[test]
fn black_and_white_readings_round_trip_per_channel() {
    // Three channels of assumed coefficients → Kubelka–Munk readings → back.
    let truth = [(0.6, 5.7), (0.9, 5.9), (1.4, 6.3)];
    let (x, backing) = (0.1, 0.9);
    let readings: Vec<(f64, f64)> = truth
        .iter()
        .map(|&(a, s)| {
            let (k, s_km) = (2.0 * a, (3.0 * s - a) / 4.0);
            (optics::km_reflectance(k, s_km, x, 0.0), optics::km_reflectance(k, s_km, x, backing))
        })
        .collect();
    let join = |f: &dyn Fn(&(f64, f64)) -> f64| readings.iter().map(|r| f(r).to_string()).collect::<Vec<_>>().join(",");
    let out = glazec(&[
        "optics",
        "--r-black",
        &join(&|r| r.0),
        "--r-white",
        &join(&|r| r.1),
        "--backing",
        "0.9",
        "--thickness",
        "0.1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = rows(&out);
    assert_eq!(rows.len(), 3);
    for (row, (a, s)) in rows.iter().zip(truth) {
        let (got_a, got_s): (f64, f64) = (row[1].parse().expect("σa"), row[2].parse().expect("σs′"));
        assert!(close(got_a, a) && close(got_s, s), "{row:?} vs ({a}, {s})");
    }
}

#[test]
fn a_csv_batch_solves_every_row_and_marks_the_impossible_ones() {
    let slab = Slab { f_top: optics::diffuse_fresnel_external(1.5), f_bottom: 0.0, p_g: 0.5, eta: 1.5 };
    let (a, s, d1, d2) = (0.8, 12.0, 0.02, 0.05);
    let r1 = SlabModel::Exponential.reflectance(slab, d1, a, s);
    let r2 = SlabModel::Exponential.reflectance(slab, d2, a, s);
    let r = SlabModel::Exponential.reflectance(slab, d1, a, s);
    let dir = tempfile::tempdir().expect("tmp");
    let csv = dir.path().join("batch.csv");
    std::fs::write(
        &csv,
        format!("r1,d1,r2,d2,reflectance,scattering,thickness\n{r1},{d1},{r2},{d2},,,\n,,,,{r},{s},{d1}\n,,,,0.4,,\n"),
    )
    .expect("writes");
    let out = glazec(&["optics", "--csv", csv.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(1), "a row fails, so the batch exits 1");
    let rows = rows(&out);
    assert_eq!(rows.len(), 3);
    for row in &rows[..2] {
        assert_eq!(row.last().map(String::as_str), Some("ok"), "{row:?}");
        let (got_a, got_s): (f64, f64) = (row[7].parse().expect("σa"), row[8].parse().expect("σs′"));
        assert!(close(got_a, a) && close(got_s, s), "{row:?}");
    }
    assert!(
        rows[2].last().is_some_and(|s| s.starts_with("error: one reflectance cannot fix two unknowns")),
        "{:?}",
        rows[2]
    );
}

#[test]
fn impossible_and_insufficient_readings_exit_1_with_the_reason() {
    let out = glazec(&["optics", "--reflectance", "0.4,0.3,0.2"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("black and a white backing, or at a second thickness"), "{stderr}");
    let out = glazec(&["optics", "--r-black", "0.5", "--r-white", "0.4", "--backing", "0.9", "--thickness", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("must exceed the one over black"));
    let out = glazec(&["optics", "--reflectance", "1.2", "--scattering", "3", "--thickness", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("outside (0, 1)"));
    let out = glazec(&["optics", "--r-black", "0.2", "--r-white", "0.3", "--thickness", "1"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing `backing`"));
    // The seed formula pushed past its regime answers, with a warning.
    let slab = Slab { f_top: optics::diffuse_fresnel_external(1.5), ..Slab::default() };
    let (r1, r2) = (optics::seed_reflectance(slab, 0.2, 0.5, 2.0), optics::seed_reflectance(slab, 0.3, 0.5, 2.0));
    let out = glazec(&[
        "optics",
        "--model",
        "seed",
        "--r1",
        &r1.to_string(),
        "--d1",
        "0.2",
        "--r2",
        &r2.to_string(),
        "--d2",
        "0.3",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("use the exponential model"));
}

#[test]
fn measured_materials_compile_and_report_what_they_derived() {
    let out = glazec(&["check", "materials/mud_clay.ron", "materials/cork_clay.ron"]);
    assert_eq!(out.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.matches("note[N0401]").count(), 2, "{stderr}");
    assert!(stderr.contains("Kubelka–Munk over black and white backing"), "{stderr}");
}
