//! coil-solver owns the finite-element engine: decks, the validated model, elements, assembly,
//! analyses, integrators, reduction, result files (`coil-solve`). It may import coil-io only;
//! the mesher, the tuner and everything above use it.
//!
//! coil-solver: a deck-driven finite-element engine in MSC Marc's style for 3D beam
//! models of helical springs: two-node beams (Marc types 52 and 98), point masses,
//! rigid ties, static, modal and transient analyses, Rayleigh damping per element set.
//!
//! Data flow (dependencies point one way):
//! deck text -> [`deck`] (located tokens -> validated [`model::Model`]) ->
//! [`element`] (pure local matrices) -> [`assembly`] through the [`dof`] map (constraints
//! eliminated onto free DOFs) -> [`analysis`] (static, modal, transient, via the
//! operator-level [`integrate`] schemes and the sparse [`linalg`] wrappers) ->
//! [`results`] and [`vtk`] files.

#![warn(missing_docs)]

pub mod analysis;
pub mod assembly;
pub mod deck;
pub mod dof;
pub mod element;
pub mod error;
pub mod integrate;
pub mod linalg;
pub mod model;
pub mod reduce;
pub mod results;
pub mod vtk;
pub mod wire;

pub use error::Error;
pub use model::Model;
