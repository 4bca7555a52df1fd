//! coil-python owns the Python binding (`import coil`): argument parsing, the GIL guard, JSON
//! results, no numerics. It may import every library crate (coil-io up to coil-ident,
//! coil-design and coil-catenary); nothing imports it.
//!
//! `coil._coil`: the native half of the Python package (python/coil/__init__.py is the
//! other). A thin layer: every function parses its arguments, calls one library function
//! of coil-mesher, coil-solver, coil-postproc, coil-tuner or coil-ident, and returns its result as
//! JSON text with the names and units of the JSON files the binaries write (the Python
//! side turns it into dicts and numpy arrays). No numerics here.
//!
//! Every function's body runs through one guard, [`guarded`] (new functions use it too):
//! - the work runs on a worker thread with the GIL released, so Dask's threads and the
//!   library's own thread pool run beside the interpreter;
//! - the calling thread wakes every [`POLL`] (50 ms) to let Python handle its signals: a
//!   Ctrl-C (SIGINT) sets `coil_io::cancel`, which every long loop checks on its
//!   progress path (every 64 time steps), and the output set refuses to commit, so the
//!   call raises `KeyboardInterrupt` within a second and the output folder is as it was;
//! - a panic inside is caught (`catch_unwind`) and raised as `CoilError` naming it as
//!   coil's bug, never as pyo3's `PanicException` (a `BaseException`); sizes are checked
//!   before allocating (the same limits as the command line), so an allocation failure,
//!   which aborts the process, is not reached from these calls;
//! - messages are `coil.CoilError` with the library's text (file, line, field and what
//!   was expected), control characters escaped and cut below 1 KB
//!   (`coil_io::clean_message`).
#![warn(missing_docs)]

use coil_tuner::cli::{self, MaterialArgs, ModelArgs, ToleranceArgs};
use coil_tuner::output::OutDir;
use coil_tuner::study::{self, Cell, Shard, Study};
use pyo3::create_exception;
use pyo3::prelude::*;
use std::path::PathBuf;

create_exception!(
    coil,
    CoilError,
    pyo3::exceptions::PyException,
    "An error in coil's input data or in a run; the message names the file, line and what was expected."
);

fn fail(error: impl std::fmt::Display) -> PyErr {
    CoilError::new_err(coil_io::clean_message(&error.to_string()))
}

/// How often the calling thread looks for a pending signal while the work runs.
const POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// The worker's stack: deep enough for the solver's recursion-free kernels with margin.
const WORKER_STACK_BYTES: usize = 64 << 20;

/// Runs `work` (plain Rust values only: no Python object) as the module doc says: on a
/// worker thread without the GIL, Ctrl-C honoured within a poll and the stop of the
/// longest loop (every 64 time steps), panics turned into `CoilError`.
pub(crate) fn guarded<T, F>(py: Python<'_>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> PyResult<T> + Send,
{
    let (done, finished) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        let worker = std::thread::Builder::new()
            .name("coil".into())
            .stack_size(WORKER_STACK_BYTES)
            .spawn_scoped(scope, move || {
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
                let _ = done.send(());
                result
            })
            .map_err(|e| fail(format!("cannot start coil's worker thread: {e}")))?;
        // A Mutex makes the receiver shareable with the GIL-free closure (never contended).
        let finished = std::sync::Mutex::new(finished);
        let mut interrupted = None;
        loop {
            let waited = py.detach(|| {
                let finished = finished.lock().unwrap_or_else(|p| p.into_inner());
                finished.recv_timeout(POLL)
            });
            if !matches!(waited, Err(std::sync::mpsc::RecvTimeoutError::Timeout)) {
                break;
            }
            if interrupted.is_none() {
                if let Err(signal) = py.check_signals() {
                    coil_io::cancel::request();
                    interrupted = Some(signal);
                }
            }
        }
        let outcome = worker.join();
        if let Some(signal) = interrupted {
            coil_io::cancel::clear();
            return Err(signal);
        }
        match outcome {
            Ok(Ok(result)) => result,
            Ok(Err(panic)) | Err(panic) => {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "a panic".into());
                Err(fail(format!(
                    "internal error in coil (a bug: please report it with the call that caused it): {what}"
                )))
            }
        }
    })
}

fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(fail)
}

/// The deck text of a spring spec given as JSON (the fields of `coil-mesh --spec`).
#[pyfunction]
fn mesh(py: Python<'_>, spec_json: &str) -> PyResult<String> {
    guarded(py, || {
        let spec: coil_mesher::SpringSpec = serde_json::from_str(spec_json).map_err(|e| {
            fail(format!(
                "spring spec: {e}; expected the fields of a spring spec (docs/mesher.md)"
            ))
        })?;
        let model = spec.build().map_err(fail)?;
        Ok(coil_solver::deck::write(&model))
    })
}

/// Checks a deck (its text, or the path of its file): its title and counts.
#[pyfunction]
#[pyo3(signature = (text=None, path=None))]
fn read_deck(py: Python<'_>, text: Option<String>, path: Option<PathBuf>) -> PyResult<String> {
    guarded(py, || {
        let model = read_model(text.as_deref(), path.as_deref())?;
        json(&serde_json::json!({
            "title": model.title(),
            "nodes": model.nodes().len(),
            "elements": model.elements().len(),
            "load_cases": model.load_cases().len(),
        }))
    })
}

/// The model of a deck's text or file: a path that does not exist is an error naming
/// it, never read as deck text.
fn read_model(
    text: Option<&str>,
    path: Option<&std::path::Path>,
) -> PyResult<coil_solver::model::Model> {
    match (text, path) {
        (Some(text), None) => coil_solver::deck::read_str(text, "<deck text>").map_err(fail),
        (None, Some(path)) => {
            if !path.exists() {
                return Err(fail(format!(
                    "{}: no such deck file; expected the path of a deck (or the deck's text, which has several lines)",
                    path.display()
                )));
            }
            coil_solver::deck::read_file(path).map_err(fail)
        }
        _ => Err(fail("give a deck's text or its path, not both")),
    }
}

/// Runs a deck's load cases as `coil-solve` does and writes its files into `out` (a
/// temporary folder when None) as one output set. Returns results.json's content, each
/// transient case with a `history` object: `time_s` and every column by its name. A
/// transient above the command line's limit is refused unless `allow_large`
/// (`coil-solve --allow-large`).
#[pyfunction]
#[pyo3(signature = (text=None, path=None, out=None, allow_large=false))]
fn solve(
    py: Python<'_>,
    text: Option<String>,
    path: Option<PathBuf>,
    out: Option<PathBuf>,
    allow_large: bool,
) -> PyResult<String> {
    guarded(py, || {
        let model = read_model(text.as_deref(), path.as_deref())?;
        let options = coil_solver::analysis::transient::RunOptions {
            progress: false,
            allow_large: Some(allow_large),
        };
        let cases = coil_solver::analysis::run_with(&model, &options).map_err(fail)?;
        let temp = tempfile::tempdir().map_err(fail)?;
        let dir = out.unwrap_or_else(|| temp.path().join("out"));
        let file = coil_solver::results::write_all(&dir, &model, &cases).map_err(fail)?;
        let mut value = serde_json::to_value(&file).map_err(fail)?;
        if let Some(entries) = value["load_cases"].as_array_mut() {
            for (entry, case) in entries.iter_mut().zip(&cases) {
                if let coil_solver::analysis::CaseSolution::Transient(t) = &case.solution {
                    let mut history = serde_json::Map::new();
                    history.insert("time_s".into(), serde_json::json!(t.history.time_s));
                    for c in &t.history.columns {
                        history.insert(c.name.clone(), serde_json::json!(c.values));
                    }
                    entry["history"] = serde_json::Value::Object(history);
                }
            }
        }
        json(&value)
    })
}

/// The paper's logarithmic decrement of a record (coil-post decrement).
#[pyfunction]
#[pyo3(signature = (time_s, values, every=10, lowpass_hz=None))]
fn decrement(
    py: Python<'_>,
    time_s: Vec<f64>,
    values: Vec<f64>,
    every: usize,
    lowpass_hz: Option<f64>,
) -> PyResult<String> {
    guarded(py, || {
        let options = coil_postproc::decrement::DecrementOptions {
            every,
            lowpass: lowpass_hz.map(|cutoff_hz| coil_postproc::decrement::Lowpass {
                cutoff_hz,
                order: 4,
            }),
            ..Default::default()
        };
        let signal = coil_postproc::signal::Signal::new(time_s, values).map_err(fail)?;
        let report = coil_postproc::decrement::analyze(&signal, &options).map_err(fail)?;
        json(&report)
    })
}

/// Draws a time history into a PNG or SVG with coil-post's renderer (`coil-post plot`).
/// The series is checked as a record is (`coil_postproc::signal::Signal`: equal
/// lengths, finite values, time increasing); the label is one printable line.
#[pyfunction]
fn plot_history(
    py: Python<'_>,
    time_s: Vec<f64>,
    values: Vec<f64>,
    label: String,
    column: String,
    path: PathBuf,
) -> PyResult<()> {
    guarded(py, || {
        if label.chars().any(char::is_control) || label.chars().count() > 200 {
            return Err(fail(format!(
                "label `{label}`; expected one printable line of at most 200 characters"
            )));
        }
        let signal = coil_postproc::signal::Signal::new(time_s, values).map_err(fail)?;
        let trace = coil_postproc::plot::Trace {
            label: &label,
            unit: coil_postproc::plot::unit_of(&column),
            time_s: signal.time_s(),
            values: signal.values(),
        };
        coil_postproc::plot::time_histories(&[trace], false, &path).map_err(fail)
    })
}

fn model_args(elements_per_coil: u32, method: &str, check: bool) -> PyResult<ModelArgs> {
    Ok(ModelArgs {
        elements_per_coil,
        method: method
            .parse()
            .map_err(|e: String| fail(format!("method {e}")))?,
        no_check: !check,
        max_points: None,
        grids: Vec::new(),
        quiet: true,
    })
}

/// Loops 1-3 of the paper's Figure 6 on a case (`coil-tune calibrate`): calibration.json's
/// content; the files go to `out`.
#[pyfunction]
#[pyo3(signature = (case, out, elements_per_coil=24, method="modal", check=true))]
fn calibrate(
    py: Python<'_>,
    case: PathBuf,
    out: PathBuf,
    elements_per_coil: u32,
    method: &str,
    check: bool,
) -> PyResult<String> {
    let model = model_args(elements_per_coil, method, check)?;
    guarded(py, || {
        let case = coil_tuner::case::read_case(&case).map_err(fail)?;
        let targets = coil_tuner::calibrate::Targets::of(&case).map_err(fail)?;
        let out = OutDir::create(out).map_err(fail)?;
        let result = coil_tuner::calibrate::calibrate(
            &case,
            &targets,
            &model.settings(),
            Some(&out),
            &model.control(),
        )
        .map_err(fail)?;
        out.commit().map_err(fail)?;
        json(&result)
    })
}

fn material(calibration: Option<PathBuf>, paper_material: bool) -> MaterialArgs {
    MaterialArgs {
        calibration,
        paper_material,
    }
}

/// The study (as JSON) of `coil-tune sweep` with these flags.
#[pyfunction]
#[pyo3(signature = (case, variants, out, calibration=None, paper_material=false, elements_per_coil=24, method="modal", check=true))]
#[allow(clippy::too_many_arguments)]
fn sweep_study(
    py: Python<'_>,
    case: PathBuf,
    variants: PathBuf,
    out: PathBuf,
    calibration: Option<PathBuf>,
    paper_material: bool,
    elements_per_coil: u32,
    method: &str,
    check: bool,
) -> PyResult<String> {
    let model = model_args(elements_per_coil, method, check)?;
    guarded(py, || {
        let out = OutDir::create(out).map_err(fail)?;
        let sweep = cli::sweep_study(
            &case,
            &variants,
            &material(calibration, paper_material),
            &model,
            Some(&out),
            None,
        )
        .map_err(fail)?;
        out.commit().map_err(fail)?;
        Ok(Study::Sweep(sweep).to_json())
    })
}

/// The study (as JSON) of `coil-tune tolerance` with these flags.
#[pyfunction]
#[pyo3(signature = (case, variants, out, samples=100, seed=1, wire_tol=0.03, grade=2, coil_diameter_tol=None, coils_tol=0.25, youngs_modulus_tol=0.02, mass_tol=0.001, calibration=None, paper_material=false, elements_per_coil=24, method="modal"))]
#[allow(clippy::too_many_arguments)]
fn tolerance_study(
    py: Python<'_>,
    case: PathBuf,
    variants: PathBuf,
    out: PathBuf,
    samples: usize,
    seed: u64,
    wire_tol: f64,
    grade: u8,
    coil_diameter_tol: Option<f64>,
    coils_tol: f64,
    youngs_modulus_tol: f64,
    mass_tol: f64,
    calibration: Option<PathBuf>,
    paper_material: bool,
    elements_per_coil: u32,
    method: &str,
) -> PyResult<String> {
    let model = model_args(elements_per_coil, method, false)?;
    if !(1..=3).contains(&grade) {
        return Err(fail(format!(
            "grade {grade}; expected 1, 2 or 3 (EN 15800)"
        )));
    }
    let tolerance = ToleranceArgs {
        samples,
        seed,
        wire_tol,
        grade,
        coil_diameter_tol,
        coils_tol,
        youngs_modulus_tol,
        mass_tol,
    };
    guarded(py, || {
        let out = OutDir::create(out).map_err(fail)?;
        let study = cli::tolerance_study(
            &case,
            &variants,
            &tolerance,
            &material(calibration, paper_material),
            &model,
            Some(&out),
            None,
        )
        .map_err(fail)?;
        out.commit().map_err(fail)?;
        Ok(Study::Tolerance(study).to_json())
    })
}

fn parse_study(study_json: &str) -> PyResult<Study> {
    Study::from_json(study_json, "study").map_err(fail)
}

/// The study's kind, task count and columns, as JSON.
#[pyfunction]
fn study_info(py: Python<'_>, study_json: &str) -> PyResult<String> {
    guarded(py, || {
        let study = parse_study(study_json)?;
        json(&serde_json::json!({
            "kind": study.kind(),
            "tasks": study.tasks(),
            "columns": study.columns(),
            "table_file": study.table_file(),
        }))
    })
}

fn cell_json(cell: &Cell) -> serde_json::Value {
    match cell {
        Cell::Text(s) => serde_json::json!(s),
        Cell::Number(x) => serde_json::json!(x),
        Cell::Missing => serde_json::Value::Null,
    }
}

/// Runs the given tasks of a study (in this process's thread pool): their rows, as JSON.
#[pyfunction]
fn run_tasks(py: Python<'_>, study_json: &str, tasks: Vec<usize>) -> PyResult<String> {
    guarded(py, || {
        let study = parse_study(study_json)?;
        let rows = study.run_tasks(&tasks).map_err(fail)?;
        let rows: Vec<Vec<serde_json::Value>> = rows
            .iter()
            .map(|row| row.iter().map(cell_json).collect())
            .collect();
        json(&rows)
    })
}

fn cell_rows(rows_json: &str) -> PyResult<Vec<Vec<Cell>>> {
    let rows: Vec<Vec<serde_json::Value>> = serde_json::from_str(rows_json).map_err(|e| {
        fail(format!(
            "rows: {e}; expected a JSON list of rows of finite numbers, strings and nulls"
        ))
    })?;
    Ok(rows
        .iter()
        .map(|row| {
            row.iter()
                .map(|v| match v {
                    serde_json::Value::String(s) => Cell::Text(s.clone()),
                    serde_json::Value::Number(n) => n.as_f64().map_or(Cell::Missing, Cell::Number),
                    _ => Cell::Missing,
                })
                .collect()
        })
        .collect())
}

/// Writes a study's table (rows in task order, as JSON) into `out` as a single run of
/// `coil-tune` does: the CSV and, for a tolerance study, the summary, report and figure.
/// Every row is checked as `merge` checks a part's ([`Study::check_row`]). Returns the
/// tolerance summary as JSON (null for a sweep).
#[pyfunction]
#[pyo3(signature = (study_json, rows_json, out, plots=true))]
fn write_table(
    py: Python<'_>,
    study_json: &str,
    rows_json: &str,
    out: PathBuf,
    plots: bool,
) -> PyResult<String> {
    guarded(py, || {
        let study = parse_study(study_json)?;
        let rows = cell_rows(rows_json)?;
        if rows.len() != study.tasks() {
            return Err(fail(format!(
                "{} rows; the study has {} tasks (one row each, in task order)",
                rows.len(),
                study.tasks()
            )));
        }
        for (k, row) in rows.iter().enumerate() {
            let cells: Vec<String> = row.iter().map(Cell::csv).collect();
            study
                .check_row(k, &cells)
                .map_err(|e| fail(format!("row {k}: {e}")))?;
        }
        let merged = study::Merged::of_cells(study, &rows);
        let out = OutDir::create(out).map_err(fail)?;
        cli::write_table(&merged, &out, plots).map_err(fail)?;
        out.commit().map_err(fail)?;
        match &merged.study {
            Study::Tolerance(t) => {
                json(&coil_tuner::tolerance::summarize(t, merged.rows()).map_err(fail)?)
            }
            Study::Sweep(_) => Ok("null".into()),
        }
    })
}

/// Runs shard `shard` ("I/N") of a study and writes its part into `out`; the part's path.
#[pyfunction]
fn run_shard(py: Python<'_>, study_json: &str, shard: &str, out: PathBuf) -> PyResult<String> {
    guarded(py, || {
        let study = parse_study(study_json)?;
        let shard: Shard = shard
            .parse()
            .map_err(|e: String| fail(format!("shard {e}")))?;
        let path = study::run_shard(&study, shard, &out).map_err(fail)?;
        Ok(path.display().to_string())
    })
}

/// Merges part files (or folders of them) into `out` as `coil-tune merge` does; the
/// merged table's path.
#[pyfunction]
#[pyo3(signature = (parts, out, plots=true))]
fn merge(py: Python<'_>, parts: Vec<PathBuf>, out: PathBuf, plots: bool) -> PyResult<String> {
    guarded(py, || {
        let files = study::part_files(&parts).map_err(fail)?;
        let merged = study::merge(&files).map_err(fail)?;
        let out = OutDir::create(out).map_err(fail)?;
        cli::write_table(&merged, &out, plots).map_err(fail)?;
        out.commit().map_err(fail)?;
        Ok(out.path(merged.study.table_file()).display().to_string())
    })
}

/// The most fixed-interface modes `diagnose` keeps (`coil-tune diagnose --modes`).
const MAX_DIAGNOSE_MODES: usize = 50;

/// Diagnoses a measured case (`coil-tune diagnose`), writes its files into `out` and
/// returns diagnosis.json's content. `modes` obeys the command line's range (0 to 50).
#[pyfunction]
#[pyo3(signature = (case, out, elements_per_coil=24, modes=4, plots=true))]
fn diagnose(
    py: Python<'_>,
    case: PathBuf,
    out: PathBuf,
    elements_per_coil: u32,
    modes: usize,
    plots: bool,
) -> PyResult<String> {
    if modes > MAX_DIAGNOSE_MODES {
        return Err(fail(format!(
            "modes {modes}; expected 0 to {MAX_DIAGNOSE_MODES} (as `coil-tune diagnose --modes`)"
        )));
    }
    guarded(py, || {
        // A case with forced records (`records.forced`) is diagnosed as the command line
        // does it: the lumped or spring model under the measured input (docs/forced.md).
        if coil_ident::forced::lists_forced(&case).map_err(fail)? {
            let settings = coil_ident::forced::ForcedSettings {
                plots,
                progress: false,
                ..Default::default()
            };
            let outcome = coil_ident::forced::diagnose_forced(&case, &settings).map_err(fail)?;
            let dir = OutDir::create(&out).map_err(fail)?;
            coil_ident::forced::report::write(&outcome, &dir, plots).map_err(fail)?;
            let path = out.join("diagnosis.json");
            return std::fs::read_to_string(&path)
                .map_err(|e| fail(format!("{}: {e}", path.display())));
        }
        let mut settings = coil_ident::diagnose::DiagnoseSettings::default();
        settings.fe.elements_per_coil = elements_per_coil;
        settings.modes = modes;
        settings.plots = plots;
        let dir = OutDir::create(&out).map_err(fail)?;
        let outcome = coil_ident::diagnose::diagnose(&case, &settings).map_err(fail)?;
        coil_ident::diagnose::write(&outcome, &dir, &settings).map_err(fail)?;
        let path = out.join("diagnosis.json");
        std::fs::read_to_string(&path).map_err(|e| fail(format!("{}: {e}", path.display())))
    })
}

/// Drives a forced diagnosis's model (model.json) with a record's input from the state
/// fitted to its first `init` outputs (`coil-tune simulate`, docs/forced.md). Writes
/// simulated.csv into `out` when given; returns `{"time_s", "output", "initial_state"}`
/// as JSON. Everything is read and computed before `out` is touched.
#[pyfunction]
#[pyo3(signature = (model, record, input, output, init, time=String::from("time_s"), out=None))]
#[allow(clippy::too_many_arguments)]
fn simulate(
    py: Python<'_>,
    model: PathBuf,
    record: PathBuf,
    input: String,
    output: String,
    init: usize,
    time: String,
    out: Option<PathBuf>,
) -> PyResult<String> {
    use coil_ident::forced::commands::{
        read_model, simulate_record, write_simulated, SimulateRequest,
    };
    guarded(py, || {
        let model = read_model(&model).map_err(fail)?;
        let request = SimulateRequest {
            record,
            time,
            input,
            output,
            init,
        };
        let sim = simulate_record(&model, &request).map_err(fail)?;
        if let Some(out) = out {
            write_simulated(&sim, &OutDir::create(&out).map_err(fail)?).map_err(fail)?;
        }
        json(&serde_json::json!({
            "time_s": sim.time_s,
            "output": sim.output,
            "initial_state": [sim.initial.0, sim.initial.1],
        }))
    })
}

/// The forced response curve of a forced diagnosis's model under a harmonic input of
/// `amplitude` from `from_hz` to `to_hz` (`coil-tune frc`, docs/forced.md): harmonic
/// balance through the folds, each point's stability by Floquet, and the backbone.
/// Writes frc.csv and backbone.csv into `out` when given; returns the curve, the
/// backbone and the folds (`jumps_hz`) as JSON.
#[pyfunction]
#[pyo3(signature = (model, amplitude, from_hz, to_hz, points=400, harmonics=7, out=None))]
#[allow(clippy::too_many_arguments)]
fn frc(
    py: Python<'_>,
    model: PathBuf,
    amplitude: f64,
    from_hz: f64,
    to_hz: f64,
    points: usize,
    harmonics: usize,
    out: Option<PathBuf>,
) -> PyResult<String> {
    use coil_ident::forced::commands::{frc_of, read_model, write_frc};
    guarded(py, || {
        let model = read_model(&model).map_err(fail)?;
        let settings = coil_ident::forced::frc::FrcSettings {
            amplitude,
            from_hz,
            to_hz,
            points,
            harmonics,
        };
        let result = frc_of(&model, &settings).map_err(fail)?;
        if let Some(out) = out {
            write_frc(&result, &OutDir::create(&out).map_err(fail)?).map_err(fail)?;
        }
        let curve = &result.points;
        let backbone = &result.backbone;
        json(&serde_json::json!({
            "curve": {
                "frequency_hz": curve.iter().map(|p| p.frequency_hz).collect::<Vec<_>>(),
                "amplitude": curve.iter().map(|p| p.amplitude).collect::<Vec<_>>(),
                "stable": curve.iter().map(|p| p.stable).collect::<Vec<_>>(),
            },
            "backbone": {
                "frequency_hz": backbone.iter().map(|p| p.frequency_hz).collect::<Vec<_>>(),
                "amplitude": backbone.iter().map(|p| p.amplitude).collect::<Vec<_>>(),
                "peak_displacement": backbone.iter().map(|p| p.peak_displacement).collect::<Vec<_>>(),
            },
            "jumps_hz": result.jumps,
        }))
    })
}

/// A pantograph-catenary case (`coil-tune catenary`, docs/catenary.md): writes its files
/// into `out` and returns catenary.json's content, or study.json's for a spring study
/// (`springs` given).
#[pyfunction]
#[pyo3(signature = (case, out, springs=Vec::new(), plots=true, damping=None, mass_share=true, reduced=false, allow_supercritical=false, speeds=None))]
#[allow(clippy::too_many_arguments)]
fn catenary(
    py: Python<'_>,
    case: PathBuf,
    out: PathBuf,
    springs: Vec<PathBuf>,
    plots: bool,
    damping: Option<String>,
    mass_share: bool,
    reduced: bool,
    allow_supercritical: bool,
    speeds: Option<Vec<f64>>,
) -> PyResult<String> {
    use coil_catenary::cli::{execute, DampingArg, Done, Request};
    let damping = match damping.as_deref() {
        None => None,
        Some("rayleigh") => Some(DampingArg::Rayleigh),
        Some("zeta_low") => Some(DampingArg::ZetaLow),
        Some("zeta_mid") => Some(DampingArg::ZetaMid),
        Some("zeta_high") => Some(DampingArg::ZetaHigh),
        Some(other) => {
            return Err(fail(format!(
                "damping `{other}`; expected rayleigh, zeta_low, zeta_mid or zeta_high"
            )))
        }
    };
    guarded(py, || {
        let request = Request {
            case,
            out: out.clone(),
            plots,
            progress: false,
            springs,
            damping,
            no_mass_share: !mass_share,
            reduced,
            springs_in_parallel: None,
            options: coil_catenary::case::CaseOptions {
                allow_supercritical,
                allow_large: false,
                speeds_km_h: speeds,
            },
        };
        let name = match execute(&request, &|_| Ok(())).map_err(fail)? {
            Done::Case(_) => "catenary.json",
            Done::Study(_) => "study.json",
        };
        let path = out.join(name);
        std::fs::read_to_string(&path).map_err(|e| fail(format!("{}: {e}", path.display())))
    })
}

/// The EN 13906-1 sheet of a SPRING.json beside coil's FE values on the same spring
/// (`coil-tune check --json`): returns the report's JSON.
#[pyfunction]
#[pyo3(signature = (spring, elements_per_coil=24))]
fn check(py: Python<'_>, spring: PathBuf, elements_per_coil: u32) -> PyResult<String> {
    guarded(py, || {
        let input = coil_design::sheet::input::read_spring(&spring).map_err(fail)?;
        let settings = coil_tuner::fe::FeSettings {
            elements_per_coil,
            ..Default::default()
        };
        let report = coil_design::sheet::check(&input, &settings).map_err(fail)?;
        report.json().map_err(fail)
    })
}

/// Designs to a TARGET.json (`coil-tune design`): writes design.json, report.md, the
/// figure and the decks into `out` and returns design.json's content.
#[pyfunction]
#[pyo3(signature = (target, out, objective=None, short_list=None, plots=true))]
fn design(
    py: Python<'_>,
    target: PathBuf,
    out: PathBuf,
    objective: Option<String>,
    short_list: Option<usize>,
    plots: bool,
) -> PyResult<String> {
    use coil_design::{self as design, target::Objective};
    let objective = match objective.as_deref() {
        None => None,
        Some("lightest") => Some(Objective::Lightest),
        Some("stress_margin") => Some(Objective::StressMargin),
        Some(other) => {
            return Err(fail(format!(
                "objective \"{other}\"; expected \"lightest\" or \"stress_margin\""
            )))
        }
    };
    guarded(py, || {
        let dir = OutDir::create(&out).map_err(fail)?;
        let target = design::target::read_target(&target).map_err(fail)?;
        let settings = design::DesignSettings {
            objective,
            short_list,
            ..Default::default()
        };
        let result = design::design(&target, &settings).map_err(fail)?;
        design::output::write(&result, &dir, plots).map_err(fail)?;
        dir.commit().map_err(fail)?;
        design::output::json(&result).map_err(fail)
    })
}

/// Which damping law? (`coil-tune damping`): fits every law to all decay records of a case,
/// writes damping.json and report.md into `out` and returns damping.json's content.
#[pyfunction]
#[pyo3(signature = (case, out, variants=None, elements_per_coil=24, scatter=0.03))]
fn damping(
    py: Python<'_>,
    case: PathBuf,
    out: PathBuf,
    variants: Option<PathBuf>,
    elements_per_coil: u32,
    scatter: f64,
) -> PyResult<String> {
    guarded(py, || {
        let mut settings = coil_ident::law::DampingSettings {
            scatter,
            ..Default::default()
        };
        settings.fe.elements_per_coil = elements_per_coil;
        settings.variants = variants.or_else(|| coil_ident::law::variants_beside(&case));
        let dir = OutDir::create(&out).map_err(fail)?;
        let report = coil_ident::law::identify(&case, &settings).map_err(fail)?;
        coil_ident::law::write(&report, &dir).map_err(fail)?;
        let path = out.join("damping.json");
        std::fs::read_to_string(&path).map_err(|e| fail(format!("{}: {e}", path.display())))
    })
}

/// Reads a measured record (UFF 58/58b, MATLAB level 5 MAT-file, CSV dialects) as the
/// commands do (`coil_postproc::record`): returns `file`, `format`, `channel`,
/// `quantity`, `unit` (as stated), `time_s` and `values` (SI).
#[pyfunction]
#[pyo3(signature = (path, channel=None, time=None, quantity=None, unit=None))]
fn read_record(
    py: Python<'_>,
    path: PathBuf,
    channel: Option<String>,
    time: Option<String>,
    quantity: Option<String>,
    unit: Option<String>,
) -> PyResult<String> {
    guarded(py, || read_record_json(path, channel, time, quantity, unit))
}

/// [`read_record`]'s work, inside the boundary guard.
fn read_record_json(
    path: PathBuf,
    channel: Option<String>,
    time: Option<String>,
    quantity: Option<String>,
    unit: Option<String>,
) -> PyResult<String> {
    use coil_postproc::record::{read_record, Quantity, RecordSpec};
    let quantity = match quantity {
        None => None,
        Some(q) => Some(Quantity::from_name(&q).ok_or_else(|| {
            fail(format!(
                "quantity `{q}`: expected acceleration, velocity or displacement"
            ))
        })?),
    };
    let r = read_record(&RecordSpec {
        file: path,
        channel,
        time,
        quantity,
        unit,
    })
    .map_err(fail)?;
    json(&serde_json::json!({
        "file": r.file,
        "format": r.format,
        "channel": r.channel,
        "quantity": r.quantity,
        "unit": r.unit,
        "time_s": r.time_s,
        "values": r.values,
    }))
}

/// Writes evenly sampled histories as UFF dataset 58 (ASCII, or 58b when `binary`),
/// the writer of `coil-solve --uff` and `coil-tune diagnose --uff`. `datasets_json` is a
/// list of objects with `name`, `node`, `direction`, `quantity` (`displacement`,
/// `velocity`, `acceleration`), `unit`, `start_s`, `step_s` and `values`.
#[pyfunction]
#[pyo3(signature = (path, datasets_json, binary=false))]
fn write_uff(py: Python<'_>, path: PathBuf, datasets_json: &str, binary: bool) -> PyResult<()> {
    guarded(py, || write_uff_file(&path, datasets_json, binary))
}

/// [`write_uff`]'s work, inside the boundary guard.
fn write_uff_file(path: &std::path::Path, datasets_json: &str, binary: bool) -> PyResult<()> {
    #[derive(serde::Deserialize)]
    struct Entry {
        name: String,
        node: i64,
        direction: i32,
        quantity: String,
        unit: String,
        start_s: f64,
        step_s: f64,
        values: Vec<f64>,
    }
    let entries: Vec<Entry> = serde_json::from_str(datasets_json).map_err(|e| {
        fail(format!(
            "datasets: {e}; expected objects with name, node, direction, quantity, unit, start_s, step_s, values"
        ))
    })?;
    let datasets: Vec<coil_io::uff::Uff58> = entries
        .into_iter()
        .map(|e| {
            let (ordinate_type, length_exponent) = coil_io::uff::Uff58::ordinate_kind(&e.quantity);
            coil_io::uff::Uff58 {
                description: format!("coil: {}", e.quantity),
                name: e.name,
                node: e.node,
                direction: e.direction,
                ordinate_type,
                length_exponent,
                ordinate_label: e.quantity,
                ordinate_unit: e.unit,
                start_s: e.start_s,
                step_s: e.step_s,
                values: e.values,
            }
        })
        .collect();
    coil_io::write_file(path, &coil_io::uff::uff58_bytes(&datasets, binary)).map_err(fail)
}

#[pymodule]
fn _coil(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("CoilError", m.py().get_type::<CoilError>())?;
    m.add_function(wrap_pyfunction!(mesh, m)?)?;
    m.add_function(wrap_pyfunction!(read_deck, m)?)?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(decrement, m)?)?;
    m.add_function(wrap_pyfunction!(plot_history, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_study, m)?)?;
    m.add_function(wrap_pyfunction!(tolerance_study, m)?)?;
    m.add_function(wrap_pyfunction!(study_info, m)?)?;
    m.add_function(wrap_pyfunction!(run_tasks, m)?)?;
    m.add_function(wrap_pyfunction!(write_table, m)?)?;
    m.add_function(wrap_pyfunction!(run_shard, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(frc, m)?)?;
    m.add_function(wrap_pyfunction!(catenary, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(design, m)?)?;
    m.add_function(wrap_pyfunction!(damping, m)?)?;
    m.add_function(wrap_pyfunction!(read_record, m)?)?;
    m.add_function(wrap_pyfunction!(write_uff, m)?)?;
    Ok(())
}
