//! Signatures of a free decay that the paper's linear model (linear spring, viscous Rayleigh
//! damping) cannot produce: amplitude loss per cycle against amplitude, frequency against
//! amplitude (the backbone), the shape of the envelope, and a second spectral line beside
//! the axial one. They start `coil-tune diagnose`'s nonlinear fits, which then refine by
//! output error: the numbers are initial estimates with honest standard errors, not final
//! values.
//!
//! # Units and signs
//! The input is the axial acceleration of the weight in m/s^2 (`decay.csv`, see
//! `docs/measured-case.md`); every displacement amplitude here is in metres (SI), so
//! that the conversions take `k` in N/m and `m` in kg. Times in s, frequencies in Hz.
//!
//! # One concept per module
//! - `cycles`: the record cut into cycles, each with its fundamental amplitude and
//!   frequency ([`cycles()`], [`cycles_in`] with the spectrum already computed).
//! - `loss`: amplitude loss per cycle against amplitude: viscous, Coulomb, quadratic
//!   ([`loss_per_cycle`] and the conversions).
//! - `backbone`: frequency against amplitude and the cubic stiffness it implies
//!   ([`backbone()`], [`cubic_from_backbone`]).
//! - `shape`: exponential, linear or beating envelope ([`envelope_shape`]).
//! - `side_peak`: the axial spectral line and a side line beside it
//!   ([`spectral_peaks`], [`side_peaks`]).
//!
//! Each module's doc gives its formulation. Estimates carry standard errors
//! ([`Estimate`]).

mod backbone;
mod cycles;
mod loss;
mod shape;
mod side_peak;
#[cfg(test)]
mod test_records;

pub use crate::stats::Estimate;
pub use backbone::{backbone, cubic_from_backbone, BackboneFit};
pub use cycles::{
    crossing_frequency, cycles, cycles_in, Cycle, CycleOptions, CycleSeries, AGREEMENT,
    CYCLE_NOISE_FLOOR, CYCLE_TOLERANCE, DEFAULT_BAND,
};
pub use loss::{
    friction_force, loss_per_cycle, loss_per_cycle_windowed, quadratic_coefficient, zeta_from_a1,
    LossFit, LossPoint, SingleTermFits, TermFit, MIN_LOSS_WINDOWS,
};
pub use shape::{
    envelope_shape, EnvelopeKind, EnvelopeShape, BEAT_MIN_DEPTH, BEAT_VARIANCE_RATIO,
    MIN_BEAT_CYCLES,
};
pub use side_peak::{
    side_peaks, spectral_peaks, SidePeak, SpectralSignature, SIDE_RANGE, SIDE_THRESHOLD,
};

/// The whole chain on synthetic records whose answers are known in closed form.
#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::PostError;
    use crate::signal::Signal;
    use std::f64::consts::{PI, TAU};
    use test_records::*;

    /// A decay whose frequency sweeps from 5 to 6 Hz (20 %) over 30 s spreads its line
    /// over about 30 native bins: the spectrum's prominence rule finds no regular peak, but
    /// the zero crossings find the oscillation at its mean frequency (the phase's closed
    /// form: 5.5 Hz) and the cycles follow the sweep (each cycle's frequency is the
    /// instantaneous one at its centre, within the 1 % a cycle's linear chirp and the
    /// crossing noise allow).
    #[test]
    fn a_line_swept_by_20_percent_is_one_oscillation() {
        let (f0, f1, seconds) = (5.0_f64, 6.0_f64, 30.0_f64);
        let rate = (f1 - f0) / seconds;
        let time = times(30_000);
        let clean: Vec<f64> = time
            .iter()
            .map(|&t| (-0.05 * t).exp() * (TAU * (f0 * t + 0.5 * rate * t * t) + 0.3).sin())
            .collect();
        let accel = measured(&clean, 7);
        let signal = sig(&time, &accel);
        let f = crossing_frequency(&signal).unwrap();
        assert!(within(f, 0.5 * (f0 + f1), 0.002), "{f}");
        let series = cycles(&signal, &CycleOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(series.cycles.len() > 120, "{}", series.cycles.len());
        for c in &series.cycles {
            assert!(within(c.frequency_hz, f0 + rate * c.time_s, 0.01), "{c:?}");
        }
    }

    #[test]
    fn viscous_decay_gives_a1_of_2_pi_zeta_and_nothing_else() {
        let (f, zeta, a0): (f64, f64, f64) = (5.0, 0.003, 0.01);
        let omega_n = TAU * f;
        let omega_d = omega_n * (1.0 - zeta * zeta).sqrt();
        let sigma = zeta * omega_n;
        let time = times(30_000);
        let clean: Vec<f64> = time
            .iter()
            .map(|t| a0 * omega_n * omega_n * (-sigma * t).exp() * (omega_d * t + 0.4).cos())
            .collect();
        let accel = measured(&clean, 1);
        let series = cycles(&sig(&time, &accel), &CycleOptions::default()).unwrap();
        // Per cycle, A = a / omega_d^2 = a0 e^{-sigma t} / (1 - zeta^2); the cycle's fit
        // over a decaying cycle is its mean to (sigma T)^2 / 24 ~ 1e-5, noise 0.1% at the
        // start and ~2% at the end: 3% covers every cycle.
        let worst = series
            .cycles
            .iter()
            .map(|c| {
                let exact = a0 * (-sigma * c.time_s).exp() / (1.0 - zeta * zeta);
                ((c.amplitude_m - exact) / exact).abs()
                    / (c.amplitude_std_error_m / exact).max(1e-4)
            })
            .fold(0.0, f64::max);
        assert!(series.cycles.len() > 120, "{} cycles", series.cycles.len());
        assert!(worst < 5.0, "worst cycle {worst} standard errors off");

        let loss = loss_per_cycle(&series.cycles).unwrap();
        let delta = 2.0 * PI * zeta / (1.0 - zeta * zeta).sqrt();
        eprintln!("viscous: {loss:#?}");
        // Weak damping: each term within three standard errors of its theory.
        assert!(
            (loss.a1.value - delta).abs() < 3.0 * loss.a1.std_error,
            "{:?}",
            loss.a1
        );
        assert!(
            loss.a0_m.value.abs() < 3.0 * loss.a0_m.std_error,
            "{:?}",
            loss.a0_m
        );
        assert!(
            loss.a2_per_m.value.abs() < 3.0 * loss.a2_per_m.std_error,
            "{:?}",
            loss.a2_per_m
        );
        // The single viscous term is sharp: 2%.
        let single = loss.single.viscous_a1.coefficient;
        assert!(within(single.value, delta, 0.02), "{single:?} vs {delta}");
        assert!(within(zeta_from_a1(single.value), zeta, 0.02));

        let bend = backbone(&series.cycles).unwrap();
        eprintln!("viscous backbone: {bend:?}");
        assert!(
            bend.b_per_m2.value.abs() < 3.0 * bend.b_per_m2.std_error,
            "{bend:?}"
        );
        assert!(within(bend.f0_hz.value, omega_d / TAU, 1e-3), "{bend:?}");

        let shape = envelope_shape(&series.cycles).unwrap();
        eprintln!("viscous shape: {shape:?}");
        assert_eq!(shape.kind, EnvelopeKind::Exponential, "{shape:?}");
        assert!(within(shape.decay_rate_per_s, sigma, 0.02), "{shape:?}");
        let spectral = spectral_peaks(&sig(&time, &accel)).unwrap();
        assert!(spectral.side.is_none(), "{spectral:?}");
    }

    #[test]
    fn bad_inputs_are_typed_errors() {
        let time = times(5000);
        let flat = vec![0.0; 5000];
        assert!(matches!(
            cycles(&sig(&time, &flat), &CycleOptions::default()),
            Err(PostError::TooFewPeaks { .. })
        ));
        let sine: Vec<f64> = time.iter().map(|t| (TAU * 5.0 * t).sin()).collect();
        let wide = CycleOptions {
            band: Some(1.5),
            ..CycleOptions::default()
        };
        assert!(matches!(
            cycles(&sig(&time, &sine), &wide),
            Err(PostError::InvalidOption(_))
        ));
        let mut nan = sine.clone();
        nan[7] = f64::NAN;
        assert!(matches!(
            Signal::new(time.clone(), nan),
            Err(PostError::InvalidSignal { index: 7, .. })
        ));
        let series = cycles(&sig(&time, &sine), &CycleOptions::default()).unwrap();
        assert!(matches!(
            loss_per_cycle(&series.cycles[..10]),
            Err(PostError::TooFewPoints { .. })
        ));
        assert!(matches!(
            loss_per_cycle_windowed(&series.cycles, 2),
            Err(PostError::InvalidOption(_))
        ));
        // A steady sine: every cycle has the same amplitude, the backbone cannot bend.
        assert!(backbone(&series.cycles[..3]).is_err());
    }
}
