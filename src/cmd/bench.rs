//! `glazec bench`: speed against accuracy on the GPU (`glazec_lab::bench`), as Markdown and, with
//! `--chart`, the speed-against-accuracy chart.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use glazec::output::{self, OutputFile};

use crate::report::{Failure, gpu_failure};

/// Measure speed against accuracy on the GPU.
///
/// Kernel throughput and static cost of every method with its error on the accuracy set, the generated kernel against a hand-written one, compile
/// times per material and target, and growth with the number of coats. Writes `bench.md` (and
/// with --chart `speed-accuracy.svg` and `.png`) into --out.
#[derive(clap::Args)]
pub struct Args {
    /// The materials whose compile times are measured.
    #[arg(default_value = "materials")]
    materials: PathBuf,
    /// Directory for `bench.md` and the chart.
    #[arg(long, short, default_value = "docs/results")]
    out: PathBuf,
    /// Also draw error against cost, with the Pareto front.
    #[arg(long)]
    chart: bool,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let sources = glazec::project::read(std::slice::from_ref(&args.materials)).map_err(anyhow::Error::from)?;
    let materials: Vec<(String, String)> = sources
        .into_iter()
        .map(|s| (s.path.file_stem().map_or_else(|| s.name(), |n| n.to_string_lossy().into_owned()), s.text))
        .collect();
    let gpu = glazec_gpu::Gpu::new().map_err(gpu_failure)?;
    let mut report = glazec_lab::bench::run(&gpu, &materials, &|what| eprintln!("measuring {what}"))
        .map_err(|e| Failure::Internal(anyhow::anyhow!(e)))?;
    report.process_ms = process_time(&args.materials).ok();
    let markdown = report.markdown();
    let path = args.out.join("bench.md");
    output::write_all(&[OutputFile { path: path.clone(), contents: markdown.clone().into_bytes() }])
        .with_context(|| format!("cannot write {}", path.display()))?;
    print!("{markdown}");
    if args.chart {
        for path in glazec_lab::chart::write(&report, &args.out).map_err(|e| Failure::Internal(anyhow::anyhow!(e)))? {
            eprintln!("wrote {}", path.display());
        }
    }
    Ok(())
}

/// Median wall time of `glazec compile <materials> -o <temporary directory>` as a new process.
fn process_time(materials: &Path) -> anyhow::Result<f64> {
    let exe = std::env::current_exe()?;
    let out = tempfile::tempdir()?;
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = Instant::now();
        let status = std::process::Command::new(&exe)
            .arg("compile")
            .arg(materials)
            .arg("-o")
            .arg(out.path())
            .stderr(std::process::Stdio::null())
            .status()?;
        if !status.success() {
            bail!("glazec compile failed");
        }
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    Ok(glazec_gpu::throughput::median(times))
}
