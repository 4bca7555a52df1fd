//! Output files are written to a temporary file in the destination's folder and renamed over
//! the destination only when complete, so a failed run never leaves a half-written file.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{PostError, Result};

fn write_error(path: &Path, source: std::io::Error) -> PostError {
    PostError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// A temporary file next to `path`, with the same extension (plotters picks the image format
/// from it).
fn temporary_beside(path: &Path) -> Result<tempfile::NamedTempFile> {
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let suffix = path
        .extension()
        .map(|ext| format!(".{}", ext.to_string_lossy()))
        .unwrap_or_default();
    let mut builder = tempfile::Builder::new();
    builder.prefix(".coil-post-").suffix(&suffix);
    // A temporary file is private (0600) by default; the result is an ordinary output file,
    // so ask for 0666 and let the umask decide, as for any newly created file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder
        .tempfile_in(folder)
        .map_err(|source| write_error(path, source))
}

/// Writes `contents` to `path` through a temporary file and a rename.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<()> {
    let mut file = temporary_beside(path)?;
    file.write_all(contents)
        .and_then(|()| file.as_file().sync_all())
        .map_err(|source| write_error(path, source))?;
    file.persist(path)
        .map_err(|error| write_error(path, error.error))?;
    Ok(())
}

/// Lets `produce` write a file at a temporary path (same folder and extension as `path`),
/// then renames it to `path`. If `produce` fails the temporary file is removed.
pub fn produce_atomic<F>(path: &Path, produce: F) -> Result<()>
where
    F: FnOnce(&Path) -> Result<()>,
{
    let file = temporary_beside(path)?;
    produce(file.path())?;
    file.persist(path)
        .map_err(|error| write_error(path, error.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_production_leaves_nothing() {
        let folder = tempfile::tempdir().unwrap();
        let target = folder.path().join("out.png");
        let result = produce_atomic(&target, |temporary| {
            std::fs::write(temporary, b"half").map_err(|source| write_error(temporary, source))?;
            Err(PostError::InvalidOption("stop".to_string()))
        });
        assert!(result.is_err());
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);

        write_atomic(&target, b"whole").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"whole");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&target).unwrap().permissions().mode();
            assert_ne!(
                mode & 0o044,
                0,
                "output readable by others under the usual umask"
            );
        }
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 1);
    }
}
