//! The modal-superposition path of a transient case: the modal basis, each mode
//! integrated exactly, and what the method leaves out, measured in [`ModalSummary`]
//! (the "Modal superposition" section of [`super`]).

use super::error::integrate_error;
use super::loads::LoadPatterns;
use super::recording::Recorder;
use crate::analysis::modal;
use crate::analysis::system::System;
use crate::error::solve::SolveError;
use crate::integrate::modal_superposition::{integrate_modal, ModalBasis, ModalState};
use crate::linalg::{sym_upper_matvec, Cholesky};
use faer::sparse::SparseColMat;
use faer::Mat;

/// One retained mode of a modal superposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalTerm {
    /// Circular natural frequency (rad/s).
    pub omega_rad_s: f64,
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// `phi^T C phi / (2 w)`: the damping ratio the mode is integrated with.
    pub zeta: f64,
    /// The damping ratio with the full modal damping matrix of the retained modes
    /// (`None` for a mode damped critically or more, whose pair of real roots has no
    /// single ratio).
    pub zeta_coupled: Option<f64>,
    /// Effective mass along global z, the spring axis (t).
    pub axial_effective_mass: f64,
}

/// What a modal superposition kept and left out.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalSummary {
    /// The retained modes, in the order integrated.
    pub modes: Vec<ModalTerm>,
    /// The damping coupling neglected and the fractions captured.
    pub capture: ModalCapture,
}

/// The damping coupling a decoupled modal integration neglects and the fractions of the
/// initial state and the loads its retained modes carry (dimensionless; written as they
/// are into results.json, flattened into the transient's `modal` entry).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModalCapture {
    /// `max |c_ij| / sqrt(c_ii c_jj)` over `i != j` of `c = Phi^T C Phi`: the largest
    /// normalised damping coupling that the decoupled integration neglects (0 for
    /// classical damping).
    pub max_damping_coupling: f64,
    /// The two modes (1-based) of that coupling.
    pub coupling_pair: Option<(usize, usize)>,
    /// `max |zeta_coupled / zeta - 1|` over the modes with both ratios.
    pub max_zeta_shift: Option<f64>,
    /// Fraction of the initial strain energy `u0^T K u0 / 2` in the retained modes
    /// (`None` when the initial displacement is zero).
    pub initial_displacement_captured: Option<f64>,
    /// Fraction of the initial kinetic energy `v0^T M v0 / 2` in the retained modes
    /// (`None` when the initial velocity is zero).
    pub initial_velocity_captured: Option<f64>,
    /// Smallest, over the load patterns (constant part and one per table), fraction of
    /// the static compliance `f^T K^-1 f` the retained modes carry (`None` without loads).
    pub load_captured: Option<f64>,
}

#[allow(clippy::too_many_arguments)]
pub(super) fn run_modal(
    system: &System,
    factor: &Cholesky,
    title: &str,
    n_modes: usize,
    dt: f64,
    steps: usize,
    u0: &[f64],
    v0: &[f64],
    loads: &LoadPatterns,
    recorder: &mut Recorder,
    progress: &coil_io::Progress,
) -> Result<ModalSummary, SolveError> {
    let fail = |e| integrate_error(system, title, true, e);
    let n = system.dim();
    let solution = modal::solve(system, factor, title, n_modes)?;
    let m = solution.modes.len();
    let shapes = Mat::from_fn(n, m, |i, j| solution.modes[j].shape_free[i]);
    let omega: Vec<f64> = solution
        .modes
        .iter()
        .map(|mode| mode.omega_squared.sqrt())
        .collect();
    let coupling = damping_coupling(system, &solution.modes, &omega);
    let zeta = coupling.zeta.clone();

    // Initial modal state q = Phi^T M x and what the basis captures of it.
    let project_mass = |x: &[f64]| -> Vec<f64> {
        let mut mx = vec![0.0; n];
        sym_upper_matvec(system.mass.as_ref(), x, 1.0, &mut mx);
        project(&shapes, &mx)
    };
    let q0 = project_mass(u0);
    let qd0 = project_mass(v0);
    let strain = quadratic(&system.stiffness, u0);
    let kinetic = quadratic(&system.mass, v0);
    let initial_displacement_captured = (strain > 0.0).then(|| {
        q0.iter()
            .zip(&omega)
            .map(|(q, w)| (w * q).powi(2))
            .sum::<f64>()
            / strain
    });
    let initial_velocity_captured =
        (kinetic > 0.0).then(|| qd0.iter().map(|q| q * q).sum::<f64>() / kinetic);

    // Modal load patterns p_k = Phi^T f_k, and their captured static compliance.
    let mut modal_patterns = Vec::with_capacity(loads.count());
    let mut load_captured: Option<f64> = None;
    for pattern in loads.patterns() {
        let p = project(&shapes, pattern);
        let mut x = pattern.to_vec();
        factor.solve_in_place(&mut x);
        let compliance: f64 = x.iter().zip(pattern).map(|(a, b)| a * b).sum();
        if compliance > 0.0 {
            let kept: f64 = p.iter().zip(&omega).map(|(pj, w)| (pj / w).powi(2)).sum();
            let ratio = kept / compliance;
            load_captured = Some(load_captured.map_or(ratio, |r: f64| r.min(ratio)));
        }
        modal_patterns.push(p);
    }

    let rows = recorder.slot_rows(&shapes);
    let output_slots: Vec<usize> = (0..rows.nrows()).collect();
    let basis = ModalBasis {
        shapes: rows.as_ref(),
        omega: &omega,
        zeta: &zeta,
    };
    let initial = ModalState {
        t: 0.0,
        q: q0,
        qd: qd0,
    };
    let mut factors = vec![0.0; loads.count()];
    integrate_modal(
        basis,
        dt,
        steps,
        &initial,
        &output_slots,
        &mut |t, p| {
            loads.factors(t, &mut factors);
            for (s, pattern) in factors.iter().zip(&modal_patterns) {
                for (pi, qi) in p.iter_mut().zip(pattern) {
                    *pi += s * qi;
                }
            }
        },
        &mut |k, t, response| {
            if k % 64 == 0 {
                progress.set(k as u64);
            }
            if recorder.wants(k) {
                recorder.record_slots(t, response.u, response.v, response.a);
            }
        },
    )
    .map_err(fail)?;

    let modes = solution
        .modes
        .iter()
        .enumerate()
        .map(|(j, mode)| ModalTerm {
            omega_rad_s: omega[j],
            frequency_hz: mode.frequency_hz,
            zeta: zeta[j],
            zeta_coupled: coupling.zeta_coupled[j],
            axial_effective_mass: mode.effective_mass[2],
        })
        .collect();
    Ok(ModalSummary {
        modes,
        capture: ModalCapture {
            max_damping_coupling: coupling.max,
            coupling_pair: coupling.pair,
            max_zeta_shift: coupling.max_zeta_shift,
            initial_displacement_captured,
            initial_velocity_captured,
            load_captured,
        },
    })
}

/// `Phi^T x`.
pub(super) fn project(shapes: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    (0..shapes.ncols())
        .map(|j| shapes.col(j).iter().zip(x).map(|(p, xi)| p * xi).sum())
        .collect()
}

pub(super) fn quadratic(a: &SparseColMat<usize, f64>, x: &[f64]) -> f64 {
    let mut y = vec![0.0; x.len()];
    sym_upper_matvec(a.as_ref(), x, 1.0, &mut y);
    x.iter().zip(&y).map(|(p, q)| p * q).sum()
}

pub(super) struct Coupling {
    /// `c_ii / (2 w_i) = phi_i^T C phi_i / (2 w_i)`.
    pub(super) zeta: Vec<f64>,
    pub(super) max: f64,
    pub(super) pair: Option<(usize, usize)>,
    pub(super) zeta_coupled: Vec<Option<f64>>,
    pub(super) max_zeta_shift: Option<f64>,
}

/// The modal damping matrix `c = Phi^T C Phi`, the modal damping ratios
/// `zeta_i = c_ii / (2 w_i)` the modes are integrated with, its largest normalised
/// off-diagonal entry, and the damping ratios of the retained modes with all of `c`: the eigenvalues
/// `lambda = -zeta w +- i w sqrt(1 - zeta^2)` of `[[0, Omega], [-Omega, -c]]` (the state
/// `(Omega q, q')`, which keeps every entry of the order of a frequency), each mode taking
/// the eigenvalue nearest its decoupled one, `zeta = -Re lambda / |lambda|`.
pub(super) fn damping_coupling(system: &System, modes: &[modal::Mode], omega: &[f64]) -> Coupling {
    let m = modes.len();
    let n = system.dim();
    let mut c_phi = vec![vec![0.0; n]; m];
    for (mode, out) in modes.iter().zip(&mut c_phi) {
        sym_upper_matvec(system.damping.as_ref(), &mode.shape_free, 1.0, out);
    }
    let c = nalgebra::DMatrix::from_fn(m, m, |i, j| {
        let a: f64 = modes[i]
            .shape_free
            .iter()
            .zip(&c_phi[j])
            .map(|(p, q)| p * q)
            .sum();
        let b: f64 = modes[j]
            .shape_free
            .iter()
            .zip(&c_phi[i])
            .map(|(p, q)| p * q)
            .sum();
        0.5 * (a + b)
    });
    // Modal damping (`LOSS FACTOR`, `MODAL DAMPING`) is diagonal in the modes.
    let mut c = c;
    for i in 0..m {
        c[(i, i)] += 2.0 * system.model.modal_damping.zeta(i) * omega[i];
    }
    let zeta: Vec<f64> = (0..m).map(|i| c[(i, i)] / (2.0 * omega[i])).collect();
    let mut max = 0.0;
    let mut pair = None;
    for i in 0..m {
        for j in i + 1..m {
            let d = (c[(i, i)] * c[(j, j)]).sqrt();
            if d > 0.0 {
                let r = c[(i, j)].abs() / d;
                if r > max {
                    max = r;
                    pair = Some((i + 1, j + 1));
                }
            }
        }
    }
    let mut zeta_coupled: Vec<Option<f64>> = zeta.iter().map(|&z| (z < 1.0).then_some(z)).collect();
    if c.iter().any(|&x| x != 0.0) && m > 0 {
        let mut a = nalgebra::DMatrix::<f64>::zeros(2 * m, 2 * m);
        for i in 0..m {
            a[(i, m + i)] = omega[i];
            a[(m + i, i)] = -omega[i];
            for j in 0..m {
                a[(m + i, m + j)] = -c[(i, j)];
            }
        }
        // A failed Schur iteration leaves the coupled ratios unknown, not wrong.
        let eigenvalues = nalgebra::linalg::Schur::try_new(a, f64::EPSILON, 100_000)
            .map(|s| s.complex_eigenvalues());
        match eigenvalues {
            Some(lambda) => {
                for (i, zc) in zeta_coupled.iter_mut().enumerate() {
                    if zc.is_none() {
                        continue;
                    }
                    let (w, z) = (omega[i], zeta[i]);
                    let target = nalgebra::Complex::new(-z * w, w * (1.0 - z * z).sqrt());
                    let nearest = lambda
                        .iter()
                        .filter(|l| l.im > 0.0)
                        .min_by(|a, b| (*a - target).norm().total_cmp(&(*b - target).norm()));
                    *zc = nearest.map(|l| -l.re / l.norm());
                }
            }
            None => zeta_coupled.iter_mut().for_each(|z| *z = None),
        }
    }
    let max_zeta_shift = zeta
        .iter()
        .zip(&zeta_coupled)
        .filter_map(|(&z, zc)| zc.filter(|_| z > 0.0).map(|zc| (zc / z - 1.0).abs()))
        .reduce(f64::max);
    Coupling {
        zeta,
        max,
        pair,
        zeta_coupled,
        max_zeta_shift,
    }
}
