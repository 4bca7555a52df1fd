//! EN 50318 contact-force statistics of a pantograph-catenary run.
//!
//! EN 50318 (validation of pantograph-catenary simulations) compares a simulation with its
//! reference ranges through a few statistics of the contact force over an evaluation
//! window, after a low-pass filter, plus the largest uplift of a support and the share of
//! time without contact. This module computes them from in-memory histories (a
//! `coil-solve` run of a catenary deck or a measured record) and has no idea of the model.
//!
//! # Inputs and conventions
//! - **Time** `time_s` (s): uniformly sampled (the [`coil_postproc::signal::Signal`] check: every
//!   step within 5 % of the median).
//! - **Contact force** `force_n` (N), one sample per time: positive presses the head on the
//!   wire; a sample with force `<= 0` is a sample without contact (a penalty contact's force
//!   is `k max(p, 0)`, exactly 0 when open).
//! - **Position** of the pantograph along the track (m): per sample ([`Track::Positions`]),
//!   or `x = start_m + v t` at the record's speed ([`Track::Uniform`], the `MOVING CONTACT`
//!   card's `s = s0 + v t`).
//! - **Evaluation window** ([`Window`]): the samples whose position `x` satisfies
//!   `start_m <= x <= end_m` (both ends included). EN 50318 evaluates the central spans of
//!   the modelled section, away from the ends where the pantograph runs onto and off the
//!   line; the case says which spans (for the 2002 reference model of 10 spans of 60 m, e.g.
//!   the two central spans, 240 to 360 m from the first support).
//! - **Low-pass**: zero-phase Butterworth ([`coil_postproc::filter::lowpass_zero_phase`]), order
//!   [`DEFAULT_ORDER`] per pass, forward then backward, so the magnitude is
//!   `|H(f)|^2 = 1 / (1 + (tan(pi f / f_s) / tan(pi f_c / f_s))^8)` (half amplitude, -6 dB,
//!   at the cutoff `f_c`, [`DEFAULT_CUTOFF_HZ`] = 20 Hz unless the case says otherwise) and
//!   no phase shift. It is applied to the **whole record before windowing**: the
//!   filter's start-up transients live at the record's ends, within
//!   `14 / (2 pi f_c sin(pi / 8))` s (0.29 s at 20 Hz, see [`coil_postproc::filter`]), and
//!   [`Evaluation::clear_of_ends`] says whether the window stays outside them.
//! - **Supports** ([`Support`]): the vertical displacement history (mm, **positive up**) of
//!   each steady arm or messenger support, with its static value and its position along
//!   the track. Not filtered (the standard's uplift is the displacement itself).
//!
//! # Statistics ([`Statistics`], the JSON keys are a contract)
//! Over the `N` window samples of the filtered force `F_i`:
//! `mean_n = sum F_i / N`; `std_n = sqrt(sum (F_i - mean)^2 / N)` (population form: the
//! record is the whole population of the window); `stat_max_n = mean + 3 std`,
//! `stat_min_n = mean - 3 std`; `max_n`, `min_n` the actual extremes of `F_i`.
//! `uplift_support_mm`: the largest `d(t_i) - d_static` over the supports whose position
//! lies in the window and the window's samples. `loss_percent`: `100 n_0 / N` with `n_0` the
//! window samples whose **unfiltered** force is `<= 0`: uniform sampling makes it the share
//! of time, and the raw force because a 20 Hz low-pass never lets a short loss reach zero.
//! `speed_km_h = 3.6 v`.
//!
//! Sources: EN 50318:2002 clause 5 (the statistics and the 20 Hz filter, as summarised in
//! S. Bruni et al., "The results of the pantograph-catenary interaction benchmark", Vehicle
//! System Dynamics 53(3), 2015, 412-435); the filter's design in [`coil_postproc::filter`].

pub mod figures;
pub mod report;
pub mod study;

use std::ops::RangeInclusive;

use serde::{Deserialize, Serialize};

use coil_postproc::error::{PostError, Result};
use coil_postproc::filter::{Band, Butterworth};
use coil_postproc::signal::Signal;

/// The usual low-pass cutoff of EN 50318's statistics (Hz).
pub const DEFAULT_CUTOFF_HZ: f64 = 20.0;

/// Butterworth order of each of the two passes of the zero-phase low-pass.
pub const DEFAULT_ORDER: usize = coil_postproc::filter::DEFAULT_ORDER;

/// The statistics' keys, in the order of [`Statistics`] (the JSON contract).
pub const KEYS: [&str; 9] = [
    "speed_km_h",
    "mean_n",
    "std_n",
    "stat_max_n",
    "stat_min_n",
    "max_n",
    "min_n",
    "uplift_support_mm",
    "loss_percent",
];

/// A speed for titles and tables: `250 km/h` for `250 / 3.6 * 3.6` (round-off below a
/// millionth of a km/h is not shown), three decimals otherwise.
pub fn speed_label(speed_km_h: f64) -> String {
    let whole = speed_km_h.round();
    if (speed_km_h - whole).abs() < 1e-6 {
        format!("{whole} km/h")
    } else {
        format!("{speed_km_h:.3} km/h")
    }
}

/// The evaluation window along the track: samples with `start_m <= x <= end_m`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Window {
    /// Start along the track (m).
    pub start_m: f64,
    /// End along the track (m).
    pub end_m: f64,
}

impl Window {
    /// Whether `x_m` is inside (both ends included).
    pub fn contains(&self, x_m: f64) -> bool {
        (self.start_m..=self.end_m).contains(&x_m)
    }

    fn check(&self) -> Result<()> {
        if self.start_m.is_finite() && self.end_m.is_finite() && self.start_m < self.end_m {
            Ok(())
        } else {
            Err(PostError::InvalidOption(format!(
                "evaluation window {} to {} m; expected finite positions with start < end",
                self.start_m, self.end_m
            )))
        }
    }
}

/// Where the pantograph is at each sample.
#[derive(Debug, Clone, Copy)]
pub enum Track<'a> {
    /// Its position along the track per sample (m).
    Positions(&'a [f64]),
    /// `x = start_m + v t` at the record's speed (the `MOVING CONTACT` card's `s0 + v t`).
    Uniform {
        /// Position at `t = 0` (m).
        start_m: f64,
    },
}

/// One support (steady arm or messenger support) and its vertical displacement.
#[derive(Debug, Clone, Copy)]
pub struct Support<'a> {
    /// Its position along the track (m).
    pub position_m: f64,
    /// Its displacement in the static state (mm, positive up).
    pub static_mm: f64,
    /// Its displacement at each time sample (mm, positive up).
    pub displacement_mm: &'a [f64],
}

/// One run's histories.
#[derive(Debug, Clone, Copy)]
pub struct Record<'a> {
    /// Time (s), uniformly sampled.
    pub time_s: &'a [f64],
    /// Contact force (N) at each time.
    pub force_n: &'a [f64],
    /// The pantograph's position along the track.
    pub track: Track<'a>,
    /// Its speed (m/s).
    pub speed_m_s: f64,
    /// The supports whose uplift is wanted.
    pub supports: &'a [Support<'a>],
}

/// How the statistics are taken.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// The evaluation window.
    pub window: Window,
    /// Low-pass cutoff (Hz), [`DEFAULT_CUTOFF_HZ`] by default.
    #[serde(default = "default_cutoff")]
    pub cutoff_hz: f64,
    /// Butterworth order per pass, [`DEFAULT_ORDER`] by default.
    #[serde(default = "default_order")]
    pub order: usize,
}

fn default_cutoff() -> f64 {
    DEFAULT_CUTOFF_HZ
}

fn default_order() -> usize {
    DEFAULT_ORDER
}

impl Settings {
    /// The window with the default filter (20 Hz, order 4 per pass).
    pub fn new(window: Window) -> Self {
        Settings {
            window,
            cutoff_hz: DEFAULT_CUTOFF_HZ,
            order: DEFAULT_ORDER,
        }
    }
}

/// EN 50318's statistics of one run (module doc); the field names are the JSON keys.
/// Reading one back ignores other keys beside them (a per-speed entry of an output may
/// carry more).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Statistics {
    /// The run's speed (km/h).
    pub speed_km_h: f64,
    /// Mean of the filtered contact force in the window (N).
    pub mean_n: f64,
    /// Its standard deviation (N).
    pub std_n: f64,
    /// `mean + 3 std` (N).
    pub stat_max_n: f64,
    /// `mean - 3 std` (N).
    pub stat_min_n: f64,
    /// Largest filtered force in the window (N).
    pub max_n: f64,
    /// Smallest filtered force in the window (N).
    pub min_n: f64,
    /// Largest uplift of a support in the window, from its static position (mm).
    pub uplift_support_mm: f64,
    /// Share of the window's time without contact, from the unfiltered force (%).
    pub loss_percent: f64,
}

impl Statistics {
    /// The value under one of [`KEYS`].
    pub fn get(&self, key: &str) -> Option<f64> {
        Some(match key {
            "speed_km_h" => self.speed_km_h,
            "mean_n" => self.mean_n,
            "std_n" => self.std_n,
            "stat_max_n" => self.stat_max_n,
            "stat_min_n" => self.stat_min_n,
            "max_n" => self.max_n,
            "min_n" => self.min_n,
            "uplift_support_mm" => self.uplift_support_mm,
            "loss_percent" => self.loss_percent,
            _ => return None,
        })
    }
}

/// The statistics with what they were computed from (for figures and checks).
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// The statistics.
    pub statistics: Statistics,
    /// The pantograph's position at each sample (m).
    pub position_m: Vec<f64>,
    /// The filtered contact force, whole record (N).
    pub filtered_n: Vec<f64>,
    /// How many samples lie in the window.
    pub window_samples: usize,
    /// First and last sample index in the window.
    pub window_indices: RangeInclusive<usize>,
    /// Each support's largest uplift over the window's samples (mm), `None` for a support
    /// outside the window.
    pub support_uplift_mm: Vec<Option<f64>>,
    /// Length of the filter's start-up transient at each end of the record (s).
    pub settle_s: f64,
    /// Whether every window sample lies at least `settle_s` from both ends of the record.
    pub clear_of_ends: bool,
}

fn check_length(what: &str, found: usize, expected: usize) -> Result<()> {
    if found == expected {
        Ok(())
    } else {
        Err(PostError::LengthMismatch {
            what: what.to_string(),
            found,
            expected,
        })
    }
}

fn check_finite(what: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(PostError::InvalidSignal {
            index,
            what: format!("{what} is {}; expected finite numbers", values[index]),
        }),
    }
}

fn positive(what: &str, value: f64, unit: &str) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(PostError::InvalidOption(format!(
            "{what} {value} {unit}; expected a positive number"
        )))
    }
}

/// The pantograph's position at each sample, checked.
fn positions(record: &Record<'_>) -> Result<Vec<f64>> {
    match record.track {
        Track::Positions(x) => {
            check_length("position_m", x.len(), record.time_s.len())?;
            check_finite("position_m", x)?;
            Ok(x.to_vec())
        }
        Track::Uniform { start_m } => {
            if !start_m.is_finite() {
                return Err(PostError::InvalidOption(format!(
                    "start position {start_m} m; expected a finite number"
                )));
            }
            Ok(record
                .time_s
                .iter()
                .map(|t| start_m + record.speed_m_s * t)
                .collect())
        }
    }
}

/// The statistics of `record` (module doc).
pub fn statistics(record: &Record<'_>, settings: &Settings) -> Result<Statistics> {
    Ok(evaluate(record, settings)?.statistics)
}

/// The statistics of `record` with the filtered force and the window (module doc).
pub fn evaluate(record: &Record<'_>, settings: &Settings) -> Result<Evaluation> {
    let n = record.time_s.len();
    check_length("force_n", record.force_n.len(), n)?;
    let signal = Signal::new(record.time_s.to_vec(), record.force_n.to_vec())?;
    positive("speed", record.speed_m_s, "m/s")?;
    settings.window.check()?;
    positive("low-pass cutoff", settings.cutoff_hz, "Hz")?;
    let nyquist_hz = 0.5 / signal.step_s();
    if settings.cutoff_hz >= nyquist_hz {
        return Err(PostError::CutoffAboveNyquist {
            cutoff_hz: settings.cutoff_hz,
            nyquist_hz,
        });
    }
    let position_m = positions(record)?;
    for (k, support) in record.supports.iter().enumerate() {
        let what = format!("support {} displacement_mm", k + 1);
        check_length(&what, support.displacement_mm.len(), n)?;
        check_finite(&what, support.displacement_mm)?;
        if !(support.position_m.is_finite() && support.static_mm.is_finite()) {
            return Err(PostError::InvalidOption(format!(
                "support {}: position {} m, static displacement {} mm; expected finite numbers",
                k + 1,
                support.position_m,
                support.static_mm
            )));
        }
    }

    let filter = Butterworth::new(
        Band::Lowpass,
        settings.order,
        settings.cutoff_hz,
        signal.step_s(),
    )?;
    let filtered_n = filter.filtfilt(record.force_n);
    let window = settings.window;
    let inside: Vec<usize> = (0..n).filter(|&i| window.contains(position_m[i])).collect();
    let (Some(&first), Some(&last)) = (inside.first(), inside.last()) else {
        let fold = |f: fn(f64, f64) -> f64, start: f64| position_m.iter().copied().fold(start, f);
        return Err(PostError::EmptyWindow {
            start_m: window.start_m,
            end_m: window.end_m,
            first_m: fold(f64::min, f64::INFINITY),
            last_m: fold(f64::max, f64::NEG_INFINITY),
        });
    };
    let support_uplift_mm: Vec<Option<f64>> = record
        .supports
        .iter()
        .map(|s| {
            window.contains(s.position_m).then(|| {
                inside
                    .iter()
                    .map(|&i| s.displacement_mm[i] - s.static_mm)
                    .fold(f64::NEG_INFINITY, f64::max)
            })
        })
        .collect();
    let uplift_support_mm = support_uplift_mm
        .iter()
        .flatten()
        .copied()
        .reduce(f64::max)
        .ok_or(PostError::NoSupportInWindow {
            start_m: window.start_m,
            end_m: window.end_m,
            supports: record.supports.len(),
        })?;

    let count = inside.len() as f64;
    let mean_n = inside.iter().map(|&i| filtered_n[i]).sum::<f64>() / count;
    let variance = inside
        .iter()
        .map(|&i| (filtered_n[i] - mean_n).powi(2))
        .sum::<f64>()
        / count;
    let std_n = variance.sqrt();
    let (min_n, max_n) = inside
        .iter()
        .map(|&i| filtered_n[i])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), f| {
            (lo.min(f), hi.max(f))
        });
    let lost = inside.iter().filter(|&&i| record.force_n[i] <= 0.0).count();
    let settle = filter.settle_samples();
    let statistics = Statistics {
        speed_km_h: 3.6 * record.speed_m_s,
        mean_n,
        std_n,
        stat_max_n: mean_n + 3.0 * std_n,
        stat_min_n: mean_n - 3.0 * std_n,
        max_n,
        min_n,
        uplift_support_mm,
        loss_percent: 100.0 * lost as f64 / count,
    };
    if let Some(key) = KEYS
        .iter()
        .find(|key| !statistics.get(key).is_some_and(f64::is_finite))
    {
        return Err(PostError::NonFiniteResult {
            what: format!("EN 50318 statistic `{key}`"),
        });
    }
    Ok(Evaluation {
        statistics,
        position_m,
        filtered_n,
        window_samples: inside.len(),
        window_indices: first..=last,
        support_uplift_mm,
        settle_s: settle as f64 * signal.step_s(),
        clear_of_ends: first >= settle && last + settle < n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const STEP: f64 = 1e-3;
    const SPEED: f64 = 50.0;

    /// 20 s at 1 kHz; the pantograph at 50 m/s from 0 m; the window 100 to 900 m (2 to
    /// 18 s, a whole number of periods of every tone below).
    fn time() -> Vec<f64> {
        (0..=20_000).map(|i| i as f64 * STEP).collect()
    }

    fn window() -> Window {
        Window {
            start_m: 100.0,
            end_m: 900.0,
        }
    }

    /// One support at 500 m, static at -10 mm, that does not move (`d` of -10 mm).
    fn still_support(d: &[f64]) -> [Support<'_>; 1] {
        [Support {
            position_m: 500.0,
            static_mm: -10.0,
            displacement_mm: d,
        }]
    }

    fn run(force: &[f64], supports: &[Support<'_>], settings: &Settings) -> Result<Evaluation> {
        let t = time();
        evaluate(
            &Record {
                time_s: &t,
                force_n: force,
                track: Track::Uniform { start_m: 0.0 },
                speed_m_s: SPEED,
                supports,
            },
            settings,
        )
    }

    /// `|H(f)|^2` of the zero-phase low-pass at 20 Hz (the forward-backward magnitude).
    fn gain(f: f64) -> f64 {
        let ratio = (PI * f * STEP).tan() / (PI * DEFAULT_CUTOFF_HZ * STEP).tan();
        1.0 / (1.0 + ratio.powi(2 * DEFAULT_ORDER as i32))
    }

    /// `F = 100 + 30 sin(2 pi f t)`: mean 100, std `g 30 / sqrt 2`, extremes `100 +- 30 g`,
    /// with `g = |H(f)|^2` the filter's closed-form attenuation: 0.999985 at 5 Hz (below the
    /// cutoff), 0.00377 at 40 Hz (above it).
    #[test]
    fn a_constant_plus_a_sine_gives_its_closed_forms_below_and_above_the_cutoff() {
        let t = time();
        let d = vec![-10.0; t.len()];
        let supports = still_support(&d);
        for (f, expected_gain) in [(5.0, 0.999985), (40.0, 0.003770)] {
            let g = gain(f);
            assert!((g - expected_gain).abs() < 1e-6, "{f} Hz: gain {g}");
            let force: Vec<f64> = t
                .iter()
                .map(|t| 100.0 + 30.0 * (2.0 * PI * f * t).sin())
                .collect();
            let e = run(&force, &supports, &Settings::new(window())).unwrap();
            let s = e.statistics;
            // 16 s window: 16001 samples, so the closed interval's extra end sample biases
            // the variance by about 1/16001 (a zero of the sine against its mean square).
            assert_eq!(e.window_samples, 16_001);
            assert!(e.clear_of_ends);
            assert!((s.mean_n - 100.0).abs() < 1e-6, "{f} Hz: mean {}", s.mean_n);
            let std = g * 30.0 / 2f64.sqrt();
            assert!(
                (s.std_n - std).abs() / std < 1e-4,
                "{f} Hz: std {} vs {std}",
                s.std_n
            );
            assert!((s.stat_max_n - (s.mean_n + 3.0 * s.std_n)).abs() < 1e-12);
            assert!((s.stat_min_n - (s.mean_n - 3.0 * s.std_n)).abs() < 1e-12);
            // The crests fall on samples (5 Hz and 40 Hz divide 1 kHz into 200 and 25).
            assert!(
                (s.max_n - (100.0 + 30.0 * g)).abs() < 1e-5 * 30.0,
                "{}",
                s.max_n
            );
            assert!(
                (s.min_n - (100.0 - 30.0 * g)).abs() < 1e-5 * 30.0,
                "{}",
                s.min_n
            );
            assert_eq!(s.loss_percent, 0.0);
            assert_eq!(s.uplift_support_mm, 0.0);
            assert!((s.speed_km_h - 180.0).abs() < 1e-12);
        }
    }

    /// A force of 100 N that is 0 for 0.4 s and negative (as a raw record may be) for 0.2 s
    /// inside the 16 s window: 0.6 / 16 = 3.75 % of the time, within one sample; before
    /// the window it does not count.
    #[test]
    fn loss_of_contact_counts_the_unfiltered_zero_interval() {
        let t = time();
        let d = vec![-10.0; t.len()];
        let supports = still_support(&d);
        let force: Vec<f64> = t
            .iter()
            .map(|&t| {
                if (6.0..6.4).contains(&t) {
                    0.0
                } else if (9.0..9.2).contains(&t) {
                    -5.0
                } else if (0.5..1.5).contains(&t) {
                    0.0
                } else {
                    100.0
                }
            })
            .collect();
        let s = run(&force, &supports, &Settings::new(window()))
            .unwrap()
            .statistics;
        let expected = 100.0 * 0.6 / 16.0;
        let one_sample = 100.0 / 16_001.0;
        assert!(
            (s.loss_percent - expected).abs() <= 2.0 * one_sample,
            "{} vs {expected}",
            s.loss_percent
        );
        // The filter keeps a pulse's area (unit gain at DC), so the filtered mean is the raw
        // one when both gaps lie well inside the window.
        let mean = 100.0 * (1.0 - 0.6 / 16.0) - 5.0 * 0.2 / 16.0;
        assert!((s.mean_n - mean).abs() < 0.05, "{} vs {mean}", s.mean_n);
    }

    /// Per-sample positions, a force equal to the position (a ramp passes the zero-phase
    /// filter unchanged): the window's closed ends give mean (a + b) / 2, min a, max b.
    #[test]
    fn window_edges_are_included_and_an_empty_window_is_an_error() {
        let t: Vec<f64> = (0..=1000).map(|i| i as f64 * STEP).collect();
        let x: Vec<f64> = (0..=1000).map(|i| i as f64 * 0.25).collect();
        let d = vec![0.0; t.len()];
        let supports = [Support {
            position_m: 100.0,
            static_mm: 0.0,
            displacement_mm: &d,
        }];
        let record = Record {
            time_s: &t,
            force_n: &x,
            track: Track::Positions(&x),
            speed_m_s: 250.0,
            supports: &supports,
        };
        let settings = Settings::new(Window {
            start_m: 50.0,
            end_m: 150.0,
        });
        let e = evaluate(&record, &settings).unwrap();
        assert_eq!(e.window_indices, 200..=600);
        assert_eq!(e.window_samples, 401);
        // The 20 Hz filter settles in 14 / (2 pi 20 sin(pi / 8)) = 0.2911 s, 292 whole
        // samples: the window starts at sample 200, inside it.
        assert!((e.settle_s - 0.292).abs() < 1e-9, "{}", e.settle_s);
        assert!(!e.clear_of_ends);
        let s = e.statistics;
        assert!((s.mean_n - 100.0).abs() < 1e-9, "{}", s.mean_n);
        assert!((s.min_n - 50.0).abs() < 1e-9 && (s.max_n - 150.0).abs() < 1e-9);
        // Uniform samples of a ramp: std = h sqrt((N^2 - 1) / 12), h = 0.25 N.
        let std = 0.25 * ((401.0f64.powi(2) - 1.0) / 12.0).sqrt();
        assert!((s.std_n - std).abs() < 1e-9, "{} vs {std}", s.std_n);
        assert!((s.speed_km_h - 900.0).abs() < 1e-12);
        assert_eq!(speed_label(3.6 * (250.0 / 3.6)), "250 km/h");
        assert_eq!(speed_label(252.5), "252.500 km/h");

        let outside = Settings::new(Window {
            start_m: 300.0,
            end_m: 400.0,
        });
        let error = evaluate(&record, &outside).unwrap_err();
        assert!(
            matches!(error, PostError::EmptyWindow { first_m, last_m, .. } if first_m == 0.0 && last_m == 250.0),
            "{error}"
        );
        assert!(error.to_string().contains("0 to 250 m"), "{error}");
        let reversed = Settings::new(Window {
            start_m: 150.0,
            end_m: 50.0,
        });
        assert!(matches!(
            evaluate(&record, &reversed),
            Err(PostError::InvalidOption(_))
        ));
    }

    /// A bump of 55 mm above the static position at a support in the window; a larger one
    /// at a support outside it (ignored); a smaller one at another inside.
    #[test]
    fn uplift_is_the_largest_bump_of_a_support_in_the_window() {
        let t = time();
        let bump = |height: f64, at_s: f64, static_mm: f64| -> Vec<f64> {
            t.iter()
                .map(|t| static_mm + height * (-((t - at_s) / 0.2).powi(2)).exp())
                .collect()
        };
        let (a, b, c) = (
            bump(55.0, 10.0, -10.0),
            bump(100.0, 19.0, 0.0),
            bump(40.0, 12.0, 5.0),
        );
        let supports = [
            Support {
                position_m: 500.0,
                static_mm: -10.0,
                displacement_mm: &a,
            },
            Support {
                position_m: 950.0,
                static_mm: 0.0,
                displacement_mm: &b,
            },
            Support {
                position_m: 600.0,
                static_mm: 5.0,
                displacement_mm: &c,
            },
        ];
        let force = vec![120.0; t.len()];
        let e = run(&force, &supports, &Settings::new(window())).unwrap();
        assert!((e.statistics.uplift_support_mm - 55.0).abs() < 1e-9);
        assert_eq!(e.support_uplift_mm[1], None);
        assert!((e.support_uplift_mm[2].unwrap() - 40.0).abs() < 1e-9);
        assert!((e.statistics.std_n).abs() < 1e-9 && (e.statistics.mean_n - 120.0).abs() < 1e-9);

        let error = run(&force, &supports[1..2], &Settings::new(window())).unwrap_err();
        assert!(
            matches!(error, PostError::NoSupportInWindow { supports: 1, .. }),
            "{error}"
        );
    }

    #[test]
    fn bad_inputs_are_typed_errors() {
        let t = time();
        let d = vec![-10.0; t.len()];
        let supports = still_support(&d);
        let force = vec![100.0; t.len()];
        let settings = Settings::new(window());

        let short = &force[..100];
        let error = run(short, &supports, &settings).unwrap_err();
        assert!(
            matches!(&error, PostError::LengthMismatch { what, found: 100, expected: 20_001 } if what == "force_n"),
            "{error}"
        );
        let short_support = [Support {
            displacement_mm: &d[..5],
            ..supports[0]
        }];
        let error = run(&force, &short_support, &settings).unwrap_err();
        assert!(
            matches!(error, PostError::LengthMismatch { found: 5, .. }),
            "{error}"
        );

        let mut nan = force.clone();
        nan[777] = f64::NAN;
        let error = run(&nan, &supports, &settings).unwrap_err();
        assert!(
            matches!(error, PostError::InvalidSignal { index: 777, .. }),
            "{error}"
        );
        let mut bad = d.clone();
        bad[3] = f64::INFINITY;
        let bad_support = [Support {
            displacement_mm: &bad,
            ..supports[0]
        }];
        let error = run(&force, &bad_support, &settings).unwrap_err();
        assert!(
            matches!(error, PostError::InvalidSignal { index: 3, .. }),
            "{error}"
        );

        let fast = Settings {
            cutoff_hz: 500.0,
            ..settings
        };
        let error = run(&force, &supports, &fast).unwrap_err();
        assert!(
            matches!(error, PostError::CutoffAboveNyquist { nyquist_hz, .. } if (nyquist_hz - 500.0).abs() < 1e-6),
            "{error}"
        );
        let zero = Settings {
            cutoff_hz: 0.0,
            ..settings
        };
        assert!(matches!(
            run(&force, &supports, &zero),
            Err(PostError::InvalidOption(_))
        ));
    }

    /// The JSON keys are the contract, in order, and read back.
    #[test]
    fn statistics_serialise_to_the_contract_keys() {
        let s = Statistics {
            speed_km_h: 250.0,
            mean_n: 115.0,
            std_n: 28.0,
            stat_max_n: 199.0,
            stat_min_n: 31.0,
            max_n: 190.0,
            min_n: 60.0,
            uplift_support_mm: 50.0,
            loss_percent: 0.0,
        };
        let value = serde_json::to_value(s).unwrap();
        let mut keys: Vec<&str> = value
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        keys.sort_unstable();
        let mut sorted = KEYS.to_vec();
        sorted.sort_unstable();
        assert_eq!(keys, sorted);
        for key in KEYS {
            assert_eq!(value[key].as_f64(), s.get(key));
        }
        let back: Statistics = serde_json::from_value(value).unwrap();
        assert_eq!(back, s);
        let settings: Settings =
            serde_json::from_str(r#"{"window": {"start_m": 240, "end_m": 360}}"#).unwrap();
        assert_eq!(settings.cutoff_hz, 20.0);
        assert_eq!(settings.order, 4);
    }
}
