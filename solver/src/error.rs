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
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}
