//! The output folder of a command: every file is written to a temporary sibling and
//! renamed, so a failed or killed run never leaves half a file (decks, logs, CSVs,
//! reports). Journals are the one exception: they are appended line by line on purpose
//! (see [`crate::grid`]).

use crate::error::{Result, TuneError};
use std::path::{Path, PathBuf};

/// A folder that receives a command's files.
#[derive(Debug, Clone)]
pub struct OutDir {
    root: PathBuf,
}

impl OutDir {
    /// Creates the folder (and its parents) if needed.
    pub fn create(root: impl Into<PathBuf>) -> Result<Self> {
        let root = root.into();
        std::fs::create_dir_all(&root).map_err(|e| TuneError::io(&root, e))?;
        Ok(OutDir { root })
    }

    /// The folder.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// A path inside the folder.
    pub fn path(&self, relative: impl AsRef<Path>) -> PathBuf {
        self.root.join(relative)
    }

    /// Writes `bytes` to `relative` atomically, creating sub-folders; returns the path.
    pub fn write(&self, relative: impl AsRef<Path>, bytes: &[u8]) -> Result<PathBuf> {
        let path = self.path(relative);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| TuneError::io(parent, e))?;
        }
        coil_solver::atomic::write_atomic(&path, bytes).map_err(|e| TuneError::io(&path, e))?;
        Ok(path)
    }

    /// A sub-folder (created).
    pub fn sub(&self, relative: impl AsRef<Path>) -> Result<OutDir> {
        OutDir::create(self.path(relative))
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
