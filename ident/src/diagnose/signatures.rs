//! Gathers the records' signatures ([`super::evidence::Signatures`]) from the
//! post-processor's analyses (`coil_postproc::signature`, `coil_postproc::static_curve`;
//! their formulas and tests are there).
//!
//! A signature that cannot be formed on a record (too few cycles for the loss windows,
//! an unidentifiable backbone) is left out, with the effects falling back to generic
//! starting values; it never stops the diagnosis.

use super::data::DecayData;
use super::effects::BaselineFigures;
use super::evidence::{
    BackboneSummary, CycleSummary, EnvelopeSummary, LossSummary, PeakSummary, Signatures,
    StaticSummary,
};
use crate::case::StaticRecord;
use crate::error::{Result, TuneError};
use coil_postproc::signature::{self, CycleOptions, EnvelopeKind};
use coil_postproc::spectrum::{amplitude_spectrum, SpectrumOptions};
use coil_postproc::static_curve;
use std::ops::Range;

fn post(context: &str) -> impl Fn(coil_postproc::PostError) -> TuneError + '_ {
    move |source| TuneError::Post {
        context: context.to_string(),
        source,
    }
}

/// The static record's fits. `branch` is the loading branch found by
/// `data::check_static` (the record passed that check).
pub fn static_fit(record: &StaticRecord, _branch: Range<usize>) -> Result<StaticSummary> {
    let fit = static_curve::analyze_static(&record.displacement_mm, &record.force_n).map_err(
        |source| TuneError::Post {
            context: format!("static record {}", record.file.display()),
            source,
        },
    )?;
    let friction = fit
        .friction_n
        .map_or((0.0, f64::INFINITY), |e| (e.value, e.std_error));
    Ok(StaticSummary {
        linear_k_n_mm: fit.linear.stiffness_n_mm.value,
        k_n_mm: fit.stiffness_n_mm.value,
        k3_n_m3: fit.cubic_n_m3.value,
        k3_se: fit.cubic_n_m3.std_error,
        friction_n: friction.0,
        friction_se: friction.1,
        linear_rms_n: fit.linear.quality.residual_rms_n,
        cubic_rms_n: fit.cubic.residual_rms_n,
    })
}

/// Signatures of the decay (and the static fit), plus the measured spectrum for the
/// figure. `figures` gives the calibrated stiffness and the gravity preload that turn
/// the backbone into a cubic stiffness.
#[allow(clippy::type_complexity)]
pub fn compute(
    decay: &DecayData,
    statics: Option<StaticSummary>,
    figures: &BaselineFigures,
) -> Result<(Signatures, Option<(Vec<f64>, Vec<f64>)>)> {
    let s = &decay.signal;
    let spectrum = amplitude_spectrum(s, &SpectrumOptions::default())
        .map_err(post("spectrum of the decay record"))?;
    // The axial line from the spectrum; a line swept over many bins by a strong
    // nonlinearity shows no regular peak (or a noise bump far from the oscillation), and
    // the record's zero-crossing rate (the conditioning's count,
    // `DecayData::frequency_hz`) is its frequency.
    let rate = decay.frequency_hz;
    let peaks = signature::spectral_peaks(s)
        .ok()
        .filter(|p| (p.axial.frequency_hz - rate).abs() <= signature::AGREEMENT * rate);
    let axial_hz = peaks
        .as_ref()
        .map_or(decay.frequency_hz, |p| p.axial.frequency_hz);
    let second_peak = peaks.and_then(|p| p.side).map(|p| PeakSummary {
        frequency_hz: p.frequency_hz,
        relative_amplitude: p.relative_amplitude,
        z_score: p.relative_amplitude / signature::SIDE_THRESHOLD,
    });
    let series = signature::cycles_in(s, &spectrum, &CycleOptions::default()).ok();
    let cycles = series.as_ref().map_or(&[][..], |c| c.cycles.as_slice());
    let crests = super::halfcycle::crests(s.values(), s.step_s(), axial_hz, decay.noise.rms);
    let half_cycle_loss = super::halfcycle::loss(&crests);
    let windowed = signature::loss_per_cycle(cycles).ok().map(|l| LossSummary {
        a0_m: l.a0_m.value,
        a0_se: l.a0_m.std_error,
        a1: l.a1.value,
        a1_se: l.a1.std_error,
        a2_per_m: l.a2_per_m.value,
        a2_se: l.a2_per_m.std_error,
        a0_two_term_z: l
            .a0_without_drag_m
            .map_or(f64::NAN, |e| e.value / e.std_error),
        a2_two_term_z: l
            .a2_without_friction_per_m
            .map_or(f64::NAN, |e| e.value / e.std_error),
    });
    // A record too short for the windowed fit (about 15 cycles) has its crests.
    let loss = windowed.or(half_cycle_loss);
    let backbone = signature::backbone(cycles).ok().map(|b| {
        // The backbone bends about the preloaded state: its tangent stiffness is the
        // dynamic one, m w^2, not the static secant.
        let w = std::f64::consts::TAU * b.f0_hz.value;
        let k3 = signature::cubic_from_backbone(
            b.b_per_m2.value,
            figures.mass_kg * w * w,
            figures.preload_m,
        )
        .unwrap_or(f64::NAN);
        BackboneSummary {
            f0_hz: b.f0_hz.value,
            b_per_m2: b.b_per_m2.value,
            b_se: b.b_per_m2.std_error,
            k3_n_m3: k3,
        }
    });
    let envelope = match signature::envelope_shape(cycles) {
        Ok(e) => EnvelopeSummary {
            kind: match e.kind {
                EnvelopeKind::Exponential => "exponential",
                EnvelopeKind::Linear => "linear",
                EnvelopeKind::Beating => "beating",
            }
            .into(),
            r2_exponential: e.r2_exponential,
            r2_linear: e.r2_linear,
            beat_period_s: e.beat_period_s,
        },
        // Too few cycles for the post-processor's test: the crests' own.
        Err(_) => super::halfcycle::envelope(&crests).unwrap_or(EnvelopeSummary {
            kind: "unknown".into(),
            r2_exponential: f64::NAN,
            r2_linear: f64::NAN,
            beat_period_s: None,
        }),
    };
    let duration = s.time_s()[s.time_s().len() - 1] - s.time_s()[0];
    Ok((
        Signatures {
            axial_hz,
            noise_rms_m_s2: series.as_ref().map_or(f64::NAN, |c| c.noise_rms),
            cycles: axial_hz * duration,
            loss,
            half_cycle_loss,
            backbone,
            envelope,
            second_peak,
            statics,
            per_cycle: cycles
                .iter()
                .map(|c| CycleSummary {
                    time_s: c.time_s,
                    amplitude_m: c.amplitude_m,
                    frequency_hz: c.frequency_hz,
                })
                .collect(),
        },
        Some((spectrum.frequency_hz.clone(), spectrum.amplitude.clone())),
    ))
}
