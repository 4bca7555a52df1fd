//! The deck reader's error: where (file, line, column), which card, what is wrong
//! and what was expected.

use coil_io::confine::sanitise_message;
use std::fmt;

/// The longest message or expectation of a deck error, characters.
const MESSAGE_CHARS: usize = 1000;

/// A position in a deck: 1-based line and 1-based column (in characters).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Loc {
    /// Line, 1-based.
    pub line: usize,
    /// Column (character), 1-based.
    pub col: usize,
}

impl Loc {
    /// A location at `line`, `col`.
    pub fn new(line: usize, col: usize) -> Self {
        Loc { line, col }
    }
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.col)
    }
}

/// Why a deck could not be read.
///
/// Displays as `<file>:<line>:<column>: <CARD>: <what is wrong>; expected <what>`.
/// The location is absent only when the file itself could not be read; the card is
/// absent when the problem is not inside a card (an unknown keyword, a misplaced
/// data line, the end of the file in the wrong section).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error, miette::Diagnostic)]
#[diagnostic(code(coil::deck))]
pub struct DeckError {
    file: String,
    loc: Option<Loc>,
    card: Option<String>,
    message: String,
    expected: Option<String>,
}

impl fmt::Display for DeckError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:", self.file)?;
        if let Some(loc) = self.loc {
            write!(f, "{}:{}:", loc.line, loc.col)?;
        }
        if let Some(card) = &self.card {
            write!(f, " {card}:")?;
        }
        write!(f, " {}", self.message)?;
        if let Some(expected) = &self.expected {
            write!(f, "; expected {expected}")?;
        }
        Ok(())
    }
}

impl DeckError {
    /// An error at a location, inside a card (`card` is the keyword, e.g. `FIXED DISP`)
    /// or outside any card (`card` = `None`).
    pub(crate) fn new(
        file: &str,
        loc: Loc,
        card: Option<&str>,
        message: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        // Messages quote deck text: short, sanitised excerpts only (docs/files.md).
        let expected = sanitise_message(&expected.into(), MESSAGE_CHARS);
        DeckError {
            file: file.to_string(),
            loc: Some(loc),
            card: card.map(|c| sanitise_message(c, 80)),
            message: sanitise_message(&message.into(), MESSAGE_CHARS),
            expected: (!expected.is_empty()).then_some(expected),
        }
    }

    /// An error about the file as a whole (it cannot be opened or read).
    pub(crate) fn file_level(
        file: &str,
        message: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        let expected = expected.into();
        DeckError {
            file: file.to_string(),
            loc: None,
            card: None,
            message: message.into(),
            expected: (!expected.is_empty()).then_some(expected),
        }
    }

    /// The 1-based line the error names, if any.
    pub fn line(&self) -> Option<usize> {
        self.loc.map(|l| l.line)
    }

    /// The 1-based column the error names, if any.
    pub fn column(&self) -> Option<usize> {
        self.loc.map(|l| l.col)
    }

    /// The file name as given to the reader.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The card (keyword) the error is in, if it is inside a card.
    pub fn card(&self) -> Option<&str> {
        self.card.as_deref()
    }

    /// What is wrong, without location, card or expectation.
    pub fn message(&self) -> &str {
        &self.message
    }

    /// What the reader expected instead, if it can say.
    pub fn expected(&self) -> Option<&str> {
        self.expected.as_deref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_has_every_part_in_order() {
        let e = DeckError::new(
            "a.dat",
            Loc::new(12, 5),
            Some("FIXED DISP"),
            "DOF 7 is out of range",
            "a DOF number 1..6",
        );
        assert_eq!(
            e.to_string(),
            "a.dat:12:5: FIXED DISP: DOF 7 is out of range; expected a DOF number 1..6"
        );
        assert_eq!(e.line(), Some(12));
        assert_eq!(e.column(), Some(5));
        assert_eq!(e.file(), "a.dat");
    }

    #[test]
    fn display_without_card_or_location() {
        let e = DeckError::new("b.dat", Loc::new(3, 1), None, "unknown keyword `X`", "");
        assert_eq!(e.to_string(), "b.dat:3:1: unknown keyword `X`");
        let e = DeckError::file_level("c.dat", "cannot read the file", "a readable file");
        assert_eq!(
            e.to_string(),
            "c.dat: cannot read the file; expected a readable file"
        );
        assert_eq!(e.line(), None);
    }
}
