//! The paper's commands of `coil-tune` (calibrate, sweep, tolerance, merge, paper, run):
//! their arguments and dispatch. The binary (the `coil-tune` crate) joins them with the
//! identification commands of `coil_ident::cli` and maps errors to the exit code.

use crate::calibrate::{calibrate, CalibrateSettings, Targets};
use crate::case::read_case;
use crate::damping::RunControl;
use crate::decay::Method;
use crate::error::Result;
use crate::output::OutDir;
use clap::{Args, Subcommand};
use coil_io::stdout::{line as stdout_line, text as stdout_text};
use std::path::PathBuf;

/// A failed write to stdout (other than a closed pipe, which is quiet).
fn stdout_error(e: std::io::Error) -> crate::TuneError {
    crate::TuneError::io("stdout", e)
}

/// Prints `s` as it is on stdout.
pub fn text(s: &str) -> Result<()> {
    stdout_text(s).map_err(stdout_error)
}

/// Prints `s` and a newline on stdout.
pub fn say(s: &str) -> Result<()> {
    stdout_line(s).map_err(stdout_error)
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

    /// How long grids may run.
    pub fn control(&self) -> RunControl {
        RunControl {
            max_new_points: self.max_points,
        }
    }
}

/// The sampling of a tolerance study (docs/scale-out.md).
#[derive(Debug, Args, Clone)]
pub struct ToleranceArgs {
    /// Samples per spring (the nominal spring is run on top, as sample 0).
    #[arg(long, default_value_t = 100)]
    pub samples: usize,
    /// Seed of the sampling.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// +- wire diameter (mm).
    #[arg(long, default_value_t = 0.03)]
    pub wire_tol: f64,
    /// EN 15800 grade of the coil diameter tolerance (1, 2 or 3).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(1..=3))]
    pub grade: u8,
    /// +- mean coil diameter (mm) instead of the EN 15800 table.
    #[arg(long)]
    pub coil_diameter_tol: Option<f64>,
    /// +- active coils.
    #[arg(long, default_value_t = 0.25)]
    pub coils_tol: f64,
    /// +- relative Young's modulus.
    #[arg(long, default_value_t = 0.02)]
    pub youngs_modulus_tol: f64,
    /// +- relative mass of the weight.
    #[arg(long, default_value_t = 0.001)]
    pub mass_tol: f64,
}

impl ToleranceArgs {
    /// The tolerances these flags give.
    pub fn tolerances(&self) -> crate::tolerance::Tolerances {
        crate::tolerance::Tolerances {
            wire_diameter_mm: self.wire_tol,
            coil_diameter_grade: self.grade,
            coil_diameter_mm: self.coil_diameter_tol,
            active_coils: self.coils_tol,
            youngs_modulus_relative: self.youngs_modulus_tol,
            mass_relative: self.mass_tol,
        }
    }
}

/// Where the validated material comes from (sweeps and tolerance studies).
#[derive(Debug, Args, Clone)]
pub struct MaterialArgs {
    /// Take E, mass, alpha and beta from a calibration.json (`calibrate`'s output)
    /// instead of calibrating first.
    #[arg(long, conflicts_with = "paper_material")]
    pub calibration: Option<PathBuf>,
    /// Use the paper's Table 2 (E, alpha, beta; the mass tuned to the period) instead.
    #[arg(long)]
    pub paper_material: bool,
}

#[derive(Debug, Subcommand)]
/// The commands of `coil-tune`.
pub enum Command {
    /// Loops 1-3 of the paper's Figure 6 on a case (folder or case.json).
    Calibrate {
        /// The measured case (a folder with case.json, or the file).
        case: PathBuf,
        /// Output folder for decks, logs, grids and figures.
        #[arg(long, default_value = "out/calibrate")]
        out: PathBuf,
        #[command(flatten)]
        /// Mesh, decay and loop settings.
        model: ModelArgs,
    },
    /// K and zeta of spring variants with the validated material (Table 4).
    Sweep {
        /// The measured case (a folder with case.json, or the file).
        case: PathBuf,
        /// The variants file (e.g. cases/160ect/table4.json).
        #[arg(long)]
        variants: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out/sweep")]
        out: PathBuf,
        #[command(flatten)]
        /// Where the validated material comes from.
        material: MaterialArgs,
        /// Run only shard I of N (round robin over the variants) and write
        /// DIR/part-IIII-of-NNNN.csv; `coil-tune merge` joins the parts.
        #[arg(long, value_name = "I/N")]
        shard: Option<crate::study::Shard>,
        #[command(flatten)]
        /// Mesh, decay and loop settings.
        model: ModelArgs,
    },
    /// K and zeta distributions of the variants as manufactured: each spring sampled
    /// within tolerances (wire and coil diameter, coils, E, mass), seeded
    /// (docs/scale-out.md).
    Tolerance {
        /// The measured case (a folder with case.json, or the file).
        case: PathBuf,
        /// The variants file (e.g. cases/160ect/table4.json).
        #[arg(long)]
        variants: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out/tolerance")]
        out: PathBuf,
        #[command(flatten)]
        /// The tolerances sampled.
        tolerance: ToleranceArgs,
        /// Run only shard I of N (round robin over the tasks) and write
        /// DIR/part-IIII-of-NNNN.csv; `coil-tune merge` joins the parts.
        #[arg(long, value_name = "I/N")]
        shard: Option<crate::study::Shard>,
        /// No figure.
        #[arg(long)]
        no_plots: bool,
        #[command(flatten)]
        /// Where the validated material comes from.
        material: MaterialArgs,
        #[command(flatten)]
        /// Mesh, decay and loop settings.
        model: ModelArgs,
    },
    /// Join the parts of a sharded `sweep` or `tolerance` into the table a single run
    /// writes; refuses missing or repeated shards and parts of another study.
    Merge {
        /// Part files, or folders holding part-*.csv.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Output folder.
        #[arg(long, default_value = "out/merge")]
        out: PathBuf,
        /// No figure (tolerance studies).
        #[arg(long)]
        no_plots: bool,
        /// No progress messages (accepted by every command; merge prints none).
        #[arg(long, short)]
        quiet: bool,
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
        /// Mesh, decay and loop settings.
        model: ModelArgs,
    },
    /// Run a procedure file (docs/procedures.md), e.g. cases/160ect/figure6.proc.
    Run {
        /// The procedure file.
        procedure: PathBuf,
        /// Output folder (overrides the file's `out`; default `out/<procedure name>`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Only parse and check the file.
        #[arg(long)]
        dry_run: bool,
        /// Stop each grid after this many new points (the journal keeps them).
        #[arg(long)]
        max_points: Option<usize>,
        /// No progress messages (accepted by every command; procedures print their
        /// own lines on stdout, unchanged).
        #[arg(long, short)]
        quiet: bool,
    },
}

/// Runs the parsed command.
pub fn run(command: Command) -> Result<()> {
    match command {
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
            material,
            shard,
            model,
        } => sweep_command(case, variants, out, material, shard, model),
        Command::Tolerance {
            case,
            variants,
            out,
            tolerance,
            shard,
            no_plots,
            material,
            model,
        } => tolerance_command(
            case, variants, out, tolerance, shard, no_plots, material, model,
        ),
        Command::Merge {
            parts,
            out,
            no_plots,
            quiet: _,
        } => {
            let files = crate::study::part_files(&parts)?;
            let merged = crate::study::merge(&files)?;
            let out = OutDir::create(out)?;
            let summary = write_table(&merged, &out, !no_plots)?;
            out.commit()?;
            text(&summary)?;
            say!(
                "{} parts, {} tasks: {}",
                files.len(),
                merged.records.len(),
                out.path(merged.study.table_file()).display()
            )?;
            Ok(())
        }
        Command::Paper {
            out,
            case,
            variants,
            model,
        } => paper_command(out, case, variants, model),
        Command::Run {
            procedure,
            out,
            dry_run,
            max_points,
            quiet: _,
        } => procedure_command(procedure, out, dry_run, max_points),
    }
}

/// `coil-tune sweep`: Table 4's variants with the validated material (or one shard of them).
fn sweep_command(
    case: PathBuf,
    variants: PathBuf,
    out: PathBuf,
    material: MaterialArgs,
    shard: Option<crate::study::Shard>,
    model: ModelArgs,
) -> Result<()> {
    if let Some(shard) = shard {
        // A shard writes one part file into a folder shared by concurrent shards:
        // no output set (its lock would refuse the other shards), one atomic file.
        let sweep = sweep_study(&case, &variants, &material, &model, None, Some(shard))?;
        let study = crate::study::Study::Sweep(sweep);
        let path = crate::study::run_shard(&study, shard, &out)?;
        say!("shard {shard}: {}", path.display())?;
        return Ok(());
    }
    let out = OutDir::create(out)?;
    let sweep = sweep_study(&case, &variants, &material, &model, Some(&out), None)?;
    let state = sweep.material;
    let variants = crate::case::VariantsFile {
        file: variants,
        source: None,
        variants: sweep.variants.clone(),
    };
    let (settings, decay) = (&sweep.fe, &sweep.decay);
    let result = crate::sweep::sweep(&state, &variants, settings, decay)?;
    out.write("sweep.csv", result.csv().as_bytes())?;
    let json = serde_json::to_string_pretty(&result)
        .map_err(|e| crate::TuneError::Invalid(format!("sweep.json: {e}")))?;
    out.write("sweep.json", json.as_bytes())?;
    out.commit()?;
    say!(
        "material: E = {:.1} MPa, mass = {:.5} kg, alpha = {:.4} 1/s, beta = {:.4e} s",
        state.youngs_modulus_mpa,
        state.mass_kg,
        state.alpha,
        state.beta
    )?;
    text(&result.table())?;
    say!("files in {}", out.root().display())?;
    Ok(())
}

/// `coil-tune tolerance`: springs sampled within their tolerances (or one shard of them).
#[allow(clippy::too_many_arguments)]
fn tolerance_command(
    case: PathBuf,
    variants: PathBuf,
    out: PathBuf,
    tolerance: ToleranceArgs,
    shard: Option<crate::study::Shard>,
    no_plots: bool,
    material: MaterialArgs,
    model: ModelArgs,
) -> Result<()> {
    if let Some(shard) = shard {
        let study = crate::study::Study::Tolerance(tolerance_study(
            &case,
            &variants,
            &tolerance,
            &material,
            &model,
            None,
            Some(shard),
        )?);
        let clock = std::time::Instant::now();
        let path = crate::study::run_shard(&study, shard, &out)?;
        say!(
            "shard {shard}: {} of {} tasks in {:.2} s: {}",
            shard.tasks(study.tasks()).len(),
            study.tasks(),
            clock.elapsed().as_secs_f64(),
            path.display()
        )?;
        return Ok(());
    }
    let out = OutDir::create(out)?;
    let study = crate::study::Study::Tolerance(tolerance_study(
        &case,
        &variants,
        &tolerance,
        &material,
        &model,
        Some(&out),
        None,
    )?);
    let clock = std::time::Instant::now();
    let rows = study.run_all()?;
    let elapsed = clock.elapsed().as_secs_f64();
    let merged = crate::study::Merged::of_cells(study, &rows);
    let summary = write_table(&merged, &out, !no_plots)?;
    out.commit()?;
    text(&summary)?;
    say!(
        "{} tasks in {elapsed:.2} s ({:.2} tasks/s); files in {}",
        merged.records.len(),
        merged.records.len() as f64 / elapsed,
        out.root().display()
    )?;
    Ok(())
}

/// `coil-tune paper`: the README's main job, Tables 3 and 4 printed beside the paper's.
fn paper_command(out: PathBuf, case: PathBuf, variants: PathBuf, model: ModelArgs) -> Result<()> {
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

/// `coil-tune run`: a procedure file, parsed and checked, then run (or only checked).
fn procedure_command(
    procedure: PathBuf,
    out: Option<PathBuf>,
    dry_run: bool,
    max_points: Option<usize>,
) -> Result<()> {
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

impl MaterialArgs {
    /// The validated material: from a calibration.json, the paper's Table 2, or a
    /// calibration run first (not with `--shard`: every shard would calibrate into the
    /// same folder).
    pub fn state(
        &self,
        case: &crate::case::MeasuredCase,
        settings: &CalibrateSettings,
        model: &ModelArgs,
        out: Option<&OutDir>,
        shard: Option<crate::study::Shard>,
    ) -> Result<crate::fe::SpringState> {
        if let Some(file) = &self.calibration {
            read_calibrated_state(file)
        } else if self.paper_material {
            crate::sweep::paper_material(case, settings)
        } else if let (Some(out), None) = (out, shard) {
            let targets = Targets::of(case)?;
            let sub = out.sub("calibration")?;
            let result = calibrate(case, &targets, settings, Some(&sub), &model.control())?;
            text(&result.summary())?;
            Ok(result.state)
        } else {
            Err(crate::TuneError::Invalid(
                "--shard needs the material fixed before the split: give --calibration calibration.json (from `coil-tune calibrate`) or --paper-material".into(),
            ))
        }
    }
}

/// The variants of `variants` with the validated material of `case` (as the flags say; a
/// calibration run writes into `out/calibration`) and the settings' decay, and whether
/// the flags ask for direct integration of the tables (`--no-check` not given).
fn validated_variants(
    case: &std::path::Path,
    variants: &std::path::Path,
    material: &MaterialArgs,
    model: &ModelArgs,
    out: Option<&OutDir>,
    shard: Option<crate::study::Shard>,
) -> Result<(crate::study::VariantSweep, bool)> {
    let case = read_case(case)?;
    let variants = crate::case::read_variants(variants)?;
    let settings = model.settings();
    let state = material.state(&case, &settings, model, out, shard)?;
    let sweep = crate::study::VariantSweep {
        material: state,
        variants: variants.variants,
        fe: settings.fe,
        decay: settings.damping.decay,
    };
    Ok((sweep, settings.damping.check_direct))
}

/// The sweep study of `variants` on `case`: the table by direct integration unless
/// `--no-check`.
pub fn sweep_study(
    case: &std::path::Path,
    variants: &std::path::Path,
    material: &MaterialArgs,
    model: &ModelArgs,
    out: Option<&OutDir>,
    shard: Option<crate::study::Shard>,
) -> Result<crate::study::VariantSweep> {
    let (mut sweep, direct) = validated_variants(case, variants, material, model, out, shard)?;
    if direct {
        sweep.decay.method = crate::decay::Method::Direct;
    }
    Ok(sweep)
}

/// The tolerance study of `variants` on `case` (zeta by `--method`, modal by default).
pub fn tolerance_study(
    case: &std::path::Path,
    variants: &std::path::Path,
    tolerance: &ToleranceArgs,
    material: &MaterialArgs,
    model: &ModelArgs,
    out: Option<&OutDir>,
    shard: Option<crate::study::Shard>,
) -> Result<crate::tolerance::ToleranceStudy> {
    let (sweep, _) = validated_variants(case, variants, material, model, out, shard)?;
    let study = crate::tolerance::ToleranceStudy {
        sweep,
        tolerances: tolerance.tolerances(),
        samples: tolerance.samples,
        seed: tolerance.seed,
    };
    study.check()?;
    Ok(study)
}

/// Writes a study's table as a single run does (and, for a tolerance study, its summary,
/// report and figure); returns the text for the terminal.
pub fn write_table(merged: &crate::study::Merged, out: &OutDir, plots: bool) -> Result<String> {
    match &merged.study {
        crate::study::Study::Tolerance(t) => {
            let summary = crate::tolerance::summarize(t, merged.rows())?;
            stage_table(merged, out)?;
            crate::tolerance::write(&summary, out, plots)?;
            Ok(summary.table())
        }
        crate::study::Study::Sweep(_) => {
            stage_table(merged, out)?;
            Ok(String::new())
        }
    }
}

/// Stages the study's table file, streamed record by record (no second copy of the
/// table in memory).
pub fn stage_table(merged: &crate::study::Merged, out: &OutDir) -> Result<()> {
    out.produce(merged.study.table_file(), |path| {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|e| crate::TuneError::io(path, e))?;
        let mut w = std::io::BufWriter::new(file);
        merged
            .write_csv(&mut w)
            .and_then(|()| std::io::Write::flush(&mut w))
            .and_then(|()| w.get_ref().sync_all())
            .map_err(|e| crate::TuneError::io(path, e))
    })?;
    Ok(())
}

/// The `state` of a calibration.json.
fn read_calibrated_state(path: &std::path::Path) -> Result<crate::fe::SpringState> {
    let text = std::fs::read_to_string(path).map_err(|e| crate::TuneError::io(path, e))?;
    #[derive(serde::Deserialize)]
    struct File {
        state: crate::fe::SpringState,
    }
    let file: File = serde_json::from_str(&text).map_err(|e| crate::TuneError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!(
            "{e}; expected a calibration.json written by `coil-tune calibrate` (with a `state`)"
        ),
    })?;
    Ok(file.state)
}
