//! A seeded fuzz test of the file boundary through the real binaries, with a fixed
//! budget: mutated decks, free and Mentat fixed format, with hostile long lines
//! (`coil-solve`), case folders with hostile record entries and mutated records
//! (`coil-tune run`, `coil-tune calibrate`), mutated CSV records (`coil-post`), mutated
//! procedure files (`coil-tune run`) and mutated part files of a sharded study
//! (`coil-tune merge`). For every input:
//! - no panic (exit 0, 1 or 2; no `panicked` on stderr), no abort (no signal) and no
//!   hang (killed after [`HANG_S`] seconds);
//! - nothing outside the output folder touched (a snapshot of the sandbox: every path,
//!   its size and modification time, before and after);
//! - no half set: no lock and no staging folder left in or beside the output folder,
//!   every file of its manifest present, and a failed run leaves the previous manifest
//!   unchanged;
//! - an error message under 1 KB without terminal control characters;
//! - parts: a merge that succeeds gives exactly the untampered table (no silent
//!   acceptance of a tampered part).
//!
//! The random generator is a fixed-seed xorshift, so each input is reproducible from its
//! index. The default run takes a small fixed number of inputs per family (seconds); set
//! `COIL_FUZZ_INPUTS=N` for N per family (a nightly run: e.g. 500). The counts are
//! printed. `coil-solve` and `coil-post` are taken beside `coil-tune` (built by `cargo test
//! --workspace`); their families are skipped with a note if absent.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Inputs per family in the default run.
const DEFAULT_INPUTS: usize = 20;
pub(crate) const HANG_S: u64 = 60;

/// Inputs per family: `COIL_FUZZ_INPUTS` or [`DEFAULT_INPUTS`].
pub(crate) fn budget() -> usize {
    std::env::var("COIL_FUZZ_INPUTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_INPUTS)
}

pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    pub(crate) fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
}

pub(crate) fn bin(name: &str) -> Option<PathBuf> {
    let tune = PathBuf::from(env!("CARGO_BIN_EXE_coil-tune"));
    let path = tune.with_file_name(name);
    path.is_file().then_some(path)
}

/// Path -> (size, mtime) of every entry under `dir` except `skip` (the output folder).
fn snapshot(dir: &Path, skip: &Path) -> BTreeMap<PathBuf, (u64, Option<std::time::SystemTime>)> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(at) = stack.pop() {
        for e in std::fs::read_dir(&at).into_iter().flatten().flatten() {
            let p = e.path();
            if p == skip {
                continue;
            }
            if let Ok(m) = std::fs::symlink_metadata(&p) {
                out.insert(p.clone(), (m.len(), m.modified().ok()));
                if m.is_dir() {
                    stack.push(p);
                }
            }
        }
    }
    out
}

fn manifest(out: &Path) -> Option<String> {
    std::fs::read_to_string(out.join(".coil-manifest")).ok()
}

/// What one run of a binary gave.
pub(crate) struct Outcome {
    /// Its exit code.
    pub code: i32,
    /// Its standard error.
    pub stderr: String,
    /// Its peak resident memory (KiB, the kernel's `ru_maxrss`).
    pub peak_kib: i64,
    /// Its wall time (s).
    pub seconds: f64,
}

/// Runs `cmd` in `sandbox` with its outputs in `out`; checks the rules of the module doc.
pub(crate) fn check(label: &str, cmd: Command, sandbox: &Path, out: &Path) -> i32 {
    run(label, cmd, sandbox, out).code
}

/// Waits for `child` (killed after [`HANG_S`] s: a hang), with its peak memory.
fn wait(label: &str, child: &mut std::process::Child) -> (std::process::ExitStatus, i64) {
    use std::os::unix::process::ExitStatusExt;
    let start = Instant::now();
    let pid = child.id() as libc::pid_t;
    loop {
        let mut status = 0;
        // SAFETY: `rusage` is plain data the kernel fills; `pid` is our own child, not yet
        // reaped (std's `Child` never waited on it).
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        let got = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if got == pid {
            return (std::process::ExitStatus::from_raw(status), usage.ru_maxrss);
        }
        assert!(got == 0, "{label}: wait4 failed");
        if start.elapsed() > Duration::from_secs(HANG_S) {
            child.kill().unwrap();
            panic!("{label}: no answer after {HANG_S} s (hang)");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// [`check`], returning what the run gave.
pub(crate) fn run(label: &str, mut cmd: Command, sandbox: &Path, out: &Path) -> Outcome {
    let before = snapshot(sandbox, out);
    let previous = manifest(out);
    let start = Instant::now();
    let mut child = cmd
        .current_dir(sandbox)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // stderr is read on its own thread so that a long message cannot block the child.
    let mut pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut err = String::new();
        use std::io::Read;
        let _ = pipe.read_to_string(&mut err);
        err
    });
    let (status, peak_kib) = wait(label, &mut child);
    let seconds = start.elapsed().as_secs_f64();
    let err = reader.join().unwrap();
    let code = status
        .code()
        .unwrap_or_else(|| panic!("{label}: killed by a signal (an abort): {err}"));
    assert!(matches!(code, 0..=2), "{label}: exit {code}: {err}");
    assert!(!err.contains("panicked"), "{label}: {err}");
    if code != 0 {
        assert!(
            err.len() < 1024,
            "{label}: a message of {} bytes",
            err.len()
        );
        assert!(
            !err.contains('\u{1b}') && !err.contains('\u{0}'),
            "{label}: control characters in {err:?}"
        );
    }
    let after = snapshot(sandbox, out);
    assert_eq!(
        before, after,
        "{label}: something outside the output folder changed"
    );
    if out.is_dir() {
        for e in std::fs::read_dir(out).unwrap().flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            assert!(
                !name.starts_with(".coil-staging") && name != ".coil-lock",
                "{label}: {name} left in the output folder"
            );
        }
        for e in std::fs::read_dir(sandbox).unwrap().flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            assert!(
                !name.contains(".coil-staging"),
                "{label}: {name} left beside the output folder"
            );
        }
        if let Some(m) = manifest(out) {
            for f in m.lines().filter(|l| !l.starts_with('#')) {
                assert!(
                    out.join(f).is_file(),
                    "{label}: {f} of the manifest missing"
                );
            }
        }
        if code != 0 {
            assert_eq!(
                previous,
                manifest(out),
                "{label}: a failed run changed the set"
            );
        }
    }
    Outcome {
        code,
        stderr: err,
        peak_kib,
        seconds,
    }
}

/// One random edit of a text: delete, duplicate or swap a line, replace a number by an
/// extreme one, insert hostile bytes, truncate.
pub(crate) fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return "\u{0}".into();
    }
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(lines.len());
        match rng.below(8) {
            0 => {
                lines.remove(i);
                if lines.is_empty() {
                    lines.push(String::new());
                }
            }
            1 => {
                let l = lines[i].clone();
                lines.insert(i, l);
            }
            2 => {
                let j = rng.below(lines.len());
                lines.swap(i, j);
            }
            3 | 4 => {
                let extreme = rng.pick(&[
                    "0",
                    "-1",
                    "1e308",
                    "-1e308",
                    "NaN",
                    "inf",
                    "1e-320",
                    "4294967296",
                    "-0",
                    "99999999999999999999",
                    "3.5e7",
                ]);
                let words: Vec<&str> = lines[i].split([',', ' ']).collect();
                let k = rng.below(words.len());
                let replaced: Vec<&str> = words
                    .iter()
                    .enumerate()
                    .map(|(n, w)| if n == k { extreme } else { *w })
                    .collect();
                lines[i] = replaced.join(",");
            }
            5 => {
                let junk = rng.pick(&[
                    "\u{1b}[2J\u{1b}[31m",
                    "\u{202e}",
                    "\u{0}",
                    "\u{feff}",
                    "\"",
                    "{",
                    "]",
                    "\\",
                    "../../etc/passwd",
                    "/dev/zero",
                    "C",
                ]);
                lines[i].push_str(junk);
            }
            6 => {
                let cut = rng.below(lines[i].len() + 1);
                let cut = (0..=cut)
                    .rev()
                    .find(|&c| lines[i].is_char_boundary(c))
                    .unwrap_or(0);
                lines[i].truncate(cut);
            }
            _ => lines.truncate(i + 1),
        }
    }
    lines.join("\n") + "\n"
}

/// `coil-tune calibrate case --out cal` stopped at its first grid point: records are
/// read (and checked) before any loop.
pub(crate) fn calibrate_first_point() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_coil-tune"));
    c.args([
        "calibrate",
        "case",
        "--out",
        "cal",
        "--elements-per-coil",
        "3",
    ]);
    c.args(["--max-points", "1", "--no-check", "--quiet"]);
    c
}

pub(crate) fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Runs `one(i, rng, sandbox)` for each of the family's inputs ([`budget`]).
pub(crate) fn family(name: &str, seed: u64, mut one: impl FnMut(usize, &mut Rng, &Path) -> i32) {
    let start = Instant::now();
    let mut rng = Rng(seed);
    let n = budget();
    let mut ok = 0;
    for i in 0..n {
        let sandbox = tempfile::tempdir().unwrap();
        if one(i, &mut rng, sandbox.path()) == 0 {
            ok += 1;
        }
    }
    eprintln!(
        "fuzz {name}: {n} inputs ({ok} accepted, {} refused cleanly; 0 panics, 0 aborts, 0 hangs) in {:.1} s",
        n - ok,
        start.elapsed().as_secs_f64()
    );
}

#[test]
fn hostile_inputs_through_the_real_binaries() {
    let decks: Vec<String> = [
        "cantilever_marc.dat",
        "every_card.dat",
        "friction_sdof.dat",
        "mentat_cantilever.dat",
        "marc_normal_fixed.dat",
    ]
    .iter()
    .map(|f| std::fs::read_to_string(repo().join("tests/decks/good").join(f)).unwrap())
    .collect();
    match bin("coil-solve") {
        Some(solve) => family("decks", 0x9e3779b97f4a7c15, |i, rng, sandbox| {
            let mut deck = mutate(&decks[rng.below(decks.len())], rng);
            if rng.below(5) == 0 {
                // A long repeated list (the 400,000-repeat deck, scaled down).
                let list = vec!["beam"; 2000].join(", ");
                deck = deck.replacen(
                    "isotropic,",
                    &format!("define, element, set, rep\n{list}\nisotropic,"),
                    1,
                );
            }
            if rng.below(4) == 0 {
                // A hostile fixed-format line: a long run of blanks (or of digits) and
                // one character, below or above the line bound.
                let mut lines: Vec<String> = deck.lines().map(str::to_string).collect();
                let at = rng.below(lines.len());
                let fill = if rng.below(2) == 0 { " " } else { "9" };
                let length = [79, 161, 99_999, 100_001, 4_000_000][rng.below(5)];
                lines.insert(at, format!("{}x", fill.repeat(length)));
                deck = lines.join("\n") + "\n";
            }
            std::fs::write(sandbox.join("d.dat"), deck).unwrap();
            let out = sandbox.join("out");
            if rng.below(3) == 0 {
                // A previous complete set in the folder.
                let mut c = Command::new(&solve);
                c.args(["d.dat", "--out", "out", "--quiet"]);
                let _ = c.current_dir(sandbox).output();
            }
            let mut c = Command::new(&solve);
            c.args(["d.dat", "--out", "out", "--quiet"]);
            check(&format!("deck {i}"), c, sandbox, &out)
        }),
        None => eprintln!("fuzz decks: coil-solve not built beside coil-tune; skipped"),
    }

    let case_json =
        std::fs::read_to_string(repo().join("cases/measured/friction_g1/case.json")).unwrap();
    let static_csv =
        std::fs::read_to_string(repo().join("cases/measured/friction_g1/static.csv")).unwrap();
    let decay_csv: String =
        std::fs::read_to_string(repo().join("cases/measured/friction_g1/decay.csv"))
            .unwrap()
            .lines()
            .take(3000)
            .collect::<Vec<_>>()
            .join("\n");
    let hostile = [
        "static.csv",
        "decay.csv",
        "../outside.csv",
        "/etc/passwd",
        "/proc/self/environ",
        "link.csv",
        "sub/../static.csv",
        "fifo.csv",
        "dir",
        "",
        "nul\u{0}.csv",
        "./static.csv",
    ];
    family("case folders", 0x2545f4914f6cdd1d, |i, rng, sandbox| {
        let case = sandbox.join("case");
        std::fs::create_dir(&case).unwrap();
        std::fs::create_dir(case.join("dir")).unwrap();
        std::fs::write(
            sandbox.join("outside.csv"),
            "displacement_mm,force_n\nSECRET,1\n",
        )
        .unwrap();
        std::os::unix::fs::symlink(sandbox.join("outside.csv"), case.join("link.csv")).unwrap();
        let _ = Command::new("mkfifo").arg(case.join("fifo.csv")).status();
        let mut json = case_json.clone();
        let entry = serde_json::json!(rng.pick(&hostile)).to_string();
        json = json.replacen("\"static.csv\"", &entry, 1);
        if rng.below(2) == 0 {
            json = mutate(&json, rng);
        }
        std::fs::write(case.join("case.json"), json).unwrap();
        let records = [&static_csv, &decay_csv];
        for (k, name) in ["static.csv", "decay.csv"].iter().enumerate() {
            let text = if rng.below(2) == 0 {
                mutate(records[k], rng)
            } else {
                records[k].to_string()
            };
            std::fs::write(case.join(name), text).unwrap();
        }
        std::fs::write(
            sandbox.join("p.proc"),
            "case case\nset elements_per_coil 3\nsolve static\nmesh m.dat\n",
        )
        .unwrap();
        let mut c = Command::new(env!("CARGO_BIN_EXE_coil-tune"));
        c.args(["run", "p.proc", "--out", "out"]);
        let code = check(&format!("case {i} (run)"), c, sandbox, &sandbox.join("out"));
        check(
            &format!("case {i} (calibrate)"),
            calibrate_first_point(),
            sandbox,
            &sandbox.join("cal"),
        );
        code
    });

    match bin("coil-post") {
        Some(post) => family("CSV records", 0xbf58476d1ce4e5b9, |i, rng, sandbox| {
            let (file, text, args): (&str, &String, &[&str]) = if rng.below(2) == 0 {
                ("r.csv", &static_csv, &["static", "r.csv", "--json"])
            } else {
                (
                    "r.csv",
                    &decay_csv,
                    &[
                        "decrement",
                        "r.csv",
                        "--column",
                        "accel_m_s2",
                        "--out",
                        "out/r.json",
                    ],
                )
            };
            std::fs::create_dir(sandbox.join("out")).unwrap();
            std::fs::write(sandbox.join(file), mutate(text, rng)).unwrap();
            let mut c = Command::new(&post);
            c.args(args);
            check(&format!("record {i}"), c, sandbox, &sandbox.join("out"))
        }),
        None => eprintln!("fuzz CSV records: coil-post not built beside coil-tune; skipped"),
    }

    let paper = repo().join("cases/160ect");
    let vocabulary = [
        "set elements_per_coil 3",
        "set elements_per_coil 0",
        "solve static",
        "solve modal",
        "mesh a.dat",
        "mesh ../a.dat",
        "mesh /tmp/coil-fuzz.dat",
        "mesh sub/b.dat",
        "mesh .coil-lock",
        "out o2",
        "out ../o3",
        "out /tmp/coil-fuzz",
        "grid alpha 0:1:1 beta 0:1e-5:1e-5 name g",
        "grid alpha 0:1:1 beta 0:1e-5:1e-5 name ../../g",
        "grid alpha -1:1:1 beta 0:1e-5:1e-5",
        "set alpha -1",
        "set dt_s 0",
        "set duration_s 1e9",
        "echo \u{1b}[31m",
        "print",
        "post",
        "choose best",
        "set mean_diameter_mm 3.001",
        "set pitch_mm 0",
        "set active_coils 1e-9",
        "tune youngs_modulus to stiffness 1e308",
    ];
    family("procedures", 0x94d049bb133111eb, |i, rng, sandbox| {
        let mut text = format!("case {}\n", paper.display());
        for _ in 0..1 + rng.below(5) {
            text.push_str(rng.pick(&vocabulary));
            text.push('\n');
        }
        if rng.below(3) == 0 {
            text = mutate(&text, rng);
        }
        std::fs::write(sandbox.join("p.proc"), text).unwrap();
        let mut c = Command::new(env!("CARGO_BIN_EXE_coil-tune"));
        c.args(["run", "p.proc", "--out", "out"]);
        check(&format!("procedure {i}"), c, sandbox, &sandbox.join("out"))
    });
    assert!(!Path::new("/tmp/coil-fuzz.dat").exists() && !Path::new("/tmp/coil-fuzz").exists());

    parts_family(&paper);
}

/// Mutated part files of a tolerance study (2 springs x 3 samples, 2 shards): every
/// merge is refused cleanly or gives exactly the untampered table.
fn parts_family(paper: &Path) {
    let base = tempfile::tempdir().unwrap();
    std::fs::write(
        base.path().join("variants.json"),
        r##"{"variants": [
  { "name": "#1", "active_coils": 14.0, "mean_diameter_mm": 28.0, "wire_diameter_mm": 3.0, "pitch_mm": 6.2 },
  { "name": "A,B \"q\"", "active_coils": 14.0, "mean_diameter_mm": 20.0, "wire_diameter_mm": 3.0, "pitch_mm": 6.2 }
]}"##,
    )
    .unwrap();
    for shard in ["1/2", "2/2"] {
        let o = Command::new(env!("CARGO_BIN_EXE_coil-tune"))
            .args([
                "tolerance",
                paper.to_str().unwrap(),
                "--variants",
                "variants.json",
            ])
            .args([
                "--paper-material",
                "--elements-per-coil",
                "6",
                "--samples",
                "2",
            ])
            .args(["--no-plots", "-q", "--out", "parts", "--shard", shard])
            .current_dir(base.path())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = Command::new(env!("CARGO_BIN_EXE_coil-tune"))
        .args(["merge", "parts", "--out", "good", "--no-plots", "-q"])
        .current_dir(base.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let good = std::fs::read(base.path().join("good/tolerance.csv")).unwrap();
    let names = ["part-0001-of-0002.csv", "part-0002-of-0002.csv"];
    let texts: Vec<String> = names
        .iter()
        .map(|n| std::fs::read_to_string(base.path().join("parts").join(n)).unwrap())
        .collect();
    let mut silent = 0;
    family("part files", 0xd6e8feb86659fd93, |i, rng, sandbox| {
        std::fs::create_dir(sandbox.join("parts")).unwrap();
        let victim = rng.below(2);
        for (k, (name, text)) in names.iter().zip(&texts).enumerate() {
            let text = if k == victim || rng.below(4) == 0 {
                mutate(text, rng)
            } else {
                text.clone()
            };
            std::fs::write(sandbox.join("parts").join(name), text).unwrap();
        }
        let mut c = Command::new(env!("CARGO_BIN_EXE_coil-tune"));
        c.args(["merge", "parts", "--out", "out", "--no-plots", "-q"]);
        let code = check(&format!("parts {i}"), c, sandbox, &sandbox.join("out"));
        if code == 0 && std::fs::read(sandbox.join("out/tolerance.csv")).ok() != Some(good.clone())
        {
            silent += 1;
        }
        code
    });
    assert_eq!(silent, 0, "tampered parts merged into another table");
}
