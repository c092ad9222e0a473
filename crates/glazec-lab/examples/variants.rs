//! The default method's variants on the accuracy set, per base: the largest directional-albedo
//! error against the stored reference and the white furnace (Lambert ρ = 1 under a clear coat,
//! lowest and highest albedo). docs/speed.md quotes this.
//!
//! `cargo run --release --example variants`

use std::path::Path;

use glazec::model::Method;
use glazec_lab::accuracy::{self, BaseKind, ReferenceData};

fn main() {
    let cases = accuracy::standard_set();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/reference/standard-multiple.bin");
    let data = ReferenceData::read(&path, cases.len()).unwrap_or_else(|e| panic!("{e}"));
    println!("| variant | Lambert | EON | copper | white furnace E |\n|---|---|---|---|---|");
    for method in [Method::INTERFACED, Method::INTERFACED_SCHLICK, Method::INTERFACED_SINGLE_SCATTERING] {
        let (mut lambert, mut eon, mut copper) = (0.0_f64, 0.0_f64, 0.0_f64);
        let (mut furnace_low, mut furnace_high) = (f64::INFINITY, 0.0_f64);
        for (i, case) in cases.iter().enumerate() {
            let m = accuracy::measure(case, method, &data.under[i], &data.albedo[i]);
            let worst = match case.base {
                BaseKind::Lambert(_) => &mut lambert,
                BaseKind::Eon => &mut eon,
                BaseKind::Copper => &mut copper,
            };
            *worst = worst.max(m.albedo_error);
            if case.base == BaseKind::Lambert(1.0) && case.tau == 0.0 {
                furnace_high = furnace_high.max(m.energy_max);
                furnace_low = m.albedos.iter().map(|a| a.min_element()).fold(furnace_low, f64::min);
            }
        }
        println!(
            "| {} | {lambert:.4} | {eon:.4} | {copper:.4} | {furnace_low:.3}–{furnace_high:.4} |",
            accuracy::method_label(method)
        );
    }
}
