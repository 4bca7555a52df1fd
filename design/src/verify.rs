//! FE verification of a design's short list (in parallel, rayon): each candidate's
//! active coils at its free pitch, the material's E and Poisson's ratio (after a
//! calibration, its E on its own mesh), the target's weight on the guided top. It must
//! meet the target rate within the tolerance by FE and keep its FE surge mode (top
//! held) out of the stated band; its zeta per damping law comes from [`super::band`].

use super::band::LawBand;
use super::search::Candidate;
use super::target::{Material, Target};
use crate::case::SpringGeometry;
use crate::error::Result;
use crate::fe::{FeSettings, SpringState};
use crate::sheet::en13906::Sheet;
use crate::sheet::fe::{fe_values, FeValues};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// A short-listed spring after the FE model (an entry of `design.json`'s `candidates`).
#[derive(Debug, Clone, Serialize)]
pub struct Verified {
    /// Rank by the objective among the handbook candidates (1 = best).
    pub rank: usize,
    /// d (mm).
    pub wire_diameter_mm: f64,
    /// D (mm).
    pub mean_diameter_mm: f64,
    /// n.
    pub active_coils: f64,
    /// nt.
    pub total_coils: f64,
    /// Pitch of the free spring (mm).
    pub pitch_mm: f64,
    /// L0 (mm).
    pub free_length_mm: f64,
    /// Handbook rate of one spring (N/mm).
    pub rate_n_mm: f64,
    /// FE rate of one spring (N/mm).
    pub fe_rate_n_mm: f64,
    /// FE rate against the target rate of one spring (%).
    pub fe_rate_error_percent: f64,
    /// Wire mass of one spring (kg).
    pub spring_mass_kg: f64,
    /// `1 - tau / (0.5 Rm)` at the second working point.
    pub stress_margin: f64,
    /// The FE values (rate, surge with the top held, peak wire shear at F2).
    pub fe: FeValues,
    /// zeta of the weight mode per damping law (empty without a calibration or weight).
    pub damping_ratio: BTreeMap<String, f64>,
    /// True when the FE rate is within the tolerance and the FE surge mode is clear.
    pub fe_verified: bool,
    /// Why not, when it is not.
    pub fe_rejection: Option<String>,
    /// The deck written (relative to the output folder).
    pub deck: String,
    /// The handbook sheet.
    pub sheet: Sheet,
    /// The spring the sheet is of (its inputs are in the sheet and the fields above).
    #[serde(skip)]
    pub spring: crate::sheet::en13906::Spring,
}

/// The FE state of a candidate with the weight of one spring.
pub fn candidate_state(c: &Candidate, material: &Material, weight_kg: f64) -> SpringState {
    SpringState {
        spring: SpringGeometry {
            active_coils: c.spring.active_coils,
            mean_diameter_mm: c.spring.mean_diameter_mm,
            wire_diameter_mm: c.spring.wire_diameter_mm,
            pitch_mm: c.pitch_mm(),
        },
        youngs_modulus_mpa: material.youngs_modulus_mpa,
        poisson_ratio: material.poisson_ratio,
        density_kg_m3: material.density_kg_m3,
        mass_kg: weight_kg,
        alpha: 0.0,
        beta: 0.0,
    }
}

/// The deck file of the candidate ranked `rank`.
pub fn deck_name(rank: usize) -> String {
    format!("decks/candidate_{rank:02}.dat")
}

/// The FE settings a candidate's deck and runs use: the material's mesh, the second
/// working force as the static load.
pub fn candidate_settings(c: &Candidate, material: &Material) -> FeSettings {
    FeSettings {
        static_force_n: c.sheet.force_2_n,
        ..material.fe.clone()
    }
}

/// Verifies `short` (ranks from 1) in parallel.
pub fn verify(
    short: &[Candidate],
    target: &Target,
    material: &Material,
    weight_kg: Option<f64>,
    band: Option<&LawBand>,
) -> Result<Vec<Verified>> {
    let springs = f64::from(target.springs_in_parallel);
    let rate = target.rate_n_mm / springs;
    let tolerance = target.rate_tolerance_percent / 100.0;
    short
        .par_iter()
        .enumerate()
        .map(|(i, c)| {
            let state = candidate_state(c, material, weight_kg.map_or(0.0, |w| w / springs));
            let settings = candidate_settings(c, material);
            let fe = fe_values(&state, c.sheet.force_2_n, &settings)?;
            let damping_ratio = match (band, weight_kg) {
                (Some(b), Some(_)) => b.zeta(&state)?,
                _ => BTreeMap::new(),
            };
            let error = fe.rate_n_mm / rate - 1.0;
            let mut why = Vec::new();
            if error.abs() > tolerance {
                why.push(format!(
                    "FE rate {:.4} N/mm is {:+.2} % from {rate:.4}",
                    fe.rate_n_mm,
                    100.0 * error
                ));
            }
            if let Some((lo, hi)) = target.surge_band_hz {
                if (lo..=hi).contains(&fe.surge_frequency_hz) {
                    why.push(format!(
                        "FE surge mode {:.1} Hz in the band [{lo}, {hi}] Hz",
                        fe.surge_frequency_hz
                    ));
                }
            }
            Ok(Verified {
                rank: i + 1,
                wire_diameter_mm: c.spring.wire_diameter_mm,
                mean_diameter_mm: c.spring.mean_diameter_mm,
                active_coils: c.spring.active_coils,
                total_coils: c.spring.total_coils,
                pitch_mm: c.pitch_mm(),
                free_length_mm: c.spring.free_length_mm,
                rate_n_mm: c.sheet.rate_n_mm,
                fe_rate_n_mm: fe.rate_n_mm,
                fe_rate_error_percent: 100.0 * error,
                spring_mass_kg: c.sheet.spring_mass_kg,
                stress_margin: c.stress_margin,
                fe,
                damping_ratio,
                fe_verified: why.is_empty(),
                fe_rejection: (!why.is_empty()).then(|| why.join("; ")),
                deck: deck_name(i + 1),
                sheet: c.sheet.clone(),
                spring: c.spring.clone(),
            })
        })
        .collect()
}
