//! Modal analysis: the lowest eigenpairs of `K phi = omega^2 M phi` on the free DOFs.
//!
//! # Method
//! Shift-invert about zero on the Cholesky factor of K that the static case already
//! computed, `P K P^T = L L^T`: the symmetric operator `A = L^-1 P M P^T L^-T` has
//! eigenvalues `mu = 1 / omega^2` with eigenvectors `y`, and `phi = P^T L^-T y`. The
//! largest `mu` are the lowest frequencies and are well separated relative to the
//! spectrum's top, which is what a Krylov method converges to fastest. faer's
//! `matrix_free::eigen::partial_self_adjoint_eigen` (thick-restart Lanczos with full
//! reorthogonalisation) computes them. Its convergence test is absolute, so the
//! operator is scaled to unit top eigenvalue by a few power iterations first; the
//! tolerance [`LANCZOS_TOLERANCE`] is then relative to `mu_1`. Systems too small for
//! faer's Lanczos (dimension not above its subspace size) are solved densely: the
//! operator is formed column by column, scaled, and given to faer's dense
//! `self_adjoint_eigen`. Fewer converged pairs than requested is an error.
//!
//! Each mode is then mass-normalised, `phi^T M phi = 1` (checked), `omega^2` is the
//! Rayleigh quotient `phi^T K phi` (second-order accurate in the eigenvector error), and
//! `|K phi - omega^2 M phi| / |K phi|` is recorded.
//!
//! # Effective modal mass
//! With `r_j` the rigid translation along global axis j in the full DOF space (every
//! node's `u_j = 1`, rotations 0, supports included) and `Phi = T phi` the full mode
//! shape, the participation factor is `Gamma_j = Phi^T M_full r_j` and the effective
//! mass `Gamma_j^2` (t). Summed over all modes it gives `r_j^T M_full T M_r^-1 T^T M_full
//! r_j`, the mass that moves with the free DOFs; the spring axis is global z, so the
//! z value identifies the axial (surge) mode.
//!
//! Units: omega in rad/s, frequency in Hz, mass in t (kg only in result files).

use super::system::System;
use crate::error::solve::SolveError;
use crate::linalg::{sym_upper_matvec, Cholesky, ShiftInvert};
use crate::model::DOFS_PER_NODE;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::matrix_free::eigen::{
    partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch, PartialEigenParams,
};
use faer::sparse::SparseColMatRef;
use faer::{Mat, Par, Side};

/// Residual tolerance of the Lanczos iteration on the operator scaled to `mu_1 ~ 1`.
/// Rounding puts a floor near `1e-15`; `1e-12` keeps a margin of three decades and
/// still gives `|r| / mu_k < 1e-12 mu_1 / mu_k`, far below what a frequency needs
/// (the eigenvalue error is of order `|r|^2 / gap`).
pub const LANCZOS_TOLERANCE: f64 = 1e-12;

/// Tolerance of the one retry after a non-converged first attempt (see [`solve`]).
pub const LANCZOS_RETRY_TOLERANCE: f64 = 1e-10;

/// Eigenvalue of the scaled operator (top ~ 1) below which a mode is massless: a
/// frequency ratio above 1e7 to the first mode, and within rounding of zero for an
/// operator of norm 1.
const MASSLESS_MU: f64 = 1e-14;

/// One mode.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// omega^2 (rad^2/s^2).
    pub omega_squared: f64,
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Natural period (s).
    pub period_s: f64,
    /// Mass-normalised shape on the free DOFs.
    pub shape_free: Vec<f64>,
    /// The same shape on all full DOFs (tied DOFs expanded, prescribed ones zero).
    pub shape: Vec<f64>,
    /// Participation factors `Gamma_j` along global x, y, z (sqrt(t)).
    pub participation: [f64; 3],
    /// Effective modal masses along global x, y, z (t).
    pub effective_mass: [f64; 3],
    /// `|K phi - omega^2 M phi| / |K phi|`.
    pub relative_residual: f64,
}

/// Result of a modal load case.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalSolution {
    /// Modes by ascending frequency.
    pub modes: Vec<Mode>,
    /// `r_j^T M_full r_j`: the model's total translational mass along x, y, z (t).
    pub total_mass: [f64; 3],
    /// `max |phi_i^T M phi_j - delta_ij|` over the computed modes.
    pub orthonormality_error: f64,
}

/// A fixed, seeded pseudo-random start vector (SplitMix64), so runs are reproducible
/// and the start is not orthogonal to symmetric or antisymmetric modes.
fn start_vector(n: usize) -> Vec<f64> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..n)
        .map(|_| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Largest `n_modes` eigenpairs `(mu, y)` of the (scaled) operator, descending.
fn eigenpairs(
    op: &ShiftInvert,
    n_modes: usize,
    tolerance: f64,
    case: &str,
) -> Result<Vec<(f64, Vec<f64>)>, SolveError> {
    let n = op.factor.dim();
    let params = PartialEigenParams {
        min_dim: (n_modes + 16).max(32),
        max_dim: (2 * n_modes + 32).max(64),
        max_restarts: 1000,
        ..Default::default()
    };
    if n <= params.max_dim {
        // Dense path: faer's Lanczos needs n above its subspace size.
        let mut a = Mat::<f64>::zeros(n, n);
        let mut e = vec![0.0; n];
        let mut col = vec![0.0; n];
        for j in 0..n {
            e.fill(0.0);
            e[j] = 1.0;
            op.apply_vec(&e, &mut col);
            for (i, &v) in col.iter().enumerate() {
                a[(i, j)] = v;
            }
        }
        let a = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
        let evd = a
            .self_adjoint_eigen(Side::Lower)
            .map_err(|_| SolveError::EigenNotConverged {
                case: case.to_string(),
                requested: n_modes,
                converged: 0,
            })?;
        let s = evd.S();
        let u = evd.U();
        // Ascending order: the largest mu are at the end.
        return Ok((0..n_modes)
            .map(|k| {
                let j = n - 1 - k;
                (s[j], (0..n).map(|i| u[(i, j)]).collect())
            })
            .collect());
    }
    let v0 = start_vector(n);
    let mut eigvecs = Mat::<f64>::zeros(n, n_modes);
    let mut eigvals = vec![0.0; n_modes];
    let par = Par::Seq;
    let mut mem = MemBuffer::try_new(partial_self_adjoint_eigen_scratch(op, n_modes, par, params))
        .map_err(|_| SolveError::Linalg("out of memory for the eigensolver".to_string()))?;
    let info = partial_self_adjoint_eigen(
        eigvecs.as_mut(),
        &mut eigvals,
        op,
        faer::ColRef::from_slice(&v0),
        tolerance,
        par,
        MemStack::new(&mut mem),
        params,
    );
    if info.n_converged_eigen < n_modes {
        return Err(SolveError::EigenNotConverged {
            case: case.to_string(),
            requested: n_modes,
            converged: info.n_converged_eigen,
        });
    }
    Ok((0..n_modes)
        .map(|k| (eigvals[k], (0..n).map(|i| eigvecs[(i, k)]).collect()))
        .collect())
}

/// Computes the lowest `n_modes` modes with a factor of the system's stiffness.
pub fn solve(
    system: &System,
    factor: &Cholesky,
    case: &str,
    n_modes: usize,
) -> Result<ModalSolution, SolveError> {
    let n = system.dim();
    if n_modes == 0 {
        return Err(SolveError::BadInput {
            what: format!("load case '{case}' asks for 0 modes"),
        });
    }
    if n_modes > n {
        return Err(SolveError::TooManyModes {
            case: case.to_string(),
            requested: n_modes,
            available: n,
        });
    }
    if !system.mass.val().iter().any(|&m| m != 0.0) {
        return Err(SolveError::BadInput {
            what: format!(
                "load case '{case}': the model has no mass (density and point masses are zero)"
            ),
        });
    }
    let mut op = ShiftInvert {
        factor,
        mass: system.mass.as_ref(),
        scale: 1.0,
    };
    // A few power iterations estimate mu_1 from below; it only sets the scale.
    let mut v = start_vector(n);
    let mut w = vec![0.0; n];
    let mut mu_estimate = 0.0;
    for _ in 0..4 {
        let nv = norm(&v);
        v.iter_mut().for_each(|x| *x /= nv);
        op.apply_vec(&v, &mut w);
        mu_estimate = norm(&w);
        std::mem::swap(&mut v, &mut w);
    }
    if !(mu_estimate > 0.0 && mu_estimate.is_finite()) {
        return Err(SolveError::NonFinite {
            what: format!(
                "load case '{case}': scale of the shift-invert operator ({mu_estimate:e})"
            ),
        });
    }
    op.scale = 1.0 / mu_estimate;
    // The power estimate is a lower bound of mu_1; should it be far off, the absolute
    // tolerance is relatively stricter and can fall under the rounding floor. One retry
    // with a looser tolerance covers that; a second failure is reported.
    let pairs = match eigenpairs(&op, n_modes, LANCZOS_TOLERANCE, case) {
        Ok(pairs) => pairs,
        Err(SolveError::EigenNotConverged { .. }) => {
            eigenpairs(&op, n_modes, LANCZOS_RETRY_TOLERANCE, case)?
        }
        Err(e) => return Err(e),
    };

    let k = system.stiffness.as_ref();
    let m = system.mass.as_ref();
    let dofs = &system.dofs;
    let (mass_r, total_mass) = rigid_translation_masses(system)?;

    let mut modes = Vec::with_capacity(n_modes);
    for (index, (mu, y)) in pairs.into_iter().enumerate() {
        // The operator is scaled to mu_1 ~ 1: mu below MASSLESS_MU is an infinite
        // frequency (a direction without mass, e.g. rotations of a lumped model with zero
        // rotary inertia), i.e. more modes requested than the mass can carry.
        if mu.is_nan() || mu <= MASSLESS_MU {
            return Err(SolveError::BadInput {
                what: format!(
                    "load case '{case}': mode {} has no mass (infinite frequency); \
                     the model has fewer DOFs with mass than the {n_modes} modes requested",
                    index + 1
                ),
            });
        }
        let mut phi = vec![0.0; n];
        factor.back_transform(&y, &mut phi);
        let mut m_phi = vec![0.0; n];
        sym_upper_matvec(m, &phi, 1.0, &mut m_phi);
        let generalized_mass = dot(&phi, &m_phi);
        let s = 1.0 / generalized_mass.sqrt();
        phi.iter_mut().for_each(|x| *x *= s);
        m_phi.iter_mut().for_each(|x| *x *= s);
        let mut k_phi = vec![0.0; n];
        sym_upper_matvec(k, &phi, 1.0, &mut k_phi);
        let omega_squared = dot(&phi, &k_phi);
        let residual: Vec<f64> = k_phi
            .iter()
            .zip(&m_phi)
            .map(|(a, b)| a - omega_squared * b)
            .collect();
        let relative_residual = norm(&residual) / norm(&k_phi);
        let shape = dofs.expand(&phi, 0.0);
        let participation = [0, 1, 2].map(|j| dot(&shape, &mass_r[j]));
        let effective_mass = participation.map(|g| g * g);
        let omega = omega_squared.sqrt();
        if !omega.is_finite() {
            return Err(SolveError::NonFinite {
                what: format!("load case '{case}': frequency of mode {}", index + 1),
            });
        }
        modes.push(Mode {
            omega_squared,
            frequency_hz: omega / std::f64::consts::TAU,
            period_s: std::f64::consts::TAU / omega,
            shape_free: phi,
            shape,
            participation,
            effective_mass,
            relative_residual,
        });
    }
    modes.sort_by(|a, b| a.omega_squared.total_cmp(&b.omega_squared));

    let orthonormality_error = orthonormality_error(m, &modes);
    Ok(ModalSolution {
        modes,
        total_mass,
        orthonormality_error,
    })
}

/// `M_full r_j` for the three rigid translations `r_j` (full space) and the total mass
/// `r_j^T M_full r_j` in each direction.
fn rigid_translation_masses(system: &System) -> Result<(Vec<Vec<f64>>, [f64; 3]), SolveError> {
    let full = system.dofs.full_len();
    let mut mass_r = Vec::with_capacity(3);
    let mut total_mass = [0.0; 3];
    for (j, total) in total_mass.iter_mut().enumerate() {
        let r: Vec<f64> = (0..full)
            .map(|d| if d % DOFS_PER_NODE == j { 1.0 } else { 0.0 })
            .collect();
        let mr = system.full_mass_times(&r)?;
        *total = dot(&r, &mr);
        mass_r.push(mr);
    }
    Ok((mass_r, total_mass))
}

/// `max |phi_i^T M phi_j - delta_ij|` over the modes (free DOFs, `m` upper triangle).
fn orthonormality_error(m: SparseColMatRef<'_, usize, f64>, modes: &[Mode]) -> f64 {
    let n = m.nrows();
    let mut orthonormality_error: f64 = 0.0;
    let m_shapes: Vec<Vec<f64>> = modes
        .iter()
        .map(|md| {
            let mut out = vec![0.0; n];
            sym_upper_matvec(m, &md.shape_free, 1.0, &mut out);
            out
        })
        .collect();
    for (i, a) in modes.iter().enumerate() {
        for (j, mb) in m_shapes.iter().enumerate() {
            let target = if i == j { 1.0 } else { 0.0 };
            orthonormality_error =
                orthonormality_error.max((dot(&a.shape_free, mb) - target).abs());
        }
    }
    orthonormality_error
}
