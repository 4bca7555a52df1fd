//! The file boundary of the real `coil-solve` (docs/files.md), run as the
//! calling user (root in CI containers: device nodes are made with `mknod` when allowed):
//! one run per `--out`, a stale lock taken over, outputs as a whole set that never
//! replaces or writes through a symlink, device or FIFO, a failed run that keeps the
//! previous set, empty decks refused, repeated set names read in linear memory, and the
//! transient work limit.

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn coil_solve(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_coil-solve"))
        .args(args)
        .output()
        .expect("coil-solve runs")
}

fn solve(deck: &Path, out: &Path) -> Output {
    coil_solve(&[deck.as_os_str(), "--out".as_ref(), out.as_os_str()])
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

fn cantilever() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/decks/good/cantilever_marc.dat")
}

fn this_host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "unknown".into())
}

#[test]
fn one_run_per_folder_and_a_stale_lock_is_taken_over() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    // A live holder: this test process.
    std::fs::write(
        out.join(".coil-lock"),
        format!(
            "pid {}\nhost {}\ncommand coil-solve other.dat\n",
            std::process::id(),
            this_host()
        ),
    )
    .unwrap();
    let o = solve(&cantilever(), &out);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("another run holds this output folder"), "{e}");
    assert!(e.contains("coil-solve other.dat"), "names the holder: {e}");
    assert_eq!(names(&out), [".coil-lock"]);

    // A dead holder (a killed run): taken over, its staging folder removed.
    let mut child = Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    std::fs::write(
        out.join(".coil-lock"),
        format!("pid {dead}\nhost {}\ncommand killed\n", this_host()),
    )
    .unwrap();
    std::fs::create_dir(out.join(".coil-staging-1")).unwrap();
    std::fs::write(out.join(".coil-staging-1/results.json"), "half").unwrap();
    let o = solve(&cantilever(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_whole_set(&out);
}

/// A committed set: manifest and results, no lock, no staging folder.
fn assert_whole_set(out: &Path) {
    let n = names(out);
    assert!(n.contains(&".coil-manifest".to_string()), "{n:?}");
    assert!(n.contains(&"results.json".to_string()), "{n:?}");
    assert!(
        !n.iter()
            .any(|f| f.starts_with(".coil-staging") || f == ".coil-lock"),
        "{n:?}"
    );
}

#[test]
fn outputs_never_replace_or_follow_special_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let outside = dir.path().join("outside.txt");
    std::fs::write(&outside, "keep").unwrap();

    // A symlink where an output goes.
    std::os::unix::fs::symlink(&outside, out.join("results.json")).unwrap();
    let o = solve(&cantilever(), &out);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("symlink"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), "keep");
    assert_eq!(names(&out), ["results.json"], "nothing of the set moved in");
    std::fs::remove_file(out.join("results.json")).unwrap();

    // A FIFO (opening it would block) and, where allowed (root), a device node.
    let fifo = out.join("model.vtu");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let o = solve(&cantilever(), &out);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("FIFO"), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    std::fs::remove_file(&fifo).unwrap();

    let device = out.join("case1_static.vtu");
    let made = Command::new("mknod")
        .arg(&device)
        .args(["c", "1", "3"])
        .status()
        .is_ok_and(|s| s.success());
    if made {
        let o = solve(&cantilever(), &out);
        assert!(!o.status.success());
        assert!(stderr(&o).contains("device node"), "{}", stderr(&o));
        let t = std::fs::symlink_metadata(&device).unwrap().file_type();
        assert!(t.is_char_device(), "the device node is left as it is");
        assert_eq!(names(&out), ["case1_static.vtu"]);
        std::fs::remove_file(&device).unwrap();
    } else {
        eprintln!("mknod not permitted here: device-node case skipped (it runs as root)");
    }
    // A symlink through /dev/null, the device every user can name.
    std::os::unix::fs::symlink("/dev/null", &device).unwrap();
    let o = solve(&cantilever(), &out);
    assert!(!o.status.success());
    assert!(std::fs::symlink_metadata(&device)
        .unwrap()
        .file_type()
        .is_symlink());
}

#[test]
fn a_failed_run_keeps_the_previous_set() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = solve(&cantilever(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(out.join("results.json")).unwrap();
    // Same mesh, no supports: a mechanism, found after the lock and before any write.
    let text = std::fs::read_to_string(cantilever()).unwrap();
    let free = text.replace("  1, 2, 3, 4, 5, 6\n  clamp,", "  1\n  tip,");
    let deck = dir.path().join("free.dat");
    std::fs::write(&deck, free).unwrap();
    let o = solve(&deck, &out);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), before);
    assert_whole_set(&out);
}

#[test]
fn decks_without_nodes_or_load_cases_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path().join("empty.dat");
    std::fs::write(&empty, "END\nEND OPTION\n").unwrap();
    let o = solve(&empty, &dir.path().join("out"));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("no nodes"), "{}", stderr(&o));
    assert!(
        !dir.path().join("out").exists(),
        "a folder the run created is removed"
    );

    let text = std::fs::read_to_string(cantilever()).unwrap();
    let cut = text.find("end option,").unwrap() + "end option,\n".len();
    let deck = dir.path().join("no_case.dat");
    std::fs::write(&deck, &text[..cut]).unwrap();
    let o = solve(&deck, &dir.path().join("out"));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("no load case"), "{}", stderr(&o));
}

#[test]
fn a_set_repeated_in_a_list_is_read_once() {
    // 100,000 references to a 10-element set: expanded before de-duplication this was
    // a million ids; read de-duplicated it is ten.
    let text = std::fs::read_to_string(cantilever()).unwrap();
    let mut list = String::from("define, element, set, many\n");
    for k in 0..10_000 {
        list.push_str(&["beam"; 10].join(", "));
        list.push_str(if k + 1 < 10_000 { ", C\n" } else { "\n" });
    }
    let deck = text.replace("isotropic,", &format!("{list}isotropic,"));
    let model = coil_solver::deck::read_str(&deck, "many.dat").unwrap();
    let many = model
        .element_sets()
        .iter()
        .find(|s| s.name == "many")
        .expect("the set");
    assert_eq!(many.elements.len(), 10);
}

/// A clamped cantilever of `n` type-52 beams along x with a tip load, then `cases`.
fn long_cantilever(n: usize, cases: &str) -> String {
    let mut d = format!(
        "title long\nsizing, 0, {n}, {}, 0\nelements, 52\nend,\nconnectivity,\n  0, 0, 1\n",
        n + 1
    );
    for e in 1..=n {
        d.push_str(&format!("  {e}, 52, {e}, {}\n", e + 1));
    }
    d.push_str(&format!("coordinates,\n  3, {}, 0, 1\n", n + 1));
    for k in 1..=n + 1 {
        d.push_str(&format!("  {k}, {}, 0.0, 0.0\n", 10.0 * (k - 1) as f64));
    }
    d.push_str(&format!(
        "isotropic,\n  1\n  1, steel\n  2.1+5, 0.3, 7.85-9, 0.0, 0.0\n  1 to {n}\n\
         geometry,\n  1\n  78.5398163397, 490.8738521234, 490.8738521234, 981.7477042468\n  0.0, 0.0, 1.0\n  1 to {n}\n\
         fixed disp,\n  0.0, 0.0, 0.0, 0.0, 0.0, 0.0\n  1, 2, 3, 4, 5, 6\n  1,\n\
         point load,\n  0.0, -100.0, 0.0\n  {},\nend option,\n{cases}",
        n + 1
    ));
    d
}

#[test]
fn a_transient_above_the_work_limit_needs_a_flag() {
    // 200 beams: 1200 free DOFs x 1e7 steps = 1.2e10 > 1e10 (under the 1e8-step guard).
    let deck = long_cantilever(200, "title, long\ndynamic change,\n1e-7, 1.0\ncontinue\n");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.dat");
    std::fs::write(&path, deck).unwrap();
    let started = std::time::Instant::now();
    let o = solve(&path, &dir.path().join("out"));
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("10000000 steps x 1200 DOFs"), "{e}");
    assert!(e.contains("--allow-large"), "{e}");
    // Refused before a step is taken (generous: debug build, a busy machine).
    assert!(started.elapsed().as_secs() < 60);
}

#[test]
fn a_transient_announces_its_steps() {
    let deck = long_cantilever(10, "title, short\ndynamic change,\n1e-4, 0.01\ncontinue\n");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("short.dat");
    std::fs::write(&path, deck).unwrap();
    let o = solve(&path, &dir.path().join("out"));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("transient of 100 steps of 0.0001 s, 60 DOFs"),
        "{}",
        stderr(&o)
    );
}

/// A run killed by SIGKILL mid-analysis leaves the previous set, a stale lock and a
/// staging folder; the next run takes the lock over, removes the staging folder and
/// writes its own whole set.
#[test]
fn a_killed_run_leaves_the_previous_set_and_the_next_run_cleans_up() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = solve(&cantilever(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(out.join("results.json")).unwrap();
    // Long enough to be killed mid-way (1200 DOFs x 2e6 steps; the limit is waived).
    let deck = long_cantilever(200, "title, long\ndynamic change,\n1e-6, 2.0\ncontinue\n");
    let path = dir.path().join("long.dat");
    std::fs::write(&path, deck).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_coil-solve"))
        .arg(&path)
        .args([
            "--out".as_ref(),
            out.as_os_str(),
            "--allow-large".as_ref(),
            "--quiet".as_ref(),
        ])
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    // The run stages its files in a hidden sibling of the output folder.
    while !names(out.parent().unwrap())
        .iter()
        .any(|n| n.contains(".coil-staging"))
    {
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before the kill"
        );
        assert!(start.elapsed().as_secs() < 60, "never started");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    std::thread::sleep(std::time::Duration::from_millis(200));
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), before);
    assert!(names(&out).contains(&".coil-lock".to_string()));

    let o = solve(&cantilever(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_whole_set(&out);
}

/// Unmounts on drop (the test may fail between mount and unmount).
struct Mounted(PathBuf);

impl Drop for Mounted {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

/// A full disk (a 64 KiB tmpfs, mounted where permitted: root) stops a run mid-write:
/// the previous set stays, byte for byte, and no staging folder is left.
#[test]
fn a_full_disk_keeps_the_previous_set() {
    let dir = tempfile::tempdir().unwrap();
    let disk = dir.path().join("disk");
    std::fs::create_dir(&disk).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
        .arg(&disk)
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("mount not permitted here: full-disk case skipped (it runs as root)");
        return;
    }
    let _guard = Mounted(disk.clone());
    let out = disk.join("out");
    let o = solve(&cantilever(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(out.join("results.json")).unwrap();
    let listing = names(&out);
    // 400 beams: its VTU files do not fit in what is left.
    let deck = long_cantilever(
        400,
        "title, push\nauto load,\n  1, 0, 0\ntime step,\n  1.0,\ncontinue,\n",
    );
    let path = dir.path().join("big.dat");
    std::fs::write(&path, deck).unwrap();
    let o = solve(&path, &out);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("No space left"), "{}", stderr(&o));
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), before);
    assert_eq!(names(&out), listing);
}

/// Past 2 s a transient shows progress on a piped stderr (plain lines, not a terminal).
#[test]
fn a_long_transient_shows_progress_when_piped() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    let deck = long_cantilever(200, "title, long\ndynamic change,\n1e-6, 2.0\ncontinue\n");
    let path = dir.path().join("long.dat");
    std::fs::write(&path, deck).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_coil-solve"))
        .arg(&path)
        .args([
            "--out".as_ref(),
            dir.path().join("out").as_os_str(),
            "--allow-large".as_ref(),
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = std::io::BufReader::new(child.stderr.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    assert!(first.contains("transient of 2000000 steps"), "{first}");
    let progress = lines.next().unwrap().unwrap();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        progress.starts_with("load case 'long': ") && progress.contains("/2000000 steps ("),
        "{progress}"
    );
}
