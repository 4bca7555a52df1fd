//! Result files of a run: `DIR/results.json`, `DIR/model.vtu`, one `.vtu` per static
//! displaced shape (with section forces and wire stresses as cell data) and per mode
//! shape, a `.pvd` series of each modal case's shapes (frequency in Hz as the series
//! value, so ParaView steps through the modes), and one history CSV per transient load
//! case; when that history records every node's displacement (a `HISTORY OUTPUT` of the
//! whole model at a stride), also a `.pvd` series of the moving model ([`transient_series`]).
//!
//! # results.json
//! ```json
//! {"title": "...", "load_cases": [
//!   {"name": "...", "kind": "static", "stiffness_n_mm": 3.86,
//!    "reference_node": {"node": 338, "ux_mm": 0, "uy_mm": 0, "uz_mm": -2.59, "rx_rad": 0, ...},
//!    "loaded_dofs": [...], "reactions": [...], "shape_file": "case1_static.vtu",
//!    "wire_stress": {"max_shear_stress_mpa": 25.3, "torsion_stress_mpa": 23.9,
//!                    "direct_shear_stress_mpa": 1.41, "element": 36, "at_mm": [...], ...},
//!    "spring": {"spring_index": 8.0, "solid_length_mm": 45.0, "coil_contact_load_n": 162.0,
//!               "nominal_stress_mpa": 22.6, "wahl_stress_mpa": 26.8, ...},
//!    "warnings": [], "section_forces": [{"element": 1, "axial_force_n": [n1, n2],
//!               "torque_n_mm": [...], "shear_stress_mpa": 23.9, ...}, ...]},
//!   {"name": "...", "kind": "modal", "total_mass_kg": 5.4,
//!    "series_file": "case2_modes.pvd",
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
//! Section forces, wire stresses and the spring summary (index, solid length, handbook
//! stresses with Wahl's and Bergsträsser's factors, the load at which adjacent coils
//! touch, a warning when the load case passes it) are defined in [`crate::wire`].
//!
//! Every file is written to a temporary file in the same directory and renamed, so a
//! failed run never leaves half a file.

use crate::analysis::transient::{ModalCapture, ModalSummary, TransientSolution};
use crate::analysis::{CaseResult, CaseSolution, ModalSolution, StaticSolution};
use crate::dof::dof_name;
use crate::error::Error;
use crate::model::{units, Integrator, Model, NodeId, TransientMethod, DOFS_PER_NODE};
use crate::{vtk, wire};
use coil_io::OutputSet;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The whole `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultsFile {
    /// The model's title.
    pub title: String,
    /// One entry per load case, in deck order.
    pub load_cases: Vec<CaseEntry>,
}

/// One load case, tagged by `"kind"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum CaseEntry {
    /// A static load case.
    Static(StaticEntry),
    /// A modal load case.
    Modal(ModalEntry),
    /// A transient load case.
    Transient(TransientEntry),
}

/// Six displacements of a node (mm, rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NodeDisplacement {
    /// The node's id.
    pub node: NodeId,
    /// Displacement along global x (mm).
    pub ux_mm: f64,
    /// Displacement along global y (mm).
    pub uy_mm: f64,
    /// Displacement along global z (mm).
    pub uz_mm: f64,
    /// Rotation about global x (rad).
    pub rx_rad: f64,
    /// Rotation about global y (rad).
    pub ry_rad: f64,
    /// Rotation about global z (rad).
    pub rz_rad: f64,
}

/// A loaded DOF: load (N or N mm), displacement (mm or rad), stiffness F/u.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoadedDofEntry {
    /// The node's id.
    pub node: NodeId,
    /// The DOF's name (`ux`, `uy`, `uz`, `rx`, `ry` or `rz`).
    pub dof: String,
    /// The applied load (N, or N mm on a rotation).
    pub load: f64,
    /// The displacement there (mm, or rad on a rotation).
    pub displacement: f64,
    /// `load / displacement` (in `stiffness_unit`); `null` when the displacement is exactly zero.
    pub stiffness: Option<f64>,
    /// Unit of `stiffness`: "N/mm" or "N mm/rad".
    pub stiffness_unit: String,
}

/// A reaction at a prescribed DOF.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReactionEntry {
    /// The node's id.
    pub node: NodeId,
    /// The DOF's name (`ux`, `uy`, `uz`, `rx`, `ry` or `rz`).
    pub dof: String,
    /// The reaction force or moment (in `unit`).
    pub value: f64,
    /// "N" or "N mm".
    pub unit: String,
}

/// A static load case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticEntry {
    /// The load case's title.
    pub name: String,
    /// F/u at the reference node's loaded translational DOF (N/mm); `null` if none is identified.
    pub stiffness_n_mm: Option<f64>,
    /// The six displacements of the reference node, when one is identified.
    pub reference_node: Option<NodeDisplacement>,
    /// Every loaded DOF with its load, displacement and F/u.
    pub loaded_dofs: Vec<LoadedDofEntry>,
    /// The reactions at the prescribed DOFs.
    pub reactions: Vec<ReactionEntry>,
    /// Largest displacement magnitude over the nodes (mm).
    pub max_displacement_mm: f64,
    /// Equilibrium check of the solve, `|T^T (K u - f)| / |T^T f|`.
    pub relative_residual: f64,
    /// The displaced shape's `.vtu` file (`caseN_static.vtu`), in the results directory.
    pub shape_file: String,
    /// The largest wire stress and where it sits (solid circular wires only).
    #[serde(default)]
    pub wire_stress: Option<WireStressEntry>,
    /// Spring index, solid length, handbook stresses and the coil contact load, when
    /// the wire is one helix about global z (see [`crate::wire`]).
    #[serde(default)]
    pub spring: Option<SpringEntry>,
    /// Things the user should know (e.g. the load passes the coil contact load).
    #[serde(default)]
    pub warnings: Vec<String>,
    /// Section forces and stresses of every beam element.
    #[serde(default)]
    pub section_forces: Vec<SectionForceEntry>,
}

/// The element with the largest combined shear stress (MPa) and its stresses.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WireStressEntry {
    /// Torsion plus direct shear, the largest along the wire.
    pub max_shear_stress_mpa: f64,
    /// Torsional shear stress `16 T / (pi d^3)` there (MPa).
    pub torsion_stress_mpa: f64,
    /// Direct (transverse) shear stress there (MPa).
    pub direct_shear_stress_mpa: f64,
    /// Bending stress `32 M / (pi d^3)` there (MPa).
    pub bending_stress_mpa: f64,
    /// Axial stress `N / A` there (MPa).
    pub axial_stress_mpa: f64,
    /// The element's id.
    pub element: u32,
    /// Midpoint of that element (mm).
    pub at_mm: [f64; 3],
}

/// What a spring engineer reads off a static case (see [`crate::wire`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpringEntry {
    /// Number of coils of the modelled helix.
    pub coils: f64,
    /// Mean coil diameter D (mm), fitted to the wire's nodes.
    pub mean_diameter_mm: f64,
    /// Wire diameter d (mm).
    pub wire_diameter_mm: f64,
    /// Axial rise per coil (mm).
    pub pitch_mm: f64,
    /// C = D / d.
    pub spring_index: f64,
    /// `(n + 1) d` of the modelled helix.
    pub solid_length_mm: f64,
    /// Axial force the wire carries (N).
    pub axial_force_n: f64,
    /// `8 F D / (pi d^3)`.
    pub nominal_stress_mpa: f64,
    /// Wahl's factor `(4C - 1)/(4C - 4) + 0.615/C`.
    pub wahl_factor: f64,
    /// `wahl_factor * nominal_stress_mpa` (MPa).
    pub wahl_stress_mpa: f64,
    /// Bergsträsser's factor `(4C + 2)/(4C - 3)`.
    pub bergstraesser_factor: f64,
    /// `bergstraesser_factor * nominal_stress_mpa` (MPa).
    pub bergstraesser_stress_mpa: f64,
    /// The axial force at which adjacent coils first touch (N); `null` when the load
    /// case opens the coils.
    pub coil_contact_load_n: Option<f64>,
    /// The node where they touch first (the lower of the two coils).
    pub coil_contact_node: Option<NodeId>,
}

/// Section resultants of one beam at its two ends `[node 1, node 2]` in the element's
/// local axes (see [`crate::wire`]), and its wire stresses (MPa).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionForceEntry {
    /// The element's id.
    pub element: u32,
    /// Axial force N at the two ends (N).
    pub axial_force_n: [f64; 2],
    /// Shear force V_y along local y at the two ends (N).
    pub shear_force_y_n: [f64; 2],
    /// Shear force V_z along local z at the two ends (N).
    pub shear_force_z_n: [f64; 2],
    /// Torque T about the local x (wire) axis at the two ends (N mm).
    pub torque_n_mm: [f64; 2],
    /// Bending moment M_y about local y at the two ends (N mm).
    pub moment_y_n_mm: [f64; 2],
    /// Bending moment M_z about local z at the two ends (N mm).
    pub moment_z_n_mm: [f64; 2],
    /// Torsional shear stress `16 T / (pi d^3)`, larger end (MPa); `null` unless a solid circle.
    pub torsion_stress_mpa: Option<f64>,
    /// Direct (transverse) shear stress, larger end (MPa); `null` unless a solid circle.
    pub direct_shear_stress_mpa: Option<f64>,
    /// Torsion plus direct shear stress, larger end (MPa); `null` unless a solid circle.
    pub shear_stress_mpa: Option<f64>,
    /// Bending stress `32 M / (pi d^3)`, larger end (MPa); `null` unless a solid circle.
    pub bending_stress_mpa: Option<f64>,
}

/// One mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeEntry {
    /// The mode's number, 1-based by ascending frequency.
    pub mode: usize,
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Natural period `1 / frequency_hz` (s).
    pub period_s: f64,
    /// Circular natural frequency (rad/s).
    pub omega_rad_s: f64,
    /// Effective modal mass along global z, the spring axis (kg).
    pub axial_effective_mass_kg: f64,
    /// Effective modal mass along global x (kg).
    pub effective_mass_x_kg: f64,
    /// Effective modal mass along global y (kg).
    pub effective_mass_y_kg: f64,
    /// Effective modal mass along global z (kg).
    pub effective_mass_z_kg: f64,
    /// `|K phi - omega^2 M phi| / |K phi|`.
    pub relative_residual: f64,
    /// The mode shape's `.vtu` file (`caseN_modeK.vtu`), in the results directory.
    pub shape_file: String,
}

/// A modal load case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalEntry {
    /// The load case's title.
    pub name: String,
    /// Total translational mass of the model, supports included (kg).
    pub total_mass_kg: f64,
    /// `max |phi_i^T M phi_j - delta_ij|` of the mass-normalised modes.
    pub orthonormality_error: f64,
    /// The modes found, by ascending frequency.
    pub modes: Vec<ModeEntry>,
    /// ParaView collection of the mode shapes, frequency (Hz) as the series value.
    #[serde(default)]
    pub series_file: String,
}

/// One mode of a modal superposition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalTermEntry {
    /// The mode's number, 1-based.
    pub mode: usize,
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// `phi^T C phi / (2 w)`, the ratio the mode is integrated with.
    pub zeta: f64,
    /// The ratio with the full modal damping matrix of the retained modes.
    pub zeta_coupled: Option<f64>,
    /// Effective modal mass along global z, the spring axis (kg).
    pub axial_effective_mass_kg: f64,
}

/// What a modal superposition kept and left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalSummaryEntry {
    /// The retained modes.
    pub modes: Vec<ModalTermEntry>,
    /// The damping coupling neglected and the fractions captured (flattened: the same
    /// keys as before in results.json).
    #[serde(flatten)]
    pub capture: ModalCapture,
}

/// A transient load case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransientEntry {
    /// The load case's title.
    pub name: String,
    /// `newmark`, `hht`, `galpha` or `modal`.
    pub method: String,
    /// HHT's alpha (`hht` only).
    pub hht_alpha: Option<f64>,
    /// Generalised-alpha's spectral radius at infinite frequency (`galpha` only).
    pub rho_inf: Option<f64>,
    /// Number of retained modes (`modal` only).
    pub modes: Option<u32>,
    /// The time step (s).
    pub dt_s: f64,
    /// The end time, `steps * dt_s` (s).
    pub total_time_s: f64,
    /// Number of time steps.
    pub steps: usize,
    /// Steps between recorded history samples.
    pub output_every: usize,
    /// The history CSV (`history.csv` or `caseN_history.csv`), in the results directory.
    pub history_file: String,
    /// The history's column names after `time_s` (SI units in the names).
    pub columns: Vec<String>,
    /// The static load case the initial displacement comes from.
    pub initial_displacement_from: Option<String>,
    /// `rest`, `nodal`, `quasi-static` or `quasi-static + nodal`.
    pub initial_velocity_field: String,
    /// What the modal superposition kept and left out (`modal` only).
    pub modal: Option<ModalSummaryEntry>,
    /// Things the user should know (off-grid table breakpoints, a rounded end time, ...).
    pub warnings: Vec<String>,
    /// ParaView collection of the whole model's displaced shape over time (time in s as
    /// the series value), written when the history records the displacement of every
    /// node along x, y and z (see [`transient_series`]).
    #[serde(default)]
    pub series_file: Option<String>,
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

/// Stages a `.vtu`: an ASCII one is checked like any text ([`stage`]); a binary one
/// (appended raw data) is written as it is (the VTK writer writes no non-finite number:
/// see [`crate::vtk`]).
fn stage_vtu(set: &OutputSet, name: &str, bytes: &[u8]) -> Result<(), Error> {
    match std::str::from_utf8(bytes) {
        Ok(text) => stage(set, name, text),
        Err(_) => {
            set.write(Path::new(name), bytes)?;
            Ok(())
        }
    }
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

/// The spring summary, the wire's stress peak and their warnings for a static case.
fn spring_results(
    model: &Model,
    s: &StaticSolution,
    forces: &[wire::ElementForces],
) -> (Option<WireStressEntry>, Option<SpringEntry>, Vec<String>) {
    let mut warnings = Vec::new();
    let stress = wire::peak(model, forces).map(|p| WireStressEntry {
        max_shear_stress_mpa: p.stress.shear_mpa,
        torsion_stress_mpa: p.stress.torsion_mpa,
        direct_shear_stress_mpa: p.stress.direct_shear_mpa,
        bending_stress_mpa: p.stress.bending_mpa,
        axial_stress_mpa: p.stress.axial_mpa,
        element: p.element,
        at_mm: p.xyz,
    });
    let spring = wire::Helix::of(model).map(|helix| {
        let force = forces
            .get(forces.len() / 2)
            .map_or(0.0, |f| f.force_global_n[2].abs());
        let (d_mean, d) = (helix.mean_diameter_mm, helix.wire_diameter_mm);
        let c = helix.index();
        let nominal = wire::nominal_stress_mpa(force, d_mean, d);
        let contact = helix
            .contact_factor(model, &s.displacement)
            .filter(|_| force > 0.0);
        if let Some((factor, node)) = contact {
            if factor < 1.0 {
                warnings.push(format!(
                    "the axial load {force:.4} N passes the load at which adjacent coils touch \
                     ({:.4} N, first at node {}): beyond it the coils are solid and this linear \
                     model does not apply",
                    factor * force,
                    model.nodes[node].id
                ));
            }
        }
        SpringEntry {
            coils: helix.coils,
            mean_diameter_mm: d_mean,
            wire_diameter_mm: d,
            pitch_mm: helix.pitch_mm,
            spring_index: c,
            solid_length_mm: helix.solid_length_mm(),
            axial_force_n: force,
            nominal_stress_mpa: nominal,
            wahl_factor: wire::wahl_factor(c),
            wahl_stress_mpa: wire::wahl_factor(c) * nominal,
            bergstraesser_factor: wire::bergstraesser_factor(c),
            bergstraesser_stress_mpa: wire::bergstraesser_factor(c) * nominal,
            coil_contact_load_n: contact.map(|(factor, _)| factor * force),
            coil_contact_node: contact.map(|(_, node)| model.nodes[node].id),
        }
    });
    (stress, spring, warnings)
}

fn section_force_entry(f: &wire::ElementForces) -> SectionForceEntry {
    let pair = |c: usize| [f.ends[0][c], f.ends[1][c]];
    SectionForceEntry {
        element: f.element,
        axial_force_n: pair(0),
        shear_force_y_n: pair(1),
        shear_force_z_n: pair(2),
        torque_n_mm: pair(3),
        moment_y_n_mm: pair(4),
        moment_z_n_mm: pair(5),
        torsion_stress_mpa: f.stress.map(|s| s.torsion_mpa),
        direct_shear_stress_mpa: f.stress.map(|s| s.direct_shear_mpa),
        shear_stress_mpa: f.stress.map(|s| s.shear_mpa),
        bending_stress_mpa: f.stress.map(|s| s.bending_mpa),
    }
}

/// The section forces and stresses as VTU cell arrays, in `model.elements` order.
pub fn cell_fields(model: &Model, forces: &[wire::ElementForces]) -> Vec<vtk::CellField> {
    type Getter = fn(&wire::ElementForces) -> f64;
    let fields: [(&str, Getter); 8] = [
        ("axial_force_n", |f| f.ends[1][0]),
        ("shear_force_n", |f| f.shear_force_n()),
        ("torque_n_mm", |f| f.ends[1][3]),
        ("bending_moment_n_mm", |f| f.bending_moment_n_mm()),
        ("torsion_stress_mpa", |f| {
            f.stress.map_or(0.0, |s| s.torsion_mpa)
        }),
        ("direct_shear_stress_mpa", |f| {
            f.stress.map_or(0.0, |s| s.direct_shear_mpa)
        }),
        ("shear_stress_mpa", |f| {
            f.stress.map_or(0.0, |s| s.shear_mpa)
        }),
        ("bending_stress_mpa", |f| {
            f.stress.map_or(0.0, |s| s.bending_mpa)
        }),
    ];
    let by_id: std::collections::HashMap<u32, &wire::ElementForces> =
        forces.iter().map(|f| (f.element, f)).collect();
    fields
        .iter()
        .map(|(name, get)| vtk::CellField {
            name: (*name).to_string(),
            components: 1,
            values: model
                .elements
                .iter()
                .map(|e| by_id.get(&e.id).map_or(0.0, |f| get(f)))
                .collect(),
        })
        .collect()
}

fn static_entry(
    model: &Model,
    name: &str,
    s: &StaticSolution,
    forces: &[wire::ElementForces],
    shape_file: String,
) -> StaticEntry {
    let translational = |dof: u8| dof <= 3;
    let (wire_stress, spring, warnings) = spring_results(model, s, forces);
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
        wire_stress,
        spring,
        warnings,
        section_forces: forces.iter().map(section_force_entry).collect(),
    }
}

fn modal_entry(
    name: &str,
    m: &ModalSolution,
    shape_file: impl Fn(usize) -> String,
    series_file: String,
) -> ModalEntry {
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
        series_file,
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
        capture: m.capture.clone(),
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
        series_file: None,
    }
}

/// Most snapshots a transient series holds; a longer history is thinned evenly.
pub const MAX_SNAPSHOTS: usize = 1000;

/// The whole model's displaced shapes of a transient, one full DOF vector (mm, rad) per
/// kept sample with its time (s), when the history holds `node{ID}_{ux,uy,uz}_disp_m`
/// of every node (a `HISTORY OUTPUT` of DISP, DOFs 1 to 3, on all nodes, at the stride
/// wanted: the "whole model" request). Rotations are taken when recorded (DOFs 4 to 6),
/// else left zero. `None` when some node's translation is not recorded. The samples are
/// those of the whole-model request's own stride (the history holds every sample any
/// request asked for), thinned further to at most [`MAX_SNAPSHOTS`].
pub fn transient_series(model: &Model, t: &TransientSolution) -> Option<Vec<(f64, Vec<f64>)>> {
    let history = &t.history;
    let rows = history.time_s.len();
    if rows == 0 || model.nodes.is_empty() {
        return None;
    }
    let mut columns: Vec<(usize, f64, &[f64])> = Vec::with_capacity(6 * model.nodes.len());
    for (i, node) in model.nodes.iter().enumerate() {
        for (dof, name) in ["ux", "uy", "uz", "rx", "ry", "rz"].iter().enumerate() {
            let (suffix, scale) = if dof < 3 {
                ("disp_m", units::MM_PER_M)
            } else {
                ("disp_rad", 1.0)
            };
            match history.column(&format!("node{}_{name}_{suffix}", node.id)) {
                Some(values) => columns.push((i * DOFS_PER_NODE + dof, scale, values)),
                None if dof < 3 => return None,
                None => {}
            }
        }
    }
    let all_nodes = model
        .outputs
        .iter()
        .filter(|o| {
            o.quantities.contains(&crate::model::Quantity::Displacement)
                && [1, 2, 3].iter().all(|d| o.dofs.contains(d))
                && o.nodes.len() >= model.nodes.len()
        })
        .map(|o| o.every as usize)
        .max()
        .unwrap_or(1);
    let request = (all_nodes / t.output_every.max(1)).max(1);
    let stride = request.max(rows.div_ceil(MAX_SNAPSHOTS)).max(1);
    Some(
        (0..rows)
            .step_by(stride)
            .map(|r| {
                let mut u = vec![0.0; model.dof_count()];
                for &(slot, scale, values) in &columns {
                    u[slot] = values[r] * scale;
                }
                (history.time_s[r], u)
            })
            .collect(),
    )
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

/// Stages each transient case's history as UFF datasets 58 beside its CSV
/// (`history.uff`, `case3_history.uff`: the CSV's name with `.uff`), one dataset per
/// column: `node{ID}_{dof}_{quantity}_{unit}` gives the response node, the direction
/// (ux..rz as 1..6) and the data type (disp 8, vel 11, accel 12), in the column's SI
/// unit. Returns the staged names. Call it after [`write_set`], whose CSV staging has
/// refused any non-finite value.
pub fn stage_history_uff(
    set: &OutputSet,
    cases: &[CaseResult],
    form: coil_io::uff::UffForm,
) -> Result<Vec<String>, Error> {
    let mut names = Vec::new();
    let mut first_transient = true;
    for (index, case) in cases.iter().enumerate() {
        let CaseSolution::Transient(t) = &case.solution else {
            continue;
        };
        let csv = history_file_name(first_transient, index + 1);
        first_transient = false;
        let name = csv.replace(".csv", ".uff");
        let h = &t.history;
        let n = h.time_s.len();
        let step_s = if n > 1 {
            (h.time_s[n - 1] - h.time_s[0]) / (n - 1) as f64
        } else {
            0.0
        };
        let mut datasets = Vec::with_capacity(h.columns.len());
        for c in &h.columns {
            datasets.push(history_dataset(
                &case.title,
                c,
                h.time_s.first().copied(),
                step_s,
            ));
        }
        set.write(
            Path::new(&name),
            &coil_io::uff::uff58_bytes(&datasets, form == coil_io::uff::UffForm::Binary),
        )?;
        names.push(name);
    }
    Ok(names)
}

/// One history column as a dataset 58 (see [`stage_history_uff`]).
fn history_dataset(
    title: &str,
    c: &crate::analysis::transient::HistoryColumn,
    start_s: Option<f64>,
    step_s: f64,
) -> coil_io::uff::Uff58 {
    let mut parts = c.name.splitn(4, '_');
    let node = parts
        .next()
        .and_then(|p| p.strip_prefix("node"))
        .and_then(|id| id.parse().ok())
        .unwrap_or(0);
    let direction = match parts.next() {
        Some("ux") => 1,
        Some("uy") => 2,
        Some("uz") => 3,
        Some("rx") => 4,
        Some("ry") => 5,
        Some("rz") => 6,
        _ => 0,
    };
    let quantity = parts.next().unwrap_or("");
    let unit = parts
        .next()
        .unwrap_or("")
        .replace("_s2", "/s^2")
        .replace("_s", "/s");
    let (ordinate_type, length_exponent) = coil_io::uff::Uff58::ordinate_kind(quantity);
    let length_exponent = if direction > 3 { 0 } else { length_exponent };
    coil_io::uff::Uff58 {
        description: format!("coil-solve: {title}"),
        name: c.name.clone(),
        node,
        direction,
        ordinate_type,
        length_exponent,
        ordinate_label: quantity.to_string(),
        ordinate_unit: unit,
        start_s: start_s.unwrap_or(0.0),
        step_s,
        values: c.values.clone(),
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
    stage_vtu(set, "model.vtu", &vtk::unstructured_grid(model, None))?;
    let mut entries = Vec::with_capacity(cases.len());
    let mut first_transient = true;
    for (index, case) in cases.iter().enumerate() {
        let c = index + 1;
        match &case.solution {
            CaseSolution::Static(s) => {
                let file = format!("case{c}_static.vtu");
                let forces = wire::element_forces(model, &s.displacement);
                stage_vtu(
                    set,
                    &file,
                    &vtk::grid(model, Some(&s.displacement), &cell_fields(model, &forces)),
                )?;
                entries.push(CaseEntry::Static(static_entry(
                    model,
                    &case.title,
                    s,
                    &forces,
                    file,
                )));
            }
            CaseSolution::Modal(m) => {
                let width = m.modes.len().to_string().len();
                let name = |k: usize| format!("case{c}_mode{k:0width$}.vtu");
                let mut series = Vec::with_capacity(m.modes.len());
                for (k, mode) in m.modes.iter().enumerate() {
                    stage_vtu(
                        set,
                        &name(k + 1),
                        &vtk::unstructured_grid(model, Some(&mode.shape)),
                    )?;
                    series.push((mode.frequency_hz, name(k + 1)));
                }
                let series_file = format!("case{c}_modes.pvd");
                stage(set, &series_file, &vtk::collection(&series))?;
                entries.push(CaseEntry::Modal(modal_entry(
                    &case.title,
                    m,
                    name,
                    series_file,
                )));
            }
            CaseSolution::Transient(t) => {
                let file = history_file_name(first_transient, c);
                first_transient = false;
                stage(set, &file, &t.history.to_csv())?;
                let mut entry = transient_entry(&case.title, t, file);
                if let Some(series) = transient_series(model, t) {
                    let width = series.len().to_string().len();
                    let mut listed = Vec::with_capacity(series.len());
                    for (k, (time, u)) in series.iter().enumerate() {
                        let name = format!("case{c}_t{k:0width$}.vtu");
                        stage_vtu(set, &name, &vtk::unstructured_grid(model, Some(u)))?;
                        listed.push((*time, name));
                    }
                    let series_file = format!("case{c}_transient.pvd");
                    stage(set, &series_file, &vtk::collection(&listed))?;
                    entry.series_file = Some(series_file);
                }
                entries.push(CaseEntry::Transient(entry));
            }
        }
    }
    let file = ResultsFile {
        title: model.title.clone(),
        load_cases: entries,
    };
    // serde_json writes a non-finite float as null: check the numbers themselves.
    let mut scan = coil_io::NonFiniteScan::default();
    // Writing into the scan cannot fail.
    let _ = std::fmt::Write::write_fmt(&mut scan, format_args!("{file:?}"));
    if let Some(at) = scan.finish() {
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
