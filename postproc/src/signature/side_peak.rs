//! The axial spectral line and a side line beside it (a second mode beating with it).
//!
//! # Formulation
//!
//! The Hann-windowed, 8 times zero-padded amplitude spectrum of [`crate::spectrum`] with its
//! log-parabolic (Gaussian) sub-bin interpolation and its prominence and side-lobe rules: the
//! largest peak is the axial one at `f_1`; the largest other peak within 0.7-1.3 `f_1` and
//! above 2% of it is the side peak `f_2` (the Wilberforce torsional mode, seen in the axial
//! record through the coupling), reported with its relative amplitude and the beat period
//! `1 / |f_1 - f_2|`.
//!
//! # Units and signs
//! The input is the axial acceleration of the weight in m/s^2 (`decay.csv`, see
//! `docs/measured-case.md`); every displacement amplitude here is in metres (SI), so
//! that the conversions below take `k` in N/m and `m` in kg. Times in s, frequencies in Hz.

use serde::Serialize;

use crate::error::{PostError, Result};
use crate::signal::Signal;
use crate::spectrum::{amplitude_spectrum, SpectralPeak, Spectrum, SpectrumOptions};

/// The side peak is searched from `SIDE_RANGE.0 f_1` to `SIDE_RANGE.1 f_1`.
pub const SIDE_RANGE: (f64, f64) = (0.7, 1.3);

/// The smallest side peak reported, relative to the axial one.
pub const SIDE_THRESHOLD: f64 = 0.02;

/// The second line beside the axial one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SidePeak {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Amplitude, m/s^2.
    pub amplitude: f64,
    /// Amplitude relative to the axial peak.
    pub relative_amplitude: f64,
    /// `1 / |f_1 - f_2|`, s.
    pub beat_period_s: f64,
}

/// Result of [`spectral_peaks`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpectralSignature {
    /// The largest peak.
    pub axial: SpectralPeak,
    /// The largest other peak within [`SIDE_RANGE`] of the axial frequency, if above
    /// [`SIDE_THRESHOLD`].
    pub side: Option<SidePeak>,
    /// Frequency resolution of the record `1 / T`, Hz.
    pub native_bin_hz: f64,
}

/// The axial peak and the side peak of a [`Signal`] (see the module doc).
pub fn spectral_peaks(signal: &Signal) -> Result<SpectralSignature> {
    let options = SpectrumOptions {
        zero_pad: 8,
        ..SpectrumOptions::default()
    };
    amplitude_spectrum(signal, &options)
        .and_then(|spectrum| side_peaks(&spectrum))
        .map_err(|error| signal.locate(error))
}

/// The axial and side peaks of a spectrum already computed ([`spectral_peaks`] uses the
/// Hann window zero-padded 8 times).
pub fn side_peaks(spectrum: &Spectrum) -> Result<SpectralSignature> {
    let peaks = spectrum.peaks(16, SIDE_THRESHOLD);
    let Some(&axial) = peaks.first().filter(|p| p.frequency_hz > 0.0) else {
        return Err(PostError::TooFewPeaks {
            kind: "spectral peaks",
            found: 0,
            needed: 1,
            hint: "the record shows no oscillation".to_string(),
        });
    };
    let f1 = axial.frequency_hz;
    let side = peaks
        .iter()
        .skip(1)
        .find(|p| (SIDE_RANGE.0 * f1..=SIDE_RANGE.1 * f1).contains(&p.frequency_hz))
        .map(|p| SidePeak {
            frequency_hz: p.frequency_hz,
            amplitude: p.amplitude,
            relative_amplitude: p.amplitude / axial.amplitude,
            beat_period_s: 1.0 / (f1 - p.frequency_hz).abs(),
        });
    Ok(SpectralSignature {
        axial,
        side,
        native_bin_hz: spectrum.native_bin_hz,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signature::cycles::{cycles, CycleOptions};
    use crate::signature::shape::{envelope_shape, EnvelopeKind};
    use crate::signature::test_records::*;
    use std::f64::consts::TAU;

    #[test]
    fn two_tones_beat_at_the_difference_frequency() {
        let (f1, f2, ratio, zeta) = (5.0, 5.4, 0.3, 0.002);
        let time = times(30_000);
        // One decay rate for both lines, so that their windowed heights keep the ratio.
        let sigma = zeta * TAU * f1;
        let tone = |f: f64, t: f64, phase: f64| (-sigma * t).exp() * (TAU * f * t + phase).cos();
        let clean: Vec<f64> = time
            .iter()
            .map(|&t| tone(f1, t, 0.2) + ratio * tone(f2, t, 1.1))
            .collect();
        let accel = measured(&clean, 6);
        let spectral = spectral_peaks(&sig(&time, &accel)).unwrap();
        eprintln!("beating: {spectral:?}");
        let side = spectral.side.unwrap();
        let beat = 1.0 / (f2 - f1);
        assert!(within(spectral.axial.frequency_hz, f1, 0.01));
        assert!(within(side.frequency_hz, f2, 0.01), "{side:?}");
        assert!(within(side.beat_period_s, beat, 0.01), "{side:?}");
        assert!(within(side.relative_amplitude, ratio, 0.01), "{side:?}");

        let series = cycles(&sig(&time, &accel), &CycleOptions::default()).unwrap();
        let shape = envelope_shape(&series.cycles).unwrap();
        eprintln!("beating shape: {shape:?}");
        assert_eq!(shape.kind, EnvelopeKind::Beating, "{shape:?}");
        assert!(
            within(shape.beat_period_s.unwrap(), beat, 0.02),
            "{shape:?}"
        );
    }
}
