//! `glazec images`: the shipped materials and the multi-coat set rendered by their generated
//! shaders and by the stochastic reference, compared with ꟻLIP (`glazec_lab::images`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use glazec::output::{self, OutputFile};

use crate::report::{Failure, gpu_failure};

/// Render materials with their shaders and with the reference, and compare them with ꟻLIP.
///
/// Every shipped material (`materials/`) and the multi-coat set of `glazec accuracy`, as spheres
/// under the preview's key light and under the sky: the generated shaders on the device, the
/// stochastic reference at the same pixels, and ꟻLIP's error map between them. Writes
/// `images.md` and one contact sheet per set (`images-shipped.png`, `images-multi-coat.png`)
/// into --out.
#[derive(clap::Args)]
pub struct Args {
    /// Directory for `images.md` and the contact sheets.
    #[arg(long, short, default_value = "docs/results")]
    out: PathBuf,
    /// Only the materials whose name contains this (for a look at one; the published files
    /// hold every material).
    #[arg(long)]
    only: Option<String>,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let gpu = glazec_gpu::Gpu::new().map_err(gpu_failure)?;
    let start = Instant::now();
    let sets = glazec_lab::images::run(&gpu, args.only.as_deref(), &|what| eprintln!("rendering {what}"))
        .map_err(|e| Failure::Internal(anyhow::anyhow!(e)))?;
    let mut markdown = String::new();
    let mut files = Vec::new();
    for set in &sets {
        if !markdown.is_empty() {
            markdown.push('\n');
        }
        markdown.push_str(&set.markdown());
        let png = glazec_gpu::preview::encode_png(&set.sheet()).map_err(gpu_failure)?;
        files.push(OutputFile { path: args.out.join(format!("images-{}.png", set.name)), contents: png });
    }
    files.push(OutputFile { path: args.out.join("images.md"), contents: markdown.clone().into_bytes() });
    output::write_all(&files).with_context(|| format!("cannot write to {}", args.out.display()))?;
    println!("{markdown}");
    eprintln!("rendered and compared in {:.0} s on {}", start.elapsed().as_secs_f64(), gpu.describe());
    Ok(())
}
