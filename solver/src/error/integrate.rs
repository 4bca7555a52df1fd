//! [`IntegrateError`] of the time integrators (`crate::integrate`) and of the
//! factorisations they run (`crate::linalg`): below both, importing nothing of the crate.

/// Any failure of a time integrator or of the factorisations it runs ([`crate::linalg`]).
/// Each variant says where it happened and what to check next; none of them is a panic.
/// DOF indices are the operator's rows, 0-based (the free-DOF numbering after
/// constraint elimination); times are in the operator's unit (s in coil).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrateError {
    /// The time step is zero, negative or not finite.
    #[error("time step dt = {dt} must be finite and > 0")]
    InvalidTimeStep { dt: f64 },

    /// A scheme parameter lies outside the range where the scheme is unconditionally
    /// stable and second-order accurate.
    #[error("{scheme}: {name} = {value} is outside [{min}, {max}]")]
    InvalidParameter {
        scheme: &'static str,
        name: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },

    /// A matrix or vector has the wrong size.
    #[error("{what} has size {found}, expected {expected}")]
    DimensionMismatch {
        what: &'static str,
        expected: usize,
        found: usize,
    },

    /// An operator matrix is not symmetric: entry (row, col) differs from (col, row)
    /// by more than round-off.
    #[error(
        "{matrix} is not symmetric: entry ({row}, {col}) = {value:e} but ({col}, {row}) = \
         {transposed:e}; the integrators need symmetric M, C, K with both triangles stored"
    )]
    NotSymmetric {
        matrix: &'static str,
        row: usize,
        col: usize,
        value: f64,
        transposed: f64,
    },

    /// An input holds NaN or infinity.
    #[error("{what} holds a non-finite value at index {index}")]
    NonFiniteInput { what: &'static str, index: usize },

    /// An operator matrix holds NaN or infinity.
    #[error("{matrix} holds a non-finite value at ({row}, {col})")]
    NonFiniteEntry {
        matrix: &'static str,
        row: usize,
        col: usize,
    },

    /// A Cholesky pivot was not positive: the matrix is singular or indefinite.
    #[error(
        "{matrix} is not positive definite (Cholesky pivot failed at DOF {dof}); look for an \
         unconstrained mechanism, a DOF with neither mass nor stiffness, or negative \
         mass/stiffness near that DOF"
    )]
    NotPositiveDefinite { matrix: &'static str, dof: usize },

    /// The sparse factorisation could not run (out of memory, index overflow).
    #[error("sparse factorisation of {matrix} failed: {message}")]
    Factorization {
        matrix: &'static str,
        message: String,
    },

    /// The state became NaN or infinite during stepping (diverging force, overflow).
    #[error(
        "non-finite state at t = {time} (step {step}), DOF {dof}; check the applied force \
         history at that time"
    )]
    NonFiniteState { step: usize, time: f64, dof: usize },

    /// A modal frequency or damping ratio is negative or not finite.
    #[error("mode {mode}: {name} = {value} must be finite and >= 0")]
    InvalidMode {
        mode: usize,
        name: &'static str,
        value: f64,
    },

    /// A requested output DOF lies outside the mode shapes.
    #[error("output DOF {dof} is out of range (mode shapes have {n_dofs} rows)")]
    DofOutOfRange { dof: usize, n_dofs: usize },

    /// Nonlinear point laws were given to a scheme whose balance is not at the end of
    /// the step (`alpha_m`, `alpha_f` not both zero).
    #[error(
        "nonlinear point laws need Newmark average acceleration (alpha_m = alpha_f = 0); \
         {scheme} balances the forces at a shifted time, where the one-DOF implicit solve \
         of a law does not apply"
    )]
    PointLawScheme { scheme: &'static str },

    /// A point law's DOF is out of range or a coefficient is negative or not finite.
    #[error(
        "point law {index} on DOF {dof}: {reason}; coefficients must be finite, the dashpot's and the friction's >= 0, \
         DOFs below the operator size {n_dofs}"
    )]
    InvalidPointLaw {
        index: usize,
        dof: usize,
        n_dofs: usize,
        reason: &'static str,
    },

    /// A point law's implicit solve failed: a non-finite input, or a softening cubic
    /// spring that lost stability (its tangent stiffness turned negative within the
    /// step's reach).
    #[error(
        "the point law on DOF {dof} has no stable solution at step {step} (t = {time}): \
         a non-finite state, or a softening spring driven beyond its stable amplitude"
    )]
    PointLawUnsolvable { step: usize, time: f64, dof: usize },

    /// The Gauss-Seidel sweeps over several point laws of one step did not converge.
    #[error(
        "the point laws of step {step} (t = {time}) did not converge in {sweeps} \
         Gauss-Seidel sweeps (last change {change:e} N); the laws' DOFs are strongly \
         coupled: try a smaller dt"
    )]
    PointLawsNotConverged {
        step: usize,
        time: f64,
        sweeps: usize,
        change: f64,
    },
}
