//! The `coil-tune` command line: argument parsing and dispatch. The binary only calls
//! [`main`] and maps its error to the exit code (1 for an error in the data or a run, 2 for
//! a usage error, as clap does).

use crate::calibrate::{calibrate, CalibrateSettings, Targets};
use crate::case::read_case;
use crate::damping::RunControl;
use crate::decay::Method;
use crate::error::Result;
use crate::output::OutDir;
use clap::{Args, Parser, Subcommand};
use coil_io::stdout::{line as stdout_line, text as stdout_text};
use std::path::PathBuf;

/// A failed write to stdout (other than a closed pipe, which is quiet).
fn stdout_error(e: std::io::Error) -> crate::TuneError {
    crate::TuneError::io("stdout", e)
}

/// Prints `s` as it is.
fn text(s: &str) -> Result<()> {
    stdout_text(s).map_err(stdout_error)
}

/// Prints `s` and a newline.
fn line(s: &str) -> std::io::Result<()> {
    stdout_line(s)
}

/// `say!(...)`: a formatted line on stdout.
macro_rules! say {
    ($($arg:tt)*) => {
        stdout_line(&format!($($arg)*)).map_err(stdout_error)
    };
}

/// coil-tune: the paper's Figure 6 calibration, procedure files, variant sweeps and the
/// paper's tables reproduced on coil's solver.
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
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// Settings shared by the commands that build and run the model.
#[derive(Debug, Args, Clone)]
pub struct ModelArgs {
    /// Beams per coil of the helix.
    #[arg(long, default_value_t = 24)]
    pub elements_per_coil: u32,
    /// How the grid's decay transients run: `modal` (superposition; the optimum is
    /// re-checked by direct integration) or `direct` (every point integrated directly).
    #[arg(long, default_value = "modal")]
    pub method: Method,
    /// Do not re-check the chosen point by direct integration (modal method).
    #[arg(long)]
    pub no_check: bool,
    /// Stop each grid after this many new points (the journal keeps them; rerun to go on).
    #[arg(long)]
    pub max_points: Option<usize>,
    /// Replace the paper's two domains by these grids (repeatable), each as in a
    /// procedure file: "alpha 0:0.1:2 beta 0:1e-5:2e-4 name domain2".
    #[arg(long = "grid", value_parser = crate::procedure::parse_grid)]
    pub grids: Vec<crate::grid::GridSpec>,
    /// No progress bars.
    #[arg(long, short)]
    pub quiet: bool,
}

impl ModelArgs {
    /// The calibration settings these flags give.
    pub fn settings(&self) -> CalibrateSettings {
        let mut s = CalibrateSettings::default();
        s.fe.elements_per_coil = self.elements_per_coil;
        s.damping.decay.method = self.method;
        s.damping.check_direct = !self.no_check && self.method == Method::Modal;
        s.damping.progress = !self.quiet;
        if !self.grids.is_empty() {
            s.damping.grids = self.grids.clone();
        }
        s
    }

    pub fn control(&self) -> RunControl {
        RunControl {
            max_new_points: self.max_points,
        }
    }
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Loops 1-3 of the paper's Figure 6 on a case (folder or case.json).
    Calibrate {
        case: PathBuf,
        /// Output folder for decks, logs, grids and figures.
        #[arg(long, default_value = "out/calibrate")]
        out: PathBuf,
        #[command(flatten)]
        model: ModelArgs,
    },
    /// K and zeta of spring variants with the validated material (Table 4).
    Sweep {
        case: PathBuf,
        /// The variants file (e.g. cases/160ect/table4.json).
        #[arg(long)]
        variants: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out/sweep")]
        out: PathBuf,
        /// Take E, mass, alpha and beta from a calibration.json (`calibrate`'s output)
        /// instead of calibrating first.
        #[arg(long, conflicts_with = "paper_material")]
        calibration: Option<PathBuf>,
        /// Use the paper's Table 2 (E, alpha, beta; the mass tuned to the period) instead.
        #[arg(long)]
        paper_material: bool,
        #[command(flatten)]
        model: ModelArgs,
    },
    /// The paper's study: calibrate + sweep on cases/160ect, Tables 3 and 4 beside the
    /// paper's, report.md, report.json and the figures.
    Paper {
        /// Output folder.
        #[arg(long, default_value = "out/paper")]
        out: PathBuf,
        /// The case.
        #[arg(long, default_value = "cases/160ect")]
        case: PathBuf,
        /// The variants file.
        #[arg(long, default_value = "cases/160ect/table4.json")]
        variants: PathBuf,
        #[command(flatten)]
        model: ModelArgs,
    },
    /// Diagnose a measured case (docs/measured-case.md): fit the paper's model,
    /// show what it misses, name the cause, extend the model and measure the gain.
    /// Writes DIR/diagnosis.json, report.md, figures and tables (docs/diagnose.md).
    Diagnose {
        /// The case folder (or its case.json).
        case: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out/diagnose")]
        out: PathBuf,
        /// Beams per coil of the helix.
        #[arg(long, default_value_t = 24)]
        elements_per_coil: u32,
        /// Fixed-interface modes kept in the reduced model (0 to 50).
        #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u16).range(0..=50))]
        modes: u16,
        /// No figures (tables and report.md only).
        #[arg(long)]
        no_plots: bool,
        /// No progress messages.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Run a procedure file (docs/procedures.md), e.g. cases/160ect/figure6.proc.
    Run {
        procedure: PathBuf,
        /// Output folder (overrides the file's `out`; default out/<procedure name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Only parse and check the file.
        #[arg(long)]
        dry_run: bool,
        /// Stop each grid after this many new points (the journal keeps them).
        #[arg(long)]
        max_points: Option<usize>,
    },
}

/// Runs the parsed command.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Calibrate { case, out, model } => {
            let case = read_case(&case)?;
            let targets = Targets::of(&case)?;
            let out = OutDir::create(out)?;
            let result = calibrate(
                &case,
                &targets,
                &model.settings(),
                Some(&out),
                &model.control(),
            )?;
            out.commit()?;
            text(&result.summary())?;
            say!("files in {}", out.root().display())?;
            Ok(())
        }
        Command::Sweep {
            case,
            variants,
            out,
            calibration,
            paper_material,
            model,
        } => {
            let case = read_case(&case)?;
            let variants = crate::case::read_variants(&variants)?;
            let out = OutDir::create(out)?;
            let settings = model.settings();
            let material = if let Some(file) = calibration {
                read_calibrated_state(&file)?
            } else if paper_material {
                crate::sweep::paper_material(&case, &settings)?
            } else {
                let targets = Targets::of(&case)?;
                let sub = out.sub("calibration")?;
                let result = calibrate(&case, &targets, &settings, Some(&sub), &model.control())?;
                text(&result.summary())?;
                result.state
            };
            // The table by direct integration unless checks are off (--no-check).
            let mut decay = settings.damping.decay.clone();
            if settings.damping.check_direct {
                decay.method = crate::decay::Method::Direct;
            }
            let result = crate::sweep::sweep(&material, &variants, &settings.fe, &decay)?;
            out.write("sweep.csv", result.csv().as_bytes())?;
            let json = serde_json::to_string_pretty(&result)
                .map_err(|e| crate::TuneError::Invalid(format!("sweep.json: {e}")))?;
            out.write("sweep.json", json.as_bytes())?;
            out.commit()?;
            say!(
                "material: E = {:.1} MPa, mass = {:.5} kg, alpha = {:.4} 1/s, beta = {:.4e} s",
                material.youngs_modulus_mpa,
                material.mass_kg,
                material.alpha,
                material.beta
            )?;
            text(&result.table())?;
            say!("files in {}", out.root().display())?;
            Ok(())
        }
        Command::Diagnose {
            case,
            out,
            elements_per_coil,
            modes,
            no_plots,
            quiet,
        } => {
            let mut settings = crate::diagnose::DiagnoseSettings::default();
            settings.fe.elements_per_coil = elements_per_coil;
            settings.modes = usize::from(modes);
            settings.plots = !no_plots;
            settings.progress = !quiet;
            let outcome = crate::diagnose::diagnose(&case, &settings)?;
            crate::diagnose::write(&outcome, &out, &settings)?;
            text(&crate::diagnose::summary(&outcome))?;
            say!("report in {}", out.join("report.md").display())?;
            Ok(())
        }
        Command::Paper {
            out,
            case,
            variants,
            model,
        } => {
            let out = OutDir::create(out)?;
            let options = crate::paper::PaperOptions {
                case,
                variants,
                settings: model.settings(),
                control: model.control(),
            };
            let report = crate::paper::run_paper(&options, &out)?;
            out.commit()?;
            say!("Table 3 ({}):", report.case)?;
            text(&crate::report::table3(&report))?;
            say!("\nTable 4:")?;
            text(&crate::report::table4(&report))?;
            let m = &report.mesh_study;
            say!(
                "\nmesh bias: the paper's E = {} MPa at ~{} elements per coil; mesh-converged E = {:.0} MPa",
                m.paper_youngs_modulus_mpa,
                m.elements_per_coil_matching_paper
                    .map_or("?".into(), |n| format!("{n:.1}")),
                m.converged_youngs_modulus_mpa
            )?;
            say!(
                "total {:.2} s; report in {}",
                report.timings.total_s,
                out.path("report.md").display()
            )?;
            Ok(())
        }
        Command::Run {
            procedure,
            out,
            dry_run,
            max_points,
        } => {
            let parsed = crate::procedure::read(&procedure)?;
            if dry_run {
                say!(
                    "{}: {} commands, no errors",
                    procedure.display(),
                    parsed.statements.len()
                )?;
                return Ok(());
            }
            let control = RunControl {
                max_new_points: max_points,
            };
            // A closed stdout ends the printing, not the run (coil_io::stdout).
            let mut failed = None;
            let result = crate::procedure::run(&parsed, out.as_deref(), &control, &mut |l| {
                if let Err(e) = line(l) {
                    failed.get_or_insert(e);
                }
            })?;
            if let Some(e) = failed {
                return Err(stdout_error(e));
            }
            if let Some(s) = result.state {
                say!(
                    "final: E = {:.1} MPa, mass = {:.5} kg, alpha = {:.4} 1/s, beta = {:.4e} s",
                    s.youngs_modulus_mpa,
                    s.mass_kg,
                    s.alpha,
                    s.beta
                )?;
            }
            Ok(())
        }
    }
}

/// The `state` of a calibration.json.
fn read_calibrated_state(path: &std::path::Path) -> Result<crate::fe::SpringState> {
    let text = std::fs::read_to_string(path).map_err(|e| crate::TuneError::io(path, e))?;
    #[derive(serde::Deserialize)]
    struct File {
        state: crate::fe::SpringState,
    }
    let file: File = serde_json::from_str(&text).map_err(|e| crate::TuneError::Procedure {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!(
            "{e}; expected a calibration.json written by `coil-tune calibrate` (with a `state`)"
        ),
    })?;
    Ok(file.state)
}
