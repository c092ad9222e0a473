//! `glazec check`: every diagnostic of material files, nothing written.

use std::path::PathBuf;

use glazec::project::Project;

use crate::report::{Failure, MessageFormat, print_diagnostics, project_failure};

/// Check material files and print diagnostics; write nothing.
#[derive(clap::Args)]
pub struct Args {
    #[arg(required = true)]
    files: Vec<PathBuf>,
    #[arg(long, value_enum, default_value = "human")]
    message_format: MessageFormat,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let project = Project {
        inputs: args.files,
        scene: None,
        out_dir: PathBuf::new(),
        targets: Vec::new(),
        bindings: Default::default(),
        harness: false,
    };
    let outcome = project.compile().map_err(|e| project_failure(e, args.message_format))?;
    for file in &outcome.notes {
        print_diagnostics(file, args.message_format);
    }
    eprintln!("{} material(s) ok", outcome.compiled.len());
    Ok(())
}
