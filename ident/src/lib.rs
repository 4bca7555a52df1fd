//! coil-ident owns identification from measured records: `diagnose` and which damping law.
//! It may import coil-io, coil-solver, coil-mesher, coil-postproc and coil-tuner; only the
//! command line, Python and the tests sit above it.
//!
//! coil-ident: identification from measured records, above the paper's calibration.
//!
//! - [`diagnose`]: fits the paper's model to a measured case, shows what it misses, names
//!   the physical cause from a catalogue, extends the model and measures the gain
//!   (docs/diagnose.md).
//! - [`law`]: which damping law the decay records of a case support (docs/damping.md);
//!   [`scatter`]: the repeat scatter of zeta it judges the laws with.
//! - [`forced`]: forced records (input and response histories): their diagnosis, the
//!   model driven by any input (`simulate`) and forced response curves (`frc`)
//!   (docs/forced.md).
//! - [`cli`]: the `diagnose`, `damping`, `simulate` and `frc` commands of `coil-tune`.
//!
//! Identification starts from the paper's calibration (the baseline is the tuner's
//! case, FE model and loops), so this crate stands above `coil-tuner`; the laws' predictions
//! for a geometry (the band the paper's report prints) stay below, in `coil_tuner::band`.

#![warn(missing_docs)]

// The tuner's modules that identification builds on, under the names the modules here use.
pub(crate) use coil_tuner::{case, decay, error, fe, loops, output, plots};

pub mod cli;
pub mod diagnose;
pub mod forced;
pub mod law;
pub mod scatter;

pub use coil_tuner::error::{Result, TuneError};
