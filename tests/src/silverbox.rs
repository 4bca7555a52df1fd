//! Silverbox (T. Wigren, J. Schoukens, "Three free data sets for development and
//! benchmarking in nonlinear system identification", ECC 2013): the forced diagnosis on
//! the shared estimation data only, the last two multisines kept out of the fit and
//! scored as the benchmark scores its test data (the model simulated under the measured
//! input from the first 50 measured outputs only; RMS error in mV over the rest).
//!
//! One piece of code for the example that prints the table and times the benchmarks
//! (`cargo run --release -p coil-tests --example silverbox`) and the ignored test that
//! holds the table to docs/forced.md and the README (`tests/tests/it/shared_data.rs`).
//! The data are read where they are (`../shared/forced/silverbox/estimation.csv` beside
//! the repository) and never copied into the repository.

use coil_ident::forced::commands::simulate_series;
use coil_ident::forced::model::{ForcedModel, InputQuantity, OutputQuantity};
use coil_ident::forced::records::{read_record, ForcedCase, ForcedEntry, ForcedRecord};
use coil_ident::forced::{diagnose_case, ForcedOutcome, ForcedSettings};
use std::path::{Path, PathBuf};

/// The shared estimation data, beside the repository.
pub fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/forced/silverbox/estimation.csv")
}

/// Samples given to the simulation as initial outputs (the benchmark's rule).
pub const INITIAL_SAMPLES: usize = 50;

/// The gaps between the multisines: runs of at least 40 samples over which the input
/// moves by less than 2 mV per sample (the generator's pause at its DC level). Returns
/// their starts.
pub fn gaps(u: &[f64]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut i = 1;
    while i < u.len() {
        let mut j = i;
        while j < u.len() && (u[j] - u[j - 1]).abs() < 0.002 {
            j += 1;
        }
        if j - i + 1 >= 40 {
            out.push(i - 1);
        }
        i = j + 1;
    }
    out
}

/// Samples `a..b` of a record.
pub fn slice(r: &ForcedRecord, a: usize, b: usize) -> ForcedRecord {
    ForcedRecord {
        t0: r.time_s[a],
        time_s: r.time_s[a..b].to_vec(),
        input: r.input[a..b].to_vec(),
        output: r.output[a..b].to_vec(),
        ..r.clone()
    }
}

/// The records as one forced case of the estimation data.
pub fn case_of(records: Vec<ForcedRecord>) -> ForcedCase {
    ForcedCase {
        file: data(),
        name: "Silverbox estimation data".into(),
        has_spring: false,
        mass_kg: None,
        records,
    }
}

/// The whole estimation record (`u_v` as a force, `y_v` as a displacement, in V).
pub fn read(file: &Path) -> Result<ForcedRecord, String> {
    let entry = ForcedEntry {
        file: file.to_path_buf(),
        time: "time_s".into(),
        input: "u_v".into(),
        output: "y_v".into(),
        input_quantity: InputQuantity::Force,
        output_quantity: OutputQuantity::Displacement,
        input_unit: "V".into(),
        output_unit: "V".into(),
    };
    read_record(&entry, None)
        .map(|(r, _)| r)
        .map_err(|e| format!("silverbox: {e} (the shared data sit at ../shared/forced/silverbox/)"))
}

/// One held-out part: its name, samples `a..b`, and the RMS simulation errors (mV) of
/// the linear and the extended model from [`INITIAL_SAMPLES`] initial outputs.
#[derive(Debug, Clone)]
pub struct HeldOut {
    pub name: &'static str,
    pub a: usize,
    pub b: usize,
    pub linear_mv: f64,
    pub extended_mv: f64,
}

/// The fit before the last two multisines and their scores.
pub struct Fit {
    /// The whole record.
    pub full: ForcedRecord,
    /// The multisines' gaps found in the input.
    pub gaps: Vec<usize>,
    /// The diagnosis on samples `0..gaps[len - 3]`.
    pub outcome: ForcedOutcome,
    /// Multisine 1 of 2, 2 of 2, and both.
    pub held_out: Vec<HeldOut>,
}

impl Fit {
    /// The sample the fit stops at (the third-last gap).
    pub fn cut(&self) -> usize {
        self.gaps[self.gaps.len() - 3]
    }

    /// The extended model's natural frequency (Hz).
    pub fn f0_hz(&self) -> f64 {
        self.outcome
            .extended()
            .model
            .oscillator
            .natural_frequency_rad_s
            / std::f64::consts::TAU
    }

    /// The extended model's damping ratio (-).
    pub fn zeta(&self) -> f64 {
        self.outcome.extended().model.oscillator.damping_ratio
    }
}

/// The RMS error (mV) of `model` simulated over `part` from its first
/// [`INITIAL_SAMPLES`] measured outputs.
pub fn score(model: &ForcedModel, part: &ForcedRecord) -> Result<f64, String> {
    let mut head = part.clone();
    head.output.truncate(INITIAL_SAMPLES);
    let sim = simulate_series(model, &head).map_err(|e| format!("simulate: {e}"))?;
    let n = part.output.len() - INITIAL_SAMPLES;
    let sse: f64 = (INITIAL_SAMPLES..part.output.len())
        .map(|i| (sim.output[i] - part.output[i]).powi(2))
        .sum();
    Ok(1e3 * (sse / n as f64).sqrt())
}

/// Reads `file`, fits on everything before the last two complete multisines and scores
/// them (module docs).
pub fn fit(file: &Path, settings: &ForcedSettings) -> Result<Fit, String> {
    let full = read(file)?;
    let g = gaps(&full.input);
    if g.len() < 3 {
        return Err(format!(
            "{}: {} gaps between multisines, expected at least 3",
            file.display(),
            g.len()
        ));
    }
    let (cut, mid, end) = (g[g.len() - 3], g[g.len() - 2], g[g.len() - 1]);
    let outcome = diagnose_case(case_of(vec![slice(&full, 0, cut)]), settings)
        .map_err(|e| format!("diagnose: {e}"))?;
    let mut held_out = Vec::new();
    for (name, a, b) in [
        ("multisine 1 of 2", cut, mid),
        ("multisine 2 of 2", mid, end),
        ("both", cut, end),
    ] {
        let part = slice(&full, a, b);
        held_out.push(HeldOut {
            name,
            a,
            b,
            linear_mv: score(&outcome.baseline.model, &part)?,
            extended_mv: score(&outcome.extended().model, &part)?,
        });
    }
    Ok(Fit {
        full,
        gaps: g,
        outcome,
        held_out,
    })
}
