//! coil-catenary owns the pantograph-catenary: its model, the head stages, the runs and
//! EN 50318's statistics. It may import coil-io, coil-solver, coil-mesher, coil-postproc and
//! coil-tuner; only the command line and the tests sit above it.
//!
//! coil-catenary: pantograph-catenary runs (`coil-tune catenary CASE --out DIR`,
//! docs/catenary.md, "Runs").
//!
//! A case ([`case`]) names a catenary and a pantograph (`coil_mesher::catenary` specs),
//! the speeds, the time step, the evaluation window, the low-pass filter and the
//! reference ranges. A run ([`run`]) meshes the model at each speed (the static state
//! first: dropper lengths for the presag), solves its STATIC case and its Newmark
//! transient from that state (speeds in parallel), and takes EN 50318's statistics of
//! the contact force and the supports' uplift over the window
//! (`coil_postproc::en50318`). [`run::write`] puts `catenary.json`, `report.md`, the
//! figures and the histories in the output folder as one set. [`cli`] is the command.
//! [`head_stage`] puts coil's springs, Craig-Bampton reduced, in the pantograph's head
//! stage.
//!
//! Layering: above `coil-mesher` (the model), `coil-solver` (the runs), `coil-postproc`
//! (the statistics and figures) and `coil-tuner` (the output folder, the error type and
//! the command-line printing shared with the other `coil-tune` commands).
//!
//! Units: the case's fields carry theirs (`_m`, `_km_h`, `_s`, `_hz`); statistics are in
//! N, mm and %.

#![warn(missing_docs)]

pub mod case;
pub mod cli;
pub mod head_stage;
pub mod run;

pub use coil_tuner::error::{Result, TuneError};
