//! (module under construction: the deck reader and writer)

use crate::model::Model;
use std::path::Path;

/// Errors from reading a deck (placeholder until the reader lands).
#[derive(Debug, thiserror::Error)]
#[error("deck error")]
pub struct DeckError;

/// Reads a deck from text; `file` names it in error messages.
pub fn read_str(_text: &str, _file: &str) -> Result<Model, DeckError> {
    Err(DeckError)
}

/// Reads a deck file.
pub fn read_file(_path: &Path) -> Result<Model, DeckError> {
    Err(DeckError)
}

/// Writes a model as a deck that reads back to an equal model.
pub fn write(_model: &Model) -> String {
    String::new()
}
