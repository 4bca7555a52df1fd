//! The axial-torsional coupling's signature in forced records: its second line.
//!
//! The coupling is linear: the weight turning on the helix adds a line beside the axial
//! one (the torsional mode, moved by the coupling). What that leaves in the records,
//! measured against the H1 estimator's own variance:
//! 1. **one linear model for every record**: each record's H1 agrees with the coupling
//!    model's within its noise (a linear system's H1 does not move with the level or the
//!    sweep's direction; a cubic spring's does);
//! 2. **the second line**: over the lines near the coupling model's second line, the
//!    guided linear model's H1 departs from the measured one beyond its noise, the
//!    coupling model's does not.
//!
//! # Estimator
//! Per record, Welch sums over Hann segments (50 % overlap, the segment of H1 per level,
//! [`super::frf::segment_length`]) of `S_uu = sum |U|^2` and `S_uy = sum U* Y`, and
//! `S_uy_m` of each model's output simulated under the record's input from its fitted
//! initial state (noise-free): `H = S_uy / S_uu`, `H_m = S_uy_m / S_uu`. The same segments
//! and window give both the same window bias and the same share of a sweep's transients,
//! so a right linear model differs from the measured H1 by the noise alone: output noise
//! `N` adds `sum U* N / S_uu`, of variance `s_N / S_uu` (`s_N = E |N|^2` per segment and
//! line) up to the correlation of overlapping segments' noise (`rho = 1/6` for Hann at
//! 50 %: a factor at most `1 + 2 rho`). The noise is measured by the coupling model's
//! residual spectrum, `s_N = sum |Y - Y_c|^2 / n_d` over the `n_d` segments, not by the
//! coherence (`(1 - gamma^2) S_yy`, Bendat and Piersol's form): a line narrower than the
//! resolution (here `zeta f` 0.3 Hz against `df` 1 Hz) makes `Y / U` differ between
//! segments with no noise at all, and the coherence would count that as noise. So
//! `sigma^2 = (1 + 2 rho) s_N / S_uu`. A coupling model that misses the records inflates
//! `s_N`: the guided model's departure is then harder to show, never easier.
//!
//! # Tests
//! On a set of `K` lines, `z_k^2 = |H_k - H_m,k|^2 / sigma_k^2` has mean 1 when the model
//! is right (per line an exponential variable of variance 1). Neighbouring lines of one
//! Hann spectrum are correlated (amplitudes -2/3 and 1/6 at one and two lines apart,
//! `rho^2` 4/9 and 1/36), so the mean over `K` lines has a variance of at most `c / K`,
//! `c = 1 + 2 (4/9 + 1/36) = 1.94`. A model **agrees** when that mean is at most
//! `1 + 3 sqrt(c / K)` (three standard deviations) and **departs** beyond. The signature
//! holds when the coupling model agrees with every record over the lines its input
//! excites (`S_uu` above 1e-3 of the record's largest), and over the lines near the
//! second line (within `2 df + zeta_2 f_2` of `f_2`: the Hann main lobe's half-width and
//! the line's half-power half-width) of all records together the guided model departs
//! and the coupling model agrees. No excited line near the second line (a line outside the
//! band) fails it: the records cannot show that line.
//!
//! Sources: J. S. Bendat, A. G. Piersol, *Random Data*, 4th ed., Wiley 2010, section 9.2
//! (H1, its random error and the resolution bias of a narrow line); F. J. Harris, "On the use of windows for harmonic analysis
//! with the discrete Fourier transform", Proc. IEEE 66 (1978) 51-83 (Hann's overlap and
//! neighbouring-line correlations).

use super::frf::segment_length;
use coil_postproc::spectrum::Window;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

/// Correlation of a Hann window's noise spectra between segments overlapping by half.
const OVERLAP_RHO: f64 = 1.0 / 6.0;

/// Variance factor of a mean of `z^2` over neighbouring lines of a Hann spectrum.
const LINE_C: f64 = 1.0 + 2.0 * (4.0 / 9.0 + 1.0 / 36.0);

/// One record under the two models.
#[derive(Debug, Clone, Copy)]
pub struct RecordRun<'a> {
    /// Sample interval, s.
    pub dt: f64,
    /// The measured input.
    pub input: &'a [f64],
    /// The measured output.
    pub output: &'a [f64],
    /// The guided linear model's output under the input.
    pub guided: &'a [f64],
    /// The coupling model's output under the input.
    pub coupled: &'a [f64],
}

/// One excited line of a record: frequency (Hz), `z^2` of the guided and the coupling
/// model.
#[derive(Debug, Clone, Copy)]
struct Line {
    hz: f64,
    guided: f64,
    coupled: f64,
}

/// The excited lines of one record (module docs, "Estimator") and their spacing (Hz);
/// `None` when the record holds fewer than two segments.
fn record_lines(run: &RecordRun<'_>, seg: usize) -> Option<(Vec<Line>, f64)> {
    let n = run.input.len();
    if n < seg {
        return None;
    }
    let mut planner = FftPlanner::new();
    let fft = planner.plan_fft_forward(seg);
    let window = Window::Hann.coefficients(seg);
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    let signals = [run.input, run.output, run.guided, run.coupled];
    let means: Vec<f64> = signals.iter().map(|s| mean(s)).collect();
    let half = seg / 2 + 1;
    let mut suu = vec![0.0; half];
    let mut see = vec![0.0; half];
    let mut suy = vec![[Complex::new(0.0, 0.0); 3]; half];
    let mut segments = 0usize;
    let mut start = 0;
    while start + seg <= n {
        let spectra: Vec<Vec<Complex<f64>>> = signals
            .iter()
            .zip(&means)
            .map(|(s, m)| {
                let mut b: Vec<Complex<f64>> = (0..seg)
                    .map(|i| Complex::new((s[start + i] - m) * window[i], 0.0))
                    .collect();
                fft.process(&mut b);
                b
            })
            .collect();
        for k in 0..half {
            let u = spectra[0][k];
            suu[k] += u.norm_sqr();
            see[k] += (spectra[1][k] - spectra[3][k]).norm_sqr();
            for (j, s) in spectra[1..].iter().enumerate() {
                suy[k][j] += u.conj() * s[k];
            }
        }
        segments += 1;
        start += seg / 2;
    }
    if segments < 2 {
        return None;
    }
    let n_d = segments as f64;
    let df = 1.0 / (seg as f64 * run.dt);
    let top = suu.iter().copied().fold(0.0, f64::max);
    let lines = (1..half)
        .filter(|&k| suu[k] > 1e-3 * top)
        .filter_map(|k| {
            let h = suy[k][0] / suu[k];
            let sigma2 = (1.0 + 2.0 * OVERLAP_RHO) * see[k] / (n_d * suu[k]);
            (sigma2 > 0.0).then(|| Line {
                hz: k as f64 * df,
                guided: (h - suy[k][1] / suu[k]).norm_sqr() / sigma2,
                coupled: (h - suy[k][2] / suu[k]).norm_sqr() / sigma2,
            })
        })
        .collect();
    Some((lines, df))
}

/// Mean `z^2` of a set of lines and its agreement bound (module docs, "Tests").
fn mean_and_bound(values: &[f64]) -> (f64, f64) {
    let k = values.len().max(1) as f64;
    (
        values.iter().sum::<f64>() / k,
        1.0 + 3.0 * (LINE_C / k).sqrt(),
    )
}

/// The coupling's signature (module docs): whether the records show the second line at
/// `second_hz` (damping ratio `second_zeta`), and the figures in words.
pub fn second_line(runs: &[RecordRun<'_>], second_hz: f64, second_zeta: f64) -> (bool, String) {
    let shortest = runs.iter().map(|r| r.input.len()).min().unwrap_or(0);
    let Some(seg) = segment_length(shortest) else {
        return (false, "the records are too short for H1".into());
    };
    let mut words = Vec::new();
    let mut every = true;
    let mut near: Vec<Line> = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let Some((lines, df)) = record_lines(run, seg) else {
            return (false, format!("record {}: too few segments for H1", i + 1));
        };
        let coupled: Vec<f64> = lines.iter().map(|l| l.coupled).collect();
        let (mean, bound) = mean_and_bound(&coupled);
        every &= !coupled.is_empty() && mean <= bound;
        words.push(format!(
            "record {}: coupling model's H1 misfit {mean:.2} (bound {bound:.2}, {} lines)",
            i + 1,
            coupled.len()
        ));
        let width = 2.0 * df + second_zeta * second_hz;
        near.extend(lines.iter().filter(|l| (l.hz - second_hz).abs() <= width));
    }
    if near.is_empty() {
        words.push(format!(
            "no excited line near the second line at {second_hz:.3} Hz"
        ));
        return (false, words.join(", "));
    }
    let guided: Vec<f64> = near.iter().map(|l| l.guided).collect();
    let coupled: Vec<f64> = near.iter().map(|l| l.coupled).collect();
    let (g, bound) = mean_and_bound(&guided);
    let (c, _) = mean_and_bound(&coupled);
    words.push(format!(
        "near the second line at {second_hz:.3} Hz ({} lines): guided {g:.2}, coupling {c:.2} \
         (bound {bound:.2})",
        near.len()
    ));
    (every && g > bound && c <= bound, words.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-pole resonator's output (`f` Hz, damping ratio `zeta`, gain `g`) under `u`
    /// sampled at `dt` (the impulse-invariant recursion; any linear filter will do here).
    fn resonator(u: &[f64], dt: f64, f: f64, zeta: f64, g: f64) -> Vec<f64> {
        let w = std::f64::consts::TAU * f;
        let r = (-zeta * w * dt).exp();
        let wd = w * (1.0 - zeta * zeta).sqrt();
        let (a1, a2) = (2.0 * r * (wd * dt).cos(), -r * r);
        let mut y = vec![0.0; u.len()];
        for i in 0..u.len() {
            let back = |k: usize| if i >= k { y[i - k] } else { 0.0 };
            let input = if i >= 1 { u[i - 1] } else { 0.0 };
            y[i] = a1 * back(1) + a2 * back(2) + g * input;
        }
        y
    }

    /// Uniform noise of unit variance from a fixed linear congruential sequence.
    fn noise(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 12f64.sqrt()
            })
            .collect()
    }

    struct Records {
        input: Vec<f64>,
        guided: Vec<f64>,
        coupled: Vec<f64>,
        measured: Vec<f64>,
    }

    /// Broadband input (white noise), the coupled system's two lines (23 and 24 Hz, the
    /// second a tenth of the first), the guided model's one line, the measured output the
    /// coupled one with 1 % noise.
    fn records(seed: u64) -> Records {
        let (n, dt) = (7500, 0.002);
        let input = noise(n, seed);
        let a = resonator(&input, dt, 23.0, 0.015, 1.0);
        let b = resonator(&input, dt, 24.0, 0.015, 0.1);
        let coupled: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x + y).collect();
        let guided = resonator(&input, dt, 23.05, 0.016, 1.08);
        let rms = (coupled.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
        let measured = coupled
            .iter()
            .zip(noise(n, seed + 1))
            .map(|(y, e)| y + 0.01 * rms * e)
            .collect();
        Records {
            input,
            guided,
            coupled,
            measured,
        }
    }

    fn run<'a>(r: &'a Records, coupled: &'a [f64]) -> RecordRun<'a> {
        RecordRun {
            dt: 0.002,
            input: &r.input,
            output: &r.measured,
            guided: &r.guided,
            coupled,
        }
    }

    #[test]
    fn the_right_coupling_model_shows_its_second_line() {
        let (r1, r2) = (records(1), records(7));
        let (pass, words) =
            second_line(&[run(&r1, &r1.coupled), run(&r2, &r2.coupled)], 24.0, 0.015);
        println!("{words}");
        assert!(pass, "{words}");
    }

    #[test]
    fn a_model_that_misses_a_record_or_a_line_outside_the_band_fails() {
        let (r1, r2) = (records(1), records(7));
        // The second record's system 3 % stiffer (its lines moved, as a level would move a
        // cubic spring's): one linear model no longer agrees with both.
        let input = &r2.input;
        let moved: Vec<f64> = resonator(input, 0.002, 23.0 * 1.015, 0.015, 1.0)
            .iter()
            .zip(resonator(input, 0.002, 24.0 * 1.015, 0.015, 0.1))
            .map(|(x, y)| x + y)
            .collect();
        let moved_records = Records {
            input: input.clone(),
            guided: r2.guided.clone(),
            coupled: r2.coupled.clone(),
            measured: moved,
        };
        let (pass, words) = second_line(
            &[
                run(&r1, &r1.coupled),
                run(&moved_records, &moved_records.coupled),
            ],
            24.0,
            0.015,
        );
        println!("{words}");
        assert!(!pass, "{words}");
        // The guided model itself as the "coupling" model: no departure to explain.
        let (pass, words) = second_line(&[run(&r1, &r1.guided)], 24.0, 0.015);
        println!("{words}");
        assert!(!pass, "{words}");
        // A second line above the band the input excites (white noise to 250 Hz: put it
        // past Nyquist).
        let (pass, words) = second_line(&[run(&r1, &r1.coupled)], 300.0, 0.015);
        println!("{words}");
        assert!(!pass, "{words}");
    }
}
