//! coil's finite-element values beside the handbook sheet, on the same spring: the rate
//! K of the beam model (pitch angle, bending, direct shear and the real helix, the top
//! guided as in [`crate::fe`]), the first axial (surge) mode with the top held (the
//! sheet's `fe`, both ends fixed), and the peak wire shear at the second working force
//! (`coil_solver::wire`: torsion plus direct shear, no curvature factor, so it sits
//! between the sheet's `tau2` and `tau_k2`).
//!
//! The FE model takes E and Poisson's ratio; the sheet's G is honoured by
//! `nu = E / (2 G) - 1`, so both use the same G and E.
//!
//! # Mesh
//! The helix is a polygon of straight beams; each chord is shorter and straighter than
//! its arc, so the rate converges from above, about as the square of the chord angle
//! (+2.1 % against the handbook at 24 beams per coil, +0.64 % at 96 on a test spring).
//! With handbook moduli nothing absorbs that bias, so [`Mesh::Converged`] refines: it
//! doubles the beams per coil from the starting mesh until the static rate moves less
//! than [`CONVERGED`] (0.1 %) between two meshes (at most [`MAX_DOUBLINGS`] doublings)
//! and reports every mesh's rate; the surge mode and the peak stress come from the
//! finest mesh. A calibration's E belongs to its own mesh (the chord bias is calibrated
//! into E), so its springs run on that mesh ([`Mesh::Fixed`]).
//!
//! # Work
//! A model has at most [`MAX_BEAMS`] beams (active coils times beams per coil; about
//! 0.3 s and 150 MB for the static and modal runs): a spring whose starting mesh is
//! larger is refused before any work, and the refinement stops below the limit. When it
//! stops before the rate has converged, the rate is extrapolated from the last two meshes
//! (Richardson, error ~ 1/m^2 in the beams per coil m: `K = K_2m + (K_2m - K_m) / 3`; on
//! the 160ECT spring the 24 and 48 meshes extrapolate to within 0.003 % of the 192 mesh's
//! own extrapolation) and `fe.mesh.extrapolated` says so.

use super::en13906::{Sheet, Spring};
use crate::case::SpringGeometry;
use crate::error::{Result, TuneError};
use crate::fe::{axial_mode_of, stiffness_of, FeSettings, SpringState};
use coil_mesher::{AnalysisKind, Top};
use coil_solver::analysis::{self, CaseSolution};
use serde::Serialize;

/// Relative change of the rate between two meshes below which it has converged.
pub const CONVERGED: f64 = 1e-3;
/// The most doublings of the beams per coil.
pub const MAX_DOUBLINGS: u32 = 4;
/// The most beams of one FE model (module docs: work).
pub const MAX_BEAMS: f64 = 10_000.0;

/// An error when `state`'s spring at `elements_per_coil` beams per coil has more than
/// [`MAX_BEAMS`] beams (checked before any work).
pub fn check_size(state: &SpringState, elements_per_coil: u32) -> Result<()> {
    let n = state.spring.active_coils;
    let beams = n * f64::from(elements_per_coil);
    if beams > MAX_BEAMS {
        return Err(TuneError::Invalid(format!(
            "active_coils = {n}: the FE model at {elements_per_coil} beams per coil would have {beams:.0} beams; coil's limit is {MAX_BEAMS} (docs/files.md): fewer active coils, or fewer beams per coil (--elements-per-coil)"
        )));
    }
    Ok(())
}

/// Which mesh the FE values come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mesh {
    /// The settings' beams per coil as they are (a calibration's mesh).
    Fixed,
    /// Refined from the settings' beams per coil until the rate moves < 0.1 %.
    Converged,
}

/// The meshes an FE value was computed on.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshStudy {
    /// `fixed` (the settings' mesh) or `converged` (refined until the rate moved less
    /// than 0.1 %).
    pub method: &'static str,
    /// Beams per coil of each mesh run, coarsest first.
    pub elements_per_coil: Vec<u32>,
    /// The static rate on each (N/mm).
    pub rates_n_mm: Vec<f64>,
    /// The rate's change between the last two meshes (%), null with one mesh.
    pub last_change_percent: Option<f64>,
    /// True when the last change is below 0.1 % (or the mesh is fixed).
    pub converged: bool,
    /// True when the refinement reached the model's size limit first and the rate is
    /// extrapolated from the last two meshes (Richardson, module docs).
    pub extrapolated: bool,
}

/// The FE values of the sheet's `fe` object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeValues {
    /// Static axial rate K (N/mm), top guided, on the finest mesh.
    pub rate_n_mm: f64,
    /// First axial mode with the top held (Hz).
    pub surge_frequency_hz: f64,
    /// Largest wire shear (torsion + direct shear) at the second working force (MPa).
    pub max_shear_stress_2_mpa: f64,
    /// The meshes.
    pub mesh: MeshStudy,
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

/// The static rate and peak wire shear of `state` at `force_2_n` on `settings`' mesh.
fn static_values(state: &SpringState, force_2_n: f64, settings: &FeSettings) -> Result<(f64, f64)> {
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
    Ok((rate, peak.stress.shear_mpa))
}

/// The FE values of `state` with the second working force `force_2_n`, on `settings`'
/// mesh or refined from it (module docs).
pub fn fe_values(
    state: &SpringState,
    force_2_n: f64,
    settings: &FeSettings,
    mesh: Mesh,
) -> Result<FeValues> {
    let mut settings = settings.clone();
    check_size(state, settings.elements_per_coil)?;
    let (mut rate, mut peak) = static_values(state, force_2_n, &settings)?;
    let mut study = MeshStudy {
        method: match mesh {
            Mesh::Fixed => "fixed",
            Mesh::Converged => "converged",
        },
        elements_per_coil: vec![settings.elements_per_coil],
        rates_n_mm: vec![rate],
        last_change_percent: None,
        converged: mesh == Mesh::Fixed,
        extrapolated: false,
    };
    let mut coarser = None;
    if mesh == Mesh::Converged {
        for _ in 0..MAX_DOUBLINGS {
            if state.spring.active_coils * f64::from(2 * settings.elements_per_coil) > MAX_BEAMS {
                // The next mesh is above the limit: extrapolate from the last two.
                if let Some(k) = coarser {
                    rate += (rate - k) / 3.0;
                    study.extrapolated = true;
                }
                break;
            }
            coarser = Some(rate);
            settings.elements_per_coil *= 2;
            let (finer, finer_peak) = static_values(state, force_2_n, &settings)?;
            let change = finer / rate - 1.0;
            (rate, peak) = (finer, finer_peak);
            study.elements_per_coil.push(settings.elements_per_coil);
            study.rates_n_mm.push(rate);
            study.last_change_percent = Some(100.0 * change);
            if change.abs() < CONVERGED {
                study.converged = true;
                break;
            }
        }
    }
    let mut spec = state.spec(&settings, &[AnalysisKind::Modal]);
    spec.top = Top::Held;
    spec.mass_kg = 0.0;
    spec.modes = settings.modes.max(6);
    let held = spec.build()?;
    let context = "modal run with the top held";
    let surge = axial_mode_of(&run(&held, context)?, context)?;
    Ok(FeValues {
        rate_n_mm: rate,
        surge_frequency_hz: surge.frequency_hz,
        max_shear_stress_2_mpa: peak,
        mesh: study,
    })
}
