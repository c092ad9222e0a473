//! `glazec`: the command-line front end. A thin layer over the library: it reads files, calls
//! the pipeline, prints diagnostics, and maps outcomes to exit codes:
//! 0 success, 1 diagnostics (or `--check` drift), 2 usage or unreadable input, 3 internal error.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use clap::{Parser, Subcommand, ValueEnum};
use codespan_reporting::term::termcolor::{ColorChoice, StandardStream};

use glam::Vec3;
use glazec::diag::{self, Diagnostic, Format, Source};
use glazec::model::{Material, Method, ParamValue};
use glazec::output::{self, OutputFile};
use glazec::project::{self, ProjectError, SourceFile};
use glazec::{Compiled, Target};

#[derive(Parser)]
#[command(name = "glazec", version, about = "A layered-material compiler: RON material stacks → WGSL, GLSL, HLSL")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum MessageFormat {
    /// Rendered source excerpts (coloured on a terminal).
    Human,
    /// One JSON object per diagnostic per line.
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
enum TargetArg {
    Wgsl,
    Glsl,
    Hlsl,
    Spv,
}

#[derive(Clone, Copy, ValueEnum)]
enum Backend {
    /// The CPU evaluation of the shared math (f32).
    Cpu,
    /// The stochastic ground truth (f64 Monte Carlo random walk; see `--samples`, `--interfaces`).
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

#[derive(Clone, Copy, ValueEnum)]
enum SetArg {
    /// 120 single-coat materials: IOR 1.33/1.5/2, roughness 0/0.05/0.2/0.5, five bases, τ 0/0.5.
    Standard,
}

#[derive(Clone, Copy, ValueEnum)]
enum InterfacesArg {
    Single,
    Multiple,
}

#[cfg(feature = "gpu")]
#[derive(Clone, Copy, ValueEnum)]
enum EnvironmentArg {
    /// No environment: the key light alone.
    None,
    /// A blue sky over a dark ground.
    Sky,
    /// A soft grey dome over a dark floor.
    Studio,
}

#[cfg(feature = "gpu")]
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum LightingArg {
    /// Image-based lighting: each lobe reads the environment prefiltered for it (reflections).
    Ibl,
    /// The environment as 256 directional lights through the BRDF (no sharp reflections).
    Samples,
}

#[derive(Clone, Copy, ValueEnum)]
enum SlabModelArg {
    Exponential,
    Seed,
}

#[derive(Subcommand)]
#[allow(clippy::large_enum_variant)] // parsed once per run
enum Command {
    /// Compile material files (or every `*.ron` in a directory) to shaders.
    Compile {
        /// Material files or directories.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Output directory; each material gets a sub-directory named after it.
        #[arg(short, long, default_value = "generated")]
        out: PathBuf,
        /// Comma-separated targets.
        #[arg(long, value_enum, value_delimiter = ',', default_value = "wgsl,glsl,hlsl")]
        target: Vec<TargetArg>,
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
        /// With --scene: measure the full and simplified kernels' throughput on the GPU.
        #[arg(long, requires = "scene")]
        throughput: bool,
        #[arg(long, value_enum, default_value = "human")]
        message_format: MessageFormat,
    },
    /// Check material files and print diagnostics; write nothing.
    Check {
        #[arg(required = true)]
        files: Vec<PathBuf>,
        #[arg(long, value_enum, default_value = "human")]
        message_format: MessageFormat,
    },
    /// Evaluate f(wi, wo) (without the cosine) for direction pairs; prints `r,g,b` per pair.
    Eval {
        file: PathBuf,
        /// CSV lines `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z` in the local frame (z = normal), a header allowed.
        #[arg(long)]
        pairs: PathBuf,
        #[arg(long, value_enum, default_value = "cpu")]
        backend: Backend,
        /// Override a runtime parameter: `name=0.3` or `name=0.8,0.5,0.3`.
        #[arg(long = "set", value_name = "NAME=VALUE")]
        set: Vec<String>,
        /// Reference backend: Monte Carlo samples per pair.
        #[arg(long, default_value_t = 4096)]
        samples: u32,
        /// Reference backend: rough interfaces with single (pbrt-compatible) or multiple
        /// (energy-conserving, Heitz et al. 2016) microfacet scattering.
        #[arg(long, value_enum, default_value = "multiple")]
        interfaces: InterfacesArg,
        /// Reference backend: also print the standard error of each value (`r,g,b,se_r,se_g,se_b`).
        #[arg(long)]
        std_err: bool,
        #[arg(long, value_enum, default_value = "human")]
        message_format: MessageFormat,
    },
    /// Measure every layering method against the stochastic reference on an evaluation set and
    /// check the BRDF laws; prints a Markdown table and writes it (Markdown and CSV).
    Accuracy {
        /// The evaluation set.
        #[arg(long, value_enum, default_value = "standard")]
        set: SetArg,
        /// Rough interfaces of the reference.
        #[arg(long, value_enum, default_value = "multiple")]
        interfaces: InterfacesArg,
        /// The stored reference values (computed by --regenerate-reference).
        #[arg(long)]
        data: Option<PathBuf>,
        /// Recompute the reference and store it (minutes, in a release build).
        #[arg(long)]
        regenerate_reference: bool,
        /// With --regenerate-reference: Monte Carlo samples per BRDF value.
        #[arg(long, default_value_t = 4096)]
        samples: u32,
        /// With --regenerate-reference: analog walks per directional albedo.
        #[arg(long, default_value_t = 200_000)]
        walks: u32,
        /// Where to write the Markdown table.
        #[arg(long, default_value = "docs/accuracy.md")]
        markdown: PathBuf,
        /// Where to write the per-case CSV.
        #[arg(long, default_value = "docs/accuracy.csv")]
        csv: PathBuf,
    },
    /// Measure speed against accuracy on the GPU: kernel throughput and static cost of every
    /// method with its error on the accuracy set, the generated kernel against a hand-written one,
    /// compile times per material and target, and growth with the number of coats.
    #[cfg(feature = "gpu")]
    Bench {
        /// The materials whose compile times are measured.
        #[arg(default_value = "materials")]
        materials: PathBuf,
        /// Where to write the Markdown report.
        #[arg(long, short, default_value = "docs/bench.md")]
        out: PathBuf,
        /// Also draw error against cost, with the Pareto front, as `speed-accuracy.svg` and
        /// `speed-accuracy.png` in this directory.
        #[arg(long, value_name = "DIR")]
        chart: Option<PathBuf>,
    },
    /// Sweep every method to the limits where layering breaks (grazing angles, roughness → 0,
    /// IOR → 1 and below, opaque coats, 16 layers, denormals); count non-finite and negative
    /// values, energy gains and discontinuities; write a summary and a heat map per method.
    Stability {
        /// Fewer values per sweep (what the tests run).
        #[arg(long)]
        reduced: bool,
        /// Evaluate on the GPU (the naga-IR kernel on the Vulkan adapter) instead of the CPU.
        #[cfg(feature = "gpu")]
        #[arg(long)]
        gpu: bool,
        /// Where to write `summary.md` and `<method>.png`.
        #[arg(long, short, default_value = "docs/stability")]
        out: PathBuf,
    },
    /// Generate the tabulated terms of the default method (rough-coat transmission and internal
    /// reflection, GGX albedo) from the reference's microsurface, into data/tables.bin.
    Tables {
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
        /// Where to write the table file (it is compiled into glazec: rebuild afterwards).
        #[arg(short, long, default_value = "data/tables.bin")]
        out: PathBuf,
    },
    /// Solve a turbid layer's absorption σa and reduced scattering σs′ from measured reflectance
    /// (seed 002): per channel (comma-separated values, any number of channels or spectral
    /// samples), or a CSV batch. Prints CSV: channel, sigma_a, sigma_s, albedo, warnings.
    Optics {
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
        /// Slab formula for two thicknesses and priors: `exponential` (default) or `seed` (eq. 1
        /// as published, linearised: sound only for σt·d ≲ 0.2).
        #[arg(long, value_enum, default_value = "exponential")]
        model: SlabModelArg,
        /// A CSV batch instead: a header naming columns (r_black, r_white, backing, thickness, r1,
        /// d1, r2, d2, reflectance, scattering, ratio, mfp, ior, f_top, f_bottom, p_g), one
        /// observation per row; the output repeats each row with the results.
        #[arg(long, value_name = "FILE", conflicts_with_all = ["r_black", "r1", "reflectance"])]
        csv: Option<PathBuf>,
    },
    /// Render a sphere with the material on the GPU and write a PNG. Several inputs (or a
    /// directory) give a labelled contact sheet.
    #[cfg(feature = "gpu")]
    Preview {
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// The PNG to write.
        #[arg(short, long)]
        out: PathBuf,
        /// Image (or tile) size in pixels.
        #[arg(long, default_value_t = 512)]
        size: u32,
        /// Direction towards the key light, `x,y,z` in view space (y up, z towards the viewer).
        #[arg(long, value_name = "X,Y,Z", default_value = "-0.5,0.6,0.62")]
        light: String,
        /// Radiance of the key light.
        #[arg(long, default_value_t = 2.5)]
        light_radiance: f32,
        #[arg(long, value_enum, default_value = "sky")]
        env: EnvironmentArg,
        /// An equirectangular Radiance `.hdr` image to light with instead of `--env` (image-based
        /// lighting; y up, the image's centre behind the viewer).
        #[arg(long, value_name = "FILE.hdr")]
        env_image: Option<PathBuf>,
        /// How the environment lights the sphere.
        #[arg(long, value_enum, default_value = "ibl")]
        lighting: LightingArg,
        /// Linear scale before sRGB encoding.
        #[arg(long, default_value_t = 1.0)]
        exposure: f32,
        /// Tiles per row of a contact sheet.
        #[arg(long, default_value_t = 3)]
        columns: usize,
        /// Before/after: each material beside its simplification for this scene.
        #[arg(long, value_name = "SCENE.ron")]
        scene: Option<PathBuf>,
        /// An image for a texture the materials read (`Texture("name", …)`), as linear data;
        /// repeatable. A texture without one is constant at its parameters' default values.
        #[arg(long = "texture", value_name = "NAME=FILE.png")]
        textures: Vec<String>,
        #[arg(long, value_enum, default_value = "human")]
        message_format: MessageFormat,
    },
}

/// How a run failed, and with which exit code.
enum Failure {
    /// Diagnostics were printed (exit 1).
    Diagnostics,
    /// Bad arguments or unreadable input (exit 2).
    Usage(anyhow::Error),
    /// A bug in glazec (exit 3).
    Internal(anyhow::Error),
}

impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Usage(e)
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Compile { inputs, out, target, check, scene, explain, throughput, message_format } => {
            let scene = scene.map(|path| SceneOptions { path, explain, throughput });
            compile(&inputs, &out, &target, check, scene.as_ref(), message_format)
        }
        Command::Check { files, message_format } => check(&files, message_format),
        Command::Eval { file, pairs, backend, set, samples, interfaces, std_err, message_format } => {
            let mode = match interfaces {
                InterfacesArg::Single => glazec::reference::InterfaceMode::Single,
                InterfacesArg::Multiple => glazec::reference::InterfaceMode::Multiple,
            };
            let reference = glazec::reference::Options { mode, samples, ..Default::default() };
            eval(&file, &pairs, backend, &set, &reference, std_err, message_format)
        }
        Command::Accuracy { set: _, interfaces, data, regenerate_reference, samples, walks, markdown, csv } => {
            let mode = match interfaces {
                InterfacesArg::Single => glazec::reference::InterfaceMode::Single,
                InterfacesArg::Multiple => glazec::reference::InterfaceMode::Multiple,
            };
            accuracy(mode, data, regenerate_reference, samples, walks, &markdown, &csv)
        }
        Command::Tables { walks, glossy_walks, glossy_only, out } => tables(walks, glossy_walks, glossy_only, &out),
        #[cfg(feature = "gpu")]
        Command::Bench { materials, out, chart } => bench(&materials, &out, chart.as_deref()),
        #[cfg(feature = "gpu")]
        Command::Stability { reduced, gpu, out } => stability(reduced, gpu, &out),
        #[cfg(not(feature = "gpu"))]
        Command::Stability { reduced, out } => stability(reduced, false, &out),
        #[cfg(feature = "gpu")]
        Command::Optics {
            r_black,
            r_white,
            backing,
            thickness,
            r1,
            d1,
            r2,
            d2,
            reflectance,
            scattering,
            ratio,
            mfp,
            ior,
            model,
            csv,
        } => {
            let seed = matches!(model, SlabModelArg::Seed);
            match csv {
                Some(path) => optics_csv(&path, seed, ior),
                None => {
                    let columns: [(&str, &[f64]); 12] = [
                        ("r_black", &r_black),
                        ("r_white", &r_white),
                        ("backing", &backing),
                        ("thickness", &thickness),
                        ("r1", &r1),
                        ("d1", &d1),
                        ("r2", &r2),
                        ("d2", &d2),
                        ("reflectance", &reflectance),
                        ("scattering", &scattering),
                        ("ratio", &ratio),
                        ("mfp", &mfp),
                    ];
                    optics(&columns, seed, ior)
                }
            }
        }
        Command::Preview {
            inputs,
            out,
            size,
            light,
            light_radiance,
            env,
            env_image,
            lighting,
            exposure,
            columns,
            scene,
            textures,
            message_format,
        } => {
            let environment = match env {
                EnvironmentArg::None => glazec::run::preview::Environment::None,
                EnvironmentArg::Sky => glazec::run::preview::Environment::Sky,
                EnvironmentArg::Studio => glazec::run::preview::Environment::Studio,
            };
            parse_vec3(&light).map_err(Failure::Usage).and_then(|light| {
                let textures = read_textures(&textures)?;
                let lighting = preview_lighting(environment, env_image.as_deref(), lighting)?;
                let options = glazec::run::preview::PreviewOptions {
                    size,
                    light,
                    light_radiance,
                    environment,
                    lighting,
                    exposure,
                    textures,
                };
                preview(&inputs, &out, &options, columns, scene.as_deref(), message_format)
            })
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Diagnostics) => ExitCode::from(1),
        Err(Failure::Usage(e)) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
        Err(Failure::Internal(e)) => {
            eprintln!("{e:#}");
            ExitCode::from(3)
        }
    }
}

/// The preview's lighting: the environment (an `.hdr` image, or the analytic one rasterised)
/// prefiltered for image-based lighting, or the analytic one's samples.
#[cfg(feature = "gpu")]
fn preview_lighting(
    environment: glazec::run::preview::Environment,
    image: Option<&Path>,
    lighting: LightingArg,
) -> Result<glazec::run::preview::Lighting, Failure> {
    use glazec::run::environment::{BASE_WIDTH, EnvironmentImage, prefilter};
    let image = match (image, lighting) {
        (Some(_), LightingArg::Samples) => {
            return Err(Failure::Usage(anyhow::anyhow!("--env-image needs --lighting ibl")));
        }
        (Some(path), LightingArg::Ibl) => Some(
            EnvironmentImage::read_hdr(path)
                .map_err(|e| Failure::Usage(anyhow::anyhow!("cannot read the environment image: {e}")))?,
        ),
        (None, LightingArg::Ibl) => environment.image(2 * BASE_WIDTH),
        (None, LightingArg::Samples) => None,
    };
    Ok(match image {
        Some(image) => glazec::run::preview::Lighting::Image(std::sync::Arc::new(prefilter(&image))),
        None => glazec::run::preview::Lighting::Samples,
    })
}

/// `NAME=FILE.png` arguments of `preview --texture`.
fn read_textures(args: &[String]) -> Result<Vec<(String, glazec::run::textures::TextureImage)>, Failure> {
    args.iter()
        .map(|arg| {
            let Some((name, file)) = arg.split_once('=') else {
                return Err(Failure::Usage(anyhow::anyhow!("--texture takes NAME=FILE.png, got `{arg}`")));
            };
            let image = glazec::run::textures::TextureImage::read_png(Path::new(file))
                .map_err(|e| Failure::Usage(anyhow::anyhow!("cannot read texture `{name}`: {e}")))?;
            Ok((name.trim().to_string(), image))
        })
        .collect()
}

/// Reads files and directories of materials (see `glazec::project::read`).
fn read_inputs(paths: &[PathBuf]) -> anyhow::Result<Vec<SourceFile>> {
    Ok(project::read(paths)?)
}

fn source_of(file: &SourceFile) -> (String, &str) {
    (file.name(), &file.text)
}

fn print_diagnostics(source: Source<'_>, diagnostics: &[Diagnostic], format: MessageFormat) {
    let format = match format {
        MessageFormat::Json => Format::Json,
        MessageFormat::Human => Format::Human { color: std::io::stderr().is_terminal() },
    };
    let choice = if matches!(format, Format::Human { color: true }) { ColorChoice::Auto } else { ColorChoice::Never };
    let mut stderr = StandardStream::stderr(choice);
    let _ = diag::emit(&mut stderr, source, diagnostics, format);
    let _ = stderr.flush();
}

/// Compiles every input, printing all diagnostics. Fails if any input has errors.
fn compile_all(inputs: &[SourceFile], format: MessageFormat) -> Result<Vec<Compiled>, Failure> {
    match project::compile(inputs) {
        Ok(compiled) => {
            // Notes (the coefficients a `Measured` layer derived) never fail a compilation.
            for (file, c) in inputs.iter().zip(&compiled) {
                if !c.source_map.notes.is_empty() {
                    let (name, text) = source_of(file);
                    print_diagnostics(Source { name: &name, text }, &c.source_map.notes, format);
                }
            }
            Ok(compiled)
        }
        Err(ProjectError::Diagnostics(failed)) => {
            for f in &failed {
                let (name, text) = source_of(&inputs[f.file]);
                print_diagnostics(Source { name: &name, text }, &f.diagnostics, format);
            }
            Err(Failure::Diagnostics)
        }
        Err(ProjectError::Internal(e)) => Err(Failure::Internal(e.into())),
    }
}

/// `compile --scene`.
struct SceneOptions {
    path: PathBuf,
    explain: bool,
    throughput: bool,
}

/// Simplifies every material for the scene; prints the reports (and throughputs).
fn simplify_for_scene(
    compiled: &[Compiled],
    options: &SceneOptions,
    format: MessageFormat,
) -> Result<(Vec<Compiled>, Vec<glazec::simplify::Report>), Failure> {
    let scene = match project::read_scene(&options.path).map_err(|e| Failure::Usage(e.into()))? {
        Ok(scene) => scene,
        Err((source, diagnostics)) => {
            let (name, text) = source_of(&source);
            print_diagnostics(Source { name: &name, text }, &diagnostics, format);
            return Err(Failure::Diagnostics);
        }
    };
    let simplified = match project::simplify_all(compiled, &scene) {
        Ok(s) => s,
        Err(project::SceneError::Diagnostics(diagnostics)) => {
            let (name, text) = source_of(&scene.source);
            print_diagnostics(Source { name: &name, text }, &diagnostics, format);
            return Err(Failure::Diagnostics);
        }
        Err(project::SceneError::Internal(e)) => return Err(Failure::Internal(e.into())),
    };
    let (simplified, reports): (Vec<Compiled>, Vec<glazec::simplify::Report>) = simplified.into_iter().unzip();
    for report in &reports {
        println!("{}", report.markdown(options.explain));
    }
    if options.throughput {
        print_throughputs(compiled, &simplified)?;
    }
    Ok((simplified, reports))
}

/// Evaluations per second of each full and simplified kernel on the GPU, timed interleaved.
#[cfg(feature = "gpu")]
fn print_throughputs(full: &[Compiled], simplified: &[Compiled]) -> Result<(), Failure> {
    let gpu = glazec::run::Gpu::new().map_err(|e| Failure::Usage(e.into()))?;
    println!(
        "Throughput on {} ({} pairs per dispatch, median of interleaved rounds):\n",
        gpu.describe(),
        glazec::bench::PAIRS
    );
    println!("| material | full (M evals/s) | simplified (M evals/s) | speed-up |\n|---|---|---|---|");
    for (f, s) in full.iter().zip(simplified) {
        let rates = glazec::bench::throughputs(&gpu, &[f, s]).map_err(run_failure)?;
        println!(
            "| {} | {:.1} | {:.1} | {:.2}× |",
            f.material.name,
            rates[0] / 1e6,
            rates[1] / 1e6,
            rates[1] / rates[0]
        );
    }
    println!();
    Ok(())
}

#[cfg(not(feature = "gpu"))]
fn print_throughputs(_: &[Compiled], _: &[Compiled]) -> Result<(), Failure> {
    Err(Failure::Usage(anyhow::anyhow!("--throughput needs glazec built with the `gpu` feature")))
}

fn compile(
    inputs: &[PathBuf],
    out: &Path,
    targets: &[TargetArg],
    check: bool,
    scene: Option<&SceneOptions>,
    format: MessageFormat,
) -> Result<(), Failure> {
    let inputs = read_inputs(inputs)?;
    let compiled = compile_all(&inputs, format)?;
    let (compiled, reports) = match scene {
        Some(options) => simplify_for_scene(&compiled, options, format)?,
        None => (compiled, Vec::new()),
    };
    let targets: Vec<Target> = targets
        .iter()
        .map(|t| match t {
            TargetArg::Wgsl => Target::Wgsl,
            TargetArg::Glsl => Target::Glsl,
            TargetArg::Hlsl => Target::Hlsl,
            TargetArg::Spv => Target::Spv,
        })
        .collect();
    let mut files = project::plan(out, &compiled, &targets).map_err(|e| Failure::Internal(e.into()))?;
    files.extend(reports.iter().map(|r| project::report_file(out, r)));
    if check {
        let drift = output::drift(&files);
        for file in &files {
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
    output::write_all(&files).with_context(|| format!("cannot write to {}", out.display()))?;
    eprintln!("wrote {} files for {} material(s) to {}", files.len(), compiled.len(), out.display());
    Ok(())
}

fn check(files: &[PathBuf], format: MessageFormat) -> Result<(), Failure> {
    let inputs = read_inputs(files)?;
    let compiled = compile_all(&inputs, format)?;
    eprintln!("{} material(s) ok", compiled.len());
    Ok(())
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
    }
    Ok(values)
}

fn eval(
    file: &Path,
    pairs: &Path,
    backend: Backend,
    set: &[String],
    reference: &glazec::reference::Options,
    std_err: bool,
    format: MessageFormat,
) -> Result<(), Failure> {
    let inputs = read_inputs(&[file.to_path_buf()])?;
    let input = &inputs[0];
    let material = match glazec::load(&input.text) {
        Ok((material, _)) => material,
        Err(diagnostics) => {
            let (name, text) = source_of(input);
            print_diagnostics(Source { name: &name, text }, &diagnostics, format);
            return Err(Failure::Diagnostics);
        }
    };
    let values = parameter_values(&material, set)?;
    let text = std::fs::read_to_string(pairs).with_context(|| format!("cannot read {}", pairs.display()))?;
    let pairs = glazec::eval::parse_pairs(&text).with_context(|| format!("{}", pairs.display()))?;
    if std_err && !matches!(backend, Backend::Reference) {
        return Err(Failure::Usage(anyhow::anyhow!("--std-err needs --backend reference")));
    }
    let results: Vec<glam::Vec3> = match backend {
        Backend::Cpu => pairs.iter().map(|p| glazec::eval::brdf(&material, &values, p.wi, p.wo)).collect(),
        Backend::Reference => {
            let stack = glazec::reference::Stack::from_material(&material, &values);
            let mut stdout = std::io::BufWriter::new(std::io::stdout().lock());
            for p in &pairs {
                let e = stack.f(p.wi.as_dvec3(), p.wo.as_dvec3(), reference);
                let (m, s) = (e.mean, e.std_err);
                if std_err {
                    writeln!(stdout, "{},{},{},{},{},{}", m.x, m.y, m.z, s.x, s.y, s.z)
                } else {
                    writeln!(stdout, "{},{},{}", m.x, m.y, m.z)
                }
                .context("cannot write to stdout")?;
            }
            stdout.flush().context("cannot write to stdout")?;
            return Ok(());
        }
        #[cfg(feature = "gpu")]
        Backend::NagaIr => eval_on_gpu(material, &pairs, &values, glazec::run::ShaderPath::NagaIr)?,
        #[cfg(feature = "gpu")]
        Backend::Wgsl => eval_on_gpu(material, &pairs, &values, glazec::run::ShaderPath::Wgsl)?,
        #[cfg(feature = "gpu")]
        Backend::Glsl => eval_on_gpu(material, &pairs, &values, glazec::run::ShaderPath::Glsl)?,
        #[cfg(feature = "gpu")]
        Backend::Hlsl => eval_on_gpu(material, &pairs, &values, glazec::run::ShaderPath::Hlsl)?,
    };
    let mut stdout = std::io::BufWriter::new(std::io::stdout().lock());
    for f in results {
        writeln!(stdout, "{}", glazec::eval::format_rgb(f)).context("cannot write to stdout")?;
    }
    stdout.flush().context("cannot write to stdout")?;
    Ok(())
}

/// Maps a device failure to an exit code: no adapter or no compiler is a usage problem (2);
/// anything the device rejects is a bug (3).
#[cfg(feature = "gpu")]
fn run_failure(e: glazec::run::RunError) -> Failure {
    use glazec::run::RunError;
    match e {
        RunError::NoAdapter { .. }
        | RunError::ToolMissing { .. }
        | RunError::NoPassthrough { .. }
        | RunError::Io(_) => Failure::Usage(e.into()),
        _ => Failure::Internal(e.into()),
    }
}

#[cfg(feature = "gpu")]
fn eval_on_gpu(
    material: Material,
    pairs: &[glazec::eval::Pair],
    values: &[ParamValue],
    path: glazec::run::ShaderPath,
) -> Result<Vec<glam::Vec3>, Failure> {
    let compiled = glazec::compile_material(material, Default::default()).map_err(|e| Failure::Internal(e.into()))?;
    let gpu = glazec::run::Gpu::new().map_err(run_failure)?;
    let kernel = glazec::run::EvalKernel::new(&gpu, &compiled, path).map_err(run_failure)?;
    kernel.eval(&gpu, pairs, values).map_err(run_failure)
}

#[cfg(feature = "gpu")]
fn parse_vec3(text: &str) -> anyhow::Result<glam::Vec3> {
    let numbers: Vec<f32> = text
        .split(',')
        .map(|x| x.trim().parse::<f32>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .with_context(|| format!("`{text}` is not three numbers x,y,z"))?;
    match numbers.as_slice() {
        [x, y, z] if (x * x + y * y + z * z) > 0.0 => Ok(glam::Vec3::new(*x, *y, *z)),
        _ => bail!("`{text}` is not a non-zero direction x,y,z"),
    }
}

#[cfg(feature = "gpu")]
fn preview(
    inputs: &[PathBuf],
    out: &Path,
    options: &glazec::run::preview::PreviewOptions,
    columns: usize,
    scene: Option<&Path>,
    format: MessageFormat,
) -> Result<(), Failure> {
    use glazec::run::preview;
    let files = read_inputs(inputs)?;
    let compiled = compile_all(&files, format)?;
    for (name, _) in &options.textures {
        if !compiled.iter().any(|c| c.material.textures().contains(&name.as_str())) {
            let read: Vec<&str> = compiled.iter().flat_map(|c| c.material.textures()).collect();
            return Err(Failure::Usage(anyhow::anyhow!(
                "--texture {name}: no material reads a texture of that name (they read: {})",
                if read.is_empty() { "none".to_string() } else { read.join(", ") }
            )));
        }
    }
    let simplified = match scene {
        Some(path) => {
            let options = SceneOptions { path: path.to_path_buf(), explain: false, throughput: false };
            Some(simplify_for_scene(&compiled, &options, format)?.0)
        }
        None => None,
    };
    let gpu = glazec::run::Gpu::new().map_err(run_failure)?;
    let mut tiles = Vec::new();
    for (i, c) in compiled.iter().enumerate() {
        let linear = preview::render(&gpu, c, &c.material.default_values(), options).map_err(run_failure)?;
        tiles.push((c.material.name.clone(), preview::encode(&linear, options.size, options.exposure)));
        if let Some(s) = simplified.as_ref().map(|s| &s[i]) {
            let scene_name = s.origin.scene.as_ref().map_or("scene", |(file, _)| file.trim_end_matches(".ron"));
            let linear = preview::render(&gpu, s, &s.material.default_values(), options).map_err(run_failure)?;
            tiles.push((scene_name.to_string(), preview::encode(&linear, options.size, options.exposure)));
        }
    }
    let single = inputs.len() == 1 && !inputs[0].is_dir() && simplified.is_none();
    let image = if single { tiles.remove(0).1 } else { preview::contact_sheet(&tiles, columns) };
    preview::write_png(out, &image).map_err(run_failure)?;
    eprintln!("wrote {} ({}×{}, {} on {})", out.display(), image.width, image.height, compiled.len(), gpu.describe());
    Ok(())
}

/// `glazec optics` with per-channel flags: a flag with one value applies to every channel.
fn optics(columns: &[(&str, &[f64])], seed: bool, ior: Option<f64>) -> Result<(), Failure> {
    let channels = columns.iter().map(|(_, v)| v.len()).max().unwrap_or(0);
    if channels == 0 {
        return Err(Failure::Usage(anyhow::anyhow!(
            "give measurements: --r-black/--r-white/--backing/--thickness, --r1/--d1/--r2/--d2, or --reflectance with \
             --scattering, --ratio or --mfp"
        )));
    }
    for (name, values) in columns {
        if values.len() > 1 && values.len() != channels {
            return Err(Failure::Usage(anyhow::anyhow!(
                "--{} has {} values, others {channels}",
                name.replace('_', "-"),
                values.len()
            )));
        }
    }
    println!("channel,sigma_a,sigma_s,albedo,warnings");
    let mut failed = false;
    for c in 0..channels {
        let mut inputs = glazec::optics::Inputs { seed_model: seed, ior, ..Default::default() };
        for (name, values) in columns {
            if let Some(v) = values.get(c).or_else(|| values.first().filter(|_| values.len() == 1)) {
                inputs.set(name, *v);
            }
        }
        match inputs.observation().and_then(|o| glazec::optics::solve(&o)) {
            Ok(s) => println!("{c},{},{},{},{}", s.sigma_a, s.sigma_s, s.albedo, s.warnings.join("; ")),
            Err(e) => {
                eprintln!("error: channel {c}: {e}");
                failed = true;
            }
        }
    }
    if failed { Err(Failure::Diagnostics) } else { Ok(()) }
}

/// `glazec optics --csv FILE`: one observation per row; the output repeats each row with
/// `sigma_a,sigma_s,albedo,status` (status `ok`, a warning, or the error). Exit 1 if a row failed.
fn optics_csv(path: &Path, seed: bool, ior: Option<f64>) -> Result<(), Failure> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<&str> = lines.next().map(|h| h.split(',').map(str::trim).collect()).unwrap_or_default();
    for name in &header {
        if !glazec::optics::INPUT_NAMES.contains(name) {
            return Err(Failure::Usage(anyhow::anyhow!(
                "{}: unknown column `{name}` (columns: {})",
                path.display(),
                glazec::optics::INPUT_NAMES.join(", ")
            )));
        }
    }
    println!("{},sigma_a,sigma_s,albedo,status", header.join(","));
    let mut failed = false;
    for (row, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let mut inputs = glazec::optics::Inputs { seed_model: seed, ior, ..Default::default() };
        let mut bad = None;
        for (name, cell) in header.iter().zip(&cells) {
            if cell.is_empty() {
                continue;
            }
            match cell.parse::<f64>() {
                Ok(v) => {
                    inputs.set(name, v);
                }
                Err(_) => bad = Some(format!("row {}: `{cell}` in column {name} is not a number", row + 2)),
            }
        }
        if cells.len() != header.len() {
            bad = Some(format!("row {}: {} cells for {} columns", row + 2, cells.len(), header.len()));
        }
        let result = match bad {
            Some(message) => Err(message),
            None => inputs.observation().and_then(|o| glazec::optics::solve(&o)).map_err(|e| e.to_string()),
        };
        match result {
            Ok(s) => {
                let status =
                    if s.warnings.is_empty() { "ok".to_string() } else { s.warnings.join("; ").replace(',', ";") };
                println!("{line},{},{},{},{status}", s.sigma_a, s.sigma_s, s.albedo);
            }
            Err(e) => {
                failed = true;
                println!("{line},,,,error: {}", e.replace(',', ";"));
            }
        }
    }
    if failed { Err(Failure::Diagnostics) } else { Ok(()) }
}

/// The default location of the stored reference for an interface mode.
fn reference_path(mode: glazec::reference::InterfaceMode) -> PathBuf {
    match mode {
        glazec::reference::InterfaceMode::Single => PathBuf::from("data/reference/standard-single.bin"),
        glazec::reference::InterfaceMode::Multiple => PathBuf::from("data/reference/standard-multiple.bin"),
    }
}

fn tables(walks: u32, glossy_walks: u32, glossy_only: bool, out: &Path) -> Result<(), Failure> {
    let start = std::time::Instant::now();
    let progress = |done: usize, total: usize| eprint!("\rtables: {done}/{total} columns");
    let (tables, report) = if glossy_only {
        let existing = std::fs::read(out).with_context(|| format!("cannot read {}", out.display()))?;
        glazec::accuracy::tables::generate_glossy_only(
            glazec::math::tables::decode_by_name(&existing),
            glossy_walks,
            &progress,
        )
        .map_err(|e| anyhow::anyhow!(e))?
    } else {
        glazec::accuracy::tables::generate(walks, glossy_walks, &progress)
    };
    eprintln!(" in {:.0} s", start.elapsed().as_secs_f64());
    if !glossy_only {
        eprintln!(
            "flux identity η²⟨T_int⟩ = ⟨T⟩: max error {:.2e}; single-event share vs quadrature: max {:.2} σ",
            report.max_flux_identity_error, report.max_single_event_sigma
        );
        eprintln!(
            "single-scattering deficit: the lookup overshot the truth by up to {:.2e} between nodes (nodes lowered)",
            report.max_deficit_excess
        );
    }
    eprintln!(
        "glossy level: fitted trapped-light generating function within {:.1e} of the walks'; lobe scale misses its target by up to {:.1e}; a white conductor under a clear coat reflected up to {:.1e} more than it received at the probes between nodes (K fitted to the law there)",
        report.glossy.max_tail_fit_error, report.glossy.max_scale_miss, report.glossy.max_energy_excess
    );
    let bytes = glazec::math::tables::encode(&tables);
    glazec::output::write_all(&[glazec::output::OutputFile { path: out.to_path_buf(), contents: bytes }])
        .with_context(|| format!("cannot write {}", out.display()))?;
    eprintln!("wrote {} ({} bytes); rebuild glazec to use it", out.display(), glazec::math::tables::total_bytes());
    Ok(())
}

fn accuracy(
    mode: glazec::reference::InterfaceMode,
    data: Option<PathBuf>,
    regenerate: bool,
    samples: u32,
    walks: u32,
    markdown: &Path,
    csv: &Path,
) -> Result<(), Failure> {
    use glazec::accuracy;
    let cases = accuracy::standard_set();
    let path = data.unwrap_or_else(|| reference_path(mode));
    let reference = if regenerate {
        let start = std::time::Instant::now();
        let done = std::sync::atomic::AtomicUsize::new(0);
        let progress = |_| {
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            eprint!("\rreference: {n}/{} cases", cases.len());
        };
        let data = accuracy::ReferenceData::compute(&cases, mode, samples, walks, &progress);
        eprintln!(" in {:.0} s", start.elapsed().as_secs_f64());
        data.write(&path).with_context(|| format!("cannot write {}", path.display()))?;
        eprintln!("wrote {}", path.display());
        data
    } else {
        accuracy::ReferenceData::read(&path, cases.len())
            .context("cannot read the reference (run with --regenerate-reference to compute it)")?
    };
    let methods: Vec<_> =
        [glazec::model::Method::INTERFACED, glazec::model::Method::WeidlichWilkie, glazec::model::Method::Additive]
            .into_iter()
            .map(|method| {
                let metrics = cases
                    .iter()
                    .enumerate()
                    .map(|(i, case)| accuracy::measure(case, method, &reference.under[i], &reference.albedo[i]))
                    .collect();
                (method, metrics)
            })
            .collect();
    let md =
        accuracy::report(&cases, &methods, &reference, Some(markdown), Some(csv)).context("cannot write the report")?;
    println!("{md}");
    Ok(())
}

/// `glazec stability`: every method over every sweep, on the CPU or the GPU.
fn stability(reduced: bool, gpu: bool, out: &Path) -> Result<(), Failure> {
    use glazec::stability;
    let sweeps = stability::sweeps(reduced);
    let mut evaluate = stability_evaluator(gpu)?;
    let methods = [Method::INTERFACED, Method::WeidlichWilkie, Method::Additive];
    let mut maps = Vec::new();
    for method in methods {
        for sweep in &sweeps {
            eprintln!("{} / {}", method.name(), sweep.name);
            // Discontinuities are refined on the CPU only (the GPU agrees with it to 2·10⁻⁴).
            maps.push(stability::run(sweep, method, &mut *evaluate, !gpu));
        }
    }
    let backend = if gpu { "the GPU (naga-IR kernel)" } else { "the CPU" };
    let md = format!("Evaluated on {backend}.\n\n{}", stability::summary(&maps, &sweeps));
    print!("{md}");
    let mut files = vec![glazec::output::OutputFile { path: out.join("summary.md"), contents: md.into_bytes() }];
    files.extend(stability_pictures(&maps, &methods, out));
    glazec::output::write_all(&files).with_context(|| format!("cannot write to {}", out.display()))?;
    eprintln!("wrote {} files to {}", files.len(), out.display());
    Ok(())
}

#[cfg(feature = "gpu")]
fn stability_pictures(
    maps: &[glazec::stability::Map],
    methods: &[Method],
    out: &Path,
) -> Vec<glazec::output::OutputFile> {
    use glazec::run::preview::{Image, contact_sheet, encode_png};
    const CELL: u32 = 32;
    let rows = maps.iter().map(|m| m.cells.len() as u32).max().unwrap_or(1);
    methods
        .iter()
        .filter_map(|&method| {
            let tiles: Vec<(String, Image)> = maps
                .iter()
                .filter(|m| m.method == method)
                .map(|m| {
                    let (width, height, rgb) = glazec::stability::heat_map(m, CELL, rows);
                    (m.sweep.to_string(), Image { width, height, rgb })
                })
                .collect();
            let sheet = contact_sheet(&tiles, 4);
            let contents = encode_png(&sheet).ok()?;
            Some(glazec::output::OutputFile { path: out.join(format!("{}.png", method.name())), contents })
        })
        .collect()
}

#[cfg(not(feature = "gpu"))]
fn stability_pictures(_: &[glazec::stability::Map], _: &[Method], _: &Path) -> Vec<glazec::output::OutputFile> {
    Vec::new()
}

type MaterialEvaluator = Box<dyn FnMut(&Material, &[(Vec3, Vec3)]) -> Vec<Vec3>>;

fn stability_evaluator(gpu: bool) -> Result<MaterialEvaluator, Failure> {
    if !gpu {
        return Ok(Box::new(glazec::stability::cpu_evaluator));
    }
    #[cfg(feature = "gpu")]
    {
        let device = glazec::run::Gpu::new().map_err(|e| Failure::Usage(e.into()))?;
        return Ok(Box::new(move |material: &Material, pairs: &[(Vec3, Vec3)]| {
            // A shader that does not compile or run counts as non-finite everywhere.
            glazec::stability::gpu_evaluation(&device, material, pairs).unwrap_or_else(|e| {
                eprintln!("error: {e}");
                vec![Vec3::NAN; pairs.len()]
            })
        }));
    }
    #[allow(unreachable_code)]
    Err(Failure::Usage(anyhow::anyhow!("glazec was built without the `gpu` feature")))
}

/// `glazec bench`: speed against accuracy on the GPU, written as Markdown.
#[cfg(feature = "gpu")]
fn bench(materials_dir: &Path, out: &Path, chart: Option<&Path>) -> Result<(), Failure> {
    let inputs = read_inputs(&[materials_dir.to_path_buf()]).map_err(Failure::Usage)?;
    let materials_text: Vec<(String, String)> = inputs
        .into_iter()
        .map(|i| (i.path.file_stem().map_or_else(|| i.name(), |s| s.to_string_lossy().into_owned()), i.text))
        .collect();
    let gpu = glazec::run::Gpu::new().map_err(|e| Failure::Usage(e.into()))?;
    let mut report = glazec::bench::run(&gpu, &materials_text, &|what| eprintln!("measuring {what}"))
        .map_err(|e| Failure::Internal(anyhow::anyhow!(e)))?;
    report.process_ms = process_time(materials_dir).ok();
    let md = report.markdown();
    print!("{md}");
    let file = OutputFile { path: out.to_path_buf(), contents: md.into_bytes() };
    output::write_all(&[file]).with_context(|| format!("cannot write {}", out.display()))?;
    if let Some(dir) = chart {
        for path in glazec::chart::write(&report, dir).map_err(|e| Failure::Internal(anyhow::anyhow!(e)))? {
            eprintln!("wrote {}", path.display());
        }
    }
    Ok(())
}

/// Median wall time of `glazec compile <materials> -o <temporary directory>` as a new process.
#[cfg(feature = "gpu")]
fn process_time(materials: &Path) -> anyhow::Result<f64> {
    let exe = std::env::current_exe()?;
    let out = tempfile::tempdir()?;
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = std::time::Instant::now();
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
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}
