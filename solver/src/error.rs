//! The crate's error type. Each stage has its own typed error carrying locations;
//! this enum gathers them for callers that drive several stages.

use std::path::PathBuf;

/// Any error of coil-solver.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or validating a deck failed.
    #[error(transparent)]
    Deck(#[from] crate::deck::DeckError),
    /// An analysis failed (mechanism, failed eigensolve, non-finite state, ...).
    #[error(transparent)]
    Solve(#[from] crate::analysis::SolveError),
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
