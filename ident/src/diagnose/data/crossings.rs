//! Zero crossings with hysteresis: the count of cycles and the frequency of a record
//! (module docs of [`super`], step 5), the half-cycles of the free-decay search and the
//! slow line's start.

use coil_postproc::noise::noise_floor;

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
