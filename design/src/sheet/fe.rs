//! coil's finite-element values beside the handbook sheet, on the same spring: the rate
//! K of the beam model (pitch angle, bending, direct shear and the real helix, the top
//! guided as in [`crate::fe`]), the first axial (surge) mode with the top held (the
//! sheet's `fe`, both ends fixed), and the peak wire shear at the second working force
//! (`coil_solver::wire`: torsion plus direct shear, no curvature factor, so it sits
//! between the sheet's `tau2` and `tau_k2`).
//!
//! The FE model takes E and Poisson's ratio; the sheet's G is honoured by
//! `nu = E / (2 G) - 1`, so both use the same G and E.

use super::en13906::{Sheet, Spring};
use crate::case::SpringGeometry;
use crate::error::{Result, TuneError};
use crate::fe::{axial_mode_of, stiffness_of, FeSettings, SpringState};
use coil_mesher::{AnalysisKind, Top};
use coil_solver::analysis::{self, CaseSolution};
use serde::Serialize;

/// The FE values of the sheet's `fe` object.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FeValues {
    /// Static axial rate K (N/mm), top guided.
    pub rate_n_mm: f64,
    /// First axial mode with the top held (Hz).
    pub surge_frequency_hz: f64,
    /// Largest wire shear (torsion + direct shear) at the second working force (MPa).
    pub max_shear_stress_2_mpa: f64,
}

/// The FE state of a sheet's spring: its active coils at the free pitch, E and the
/// Poisson's ratio that gives the sheet's G, no weight, no damping.
pub fn state_of(spring: &Spring, sheet: &Sheet) -> SpringState {
    SpringState {
        spring: SpringGeometry {
            active_coils: spring.active_coils,
            mean_diameter_mm: spring.mean_diameter_mm,
            wire_diameter_mm: spring.wire_diameter_mm,
            pitch_mm: sheet.pitch_mm,
        },
        youngs_modulus_mpa: spring.youngs_modulus_mpa,
        poisson_ratio: spring.youngs_modulus_mpa / (2.0 * spring.shear_modulus_mpa) - 1.0,
        density_kg_m3: spring.density_kg_m3,
        mass_kg: 0.0,
        alpha: 0.0,
        beta: 0.0,
    }
}

fn run(model: &coil_solver::Model, context: &str) -> Result<Vec<analysis::CaseResult>> {
    analysis::run(model).map_err(|source| TuneError::Solve {
        context: context.to_string(),
        source: Box::new(source),
    })
}

/// The FE values of `state` with the second working force `force_2_n`.
pub fn fe_values(state: &SpringState, force_2_n: f64, settings: &FeSettings) -> Result<FeValues> {
    let loaded = FeSettings {
        static_force_n: force_2_n,
        ..settings.clone()
    };
    let model = state.model(&loaded, &[AnalysisKind::Static])?;
    let context = "static run at the second working force";
    let results = run(&model, context)?;
    let rate = stiffness_of(&results, context)?;
    let peak = results
        .iter()
        .find_map(|r| match &r.solution {
            CaseSolution::Static(s) => Some(&s.displacement),
            _ => None,
        })
        .and_then(|u| {
            coil_solver::wire::peak(&model, &coil_solver::wire::element_forces(&model, u))
        })
        .ok_or_else(|| TuneError::Missing {
            context: context.into(),
            what: "no wire stress in the static case".into(),
        })?;
    let mut spec = state.spec(settings, &[AnalysisKind::Modal]);
    spec.top = Top::Held;
    spec.mass_kg = 0.0;
    spec.modes = settings.modes.max(6);
    let held = spec.build()?;
    let context = "modal run with the top held";
    let surge = axial_mode_of(&run(&held, context)?, context)?;
    Ok(FeValues {
        rate_n_mm: rate,
        surge_frequency_hz: surge.frequency_hz,
        max_shear_stress_2_mpa: peak.stress.shear_mpa,
    })
}
