//! Crests (or troughs) of an oscillation, located to sub-sample accuracy.
//!
//! # Segmentation
//! The signal is cut into half-cycles by its zero crossings with hysteresis: a positive lobe
//! starts when the signal rises above `+h` after having been below `-h`, and ends when it
//! falls below `-h` again; its crest is the largest sample in between. So noise and small
//! higher modes riding on the crest give one crest per cycle, not many local maxima. Lobes cut
//! by the ends of the record are dropped (the record may start or end inside one).
//! `h = 3 sigma`, where `sigma` is a robust estimate of the white noise: the median absolute
//! fourth difference divided by `0.6745 sqrt(70)` (a smooth oscillation with `N` samples per
//! period contributes only `(2 pi / N)^4` of its amplitude to the fourth difference, noise
//! `sqrt(70) sigma`). `h` is at least [`MIN_HYSTERESIS`] of the largest magnitude, so a clean
//! signal is segmented down to 0.1% of its peak and no further.
//!
//! # Which crests are kept
//! Crests must exceed `10 sigma` (below that the fit error is over 1/(10 sqrt(window)) in
//! ln amplitude). Then the intervals between consecutive crests are compared with their
//! median; an interval outside +-25% marks a missed or spurious cycle, and the longest run of
//! regular intervals is kept. So the decrement's crest numbering `n` counts true cycles.
//!
//! # Sub-sample refinement ([`PeakFit`])
//! A crest of `A e^{-sigma t} cos(omega_d t + phi)` sampled at step `dt` lies up to half a
//! sample from the largest sample, whose value is low by up to `1 - cos(omega dt / 2)`,
//! `(omega dt)^2 / 8` relative: 9.3e-5 for 4.35 Hz at 1 kHz. That error depends on where the
//! sampling grid falls, i.e. varies from crest to crest, and goes straight into
//! `ln(x1 / xn)`.
//!
//! The default fit ([`PeakFit::LeastSquares`]) is a least-squares quartic through the
//! `2W + 1` samples around the largest one, `W = round(N / 8)` for `N` samples per period
//! (+-45 degrees of phase), maximised by Newton's method. Over that window a cosine differs
//! from a quartic by its `u^6 / 720` term, so the crest value has a constant relative bias
//! (measured -8e-6; the same for every crest, so it cancels in amplitude ratios), and the part
//! that varies with the sub-sample offset, which does not cancel, is 1e-7 at 230 samples per
//! period and 3e-5 at 20. The odd terms of the quartic follow the envelope's slope across the
//! window, so the crest of a damped signal is located without a shift. The window averages
//! white noise: the crest scatter is 0.23 times the noise at 230 samples per period, against
//! 0.95 for the largest sample. If the maximum lies more than half a sample from the window
//! centre (the largest sample sat on a ripple beside the smooth crest), the window is
//! re-centred on it, up to four times. Below 12 samples per period (`W < 2`) the fit falls
//! back to the three-point parabola. [`PeakFit::Parabola3`] is that classical vertex (exact
//! enough on clean data, 1.3e-8 spread at 230 samples per period, but it averages no noise);
//! [`PeakFit::Raw`] takes the largest sample as is and exists to show why refinement is
//! needed. The numbers come from the `crest_fit_study` test (see `docs/postproc.md`).
//!
//! After a filter, crests within its settling length of either end can be excluded
//! ([`PeakOptions::edge_guard_samples`]).
//!
//! Troughs are crests of `-x`; their amplitude is reported as a positive magnitude.

use serde::Serialize;

use crate::error::Result;
use crate::signal::Signal;
use crate::stats::{median, noise_rms};

/// Smallest hysteresis, relative to the largest magnitude of the signal.
pub const MIN_HYSTERESIS: f64 = 1e-3;

/// Crests whose amplitude is below this many noise standard deviations are not used.
pub const NOISE_FLOOR: f64 = 10.0;

/// Relative tolerance of a crest interval against the median interval.
pub const INTERVAL_TOLERANCE: f64 = 0.25;

/// Most re-centrings of the least-squares window before a crest is given up.
const RECENTRE_LIMIT: usize = 4;

/// Fraction of a period covered by each side of the least-squares window.
pub const LSQ_HALF_WINDOW_PERIODS: f64 = 1.0 / 8.0;

/// Positive crests (as in the paper) or troughs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Polarity {
    #[default]
    /// Crests (maxima).
    Crests,
    /// Troughs (minima, reported as positive magnitudes).
    Troughs,
}

impl Polarity {
    /// Plural noun for messages.
    pub fn noun(self) -> &'static str {
        match self {
            Polarity::Crests => "crests",
            Polarity::Troughs => "troughs",
        }
    }
}

/// How a crest is located between samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PeakFit {
    /// Least-squares quartic over +-1/8 period around the largest sample.
    #[default]
    LeastSquares,
    /// Parabola through the largest sample and its two neighbours.
    Parabola3,
    /// The largest sample itself (no interpolation).
    Raw,
}

/// Options of [`find_peaks`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeakOptions {
    /// Crests or troughs.
    pub polarity: Polarity,
    /// How it was fitted.
    pub fit: PeakFit,
    /// Half-width of the least-squares window, periods (default [`LSQ_HALF_WINDOW_PERIODS`]).
    pub half_window_periods: f64,
    /// Crests within this many samples of either end are not used (a filter's settling).
    pub edge_guard_samples: usize,
}

impl Default for PeakOptions {
    fn default() -> Self {
        PeakOptions {
            polarity: Polarity::Crests,
            fit: PeakFit::LeastSquares,
            half_window_periods: LSQ_HALF_WINDOW_PERIODS,
            edge_guard_samples: 0,
        }
    }
}

/// One located crest.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Peak {
    /// Time of the crest, seconds.
    pub time_s: f64,
    /// Crest value (trough magnitude for troughs), in the signal's unit.
    pub amplitude: f64,
    /// Fractional sample index of the crest.
    pub index: f64,
}

/// The crests found in a signal and what the search measured on the way.
#[derive(Debug, Clone, Serialize)]
pub struct PeakSearch {
    /// The regular run of crests, in time order.
    pub peaks: Vec<Peak>,
    /// Candidate crests (one per closed lobe) before the regularity check.
    pub candidates: usize,
    /// Candidates left out: below the noise floor or outside the regular run.
    pub rejected: usize,
    /// Robust estimate of the white-noise standard deviation, signal unit.
    pub noise_rms: f64,
    /// Median crest interval, seconds (a rough period; the decrement refines it).
    pub period_s: f64,
    /// Half-width of the least-squares window, samples (0 for the other fits).
    pub fit_half_width: usize,
}

/// Locates the crests (or troughs) of a signal; see the module doc.
pub fn find_peaks(signal: &Signal, options: &PeakOptions) -> Result<PeakSearch> {
    let (time_s, values, step_s) = (signal.time_s(), signal.values(), signal.step_s());
    let sign = match options.polarity {
        Polarity::Crests => 1.0,
        Polarity::Troughs => -1.0,
    };
    let y: Vec<f64> = values.iter().map(|v| sign * v).collect();
    let noise_rms = noise_rms(&y);
    let largest = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let hysteresis = (3.0 * noise_rms).max(MIN_HYSTERESIS * largest);

    let lobes = lobe_maxima(&y, hysteresis);
    let candidates = lobes.len();
    let intervals: Vec<f64> = lobes.windows(2).map(|w| (w[1] - w[0]) as f64).collect();
    let samples_per_period = median(&intervals).unwrap_or(0.0);
    // The quartic needs five samples; with fewer than 2 per side, fall back to three points.
    let lsq_half_width = (samples_per_period * options.half_window_periods).round() as usize;
    let (fit, fit_half_width) = match options.fit {
        PeakFit::LeastSquares if lsq_half_width >= 2 => (PeakFit::LeastSquares, lsq_half_width),
        PeakFit::LeastSquares | PeakFit::Parabola3 => (PeakFit::Parabola3, 1),
        PeakFit::Raw => (PeakFit::Raw, 0),
    };

    let floor = NOISE_FLOOR * noise_rms;
    let refined: Vec<Option<Peak>> = lobes
        .iter()
        .map(|&at| {
            let guard = options.edge_guard_samples;
            if at < guard || at + guard >= y.len() {
                return None;
            }
            let (index, amplitude) = refine(&y, at, fit, fit_half_width)?;
            (amplitude > floor.max(hysteresis)).then_some(Peak {
                time_s: time_s[0] + index * step_s,
                amplitude,
                index,
            })
        })
        .collect();

    let peaks = longest_regular_run(&refined, samples_per_period);
    Ok(PeakSearch {
        rejected: candidates - peaks.len(),
        candidates,
        peaks,
        noise_rms,
        period_s: samples_per_period * step_s,
        fit_half_width,
    })
}

/// Index of the largest sample of each closed positive lobe (see the module doc).
fn lobe_maxima(y: &[f64], hysteresis: f64) -> Vec<usize> {
    #[derive(PartialEq)]
    enum State {
        /// Not yet seen the signal below `-h`: a lobe now could have started before the record.
        Unknown,
        Below,
        Above {
            at: usize,
        },
    }
    let mut state = State::Unknown;
    let mut maxima = Vec::new();
    for (i, &v) in y.iter().enumerate() {
        state = match state {
            State::Unknown if v < -hysteresis => State::Below,
            State::Below if v > hysteresis => State::Above { at: i },
            State::Above { at } if v < -hysteresis => {
                maxima.push(at);
                State::Below
            }
            State::Above { at } if v > y[at] => State::Above { at: i },
            other => other,
        };
    }
    maxima
}

/// Sub-sample crest near sample `at`: (fractional index, value), `None` when the fit does not
/// describe a maximum there.
fn refine(y: &[f64], at: usize, fit: PeakFit, half_width: usize) -> Option<(f64, f64)> {
    match fit {
        PeakFit::Raw => Some((at as f64, y[at])),
        PeakFit::Parabola3 => {
            if at == 0 || at + 1 >= y.len() {
                return None;
            }
            let (left, centre, right) = (y[at - 1], y[at], y[at + 1]);
            let curvature = left - 2.0 * centre + right;
            if curvature >= 0.0 {
                return None;
            }
            let offset = 0.5 * (left - right) / curvature;
            Some((at as f64 + offset, centre - 0.25 * (left - right) * offset))
        }
        PeakFit::LeastSquares => {
            // The largest sample may sit on a ripple beside the smooth crest; follow the
            // fitted maximum, re-centring the window a few times.
            let mut centre = at;
            let mut previous = None;
            for _ in 0..RECENTRE_LIMIT {
                let (offset, value) = quartic_vertex(y, centre, half_width)?;
                let moved = (centre as f64 + offset).round();
                if offset.abs() <= 0.5 || (moved >= 0.0 && Some(moved as usize) == previous) {
                    // Converged, or stepping back and forth around a half-sample position.
                    return Some((centre as f64 + offset, value));
                }
                if moved < 0.0 {
                    return None;
                }
                previous = Some(centre);
                centre = moved as usize;
            }
            None
        }
    }
}

/// Least-squares quartic `c0 + c1 u + ... + c4 u^4` over samples `centre - w ..= centre + w`
/// (`u` in units of `w`), maximised by Newton's method from the vertex of its quadratic part;
/// returns (offset in samples, value) when the maximum is inside the window. On a symmetric
/// window the odd and even coefficients decouple into a 2x2 and a 3x3 system.
fn quartic_vertex(y: &[f64], centre: usize, w: usize) -> Option<(f64, f64)> {
    if w < 2 || centre < w || centre + w >= y.len() {
        return None;
    }
    // Moments m[p] = sum u^p and projections r[p] = sum u^p y, p = 0..8 and 0..4.
    let mut m = [0.0; 9];
    let mut r = [0.0; 5];
    for k in 0..=2 * w {
        let u = (k as f64 - w as f64) / w as f64;
        let v = y[centre + k - w];
        let mut power = 1.0;
        for p in 0..9 {
            m[p] += power;
            if p < 5 {
                r[p] += power * v;
            }
            power *= u;
        }
    }
    let even = solve3(
        [[m[0], m[2], m[4]], [m[2], m[4], m[6]], [m[4], m[6], m[8]]],
        [r[0], r[2], r[4]],
    )?;
    let odd_det = m[2] * m[6] - m[4] * m[4];
    let c1 = (m[6] * r[1] - m[4] * r[3]) / odd_det;
    let c3 = (m[2] * r[3] - m[4] * r[1]) / odd_det;
    let [c0, c2, c4] = even;
    let slope = |u: f64| c1 + u * (2.0 * c2 + u * (3.0 * c3 + u * 4.0 * c4));
    let curvature = |u: f64| 2.0 * c2 + u * (6.0 * c3 + u * 12.0 * c4);
    if c2 >= 0.0 {
        return None;
    }
    let mut u = -c1 / (2.0 * c2);
    for _ in 0..20 {
        let step = slope(u) / curvature(u);
        u -= step;
        if step.abs() < 1e-14 {
            break;
        }
    }
    if !(u.abs() <= 1.0 && curvature(u) < 0.0 && u.is_finite()) {
        return None;
    }
    let value = c0 + u * (c1 + u * (c2 + u * (c3 + u * c4)));
    Some((u * w as f64, value))
}

/// Solves a 3x3 linear system by Cramer's rule (the moment matrices here are well
/// conditioned: `u` is scaled to [-1, 1]).
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let mut x = [0.0; 3];
    for (column, xi) in x.iter_mut().enumerate() {
        let mut replaced = a;
        for row in 0..3 {
            replaced[row][column] = b[row];
        }
        *xi = det(replaced) / d;
    }
    Some(x)
}

/// The longest run of consecutive usable crests whose intervals are within
/// [`INTERVAL_TOLERANCE`] of the median lobe interval.
fn longest_regular_run(refined: &[Option<Peak>], samples_per_period: f64) -> Vec<Peak> {
    let mut best: &[Option<Peak>] = &[];
    let mut start = 0;
    for end in 0..=refined.len() {
        let breaks = end == refined.len()
            || refined[end].is_none()
            || (end > start
                && match (refined[end - 1], refined[end]) {
                    (Some(a), Some(b)) => {
                        ((b.index - a.index) - samples_per_period).abs()
                            > INTERVAL_TOLERANCE * samples_per_period
                    }
                    _ => true,
                });
        if breaks {
            if end - start > best.len() {
                best = &refined[start..end];
            }
            start = if end < refined.len() && refined[end].is_some() {
                end
            } else {
                end + 1
            };
        }
    }
    best.iter().flatten().copied().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_docs::assert_printed;
    use crate::test_signals::{damped_sine, DampedSine, Rng};

    fn sig(time_s: &[f64], values: &[f64]) -> Signal {
        Signal::new(time_s.to_vec(), values.to_vec()).unwrap()
    }

    fn true_crest_amplitudes(sine: &DampedSine, times: &[f64]) -> Vec<f64> {
        times.iter().map(|&t| sine.value(t)).collect()
    }

    #[test]
    fn every_cycle_gives_one_crest_at_the_true_time() {
        let sine = DampedSine {
            frequency_hz: 4.35,
            zeta: 0.00175,
            amplitude: 1.0,
            phase: 1.1,
            offset: 0.0,
        };
        let (time, x) = damped_sine(&sine, 1000.0, 20.0);
        let search = find_peaks(&sig(&time, &x), &PeakOptions::default()).unwrap();
        let crests = sine.crest_times(20.0);
        // A crest at the very start or end has no closed lobe around it.
        assert!(
            search.peaks.len() + 2 >= crests.len(),
            "{}",
            search.peaks.len()
        );
        for peak in &search.peaks {
            let nearest = crests
                .iter()
                .map(|t| (t - peak.time_s).abs())
                .fold(f64::INFINITY, f64::min);
            // The least-squares vertex is within 1e-6 s (1e-3 samples) of the true crest.
            assert!(nearest < 1e-6, "crest time error {nearest:e} s");
        }
        assert_eq!(search.rejected, search.candidates - search.peaks.len());
    }

    /// Relative crest amplitude errors (min, max) of a unit sine over 20 sub-sample offsets.
    fn crest_errors(fit: PeakFit, samples_per_period: f64, half_window_periods: f64) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for k in 0..20 {
            let sine = DampedSine {
                frequency_hz: 1.0,
                zeta: 0.0,
                amplitude: 1.0,
                phase: k as f64 * 0.05 * std::f64::consts::TAU / samples_per_period,
                offset: 0.0,
            };
            let (time, x) = damped_sine(&sine, samples_per_period, 6.0);
            let options = PeakOptions {
                fit,
                half_window_periods,
                ..PeakOptions::default()
            };
            for peak in find_peaks(&sig(&time, &x), &options).unwrap().peaks {
                lo = lo.min(peak.amplitude - 1.0);
                hi = hi.max(peak.amplitude - 1.0);
            }
        }
        (lo, hi)
    }

    /// Standard deviation of the relative crest amplitude error with white noise of
    /// `noise` times the amplitude.
    fn crest_scatter(
        fit: PeakFit,
        samples_per_period: f64,
        half_window_periods: f64,
        noise: f64,
    ) -> f64 {
        let sine = DampedSine {
            frequency_hz: 1.0,
            zeta: 0.0,
            amplitude: 1.0,
            phase: 0.3,
            offset: 0.0,
        };
        let (time, mut x) = damped_sine(&sine, samples_per_period, 200.0);
        let mut rng = Rng::new(11);
        for v in &mut x {
            *v += noise * rng.normal();
        }
        let options = PeakOptions {
            fit,
            half_window_periods,
            ..PeakOptions::default()
        };
        let peaks = find_peaks(&sig(&time, &x), &options).unwrap().peaks;
        let n = peaks.len() as f64;
        (peaks
            .iter()
            .map(|p| (p.amplitude - 1.0).powi(2))
            .sum::<f64>()
            / n)
            .sqrt()
    }

    /// docs/postproc.md's crest-fit table, read from the page, each figure to half a unit of
    /// its printed last digit (the sweep over sub-sample offsets is deterministic and the
    /// noise seeded): per sampling density, the spread (max - min) of the relative crest
    /// error of raw samples, the 3-point parabola and the default quartic, the quartic's
    /// constant bias (the middle of its range), and each one's crest scatter per unit noise
    /// deviation. Also prints the quartic at half-windows of 1/16 and 1/6 period, the
    /// choices the default was picked against.
    #[test]
    fn crest_fit_study() {
        let rows = crate::test_docs::table("| samples/period | raw: varying |");
        assert_eq!(rows.len(), 4, "{rows:?}");
        let noise = 1e-3;
        for row in &rows {
            let spp: f64 = row[0].parse().unwrap();
            let (lsq_spread, lsq_bias) = row[3].split_once(" (").unwrap();
            let lsq_bias = lsq_bias.trim_end_matches(')');
            let scatters: Vec<&str> = row[4].split(" / ").collect();
            let fits = [
                (PeakFit::Raw, 0.0, row[1].as_str(), scatters[0]),
                (PeakFit::Parabola3, 0.0, row[2].as_str(), scatters[1]),
                (
                    PeakFit::LeastSquares,
                    LSQ_HALF_WINDOW_PERIODS,
                    lsq_spread,
                    scatters[2],
                ),
            ];
            for (fit, hw, spread_printed, scatter_printed) in fits {
                let (lo, hi) = crest_errors(fit, spp, hw);
                let scatter = crest_scatter(fit, spp, hw, noise) / noise;
                println!(
                    "{spp:5} {fit:?}: error [{lo:+.3e}, {hi:+.3e}], spread {:.3e}, bias {:+.3e}, scatter per noise {scatter:.4}",
                    hi - lo,
                    0.5 * (lo + hi)
                );
                let what = format!("{spp} samples per period, {fit:?}");
                assert_printed(hi - lo, spread_printed, &format!("{what}: spread"));
                assert_printed(scatter, scatter_printed, &format!("{what}: noise"));
                if fit == PeakFit::LeastSquares {
                    assert_printed(0.5 * (lo + hi), lsq_bias, &format!("{what}: bias"));
                }
            }
            for hw in [1.0 / 16.0, 1.0 / 6.0] {
                let (lo, hi) = crest_errors(PeakFit::LeastSquares, spp, hw);
                let scatter = crest_scatter(PeakFit::LeastSquares, spp, hw, noise) / noise;
                println!(
                    "{spp:5} quartic over +-{hw:.3} period: spread {:.3e}, bias {:+.3e}, scatter per noise {scatter:.4}",
                    hi - lo,
                    0.5 * (lo + hi)
                );
            }
        }
    }

    /// The spread over sub-sample offsets leaks into amplitude ratios; the fit's is far below
    /// the raw sample's `(omega dt)^2 / 8`.
    #[test]
    fn least_squares_crests_vary_less_than_raw_samples() {
        let spread = |fit, spp| {
            let (lo, hi) = crest_errors(fit, spp, LSQ_HALF_WINDOW_PERIODS);
            (hi - lo, lo.abs().max(hi.abs()))
        };
        let (raw, _) = spread(PeakFit::Raw, 230.0);
        let (lsq, lsq_bias) = spread(PeakFit::LeastSquares, 230.0);
        let (three, _) = spread(PeakFit::Parabola3, 230.0);
        // Raw: up to (omega dt)^2 / 8 = 9.3e-5 at 230 samples per period.
        assert!(raw > 5e-5 && raw < 1e-4, "raw spread {raw:e}");
        // Measured: spread 1.0e-7, constant bias -8.1e-6 (cancels in ratios).
        assert!(
            lsq < 2e-7 && lsq_bias < 1e-5,
            "least-squares spread {lsq:e}, bias {lsq_bias:e}"
        );
        assert!(three < 2e-8, "three-point spread {three:e}");
        let (lsq_coarse, _) = spread(PeakFit::LeastSquares, 20.0);
        let (raw_coarse, _) = spread(PeakFit::Raw, 20.0);
        // Measured at 20 samples per period: 3.1e-5 against 1.2e-2.
        assert!(
            lsq_coarse < 1e-4 && raw_coarse > 1e-2,
            "{lsq_coarse:e} {raw_coarse:e}"
        );
    }

    #[test]
    fn noise_estimate_matches_the_added_noise() {
        let sine = DampedSine {
            frequency_hz: 4.35,
            zeta: 0.002,
            amplitude: 1.0,
            phase: 0.0,
            offset: 0.0,
        };
        let (time, mut x) = damped_sine(&sine, 1000.0, 10.0);
        let mut rng = Rng::new(7);
        for v in &mut x {
            *v += 0.01 * rng.normal();
        }
        let search = find_peaks(&sig(&time, &x), &PeakOptions::default()).unwrap();
        // 10 000 samples: the median-based estimate scatters by ~1.5%; the signal adds
        // (2 pi / 230)^4 / 8.4 ~ 7e-8, nothing.
        assert!(
            (search.noise_rms / 0.01 - 1.0).abs() < 0.05,
            "{}",
            search.noise_rms
        );
        let truth = true_crest_amplitudes(
            &sine,
            &search.peaks.iter().map(|p| p.time_s).collect::<Vec<_>>(),
        );
        for (peak, exact) in search.peaks.iter().zip(truth) {
            // The window holds 2 * 14 + 1 samples, so the vertex scatters by roughly
            // 0.01 * 1.5 / sqrt(29) ~ 3e-3; 5 sigma.
            assert!(
                (peak.amplitude - exact).abs() < 0.015,
                "{} vs {exact}",
                peak.amplitude
            );
        }
    }

    #[test]
    fn a_missing_cycle_breaks_the_run() {
        let sine = DampedSine {
            frequency_hz: 5.0,
            zeta: 0.0,
            amplitude: 1.0,
            phase: 0.0,
            offset: 0.0,
        };
        let (time, mut x) = damped_sine(&sine, 1000.0, 10.0);
        // Silence cycles 10 to 13: the run before (about 9 crests) is shorter than after.
        for v in &mut x[2000..2700] {
            *v = 0.0;
        }
        let search = find_peaks(&sig(&time, &x), &PeakOptions::default()).unwrap();
        assert!(search.peaks.iter().all(|p| p.time_s > 2.7));
        assert!(search.rejected >= 8);
    }

    #[test]
    fn troughs_are_crests_of_the_negated_signal() {
        let sine = DampedSine {
            frequency_hz: 4.0,
            zeta: 0.01,
            amplitude: 2.0,
            phase: 0.4,
            offset: 0.0,
        };
        let (time, x) = damped_sine(&sine, 800.0, 5.0);
        let troughs = find_peaks(
            &sig(&time, &x),
            &PeakOptions {
                polarity: Polarity::Troughs,
                ..PeakOptions::default()
            },
        )
        .unwrap();
        for trough in &troughs.peaks {
            assert!(trough.amplitude > 0.0);
            // The quartic's constant bias is -8e-6 relative at 200 samples per period.
            let exact = -sine.value(trough.time_s);
            assert!((trough.amplitude / exact - 1.0).abs() < 1.5e-5);
        }
    }
}
