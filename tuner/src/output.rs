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

/// CSV text from a header and rows of cells (cells are numbers or plain words; nothing
/// here needs quoting).
pub fn csv(header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut out = header.join(",");
    out.push('\n');
    for row in rows {
        out.push_str(&row.join(","));
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
    /// The CSV text: numbers with every digit needed to read them back exactly.
    pub fn csv(&self) -> String {
        match self {
            Cell::Text(s) => s.clone(),
            Cell::Number(x) => exact(*x),
            Cell::Missing => String::new(),
        }
    }
}

/// CSV text of a table whose cells need no quoting (numbers, names without commas).
pub fn csv_table(columns: &[&str], rows: impl IntoIterator<Item = Vec<Cell>>) -> String {
    csv(
        columns,
        rows.into_iter()
            .map(|row| row.iter().map(Cell::csv).collect()),
    )
}
