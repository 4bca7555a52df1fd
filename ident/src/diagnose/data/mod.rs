//! Conditioning and checking measured records before anything is fitted: a decay record
//! as a lab writes it becomes a uniformly sampled acceleration with its noise floor.
//!
//! # Steps (decay record)
//! 1. **Columns** ([`crate::case::read_decay_record`]): exactly one of `accel_m_s2`,
//!    `velocity_m_s`, `displacement_mm` beside `time_s`, in SI from here on.
//! 2. **Time stamps.** `h` is the median step. Steps within the post-processor's
//!    tolerance (5 % of `h` plus the printing resolution) are uniform: the ideal grid
//!    `t_0 + i h_mean` is used. Steps that jitter by up to [`JITTER_LIMIT`] of `h` (a
//!    data logger at 100 Hz +- 1 ms has steps of 8 to 12 ms, 20 %) are **resampled** to
//!    that grid by cubic Lagrange interpolation on the four nearest stamps (error about
//!    `(w h)^4 / 100` of the amplitude, 1e-4 at 100 Hz for a 5 Hz spring), with a warning.
//!    A step beyond that is an **error naming its line**: one dropped sample makes a step
//!    of `2 h`, which interpolation would fill with an invented sample; the limit sits
//!    halfway between the worst jitter accepted (each stamp within +-h/4) and a lost
//!    sample.
//! 3. **Glitches** (position and velocity only, `despike`): isolated samples far off
//!    the cubic through their neighbours (an ultrasonic sensor's echoes) are replaced,
//!    with a warning. **Flat and clipped** (below): on the measured column.
//! 4. **Impulse left at the start** ([`find_free_decay`]): the record's half-cycles
//!    between zero crossings (with hysteresis) are regular in a free decay (duration
//!    within [`HALF_CYCLE_TOLERANCE`] of the median, a peak no more than
//!    [`PEAK_JUMP`] times the largest of the next three). An impulse leaves irregular
//!    ones at the start: a rest before it (a long first segment), the blow itself (a peak
//!    far above what follows), the ringing of higher modes (short half-cycles). The
//!    record is cut at the zero crossing that ends the last irregular half-cycle within
//!    the first [`START_SHARE`] of the record, and the cut is reported. A free decay
//!    starting anywhere in its phase is not cut (the test checks it on every generated
//!    case).
//! 5. **Length**: at least [`MIN_CYCLES`] cycles after the cut (after an impulse, the
//!    message says the record is all impulse), at most [`MAX_CYCLES`] (a longer record
//!    is refused with the length to cut it to). A record of more than
//!    [`DECIMATE_ABOVE`] samples per period (a 50 kHz logger on a 5 Hz oscillation:
//!    10 000) is **decimated** to the band the model needs: a zero-phase low-pass at
//!    [`DECIMATED_CUTOFF`] times the oscillation's frequency, then every `q`-th sample,
//!    keeping at least [`DECIMATED_PER_PERIOD`] per period, with a warning. The model
//!    steps each sample at least once, so without it a 1 000 000-sample record would
//!    cost 100 times the steps the oscillation needs.
//! 6. **Acceleration**: a velocity or position record is differentiated by
//!    [`coil_postproc::differentiate`] (zero-phase low-pass at 4 times the dominant
//!    frequency, sixth-order central differences; gain and noise in its docs); the
//!    three samples at each end the stencil cannot reach are dropped from every series.
//! 7. **Noise floor** ([`coil_postproc::noise::noise_floor`]): from the Welch spectrum
//!    outside the signal's lines, so that it holds on band-limited records (where the
//!    fourth differences read nearly 0) and on a differentiated position.
//! 8. **A slow line** ([`slow_line`]): a lightly damped oscillation far below the axial
//!    one (another mode of the rig) is found in the measured record, fitted beside
//!    every model as the offset and drift are, and removed from the acceleration the
//!    signatures read, with a warning.
//!
//! # Other checks
//! - **not flat**: at least [`MIN_LEVELS`] distinct values and a non-zero spread;
//! - **not clipped**: a clipped record dwells at its extreme value; if more than
//!   [`CLIP_FRACTION`] of the samples sit within half a quantisation step of the
//!   record's maximum or minimum, the record is refused (a free decay touches its
//!   extremes only at a few crests near the start);
//! - **static record**: a loading branch, i.e. at least [`MIN_BRANCH`] successive
//!   increases of the compression.

mod checks;
mod crossings;
mod free_decay;
mod grid;
pub mod record;
pub mod slow_line;
#[cfg(test)]
mod tests;

pub use checks::{check_amplitude, check_static};
pub use free_decay::find_free_decay;
pub use grid::resample;
pub use record::*;
pub use slow_line::SlowLine;

use checks::check_levels;
use crossings::crossings;
use free_decay::blow_in;
use grid::{despike, uniform_grid};
use record::{bad, post};

use crate::case::{MeasuredDecay, Quantity};
use crate::error::{Result, TuneError};
use coil_postproc::differentiate::Differentiator;
use coil_postproc::filter::{Band, Butterworth};
use coil_postproc::noise::{detrend, noise_floor};
use coil_postproc::signal::Signal;

/// Samples per period of the oscillation at `frequency_hz`.
fn samples_per_period(signal: &Signal, frequency_hz: f64) -> f64 {
    1.0 / (frequency_hz * signal.step_s())
}

/// The record decimated to the band the model needs (module docs, step 6): above
/// [`DECIMATE_ABOVE`] samples per period, a zero-phase Butterworth low-pass at
/// [`DECIMATED_CUTOFF`] times the oscillation's frequency, then every `q`-th sample,
/// `q` the largest integer that keeps at least [`DECIMATED_PER_PERIOD`] samples per
/// period. Returns the record and `q` (`None`: unchanged).
fn decimated(signal: Signal, frequency_hz: f64) -> Result<(Signal, Option<usize>)> {
    let per_period = samples_per_period(&signal, frequency_hz);
    if per_period.is_nan() || per_period <= DECIMATE_ABOVE {
        return Ok((signal, None));
    }
    let q = (per_period / DECIMATED_PER_PERIOD).floor() as usize;
    let lowpass = Butterworth::new(
        Band::Lowpass,
        4,
        DECIMATED_CUTOFF * frequency_hz,
        signal.step_s(),
    )
    .map_err(post)?;
    let filtered = lowpass.filtfilt(signal.values());
    let values: Vec<f64> = filtered.iter().step_by(q).copied().collect();
    let decimated = Signal::uniform(signal.time_s()[0], q as f64 * signal.step_s(), values)
        .map_err(post)?
        .named(signal.source().to_path_buf(), signal.column());
    Ok((decimated, Some(q)))
}

/// Checks an acceleration record already on a uniform grid (module docs, steps 3-7).
pub fn check_decay(signal: Signal) -> Result<DecayData> {
    let n = signal.values().len();
    condition(
        MeasuredDecay {
            file: signal.source().to_path_buf(),
            quantity: Quantity::Acceleration,
            lines: (2..n as u64 + 2).collect(),
            time_s: signal.time_s().to_vec(),
            values: signal.values().to_vec(),
            time_resolution_s: 0.0,
        },
        Some(signal),
    )
}

/// Conditions and checks a decay record as read (module docs).
pub fn condition_decay(record: MeasuredDecay) -> Result<DecayData> {
    condition(record, None)
}

/// A position or velocity record with its isolated sensor glitches replaced
/// ([`despike`]), and a warning naming how many and where.
fn without_glitches(
    signal: Signal,
    record: &MeasuredDecay,
    warnings: &mut Vec<String>,
) -> Result<Signal> {
    let mut values = signal.values().to_vec();
    let glitches = despike(&mut values);
    if !glitches.is_empty() {
        let at: Vec<String> = glitches
            .iter()
            .take(5)
            .map(|&i| format!("{:.3}", signal.time_s()[i]))
            .collect();
        warnings.push(format!(
            "{}: {} isolated outliers (sensor glitches) replaced by the cubic through \
             their neighbours, at t = {} s{}",
            record.file.display(),
            glitches.len(),
            at.join(", "),
            if glitches.len() > 5 { ", ..." } else { "" }
        ));
    }
    signal.with_values(values).map_err(post)
}

fn condition(record: MeasuredDecay, uniform: Option<Signal>) -> Result<DecayData> {
    let mut warnings = Vec::new();
    let (signal, resampled, resolution) = on_grid(&record, uniform, &mut warnings)?;
    let free = free_decay(signal, &record, &mut warnings)?;
    let (signal, decimation) = decimated(free.signal, free.frequency_hz)?;
    let n = signal.values().len();
    if let Some(q) = decimation {
        warnings.push(format!(
            "{}: {} samples at {:.1} samples per period of the {:.4} Hz oscillation; \
             decimated by {q} (zero-phase low-pass at {:.3} Hz first) to {n} samples, \
             {:.1} per period",
            signal.source().display(),
            free.samples,
            q as f64 * samples_per_period(&signal, free.frequency_hz),
            free.frequency_hz,
            DECIMATED_CUTOFF * free.frequency_hz,
            samples_per_period(&signal, free.frequency_hz)
        ));
    }
    let detrended = if decimation.is_some() {
        detrend(signal.values())
    } else {
        free.detrended
    };
    let measured_noise = noise_floor(&detrended);
    let (signal, measured, cutoff) =
        acceleration(signal, record.quantity, free.frequency_hz, &mut warnings)?;
    let (signal, slow_line) = without_slow_line(
        signal,
        &measured,
        record.quantity,
        free.frequency_hz,
        measured_noise.rms,
        &mut warnings,
    )?;
    let noise = noise_floor(signal.values());
    Ok(DecayData {
        signal,
        quantity: record.quantity,
        measured,
        cycles: free.cycles,
        frequency_hz: free.frequency_hz,
        resolution,
        noise,
        measured_noise,
        differentiation_cutoff_hz: cutoff,
        resampled,
        cut: free.cut,
        slow_line,
        warnings,
    })
}

/// Steps 2 and 3 and the flat and clipped checks: the record on its uniform grid,
/// its glitches replaced; returns it, the resampling if one was needed, and the
/// record's resolution.
fn on_grid(
    record: &MeasuredDecay,
    uniform: Option<Signal>,
    warnings: &mut Vec<String>,
) -> Result<(Signal, Option<Resampling>, f64)> {
    let (signal, resampled) = match uniform {
        Some(s) => (s, None),
        None => {
            let (time_s, step_s, values, resampled) = uniform_grid(record)?;
            let grid = Signal::uniform(time_s[0], step_s, values).map_err(post)?;
            (grid, resampled)
        }
    };
    if let Some(r) = &resampled {
        warnings.push(format!(
            "{}: time stamps jitter by up to {:.3e} s about the step {:.6e} s; the record \
             was resampled to a uniform grid (cubic interpolation)",
            record.file.display(),
            r.max_step_deviation_s,
            r.step_s
        ));
    }
    let signal = signal.named(record.file.clone(), record.quantity.column());
    let signal = if record.quantity == Quantity::Acceleration {
        signal
    } else {
        without_glitches(signal, record, warnings)?
    };
    let resolution = check_levels(&signal, record.quantity)?;
    Ok((signal, resampled, resolution))
}

/// The free decay (steps 4 and 5 up to the decimation): the record after the impulse
/// cut from its start, its length checked.
struct FreeDecay {
    signal: Signal,
    /// The record's samples before any decimation.
    samples: usize,
    detrended: Vec<f64>,
    cut: Option<Cut>,
    cycles: usize,
    frequency_hz: f64,
}

/// Step 4 and the length check of step 5 ([`FreeDecay`]).
fn free_decay(
    signal: Signal,
    record: &MeasuredDecay,
    warnings: &mut Vec<String>,
) -> Result<FreeDecay> {
    let detrended = detrend(signal.values());
    let (start, cut) = find_free_decay(&detrended, signal.time_s());
    let signal = match &cut {
        Some(c) => {
            warnings.push(format!(
                "{}: the record starts with the impulse ({}); the first {} samples \
                 (up to t = {:.4} s) were cut, the free decay starts there",
                record.file.display(),
                c.reason,
                c.samples,
                c.time_s
            ));
            signal.slice(start..signal.len()).map_err(post)?
        }
        None => signal,
    };
    let detrended = detrend(signal.values());
    let (crossings, span_s) = crossings(&detrended, signal.time_s());
    let cycles = crossings / 2;
    let n = signal.values().len();
    if cycles < MIN_CYCLES {
        return Err(too_short(&signal, &detrended, cut.as_ref(), cycles));
    }
    let frequency_hz = if span_s > 0.0 {
        (crossings.saturating_sub(1)) as f64 / (2.0 * span_s)
    } else {
        0.0
    };
    if cycles > MAX_CYCLES {
        let keep_s = MAX_CYCLES as f64 / frequency_hz.max(f64::MIN_POSITIVE);
        return Err(bad(
            &signal,
            format!(
                "{cycles} oscillation cycles at {frequency_hz:.4} Hz ({n} samples); the \
                 diagnosis fits at most {MAX_CYCLES} cycles (each fit simulates every cycle \
                 thousands of times); cut the record to its first {keep_s:.1} s"
            ),
            &format!("at most {MAX_CYCLES} cycles"),
        ));
    }
    Ok(FreeDecay {
        signal,
        samples: n,
        detrended,
        cut,
        cycles,
        frequency_hz,
    })
}

/// The error for a record of fewer than [`MIN_CYCLES`] cycles, naming the impulse when
/// one took the rest.
fn too_short(signal: &Signal, detrended: &[f64], cut: Option<&Cut>, cycles: usize) -> TuneError {
    let n = signal.values().len();
    let blow = cut.map(|c| (c.reason.clone(), c.time_s)).or_else(|| {
        blow_in(detrended).map(|i| {
            (
                "a blow with nothing comparable after it".to_string(),
                signal.time_s()[i],
            )
        })
    });
    let duration = signal.time_s()[n - 1] - signal.time_s()[0];
    let what = match &blow {
        Some((reason, at)) => format!(
            "the record is all impulse: after the impulse ({reason}, at t = {at:.4} s) \
             {cycles} oscillation cycles remain in {duration:.3} s"
        ),
        None => format!("{cycles} oscillation cycles in {duration:.3} s"),
    };
    bad(
        signal,
        what,
        &format!("at least {MIN_CYCLES} cycles of the free decay"),
    )
}

/// Step 6: the acceleration, as measured or differentiated from a velocity or a
/// position; returns it, the measured quantity on its grid, and the differentiation's
/// cut-off.
fn acceleration(
    signal: Signal,
    quantity: Quantity,
    frequency_hz: f64,
    warnings: &mut Vec<String>,
) -> Result<(Signal, Vec<f64>, Option<f64>)> {
    let derivatives = quantity.derivatives_to_acceleration();
    if derivatives == 0 {
        let measured = signal.values().to_vec();
        return Ok((signal, measured, None));
    }
    let n = signal.values().len();
    let d = Differentiator::for_dominant(frequency_hz, signal.step_s()).map_err(|e| {
        bad(
            &signal,
            e.to_string(),
            "a record that can be differentiated",
        )
    })?;
    let accel = if derivatives == 1 {
        d.first_derivative(signal.values())
    } else {
        d.second_derivative(signal.values())
    };
    let h = coil_postproc::differentiate::HALF_WIDTH;
    let keep = h..n - h;
    warnings.push(format!(
        "{}: the acceleration is derived from `{}` (zero-phase low-pass at {:.3} Hz, gain \
         {:.5} at the dominant {:.3} Hz; sixth-order central differences)",
        signal.source().display(),
        quantity.column(),
        d.cutoff_hz,
        d.gain(derivatives, frequency_hz),
        frequency_hz
    ));
    let measured = signal.values()[keep.clone()].to_vec();
    let signal = signal
        .slice(keep)
        .and_then(|s| s.with_values(accel))
        .map_err(post)?;
    Ok((signal, measured, Some(d.cutoff_hz)))
}

/// Step 8: a slow line beside the oscillation ([`slow_line`]), said in a warning, and
/// the acceleration without it.
fn without_slow_line(
    signal: Signal,
    measured: &[f64],
    quantity: Quantity,
    frequency_hz: f64,
    noise_rms: f64,
    warnings: &mut Vec<String>,
) -> Result<(Signal, Option<SlowLine>)> {
    let step = signal.step_s();
    let Some(line) = slow_line::find(measured, step, frequency_hz, noise_rms) else {
        return Ok((signal, None));
    };
    warnings.push(slow_line::note(
        &line,
        frequency_hz,
        quantity,
        &signal.source().display().to_string(),
    ));
    let k = quantity.derivatives_to_acceleration();
    let slow = line.derivative(k, step, signal.values().len());
    let values: Vec<f64> = signal
        .values()
        .iter()
        .zip(&slow)
        .map(|(a, s)| a - s)
        .collect();
    Ok((signal.with_values(values).map_err(post)?, Some(line)))
}
