//! [`IntegrateError`] of the time integrators (`crate::integrate`) and of the
//! factorisations they run (`crate::linalg`): below both, importing nothing of the crate.

/// Any failure of a time integrator or of the factorisations it runs ([`crate::linalg`]).
/// Each variant says where it happened and what to check next; none of them is a panic.
/// DOF indices are the operator's rows, 0-based (the free-DOF numbering after
/// constraint elimination); times are in the operator's unit (s in coil).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrateError {
    /// A stop was requested (`coil_io::cancel`: Ctrl-C from Python).
    #[error("interrupted (Ctrl-C) at step {step}")]
    Interrupted {
        /// The step reached.
        step: usize,
    },

    /// The time step is zero, negative or not finite.
    #[error("time step dt = {dt} must be finite and > 0")]
    InvalidTimeStep {
        /// The rejected time step (s in coil).
        dt: f64,
    },

    /// A scheme parameter lies outside the range where the scheme is unconditionally
    /// stable and second-order accurate.
    #[error("{scheme}: {name} = {value} is outside [{min}, {max}]")]
    InvalidParameter {
        /// The scheme's name.
        scheme: &'static str,
        /// The parameter's name.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// Lower end of the admissible range.
        min: f64,
        /// Upper end of the admissible range.
        max: f64,
    },

    /// A matrix or vector has the wrong size.
    #[error("{what} has size {found}, expected {expected}")]
    DimensionMismatch {
        /// Which matrix or vector.
        what: &'static str,
        /// The size it must have.
        expected: usize,
        /// The size it has.
        found: usize,
    },

    /// An operator matrix is not symmetric: entry (row, col) differs from (col, row)
    /// by more than round-off.
    #[error(
        "{matrix} is not symmetric: entry ({row}, {col}) = {value:e} but ({col}, {row}) = \
         {transposed:e}; the integrators need symmetric M, C, K with both triangles stored"
    )]
    NotSymmetric {
        /// The matrix's name.
        matrix: &'static str,
        /// Row of the entry (0-based).
        row: usize,
        /// Column of the entry (0-based).
        col: usize,
        /// The entry at (`row`, `col`).
        value: f64,
        /// The entry at (`col`, `row`).
        transposed: f64,
    },

    /// An input holds NaN or infinity.
    #[error("{what} holds a non-finite value at index {index}")]
    NonFiniteInput {
        /// Which input.
        what: &'static str,
        /// Index of the non-finite entry (0-based).
        index: usize,
    },

    /// An operator matrix holds NaN or infinity.
    #[error("{matrix} holds a non-finite value at ({row}, {col})")]
    NonFiniteEntry {
        /// The matrix's name.
        matrix: &'static str,
        /// Row of the non-finite entry (0-based).
        row: usize,
        /// Column of the non-finite entry (0-based).
        col: usize,
    },

    /// A Cholesky pivot was not positive: the matrix is singular or indefinite.
    #[error(
        "{matrix} is not positive definite (Cholesky pivot failed at DOF {dof}); look for an \
         unconstrained mechanism, a DOF with neither mass nor stiffness, or negative \
         mass/stiffness near that DOF"
    )]
    NotPositiveDefinite {
        /// The matrix's name.
        matrix: &'static str,
        /// The operator row (0-based) whose pivot failed.
        dof: usize,
    },

    /// The sparse factorisation could not run (out of memory, index overflow).
    #[error("sparse factorisation of {matrix} failed: {message}")]
    Factorization {
        /// The matrix's name.
        matrix: &'static str,
        /// faer's message.
        message: String,
    },

    /// The state became NaN or infinite during stepping (diverging force, overflow).
    #[error(
        "non-finite state at t = {time} (step {step}), DOF {dof}; check the applied force \
         history at that time"
    )]
    NonFiniteState {
        /// The step at which the state became non-finite.
        step: usize,
        /// The time of that step (s in coil).
        time: f64,
        /// The first non-finite operator row (0-based; the mode's index in modal superposition).
        dof: usize,
    },

    /// A modal frequency or damping ratio is negative or not finite.
    #[error("mode {mode}: {name} = {value} must be finite and >= 0")]
    InvalidMode {
        /// The mode's index (0-based).
        mode: usize,
        /// The quantity's name (e.g. `omega`, `zeta`).
        name: &'static str,
        /// The rejected value.
        value: f64,
    },

    /// A requested output DOF lies outside the mode shapes.
    #[error("output DOF {dof} is out of range (mode shapes have {n_dofs} rows)")]
    DofOutOfRange {
        /// The requested output DOF (0-based row).
        dof: usize,
        /// Number of rows of the mode shapes.
        n_dofs: usize,
    },

    /// Nonlinear point laws were given to a scheme whose balance is not at the end of
    /// the step (`alpha_m`, `alpha_f` not both zero).
    #[error(
        "nonlinear point laws need Newmark average acceleration (alpha_m = alpha_f = 0); \
         {scheme} balances the forces at a shifted time, where the one-DOF implicit solve \
         of a law does not apply"
    )]
    PointLawScheme {
        /// The scheme's name.
        scheme: &'static str,
    },

    /// A point law's DOF is out of range or a coefficient is negative or not finite.
    #[error(
        "point law {index} on DOF {dof}: {reason}; coefficients must be finite, the dashpot's and the friction's >= 0, \
         DOFs below the operator size {n_dofs}"
    )]
    InvalidPointLaw {
        /// The law's position in the list given (0-based).
        index: usize,
        /// The operator row (0-based) the law acts on.
        dof: usize,
        /// Number of operator rows.
        n_dofs: usize,
        /// What is wrong with the law.
        reason: &'static str,
    },

    /// A point law's implicit solve failed: a non-finite input, or a softening cubic
    /// spring that lost stability (its tangent stiffness turned negative within the
    /// step's reach).
    #[error(
        "the point law on DOF {dof} has no stable solution at step {step} (t = {time}): \
         a non-finite state, or a softening spring driven beyond its stable amplitude"
    )]
    PointLawUnsolvable {
        /// The step at which the solve failed.
        step: usize,
        /// The time of that step (s in coil).
        time: f64,
        /// The operator row (0-based) the law acts on.
        dof: usize,
    },

    /// The Gauss-Seidel sweeps over several point laws of one step did not converge.
    #[error(
        "the point laws of step {step} (t = {time}) did not converge in {sweeps} \
         Gauss-Seidel sweeps (last change {change:e} N); the laws' DOFs are strongly \
         coupled: try a smaller dt"
    )]
    PointLawsNotConverged {
        /// The step whose sweeps did not converge.
        step: usize,
        /// The time of that step (s in coil).
        time: f64,
        /// Number of sweeps run.
        sweeps: usize,
        /// The last sweep's largest change of a law force (N in coil).
        change: f64,
    },
}
