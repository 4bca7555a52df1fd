//! `coil-solve deck.dat --out DIR`: reads a deck, runs its load cases, writes
//! `DIR/results.json` and the `.vtu` files. Errors go to stderr with their location and
//! a non-zero exit status.

use clap::Parser;
use coil_solver::analysis::{self, CaseResult, CaseSolution};
use coil_solver::{deck, results, Error};
use std::path::PathBuf;
use std::process::ExitCode;

/// Solve a coil deck (static and modal load cases of 3D beam models).
#[derive(Debug, Parser)]
#[command(name = "coil-solve", version)]
struct Cli {
    /// The input deck (Marc-style, see docs/deck.md).
    deck: PathBuf,
    /// Directory for results.json and the .vtu files (created if missing).
    #[arg(long, short)]
    out: PathBuf,
    /// Print nothing on success.
    #[arg(long, short)]
    quiet: bool,
}

fn summary(cases: &[CaseResult]) -> String {
    let mut out = String::new();
    for case in cases {
        match &case.solution {
            CaseSolution::Static(s) => {
                let k = s.stiffness_n_mm.map_or_else(
                    || "n/a (no single reference load)".to_string(),
                    |k| format!("{k:.6} N/mm"),
                );
                out.push_str(&format!("static '{}': stiffness {k}\n", case.title));
            }
            CaseSolution::Modal(m) => {
                out.push_str(&format!(
                    "modal '{}': {} modes\n",
                    case.title,
                    m.modes.len()
                ));
                out.push_str("  mode  frequency_hz    period_s  axial_m_eff_kg\n");
                for (i, mode) in m.modes.iter().enumerate() {
                    out.push_str(&format!(
                        "  {:4}  {:12.5}  {:10.6}  {:14.6}\n",
                        i + 1,
                        mode.frequency_hz,
                        mode.period_s,
                        mode.effective_mass[2] * 1e3
                    ));
                }
            }
        }
    }
    out
}

fn run(cli: &Cli) -> Result<Vec<CaseResult>, Error> {
    let model = deck::read_file(&cli.deck)?;
    let cases = analysis::run(&model)?;
    results::write_all(&cli.out, &model, &cases)?;
    Ok(cases)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(cases) => {
            if !cli.quiet {
                print!("{}", summary(&cases));
                println!("results in {}", cli.out.join("results.json").display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            // Deck errors carry file:line:column themselves; analysis errors name nodes,
            // DOFs and elements of the deck given on the command line. Every message
            // already includes its cause, so the source chain is not repeated.
            match &e {
                Error::Solve(_) => eprintln!("error: {}: {e}", cli.deck.display()),
                _ => eprintln!("error: {e}"),
            }
            ExitCode::FAILURE
        }
    }
}
