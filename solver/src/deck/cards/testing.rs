//! Test fixtures shared by the cards' tests: a small complete deck to embed one card in.

use crate::deck::error::DeckError;
use crate::deck::lexer::{lex, Line};
pub(crate) use crate::deck::read_str;
pub(crate) use crate::model::ElementType;
pub(crate) use crate::model::Model;

pub(crate) fn first_line(text: &str) -> Line {
    lex(text).unwrap().remove(0)
}

// A small but complete deck to embed one card's test in.
pub(crate) const PARAMS: &str = "TITLE, t\nELEMENTS, 98\nEND\n";

pub(crate) const MESH: &str = "COORDINATES\n3, 3\n1, 0, 0, 0\n2, 50, 0, 0\n3, 100, 0, 0\n\
    CONNECTIVITY\n0\n1, 98, 1, 2\n2, 98, 2, 3\n\
    DEFINE, ELEMENT, SET, wire\n1 TO 2\n\
    ISOTROPIC\n1\n1, steel\n2.0e5, 0.3, 7.85e-9\nwire\n\
    GEOMETRY\n1\n3.0\n0, 0, 1\nwire\n\
    FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1\n";

pub(crate) const STATIC: &str = "END OPTION\nAUTO LOAD\n1\nTIME STEP\n1.0\nCONTINUE\n";

pub(crate) fn with_model(extra: &str) -> Result<Model, DeckError> {
    read_str(&format!("{PARAMS}{MESH}{extra}{STATIC}"), "t.dat")
}

pub(crate) fn err_with_model(extra: &str) -> String {
    with_model(extra).unwrap_err().to_string()
}
