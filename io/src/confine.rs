//! Confined reads: a path written inside a user file (a record of a case) is an *entry*.
//! An entry is relative, has no `..` and, once every symlink is resolved, names a regular
//! file inside its folder ([`resolve_inside`]). Inputs are read with a size limit
//! ([`read_bounded`]); a FIFO or a device is refused before it is opened (opening a FIFO
//! would block). Error messages name the entry and never show the target's content; text
//! quoted from a user file goes through [`excerpt`] (control characters replaced, length
//! capped), so a hostile file cannot forge terminal output or flood it.

use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// The longest excerpt of a user file an error message quotes, characters.
pub const EXCERPT_CHARS: usize = 60;

/// Why an entry or an input file was refused.
#[derive(Debug, thiserror::Error)]
pub enum ConfineError {
    #[error("entry \"{}\": an empty path; expected a file name relative to {}", excerpt(entry), folder.display())]
    /// An empty name.
    Empty {
        /// The name as written.
        entry: String,
        /// The folder it must stay in.
        folder: PathBuf,
    },
    #[error("entry \"{}\": an absolute path; expected a path relative to {}", excerpt(entry), folder.display())]
    /// An absolute path where a relative one is expected.
    Absolute {
        /// The name as written.
        entry: String,
        /// The folder it must stay in.
        folder: PathBuf,
    },
    #[error("entry \"{}\": `..` is not allowed; expected a path inside {}", excerpt(entry), folder.display())]
    /// A `..` component.
    Parent {
        /// The name as written.
        entry: String,
        /// The folder it must stay in.
        folder: PathBuf,
    },
    #[error("entry \"{}\": resolves (through a symlink) outside {}; expected a file inside the folder", excerpt(entry), folder.display())]
    /// A name that leaves its folder once symlinks are resolved.
    Escapes {
        /// The name as written.
        entry: String,
        /// The folder it must stay in.
        folder: PathBuf,
    },
    #[error("entry \"{}\": no such file in {} ({source})", excerpt(entry), folder.display())]
    /// A name that does not exist (or cannot be resolved).
    Missing {
        /// The name as written.
        entry: String,
        /// The folder it must stay in.
        folder: PathBuf,
        #[source]
        /// The underlying error.
        source: std::io::Error,
    },
    #[error("{}: not a regular file (a folder, device, FIFO or socket); expected a file", path.display())]
    /// Not a regular file.
    NotAFile {
        /// The file.
        path: PathBuf,
    },
    #[error("{}: {size} bytes, above the limit of {limit} bytes for {what} (docs/files.md)", path.display())]
    /// A file above its size limit.
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size, bytes.
        size: u64,
        /// The limit, bytes.
        limit: u64,
        /// What the file was read as.
        what: &'static str,
    },
    #[error("{}: not UTF-8 text (byte {at}); expected a text file", path.display())]
    /// A file that is not UTF-8 text.
    NotText {
        /// The file.
        path: PathBuf,
        /// Byte offset of the first invalid byte.
        at: usize,
    },
    #[error("{}: cannot read the file: {source}", path.display())]
    /// Reading or writing failed.
    Io {
        /// The file.
        path: PathBuf,
        #[source]
        /// The underlying error.
        source: std::io::Error,
    },
}

/// At most [`EXCERPT_CHARS`] characters of `text`, control characters (newlines, escape
/// sequences, NUL) replaced by `?`, with `...` when cut.
pub fn excerpt(text: &str) -> String {
    excerpt_n(text, EXCERPT_CHARS)
}

/// [`excerpt`] with a chosen length.
pub fn excerpt_n(text: &str, max_chars: usize) -> String {
    let mut out = String::new();
    for (count, c) in text.chars().enumerate() {
        if count == max_chars {
            out.push_str("...");
            break;
        }
        out.push(if c.is_control() || is_bidi_control(c) {
            '?'
        } else {
            c
        });
    }
    out
}

/// A message that may quote user text: every `` `quoted` `` span is cut to an
/// [`excerpt`], and the whole is sanitised and capped at `max_chars`.
pub fn sanitise_message(message: &str, max_chars: usize) -> String {
    let mut out = String::new();
    for (k, part) in message.split('`').enumerate() {
        if k > 0 {
            out.push('`');
        }
        if k % 2 == 1 {
            out.push_str(&excerpt(part));
        } else {
            out.push_str(part);
        }
    }
    excerpt_n(&out, max_chars)
}

/// The longest error message shown, bytes.
pub const MAX_MESSAGE_BYTES: usize = 1000;

/// An error message as shown to a person (stderr, a Python exception): every
/// `` `quoted` `` span of user text cut to an [`excerpt`], control characters other than
/// line breaks and tabs escaped (`\u{1b}`), bidirectional overrides escaped, and the whole
/// cut below [`MAX_MESSAGE_BYTES`] with `... (cut)`.
pub fn clean_message(message: &str) -> String {
    let mut spans = String::new();
    for (k, part) in message.split('`').enumerate() {
        if k > 0 {
            spans.push('`');
        }
        if k % 2 == 1 && part.chars().count() > EXCERPT_CHARS {
            spans.extend(part.chars().take(EXCERPT_CHARS));
            spans.push_str("...");
        } else {
            spans.push_str(part);
        }
    }
    let mut out = String::new();
    for c in spans.chars() {
        let piece = if (c.is_control() && c != '\n' && c != '\t') || is_bidi_control(c) {
            c.escape_unicode().to_string()
        } else {
            c.to_string()
        };
        if out.len() + piece.len() > MAX_MESSAGE_BYTES - 12 {
            out.push_str("... (cut)");
            break;
        }
        out.push_str(&piece);
    }
    out
}

/// Bidirectional overrides that reorder what a terminal shows.
fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// Checks the form of an entry: non-empty, relative, no `..` (a `.` is allowed).
pub fn check_entry(entry: &str, folder: &Path) -> Result<(), ConfineError> {
    let err_entry = || entry.to_string();
    if entry.is_empty() {
        return Err(ConfineError::Empty {
            entry: err_entry(),
            folder: folder.into(),
        });
    }
    let path = Path::new(entry);
    for component in path.components() {
        match component {
            Component::Normal(_) | Component::CurDir => {}
            Component::ParentDir => {
                return Err(ConfineError::Parent {
                    entry: err_entry(),
                    folder: folder.into(),
                })
            }
            Component::RootDir | Component::Prefix(_) => {
                return Err(ConfineError::Absolute {
                    entry: err_entry(),
                    folder: folder.into(),
                })
            }
        }
    }
    Ok(())
}

/// Resolves `entry` (from a user file) inside `folder`: the canonical path of a regular
/// file inside the canonical `folder`, or an error naming the entry.
pub fn resolve_inside(folder: &Path, entry: &str) -> Result<PathBuf, ConfineError> {
    check_entry(entry, folder)?;
    let base = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    let root = base.canonicalize().map_err(|source| ConfineError::Io {
        path: folder.into(),
        source,
    })?;
    let target = root
        .join(entry)
        .canonicalize()
        .map_err(|source| ConfineError::Missing {
            entry: entry.into(),
            folder: folder.into(),
            source,
        })?;
    if !target.starts_with(&root) || target == root {
        return Err(ConfineError::Escapes {
            entry: entry.into(),
            folder: folder.into(),
        });
    }
    let meta = std::fs::metadata(&target).map_err(|source| ConfineError::Io {
        path: folder.join(entry),
        source,
    })?;
    if !meta.is_file() {
        return Err(ConfineError::NotAFile {
            path: folder.join(entry),
        });
    }
    Ok(target)
}

/// Reads a text input of at most `limit` bytes (`what` names the kind for the error). A
/// non-regular file is refused before it is opened.
pub fn read_bounded(path: &Path, limit: u64, what: &'static str) -> Result<String, ConfineError> {
    let bytes = read_bounded_bytes(path, limit, what)?;
    String::from_utf8(bytes).map_err(|e| ConfineError::NotText {
        path: path.into(),
        at: e.utf8_error().valid_up_to(),
    })
}

/// [`read_bounded`] without the UTF-8 check.
pub fn read_bounded_bytes(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> Result<Vec<u8>, ConfineError> {
    let io = |source| ConfineError::Io {
        path: path.into(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(ConfineError::NotAFile { path: path.into() });
    }
    let too_large = |size| ConfineError::TooLarge {
        path: path.into(),
        size,
        limit,
        what,
    };
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excerpts_are_short_and_clean() {
        assert_eq!(excerpt("a\u{1b}[31mb\nc"), "a?[31mb?c");
        let long = "x".repeat(500);
        assert_eq!(excerpt(&long).chars().count(), EXCERPT_CHARS + 3);
        assert_eq!(excerpt("\u{202e}abc"), "?abc");
        let m = sanitise_message(&format!("bad `{}` here", "7".repeat(500)), 200);
        assert_eq!(m, format!("bad `{}...` here", "7".repeat(EXCERPT_CHARS)));
    }

    #[test]
    fn entries_stay_inside() {
        let dir = tempfile::tempdir().unwrap();
        let case = dir.path().join("case");
        std::fs::create_dir(&case).unwrap();
        std::fs::write(case.join("ok.csv"), "1").unwrap();
        std::fs::create_dir(case.join("sub")).unwrap();
        std::fs::write(case.join("sub/in.csv"), "1").unwrap();
        std::fs::write(dir.path().join("secret"), "root:x:0:0").unwrap();
        std::os::unix::fs::symlink(dir.path().join("secret"), case.join("link.csv")).unwrap();
        std::os::unix::fs::symlink("ok.csv", case.join("inner.csv")).unwrap();
        std::os::unix::fs::symlink("..", case.join("up")).unwrap();

        assert!(resolve_inside(&case, "ok.csv").is_ok());
        assert!(resolve_inside(&case, "./sub/in.csv").is_ok());
        assert!(resolve_inside(&case, "inner.csv").is_ok(), "symlink inside");
        for (entry, kind) in [
            ("../secret", "`..`"),
            ("/etc/passwd", "absolute"),
            ("link.csv", "outside"),
            ("up/secret", "outside"),
            ("", "empty"),
            ("sub", "not a regular"),
            ("nothing.csv", "no such file"),
        ] {
            let e = resolve_inside(&case, entry).unwrap_err().to_string();
            assert!(e.contains(kind), "{entry}: {e}");
            assert!(!e.contains("root:x"), "{e}");
        }
    }

    #[test]
    fn bounded_reads() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        std::fs::write(&p, "0123456789").unwrap();
        assert_eq!(read_bounded(&p, 10, "a test").unwrap(), "0123456789");
        let e = read_bounded(&p, 9, "a test").unwrap_err().to_string();
        assert!(e.contains("above the limit of 9 bytes for a test"), "{e}");
        std::fs::write(&p, [b'a', 0xff, b'b']).unwrap();
        assert!(read_bounded(&p, 10, "a test")
            .unwrap_err()
            .to_string()
            .contains("byte 1"));
        assert!(matches!(
            read_bounded(dir.path(), 10, "a test"),
            Err(ConfineError::NotAFile { .. })
        ));
    }

    #[test]
    fn messages_are_escaped_and_short() {
        let header = "time_s,\u{1b}[2J\u{1b}[31maccel";
        let m = clean_message(&format!("r.csv:1: column `{header}` unknown\nsecond line"));
        assert!(!m.contains('\u{1b}'), "{m}");
        assert!(m.contains("\\u{1b}[2J"), "{m}");
        assert!(m.contains("\nsecond line"), "{m}");
        let huge = format!("cell `{}` and {}", "x".repeat(200_000), "y".repeat(200_000));
        let m = clean_message(&huge);
        assert!(m.len() < 1024 && m.ends_with("... (cut)"), "{}", m.len());
        assert!(m.contains("xxx...`"), "the cell is cut to an excerpt");
    }
}
