//! coil-tuner: the paper's Figure 6 validation procedure on coil's own solver.
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
pub mod calibrate;
pub mod cli;
pub mod damping;
pub mod decay;
pub mod diagnose;
pub mod grid;
pub mod law;
pub mod paper;
pub mod plots;
pub mod procedure;
pub mod report;
pub mod scatter;
pub mod study;
pub mod sweep;
pub mod tolerance;
