//! coil's input-deck language: MSC Marc's card structure in free format, for 3D beam
//! models of springs. The reader turns text into a validated, immutable
//! [`Model`]; the writer turns a model back into a deck that reads back equal.
//!
//! # Structure
//! A parameter section ending with `END`, a model definition ending with `END OPTION`,
//! then a history of load cases each closed by `CONTINUE`. Keywords are
//! case-insensitive, `$` starts a comment line, fields are separated by commas and/or
//! blanks, and multi-word keywords keep their blank (`FIXED DISP`). Every card is one
//! entry of [`cards::KEYWORDS`], defined beside its parse function and tests; docs/deck.md
//! is generated from that table.
//!
//! # Units and DOFs
//! Marc's consistent units: mm, N, tonne, s (E in MPa, density in t/mm^3, rotary
//! inertia in t mm^2). DOFs 1..6 = u_x, u_y, u_z, theta_x, theta_y, theta_z in global
//! axes. See [`crate::model`].
//!
//! # Reading in two stages
//! 1. [`lexer`]: text -> lines of located fields (file, line, column).
//! 2. [`reader`] + [`cards`]: lines -> cards, each field checked where it is read,
//!    into a located raw deck ([`raw`]); [`build`]: raw deck -> [`Model`], each card
//!    family's build function resolving ids and sets ([`resolve`]) into the model's
//!    parts, which [`Model::try_new`] validates; its errors are mapped back to lines.
//!
//! # Modules, lowest first (no import circle)
//! [`error`] (locations, [`DeckError`]) <- [`lexer`] <- [`raw`] <- [`card`] (the
//! [`Keyword`] entry type and the card context) and [`resolve`] (list resolution) <-
//! [`cards`] (one module per family: entries, parse and build functions, tests; the
//! registry [`KEYWORDS`]) <- [`reader`] and [`build`]; [`writer`] reads only the model.
//!
//! Every error is a [`DeckError`] naming `file:line:column`, the card, what is wrong
//! and what was expected. No input makes the reader panic.

mod build;
mod card;
pub mod cards;
mod error;
mod lexer;
mod raw;
mod reader;
mod resolve;
mod writer;

pub use card::{DeckSection, Keyword, Origin};
pub use cards::{reference_markdown, KEYWORDS};
pub use error::{DeckError, Loc};
pub use writer::dmig_card;

use crate::model::Model;
use std::path::Path;

/// Reads a deck from text; `file` names it in error messages.
pub fn read_str(text: &str, file: &str) -> Result<Model, DeckError> {
    read_str_noting(text, file).map(|(m, _)| m)
}

/// A card that was read and changes nothing coil computes (Marc's `PROCESSOR`,
/// `OPTIMIZE`, `POST`, ...): its keyword and the line of its first appearance. A run
/// lists these once in its log.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotNeeded {
    /// The card's keyword.
    pub card: String,
    /// Line of its first appearance.
    pub line: usize,
}

/// [`read_str`], also returning the cards read and not needed.
pub fn read_str_noting(text: &str, file: &str) -> Result<(Model, Vec<NotNeeded>), DeckError> {
    let lines = lexer::lex(text)
        .map_err(|e| DeckError::new(file, e.loc, None, e.message, "a text deck"))?;
    let raw = reader::read_cards(&lines, file, DeckSection::Parameters, true)?;
    let notes = raw
        .not_needed
        .iter()
        .map(|(card, loc)| NotNeeded {
            card: card.clone(),
            line: loc.line,
        })
        .collect();
    Ok((build::build(raw, file)?, notes))
}

/// Reads a deck file. A file that cannot be read, or is not UTF-8 text, is a
/// [`DeckError`] too (naming the line and column of the first bad byte).
pub fn read_file(path: &Path) -> Result<Model, DeckError> {
    read_file_noting(path).map(|(m, _)| m)
}

/// [`read_file`], also returning the cards read and not needed.
pub fn read_file_noting(path: &Path) -> Result<(Model, Vec<NotNeeded>), DeckError> {
    let name = path.display().to_string();
    let bytes = coil_io::confine::read_bounded_bytes(path, coil_io::MAX_DECK_BYTES, "a deck")
        .map_err(|e| match e {
            coil_io::ConfineError::Io { source, .. } => DeckError::file_level(
                &name,
                format!("cannot read the file: {source}"),
                "a readable deck file",
            ),
            other => DeckError::file_level(
                &name,
                other.to_string(),
                "a deck file within the size limit (docs/files.md)",
            ),
        })?;
    match String::from_utf8(bytes) {
        Ok(text) => read_str_noting(&text, &name),
        Err(e) => {
            let bytes = e.as_bytes();
            let valid = e.utf8_error().valid_up_to();
            let prefix = String::from_utf8_lossy(&bytes[..valid]);
            let line = prefix.matches('\n').count() + 1;
            let col = prefix.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            let byte = bytes.get(valid).copied().unwrap_or(0);
            Err(DeckError::new(
                &name,
                Loc::new(line, col),
                None,
                format!("the file is not UTF-8 text (byte 0x{byte:02X}; is this a binary file?)"),
                "a text deck",
            ))
        }
    }
}

/// Writes a model as a deck that reads back to an equal model (see [`writer`] for the
/// few things a hand-built model could hold that a deck cannot).
pub fn write(model: &Model) -> String {
    writer::write(model)
}

/// Writes a model in Marc's extended fixed format, the format Mentat writes (see
/// [`writer::write_mentat`]); it reads back to an equal model too.
pub fn write_mentat(model: &Model) -> String {
    writer::write_mentat(model)
}
