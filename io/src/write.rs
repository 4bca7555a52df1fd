//! Regular-file writes. A file is written to a fresh temporary in its own folder
//! (created with `O_CREAT|O_EXCL`, which never follows or reuses an existing name) and
//! renamed over the destination only when complete, and only if the destination is absent
//! or a regular file: a symlink, a device node, a FIFO, a socket or a folder at the
//! destination is an error and is left as it is. `rename` replaces the directory entry
//! itself and never writes through a symlink, so the check before it is what keeps a
//! device node from being replaced. Journals, the one file appended in place, are opened
//! by [`open_journal`], which refuses anything but a regular file with one link.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::os::unix::fs::{FileTypeExt, MetadataExt};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Why an output file was not written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("{}: refusing to replace or write through a {kind}; expected a regular file or nothing there", path.display())]
    /// The target exists and is not a regular file (a symlink, device, FIFO or socket).
    NotRegular {
        /// The file.
        path: PathBuf,
        /// What it is instead.
        kind: &'static str,
    },
    #[error("{}: {source}", path.display())]
    /// Reading or writing failed.
    Io {
        /// The file.
        path: PathBuf,
        #[source]
        /// The underlying error.
        source: std::io::Error,
    },
}

impl WriteError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        WriteError::Io {
            path: path.into(),
            source,
        }
    }
}

/// What a directory entry is, in words.
pub(crate) fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_symlink() {
        "symlink"
    } else if t.is_dir() {
        "folder"
    } else if t.is_fifo() {
        "FIFO"
    } else if t.is_socket() {
        "socket"
    } else if t.is_block_device() || t.is_char_device() {
        "device node"
    } else if t.is_file() {
        "regular file"
    } else {
        "special file"
    }
}

/// Ok when `path` is absent or a regular file (not followed if a symlink).
pub fn check_replaceable(path: &Path) -> Result<(), WriteError> {
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_file() => Ok(()),
        Ok(meta) => Err(WriteError::NotRegular {
            path: path.into(),
            kind: kind_of(&meta),
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(WriteError::io(path, e)),
    }
}

/// A fresh temporary name beside `path`, keeping its extension (plotters picks the image
/// format from it): `.<stem>.coil-<pid>-<n>.<ext>`.
pub(crate) fn temporary_beside(path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let stem = path
        .file_stem()
        .map_or("out".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    let name = format!(".{stem}.coil-{}-{n}{ext}", std::process::id());
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.join(name),
        _ => PathBuf::from(name),
    }
}

/// Creates a new empty file (never an existing name, never through a symlink).
pub(crate) fn create_new(path: &Path) -> Result<File, WriteError> {
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
        .map_err(|e| WriteError::io(path, e))
}

/// Moves a finished temporary over `path` if `path` is absent or a regular file.
pub(crate) fn rename_over(temporary: &Path, path: &Path) -> Result<(), WriteError> {
    check_replaceable(path)?;
    std::fs::rename(temporary, path).map_err(|e| WriteError::io(path, e))
}

/// Writes `bytes` to `path` through a temporary and a rename (see the module doc).
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    produce_file(path, |temporary| {
        let mut file = OpenOptions::new()
            .write(true)
            .open(temporary)
            .map_err(|e| WriteError::io(temporary, e))?;
        file.write_all(bytes)
            .and_then(|()| file.sync_all())
            .map_err(|e| WriteError::io(path, e))
    })
}

/// Lets `produce` fill a fresh temporary file (same folder and extension as `path`,
/// created empty beforehand), then renames it over `path` as [`write_file`] does. If
/// `produce` or the rename fails, the temporary is removed and `path` is untouched.
pub fn produce_file<E, F>(path: &Path, produce: F) -> Result<(), E>
where
    E: From<WriteError>,
    F: FnOnce(&Path) -> Result<(), E>,
{
    check_replaceable(path)?;
    let temporary = temporary_beside(path);
    drop(create_new(&temporary)?);
    let result = produce(&temporary).and_then(|()| {
        // The producer may have replaced the file: it must still be a regular file.
        check_replaceable(&temporary)?;
        rename_over(&temporary, path).map_err(E::from)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Opens a journal for reading and appending (created if absent). Refuses a symlink, a
/// non-regular file and a file with other hard links, checked on the opened file itself.
pub fn open_journal(path: &Path) -> Result<File, WriteError> {
    check_replaceable(path)?;
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(|e| WriteError::io(path, e))?;
    let opened = file.metadata().map_err(|e| WriteError::io(path, e))?;
    let now = std::fs::symlink_metadata(path).map_err(|e| WriteError::io(path, e))?;
    if !opened.is_file()
        || opened.nlink() != 1
        || (opened.dev(), opened.ino()) != (now.dev(), now.ino())
    {
        return Err(WriteError::NotRegular {
            path: path.into(),
            kind: if opened.nlink() != 1 {
                "hard-linked file"
            } else {
                kind_of(&now)
            },
        });
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(dir: &Path) -> usize {
        std::fs::read_dir(dir).unwrap().count()
    }

    #[test]
    fn writes_replace_regular_files_only() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_file(&p, b"one").unwrap();
        write_file(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(entries(dir.path()), 1);

        let outside = dir.path().join("outside");
        std::fs::write(&outside, "keep").unwrap();
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink(&outside, &link).unwrap();
        let e = write_file(&link, b"x").unwrap_err().to_string();
        assert!(e.contains("symlink"), "{e}");
        assert_eq!(std::fs::read(&outside).unwrap(), b"keep");
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());

        let null = dir.path().join("null.txt");
        std::os::unix::fs::symlink("/dev/null", &null).unwrap();
        assert!(write_file(&null, b"x").is_err());
        let sub = dir.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        assert!(write_file(&sub, b"x")
            .unwrap_err()
            .to_string()
            .contains("folder"));
        assert_eq!(entries(dir.path()), 5, "no temporaries left");
    }

    #[test]
    fn failed_production_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("fig.png");
        let r: Result<(), WriteError> = produce_file(&p, |t| {
            assert_eq!(t.extension().unwrap(), "png");
            std::fs::write(t, "half").unwrap();
            Err(WriteError::io(t, std::io::Error::other("stop")))
        });
        assert!(r.is_err());
        assert_eq!(entries(dir.path()), 0);
    }

    #[test]
    fn journals_are_regular_files() {
        let dir = tempfile::tempdir().unwrap();
        let j = dir.path().join("g.journal.jsonl");
        open_journal(&j).unwrap().write_all(b"x\n").unwrap();
        let other = dir.path().join("other");
        std::fs::write(&other, "").unwrap();
        let link = dir.path().join("l.jsonl");
        std::os::unix::fs::symlink(&other, &link).unwrap();
        assert!(open_journal(&link).is_err());
        let hard = dir.path().join("h.jsonl");
        std::fs::hard_link(&other, &hard).unwrap();
        assert!(open_journal(&hard)
            .unwrap_err()
            .to_string()
            .contains("hard-linked"));
    }
}
