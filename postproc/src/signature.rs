//! Signatures of a free decay that the paper's linear model (linear spring, viscous Rayleigh
//! damping) cannot produce: amplitude loss per cycle against amplitude, frequency against
//! amplitude (the backbone), the shape of the envelope, and a second spectral line beside
//! the axial one. They start `coil-tune diagnose`'s nonlinear fits, which then refine by
//! output error: the numbers are initial estimates with honest standard errors, not final
//! values.
//!
//! # Units and signs
//! The input is the axial acceleration of the weight in m/s^2 (`decay.csv`, see
//! `docs/measured-case.md`); every displacement amplitude here is in metres (SI), so
//! that the conversions below take `k` in N/m and `m` in kg. Times in s, frequencies in Hz.
//!
//! # Cycles ([`cycles`])
//! The record (mean removed) is band-passed around its dominant spectral peak `f_0`, from
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
//! deviation `s` (the robust estimate of [`crate::peaks::noise_rms`]); band-passing does not
//! change it, since the noise near `f` passes the filter.
//!
//! With dry friction the fundamental also has a quadrature part `4 F / (pi m)`, which raises
//! `a_k` by the factor `sqrt(1 + (a_0 / (pi A))^2)`: 0.4% at `A = 5 a_0`, 2.5% at `2 a_0`.
//!
//! # Loss per cycle ([`loss_per_cycle`])
//! For weak damping, the energy lost per cycle by harmonic balance (`x = A cos(omega t)`)
//! gives the amplitude loss per cycle `dA = dE / (k A)`:
//!
//! ```text
//! viscous c v          dA = 2 pi zeta A            a_1 = 2 pi zeta (the log decrement delta)
//! Coulomb F sgn(v)     dA = 4 F / k                a_0 = 4 F / k,  k = m omega^2
//! quadratic c2 v|v|    dA = (8/3) (c2 / m) A^2     a_2 = (8/3) c2 / m
//! ```
//!
//! (Coulomb: two half-cycles, each about a centre shifted by `F / k`, each losing `2 F / k`,
//! exact; quadratic: `int c2 |v|^3 dt = (8/3) c2 omega^2 A^3` per cycle.) The fit
//! `dA = a_0 + a_1 A + a_2 A^2` uses the local slope of `A(t)`, not raw differences
//! `A_k - A_{k+1}`, whose noise is `sqrt 2` times an amplitude's: the cycles are cut into
//! disjoint windows of `m` cycles (`m = n / 8` clamped to 3..16), a weighted line
//! `A = A_c + s (t - t_c)` is fitted in each (weights `1 / se^2`), and the window gives the
//! loss per cycle `y = -s T` (`T` its mean period) at amplitude `A_c`, with the standard error
//! of `s` from the amplitudes' standard errors. Disjoint windows keep the `y` independent. The
//! three-term fit is weighted by `1 / var(y)`; its standard errors are those of the weights,
//! scaled by the reduced chi-square when that exceeds 1 (model error or noise above the
//! estimate), never shrunk below the noise. Over a short range of amplitudes the three basis
//! functions are nearly collinear and the standard errors say so; single-term fits
//! ([`LossFit::single`]) are reported beside it. The conversions are [`friction_force`],
//! [`quadratic_coefficient`] and [`zeta_from_a1`].
//!
//! # Backbone ([`backbone`])
//! A spring force `k x + k3 x^3` (`x` compression from free length) preloaded by the weight to
//! `x_s` (`k x_s + k3 x_s^3 = m g`) has, about `x_s`, the restoring force
//! `k_t y + 3 k3 x_s y^2 + k3 y^3`, `k_t = k + 3 k3 x_s^2`. For `y'' + omega_0^2 y + alpha y^2
//! + beta y^3 = 0` the Lindstedt-Poincare expansion (Landau & Lifshitz, Mechanics, section 28;
//! Nayfeh & Mook, Nonlinear Oscillations, 4.1) gives
//! `omega = omega_0 + (3 beta / (8 omega_0) - 5 alpha^2 / (12 omega_0^3)) A^2`, so
//!
//! ```text
//! f^2 = f_0^2 (1 + b A^2),   b = 3 k3 / (4 k_t) - 5 (3 k3 x_s)^2 / (6 k_t^2)
//! ```
//!
//! The fit is `f_k^2 = c_0 + c_1 A_k^2` by least squares weighted by `(A_k / se_k)^2 / f_k^4`
//! (the crossing jitter, hence the relative frequency error, scales as `se / A`), with
//! `f_0 = sqrt(c_0)`, `b = c_1 / c_0` and standard errors by the delta method from the
//! residual-scaled covariance (neighbouring cycles share a crossing, which makes the
//! per-cycle errors negatively correlated: the standard errors are then conservative).
//! Damping lowers `f` by `sqrt(1 - zeta^2)`, constant for viscous damping and absorbed in
//! `f_0`. The next term of the expansion changes `b` by about `0.2 (k3 / k) A^2` relative.
//! [`cubic_from_backbone`] solves the quadratic in `k3` for its root that tends to
//! `4 k_t b / 3` as `x_s -> 0`.
//!
//! # Envelope shape ([`envelope_shape`])
//! Three fits of the per-cycle amplitudes, weighted by `1 / se^2`, each with its `R^2`:
//! `ln A = c - sigma t` (viscous, exponential), `A = c - r t` (Coulomb, linear) and a beat
//! model. The beat model is a quadratic trend in `t` plus a sinusoid at `f_b` and its second
//! harmonic; `f_b` is scanned from `1.5 / T_record` (at least one and a half beats) to
//! 0.45 times the cycle rate, 10 points per Rayleigh resolution `1 / T_record`, refined by a
//! parabola. Decision rule: **Beating** when, at the best `f_b`, adding the sinusoid cuts the
//! weighted residual of the quadratic trend by at least 4 ([`BEAT_VARIANCE_RATIO`]) in each of
//! `ln A`, `A` and `1 / A` (in one of these every monotone decay of the catalogue is nearly a
//! quadratic in `t`, so a smooth bend is never read as a beat) and the modulation depth (the
//! amplitude of the fundamental term in `ln A`) is at least 5% ([`BEAT_MIN_DEPTH`]);
//! otherwise **Exponential** when the exponential fit leaves the smaller weighted residual,
//! else **Linear**. Quadratic damping (`A = A_0 / (1 + a_2 A_0 n)`) is told apart by the loss
//! fit, not here.
//!
//! # Spectral peaks ([`spectral_peaks`])
//! The Hann-windowed, 8 times zero-padded amplitude spectrum of [`crate::spectrum`] with its
//! log-parabolic (Gaussian) sub-bin interpolation and its prominence and side-lobe rules: the
//! largest peak is the axial one at `f_1`; the largest other peak within 0.7-1.3 `f_1` and
//! above 2% of it is the side peak `f_2` (the Wilberforce torsional mode, seen in the axial
//! record through the coupling), reported with its relative amplitude and the beat period
//! `1 / |f_1 - f_2|`.

use serde::Serialize;
use std::f64::consts::TAU;

use crate::decrement::zeta_from_decrement;
use crate::error::{show, PostError, Result};
use crate::filter::{Band, Butterworth};
use crate::fit::{least_squares, weighted_fit};
use crate::peaks::{median, noise_rms};
use crate::signal::{self, Detrend, Signal};
use crate::spectrum::{self, SpectralPeak, SpectrumOptions};

/// Default relative half-width of the band-pass around the dominant peak.
pub const DEFAULT_BAND: f64 = 0.5;

/// Cycles whose amplitude is below this many standard errors are dropped.
pub const CYCLE_NOISE_FLOOR: f64 = 5.0;

/// Relative tolerance of a cycle's length against the median length.
pub const CYCLE_TOLERANCE: f64 = 0.25;

/// Beat decision: the sinusoid must cut the trend's residual to this fraction or less.
pub const BEAT_VARIANCE_RATIO: f64 = 0.25;

/// Beat decision: the smallest modulation depth (amplitude of the fundamental in `ln A`).
pub const BEAT_MIN_DEPTH: f64 = 0.05;

/// The side peak is searched from `SIDE_RANGE.0 f_1` to `SIDE_RANGE.1 f_1`.
pub const SIDE_RANGE: (f64, f64) = (0.7, 1.3);

/// The smallest side peak reported, relative to the axial one.
pub const SIDE_THRESHOLD: f64 = 0.02;

/// A value with its standard error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    pub value: f64,
    pub std_error: f64,
}

impl Estimate {
    /// `value / std_error` (infinite for an exact value).
    pub fn t_ratio(&self) -> f64 {
        self.value / self.std_error
    }
}

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
    pub end_s: f64,
    /// Centre, s.
    pub time_s: f64,
    /// `1 / (end - start)`, Hz.
    pub frequency_hz: f64,
    /// Fundamental acceleration amplitude (gain-corrected), m/s^2.
    pub accel_amplitude: f64,
    pub accel_std_error: f64,
    /// Displacement amplitude `accel / (2 pi f)^2`, m.
    pub amplitude_m: f64,
    pub amplitude_std_error_m: f64,
}

/// The cycles of a record and how they were found.
#[derive(Debug, Clone, Serialize)]
pub struct CycleSeries {
    /// Largest spectral peak, Hz.
    pub dominant_frequency_hz: f64,
    /// Pass band applied, Hz.
    pub band_hz: Option<(f64, f64)>,
    pub filter_order: usize,
    /// Robust white-noise estimate of the record, m/s^2.
    pub noise_rms: f64,
    /// Time excluded at each end (filter settling), s.
    pub edge_guard_s: f64,
    /// Candidate cycles dropped (irregular length, below the noise floor).
    pub rejected: usize,
    pub cycles: Vec<Cycle>,
}

/// Cycles of a [`Signal`] of axial acceleration in m/s^2 (see the module doc).
pub fn cycles(signal: &Signal, options: &CycleOptions) -> Result<CycleSeries> {
    cycles_of(&signal.time_s, &signal.values, options).map_err(|error| signal.locate(error))
}

/// [`cycles`] on plain slices.
pub fn cycles_of(time_s: &[f64], accel: &[f64], options: &CycleOptions) -> Result<CycleSeries> {
    let step_s = signal::uniform_step(time_s, accel)?;
    let (y, _) = signal::remove_offset(time_s, accel, Detrend::Mean)?;
    let f0 = dominant_frequency(time_s, &y)?;
    let noise = noise_rms(&y);
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
    // In-band noise: white noise of deviation s through |H|^2 has variance
    // s^2 2 dt int_0^{f_s/2} |H|^4 df.
    let band_noise = match band_hz {
        Some((_, high)) => {
            let top = (4.0 * high).min(0.5 / step_s);
            let points = 4000;
            let df = top / points as f64;
            let integral: f64 = (0..points)
                .map(|j| gain((j as f64 + 0.5) * df).powi(2) * df)
                .sum();
            noise * (2.0 * step_s * integral).sqrt()
        }
        None => noise,
    };

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
    let frequencies: Vec<f64> = raw.iter().map(|r| 1.0 / ((r.1 - r.0) * step_s)).collect();
    let cycles: Vec<Cycle> = raw
        .iter()
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
        .collect();
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

fn dominant_frequency(time_s: &[f64], y: &[f64]) -> Result<f64> {
    let options = SpectrumOptions {
        detrend: Detrend::None,
        ..SpectrumOptions::default()
    };
    spectrum::amplitude_spectrum(time_s, y, &options)?
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

/// One window of the loss fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LossPoint {
    /// Window centre (weighted mean time), s.
    pub time_s: f64,
    /// Amplitude at the centre, m.
    pub amplitude_m: f64,
    /// Amplitude loss per cycle, m.
    pub loss_m: f64,
    pub loss_std_error_m: f64,
}

/// A one-term fit `dA = a_j phi_j(A)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TermFit {
    pub coefficient: Estimate,
    /// Weighted residual per degree of freedom (1 when the term explains the loss to the
    /// noise).
    pub reduced_chi2: f64,
}

/// The three one-term fits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SingleTermFits {
    /// `dA = a_0` (Coulomb), m.
    pub coulomb_a0_m: TermFit,
    /// `dA = a_1 A` (viscous), dimensionless.
    pub viscous_a1: TermFit,
    /// `dA = a_2 A^2` (velocity squared), 1/m.
    pub quadratic_a2_per_m: TermFit,
}

/// Result of [`loss_per_cycle`]: `dA = a_0 + a_1 A + a_2 A^2` per cycle.
#[derive(Debug, Clone, Serialize)]
pub struct LossFit {
    /// m.
    pub a0_m: Estimate,
    /// Dimensionless (the log decrement of the viscous part).
    pub a1: Estimate,
    /// 1/m.
    pub a2_per_m: Estimate,
    /// Weighted residual of the three-term fit per degree of freedom.
    pub reduced_chi2: f64,
    pub cycles_per_window: usize,
    /// Smallest and largest window amplitude, m.
    pub amplitude_range_m: (f64, f64),
    pub single: SingleTermFits,
    pub points: Vec<LossPoint>,
}

/// Loss per cycle against amplitude with `m = n / 8` cycles per window, clamped to 3..16.
pub fn loss_per_cycle(cycles: &[Cycle]) -> Result<LossFit> {
    loss_per_cycle_windowed(cycles, (cycles.len() / 8).clamp(3, 16))
}

/// Smallest number of windows of the loss fit (three coefficients and two degrees of
/// freedom).
pub const MIN_LOSS_WINDOWS: usize = 5;

/// [`loss_per_cycle`] with `cycles_per_window` cycles in each window (at least 3).
pub fn loss_per_cycle_windowed(cycles: &[Cycle], cycles_per_window: usize) -> Result<LossFit> {
    let m = cycles_per_window;
    if m < 3 {
        return Err(PostError::InvalidOption(format!(
            "{m} cycles per loss window; need at least 3 for a slope with an error"
        )));
    }
    let windows = cycles.len() / m;
    if windows < MIN_LOSS_WINDOWS {
        return Err(PostError::TooFewPoints {
            what: "loss per cycle",
            found: windows,
            needed: MIN_LOSS_WINDOWS,
            hint: format!(
                "{} cycles make {windows} windows of {m}; a longer record or fewer cycles per \
                 window",
                cycles.len()
            ),
        });
    }
    let floor = 1e-12 * cycles.iter().map(|c| c.amplitude_m).fold(0.0, f64::max);
    let mut points = Vec::with_capacity(windows);
    for block in cycles.chunks_exact(m) {
        let w: Vec<f64> = block
            .iter()
            .map(|c| c.amplitude_std_error_m.max(floor).powi(-2))
            .collect();
        let total: f64 = w.iter().sum();
        let t_c = block.iter().zip(&w).map(|(c, w)| w * c.time_s).sum::<f64>() / total;
        let a_c = block
            .iter()
            .zip(&w)
            .map(|(c, w)| w * c.amplitude_m)
            .sum::<f64>()
            / total;
        let (mut sxx, mut sxy) = (0.0, 0.0);
        for (c, w) in block.iter().zip(&w) {
            sxx += w * (c.time_s - t_c).powi(2);
            sxy += w * (c.time_s - t_c) * (c.amplitude_m - a_c);
        }
        let slope = sxy / sxx;
        let period = block.len() as f64 / block.iter().map(|c| c.frequency_hz).sum::<f64>();
        points.push(LossPoint {
            time_s: t_c,
            amplitude_m: a_c,
            loss_m: -slope * period,
            // With known variances, var(slope) = 1 / sum w (t - t_c)^2.
            loss_std_error_m: period / sxx.sqrt(),
        });
    }
    let y: Vec<f64> = points.iter().map(|p| p.loss_m).collect();
    let w: Vec<f64> = points
        .iter()
        .map(|p| p.loss_std_error_m.max(f64::MIN_POSITIVE).powi(-2))
        .collect();
    let fit_terms = |columns: &[usize]| {
        let basis: Vec<Vec<f64>> = points
            .iter()
            .map(|p| {
                columns
                    .iter()
                    .map(|&j| p.amplitude_m.powi(j as i32))
                    .collect()
            })
            .collect();
        weighted_fit(&basis, &y, &w).map(|fit| {
            let reduced_chi2 = fit.weighted_residual_sum / fit.dof as f64;
            let scale = reduced_chi2.max(1.0);
            let estimates: Vec<Estimate> = (0..columns.len())
                .map(|j| Estimate {
                    value: fit.coefficients[j],
                    std_error: (fit.unscaled_covariance[j][j].max(0.0) * scale).sqrt(),
                })
                .collect();
            (estimates, reduced_chi2)
        })
    };
    let singular = || PostError::Unidentifiable {
        what: "the loss per cycle",
        why: "the windows' amplitudes do not spread enough to separate the terms".to_string(),
    };
    let (full, reduced_chi2) = fit_terms(&[0, 1, 2]).ok_or_else(singular)?;
    let single = |j: usize| {
        fit_terms(&[j]).map(|(e, reduced_chi2)| TermFit {
            coefficient: e[0],
            reduced_chi2,
        })
    };
    let single = SingleTermFits {
        coulomb_a0_m: single(0).ok_or_else(singular)?,
        viscous_a1: single(1).ok_or_else(singular)?,
        quadratic_a2_per_m: single(2).ok_or_else(singular)?,
    };
    let amplitudes = points.iter().map(|p| p.amplitude_m);
    let amplitude_range_m = (
        amplitudes.clone().fold(f64::INFINITY, f64::min),
        amplitudes.fold(0.0, f64::max),
    );
    Ok(LossFit {
        a0_m: full[0],
        a1: full[1],
        a2_per_m: full[2],
        reduced_chi2,
        cycles_per_window: m,
        amplitude_range_m,
        single,
        points,
    })
}

/// Coulomb friction force from the constant loss per cycle: `F = a_0 k / 4` (N, with `a_0`
/// in m and `k = m omega^2` in N/m). Standard errors scale the same way.
pub fn friction_force(a0_m: f64, stiffness_n_m: f64) -> f64 {
    a0_m * stiffness_n_m / 4.0
}

/// Velocity-squared damping coefficient from the quadratic loss: `c2 = 3 a_2 m / 8`
/// (N s^2/m^2, with `a_2` in 1/m and the mass in kg). Standard errors scale the same way.
pub fn quadratic_coefficient(a2_per_m: f64, mass_kg: f64) -> f64 {
    3.0 * a2_per_m * mass_kg / 8.0
}

/// Viscous damping ratio from the linear loss: `a_1` is the logarithmic decrement, so
/// `zeta = a_1 / sqrt(4 pi^2 + a_1^2)` (the paper's Eq. 3).
pub fn zeta_from_a1(a1: f64) -> f64 {
    zeta_from_decrement(a1)
}

/// Result of [`backbone`]: `f^2 = f_0^2 (1 + b A^2)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BackboneFit {
    /// Small-amplitude (damped) frequency, Hz.
    pub f0_hz: Estimate,
    /// 1/m^2.
    pub b_per_m2: Estimate,
    /// `b A_max^2`: the relative change of `f^2` over the record.
    pub shift_at_largest: f64,
    pub amplitude_range_m: (f64, f64),
    pub cycles: usize,
    /// Residual RMS of `f` about the fit, Hz.
    pub residual_rms_hz: f64,
}

/// Fits the backbone `f^2 = f_0^2 (1 + b A^2)` to the cycles (see the module doc).
pub fn backbone(cycles: &[Cycle]) -> Result<BackboneFit> {
    if cycles.len() < 4 {
        return Err(PostError::TooFewPoints {
            what: "backbone",
            found: cycles.len(),
            needed: 4,
            hint: "a longer record".to_string(),
        });
    }
    let basis: Vec<Vec<f64>> = cycles
        .iter()
        .map(|c| vec![1.0, c.amplitude_m * c.amplitude_m])
        .collect();
    let y: Vec<f64> = cycles.iter().map(|c| c.frequency_hz.powi(2)).collect();
    let w: Vec<f64> = cycles
        .iter()
        .map(|c| {
            let relative = c.amplitude_std_error_m / c.amplitude_m;
            (relative.max(1e-12) * c.frequency_hz.powi(2)).powi(-2)
        })
        .collect();
    let fit = weighted_fit(&basis, &y, &w).ok_or_else(|| PostError::Unidentifiable {
        what: "the backbone",
        why: "the cycles' amplitudes are all equal".to_string(),
    })?;
    let (c0, c1) = (fit.coefficients[0], fit.coefficients[1]);
    if c0 <= 0.0 {
        return Err(PostError::Unidentifiable {
            what: "the backbone",
            why: format!("the fitted f0^2 = {} Hz^2 is not positive", show(c0)),
        });
    }
    let cov = &fit.covariance;
    let f0 = c0.sqrt();
    let b = c1 / c0;
    // Delta method for b = c1 / c0.
    let var_b = cov[1][1] / (c0 * c0) + c1 * c1 * cov[0][0] / c0.powi(4)
        - 2.0 * c1 * cov[0][1] / c0.powi(3);
    let amplitudes = cycles.iter().map(|c| c.amplitude_m);
    let largest = amplitudes.clone().fold(0.0, f64::max);
    let residual_rms_hz = (cycles
        .iter()
        .zip(&fit.residuals)
        .map(|(c, r)| (r / (2.0 * c.frequency_hz)).powi(2))
        .sum::<f64>()
        / cycles.len() as f64)
        .sqrt();
    Ok(BackboneFit {
        f0_hz: Estimate {
            value: f0,
            std_error: cov[0][0].max(0.0).sqrt() / (2.0 * f0),
        },
        b_per_m2: Estimate {
            value: b,
            std_error: var_b.max(0.0).sqrt(),
        },
        shift_at_largest: b * largest * largest,
        amplitude_range_m: (amplitudes.fold(f64::INFINITY, f64::min), largest),
        cycles: cycles.len(),
        residual_rms_hz,
    })
}

/// The cubic stiffness `k3` (N/m^3) that gives the backbone coefficient `b` (1/m^2) about a
/// static compression `x_s` (m) with tangent stiffness `k_t` (N/m, e.g. `m (2 pi f_0)^2`):
/// the root of `(15/2) (x_s / k_t)^2 k3^2 - 3 k3 / (4 k_t) + b = 0` that tends to
/// `4 k_t b / 3` as `x_s -> 0`, written as `2 b / (3/(4 k_t) + sqrt(9/(16 k_t^2) - 30 b
/// x_s^2 / k_t^2))` (no cancellation). An error when `b` exceeds `3 / (160 x_s^2)`, the
/// largest value any `k3` gives.
pub fn cubic_from_backbone(
    b_per_m2: f64,
    tangent_stiffness_n_m: f64,
    static_compression_m: f64,
) -> Result<f64> {
    let (b, k_t, x_s) = (b_per_m2, tangent_stiffness_n_m, static_compression_m);
    if !(k_t > 0.0 && k_t.is_finite() && b.is_finite() && x_s.is_finite()) {
        return Err(PostError::InvalidOption(format!(
            "backbone b = {} 1/m^2, k_t = {} N/m, x_s = {} m; expected finite numbers and a \
             positive stiffness",
            show(b),
            show(k_t),
            show(x_s)
        )));
    }
    let linear = 3.0 / (4.0 * k_t);
    let discriminant = linear * linear - 30.0 * b * x_s * x_s / (k_t * k_t);
    if discriminant < 0.0 {
        return Err(PostError::Unidentifiable {
            what: "the cubic stiffness",
            why: format!(
                "b = {} 1/m^2 exceeds 3 / (160 x_s^2) = {} 1/m^2, the largest backbone bend a \
                 cubic spring preloaded to x_s = {} m can give",
                show(b),
                show(3.0 / (160.0 * x_s * x_s)),
                show(x_s)
            ),
        });
    }
    Ok(2.0 * b / (linear + discriminant.sqrt()))
}

/// What the envelope looks like.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EnvelopeKind {
    /// `ln A` linear in time: viscous damping.
    Exponential,
    /// `A` linear in time: dry friction.
    Linear,
    /// Periodic envelope minima: two close modes exchanging energy.
    Beating,
}

/// Result of [`envelope_shape`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnvelopeShape {
    pub kind: EnvelopeKind,
    /// `R^2` (weighted, in `A`) of `ln A = c - sigma t`.
    pub r2_exponential: f64,
    /// `R^2` of `A = c - r t`.
    pub r2_linear: f64,
    /// `R^2` of the best beat model (quadratic trend plus sinusoid), if scanned.
    pub r2_beating: Option<f64>,
    /// `sigma` of the exponential fit, 1/s.
    pub decay_rate_per_s: f64,
    /// `r` of the linear fit, m/s.
    pub loss_rate_m_per_s: f64,
    /// Period of the best beat candidate, s.
    pub beat_candidate_period_s: Option<f64>,
    /// Largest (over `ln A`, `A`, `1/A`) ratio of the residual with the sinusoid to the
    /// residual of the trend alone.
    pub beat_variance_ratio: Option<f64>,
    /// Amplitude of the candidate's fundamental in `ln A`.
    pub modulation_depth: Option<f64>,
    /// The beat period when `kind` is `Beating`, s.
    pub beat_period_s: Option<f64>,
    /// Record length covered by the cycles, s.
    pub duration_s: f64,
}

/// Fewest cycles for the beat scan (a 7-parameter model with a meaningful residual).
pub const MIN_BEAT_CYCLES: usize = 16;

/// Classifies the envelope (see the module doc for the rule).
pub fn envelope_shape(cycles: &[Cycle]) -> Result<EnvelopeShape> {
    let n = cycles.len();
    if n < 4 {
        return Err(PostError::TooFewPoints {
            what: "envelope shape",
            found: n,
            needed: 4,
            hint: "a longer record".to_string(),
        });
    }
    let t: Vec<f64> = cycles.iter().map(|c| c.time_s).collect();
    let a: Vec<f64> = cycles.iter().map(|c| c.amplitude_m).collect();
    let floor = 1e-12 * a.iter().copied().fold(0.0, f64::max);
    let w: Vec<f64> = cycles
        .iter()
        .map(|c| c.amplitude_std_error_m.max(floor).powi(-2))
        .collect();
    let t_mid = 0.5 * (t[0] + t[n - 1]);
    let duration_s = cycles[n - 1].end_s - cycles[0].start_s;
    let tau: Vec<f64> = t.iter().map(|t| (t - t_mid) / duration_s).collect();
    let total: f64 = w.iter().sum();
    let mean = a.iter().zip(&w).map(|(a, w)| a * w).sum::<f64>() / total;
    let sst: f64 = a.iter().zip(&w).map(|(a, w)| w * (a - mean).powi(2)).sum();
    let r2 = |predicted: &[f64]| {
        let ss: f64 = a
            .iter()
            .zip(predicted)
            .zip(&w)
            .map(|((a, p), w)| w * (a - p).powi(2))
            .sum();
        (1.0 - ss / sst, ss)
    };
    let unidentifiable = || PostError::Unidentifiable {
        what: "the envelope shape",
        why: "the cycles' times do not spread".to_string(),
    };
    let line: Vec<Vec<f64>> = tau.iter().map(|&x| vec![1.0, x]).collect();

    let ln_a: Vec<f64> = a.iter().map(|a| a.ln()).collect();
    let w_ln: Vec<f64> = a.iter().zip(&w).map(|(a, w)| w * a * a).collect();
    let exponential = least_squares(&line, &ln_a, &w_ln).ok_or_else(unidentifiable)?;
    let predicted: Vec<f64> = tau
        .iter()
        .map(|x| (exponential[0] + exponential[1] * x).exp())
        .collect();
    let (r2_exponential, ss_exponential) = r2(&predicted);
    let linear = least_squares(&line, &a, &w).ok_or_else(unidentifiable)?;
    let predicted: Vec<f64> = tau.iter().map(|x| linear[0] + linear[1] * x).collect();
    let (r2_linear, ss_linear) = r2(&predicted);

    let mut shape = EnvelopeShape {
        kind: if ss_exponential <= ss_linear {
            EnvelopeKind::Exponential
        } else {
            EnvelopeKind::Linear
        },
        r2_exponential,
        r2_linear,
        r2_beating: None,
        decay_rate_per_s: -exponential[1] / duration_s,
        loss_rate_m_per_s: -linear[1] / duration_s,
        beat_candidate_period_s: None,
        beat_variance_ratio: None,
        modulation_depth: None,
        beat_period_s: None,
        duration_s,
    };
    if n < MIN_BEAT_CYCLES {
        return Ok(shape);
    }
    // Beat scan in ln A; frequencies in cycles per record length.
    let cycle_rate = n as f64 / duration_s;
    let (low, high) = (1.5, 0.45 * cycle_rate * duration_s);
    if high <= low {
        return Ok(shape);
    }
    let residual_at = |z: &[f64], weights: &[f64], beats: f64| beat_fit(&tau, z, weights, beats);
    let grid_step = 0.1;
    let count = ((high - low) / grid_step).floor() as usize + 1;
    let scores: Vec<f64> = (0..count)
        .map(|j| {
            residual_at(&ln_a, &w_ln, low + j as f64 * grid_step)
                .map_or(f64::INFINITY, |fit| fit.beat_residual)
        })
        .collect();
    let Some(best) = (0..count).min_by(|&i, &j| scores[i].total_cmp(&scores[j])) else {
        return Ok(shape);
    };
    let mut beats = low + best as f64 * grid_step;
    if best > 0 && best + 1 < count {
        let (l, c, r) = (scores[best - 1], scores[best], scores[best + 1]);
        let curvature = l - 2.0 * c + r;
        if curvature > 0.0 && curvature.is_finite() {
            beats += grid_step * 0.5 * (l - r) / curvature;
        }
    }
    let Some(in_log) = residual_at(&ln_a, &w_ln, beats) else {
        return Ok(shape);
    };
    let w_inverse: Vec<f64> = a.iter().zip(&w).map(|(a, w)| w * a.powi(4)).collect();
    let inverse: Vec<f64> = a.iter().map(|a| 1.0 / a).collect();
    let ratio_of = |fit: Option<BeatFit>| {
        fit.map_or(f64::INFINITY, |fit| fit.beat_residual / fit.trend_residual)
    };
    let ratio = (in_log.beat_residual / in_log.trend_residual)
        .max(ratio_of(residual_at(&a, &w, beats)))
        .max(ratio_of(residual_at(&inverse, &w_inverse, beats)));
    let predicted: Vec<f64> = in_log.predicted.iter().map(|z| z.exp()).collect();
    let period = duration_s / beats;
    shape.r2_beating = Some(r2(&predicted).0);
    shape.beat_candidate_period_s = Some(period);
    shape.beat_variance_ratio = Some(ratio);
    shape.modulation_depth = Some(in_log.depth);
    if ratio <= BEAT_VARIANCE_RATIO && in_log.depth >= BEAT_MIN_DEPTH {
        shape.kind = EnvelopeKind::Beating;
        shape.beat_period_s = Some(period);
    }
    Ok(shape)
}

#[derive(Clone)]
struct BeatFit {
    trend_residual: f64,
    beat_residual: f64,
    depth: f64,
    predicted: Vec<f64>,
}

/// Weighted fits of `z` by a quadratic in `tau` and by the quadratic plus a sinusoid of
/// `beats` periods per unit `tau` and its second harmonic.
fn beat_fit(tau: &[f64], z: &[f64], w: &[f64], beats: f64) -> Option<BeatFit> {
    let residual = |basis: &[Vec<f64>], c: &[f64]| -> (f64, Vec<f64>) {
        let predicted: Vec<f64> = basis
            .iter()
            .map(|row| row.iter().zip(c).map(|(x, c)| x * c).sum())
            .collect();
        let ss = predicted
            .iter()
            .zip(z)
            .zip(w)
            .map(|((p, z), w)| w * (z - p).powi(2))
            .sum();
        (ss, predicted)
    };
    let trend: Vec<Vec<f64>> = tau.iter().map(|&x| vec![1.0, x, x * x]).collect();
    let c = least_squares(&trend, z, w)?;
    let (trend_residual, _) = residual(&trend, &c);
    let full: Vec<Vec<f64>> = tau
        .iter()
        .map(|&x| {
            let (s1, c1) = (TAU * beats * x).sin_cos();
            let (s2, c2) = (2.0 * TAU * beats * x).sin_cos();
            vec![1.0, x, x * x, c1, s1, c2, s2]
        })
        .collect();
    let c = least_squares(&full, z, w)?;
    let (beat_residual, predicted) = residual(&full, &c);
    Some(BeatFit {
        trend_residual,
        beat_residual,
        depth: c[3].hypot(c[4]),
        predicted,
    })
}

/// The second line beside the axial one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SidePeak {
    pub frequency_hz: f64,
    /// Amplitude, m/s^2.
    pub amplitude: f64,
    /// Amplitude relative to the axial peak.
    pub relative_amplitude: f64,
    /// `1 / |f_1 - f_2|`, s.
    pub beat_period_s: f64,
}

/// Result of [`spectral_peaks`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpectralSignature {
    /// The largest peak.
    pub axial: SpectralPeak,
    /// The largest other peak within [`SIDE_RANGE`] of the axial frequency, if above
    /// [`SIDE_THRESHOLD`].
    pub side: Option<SidePeak>,
    /// Frequency resolution of the record `1 / T`, Hz.
    pub native_bin_hz: f64,
}

/// The axial peak and the side peak of a [`Signal`] (see the module doc).
pub fn spectral_peaks(signal: &Signal) -> Result<SpectralSignature> {
    spectral_peaks_of(&signal.time_s, &signal.values).map_err(|error| signal.locate(error))
}

/// [`spectral_peaks`] on plain slices.
pub fn spectral_peaks_of(time_s: &[f64], values: &[f64]) -> Result<SpectralSignature> {
    let options = SpectrumOptions {
        zero_pad: 8,
        ..SpectrumOptions::default()
    };
    let spectrum = spectrum::amplitude_spectrum(time_s, values, &options)?;
    let peaks = spectrum.peaks(16, SIDE_THRESHOLD);
    let Some(&axial) = peaks.first().filter(|p| p.frequency_hz > 0.0) else {
        return Err(PostError::TooFewPeaks {
            kind: "spectral peaks",
            found: 0,
            needed: 1,
            hint: "the record shows no oscillation".to_string(),
        });
    };
    let f1 = axial.frequency_hz;
    let side = peaks
        .iter()
        .skip(1)
        .find(|p| (SIDE_RANGE.0 * f1..=SIDE_RANGE.1 * f1).contains(&p.frequency_hz))
        .map(|p| SidePeak {
            frequency_hz: p.frequency_hz,
            amplitude: p.amplitude,
            relative_amplitude: p.amplitude / axial.amplitude,
            beat_period_s: 1.0 / (f1 - p.frequency_hz).abs(),
        });
    Ok(SpectralSignature {
        axial,
        side,
        native_bin_hz: spectrum.native_bin_hz,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::test_signals::Rng;
    use std::f64::consts::PI;

    const RATE_HZ: f64 = 1000.0;

    /// 1% Gaussian noise (of the largest magnitude) and a 16-bit converter whose full scale
    /// is 1.25 times the largest magnitude: what every synthetic record here carries.
    pub(crate) fn measured(clean: &[f64], seed: u64) -> Vec<f64> {
        let largest = clean.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let quantum = 2.0 * 1.25 * largest / 65536.0;
        let mut rng = Rng::new(seed);
        clean
            .iter()
            .map(|v| ((v + 0.01 * largest * rng.normal()) / quantum).round() * quantum)
            .collect()
    }

    fn times(n: usize) -> Vec<f64> {
        (0..n).map(|i| i as f64 / RATE_HZ).collect()
    }

    /// One mass on a spring `k x + k3 x^3` (x compression, m) under gravity, with dashpots
    /// `c v` and `c2 v|v|`, released from `x_s + lift` at rest; returns the weight's
    /// acceleration away from the base (m/s^2) by RK4 at `RATE_HZ` with 4 substeps.
    #[derive(Clone, Copy)]
    pub(crate) struct Sdof {
        pub mass: f64,
        pub k: f64,
        pub k3: f64,
        pub c: f64,
        pub c2: f64,
        pub gravity: f64,
    }

    impl Sdof {
        fn force(&self, x: f64, v: f64) -> f64 {
            self.mass * self.gravity
                - self.k * x
                - self.k3 * x.powi(3)
                - self.c * v
                - self.c2 * v * v.abs()
        }
        pub(crate) fn static_compression(&self) -> f64 {
            let mut x = self.mass * self.gravity / self.k;
            for _ in 0..50 {
                x -= (self.k * x + self.k3 * x.powi(3) - self.mass * self.gravity)
                    / (self.k + 3.0 * self.k3 * x * x);
            }
            x
        }
        pub(crate) fn tangent_stiffness(&self) -> f64 {
            self.k + 3.0 * self.k3 * self.static_compression().powi(2)
        }
        pub(crate) fn accel(&self, lift: f64, seconds: f64) -> Vec<f64> {
            let n = (seconds * RATE_HZ) as usize;
            let substeps = 4;
            let h = 1.0 / (RATE_HZ * substeps as f64);
            let (mut x, mut v) = (self.static_compression() + lift, 0.0);
            let a = |x: f64, v: f64| self.force(x, v) / self.mass;
            let mut out = Vec::with_capacity(n);
            for _ in 0..n {
                // x is compression: the weight moves down as x grows, so the acceleration
                // away from the base is -x''.
                out.push(-a(x, v));
                for _ in 0..substeps {
                    let (k1x, k1v) = (v, a(x, v));
                    let (k2x, k2v) = (v + 0.5 * h * k1v, a(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
                    let (k3x, k3v) = (v + 0.5 * h * k2v, a(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
                    let (k4x, k4v) = (v + h * k3v, a(x + h * k3x, v + h * k3v));
                    x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                    v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                }
            }
            out
        }
    }

    /// Exact Coulomb decay: half-cycles of `omega` about `+-d`, `d = F / k`, from `x0` at
    /// rest, sticking once `|x| <= d`. Returns the acceleration `-omega^2 (x - centre)`.
    pub(crate) fn coulomb_accel(omega: f64, d: f64, x0: f64, seconds: f64) -> Vec<f64> {
        let n = (seconds * RATE_HZ) as usize;
        let half = PI / omega;
        let mut out = Vec::with_capacity(n);
        let (mut start_t, mut start_x) = (0.0, x0);
        for i in 0..n {
            let t = i as f64 / RATE_HZ;
            while start_x.abs() > d && t - start_t >= half {
                let centre = start_x.signum() * d;
                start_x = 2.0 * centre - start_x;
                start_t += half;
            }
            if start_x.abs() <= d {
                out.push(0.0);
                continue;
            }
            let centre = start_x.signum() * d;
            let x = centre + (start_x - centre) * (omega * (t - start_t)).cos();
            out.push(-omega * omega * (x - centre));
        }
        out
    }

    fn within(got: f64, exact: f64, relative: f64) -> bool {
        (got - exact).abs() <= relative * exact.abs()
    }

    #[test]
    fn viscous_decay_gives_a1_of_2_pi_zeta_and_nothing_else() {
        let (f, zeta, a0): (f64, f64, f64) = (5.0, 0.003, 0.01);
        let omega_n = TAU * f;
        let omega_d = omega_n * (1.0 - zeta * zeta).sqrt();
        let sigma = zeta * omega_n;
        let time = times(30_000);
        let clean: Vec<f64> = time
            .iter()
            .map(|t| a0 * omega_n * omega_n * (-sigma * t).exp() * (omega_d * t + 0.4).cos())
            .collect();
        let accel = measured(&clean, 1);
        let series = cycles_of(&time, &accel, &CycleOptions::default()).unwrap();
        // Per cycle, A = a / omega_d^2 = a0 e^{-sigma t} / (1 - zeta^2); the cycle's fit
        // over a decaying cycle is its mean to (sigma T)^2 / 24 ~ 1e-5, noise 0.1% at the
        // start and ~2% at the end: 3% covers every cycle.
        let worst = series
            .cycles
            .iter()
            .map(|c| {
                let exact = a0 * (-sigma * c.time_s).exp() / (1.0 - zeta * zeta);
                ((c.amplitude_m - exact) / exact).abs()
                    / (c.amplitude_std_error_m / exact).max(1e-4)
            })
            .fold(0.0, f64::max);
        assert!(series.cycles.len() > 120, "{} cycles", series.cycles.len());
        assert!(worst < 5.0, "worst cycle {worst} standard errors off");

        let loss = loss_per_cycle(&series.cycles).unwrap();
        let delta = 2.0 * PI * zeta / (1.0 - zeta * zeta).sqrt();
        eprintln!("viscous: {loss:#?}");
        // Weak damping: each term within three standard errors of its theory.
        assert!(
            (loss.a1.value - delta).abs() < 3.0 * loss.a1.std_error,
            "{:?}",
            loss.a1
        );
        assert!(
            loss.a0_m.value.abs() < 3.0 * loss.a0_m.std_error,
            "{:?}",
            loss.a0_m
        );
        assert!(
            loss.a2_per_m.value.abs() < 3.0 * loss.a2_per_m.std_error,
            "{:?}",
            loss.a2_per_m
        );
        // The single viscous term is sharp: 2%.
        let single = loss.single.viscous_a1.coefficient;
        assert!(within(single.value, delta, 0.02), "{single:?} vs {delta}");
        assert!(within(zeta_from_a1(single.value), zeta, 0.02));

        let bend = backbone(&series.cycles).unwrap();
        eprintln!("viscous backbone: {bend:?}");
        assert!(
            bend.b_per_m2.value.abs() < 3.0 * bend.b_per_m2.std_error,
            "{bend:?}"
        );
        assert!(within(bend.f0_hz.value, omega_d / TAU, 1e-3), "{bend:?}");

        let shape = envelope_shape(&series.cycles).unwrap();
        eprintln!("viscous shape: {shape:?}");
        assert_eq!(shape.kind, EnvelopeKind::Exponential, "{shape:?}");
        assert!(within(shape.decay_rate_per_s, sigma, 0.02), "{shape:?}");
        let spectral = spectral_peaks_of(&time, &accel).unwrap();
        assert!(spectral.side.is_none(), "{spectral:?}");
    }

    #[test]
    fn coulomb_decay_gives_a0_of_4f_over_k() {
        let (mass, f) = (5.0, 5.0);
        let omega = TAU * f;
        let k = mass * omega * omega;
        let friction = 0.11; // N: 4F/k = 0.09 mm per cycle from 10 mm
        let accel = measured(&coulomb_accel(omega, friction / k, 0.01, 25.0), 2);
        let time = times(accel.len());
        let series = cycles_of(&time, &accel, &CycleOptions::default()).unwrap();
        let loss = loss_per_cycle(&series.cycles).unwrap();
        eprintln!("coulomb: {loss:#?}");
        let exact = 4.0 * friction / k;
        assert!(
            within(loss.a0_m.value, exact, 0.05),
            "{:?} vs {exact}",
            loss.a0_m
        );
        assert!(within(friction_force(loss.a0_m.value, k), friction, 0.05));
        assert!(
            loss.a1.value.abs() < 3.0 * loss.a1.std_error,
            "{:?}",
            loss.a1
        );
        let shape = envelope_shape(&series.cycles).unwrap();
        eprintln!("coulomb shape: {shape:?}");
        assert_eq!(shape.kind, EnvelopeKind::Linear, "{shape:?}");
        assert!(shape.r2_linear > shape.r2_exponential);
    }

    #[test]
    fn quadratic_damping_gives_a2_of_8_c2_over_3m() {
        let sdof = Sdof {
            mass: 5.0,
            k: 5.0 * (TAU * 5.0_f64).powi(2),
            k3: 0.0,
            c: 0.0,
            c2: 7.5,
            gravity: 0.0,
        };
        let accel = measured(&sdof.accel(0.01, 30.0), 3);
        let time = times(accel.len());
        let series = cycles_of(&time, &accel, &CycleOptions::default()).unwrap();
        let loss = loss_per_cycle(&series.cycles).unwrap();
        eprintln!("quadratic: {loss:#?}");
        let exact = 8.0 * sdof.c2 / (3.0 * sdof.mass);
        assert!(
            within(loss.a2_per_m.value, exact, 0.10),
            "{:?} vs {exact}",
            loss.a2_per_m
        );
        assert!(within(
            quadratic_coefficient(loss.a2_per_m.value, sdof.mass),
            sdof.c2,
            0.10
        ));
    }

    fn backbone_of(sdof: &Sdof, lift: f64, seed: u64) -> BackboneFit {
        let accel = measured(&sdof.accel(lift, 30.0), seed);
        let time = times(accel.len());
        let series = cycles_of(&time, &accel, &CycleOptions::default()).unwrap();
        backbone(&series.cycles).unwrap()
    }

    #[test]
    fn duffing_without_preload_gives_b_and_k3() {
        let sdof = Sdof {
            mass: 5.0,
            k: 8000.0,
            k3: 5e6,
            c: 2.0 * 0.003 * (5.0_f64 * 8000.0).sqrt(),
            c2: 0.0,
            gravity: 0.0,
        };
        let fit = backbone_of(&sdof, 0.01, 4);
        eprintln!("duffing: {fit:?}");
        let exact = 3.0 * sdof.k3 / (4.0 * sdof.k);
        assert!(
            within(fit.b_per_m2.value, exact, 0.10),
            "{fit:?} vs {exact}"
        );
        let k_t = sdof.mass * (TAU * fit.f0_hz.value).powi(2);
        let k3 = cubic_from_backbone(fit.b_per_m2.value, k_t, 0.0).unwrap();
        assert!(within(k3, sdof.k3, 0.10), "k3 {k3}");
    }

    #[test]
    fn duffing_with_preload_gives_b_and_k3() {
        let sdof = Sdof {
            mass: 5.0,
            k: 8000.0,
            k3: 5e6,
            c: 2.0 * 0.003 * (5.0_f64 * 8540.0).sqrt(),
            c2: 0.0,
            gravity: 9.81,
        };
        let x_s = sdof.static_compression();
        let k_t = sdof.tangent_stiffness();
        let fit = backbone_of(&sdof, 0.006, 5);
        eprintln!("preloaded duffing: x_s {x_s}, k_t {k_t}, {fit:?}");
        let exact =
            3.0 * sdof.k3 / (4.0 * k_t) - 5.0 * (3.0 * sdof.k3 * x_s).powi(2) / (6.0 * k_t * k_t);
        // Without the quadratic term's correction b would be 3 k3 / (4 k_t), 20% higher:
        // the 10% tolerance tells the two apart.
        assert!(3.0 * sdof.k3 / (4.0 * k_t) > 1.2 * exact);
        assert!(
            within(fit.b_per_m2.value, exact, 0.10),
            "{fit:?} vs {exact}"
        );
        let k_t_measured = sdof.mass * (TAU * fit.f0_hz.value).powi(2);
        let k3 = cubic_from_backbone(fit.b_per_m2.value, k_t_measured, x_s).unwrap();
        assert!(within(k3, sdof.k3, 0.10), "k3 {k3}");
    }

    #[test]
    fn cubic_from_backbone_inverts_the_backbone_formula() {
        let (k_t, x_s) = (8540.0, 0.006);
        for k3 in [0.0_f64, 1e6, 5e6, -2e6] {
            let b = 3.0 * k3 / (4.0 * k_t) - 5.0 * (3.0 * k3 * x_s).powi(2) / (6.0 * k_t * k_t);
            let back = cubic_from_backbone(b, k_t, x_s).unwrap();
            assert!(
                (back - k3).abs() <= 1e-9 * k3.abs().max(1.0),
                "{k3} -> {b} -> {back}"
            );
        }
        // Largest b any k3 gives: 3 / (160 x_s^2).
        let too_bent = 1.01 * 3.0 / (160.0 * x_s * x_s);
        assert!(matches!(
            cubic_from_backbone(too_bent, k_t, x_s),
            Err(PostError::Unidentifiable { .. })
        ));
        assert!(cubic_from_backbone(1.0, 0.0, x_s).is_err());
    }

    #[test]
    fn two_tones_beat_at_the_difference_frequency() {
        let (f1, f2, ratio, zeta) = (5.0, 5.4, 0.3, 0.002);
        let time = times(30_000);
        // One decay rate for both lines, so that their windowed heights keep the ratio.
        let sigma = zeta * TAU * f1;
        let tone = |f: f64, t: f64, phase: f64| (-sigma * t).exp() * (TAU * f * t + phase).cos();
        let clean: Vec<f64> = time
            .iter()
            .map(|&t| tone(f1, t, 0.2) + ratio * tone(f2, t, 1.1))
            .collect();
        let accel = measured(&clean, 6);
        let spectral = spectral_peaks_of(&time, &accel).unwrap();
        eprintln!("beating: {spectral:?}");
        let side = spectral.side.unwrap();
        let beat = 1.0 / (f2 - f1);
        assert!(within(spectral.axial.frequency_hz, f1, 0.01));
        assert!(within(side.frequency_hz, f2, 0.01), "{side:?}");
        assert!(within(side.beat_period_s, beat, 0.01), "{side:?}");
        assert!(within(side.relative_amplitude, ratio, 0.01), "{side:?}");

        let series = cycles_of(&time, &accel, &CycleOptions::default()).unwrap();
        let shape = envelope_shape(&series.cycles).unwrap();
        eprintln!("beating shape: {shape:?}");
        assert_eq!(shape.kind, EnvelopeKind::Beating, "{shape:?}");
        assert!(
            within(shape.beat_period_s.unwrap(), beat, 0.02),
            "{shape:?}"
        );
    }

    #[test]
    fn bad_inputs_are_typed_errors() {
        let time = times(5000);
        let flat = vec![0.0; 5000];
        assert!(matches!(
            cycles_of(&time, &flat, &CycleOptions::default()),
            Err(PostError::TooFewPeaks { .. })
        ));
        let sine: Vec<f64> = time.iter().map(|t| (TAU * 5.0 * t).sin()).collect();
        let wide = CycleOptions {
            band: Some(1.5),
            ..CycleOptions::default()
        };
        assert!(matches!(
            cycles_of(&time, &sine, &wide),
            Err(PostError::InvalidOption(_))
        ));
        let mut nan = sine.clone();
        nan[7] = f64::NAN;
        assert!(matches!(
            cycles_of(&time, &nan, &CycleOptions::default()),
            Err(PostError::InvalidSignal { index: 7, .. })
        ));
        let series = cycles_of(&time, &sine, &CycleOptions::default()).unwrap();
        assert!(matches!(
            loss_per_cycle(&series.cycles[..10]),
            Err(PostError::TooFewPoints { .. })
        ));
        assert!(matches!(
            loss_per_cycle_windowed(&series.cycles, 2),
            Err(PostError::InvalidOption(_))
        ));
        // A steady sine: every cycle has the same amplitude, the backbone cannot bend.
        assert!(backbone(&series.cycles[..3]).is_err());
    }
}
