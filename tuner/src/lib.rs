//! coil-tuner owns the paper's procedure: cases and records, the FE spring model, the loops,
//! the Rayleigh grids, studies and the damping-law band. It may import coil-io, coil-solver,
//! coil-mesher and coil-postproc; identification, design and the catenary sit above it.
//!
//! coil-tuner: the paper's Figure 6 validation procedure on coil's own solver.
//!
//! - [`band`]: the damping laws and what each predicts for a geometry (the band beside
//!   Table 4); identification from measured records is the `coil-ident` crate above this one.
//!
//! - [`case`]: reading a measured case (`docs/measured-case.md`) and a variants file.
//! - [`study`]: a sweep as independent tasks, its shards and their merge; [`tolerance`]:
//!   the tolerance study of the Table 4 springs.

#![warn(missing_docs)]

pub mod case;
pub mod error;
pub mod fe;
pub mod fields;
pub mod json;
pub mod loops;
pub mod output;

pub use error::{Result, TuneError};
pub mod band;
pub mod calibrate;
pub mod cli;
pub mod damping;
pub mod decay;
pub mod en15800;
pub mod grid;
pub mod paper;
pub mod plots;
pub mod procedure;
pub mod report;
pub mod study;
pub mod sweep;
pub mod tolerance;
