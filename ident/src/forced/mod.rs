//! Forced records: a shaker's or a servo-hydraulic machine's input and response histories
//! in, the cause out, and the model driven by any input (docs/forced.md).
//!
//! - [`records`]: the `records.forced` entries of a case and the histories they name.
//! - [`model`]: the lumped single-mode oscillator, the reduced FE spring in modal form,
//!   and their file (`model.json`).
//! - [`spring`]: a case's spring meshed, reduced and put in modal form.
//! - [`simulate`]: the model under a sampled input (RK4, first-order hold).
//! - [`fit`]: output-error fits (linear start, then each effect).
//! - [`frf`]: H1 per input level and the restoring force (evidence and signatures).
//! - [`lines`]: the coupling's signature, its second line in every record's H1.
//! - [`run`]: the diagnosis (catalogue, four tests, the cause).
//! - [`report`]: diagnosis.json, report.md, model.json, model_linear.json.
//! - [`hb`] and [`frc`]: harmonic balance (AFT) and its continuation, stability and
//!   backbone.
//! - [`commands`]: `simulate` and `frc` on a model file.
//!
//! Dependencies run one way: `model` at the bottom, then `spring`, `simulate`, `hb`, `records`,
//! `fit`, `frf`, `lines`, `frc`, `run`, `report`, `commands`.

pub mod commands;
pub mod fit;
pub mod frc;
pub mod frf;
pub mod hb;
pub mod lines;
pub mod model;
pub mod records;
pub mod report;
pub mod run;
pub mod simulate;
pub mod spring;

pub use records::lists_forced;
pub use run::{diagnose_case, diagnose_forced, ForcedOutcome, ForcedSettings};
