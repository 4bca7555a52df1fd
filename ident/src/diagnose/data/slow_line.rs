//! A slow line beside the oscillation (module docs of [`super`], step 8): a second,
//! slower mode of the rig (its frame, a pendulum swing of the weight, a coupled mode
//! five to ten times slower) adds to the record a lightly damped oscillation far below
//! the axial line, which no catalogue effect models.
//!
//! # Formulation
//! The measured quantity `y` (SI), less its straight line, is averaged twice by a
//! centred moving average over `m` samples, `m` the odd number nearest below one axial
//! period: its gain `H = sin(m x)/(m sin x)`, `x = w h / 2`, is zero at the axial line
//! and its harmonics when `m h` is the period (within one sample of it, under
//! `1/m` per pass), and on `e^(lambda t)` it is the complex
//! `H(lambda) = (1/m) sum_k e^(lambda k h)`, so the average `z` keeps a damped line's
//! form (`z` starts `m - 1` samples after the record, where both averages reach full
//! windows). A low-pass filter would not do: its start-up on the axial oscillation's
//! first sample is a transient larger than the line. The slow line is the damped
//! sinusoid `s(t) = e^(-sigma t) (a cos(w t) + b sin(w t))` beside a straight line
//! `c0 + c1 t` (the offset and drift): for given `(w, sigma)` the four coefficients are
//! linear least squares, and `(w, sigma)` minimise what is left of `z` (variable
//! projection, Golub and Pereyra 1973; Levenberg-Marquardt from `z`'s zero-crossing rate
//! and `sigma = 0`); `a - i b` is `z`'s over `H(lambda)^2`. It is a line below
//! [`CUTOFF`] of the axial frequency, and is kept, when all hold:
//! - `z` crosses zero (with the crossings' hysteresis) at least [`MIN_CROSSINGS`] times
//!   (two slow cycles: a drift or the slow shift of a softening spring's centre does not);
//! - the line explains at least [`MIN_EXPLAINED`] of `z`'s power about its straight line
//!   (a friction record's rest after it sticks, a step, is no line);
//! - its amplitude at the start `sqrt(a^2 + b^2)` is at least [`MIN_SNR`] times the
//!   standard deviation the first average leaves of the record's white noise,
//!   `sigma_noise / sqrt(m)` (the second average lowers it further, by `sqrt(2/3)`);
//! - its damping ratio `sigma / sqrt(sigma^2 + w^2)` is below [`MAX_DAMPING_RATIO`].
//!
//! The line's form is then fitted beside every model as the offset and drift are (its
//! amplitude and phase by least squares, `fit::Segment::slow_line`), and its
//! acceleration, `Re(C lambda^k e^(lambda t))` with `C = a - i b`,
//! `lambda = -sigma + i w` and `k` the derivatives from the measured quantity to the
//! acceleration, is removed from the acceleration the signatures read.
//!
//! Units: SI (the measured quantity's unit for `a` and `b`); `w` in rad/s, `sigma` in 1/s.

use super::crossings::crossings;
use crate::case::Quantity;
use crate::diagnose::lm::{self, LmOptions};
use serde::Serialize;

/// The highest frequency of a slow line, as a share of the axial frequency.
pub const CUTOFF: f64 = 0.5;
/// Fewest zero crossings of the low-passed record (two slow cycles).
pub const MIN_CROSSINGS: usize = 4;
/// Smallest share of the low-passed record's power (about its straight line) the line
/// explains.
pub const MIN_EXPLAINED: f64 = 0.8;
/// Smallest amplitude of the line at the record's start, in standard deviations of the
/// averaged noise.
pub const MIN_SNR: f64 = 10.0;
/// Largest damping ratio of a line.
pub const MAX_DAMPING_RATIO: f64 = 0.2;

/// A slow line found in a decay record.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SlowLine {
    /// Its angular frequency `w` (rad/s).
    pub omega_rad_s: f64,
    /// Its decay rate `sigma` (1/s).
    pub decay_rate_1_s: f64,
    /// Its cosine and sine coefficients `a`, `b` at the record's first sample (the
    /// measured quantity's SI unit).
    pub coefficients: [f64; 2],
    /// The share of the low-passed record's power it explains (-).
    pub explained: f64,
}

impl SlowLine {
    /// Its frequency (Hz).
    pub fn frequency_hz(&self) -> f64 {
        self.omega_rad_s / std::f64::consts::TAU
    }

    /// Its amplitude at the record's start (the measured quantity's SI unit).
    pub fn amplitude(&self) -> f64 {
        self.coefficients[0].hypot(self.coefficients[1])
    }

    /// Its damping ratio (-).
    pub fn damping_ratio(&self) -> f64 {
        self.decay_rate_1_s / self.decay_rate_1_s.hypot(self.omega_rad_s)
    }

    /// The two columns of its form, `e^(-sigma t) cos(w t)` and `e^(-sigma t) sin(w t)`,
    /// over `n` samples `step_s` apart from the record's start.
    pub fn columns(omega: f64, sigma: f64, step_s: f64, n: usize) -> [Vec<f64>; 2] {
        let at = |i: usize| {
            let t = i as f64 * step_s;
            let e = (-sigma * t).exp();
            (e * (omega * t).cos(), e * (omega * t).sin())
        };
        [
            (0..n).map(|i| at(i).0).collect(),
            (0..n).map(|i| at(i).1).collect(),
        ]
    }

    /// Its `k`-th time derivative at `n` samples `step_s` apart from the start.
    pub fn derivative(&self, k: usize, step_s: f64, n: usize) -> Vec<f64> {
        // C lambda^k as a complex number (re, im); Re(C lambda^k e^(lambda t)).
        let (mut re, mut im) = (self.coefficients[0], -self.coefficients[1]);
        let (lr, li) = (-self.decay_rate_1_s, self.omega_rad_s);
        for _ in 0..k {
            (re, im) = (re * lr - im * li, re * li + im * lr);
        }
        let [c, s] = Self::columns(self.omega_rad_s, self.decay_rate_1_s, step_s, n);
        // Re((re + i im)(cos + i sin) e^(-sigma t)) = re cos - im sin.
        c.iter().zip(&s).map(|(c, s)| re * c - im * s).collect()
    }
}

/// The least-squares residual of `z` (samples `step_s` apart from `t0`) on the straight
/// line and the damped sinusoid of `(omega, sigma)`, and the coefficients
/// `[c0, c1, a, b]` (`a`, `b` at `t = 0`).
fn projected(
    z: &[f64],
    t0: f64,
    step_s: f64,
    omega: f64,
    sigma: f64,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let n = z.len();
    let columns = vec![
        vec![1.0; n],
        (0..n).map(|i| i as f64 / n as f64).collect(),
        (0..n)
            .map(|i| {
                let t = t0 + i as f64 * step_s;
                (-sigma * t).exp() * (omega * t).cos()
            })
            .collect(),
        (0..n)
            .map(|i| {
                let t = t0 + i as f64 * step_s;
                (-sigma * t).exp() * (omega * t).sin()
            })
            .collect::<Vec<f64>>(),
    ];
    let coef = lm::linear_least_squares(&columns, z)?;
    let residual = (0..n)
        .map(|i| {
            z[i] - columns
                .iter()
                .zip(&coef)
                .map(|(col, k)| k * col[i])
                .sum::<f64>()
        })
        .collect();
    Some((residual, coef))
}

/// The centred moving average of `m` samples (odd), over the samples it reaches fully.
fn moving_average(x: &[f64], m: usize) -> Vec<f64> {
    if x.len() < m {
        return Vec::new();
    }
    let mut sum: f64 = x[..m].iter().sum();
    let mut out = vec![sum / m as f64];
    for i in m..x.len() {
        sum += x[i] - x[i - m];
        out.push(sum / m as f64);
    }
    out
}

/// The complex gain `(1/m) sum_k e^(lambda k h)`, `k = -(m-1)/2 .. (m-1)/2`, of the
/// centred moving average of `m` samples on `e^(lambda t)`, `lambda = -sigma + i w`.
fn moving_average_gain(m: usize, step_s: f64, omega: f64, sigma: f64) -> (f64, f64) {
    let half = (m as i64 - 1) / 2;
    let (mut re, mut im) = (0.0, 0.0);
    for k in -half..=half {
        let t = k as f64 * step_s;
        let e = (-sigma * t).exp();
        re += e * (omega * t).cos();
        im += e * (omega * t).sin();
    }
    (re / m as f64, im / m as f64)
}

/// The slow line of the measured record `y` (`step_s` apart, the oscillation at
/// `frequency_hz`, white noise `noise_rms` per sample), if it holds one (module docs).
pub fn find(y: &[f64], step_s: f64, frequency_hz: f64, noise_rms: f64) -> Option<SlowLine> {
    // Twice the centred moving average over one axial period (an odd number of
    // samples): zero gain at the axial line and its harmonics, a known gain on the
    // slow line's form, which it keeps.
    let period = 1.0 / (frequency_hz * step_s);
    if !(period.is_finite() && period >= 3.0) {
        return None;
    }
    let m = 2 * ((period / 2.0).floor() as usize) + 1;
    let detrended = coil_postproc::noise::detrend(y);
    let z = moving_average(&moving_average(&detrended, m), m);
    let t0 = (m - 1) as f64 * step_s;
    if z.len() < 4 * m {
        return None;
    }
    let time: Vec<f64> = (0..z.len()).map(|i| t0 + i as f64 * step_s).collect();
    let (count, span_s) = crossings(&z, &time);
    if count < MIN_CROSSINGS || span_s <= 0.0 {
        return None;
    }
    let omega0 = std::f64::consts::PI * (count - 1) as f64 / span_s;
    let residuals = |p: &[f64]| -> Result<Vec<f64>, String> {
        projected(&z, t0, step_s, p[0], p[1])
            .map(|r| r.0)
            .ok_or_else(|| "no projection".to_string())
    };
    let options = LmOptions {
        max_iterations: 60,
        scale: vec![omega0, 0.01 * omega0],
    };
    let fit = lm::fit(&residuals, &[omega0, 0.0], &options).ok()?;
    let (omega, sigma) = (fit.params[0], fit.params[1]);
    let (residual, coef) = projected(&z, t0, step_s, omega, sigma)?;
    // The power about the straight line alone.
    let n = z.len();
    let ramp: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
    let straight = lm::linear_least_squares(&[vec![1.0; n], ramp.clone()], &z)?;
    let power: f64 = (0..n)
        .map(|i| (z[i] - straight[0] - straight[1] * ramp[i]).powi(2))
        .sum();
    let left: f64 = residual.iter().map(|x| x * x).sum();
    // The coefficients before the two averages: C = C_z / H^2, C = a - i b.
    let (hr, hi) = moving_average_gain(m, step_s, omega, sigma);
    let (gr, gi) = (hr * hr - hi * hi, 2.0 * hr * hi);
    let (zr, zi) = (coef[2], -coef[3]);
    let norm = gr * gr + gi * gi;
    if norm <= 0.0 {
        return None;
    }
    let (cr, ci) = ((zr * gr + zi * gi) / norm, (zi * gr - zr * gi) / norm);
    let line = SlowLine {
        omega_rad_s: omega,
        decay_rate_1_s: sigma,
        coefficients: [cr, -ci],
        explained: if power > 0.0 { 1.0 - left / power } else { 0.0 },
    };
    let keep = omega > 0.0
        && omega < CUTOFF * std::f64::consts::TAU * frequency_hz
        && line.explained >= MIN_EXPLAINED
        && line.amplitude() >= MIN_SNR * noise_rms / (m as f64).sqrt()
        && line.damping_ratio().abs() < MAX_DAMPING_RATIO;
    keep.then_some(line)
}

/// The warning that says what was found and done.
pub fn note(line: &SlowLine, frequency_hz: f64, quantity: Quantity, file: &str) -> String {
    let (scale, unit) = match quantity {
        Quantity::Displacement => (1e3, "mm"),
        Quantity::Velocity => (1.0, "m/s"),
        Quantity::Acceleration => (1.0, "m/s^2"),
    };
    format!(
        "{file}: a slow line at {:.4} Hz ({:.1} times slower than the {frequency_hz:.4} Hz \
         oscillation), {:.4} {unit} at the start, damping ratio {:.4}, {:.1} % of the record \
         below {:.3} Hz: another mode of the rig, which no catalogue effect models; its \
         form is fitted beside every model as the offset and drift are (amplitude and \
         phase by least squares), and its acceleration is removed from the signatures' record",
        line.frequency_hz(),
        frequency_hz / line.frequency_hz(),
        scale * line.amplitude(),
        line.damping_ratio(),
        100.0 * line.explained,
        CUTOFF * frequency_hz
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A damped line an eighth of the axial frequency beside a decaying axial one is
    /// found with its frequency and decay rate; the axial decay alone holds none.
    #[test]
    fn finds_a_slow_line_and_no_other() {
        let (fs, f) = (200.0, 5.0);
        let n = 1600;
        let (ws, sigma) = (std::f64::consts::TAU * f / 8.0, 0.04);
        let axial = |t: f64| 3e-3 * (-0.03 * t).exp() * (std::f64::consts::TAU * f * t).cos();
        let slow = |t: f64| 0.9e-3 * (-sigma * t).exp() * (ws * t + 0.7).cos();
        let noise = |i: usize| 1.5e-5 * ((i as f64 * 12.9898).sin() * 43758.5453).fract();
        let with: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                axial(t) + slow(t) + 0.01 + 1e-4 * t + noise(i)
            })
            .collect();
        let line = find(&with, 1.0 / fs, f, 1e-5).expect("the slow line");
        assert!((line.omega_rad_s / ws - 1.0).abs() < 1e-3, "{line:?}");
        assert!((line.decay_rate_1_s - sigma).abs() < 2e-3, "{line:?}");
        assert!((line.amplitude() / 0.9e-3 - 1.0).abs() < 0.02, "{line:?}");
        let without: Vec<f64> = (0..n)
            .map(|i| axial(i as f64 / fs) + 0.01 + noise(i))
            .collect();
        assert_eq!(find(&without, 1.0 / fs, f, 1e-5), None);
    }

    /// The derivative of the line's form against central differences.
    #[test]
    fn derivative_of_the_line() {
        let line = SlowLine {
            omega_rad_s: 3.0,
            decay_rate_1_s: 0.2,
            coefficients: [0.7, -0.4],
            explained: 1.0,
        };
        let h = 1e-4;
        let y = line.derivative(0, h, 2001);
        let d2 = line.derivative(2, h, 2001);
        for i in [1, 500, 1999] {
            let fd = (y[i + 1] - 2.0 * y[i] + y[i - 1]) / (h * h);
            assert!(
                (fd - d2[i]).abs() < 1e-5 * d2[i].abs().max(1.0),
                "{fd} {}",
                d2[i]
            );
        }
    }
}
