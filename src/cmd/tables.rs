//! `glazec tables`: bakes the tabulated terms of the default method from the reference's
//! microsurfaces (`glazec_lab::bake`) into the file the compiler includes.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use glazec::math::tables;
use glazec::output::{self, OutputFile};

use crate::report::Failure;

/// Generate the tabulated terms of the default method from the reference's microsurfaces.
///
/// Rough-coat transmission and internal reflection, GGX albedo, the glossy level.
#[derive(clap::Args)]
pub struct Args {
    /// Microsurface random walks per rough-interface entry.
    #[arg(long, default_value_t = 20_000)]
    walks: u32,
    /// White random walks through coat and conductor per node of the glossy level's tables
    /// (a conductor under a coat).
    #[arg(long, default_value_t = 20_000)]
    glossy_walks: u32,
    /// Regenerate only the glossy level's tables, keeping the others of the existing table
    /// file at --out (a full run reproduces them exactly).
    #[arg(long)]
    glossy_only: bool,
    /// Where to write the table file; the compiler includes `crates/glazec/data/tables.bin`
    /// (rebuild afterwards).
    #[arg(short, long, default_value = "crates/glazec/data/tables.bin")]
    out: PathBuf,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let start = Instant::now();
    let progress = |done: usize, total: usize| eprint!("\rtables: {done}/{total} columns");
    let (values, report) = if args.glossy_only {
        let existing = std::fs::read(&args.out).with_context(|| format!("cannot read {}", args.out.display()))?;
        glazec_lab::bake::generate_glossy_only(tables::decode_by_name(&existing), args.glossy_walks, &progress)
            .map_err(Failure::usage)?
    } else {
        glazec_lab::bake::generate(args.walks, args.glossy_walks, &progress)
    };
    eprintln!(" in {:.0} s", start.elapsed().as_secs_f64());
    if !args.glossy_only {
        eprintln!(
            "flux identity η²⟨T_int⟩ = ⟨T⟩: max error {:.2e}; single-event share vs quadrature: max {:.2} σ",
            report.max_flux_identity_error, report.max_single_event_sigma
        );
        eprintln!(
            "coat lobe scale c ∈ [{:.3}, {:.3}]: the scaled lobe reflects E_ss + E_ms within {:.1e} at the nodes",
            report.scale_range.0, report.scale_range.1, report.max_scale_miss
        );
        eprintln!(
            "coat deficit: the lookup overshot the scaled lobe's by up to {:.2e} between nodes (nodes lowered)",
            report.max_deficit_excess
        );
    }
    eprintln!(
        "glossy level: fitted trapped-light generating function within {:.1e} of the walks'; lobe scale misses its \
         target by up to {:.1e}; a white conductor under a clear coat reflected up to {:.1e} more than it received \
         at the probes between nodes (K fitted to the law there: E − 1 ≤ {:.1e} at every probe after the fit)",
        report.glossy.max_tail_fit_error,
        report.glossy.max_scale_miss,
        report.glossy.max_energy_excess,
        report.glossy.max_energy_after_fit
    );
    let file = OutputFile { path: args.out.clone(), contents: tables::encode(&values) };
    output::write_all(&[file]).with_context(|| format!("cannot write {}", args.out.display()))?;
    eprintln!("wrote {} ({} bytes); rebuild glazec to use it", args.out.display(), tables::total_bytes());
    Ok(())
}
