//! `coil-solve deck.dat --out DIR [--method direct|modal [--modes N]]`: reads a deck,
//! runs its load cases, writes `DIR/results.json`, the `.vtu` files and the transient
//! histories (`DIR/history.csv`, ...). Errors go to stderr with their location and a
//! non-zero exit status.

use clap::{Parser, ValueEnum};
use coil_solver::analysis::transient::{self, override_method, MethodOverride};
use coil_solver::analysis::{self, CaseResult, CaseSolution};
use coil_solver::{deck, results, wire, Error, Model};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Method {
    /// Direct time integration (the deck's scheme, or Newmark average acceleration).
    Direct,
    /// Modal superposition, each mode integrated exactly.
    Modal,
}

/// Solve a coil deck (static, modal and transient load cases of 3D beam models).
#[derive(Debug, Parser)]
#[command(
    name = "coil-solve",
    version,
    after_help = "Files (docs/files.md): --out is locked for the run (a second run into it is refused) and \
its files appear as a whole set or not at all; existing symlinks, devices and FIFOs there are never \
replaced. Limits: decks up to 64 MiB; a transient of at most 1e8 steps and 1e10 steps x DOFs \
unless --allow-large. A transient announces its steps and shows progress past 2 s on stderr."
)]
struct Cli {
    /// The input deck (Marc-style, see docs/deck.md).
    deck: PathBuf,
    /// Directory for results.json, the .vtu files and the histories (created if missing).
    #[arg(long, short)]
    out: PathBuf,
    /// Solve every transient load case by this method instead of the deck's.
    #[arg(long, value_enum)]
    method: Option<Method>,
    /// Modes of `--method modal` [default: the deck's count, else 20].
    #[arg(long, value_name = "N", requires = "method", value_parser = clap::value_parser!(u32).range(1..))]
    modes: Option<u32>,
    /// Run a transient above the work limit (steps x DOFs > 1e10, about a minute;
    /// docs/files.md).
    #[arg(long)]
    allow_large: bool,
    /// Print nothing on success (no step counts, no progress).
    #[arg(long, short)]
    quiet: bool,
    /// Also write each transient history as UFF dataset 58 (`history.uff` beside
    /// `history.csv`): ASCII, or binary (58b).
    #[arg(long, value_enum)]
    uff: Option<UffArg>,
}

/// The form of the UFF histories.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum UffArg {
    /// ASCII dataset 58.
    Ascii,
    /// Binary dataset 58b.
    Binary,
}

fn summary(model: &Model, cases: &[CaseResult]) -> String {
    let mut out = String::new();
    let mut first_transient = true;
    for (index, case) in cases.iter().enumerate() {
        match &case.solution {
            CaseSolution::Static(s) => {
                let k = s.stiffness_n_mm.map_or_else(
                    || "n/a (no single reference load)".to_string(),
                    |k| format!("{k:.6} N/mm"),
                );
                out.push_str(&format!("static '{}': stiffness {k}\n", case.title));
                let forces = wire::element_forces(model, &s.displacement);
                if let Some(p) = wire::peak(model, &forces) {
                    out.push_str(&format!(
                        "  wire stress: torsion + direct shear {:.2} MPa (torsion {:.2}, direct \
                         shear {:.2}, bending {:.2}) at element {}\n",
                        p.stress.shear_mpa,
                        p.stress.torsion_mpa,
                        p.stress.direct_shear_mpa,
                        p.stress.bending_mpa,
                        p.element
                    ));
                }
                if let Some(helix) = wire::Helix::of(model) {
                    let c = helix.index();
                    let force = forces
                        .get(forces.len() / 2)
                        .map_or(0.0, |f| f.force_global_n[2].abs());
                    let nominal = wire::nominal_stress_mpa(
                        force,
                        helix.mean_diameter_mm,
                        helix.wire_diameter_mm,
                    );
                    out.push_str(&format!(
                        "  spring index C = {c:.3}, solid length {:.2} mm; handbook stress at \
                         {force:.3} N: nominal {nominal:.2} MPa, Wahl {:.2} MPa, Bergstraesser {:.2} MPa\n",
                        helix.solid_length_mm(),
                        wire::wahl_factor(c) * nominal,
                        wire::bergstraesser_factor(c) * nominal,
                    ));
                    if let Some((factor, node)) = helix.contact_factor(model, &s.displacement) {
                        out.push_str(&format!(
                            "  adjacent coils touch at {:.2} N (node {})\n",
                            factor * force,
                            model.nodes()[node].id
                        ));
                        if factor < 1.0 {
                            out.push_str(&format!(
                                "  warning: the load passes it: beyond {:.2} N the coils are solid \
                                 and this linear model does not apply\n",
                                factor * force
                            ));
                        }
                    }
                }
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
            CaseSolution::Transient(t) => {
                let file = results::history_file_name(first_transient, index + 1);
                first_transient = false;
                let method = transient::method_label(&t.method);
                out.push_str(&format!(
                    "transient '{}': {method}, {} steps of {} s, {} columns -> {file}\n",
                    case.title,
                    t.steps,
                    t.dt_s,
                    t.history.columns.len()
                ));
                if let Some(m) = &t.modal {
                    let percent = |x: Option<f64>| {
                        x.map_or_else(|| "-".to_string(), |x| format!("{:.4}%", 100.0 * x))
                    };
                    out.push_str(&format!(
                        "  damping coupling neglected: {:.2e}{}, largest zeta shift {}; \
                         captured: initial displacement {}, velocity {}, loads {}\n",
                        m.capture.max_damping_coupling,
                        m.capture
                            .coupling_pair
                            .map_or(String::new(), |(i, j)| format!(" (modes {i}, {j})")),
                        m.capture
                            .max_zeta_shift
                            .map_or_else(|| "-".to_string(), |x| format!("{x:.2e}")),
                        percent(m.capture.initial_displacement_captured),
                        percent(m.capture.initial_velocity_captured),
                        percent(m.capture.load_captured),
                    ));
                }
                for w in &t.warnings {
                    out.push_str(&format!("  warning: {w}\n"));
                }
            }
        }
    }
    out
}

fn run(cli: &Cli) -> Result<(Model, Vec<CaseResult>), Error> {
    let (mut model, not_needed) = deck::read_file_noting(&cli.deck)?;
    if !not_needed.is_empty() {
        let cards: Vec<String> = not_needed
            .iter()
            .map(|n| format!("{} (line {})", n.card, n.line))
            .collect();
        eprintln!("read and not needed: {}", cards.join(", "));
    }
    match cli.method {
        Some(Method::Direct) => override_method(&mut model, MethodOverride::Direct),
        Some(Method::Modal) => {
            override_method(&mut model, MethodOverride::Modal { modes: cli.modes })
        }
        None => {}
    }
    // The folder is held for the whole run: a second run into it is refused at once.
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let set = coil_io::OutputSet::open(&cli.out, &command)?;
    let options = transient::RunOptions {
        progress: !cli.quiet,
        allow_large: Some(cli.allow_large),
    };
    let cases = analysis::run_with(&model, &options)?;
    results::write_set(&set, &model, &cases)?;
    if let Some(form) = cli.uff {
        let form = match form {
            UffArg::Ascii => coil_io::uff::UffForm::Ascii,
            UffArg::Binary => coil_io::uff::UffForm::Binary,
        };
        results::stage_history_uff(&set, &cases, form)?;
    }
    set.commit()?;
    Ok((model, cases))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if cli.method == Some(Method::Direct) && cli.modes.is_some() {
        eprintln!("error: --modes applies to --method modal only");
        return ExitCode::from(2);
    }
    match run(&cli) {
        Ok((model, cases)) => {
            if !cli.quiet {
                // The results are already on disk; a closed stdout (`| head`) is not an
                // error worth a panic or a failure exit.
                use std::io::Write;
                let mut out = std::io::stdout().lock();
                let _ = write!(out, "{}", summary(&model, &cases)).and_then(|()| {
                    writeln!(out, "results in {}", cli.out.join("results.json").display())
                });
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            // Deck errors carry file:line:column themselves; analysis errors name nodes,
            // DOFs and elements of the deck given on the command line. Every message
            // already includes its cause, so the source chain is not repeated.
            match &e {
                Error::Solve(_) => eprintln!(
                    "error: {}",
                    coil_io::clean_message(&format!("{}: {e}", cli.deck.display()))
                ),
                _ => eprintln!("error: {}", coil_io::clean_message(&e.to_string())),
            }
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn method_flags_parse() {
        let cli = Cli::try_parse_from(["coil-solve", "d.dat", "--out", "o", "--method", "modal"])
            .unwrap();
        assert_eq!((cli.method, cli.modes), (Some(Method::Modal), None));
        let cli = Cli::try_parse_from([
            "coil-solve",
            "d.dat",
            "-o",
            "o",
            "--method",
            "modal",
            "--modes",
            "12",
        ])
        .unwrap();
        assert_eq!(cli.modes, Some(12));
        // --modes needs --method, and at least one mode.
        assert!(Cli::try_parse_from(["coil-solve", "d.dat", "-o", "o", "--modes", "3"]).is_err());
        assert!(Cli::try_parse_from([
            "coil-solve",
            "d.dat",
            "-o",
            "o",
            "--method",
            "modal",
            "--modes",
            "0"
        ])
        .is_err());
        assert!(
            Cli::try_parse_from(["coil-solve", "d.dat", "-o", "o", "--method", "rk4"]).is_err()
        );
    }
}
