//! The whole run, not only the evaluation window: where the contact force is largest and
//! smallest and where the contact is lost (docs/catenary.md, "Runs").
//!
//! EN 50318's statistics look at the window alone; a loss of contact or a force peak
//! outside it (at a span's end, near the run's start) is still a fact of the run. From
//! the raw contact force `F_i` (N) at the head's positions `x_i` (m):
//! - the raw extremes over every sample, with their position and time;
//! - the filtered extremes over the samples clear of the filter's start-up transients
//!   (`settle` samples at each end; the filter's ringing there is not the run's);
//! - every interval of consecutive samples with `F_i <= 0` (loss of contact), its first
//!   and last position, its duration `samples x dt`, and whether it touches the window.
//!
//! At most [`MAX_INTERVALS`] intervals are kept (the count of all of them is kept too).
//! Units: N, m, s.

use crate::en50318::Window;
use serde::Serialize;

/// Most loss-of-contact intervals listed.
pub const MAX_INTERVALS: usize = 1000;

/// One extreme value and where it happens.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Extreme {
    /// The force (N).
    pub force_n: f64,
    /// The head's position (m).
    pub position_m: f64,
    /// The time (s).
    pub time_s: f64,
}

/// One interval without contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LossInterval {
    /// First position without contact (m).
    pub start_m: f64,
    /// Last position without contact (m).
    pub end_m: f64,
    /// First time without contact (s).
    pub start_s: f64,
    /// Its duration, samples times the step (s).
    pub duration_s: f64,
    /// Whether any of it lies in the evaluation window.
    pub in_window: bool,
}

/// The run's extremes and losses of contact (module doc).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WholeRun {
    /// Largest raw force.
    pub raw_max: Extreme,
    /// Smallest raw force.
    pub raw_min: Extreme,
    /// Largest filtered force clear of the filter's ends.
    pub filtered_max: Option<Extreme>,
    /// Smallest filtered force clear of the filter's ends.
    pub filtered_min: Option<Extreme>,
    /// Share of the whole run without contact (%).
    pub loss_percent: f64,
    /// How many intervals without contact.
    pub loss_intervals: usize,
    /// The first [`MAX_INTERVALS`] of them.
    pub losses: Vec<LossInterval>,
}

fn extreme(
    indices: impl Iterator<Item = usize>,
    values: &[f64],
    x: &[f64],
    t: &[f64],
    larger: bool,
) -> Option<Extreme> {
    let mut best: Option<usize> = None;
    for i in indices {
        let better = match best {
            None => true,
            Some(b) => (values[i] > values[b]) == larger && values[i] != values[b],
        };
        if better {
            best = Some(i);
        }
    }
    best.map(|i| Extreme {
        force_n: values[i],
        position_m: x[i],
        time_s: t[i],
    })
}

/// The whole run of the raw force `raw_n` and filtered `filtered_n` at positions
/// `position_m` and times `time_s` (all of one length, at least one sample), with
/// `settle` samples of filter start-up at each end and the evaluation `window`.
pub fn whole_run(
    time_s: &[f64],
    position_m: &[f64],
    raw_n: &[f64],
    filtered_n: &[f64],
    settle: usize,
    window: Window,
) -> Option<WholeRun> {
    let n = raw_n.len();
    if n == 0 || time_s.len() != n || position_m.len() != n || filtered_n.len() != n {
        return None;
    }
    let dt = if n > 1 {
        (time_s[n - 1] - time_s[0]) / (n - 1) as f64
    } else {
        0.0
    };
    let raw_max = extreme(0..n, raw_n, position_m, time_s, true)?;
    let raw_min = extreme(0..n, raw_n, position_m, time_s, false)?;
    let clear = settle..n.saturating_sub(settle);
    let filtered_max = extreme(clear.clone(), filtered_n, position_m, time_s, true);
    let filtered_min = extreme(clear, filtered_n, position_m, time_s, false);
    let mut losses = Vec::new();
    let mut count = 0;
    let mut lost = 0;
    let mut i = 0;
    while i < n {
        if raw_n[i] > 0.0 {
            i += 1;
            continue;
        }
        let first = i;
        while i < n && raw_n[i] <= 0.0 {
            i += 1;
        }
        let last = i - 1;
        lost += i - first;
        count += 1;
        if losses.len() < MAX_INTERVALS {
            losses.push(LossInterval {
                start_m: position_m[first],
                end_m: position_m[last],
                start_s: time_s[first],
                duration_s: (i - first) as f64 * dt,
                in_window: (first..=last).any(|k| window.contains(position_m[k])),
            });
        }
    }
    Some(WholeRun {
        raw_max,
        raw_min,
        filtered_max,
        filtered_min,
        loss_percent: 100.0 * lost as f64 / n as f64,
        loss_intervals: count,
        losses,
    })
}

impl WholeRun {
    /// A markdown paragraph: the extremes and the losses of contact with where.
    pub fn markdown(&self) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let at = |e: &Extreme| {
            format!(
                "{:.2} N at {:.2} m ({:.3} s)",
                e.force_n, e.position_m, e.time_s
            )
        };
        let _ = writeln!(
            s,
            "Whole run: raw contact force from {} to {}",
            at(&self.raw_min),
            at(&self.raw_max)
        );
        if let (Some(lo), Some(hi)) = (&self.filtered_min, &self.filtered_max) {
            let _ = writeln!(
                s,
                "; filtered (clear of the filter's ends) from {} to {}",
                at(lo),
                at(hi)
            );
        }
        if self.loss_intervals == 0 {
            s.push_str("; no loss of contact anywhere in the run.\n");
        } else {
            let _ = writeln!(
                s,
                "; **{} loss(es) of contact** ({:.3} % of the run):",
                self.loss_intervals, self.loss_percent
            );
            for l in self.losses.iter().take(20) {
                let _ = writeln!(
                    s,
                    "- {:.2} to {:.2} m (from {:.4} s, {:.4} s){}",
                    l.start_m,
                    l.end_m,
                    l.start_s,
                    l.duration_s,
                    if l.in_window {
                        ", in the window"
                    } else {
                        ", outside the window"
                    }
                );
            }
            if self.loss_intervals > 20 {
                let _ = writeln!(
                    s,
                    "- ... {} more (catenary.json lists up to {MAX_INTERVALS})",
                    self.loss_intervals - 20
                );
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn losses_and_extremes_are_found_with_their_positions() {
        // 0.01 s steps at 10 m/s: x = 10 t; contact lost at samples 3-4 and 8.
        let t: Vec<f64> = (0..10).map(|i| 0.01 * f64::from(i)).collect();
        let x: Vec<f64> = t.iter().map(|t| 10.0 * t).collect();
        let f = [100.0, 120.0, 50.0, 0.0, -0.0, 80.0, 200.0, 90.0, 0.0, 60.0];
        let w = whole_run(
            &t,
            &x,
            &f,
            &f,
            1,
            Window {
                start_m: 0.25,
                end_m: 0.45,
            },
        )
        .unwrap();
        assert_eq!(w.loss_intervals, 2);
        assert!((w.loss_percent - 30.0).abs() < 1e-12);
        assert!(
            (w.losses[0].start_m - 0.3).abs() < 1e-12 && (w.losses[0].end_m - 0.4).abs() < 1e-12
        );
        assert!((w.losses[0].duration_s - 0.02).abs() < 1e-12);
        assert!(w.losses[0].in_window && !w.losses[1].in_window);
        assert_eq!(w.raw_max.force_n, 200.0);
        assert!((w.raw_max.position_m - 0.6).abs() < 1e-12);
        assert_eq!(w.raw_min.force_n, 0.0);
        // Clear of one settle sample at each end: samples 1..9.
        assert_eq!(w.filtered_min.unwrap().force_n, 0.0);
        assert!(w.markdown().contains("2 loss(es) of contact"));
    }
}
