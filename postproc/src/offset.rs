//! Offsets: what constant is removed from a signal before analysis ([`Detrend`]) and the
//! equilibrium line of a decaying oscillation from crest/trough triples
//! ([`midline_offset`]).

use serde::Serialize;

use crate::error::{PostError, Result};
use crate::peaks::{self, PeakOptions, Polarity};
use crate::signal::Signal;

/// What constant to remove from a signal before analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Detrend {
    /// Analyse the signal as given. Right for AC-coupled accelerometer records and for FE
    /// accelerations (zero at static equilibrium).
    #[default]
    None,
    /// Subtract the record's mean. On a decaying oscillation the mean is not the midline: it
    /// leaves a residual of order `A / (omega * T_record)` (about 0.2% of the first amplitude
    /// for the paper's 20 s, 4.35 Hz record), enough to bias the decrement by ~0.2%. Fine for
    /// spectra and envelopes, not recommended for the decrement.
    Mean,
    /// Estimate the equilibrium line from crest/trough triples: for a crest `P` between
    /// troughs `T1` and `T2` of an exponential decay about an offset `c`,
    /// `(P - c)^2 = (c - T1)(c - T2)`, so `c = (P^2 - T1 T2) / (2P - T1 - T2)` exactly; the
    /// median over all cycles is subtracted. Use it for FE displacements that oscillate about
    /// a gravity-preloaded position.
    Midline,
}

/// Removes the offset chosen by `detrend`; returns the new signal and the constant removed.
pub fn remove_offset(signal: &Signal, detrend: Detrend) -> Result<(Signal, f64)> {
    let offset = match detrend {
        Detrend::None => 0.0,
        Detrend::Mean => mean(signal.values()),
        Detrend::Midline => midline_offset(signal)?,
    };
    let values = signal.values().iter().map(|x| x - offset).collect();
    Ok((signal.with_values(values)?, offset))
}

fn mean(values: &[f64]) -> f64 {
    if values.is_empty() {
        0.0
    } else {
        values.iter().sum::<f64>() / values.len() as f64
    }
}

/// The equilibrium line of a decaying oscillation from crest/trough triples (see
/// [`Detrend::Midline`]).
pub fn midline_offset(signal: &Signal) -> Result<f64> {
    // The mean is a coarse first guess, good enough to segment the signal into half-cycles.
    let coarse = mean(signal.values());
    let centred = signal.with_values(signal.values().iter().map(|x| x - coarse).collect())?;
    let options = |polarity| PeakOptions {
        polarity,
        ..PeakOptions::default()
    };
    let crests = peaks::find_peaks(&centred, &options(Polarity::Crests))?;
    let troughs = peaks::find_peaks(&centred, &options(Polarity::Troughs))?;
    let half_period = 0.5 * crests.period_s;
    let mut estimates = Vec::new();
    for crest in &crests.peaks {
        let before = troughs
            .peaks
            .iter()
            .rev()
            .find(|trough| trough.time_s < crest.time_s);
        let after = troughs
            .peaks
            .iter()
            .find(|trough| trough.time_s > crest.time_s);
        let (Some(before), Some(after)) = (before, after) else {
            continue;
        };
        let regular = |gap: f64| (gap - half_period).abs() < 0.25 * half_period;
        if !regular(crest.time_s - before.time_s) || !regular(after.time_s - crest.time_s) {
            continue;
        }
        let p = crest.amplitude;
        let (t1, t2) = (-before.amplitude, -after.amplitude);
        let denominator = 2.0 * p - t1 - t2;
        if denominator > 0.0 {
            estimates.push((p * p - t1 * t2) / denominator);
        }
    }
    if estimates.is_empty() {
        return Err(PostError::TooFewPeaks {
            kind: "crest/trough triples",
            found: 0,
            needed: 1,
            hint: "the midline detrend needs a crest between two troughs half a period away"
                .to_string(),
        });
    }
    estimates.sort_by(f64::total_cmp);
    let middle = estimates.len() / 2;
    let median = if estimates.len() % 2 == 1 {
        estimates[middle]
    } else {
        0.5 * (estimates[middle - 1] + estimates[middle])
    };
    Ok(coarse + median)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_signals::{damped_sine, DampedSine};

    #[test]
    fn midline_recovers_an_offset_exactly_where_the_mean_does_not() {
        // zeta = 0.01 decays fast enough that the mean of 10 s misses the midline.
        let offset = 3.7;
        let sine = DampedSine {
            frequency_hz: 4.35,
            zeta: 0.01,
            amplitude: 1.0,
            phase: 0.3,
            offset,
        };
        let (time, x) = damped_sine(&sine, 1000.0, 10.0);
        let midline = midline_offset(&Signal::new(time, x.clone()).unwrap()).unwrap();
        let mean_error = (mean(&x) - offset).abs();
        let midline_error = (midline - offset).abs();
        // The triple formula is exact for an exponential decay; what is left comes from the
        // crest fits (relative ~1e-7 of the amplitude).
        assert!(midline_error < 1e-5, "midline error {midline_error:e}");
        assert!(
            mean_error > 100.0 * midline_error,
            "mean error {mean_error:e}"
        );
    }
}
