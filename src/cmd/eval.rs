//! `glazec eval`: f(wi, wo) of a material at direction pairs, on the CPU, the stochastic
//! reference (feature `lab`) or a GPU path (feature `gpu`).

use std::path::PathBuf;

use anyhow::{Context, bail};
use clap::ValueEnum;
use glazec::model::{Material, ParamValue};
use glazec::project::{FileDiagnostics, SourceFile};

use crate::report::{Failure, MessageFormat, print_diagnostics, print_lines};

/// Evaluate f(wi, wo) (without the cosine) for direction pairs; prints `r,g,b` per pair.
#[derive(clap::Args)]
pub struct Args {
    file: PathBuf,
    /// CSV lines `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z` in the local frame (z = normal), a header allowed.
    #[arg(long)]
    pairs: PathBuf,
    #[arg(long, value_enum, default_value = "cpu")]
    backend: Backend,
    /// Override a runtime parameter: `name=0.3` or `name=0.8,0.5,0.3`.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    #[command(flatten)]
    reference: ReferenceArgs,
    #[arg(long, value_enum, default_value = "human")]
    message_format: MessageFormat,
}

/// Options of the reference backend.
#[derive(clap::Args)]
struct ReferenceArgs {
    /// Reference backend: Monte Carlo samples per pair.
    #[arg(long, default_value_t = 4096)]
    samples: u32,
    /// Reference backend: how rough interfaces scatter.
    #[cfg(feature = "lab")]
    #[arg(long, value_parser = crate::choice::parser::<glazec_lab::reference::InterfaceMode>(), default_value = "multiple")]
    interfaces: glazec_lab::reference::InterfaceMode,
    /// Reference backend: also print the standard error of each value (`r,g,b,se_r,se_g,se_b`).
    #[arg(long)]
    std_err: bool,
}

/// Where f is evaluated.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Backend {
    /// The CPU evaluation of the shared math (f32).
    Cpu,
    /// The stochastic ground truth (f64 Monte Carlo random walk; see `--samples`, `--interfaces`).
    #[cfg(feature = "lab")]
    Reference,
    /// The naga module itself, on the GPU (lavapipe).
    #[cfg(feature = "gpu")]
    NagaIr,
    /// The emitted WGSL through wgpu's front end, on the GPU.
    #[cfg(feature = "gpu")]
    Wgsl,
    /// The emitted GLSL compiled by glslangValidator, on the GPU.
    #[cfg(feature = "gpu")]
    Glsl,
    /// The emitted HLSL compiled by glslang's HLSL front end, on the GPU (passthrough SPIR-V).
    #[cfg(feature = "gpu")]
    Hlsl,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let source = glazec::project::read(std::slice::from_ref(&args.file)).map_err(anyhow::Error::from)?;
    let Some(SourceFile { path, text }) = source.into_iter().next() else {
        return Err(Failure::usage(format!("no material in {}", args.file.display())));
    };
    let material = match glazec::load(&text) {
        Ok((material, _)) => material,
        Err(diagnostics) => {
            print_diagnostics(&FileDiagnostics { file: SourceFile { path, text }, diagnostics }, args.message_format);
            return Err(Failure::Diagnostics);
        }
    };
    let values = parameter_values(&material, &args.set)?;
    let pairs_text =
        std::fs::read_to_string(&args.pairs).with_context(|| format!("cannot read {}", args.pairs.display()))?;
    let pairs = glazec::eval::parse_pairs(&pairs_text).with_context(|| args.pairs.display().to_string())?;
    if args.reference.std_err && !is_reference(args.backend) {
        return Err(Failure::usage("--std-err needs --backend reference"));
    }
    let lines: Vec<String> = match args.backend {
        Backend::Cpu => {
            pairs.iter().map(|p| glazec::eval::format_rgb(glazec::eval::brdf(&material, &values, p.wi, p.wo))).collect()
        }
        #[cfg(feature = "lab")]
        Backend::Reference => reference(&material, &values, &pairs, &args.reference),
        #[cfg(feature = "gpu")]
        Backend::NagaIr => on_gpu(material, &pairs, &values, glazec_gpu::ShaderPath::NagaIr)?,
        #[cfg(feature = "gpu")]
        Backend::Wgsl => on_gpu(material, &pairs, &values, glazec_gpu::ShaderPath::Wgsl)?,
        #[cfg(feature = "gpu")]
        Backend::Glsl => on_gpu(material, &pairs, &values, glazec_gpu::ShaderPath::Glsl)?,
        #[cfg(feature = "gpu")]
        Backend::Hlsl => on_gpu(material, &pairs, &values, glazec_gpu::ShaderPath::Hlsl)?,
    };
    print_lines(lines)
}

fn is_reference(backend: Backend) -> bool {
    #[cfg(feature = "lab")]
    if backend == Backend::Reference {
        return true;
    }
    let _ = backend;
    false
}

/// Parses `--set name=value` overrides against the material's parameters.
fn parameter_values(material: &Material, overrides: &[String]) -> anyhow::Result<Vec<ParamValue>> {
    let mut values = material.default_values();
    for item in overrides {
        let Some((name, value)) = item.split_once('=') else {
            bail!("--set expects NAME=VALUE, got `{item}`");
        };
        let Some(index) = material.params.iter().position(|p| p.name == name.trim()) else {
            let names: Vec<&str> = material.params.iter().map(|p| p.name.as_str()).collect();
            bail!("material `{}` has no parameter `{name}` (it has: {})", material.name, names.join(", "));
        };
        let numbers: Vec<f32> = value
            .split(',')
            .map(|x| x.trim().parse::<f32>().ok().filter(|v| v.is_finite()))
            .collect::<Option<_>>()
            .with_context(|| format!("--set {name}: `{value}` is not a finite number or r,g,b triple"))?;
        values[index] = match (values[index], numbers.as_slice()) {
            (ParamValue::Scalar(_), [x]) => ParamValue::Scalar(*x),
            (ParamValue::Rgb(_), [x]) => ParamValue::Rgb([*x; 3]),
            (ParamValue::Rgb(_), [r, g, b]) => ParamValue::Rgb([*r, *g, *b]),
            (default, _) => bail!("--set {name}: expected a {} value", default.type_name()),
        };
        // What the material's slots accept (a literal outside it would not have compiled).
        let [lo, hi] = material.params[index].range;
        if let Some(x) = numbers.iter().find(|x| !(lo..=hi).contains(*x)) {
            bail!("--set {name}: {x} is outside [{lo}, {hi}], the values its slots accept");
        }
    }
    Ok(values)
}

/// The reference's mean per pair (and its standard error with `--std-err`), f64 as printed.
#[cfg(feature = "lab")]
fn reference(
    material: &Material,
    values: &[ParamValue],
    pairs: &[glazec::eval::Pair],
    args: &ReferenceArgs,
) -> Vec<String> {
    use glazec_lab::reference::{Options, Stack};
    let options = Options { mode: args.interfaces, samples: args.samples, ..Default::default() };
    let stack = Stack::from_material(material, values);
    pairs
        .iter()
        .map(|p| {
            let e = stack.f(p.wi.as_dvec3(), p.wo.as_dvec3(), &options);
            let (m, s) = (e.mean, e.std_err);
            if args.std_err {
                format!("{},{},{},{},{},{}", m.x, m.y, m.z, s.x, s.y, s.z)
            } else {
                format!("{},{},{}", m.x, m.y, m.z)
            }
        })
        .collect()
}

/// The kernel's values per pair, printed as the CPU's are.
#[cfg(feature = "gpu")]
fn on_gpu(
    material: Material,
    pairs: &[glazec::eval::Pair],
    values: &[ParamValue],
    path: glazec_gpu::ShaderPath,
) -> Result<Vec<String>, Failure> {
    use crate::report::gpu_failure;
    let compiled = glazec::compile_material(material, Default::default()).map_err(|e| Failure::Internal(e.into()))?;
    let gpu = glazec_gpu::Gpu::new().map_err(gpu_failure)?;
    let kernel = glazec_gpu::EvalKernel::new(&gpu, &compiled, path).map_err(gpu_failure)?;
    let f = kernel.eval(&gpu, pairs, values).map_err(gpu_failure)?;
    Ok(f.into_iter().map(glazec::eval::format_rgb).collect())
}
