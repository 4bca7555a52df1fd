//! Zero-phase Butterworth filters (forward-backward, as MATLAB's and SciPy's `filtfilt`).
//!
//! # Design
//! The analog Butterworth prototype of order `N` has poles `p_k = exp(i pi (2k + N - 1) / 2N)`,
//! `k = 1..N`, on the unit circle in the left half plane. The cutoff is pre-warped,
//! `Omega_c = 2 f_s tan(pi f_c / f_s)`, so that the bilinear transform
//! `z = (2 f_s + s) / (2 f_s - s)` puts the -3 dB point exactly at `f_c`. Low-pass poles are
//! `Omega_c p_k` with all zeros at `z = -1`; high-pass poles are `Omega_c / p_k` with zeros at
//! `z = +1`. Conjugate pairs become second-order sections (a first-order one for odd `N`), each
//! normalised to unit gain at DC (low-pass) or Nyquist (high-pass). The digital response is
//! `|H(f)|^2 = 1 / (1 + (tan(pi f / f_s) / tan(pi f_c / f_s))^(2N))`.
//!
//! # Zero phase
//! [`Butterworth::filtfilt`] runs the cascade forward, then backward over the reversed
//! output: the phases cancel and the magnitude is `|H|^2`. So an in-band component keeps its
//! amplitude to `1 - |H|^2` (for a 4.35 Hz signal and a 50 Hz order-4 cutoff, 3e-9) and its
//! phase exactly, and a component at Nyquist (`z = -1`, the ripple that alternates every time
//! step) is removed exactly. A damped exponential `e^{st}` is an eigenfunction of any linear
//! time-invariant filter: away from the ends, filtering only multiplies it by the constant
//! `H(e^{s dt})`, so decay rate and period are untouched and the decrement is unbiased.
//!
//! # Ends
//! The record is extended at each end by its point reflection (`2 x_0 - x_k`, which keeps value
//! and slope continuous), and each pass starts from the steady state of its first input value,
//! as SciPy's `sosfiltfilt` does. The extension is the settling length: 14 time constants of
//! the slowest pole, `14 / (2 pi f_c sin(pi / 2N))` seconds (its envelope falls by e^-14 ~
//! 1e-6; 5.8 / f_c for N = 4, capped at the record length). What is left at the ends is the
//! transient of whatever the reflection gets wrong, e.g. a step ripple at `x_0`: it dies over
//! the same length, so [`Butterworth::settle_samples`] samples at each end of the output
//! should not be trusted to better than the ripple (the decrement drops crests there). The
//! tests measure it.

use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

use crate::error::{show, PostError, Result};

/// Highest order accepted (sections beyond this add nothing but round-off).
pub const MAX_ORDER: usize = 10;

/// Length of the end extension and of the settling, in time constants of the slowest pole.
pub const SETTLE_TIME_CONSTANTS: f64 = 14.0;

/// Lowest cutoff accepted, relative to the sampling rate.
pub const MIN_RELATIVE_CUTOFF: f64 = 1e-6;

/// Order used when the caller gives none.
pub const DEFAULT_ORDER: usize = 4;

/// One second-order section `(b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Section {
    b: [f64; 3],
    a: [f64; 2],
}

impl Section {
    fn dc_gain(&self) -> f64 {
        (self.b[0] + self.b[1] + self.b[2]) / (1.0 + self.a[0] + self.a[1])
    }

    /// Transposed direct form II state for a constant input `u` held forever.
    fn steady_state(&self, u: f64) -> [f64; 2] {
        let y = self.dc_gain() * u;
        let s2 = self.b[2] * u - self.a[1] * y;
        let s1 = self.b[1] * u - self.a[0] * y + s2;
        [s1, s2]
    }

    fn response(&self, z: Complex64) -> Complex64 {
        let zi = z.inv();
        (self.b[0] + zi * (self.b[1] + zi * self.b[2])) / (1.0 + zi * (self.a[0] + zi * self.a[1]))
    }
}

/// Low- or high-pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Band {
    /// Low-pass.
    Lowpass,
    /// High-pass.
    Highpass,
}

/// A digital Butterworth filter as a cascade of second-order sections.
#[derive(Debug, Clone)]
pub struct Butterworth {
    sections: Vec<Section>,
    step_s: f64,
    /// Length of the end extension, samples.
    settle_samples: usize,
}

impl Butterworth {
    /// Designs a filter of `order` with -3 dB point `cutoff_hz` for samples `step_s` apart.
    pub fn new(band: Band, order: usize, cutoff_hz: f64, step_s: f64) -> Result<Self> {
        let rate_hz = 1.0 / step_s;
        if !(1..=MAX_ORDER).contains(&order) {
            return Err(PostError::InvalidOption(format!(
                "filter order {order}; expected 1 to {MAX_ORDER}"
            )));
        }
        if !(step_s.is_finite() && step_s > 0.0) {
            return Err(PostError::InvalidOption(format!(
                "sampling step {step_s} s; expected a positive number"
            )));
        }
        // Below 1e-6 of the sampling rate the poles crowd z = 1 and round-off takes over.
        if !(cutoff_hz >= MIN_RELATIVE_CUTOFF * rate_hz && cutoff_hz < 0.5 * rate_hz) {
            return Err(PostError::InvalidOption(format!(
                "cutoff {} Hz; expected between {} Hz and the Nyquist frequency {} Hz",
                show(cutoff_hz),
                show(MIN_RELATIVE_CUTOFF * rate_hz),
                show(0.5 * rate_hz)
            )));
        }
        let two_fs = 2.0 * rate_hz;
        let omega_c = two_fs * (PI * cutoff_hz / rate_hz).tan();
        let bilinear = |s: Complex64| (two_fs + s) / (two_fs - s);
        let prototype = |k: usize| {
            Complex64::from_polar(1.0, PI * (2 * k + order - 1) as f64 / (2 * order) as f64)
        };
        let analog = |p: Complex64| match band {
            Band::Lowpass => p * omega_c,
            Band::Highpass => omega_c / p,
        };
        let zero_sign = match band {
            Band::Lowpass => 1.0,
            Band::Highpass => -1.0,
        };

        let mut sections = Vec::new();
        // k = 1..N/2 are the upper-half-plane poles; their conjugates are k = N+1-k.
        for k in 1..=order / 2 {
            let z = bilinear(analog(prototype(k)));
            sections.push(Section {
                b: [1.0, 2.0 * zero_sign, 1.0],
                a: [-2.0 * z.re, z.norm_sqr()],
            });
        }
        if order % 2 == 1 {
            let z = bilinear(analog(Complex64::new(-1.0, 0.0)));
            sections.push(Section {
                b: [1.0, zero_sign, 0.0],
                a: [-z.re, 0.0],
            });
        }
        let reference = Complex64::new(zero_sign, 0.0);
        for section in &mut sections {
            let gain = section.response(reference).norm();
            for b in &mut section.b {
                *b /= gain;
            }
        }
        // The slowest pole, closest to the imaginary axis, has real part
        // omega_c sin(pi / 2N): its envelope falls by e^-14 (~1e-6) in 14 time constants.
        let time_constant_s = 1.0 / (2.0 * PI * cutoff_hz * (PI / (2 * order) as f64).sin());
        let settle_samples = (SETTLE_TIME_CONSTANTS * time_constant_s * rate_hz).ceil() as usize;
        Ok(Butterworth {
            sections,
            step_s,
            settle_samples,
        })
    }

    /// Samples at each end of a [`Butterworth::filtfilt`] output still touched by the start-up
    /// transient (`6 f_s / f_c`; see the module doc).
    pub fn settle_samples(&self) -> usize {
        self.settle_samples
    }

    /// Complex response of one forward pass at `frequency_hz`.
    pub fn response(&self, frequency_hz: f64) -> Complex64 {
        let z = Complex64::from_polar(1.0, 2.0 * PI * frequency_hz * self.step_s);
        self.sections
            .iter()
            .map(|section| section.response(z))
            .product()
    }

    /// Causal filtering, starting from the steady state of `x[0]`.
    pub fn filter(&self, x: &[f64]) -> Vec<f64> {
        let mut y = x.to_vec();
        for section in &self.sections {
            let Some(&first) = y.first() else {
                break;
            };
            let [mut s1, mut s2] = section.steady_state(first);
            for v in &mut y {
                let input = *v;
                let output = section.b[0] * input + s1;
                s1 = section.b[1] * input - section.a[0] * output + s2;
                s2 = section.b[2] * input - section.a[1] * output;
                *v = output;
            }
        }
        y
    }

    /// Zero-phase forward-backward filtering with reflected ends (see the module doc).
    pub fn filtfilt(&self, x: &[f64]) -> Vec<f64> {
        let n = x.len();
        if n < 2 {
            return x.to_vec();
        }
        let pad = self.settle_samples.min(n - 1);
        let mut extended = Vec::with_capacity(n + 2 * pad);
        extended.extend((1..=pad).rev().map(|k| 2.0 * x[0] - x[k]));
        extended.extend_from_slice(x);
        extended.extend((1..=pad).map(|k| 2.0 * x[n - 1] - x[n - 1 - k]));

        let mut forward = self.filter(&extended);
        forward.reverse();
        let mut backward = self.filter(&forward);
        backward.reverse();
        backward[pad..pad + n].to_vec()
    }
}

/// Zero-phase low-pass of order `order` at `cutoff_hz` (see the module doc).
pub fn lowpass_zero_phase(
    x: &[f64],
    step_s: f64,
    cutoff_hz: f64,
    order: usize,
) -> Result<Vec<f64>> {
    Ok(Butterworth::new(Band::Lowpass, order, cutoff_hz, step_s)?.filtfilt(x))
}

/// Zero-phase band-pass: a high-pass at `low_hz` followed by a low-pass at `high_hz`.
pub fn bandpass_zero_phase(
    x: &[f64],
    step_s: f64,
    low_hz: f64,
    high_hz: f64,
    order: usize,
) -> Result<Vec<f64>> {
    if !matches!(low_hz.partial_cmp(&high_hz), Some(std::cmp::Ordering::Less)) {
        return Err(PostError::InvalidOption(format!(
            "band {low_hz} to {high_hz} Hz; expected low < high"
        )));
    }
    let high = Butterworth::new(Band::Highpass, order, low_hz, step_s)?;
    let low = Butterworth::new(Band::Lowpass, order, high_hz, step_s)?;
    Ok(low.filtfilt(&high.filtfilt(x)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn butterworth_magnitude_matches_the_closed_form() {
        let step = 1e-3;
        for order in [1, 2, 3, 4, 7] {
            let filter = Butterworth::new(Band::Lowpass, order, 50.0, step).unwrap();
            for f in [0.0, 4.35, 20.0, 50.0, 120.0, 400.0] {
                let ratio = (PI * f * step).tan() / (PI * 50.0 * step).tan();
                let exact = 1.0 / (1.0 + ratio.powi(2 * order as i32)).sqrt();
                let got = filter.response(f).norm();
                assert!(
                    (got - exact).abs() < 1e-12,
                    "order {order}, {f} Hz: {got} vs {exact}"
                );
            }
            assert!(filter.response(500.0).norm() < 1e-12);
            let high = Butterworth::new(Band::Highpass, order, 2.0, step).unwrap();
            let ratio = (PI * 2.0 * step).tan() / (PI * 8.0 * step).tan();
            let exact = 1.0 / (1.0 + ratio.powi(2 * order as i32)).sqrt();
            assert!((high.response(8.0).norm() - exact).abs() < 1e-12);
            assert!(high.response(0.0).norm() < 1e-12);
        }
    }

    #[test]
    fn bad_options_are_errors() {
        assert!(Butterworth::new(Band::Lowpass, 4, 500.0, 1e-3).is_err());
        assert!(Butterworth::new(Band::Lowpass, 0, 50.0, 1e-3).is_err());
        assert!(Butterworth::new(Band::Lowpass, 4, -1.0, 1e-3).is_err());
        assert!(Butterworth::new(Band::Lowpass, 4, 1e-300, 1e-3).is_err());
        assert!(Butterworth::new(Band::Lowpass, 4, f64::NAN, 1e-3).is_err());
        assert!(bandpass_zero_phase(&[0.0; 10], 1e-3, 10.0, 5.0, 4).is_err());
    }

    /// The in-band sine keeps amplitude and phase; the Nyquist ripple vanishes.
    #[test]
    fn lowpass_keeps_an_in_band_sine_and_kills_a_nyquist_ripple() {
        let step = 1e-3;
        let n = 10_000;
        let omega = 2.0 * PI * 4.35;
        let clean: Vec<f64> = (0..n)
            .map(|i| (omega * i as f64 * step + 0.7).sin())
            .collect();
        let noisy: Vec<f64> = clean
            .iter()
            .enumerate()
            .map(|(i, v)| v + if i % 2 == 0 { 0.05 } else { -0.05 })
            .collect();
        let filtered = lowpass_zero_phase(&noisy, step, 50.0, 4).unwrap();
        let error = |range: std::ops::Range<usize>| {
            range
                .map(|i| (filtered[i] - clean[i]).abs())
                .fold(0.0, f64::max)
        };
        // Interior: |H|^2 at 4.35 Hz differs from 1 by 3e-9; the ripple is a zero of H.
        let interior = error(200..n - 200);
        assert!(interior < 1e-8, "interior error {interior:e}");
        // Ends: the reflection pivots on x[0], which carries the ripple, so the first output
        // sample keeps it (0.05); the transient then dies with the slowest pole: measured
        // 2e-3 at 20 samples, 1.4e-4 at 40, 1e-8 at 117 = settle_samples().
        let filter = Butterworth::new(Band::Lowpass, 4, 50.0, step).unwrap();
        let settle = filter.settle_samples();
        // 14 / (2 pi 50 Hz sin(pi / 8)) = 0.1164 s.
        assert_eq!(settle, 117);
        assert!(error(0..settle).max(error(n - settle..n)) <= 0.0501);
        let after_settling = error(settle..settle + 10).max(error(n - settle - 10..n - settle));
        assert!(
            after_settling < 1e-7,
            "error after settling {after_settling:e}"
        );
    }

    #[test]
    fn bandpass_keeps_the_band_and_removes_offset_and_ripple() {
        let step = 1e-3;
        let n = 8000;
        let omega = 2.0 * PI * 5.0;
        let clean: Vec<f64> = (0..n).map(|i| (omega * i as f64 * step).cos()).collect();
        let dirty: Vec<f64> = clean
            .iter()
            .enumerate()
            .map(|(i, v)| v + 3.0 + 0.1 * (2.0 * PI * 80.0 * i as f64 * step).sin())
            .collect();
        let filtered = bandpass_zero_phase(&dirty, step, 2.5, 10.0, 4).unwrap();
        // The pass band of an order-4 octave band still loses 2 x 0.4% at its centre:
        // the forward-backward gain is |H_high(5)|^2 |H_low(5)|^2.
        let high = Butterworth::new(Band::Highpass, 4, 2.5, step).unwrap();
        let low = Butterworth::new(Band::Lowpass, 4, 10.0, step).unwrap();
        let gain = (high.response(5.0).norm() * low.response(5.0).norm()).powi(2);
        assert!((gain - 0.9922).abs() < 1e-3, "gain {gain}");
        let settle = high.settle_samples();
        let interior = (settle..n - settle)
            .map(|i| (filtered[i] - gain * clean[i]).abs())
            .fold(0.0, f64::max);
        // What is left: the 80 Hz tone at |H_low(80)|^2 ~ 6e-8 and the offset at 0.
        assert!(interior < 1e-6, "interior error {interior:e}");
    }
}
