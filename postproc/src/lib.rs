//! coil's post-processor: free-decay signals to period, logarithmic decrement, damping ratio,
//! spectra, envelopes and plots.
//!
//! The crate stands alone (no other coil crate): it reads any CSV with a `time_s` column
//! ([`signal::read_csv`]) and works on plain slices, so the tuner can call it on in-memory
//! histories. Each module documents its formulation and measured accuracy; `docs/postproc.md`
//! gathers them.
//!
//! - [`signal`]: CSV reading, time-axis checks, offset removal.
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
//!   shape and side peaks: what a linear model misses.
//! - [`static_curve`]: force-compression records: stiffness, cubic term, friction.
//! - [`plot`]: PNG/SVG plots with an embedded font.
//! - [`output`]: temp-file-and-rename writing.

pub mod decrement;
pub mod differentiate;
pub mod envelope;
pub mod error;
pub mod filter;
mod fit;
pub mod noise;
pub mod output;
pub mod peaks;
pub mod plot;
pub mod signal;
pub mod signature;
pub mod spectrum;
pub mod static_curve;

#[cfg(test)]
mod test_signals;

pub use error::{PostError, Result};
