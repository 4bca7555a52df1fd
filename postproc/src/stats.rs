//! Small robust statistics shared by the analyses: the median and the white-noise level of
//! a record from its fourth differences (see [`noise_rms`]), and a value with its standard
//! error ([`Estimate`]).

use serde::Serialize;

/// Robust white-noise standard deviation from the median absolute fourth difference.
pub fn noise_rms(y: &[f64]) -> f64 {
    if y.len() < 5 {
        return 0.0;
    }
    let mut fourth: Vec<f64> = y
        .windows(5)
        .map(|w| (w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4]).abs())
        .collect();
    fourth.sort_by(f64::total_cmp);
    // For Gaussian noise the fourth difference has standard deviation sqrt(70) sigma, and the
    // median absolute value of a normal variable is 0.6745 of its standard deviation.
    fourth[fourth.len() / 2] / (0.6745 * 70f64.sqrt())
}

/// Median of a slice (`None` when empty).
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let middle = sorted.len() / 2;
    Some(if sorted.len() % 2 == 1 {
        sorted[middle]
    } else {
        0.5 * (sorted[middle - 1] + sorted[middle])
    })
}

/// A value with its standard error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// The value.
    pub value: f64,
    /// Its standard error.
    pub std_error: f64,
}

impl Estimate {
    /// `value / std_error` (infinite for an exact value).
    pub fn t_ratio(&self) -> f64 {
        self.value / self.std_error
    }
}
