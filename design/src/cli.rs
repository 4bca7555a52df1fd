//! The spring-design commands of `coil-tune`: `check` (the EN 13906-1 sheet) and `design`
//! (design to a target), docs/spring-design.md. Their arguments and dispatch; the binary
//! joins them with the tuner's, the identification and the catenary commands.

use crate::error::Result;
use clap::Subcommand;
use coil_tuner::cli::{say, text};
use coil_tuner::output::OutDir;
use std::path::PathBuf;

/// The spring-design commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The EN 13906-1 sheet of a compression spring (SPRING.json, docs/spring-design.md)
    /// beside coil's FE values on the same spring: rate, surge mode, peak wire shear.
    Check {
        /// The spring (e.g. cases/spring-design/160ect_spring.json).
        spring: PathBuf,
        /// Print the sheet as JSON (snake_case keys with units) instead of the table.
        #[arg(long)]
        json: bool,
        /// Also write DIR/sheet.json and DIR/sheet.md (one output set).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Beams per coil of the FE helix to start from: the rate is refined by doubling
        /// them until it moves less than 0.1 %.
        #[arg(long, default_value_t = 24, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(4..=512))]
        elements_per_coil: u32,
    },
    /// Design to a target (TARGET.json, docs/spring-design.md): search standard wires,
    /// mean diameters, quarter turns and the pitch through every EN 13906-1 check and
    /// the envelope, verify the short list by FE, predict each one's zeta per damping
    /// law; writes DIR/design.json, report.md, design.png and decks/.
    Design {
        /// The target (e.g. cases/spring-design/160ect_target.json).
        target: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out/design")]
        out: PathBuf,
        /// Rank by this instead of the target's `objective`.
        #[arg(long, value_enum)]
        objective: Option<crate::target::Objective>,
        /// Short-list this many FE-verified candidates, verifying down the ranking
        /// (default: the target's `short_list`, else 8; 1 to 32).
        #[arg(long, allow_negative_numbers = true, value_parser = clap::value_parser!(u64).range(1..=32))]
        short_list: Option<u64>,
        /// With a wire grade: the beams per coil the converged FE check starts from
        /// (default 24). Refused with a calibration, whose E belongs to its mesh.
        #[arg(long, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(4..=512))]
        elements_per_coil: Option<u32>,
        /// Use this calibration.json (of `coil-tune calibrate`) as the material instead
        /// of the target's `material` (its grade, if any, still gives Rm).
        #[arg(long)]
        calibration: Option<PathBuf>,
        /// No figure.
        #[arg(long)]
        no_plots: bool,
    },
}

/// Runs the parsed command.
pub fn run(command: Command) -> Result<()> {
    match command {
        Command::Check {
            spring,
            json,
            out,
            elements_per_coil,
        } => check_command(&spring, json, out, elements_per_coil),
        Command::Design {
            target,
            out,
            objective,
            short_list,
            elements_per_coil,
            calibration,
            no_plots,
        } => {
            let path = target;
            let mut target = crate::target::read_target(&path)?;
            if let Some(file) = calibration {
                target.material = crate::target::with_calibration(&target.material, file);
            }
            let settings = crate::DesignSettings {
                objective,
                short_list: short_list.map(|n| n as usize),
                elements_per_coil,
            };
            let design = crate::design(&target, &settings).map_err(|e| match e {
                // A bound of the search or of the FE verification: say which file.
                crate::TuneError::Invalid(message) => {
                    crate::TuneError::Invalid(format!("{}: {message}", path.display()))
                }
                other => other,
            })?;
            let out = OutDir::create(out)?;
            crate::output::write(&design, &out, !no_plots)?;
            out.commit()?;
            text(&crate::output::summary(&design))?;
            say(&format!("design in {}", out.path("design.json").display()))?;
            Ok(())
        }
    }
}

/// `coil-tune check`: the EN 13906-1 sheet beside coil's FE values.
fn check_command(
    spring: &std::path::Path,
    json: bool,
    out: Option<PathBuf>,
    elements_per_coil: u32,
) -> Result<()> {
    let input = crate::sheet::input::read_spring(spring)?;
    let settings = coil_tuner::fe::FeSettings {
        elements_per_coil,
        ..Default::default()
    };
    let report = crate::sheet::check(&input, &settings).map_err(|e| match e {
        // The FE model's size limit: say which file.
        crate::TuneError::Invalid(message) => {
            crate::TuneError::Invalid(format!("{}: {message}", spring.display()))
        }
        other => other,
    })?;
    let json_text = report.json()?;
    let out = out.map(OutDir::create).transpose()?;
    if let Some(out) = &out {
        out.write("sheet.json", json_text.as_bytes())?;
        out.write("sheet.md", report.markdown(spring).as_bytes())?;
        out.commit()?;
    }
    if json {
        say(&json_text)?;
    } else {
        text(&report.table())?;
        if let Some(out) = &out {
            say(&format!("sheet in {}", out.path("sheet.md").display()))?;
        }
    }
    Ok(())
}
