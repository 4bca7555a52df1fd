//! Output files go through [`coil_io::write`]: a fresh temporary in the destination's
//! folder renamed over the destination only when complete, and only over nothing or a
//! regular file (never a symlink, device, FIFO or socket), so a failed run never leaves a
//! half-written file and never writes through a link.

use std::path::Path;

use crate::error::Result;

/// Writes `contents` to `path` through a temporary file and a rename.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<()> {
    Ok(coil_io::write_file(path, contents)?)
}

/// Lets `produce` write a file at a temporary path (same folder and extension as `path`),
/// then renames it to `path`. If `produce` fails the temporary file is removed.
pub fn produce_atomic<F>(path: &Path, produce: F) -> Result<()>
where
    F: FnOnce(&Path) -> Result<()>,
{
    coil_io::produce_file(path, produce)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::PostError;

    #[test]
    fn failed_production_leaves_nothing() {
        let folder = tempfile::tempdir().unwrap();
        let target = folder.path().join("out.png");
        let result = produce_atomic(&target, |temporary| {
            std::fs::write(temporary, b"half").unwrap();
            Err(PostError::InvalidOption("stop".to_string()))
        });
        assert!(result.is_err());
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);

        write_atomic(&target, b"whole").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"whole");
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&target).unwrap().permissions().mode();
        assert_ne!(
            mode & 0o044,
            0,
            "output readable by others under the usual umask"
        );
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 1);

        std::os::unix::fs::symlink("/dev/null", folder.path().join("null.json")).unwrap();
        assert!(write_atomic(&folder.path().join("null.json"), b"x").is_err());
    }
}
