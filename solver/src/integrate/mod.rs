//! Time integrators at the operator level: they see `M a + C v + K u = f(t)` as sparse
//! matrices and a load callback, never the finite-element model.
//!
//! * [`stepper`]: the stepper core, direct implicit integration by the generalised-alpha
//!   family ([`Scheme::AverageAcceleration`], the default; [`Scheme::Hht`];
//!   [`Scheme::GeneralizedAlpha`]), one predictor-solve-corrector step, the effective
//!   matrix factored once per `dt` with its ordering reused, on one of two engines:
//!   `banded` (beam models: the envelope Cholesky and block panels of
//!   [`crate::linalg`], one banded product per step) or `sparse` (the simplicial sparse
//!   Cholesky of [`crate::linalg`], one fused pass over the merged pattern of
//!   `operator`).
//! * [`dense`]: the same average-acceleration step on small dense operators (reduced
//!   models run thousands of times inside a fit).
//! * [`scheme`]: the schemes and the one place their coefficients are derived;
//!   [`state`]: the `(t, u, v, a)` a step carries; [`point`]: the nonlinear point laws
//!   and the one end-of-step solve both steppers use.
//! * [`modal_superposition`]: modal superposition, each mode integrated exactly
//!   (closed-form state-transition matrix of the damped oscillator, exact for loads
//!   linear between samples).
//!
//! Within the module the arrows point one way: `stepper -> {banded, sparse} ->
//! {operator, scheme, state}`, the engines -> [`crate::linalg`] (every factorisation)
//! -> [`crate::error`]; `dense -> {scheme, point}`; nothing imports `stepper` or this
//! module's root.
//!
//! # Operators
//! `M`, `C` (optional), `K` are square, symmetric, finite, of one size `n`, in
//! compressed sparse column form (`faer::sparse::SparseColMatRef<usize, f64>`); their
//! patterns may differ. They are given as their upper triangles, the crate's convention
//! ([`Stepper::new_upper`]: the finite-element system's matrices as stored), or, for a
//! caller holding full matrices, with both triangles stored and checked symmetric to a
//! relative 1e-10 of the largest entry ([`Stepper::new`]). Inside, the engines keep the
//! lower triangle, the side their factors are written in (`crate::linalg`, "Triangle
//! convention"). Rows and columns are the engine's free DOFs after constraint elimination,
//! 0-based. Units are consistent (coil: mm, N, tonne, s), so `u` in mm, `v` in mm/s,
//! `a` in mm/s^2, `f` in N.
//!
//! The derivations, parameters and measured numerical damping and period error are in
//! `docs/integrators.md`.

mod banded;
pub mod dense;
pub mod modal_superposition;
mod operator;
pub mod point;
pub mod scheme;
mod sparse;
pub mod state;
pub mod stepper;

#[cfg(test)]
mod engine_tests;
#[cfg(test)]
pub(crate) mod tests;

pub use crate::error::integrate::IntegrateError;
pub use dense::{DenseError, DenseStepper};
pub use operator::Operators;
pub use point::{PointLaw, PointSolve};
pub use scheme::{Coefficients, Scheme};
pub use state::State;
pub use stepper::{integrate, Stepper};
