//! One run per output folder, and its files as a whole set.
//!
//! **Lock.** [`OutputSet::open`] creates `<out>/.coil-lock` with `O_CREAT|O_EXCL`, holding
//! `pid`, `host` and `command`. A second run into the folder is refused with a message
//! naming the holder. A lock whose pid is not alive on this host (checked in `/proc`) is
//! stale (a killed run): it is taken over. A lock from another host is never taken over
//! (the message says to remove it by hand if that run is gone).
//!
//! **Staging.** Every file of the run is written into `<out>/.coil-staging-<pid>/` (same
//! file system, so moving is a rename). [`OutputSet::commit`] then
//! 1. writes the new manifest (the list of files) into the staging folder: the set is now
//!    complete;
//! 2. checks that every destination is absent or a regular file (else nothing moves);
//! 3. renames each file into `<out>`, removes the files of the previous set that the new
//!    one does not have, and renames the manifest to `<out>/.coil-manifest` last;
//! 4. removes the staging folder.
//!
//! A run that fails or is killed before step 1 leaves the previous set untouched; its
//! staging folder is removed when the set is dropped or, after a kill, by the next run.
//! A run killed during step 3 (renames only: no data is written, a full disk cannot stop
//! it) leaves a staging folder with a manifest, and the next run into the folder completes
//! the move first (roll forward). Until then `<out>/.coil-manifest` still lists the
//! previous set, so a reader can tell. Journals (resumable grids) are not part of a set:
//! they are appended in place ([`crate::write::open_journal`]) so that a killed run keeps
//! its points.

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
/// The staging folders' prefix.
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
}

fn io(path: &Path, e: std::io::Error) -> SetError {
    SetError::Write(WriteError::io(path, e))
}

/// A locked output folder and the files staged for it (see the module doc).
#[derive(Debug)]
pub struct OutputSet {
    root: PathBuf,
    staging: PathBuf,
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
        let staging = root.join(format!("{STAGING_PREFIX}{}", std::process::id()));
        std::fs::create_dir(&staging).map_err(|e| io(&staging, e))?;
        Ok(OutputSet {
            root: root.into(),
            staging,
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
        finish(&self.root, &self.staging)?;
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

/// What killed runs left in `root` (we hold the lock): a complete staging folder is
/// moved in, an incomplete one removed.
fn recover(root: &Path) -> Result<(), SetError> {
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
        assert_eq!(
            names(&out),
            [
                ".coil-lock",
                &format!(".coil-staging-{}", std::process::id())
            ]
        );
        set.commit().unwrap();
        assert_eq!(names(&out), [".coil-manifest", "a.txt", "sub"]);

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
