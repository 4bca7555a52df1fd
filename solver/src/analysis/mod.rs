//! Analyses of a [`Model`]: the assembled [`System`] they share, linear static
//! ([`static_analysis`]), modal ([`modal`]) and transient ([`transient`]) load cases,
//! and [`run`], which executes a model's load cases in order.
//!
//! # The shared system
//! [`System::new`] builds, once per model, the [`DofMap`](crate::dof::DofMap) (constraints), the global
//! element matrices, the [`Assembler`](crate::assembly::Assembler) with its pattern, the reduced stiffness `K`,
//! mass `M` and Rayleigh damping `C` on that one pattern, the load that prescribed
//! displacements put on the free DOFs, and the symbolic Cholesky of the pattern.
//!
//! The symbolic Cholesky ([`System::symbolic`]) serves the stiffness factor only:
//! static cases, modal cases, modal superposition and the quasi-static initial velocity
//! share one numeric factor of `K` per run. A direct transient does not use it: it
//! hands `M`, `C`, `K` (upper triangles, [`crate::integrate::Stepper::new_upper`]) to
//! the operator-level [`crate::integrate::Stepper`], which factors its own effective matrix
//! `(1-am) M + (1-af) gamma dt C + (1-af) beta dt^2 K` (the banded envelope or the
//! simplicial sparse factor of [`crate::linalg`]). The load at time t comes from
//! [`System::point_load_vector`] + [`System::free_load`], and the DOF map expands free
//! vectors to nodes ([`crate::dof::DofMap::expand`]) for history output.
//!
//! # Modules
//! [`system`] (the assembled system and the load tables), [`static_analysis`],
//! [`modal`], [`transient`]; this root only runs a model's load cases in order. The
//! error type is [`crate::error::solve::SolveError`] (re-exported here), below every layer
//! that returns it, so `assembly`, `dof` and `linalg` never import `analysis`.
//!
//! # Damping
//! `C = sum over DAMPING entries of (alpha M_e + beta K_e)` over the entry's elements,
//! plus `alpha M_p` for the point masses at the entry's `mass_nodes` only: a point
//! mass (the spring's weight) gets no mass-proportional damping unless an entry names
//! its node.
//!
//! # Loads
//! A load case applies the model-definition `POINT LOAD`s plus its own. A load with a
//! table is scaled by the table at the evaluation time: the end time of a static load
//! case (`Static { time }`), the current time of a transient. Tables are
//! piecewise-linear and hold their first and last values outside their range.
//!
//! Units throughout: mm, N, t, s (see [`crate::model`]).

pub mod modal;
pub mod static_analysis;
pub mod system;
pub mod transient;
pub mod unilateral;

pub use crate::error::solve::SolveError;
pub use modal::{ModalSolution, Mode};
pub use static_analysis::{LoadedDof, Reaction, StaticSolution};
pub use system::{table_factor, table_points, System};
pub use transient::{History, HistoryColumn, TransientSolution};

use crate::linalg::Cholesky;
use crate::model::{Analysis, Model};

/// What one load case produced.
#[derive(Debug, Clone)]
pub enum CaseSolution {
    /// A static load case's solution.
    Static(StaticSolution),
    /// A modal load case's solution.
    Modal(ModalSolution),
    /// A transient load case's solution.
    Transient(TransientSolution),
}

/// One load case's title and solution.
#[derive(Debug, Clone)]
pub struct CaseResult {
    /// The load case's title.
    pub title: String,
    /// What the load case produced.
    pub solution: CaseSolution,
}

/// Runs the model's load cases in order. The stiffness is factored at most once and
/// shared by the static, modal and modal-superposition cases (and the quasi-static
/// initial velocity), dropped during a direct transient that does not use it; a transient case starts from the displacement of a static case run
/// immediately before it (see [`transient`]); direct transient cases share one stepper,
/// refactored only when the scheme or `dt` changes.
pub fn run(model: &Model) -> Result<Vec<CaseResult>, SolveError> {
    run_with(model, &transient::RunOptions::default())
}

/// [`run`] with reporting and limits ([`transient::RunOptions`]).
pub fn run_with(
    model: &Model,
    options: &transient::RunOptions,
) -> Result<Vec<CaseResult>, SolveError> {
    if model.nodes.is_empty() {
        return Err(SolveError::BadInput {
            what: "the model has no nodes (COORDINATES); expected a structure to solve".into(),
        });
    }
    if model.load_cases.is_empty() {
        return Err(SolveError::BadInput {
            what: "the deck has no load case (an analysis after END OPTION); expected at \
                   least one static, modal or transient case"
                .into(),
        });
    }
    let system = System::new(model)?;
    let mut factor: Option<Cholesky> = None;
    let mut context = transient::Context::default();
    context.options = options.clone();
    let mut out: Vec<CaseResult> = Vec::with_capacity(model.load_cases.len());
    for case in &model.load_cases {
        let solution = match &case.analysis {
            Analysis::Static { time, .. } => {
                let chol = match &mut factor {
                    Some(c) => c,
                    None => factor.insert(system.factor_stiffness()?),
                };
                CaseSolution::Static(static_analysis::solve(&system, chol, case, *time)?)
            }
            Analysis::Modal { modes } => {
                let chol = match &mut factor {
                    Some(c) => c,
                    None => factor.insert(system.factor_stiffness()?),
                };
                CaseSolution::Modal(modal::solve(&system, chol, &case.title, *modes as usize)?)
            }
            Analysis::Transient { method, .. } => {
                let chol = if transient::needs_stiffness_factor(model, method) {
                    Some(match &mut factor {
                        Some(c) => &*c,
                        None => &*factor.insert(system.factor_stiffness()?),
                    })
                } else {
                    // Not kept through a transient that does not use it (its memory
                    // is the step's own again); a later case factors again.
                    factor = None;
                    None
                };
                let start = match out.last() {
                    Some(CaseResult {
                        title,
                        solution: CaseSolution::Static(solution),
                    }) => Some(transient::StaticStart { title, solution }),
                    _ => None,
                };
                CaseSolution::Transient(transient::solve(&system, &mut context, chol, case, start)?)
            }
        };
        out.push(CaseResult {
            title: case.title.clone(),
            solution,
        });
    }
    Ok(out)
}

#[cfg(test)]
pub(crate) mod test_support;

#[cfg(test)]
mod tests {
    use super::test_support::{damped_tied_frame, tied_frame};
    use super::*;
    use crate::linalg::sym_upper_matvec;
    use crate::model::{NodeId, PointMass, Table};
    use faer::sparse::SparseColMat;

    fn quadratic(a: &SparseColMat<usize, f64>, x: &[f64]) -> f64 {
        let mut y = vec![0.0; x.len()];
        sym_upper_matvec(a.as_ref(), x, 1.0, &mut y);
        x.iter().zip(&y).map(|(p, q)| p * q).sum()
    }

    /// C = alpha M_e + beta K_e on the damped elements; the point mass gets alpha only
    /// when its node is named.
    #[test]
    fn rayleigh_damping_skips_unnamed_point_masses() {
        let (alpha, beta) = (0.8, 1.2e-4);
        let mut model = damped_tied_frame(alpha, beta);
        let x: Vec<f64> = (0..System::new(&model).unwrap().dim())
            .map(|i| (0.7 * i as f64).sin())
            .collect();
        let system = System::new(&model).unwrap();
        let mut bare = model.clone();
        bare.point_masses.clear();
        let bare_system = System::new(&bare).unwrap();
        let (m, m_bare, k) = (
            quadratic(&system.mass, &x),
            quadratic(&bare_system.mass, &x),
            quadratic(&system.stiffness, &x),
        );
        assert!(m > m_bare * 1.01, "the point mass moves with x");
        let c = quadratic(&system.damping, &x);
        let expected = alpha * m_bare + beta * k;
        assert!(
            (c - expected).abs() < 1e-12 * expected.abs(),
            "{c} vs {expected}"
        );
        model.damping[0].mass_nodes = vec![10];
        let named = System::new(&model).unwrap();
        let c = quadratic(&named.damping, &x);
        let expected = alpha * m + beta * k;
        assert!(
            (c - expected).abs() < 1e-12 * expected.abs(),
            "{c} vs {expected}"
        );
        // Naming a node without a point mass is an error, not a silent no-op.
        model.damping[0].mass_nodes = vec![2];
        assert!(matches!(
            System::new(&model),
            Err(SolveError::BadInput { .. })
        ));
    }

    /// Degenerate models give results or errors, never panics.
    #[test]
    fn fully_fixed_and_empty_models_do_not_panic() {
        let mut model = tied_frame();
        model.fixed_disp.push(crate::model::FixedDisp {
            dofs: (1..=6).map(|d| (d, 0.0)).collect(),
            nodes: vec![2, 3],
        });
        model.fixed_disp.push(crate::model::FixedDisp {
            dofs: [1, 2, 5, 6].map(|d| (d, 0.0)).to_vec(),
            nodes: vec![10],
        });
        for analysis in [
            Analysis::Static {
                steps: 1,
                time: 1.0,
            },
            Analysis::Modal { modes: 1 },
        ] {
            model.load_cases = vec![crate::model::LoadCase {
                title: "case".to_string(),
                analysis,
                point_loads: Vec::new(),
            }];
            match run(&model) {
                Ok(cases) => assert!(matches!(cases[0].solution, CaseSolution::Static(_))),
                Err(e) => assert!(
                    matches!(e, SolveError::TooManyModes { available: 0, .. }),
                    "{e}"
                ),
            }
        }
        let mut empty = test_support::model(&[], &[]);
        empty.load_cases = model.load_cases.clone();
        assert!(run(&empty).is_err());
        empty.load_cases[0].analysis = Analysis::Static {
            steps: 1,
            time: 1.0,
        };
        // A model without nodes is nonsense, refused, not an empty result.
        let e = run(&empty).unwrap_err().to_string();
        assert!(e.contains("no nodes"), "{e}");
        let mut no_case = model.clone();
        no_case.load_cases.clear();
        assert!(run(&no_case)
            .unwrap_err()
            .to_string()
            .contains("no load case"));
    }

    /// Massless beams with one point mass carry three modes; a fourth is an error that
    /// says so, not an infinite frequency.
    #[test]
    fn more_modes_than_the_mass_carries_is_an_error() {
        let mut model = test_support::model(
            &[
                (1, [0.0; 3]),
                (2, [10.0, 0.0, 0.0]),
                (3, [20.0, 1.0, 0.0]),
                (4, [30.0, 0.0, 2.0]),
            ],
            &[[1, 2], [2, 3], [3, 4]],
        );
        model.materials[0].density = 0.0;
        model.fixed_disp.push(crate::model::FixedDisp {
            dofs: (1..=6).map(|d| (d, 0.0)).collect(),
            nodes: vec![1],
        });
        model.point_masses.push(PointMass {
            node: 4,
            mass: 1e-3,
            inertia: [0.0; 3],
        });
        let system = System::new(&model).unwrap();
        let factor = system.factor_stiffness().unwrap();
        let three = modal::solve(&system, &factor, "three", 3).unwrap();
        let total: f64 = three
            .modes
            .iter()
            .map(|m| m.effective_mass.iter().sum::<f64>())
            .sum();
        assert!(
            (total - 3e-3).abs() < 1e-12,
            "all the mass in three modes: {total}"
        );
        match modal::solve(&system, &factor, "four", 4) {
            Err(SolveError::BadInput { what }) => assert!(what.contains("no mass"), "{what}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn tables_interpolate_and_hold_their_ends() {
        let mut model = tied_frame();
        model.tables.push(Table {
            name: "pulse".to_string(),
            points: vec![(0.0, 0.0), (0.001, 1.0), (0.002, 0.0)],
        });
        let f = |t| table_factor(&model, "PULSE", t).unwrap();
        assert_eq!(f(-1.0), 0.0);
        assert!((f(0.0005) - 0.5).abs() < 1e-12);
        assert_eq!(f(0.001), 1.0);
        assert!((f(0.0015) - 0.5).abs() < 1e-12);
        assert_eq!(f(5.0), 0.0);
        assert!(matches!(
            table_factor(&model, "nope", 0.0),
            Err(SolveError::UnknownTable { .. })
        ));
    }

    #[test]
    fn modal_requests_beyond_the_model_are_errors() {
        let mut model = tied_frame();
        model.load_cases.push(crate::model::LoadCase {
            title: "too many".to_string(),
            analysis: Analysis::Modal { modes: 1000 },
            point_loads: Vec::new(),
        });
        match run(&model) {
            Err(SolveError::TooManyModes {
                requested,
                available,
                ..
            }) => {
                assert_eq!(requested, 1000);
                assert_eq!(available, System::new(&model).unwrap().dim());
            }
            other => panic!("{other:?}"),
        }
    }

    /// Lowest omega^2 of `K phi = omega^2 M phi` by a dense reference (nalgebra):
    /// `L_M^-1 K L_M^-T` with the Cholesky factor of M.
    fn dense_omega2(system: &System) -> Vec<f64> {
        let n = system.dim();
        let dense = |a: &SparseColMat<usize, f64>| {
            let mut out = nalgebra::DMatrix::<f64>::zeros(n, n);
            for j in 0..n {
                for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                    out[(i, j)] += v;
                    if i != j {
                        out[(j, i)] += v;
                    }
                }
            }
            out
        };
        let (k, m) = (dense(&system.stiffness), dense(&system.mass));
        let l_inv = m.clone().cholesky().unwrap().l().try_inverse().unwrap();
        let a = &l_inv * &k * l_inv.transpose();
        let eigen = ((&a + a.transpose()) * 0.5).symmetric_eigen();
        // Rayleigh quotients of the back-transformed vectors: the ill-conditioned L_M^-1
        // spoils the eigenvalues at 1e-8, the quotient is second order in that error.
        let mut w: Vec<f64> = eigen
            .eigenvectors
            .column_iter()
            .map(|y| {
                let x = l_inv.transpose() * y;
                (x.transpose() * &k * &x)[0] / (x.transpose() * &m * &x)[0]
            })
            .collect();
        w.sort_by(f64::total_cmp);
        w
    }

    /// A 3-element chain has fewer DOFs than faer's Lanczos subspace, so the dense path
    /// runs; a 40-element chain goes through Lanczos. Both must match a dense
    /// generalised eigensolution (1e-9 relative: Lanczos locks residuals at 1e-12 of
    /// the top eigenvalue) and give M-orthonormal modes.
    #[test]
    fn dense_and_lanczos_paths_match_a_dense_reference() {
        let n = 40;
        let nodes: Vec<(NodeId, [f64; 3])> = (0..=n)
            .map(|i| {
                (
                    i as NodeId + 1,
                    [i as f64 * 3.0, (i as f64 * 0.3).sin(), 0.0],
                )
            })
            .collect();
        let elements: Vec<[NodeId; 2]> = (1..=n as NodeId).map(|i| [i, i + 1]).collect();
        for (count, modes) in [(3, 5), (n, 12)] {
            let mut model = test_support::model(&nodes[..=count], &elements[..count]);
            model.fixed_disp.push(crate::model::FixedDisp {
                dofs: (1..=6).map(|d| (d, 0.0)).collect(),
                nodes: vec![1],
            });
            let system = System::new(&model).unwrap();
            let factor = system.factor_stiffness().unwrap();
            let sol = modal::solve(&system, &factor, "modes", modes).unwrap();
            let reference = dense_omega2(&system);
            assert!(sol.orthonormality_error < 1e-10);
            for (mode, w2) in sol.modes.iter().zip(&reference) {
                assert!(
                    (mode.omega_squared - w2).abs() < 1e-9 * w2,
                    "{count}: {} vs {w2}",
                    mode.omega_squared
                );
                assert!(mode.relative_residual < 1e-8, "{}", mode.relative_residual);
            }
        }
    }
}
