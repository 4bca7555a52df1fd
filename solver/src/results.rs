//! Result files of a run: `DIR/results.json`, `DIR/model.vtu`, one `.vtu` per static
//! displaced shape and per mode shape, and one history CSV per transient load case.
//!
//! # results.json
//! ```json
//! {"title": "...", "load_cases": [
//!   {"name": "...", "kind": "static", "stiffness_n_mm": 3.86,
//!    "reference_node": {"node": 338, "ux_mm": 0, "uy_mm": 0, "uz_mm": -2.59, "rx_rad": 0, ...},
//!    "loaded_dofs": [...], "reactions": [...], "shape_file": "case1_static.vtu"},
//!   {"name": "...", "kind": "modal", "total_mass_kg": 5.4,
//!    "modes": [{"mode": 1, "frequency_hz": 4.34, "period_s": 0.2304, "omega_rad_s": 27.3,
//!               "axial_effective_mass_kg": 5.2, "effective_mass_x_kg": ..., ...}]},
//!   {"name": "...", "kind": "transient", "method": "newmark", "dt_s": 0.001,
//!    "total_time_s": 20.0, "steps": 20000, "output_every": 1,
//!    "history_file": "history.csv", "columns": ["node1_uz_disp_m", ...],
//!    "initial_displacement_from": null, "initial_velocity_field": "quasi-static",
//!    "modal": null, "warnings": []}]}
//! ```
//! A transient's `method` is `newmark`, `hht` (with `hht_alpha`), `galpha` (with
//! `rho_inf`) or `modal` (with `modes`, and a `modal` object: each retained mode's
//! frequency and damping ratios, the largest damping coupling neglected, what the basis
//! captures of the initial state and loads; see
//! [`crate::analysis::transient::ModalSummary`]).
//!
//! # History files
//! The first transient load case writes `DIR/history.csv`; any further transient case
//! writes `DIR/caseN_history.csv`, N its 1-based load case number. Header `time_s`, then
//! one column per signal named `node{ID}_{dof}_{quantity}_{unit}` in SI units (see
//! [`crate::analysis::transient`]); `coil-post` reads it directly.
//! Units are in the names: the model's mm, N, N mm, rad for displacements and loads;
//! SI for masses (kg), frequencies (Hz) and periods (s), converted here from the model's
//! tonnes. `axial_effective_mass_kg` is the effective mass along global z, the spring
//! axis of coil's models. `stiffness_n_mm` is `null` when no single loaded DOF
//! identifies the reference node (see [`crate::analysis::static_analysis`]).
//!
//! Every file is written to a temporary file in the same directory and renamed, so a
//! failed run never leaves half a file.

use crate::analysis::transient::{ModalSummary, TransientSolution};
use crate::analysis::{CaseResult, CaseSolution, ModalSolution, StaticSolution};
use crate::dof::dof_name;
use crate::error::Error;
use crate::model::{units, Integrator, Model, NodeId, TransientMethod, DOFS_PER_NODE};
use crate::vtk;
use coil_io::OutputSet;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The whole `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultsFile {
    pub title: String,
    pub load_cases: Vec<CaseEntry>,
}

/// One load case, tagged by `"kind"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum CaseEntry {
    Static(StaticEntry),
    Modal(ModalEntry),
    Transient(TransientEntry),
}

/// Six displacements of a node (mm, rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NodeDisplacement {
    pub node: NodeId,
    pub ux_mm: f64,
    pub uy_mm: f64,
    pub uz_mm: f64,
    pub rx_rad: f64,
    pub ry_rad: f64,
    pub rz_rad: f64,
}

/// A loaded DOF: load (N or N mm), displacement (mm or rad), stiffness F/u.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoadedDofEntry {
    pub node: NodeId,
    pub dof: String,
    pub load: f64,
    pub displacement: f64,
    pub stiffness: Option<f64>,
    /// Unit of `stiffness`: "N/mm" or "N mm/rad".
    pub stiffness_unit: String,
}

/// A reaction at a prescribed DOF.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReactionEntry {
    pub node: NodeId,
    pub dof: String,
    pub value: f64,
    /// "N" or "N mm".
    pub unit: String,
}

/// A static load case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticEntry {
    pub name: String,
    pub stiffness_n_mm: Option<f64>,
    pub reference_node: Option<NodeDisplacement>,
    pub loaded_dofs: Vec<LoadedDofEntry>,
    pub reactions: Vec<ReactionEntry>,
    /// Largest displacement magnitude over the nodes (mm).
    pub max_displacement_mm: f64,
    /// Equilibrium check of the solve, `|T^T (K u - f)| / |T^T f|`.
    pub relative_residual: f64,
    pub shape_file: String,
}

/// One mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeEntry {
    pub mode: usize,
    pub frequency_hz: f64,
    pub period_s: f64,
    pub omega_rad_s: f64,
    /// Effective modal mass along global z, the spring axis (kg).
    pub axial_effective_mass_kg: f64,
    pub effective_mass_x_kg: f64,
    pub effective_mass_y_kg: f64,
    pub effective_mass_z_kg: f64,
    /// `|K phi - omega^2 M phi| / |K phi|`.
    pub relative_residual: f64,
    pub shape_file: String,
}

/// A modal load case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalEntry {
    pub name: String,
    /// Total translational mass of the model, supports included (kg).
    pub total_mass_kg: f64,
    /// `max |phi_i^T M phi_j - delta_ij|` of the mass-normalised modes.
    pub orthonormality_error: f64,
    pub modes: Vec<ModeEntry>,
}

/// One mode of a modal superposition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalTermEntry {
    pub mode: usize,
    pub frequency_hz: f64,
    /// `phi^T C phi / (2 w)`, the ratio the mode is integrated with.
    pub zeta: f64,
    /// The ratio with the full modal damping matrix of the retained modes.
    pub zeta_coupled: Option<f64>,
    pub axial_effective_mass_kg: f64,
}

/// What a modal superposition kept and left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalSummaryEntry {
    pub modes: Vec<ModalTermEntry>,
    /// Largest `|c_ij| / sqrt(c_ii c_jj)` of `Phi^T C Phi`, `i != j`.
    pub max_damping_coupling: f64,
    /// The two modes of that coupling (1-based).
    pub coupling_pair: Option<(usize, usize)>,
    /// Largest `|zeta_coupled / zeta - 1|`.
    pub max_zeta_shift: Option<f64>,
    /// Fraction of the initial strain energy in the retained modes.
    pub initial_displacement_captured: Option<f64>,
    /// Fraction of the initial kinetic energy in the retained modes.
    pub initial_velocity_captured: Option<f64>,
    /// Smallest fraction of a load pattern's static compliance in the retained modes.
    pub load_captured: Option<f64>,
}

/// A transient load case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransientEntry {
    pub name: String,
    /// `newmark`, `hht`, `galpha` or `modal`.
    pub method: String,
    pub hht_alpha: Option<f64>,
    pub rho_inf: Option<f64>,
    pub modes: Option<u32>,
    pub dt_s: f64,
    pub total_time_s: f64,
    pub steps: usize,
    pub output_every: usize,
    pub history_file: String,
    pub columns: Vec<String>,
    /// The static load case the initial displacement comes from.
    pub initial_displacement_from: Option<String>,
    /// `rest`, `nodal`, `quasi-static` or `quasi-static + nodal`.
    pub initial_velocity_field: String,
    pub modal: Option<ModalSummaryEntry>,
    pub warnings: Vec<String>,
}

/// Stages `text` as `name` in `set` unless it holds a non-finite number.
fn stage(set: &OutputSet, name: &str, text: &str) -> Result<(), Error> {
    if let Some(at) = coil_io::non_finite_token(text) {
        return Err(Error::NonFinite {
            file: name.to_string(),
            at,
        });
    }
    set.write(Path::new(name), text.as_bytes())?;
    Ok(())
}

fn node_displacement(model: &Model, u: &[f64], node: NodeId) -> Option<NodeDisplacement> {
    let i = model.node_index(node)?;
    let d = &u[i * DOFS_PER_NODE..(i + 1) * DOFS_PER_NODE];
    Some(NodeDisplacement {
        node,
        ux_mm: d[0],
        uy_mm: d[1],
        uz_mm: d[2],
        rx_rad: d[3],
        ry_rad: d[4],
        rz_rad: d[5],
    })
}

fn static_entry(model: &Model, name: &str, s: &StaticSolution, shape_file: String) -> StaticEntry {
    let translational = |dof: u8| dof <= 3;
    StaticEntry {
        name: name.to_string(),
        stiffness_n_mm: s.stiffness_n_mm,
        reference_node: s
            .reference_node
            .and_then(|n| node_displacement(model, &s.displacement, n)),
        loaded_dofs: s
            .loaded
            .iter()
            .map(|l| LoadedDofEntry {
                node: l.node,
                dof: dof_name(l.dof).to_string(),
                load: l.load,
                displacement: l.displacement,
                stiffness: l.stiffness,
                stiffness_unit: if translational(l.dof) {
                    "N/mm"
                } else {
                    "N mm/rad"
                }
                .to_string(),
            })
            .collect(),
        reactions: s
            .reactions
            .iter()
            .map(|r| ReactionEntry {
                node: r.node,
                dof: dof_name(r.dof).to_string(),
                value: r.value,
                unit: if translational(r.dof) { "N" } else { "N mm" }.to_string(),
            })
            .collect(),
        max_displacement_mm: s
            .displacement
            .chunks(DOFS_PER_NODE)
            .map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
            .fold(0.0, f64::max),
        relative_residual: s.relative_residual,
        shape_file,
    }
}

fn modal_entry(name: &str, m: &ModalSolution, shape_file: impl Fn(usize) -> String) -> ModalEntry {
    let kg = units::mass_to_si;
    ModalEntry {
        name: name.to_string(),
        total_mass_kg: kg(m.total_mass[2]),
        orthonormality_error: m.orthonormality_error,
        modes: m
            .modes
            .iter()
            .enumerate()
            .map(|(k, mode)| ModeEntry {
                mode: k + 1,
                frequency_hz: mode.frequency_hz,
                period_s: mode.period_s,
                omega_rad_s: mode.omega_squared.sqrt(),
                axial_effective_mass_kg: kg(mode.effective_mass[2]),
                effective_mass_x_kg: kg(mode.effective_mass[0]),
                effective_mass_y_kg: kg(mode.effective_mass[1]),
                effective_mass_z_kg: kg(mode.effective_mass[2]),
                relative_residual: mode.relative_residual,
                shape_file: shape_file(k + 1),
            })
            .collect(),
    }
}

fn modal_summary_entry(m: &ModalSummary) -> ModalSummaryEntry {
    ModalSummaryEntry {
        modes: m
            .modes
            .iter()
            .enumerate()
            .map(|(k, t)| ModalTermEntry {
                mode: k + 1,
                frequency_hz: t.frequency_hz,
                zeta: t.zeta,
                zeta_coupled: t.zeta_coupled,
                axial_effective_mass_kg: units::mass_to_si(t.axial_effective_mass),
            })
            .collect(),
        max_damping_coupling: m.max_damping_coupling,
        coupling_pair: m.coupling_pair,
        max_zeta_shift: m.max_zeta_shift,
        initial_displacement_captured: m.initial_displacement_captured,
        initial_velocity_captured: m.initial_velocity_captured,
        load_captured: m.load_captured,
    }
}

fn transient_entry(name: &str, t: &TransientSolution, history_file: String) -> TransientEntry {
    let (method, hht_alpha, rho_inf, modes) = match t.method {
        TransientMethod::Direct(Integrator::AverageAcceleration) => ("newmark", None, None, None),
        TransientMethod::Direct(Integrator::Hht { alpha }) => ("hht", Some(alpha), None, None),
        TransientMethod::Direct(Integrator::GeneralizedAlpha { rho_inf }) => {
            ("galpha", None, Some(rho_inf), None)
        }
        TransientMethod::Modal { modes } => ("modal", None, None, Some(modes)),
    };
    TransientEntry {
        name: name.to_string(),
        method: method.to_string(),
        hht_alpha,
        rho_inf,
        modes,
        dt_s: t.dt_s,
        total_time_s: t.total_time_s,
        steps: t.steps,
        output_every: t.output_every,
        history_file,
        columns: t.history.names(),
        initial_displacement_from: t.initial_displacement_from.clone(),
        initial_velocity_field: t.velocity_field.name().to_string(),
        modal: t.modal.as_ref().map(modal_summary_entry),
        warnings: t.warnings.clone(),
    }
}

/// The history file of load case `case_number` (1-based): `history.csv` for the first
/// transient case, `caseN_history.csv` for any later one.
pub fn history_file_name(first_transient: bool, case_number: usize) -> String {
    if first_transient {
        "history.csv".to_string()
    } else {
        format!("case{case_number}_history.csv")
    }
}

/// Builds the `results.json` content and writes every file of a run into `dir` (created
/// if missing) as one set: locked, staged, moved in together ([`coil_io::set`]).
pub fn write_all(dir: &Path, model: &Model, cases: &[CaseResult]) -> Result<ResultsFile, Error> {
    let set = OutputSet::open(dir, "coil-solve (results)")?;
    let file = write_set(&set, model, cases)?;
    set.commit()?;
    Ok(file)
}

/// Stages every file of a run in `set` (the caller commits). A non-finite number in any
/// of them is an error ([`Error::NonFinite`]) and nothing is written.
pub fn write_set(
    set: &OutputSet,
    model: &Model,
    cases: &[CaseResult],
) -> Result<ResultsFile, Error> {
    stage(set, "model.vtu", &vtk::unstructured_grid(model, None))?;
    let mut entries = Vec::with_capacity(cases.len());
    let mut first_transient = true;
    for (index, case) in cases.iter().enumerate() {
        let c = index + 1;
        match &case.solution {
            CaseSolution::Static(s) => {
                let file = format!("case{c}_static.vtu");
                stage(
                    set,
                    &file,
                    &vtk::unstructured_grid(model, Some(&s.displacement)),
                )?;
                entries.push(CaseEntry::Static(static_entry(model, &case.title, s, file)));
            }
            CaseSolution::Modal(m) => {
                let width = m.modes.len().to_string().len();
                let name = |k: usize| format!("case{c}_mode{k:0width$}.vtu");
                for (k, mode) in m.modes.iter().enumerate() {
                    stage(
                        set,
                        &name(k + 1),
                        &vtk::unstructured_grid(model, Some(&mode.shape)),
                    )?;
                }
                entries.push(CaseEntry::Modal(modal_entry(&case.title, m, name)));
            }
            CaseSolution::Transient(t) => {
                let file = history_file_name(first_transient, c);
                first_transient = false;
                stage(set, &file, &t.history.to_csv())?;
                entries.push(CaseEntry::Transient(transient_entry(&case.title, t, file)));
            }
        }
    }
    let file = ResultsFile {
        title: model.title.clone(),
        load_cases: entries,
    };
    // serde_json writes a non-finite float as null: check the numbers themselves.
    if let Some(at) = coil_io::non_finite_token(&format!("{file:?}")) {
        return Err(Error::NonFinite {
            file: "results.json".into(),
            at,
        });
    }
    let json = serde_json::to_string_pretty(&file).map_err(|e| Error::Io {
        path: set.destination(Path::new("results.json")),
        source: std::io::Error::other(e),
    })?;
    stage(set, "results.json", &json)?;
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::test_support::tied_frame;
    use crate::model::{Analysis, LoadCase, PointLoad};

    #[test]
    fn writes_results_and_shapes_atomically() {
        let mut model = tied_frame();
        model.point_loads.push(PointLoad {
            dofs: vec![(2, 5.0)],
            nodes: vec![3],
            table: None,
        });
        model.load_cases.push(LoadCase {
            title: "push".to_string(),
            analysis: Analysis::Static {
                steps: 1,
                time: 1.0,
            },
            point_loads: Vec::new(),
        });
        model.load_cases.push(LoadCase {
            title: "modes".to_string(),
            analysis: Analysis::Modal { modes: 3 },
            point_loads: Vec::new(),
        });
        let cases = crate::analysis::run(&model).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let written = write_all(dir.path(), &model, &cases).unwrap();
        let text = std::fs::read_to_string(dir.path().join("results.json")).unwrap();
        let read: ResultsFile = serde_json::from_str(&text).unwrap();
        assert_eq!(read.load_cases.len(), written.load_cases.len());
        let (CaseEntry::Static(r), CaseEntry::Static(w)) =
            (&read.load_cases[0], &written.load_cases[0])
        else {
            panic!("static first")
        };
        assert_eq!(r.reactions.len(), w.reactions.len());
        let k = (r.stiffness_n_mm.unwrap(), w.stiffness_n_mm.unwrap());
        // serde_json's default float parsing may differ in the last bit.
        assert!((k.0 - k.1).abs() <= 1e-15 * k.1);
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(value["load_cases"][0]["kind"], "static");
        assert_eq!(value["load_cases"][0]["name"], "push");
        assert_eq!(value["load_cases"][1]["kind"], "modal");
        let modes = value["load_cases"][1]["modes"].as_array().unwrap();
        assert_eq!(modes.len(), 3);
        assert!(modes[0]["frequency_hz"].as_f64().unwrap() > 0.0);
        assert!(modes[0]["axial_effective_mass_kg"].as_f64().is_some());
        for f in [
            "model.vtu",
            "case1_static.vtu",
            "case2_mode1.vtu",
            "case2_mode3.vtu",
        ] {
            assert!(dir.path().join(f).is_file(), "{f}");
        }
        // No temporaries left behind.
        let leftovers = std::fs::read_dir(dir.path())
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            })
            .count();
        assert_eq!(leftovers, 0);
    }
}
