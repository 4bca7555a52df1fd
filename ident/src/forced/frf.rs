//! What forced records show without a model: the H1 frequency response per input level,
//! and the restoring force against the displacement.
//!
//! # H1 per level
//! Records whose input RMS agree within 10 % form one level. Per level, Welch's averaged
//! cross- and auto-spectra over Hann-windowed segments (50 % overlap, the segment the
//! largest power of two up to an eighth of the shortest record, at least 256 samples):
//! `H1(f) = S_uy(f) / S_uu(f)`, unbiased by output noise. A hardening spring moves the
//! resonance up with the level, a softening one down; friction's damping falls with the
//! level, drag's rises.
//!
//! # Restoring force
//! For a displacement output, `z = y - y0` with central differences for `z'` and `z''`
//! gives the restoring force per unit mass `b u - z''` at every sample; less the linear
//! damping `2 zeta w0 z'`, it is the stiffness curve `w0^2 z + kappa z^3 + ...` (S. F. Masri,
//! T. K. Caughey, "A nonparametric identification technique for nonlinear dynamic
//! problems", J. Appl. Mech. 46 (1979) 433-447). Differences amplify noise: the curve is
//! evidence to look at, and its regression on an effect's term (its sign and t-value) is
//! the signature test of the diagnosis.
//!
//! Source: J. S. Bendat, A. G. Piersol, *Random Data*, 4th ed., Wiley 2010, sections 9.2
//! (H1) and 11.5 (Welch).

// Harmonic and sample indices are the formulation's own (x_n, tau_j, line k): the kernels
// keep them rather than zipping five slices.
#![allow(clippy::needless_range_loop)]

use super::model::ForcedModel;
use coil_postproc::spectrum::Window;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

/// One level's H1 estimate.
#[derive(Debug, Clone)]
pub struct LevelFrf {
    /// Input RMS of the level, input unit.
    pub input_rms: f64,
    /// `(frequency Hz, |H1|, phase rad)` per line.
    pub lines: Vec<(f64, f64, f64)>,
    /// Frequency of the largest |H1|, Hz.
    pub peak_hz: f64,
}

/// Welch's segment for records of at least `shortest` samples (module docs): the largest
/// power of two up to an eighth of it, at least 256; `None` when the records are shorter.
pub fn segment_length(shortest: usize) -> Option<usize> {
    let mut seg = 256usize;
    while seg * 2 <= shortest / 8 {
        seg *= 2;
    }
    (shortest >= seg).then_some(seg)
}

/// Groups records `(dt, input, output)` by input level and estimates H1 per level.
pub fn levels(records: &[(f64, &[f64], &[f64])]) -> Vec<LevelFrf> {
    let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt();
    let mut groups: Vec<(f64, Vec<usize>)> = Vec::new();
    for (i, r) in records.iter().enumerate() {
        let level = rms(r.1);
        match groups
            .iter_mut()
            .find(|g| (g.0 - level).abs() <= 0.1 * g.0.max(level))
        {
            Some(g) => g.1.push(i),
            None => groups.push((level, vec![i])),
        }
    }
    groups.sort_by(|a, b| a.0.total_cmp(&b.0));
    let shortest = records.iter().map(|r| r.1.len()).min().unwrap_or(0);
    let Some(seg) = segment_length(shortest) else {
        return Vec::new();
    };
    let mut planner = FftPlanner::new();
    let fft = planner.plan_fft_forward(seg);
    let window = Window::Hann.coefficients(seg);
    groups
        .into_iter()
        .map(|(level, members)| {
            let mut suu = vec![0.0; seg / 2 + 1];
            let mut suy = vec![Complex::new(0.0, 0.0); seg / 2 + 1];
            let mut dt = 0.0;
            for &m in &members {
                let (step, u, y) = records[m];
                dt = step;
                let mu = u.iter().sum::<f64>() / u.len() as f64;
                let my = y.iter().sum::<f64>() / y.len() as f64;
                let mut start = 0;
                while start + seg <= u.len() {
                    let mut bu: Vec<Complex<f64>> = (0..seg)
                        .map(|i| Complex::new((u[start + i] - mu) * window[i], 0.0))
                        .collect();
                    let mut by: Vec<Complex<f64>> = (0..seg)
                        .map(|i| Complex::new((y[start + i] - my) * window[i], 0.0))
                        .collect();
                    fft.process(&mut bu);
                    fft.process(&mut by);
                    for k in 0..=seg / 2 {
                        suu[k] += bu[k].norm_sqr();
                        suy[k] += bu[k].conj() * by[k];
                    }
                    start += seg / 2;
                }
            }
            let df = 1.0 / (seg as f64 * dt);
            // Lines where the input carries power (a multisine's excited lines, a sweep's band).
            let max_suu = suu.iter().copied().fold(0.0, f64::max);
            let lines: Vec<(f64, f64, f64)> = (1..=seg / 2)
                .filter(|&k| suu[k] > 1e-6 * max_suu)
                .map(|k| {
                    let h = suy[k] / suu[k];
                    (k as f64 * df, h.norm(), h.arg())
                })
                .collect();
            let peak_hz = lines
                .iter()
                .max_by(|a, b| a.1.total_cmp(&b.1))
                .map_or(f64::NAN, |l| l.0);
            LevelFrf {
                input_rms: level,
                lines,
                peak_hz,
            }
        })
        .collect()
}

/// Restoring-force samples `(z, force per unit mass less the linear damping)` from a
/// displacement record (module docs), every `stride`-th sample.
pub fn restoring_force(
    model: &ForcedModel,
    dt: f64,
    input: &[f64],
    output: &[f64],
    stride: usize,
) -> Vec<(f64, f64)> {
    let o = &model.oscillator;
    let c = 2.0 * o.damping_ratio * o.natural_frequency_rad_s;
    (1..output.len().saturating_sub(1))
        .step_by(stride.max(1))
        .map(|i| {
            let z = output[i] - o.output_offset;
            let v = (output[i + 1] - output[i - 1]) / (2.0 * dt);
            let a = (output[i + 1] - 2.0 * output[i] + output[i - 1]) / (dt * dt);
            (z, o.input_gain * input[i] - a - c * v)
        })
        .collect()
}

/// The regression of the linear model's force residual on one term beside its linear
/// counterpart (the displacement for a spring term, the velocity for a damping term, which the
/// linear fit has already partly absorbed): the term's `(coefficient, t-value)`.
/// `term(z, v)` is the effect's term, `velocity_like` whether its counterpart is `v`.
pub fn signature(
    model: &ForcedModel,
    dt: f64,
    input: &[f64],
    output: &[f64],
    term: &dyn Fn(f64, f64) -> f64,
    velocity_like: bool,
) -> (f64, f64) {
    let o = &model.oscillator;
    let w0 = o.natural_frequency_rad_s;
    let c = 2.0 * o.damping_ratio * w0;
    // Normal equations of q = a x + e l.
    let (mut sxx, mut sxl, mut sll, mut sxq, mut slq, mut sqq, mut n) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0usize);
    for i in 1..output.len().saturating_sub(1) {
        let z = output[i] - o.output_offset;
        let v = (output[i + 1] - output[i - 1]) / (2.0 * dt);
        let a = (output[i + 1] - 2.0 * output[i] + output[i - 1]) / (dt * dt);
        let q = o.input_gain * input[i] - a - c * v - w0 * w0 * z;
        let x = term(z, v);
        let l = if velocity_like { v } else { z };
        sxx += x * x;
        sxl += x * l;
        sll += l * l;
        sxq += x * q;
        slq += l * q;
        sqq += q * q;
        n += 1;
    }
    let det = sxx * sll - sxl * sxl;
    if det.is_nan() || det <= 0.0 || n < 4 {
        return (0.0, 0.0);
    }
    let coef = (sll * sxq - sxl * slq) / det;
    let lin = (sxx * slq - sxl * sxq) / det;
    let rss = (sqq - coef * sxq - lin * slq).max(0.0);
    let var = rss / (n - 2) as f64;
    // The residuals of differenced data are correlated over a few samples: the t-value is
    // indicative, and the test asks for its sign and a modest size.
    let se = (var * sll / det).sqrt();
    (coef, if se > 0.0 { coef / se } else { f64::INFINITY })
}
