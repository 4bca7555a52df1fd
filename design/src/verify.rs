//! FE verification of a design's short list (in parallel, rayon): each candidate's
//! active coils at its free pitch, the material's E and Poisson's ratio (after a
//! calibration, its E on its own mesh), the target's weight on the guided top. It must
//! meet the target rate within the tolerance by FE and keep its FE surge mode (top
//! held) out of the stated band; its zeta per damping law comes from [`super::band`].
//! With a grade (handbook E) the FE rate comes from a converged mesh
//! ([`crate::sheet::fe::Mesh::Converged`]); with a calibration from the calibration's mesh,
//! whose E absorbed the chord stiffening.

use super::band::LawBand;
use super::search::Candidate;
use super::target::{Material, Target};
use crate::case::SpringGeometry;
use crate::error::Result;
use crate::fe::{FeSettings, SpringState};
use crate::sheet::en13906::Sheet;
use crate::sheet::fe::{fe_values, FeValues, Mesh};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// A short-listed spring after the FE model (an entry of `design.json`'s `candidates`).
#[derive(Debug, Clone, Serialize)]
pub struct Verified {
    /// Rank among the FE-verified candidates (1 = best, no gaps); 0 for a rejected one.
    pub rank: usize,
    /// Rank by the objective among the feasible handbook springs (1 = best).
    pub search_rank: usize,
    /// How the handbook spring was corrected by its FE rate, if it was (the active
    /// coils scaled by K_FE / K_target to the nearest quarter turn).
    pub corrected_from: Option<String>,
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
    /// Static: `1 - tau2 / (0.5 Rm)`; dynamic: `1 - tau_kh / tau_kH` (fatigue).
    pub stress_margin: f64,
    /// Stroke stress tau_kh (MPa).
    pub stroke_stress_mpa: f64,
    /// Permissible stroke stress tau_kH at tau_k1 (MPa).
    pub permissible_stroke_stress_mpa: f64,
    /// True when the fatigue check passes.
    pub fatigue_passed: bool,
    /// The FE values (rate, surge with the top held, peak wire shear at F2).
    pub fe: FeValues,
    /// zeta of the weight mode per damping law (empty without a calibration or weight).
    pub damping_ratio: BTreeMap<String, f64>,
    /// True when the FE rate is within the tolerance and the FE surge mode is clear.
    pub fe_verified: bool,
    /// Why not, when it is not.
    pub fe_rejection: Option<String>,
    /// The deck written (relative to the output folder): `decks/candidate_NN.dat` by
    /// rank, `decks/rejected_NN.dat` for the FE-rejected ones.
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

/// The deck file of the candidate ranked `rank`, or of the `rank`-th rejected spring.
pub fn deck_name(rank: usize, verified: bool) -> String {
    if verified {
        format!("decks/candidate_{rank:02}.dat")
    } else {
        format!("decks/rejected_{rank:02}.dat")
    }
}

/// The mesh a material's FE runs use (module docs).
pub fn mesh_of(material: &Material) -> Mesh {
    if material.damping.is_some() {
        Mesh::Fixed
    } else {
        Mesh::Converged
    }
}

/// The FE settings a candidate's deck and runs use: the material's mesh, the second
/// working force as the static load.
pub fn candidate_settings(c: &Candidate, material: &Material) -> FeSettings {
    FeSettings {
        static_force_n: c.sheet.force_2_n,
        ..material.fe.clone()
    }
}

/// Verifies `short` (each with its search rank and the correction that made it, if
/// any) in parallel.
pub fn verify(
    short: &[(usize, Candidate, Option<String>)],
    target: &Target,
    material: &Material,
    weight_kg: Option<f64>,
    band: Option<&LawBand>,
) -> Result<Vec<Verified>> {
    let springs = f64::from(target.springs_in_parallel);
    let rate = target.rate_n_mm / springs;
    let tolerance = target.rate_tolerance_percent / 100.0;
    let mesh = mesh_of(material);
    short
        .par_iter()
        .map(|(search_rank, c, corrected_from)| {
            let state = candidate_state(c, material, weight_kg.map_or(0.0, |w| w / springs));
            let settings = candidate_settings(c, material);
            let fe = fe_values(&state, c.sheet.force_2_n, &settings, mesh)?;
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
                rank: 0,
                search_rank: *search_rank,
                corrected_from: corrected_from.clone(),
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
                stroke_stress_mpa: c.sheet.stroke_stress_mpa,
                permissible_stroke_stress_mpa: c.sheet.fatigue.permissible_stroke_stress_mpa,
                fatigue_passed: c.sheet.fatigue.passed,
                fe,
                damping_ratio,
                fe_verified: why.is_empty(),
                fe_rejection: (!why.is_empty()).then(|| why.join("; ")),
                deck: String::new(),
                sheet: c.sheet.clone(),
                spring: c.spring.clone(),
            })
        })
        .collect()
}
