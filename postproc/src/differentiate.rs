//! Acceleration from a displacement or velocity record: a zero-phase low-pass followed
//! by a sixth-order central difference.
//!
//! # Formulation
//! A position sensor (laser, LVDT, video) writes `x_i = x(t_i) + e_i` on a uniform step
//! `dt`, `e_i` its noise and quantisation. Differentiating twice multiplies the noise at
//! frequency `f` by `(2 pi f)^2`, so the record is first low-passed: a Butterworth filter
//! of order [`ORDER`], run forward and backward ([`crate::filter::Butterworth::filtfilt`],
//! magnitude `|H(f)|^2`, zero phase), with the cut-off
//!
//! ```text
//! f_c = min(CUTOFF_OVER_DOMINANT f_0, MAX_CUTOFF_OVER_RATE f_s)
//! ```
//!
//! from the record's dominant frequency `f_0`: four times `f_0` keeps the third harmonic
//! (a cubic spring's and dry friction's) at `|H|^2 = 1/(1 + (3/4)^12) = 0.969`, the
//! dominant line at `1 - 6e-8`, and the coupled pair (0.7-1.3 `f_0`) at better than 1e-4.
//! The difference stencils are exact for polynomials up to degree 6 (Fornberg, "Generation
//! of finite difference formulas on arbitrarily spaced grids", Math. Comp. 51, 1988):
//!
//! ```text
//! x'_i  = (-x_{i-3} + 9 x_{i-2} - 45 x_{i-1} + 45 x_{i+1} - 9 x_{i+2} + x_{i+3}) / (60 dt)
//! x''_i = (2 x_{i-3} - 27 x_{i-2} + 270 x_{i-1} - 490 x_i + 270 x_{i+1} - 27 x_{i+2} + 2 x_{i+3}) / (180 dt^2)
//! ```
//!
//! Both are symmetric (or antisymmetric), so the whole chain has zero phase. On
//! `e^{i w t}`, with `theta = w dt`, their symbols are
//!
//! ```text
//! D1(theta) = i (90 sin theta - 18 sin 2 theta + 2 sin 3 theta) / (60 dt)
//! D2(theta) = -(490 - 540 cos theta + 54 cos 2 theta - 4 cos 3 theta) / (180 dt^2)
//! ```
//!
//! so the chain's gain relative to the exact derivative, [`Differentiator::gain`], is
//! `|H(f)|^2 D_n(theta) / (i w)^n`: 1 - theta^6/140 (first) and 1 - theta^6/560
//! (second derivative) in the band. At the coarsest sampling met (a 4.35 Hz spring
//! filmed at 30 Hz, theta = 0.91) that is 0.9959 and 0.9990 for the dominant line.
//!
//! # Noise
//! White noise of standard deviation `s` (quantisation in steps `q`: `s = q / sqrt 12`)
//! comes out of the second derivative with variance
//! `s^2 (2/f_s) integral_0^{f_s/2} |H(f)|^4 |D2(2 pi f dt)|^2 df`, about
//! `s^2 (2 pi)^4 f_c^5 / (2.5 f_s)` for a sharp cut-off. [`Differentiator::noise_gain`]
//! evaluates the integral numerically; the tests check it on quantised and white noise.
//!
//! # Ends
//! The stencils need three samples on each side: the derivative has `n - 6` samples, for
//! the times `t_3 .. t_{n-4}`. The filter's reflected ends keep value and slope
//! continuous; what they get wrong decays within a few periods of `f_c`.

use crate::error::{PostError, Result};
use crate::filter::{Band, Butterworth};
use std::f64::consts::PI;

/// Order of the Butterworth low-pass (each of its two passes).
pub const ORDER: usize = 6;
/// Cut-off over the dominant frequency.
pub const CUTOFF_OVER_DOMINANT: f64 = 4.0;
/// Highest cut-off over the sampling rate (below Nyquist, where the stencils still hold).
pub const MAX_CUTOFF_OVER_RATE: f64 = 0.4;
/// Samples lost at each end to the stencils.
pub const HALF_WIDTH: usize = 3;

const FIRST: [f64; 7] = [-1.0, 9.0, -45.0, 0.0, 45.0, -9.0, 1.0];
const FIRST_SCALE: f64 = 60.0;
const SECOND: [f64; 7] = [2.0, -27.0, 270.0, -490.0, 270.0, -27.0, 2.0];
const SECOND_SCALE: f64 = 180.0;

/// The low-pass and the stencils for one record.
#[derive(Debug, Clone)]
pub struct Differentiator {
    /// The low-pass cut-off (Hz).
    pub cutoff_hz: f64,
    /// Sampling step (s).
    pub step_s: f64,
    lowpass: Butterworth,
}

impl Differentiator {
    /// The filter for a record sampled every `step_s` whose dominant frequency is
    /// `dominant_hz` (module docs for the cut-off).
    pub fn for_dominant(dominant_hz: f64, step_s: f64) -> Result<Self> {
        if !(dominant_hz.is_finite() && dominant_hz > 0.0 && step_s.is_finite() && step_s > 0.0) {
            return Err(PostError::InvalidOption(format!(
                "differentiation at a dominant frequency of {dominant_hz} Hz with a step of \
                 {step_s} s; expected both positive"
            )));
        }
        let cutoff_hz = (CUTOFF_OVER_DOMINANT * dominant_hz).min(MAX_CUTOFF_OVER_RATE / step_s);
        Ok(Differentiator {
            cutoff_hz,
            step_s,
            lowpass: Butterworth::new(Band::Lowpass, ORDER, cutoff_hz, step_s)?,
        })
    }

    /// The low-passed record (same length).
    pub fn smooth(&self, x: &[f64]) -> Vec<f64> {
        self.lowpass.filtfilt(x)
    }

    /// First derivative of `x` (unit of x per second), `n - 6` samples (module docs).
    pub fn first_derivative(&self, x: &[f64]) -> Vec<f64> {
        stencil(&self.smooth(x), &FIRST, FIRST_SCALE * self.step_s)
    }

    /// Second derivative of `x` (unit of x per second squared), `n - 6` samples.
    pub fn second_derivative(&self, x: &[f64]) -> Vec<f64> {
        stencil(
            &self.smooth(x),
            &SECOND,
            SECOND_SCALE * self.step_s * self.step_s,
        )
    }

    /// Gain of the chain for derivative `order` (1 or 2) at `frequency_hz`, relative to
    /// the exact derivative `(i w)^order` (real: the chain has zero phase).
    pub fn gain(&self, order: usize, frequency_hz: f64) -> f64 {
        let w = 2.0 * PI * frequency_hz;
        let theta = w * self.step_s;
        let h2 = self.lowpass.response(frequency_hz).norm_sqr();
        let stencil = if order == 1 {
            (90.0 * theta.sin() - 18.0 * (2.0 * theta).sin() + 2.0 * (3.0 * theta).sin())
                / (60.0 * theta)
        } else {
            (490.0 - 540.0 * theta.cos() + 54.0 * (2.0 * theta).cos() - 4.0 * (3.0 * theta).cos())
                / (180.0 * theta * theta)
        };
        h2 * stencil
    }

    /// Standard deviation of the derivative of `order` of unit white noise:
    /// `sqrt((2/f_s) integral_0^{f_s/2} (gain(f) (2 pi f)^order)^2 df)` (midpoint rule,
    /// 20 000 panels).
    pub fn noise_gain(&self, order: usize) -> f64 {
        let nyquist = 0.5 / self.step_s;
        let panels = 20_000;
        let df = nyquist / panels as f64;
        let sum: f64 = (0..panels)
            .map(|k| {
                let f = (k as f64 + 0.5) * df;
                (self.gain(order, f) * (2.0 * PI * f).powi(order as i32)).powi(2)
            })
            .sum();
        (2.0 * self.step_s * sum * df).sqrt()
    }
}

fn stencil(x: &[f64], weights: &[f64; 7], scale: f64) -> Vec<f64> {
    x.windows(7)
        .map(|w| w.iter().zip(weights).map(|(a, b)| a * b).sum::<f64>() / scale)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic uniform numbers in [-0.5, 0.5) (a 64-bit LCG).
    fn uniform(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    /// A sinusoid's derivatives come out with the closed-form gain and no phase, at 30 Hz
    /// (theta = 0.91) and 1 kHz sampling and up to the cut-off: measured amplitude and
    /// phase by least squares on the interior (away from the ends).
    #[test]
    fn gain_and_phase_match_the_closed_form() {
        for (f0, fs) in [(4.35, 30.0), (4.35, 100.0), (10.0, 1000.0)] {
            let d = Differentiator::for_dominant(f0, 1.0 / fs).unwrap();
            for ratio in [0.5, 1.0, 1.3, 3.0] {
                let f = ratio * f0;
                if f >= 0.45 * fs {
                    continue;
                }
                let w = 2.0 * PI * f;
                let n = (400.0 * fs / f0) as usize;
                let x: Vec<f64> = (0..n).map(|i| (w * i as f64 / fs + 0.4).sin()).collect();
                for order in [1, 2] {
                    let y = if order == 1 {
                        d.first_derivative(&x)
                    } else {
                        d.second_derivative(&x)
                    };
                    // Fit y = a cos + b sin on the middle half.
                    let (mut scc, mut sss, mut scs, mut syc, mut sys) = (0.0, 0.0, 0.0, 0.0, 0.0);
                    for (j, v) in y.iter().enumerate().skip(n / 4).take(n / 2) {
                        let t = (j + HALF_WIDTH) as f64 / fs;
                        let (s, c) = (w * t + 0.4).sin_cos();
                        scc += c * c;
                        sss += s * s;
                        scs += c * s;
                        syc += v * c;
                        sys += v * s;
                    }
                    let det = scc * sss - scs * scs;
                    let a = (syc * sss - sys * scs) / det;
                    let b = (sys * scc - syc * scs) / det;
                    // Exact: order 1 -> w cos, order 2 -> -w^2 sin.
                    let (amp, phase_err) = if order == 1 {
                        (a / w, b / a)
                    } else {
                        (-b / (w * w), a / b)
                    };
                    let expected = d.gain(order, f);
                    assert!(
                        (amp - expected).abs() < 1e-6,
                        "f0 {f0} fs {fs} f {f} order {order}: {amp} vs {expected}"
                    );
                    assert!(phase_err.abs() < 1e-6, "{phase_err}");
                    if ratio <= 1.3 {
                        // In the band, within the stencil's theta^6 error.
                        let theta = w / fs;
                        assert!((1.0 - amp).abs() < theta.powi(6) / 100.0 + 1e-4, "{amp}");
                    }
                }
            }
        }
    }

    /// Quantised position (0.1 mm steps of a 4 mm, 4.35 Hz decay at 100 Hz): the error
    /// of the derived acceleration has the standard deviation that `noise_gain` predicts
    /// for white noise of `q / sqrt 12`, within 15 % (quantisation noise is nearly white
    /// when the signal crosses many steps per sample), and stays a few percent of the
    /// acceleration's amplitude.
    #[test]
    fn quantised_position_noise_is_amplified_as_predicted() {
        let (f0, fs, amp_mm, q) = (4.35, 100.0, 4.0, 0.1);
        let w = 2.0 * PI * f0;
        let n = 6000;
        let truth = |t: f64| amp_mm * (w * t).sin();
        let x: Vec<f64> = (0..n)
            .map(|i| (truth(i as f64 / fs) / q).round() * q)
            .collect();
        let d = Differentiator::for_dominant(f0, 1.0 / fs).unwrap();
        let a = d.second_derivative(&x);
        let gain = d.gain(2, f0);
        let errors: Vec<f64> = a
            .iter()
            .enumerate()
            .skip(200)
            .take(a.len() - 400)
            .map(|(j, v)| v + gain * w * w * truth((j + HALF_WIDTH) as f64 / fs))
            .collect();
        let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
        let predicted = d.noise_gain(2) * q / 12f64.sqrt();
        println!(
            "cut-off {:.2} Hz, error rms {rms:.4} mm/s^2, predicted {predicted:.4}, \
             amplitude {:.1}",
            d.cutoff_hz,
            amp_mm * w * w
        );
        assert!((rms / predicted - 1.0).abs() < 0.15, "{rms} vs {predicted}");
        assert!(rms < 0.03 * amp_mm * w * w);
    }

    /// White noise: the measured amplification of both derivatives matches `noise_gain`
    /// to the sampling error of a standard deviation over ~n/(f_s/f_c) independent values.
    #[test]
    fn white_noise_amplification() {
        let fs = 200.0;
        let d = Differentiator::for_dominant(5.0, 1.0 / fs).unwrap();
        let mut seed = 11;
        let n = 40_000;
        let x: Vec<f64> = (0..n).map(|_| uniform(&mut seed) * 12f64.sqrt()).collect();
        for order in [1, 2] {
            let y = if order == 1 {
                d.first_derivative(&x)
            } else {
                d.second_derivative(&x)
            };
            let inner = &y[500..y.len() - 500];
            let rms = (inner.iter().map(|e| e * e).sum::<f64>() / inner.len() as f64).sqrt();
            let predicted = d.noise_gain(order);
            assert!(
                (rms / predicted - 1.0).abs() < 0.05,
                "order {order}: {rms} vs {predicted}"
            );
        }
    }

    #[test]
    fn nonsense_is_refused() {
        assert!(Differentiator::for_dominant(0.0, 0.01).is_err());
        assert!(Differentiator::for_dominant(5.0, f64::NAN).is_err());
    }
}
