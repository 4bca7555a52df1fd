//! The record's uniform time axis (module docs of [`super`], step 2) and the
//! replacement of isolated sensor glitches (step 3).

use super::record::{Resampling, GLITCH_SIGMAS, JITTER_LIMIT, MAX_GLITCH_SHARE, STEP_TOLERANCE};
use crate::case::MeasuredDecay;
use crate::error::{Result, TuneError};

/// The uniform time axis of a record (module docs, step 2): its times, step, values and
/// the resampling if one was needed.
pub(super) type Grid = (Vec<f64>, f64, Vec<f64>, Option<Resampling>);

pub(super) fn uniform_grid(r: &MeasuredDecay) -> Result<Grid> {
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
pub(super) fn despike(x: &mut [f64]) -> Vec<usize> {
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
