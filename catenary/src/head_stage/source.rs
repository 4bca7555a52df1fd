//! What every spring source gives the head stage (`super::from_spring`,
//! `super::design`): one spring ready to become a stage, the shared limits and the
//! assumed damping law, and the helpers their messages use.

use super::springs::HeadStage;
use crate::TuneError;
use coil_tuner::fe::{FeSettings, SpringState};
use std::path::Path;

/// The damping law assumed for a spring that names none: the 160ECT's calibrated
/// Rayleigh law on coil's model, alpha = 0.8 1/s (the paper's Table 2) and beta
/// recalibrated to the measured zeta (docs/catenary.md, "Head stages from coil's
/// springs").
pub const ASSUMED_RAYLEIGH: [f64; 2] = [0.8, 1.2413e-4];

/// Most springs in parallel.
pub const MAX_SPRINGS_IN_PARALLEL: u32 = 64;

/// Largest spring source file read (bytes).
pub const MAX_SOURCE_BYTES: u64 = 1 << 20;

/// One spring, ready to become a stage.
#[derive(Debug, Clone)]
pub(crate) struct Spring {
    pub(crate) name: String,
    pub(crate) source: String,
    pub(crate) state: SpringState,
    pub(crate) rayleigh: [f64; 2],
    pub(crate) rayleigh_note: String,
    pub(crate) band: Option<HeadStage>,
    /// The FE settings of the spring's own model (a design's mesh), instead of the
    /// caller's.
    pub(crate) fe: Option<FeSettings>,
}

pub(crate) fn invalid(message: String) -> TuneError {
    TuneError::Invalid(message)
}

/// A spring's name from its file: the stem, or the folder's name for the files whose
/// name says only what they are (`case.json`, `calibration.json`, `design.json`).
pub(crate) fn stem(path: &Path) -> String {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    match stem.as_deref() {
        Some("case") | Some("calibration") | Some("design") | None => path
            .parent()
            .and_then(Path::file_name)
            .map_or("spring".into(), |n| n.to_string_lossy().into_owned()),
        Some(s) => s.to_string(),
    }
}
