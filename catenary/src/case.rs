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
//! `catenary` and `pantograph` are the objects of `crate::model` (a
//! [`CatenarySpec`] and a [`PantographSpec`]) or the names of JSON files holding them,
//! inside the case folder. Optional: `title`, `end_m` (where each run stops, default the
//! last support), `output_every` (default 1), `cutoff_hz` (default 20), `filter_order`
//! (Butterworth order per pass of the zero-phase filter, default 4) and `reference`
//! (`crate::en50318::report::Reference`). Unknown fields are errors; errors name
//! the file, its line and the field.

use crate::assess::AssessmentSpec;
use crate::en50318::report::Reference;
use crate::en50318::{Settings, Window, DEFAULT_CUTOFF_HZ, DEFAULT_ORDER};
use crate::head_stage::from_spring::{split_name, HeadSpringSpec};
use crate::model::{CatenarySpec, PantographSpec, RunSpec};
use crate::{Result, TuneError};
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
    #[serde(default)]
    assessment: AssessmentSpec,
}

/// Longest case title (characters).
pub const MAX_TITLE_CHARS: usize = 200;

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
    /// The design criteria's settings.
    pub assessment: AssessmentSpec,
    /// The head stage from a spring (`pantograph.head_spring`), if the case names one.
    pub head_spring: Option<HeadSpringSpec>,
    /// Its source resolved inside the case folder.
    pub head_spring_source: Option<PathBuf>,
    /// Runs at or above the contact wire's wave speed are allowed
    /// (`--allow-supercritical`).
    pub allow_supercritical: bool,
    /// Runs above the transient work limit are allowed (`--allow-large`).
    pub allow_large: bool,
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
            allow_supercritical: self.allow_supercritical,
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
/// case folder; `take` removes a key from the object first and returns it beside.
fn part<T: serde::de::DeserializeOwned>(
    folder: &Path,
    case_path: &Path,
    field: &str,
    value: serde_json::Value,
    take: Option<&str>,
) -> Result<(T, Option<serde_json::Value>)> {
    let (mut value, file) = match value {
        serde_json::Value::String(entry) => {
            let path = coil_io::resolve_inside(folder, &entry)?;
            let text = coil_io::read_bounded(&path, MAX_CASE_BYTES, "catenary spec")?;
            let value: serde_json::Value = serde_json::from_str(&text)
                .map_err(|e| json_error(&folder.join(&entry), &e, &format!("the {field} spec")))?;
            (value, folder.join(&entry))
        }
        other => (other, case_path.to_path_buf()),
    };
    let taken = match (take, value.as_object_mut()) {
        (Some(key), Some(object)) => object.remove(key),
        _ => None,
    };
    let parsed = serde_json::from_value(value).map_err(|e| {
        TuneError::Invalid(format!(
            "{}: field `{field}`: {e}; expected the {field} spec or the name of a JSON file \
             holding it (docs/catenary.md)",
            file.display()
        ))
    })?;
    Ok((parsed, taken))
}

/// `pantograph.head_spring` read and checked, with its source resolved inside `folder`.
fn head_spring(
    folder: &Path,
    file: &Path,
    value: Option<serde_json::Value>,
) -> Result<(Option<HeadSpringSpec>, Option<PathBuf>)> {
    let Some(value) = value else {
        return Ok((None, None));
    };
    let spec: HeadSpringSpec = serde_json::from_value(value).map_err(|e| {
        TuneError::Invalid(format!(
            "{}: field `pantograph.head_spring`: {e}; expected `source`, `springs_in_parallel`, \
             `head_mass_kg`, `damping`, `mass_share`, `reduced`, `rayleigh_alpha`, \
             `rayleigh_beta` (docs/catenary.md, \"The head stage from a spring\")",
            file.display()
        ))
    })?;
    spec.check()
        .map_err(|e| TuneError::Invalid(format!("{}: {e}", file.display())))?;
    let source = match &spec.source {
        None => None,
        Some(entry) => {
            let (path, name) = split_name(entry);
            let mut resolved = coil_io::resolve_inside(folder, path)?.into_os_string();
            if let Some(name) = name {
                resolved.push(":");
                resolved.push(name);
            }
            Some(PathBuf::from(resolved))
        }
    };
    Ok((Some(spec), source))
}

/// Refuses a title that is not one printable line of at most [`MAX_TITLE_CHARS`]: a
/// terminal escape in it would reach the terminal and report.md.
fn check_title(file: &Path, title: &str) -> Result<()> {
    if coil_io::confine::excerpt_n(title, MAX_TITLE_CHARS) == title {
        Ok(())
    } else {
        Err(TuneError::Invalid(format!(
            "{}: title `{title}`: expected one printable line of at most {MAX_TITLE_CHARS} \
             characters (no control characters or terminal escapes)",
            file.display()
        )))
    }
}

/// What the command line allows beyond the case's limits.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CaseOptions {
    /// Run at or above the contact wire's wave speed (`--allow-supercritical`).
    pub allow_supercritical: bool,
    /// Run a transient above the work limit (`--allow-large`).
    pub allow_large: bool,
    /// The speeds to run instead of the case's `speeds_km_h` (`--speeds`), checked as
    /// the case's are.
    pub speeds_km_h: Option<Vec<f64>>,
}

/// Reads a case: a folder holding `case.json`, or the file itself.
pub fn read_case(path: &Path) -> Result<Case> {
    read_case_with(path, CaseOptions::default())
}

/// The transient's work estimated from the spec before anything is built: steps times
/// the DOFs of two wires of two DOFs per node (docs/files.md, "a transient case").
fn estimated_work(case: &Case, speed_km_h: f64) -> (f64, f64, f64) {
    let c = &case.catenary;
    let per_span =
        (c.span_length_m / c.element_length_m).ceil() + c.droppers.positions_m.len() as f64;
    let dofs = 4.0 * (f64::from(c.spans) * per_span + 1.0);
    let length = case.end_m.unwrap_or(c.length_m());
    let steps = (length / (speed_km_h / 3.6) / case.time_step_s).ceil();
    (steps, dofs, steps * dofs)
}

/// [`read_case`] with the command line's permissions.
pub fn read_case_with(path: &Path, options: CaseOptions) -> Result<Case> {
    let file = if path.is_dir() {
        path.join("case.json")
    } else {
        path.to_path_buf()
    };
    let folder = file.parent().unwrap_or(Path::new(".")).to_path_buf();
    let text = coil_io::read_bounded(&file, MAX_CASE_BYTES, "case file")?;
    let raw: CaseFile =
        serde_json::from_str(&text).map_err(|e| json_error(&file, &e, "a catenary case"))?;
    let (catenary, _): (CatenarySpec, _) = part(&folder, &file, "catenary", raw.catenary, None)?;
    let (pantograph, taken): (PantographSpec, _) = part(
        &folder,
        &file,
        "pantograph",
        raw.pantograph,
        Some("head_spring"),
    )?;
    let (head_spring, head_spring_source) = head_spring(&folder, &file, taken)?;
    check_title(&file, &raw.title)?;
    let invalid = |what: String| TuneError::Invalid(format!("{}: {what}", file.display()));
    raw.assessment.check().map_err(invalid)?;
    catenary.validate().map_err(|e| invalid(e.to_string()))?;
    pantograph.validate().map_err(|e| invalid(e.to_string()))?;
    let (speeds_km_h, speeds_from) = match options.speeds_km_h {
        Some(speeds) => (speeds, "--speeds"),
        None => (raw.speeds_km_h, "speeds_km_h"),
    };
    if speeds_km_h.is_empty() || speeds_km_h.len() > MAX_SPEEDS {
        return Err(invalid(format!(
            "{speeds_from} has {} speeds; expected 1 to {MAX_SPEEDS}",
            speeds_km_h.len()
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
        speeds_km_h,
        time_step_s: raw.time_step_s,
        end_m: raw.end_m,
        output_every: raw.output_every,
        settings: Settings {
            window: raw.window,
            cutoff_hz: raw.cutoff_hz,
            order: raw.filter_order,
        },
        reference: raw.reference,
        assessment: raw.assessment,
        head_spring,
        head_spring_source,
        allow_supercritical: options.allow_supercritical,
        allow_large: options.allow_large,
    };
    for (k, &v) in case.speeds_km_h.iter().enumerate() {
        let spec = case.run_spec(v);
        spec.validate(length).map_err(|e| invalid(e.to_string()))?;
        if case.speeds_km_h[..k].contains(&v) {
            return Err(invalid(format!(
                "{speeds_from} lists {v} km/h twice; expected each speed once"
            )));
        }
        crate::model::check_wave_speed(&case.catenary, &spec)
            .map_err(|e| invalid(e.to_string()))?;
        let (steps, dofs, work) = estimated_work(&case, v);
        let limit = coil_solver::analysis::transient::MAX_WORK;
        if work > limit && !case.allow_large {
            return Err(invalid(format!(
                "at {v} km/h about {steps:.0} steps x {dofs:.0} DOFs = {work:.2e}, above the \
                 transient work limit of {limit:.0e} (docs/files.md); expected a larger \
                 time_step_s or element_length_m, or pass --allow-large"
            )));
        }
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
