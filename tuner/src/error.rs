//! The tuner's one error type. Each variant says where (file, line, field, loop, grid
//! point) and what to do next; nothing in the library panics on user data.

use crate::case::CaseError;
use std::path::PathBuf;

/// Everything that can stop a tuner command.
#[derive(Debug, thiserror::Error)]
pub enum TuneError {
    /// The case or variants file is unreadable or invalid.
    #[error(transparent)]
    Case(#[from] CaseError),
    /// The spring cannot be meshed with these values.
    #[error("cannot mesh the spring: {0}")]
    Spec(#[from] coil_mesher::SpecError),
    /// The solver refused or failed a run.
    #[error("{context}: {source}")]
    Solve {
        context: String,
        #[source]
        source: Box<coil_solver::analysis::SolveError>,
    },
    /// A time integration failed.
    #[error("{context}: {source}")]
    Integrate {
        context: String,
        #[source]
        source: coil_solver::integrate::IntegrateError,
    },
    /// The post-processor could not analyse a history.
    #[error("{context}: {source}")]
    Post {
        context: String,
        #[source]
        source: coil_postproc::PostError,
    },
    /// A run did not produce what the loop needs (no stiffness, no axial mode).
    #[error("{context}: {what}")]
    Missing { context: String, what: String },
    /// A loop did not reach its tolerance.
    #[error(
        "{name}: no convergence after {iterations} iterations (last relative error {last_error:.3e}, \
         tolerance {tolerance:.1e}); {hint}"
    )]
    NotConverged {
        name: String,
        iterations: usize,
        last_error: f64,
        tolerance: f64,
        hint: String,
    },
    /// An option or setting out of its range.
    #[error("{0}")]
    Invalid(String),
    /// Writing or reading an output file failed.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The output folder is held by another run, or a file cannot be put there.
    #[error(transparent)]
    Output(#[from] coil_io::SetError),
    /// An output file cannot be written (or would replace a non-regular file).
    #[error(transparent)]
    Write(#[from] coil_io::WriteError),
    /// An input file outside its folder, too large, or not a regular file.
    #[error(transparent)]
    Input(#[from] coil_io::ConfineError),
    /// A grid journal that cannot be resumed.
    #[error("{}:{line}: {problem}; {hint}", path.display())]
    Journal {
        path: PathBuf,
        line: usize,
        problem: String,
        hint: String,
    },
    /// A procedure file error at a line.
    #[error("{}:{line}: {message}", path.display())]
    Procedure {
        path: PathBuf,
        line: usize,
        message: String,
    },
    /// A procedure step that failed, with its line.
    #[error("{}:{line}: {source}", path.display())]
    AtLine {
        path: PathBuf,
        line: usize,
        #[source]
        source: Box<TuneError>,
    },
    /// A diagnosis step that failed after the case's records were read and checked.
    #[error("{}: {source}", case.display())]
    InCase {
        case: PathBuf,
        #[source]
        source: Box<TuneError>,
    },
    /// A plot could not be drawn.
    #[error("{}: cannot draw the plot: {message}", path.display())]
    Plot { path: PathBuf, message: String },
}

impl TuneError {
    /// Wraps an I/O error with its path.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        TuneError::Io {
            path: path.into(),
            source,
        }
    }
}

/// The tuner's result type.
pub type Result<T, E = TuneError> = std::result::Result<T, E>;
