//! The `catenary` command of `coil-tune`: its arguments and dispatch; the binary joins it
//! with the paper's and the identification commands.

use crate::Result;
use clap::Subcommand;
use coil_tuner::cli::{say, text};
use coil_tuner::output::OutDir;
use std::path::PathBuf;

/// The pantograph-catenary commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a pantograph-catenary case (docs/catenary.md, "Runs"): the catenary's static
    /// state (dropper lengths for the presag), then the pantograph's run at each speed
    /// from it, EN 50318's statistics of the contact force over the evaluation window
    /// against the case's reference ranges. Writes DIR/catenary.json, report.md, the
    /// figures and the histories.
    Catenary {
        /// The case folder (or its case.json).
        case: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out/catenary")]
        out: PathBuf,
        /// No figures (catenary.json, report.md and the histories only).
        #[arg(long)]
        no_plots: bool,
        /// No progress messages.
        #[arg(long, short)]
        quiet: bool,
    },
}

/// Runs the parsed command.
pub fn run(command: Command) -> Result<()> {
    match command {
        Command::Catenary {
            case,
            out,
            no_plots,
            quiet,
        } => {
            let case = crate::case::read_case(&case)?;
            // The folder is held for the whole run (one run per folder).
            let out = OutDir::create(out)?;
            if !quiet {
                say(&format!(
                    "catenary '{}': {} speeds, {} spans",
                    case.title,
                    case.speeds_km_h.len(),
                    case.catenary.spans
                ))?;
            }
            let outcome = crate::run::run_case(&case)?;
            crate::run::write(&outcome, &out, !no_plots)?;
            out.commit()?;
            text(&crate::run::summary(&outcome))?;
            say(&format!("report in {}", out.path("report.md").display()))?;
            Ok(())
        }
    }
}
