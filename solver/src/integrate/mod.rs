//! Time integrators at the operator level: they see `M a + C v + K u = f(t)` as sparse
//! matrices and a load callback, never the finite-element model.
//!
//! * [`newmark`]: direct implicit integration by the generalised-alpha family
//!   ([`Scheme::AverageAcceleration`], the default; [`Scheme::Hht`];
//!   [`Scheme::GeneralizedAlpha`]), one predictor-solve-corrector step, the effective
//!   matrix factored once per `dt` with its ordering reused; banded operators (beam
//!   models) run on a banded engine with one banded product per step.
//! * [`modal`]: modal superposition, each mode integrated exactly (closed-form
//!   state-transition matrix of the damped oscillator, exact for loads linear between
//!   samples).
//!
//! # Operators
//! `M`, `C` (optional), `K` are square, symmetric (both triangles stored; checked to a
//! relative 1e-10 of the largest entry), finite, of one size `n`, in compressed sparse
//! column form (`faer::sparse::SparseColMatRef<usize, f64>`); their patterns may
//! differ. Rows and columns are the engine's free DOFs after constraint elimination,
//! 0-based. Units are consistent (coil: mm, N, tonne, s), so `u` in mm, `v` in mm/s,
//! `a` in mm/s^2, `f` in N.
//!
//! The derivations, parameters and measured numerical damping and period error are in
//! `docs/integrators.md`.

mod banded;
mod blocked;
pub mod error;
mod factor;
pub mod modal;
pub mod newmark;
mod operator;
pub mod point;
mod profile;
mod sparse;

#[cfg(test)]
mod tests;

use faer::sparse::SparseColMatRef;

pub use error::IntegrateError;
pub use newmark::{integrate, Coefficients, Scheme, State, Stepper};
pub use point::{PointLaw, PointSolve};

/// The structural operators of `M a + C v + K u = f(t)`.
#[derive(Debug, Clone, Copy)]
pub struct Operators<'a> {
    /// Mass matrix: symmetric positive semi-definite; zero columns mark massless DOFs.
    pub m: SparseColMatRef<'a, usize, f64>,
    /// Viscous damping matrix (symmetric positive semi-definite), or `None` for none.
    pub c: Option<SparseColMatRef<'a, usize, f64>>,
    /// Stiffness matrix: symmetric positive semi-definite.
    pub k: SparseColMatRef<'a, usize, f64>,
}
