//! Half-cycle amplitude signatures: the damping laws read from every peak and trough,
//! so that a record of 8 cycles (16 points) gives each dissipative effect a signature
//! and a start, where the windowed per-cycle loss fit (`coil_postproc::signature::
//! loss_per_cycle`, five windows of at least three cycles) needs about 15 cycles.
//!
//! # Formulation
//! Between two successive crests of a weakly damped oscillator, by energy balance over
//! the half cycle (Den Hartog, *Mechanical Vibrations*, 4th ed., 1956, sections 2.8
//! and 8.3; the per-cycle forms of docs/diagnose.md, section 2, halved):
//! ```text
//! dA_half = b0 + b1 A + b2 A^2,   b0 = 2 F / k   (dry friction: a constant step),
//!                                  b1 = pi zeta   (viscous: proportional to A),
//!                                  b2 = (4/3) c2 / m (velocity-squared drag)
//! ```
//! `A` the displacement amplitude (m). The per-cycle coefficients of
//! [`LossSummary`] are twice these.
//!
//! # Reading the crests
//! The record is the weight's acceleration (measured, or derived from a velocity or a
//! position). Its half cycles are the segments between sign changes taken with a
//! hysteresis of [`HYSTERESIS_NOISE`] noise RMS; each segment's largest `|a|`
//! (refined by a parabola through its three samples) over `w^2` is the crest's
//! displacement amplitude. Under dry friction the acceleration jumps by `2F/m` at each
//! crest and the largest `|a|` is the one just before it, `w^2 (A + F/k)`: an offset of
//! `F/k` on every amplitude, which leaves the step `2F/k` between successive crests
//! exact.
//!
//! The first segment (the record starts inside it) is left out. A record that sticks
//! ends in a segment that never changes sign again: its crest is kept when the motion
//! turned back from it (the acceleration fell below half the crest for a quarter
//! period after it) and it stands above [`CREST_NOISE`] noise RMS: the last crests
//! before the stop are data, not noise. Crests below that level, and everything after
//! a segment longer than [`STUCK_HALF_PERIODS`] half periods (the weight rests), are
//! left out.
//!
//! # Fits and their errors
//! The loss `A_i - A_{i+1}` is fitted against the pair's mean amplitude by ordinary
//! least squares, three terms and the two two-term forms (without drag, without
//! friction); the standard errors are `s^2 (X^T X)^-1` with `s^2` the residuals'
//! variance: the scatter of the points sets them, not a noise model. The envelope test
//! compares `R^2` of `A` and of `ln A` linear in time over the crests: a straight line
//! is dry friction's envelope, an exponential viscous damping's.

use super::evidence::{EnvelopeSummary, LossSummary};

/// Hysteresis of the sign changes, in noise RMS of the acceleration.
pub const HYSTERESIS_NOISE: f64 = 3.0;
/// A crest is kept when its acceleration exceeds this many noise RMS.
pub const CREST_NOISE: f64 = 8.0;
/// A segment longer than this many half periods ends the motion (the weight rests).
pub const STUCK_HALF_PERIODS: f64 = 1.6;
/// Fewest crests for a fit: seven losses, so the three-term fit keeps four degrees
/// of freedom (an 8-cycle record holds about 15).
pub const MIN_CRESTS: usize = 8;

/// The crests of a record: times (s) and displacement amplitudes (m).
#[derive(Debug, Clone, Default)]
pub struct Crests {
    /// Time of each crest (s).
    pub time_s: Vec<f64>,
    /// Displacement amplitude of each crest (m).
    pub amplitude_m: Vec<f64>,
    /// True when the motion stopped above the noise: the last crest's segment never
    /// changed sign again, or lasted longer than [`STUCK_HALF_PERIODS`] (the weight
    /// sticks), rather than the crests fading into the noise.
    pub stopped: bool,
}

/// The crests of the acceleration `signal` sampled every `step_s` (module docs), for
/// an oscillation at `frequency_hz` with acceleration noise `noise_rms`.
pub fn crests(signal: &[f64], step_s: f64, frequency_hz: f64, noise_rms: f64) -> Crests {
    let mut out = Crests::default();
    if signal.len() < 8 || !(frequency_hz > 0.0 && step_s > 0.0) {
        return out;
    }
    let w = std::f64::consts::TAU * frequency_hz;
    let half_period = 0.5 / (frequency_hz * step_s);
    let peak = signal.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let noise = if noise_rms.is_finite() && noise_rms > 0.0 {
        noise_rms
    } else {
        1e-6 * peak
    };
    let h = HYSTERESIS_NOISE * noise;
    // Segment boundaries: the sample where the signal passes the hysteresis band of
    // the opposite sign.
    let mut sign = 0.0_f64;
    let mut starts = Vec::new();
    for (i, &a) in signal.iter().enumerate() {
        let s = if a > h {
            1.0
        } else if a < -h {
            -1.0
        } else {
            continue;
        };
        if s != sign {
            sign = s;
            starts.push(i);
        }
    }
    // The first segment is partial; each later one runs to the next boundary, the last
    // to the record's end.
    for (k, &start) in starts.iter().enumerate().skip(1) {
        let end = starts.get(k + 1).copied().unwrap_or(signal.len());
        let last = k + 1 == starts.len();
        let seg = &signal[start..end];
        let (j, &a) = match seg
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
        {
            Some(x) => x,
            None => break,
        };
        if a.abs() < CREST_NOISE * noise {
            break;
        }
        let i = start + j;
        // The motion turned back from the crest within the segment.
        let quarter = (0.5 * half_period).ceil() as usize;
        let turned = signal[i..end.min(i + quarter + 1)]
            .iter()
            .any(|x| x.abs() < 0.5 * a.abs());
        if last && !turned {
            break;
        }
        let (t, value) = parabola(signal, i, step_s, w);
        out.time_s.push(t);
        out.amplitude_m.push(value.abs() / (w * w));
        let long = (end - start) as f64 > STUCK_HALF_PERIODS * half_period;
        if last || long {
            out.stopped = long;
            break;
        }
    }
    out
}

/// The vertex of the parabola through samples `i - 1, i, i + 1` (time, value); the
/// sample itself at the record's ends, when the three are collinear, or when they
/// straddle a jump rather than a smooth crest. A smooth crest of an oscillation at `w`
/// has the second difference `-(w dt)^2` times its value; under dry friction the
/// acceleration jumps by `2F/m` at the crest, and a parabola through the jump would add
/// up to an eighth of the jump to the crest (a quarter of `F/k` to its amplitude, and
/// more to the last crest before the weight sticks, whose jump is to zero). A second
/// difference beyond four times the smooth one marks the jump; the largest sample is
/// then the crest, within `(w dt)^2 / 2` of it.
fn parabola(y: &[f64], i: usize, step_s: f64, w: f64) -> (f64, f64) {
    if i == 0 || i + 1 >= y.len() {
        return (i as f64 * step_s, y[i]);
    }
    let (a, b, c) = (y[i - 1], y[i], y[i + 1]);
    let denom = a - 2.0 * b + c;
    let smooth = (w * step_s).powi(2) * b.abs();
    if denom == 0.0 || denom.abs() > 4.0 * smooth {
        return (i as f64 * step_s, b);
    }
    let d = (0.5 * (a - c) / denom).clamp(-0.5, 0.5);
    ((i as f64 + d) * step_s, b - 0.25 * (a - c) * d)
}

/// Ordinary least squares `y = X c` with the scatter's standard errors; `None` when
/// there are not two more rows than columns or `X^T X` is singular.
fn ols(rows: &[(Vec<f64>, f64)]) -> Option<(Vec<f64>, Vec<f64>)> {
    let p = rows.first()?.0.len();
    if rows.len() < p + 2 {
        return None;
    }
    let x = nalgebra::DMatrix::from_fn(rows.len(), p, |i, j| rows[i].0[j]);
    let y = nalgebra::DVector::from_iterator(rows.len(), rows.iter().map(|r| r.1));
    let inv = (x.transpose() * &x).try_inverse()?;
    let c = &inv * x.transpose() * &y;
    let s2 = (&y - &x * &c).norm_squared() / (rows.len() - p) as f64;
    let se = (0..p).map(|j| (s2 * inv[(j, j)]).max(0.0).sqrt()).collect();
    Some((c.iter().copied().collect(), se))
}

/// The loss per half cycle fitted over the crests (module docs), as per-cycle
/// coefficients; `None` with fewer than [`MIN_CRESTS`] crests or a singular fit.
pub fn loss(crests: &Crests) -> Option<LossSummary> {
    let a = &crests.amplitude_m;
    if a.len() < MIN_CRESTS {
        return None;
    }
    // Columns scaled by the largest amplitude, so X^T X is well conditioned.
    let scale = a.iter().fold(0.0_f64, |m, x| m.max(*x));
    if scale <= 0.0 {
        return None;
    }
    let pairs: Vec<(f64, f64)> = a
        .windows(2)
        .map(|w| (0.5 * (w[0] + w[1]) / scale, (w[0] - w[1]) / scale))
        .collect();
    let rows = |terms: &[usize]| -> Vec<(Vec<f64>, f64)> {
        pairs
            .iter()
            .map(|&(x, y)| (terms.iter().map(|&t| x.powi(t as i32)).collect(), y))
            .collect()
    };
    let (c, se) = ols(&rows(&[0, 1, 2]))?;
    let z = |fit: Option<(Vec<f64>, Vec<f64>)>, k: usize| {
        fit.map_or(
            f64::NAN,
            |(c, se)| {
                if se[k] > 0.0 {
                    c[k] / se[k]
                } else {
                    f64::NAN
                }
            },
        )
    };
    // Back to metres, per cycle (twice the half cycle's loss).
    Some(LossSummary {
        a0_m: 2.0 * c[0] * scale,
        a0_se: 2.0 * se[0] * scale,
        a1: 2.0 * c[1],
        a1_se: 2.0 * se[1],
        a2_per_m: 2.0 * c[2] / scale,
        a2_se: 2.0 * se[2] / scale,
        a0_two_term_z: z(ols(&rows(&[0, 1])), 0),
        a2_two_term_z: z(ols(&rows(&[1, 2])), 1),
    })
}

/// The envelope test over the crests: `R^2` of `A` and of `ln A` linear in time;
/// `linear` when the straight line fits better, else `exponential`; `None` with fewer
/// than [`MIN_CRESTS`] crests.
pub fn envelope(crests: &Crests) -> Option<EnvelopeSummary> {
    let (t, a) = (&crests.time_s, &crests.amplitude_m);
    if a.len() < MIN_CRESTS || a.iter().any(|x| *x <= 0.0) {
        return None;
    }
    let r2 = |y: &[f64]| -> f64 {
        let rows: Vec<(Vec<f64>, f64)> =
            t.iter().zip(y).map(|(&t, &y)| (vec![1.0, t], y)).collect();
        let Some((c, _)) = ols(&rows) else {
            return f64::NAN;
        };
        let mean = y.iter().sum::<f64>() / y.len() as f64;
        let total: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
        let resid: f64 = rows
            .iter()
            .map(|(x, y)| (y - c[0] * x[0] - c[1] * x[1]).powi(2))
            .sum();
        1.0 - resid / total
    };
    let ln: Vec<f64> = a.iter().map(|x| x.ln()).collect();
    let (r2_linear, r2_exponential) = (r2(a), r2(&ln));
    Some(EnvelopeSummary {
        kind: if r2_linear > r2_exponential {
            "linear"
        } else {
            "exponential"
        }
        .into(),
        r2_exponential,
        r2_linear,
        beat_period_s: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sampled oscillator at 5 Hz with dry friction `f_over_k` (m), viscous damping
    /// `zeta` and drag `c2_over_m` (1/m), by RK4 with the friction's sign from the
    /// velocity; it sticks when the spring force at a stop is within the friction.
    fn decay(a0: f64, f_over_k: f64, zeta: f64, c2_over_m: f64, cycles: f64) -> Vec<f64> {
        let w = std::f64::consts::TAU * 5.0;
        let dt = 1e-3;
        let samples = (cycles / 5.0 / dt) as usize;
        let acc = |x: f64, v: f64, dir: f64| {
            -w * w * x - 2.0 * zeta * w * v - c2_over_m * v * v.abs() - w * w * f_over_k * dir
        };
        let (mut x, mut v, mut dir) = (a0, 0.0_f64, -1.0_f64);
        let mut out = Vec::with_capacity(samples);
        let mut stuck = false;
        let h = dt / 20.0;
        while out.len() < samples {
            out.push(if stuck { 0.0 } else { acc(x, v, dir) });
            for _ in 0..20 {
                if stuck {
                    break;
                }
                let f = |x: f64, v: f64| (v, acc(x, v, dir));
                let (k1x, k1v) = f(x, v);
                let (k2x, k2v) = f(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
                let (k3x, k3v) = f(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
                let (k4x, k4v) = f(x + h * k3x, v + h * k3v);
                x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                let nv = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                if v != 0.0 && nv.signum() != v.signum() {
                    // A stop: the weight sticks when the spring is within the friction.
                    stuck = x.abs() <= f_over_k;
                    dir = -dir;
                }
                v = nv;
            }
        }
        out
    }

    #[test]
    fn dry_friction_is_a_constant_step_on_eight_cycles() {
        // F/k = 0.08 mm on 3 mm: 0.32 mm lost per cycle, the weight sticks after
        // about 9 cycles and rests for 3.
        let a = decay(3e-3, 8e-5, 0.0, 0.0, 12.0);
        let c = crests(&a, 1e-3, 5.0, 1e-9);
        assert!(c.amplitude_m.len() >= 14, "{}", c.amplitude_m.len());
        assert!(c.stopped);
        let l = loss(&c).expect("a fit");
        // a0 = 4 F/k per cycle = 0.32 mm.
        assert!((l.a0_m / 3.2e-4 - 1.0).abs() < 0.02, "{}", l.a0_m);
        assert!(l.a0_m / l.a0_se > 10.0, "{}", l.a0_m / l.a0_se);
        assert_eq!(envelope(&c).expect("an envelope").kind, "linear");
    }

    #[test]
    fn drag_and_viscous_losses_are_told_apart() {
        // Drag: (8/3) c2/m per cycle with c2/m = 20 1/m; 10 cycles.
        let a = decay(3e-3, 0.0, 0.0, 20.0, 10.0);
        let l = loss(&crests(&a, 1e-3, 5.0, 1e-9)).expect("a fit");
        assert!(
            (l.a2_per_m / (8.0 / 3.0 * 20.0) - 1.0).abs() < 0.05,
            "{}",
            l.a2_per_m
        );
        // No friction term: the record is noise-free, so the scatter's standard error
        // measures only the half-cycle law's neglected second order (the relative loss
        // per half cycle squared, 0.1^2 here) and a z-test would be meaningless; the
        // constant term must stay within that order of the smallest crest's loss.
        let c = crests(&a, 1e-3, 5.0, 1e-9);
        let smallest = c.amplitude_m.iter().fold(f64::INFINITY, |m, x| m.min(*x));
        let loss_there = 8.0 / 3.0 * 20.0 * smallest * smallest;
        assert!(
            l.a0_m.abs() < 0.01 * loss_there,
            "{} {}",
            l.a0_m,
            loss_there
        );
        // Viscous: 2 pi zeta per cycle, zeta = 0.01.
        let a = decay(3e-3, 0.0, 0.01, 0.0, 10.0);
        let c = crests(&a, 1e-3, 5.0, 1e-9);
        let l = loss(&c).expect("a fit");
        let expected = std::f64::consts::TAU * 0.01;
        assert!((l.a1 / expected - 1.0).abs() < 0.05, "{}", l.a1);
        assert_eq!(envelope(&c).expect("an envelope").kind, "exponential");
    }
}
