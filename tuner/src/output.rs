//! The output folder of a command, on [`coil_io::OutputSet`]: the folder is locked for
//! the run, every file is staged inside it and the files move in as a set at
//! [`OutDir::commit`] (a failed or killed run leaves the previous set, never a mix; see
//! `docs/files.md`). Names are relative and stay inside the folder. Journals are the one
//! exception: they are appended in place, line by line, on purpose (see [`crate::grid`]).

use crate::error::{Result, TuneError};
use coil_io::OutputSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A folder (or a sub-folder of one) that receives a command's files.
#[derive(Debug, Clone)]
pub struct OutDir {
    set: Arc<OutputSet>,
    prefix: PathBuf,
}

impl OutDir {
    /// Creates the folder (and its parents) if needed and locks it for this run.
    pub fn create(root: impl Into<PathBuf>) -> Result<Self> {
        let root = root.into();
        let command = std::env::args().collect::<Vec<_>>().join(" ");
        Ok(OutDir {
            set: Arc::new(OutputSet::open(&root, &command)?),
            prefix: PathBuf::new(),
        })
    }

    /// The folder (where the files will be once committed).
    pub fn root(&self) -> PathBuf {
        self.set.root().join(&self.prefix)
    }

    /// Where `relative` will be once committed (for messages).
    pub fn path(&self, relative: impl AsRef<Path>) -> PathBuf {
        self.root().join(relative)
    }

    /// The staged path to write `relative` to (sub-folders created); it is part of the set.
    pub fn staged(&self, relative: impl AsRef<Path>) -> Result<PathBuf> {
        Ok(self.set.staged_path(&self.prefix.join(relative))?)
    }

    /// The staging folder of this (sub-)folder, created: files put there are in the set.
    pub fn staging_folder(&self) -> Result<PathBuf> {
        let folder = self.set.staging().join(&self.prefix);
        std::fs::create_dir_all(&folder).map_err(|e| TuneError::io(&folder, e))?;
        Ok(folder)
    }

    /// The path of a journal inside the folder, appended in place (not staged).
    pub fn journal(&self, relative: impl AsRef<Path>) -> Result<PathBuf> {
        Ok(self.set.journal_path(&self.prefix.join(relative))?)
    }

    /// Lets `produce` write the staged file for `relative` (through a temporary that is
    /// renamed when complete); returns the final path.
    pub fn produce(
        &self,
        relative: impl AsRef<Path>,
        produce: impl FnOnce(&Path) -> Result<()>,
    ) -> Result<PathBuf> {
        self.set.produce(&self.prefix.join(relative), produce)
    }

    /// Stages `bytes` as `relative`; returns the final path.
    pub fn write(&self, relative: impl AsRef<Path>, bytes: &[u8]) -> Result<PathBuf> {
        Ok(self.set.write(&self.prefix.join(relative), bytes)?)
    }

    /// A sub-folder, part of the same set.
    pub fn sub(&self, relative: impl AsRef<Path>) -> Result<OutDir> {
        let prefix = self.prefix.join(relative);
        self.set.staged_path(&prefix)?;
        Ok(OutDir {
            set: Arc::clone(&self.set),
            prefix,
        })
    }

    /// Moves every staged file of the run in as a set and releases the folder.
    pub fn commit(&self) -> Result<()> {
        self.set.commit()?;
        Ok(())
    }
}

/// One CSV field (RFC 4180): quoted, with its quotes doubled, when it holds a comma, a
/// quote, a line break or a blank at either end; as it is otherwise (numbers, plain
/// names), so the tables of plain studies are unchanged.
pub fn csv_field(text: &str) -> std::borrow::Cow<'_, str> {
    let needs = text.contains([',', '"', '\n', '\r'])
        || text.starts_with([' ', '\t'])
        || text.ends_with([' ', '\t']);
    if needs {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}

/// One CSV record (without its line end) from its fields, each quoted as needed.
pub fn csv_record<S: AsRef<str>>(fields: impl IntoIterator<Item = S>) -> String {
    let mut out = String::new();
    for (k, f) in fields.into_iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        out.push_str(&csv_field(f.as_ref()));
    }
    out
}

/// The fields of one CSV record written by [`csv_record`] (one line: coil's names are
/// single lines). An unclosed quote or text after a closing quote is an error naming
/// the column.
pub fn split_csv_record(line: &str) -> std::result::Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut chars = line.char_indices().peekable();
    loop {
        let mut field = String::new();
        match chars.peek() {
            Some(&(start, '"')) => {
                chars.next();
                loop {
                    match chars.next() {
                        Some((_, '"')) if chars.peek().is_some_and(|&(_, c)| c == '"') => {
                            chars.next();
                            field.push('"');
                        }
                        Some((_, '"')) => break,
                        Some((_, c)) => field.push(c),
                        None => {
                            return Err(format!(
                                "column {}: a quoted field without its closing quote",
                                start + 1
                            ))
                        }
                    }
                }
                match chars.next() {
                    None => {
                        fields.push(field);
                        return Ok(fields);
                    }
                    Some((_, ',')) => fields.push(field),
                    Some((at, _)) => {
                        return Err(format!(
                            "column {}: text after a closing quote; expected a comma",
                            at + 1
                        ))
                    }
                }
            }
            _ => loop {
                match chars.next() {
                    None => {
                        fields.push(field);
                        return Ok(fields);
                    }
                    Some((_, ',')) => {
                        fields.push(field);
                        break;
                    }
                    Some((at, '"')) => {
                        return Err(format!(
                            "column {}: a quote inside an unquoted field",
                            at + 1
                        ))
                    }
                    Some((_, c)) => field.push(c),
                }
            },
        }
    }
}

/// CSV text from a header and rows of cells, each quoted as needed ([`csv_field`]).
pub fn csv(header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut out = csv_record(header);
    out.push('\n');
    for row in rows {
        out.push_str(&csv_record(&row));
        out.push('\n');
    }
    out
}

/// A number with all the digits needed to read it back exactly.
pub fn exact(x: f64) -> String {
    format!("{x:?}")
}

/// One cell of a study's table.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// Text.
    Text(String),
    /// A number.
    Number(f64),
    /// An optional value that is absent (an empty CSV cell).
    Missing,
}

impl From<Option<f64>> for Cell {
    fn from(value: Option<f64>) -> Self {
        value.map_or(Cell::Missing, Cell::Number)
    }
}

impl Cell {
    /// The cell's text (unquoted: [`csv_record`] quotes): numbers with every digit
    /// needed to read them back exactly.
    pub fn csv(&self) -> String {
        match self {
            Cell::Text(s) => s.clone(),
            Cell::Number(x) => exact(*x),
            Cell::Missing => String::new(),
        }
    }
}

/// CSV text of a table of cells (text quoted as needed).
pub fn csv_table(columns: &[&str], rows: impl IntoIterator<Item = Vec<Cell>>) -> String {
    csv(
        columns,
        rows.into_iter()
            .map(|row| row.iter().map(Cell::csv).collect()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_are_quoted_when_needed_and_read_back() {
        for fields in [
            vec!["A,B", "plain", "say \"hi\"", "", " lead", "1.5e-7"],
            vec![""],
            vec!["\"", ","],
        ] {
            let line = csv_record(&fields);
            assert_eq!(split_csv_record(&line).unwrap(), fields, "{line}");
        }
        assert_eq!(csv_record(["1", "#1", "2.5"]), "1,#1,2.5");
        assert_eq!(csv_record(["A,B", "x"]), "\"A,B\",x");
        for bad in ["\"open", "\"a\"b", "a\"b"] {
            assert!(split_csv_record(bad).is_err(), "{bad}");
        }
    }
}
