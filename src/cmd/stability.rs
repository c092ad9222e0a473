//! `glazec stability`: every layering method swept to the limits where layering breaks, on the
//! CPU or (feature `gpu`) the GPU (`glazec_lab::stability`).

use std::path::PathBuf;

use anyhow::Context;
use glam::Vec3;
use glazec::model::Material;
use glazec::output::{self, OutputFile};
use glazec_lab::stability;

use crate::report::Failure;

/// Sweep every method to the limits where layering breaks.
///
/// Grazing angles, roughness → 0, IOR → 1 and below, opaque coats, 16 layers, denormals); count non-finite and negative values, energy
/// gains and discontinuities; write a summary (and with the `gpu` feature a heat map per method).
#[derive(clap::Args)]
pub struct Args {
    /// Fewer values per sweep (what the quick test tier runs).
    #[arg(long)]
    reduced: bool,
    /// Evaluate on the GPU (the naga-IR kernel on the Vulkan adapter) instead of the CPU.
    #[cfg(feature = "gpu")]
    #[arg(long)]
    gpu: bool,
    /// Directory for `summary.md` and `<method>.png`.
    #[arg(long, short, default_value = "docs/results/stability")]
    out: PathBuf,
}

type Evaluator = Box<dyn FnMut(&Material, &[(Vec3, Vec3)]) -> Vec<Vec3>>;

pub fn run(args: Args) -> Result<(), Failure> {
    #[cfg(feature = "gpu")]
    let (gpu, evaluate): (bool, Evaluator) = if args.gpu {
        let device = glazec_gpu::Gpu::new().map_err(crate::report::gpu_failure)?;
        let evaluate = move |material: &Material, pairs: &[(Vec3, Vec3)]| {
            // A shader that does not compile or run counts as non-finite everywhere.
            stability::gpu_evaluation(&device, material, pairs).unwrap_or_else(|e| {
                eprintln!("error: {e}");
                vec![Vec3::NAN; pairs.len()]
            })
        };
        (true, Box::new(evaluate))
    } else {
        (false, Box::new(stability::cpu_evaluator))
    };
    #[cfg(not(feature = "gpu"))]
    let (gpu, evaluate): (bool, Evaluator) = (false, Box::new(stability::cpu_evaluator));
    let mut evaluate = evaluate;
    let sweeps = stability::sweeps(args.reduced);
    let mut maps = Vec::new();
    for method in glazec_lab::METHODS {
        for sweep in &sweeps {
            eprintln!("{} / {}", method.name(), sweep.name);
            // Discontinuities are refined on the CPU only (the GPU agrees with it to 2·10⁻⁴).
            maps.push(stability::run(sweep, method, &mut *evaluate, !gpu));
        }
    }
    let md = stability::summary_page(&maps, &sweeps, gpu);
    print!("{md}");
    let summary = OutputFile { path: args.out.join("summary.md"), contents: md.into_bytes() };
    #[cfg(feature = "gpu")]
    let files =
        [vec![summary], stability::heat_map_files(&maps, &args.out).map_err(crate::report::gpu_failure)?].concat();
    #[cfg(not(feature = "gpu"))]
    let files = vec![summary];
    output::write_all(&files).with_context(|| format!("cannot write to {}", args.out.display()))?;
    eprintln!("wrote {} files to {}", files.len(), args.out.display());
    Ok(())
}
