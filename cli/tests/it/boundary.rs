//! The file boundary of the real `coil-tune` (issue 9, docs/files.md): record paths stay
//! in the case folder and errors never show a target's content; procedure files write
//! only inside their output folder; one run per output folder; junk records refused under
//! `calibrate` whatever the targets; negative damping grids refused; a closed stdout is
//! not a panic.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn coil_tune() -> Command {
    Command::new(env!("CARGO_BIN_EXE_coil-tune"))
}

fn run(args: &[&str], cwd: &Path) -> Output {
    coil_tune()
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn paper_case() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect")
}

/// Every path under `dir` (recursive), sorted: the sandbox snapshot.
fn tree(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    fn walk(root: &Path, at: &Path, out: &mut Vec<String>) {
        if let Ok(entries) = std::fs::read_dir(at) {
            for e in entries.flatten() {
                let p = e.path();
                out.push(p.strip_prefix(root).unwrap().display().to_string());
                if std::fs::symlink_metadata(&p).is_ok_and(|m| m.is_dir()) {
                    walk(root, &p, out);
                }
            }
        }
    }
    walk(dir, dir, &mut out);
    out.sort();
    out
}

const SECRET: &str = "root:SECRET-CONTENT:0:0";

/// A case folder whose static record entry is `entry`, inside `dir/case`.
fn case_with_record(dir: &Path, entry: &str) -> PathBuf {
    let case = dir.join("case");
    std::fs::create_dir_all(&case).unwrap();
    let text = std::fs::read_to_string(paper_case().join("case.json")).unwrap();
    let text = text.replace(
        r#""records": { "static": [], "decay": [] }"#,
        &format!(
            r#""records": {{ "static": [{}], "decay": [] }}"#,
            serde_json::json!(entry)
        ),
    );
    std::fs::write(case.join("case.json"), text).unwrap();
    case
}

#[test]
fn record_paths_stay_in_the_case_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("secret.csv"), format!("{SECRET}\n1,2\n")).unwrap();
    let cases = [
        ("../secret.csv", "`..` is not allowed"),
        ("/etc/passwd", "an absolute path"),
        ("/proc/self/environ", "an absolute path"),
        ("link.csv", "outside"),
        ("", "empty string"),
    ];
    for (entry, expected) in cases {
        let case = case_with_record(dir.path(), entry);
        let _ = std::fs::remove_file(case.join("link.csv"));
        std::os::unix::fs::symlink(dir.path().join("secret.csv"), case.join("link.csv")).unwrap();
        let o = run(&["calibrate", "case", "--out", "out"], dir.path());
        assert_eq!(o.status.code(), Some(1), "{entry}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains(expected), "{entry}: {e}");
        assert!(
            e.contains("case.json:"),
            "names the case file and line: {e}"
        );
        assert!(!e.contains("SECRET"), "never the target's content: {e}");
        assert!(!e.contains("PATH="), "never the environment: {e}");
        assert!(
            !dir.path().join("out").exists(),
            "{entry}: no output folder left"
        );
    }
}

#[test]
fn error_excerpts_of_user_files_are_short_and_clean() {
    let dir = tempfile::tempdir().unwrap();
    let case = case_with_record(dir.path(), "static.csv");
    let long = format!("\x1b[31m{}", "x".repeat(5000));
    std::fs::write(
        case.join("static.csv"),
        format!("displacement_mm,force_n\n1,{long}\n"),
    )
    .unwrap();
    let o = run(&["calibrate", "case", "--out", "out"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("static.csv:2"), "{e}");
    assert!(!e.contains('\x1b'), "control characters stripped: {e:?}");
    assert!(e.len() < 1000, "length capped: {} bytes", e.len());
}

#[test]
fn junk_records_are_refused_whatever_the_targets() {
    let dir = tempfile::tempdir().unwrap();
    let case = case_with_record(dir.path(), "static.csv");
    std::fs::write(case.join("static.csv"), "this is not a record\n").unwrap();
    let o = run(&["calibrate", "case", "--out", "out"], dir.path());
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("static.csv"), "{}", stderr(&o));
}

#[test]
fn procedures_write_only_inside_their_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let sandbox = dir.path();
    std::fs::create_dir(sandbox.join("work")).unwrap();
    let before = tree(sandbox);
    let case = paper_case();
    for (line, expected) in [
        ("mesh ../x.dat", "`..` is not allowed"),
        ("mesh /tmp/coil-escaped.dat", "an absolute path"),
        ("out /tmp/coil-escaped", "an absolute path"),
        ("out ../escaped", "`..` is not allowed"),
        (
            "grid alpha 0:1:1 beta 0:1e-5:1e-5 name ../../escaped",
            "grid name",
        ),
        (
            "grid alpha -0.1:0.1:0.1 beta 0:1e-5:1e-5",
            "negative damping",
        ),
    ] {
        let proc_file = sandbox.join("work/p.proc");
        std::fs::write(&proc_file, format!("case {}\n{line}\n", case.display())).unwrap();
        let o = run(&["run", "p.proc"], &sandbox.join("work"));
        assert_eq!(o.status.code(), Some(1), "{line}: {}", stderr(&o));
        assert!(stderr(&o).contains(expected), "{line}: {}", stderr(&o));
        assert!(stderr(&o).contains("p.proc:2"), "{line}: {}", stderr(&o));
    }
    let mut after = tree(sandbox);
    after.retain(|p| p != "work/p.proc");
    assert_eq!(before, after, "nothing created outside");
    assert!(!Path::new("/tmp/coil-escaped.dat").exists());
}

#[test]
fn negative_damping_grids_are_refused_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        &[
            "calibrate",
            paper_case().to_str().unwrap(),
            "--out",
            "out",
            "--grid",
            "alpha 0:0.1:0.2 beta -1e-5:1e-5:1e-5",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "a usage error: {}", stderr(&o));
    assert!(stderr(&o).contains("negative damping"), "{}", stderr(&o));
}

#[test]
fn a_held_output_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap_or_default();
    std::fs::write(
        out.join(".coil-lock"),
        format!(
            "pid {}\nhost {}\ncommand coil-tune paper\n",
            std::process::id(),
            host.trim()
        ),
    )
    .unwrap();
    let o = run(
        &["calibrate", paper_case().to_str().unwrap(), "--out", "out"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("another run holds"), "{}", stderr(&o));
    assert!(stderr(&o).contains("coil-tune paper"), "{}", stderr(&o));
}

/// `coil-tune run ... | head -1`: the reader leaves after one line; the run finishes,
/// writes its files and exits 0 without a panic.
#[test]
fn a_closed_stdout_is_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut lines = format!("case {}\nset elements_per_coil 8\n", paper_case().display());
    for k in 0..200 {
        lines.push_str(&format!("echo line {k}\n"));
    }
    lines.push_str("solve static\nsolve modal\n");
    for k in 0..200 {
        lines.push_str(&format!("echo after {k}\n"));
    }
    std::fs::write(dir.path().join("p.proc"), lines).unwrap();
    let mut child = coil_tune()
        .args(["run", "p.proc", "--out", "out"])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    // The reader is gone (the pipe's read end dropped above).
    let o = child.wait_with_output().unwrap();
    assert!(first.starts_with("case:"), "{first}");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert!(dir.path().join("out/procedure.json").is_file());
}
