//! The tuner's error types: [`CaseError`] for the case, record and variants readers and
//! [`TuneError`] for everything a command does. Each variant says where (file, line,
//! field, loop, grid point) and what to do next; nothing in the library panics on user
//! data. This module sits at the bottom of the crate: it imports only the field errors
//! it wraps.

use crate::fields::FieldError;
use std::path::PathBuf;

/// Everything that can be wrong with a case, a variants file or a record.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    #[error("{}: cannot read the file: {source}", path.display())]
    /// Reading or writing failed.
    Io {
        /// The file.
        path: PathBuf,
        /// Where the values come from (a citation), if given.
        source: std::io::Error,
    },
    #[error("{}:{line}:{column}: invalid JSON: {message}", path.display())]
    /// A file that is not valid JSON.
    Syntax {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// Its column (1-based).
        column: usize,
        /// What is wrong and what was expected.
        message: String,
    },
    #[error(transparent)]
    /// A field missing or out of range.
    Field(#[from] FieldError),
    /// An input outside its limits or its folder (docs/files.md).
    #[error(transparent)]
    Input(#[from] coil_io::ConfineError),
    /// A record file (decay) that the post-processor cannot read.
    #[error(transparent)]
    Record(#[from] coil_postproc::PostError),
    /// A decay record whose columns or time stamps are wrong.
    #[error("{}:{line}: {problem}; expected {expected}", path.display())]
    DecayRecord {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// What is wrong.
        problem: String,
        /// What was expected.
        expected: String,
    },
    /// A static record that cannot be read.
    #[error("{}:{line}: {problem}; expected {expected}", path.display())]
    StaticRecord {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// What is wrong.
        problem: String,
        /// What was expected.
        expected: String,
    },
}

impl CaseError {
    /// A bounded read's error: an unreadable file stays [`CaseError::Io`].
    pub(crate) fn input(e: coil_io::ConfineError) -> CaseError {
        match e {
            coil_io::ConfineError::Io { path, source } => CaseError::Io { path, source },
            other => CaseError::Input(other),
        }
    }
}

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
        /// What was being done.
        context: String,
        #[source]
        /// The underlying error.
        source: Box<coil_solver::analysis::SolveError>,
    },
    /// A time integration failed.
    #[error("{context}: {source}")]
    Integrate {
        /// What was being done.
        context: String,
        #[source]
        /// The underlying error.
        source: coil_solver::integrate::IntegrateError,
    },
    /// The post-processor could not analyse a history.
    #[error("{context}: {source}")]
    Post {
        /// What was being done.
        context: String,
        #[source]
        /// The underlying error.
        source: coil_postproc::PostError,
    },
    /// A run did not produce what the loop needs (no stiffness, no axial mode).
    #[error("{context}: {what}")]
    Missing {
        /// What was being done.
        context: String,
        /// What is wrong.
        what: String,
    },
    /// A loop did not reach its tolerance.
    #[error(
        "{name}: no convergence after {iterations} iterations (last relative error {last_error:.3e}, \
         tolerance {tolerance:.1e}); {hint}"
    )]
    NotConverged {
        /// The loop.
        name: String,
        /// Iterations run.
        iterations: usize,
        /// The last relative error.
        last_error: f64,
        /// Relative tolerance.
        tolerance: f64,
        /// What to do next.
        hint: String,
    },
    /// An option or setting out of its range.
    #[error("{0}")]
    Invalid(String),
    /// Writing or reading an output file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        #[source]
        /// The underlying error.
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
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// What is wrong.
        problem: String,
        /// What to do next.
        hint: String,
    },
    /// A procedure file that does not parse, at a line.
    #[error("{}:{line}: {source}", path.display())]
    Procedure {
        /// The procedure file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// What is wrong there.
        #[source]
        source: ProcedureError,
    },
    /// A JSON file that does not parse, at a line.
    #[error("{}:{line}: {message}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A procedure step that failed, with its line.
    #[error("{}:{line}: {source}", path.display())]
    AtLine {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        #[source]
        /// The underlying error.
        source: Box<TuneError>,
    },
    /// A diagnosis step that failed after the case's records were read and checked.
    #[error("{}: {source}", case.display())]
    InCase {
        /// The case file.
        case: PathBuf,
        #[source]
        /// The underlying error.
        source: Box<TuneError>,
    },
    /// A plot could not be drawn.
    #[error("{}: cannot draw the plot: {message}", path.display())]
    Plot {
        /// The file.
        path: PathBuf,
        /// What is wrong and what was expected.
        message: String,
    },
}

/// Why a line of a procedure file does not parse (`docs/procedures.md`). The file and line
/// are added by [`TuneError::Procedure`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProcedureError {
    /// A `"` without its closing `"`.
    #[error("a quoted word is not closed; expected a closing `\"`")]
    UnclosedQuote,
    /// A word that should be a finite number.
    #[error("`{word}` is not a number; expected {expected}")]
    NotANumber {
        /// The word as written.
        word: String,
        /// What the command expects there.
        expected: String,
    },
    /// A number that should be positive.
    #[error("{value}: expected a positive {what}")]
    NotPositive {
        /// The number.
        value: f64,
        /// The quantity and its unit.
        what: String,
    },
    /// A first word that is no command.
    #[error("unknown command `{name}`; expected one of: {known}")]
    UnknownCommand {
        /// The word.
        name: String,
        /// The commands, comma-separated.
        known: String,
    },
    /// A `set` of a name that is no setting.
    #[error("unknown setting `{name}`; expected one of: {known}")]
    UnknownSetting {
        /// The name.
        name: String,
        /// The settings, comma-separated.
        known: String,
    },
    /// A `set` whose value is not of the setting's kind.
    #[error("set {name} {value}: expected {expected}")]
    BadSetting {
        /// The setting.
        name: String,
        /// The value as written.
        value: String,
        /// What the setting takes.
        expected: String,
    },
    /// A line with too few or too many words.
    #[error("`{text}` takes {takes}; expected `{usage}`")]
    WordCount {
        /// The line's words.
        text: String,
        /// How many words the command takes.
        takes: String,
        /// The command's form.
        usage: String,
    },
    /// A line that is not of the command's form.
    #[error("`{text}`: expected `{usage}`")]
    Usage {
        /// The line's words.
        text: String,
        /// The command's form.
        usage: String,
    },
    /// Words left over after a complete command.
    #[error("unexpected `{text}`; expected `{usage}`")]
    Unexpected {
        /// The extra words.
        text: String,
        /// The command's form.
        usage: String,
    },
    /// A `tolerance` outside (0, 1).
    #[error("tolerance {value}: expected a relative tolerance in (0, 1)")]
    Tolerance {
        /// The number.
        value: f64,
    },
    /// `solve` of an analysis that is none of the three.
    #[error("solve {word}: expected static, modal or transient")]
    Analysis {
        /// The word.
        word: String,
    },
    /// A grid axis (`START:STEP:END`) that does not parse.
    #[error("{0}")]
    Axis(String),
    /// A grid whose Rayleigh coefficient range starts below zero.
    #[error(
        "{what} {axis}: a negative Rayleigh coefficient is negative damping (energy \
         created); expected a range starting at 0 or above"
    )]
    NegativeRayleigh {
        /// `alpha` or `beta`.
        what: &'static str,
        /// The axis as written back.
        axis: String,
    },
    /// A target damping ratio of 1 or more.
    #[error("zeta {value}: expected a damping ratio below 1")]
    Overdamped {
        /// The number.
        value: f64,
    },
    /// A file or folder name that would leave the output folder.
    #[error("{reason}; expected {expected}")]
    Outside {
        /// Why the name is refused.
        reason: String,
        /// What the command expects there.
        expected: String,
    },
    /// A file or folder name with control characters.
    #[error("`{text}`: expected {expected}")]
    BadName {
        /// The name, shortened and sanitised.
        text: String,
        /// What the command expects there.
        expected: String,
    },
    /// A grid name that cannot name files.
    #[error(
        "grid name `{text}`: expected letters, digits, `_`, `-` or `.` (at most 64, not \
         starting with `.`): it names the grid's files inside the output folder"
    )]
    GridName {
        /// The name, shortened and sanitised.
        text: String,
    },
    /// Two grids of one procedure with the same name.
    #[error("a grid named {name} appears twice; give each grid its own `name`")]
    DuplicateGrid {
        /// The name.
        name: String,
    },
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
