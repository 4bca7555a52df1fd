//! The noise floor of a record whose noise need not be white: from the spectrum outside
//! the signal's lines.
//!
//! # Why not differences
//! [`crate::stats::noise_rms`] reads white noise from fourth differences, which pass
//! mostly the top of the band. A record low-passed before it reaches us (an
//! anti-alias or display filter, a position differentiated by [`crate::differentiate`])
//! has no noise there, and the differences read almost nothing: a model would then
//! have to fit the record far below its true noise.
//!
//! # Method
//! 1. Remove the least-squares line (offset and drift are not noise).
//! 2. Welch's averaged periodogram: segments of `L` samples, `L` the largest power of
//!    two up to half the record (at least [`MIN_SEGMENT`]), overlapping by half, each
//!    under a four-term Blackman-Harris window (side lobes below -92 dB, so a line
//!    10^9 above the noise leaks into bins 8 or more away by less than the noise). Each
//!    one-sided bin `k` holds `v_k`, the variance per bin, so that white noise of
//!    variance `s^2` gives `E v_k = 2 s^2 / L` and `sum_k v_k = s^2`.
//! 3. Lines: a bin is signal when `v_k` exceeds [`LINE_FACTOR`] times the running median
//!    over `+-W` bins (`W` = [`HALF_WINDOW`]); each such bin masks `+-`[`MASK_BINS`]
//!    around it (the window's main lobe is +-4 bins). DC and the first bins up to
//!    [`MASK_BINS`] are masked too (what is left of a drift).
//! 4. The noise level at each bin is the mean of the unmasked `v` within `+-W` bins (the
//!    window widened until it holds `W` unmasked bins): it follows a coloured noise and
//!    bridges the masked lines by their neighbours. Step 3 is repeated once with the level
//!    of step 4 in place of the median (a line's shoulders, above the noise but below the
//!    first threshold, are masked too).
//! 5. `noise rms = sqrt(sum_k level_k)`.
//!
//! The estimate is the noise of the whole record, the residual a perfect model would
//! leave. The tests measure it on white, band-limited and quantised noise under a
//! decaying line.

/// Smallest Welch segment (samples).
pub const MIN_SEGMENT: usize = 256;
/// Half-width of the running median and mean (bins).
pub const HALF_WINDOW: usize = 24;
/// A bin above this many times the local noise level is a line.
pub const LINE_FACTOR: f64 = 8.0;
/// Bins masked either side of a line's bin.
pub const MASK_BINS: usize = 8;

use rustfft::{num_complex::Complex64, FftPlanner};

/// The noise floor of a record.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseFloor {
    /// Standard deviation of the noise (the record's unit).
    pub rms: f64,
    /// The fourth-difference estimate of white noise, for comparison
    /// ([`crate::stats::noise_rms`]).
    pub white_rms: f64,
    /// Welch segment length (samples).
    pub segment: usize,
    /// Share of the one-sided bins masked as signal.
    pub masked_share: f64,
}

/// The noise floor of `x` (module docs). Records shorter than [`MIN_SEGMENT`] fall
/// back to the fourth differences.
pub fn noise_floor(x: &[f64]) -> NoiseFloor {
    let n = x.len();
    let white_rms = crate::stats::noise_rms(x);
    if n < MIN_SEGMENT {
        return NoiseFloor {
            rms: white_rms,
            white_rms,
            segment: n,
            masked_share: 0.0,
        };
    }
    let y = detrend(x);
    let mut segment = MIN_SEGMENT;
    while segment * 2 <= n / 2 {
        segment *= 2;
    }
    let v = welch(&y, segment);
    let bins = v.len();

    let mut mask = vec![false; bins];
    let median_level = running(&v, &mask, |w| {
        let mut w = w.to_vec();
        w.sort_by(f64::total_cmp);
        w[w.len() / 2]
    });
    mark_lines(&v, &median_level, &mut mask);
    let mut level = running(&v, &mask, |w| w.iter().sum::<f64>() / w.len() as f64);
    mark_lines(&v, &level, &mut mask);
    level = running(&v, &mask, |w| w.iter().sum::<f64>() / w.len() as f64);
    let masked = mask.iter().filter(|&&m| m).count();
    NoiseFloor {
        rms: level.iter().sum::<f64>().sqrt(),
        white_rms,
        segment,
        masked_share: masked as f64 / bins as f64,
    }
}

/// `x` minus its least-squares line (against the sample index).
pub fn detrend(x: &[f64]) -> Vec<f64> {
    let n = x.len() as f64;
    let mt = (n - 1.0) / 2.0;
    let mx = x.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, v) in x.iter().enumerate() {
        let d = i as f64 - mt;
        sxy += d * (v - mx);
        sxx += d * d;
    }
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    x.iter()
        .enumerate()
        .map(|(i, v)| v - mx - slope * (i as f64 - mt))
        .collect()
}

/// One-sided variance per bin (bins 0..=L/2), averaged over half-overlapping segments.
fn welch(y: &[f64], segment: usize) -> Vec<f64> {
    let window: Vec<f64> = (0..segment)
        .map(|i| {
            let p = 2.0 * std::f64::consts::PI * i as f64 / segment as f64;
            0.35875 - 0.48829 * p.cos() + 0.14128 * (2.0 * p).cos() - 0.01168 * (3.0 * p).cos()
        })
        .collect();
    let power: f64 = window.iter().map(|w| w * w).sum();
    let fft = FftPlanner::new().plan_fft_forward(segment);
    let hop = segment / 2;
    let mut v = vec![0.0; segment / 2 + 1];
    let mut count = 0;
    let mut start = 0;
    while start + segment <= y.len() {
        let mut buf: Vec<Complex64> = y[start..start + segment]
            .iter()
            .zip(&window)
            .map(|(a, w)| Complex64::new(a * w, 0.0))
            .collect();
        fft.process(&mut buf);
        for (k, out) in v.iter_mut().enumerate() {
            let both = if k == 0 || k == segment / 2 { 1.0 } else { 2.0 };
            *out += both * buf[k].norm_sqr() / (segment as f64 * power);
        }
        count += 1;
        start += hop;
    }
    v.iter_mut().for_each(|x| *x /= count.max(1) as f64);
    v
}

/// `statistic` of the unmasked values within `+-HALF_WINDOW` bins of each bin, the
/// window widened until it holds `HALF_WINDOW` unmasked values (or the whole spectrum).
fn running(v: &[f64], mask: &[bool], statistic: impl Fn(&[f64]) -> f64) -> Vec<f64> {
    let n = v.len();
    let mut out = Vec::with_capacity(n);
    let mut buf = Vec::new();
    for k in 0..n {
        let mut half = HALF_WINDOW;
        loop {
            buf.clear();
            let lo = k.saturating_sub(half);
            let hi = (k + half + 1).min(n);
            buf.extend((lo..hi).filter(|&j| !mask[j]).map(|j| v[j]));
            if buf.len() >= HALF_WINDOW || (lo == 0 && hi == n) {
                break;
            }
            half *= 2;
        }
        out.push(if buf.is_empty() { 0.0 } else { statistic(&buf) });
    }
    out
}

fn mark_lines(v: &[f64], level: &[f64], mask: &mut [bool]) {
    let n = v.len();
    let lines: Vec<usize> = (0..n)
        .filter(|&k| k <= MASK_BINS || v[k] > LINE_FACTOR * level[k])
        .collect();
    for k in lines {
        for m in mask
            .iter_mut()
            .take((k + MASK_BINS + 1).min(n))
            .skip(k.saturating_sub(MASK_BINS))
        {
            *m = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::lowpass_zero_phase;
    use std::f64::consts::TAU;

    /// Standard normal numbers (Box-Muller on a 64-bit LCG), seeded.
    fn normals(seed: u64, n: usize) -> Vec<f64> {
        let mut s = seed;
        let mut u = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| (-2.0 * u().ln()).sqrt() * (TAU * u()).cos())
            .collect()
    }

    /// A 4.35 Hz decay (zeta 0.002, 40 s at 500 Hz, amplitude 1) with a slow drift.
    fn decay(fs: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                (-0.002 * TAU * 4.35 * t).exp() * (TAU * 4.35 * t + 0.3).sin() + 0.01 * t
            })
            .collect()
    }

    fn rms(x: &[f64]) -> f64 {
        (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
    }

    /// White noise 0.5 % of the amplitude: within 5 % (the level averages ~1000 bins per
    /// window width and several segments), as the fourth differences.
    #[test]
    fn white_noise_under_a_decay() {
        let (fs, n) = (500.0, 20_000);
        let noise: Vec<f64> = normals(3, n).iter().map(|e| 0.005 * e).collect();
        let x: Vec<f64> = decay(fs, n)
            .iter()
            .zip(&noise)
            .map(|(a, b)| a + b)
            .collect();
        let floor = noise_floor(&x);
        let truth = rms(&noise);
        println!("{floor:?} truth {truth}");
        assert!((floor.rms / truth - 1.0).abs() < 0.05, "{}", floor.rms);
        assert!((floor.white_rms / truth - 1.0).abs() < 0.05);
    }

    /// The same noise low-passed at 15 Hz (the record's filter, order 4, zero phase):
    /// the fourth differences read under 2 % of it; the spectral floor within 10 %.
    #[test]
    fn band_limited_noise_under_a_decay() {
        let (fs, n) = (500.0, 20_000);
        let white: Vec<f64> = normals(5, n).iter().map(|e| 0.02 * e).collect();
        let noise = lowpass_zero_phase(&white, 1.0 / fs, 15.0, 4).unwrap();
        let x: Vec<f64> = decay(fs, n)
            .iter()
            .zip(&noise)
            .map(|(a, b)| a + b)
            .collect();
        let floor = noise_floor(&x);
        let truth = rms(&noise);
        println!("{floor:?} truth {truth}");
        assert!(floor.white_rms < 0.02 * truth, "{}", floor.white_rms);
        assert!(
            (floor.rms / truth - 1.0).abs() < 0.10,
            "{} vs {truth}",
            floor.rms
        );
    }

    /// A decay quantised in steps q (no other noise), 40 levels at the start: the
    /// floor is the quantisation's q / sqrt 12 within 15 %.
    #[test]
    fn quantisation_noise_under_a_decay() {
        let (fs, n) = (100.0, 6_000);
        let q = 0.05;
        let clean = decay(fs, n);
        let x: Vec<f64> = clean.iter().map(|v| (v / q).round() * q).collect();
        let floor = noise_floor(&x);
        let error: Vec<f64> = x.iter().zip(&clean).map(|(a, b)| a - b).collect();
        println!(
            "{floor:?} q/sqrt12 {} error rms {}",
            q / 12f64.sqrt(),
            rms(&error)
        );
        assert!(
            (floor.rms / (q / 12f64.sqrt()) - 1.0).abs() < 0.15,
            "{}",
            floor.rms
        );
    }

    /// Pure noise: nothing is masked but the first bins, and the estimate is unbiased.
    #[test]
    fn pure_noise() {
        let noise = normals(9, 8192);
        let floor = noise_floor(&noise);
        assert!((floor.rms / rms(&noise) - 1.0).abs() < 0.05, "{floor:?}");
        assert!(floor.masked_share < 0.05, "{floor:?}");
    }
}
