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
//!    message says the record is all impulse).
//! 6. **Acceleration**: a velocity or position record is differentiated by
//!    [`coil_postproc::differentiate`] (zero-phase low-pass at 4 times the dominant
//!    frequency, sixth-order central differences; gain and noise in its docs); the
//!    three samples at each end the stencil cannot reach are dropped from every series.
//! 7. **Noise floor** ([`coil_postproc::noise::noise_floor`]): from the Welch spectrum
//!    outside the signal's lines, so that it holds on band-limited records (where the
//!    fourth differences read nearly 0) and on a differentiated position.
//!
//! # Other checks
//! - **not flat**: at least [`MIN_LEVELS`] distinct values and a non-zero spread;
//! - **not clipped**: a clipped record dwells at its extreme value; if more than
//!   [`CLIP_FRACTION`] of the samples sit within half a quantisation step of the
//!   record's maximum or minimum, the record is refused (a free decay touches its
//!   extremes only at a few crests near the start);
//! - **static record**: a loading branch, i.e. at least [`MIN_BRANCH`] successive
//!   increases of the compression.

use crate::case::{MeasuredDecay, Quantity, StaticRecord};
use crate::error::{Result, TuneError};
use coil_postproc::differentiate::Differentiator;
use coil_postproc::noise::{detrend, noise_floor, NoiseFloor};
use coil_postproc::signal::Signal;
use serde::Serialize;

/// Fewest oscillation cycles in a decay record.
pub const MIN_CYCLES: usize = 20;
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
    /// What the conditioning did, in words (resampling, cut, differentiation).
    pub warnings: Vec<String>,
}

/// A record that failed a check of the post-processor's signal.
fn post(source: coil_postproc::PostError) -> TuneError {
    TuneError::Post {
        context: "the decay record".to_string(),
        source,
    }
}

fn bad(signal: &Signal, problem: String, expected: &str) -> TuneError {
    TuneError::Invalid(format!(
        "{} (column `{}`): {problem}; expected {expected}",
        signal.source().display(),
        signal.column()
    ))
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
    let column = record.quantity.column();
    let (signal, resampled) = match uniform {
        Some(s) => (s, None),
        None => {
            let (time_s, step_s, values, resampled) = uniform_grid(&record)?;
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
    let signal = signal.named(record.file.clone(), column);
    let signal = if record.quantity == Quantity::Acceleration {
        signal
    } else {
        without_glitches(signal, &record, &mut warnings)?
    };
    let resolution = check_levels(&signal, record.quantity)?;

    // The impulse, then the length.
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
        let blow = cut
            .as_ref()
            .map(|c| (c.reason.clone(), c.time_s))
            .or_else(|| {
                blow_in(&detrended).map(|i| {
                    (
                        "a blow with nothing comparable after it".to_string(),
                        signal.time_s()[i],
                    )
                })
            });
        let what = match &blow {
            Some((reason, at)) => format!(
                "the record is all impulse: after the impulse ({reason}, at t = {at:.4} s) \
                 {cycles} oscillation cycles remain in {:.3} s",
                signal.time_s()[n - 1] - signal.time_s()[0]
            ),
            None => format!(
                "{cycles} oscillation cycles in {:.3} s",
                signal.time_s()[n - 1] - signal.time_s()[0]
            ),
        };
        return Err(bad(
            &signal,
            what,
            &format!("at least {MIN_CYCLES} cycles of the free decay"),
        ));
    }
    let frequency_hz = if span_s > 0.0 {
        (crossings.saturating_sub(1)) as f64 / (2.0 * span_s)
    } else {
        0.0
    };

    // The acceleration.
    let derivatives = record.quantity.derivatives_to_acceleration();
    let measured_noise = noise_floor(&detrended);
    let (signal, measured, cutoff) = if derivatives == 0 {
        let measured = signal.values().to_vec();
        (signal, measured, None)
    } else {
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
            "{}: the acceleration is derived from `{column}` (zero-phase low-pass at \
             {:.3} Hz, gain {:.5} at the dominant {:.3} Hz; sixth-order central \
             differences)",
            signal.source().display(),
            d.cutoff_hz,
            d.gain(derivatives, frequency_hz),
            frequency_hz
        ));
        let measured = signal.values()[keep.clone()].to_vec();
        (
            signal
                .slice(keep)
                .and_then(|s| s.with_values(accel))
                .map_err(post)?,
            measured,
            Some(d.cutoff_hz),
        )
    };
    let noise = noise_floor(signal.values());
    Ok(DecayData {
        signal,
        quantity: record.quantity,
        measured,
        cycles,
        frequency_hz,
        resolution,
        noise,
        measured_noise,
        differentiation_cutoff_hz: cutoff,
        resampled,
        cut,
        warnings,
    })
}

/// The uniform time axis of a record (module docs, step 2): its times, step, values and
/// the resampling if one was needed.
type Grid = (Vec<f64>, f64, Vec<f64>, Option<Resampling>);

fn uniform_grid(r: &MeasuredDecay) -> Result<Grid> {
    let n = r.time_s.len();
    let steps: Vec<f64> = r.time_s.windows(2).map(|w| w[1] - w[0]).collect();
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let mean = (r.time_s[n - 1] - r.time_s[0]) / (n - 1) as f64;
    let grid: Vec<f64> = (0..n).map(|i| r.time_s[0] + i as f64 * mean).collect();
    let strict = STEP_TOLERANCE * median + r.time_resolution_s.min(0.45 * median);
    let deviation = |s: &f64| (s - median).abs();
    let worst = steps.iter().map(deviation).fold(0.0, f64::max);
    if worst <= strict {
        return Ok((grid, mean, r.values.clone(), None));
    }
    if let Some(i) = steps
        .iter()
        .position(|s| deviation(s) > JITTER_LIMIT * median)
    {
        return Err(TuneError::Invalid(format!(
            "{}:{}: a time step of {:.6e} s after time_s = {} against the median step \
             {median:.6e} s (a gap: a dropped sample or a pause); expected steps within \
             {:.0} % of the median (jitter is resampled, a gap cannot be filled)",
            r.file.display(),
            r.lines[i + 1],
            steps[i],
            r.time_s[i],
            100.0 * JITTER_LIMIT
        )));
    }
    let values = resample(&r.time_s, &r.values, &grid);
    Ok((
        grid,
        mean,
        values,
        Some(Resampling {
            step_s: mean,
            max_step_deviation_s: worst,
        }),
    ))
}

/// Cubic Lagrange interpolation of `(t, x)` (increasing t) at `grid` on the four nearest
/// stamps (clamped at the ends).
pub fn resample(t: &[f64], x: &[f64], grid: &[f64]) -> Vec<f64> {
    let n = t.len();
    let mut j = 0;
    grid.iter()
        .map(|&g| {
            while j + 2 < n && t[j + 1] <= g {
                j += 1;
            }
            if n < 4 {
                return x[j];
            }
            let first = j.saturating_sub(1).min(n - 4);
            let nodes = first..first + 4;
            nodes
                .clone()
                .map(|a| {
                    let weight: f64 = nodes
                        .clone()
                        .filter(|&b| b != a)
                        .map(|b| (g - t[b]) / (t[a] - t[b]))
                        .product();
                    weight * x[a]
                })
                .sum()
        })
        .collect()
}

/// Replaces isolated outliers of a position or velocity record (an ultrasonic sensor's
/// glitches: one to three samples tens of mm off) and returns their indices. Each sample
/// is predicted by the cubic through the two nearest good samples on each side (with
/// its direct neighbours, `p_i = (-x_{i-2} + 4 x_{i-1} + 4 x_{i+1} - x_{i+2}) / 6`; error
/// `(w dt)^4 A / 6` on a sinusoid: 1e-5 of the amplitude at 70 samples per cycle, 1e-2
/// at 10). The largest residual beyond [`GLITCH_SIGMAS`] robust standard deviations of
/// all residuals (1.4826 times their median absolute value) marks its sample bad, the
/// neighbours are predicted again without it, and the search repeats; the bad samples
/// are then replaced by their predictions. A record with more than [`MAX_GLITCH_SHARE`] of such samples is not a
/// record with glitches but a noisy one: it is left as it is. Accelerometer records are
/// not touched (a hammer blow or a friction jump is physics, not a glitch).
fn despike(x: &mut [f64]) -> Vec<usize> {
    let n = x.len();
    if n < 16 {
        return Vec::new();
    }
    // The cubic through the two nearest good samples on each side, at i.
    let predict = |x: &[f64], bad: &[bool], i: usize| -> Option<f64> {
        let left: Vec<usize> = (0..i).rev().filter(|&j| !bad[j]).take(2).collect();
        let right: Vec<usize> = (i + 1..n).filter(|&j| !bad[j]).take(2).collect();
        if left.len() < 2 || right.len() < 2 {
            return None;
        }
        let nodes = [left[1], left[0], right[0], right[1]];
        Some(
            nodes
                .iter()
                .map(|&a| {
                    let w: f64 = nodes
                        .iter()
                        .filter(|&&b| b != a)
                        .map(|&b| (i as f64 - b as f64) / (a as f64 - b as f64))
                        .product();
                    w * x[a]
                })
                .sum(),
        )
    };
    let mut bad = vec![false; n];
    let mut abs: Vec<f64> = (2..n - 2)
        .filter_map(|i| predict(x, &bad, i).map(|p| (x[i] - p).abs()))
        .collect();
    abs.sort_by(f64::total_cmp);
    let sigma = 1.4826 * abs[abs.len() / 2];
    if sigma <= 0.0 {
        return Vec::new();
    }
    let limit = GLITCH_SIGMAS * sigma;
    let mut residual: Vec<f64> = (0..n)
        .map(|i| predict(x, &bad, i).map_or(0.0, |p| (x[i] - p).abs()))
        .collect();
    let mut replaced = Vec::new();
    loop {
        let (worst, size) = residual
            .iter()
            .enumerate()
            .filter(|(i, _)| !bad[*i])
            .fold((0, 0.0_f64), |a, (i, &r)| if r > a.1 { (i, r) } else { a });
        if size <= limit {
            break;
        }
        if replaced.len() as f64 >= MAX_GLITCH_SHARE * n as f64 {
            return Vec::new();
        }
        bad[worst] = true;
        replaced.push(worst);
        // Only the neighbours' predictions changed.
        for i in worst.saturating_sub(4)..(worst + 5).min(n) {
            residual[i] = predict(x, &bad, i).map_or(0.0, |p| (x[i] - p).abs());
        }
    }
    let fixed: Vec<(usize, f64)> = replaced
        .iter()
        .filter_map(|&i| predict(x, &bad, i).map(|p| (i, p)))
        .collect();
    for (i, p) in fixed {
        x[i] = p;
    }
    replaced.sort_unstable();
    replaced
}

/// Flat and clipped checks (module docs); returns the resolution.
fn check_levels(signal: &Signal, quantity: Quantity) -> Result<f64> {
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

/// The hysteresis of the crossings: the larger of 5 % of the record's 99th-percentile
/// excursion (a blow of a few samples does not set it) and four standard deviations of
/// the noise (the spectral floor, which a band-limited record does not hide).
fn hysteresis(y: &[f64]) -> f64 {
    let mut abs: Vec<f64> = y.iter().map(|v| v.abs()).collect();
    abs.sort_by(f64::total_cmp);
    let p99 = abs[((abs.len() as f64 * 0.99) as usize).min(abs.len() - 1)];
    (0.05 * p99).max(4.0 * noise_floor(y).rms)
}

/// Zero crossings of `y` with hysteresis ([`hysteresis`]): a crossing counts only once the
/// signal has gone beyond `+-h` on the other side. Returns, per crossing, the index of
/// the first sample past the zero and the interpolated zero time.
fn zero_crossings(y: &[f64], time_s: &[f64]) -> Vec<(usize, f64)> {
    let h = hysteresis(y);
    let mut side = 0i8;
    let mut last_zero = (0usize, time_s[0]);
    let mut out = Vec::new();
    for i in 0..y.len() {
        if i > 0 && (y[i - 1] < 0.0) != (y[i] < 0.0) {
            let (a, b) = (y[i - 1], y[i]);
            let f = if a == b { 0.0 } else { a / (a - b) };
            last_zero = (i, time_s[i - 1] + f * (time_s[i] - time_s[i - 1]));
        }
        let now = if y[i] > h {
            1
        } else if y[i] < -h {
            -1
        } else {
            0
        };
        if now != 0 && now != side {
            if side != 0 {
                out.push(last_zero);
            }
            side = now;
        }
    }
    out
}

/// The count of crossings and the time between the first and the last.
fn crossings(y: &[f64], time_s: &[f64]) -> (usize, f64) {
    let c = zero_crossings(y, time_s);
    let span = if c.len() > 1 {
        c[c.len() - 1].1 - c[0].1
    } else {
        0.0
    };
    (c.len(), span)
}

/// The end of a blow too short to leave half-cycles: the sample after the largest
/// excursion where the record first falls below 1/[`PEAK_JUMP`] of it, if nothing after
/// that reaches it again (a decay's next crest always does).
fn blow_in(y: &[f64]) -> Option<usize> {
    let (top, peak) = y.iter().enumerate().fold((0, 0.0_f64), |(i, m), (j, v)| {
        if v.abs() > m {
            (j, v.abs())
        } else {
            (i, m)
        }
    });
    let end = top + y[top..].iter().position(|v| v.abs() < peak / PEAK_JUMP)?;
    let after = y[end..].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    (after < peak / PEAK_JUMP).then_some(end)
}

/// Where the free decay starts in the detrended record `y` (module docs, step 4): the
/// index of the first sample kept and the cut, or 0 and None.
pub fn find_free_decay(y: &[f64], time_s: &[f64]) -> (usize, Option<Cut>) {
    let c = zero_crossings(y, time_s);
    if c.len() < 8 {
        return (0, None);
    }
    let mut durations: Vec<f64> = c.windows(2).map(|w| w[1].1 - w[0].1).collect();
    durations.sort_by(f64::total_cmp);
    let half = durations[durations.len() / 2];
    // Segment k ends at crossing k; segment 0 starts with the record.
    let bounds: Vec<(usize, f64)> = std::iter::once((0, time_s[0]))
        .chain(c.iter().copied())
        .collect();
    let peaks: Vec<f64> = bounds
        .windows(2)
        .map(|w| {
            y[w[0].0..w[1].0]
                .iter()
                .fold(0.0_f64, |m, v| m.max(v.abs()))
        })
        .collect();
    let limit = time_s[0] + START_SHARE * (time_s[time_s.len() - 1] - time_s[0]);
    let mut last = None;
    // The blow: a peak 1.5 times anything after it (a beat or a fast decay never is).
    let mut later = 0.0_f64;
    let mut blow = None;
    for k in (0..peaks.len()).rev() {
        if bounds[k].1 <= limit && peaks[k] > PEAK_JUMP * later && blow.is_none() {
            blow = Some(k);
        }
        later = later.max(peaks[k]);
    }
    if let Some(k) = blow {
        let next = peaks[k + 1..].iter().fold(0.0_f64, |m, &p| m.max(p));
        last = Some((
            k,
            format!(
                "a peak {:.1} times anything after it at t = {:.4} s",
                peaks[k] / next,
                bounds[k].1
            ),
        ));
    }
    // A rest before it: the first segment longer than a half-cycle.
    let first = bounds[1].1 - bounds[0].1;
    if last.is_none() && first > (1.0 + HALF_CYCLE_TOLERANCE) * half {
        last = Some((
            0,
            format!("{first:.3} s without a crossing where a half-cycle lasts {half:.3} s"),
        ));
    }
    // The ringing of higher modes right after it: short half-cycles.
    if let Some((mut k, reason)) = last.take() {
        while k + 1 < peaks.len()
            && bounds[k + 1].1 <= limit
            && bounds[k + 2].1 - bounds[k + 1].1 < (1.0 - HALF_CYCLE_TOLERANCE) * half
        {
            k += 1;
        }
        last = Some((k, reason));
    }
    match last {
        Some((k, reason)) => {
            let index = bounds[k + 1].0;
            (
                index,
                Some(Cut {
                    samples: index,
                    time_s: time_s[index],
                    reason,
                }),
            )
        }
        None => (0, None),
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn signal(values: Vec<f64>, dt: f64) -> Signal {
        Signal::uniform(0.0, dt, values)
            .unwrap()
            .named(PathBuf::from("decay.csv"), "accel_m_s2")
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

    /// Seeded uniform numbers in [-0.5, 0.5) (a 64-bit LCG).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    /// A 4.35 Hz position decay (mm in the file, m here), amplitude 4 mm, zeta 0.002.
    fn position_m(t: f64) -> f64 {
        let w = std::f64::consts::TAU * 4.35;
        4e-3 * (-0.002 * w * t).exp() * (w * t + 0.7).sin()
    }

    fn record(quantity: Quantity, time_s: Vec<f64>, values: Vec<f64>) -> MeasuredDecay {
        MeasuredDecay {
            file: PathBuf::from("decay.csv"),
            quantity,
            lines: (2..time_s.len() as u64 + 2).collect(),
            time_s,
            values,
            time_resolution_s: 1e-6,
        }
    }

    /// 100 Hz +- 1 ms stamps, the values taken at the jittered times: resampled with a
    /// warning, and the acceleration derived from the quantised (0.01 mm) position
    /// matches the closed form to the differentiation's predicted noise (3 sigma) plus
    /// the interpolation error.
    #[test]
    fn jittered_position_is_resampled_and_differentiated() {
        let mut seed = 5;
        let n = 4000;
        let time_s: Vec<f64> = (0..n)
            .map(|i| i as f64 * 0.01 + 0.001 + 0.002 * lcg(&mut seed))
            .collect();
        let q = 1e-5;
        let values: Vec<f64> = time_s
            .iter()
            .map(|&t| (position_m(t) / q).round() * q)
            .collect();
        let d = condition_decay(record(Quantity::Displacement, time_s, values)).unwrap();
        let r = d.resampled.as_ref().expect("resampled");
        assert!(r.max_step_deviation_s > 1e-3 && r.max_step_deviation_s <= 2e-3);
        assert!(d.warnings.iter().any(|w| w.contains("resampled")));
        assert!(d.cut.is_none(), "{:?}", d.cut);
        assert_eq!(d.signal.values().len(), n - 6);
        assert_eq!(d.measured.len(), n - 6);
        let w = std::f64::consts::TAU * 4.35;
        let peak = 4e-3 * w * w;
        let errors: Vec<f64> = d
            .signal
            .time_s()
            .iter()
            .zip(d.signal.values())
            .skip(100)
            .take(n - 206)
            .map(|(&t, &a)| {
                // The exact second derivative of the damped sinusoid.
                let h = 1e-4;
                let exact = (position_m(t + h) - 2.0 * position_m(t) + position_m(t - h)) / (h * h);
                a - exact
            })
            .collect();
        let worst = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
        let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
        println!(
            "accel error rms {rms:.3e}, worst {worst:.3e} of peak {peak:.3}; noise floor {:.3e}",
            d.noise.rms
        );
        assert!(rms < 0.005 * peak, "{rms}");
        assert!(
            (d.noise.rms / rms - 1.0).abs() < 0.5,
            "{} vs {rms}",
            d.noise.rms
        );
    }

    /// A gap (one dropped sample, a step of 2 h) is an error naming its line and the
    /// limit.
    #[test]
    fn a_gap_is_an_error_naming_the_line() {
        let time_s: Vec<f64> = (0..3000)
            .filter(|&i| i != 1200)
            .map(|i| i as f64 * 0.01)
            .collect();
        let values = time_s.iter().map(|&t| position_m(t)).collect();
        let e = condition_decay(record(Quantity::Displacement, time_s, values)).unwrap_err();
        let e = e.to_string();
        assert!(
            e.contains("decay.csv:1202:") && e.contains("gap") && e.contains("50 %"),
            "{e}"
        );
    }

    /// A record whose ADC sits before the blow: a rest, a half-sine blow 10 times the
    /// decay's peak, ringing at 9 f0: the cut lands within a few half-cycles after the
    /// blow; the same decay without the blow, started at any phase, is not cut.
    #[test]
    fn the_impulse_is_cut_and_a_plain_decay_is_not() {
        let fs = 500.0;
        let w = std::f64::consts::TAU * 4.35;
        let (rest, blow) = (0.3, 0.004);
        let n = 10_000;
        let mut seed = 9;
        let time_s: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
        let accel: Vec<f64> = time_s
            .iter()
            .map(|&t| {
                let noise = 0.01 * lcg(&mut seed);
                if t < rest {
                    return noise;
                }
                let s = t - rest;
                let spike = if s < blow {
                    10.0 * (std::f64::consts::PI * s / blow).sin()
                } else {
                    0.0
                };
                let ring = 0.8 * (-30.0 * s).exp() * (9.0 * w * s).sin();
                spike + ring - (-0.002 * w * s).exp() * (w * s).sin() + noise
            })
            .collect();
        let d = condition_decay(record(Quantity::Acceleration, time_s.clone(), accel)).unwrap();
        let cut = d.cut.as_ref().expect("a cut");
        println!("{cut:?}");
        assert!(
            cut.time_s > rest + blow && cut.time_s < rest + 0.5,
            "{cut:?}"
        );
        assert!(d.warnings.iter().any(|w| w.contains("impulse")));
        for phase in [0.0, 0.8, 1.6, 2.4, 3.2, 4.0, 4.8, 5.6] {
            let plain: Vec<f64> = time_s
                .iter()
                .map(|&t| (-0.004 * w * t).exp() * (w * t + phase).sin() + 0.01 * lcg(&mut seed))
                .collect();
            let d = condition_decay(record(Quantity::Acceleration, time_s.clone(), plain)).unwrap();
            assert!(d.cut.is_none(), "phase {phase}: {:?}", d.cut);
        }
        // A position at rest, then the decay: cut at the first crossing after the rest.
        let position: Vec<f64> = time_s
            .iter()
            .map(|&t| if t < rest { 0.0 } else { position_m(t - rest) } + 1e-6 * lcg(&mut seed))
            .collect();
        let d = condition_decay(record(Quantity::Displacement, time_s.clone(), position)).unwrap();
        let cut = d.cut.as_ref().expect("a cut");
        assert!(cut.time_s > rest && cut.time_s < rest + 0.2, "{cut:?}");
    }

    /// Glitches of a position record (one sample 40 mm off, two successive ones 25 and
    /// 15 mm off, on a 4 mm decay quantised to 0.01 mm) are replaced to within 0.05 mm
    /// of the truth; the same record without them, and the accelerometer's, are not
    /// touched.
    #[test]
    fn position_glitches_are_replaced() {
        let fs = 100.0;
        let q = 1e-5;
        let clean: Vec<f64> = (0..4000)
            .map(|i| (position_m(i as f64 / fs) / q).round() * q)
            .collect();
        let mut x = clean.clone();
        assert!(despike(&mut x).is_empty());
        assert_eq!(x, clean);
        x[500] += 0.04;
        x[1700] += 0.025;
        x[1701] += 0.015;
        let replaced = despike(&mut x);
        println!("{replaced:?}");
        for i in [500, 1700, 1701] {
            assert!(replaced.contains(&i), "{replaced:?}");
        }
        assert!(replaced.len() <= 5, "{replaced:?}");
        for &i in &replaced {
            assert!(
                (x[i] - clean[i]).abs() < 5e-5,
                "{i}: {} vs {}",
                x[i],
                clean[i]
            );
        }
        let time_s: Vec<f64> = (0..4000).map(|i| i as f64 / fs).collect();
        let mut glitchy = clean.clone();
        glitchy[500] += 0.04;
        let d = condition_decay(record(Quantity::Displacement, time_s, glitchy)).unwrap();
        assert!(d.warnings.iter().any(|w| w.contains("1 isolated outliers")));
    }

    /// A record that is all impulse (a blow and 10 cycles of ringing down) is refused as
    /// such.
    #[test]
    fn a_record_that_is_all_impulse_is_refused() {
        let fs = 500.0;
        let w = std::f64::consts::TAU * 4.35;
        let mut seed = 3;
        let time_s: Vec<f64> = (0..3000).map(|i| i as f64 / fs).collect();
        let accel: Vec<f64> = time_s
            .iter()
            .map(|&t| {
                let s = t - 0.3;
                let v = if s < 0.0 {
                    0.0
                } else if s < 0.004 {
                    10.0 * (std::f64::consts::PI * s / 0.004).sin()
                } else {
                    (-0.25 * w * s).exp() * (w * s).sin()
                };
                v + 0.002 * lcg(&mut seed)
            })
            .collect();
        let e = condition_decay(record(Quantity::Acceleration, time_s, accel)).unwrap_err();
        assert!(e.to_string().contains("all impulse"), "{e}");
    }

    /// Band-limited noise (the record low-passed at 3 f0 after the noise was added): the
    /// noise floor is the filtered noise's, where the fourth differences read nearly 0.
    #[test]
    fn noise_floor_on_a_band_limited_record() {
        let fs = 500.0;
        let n = 12_500;
        let mut seed = 21;
        let noise: Vec<f64> = (0..n)
            .map(|_| 0.02 * lcg(&mut seed) * 12f64.sqrt())
            .collect();
        let filtered =
            coil_postproc::filter::lowpass_zero_phase(&noise, 1.0 / fs, 13.0, 2).unwrap();
        let w = std::f64::consts::TAU * 4.35;
        let time_s: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
        let accel: Vec<f64> = time_s
            .iter()
            .zip(&filtered)
            .map(|(&t, e)| (-0.002 * w * t).exp() * (w * t).sin() + e)
            .collect();
        let d = condition_decay(record(Quantity::Acceleration, time_s, accel)).unwrap();
        let truth = (filtered.iter().map(|e| e * e).sum::<f64>() / n as f64).sqrt();
        println!(
            "noise floor {:.4e}, fourth differences {:.4e}, truth {truth:.4e}",
            d.noise.rms, d.noise.white_rms
        );
        assert!((d.noise.rms / truth - 1.0).abs() < 0.1);
        assert!(d.noise.white_rms < 0.2 * truth);
    }

    /// The shared real recordings (position at 100 Hz, 0.1 mm), when the folder exists:
    /// what the conditioning does to them (no impulse to cut: they start after the
    /// release; uniform stamps; the derived acceleration's and the position's noise).
    /// `cargo test -p coil-ident --lib real_recordings -- --ignored --nocapture` (the
    /// folder is `../shared/real` beside the repository, or `$COIL_SHARED_REAL`).
    #[test]
    #[ignore = "reads the shared real recordings when they exist"]
    fn real_recordings_are_conditioned() {
        let root = std::env::var_os("COIL_SHARED_REAL")
            .map(PathBuf::from)
            .unwrap_or_else(|| {
                std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/real")
            });
        let Ok(entries) = std::fs::read_dir(&root) else {
            println!("no {}: skipped", root.display());
            return;
        };
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path().join("position.csv")))
            .filter(|p| p.is_file())
            .collect();
        files.sort();
        for file in files {
            let r = crate::case::read_decay_record(&file).unwrap();
            let d = condition_decay(r).unwrap();
            println!(
                "{}: {} samples, {} cycles at {:.4} Hz, cut {:?}, resampled {:?}, \
                 cut-off {:?} Hz, position noise {:.3e} m (fourth differences {:.3e}), \
                 acceleration noise {:.3e} m/s^2 of rms {:.3e}",
                file.display(),
                d.signal.values().len(),
                d.cycles,
                d.frequency_hz,
                d.cut,
                d.resampled,
                d.differentiation_cutoff_hz,
                d.measured_noise.rms,
                d.measured_noise.white_rms,
                d.noise.rms,
                (d.signal.values().iter().map(|a| a * a).sum::<f64>()
                    / d.signal.values().len() as f64)
                    .sqrt()
            );
            for w in &d.warnings {
                println!("  {w}");
            }
            assert!(d.cut.is_none());
        }
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
