//! The identification commands of `coil-tune`: `diagnose` (docs/diagnose.md; forced
//! records: docs/forced.md), `damping` (docs/damping.md), and `simulate` and `frc` on a
//! forced diagnosis's model (docs/forced.md). Their arguments and dispatch; the binary joins them with the
//! paper's commands of `coil_tuner::cli`.

use crate::error::Result;
use crate::output::OutDir;
use clap::Subcommand;
use coil_tuner::cli::{say, text};
use std::path::PathBuf;

/// The identification commands.
#[derive(Debug, Subcommand)]
pub enum Command {
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
        /// Fixed-interface modes kept in the reduced model (0 to 8: the axial frequency
        /// has converged with 4, and the time grows with their square).
        #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u16).range(0..=8))]
        modes: u16,
        /// No figures (tables and report.md only).
        #[arg(long)]
        no_plots: bool,
        /// Also write the fits as DIR/fits.uff: UFF dataset 58, ASCII or binary (58b).
        #[arg(long, value_enum)]
        uff: Option<UffArg>,
        /// No progress messages.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Drive a model (DIR/model.json of a forced diagnosis) with a record's input, from the
    /// initial state fitted to the first --init output samples (the rest of the output
    /// column is never read and may be empty). Writes DIR/simulated.csv (time_s,output).
    Simulate {
        /// The model file (model.json or model_linear.json of a forced diagnosis).
        model: PathBuf,
        /// The record: CSV of any dialect, a level 5 `.mat` file or UFF 58 (recognised
        /// by content; values as written).
        #[arg(long)]
        record: PathBuf,
        /// Its time column or `.mat` variable (s); a UFF dataset's abscissa is its time.
        #[arg(long, default_value = "time_s")]
        time: String,
        /// Its input column, `.mat` variable or UFF dataset (index or `node:direction`).
        #[arg(long)]
        input: String,
        /// Its output column, variable or dataset (only the first --init values are read).
        #[arg(long)]
        output: String,
        /// Output samples the initial state is fitted to.
        #[arg(long)]
        init: usize,
        /// Output folder.
        #[arg(long, default_value = "out/simulate")]
        out: PathBuf,
        /// No progress messages.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Forced response curve of a model (DIR/model.json of a forced diagnosis) under a
    /// harmonic input of amplitude A from F1 to F2 Hz: harmonic balance continued through
    /// the folds, each point's stability by Floquet. Writes DIR/frc.csv
    /// (frequency_hz,amplitude,stable) and DIR/backbone.csv.
    Frc {
        /// The model file.
        model: PathBuf,
        /// Input amplitude, in the model's input unit.
        #[arg(long)]
        amplitude: f64,
        /// First frequency, Hz.
        #[arg(long = "from")]
        from_hz: f64,
        /// Last frequency, Hz.
        #[arg(long = "to")]
        to_hz: f64,
        /// About how many points across the span.
        #[arg(long, default_value_t = 400)]
        points: usize,
        /// Harmonics kept in the balance.
        #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u16).range(1..=40))]
        harmonics: u16,
        /// Output folder.
        #[arg(long, default_value = "out/frc")]
        out: PathBuf,
        /// No progress messages.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Which damping law? Fits Rayleigh, hysteretic and an external dashpot to all decay
    /// records of a case at once (records at several masses, a surge record, repeats),
    /// judged against the repeat scatter of zeta; names the law when it alone fits or says
    /// it cannot, and writes DIR/damping.json
    /// (docs/measured-case.md) and DIR/report.md (docs/damping.md).
    Damping {
        /// The case folder (or its case.json).
        case: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out/damping")]
        out: PathBuf,
        /// Table 4 variants to predict (default: table4.json beside case.json, if any).
        #[arg(long)]
        variants: Option<PathBuf>,
        /// Beams per coil of the helix.
        #[arg(long, default_value_t = 24)]
        elements_per_coil: u32,
        /// Repeat scatter of one test's zeta (relative) when the case has no repeated tests
        /// (records of one mode at one mass); with repeats, their estimate is used. It weighs
        /// each record in the fit, sets how far a law may miss, and sizes the proposed test.
        #[arg(long, default_value_t = 0.03)]
        scatter: f64,
        /// No progress messages (accepted by every command; damping prints none).
        #[arg(long, short)]
        quiet: bool,
    },
}

/// Runs the parsed command.
pub fn run(command: Command) -> Result<()> {
    match command {
        Command::Simulate {
            model,
            record,
            time,
            input,
            output,
            init,
            out,
            quiet: _,
        } => {
            let model = crate::forced::commands::read_model(&model)?;
            let request = crate::forced::commands::SimulateRequest {
                record,
                time,
                input,
                output,
                init,
            };
            // Everything is read and computed before the folder is touched.
            let sim = crate::forced::commands::simulate_record(&model, &request)?;
            let out = OutDir::create(out)?;
            crate::forced::commands::write_simulated(&sim, &out)?;
            say(&format!(
                "{} samples simulated from the state fitted to the first {init}: {}",
                sim.output.len(),
                out.path("simulated.csv").display()
            ))?;
            Ok(())
        }
        Command::Frc {
            model,
            amplitude,
            from_hz,
            to_hz,
            points,
            harmonics,
            out,
            quiet: _,
        } => {
            let model = crate::forced::commands::read_model(&model)?;
            let settings = crate::forced::frc::FrcSettings {
                amplitude,
                from_hz,
                to_hz,
                points,
                harmonics: usize::from(harmonics),
            };
            let result = crate::forced::commands::frc_of(&model, &settings)?;
            let out = OutDir::create(out)?;
            crate::forced::commands::write_frc(&result, &out)?;
            let jumps: Vec<String> = result.jumps.iter().map(|f| format!("{f:.5}")).collect();
            say(&format!(
                "{} points, {} unstable; stability changes (folds) at [{}] Hz",
                result.points.len(),
                result.points.iter().filter(|p| !p.stable).count(),
                jumps.join(", ")
            ))?;
            say(&format!("frc.csv in {}", out.root().display()))?;
            Ok(())
        }
        Command::Damping {
            case,
            out,
            variants,
            elements_per_coil,
            scatter,
            quiet: _,
        } => {
            let mut settings = crate::law::DampingSettings {
                scatter,
                ..Default::default()
            };
            settings.fe.elements_per_coil = elements_per_coil;
            settings.variants = variants.or_else(|| crate::law::variants_beside(&case));
            let out = OutDir::create(out)?;
            let report = crate::law::identify(&case, &settings)?;
            // One output set: damping.json and report.md appear together or not at all.
            crate::law::write(&report, &out)?;
            text(&crate::law::summary(&report))?;
            say(&format!("damping.json in {}", out.root().display()))?;
            Ok(())
        }
        Command::Diagnose {
            case,
            out,
            elements_per_coil,
            modes,
            no_plots,
            uff,
            quiet,
        } => {
            if crate::forced::lists_forced(&case)? {
                let settings = crate::forced::ForcedSettings {
                    plots: !no_plots,
                    progress: !quiet,
                    ..Default::default()
                };
                let outcome = crate::forced::diagnose_forced(&case, &settings)?;
                let out = OutDir::create(out)?;
                crate::forced::report::write(&outcome, &out, settings.plots)?;
                say(&crate::forced::report::summary(&outcome))?;
                say(&format!("report in {}", out.path("report.md").display()))?;
                return Ok(());
            }
            let mut settings = crate::diagnose::DiagnoseSettings {
                fits_uff: uff.map(UffArg::form),
                ..Default::default()
            };
            settings.fe.elements_per_coil = elements_per_coil;
            settings.modes = usize::from(modes);
            settings.plots = !no_plots;
            settings.progress = !quiet;
            // The folder is held for the whole run, not only while writing (one run per folder).
            let out = OutDir::create(out)?;
            let outcome = crate::diagnose::diagnose(&case, &settings)?;
            crate::diagnose::write(&outcome, &out, &settings)?;
            text(&crate::diagnose::summary(&outcome))?;
            say(&format!("report in {}", out.path("report.md").display()))?;
            Ok(())
        }
    }
}

/// The form of a UFF output (`--uff`).
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum UffArg {
    /// ASCII dataset 58.
    Ascii,
    /// Binary dataset 58b.
    Binary,
}

impl UffArg {
    /// The writer's form.
    pub fn form(self) -> coil_io::uff::UffForm {
        match self {
            UffArg::Ascii => coil_io::uff::UffForm::Ascii,
            UffArg::Binary => coil_io::uff::UffForm::Binary,
        }
    }
}
