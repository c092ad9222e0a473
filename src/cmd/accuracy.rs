//! `glazec accuracy`: every layering method against the stored stochastic reference on the
//! standard set, and the BRDF laws (`glazec_lab::accuracy`).

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::Context;
use glazec::output::{self, OutputFile};
use glazec_lab::accuracy::full::{self, FullReference};
use glazec_lab::accuracy::stated;
use glazec_lab::accuracy::{self, ReferenceData};
use glazec_lab::reference::InterfaceMode;

use crate::choice;
use crate::report::Failure;

/// Measure every layering method against the stochastic reference, and the BRDF laws.
///
/// On the standard set (120 single-coat materials); prints a Markdown table and writes it
/// (`accuracy.md`, `accuracy.csv`) into `--out`.
#[derive(clap::Args)]
pub struct Args {
    /// Rough interfaces of the reference.
    #[arg(long, value_parser = choice::parser::<InterfaceMode>(), default_value = "multiple")]
    interfaces: InterfaceMode,
    /// The stored reference values [default: the lab's `data/reference/standard-<interfaces>.bin`].
    #[arg(long)]
    data: Option<PathBuf>,
    /// Recompute the reference and store it at --data (minutes, in a release build).
    #[arg(long)]
    regenerate_reference: bool,
    /// With --regenerate-reference: Monte Carlo samples per BRDF value.
    #[arg(long, default_value_t = 4096)]
    samples: u32,
    /// With --regenerate-reference: analog walks per directional albedo.
    #[arg(long, default_value_t = 200_000)]
    walks: u32,
    /// Recompute only the whole-BRDF references (the standard metrics read the stored one)
    #[arg(long)]
    regenerate_full_reference: bool,
    /// Recompute only the reference albedos the stated albedos are measured against
    #[arg(long)]
    regenerate_albedo_reference: bool,
    /// Reference samples per value of the whole-BRDF bands (with --regenerate-reference)
    #[arg(long, default_value_t = 16_384)]
    full_samples: u32,
    /// Directory for `accuracy.md`, `accuracy.csv`, `accuracy-full.md` and `stated-albedo.md`.
    #[arg(long, short, default_value = "docs/results")]
    out: PathBuf,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let cases = accuracy::standard_set();
    let path = args.data.unwrap_or_else(|| accuracy::stored_reference(args.interfaces));
    let reference = if args.regenerate_reference {
        let start = Instant::now();
        let done = AtomicUsize::new(0);
        let progress = |_| {
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            eprint!("\rreference: {n}/{} cases", cases.len());
        };
        let data = ReferenceData::compute(&cases, args.interfaces, args.samples, args.walks, &progress);
        eprintln!(" in {:.0} s", start.elapsed().as_secs_f64());
        data.write(&path).with_context(|| format!("cannot write {}", path.display()))?;
        eprintln!("wrote {}", path.display());
        data
    } else {
        ReferenceData::read(&path, cases.len()).with_context(|| {
            format!("cannot read the reference {} (--regenerate-reference computes it)", path.display())
        })?
    };
    let methods = accuracy::measure_methods(&cases, &reference);
    let markdown = accuracy::markdown(&cases, &methods, &reference);
    let full = args.regenerate_reference || args.regenerate_full_reference;
    let (full_markdown, stated_markdown) =
        whole_brdf(full, full || args.regenerate_albedo_reference, args.full_samples)?;
    let files = [
        OutputFile { path: args.out.join("accuracy.md"), contents: markdown.clone().into_bytes() },
        OutputFile { path: args.out.join("accuracy.csv"), contents: accuracy::csv(&cases, &methods).into_bytes() },
        OutputFile { path: args.out.join("accuracy-full.md"), contents: full_markdown.clone().into_bytes() },
        OutputFile { path: args.out.join("stated-albedo.md"), contents: stated_markdown.clone().into_bytes() },
    ];
    output::write_all(&files).with_context(|| format!("cannot write to {}", args.out.display()))?;
    println!("{markdown}\n{full_markdown}\n{stated_markdown}");
    Ok(())
}

/// The whole-BRDF bands and the stated albedos of the standard set, the multi-coat set and the
/// shipped materials, against their stored references (computed first with `bands` and
/// `albedos`).
fn whole_brdf(bands: bool, albedos: bool, samples: u32) -> Result<(String, String), Failure> {
    for full::Set { name, subjects, .. } in full::sets().map_err(|e| anyhow::anyhow!(e))? {
        if bands {
            let path = full::stored_reference(name);
            let start = Instant::now();
            let done = AtomicUsize::new(0);
            let progress = |_| {
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                eprint!("\rwhole-BRDF reference, {name}: {n}/{}", subjects.len());
            };
            let data = FullReference::compute(&subjects, samples, &progress);
            eprintln!(" in {:.0} s", start.elapsed().as_secs_f64());
            data.write(&path).with_context(|| format!("cannot write {}", path.display()))?;
        }
        if albedos {
            let path = stated::stored_albedo_reference(name);
            let start = Instant::now();
            let data = stated::compute(&subjects, stated::ALBEDO_WALKS, &|_| {});
            eprintln!("reference albedos, {name}: {:.0} s", start.elapsed().as_secs_f64());
            data.write(&path).with_context(|| format!("cannot write {}", path.display()))?;
        }
    }
    // (Read back even when just computed: the file stores f32, and the tables must not depend on
    // whether the reference was recomputed.)
    let bands_md = full::report().map_err(|e| anyhow::anyhow!(e))?;
    let albedos_md = stated::report(&full::sets().map_err(|e| anyhow::anyhow!(e))?).map_err(|e| anyhow::anyhow!(e))?;
    Ok((bands_md, albedos_md))
}
