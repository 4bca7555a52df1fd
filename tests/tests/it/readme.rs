//! The README holds: every command in its `sh` blocks runs as written, in order, from a
//! fresh folder that holds only the repository's `cases/` (so nothing is written beside
//! them but `out/`), and every relative link in the repository's Markdown files points
//! at a file that exists; no link leaves the repository.
//!
//! Commands are taken from the README's ```` ```sh ```` blocks (continuation lines
//! joined, `#` comments dropped) and run by a small interpreter:
//! - `cargo run --release -p P --bin X -- ARGS` and `$B/X ARGS` run the binary X built
//!   beside this test (the README's test command, `cargo test --release --workspace`,
//!   builds every binary and example of the workspace into the same profile folder);
//! - `cargo run --release -p P --example E` runs the example E;
//! - `B=...` sets `$B`; `mkdir -p DIRS` creates the folders;
//! - `cargo build ...` and `cargo test ...` are what built and runs this test: skipped.
//!
//! When the binaries are missing (a `cargo test -p coil-tests` that did not build the
//! other packages' binaries) the command test says so and passes without running: the
//! README's own test command always builds them.

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// The profile folder this test was built into (`target/release` or `target/debug`).
fn profile_dir() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    // target/<profile>/deps/readme-HASH
    Some(exe.parent()?.parent()?.to_path_buf())
}

/// The shell commands of the README's `sh` blocks, continuation lines joined.
fn commands(readme: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_sh = false;
    let mut pending = String::new();
    for line in readme.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("```") {
            in_sh = !in_sh && trimmed == "```sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        // Comments: a whole-line `#`, or ` #` after the command.
        let code = if trimmed.starts_with('#') {
            ""
        } else {
            line.find(" #").map_or(line, |i| &line[..i])
        };
        let code = code.trim_end();
        if let Some(head) = code.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        pending.push_str(code);
        let command = pending.split_whitespace().collect::<Vec<_>>().join(" ");
        pending.clear();
        if !command.is_empty() {
            out.push(command);
        }
    }
    out
}

/// What to run for one README command.
#[derive(Debug, PartialEq)]
enum Step {
    Run { program: PathBuf, args: Vec<String> },
    Mkdir(Vec<String>),
    SetB(String),
    Skip,
}

fn step(command: &str, bins: &Path, b: &str) -> Step {
    let words: Vec<String> = command
        .split_whitespace()
        .map(|w| w.replace("$B", b))
        .collect();
    let exe = |name: &str| bins.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    match words.first().map(String::as_str) {
        Some("cargo") if words.get(1).map(String::as_str) == Some("run") => {
            let after = |flag: &str| {
                words
                    .iter()
                    .position(|w| w == flag)
                    .and_then(|i| words.get(i + 1))
            };
            let args: Vec<String> = words
                .iter()
                .position(|w| w == "--")
                .map_or_else(Vec::new, |i| words[i + 1..].to_vec());
            if let Some(bin) = after("--bin") {
                Step::Run {
                    program: exe(bin),
                    args,
                }
            } else if let Some(example) = after("--example") {
                Step::Run {
                    program: bins
                        .join("examples")
                        .join(format!("{example}{}", std::env::consts::EXE_SUFFIX)),
                    args,
                }
            } else if let Some(package) = after("-p") {
                // A package with one binary of its own name (`cargo run -p coil-tune`).
                Step::Run {
                    program: exe(package),
                    args,
                }
            } else {
                panic!("README: `{command}` names neither --bin, --example nor -p")
            }
        }
        Some("cargo") => Step::Skip,
        // The Python quickstart (`pip install ./python`, `python -c ...`) needs a venv and a
        // maturin build: .ci/run's Python stage runs both commands as written.
        Some("pip" | "python") => Step::Skip,
        Some("mkdir") => Step::Mkdir(words[1..].iter().filter(|w| *w != "-p").cloned().collect()),
        Some(w) if w.starts_with("B=") => Step::SetB(w[2..].to_string()),
        Some(program) if program.starts_with(b) && !b.is_empty() => {
            let name = Path::new(program)
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            Step::Run {
                program: exe(&name),
                args: words[1..].to_vec(),
            }
        }
        _ => panic!("README: the test cannot run `{command}`; teach tests/tests/readme.rs"),
    }
}

#[test]
fn readme_commands_run_as_written_and_write_only_under_out() {
    let repo = repo();
    let readme = std::fs::read_to_string(repo.join("README.md")).expect("README.md");
    let commands = commands(&readme);
    assert!(commands.len() >= 15, "found only {commands:?}");
    let Some(bins) = profile_dir() else {
        panic!("cannot locate the test's profile folder")
    };
    let missing: Vec<&str> = ["coil-mesh", "coil-solve", "coil-post", "coil-tune"]
        .into_iter()
        .filter(|b| {
            !bins
                .join(format!("{b}{}", std::env::consts::EXE_SUFFIX))
                .is_file()
        })
        .collect();
    if !missing.is_empty() {
        eprintln!(
            "skipped: {missing:?} not built in {} (run the README's test command, \
             `cargo test --release --workspace --locked`, which builds them)",
            bins.display()
        );
        return;
    }
    let work = tempfile::tempdir().expect("temp dir");
    let cases = work.path().join("cases");
    copy_dir(&repo.join("cases"), &cases);
    let mut b = String::new();
    for command in &commands {
        match step(command, &bins, &b) {
            Step::Skip => {}
            Step::SetB(value) => b = value,
            Step::Mkdir(dirs) => {
                for d in dirs {
                    std::fs::create_dir_all(work.path().join(d)).expect("mkdir");
                }
            }
            Step::Run { program, args } => {
                assert!(
                    program.is_file(),
                    "README: `{command}`: {} is not built",
                    program.display()
                );
                let start = std::time::Instant::now();
                let output = Command::new(&program)
                    .args(&args)
                    .current_dir(work.path())
                    .output()
                    .expect("runs");
                eprintln!("{:7.2} s  {command}", start.elapsed().as_secs_f64());
                assert!(
                    output.status.success(),
                    "README: `{command}` failed:\n{}\n{}",
                    String::from_utf8_lossy(&output.stdout),
                    String::from_utf8_lossy(&output.stderr)
                );
            }
        }
    }
    // Only `cases/` (the copy) and `out/` in the folder afterwards, `cases/` unchanged.
    let mut names: Vec<String> = std::fs::read_dir(work.path())
        .expect("read")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["cases", "out"],
        "the README's commands wrote beside out/"
    );
    assert_eq!(
        tree(&cases),
        tree(&repo.join("cases")),
        "a README command wrote into cases/"
    );
    for file in [
        "out/paper/report.md",
        "out/spring/results.json",
        "out/spring/case2_modes.pvd",
        "out/post/decay.png",
        "out/decay/history.csv",
        "out/coupling_g5/diagnosis.json",
        "out/friction_g1/diagnosis.json",
    ] {
        assert!(work.path().join(file).is_file(), "{file} not written");
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for entry in std::fs::read_dir(from).expect("read") {
        let entry = entry.expect("entry");
        let target = to.join(entry.file_name());
        if entry.file_type().expect("type").is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).expect("copy");
        }
    }
}

/// Relative paths and sizes of every file under `root`, sorted.
fn tree(root: &Path) -> Vec<(PathBuf, u64)> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("read") {
            let entry = entry.expect("entry");
            let path = entry.path();
            if entry.file_type().expect("type").is_dir() {
                stack.push(path);
            } else {
                let size = entry.metadata().expect("metadata").len();
                out.push((
                    path.strip_prefix(root).expect("under root").to_path_buf(),
                    size,
                ));
            }
        }
    }
    out.sort();
    out
}

/// Markdown files of the repository (not under target/ or out/).
fn markdown_files(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("read") {
            let entry = entry.expect("entry");
            let name = entry.file_name().to_string_lossy().into_owned();
            let path = entry.path();
            if entry.file_type().expect("type").is_dir() {
                if !name.starts_with('.') && name != "target" && name != "out" {
                    stack.push(path);
                }
            } else if name.ends_with(".md") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The targets of the inline links `[text](target)` of a Markdown text.
fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        if let Some(end) = rest.find(')') {
            out.push(rest[..end].to_string());
            rest = &rest[end..];
        }
    }
    out
}

#[test]
fn every_markdown_link_points_inside_the_repository_at_a_file_that_exists() {
    let repo = repo();
    let files = markdown_files(&repo);
    assert!(files.len() >= 10, "{files:?}");
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).expect("read");
        for target in links(&text) {
            let path = target.split('#').next().unwrap_or_default();
            if path.is_empty() {
                continue;
            }
            let is_url = path.contains("://") || path.starts_with("mailto:");
            // A link within the workspace: relative, and resolving inside the repository.
            let resolved = file.parent().expect("parent").join(path);
            let inside = !is_url
                && resolved
                    .canonicalize()
                    .is_ok_and(|p| p.starts_with(repo.canonicalize().expect("repo")));
            if !inside {
                broken.push(format!("{}: {target}", file.display()));
            }
            checked += 1;
        }
        // A path to the shared folder outside the repository is a link that leaves it.
        if text.contains("shared/spec/") {
            broken.push(format!("{}: names shared/spec/", file.display()));
        }
    }
    assert!(checked >= 20, "only {checked} links");
    assert!(
        broken.is_empty(),
        "broken or outside links:\n{}",
        broken.join("\n")
    );
}

#[test]
fn the_command_reader_joins_lines_and_drops_comments() {
    let text = "text\n```sh\n# a comment\n$B/coil-mesh --a 1 \\\n    --b 2 -o x.dat   # why\nmkdir -p out/a out/b\n```\n```\nnot a command\n```\n";
    assert_eq!(
        commands(text),
        ["$B/coil-mesh --a 1 --b 2 -o x.dat", "mkdir -p out/a out/b"]
    );
    let bins = Path::new("/bin-dir");
    assert_eq!(
        step(
            "cargo run --release -p coil-tune -- paper --out out/paper",
            bins,
            ""
        ),
        Step::Run {
            program: bins.join(format!("coil-tune{}", std::env::consts::EXE_SUFFIX)),
            args: vec!["paper".into(), "--out".into(), "out/paper".into()],
        }
    );
    assert_eq!(
        step("cargo test --release --workspace --locked", bins, ""),
        Step::Skip
    );
    assert_eq!(
        step("B=target/release", bins, ""),
        Step::SetB("target/release".into())
    );
}
