//! `glazec compile`: material files to shaders (optionally simplified for a scene), written all
//! or nothing, or compared with what is on disk (`--check`).

use std::path::PathBuf;

use anyhow::Context;
use glazec::lower::bindings::{Choice, Resource, Slot};
use glazec::project::{Outcome, Project};
use glazec::{Target, output};

use crate::choice;
use crate::report::{Failure, MessageFormat, print_diagnostics, project_failure};

/// Compile material files (or every `*.ron` in a directory) to shaders.
#[derive(clap::Args)]
pub struct Args {
    /// Material files or directories.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Output directory; each material gets a sub-directory named after it.
    #[arg(short, long, default_value = "generated")]
    out: PathBuf,
    /// Comma-separated targets.
    #[arg(long, value_parser = choice::parser::<Target>(), value_delimiter = ',', default_value = "wgsl,naga-oil,glsl,hlsl")]
    target: Vec<Target>,
    /// Where a library resource is bound, instead of glazec's default (repeatable):
    /// `params`, `tables`, `textures` (the sampler; textures follow) or `environment` (the
    /// sampler; radiance and irradiance follow) at GROUP:BINDING, e.g. `--bind params=2:0`.
    /// Defaults: params 0:3, tables right after params, textures 1:0. Placing `environment`
    /// adds glazec's environment lookup `<m>_ibl` to the libraries.
    #[arg(long, value_name = "RESOURCE=GROUP:BINDING", value_parser = parse_bind)]
    bind: Vec<(Resource, Slot)>,
    /// Also write glazec's own harness beside each library: its `eval_pairs` kernel and preview
    /// pipelines (`<m>.harness.wgsl`, `<m>.<entry>.<stage>.glsl`, `<m>.hlsl`), which glazec's
    /// tests, `eval`, `bench` and `preview` run. A host needs only the libraries.
    #[arg(long)]
    harness: bool,
    /// Write nothing; exit 1 if any output differs from what is on disk.
    #[arg(long)]
    check: bool,
    /// Simplify each material for this scene (see `scenes/`): drop what the scene cannot see
    /// within its tolerance, print the report and write it next to the outputs.
    #[arg(long, value_name = "SCENE.ron")]
    scene: Option<PathBuf>,
    /// With --scene: also print the changes that were tried and not kept, with their errors.
    #[arg(long, requires = "scene")]
    explain: bool,
    /// With --scene: measure the full and simplified kernels' throughput on the GPU (needs the
    /// `gpu` feature).
    #[arg(long, requires = "scene")]
    throughput: bool,
    #[arg(long, value_enum, default_value = "human")]
    message_format: MessageFormat,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let bindings = args.bind.iter().fold(Choice::default(), |choice, &(resource, slot)| choice.with(resource, slot));
    let project = Project {
        inputs: args.inputs,
        scene: args.scene,
        out_dir: args.out.clone(),
        targets: args.target,
        bindings,
        harness: args.harness,
    };
    if project.scene.is_none() && !args.check {
        // Compiled, emitted and staged material by material: memory does not grow with the folder.
        let written = project.write().map_err(|e| project_failure(e, args.message_format))?;
        for file in &written.notes {
            print_diagnostics(file, args.message_format);
        }
        eprintln!("wrote {} files for {} material(s) to {}", written.files, written.materials, args.out.display());
        return Ok(());
    }
    let outcome = project.compile().map_err(|e| project_failure(e, args.message_format))?;
    for file in &outcome.notes {
        print_diagnostics(file, args.message_format);
    }
    for (_, report) in &outcome.simplified {
        println!("{}", report.markdown(args.explain));
    }
    if args.throughput {
        print_throughputs(&outcome)?;
    }
    let (files, out) = (&outcome.files, &args.out);
    if args.check {
        let drift = output::drift(files);
        for file in files {
            print!("{}", output::unified_diff(file));
        }
        for d in &drift {
            eprintln!("{d}");
        }
        if !drift.is_empty() {
            eprintln!(
                "{} of {} files differ; run `glazec compile` without --check to update them",
                drift.len(),
                files.len()
            );
            return Err(Failure::Diagnostics);
        }
        eprintln!("{} files up to date in {}", files.len(), out.display());
        return Ok(());
    }
    output::write_all(files).with_context(|| format!("cannot write to {}", out.display()))?;
    eprintln!("wrote {} files for {} material(s) to {}", files.len(), outcome.compiled.len(), out.display());
    Ok(())
}

/// Evaluations per second of each full and simplified kernel on the GPU, timed interleaved.
#[cfg(feature = "gpu")]
fn print_throughputs(outcome: &Outcome) -> Result<(), Failure> {
    use crate::report::gpu_failure;
    use glazec_gpu::throughput;
    let gpu = glazec_gpu::Gpu::new().map_err(gpu_failure)?;
    println!(
        "Throughput on {} ({} pairs per dispatch, median of interleaved rounds):\n",
        gpu.describe(),
        throughput::PAIRS
    );
    println!("| material | full (M evals/s) | simplified (M evals/s) | speed-up |\n|---|---|---|---|");
    for (full, (simplified, _)) in outcome.compiled.iter().zip(&outcome.simplified) {
        let rates = throughput::throughputs(&gpu, &[full, simplified]).map_err(gpu_failure)?;
        println!(
            "| {} | {:.1} | {:.1} | {:.2}× |",
            full.material.name,
            rates[0] / 1e6,
            rates[1] / 1e6,
            rates[1] / rates[0]
        );
    }
    println!();
    Ok(())
}

#[cfg(not(feature = "gpu"))]
fn print_throughputs(_: &Outcome) -> Result<(), Failure> {
    Err(Failure::usage("--throughput needs glazec built with the `gpu` feature"))
}

/// `RESOURCE=GROUP:BINDING`.
fn parse_bind(text: &str) -> Result<(Resource, Slot), String> {
    let (name, slot) = text.split_once('=').ok_or_else(|| format!("`{text}` is not RESOURCE=GROUP:BINDING"))?;
    let names: Vec<&str> = Resource::ALL.iter().map(|r| r.name()).collect();
    let resource = Resource::ALL
        .into_iter()
        .find(|r| r.name() == name.trim())
        .ok_or_else(|| format!("no resource `{name}`; one of: {}", names.join(", ")))?;
    Ok((resource, slot.parse()?))
}
