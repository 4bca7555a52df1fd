//! coil-catenary owns the pantograph-catenary: its model, the head stages, the runs and
//! EN 50318's statistics. It may import coil-io, coil-solver, coil-mesher, coil-postproc and
//! coil-tuner; only the command line and the tests sit above it.
//!
//! The concern end to end: the model builder ([`model`], `coil-mesh catenary`), the head
//! stages from coil's springs ([`head_stage`]), the runs ([`run`], `coil-tune catenary`)
//! and EN 50318's statistics ([`en50318`]).
//!
//! A case ([`case`]) names a catenary and a pantograph ([`model`] specs), the speeds, the
//! time step, the evaluation window, the low-pass filter and the reference ranges. A run
//! ([`run`]) meshes the model at each speed (the static state first: dropper lengths for
//! the presag), solves its STATIC case and its Newmark transient from that state (speeds
//! in parallel), and takes EN 50318's statistics of the contact force and the supports'
//! uplift over the window ([`en50318`]). [`run::write`] puts `catenary.json`, `report.md`,
//! the figures and the histories in the output folder as one set. [`cli`] is the command.
//! [`head_stage`] builds the pantograph's head stage from coil's springs, lumped or
//! Craig-Bampton reduced.
//!
//! Layering: above `coil-mesher` (the spec checks), `coil-solver` (the runs),
//! `coil-postproc` (the filter and plots) and `coil-tuner` (the calibrated spring, the
//! output folder, the error type and the command-line printing shared with the other
//! `coil-tune` commands).
//!
//! Units: the case's fields carry theirs (`_m`, `_km_h`, `_s`, `_hz`); statistics are in
//! N, mm and %.

#![warn(missing_docs)]

pub mod assess;
pub mod case;
pub mod cli;
pub mod en50318;
pub mod head_stage;
pub mod model;
pub mod output;
pub mod run;
pub mod study;
pub mod whole_run;

pub use coil_tuner::error::{Result, TuneError};
