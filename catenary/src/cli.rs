//! The `catenary` command of `coil-tune`: its arguments and dispatch; the binary joins it
//! with the paper's and the identification commands.

use crate::case::{read_case_with, CaseOptions};
use crate::head_stage::from_spring::{build_heads, DampingChoice, HeadSpringSpec};
use crate::Result;
use clap::{Subcommand, ValueEnum};
use coil_tuner::cli::{say, text};
use coil_tuner::fe::FeSettings;
use coil_tuner::output::OutDir;
use std::path::PathBuf;

/// `--damping`'s values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DampingArg {
    /// `c = alpha n m_s / 3 + beta K` (the spring's Rayleigh law).
    Rayleigh,
    /// `c = 2 zeta_low sqrt(K m)`.
    ZetaLow,
    /// `c = 2 zeta_mid sqrt(K m)`.
    ZetaMid,
    /// `c = 2 zeta_high sqrt(K m)`.
    ZetaHigh,
}

/// The pantograph-catenary commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a pantograph-catenary case (docs/catenary.md, "Runs"): the catenary's static
    /// state (dropper lengths for the presag), then the pantograph's run at each speed
    /// from it, EN 50318's statistics of the contact force over the evaluation window,
    /// the validation against the reference ranges (the reference model only) and the
    /// EN 50367 / EN 50119 assessment. Writes DIR/catenary.json, report.md, the figures
    /// and the histories; with --springs, a spring study (study.json, report.md).
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
        /// A spring study: the case once per spring source in the head stage (a measured
        /// case folder, a variants file or `FILE:NAME` for one variant, a calibration.json,
        /// a SPRING.json, a design.json or `FILE:RANK` for one of its candidates), one
        /// table.
        #[arg(long, num_args = 1.., value_name = "SPRING")]
        springs: Vec<PathBuf>,
        /// The head stage's dashpot (overrides the case's `head_spring.damping`).
        #[arg(long, value_enum)]
        damping: Option<DampingArg>,
        /// Leave the springs' mass off the head.
        #[arg(long)]
        no_mass_share: bool,
        /// The head stage as the reduced spring model (the surge modes kept).
        #[arg(long)]
        reduced: bool,
        /// Springs in parallel under the head (overrides the case's).
        #[arg(long, value_name = "N")]
        springs_in_parallel: Option<u32>,
        /// The speeds to run (km/h) instead of the case's `speeds_km_h`: "which spring
        /// gives the lowest sigma at 300 km/h" is `--springs ... --speeds 300`.
        #[arg(long, num_args = 1.., value_name = "KM_H")]
        speeds: Vec<f64>,
        /// Run speeds at or above the contact wire's wave speed (a regime the model does
        /// not cover; refused without this flag).
        #[arg(long)]
        allow_supercritical: bool,
        /// Run transients above the work limit (steps x DOFs > 1e10, docs/files.md).
        #[arg(long)]
        allow_large: bool,
    },
}

/// The head-stage options: the case's `head_spring`, the flags over it.
fn head_options(
    case: Option<&HeadSpringSpec>,
    damping: Option<DampingArg>,
    no_mass_share: bool,
    reduced: bool,
    springs_in_parallel: Option<u32>,
) -> HeadSpringSpec {
    let mut spec = case.cloned().unwrap_or_default();
    if let Some(d) = damping {
        spec.damping = match d {
            DampingArg::Rayleigh => DampingChoice::Rayleigh,
            DampingArg::ZetaLow => DampingChoice::ZetaLow,
            DampingArg::ZetaMid => DampingChoice::ZetaMid,
            DampingArg::ZetaHigh => DampingChoice::ZetaHigh,
        };
    }
    if no_mass_share {
        spec.mass_share = false;
    }
    if reduced {
        spec.reduced = true;
    }
    if let Some(n) = springs_in_parallel {
        spec.springs_in_parallel = n;
    }
    spec
}

/// What a catenary command asks for, from the command line or Python.
#[derive(Debug, Clone, Default)]
pub struct Request {
    /// The case folder (or its case.json).
    pub case: PathBuf,
    /// Output folder.
    pub out: PathBuf,
    /// Write the figures.
    pub plots: bool,
    /// Progress on stderr.
    pub progress: bool,
    /// Spring sources for a spring study (empty: one run of the case).
    pub springs: Vec<PathBuf>,
    /// `--damping`.
    pub damping: Option<DampingArg>,
    /// `--no-mass-share`.
    pub no_mass_share: bool,
    /// `--reduced`.
    pub reduced: bool,
    /// `--springs-in-parallel`.
    pub springs_in_parallel: Option<u32>,
    /// `--allow-supercritical`, `--allow-large`, `--speeds`.
    pub options: CaseOptions,
}

/// What a request produced (its files are in the output folder).
#[derive(Debug)]
pub enum Done {
    /// One run of the case (`catenary.json`).
    Case(Box<crate::run::Outcome>),
    /// A spring study (`study.json`).
    Study(Box<crate::study::Study>),
}

/// Reads, checks, runs and writes a request; every input is checked before the output
/// folder is taken or a run starts.
pub fn execute(request: &Request, announce: &dyn Fn(&str) -> Result<()>) -> Result<Done> {
    let case = read_case_with(&request.case, request.options.clone())?;
    let head_spec = head_options(
        case.head_spring.as_ref(),
        request.damping,
        request.no_mass_share,
        request.reduced,
        request.springs_in_parallel,
    );
    head_spec.check().map_err(crate::TuneError::Invalid)?;
    let fe = FeSettings::default();
    let heads = if request.springs.is_empty() {
        match &case.head_spring_source {
            Some(source) => build_heads(
                std::slice::from_ref(source),
                &head_spec,
                &case.pantograph,
                &fe,
            )?,
            None => Vec::new(),
        }
    } else {
        build_heads(&request.springs, &head_spec, &case.pantograph, &fe)?
    };
    // The folder is held for the whole run (one run per folder).
    let out = OutDir::create(&request.out)?;
    if !request.springs.is_empty() {
        announce(&format!(
            "catenary '{}': spring study, {} springs x {} speeds",
            case.title,
            heads.len(),
            case.speeds_km_h.len()
        ))?;
        let study = crate::study::run_study(&case, &heads, request.progress)?;
        crate::study::write(&study, &out, request.plots)?;
        out.commit()?;
        Ok(Done::Study(Box::new(study)))
    } else {
        announce(&format!(
            "catenary '{}': {} speeds, {} spans{}",
            case.title,
            case.speeds_km_h.len(),
            case.catenary.spans,
            heads.first().map_or(String::new(), |h| format!(
                ", head stage from spring `{}`",
                h.name
            ))
        ))?;
        let outcome = crate::run::run_case_with(&case, heads.first(), request.progress)?;
        crate::output::write(&outcome, &out, request.plots)?;
        out.commit()?;
        Ok(Done::Case(Box::new(outcome)))
    }
}

/// Runs the parsed command.
pub fn run(command: Command) -> Result<()> {
    let Command::Catenary {
        case,
        out,
        no_plots,
        quiet,
        springs,
        damping,
        no_mass_share,
        reduced,
        springs_in_parallel,
        speeds,
        allow_supercritical,
        allow_large,
    } = command;
    let request = Request {
        case,
        out: out.clone(),
        plots: !no_plots,
        progress: !quiet,
        springs,
        damping,
        no_mass_share,
        reduced,
        springs_in_parallel,
        options: CaseOptions {
            allow_supercritical,
            allow_large,
            speeds_km_h: (!speeds.is_empty()).then_some(speeds),
        },
    };
    let announce = |line: &str| if quiet { Ok(()) } else { say(line) };
    match execute(&request, &announce)? {
        Done::Case(outcome) => text(&crate::output::summary(&outcome))?,
        Done::Study(study) => text(&crate::study::summary(&study))?,
    }
    say(&format!("report in {}", out.join("report.md").display()))?;
    Ok(())
}
