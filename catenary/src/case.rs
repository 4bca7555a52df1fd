//! The catenary case file (`case.json` in a case folder; docs/catenary.md, "Runs").
//!
//! ```json
//! {
//!   "title": "EN 50318:2002 reference model",
//!   "catenary": "catenary.json",            // or the spec itself (an object)
//!   "pantograph": { "stages": [...], "uplift_force_n": 120, "contact_stiffness_n_m": 50000 },
//!   "speeds_km_h": [250, 300],
//!   "time_step_s": 0.001,
//!   "window": { "start_m": 240, "end_m": 360 },
//!   "cutoff_hz": 20,
//!   "reference": { "250": { "mean_n": [110, 120] } }
//! }
//! ```
//! `catenary` and `pantograph` are the objects of `coil_mesher::catenary` (a
//! [`CatenarySpec`] and a [`PantographSpec`]) or the names of JSON files holding them,
//! inside the case folder. Optional: `title`, `end_m` (where each run stops, default the
//! last support), `output_every` (default 1), `cutoff_hz` (default 20), `filter_order`
//! (Butterworth order per pass of the zero-phase filter, default 4) and `reference`
//! (`coil_postproc::en50318::report::Reference`). Unknown fields are errors; errors name
//! the file, its line and the field.

use crate::{Result, TuneError};
use coil_mesher::catenary::{CatenarySpec, PantographSpec, RunSpec};
use coil_postproc::en50318::report::Reference;
use coil_postproc::en50318::{Settings, Window, DEFAULT_CUTOFF_HZ, DEFAULT_ORDER};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Largest case or spec file read (bytes).
pub const MAX_CASE_BYTES: u64 = 1 << 20;
/// Most speeds in a case.
pub const MAX_SPEEDS: usize = 64;

fn default_cutoff() -> f64 {
    DEFAULT_CUTOFF_HZ
}

fn default_order() -> usize {
    DEFAULT_ORDER
}

fn default_every() -> u32 {
    1
}

/// `case.json` as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseFile {
    #[serde(default)]
    title: String,
    catenary: serde_json::Value,
    pantograph: serde_json::Value,
    speeds_km_h: Vec<f64>,
    time_step_s: f64,
    window: Window,
    #[serde(default)]
    end_m: Option<f64>,
    #[serde(default = "default_every")]
    output_every: u32,
    #[serde(default = "default_cutoff")]
    cutoff_hz: f64,
    #[serde(default = "default_order")]
    filter_order: usize,
    #[serde(default)]
    reference: Reference,
}

/// A read and checked case.
#[derive(Debug, Clone, Serialize)]
pub struct Case {
    /// The case file.
    pub path: PathBuf,
    /// Its title (the folder's name if none).
    pub title: String,
    /// The catenary.
    pub catenary: CatenarySpec,
    /// The pantograph.
    pub pantograph: PantographSpec,
    /// Speeds (km/h), in the order of the file.
    pub speeds_km_h: Vec<f64>,
    /// Time step (s).
    pub time_step_s: f64,
    /// Where each run stops (m), `None` for the last support.
    pub end_m: Option<f64>,
    /// Record every k-th step.
    pub output_every: u32,
    /// Window and filter of the statistics.
    pub settings: Settings,
    /// Reference ranges.
    pub reference: Reference,
}

impl Case {
    /// The run at `speed_km_h`.
    pub fn run_spec(&self, speed_km_h: f64) -> RunSpec {
        RunSpec {
            speed_km_h,
            time_step_s: self.time_step_s,
            start_m: 0.0,
            end_m: self.end_m,
            output_every: self.output_every,
        }
    }
}

fn json_error(path: &Path, e: &serde_json::Error, what: &str) -> TuneError {
    TuneError::Json {
        path: path.into(),
        line: e.line(),
        message: format!("{e}; expected {what} (docs/catenary.md, \"Runs\")"),
    }
}

/// Reads `field` of the case: the object itself or a file named by a string, inside the
/// case folder.
fn part<T: serde::de::DeserializeOwned>(
    folder: &Path,
    case_path: &Path,
    field: &str,
    value: serde_json::Value,
) -> Result<T> {
    match value {
        serde_json::Value::String(entry) => {
            let path = coil_io::resolve_inside(folder, &entry)?;
            let text = coil_io::read_bounded(&path, MAX_CASE_BYTES, "catenary spec")?;
            serde_json::from_str(&text)
                .map_err(|e| json_error(&folder.join(&entry), &e, &format!("the {field} spec")))
        }
        other => serde_json::from_value(other).map_err(|e| {
            TuneError::Invalid(format!(
                "{}: field `{field}`: {e}; expected the {field} spec or the name of a JSON file \
                 holding it (docs/catenary.md)",
                case_path.display()
            ))
        }),
    }
}

/// Reads a case: a folder holding `case.json`, or the file itself.
pub fn read_case(path: &Path) -> Result<Case> {
    let file = if path.is_dir() {
        path.join("case.json")
    } else {
        path.to_path_buf()
    };
    let folder = file.parent().unwrap_or(Path::new(".")).to_path_buf();
    let text = coil_io::read_bounded(&file, MAX_CASE_BYTES, "case file")?;
    let raw: CaseFile =
        serde_json::from_str(&text).map_err(|e| json_error(&file, &e, "a catenary case"))?;
    let catenary: CatenarySpec = part(&folder, &file, "catenary", raw.catenary)?;
    let pantograph: PantographSpec = part(&folder, &file, "pantograph", raw.pantograph)?;
    let invalid = |what: String| TuneError::Invalid(format!("{}: {what}", file.display()));
    catenary.validate().map_err(|e| invalid(e.to_string()))?;
    pantograph.validate().map_err(|e| invalid(e.to_string()))?;
    if raw.speeds_km_h.is_empty() || raw.speeds_km_h.len() > MAX_SPEEDS {
        return Err(invalid(format!(
            "speeds_km_h has {} speeds; expected 1 to {MAX_SPEEDS}",
            raw.speeds_km_h.len()
        )));
    }
    let length = catenary.length_m();
    let title = if raw.title.is_empty() {
        folder
            .file_name()
            .map_or("catenary".into(), |n| n.to_string_lossy().into_owned())
    } else {
        raw.title
    };
    let case = Case {
        path: file.clone(),
        title,
        catenary,
        pantograph,
        speeds_km_h: raw.speeds_km_h,
        time_step_s: raw.time_step_s,
        end_m: raw.end_m,
        output_every: raw.output_every,
        settings: Settings {
            window: raw.window,
            cutoff_hz: raw.cutoff_hz,
            order: raw.filter_order,
        },
        reference: raw.reference,
    };
    for &v in &case.speeds_km_h {
        case.run_spec(v)
            .validate(length)
            .map_err(|e| invalid(e.to_string()))?;
    }
    let w = case.settings.window;
    let end = case.end_m.unwrap_or(length);
    if !(w.start_m.is_finite()
        && w.end_m.is_finite()
        && 0.0 <= w.start_m
        && w.start_m < w.end_m
        && w.end_m <= end)
    {
        return Err(invalid(format!(
            "window {} to {} m; expected 0 <= start_m < end_m <= {end} m (the run's end)",
            w.start_m, w.end_m
        )));
    }
    if !(case.settings.cutoff_hz > 0.0 && case.settings.cutoff_hz.is_finite()) {
        return Err(invalid(format!(
            "cutoff_hz = {}; expected a positive frequency below the Nyquist frequency 1 / (2 time_step_s)",
            case.settings.cutoff_hz
        )));
    }
    if !(1..=8).contains(&case.settings.order) {
        return Err(invalid(format!(
            "filter_order = {}; expected 1 to 8",
            case.settings.order
        )));
    }
    case.reference.check().map_err(|e| invalid(e.to_string()))?;
    Ok(case)
}
