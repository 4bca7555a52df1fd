//! Procedure files: a small line-oriented command language in the spirit of Mentat's
//! procedure files, documented in `docs/procedures.md` (written from the tables here:
//! [`COMMANDS`] and [`SETTINGS`]).
//!
//! One command per line; `#` starts a comment; words are separated by blanks; a word
//! with blanks goes in double quotes. The whole file is parsed and checked first, so a
//! typo on line 40 is reported (`file:40: ...`) before line 1 runs anything. Errors while
//! running name the line too.
//!
//! The commands call the same library functions as `coil-tune calibrate` (loops 1 and 2,
//! [`crate::damping::Loop3`] for grids and the choice), so `figure6.proc` and `calibrate`
//! give the same E, mass, alpha and beta. Grids are journaled in the output folder, so a
//! procedure rerun after a kill resumes its grids; a user can edit the file and rerun any
//! step.
//!
//! # Layout
//! - `words`: a line's words and the small values commands read from them.
//! - `settings`: the [`SETTINGS`] table, parsing a value by its kind, applying it.
//! - `session`: the interpreter's state while a procedure runs.
//! - `commands`: [`COMMANDS`], one entry per command (name, form, meaning, parse, run and
//!   its tests together).
//! - here: a file to a [`Procedure`] ([`parse`], [`read`]) and running it ([`run`]).

mod commands;
mod session;
mod settings;
mod words;

pub use commands::{parse_grid, Command, COMMANDS};
pub use settings::{Kind, SetValue, SettingSpec, SETTINGS};
pub use words::TargetValue;

use crate::calibrate::CalibrateSettings;
use crate::damping::{DampingReport, RunControl};
use crate::error::{Result, TuneError};
use crate::fe::SpringState;
use crate::loops::LoopReport;
use crate::output::OutDir;
use commands::{parse_line, Action, Parsing};
use serde::Serialize;
use session::Session;
use std::path::{Path, PathBuf};

/// A parsed line.
#[derive(Debug)]
pub struct Statement {
    /// Its line in the file (1-based).
    pub line: usize,
    /// What it does.
    action: Box<dyn Action>,
}

/// A parsed procedure file.
#[derive(Debug)]
pub struct Procedure {
    /// The file (for messages; its folder anchors `case`).
    pub path: PathBuf,
    /// Its commands in order.
    pub statements: Vec<Statement>,
}

/// Parses a procedure's text; `path` names it in errors.
pub fn parse(text: &str, path: &Path) -> Result<Procedure> {
    let mut statements = Vec::new();
    let mut parsing = Parsing::default();
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let fail = |source| TuneError::Procedure {
            path: path.to_path_buf(),
            line,
            source,
        };
        let w = words::words(raw).map_err(fail)?;
        if w.is_empty() {
            continue;
        }
        let action = parse_line(&w, &mut parsing).map_err(fail)?;
        statements.push(Statement { line, action });
    }
    Ok(Procedure {
        path: path.to_path_buf(),
        statements,
    })
}

/// Reads and parses a procedure file.
pub fn read(path: &Path) -> Result<Procedure> {
    let text = std::fs::read_to_string(path).map_err(|e| TuneError::io(path, e))?;
    parse(&text, path)
}

/// What a procedure run leaves.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProcedureResult {
    /// The procedure file.
    pub procedure: String,
    /// The case's name, if one was read.
    pub case: Option<String>,
    /// The final values (E, mass, alpha, beta with the geometry).
    pub state: Option<SpringState>,
    /// The settings at the end.
    pub settings: CalibrateSettings,
    /// Loops run by `tune`, in order.
    pub loops: Vec<LoopReport>,
    /// The last `choose best`.
    pub damping: Option<DampingReport>,
}

/// Runs a parsed procedure. `out` (from the command line) overrides the file's `out`;
/// without either, files go to `out/<procedure name>`. `say` receives each printed line.
pub fn run(
    procedure: &Procedure,
    out: Option<&Path>,
    control: &RunControl,
    say: &mut dyn FnMut(&str),
) -> Result<ProcedureResult> {
    let out = match out {
        Some(dir) => Some(OutDir::create(dir)?),
        None => None,
    };
    let mut session = Session::new(&procedure.path, out, control);
    for statement in &procedure.statements {
        statement
            .action
            .run(&mut session, say)
            .map_err(|source| TuneError::AtLine {
                path: procedure.path.clone(),
                line: statement.line,
                source: Box::new(source),
            })?;
    }
    let result = ProcedureResult {
        procedure: procedure.path.display().to_string(),
        case: session.case.as_ref().map(|c| c.name.clone()),
        state: session.state,
        settings: session.settings.clone(),
        loops: session.loops.clone(),
        damping: session.damping.clone(),
    };
    let out = session.out()?;
    let json = serde_json::to_string_pretty(&result)
        .map_err(|e| TuneError::Invalid(format!("procedure.json: {e}")))?;
    out.write("procedure.json", json.as_bytes())?;
    out.commit()?;
    Ok(result)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::error::ProcedureError;

    /// The line and message of the first parse error of `text`.
    pub(crate) fn parse_err(text: &str) -> (usize, String) {
        match parse(text, Path::new("t.proc")) {
            Err(TuneError::Procedure { line, source, .. }) => (line, source.to_string()),
            other => panic!("{other:?}"),
        }
    }

    /// Asserts that each text fails to parse at its line with a message holding the needle.
    pub(crate) fn assert_parse_errors(cases: &[(&str, usize, &str)]) {
        for &(text, line, needle) in cases {
            let (l, message) = parse_err(text);
            assert_eq!(l, line, "{text}: {message}");
            assert!(message.contains(needle), "{text}: {message}");
        }
    }

    #[test]
    fn parse_errors_name_the_line() {
        assert_parse_errors(&[
            ("\n# c\nfly away\n", 3, "unknown command `fly`"),
            (
                "grid alpha 0 beta 0\ngrid alpha 1 beta 1 name grid1\n",
                2,
                "twice",
            ),
            ("echo ok\ncase \"unclosed\n", 2, "not closed"),
        ]);
        assert!(matches!(
            parse("echo ok\ncase \"unclosed\n", Path::new("t.proc")),
            Err(TuneError::Procedure {
                source: ProcedureError::UnclosedQuote,
                ..
            })
        ));
    }

    /// docs/procedures.md lists every command and every setting of the tables.
    #[test]
    fn the_reference_documents_every_keyword() {
        let doc = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/procedures.md"),
        )
        .unwrap();
        for c in COMMANDS {
            assert!(doc.contains(&format!("| `{}` |", c.name)), "{}", c.name);
        }
        for s in SETTINGS {
            assert!(doc.contains(&format!("| `{}` |", s.name)), "{}", s.name);
        }
    }
}
