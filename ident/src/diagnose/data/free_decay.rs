//! Zero crossings with hysteresis and the free decay after an impulse left at the
//! start (module docs of [`super`], steps 4 and 5).

use super::*;

/// The hysteresis of the crossings: the larger of 5 % of the record's 99th-percentile
/// excursion (a blow of a few samples does not set it) and four standard deviations of
/// the noise (the spectral floor, which a band-limited record does not hide).
pub(super) fn hysteresis(y: &[f64]) -> f64 {
    let mut abs: Vec<f64> = y.iter().map(|v| v.abs()).collect();
    abs.sort_by(f64::total_cmp);
    let p99 = abs[((abs.len() as f64 * 0.99) as usize).min(abs.len() - 1)];
    (0.05 * p99).max(4.0 * noise_floor(y).rms)
}

/// Zero crossings of `y` with hysteresis ([`hysteresis`]): a crossing counts only once the
/// signal has gone beyond `+-h` on the other side. Returns, per crossing, the index of
/// the first sample past the zero and the interpolated zero time.
pub(super) fn zero_crossings(y: &[f64], time_s: &[f64]) -> Vec<(usize, f64)> {
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
pub(super) fn crossings(y: &[f64], time_s: &[f64]) -> (usize, f64) {
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
pub(super) fn blow_in(y: &[f64]) -> Option<usize> {
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
