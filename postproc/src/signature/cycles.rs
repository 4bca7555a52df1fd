//! Cycles of a free decay: the record cut at its upward zero crossings, each cycle's
//! fundamental amplitude and frequency.
//!
//! # Formulation
//!
//! The record (mean removed) is band-passed around its dominant spectral peak `f_0` (when
//! the spectrum shows no regular peak within [`AGREEMENT`] of the zero-crossing rate, a
//! line swept over many bins by a strong nonlinearity, `f_0` is that rate,
//! [`crossing_frequency`]), from
//! `(1 - b) f_0` to `(1 + b) f_0` (zero-phase Butterworth of [`crate::filter`]; `b` is
//! [`CycleOptions::band`], default 0.5 so that a second line within 0.7-1.3 `f_0` is kept
//! and beats with the first; `None` skips the filter). The band keeps the fundamental and
//! removes the harmonics that friction (a square wave in the acceleration) and a cubic or
//! preloaded spring put at `2 f`, `3 f`. It is cut into cycles at its upward zero crossings,
//! found with hysteresis (`3` times the in-band noise) and located by a least-squares line
//! over +-1/16 period around each crossing. Over each cycle `[c_k, c_{k+1}]` a Fourier
//! series `c + sum_{h=1..3} (a_h cos h theta + b_h sin h theta)`,
//! `theta = 2 pi (t - c_k) / (c_{k+1} - c_k)`, is fitted by least squares; the cycle's
//! acceleration amplitude is `sqrt(a_1^2 + b_1^2)` divided by the filter's forward-backward
//! gain `|H(f_k)|^2` at the cycle's frequency `f_k = 1 / (c_{k+1} - c_k)` (so the filter's
//! pass-band droop does not bias amplitudes). By harmonic balance the fundamental of the
//! acceleration is `-(2 pi f)^2` times the fundamental of the displacement, so
//! `A_k = a_k / (2 pi f)^2`, with `f` the mean of the frequencies of cycles `k-2..k+2`
//! (crossing jitter would otherwise enter `A` twice). Cycles within half the filter's settling
//! length of either end ([`crate::filter::Butterworth::settle_samples`]), cycles whose length
//! is more than 25% from the median, and cycles below 5 standard errors are dropped. The
//! standard error of an amplitude is `s sqrt(2 / n)` for `n` samples of white noise of
//! deviation `s` (the robust estimate of [`crate::stats::noise_rms`]); band-passing does not
//! change it, since the noise near `f` passes the filter.
//!
//! With dry friction the fundamental also has a quadrature part `4 F / (pi m)`, which raises
//! `a_k` by the factor `sqrt(1 + (a_0 / (pi A))^2)`: 0.4% at `A = 5 a_0`, 2.5% at `2 a_0`.
//!
//! # Units and signs
//! The input is the axial acceleration of the weight in m/s^2 (`decay.csv`, see
//! `docs/measured-case.md`); every displacement amplitude here is in metres (SI), so
//! that the conversions below take `k` in N/m and `m` in kg. Times in s, frequencies in Hz.

use serde::Serialize;
use std::f64::consts::TAU;

use crate::error::{show, PostError, Result};
use crate::filter::{Band, Butterworth};
use crate::fit::least_squares;
use crate::offset::{remove_offset, Detrend};
use crate::signal::Signal;
use crate::spectrum::{amplitude_spectrum, Spectrum, SpectrumOptions};
use crate::stats::{median, noise_rms};

/// Default relative half-width of the band-pass around the dominant peak.
pub const DEFAULT_BAND: f64 = 0.5;

/// Cycles whose amplitude is below this many standard errors are dropped.
pub const CYCLE_NOISE_FLOOR: f64 = 5.0;

/// Largest relative distance of the dominant spectral peak from the zero-crossing rate
/// for the peak to be taken as the oscillation's frequency (a second line of a beating
/// pair lies within 0.3 of it; a swept line's noise bump far outside).
pub const AGREEMENT: f64 = 0.3;

/// Relative tolerance of a cycle's length against the median length.
pub const CYCLE_TOLERANCE: f64 = 0.25;

/// Options of [`cycles`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleOptions {
    /// Relative half-width `b` of the band-pass `(1 - b) f_0 .. (1 + b) f_0`; `None`: no
    /// filter. Keep `b` above `|f_2 - f_1| / f_1` to keep a second line. The edges are
    /// gentle (order 4: `|H|^2 = 1 / (1 + r^8)`), so a narrow band does not remove a close
    /// line either: with `b = 0.03` a line 8% above `f_0` still passes at 41%.
    pub band: Option<f64>,
    /// Butterworth order of each band edge.
    pub filter_order: usize,
}

impl Default for CycleOptions {
    fn default() -> Self {
        CycleOptions {
            band: Some(DEFAULT_BAND),
            filter_order: crate::filter::DEFAULT_ORDER,
        }
    }
}

/// One cycle of the axial oscillation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cycle {
    /// Upward zero crossings bounding the cycle, s.
    pub start_s: f64,
    /// End, s.
    pub end_s: f64,
    /// Centre, s.
    pub time_s: f64,
    /// `1 / (end - start)`, Hz.
    pub frequency_hz: f64,
    /// Fundamental acceleration amplitude (gain-corrected), m/s^2.
    pub accel_amplitude: f64,
    /// Its standard error, m/s^2.
    pub accel_std_error: f64,
    /// Displacement amplitude `accel / (2 pi f)^2`, m.
    pub amplitude_m: f64,
    /// Its standard error, m.
    pub amplitude_std_error_m: f64,
}

/// The cycles of a record and how they were found.
#[derive(Debug, Clone, Serialize)]
pub struct CycleSeries {
    /// Largest spectral peak (or the zero-crossing rate without one), Hz.
    pub dominant_frequency_hz: f64,
    /// Pass band applied, Hz.
    pub band_hz: Option<(f64, f64)>,
    /// Butterworth order of each band edge.
    pub filter_order: usize,
    /// Robust white-noise estimate of the record, m/s^2.
    pub noise_rms: f64,
    /// Time excluded at each end (filter settling), s.
    pub edge_guard_s: f64,
    /// Candidate cycles dropped (irregular length, below the noise floor).
    pub rejected: usize,
    /// The cycles.
    pub cycles: Vec<Cycle>,
}

/// Cycles of a [`Signal`] of axial acceleration in m/s^2 (see the module doc).
pub fn cycles(signal: &Signal, options: &CycleOptions) -> Result<CycleSeries> {
    let spectrum = amplitude_spectrum(signal, &SpectrumOptions::default())
        .map_err(|error| signal.locate(error))?;
    cycles_in(signal, &spectrum, options)
}

/// [`cycles`] with the signal's spectrum already computed, so that a caller who needs it
/// too computes it once: `spectrum` must be [`amplitude_spectrum`] of `signal` with
/// [`SpectrumOptions::default`] (its dominant peak is `f_0`); a spectrum of another record
/// length or window is an error.
pub fn cycles_in(
    signal: &Signal,
    spectrum: &Spectrum,
    options: &CycleOptions,
) -> Result<CycleSeries> {
    cycles_of(signal, spectrum, options).map_err(|error| signal.locate(error))
}

fn cycles_of(signal: &Signal, spectrum: &Spectrum, options: &CycleOptions) -> Result<CycleSeries> {
    let defaults = SpectrumOptions::default();
    if spectrum.samples != signal.len() || spectrum.window != defaults.window {
        return Err(PostError::InvalidOption(format!(
            "a {:?} spectrum of {} samples for a record of {}; expected the record's \
             default spectrum",
            spectrum.window,
            spectrum.samples,
            signal.len()
        )));
    }
    let (time_s, step_s) = (signal.time_s(), signal.step_s());
    let (y, _) = remove_offset(signal, Detrend::Mean)?;
    let (_, y) = y.into_parts();
    let noise = noise_rms(&y);
    // A line swept by a strong nonlinearity spreads over many bins and may leave no
    // regular spectral peak (or only a noise bump as the most prominent one); the
    // zero-crossing rate still finds the oscillation, and it decides whenever the
    // spectral peak lies outside the band around it.
    let f0 = match (
        dominant_frequency(spectrum),
        crossing_rate(&y, noise, step_s),
    ) {
        (Ok(f), Some(rate)) if (f - rate).abs() <= AGREEMENT * rate => f,
        (_, Some(rate)) => rate,
        (Ok(f), None) => f,
        (Err(e), None) => return Err(e),
    };
    let n = y.len();

    let (y, band_hz, filters, guard) = match options.band {
        None => (y, None, None, 0),
        Some(b) if b > 0.0 && b < 1.0 => {
            let (low, high) = ((1.0 - b) * f0, (1.0 + b) * f0);
            let order = options.filter_order;
            let highpass = Butterworth::new(Band::Highpass, order, low, step_s)?;
            let lowpass = Butterworth::new(Band::Lowpass, order, high, step_s)?;
            let filtered = lowpass.filtfilt(&highpass.filtfilt(&y));
            // Half the settling: the end transient is down to e^-7 ~ 1e-3 there.
            let guard = highpass.settle_samples().max(lowpass.settle_samples()) / 2;
            (
                filtered,
                Some((low, high)),
                Some((highpass, lowpass)),
                guard,
            )
        }
        Some(b) => {
            return Err(PostError::InvalidOption(format!(
                "band half-width {}; expected between 0 and 1 (a fraction of the dominant \
                 frequency {} Hz)",
                show(b),
                show(f0)
            )))
        }
    };
    let gain = |f: f64| match &filters {
        Some((highpass, lowpass)) => {
            (highpass.response(f).norm() * lowpass.response(f).norm()).powi(2)
        }
        None => 1.0,
    };
    let band_noise = in_band_noise(noise, band_hz.map(|(_, high)| high), step_s, gain);

    let largest = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let hysteresis = (3.0 * band_noise).max(1e-3 * largest);
    let samples_per_period = 1.0 / (f0 * step_s);
    let half_line = ((samples_per_period / 16.0).round() as usize).max(1);
    let crossings: Vec<f64> = upward_crossings(&y, hysteresis, half_line)
        .into_iter()
        .filter(|&c| c >= guard as f64 && c <= (n - 1).saturating_sub(guard) as f64)
        .collect();

    let lengths: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
    let typical = median(&lengths).unwrap_or(0.0);
    let candidates = lengths.len();
    let mut raw: Vec<(f64, f64, f64, f64)> = Vec::new(); // start, end, accel, std error
    for pair in crossings.windows(2) {
        let (start, end) = (pair[0], pair[1]);
        let length = end - start;
        if (length - typical).abs() > CYCLE_TOLERANCE * typical {
            continue;
        }
        let Some((amplitude, count)) = cycle_amplitude(&y, start, end) else {
            continue;
        };
        let frequency = 1.0 / (length * step_s);
        let g = gain(frequency);
        let accel = amplitude / g;
        let std_error = noise * (2.0 / count as f64).sqrt() / g;
        if accel < CYCLE_NOISE_FLOOR * std_error {
            continue;
        }
        raw.push((start, end, accel, std_error));
    }
    let t0 = time_s[0];
    let cycles = cycles_from(&raw, t0, step_s);
    if cycles.len() < 3 {
        return Err(PostError::TooFewPeaks {
            kind: "cycles",
            found: cycles.len(),
            needed: 3,
            hint: format!(
                "the band-passed record around {} Hz has too few regular cycles above the \
                 noise; is it an oscillation, and longer than the filter's settling ({} s at \
                 each end)?",
                show(f0),
                show(guard as f64 * step_s)
            ),
        });
    }
    Ok(CycleSeries {
        dominant_frequency_hz: f0,
        band_hz,
        filter_order: options.filter_order,
        noise_rms: noise,
        edge_guard_s: guard as f64 * step_s,
        rejected: candidates - cycles.len(),
        cycles,
    })
}

/// Each raw cycle `(start, end, accel, std error)` (sample positions, m/s^2) as a
/// [`Cycle`]: its frequency from its own length, its displacement amplitude through the
/// mean frequency of it and its two neighbours on each side (a smoother `omega^2`).
fn cycles_from(raw: &[(f64, f64, f64, f64)], t0: f64, step_s: f64) -> Vec<Cycle> {
    let frequencies: Vec<f64> = raw.iter().map(|r| 1.0 / ((r.1 - r.0) * step_s)).collect();
    raw.iter()
        .enumerate()
        .map(|(k, &(start, end, accel, std_error))| {
            let near = &frequencies[k.saturating_sub(2)..(k + 3).min(frequencies.len())];
            let smooth = near.iter().sum::<f64>() / near.len() as f64;
            let omega_squared = (TAU * smooth).powi(2);
            Cycle {
                start_s: t0 + start * step_s,
                end_s: t0 + end * step_s,
                time_s: t0 + 0.5 * (start + end) * step_s,
                frequency_hz: frequencies[k],
                accel_amplitude: accel,
                accel_std_error: std_error,
                amplitude_m: accel / omega_squared,
                amplitude_std_error_m: std_error / omega_squared,
            }
        })
        .collect()
}

/// In-band noise: white noise of deviation `noise` through the filters' `|H|^2` (`gain`)
/// has variance `noise^2 2 dt int_0^{f_s/2} |H|^4 df`, integrated up to 4 times the band's
/// top edge `high` (no band: the noise itself).
fn in_band_noise(noise: f64, high: Option<f64>, step_s: f64, gain: impl Fn(f64) -> f64) -> f64 {
    match high {
        Some(high) => {
            let top = (4.0 * high).min(0.5 / step_s);
            let points = 4000;
            let df = top / points as f64;
            let integral: f64 = (0..points)
                .map(|j| gain((j as f64 + 0.5) * df).powi(2) * df)
                .sum();
            noise * (2.0 * step_s * integral).sqrt()
        }
        None => noise,
    }
}

/// The oscillation's mean frequency in the time domain, Hz: the rate of the upward zero
/// crossings of the mean-removed record `y` (hysteresis 3 times its noise `noise`, or
/// 1e-3 of its peak), `(n - 1) / (c_n - c_1)` over its `n` crossings. A line whose
/// frequency sweeps by 20 % over the record (a strong softening or hardening spring)
/// spreads over many spectral bins and may show no regular spectral peak; it is still one
/// oscillation here, at its mean frequency. `None` with fewer than 3 crossings.
fn crossing_rate(y: &[f64], noise: f64, step_s: f64) -> Option<f64> {
    let largest = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let c = upward_crossings(y, (3.0 * noise).max(1e-3 * largest), 1);
    (c.len() >= 3).then(|| (c.len() - 1) as f64 / ((c[c.len() - 1] - c[0]) * step_s))
}

/// [`crossing_rate`] of a [`Signal`] (mean removed first), Hz: the time domain's
/// frequency of an oscillation, for records whose spectrum shows no regular peak.
pub fn crossing_frequency(signal: &Signal) -> Option<f64> {
    let (y, _) = remove_offset(signal, Detrend::Mean).ok()?;
    let (_, y) = y.into_parts();
    crossing_rate(&y, noise_rms(&y), signal.step_s())
}

/// The dominant peak of the record's default spectrum (that of the mean-removed record).
fn dominant_frequency(spectrum: &Spectrum) -> Result<f64> {
    spectrum
        .dominant_peak()
        .map(|peak| peak.frequency_hz)
        .filter(|&f| f > 0.0)
        .ok_or_else(|| PostError::TooFewPeaks {
            kind: "spectral peaks",
            found: 0,
            needed: 1,
            hint: "the signature needs an oscillation; the spectrum has no peak".to_string(),
        })
}

/// Fractional sample indices of the upward zero crossings, with hysteresis `h`: a crossing
/// counts when the signal goes from below `-h` to above `+h`; it is the zero of a
/// least-squares line over the `2 w` samples around the last sign change in between.
fn upward_crossings(y: &[f64], h: f64, w: usize) -> Vec<f64> {
    let mut crossings = Vec::new();
    let mut below: Option<usize> = None;
    for i in 0..y.len() {
        if y[i] < -h {
            below = Some(i);
        } else if y[i] > h {
            let Some(from) = below.take() else {
                continue;
            };
            let Some(j) = (from..i).rev().find(|&j| y[j] <= 0.0 && y[j + 1] > 0.0) else {
                continue;
            };
            let linear = j as f64 + y[j] / (y[j] - y[j + 1]);
            let refined = (j + 1 >= w && j + w < y.len())
                .then(|| {
                    // Symmetric about j + 1/2: a cosine's cubic term does not move the zero.
                    let centre = j as f64 + 0.5;
                    let (mut su, mut suu, mut sy, mut suy) = (0.0, 0.0, 0.0, 0.0);
                    let count = 2 * w;
                    for (k, &value) in y.iter().enumerate().take(j + w + 1).skip(j + 1 - w) {
                        let u = k as f64 - centre;
                        su += u;
                        suu += u * u;
                        sy += value;
                        suy += u * value;
                    }
                    let m = count as f64;
                    let slope = (m * suy - su * sy) / (m * suu - su * su);
                    let intercept = (sy - slope * su) / m;
                    centre - intercept / slope
                })
                .filter(|c| c.is_finite() && (c - linear).abs() < 1.0);
            crossings.push(refined.unwrap_or(linear));
        }
    }
    crossings
}

/// Fundamental amplitude over `[start, end]` (fractional indices) and the number of samples.
fn cycle_amplitude(y: &[f64], start: f64, end: f64) -> Option<(f64, usize)> {
    let first = start.ceil() as usize;
    let last = (end.floor() as usize).min(y.len().checked_sub(1)?);
    if last < first {
        return None;
    }
    let count = last - first + 1;
    // Three harmonics need 7 columns; fall back to the fundamental alone on coarse sampling.
    let harmonics = if count >= 16 { 3 } else { 1 };
    if count < 2 * harmonics + 2 {
        return None;
    }
    let length = end - start;
    let basis: Vec<Vec<f64>> = (first..=last)
        .map(|i| {
            let theta = TAU * (i as f64 - start) / length;
            let mut row = vec![1.0];
            for h in 1..=harmonics {
                let (s, c) = (h as f64 * theta).sin_cos();
                row.push(c);
                row.push(s);
            }
            row
        })
        .collect();
    let c = least_squares(&basis, &y[first..=last], &vec![1.0; count])?;
    Some((c[1].hypot(c[2]), count))
}
