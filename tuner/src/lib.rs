//! coil-tuner: the paper's Figure 6 validation procedure on coil's own solver.
//!
//! - [`band`]: the damping laws and what each predicts for a geometry (the band beside
//!   Table 4); identification from measured records is the `coil-ident` crate above this one.
//!
//! - [`head_stage`]: the pantograph head stage (K of four springs in parallel, the damping
//!   band's zeta and dashpots) per spring, for a catenary run.
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
pub mod head_stage;
pub mod head_stage_reduced;
pub mod paper;
pub mod plots;
pub mod procedure;
pub mod report;
pub mod study;
pub mod sweep;
pub mod tolerance;
