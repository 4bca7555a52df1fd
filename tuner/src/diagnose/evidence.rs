//! The records' signatures the diagnosis reads (what the linear model misses), gathered
//! from the post-processor's analyses (`coil_postproc::signature`, `static_curve`).

use serde::Serialize;

/// Per-cycle amplitude loss `dA = a0 + a1 A + a2 A^2` (A displacement amplitude, m).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LossSummary {
    pub a0_m: f64,
    pub a0_se: f64,
    pub a1: f64,
    pub a1_se: f64,
    pub a2_per_m: f64,
    pub a2_se: f64,
}

/// Backbone `f^2 = f0^2 (1 + b A^2)` and the cubic stiffness it implies.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct BackboneSummary {
    pub f0_hz: f64,
    pub b_per_m2: f64,
    pub b_se: f64,
    pub k3_n_m3: f64,
}

/// Envelope shape.
#[derive(Debug, Clone, Serialize)]
pub struct EnvelopeSummary {
    /// `exponential`, `linear` or `beating`.
    pub kind: String,
    pub r2_exponential: f64,
    pub r2_linear: f64,
    pub beat_period_s: Option<f64>,
}

/// A second spectral line beside the axial one.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct PeakSummary {
    pub frequency_hz: f64,
    /// Its amplitude over the axial line's.
    pub relative_amplitude: f64,
    /// Its relative amplitude over the detection threshold (2 % of the axial line).
    pub z_score: f64,
}

/// The static record's fits.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StaticSummary {
    /// Stiffness of the straight line `F = k x + s F_f` through both branches (N/mm).
    pub linear_k_n_mm: f64,
    /// `F = k x + k3 x^3 + s Ff` (s = +1 loading, -1 unloading).
    pub k_n_mm: f64,
    pub k3_n_m3: f64,
    pub k3_se: f64,
    pub friction_n: f64,
    pub friction_se: f64,
    /// Residual RMS of the straight line and of the cubic fit with hysteresis (N).
    pub linear_rms_n: f64,
    pub cubic_rms_n: f64,
}

/// One cycle of the band-passed axial mode.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CycleSummary {
    pub time_s: f64,
    pub amplitude_m: f64,
    pub frequency_hz: f64,
}

/// Everything the effects read.
#[derive(Debug, Clone, Serialize)]
pub struct Signatures {
    pub axial_hz: f64,
    /// Robust estimate of the record's white noise (m/s^2; from the median absolute
    /// fourth difference, `coil_postproc::signature::cycles`; NaN if no cycles were
    /// found).
    pub noise_rms_m_s2: f64,
    pub cycles: f64,
    pub loss: Option<LossSummary>,
    pub backbone: Option<BackboneSummary>,
    pub envelope: EnvelopeSummary,
    pub second_peak: Option<PeakSummary>,
    pub statics: Option<StaticSummary>,
    #[serde(skip)]
    pub per_cycle: Vec<CycleSummary>,
}
