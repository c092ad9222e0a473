//! `glazec optics`: a turbid layer's σa and σs′ from measured reflectance, per channel from flags
//! or per row of a CSV batch (`glazec::optics`).

use std::path::PathBuf;

use anyhow::Context;
use clap::ValueEnum;
use glazec::optics::{Batch, Inputs};

use crate::report::{Failure, print_lines};

/// Solve a turbid layer's absorption σa and reduced scattering σs′ from measured reflectance.
///
/// Per channel (comma-separated values, any number of channels or spectral samples), or a CSV
/// batch. Prints CSV: channel, sigma_a, sigma_s, albedo, warnings.
#[derive(clap::Args)]
pub struct Args {
    /// Reflectance over a black backing (Kubelka–Munk, with --r-white, --backing, --thickness).
    #[arg(long, value_delimiter = ',')]
    r_black: Vec<f64>,
    /// Reflectance over the white backing.
    #[arg(long, value_delimiter = ',')]
    r_white: Vec<f64>,
    /// Reflectance of the white backing (or, for slab models, F_dr,b: what is under the sample).
    #[arg(long, value_delimiter = ',')]
    backing: Vec<f64>,
    /// Sample thickness.
    #[arg(long, value_delimiter = ',')]
    thickness: Vec<f64>,
    /// Two thicknesses: reflectance at the first.
    #[arg(long, value_delimiter = ',')]
    r1: Vec<f64>,
    #[arg(long, value_delimiter = ',')]
    d1: Vec<f64>,
    #[arg(long, value_delimiter = ',')]
    r2: Vec<f64>,
    #[arg(long, value_delimiter = ',')]
    d2: Vec<f64>,
    /// One reflectance (needs --scattering, --ratio or --mfp as well).
    #[arg(long, value_delimiter = ',')]
    reflectance: Vec<f64>,
    /// Known reduced scattering coefficient σs′.
    #[arg(long, value_delimiter = ',')]
    scattering: Vec<f64>,
    /// Known ratio σs′/σa.
    #[arg(long, value_delimiter = ',')]
    ratio: Vec<f64>,
    /// Diffuse mean free path ℓ_d of a thick sample (diffusion dipole).
    #[arg(long, value_delimiter = ',')]
    mfp: Vec<f64>,
    /// Boundary index (default 1.5): F_dr,t of the slab models and the dipole's boundary.
    #[arg(long)]
    ior: Option<f64>,
    /// Slab formula for two thicknesses and priors.
    #[arg(long, value_enum, default_value = "exponential")]
    model: SlabModelArg,
    /// A CSV batch instead: a header naming columns (r_black, r_white, backing, thickness, r1,
    /// d1, r2, d2, reflectance, scattering, ratio, mfp, ior, f_top, f_bottom, p_g), one
    /// observation per row; the output repeats each row with the results.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["r_black", "r1", "reflectance"])]
    csv: Option<PathBuf>,
}

/// The slab formula (`glazec::optics::SlabModel`, chosen by `Inputs::seed_model`).
#[derive(Clone, Copy, ValueEnum)]
enum SlabModelArg {
    /// Single scattering with exact exponential attenuation (sound at any optical depth).
    Exponential,
    /// The same with the attenuation linearised, as published: sound only for σt·d ≲ 0.2.
    Seed,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let seed = matches!(args.model, SlabModelArg::Seed);
    if let Some(path) = &args.csv {
        return batch(path, seed, args.ior);
    }
    let columns: [(&str, &[f64]); 12] = [
        ("r_black", &args.r_black),
        ("r_white", &args.r_white),
        ("backing", &args.backing),
        ("thickness", &args.thickness),
        ("r1", &args.r1),
        ("d1", &args.d1),
        ("r2", &args.r2),
        ("d2", &args.d2),
        ("reflectance", &args.reflectance),
        ("scattering", &args.scattering),
        ("ratio", &args.ratio),
        ("mfp", &args.mfp),
    ];
    channels(&columns, seed, args.ior)
}

/// Per-channel flags: a flag with one value applies to every channel.
fn channels(columns: &[(&str, &[f64])], seed: bool, ior: Option<f64>) -> Result<(), Failure> {
    let channels = columns.iter().map(|(_, v)| v.len()).max().unwrap_or(0);
    if channels == 0 {
        return Err(Failure::usage(
            "give measurements: --r-black/--r-white/--backing/--thickness, --r1/--d1/--r2/--d2, or --reflectance with \
             --scattering, --ratio or --mfp",
        ));
    }
    for (name, values) in columns {
        if values.len() > 1 && values.len() != channels {
            return Err(Failure::usage(format!(
                "--{} has {} values, others {channels}",
                name.replace('_', "-"),
                values.len()
            )));
        }
    }
    let mut lines = vec!["channel,sigma_a,sigma_s,albedo,warnings".to_string()];
    let mut failed = false;
    for c in 0..channels {
        let mut inputs = Inputs { seed_model: seed, ior, ..Default::default() };
        for (name, values) in columns {
            if let Some(v) = values.get(c).or_else(|| values.first().filter(|_| values.len() == 1)) {
                inputs.set(name, *v);
            }
        }
        match inputs.observation().and_then(|o| glazec::optics::solve(&o)) {
            Ok(s) => lines.push(format!("{c},{},{},{},{}", s.sigma_a, s.sigma_s, s.albedo, s.warnings.join("; "))),
            Err(e) => {
                eprintln!("error: channel {c}: {e}");
                failed = true;
            }
        }
    }
    print_lines(lines)?;
    if failed { Err(Failure::Diagnostics) } else { Ok(()) }
}

/// A CSV batch: the output repeats each row with `sigma_a,sigma_s,albedo,status` (status `ok`, a
/// warning, or the error). Exit 1 if a row failed.
fn batch(path: &std::path::Path, seed: bool, ior: Option<f64>) -> Result<(), Failure> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let batch = Batch::solve(&text, seed, ior).with_context(|| path.display().to_string())?;
    let mut lines = vec![format!("{},sigma_a,sigma_s,albedo,status", batch.header.join(","))];
    let mut failed = false;
    for row in &batch.rows {
        lines.push(match &row.result {
            Ok(s) => {
                let status =
                    if s.warnings.is_empty() { "ok".to_string() } else { s.warnings.join("; ").replace(',', ";") };
                format!("{},{},{},{},{status}", row.line, s.sigma_a, s.sigma_s, s.albedo)
            }
            Err(e) => {
                failed = true;
                format!("{},,,,error: {}", row.line, e.replace(',', ";"))
            }
        });
    }
    print_lines(lines)?;
    if failed { Err(Failure::Diagnostics) } else { Ok(()) }
}
