//! `glazec`: the command-line front end, one file per subcommand in `cmd/`. Each is a shell over
//! a library call that returns data; it renders the result once and maps the outcome to an exit
//! code: 0 success, 1 diagnostics (or `--check` drift), 2 usage or unreadable input, 3 internal
//! error.
//!
//! The default build has the compiler's commands (`compile`, `check`, `eval` on the CPU,
//! `optics`). Feature `gpu` adds `preview` and the GPU backends of `eval`; feature `lab` adds
//! `accuracy`, `stability`, `tables` and the reference backend of `eval`; both together add
//! `bench` and `images`.

mod choice;
mod cmd;
mod report;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "glazec",
    version,
    about = "A layered-material compiler: RON material stacks → WGSL, GLSL, HLSL",
    after_help = AFTER_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Which optional commands this build has, and how to get the others.
#[cfg(all(feature = "gpu", feature = "lab"))]
const AFTER_HELP: &str = "This build has every command (features `gpu` and `lab`).";
#[cfg(not(all(feature = "gpu", feature = "lab")))]
const AFTER_HELP: &str = "Optional commands: `preview` and the GPU backends of `eval` (feature `gpu`); `accuracy`, \
     `stability`, `tables` and `eval --backend reference` (feature `lab`); `bench` and `images` (both). Build with \
     `cargo run --release --features gpu,lab -- …` for every command.";

#[derive(Subcommand)]
#[allow(clippy::large_enum_variant)] // parsed once per run
enum Command {
    Compile(cmd::compile::Args),
    Check(cmd::check::Args),
    Eval(cmd::eval::Args),
    Optics(cmd::optics::Args),
    #[cfg(feature = "gpu")]
    Preview(cmd::preview::Args),
    #[cfg(feature = "lab")]
    Accuracy(cmd::accuracy::Args),
    #[cfg(all(feature = "lab", feature = "gpu"))]
    Bench(cmd::bench::Args),
    #[cfg(all(feature = "lab", feature = "gpu"))]
    Images(cmd::images::Args),
    #[cfg(feature = "lab")]
    Stability(cmd::stability::Args),
    #[cfg(feature = "lab")]
    Tables(cmd::tables::Args),
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Compile(args) => cmd::compile::run(args),
        Command::Check(args) => cmd::check::run(args),
        Command::Eval(args) => cmd::eval::run(args),
        Command::Optics(args) => cmd::optics::run(args),
        #[cfg(feature = "gpu")]
        Command::Preview(args) => cmd::preview::run(args),
        #[cfg(feature = "lab")]
        Command::Accuracy(args) => cmd::accuracy::run(args),
        #[cfg(all(feature = "lab", feature = "gpu"))]
        Command::Bench(args) => cmd::bench::run(args),
        #[cfg(all(feature = "lab", feature = "gpu"))]
        Command::Images(args) => cmd::images::run(args),
        #[cfg(feature = "lab")]
        Command::Stability(args) => cmd::stability::run(args),
        #[cfg(feature = "lab")]
        Command::Tables(args) => cmd::tables::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => failure.exit(),
    }
}
