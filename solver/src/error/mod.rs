//! The crate's error types. Each stage's typed error lives below every module that
//! returns it: [`solve`] ([`SolveError`] and the DOF labels of its messages) and
//! [`integrate`] ([`IntegrateError`]) import nothing above them, and the crate's own
//! modules import them from there. This root gathers them, with the deck's error, in
//! [`Error`] for callers that drive several stages (it sits above the deck, so nothing
//! inside the crate imports this root).

pub mod integrate;
pub mod solve;

pub use integrate::IntegrateError;
pub use solve::{dof_name, SolveError, DOF_NAMES};

use std::path::PathBuf;

/// Any error of coil-solver.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or validating a deck failed.
    #[error(transparent)]
    Deck(#[from] crate::deck::DeckError),
    /// An analysis failed (mechanism, failed eigensolve, non-finite state, ...).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// The output folder is held by another run, or a file cannot be put there.
    #[error(transparent)]
    Output(#[from] coil_io::SetError),
    /// A result holds a non-finite number: nothing is written.
    #[error("{file}: a non-finite number (NaN or inf) at byte {at} of the results; nothing was written (the model or its loads are out of range)")]
    NonFinite {
        /// The file that would have been written.
        file: String,
        /// Byte offset of the number.
        at: usize,
    },
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}
