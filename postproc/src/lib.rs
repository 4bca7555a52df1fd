//! coil-postproc owns signals and records: the record readers (CSV, UFF, MAT), the paper's
//! estimators, spectra, envelopes, signatures, filters, plots (`coil-post`). It may import
//! coil-io only, so it stands beside the solver; the tuner and everything above use it.
//!
//! coil's post-processor: free-decay signals to period, logarithmic decrement, damping ratio,
//! spectra, envelopes and plots.
//!
//! The crate stands alone (no other coil crate but `coil-io`): it reads any CSV with a
//! `time_s` column ([`signal::read_csv`]) and every record format labs store
//! ([`record::read_signal`]), and works on in-memory histories too: every analysis takes a
//! [`signal::Signal`], checked once when it is made. Each module documents its formulation
//! and measured accuracy; `docs/postproc.md` gathers them.
//!
//! - [`signal`]: CSV reading and the checked [`signal::Signal`] every analysis takes.
//! - [`record`]: measured records as labs store them (UFF 58/58b, MAT-files, CSV
//!   dialects, units), the one reader of every command that reads a decay record.
//! - [`offset`]: what constant is removed before analysis ([`offset::Detrend`]).
//! - [`stats`]: the median, the robust white-noise level, a value with its standard error.
//! - [`peaks`]: crests to sub-sample accuracy.
//! - [`decrement`]: the paper's Eqs. 2-3 and an exponential envelope fit.
//! - [`filter`]: zero-phase Butterworth low-, high- and band-pass.
//! - [`differentiate`]: velocity and acceleration from a position record (low-pass and
//!   sixth-order central differences, with their closed-form gain).
//! - [`noise`]: the noise floor of a record whose noise need not be white (Welch spectrum
//!   outside the signal's lines).
//! - [`spectrum`]: windowed, zero-padded amplitude spectrum with interpolated peaks.
//! - [`envelope`]: Hilbert envelope, instantaneous frequency, backbone and damping curves.
//! - [`signature`]: per-cycle amplitude and frequency, loss per cycle, backbone, envelope
//!   shape and side peaks (one module each): what a linear model misses.
//! - [`static_curve`]: force-compression records: stiffness, cubic term, friction.
//! - [`plot`]: PNG/SVG plots with an embedded font.
//! - [`report`]: each `coil-post` command's JSON report and table, and its plots (the
//!   binary only parses arguments, calls these and prints).
//! - [`output`]: temp-file-and-rename writing.

#![warn(missing_docs)]

pub mod decrement;
pub mod differentiate;
pub mod envelope;
pub mod error;
pub mod filter;
mod fit;
pub mod noise;
pub mod offset;
pub mod output;
pub mod peaks;
pub mod plot;
pub mod record;
pub mod report;
pub mod signal;
pub mod signature;
pub mod spectrum;
pub mod static_curve;
pub mod stats;

#[cfg(test)]
mod test_docs;
#[cfg(test)]
mod test_signals;

pub use error::{PostError, Result};
