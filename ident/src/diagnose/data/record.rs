//! What the conditioning gives ([`DecayData`], [`Cut`], [`Resampling`]), its limits
//! (the module docs of [`super`] say where each applies) and the error every check
//! of the record raises: the leaf the conditioning's steps share.

use super::slow_line::SlowLine;
use crate::case::Quantity;
use crate::error::TuneError;
use coil_postproc::noise::NoiseFloor;
use coil_postproc::signal::Signal;
use serde::Serialize;

/// Fewest oscillation cycles in a decay record.
pub const MIN_CYCLES: usize = 8;
/// Most oscillation cycles in a decay record: each fit simulates every cycle thousands
/// of times, so the time grows with the cycles (a longer record is refused with the
/// length to cut it to).
pub const MAX_CYCLES: usize = 1000;
/// Samples per period above which a record is decimated to the band the model needs.
pub const DECIMATE_ABOVE: f64 = 500.0;
/// Fewest samples per period after decimation.
pub const DECIMATED_PER_PERIOD: f64 = 100.0;
/// The anti-alias low-pass before decimation, in multiples of the oscillation's
/// frequency: it keeps the harmonics a cubic spring or friction put at 3, 5, 7 times it,
/// and at 100 samples per period (Nyquist at 50 times) its fourth-order response,
/// applied forward and backward, is down to `(20 / 50)^16 = 4e-7` at the new Nyquist
/// frequency.
pub const DECIMATED_CUTOFF: f64 = 20.0;
/// Fewest distinct values in a decay record.
pub const MIN_LEVELS: usize = 16;
/// Largest share of samples at the record's extremes.
pub const CLIP_FRACTION: f64 = 0.002;
/// Fewest successive increasing points of a static record's loading branch.
pub const MIN_BRANCH: usize = 4;
/// Tolerance of a uniform step (relative to the median step), as the post-processor's.
pub const STEP_TOLERANCE: f64 = coil_postproc::signal::STEP_TOLERANCE;
/// Largest deviation of a step from the median step that is resampled (relative).
pub const JITTER_LIMIT: f64 = 0.5;
/// A regular half-cycle lasts within this share of the median half-cycle.
pub const HALF_CYCLE_TOLERANCE: f64 = 0.3;
/// A half-cycle whose peak exceeds the largest of the next three by this factor is the
/// blow, not the decay.
pub const PEAK_JUMP: f64 = 1.5;
/// A position or velocity sample this many robust standard deviations off the cubic
/// through its neighbours is a glitch.
pub const GLITCH_SIGMAS: f64 = 12.0;
/// Largest share of glitches replaced.
pub const MAX_GLITCH_SHARE: f64 = 0.02;
/// Share of the record searched for an impulse.
pub const START_SHARE: f64 = 0.25;

/// The part of a record cut off before the free decay.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cut {
    /// Samples removed from the start.
    pub samples: usize,
    /// Time stamp of the first sample kept (s, in the record's time).
    pub time_s: f64,
    /// What was found before it.
    pub reason: String,
}

/// How jittered time stamps were resampled.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Resampling {
    /// The uniform step (s).
    pub step_s: f64,
    /// Largest deviation of a step from the median step (s).
    pub max_step_deviation_s: f64,
}

/// A decay record that passed the checks, conditioned.
#[derive(Debug, Clone)]
pub struct DecayData {
    /// The weight's acceleration (m/s^2) on the uniform grid, after the cut: as measured,
    /// or derived from the measured velocity or position. `column` is the file's column.
    pub signal: Signal,
    /// What the file measured.
    pub quantity: Quantity,
    /// The measured quantity in SI (m/s^2, m/s, m) on `signal.time_s`, unfiltered (a
    /// position keeps its offset and drift).
    pub measured: Vec<f64>,
    /// Zero crossings of the detrended record (with hysteresis) divided by two.
    pub cycles: usize,
    /// Mean frequency of those crossings (Hz).
    pub frequency_hz: f64,
    /// Smallest step between distinct values of the measured column (SI; the ADC's or
    /// position sensor's resolution, if quantised).
    pub resolution: f64,
    /// Noise floor of `signal` (m/s^2).
    pub noise: NoiseFloor,
    /// Noise floor of `measured` (SI).
    pub measured_noise: NoiseFloor,
    /// The low-pass cut-off of the differentiation (Hz), if the acceleration is derived.
    pub differentiation_cutoff_hz: Option<f64>,
    /// Resampling of jittered time stamps, if any.
    pub resampled: Option<Resampling>,
    /// The impulse cut from the start, if any.
    pub cut: Option<Cut>,
    /// A slow line beside the oscillation (step 8), fitted beside every model and
    /// removed from `signal`.
    pub slow_line: Option<SlowLine>,
    /// What the conditioning did, in words (resampling, cut, differentiation).
    pub warnings: Vec<String>,
}

/// A record that failed a check of the post-processor's signal.
pub(super) fn post(source: coil_postproc::PostError) -> TuneError {
    TuneError::Post {
        context: "the decay record".to_string(),
        source,
    }
}

pub(super) fn bad(signal: &Signal, problem: String, expected: &str) -> TuneError {
    TuneError::Invalid(format!(
        "{} (column `{}`): {problem}; expected {expected}",
        signal.source().display(),
        signal.column()
    ))
}
