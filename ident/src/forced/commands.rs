//! `coil-tune simulate` and `coil-tune frc` on a model file (docs/forced.md): read and check
//! everything first, compute, then write the output set (nothing is written on an error).

use super::frc::{self, BackbonePoint, FrcPoint, FrcSettings};
use super::model::{ForcedModel, OutputQuantity};
use super::records::{read_record, ForcedEntry, ForcedRecord};
use super::simulate::{self, Grid};
use crate::error::{Result, TuneError};
use crate::output::{csv, OutDir};
use std::path::{Path, PathBuf};

/// Reads and checks a model file (`model.json` of a forced diagnosis).
pub fn read_model(path: &Path) -> Result<ForcedModel> {
    let bytes = coil_io::confine::read_bounded_bytes(path, coil_io::MAX_RECORD_BYTES, "a model")?;
    let text = String::from_utf8_lossy(&bytes);
    let model: ForcedModel = serde_json::from_str(&text).map_err(|e| TuneError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!(
            "{e}; expected a model file written by `coil-tune diagnose` on forced records \
             (model.json, docs/forced.md)"
        ),
    })?;
    model.check().map_err(|message| TuneError::Json {
        path: path.to_path_buf(),
        line: 1,
        message,
    })?;
    Ok(model)
}

/// What `simulate` reads from a record.
#[derive(Debug, Clone)]
pub struct SimulateRequest {
    /// The record file.
    pub record: PathBuf,
    /// Its time column.
    pub time: String,
    /// Its input column.
    pub input: String,
    /// Its output column (only the first `init` cells are read).
    pub output: String,
    /// Output samples the initial state is fitted to.
    pub init: usize,
}

/// A simulation: the record's time stamps and the simulated output.
#[derive(Debug, Clone)]
pub struct Simulated {
    /// Time stamps, s.
    pub time_s: Vec<f64>,
    /// Simulated output, the output's unit.
    pub output: Vec<f64>,
    /// The initial state fitted `(z0, v0)`.
    pub initial: (f64, f64),
}

/// Drives `model` with a record's input from the state fitted to its first outputs.
pub fn simulate_record(model: &ForcedModel, request: &SimulateRequest) -> Result<Simulated> {
    if request.init < 2 {
        return Err(TuneError::Invalid(format!(
            "--init {}: expected at least 2 output samples to fit the initial state to",
            request.init
        )));
    }
    let entry = ForcedEntry {
        file: request.record.clone(),
        time: request.time.clone(),
        input: request.input.clone(),
        output: request.output.clone(),
        input_quantity: model.input_quantity,
        output_quantity: model.output_quantity,
        input_unit: model.input_unit.clone(),
        output_unit: model.output_unit.clone(),
    };
    let (record, _) = read_record(&entry, Some(request.init))?;
    simulate_series(model, &record)
        .map_err(|e| TuneError::Invalid(format!("{}: {e}", request.record.display())))
}

/// [`simulate_record`] on a record in memory (its `output` holds the initial samples).
pub fn simulate_series(
    model: &ForcedModel,
    record: &ForcedRecord,
) -> std::result::Result<Simulated, String> {
    let o = &model.oscillator;
    let w = o.natural_frequency_rad_s;
    let head_max = record
        .output
        .iter()
        .map(|y| (y - o.output_offset).abs())
        .fold(0.0, f64::max);
    let u_max = record.input.iter().fold(0.0f64, |m, u| m.max(u.abs()));
    // Displacement scale: the head's, or the static response to the largest input.
    let z_head = match model.output_quantity {
        OutputQuantity::Displacement => head_max,
        OutputQuantity::Velocity => head_max / w,
        OutputQuantity::Acceleration => head_max / (w * w),
    };
    let mut z_max = z_head.max(o.input_gain.abs() * u_max / (w * w));
    let bound = simulate::bound_for(1e3 * z_max.max(1e-300));
    for _ in 0..4 {
        let grid = Grid {
            dt: record.dt,
            substeps: simulate::substeps(o, record.dt, z_max, w * z_max),
        };
        let initial =
            simulate::fit_initial_state(model, grid, &record.input, &record.output, bound)?;
        let m = simulate::motion(o, grid, &record.input, initial, bound)?;
        let reached = m.z.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let v_reached = m.v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let needed = simulate::substeps(o, record.dt, reached, v_reached);
        if needed <= grid.substeps {
            let output = (0..record.input.len())
                .map(|i| model.output(m.z[i], m.v[i], m.a[i], record.input[i]))
                .collect();
            return Ok(Simulated {
                time_s: record.time_s.clone(),
                output,
                initial,
            });
        }
        z_max = reached;
    }
    Err("the simulation needs ever finer steps (the model's response grows without bound)".into())
}

/// Writes `simulated.csv` (`time_s,output`).
pub fn write_simulated(sim: &Simulated, out: &OutDir) -> Result<()> {
    let mut text = String::with_capacity(sim.output.len() * 32);
    text.push_str("time_s,output\n");
    for (t, y) in sim.time_s.iter().zip(&sim.output) {
        text.push_str(&format!("{t},{y:e}\n"));
    }
    out.write("simulated.csv", text.as_bytes())?;
    out.commit()
}

/// A forced response curve and its backbone.
#[derive(Debug, Clone)]
pub struct FrcResult {
    /// The curve.
    pub points: Vec<FrcPoint>,
    /// The backbone.
    pub backbone: Vec<BackbonePoint>,
    /// Frequencies where the stability changes (the folds), Hz.
    pub jumps: Vec<f64>,
}

/// The forced response curve and backbone of `model`.
pub fn frc_of(model: &ForcedModel, settings: &FrcSettings) -> Result<FrcResult> {
    let points = frc::frc(model, settings).map_err(TuneError::Invalid)?;
    let peak = points
        .iter()
        .map(|p| super::hb::first_harmonic(&p.coefficients))
        .fold(0.0, f64::max);
    let backbone =
        frc::backbone(model, 1.1 * peak, 60, settings.harmonics).map_err(TuneError::Invalid)?;
    let jumps = frc::jumps(&points);
    Ok(FrcResult {
        points,
        backbone,
        jumps,
    })
}

/// Writes `frc.csv` (`frequency_hz,amplitude,stable`) and `backbone.csv`
/// (`frequency_hz,amplitude,peak_displacement`).
pub fn write_frc(result: &FrcResult, out: &OutDir) -> Result<()> {
    let curve = result.points.iter().map(|p| {
        vec![
            p.frequency_hz.to_string(),
            format!("{:e}", p.amplitude),
            p.stable.to_string(),
        ]
    });
    out.write(
        "frc.csv",
        csv(&["frequency_hz", "amplitude", "stable"], curve).as_bytes(),
    )?;
    let backbone = result.backbone.iter().map(|p| {
        vec![
            p.frequency_hz.to_string(),
            format!("{:e}", p.amplitude),
            format!("{:e}", p.peak_displacement),
        ]
    });
    out.write(
        "backbone.csv",
        csv(
            &["frequency_hz", "amplitude", "peak_displacement"],
            backbone,
        )
        .as_bytes(),
    )?;
    out.commit()
}
