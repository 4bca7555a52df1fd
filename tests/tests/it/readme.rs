//! The README holds: every command in its `sh` blocks runs as written, in order, from a
//! fresh folder that holds only the repository's `cases/` (so nothing is written beside
//! them but `out/`); what each block prints agrees with the README's output block that
//! follows it; and every relative link in the repository's Markdown files points at a
//! file that exists; no link leaves the repository.
//!
//! # Commands
//! Taken from the README's ```` ```sh ```` blocks (continuation lines joined, `#`
//! comments dropped) and run by a small interpreter:
//! - `cargo run --release -p P --bin X -- ARGS` and `$B/X ARGS` run the binary X built
//!   beside this test; `cargo run --release -p P --example E` runs the example E. The
//!   package P must own X or E (read from the members' `Cargo.toml` and `examples/`), so
//!   a command that cargo would refuse fails here too;
//! - `B=...` sets `$B`; `mkdir -p DIRS` creates the folders;
//! - `grep -F "TEXT" FILE` prints the lines of FILE (a file an earlier command wrote)
//!   that hold TEXT, as grep does, so that a number the README quotes from a report is
//!   compared like a printed one; no line found fails, as grep's exit status 1 would;
//! - `cargo build ...` and `cargo test ...` are what built and runs this test: skipped;
//! - `pip` and `python`: the Python quickstart needs a venv and a maturin build; `.ci/run`
//!   runs it as written and compares its printed number with the README's.
//!
//! When a binary is missing (a `cargo test -p coil-tests` that did not build the other
//! packages' binaries), the test builds the workspace's binaries and examples into its own
//! profile and fails if that does not give them: never a silent pass.
//!
//! # Printed numbers
//! The first plain ```` ``` ```` block after a `sh` block (before the next `sh` block) is
//! what that block's commands print; the README may show an excerpt. Each of its lines
//! must be printed by the block's commands (stdout, then stderr), in order where the order
//! is ambiguous: the line's words must match exactly (runs of spaces are one space) and
//! its numbers, in place, by this rule:
//! - a number with a decimal point or an exponent: within one unit of the README's last
//!   printed digit (`3.8641` within 1e-4, `1.0893e-4` within 1e-8, `+0.01%` within 0.01);
//! - a number without (a count, an index, a wire size in whole mm): exactly;
//! - a wall-clock time, written `(X s)`: depends on the machine's load, so it need only be
//!   a number;
//! - a line ending in `...` is an excerpt: the printed line need only start with it.
//!
//! The failure names the README's line, the command, the expected and the printed line and
//! every number out of tolerance. Everything this file runs is the second CI stage
//! (`claim_`, `#[ignore]`d: about 2-4 minutes on the loaded 2-core machine, most of it
//! the EN 50318 catenary run and the damping benchmark):
//! `cargo test --release -p coil-tests --test it claim_readme -- --ignored --nocapture`.

use std::collections::BTreeMap;
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
    // target/<profile>/deps/it-HASH
    Some(exe.parent()?.parent()?.to_path_buf())
}

/// One `sh` block: its commands and the output block that follows it, if any.
#[derive(Debug, Default, PartialEq)]
struct Block {
    /// README line of the block's opening fence (1-based).
    line: usize,
    commands: Vec<String>,
    /// (README line, text) of each line of the output block.
    output: Vec<(usize, String)>,
}

/// The README's `sh` blocks with their commands (continuation lines joined, comments
/// dropped) and the plain block that follows each.
fn blocks(readme: &str) -> Vec<Block> {
    #[derive(PartialEq)]
    enum Fence {
        Outside,
        Sh,
        Output,
        Other,
    }
    let mut out: Vec<Block> = Vec::new();
    let mut fence = Fence::Outside;
    let mut pending = String::new();
    // Whether the last `sh` block may still take an output block.
    let mut open = false;
    for (i, line) in readme.lines().enumerate() {
        let trimmed = line.trim_start();
        if let Some(lang) = trimmed.strip_prefix("```") {
            fence = match fence {
                Fence::Outside => match lang.trim() {
                    "sh" => {
                        out.push(Block {
                            line: i + 1,
                            ..Block::default()
                        });
                        open = true;
                        Fence::Sh
                    }
                    "" if open => Fence::Output,
                    _ => Fence::Other,
                },
                Fence::Output => {
                    open = false;
                    Fence::Outside
                }
                _ => Fence::Outside,
            };
            continue;
        }
        match fence {
            Fence::Sh => {
                let block = out.last_mut().expect("inside a sh block");
                if let Some(command) = command_line(line, &mut pending) {
                    block.commands.push(command);
                }
            }
            Fence::Output => {
                let block = out.last_mut().expect("after a sh block");
                if !line.trim().is_empty() {
                    block.output.push((i + 1, line.to_string()));
                }
            }
            _ => {}
        }
    }
    out
}

/// Adds one line of a `sh` block to `pending`; returns the whole command when it ends.
fn command_line(line: &str, pending: &mut String) -> Option<String> {
    let trimmed = line.trim_start();
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
        return None;
    }
    pending.push_str(code);
    let command = pending.split_whitespace().collect::<Vec<_>>().join(" ");
    pending.clear();
    (!command.is_empty()).then_some(command)
}

/// The shell commands of the README's `sh` blocks, in order.
fn commands(readme: &str) -> Vec<String> {
    blocks(readme)
        .into_iter()
        .flat_map(|b| b.commands)
        .collect()
}

/// The workspace's packages: name -> (binaries, examples).
type Packages = BTreeMap<String, (Vec<String>, Vec<String>)>;

/// Reads the members' `Cargo.toml` (package name, `[[bin]]` names or `src/main.rs`) and
/// their `examples/*.rs`.
fn packages(repo: &Path) -> Packages {
    let mut out = Packages::new();
    for entry in std::fs::read_dir(repo).expect("read the repository") {
        let dir = entry.expect("entry").path();
        let Ok(manifest) = std::fs::read_to_string(dir.join("Cargo.toml")) else {
            continue;
        };
        let mut section = String::new();
        let mut name = None;
        let mut bins = Vec::new();
        for line in manifest.lines().map(str::trim) {
            if line.starts_with('[') {
                section = line.to_string();
            } else if let Some(value) = line.strip_prefix("name = ") {
                let value = value.trim_matches('"').to_string();
                match section.as_str() {
                    "[package]" => name = Some(value),
                    "[[bin]]" => bins.push(value),
                    _ => {}
                }
            }
        }
        let Some(name) = name else { continue };
        if bins.is_empty() && dir.join("src/main.rs").is_file() {
            bins.push(name.clone());
        }
        let mut examples: Vec<String> = std::fs::read_dir(dir.join("examples"))
            .into_iter()
            .flatten()
            .filter_map(|e| {
                let path = e.ok()?.path();
                (path.extension()? == "rs").then(|| path.file_stem()?.to_str().map(String::from))?
            })
            .collect();
        examples.sort();
        out.insert(name, (bins, examples));
    }
    out
}

/// What to run for one README command.
#[derive(Debug, PartialEq)]
enum Step {
    Run {
        program: PathBuf,
        args: Vec<String>,
    },
    Mkdir(Vec<String>),
    SetB(String),
    /// `grep -F TEXT FILE`: the lines of FILE that hold TEXT.
    Grep {
        text: String,
        file: String,
    },
    /// A build or test command (what built this test).
    Skip,
    /// The Python quickstart, run and compared by `.ci/run`.
    Python,
}

/// What to run for `command`, or why the README's command would not run as written.
fn step(command: &str, bins: &Path, b: &str, packages: &Packages) -> Result<Step, String> {
    let words: Vec<String> = shell_words(command)?
        .into_iter()
        .map(|w| w.replace("$B", b))
        .collect();
    let exe = |name: &str| bins.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    Ok(match words.first().map(String::as_str) {
        Some("cargo") if words.get(1).map(String::as_str) == Some("run") => {
            return cargo_run(command, &words, packages, bins)
        }
        Some("cargo") => Step::Skip,
        Some("pip" | "python") => Step::Python,
        Some("grep") => match &words[1..] {
            [flag, text, file] if flag == "-F" => Step::Grep {
                text: text.clone(),
                file: file.clone(),
            },
            _ => {
                return Err(format!(
                    "README: `{command}`: the test reads `grep -F \"TEXT\" FILE` only"
                ))
            }
        },
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
        _ => {
            return Err(format!(
                "README: the test cannot run `{command}`; teach tests/tests/it/readme.rs"
            ))
        }
    })
}

/// A command's words as a POSIX shell splits them: whitespace separates words outside
/// quotes; single and double quotes group (no escapes or expansions inside: the README's
/// commands need none).
fn shell_words(command: &str) -> Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut word: Option<String> = None;
    let mut quote: Option<char> = None;
    for c in command.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.get_or_insert_with(String::new).push(c),
            (None, '"' | '\'') => {
                quote = Some(c);
                word.get_or_insert_with(String::new);
            }
            (None, c) if c.is_whitespace() => words.extend(word.take()),
            (None, c) => word.get_or_insert_with(String::new).push(c),
        }
    }
    if let Some(q) = quote {
        return Err(format!("README: `{command}`: an unclosed {q}"));
    }
    words.extend(word);
    Ok(words)
}

/// `cargo run --release -p P [--bin X | --example E] -- ARGS`, checked against the
/// workspace as cargo would check it.
fn cargo_run(
    command: &str,
    words: &[String],
    packages: &Packages,
    bins: &Path,
) -> Result<Step, String> {
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
    let Some(package) = after("-p") else {
        return Err(format!("README: `{command}` names no package (-p)"));
    };
    let Some((package_bins, package_examples)) = packages.get(package.as_str()) else {
        return Err(format!(
            "README: `{command}`: no package {package} in the workspace (packages: {:?})",
            packages.keys().collect::<Vec<_>>()
        ));
    };
    let exe =
        |dir: PathBuf, name: &str| dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    if let Some(example) = after("--example") {
        if !package_examples.contains(example) {
            return Err(format!(
                "README: `{command}`: package {package} has no example {example} (examples: {package_examples:?})"
            ));
        }
        return Ok(Step::Run {
            program: exe(bins.join("examples"), example),
            args,
        });
    }
    let bin = match after("--bin") {
        Some(bin) => bin.clone(),
        None if package_bins.len() == 1 => package_bins[0].clone(),
        // A package with several binaries names its `default-run` (coil-tune does).
        None if package_bins.iter().any(|b| b.as_str() == package.as_str()) => package.to_string(),
        None => {
            return Err(format!(
                "README: `{command}`: package {package} has binaries {package_bins:?}; cargo needs --bin"
            ))
        }
    };
    if !package_bins.contains(&bin) {
        return Err(format!(
            "README: `{command}`: package {package} has no binary {bin} (binaries: {package_bins:?})"
        ));
    }
    Ok(Step::Run {
        program: exe(bins.to_path_buf(), &bin),
        args,
    })
}

/// A number as printed: its value, one unit of its last digit (0 for an exact integer)
/// and whether it is a wall-clock time.
#[derive(Debug, Clone, PartialEq)]
struct Number {
    value: f64,
    unit: f64,
    timing: bool,
    text: String,
}

/// A printed line: its words with every number replaced by `<n>` (runs of whitespace one
/// space) and its numbers.
#[derive(Debug, Clone, PartialEq)]
struct Printed {
    skeleton: String,
    numbers: Vec<Number>,
}

/// Splits a line into its skeleton and its numbers (see the module doc for the rule).
fn printed(line: &str) -> Printed {
    let chars: Vec<char> = line.chars().collect();
    let mut skeleton = String::new();
    let mut numbers = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let prev = if i == 0 { ' ' } else { chars[i - 1] };
        let starts_word = !(prev.is_alphanumeric() || prev == '_' || prev == '.');
        let signed =
            matches!(chars[i], '+' | '-') && chars.get(i + 1).is_some_and(char::is_ascii_digit);
        if starts_word && (chars[i].is_ascii_digit() || signed) {
            let (number, end) = number_at(&chars, i);
            let timing = skeleton.ends_with('(')
                && chars[end..].iter().collect::<String>().starts_with(" s)");
            numbers.push(Number { timing, ..number });
            skeleton.push_str("<n>");
            i = end;
        } else {
            skeleton.push(chars[i]);
            i += 1;
        }
    }
    Printed {
        skeleton: skeleton.split_whitespace().collect::<Vec<_>>().join(" "),
        numbers,
    }
}

/// The number starting at `start`: `[+-]digits[.digits][e[+-]digits]`.
fn number_at(chars: &[char], start: usize) -> (Number, usize) {
    let digits = |mut i: usize| {
        while chars.get(i).is_some_and(char::is_ascii_digit) {
            i += 1;
        }
        i
    };
    let mut end = digits(start + usize::from(!chars[start].is_ascii_digit()));
    let mut decimals = None;
    if chars.get(end) == Some(&'.') && chars.get(end + 1).is_some_and(char::is_ascii_digit) {
        let after = digits(end + 1);
        decimals = Some(after - end - 1);
        end = after;
    }
    let mut exponent = None;
    if matches!(chars.get(end), Some('e' | 'E')) {
        let sign = usize::from(matches!(chars.get(end + 1), Some('+' | '-')));
        if chars.get(end + 1 + sign).is_some_and(char::is_ascii_digit) {
            let after = digits(end + 1 + sign);
            exponent = chars[end + 1..after]
                .iter()
                .collect::<String>()
                .parse::<i32>()
                .ok();
            end = after;
        }
    }
    let text: String = chars[start..end].iter().collect();
    let value = text.parse::<f64>().unwrap_or(f64::NAN);
    let unit = match (decimals, exponent) {
        (None, None) => 0.0,
        (d, e) => 10f64.powi(e.unwrap_or(0) - d.unwrap_or(0) as i32),
    };
    let number = Number {
        value,
        unit,
        timing: false,
        text,
    };
    (number, end)
}

/// Why a printed line does not agree with the README's, or `None` when it does. An
/// expected line ending in `...` is an excerpt of the printed one.
fn disagreement(expected: &str, actual: &str) -> Option<String> {
    let (expected, excerpt) = match expected.trim_end().strip_suffix("...") {
        Some(head) => (head, true),
        None => (expected, false),
    };
    let (e, a) = (printed(expected), printed(actual));
    let same_words = if excerpt {
        a.skeleton.starts_with(e.skeleton.trim_end()) && a.numbers.len() >= e.numbers.len()
    } else {
        a.skeleton == e.skeleton
    };
    if !same_words {
        return Some("other words".to_string());
    }
    let off: Vec<String> = e
        .numbers
        .iter()
        .zip(&a.numbers)
        .enumerate()
        .filter(|(_, (e, a))| {
            let close = (a.value - e.value).abs() <= e.unit * (1.0 + 1e-9);
            !(close || (e.timing && a.timing && a.value >= 0.0))
        })
        .map(|(k, (e, a))| {
            let tolerance = if e.unit == 0.0 {
                "exactly".to_string()
            } else {
                format!("+- {:e}", e.unit)
            };
            format!(
                "number {}: README {} ({tolerance}), printed {}",
                k + 1,
                e.text,
                a.text
            )
        })
        .collect();
    (!off.is_empty()).then(|| off.join("; "))
}

/// Checks a block's output lines against what its commands printed; returns one message
/// per disagreement.
fn compare(block: &Block, printed_text: &str, what: &str) -> Vec<String> {
    let lines: Vec<&str> = printed_text.lines().collect();
    let mut used = vec![false; lines.len()];
    let mut next = 0;
    let mut failures = Vec::new();
    for (line_no, expected) in &block.output {
        // The first unused printed line with the same words, after the previous match if
        // there is one there (tables repeat their words row after row).
        let same_words = |i: &usize| {
            !used[*i] && disagreement(expected, lines[*i]).is_none_or(|why| why != "other words")
        };
        let found = (next..lines.len())
            .find(same_words)
            .or_else(|| (0..lines.len()).find(same_words));
        match found {
            Some(i) => {
                used[i] = true;
                next = i + 1;
                if let Some(why) = disagreement(expected, lines[i]) {
                    failures.push(format!(
                        "README.md:{line_no}: `{}`\n    {what} printed `{}`\n    {why}",
                        expected.trim(),
                        lines[i].trim()
                    ));
                }
            }
            None => failures.push(format!(
                "README.md:{line_no}: `{}`\n    {what} printed no line with these words",
                expected.trim()
            )),
        }
    }
    failures
}

/// Builds the workspace's binaries and examples into this test's profile when one of
/// them is missing, and fails if they are still missing.
fn ensure_built(bins: &Path, names: &[&str]) {
    let missing = |names: &[&str]| -> Vec<String> {
        names
            .iter()
            .filter(|b| {
                !bins
                    .join(format!("{b}{}", std::env::consts::EXE_SUFFIX))
                    .is_file()
            })
            .map(|b| b.to_string())
            .collect()
    };
    if missing(names).is_empty() {
        return;
    }
    let release = bins.file_name().is_some_and(|n| n == "release");
    let mut cargo = Command::new(env!("CARGO"));
    cargo
        .args(["build", "--workspace", "--bins", "--examples", "--locked"])
        .current_dir(repo());
    if release {
        cargo.arg("--release");
    }
    eprintln!("building the workspace's binaries and examples: {cargo:?}");
    let status = cargo.status().expect("runs cargo");
    let still = missing(names);
    assert!(
        status.success() && still.is_empty(),
        "{still:?} not built in {} (cargo build: {status}); run the README's test command, \
         `cargo test --release --workspace --locked`, which builds them",
        bins.display()
    );
}

/// Runs one block's commands in `work`; returns what they printed (stdout, then stderr).
fn run_block(
    block: &Block,
    work: &Path,
    bins: &Path,
    b: &mut String,
    packages: &Packages,
) -> (String, bool) {
    let mut printed = String::new();
    let mut python = false;
    for command in &block.commands {
        match step(command, bins, b, packages).unwrap_or_else(|why| panic!("{why}")) {
            Step::Skip => {}
            Step::Python => python = true,
            Step::SetB(value) => *b = value,
            Step::Mkdir(dirs) => {
                for d in dirs {
                    std::fs::create_dir_all(work.join(d)).expect("mkdir");
                }
            }
            Step::Grep { text, file } => {
                let body = std::fs::read_to_string(work.join(&file))
                    .unwrap_or_else(|e| panic!("README: `{command}`: {file}: {e}"));
                let lines: Vec<&str> = body.lines().filter(|l| l.contains(&text)).collect();
                assert!(
                    !lines.is_empty(),
                    "README: `{command}`: no line of {file} holds {text:?}"
                );
                for line in lines {
                    printed.push_str(line);
                    printed.push('\n');
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
                    .current_dir(work)
                    .output()
                    .expect("runs");
                eprintln!("{:7.2} s  {command}", start.elapsed().as_secs_f64());
                let (stdout, stderr) = (
                    String::from_utf8_lossy(&output.stdout),
                    String::from_utf8_lossy(&output.stderr),
                );
                assert!(
                    output.status.success(),
                    "README: `{command}` failed:\n{stdout}\n{stderr}"
                );
                printed.push_str(&stdout);
                printed.push_str(&stderr);
            }
        }
    }
    (printed, python)
}

#[test]
#[ignore = "second CI stage"]
fn claim_readme_commands_print_what_the_readme_says() {
    let repo = repo();
    let readme = std::fs::read_to_string(repo.join("README.md")).expect("README.md");
    let blocks = blocks(&readme);
    let count: usize = blocks.iter().map(|b| b.commands.len()).sum();
    assert!(count >= 15, "found only {blocks:?}");
    let Some(bins) = profile_dir() else {
        panic!("cannot locate the test's profile folder")
    };
    ensure_built(
        &bins,
        &["coil-mesh", "coil-solve", "coil-post", "coil-tune"],
    );
    let packages = packages(&repo);
    let work = tempfile::tempdir().expect("temp dir");
    let cases = work.path().join("cases");
    copy_dir(&repo.join("cases"), &cases);
    let mut b = String::new();
    let mut failures = Vec::new();
    let mut compared = 0;
    for block in &blocks {
        let (printed, python) = run_block(block, work.path(), &bins, &mut b, &packages);
        if block.output.is_empty() {
            continue;
        }
        if python {
            eprintln!(
                "README.md:{}: the Python quickstart's output is compared by .ci/run",
                block.line
            );
            continue;
        }
        let what = format!("the block of README.md:{}", block.line);
        let found = compare(block, &printed, &what);
        if !found.is_empty() {
            failures.push(format!(
                "{}\n  --- what it printed ---\n{printed}",
                found.join("\n")
            ));
        }
        compared += block.output.len();
    }
    assert!(compared >= 20, "compared only {compared} README lines");
    assert!(
        failures.is_empty(),
        "the README disagrees with what its commands print (rule: tests/tests/it/readme.rs):\n{}",
        failures.join("\n\n")
    );
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
        "out/catenary/catenary.json",
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

/// The README's blocks as this file reads them: every command block is `sh` (a command in
/// a `text` block would never run), and the README's own test command and quickstart are
/// among them.
#[test]
fn the_readme_keeps_its_commands_in_sh_blocks() {
    let readme = std::fs::read_to_string(repo().join("README.md")).expect("README.md");
    for (i, line) in readme.lines().enumerate() {
        let fence = line.trim_start().strip_prefix("```");
        assert!(
            !matches!(fence.map(str::trim), Some("text" | "bash" | "shell" | "console")),
            "README.md:{}: `{line}`: commands go in ```sh blocks, printed output in plain ``` blocks",
            i + 1
        );
    }
    let commands = commands(&readme);
    for needed in [
        "cargo test --release --workspace --locked",
        "cargo run --release -p coil-tune -- paper --out out/paper",
    ] {
        assert!(
            commands.iter().any(|c| c == needed),
            "{needed} not in {commands:?}"
        );
    }
}

#[test]
fn the_command_reader_joins_lines_and_drops_comments() {
    let text = "text\n```sh\n# a comment\n$B/coil-mesh --a 1 \\\n    --b 2 -o x.dat   # why\nmkdir -p out/a out/b\n```\nsome text\n```\nK = 3.8641 N/mm\n```\n```\nnot a command\n```\n";
    let read = blocks(text);
    assert_eq!(
        read,
        [Block {
            line: 2,
            commands: vec![
                "$B/coil-mesh --a 1 --b 2 -o x.dat".into(),
                "mkdir -p out/a out/b".into()
            ],
            output: vec![(10, "K = 3.8641 N/mm".into())],
        }]
    );
    let packages = packages(&repo());
    let bins = Path::new("/bin-dir");
    let exe = |name: &str| bins.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    let step = |command: &str| step(command, bins, "", &packages);
    assert_eq!(
        step("cargo run --release -p coil-tune -- paper --out out/paper"),
        Ok(Step::Run {
            program: exe("coil-tune"),
            args: vec!["paper".into(), "--out".into(), "out/paper".into()],
        })
    );
    assert_eq!(
        step("cargo test --release --workspace --locked"),
        Ok(Step::Skip)
    );
    assert_eq!(
        step("B=target/release"),
        Ok(Step::SetB("target/release".into()))
    );
    // cargo refuses a binary or an example the package does not own: so does the reader.
    let wrong = step("cargo run --release -p coil-tuner --bin coil-tune -- check x");
    assert!(wrong.is_err_and(|why| why.contains("package coil-tuner has no binary coil-tune")));
    assert!(step("cargo run --release -p coil-tune --example quickstart").is_err());
    assert!(step("cargo run --release -p coil-mesher --example quickstart").is_ok());
    // Quotes group words, as the shell's do.
    assert_eq!(
        step(r#"grep -F "valley, alpha = 0" out/paper/report.md"#),
        Ok(Step::Grep {
            text: "valley, alpha = 0".into(),
            file: "out/paper/report.md".into(),
        })
    );
    assert_eq!(
        shell_words("a 'b  c' \"\" d"),
        Ok(vec!["a".into(), "b  c".into(), String::new(), "d".into()])
    );
    assert!(step("grep valley out/paper/report.md").is_err());
    assert!(step("grep -F \"open out/x").is_err());
}

#[test]
fn printed_numbers_are_compared_at_the_readmes_precision() {
    let p =
        printed("| #2 | 14 | 24 | 3.5 | 7.273 | 7.2530 | -0.27% | 1.0893e-4 s (4.5 s) node1_uz");
    assert_eq!(
        p.skeleton,
        "| #<n> | <n> | <n> | <n> | <n> | <n> | <n>% | <n> s (<n> s) node1_uz"
    );
    let units: Vec<f64> = p.numbers.iter().map(|n| n.unit).collect();
    assert_eq!(units, [0.0, 0.0, 0.0, 0.1, 0.001, 1e-4, 0.01, 1e-8, 0.1]);
    assert!(p.numbers[8].timing && !p.numbers[7].timing);
    // Within one unit of the last digit; a count exactly; a time only a number.
    assert_eq!(disagreement("K 3.8641 N/mm", "K 3.86419 N/mm"), None);
    assert!(disagreement("K 3.8641 N/mm", "K 3.8643 N/mm").is_some());
    assert!(disagreement("48 tried", "49 tried").is_some());
    assert_eq!(
        disagreement("gain 0.07 (4.5 s)", "gain 0.07 (12.25 s)"),
        None
    );
    assert_eq!(disagreement("x 0.00174, ...", "x 0.00174, y 2, z"), None);
    assert_eq!(disagreement("3.92749937...", "3.9274993712"), None);
    assert_eq!(
        disagreement("zeta 0.0017", "alpha 0.0017"),
        Some("other words".to_string())
    );
    let block = Block {
        line: 1,
        commands: vec![],
        output: vec![(3, "| #1 | 2.4799 |".into()), (4, "| #2 | 7.2530 |".into())],
    };
    assert!(compare(&block, "head\n| #1 | 2.4799 |\n| #2 | 7.2530 |\n", "x").is_empty());
    let failures = compare(&block, "| #1 | 2.4799 |\n| #2 | 7.2540 |\n", "x");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("README.md:4") && failures[0].contains("printed 7.2540"));
}
