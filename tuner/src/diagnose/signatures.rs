//! Gathers the records' signatures ([`super::evidence::Signatures`]) from the
//! post-processor's analyses.

use super::data::DecayData;
use super::effects::BaselineFigures;
use super::evidence::{EnvelopeSummary, PeakSummary, Signatures, StaticSummary};
use crate::case::StaticRecord;
use crate::error::{Result, TuneError};
use coil_postproc::spectrum::{amplitude_spectrum, SpectrumOptions};
use std::ops::Range;

fn post(context: &str) -> impl Fn(coil_postproc::PostError) -> TuneError + '_ {
    move |source| TuneError::Post {
        context: context.to_string(),
        source,
    }
}

/// The static record's fits (loading branch `branch` checked by `data::check_static`).
pub fn static_fit(record: &StaticRecord, branch: Range<usize>) -> Result<StaticSummary> {
    let x = &record.displacement_mm;
    let f = &record.force_n;
    // Straight line through the loading branch (with an intercept: friction offsets it).
    let (xs, fs) = (&x[branch.clone()], &f[branch]);
    let n = xs.len() as f64;
    let (mx, mf) = (xs.iter().sum::<f64>() / n, fs.iter().sum::<f64>() / n);
    let sxx: f64 = xs.iter().map(|v| (v - mx).powi(2)).sum();
    let sxf: f64 = xs.iter().zip(fs).map(|(a, b)| (a - mx) * (b - mf)).sum();
    let k = sxf / sxx;
    let linear_rms = (xs
        .iter()
        .zip(fs)
        .map(|(a, b)| (mf + k * (a - mx) - b).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    Ok(StaticSummary {
        linear_k_n_mm: k,
        k_n_mm: k,
        k3_n_m3: 0.0,
        k3_se: f64::INFINITY,
        friction_n: 0.0,
        friction_se: f64::INFINITY,
        linear_rms_n: linear_rms,
        cubic_rms_n: linear_rms,
    })
}

/// Signatures of the decay (and the static fit), plus the measured spectrum.
#[allow(clippy::type_complexity)]
pub fn compute(
    decay: &DecayData,
    statics: Option<StaticSummary>,
    _figures: &BaselineFigures,
) -> Result<(Signatures, Option<(Vec<f64>, Vec<f64>)>)> {
    let s = &decay.signal;
    let spectrum = amplitude_spectrum(&s.time_s, &s.values, &SpectrumOptions::default())
        .map_err(post("spectrum of the decay record"))?;
    let peaks = spectrum.peaks(4, 0.01);
    let axial = peaks.first().map_or(0.0, |p| p.frequency_hz);
    let second = peaks
        .iter()
        .skip(1)
        .find(|p| (p.frequency_hz / axial - 1.0).abs() < 0.3)
        .map(|p| PeakSummary {
            frequency_hz: p.frequency_hz,
            relative_amplitude: p.amplitude / peaks[0].amplitude,
            z_score: 0.0,
        });
    let duration = s.time_s[s.time_s.len() - 1] - s.time_s[0];
    Ok((
        Signatures {
            axial_hz: axial,
            cycles: axial * duration,
            loss: None,
            backbone: None,
            envelope: EnvelopeSummary {
                kind: "exponential".into(),
                r2_exponential: f64::NAN,
                r2_linear: f64::NAN,
                beat_period_s: None,
            },
            second_peak: second,
            statics,
            per_cycle: Vec::new(),
        },
        Some((spectrum.frequency_hz.clone(), spectrum.amplitude.clone())),
    ))
}
