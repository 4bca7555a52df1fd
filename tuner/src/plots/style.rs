//! The tuner's figure style: axis text sizes, colours, the renderer (the
//! post-processor's, errors as [`TuneError::Plot`]) and tick labels.

use crate::error::{Result, TuneError};
use coil_postproc::plot::{self, Figure};
use plotters::prelude::*;
use std::path::Path;

/// The axes of the tuner's figures (names 18 pt, ticks 16 pt).
pub(super) const TUNER_AXES: plot::AxisText = plot::AxisText {
    names: 18,
    ticks: 16,
};

pub(super) const BLUE: RGBColor = RGBColor(31, 119, 180);
pub(super) const RED: RGBColor = RGBColor(214, 39, 40);
pub(super) const GREEN: RGBColor = RGBColor(44, 160, 44);

/// Draws `figure` into `path` (PNG or SVG) with the post-processor's renderer: same
/// font, same size, same atomic output.
pub(super) fn render<F: Figure>(path: &Path, figure: &F) -> Result<()> {
    plot::render(path, figure).map_err(|source| TuneError::Plot {
        path: path.to_path_buf(),
        message: source.to_string(),
    })
}

pub(super) fn e<T: std::fmt::Display>(x: T) -> String {
    x.to_string()
}

/// Viridis-like colour for t in [0, 1].
pub(super) fn colour(t: f64) -> RGBColor {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [68.0, 1.0, 84.0]),
        (0.25, [59.0, 82.0, 139.0]),
        (0.5, [33.0, 145.0, 140.0]),
        (0.75, [94.0, 201.0, 98.0]),
        (1.0, [253.0, 231.0, 37.0]),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let k = STOPS
        .windows(2)
        .position(|w| t <= w[1].0)
        .unwrap_or(STOPS.len() - 2);
    let (t0, c0) = STOPS[k];
    let (t1, c1) = STOPS[k + 1];
    let s = (t - t0) / (t1 - t0);
    let mix = |i: usize| (c0[i] + s * (c1[i] - c0[i])).round() as u8;
    RGBColor(mix(0), mix(1), mix(2))
}

/// Short number for ticks: up to 4 decimals or 3 significant digits.
pub fn short(x: &f64) -> String {
    let x = *x;
    if x.abs() < 1e-15 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-2..1e5).contains(&a) {
        let s = format!("{x:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{x:.2e}")
    }
}

/// Integer tick labels only (iterations).
pub(super) fn whole(x: &f64) -> String {
    if (x - x.round()).abs() < 1e-6 {
        format!("{}", x.round())
    } else {
        String::new()
    }
}

/// The range of the finite `values`, padded on both sides (axis limits).
pub fn range_of(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1e-12)
    };
    (lo - pad, hi + pad)
}
