//! One run per output folder, and its files as a whole set.
//!
//! **Lock.** [`OutputSet::open`] creates `<out>/.coil-lock` with `O_CREAT|O_EXCL`, holding
//! `pid`, `host` and `command`. A second run into the folder is refused with a message
//! naming the holder. A lock whose pid is not alive on this host (checked in `/proc`) is
//! stale (a killed run): it is taken over. A lock from another host is never taken over
//! (the message says to remove it by hand if that run is gone).
//!
//! **Staging in a sibling folder and one swap.** Every file of the run is written into a
//! sibling of the output folder, `<parent>/.<out>.coil-staging-<pid>/` (same file system,
//! checked). [`OutputSet::commit`] then
//! 1. writes the new manifest (the list of files) into the staging folder;
//! 2. checks that every destination in `<out>` is absent or a regular file (else nothing
//!    moves);
//! 3. carries over into the staging folder what `<out>` holds besides the previous set
//!    (the lock, grid journals, a person's own files) as hard links (symlinks recreated,
//!    folders made), so nothing of it is copied or lost;
//! 4. swaps the two folders with one `renameat2(RENAME_EXCHANGE)`: the path `<out>` names
//!    the new folder at once, and the sibling now names the previous one;
//! 5. removes the sibling (the previous set; the carried files live on through their
//!    other link).
//!
//! So at every instant, SIGKILL included, `<out>` as a person opens it holds either the
//! previous set or the new one, never a mix. A sibling left by a killed run (before or
//! after the swap: either way it is not `<out>`) is removed by the next run into `<out>`.
//!
//! **Fallback: staging inside the folder.** Where the swap is not possible (`<out>` is a
//! mount point or the file system root, the parent folder is not writable, a file system
//! without `RENAME_EXCHANGE` or hard links, a FIFO or socket to carry, not Linux), the
//! files are staged in `<out>/.coil-staging-<pid>/` and moved in one rename each, the
//! manifest renamed to `<out>/.coil-manifest` last. A run killed during those renames
//! leaves a staging folder with a manifest; the next run into the folder completes the
//! move first (roll forward), and until then `<out>/.coil-manifest` still lists the
//! previous set, so a reader can tell. In both modes a run that fails or is killed before
//! the swap (or the renames) leaves the previous set untouched. Journals (resumable grids)
//! are not part of a set: they are appended in place ([`crate::write::open_journal`]) so
//! that a killed run keeps its points.

use crate::confine::{check_entry, excerpt_n, ConfineError};
use crate::write::{check_replaceable, kind_of, produce_file, write_file, WriteError};
use std::collections::BTreeSet;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// The lock file's name inside an output folder.
pub const LOCK: &str = ".coil-lock";
/// The manifest's name: the files of the last complete set, one relative path a line.
pub const MANIFEST: &str = ".coil-manifest";
/// The staging folders' prefix (inside the folder in the fallback mode; after
/// `.<out>` for the sibling of the swap).
pub const STAGING_PREFIX: &str = ".coil-staging-";
const MANIFEST_HEADER: &str = "# coil output set: files of the last complete run";

/// Why an output folder could not be used or its set not be moved in.
#[derive(Debug, thiserror::Error)]
pub enum SetError {
    #[error("{}: another run holds this output folder ({holder}); wait for it, or use another --out (if that run is gone, remove {})", root.display(), root.join(LOCK).display())]
    /// The folder is held by another run.
    Locked {
        /// The folder.
        root: PathBuf,
        /// The lock file's holder (pid, host, command).
        holder: String,
    },
    #[error("{}: the output folder is a {kind}; expected a folder", root.display())]
    /// The output path exists and is not a folder.
    NotAFolder {
        /// The folder.
        root: PathBuf,
        /// What the path is instead.
        kind: &'static str,
    },
    #[error("output file name: {0}")]
    /// A file name that would leave the folder.
    Name(#[from] ConfineError),
    #[error(transparent)]
    /// A file that cannot be written.
    Write(#[from] WriteError),
    #[error("{}: {}", root.display(), crate::cancel::INTERRUPTED)]
    /// A stop was requested ([`crate::cancel`]): the set is not moved in.
    Interrupted {
        /// The folder.
        root: PathBuf,
    },
}

fn io(path: &Path, e: std::io::Error) -> SetError {
    SetError::Write(WriteError::io(path, e))
}

/// A locked output folder and the files staged for it (see the module doc).
#[derive(Debug)]
pub struct OutputSet {
    root: PathBuf,
    staging: PathBuf,
    /// `Some(the folder's real path)`: staged in a sibling, committed by a swap.
    swap: Option<PathBuf>,
    lock: Mutex<Lock>,
    committed: AtomicBool,
    /// The run created the folder: a failed run removes it again if it is empty.
    created_root: bool,
}

impl OutputSet {
    /// Creates `root` if needed, locks it for `command` (a short description shown to a
    /// second run), finishes or removes what a killed run left, and opens a staging folder.
    pub fn open(root: &Path, command: &str) -> Result<Self, SetError> {
        let created_root = std::fs::symlink_metadata(root).is_err();
        std::fs::create_dir_all(root).map_err(|e| io(root, e))?;
        let meta = std::fs::metadata(root).map_err(|e| io(root, e))?;
        if !meta.is_dir() {
            return Err(SetError::NotAFolder {
                root: root.into(),
                kind: kind_of(&meta),
            });
        }
        let lock = Lock::take(root, command)?;
        recover(root)?;
        let (staging, swap) = match sibling_staging(root) {
            Some((staging, real)) => (staging, Some(real)),
            None => {
                let staging = root.join(format!("{STAGING_PREFIX}{}", std::process::id()));
                std::fs::create_dir(&staging).map_err(|e| io(&staging, e))?;
                (staging, None)
            }
        };
        Ok(OutputSet {
            root: root.into(),
            staging,
            swap,
            lock: Mutex::new(lock),
            committed: AtomicBool::new(false),
            created_root,
        })
    }

    /// The output folder.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// Where `relative` will be once the set is committed.
    pub fn destination(&self, relative: &Path) -> PathBuf {
        self.root.join(relative)
    }

    /// The staging folder: every regular file in it at [`OutputSet::commit`] is part of
    /// the set (a writer may put files there directly, e.g. a figure renderer).
    pub fn staging(&self) -> &Path {
        &self.staging
    }

    /// The staging path for `relative` (checked: relative, no `..`, no control
    /// characters), with its sub-folders created.
    pub fn staged_path(&self, relative: &Path) -> Result<PathBuf, SetError> {
        let rel = check_name(relative, &self.root)?;
        let path = self.staging.join(&rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| io(parent, e))?;
        }
        Ok(path)
    }

    /// Stages `bytes` as `relative`; returns the destination path.
    pub fn write(&self, relative: &Path, bytes: &[u8]) -> Result<PathBuf, SetError> {
        let path = self.staged_path(relative)?;
        write_file(&path, bytes)?;
        Ok(self.destination(relative))
    }

    /// Lets `produce` write the staged file for `relative` (a plot renderer); returns
    /// the destination path.
    pub fn produce<E, F>(&self, relative: &Path, produce: F) -> Result<PathBuf, E>
    where
        E: From<SetError> + From<WriteError>,
        F: FnOnce(&Path) -> Result<(), E>,
    {
        let path = self.staged_path(relative)?;
        produce_file(&path, produce)?;
        Ok(self.destination(relative))
    }

    /// The path of a journal (appended in place, not part of the set), its sub-folders
    /// created inside the output folder and never through a symlink.
    pub fn journal_path(&self, relative: &Path) -> Result<PathBuf, SetError> {
        let rel = check_name(relative, &self.root)?;
        make_parents(&self.root, &rel)?;
        Ok(self.root.join(rel))
    }

    /// Moves the staged files in as a set (module doc); returns their destinations. A
    /// set is committed once; later writes into it fail.
    pub fn commit(&self) -> Result<Vec<PathBuf>, SetError> {
        if self.committed.load(Ordering::SeqCst) {
            return Ok(Vec::new());
        }
        if crate::cancel::requested() {
            return Err(SetError::Interrupted {
                root: self.root.clone(),
            });
        }
        let mut files = Vec::new();
        staged_files(&self.staging, Path::new(""), &mut files)?;
        files.sort();
        let mut text = format!("{MANIFEST_HEADER}\n");
        for f in &files {
            text.push_str(&f.to_string_lossy());
            text.push('\n');
        }
        write_file(&self.staging.join(MANIFEST), text.as_bytes())?;
        for f in &files {
            check_replaceable(&self.root.join(f))?;
        }
        let swapped = match &self.swap {
            Some(real) => swap_in(real, &self.staging)?,
            None => false,
        };
        if !swapped {
            finish(&self.root, &self.staging)?;
        }
        self.committed.store(true, Ordering::SeqCst);
        self.lock
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .release();
        Ok(files.iter().map(|f| self.root.join(f)).collect())
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        if !self.committed.load(Ordering::SeqCst) {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
        self.lock
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .release();
        if self.created_root && !self.committed.load(Ordering::SeqCst) {
            let _ = std::fs::remove_dir(&self.root);
        }
    }
}

/// The regular files under `dir` (relative to the staging folder), skipping unfinished
/// temporaries of a writer; a symlink or special file there is an error.
fn staged_files(dir: &Path, rel: &Path, out: &mut Vec<PathBuf>) -> Result<(), SetError> {
    let here = dir.join(rel);
    for entry in std::fs::read_dir(&here).map_err(|e| io(&here, e))? {
        let entry = entry.map_err(|e| io(&here, e))?;
        let name = rel.join(entry.file_name());
        let meta = std::fs::symlink_metadata(entry.path()).map_err(|e| io(&entry.path(), e))?;
        if meta.is_dir() {
            staged_files(dir, &name, out)?;
        } else if meta.is_file() {
            if !entry.file_name().to_string_lossy().contains(".coil-") {
                out.push(name);
            }
        } else {
            return Err(SetError::Write(WriteError::NotRegular {
                path: entry.path(),
                kind: kind_of(&meta),
            }));
        }
    }
    Ok(())
}

/// A relative output name: checked as an entry, without control characters.
fn check_name(relative: &Path, root: &Path) -> Result<PathBuf, SetError> {
    let text = relative.to_string_lossy();
    check_entry(&text, root)?;
    if text.chars().any(char::is_control) || text.starts_with(".coil-") {
        return Err(SetError::Name(ConfineError::NotAFile {
            path: PathBuf::from(excerpt_n(&text, 60)),
        }));
    }
    Ok(relative
        .components()
        .filter(|c| matches!(c, std::path::Component::Normal(_)))
        .collect())
}

/// Creates the folders of `rel`'s parent inside `root`, refusing any existing component
/// that is not a folder (a symlink to a folder included).
fn make_parents(root: &Path, rel: &Path) -> Result<(), SetError> {
    let mut at = root.to_path_buf();
    let Some(parent) = rel.parent() else {
        return Ok(());
    };
    for part in parent.components() {
        at.push(part);
        match std::fs::symlink_metadata(&at) {
            Ok(m) if m.is_dir() => {}
            Ok(m) => {
                return Err(SetError::Write(WriteError::NotRegular {
                    path: at,
                    kind: kind_of(&m),
                }))
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                std::fs::create_dir(&at).map_err(|e| io(&at, e))?;
            }
            Err(e) => return Err(io(&at, e)),
        }
    }
    Ok(())
}

/// The files of a manifest (lines that are valid names; others ignored).
fn manifest_files(path: &Path, root: &Path) -> BTreeSet<PathBuf> {
    let Ok(text) = crate::confine::read_bounded(path, 16 << 20, "a manifest") else {
        return BTreeSet::new();
    };
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
        .filter_map(|l| check_name(Path::new(l), root).ok())
        .collect()
}

/// Step 3 of the module doc, also used to roll a killed run's commit forward.
fn finish(root: &Path, staging: &Path) -> Result<(), SetError> {
    let new = manifest_files(&staging.join(MANIFEST), root);
    let old = manifest_files(&root.join(MANIFEST), root);
    for f in &new {
        let from = staging.join(f);
        match std::fs::symlink_metadata(&from) {
            Ok(m) if m.is_file() => {
                make_parents(root, f)?;
                let to = root.join(f);
                check_replaceable(&to)?;
                std::fs::rename(&from, &to).map_err(|e| io(&to, e))?;
            }
            // Moved already by the interrupted commit (or not a file: never moved).
            _ => {}
        }
    }
    for f in old.difference(&new) {
        let path = root.join(f);
        if std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
            std::fs::remove_file(&path).map_err(|e| io(&path, e))?;
        }
    }
    let manifest = root.join(MANIFEST);
    check_replaceable(&manifest)?;
    std::fs::rename(staging.join(MANIFEST), &manifest).map_err(|e| io(&manifest, e))?;
    std::fs::remove_dir_all(staging).map_err(|e| io(staging, e))
}

/// What killed runs left (we hold the lock): a sibling staging folder (before or after
/// its swap it is not `root`) is removed; inside `root`, a complete staging folder of the
/// fallback mode is moved in, an incomplete one removed.
fn recover(root: &Path) -> Result<(), SetError> {
    if let Some((parent, prefix)) = sibling_prefix(root) {
        if let Ok(entries) = std::fs::read_dir(&parent) {
            for entry in entries.flatten() {
                let name = entry.file_name();
                let name = name.to_string_lossy();
                let ours = name
                    .strip_prefix(&prefix)
                    .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()));
                if ours && entry.file_type().is_ok_and(|t| t.is_dir()) {
                    let path = entry.path();
                    std::fs::remove_dir_all(&path).map_err(|e| io(&path, e))?;
                }
            }
        }
    }
    let entries = std::fs::read_dir(root).map_err(|e| io(root, e))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        if !name.to_string_lossy().starts_with(STAGING_PREFIX) {
            continue;
        }
        let path = entry.path();
        let Ok(meta) = std::fs::symlink_metadata(&path) else {
            continue;
        };
        if !meta.is_dir() {
            std::fs::remove_file(&path).map_err(|e| io(&path, e))?;
        } else if std::fs::symlink_metadata(path.join(MANIFEST)).is_ok_and(|m| m.is_file()) {
            finish(root, &path)?;
        } else {
            std::fs::remove_dir_all(&path).map_err(|e| io(&path, e))?;
        }
    }
    Ok(())
}

/// The real path of `root`, its parent and the sibling staging folders' prefix
/// (`.<name>.coil-staging-`); `None` for the file system root.
fn sibling_prefix(root: &Path) -> Option<(PathBuf, String)> {
    let real = std::fs::canonicalize(root).ok()?;
    let parent = real.parent()?.to_path_buf();
    let name = real.file_name()?.to_string_lossy().into_owned();
    Some((parent, format!(".{name}{STAGING_PREFIX}")))
}

/// Creates the sibling staging folder if the swap can work here: Linux, a parent on
/// the same file system (not a mount point), writable. Returns it and `root`'s real path.
fn sibling_staging(root: &Path) -> Option<(PathBuf, PathBuf)> {
    use std::os::unix::fs::MetadataExt;
    if !cfg!(target_os = "linux") {
        return None;
    }
    let real = std::fs::canonicalize(root).ok()?;
    let (parent, prefix) = sibling_prefix(&real)?;
    let same_device =
        std::fs::metadata(&parent).ok()?.dev() == std::fs::metadata(&real).ok()?.dev();
    if !same_device {
        return None;
    }
    let staging = parent.join(format!("{prefix}{}", std::process::id()));
    std::fs::create_dir(&staging).ok()?;
    Some((staging, real))
}

/// Steps 3-5 of the module doc. `Ok(false)`: the swap is not possible here (nothing in
/// `real` changed; the caller moves the files one by one instead).
fn swap_in(real: &Path, staging: &Path) -> Result<bool, SetError> {
    let old = manifest_files(&real.join(MANIFEST), real);
    if !carry(real, staging, Path::new(""), &old)? {
        return Ok(false);
    }
    if let Ok(meta) = std::fs::metadata(real) {
        let _ = std::fs::set_permissions(staging, meta.permissions());
    }
    if !exchange(staging, real) {
        return Ok(false);
    }
    // `staging` now names the previous folder. Removing it frees the previous set; a
    // failure here leaves a hidden sibling that the next run removes.
    let _ = std::fs::remove_dir_all(staging);
    Ok(true)
}

/// Links into `staging` every entry of `real/rel` that is not a file of the previous
/// set (`old`) nor already staged (the new set wins); `Ok(false)` if one cannot be
/// carried (a FIFO, a socket, a device, or a file system without hard links).
fn carry(
    real: &Path,
    staging: &Path,
    rel: &Path,
    old: &BTreeSet<PathBuf>,
) -> Result<bool, SetError> {
    let here = real.join(rel);
    for entry in std::fs::read_dir(&here).map_err(|e| io(&here, e))? {
        let entry = entry.map_err(|e| io(&here, e))?;
        let name = rel.join(entry.file_name());
        if name.as_os_str() == MANIFEST || old.contains(&name) {
            continue;
        }
        let from = entry.path();
        let to = staging.join(&name);
        let meta = std::fs::symlink_metadata(&from).map_err(|e| io(&from, e))?;
        let staged = std::fs::symlink_metadata(&to).ok();
        if meta.is_dir() {
            match staged {
                Some(s) if s.is_dir() => {}
                Some(_) => continue,
                None => {
                    std::fs::create_dir(&to).map_err(|e| io(&to, e))?;
                    let _ = std::fs::set_permissions(&to, meta.permissions());
                }
            }
            if !carry(real, staging, &name, old)? {
                return Ok(false);
            }
        } else if staged.is_some() {
            continue;
        } else if meta.file_type().is_symlink() {
            let target = std::fs::read_link(&from).map_err(|e| io(&from, e))?;
            std::os::unix::fs::symlink(target, &to).map_err(|e| io(&to, e))?;
        } else if !meta.is_file() || std::fs::hard_link(&from, &to).is_err() {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Swaps two folders in one step (Linux `renameat2` with `RENAME_EXCHANGE`); false if
/// the system or the file system cannot.
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> bool {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let (Ok(a), Ok(b)) = (
        CString::new(a.as_os_str().as_bytes()),
        CString::new(b.as_os_str().as_bytes()),
    ) else {
        return false;
    };
    // SAFETY: two valid NUL-terminated paths; the call reads them and nothing else.
    let status = unsafe {
        libc::syscall(
            libc::SYS_renameat2,
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    status == 0
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> bool {
    false
}

/// The held lock file.
#[derive(Debug)]
struct Lock {
    path: PathBuf,
    content: String,
    held: bool,
}

/// This machine's name.
fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .or_else(|_| std::fs::read_to_string("/etc/hostname"))
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "unknown".into())
}

/// Whether `pid` is a live process here (`None`: cannot tell without `/proc`).
fn alive(pid: u32) -> Option<bool> {
    if !Path::new("/proc/self").exists() {
        return None;
    }
    Some(Path::new("/proc").join(pid.to_string()).exists())
}

impl Lock {
    fn take(root: &Path, command: &str) -> Result<Lock, SetError> {
        let path = root.join(LOCK);
        let content = format!(
            "pid {}\nhost {}\ncommand {}\n",
            std::process::id(),
            host(),
            excerpt_n(command, 200)
        );
        for _ in 0..4 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut file) => {
                    file.write_all(content.as_bytes())
                        .and_then(|()| file.sync_all())
                        .map_err(|e| io(&path, e))?;
                    return Ok(Lock {
                        path,
                        content,
                        held: true,
                    });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let meta = std::fs::symlink_metadata(&path).map_err(|e| io(&path, e))?;
                    if !meta.is_file() {
                        return Err(SetError::Write(WriteError::NotRegular {
                            path,
                            kind: kind_of(&meta),
                        }));
                    }
                    let held = read_lock(&path);
                    if is_stale(&held, &meta) {
                        // Remove only the stale lock we read, not a new one.
                        if read_lock(&path) == held {
                            let _ = std::fs::remove_file(&path);
                        }
                        continue;
                    }
                    let holder = held
                        .lines()
                        .map(|l| excerpt_n(l, 120))
                        .collect::<Vec<_>>()
                        .join(", ");
                    return Err(SetError::Locked {
                        root: root.into(),
                        holder,
                    });
                }
                Err(e) => return Err(io(&path, e)),
            }
        }
        Err(SetError::Locked {
            root: root.into(),
            holder: "runs keep taking it".into(),
        })
    }

    fn release(&mut self) {
        if self.held && read_lock(&self.path) == self.content {
            let _ = std::fs::remove_file(&self.path);
        }
        self.held = false;
    }
}

/// At most 4 KiB of a lock file.
fn read_lock(path: &Path) -> String {
    let mut text = String::new();
    if let Ok(file) = std::fs::File::open(path) {
        let _ = file.take(4096).read_to_string(&mut text);
    }
    text
}

/// A lock of a dead process on this host, or an unreadable one older than a minute.
fn is_stale(held: &str, meta: &std::fs::Metadata) -> bool {
    let field = |key: &str| {
        held.lines()
            .find_map(|l| l.strip_prefix(key).map(|v| v.trim().to_string()))
    };
    match (field("pid "), field("host ")) {
        (Some(pid), Some(h)) if h == host() => match pid.parse::<u32>() {
            Ok(pid) => alive(pid) == Some(false),
            Err(_) => false,
        },
        (Some(_), Some(_)) => false,
        // Half written (killed between creating and writing it) or junk.
        _ => meta
            .modified()
            .ok()
            .and_then(|m| m.elapsed().ok())
            .is_some_and(|age| age.as_secs() > 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_set_replaces_the_previous_one_whole() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let set = OutputSet::open(&out, "test one").unwrap();
        set.write(Path::new("a.txt"), b"1").unwrap();
        set.write(Path::new("sub/b.txt"), b"1").unwrap();
        assert_eq!(names(&out), [".coil-lock"], "staged beside, not inside");
        assert_eq!(
            names(dir.path()),
            [&format!(".out.coil-staging-{}", std::process::id()), "out"]
        );
        use std::os::unix::fs::MetadataExt;
        let before = std::fs::metadata(&out).unwrap().ino();
        set.commit().unwrap();
        assert_eq!(names(&out), [".coil-manifest", "a.txt", "sub"]);
        assert_eq!(names(dir.path()), ["out"], "the previous folder is removed");
        assert_ne!(std::fs::metadata(&out).unwrap().ino(), before, "swapped");

        // A failed run leaves the previous set.
        let set = OutputSet::open(&out, "test two").unwrap();
        set.write(Path::new("a.txt"), b"2").unwrap();
        drop(set);
        assert_eq!(names(&out), [".coil-manifest", "a.txt", "sub"]);
        assert_eq!(std::fs::read(out.join("a.txt")).unwrap(), b"1");

        // A new set without sub/b.txt removes it.
        let set = OutputSet::open(&out, "test three").unwrap();
        set.write(Path::new("a.txt"), b"3").unwrap();
        set.commit().unwrap();
        assert!(!out.join("sub/b.txt").exists());
        assert_eq!(std::fs::read(out.join("a.txt")).unwrap(), b"3");
    }

    #[test]
    fn names_stay_inside_and_destinations_must_be_regular() {
        let dir = tempfile::tempdir().unwrap();
        let set = OutputSet::open(dir.path(), "t").unwrap();
        for bad in ["../x", "/tmp/x", "a/../../x", "", ".coil-lock", "a\nb"] {
            assert!(set.write(Path::new(bad), b"x").is_err(), "{bad:?}");
        }
        std::os::unix::fs::symlink("/dev/null", dir.path().join("null.txt")).unwrap();
        set.write(Path::new("null.txt"), b"x").unwrap();
        set.write(Path::new("fine.txt"), b"x").unwrap();
        let e = set.commit().unwrap_err().to_string();
        assert!(e.contains("symlink"), "{e}");
        assert!(!dir.path().join("fine.txt").exists(), "nothing moved");
        assert!(std::fs::symlink_metadata(dir.path().join("null.txt"))
            .unwrap()
            .file_type()
            .is_symlink());
    }

    #[test]
    fn one_run_per_folder_and_stale_locks_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let first = OutputSet::open(dir.path(), "coil-solve a.dat").unwrap();
        let e = OutputSet::open(dir.path(), "second")
            .unwrap_err()
            .to_string();
        assert!(e.contains("another run holds"), "{e}");
        assert!(e.contains("coil-solve a.dat"), "{e}");
        assert!(e.contains(&format!("pid {}", std::process::id())), "{e}");
        drop(first);
        assert!(!dir.path().join(LOCK).exists());

        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        std::fs::write(
            dir.path().join(LOCK),
            format!("pid {dead}\nhost {}\ncommand killed\n", host()),
        )
        .unwrap();
        let staging = dir.path().join(".coil-staging-1");
        std::fs::create_dir(&staging).unwrap();
        std::fs::write(staging.join("half.txt"), "half").unwrap();
        let set = OutputSet::open(dir.path(), "after").unwrap();
        assert!(!staging.exists(), "an incomplete staging folder is removed");
        drop(set);
    }

    #[test]
    fn the_swap_carries_what_is_not_the_set() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let set = OutputSet::open(&out, "first").unwrap();
        set.write(Path::new("old.txt"), b"1").unwrap();
        set.write(Path::new("kept.txt"), b"1").unwrap();
        set.commit().unwrap();
        // A person's files, a journal appended in place, a symlink, a sub-folder.
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        std::fs::create_dir(out.join("mine")).unwrap();
        std::fs::write(out.join("mine/x.txt"), "x").unwrap();
        std::os::unix::fs::symlink("notes.txt", out.join("link")).unwrap();
        let set = OutputSet::open(&out, "second").unwrap();
        let journal = set.journal_path(Path::new("j/grid.jsonl")).unwrap();
        std::fs::write(&journal, "point\n").unwrap();
        set.write(Path::new("kept.txt"), b"2").unwrap();
        set.commit().unwrap();
        assert_eq!(
            names(&out),
            [
                ".coil-manifest",
                "j",
                "kept.txt",
                "link",
                "mine",
                "notes.txt"
            ]
        );
        assert_eq!(std::fs::read(out.join("kept.txt")).unwrap(), b"2");
        assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"mine");
        assert_eq!(std::fs::read(out.join("mine/x.txt")).unwrap(), b"x");
        assert_eq!(std::fs::read(out.join("link")).unwrap(), b"mine");
        assert_eq!(std::fs::read(&journal).unwrap(), b"point\n");
        use std::os::unix::fs::MetadataExt;
        let links = std::fs::metadata(&journal).unwrap().nlink();
        assert_eq!(links, 1, "the previous folder's link is gone");
        assert_eq!(names(dir.path()), ["out"]);
    }

    #[test]
    fn a_swap_killed_before_or_after_leaves_one_whole_set() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let set = OutputSet::open(&out, "first").unwrap();
        set.write(Path::new("a.txt"), b"old").unwrap();
        set.commit().unwrap();
        // Killed after carrying, before the swap: `out` is the previous set; the
        // sibling is removed by the next run.
        let set = OutputSet::open(&out, "killed").unwrap();
        set.write(Path::new("a.txt"), b"new").unwrap();
        let old = manifest_files(&out.join(MANIFEST), &out);
        assert!(carry(&out, set.staging(), Path::new(""), &old).unwrap());
        std::mem::forget(set);
        assert_eq!(std::fs::read(out.join("a.txt")).unwrap(), b"old");
        std::fs::remove_file(out.join(LOCK)).unwrap();
        drop(OutputSet::open(&out, "next").unwrap());
        assert_eq!(names(dir.path()), ["out"]);
        assert_eq!(names(&out), [".coil-manifest", "a.txt"]);
    }

    #[test]
    fn a_commit_killed_halfway_is_rolled_forward() {
        let dir = tempfile::tempdir().unwrap();
        let staging = dir.path().join(".coil-staging-7");
        std::fs::create_dir(&staging).unwrap();
        std::fs::write(staging.join("b.txt"), "new").unwrap();
        std::fs::write(dir.path().join("a.txt"), "new, moved before the kill").unwrap();
        std::fs::write(
            staging.join(MANIFEST),
            format!("{MANIFEST_HEADER}\na.txt\nb.txt\n"),
        )
        .unwrap();
        drop(OutputSet::open(dir.path(), "next").unwrap());
        assert_eq!(names(dir.path()), [".coil-manifest", "a.txt", "b.txt"]);
        assert_eq!(std::fs::read(dir.path().join("b.txt")).unwrap(), b"new");
    }
}
