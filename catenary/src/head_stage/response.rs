//! The head stage alone, lumped against reduced, in the frequency domain: for each spring
//! (the 160ECT and Table 4's #1-#6) the collector head (EN 50318's m1) on the springs in
//! parallel, either the lumped stage of [`super::springs`] (`K = n k`, the dashpot of the
//! paper's damping law carried over to the head, `zeta_mid`) or the Craig-Bampton stage
//! of [`super::reduced`] (the same calibrated springs, their surge modes kept, Rayleigh
//! damping on the wire with the same law). docs/catenary.md, "The head stage reduced",
//! prints the table this module computes.
//!
//! # Formulation
//! Two frequency responses, 0-100 Hz, computed exactly from the dense matrices
//! (`Z(w) = K - w^2 M + i w C`, the frame's row and column taken out, units N, mm, t, s):
//! - the receptance `H = u_head / F` of a force on the head with the frame held (what a
//!   contact force does), mm/N;
//! - the transmissibility `T = u_head / u_frame` with the frame moving.
//!
//! A lumped stage `(K, c, m)` has `H = 1 / (K - w^2 m + i w c)` and
//! `T = (K + i w c) H`. The "corrected" lumped stage puts a third of the springs' mass on
//! the head (Rayleigh's static-shape estimate) and the wire's Rayleigh damping on the
//! static shape, `c = alpha m_s / 3 + beta K`.
//!
//! Per spring: the head's resonance (lumped `sqrt(K / m)`, Rayleigh's
//! `sqrt(K / (m + m_s / 3))`, reduced), the first surge, the peak ratio of `|H|`, the
//! largest relative difference `|H_r - H_l| / |H_l|` inside the 20 Hz band that EN 50318
//! keeps (also outside +-0.5 Hz of the resonance, and against the corrected stage), the
//! ratio of `int_0^20 |H|^2 df` (what a broadband force's response variance scales
//! with), and above the band the largest differences of `H` and `T`. The scan steps
//! 0.005 Hz, a fifth of the narrowest half-power band (zeta ~ 0.0012 at 5 Hz gives 0.012
//! Hz), so the peaks are resolved to about 0.1 %.

use super::reduced::{reduced_stage, ReducedStage, FRAME, HEAD};
use super::springs::{HeadStageSettings, HeadStages};
use crate::Result;
use coil_tuner::case::VariantsFile;
use nalgebra::{Complex, DMatrix};
use std::f64::consts::TAU;

/// The band the standard's statistics keep (Hz).
pub const BAND_HZ: f64 = 20.0;
/// The top of the scan (Hz).
pub const TOP_HZ: f64 = 100.0;
/// The frequency step of the scan (Hz).
pub const STEP_HZ: f64 = 0.005;

/// One spring's comparison (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseRow {
    /// The spring's name.
    pub name: String,
    /// Surge modes kept in the reduced stage.
    pub modes: usize,
    /// The first surge mode, weight held (Hz).
    pub surge_hz: f64,
    /// The head's resonance on the lumped stage, `sqrt(K / m)` (Hz).
    pub f_lumped_hz: f64,
    /// Rayleigh's estimate `sqrt(K / (m + m_s / 3))` (Hz).
    pub f_rayleigh_hz: f64,
    /// The head's resonance on the reduced stage (Hz).
    pub f_reduced_hz: f64,
    /// Peak `|H|`, reduced over lumped.
    pub peak_ratio: f64,
    /// Largest `|H_r - H_l| / |H_l|` over 0-20 Hz.
    pub max_dh_band: f64,
    /// The same outside +-0.5 Hz of the reduced resonance.
    pub max_dh_off_resonance: f64,
    /// `int_0^20 |H|^2 df`, reduced over lumped.
    pub energy_ratio: f64,
    /// Largest `|H_r - H_c| / |H_c|` over 0-20 Hz against the corrected lumped stage.
    pub corrected_dh_band: f64,
    /// Largest `|H_r - H_l| / |H_l|` over 20-100 Hz.
    pub max_dh_above: f64,
    /// Largest `|T_r - T_l| / |T_l|` over 20-100 Hz.
    pub max_dt_above: f64,
}

/// `(H, T)` of a lumped stage at `f` Hz: `k` N/mm, `c` N s/mm, the mass `m` t.
pub fn lumped(k: f64, c: f64, m: f64, f: f64) -> (Complex<f64>, Complex<f64>) {
    let w = TAU * f;
    let z = Complex::new(k - w * w * m, w * c);
    let support = Complex::new(k, w * c);
    (z.inv(), support / z)
}

/// `(H, T)` of the reduced stage carrying a head of `head_t` tonnes at `f` Hz (NaN
/// where `Z` is singular).
pub fn reduced(s: &ReducedStage, head_t: f64, f: f64) -> (Complex<f64>, Complex<f64>) {
    let w = TAU * f;
    let n = s.dim();
    let free: Vec<usize> = (0..n).filter(|&i| i != FRAME).collect();
    let z = |r: usize, c: usize| {
        let mut m = s.m[(r, c)];
        if r == HEAD && c == HEAD {
            m += head_t;
        }
        Complex::new(s.k[(r, c)] - w * w * m, w * s.c[(r, c)])
    };
    let zff = DMatrix::from_fn(free.len(), free.len(), |r, c| z(free[r], free[c]));
    let lu = zff.lu();
    let head = free.iter().position(|&i| i == HEAD).unwrap_or(0);
    let mut unit = DMatrix::<Complex<f64>>::zeros(free.len(), 1);
    unit[(head, 0)] = Complex::new(1.0, 0.0);
    let nan = Complex::new(f64::NAN, 0.0);
    let h = lu.solve(&unit).map_or(nan, |x| x[(head, 0)]);
    let drive = DMatrix::from_fn(free.len(), 1, |r, _| -z(free[r], FRAME));
    let t = lu.solve(&drive).map_or(nan, |x| x[(head, 0)]);
    (h, t)
}

/// Each spring of `stages` (the case's, then `variants` in order) compared on a head of
/// `head_mass_kg` (module doc), with the reduced stage at the paper's Rayleigh law.
pub fn compare(
    stages: &HeadStages,
    variants: &VariantsFile,
    head_mass_kg: f64,
    settings: &HeadStageSettings,
) -> Result<Vec<(ResponseRow, ReducedStage)>> {
    let [alpha, beta] = stages.rayleigh_mid;
    let head_t = head_mass_kg * 1e-3;
    let springs =
        std::iter::once(stages.material.spring).chain(variants.variants.iter().map(|v| v.spring));
    let mut rows = Vec::new();
    for (lumped_stage, spring) in stages.stages.iter().zip(springs) {
        let state = stages.material.with_spring(spring);
        let stage = reduced_stage(&state, &settings.fe, alpha, beta)?;
        let k = lumped_stage.stiffness_n_m / 1e3;
        let c = lumped_stage.damping_mid_n_s_m / 1e3;
        let m_s = f64::from(lumped_stage.springs) * stage.spring_mass_t;
        let (m_corr, c_corr) = (head_t + m_s / 3.0, alpha * m_s / 3.0 + beta * k);
        let f_reduced = stage
            .frequencies_on_head_hz(head_t)
            .and_then(|f| f.first().copied())
            .unwrap_or(f64::NAN);
        let scan = scan(
            &stage,
            head_t,
            (k, c, head_t),
            (k, c_corr, m_corr),
            f_reduced,
        );
        rows.push((
            ResponseRow {
                name: lumped_stage.name.clone(),
                modes: stage.dim() - 2,
                surge_hz: stage.surge_hz,
                f_lumped_hz: (k / head_t).sqrt() / TAU,
                f_rayleigh_hz: (k / m_corr).sqrt() / TAU,
                f_reduced_hz: f_reduced,
                peak_ratio: scan.peak[1] / scan.peak[0],
                max_dh_band: scan.worst[0],
                max_dh_off_resonance: scan.worst[1],
                energy_ratio: scan.energy[1] / scan.energy[0],
                corrected_dh_band: scan.worst[2],
                max_dh_above: scan.worst[3],
                max_dt_above: scan.worst[4],
            },
            stage,
        ));
    }
    Ok(rows)
}

/// Peaks of `|H|` (lumped, reduced), band energies, and the largest differences in
/// [`ResponseRow`]'s order.
struct Scan {
    peak: [f64; 2],
    energy: [f64; 2],
    worst: [f64; 5],
}

/// The 0-100 Hz scan of one spring: the lumped and corrected stages as `(k, c, m)`.
fn scan(
    stage: &ReducedStage,
    head_t: f64,
    plain: (f64, f64, f64),
    corrected: (f64, f64, f64),
    f_reduced: f64,
) -> Scan {
    let mut out = Scan {
        peak: [0.0; 2],
        energy: [0.0; 2],
        worst: [0.0; 5],
    };
    let rel = |a: Complex<f64>, b: Complex<f64>| (a - b).norm() / b.norm();
    let steps = (TOP_HZ / STEP_HZ).round() as usize;
    for i in 0..=steps {
        let f = i as f64 * STEP_HZ;
        let (hl, tl) = lumped(plain.0, plain.1, plain.2, f);
        let (hr, tr) = reduced(stage, head_t, f);
        out.peak[0] = out.peak[0].max(hl.norm());
        out.peak[1] = out.peak[1].max(hr.norm());
        let values = if f <= BAND_HZ {
            let (hc, _) = lumped(corrected.0, corrected.1, corrected.2, f);
            out.energy[0] += hl.norm_sqr() * STEP_HZ;
            out.energy[1] += hr.norm_sqr() * STEP_HZ;
            let off = (f - f_reduced).abs() > 0.5;
            let d = rel(hr, hl);
            [d, if off { d } else { 0.0 }, rel(hr, hc), 0.0, 0.0]
        } else {
            [0.0, 0.0, 0.0, rel(hr, hl), rel(tr, tl)]
        };
        for (w, v) in out.worst.iter_mut().zip(values) {
            *w = w.max(v);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::head_stage::springs::head_stages_of_files;
    use std::path::Path;

    /// docs/catenary.md's frequency-response table, each column to half a unit of its
    /// printed last digit; and a lumped stage's own closed forms (`|H(0)| = 1/K`, `T(0) =
    /// 1`, the undamped resonance of `K, m`).
    #[test]
    fn the_docs_frequency_response_table() {
        let (h0, t0) = lumped(15.71, 0.0, 7.2e-3, 0.0);
        assert!((h0.norm() * 15.71 - 1.0).abs() < 1e-12 && (t0.norm() - 1.0).abs() < 1e-12);
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
        let settings = HeadStageSettings::default();
        let variants = coil_tuner::case::read_variants(&root.join("table4.json")).unwrap();
        let stages =
            head_stages_of_files(&root, &root.join("table4.json"), 7.2, &settings).unwrap();
        let rows = compare(&stages, &variants, 7.2, &settings).unwrap();
        #[rustfmt::skip]
        let docs: [(&str, usize, [f64; 11]); 7] = [
            ("160ECT", 8, [129.8, 7.4343, 7.3943, 7.3942, 0.588, 1.86, 0.090, 0.585, 0.0068, 0.021, 2.64]),
            ("#1", 9, [96.1, 5.9074, 5.8704, 5.8703, 0.612, 2.62, 0.083, 0.585, 0.0106, 0.088, 23.29]),
            ("#2", 6, [151.2, 10.1028, 10.0290, 10.0287, 0.591, 1.87, 0.160, 0.584, 0.0080, 0.022, 1.35]),
            ("#3", 8, [108.3, 5.1697, 5.1503, 5.1503, 0.588, 1.83, 0.045, 0.585, 0.0056, 0.028, 8.98]),
            ("#4", 4, [185.9, 9.7511, 9.7072, 9.7070, 0.587, 1.24, 0.099, 0.585, 0.0040, 0.012, 0.69]),
            ("#5", 5, [152.8, 8.0320, 7.9949, 7.9948, 0.593, 1.51, 0.084, 0.585, 0.0058, 0.014, 1.35]),
            ("#6", 8, [113.3, 6.9530, 6.9103, 6.9101, 0.597, 2.23, 0.095, 0.585, 0.0082, 0.035, 5.86]),
        ];
        let units = [
            0.1, 1e-4, 1e-4, 1e-4, 1e-3, 1e-2, 1e-3, 1e-3, 1e-4, 1e-3, 1e-2,
        ];
        assert_eq!(rows.len(), docs.len());
        for ((row, _), (name, modes, printed)) in rows.iter().zip(docs) {
            assert_eq!((row.name.as_str(), row.modes), (name, modes));
            let got = [
                row.surge_hz,
                row.f_lumped_hz,
                row.f_rayleigh_hz,
                row.f_reduced_hz,
                row.peak_ratio,
                row.max_dh_band,
                row.max_dh_off_resonance,
                row.energy_ratio,
                row.corrected_dh_band,
                row.max_dh_above,
                row.max_dt_above,
            ];
            for (i, ((g, p), u)) in got.iter().zip(printed).zip(units).enumerate() {
                assert!(
                    (g - p).abs() <= 0.5 * u + 1e-12,
                    "{name} column {i}: {g} against the docs' {p}"
                );
            }
        }
    }
}
