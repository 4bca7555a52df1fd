//! coil-tune (cli/) owns the command line only: it parses arguments, runs a command of
//! coil-tuner, coil-design, coil-ident or coil-catenary and maps errors to exit codes. It
//! may import those crates and coil-io; nothing imports it.
//!
//! `coil-tune`: the paper's commands (`coil_tuner::cli`), the spring sheet and design
//! (`coil_design::cli`), the identification commands
//! (`coil_ident::cli`) and the pantograph-catenary command (`coil_catenary::cli`) on one
//! command line. It parses the arguments, runs the command and
//! maps errors to the exit code: 1 for an error in the data or a run (the message on
//! stderr), 2 for a usage error (as clap does).

use clap::{Parser, Subcommand};

/// coil-tune: the paper's Figure 6 calibration, procedure files, variant sweeps and the
/// paper's tables reproduced on coil's solver; diagnosis of measured records and the damping
/// law they support; pantograph-catenary runs with EN 50318's statistics.
#[derive(Debug, Parser)]
#[command(
    name = "coil-tune",
    version,
    about,
    after_help = "Files (docs/files.md): --out is locked for the run and its files appear as a whole \
set (a failed or killed run leaves the previous set); record paths in case.json stay inside the case \
folder; procedure files write only inside their output folder. Records up to 64 MiB. A closed \
stdout (| head) ends the printing, not the run."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Every command, in the order `--help` lists them.
#[derive(Debug, Subcommand)]
enum Command {
    #[command(flatten)]
    Paper(coil_tuner::cli::Command),
    #[command(flatten)]
    Design(coil_design::cli::Command),
    #[command(flatten)]
    Ident(coil_ident::cli::Command),
    #[command(flatten)]
    Catenary(coil_catenary::cli::Command),
}

fn main() -> std::process::ExitCode {
    let result = match Cli::parse().command {
        Command::Paper(command) => coil_tuner::cli::run(command),
        Command::Design(command) => coil_design::cli::run(command),
        Command::Ident(command) => coil_ident::cli::run(command),
        Command::Catenary(command) => coil_catenary::cli::run(command),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            // Every message already carries its causes (file, line, field, what was expected).
            eprintln!(
                "coil-tune: error: {}",
                coil_io::clean_message(&error.to_string())
            );
            std::process::ExitCode::FAILURE
        }
    }
}
