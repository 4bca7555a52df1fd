//! The pantograph's head stage as coil's own spring model, reduced: four springs in
//! parallel between the frame end and the head end, Craig-Bampton reduced so that the
//! surge modes stay in, written as a `DMIG` matrix element (the solver's
//! `deck::cards::superelement`) for given node numbers. The lumped stage beside it
//! ([`super::springs`]) keeps only `K = 4 k` and a dashpot.
//!
//! # Formulation
//! - **One spring, both ends guided.** The calibrated spring ([`SpringState`], loops 1
//!   and 2) as the tuner meshes it, except that its base end is guided like its top
//!   (translations across and rotations held, the axial translation free). Boundary:
//!   the two ends' axial DOFs, `[frame u_z, head u_z]` (the base node and the weight's
//!   reference node). Its Craig-Bampton model ([`coil_solver::reduce`]) has, exactly in
//!   statics, the boundary stiffness `k [1, -1; -1, 1]` (a rigid axial translation is
//!   free), and the fixed-interface modes are those of the spring held at both ends,
//!   the head stage's surge modes among them.
//! - **Four in parallel.** Four identical springs on the same two boundary DOFs move
//!   alike when the boundary moves: every fixed-interface mode comes four times, and
//!   only the combination in which the four springs move together couples to the
//!   boundary (the other three are orthogonal to it in mass and stiffness and are never
//!   excited from the ends). The stage is therefore the one spring's reduced matrices
//!   times [`SPRINGS_IN_PARALLEL`], a modal coordinate standing for the four springs'
//!   common amplitude.
//! - **Which modes.** A fixed-interface mode acts on the ends through its coupling
//!   mass `L_j = M[eta_j, end]`; its share of the moving mass is `L_j^2` (a bar's
//!   surge modes: `2 m_s / (n pi)^2`, 1, 1/4, 1/9 of the first). Kept: every mode of
//!   one spring held at both ends below [`CUTOFF_HZ`] = 300 Hz, three times the top of
//!   the 0-100 Hz range the stage is compared over (a mode at `f_j` changes the
//!   response at `f` by about `(f / f_j)^2` of its share, so the first dropped surge
//!   mode, the third, near 380 Hz with a tenth of the first's share, changes the
//!   head's dynamic mass at 100 Hz by about 3e-8 t, 5e-6 of the 7.2 kg head), less the
//!   modes not coupled to the ends at all (share below [`UNCOUPLED`] of the largest).
//!   For the 160ECT that is 8 modes: the first two surge modes (129.8 and 260.0 Hz,
//!   the largest shares) and the coil's bending modes that the helix couples to the
//!   axis (109.6 Hz, 3.5 % of the first surge's share; 244.8 Hz, 5 %). The lowest held
//!   mode is such a coupled bending mode, not the surge; the surge is the mode with the
//!   largest share, the one [`super::springs`] reports. The statics stay exact
//!   whatever is dropped (the constraint modes carry them).
//! - **Damping.** Rayleigh on the spring's wire, `C = alpha M_wire + beta K`, the
//!   calibrated law's alpha and beta ([`super::springs::HeadStages::rayleigh_mid`]):
//!   the reduced `C` is the projection of the full one (the basis is fixed).
//!
//! Units: the deck's (mm, N, t, s). A modal coordinate is the amplitude of a
//! mass-normalised mode (sqrt(t) mm); in a deck it is DOF 1 of an extra node whose other
//! DOFs are held.

use super::springs::SPRINGS_IN_PARALLEL;
use crate::model::{StageMatrix, StageSpec};
use crate::{Result, TuneError};
use coil_mesher::{AnalysisKind, BASE_NODE, WEIGHT_NODE};
use coil_solver::deck::dmig_card;
use coil_solver::model::{MatrixElement, NodeId};
use coil_solver::reduce::{craig_bampton, generalized_eigenvalues};
use coil_tuner::fe::{FeSettings, SpringState};
use nalgebra::DMatrix;

/// Fixed-interface modes computed to find the surge modes among.
pub const CANDIDATE_MODES: usize = 40;
/// Fixed-interface modes below this frequency are kept (Hz; module doc).
pub const CUTOFF_HZ: f64 = 300.0;
/// A mode whose coupling share is below this fraction of the largest is not coupled to
/// the ends at all (a mode antisymmetric in the coil's plane: exactly zero up to
/// rounding) and is dropped.
pub const UNCOUPLED: f64 = 1e-6;

/// A reduced head stage: the dense matrices of four springs in parallel, in the
/// coordinates `[frame u_z, head u_z, eta_1, ..]` (module doc).
#[derive(Debug, Clone)]
pub struct ReducedStage {
    /// Stiffness (N/mm and N/(sqrt(t)) per modal unit).
    pub k: DMatrix<f64>,
    /// Mass (t).
    pub m: DMatrix<f64>,
    /// Rayleigh damping (N s/mm).
    pub c: DMatrix<f64>,
    /// Frequencies of the kept modes, both ends held (Hz, ascending).
    pub modes_hz: Vec<f64>,
    /// Each kept mode's coupling share `L_j^2` (t, per spring).
    pub coupling_t: Vec<f64>,
    /// The first surge mode: the held mode with the largest coupling share (Hz).
    pub surge_hz: f64,
    /// The largest coupling share among the modes dropped (t, per spring).
    pub largest_dropped_t: f64,
    /// One spring's wire mass (t) from the reduced mass's rigid translation.
    pub spring_mass_t: f64,
}

/// Index of the frame's axial DOF in the stage's coordinates.
pub const FRAME: usize = 0;
/// Index of the head's axial DOF in the stage's coordinates.
pub const HEAD: usize = 1;

fn reduce_err(context: &str) -> impl Fn(coil_solver::reduce::ReduceError) -> TuneError + '_ {
    move |e| TuneError::Missing {
        context: context.to_string(),
        what: e.to_string(),
    }
}

/// The reduced stage of four `state` springs (module doc), with Rayleigh `alpha` (1/s)
/// and `beta` (s) on the wire.
pub fn reduced_stage(
    state: &SpringState,
    fe: &FeSettings,
    alpha: f64,
    beta: f64,
) -> Result<ReducedStage> {
    let model = state.model(fe, &[AnalysisKind::Modal])?;
    let mut parts = model.into_parts();
    // The base guided instead of clamped: its axial translation is the frame's DOF.
    for f in &mut parts.fixed_disp {
        if f.nodes == [BASE_NODE] {
            f.dofs.retain(|&(d, _)| d != 3);
        }
    }
    parts.point_masses.clear();
    parts.load_cases.clear();
    parts.outputs.clear();
    parts.initial_velocities.clear();
    parts.damping.clear();
    let model = parts
        .build()
        .map_err(|e| TuneError::Invalid(format!("the guided spring: {e}")))?;
    let context = "reducing the head stage's spring";
    let boundary = [(BASE_NODE, 3), (WEIGHT_NODE, 3)];
    let red = craig_bampton(&model, &boundary, CANDIDATE_MODES).map_err(reduce_err(context))?;
    let ops = red
        .operators(1.0, &[0.0, 0.0], alpha, beta)
        .map_err(reduce_err(context))?;
    let m_all = &ops.m;
    let share = |j: usize| {
        m_all[(2 + j, HEAD)]
            .powi(2)
            .max(m_all[(2 + j, FRAME)].powi(2))
    };
    let largest = (0..red.n_modes).map(share).fold(0.0, f64::max);
    let hz = &red.fixed_interface_hz;
    if hz.last().is_none_or(|&f| f <= CUTOFF_HZ) {
        return Err(TuneError::Missing {
            context: context.to_string(),
            what: format!(
                "the {CANDIDATE_MODES} lowest held modes end at {:?} Hz, below the {CUTOFF_HZ} Hz cut-off",
                hz.last()
            ),
        });
    }
    let kept: Vec<usize> = (0..red.n_modes)
        .filter(|&j| hz[j] < CUTOFF_HZ && share(j) >= UNCOUPLED * largest)
        .collect();
    let surge = (0..red.n_modes)
        .max_by(|&a, &b| share(a).total_cmp(&share(b)))
        .unwrap_or(0);
    let largest_dropped_t = (0..red.n_modes)
        .filter(|j| !kept.contains(j))
        .map(share)
        .fold(0.0, f64::max);
    let keep: Vec<usize> = [FRAME, HEAD]
        .into_iter()
        .chain(kept.iter().map(|j| 2 + j))
        .collect();
    let n = f64::from(SPRINGS_IN_PARALLEL);
    let pick = |a: &DMatrix<f64>| {
        DMatrix::from_fn(keep.len(), keep.len(), |r, c| n * a[(keep[r], keep[c])])
    };
    let rigid = m_all[(FRAME, FRAME)] + 2.0 * m_all[(FRAME, HEAD)] + m_all[(HEAD, HEAD)];
    Ok(ReducedStage {
        k: pick(&ops.k),
        m: pick(&ops.m),
        c: pick(&ops.c),
        modes_hz: kept.iter().map(|&j| hz[j]).collect(),
        coupling_t: kept.iter().map(|&j| share(j)).collect(),
        surge_hz: hz[surge],
        largest_dropped_t,
        spring_mass_t: rigid,
    })
}

impl ReducedStage {
    /// Number of coordinates (2 + kept modes).
    pub fn dim(&self) -> usize {
        self.k.nrows()
    }

    /// The static stiffness between the ends, `K_head,head` with the frame held and the
    /// modes relaxed (N/mm): the Schur complement of the modal block.
    pub fn static_stiffness_n_mm(&self) -> f64 {
        let n = self.dim();
        let kmm = self.k.view((2, 2), (n - 2, n - 2)).into_owned();
        let khm = self.k.view((HEAD, 2), (1, n - 2)).into_owned();
        let correction = match kmm.clone().try_inverse() {
            Some(inv) => (&khm * inv * khm.transpose())[(0, 0)],
            None => f64::NAN,
        };
        self.k[(HEAD, HEAD)] - correction
    }

    /// Undamped frequencies (Hz, ascending) with the frame held and `head_mass_t` on the
    /// head's DOF, or `None` if the mass is not positive definite.
    pub fn frequencies_on_head_hz(&self, head_mass_t: f64) -> Option<Vec<f64>> {
        let n = self.dim();
        let keep: Vec<usize> = (1..n).collect();
        let sub = |a: &DMatrix<f64>| DMatrix::from_fn(n - 1, n - 1, |r, c| a[(keep[r], keep[c])]);
        let k = sub(&self.k);
        let mut m = sub(&self.m);
        m[(0, 0)] += head_mass_t;
        let w2 = generalized_eigenvalues(&k, &m)?;
        Some(
            w2.iter()
                .map(|w| w.max(0.0).sqrt() / std::f64::consts::TAU)
                .collect(),
        )
    }

    /// The stage as a matrix element named `name`: the frame's and the head's axial
    /// DOFs on `frame` and `head` (DOF `axis`, 1..3, the direction the head moves), the
    /// modes on DOF 1 of `modal_nodes` (one per kept mode; the caller holds their other
    /// DOFs).
    pub fn matrix_element(
        &self,
        name: &str,
        frame: NodeId,
        head: NodeId,
        axis: u8,
        modal_nodes: &[NodeId],
    ) -> Result<MatrixElement> {
        if modal_nodes.len() != self.dim() - 2 || !(1..=3).contains(&axis) {
            return Err(TuneError::Invalid(format!(
                "{} modal nodes on axis {axis}; expected {} (one per kept mode) and an axis 1..3",
                modal_nodes.len(),
                self.dim() - 2
            )));
        }
        let row_major = |a: &DMatrix<f64>| a.transpose().as_slice().to_vec();
        let mut dofs = vec![(frame, axis), (head, axis)];
        dofs.extend(modal_nodes.iter().map(|&n| (n, 1)));
        Ok(MatrixElement {
            name: name.to_string(),
            dofs,
            stiffness: row_major(&self.k),
            mass: row_major(&self.m),
            damping: row_major(&self.c),
        })
    }

    /// [`ReducedStage::matrix_element`] as the text of a `DMIG` card.
    pub fn dmig_text(
        &self,
        name: &str,
        frame: NodeId,
        head: NodeId,
        axis: u8,
        modal_nodes: &[NodeId],
    ) -> Result<String> {
        Ok(dmig_card(&[self.matrix_element(
            name,
            frame,
            head,
            axis,
            modal_nodes,
        )?]))
    }
}

fn row_major(a: &DMatrix<f64>) -> Vec<f64> {
    a.transpose().as_slice().to_vec()
}

/// The stage spec of `stage` under a mass of `mass_kg` (module doc).
pub fn reduced_stage_spec(stage: &ReducedStage, mass_kg: f64) -> StageSpec {
    StageSpec {
        mass_kg,
        stiffness_n_m: stage.static_stiffness_n_mm() * 1e3,
        damping_n_s_m: 0.0,
        matrix: Some(StageMatrix {
            stiffness: row_major(&stage.k),
            mass: row_major(&stage.m),
            damping: Some(row_major(&stage.c)),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::super::springs::{head_stages_of_files, HeadStageSettings};
    use super::*;
    use std::path::Path;

    #[test]
    fn the_reduced_stage_is_the_lumped_one_with_its_surge_modes() {
        let start = std::time::Instant::now();
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
        let settings = HeadStageSettings::default();
        let stages =
            head_stages_of_files(&root, &root.join("table4.json"), 7.2, &settings).unwrap();
        let lumped = &stages.stages[0];
        let [alpha, beta] = stages.rayleigh_mid;
        let stage = reduced_stage(&stages.material, &settings.fe, alpha, beta).unwrap();
        eprintln!(
            "modes {:?} Hz, shares {:?} t, surge {} Hz, largest dropped {:e} t, spring {} t, {:.2} s",
            stage.modes_hz,
            stage.coupling_t,
            stage.surge_hz,
            stage.largest_dropped_t,
            stage.spring_mass_t,
            start.elapsed().as_secs_f64()
        );
        // Statics: K = 4 k to rounding.
        let k = stage.static_stiffness_n_mm();
        let want = lumped.stiffness_n_m / 1e3;
        eprintln!("static {k} N/mm, lumped {want} N/mm");
        assert!((k - want).abs() <= 1e-9 * want, "{k} {want}");
        // The lowest held mode is head_stage's surge.
        let f1 = stage.surge_hz;
        assert!(
            (f1 - lumped.surge_frequency_hz).abs() <= 1e-9 * f1,
            "{f1} {}",
            lumped.surge_frequency_hz
        );
        // The head on the stage: Rayleigh's sqrt(K / (m + m_s / 3)).
        let m_head = 7.2e-3;
        let f = stage.frequencies_on_head_hz(m_head).unwrap();
        let m_s = 4.0 * stage.spring_mass_t;
        let rayleigh = (want / (m_head + m_s / 3.0)).sqrt() / std::f64::consts::TAU;
        let bare = (want / m_head).sqrt() / std::f64::consts::TAU;
        eprintln!(
            "head on stage {} Hz, Rayleigh {rayleigh} Hz, lumped {bare} Hz",
            f[0]
        );
        assert!((f[0] - rayleigh).abs() <= 1e-4 * rayleigh);

        // The card's text in a deck: frame node 1 held, head node 2 (7.2 kg) free along
        // z, the modes on nodes 11.. (u_x free); its modes are the stage's.
        let modal: Vec<u32> = (0..stage.dim() as u32 - 2).map(|i| 11 + i).collect();
        let card = stage.dmig_text("head_stage", 1, 2, 3, &modal).unwrap();
        let mut deck = String::from("TITLE, stage\nELEMENTS, 98\nEND\n");
        deck.push_str(&format!(
            "COORDINATES\n3, {}\n1, 0, 0, 0\n2, 0, 0, 100\n",
            modal.len() + 2
        ));
        for n in &modal {
            deck.push_str(&format!("{n}, {n}, 0, 0\n"));
        }
        deck.push_str(&card);
        deck.push_str(&format!(
            "POINT MASS\n2, {m_head}, 0, 0, 0\nFIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1\n\
             0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n2\n0, 0, 0, 0, 0\n2, 3, 4, 5, 6\n{} TO {}\n\
             END OPTION\nMODAL SHAPE\n3\nCONTINUE\n",
            modal[0],
            modal[modal.len() - 1]
        ));
        let model = coil_solver::deck::read_str(&deck, "stage.dat").unwrap();
        let results = coil_solver::analysis::run(&model).unwrap();
        let coil_solver::analysis::CaseSolution::Modal(modes) = &results[0].solution else {
            panic!("not modal")
        };
        for (got, want) in modes.modes.iter().zip(&f) {
            let got = got.frequency_hz;
            assert!(
                (got - want).abs() <= 1e-9 * want,
                "deck {got} Hz, stage {want} Hz"
            );
        }
    }
}
