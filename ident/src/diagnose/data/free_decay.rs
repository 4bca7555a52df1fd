//! The free decay after an impulse left at the start (module docs of [`super`], step 4).

use super::crossings::zero_crossings;
use super::record::{Cut, HALF_CYCLE_TOLERANCE, PEAK_JUMP, START_SHARE};

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
