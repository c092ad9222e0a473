//! How the CLI reports: diagnostics rendered once per file (human or JSON lines), and failures
//! mapped to exit codes. Errors print each cause once (`{:#}` of an `anyhow` chain; the
//! libraries' errors name their causes through `source()`, not in their own text).

use std::io::{IsTerminal, Write};

use clap::ValueEnum;
use codespan_reporting::term::termcolor::{ColorChoice, StandardStream};
use glazec::diag::{self, Format, Source};
use glazec::project::{FileDiagnostics, ProjectError};

/// How diagnostics are printed.
#[derive(Clone, Copy, ValueEnum)]
pub enum MessageFormat {
    /// Rendered source excerpts (coloured on a terminal).
    Human,
    /// One JSON object per diagnostic per line.
    Json,
}

/// How a run failed, and with which exit code.
pub enum Failure {
    /// Diagnostics (or drift) were printed (exit 1).
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

impl Failure {
    /// A usage failure with a message.
    pub fn usage(message: impl std::fmt::Display) -> Failure {
        Failure::Usage(anyhow::anyhow!("{message}"))
    }

    /// Prints the error (with each cause once) and returns the exit code.
    pub fn exit(self) -> std::process::ExitCode {
        match self {
            Failure::Diagnostics => std::process::ExitCode::from(1),
            Failure::Usage(e) => {
                eprintln!("error: {e:#}");
                std::process::ExitCode::from(2)
            }
            Failure::Internal(e) => {
                eprintln!("internal error: {e:#}");
                std::process::ExitCode::from(3)
            }
        }
    }
}

/// Prints one file's diagnostics to stderr.
pub fn print_diagnostics(file: &FileDiagnostics, format: MessageFormat) {
    let format = match format {
        MessageFormat::Json => Format::Json,
        MessageFormat::Human => Format::Human { color: std::io::stderr().is_terminal() },
    };
    let choice = if matches!(format, Format::Human { color: true }) { ColorChoice::Auto } else { ColorChoice::Never };
    let mut stderr = StandardStream::stderr(choice);
    let name = file.file.name();
    let source = Source { name: &name, text: &file.file.text };
    // A closed stderr leaves nothing to report to.
    let _ = diag::emit(&mut stderr, source, &file.diagnostics, format);
    let _ = stderr.flush();
}

/// Renders a library failure: every file's diagnostics (exit 1), an unreadable input (exit 2),
/// or a compiler bug (exit 3).
pub fn project_failure(e: ProjectError, format: MessageFormat) -> Failure {
    match e {
        ProjectError::Diagnostics(failed) => {
            for file in &failed {
                print_diagnostics(file, format);
            }
            Failure::Diagnostics
        }
        ProjectError::Read(e) => Failure::Usage(e.into()),
        e @ (ProjectError::Bind { .. } | ProjectError::Write { .. }) => Failure::Usage(e.into()),
        e @ (ProjectError::Validate(_) | ProjectError::Emit(_)) => Failure::Internal(e.into()),
    }
}

/// Maps a device failure to an exit code: no adapter or no compiler is a usage problem (2);
/// anything the device rejects is a bug (3).
#[cfg(feature = "gpu")]
pub fn gpu_failure(e: glazec_gpu::RunError) -> Failure {
    use glazec_gpu::RunError;
    match e {
        RunError::NoAdapter { .. }
        | RunError::ToolMissing { .. }
        | RunError::NoPassthrough { .. }
        | RunError::Io(_) => Failure::Usage(e.into()),
        _ => Failure::Internal(e.into()),
    }
}

/// Writes `lines` to stdout through one buffer.
pub fn print_lines(lines: impl IntoIterator<Item = String>) -> Result<(), Failure> {
    let mut stdout = std::io::BufWriter::new(std::io::stdout().lock());
    for line in lines {
        writeln!(stdout, "{line}")
            .map_err(|e| Failure::Usage(anyhow::Error::new(e).context("cannot write to stdout")))?;
    }
    stdout.flush().map_err(|e| Failure::Usage(anyhow::Error::new(e).context("cannot write to stdout")))
}
