//! Checks that measured records can carry a diagnosis, before anything is computed or
//! written. The readers (`crate::case`, `coil_postproc::signal`) already refuse missing
//! or misnamed columns, non-uniform time and non-finite cells with the file and line;
//! this module adds what a free-decay fit needs:
//!
//! - **length**: at least [`MIN_CYCLES`] cycles of the dominant oscillation, counted
//!   from the zero crossings of the mean-removed record with hysteresis (noise in a
//!   dead band does not count; the decrement and the per-cycle curves need that many;
//!   the paper used every 10th crest);
//! - **not flat**: at least [`MIN_LEVELS`] distinct values and a non-zero spread;
//! - **not clipped**: a clipped record dwells at its extreme value; if more than
//!   [`CLIP_FRACTION`] of the samples sit within half a quantisation step of the
//!   record's maximum or minimum, the record is refused (a free decay touches its
//!   extremes only at a few crests near the start);
//! - **static record**: a loading branch, i.e. at least [`MIN_BRANCH`] successive
//!   increases of the compression.

use super::model::Quantity;
use crate::case::StaticRecord;
use crate::error::{Result, TuneError};
use coil_postproc::signal::Signal;

/// Fewest oscillation cycles in a decay record.
pub const MIN_CYCLES: usize = 20;
/// Fewest distinct values in a decay record.
pub const MIN_LEVELS: usize = 16;
/// Largest share of samples at the record's extremes.
pub const CLIP_FRACTION: f64 = 0.002;
/// Fewest successive increasing points of a static record's loading branch.
pub const MIN_BRANCH: usize = 4;

/// A decay record that passed the checks.
#[derive(Debug, Clone)]
pub struct DecayData {
    pub signal: Signal,
    /// Zero crossings of the mean-removed record (with hysteresis) divided by two.
    pub cycles: usize,
    /// Mean frequency of those crossings (Hz).
    pub frequency_hz: f64,
    /// Smallest step between distinct values (the ADC's resolution, if quantised).
    pub resolution: f64,
    /// The quantity the record measures (the fit compares it as measured).
    pub quantity: Quantity,
    /// The record's own quantity in SI (m/s^2, m/s or m) on `signal`'s time grid,
    /// offset and drift kept (the fit takes them out).
    pub measured: Vec<f64>,
    /// Noise RMS of `measured` (SI); NaN when not estimated (the signatures' estimate
    /// on the acceleration is used then).
    pub measured_noise_rms: f64,
    /// The record's own attached mass (kg), when the case gives one.
    pub mass_kg: Option<f64>,
    /// What conditioning the record needed (resampling, a cut impulse).
    pub warnings: Vec<String>,
}

fn bad(signal: &Signal, problem: String, expected: &str) -> TuneError {
    TuneError::Invalid(format!(
        "{} (column `{}`): {problem}; expected {expected}",
        signal.source.display(),
        signal.column
    ))
}

/// Checks a decay record (module docs).
pub fn check_decay(signal: Signal) -> Result<DecayData> {
    let x = &signal.values;
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n.max(1) as f64;
    let spread = (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n.max(1) as f64).sqrt();
    let mut sorted = x.clone();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    if spread == 0.0 || sorted.len() < MIN_LEVELS {
        return Err(bad(
            &signal,
            format!(
                "the signal is flat ({} distinct values, standard deviation {spread:.3e})",
                sorted.len()
            ),
            "a free decay of the weight's acceleration",
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
            &signal,
            format!(
                "{at_extremes} of {n} samples sit at the extremes {lo} / {hi}: the signal is clipped"
            ),
            "a record within the sensor's range (lower the gain or the impulse)",
        ));
    }
    let (crossings, span_s) = crossings(&signal, mean);
    let cycles = crossings / 2;
    if cycles < MIN_CYCLES {
        return Err(bad(
            &signal,
            format!(
                "{cycles} oscillation cycles in {:.3} s",
                signal.time_s[n - 1] - signal.time_s[0]
            ),
            &format!("at least {MIN_CYCLES} cycles of the free decay"),
        ));
    }
    Ok(DecayData {
        quantity: Quantity::Acceleration,
        measured: signal.values.clone(),
        measured_noise_rms: f64::NAN,
        mass_kg: None,
        warnings: Vec::new(),
        frequency_hz: if span_s > 0.0 {
            (crossings.saturating_sub(1)) as f64 / (2.0 * span_s)
        } else {
            0.0
        },
        signal,
        cycles,
        resolution,
    })
}

/// Zero crossings of the oscillation about `mean` with hysteresis, and the time between
/// the first and the last: a crossing counts only once the signal has gone beyond
/// `+-h` on the other side, `h` the larger of 5 % of the largest excursion and four
/// standard deviations of the noise (the post-processor's robust estimate from fourth
/// differences, which a sampled oscillation barely reaches at 10 or more samples per
/// cycle), so noise in a dead band or after the decay does not count as cycles.
fn crossings(signal: &Signal, mean: f64) -> (usize, f64) {
    let x = &signal.values;
    let peak = x.iter().fold(0.0_f64, |m, v| m.max((v - mean).abs()));
    let sigma = coil_postproc::peaks::noise_rms(x);
    let h = (0.05 * peak).max(4.0 * sigma);
    let mut side = 0i8;
    let mut count = 0;
    let (mut first, mut last) = (f64::NAN, f64::NAN);
    for (v, t) in x.iter().zip(&signal.time_s) {
        let now = if v - mean > h {
            1
        } else if v - mean < -h {
            -1
        } else {
            0
        };
        if now != 0 && now != side {
            if side != 0 {
                count += 1;
                if first.is_nan() {
                    first = *t;
                }
                last = *t;
            }
            side = now;
        }
    }
    let span = if count > 1 { last - first } else { 0.0 };
    (count, span)
}

/// Checks the decay's size against the spring: its displacement amplitude, the peak
/// acceleration over `(2 pi f)^2` at the record's mean crossing frequency, must fit in
/// the coils' free travel `n (h - d)` (beyond it the coils touch; a record that claims
/// more is in the wrong unit, e.g. mm/s^2 for m/s^2).
pub fn check_amplitude(decay: &DecayData, case: &crate::case::MeasuredCase) -> Result<()> {
    let x = &decay.signal.values;
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn signal(values: Vec<f64>, dt: f64) -> Signal {
        Signal {
            source: PathBuf::from("decay.csv"),
            column: "accel_m_s2".into(),
            time_s: (0..values.len()).map(|i| i as f64 * dt).collect(),
            step_s: dt,
            values,
        }
    }

    fn decay(cycles: f64, clip: f64) -> Vec<f64> {
        let n = 4000;
        (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                let x = (-t).exp() * (std::f64::consts::TAU * cycles * t + 0.3).sin();
                (x.clamp(-clip, clip) * 3000.0).round() / 3000.0
            })
            .collect()
    }

    #[test]
    fn a_decay_passes() {
        let d = check_decay(signal(decay(40.0, 2.0), 1e-3)).unwrap();
        assert!((39..=41).contains(&d.cycles));
    }

    #[test]
    fn a_coarsely_sampled_noisy_decay_counts_its_cycles() {
        // 14 samples per cycle (a 35 Hz spring at 500 Hz) with 1 % noise: the hysteresis
        // must follow the noise, not the signal's sample-to-sample slope.
        let mut seed = 7_u64;
        let mut noise = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let n = 1000;
        let values = (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                (-t).exp() * (std::f64::consts::TAU * 71.0 * t).sin() + 0.035 * noise()
            })
            .collect();
        let d = check_decay(signal(values, 2e-3)).unwrap();
        assert!((69..=72).contains(&d.cycles), "{}", d.cycles);
        assert!((d.frequency_hz - 35.5).abs() < 0.5, "{}", d.frequency_hz);
    }

    #[test]
    fn short_flat_and_clipped_records_are_refused() {
        let short = check_decay(signal(decay(10.0, 2.0), 1e-3)).unwrap_err();
        assert!(short.to_string().contains("cycles"), "{short}");
        let flat = check_decay(signal(vec![0.5; 1000], 1e-3)).unwrap_err();
        assert!(flat.to_string().contains("flat"), "{flat}");
        let clipped = check_decay(signal(decay(40.0, 0.5), 1e-3)).unwrap_err();
        assert!(clipped.to_string().contains("clipped"), "{clipped}");
    }

    #[test]
    fn static_record_needs_a_loading_branch() {
        let record = |x: Vec<f64>| StaticRecord {
            file: PathBuf::from("static.csv"),
            force_n: x.clone(),
            displacement_mm: x,
        };
        let r = record(vec![0.0, 1.0, 2.0, 3.0, 4.0, 3.0, 2.0]);
        assert_eq!(check_static(&r).unwrap(), 0..5);
        let e = check_static(&record(vec![4.0, 3.0, 2.0, 1.0, 0.0])).unwrap_err();
        assert!(e.to_string().contains("no loading branch"), "{e}");
    }
}
