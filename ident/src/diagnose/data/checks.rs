//! The checks a record must pass (module docs of [`super`], "Other checks"): not flat,
//! not clipped, a displacement within the coils' travel, a static record with a
//! loading branch.

use super::record::{bad, DecayData, CLIP_FRACTION, MIN_BRANCH, MIN_LEVELS};
use crate::case::{Quantity, StaticRecord};
use crate::error::{Result, TuneError};
use coil_postproc::signal::Signal;

/// Flat and clipped checks (module docs); returns the resolution.
pub(super) fn check_levels(signal: &Signal, quantity: Quantity) -> Result<f64> {
    let x = signal.values();
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n.max(1) as f64;
    let spread = (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n.max(1) as f64).sqrt();
    let mut sorted = x.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    if spread == 0.0 || sorted.len() < MIN_LEVELS {
        return Err(bad(
            signal,
            format!(
                "the signal is flat ({} distinct values, standard deviation {spread:.3e})",
                sorted.len()
            ),
            match quantity {
                Quantity::Acceleration => "a free decay of the weight's acceleration",
                Quantity::Velocity => "a free decay of the weight's velocity",
                Quantity::Displacement => "a free decay of the weight's position",
            },
        ));
    }
    let resolution = sorted
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let (lo, hi) = (sorted[0], sorted[sorted.len() - 1]);
    let tol = 0.5 * resolution;
    let at_extremes = x
        .iter()
        .filter(|&&v| v >= hi - tol || v <= lo + tol)
        .count();
    // Several samples at one extreme are normal for a coarse ADC on a slow crest; a
    // clipped record holds them at every large crest.
    if at_extremes as f64 > CLIP_FRACTION * n as f64 && at_extremes > 8 {
        return Err(bad(
            signal,
            format!(
                "{at_extremes} of {n} samples sit at the extremes {lo} / {hi}: the signal is clipped"
            ),
            "a record within the sensor's range (lower the gain or the impulse)",
        ));
    }
    Ok(resolution)
}

/// Checks the decay's size against the spring: its displacement amplitude, the peak
/// acceleration over `(2 pi f)^2` at the record's mean crossing frequency, must fit in
/// the coils' free travel `n (h - d)` (beyond it the coils touch; a record that claims
/// more is in the wrong unit, e.g. mm/s^2 for m/s^2).
pub fn check_amplitude(decay: &DecayData, case: &crate::case::MeasuredCase) -> Result<()> {
    let x = decay.signal.values();
    let mean = x.iter().sum::<f64>() / x.len().max(1) as f64;
    let peak = x.iter().fold(0.0_f64, |m, v| m.max((v - mean).abs()));
    let w = std::f64::consts::TAU * decay.frequency_hz;
    let amplitude_mm = 1e3 * peak / (w * w);
    let s = &case.spring;
    let travel_mm = s.active_coils * (s.pitch_mm - s.wire_diameter_mm);
    if !(amplitude_mm.is_finite() && amplitude_mm <= travel_mm) {
        return Err(bad(
            &decay.signal,
            format!(
                "a peak of {peak:.4e} m/s^2 at {:.3} Hz is a displacement amplitude of \
                 {amplitude_mm:.4e} mm, more than the coils' free travel n (h - d) = \
                 {travel_mm:.3} mm",
                decay.frequency_hz
            ),
            "the weight's acceleration in m/s^2 (not mm/s^2 or g) within the spring's travel",
        ));
    }
    Ok(())
}

/// Checks that a static record has a loading branch; returns the index range of the
/// first one (successive increases of the compression).
pub fn check_static(record: &StaticRecord) -> Result<std::ops::Range<usize>> {
    let x = &record.displacement_mm;
    let mut best = 0..0;
    let mut start = 0;
    for i in 1..=x.len() {
        let rising = i < x.len() && x[i] > x[i - 1];
        if !rising {
            if i - start > best.len() {
                best = start..i;
            }
            start = i;
        }
    }
    if best.len() < MIN_BRANCH {
        return Err(TuneError::Invalid(format!(
            "{}: no loading branch (the longest run of increasing displacement_mm has {} points)\
             ; expected the compression to grow over at least {MIN_BRANCH} successive points",
            record.file.display(),
            best.len()
        )));
    }
    Ok(best)
}
