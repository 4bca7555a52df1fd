//! The real `coil-tune` binary in temporary folders: exit codes, messages with file and
//! line, nothing half-written, a grid killed with SIGKILL and resumed from its journal,
//! `run` against `calibrate`, `sweep`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn coil_tune() -> Command {
    Command::new(env!("CARGO_BIN_EXE_coil-tune"))
}

fn case_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect")
}

fn run(args: &[&str], cwd: &Path) -> Output {
    coil_tune()
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Files under `dir`, relative, sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                for f in files(&p) {
                    out.push(format!("{}/{f}", e.file_name().to_string_lossy()));
                }
            } else {
                out.push(e.file_name().to_string_lossy().into_owned());
            }
        }
    }
    out.sort();
    out
}

const CASE: &str = r#"{
  "name": "test spring",
  "spring": { "active_coils": 14.0, "mean_diameter_mm": 24.0, "wire_diameter_mm": 3.0, "pitch_mm": 6.2 },
  "material": { "youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0 },
  "mass_kg": 5.3,
  "gravity_m_s2": 9.81,
  "targets": { "stiffness_n_mm": 3.9275, "damping_ratio": 0.00175, "period_s": 0.23 }
}"#;

/// Broken case files: exit code 1, one message naming the file, line and field and what
/// was expected, no panic, and no output folder.
#[test]
fn bad_case_files_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    for (from, to, needle) in [
        (
            "\"mass_kg\": 5.3,",
            "\"mass_kg\": \"heavy\",",
            "case.json:5:14: `mass_kg`",
        ),
        (
            "\"pitch_mm\": 6.2",
            "\"pitch_mm\": -6.2",
            "`spring.pitch_mm`",
        ),
        (
            "\"poisson_ratio\": 0.3,",
            "",
            "`material.poisson_ratio`: missing",
        ),
        (
            "\"period_s\": 0.23",
            "\"period_s\": 0",
            "`targets.period_s`",
        ),
        (
            "\"name\": \"test spring\",",
            "\"name\": \"test spring\"",
            "invalid JSON",
        ),
        (
            "\"stiffness_n_mm\": 3.9275, ",
            "",
            "case.json:7:14: `targets.stiffness_n_mm`: missing",
        ),
    ] {
        let case = dir.path().join("case");
        std::fs::create_dir_all(&case).unwrap();
        std::fs::write(case.join("case.json"), CASE.replacen(from, to, 1)).unwrap();
        let out = dir.path().join("out");
        let o = run(
            &[
                "calibrate",
                "case",
                "--out",
                "out",
                "--elements-per-coil",
                "8",
                "-q",
            ],
            dir.path(),
        );
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{needle}: {err}");
        assert!(err.contains(needle), "expected `{needle}` in: {err}");
        assert!(err.contains("expected"), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!out.exists(), "nothing written for {needle}");
    }
    let o = run(&["calibrate", "no-such-case"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("no-such-case"));
    let o = run(&["calibrate"], dir.path());
    assert_eq!(o.status.code(), Some(2), "usage error");
}

/// A procedure with a typo is rejected before anything runs, naming file:line.
#[test]
fn procedure_errors_name_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let proc_file = dir.path().join("bad.proc");
    std::fs::write(
        &proc_file,
        format!(
            "case {}\nset elements_per_coil 8\ntune youngs_modulus to stifness target\n",
            case_dir().display()
        ),
    )
    .unwrap();
    let o = run(&["run", "bad.proc", "--out", "out"], dir.path());
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("bad.proc:3:"), "{err}");
    assert!(!dir.path().join("out").exists(), "nothing ran");

    // A runtime error names its line too (a grid before any case).
    std::fs::write(&proc_file, "echo start\ngrid alpha 0 beta 0\n").unwrap();
    let o = run(&["run", "bad.proc", "--out", "out"], dir.path());
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1));
    assert!(err.contains("bad.proc:2:") && err.contains("case"), "{err}");

    let o = run(
        &[
            "run",
            case_dir().join("figure6.proc").to_str().unwrap(),
            "--dry-run",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
}

/// `run` of a procedure and `calibrate` with the same (reduced) settings give the same E,
/// mass, alpha and beta: figure6.proc with a coarse mesh and one coarse grid.
#[test]
fn run_equals_calibrate() {
    let dir = tempfile::tempdir().unwrap();
    let grid = "alpha 0:0.5:2 beta 0:0.00002:0.0002 name coarse";
    let figure6 = std::fs::read_to_string(case_dir().join("figure6.proc")).unwrap();
    let reduced: String = figure6
        .lines()
        .filter(|l| !l.starts_with("grid"))
        .map(|l| {
            if l.starts_with("case") {
                format!("case {}", case_dir().display())
            } else if l.starts_with("choose best") {
                format!("grid {grid}\n{l}")
            } else {
                l.replace("set elements_per_coil 24", "set elements_per_coil 8")
                    .replace("set check_direct on", "set check_direct off")
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(dir.path().join("reduced.proc"), &reduced).unwrap();
    let o = run(&["run", "reduced.proc", "--out", "proc"], dir.path());
    assert!(o.status.success(), "{}\n{reduced}", text(&o.stderr));
    let o = run(
        &[
            "calibrate",
            case_dir().to_str().unwrap(),
            "--out",
            "cal",
            "--elements-per-coil",
            "8",
            "--no-check",
            "--grid",
            grid,
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.path().join(f)).unwrap()).unwrap()
    };
    let (p, c) = (read("proc/procedure.json"), read("cal/calibration.json"));
    for key in ["youngs_modulus_mpa", "mass_kg", "alpha", "beta"] {
        let (x, y) = (
            p["state"][key].as_f64().unwrap(),
            c["state"][key].as_f64().unwrap(),
        );
        // The static solve may sum in another order from run to run (parallel
        // factorisation): agreement to 1e-12 is agreement.
        assert!(
            (x - y).abs() <= 1e-12 * y.abs(),
            "{key}: run {x} vs calibrate {y}"
        );
    }
    assert!(c["state"]["alpha"].as_f64().unwrap() >= 0.0);
}

/// A grid killed by SIGKILL resumes from its journal: the rerun takes every complete
/// line as done, recomputes none of them (no point appears twice in the journal) and
/// loses none.
#[test]
fn a_killed_grid_resumes_from_its_journal() {
    let dir = tempfile::tempdir().unwrap();
    // A grid far too large to finish before the kill.
    std::fs::write(
        dir.path().join("kill.proc"),
        format!(
            "case {}\nset elements_per_coil 8\ntune youngs_modulus to stiffness target\n\
             tune mass to period target\ngrid alpha 0:0.001:2 beta 0:0.000001:0.0002 name big\n",
            case_dir().display()
        ),
    )
    .unwrap();
    let journal = dir.path().join("out/loop3_big.journal.jsonl");
    let mut child = coil_tune()
        .args(["run", "kill.proc", "--out", "out"])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    loop {
        let lines = std::fs::read_to_string(&journal).map_or(0, |t| t.lines().count());
        if lines > 30 {
            break;
        }
        assert!(start.elapsed().as_secs() < 120, "the grid never started");
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before the kill"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let before = std::fs::read_to_string(&journal).unwrap();
    let complete = before[..before.rfind('\n').unwrap() + 1].lines().count() - 1;

    let o = run(
        &["run", "kill.proc", "--out", "out", "--max-points", "25"],
        dir.path(),
    );
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        stdout.contains(&format!("(25 run, {complete} from the journal)")),
        "{complete} journaled points: {stdout}"
    );
    let after = std::fs::read_to_string(&journal).unwrap();
    let lines: Vec<&str> = after.lines().collect();
    assert_eq!(
        lines.len(),
        1 + complete + 25,
        "no point recomputed or lost"
    );
    let mut seen = std::collections::HashSet::new();
    for line in &lines[1..] {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert!(
            seen.insert((v["i"].as_u64().unwrap(), v["j"].as_u64().unwrap())),
            "a point appears twice: {line}"
        );
    }
    assert!(
        after.starts_with(&before[..before.rfind('\n').unwrap() + 1]),
        "old lines kept"
    );
}

/// Table 4's K within 1% of the paper even on an 8-per-coil mesh: the calibrated E
/// absorbs the chord polygon's bias, which is the same relative bias for every variant.
#[test]
fn sweep_gives_table4_stiffness() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        &[
            "sweep",
            case_dir().to_str().unwrap(),
            "--variants",
            case_dir().join("table4.json").to_str().unwrap(),
            "--out",
            "sweep",
            "--elements-per-coil",
            "8",
            "--no-check",
            "--grid",
            "alpha 0:1:2 beta 0.0001:0.00001:0.00014",
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("sweep/sweep.json")).unwrap(),
    )
    .unwrap();
    let variants = json["variants"].as_array().unwrap();
    assert_eq!(variants.len(), 6);
    for v in variants {
        let e = v["stiffness_relative_error"].as_f64().unwrap();
        assert!(e.abs() < 0.01, "{}: {e}", v["name"]);
    }
    assert!(files(&dir.path().join("sweep")).contains(&"sweep.csv".to_string()));
}

const TWO_VARIANTS: &str = r##"{"variants": [
  { "name": "#1", "active_coils": 14.0, "mean_diameter_mm": 28.0, "wire_diameter_mm": 3.0, "pitch_mm": 6.2 },
  { "name": "#4, \"wide\"", "active_coils": 14.0, "mean_diameter_mm": 20.0, "wire_diameter_mm": 3.0, "pitch_mm": 6.2 }
]}"##;

/// A tolerance study run whole and as 4 shards merged: the same table and summary, byte
/// for byte; merge refuses a missing shard, a repeated one and a part of another study,
/// naming the shard and the file.
#[test]
fn tolerance_shards_merge_to_the_single_run() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("variants.json"), TWO_VARIANTS).unwrap();
    let case = case_dir();
    let tolerance = |out: &str, seed: &str, extra: &[&str]| {
        let mut args = vec![
            "tolerance",
            case.to_str().unwrap(),
            "--variants",
            "variants.json",
            "--paper-material",
            "--elements-per-coil",
            "8",
            "--samples",
            "2",
            "--seed",
            seed,
            "--no-plots",
            "-q",
            "--out",
            out,
        ];
        args.extend_from_slice(extra);
        run(&args, dir.path())
    };
    let o = tolerance("single", "7", &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for i in 1..=4 {
        let shard = format!("{i}/4");
        let o = tolerance("parts", "7", &["--shard", &shard]);
        assert!(o.status.success(), "{shard}: {}", text(&o.stderr));
    }
    let o = run(
        &["merge", "parts", "--out", "merged", "--no-plots"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    for file in ["tolerance.csv", "tolerance_summary.json", "tolerance.md"] {
        let single = std::fs::read(dir.path().join("single").join(file)).unwrap();
        let merged = std::fs::read(dir.path().join("merged").join(file)).unwrap();
        assert!(single == merged, "{file} differs");
    }
    let table = std::fs::read_to_string(dir.path().join("single/tolerance.csv")).unwrap();
    assert_eq!(table.lines().count(), 1 + 2 * 3, "{table}");
    // A name with a comma and quotes is one quoted field (RFC 4180): every row has the
    // header's 12 fields.
    assert!(table.contains(",\"#4, \"\"wide\"\"\","), "{table}");
    tampered_parts_are_refused(dir.path());

    // A missing shard.
    let part = |i: usize| format!("parts/part-{i:04}-of-0004.csv");
    let o = run(
        &["merge", &part(1), &part(2), &part(4), "--out", "bad"],
        dir.path(),
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("shard 3/4 missing"), "{err}");
    // A shard given twice.
    std::fs::create_dir(dir.path().join("copy")).unwrap();
    std::fs::copy(
        dir.path().join(part(2)),
        dir.path().join("copy/part-0002-of-0004.csv"),
    )
    .unwrap();
    let o = run(&["merge", "parts", "copy", "--out", "bad"], dir.path());
    let err = text(&o.stderr);
    assert!(
        err.contains("shard 2/4 is given twice") && err.contains("copy"),
        "{err}"
    );
    // A part of another study (another seed).
    let o = tolerance("other", "8", &["--shard", "3/4"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = run(
        &[
            "merge",
            &part(1),
            &part(2),
            "other/part-0003-of-0004.csv",
            &part(4),
            "--out",
            "bad",
        ],
        dir.path(),
    );
    let err = text(&o.stderr);
    assert!(
        err.contains("another study") && err.contains("other/part-0003"),
        "{err}"
    );
    assert!(!dir.path().join("bad").join("tolerance.csv").exists());
    // A shard without a fixed material.
    let o = run(
        &[
            "sweep",
            case.to_str().unwrap(),
            "--variants",
            "variants.json",
            "--shard",
            "1/2",
            "--out",
            "s",
        ],
        dir.path(),
    );
    assert!(
        text(&o.stderr).contains("--shard needs the material"),
        "{}",
        text(&o.stderr)
    );
}

/// Every edit of a part that a careless or hostile hand may make is refused with exit 1,
/// naming the file and line, and the output folder is left without a table: an edited
/// or non-finite K, a negative one, a truncated field or file, an edited `# study`
/// line in every part (with or without its digest recomputed), counts that would
/// overflow or exhaust memory (2^62 and 1e12 samples).
fn tampered_parts_are_refused(root: &Path) {
    let parts = root.join("parts");
    let names: Vec<PathBuf> = (1..=4)
        .map(|i| parts.join(format!("part-{i:04}-of-0004.csv")))
        .collect();
    let original: Vec<String> = names
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    // task, then tolerance.csv's columns: stiffness_n_mm is the 11th.
    const K_COLUMN: usize = 10;
    let edit_k = |text: &str, k: &str| -> String {
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        let fields: Vec<String> = lines[4].split(',').map(str::to_string).collect();
        let mut f = fields.clone();
        f[K_COLUMN] = k.to_string();
        lines[4] = f.join(",");
        lines.join("\n") + "\n"
    };
    let study_line = |text: &str| text.lines().nth(1).unwrap().to_string();
    let redigest = |text: &str, study: &str| -> String {
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        lines[1] = study.to_string();
        let json = study.strip_prefix("# study ").unwrap();
        lines[2] = format!(
            "# study-sha256 {}",
            coil_io::digest::sha256_hex(json.as_bytes())
        );
        lines.join("\n") + "\n"
    };
    let k = original[0]
        .lines()
        .nth(4)
        .unwrap()
        .split(',')
        .nth(K_COLUMN)
        .unwrap()
        .to_string();
    let slightly: f64 = k.parse::<f64>().unwrap() * 1.001;
    type Edit<'a> = Box<dyn Fn(usize, &str) -> String + 'a>;
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "edited K",
            Box::new(move |i, t| {
                if i == 0 {
                    edit_k(t, &slightly.to_string())
                } else {
                    t.into()
                }
            }),
            "digest",
        ),
        (
            "NaN K",
            Box::new(move |i, t| if i == 0 { edit_k(t, "NaN") } else { t.into() }),
            "finite",
        ),
        (
            "inf K",
            Box::new(move |i, t| if i == 0 { edit_k(t, "inf") } else { t.into() }),
            "finite",
        ),
        (
            "-inf K",
            Box::new(move |i, t| if i == 0 { edit_k(t, "-inf") } else { t.into() }),
            "finite",
        ),
        (
            "1e400 K",
            Box::new(move |i, t| if i == 0 { edit_k(t, "1e400") } else { t.into() }),
            "finite",
        ),
        (
            "negative K",
            Box::new(move |i, t| if i == 0 { edit_k(t, "-3.9") } else { t.into() }),
            "stiffness_n_mm",
        ),
        (
            "truncated last field",
            Box::new(|i, t: &str| {
                if i == 3 {
                    let body = t
                        .lines()
                        .take(t.lines().count() - 1)
                        .collect::<Vec<_>>()
                        .join("\n");
                    body[..body.len() - 3].to_string() + "\n"
                } else {
                    t.into()
                }
            }),
            "rows-sha256",
        ),
        (
            "truncated file",
            Box::new(|i, t: &str| {
                if i == 1 {
                    t[..t.len() * 2 / 3].to_string()
                } else {
                    t.into()
                }
            }),
            "part-0002",
        ),
        (
            "seed edited in every part",
            Box::new(|_, t: &str| t.replacen("\"seed\":7", "\"seed\":9", 1)),
            "digest",
        ),
        (
            "alpha edited in every part, digests recomputed",
            Box::new(move |_, t: &str| {
                let s = study_line(t).replacen("\"alpha\":", "\"alpha\":1", 1);
                redigest(t, &s)
            }),
            "digest",
        ),
        (
            "2^62 samples",
            Box::new(move |_, t: &str| {
                let s =
                    study_line(t).replacen("\"samples\":2", "\"samples\":4611686018427387904", 1);
                redigest(t, &s)
            }),
            "at most 10000000 tasks",
        ),
        (
            "1e12 samples",
            Box::new(move |_, t: &str| {
                let s = study_line(t).replacen("\"samples\":2", "\"samples\":1000000000000", 1);
                redigest(t, &s)
            }),
            "at most 10000000 tasks",
        ),
        (
            "1 sample",
            Box::new(move |_, t: &str| {
                let s = study_line(t).replacen("\"samples\":2", "\"samples\":1", 1);
                redigest(t, &s)
            }),
            "at least 2",
        ),
    ];
    for (label, edit, expected) in &cases {
        for (i, p) in names.iter().enumerate() {
            std::fs::write(p, edit(i, &original[i])).unwrap();
        }
        let o = run(&["merge", "parts", "--out", "tampered", "--no-plots"], root);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{label}: {err}");
        assert!(err.contains(expected), "{label}: {err}");
        assert!(err.contains("part-000"), "{label}: names the file: {err}");
        assert!(err.len() < 1024, "{label}: {} bytes", err.len());
        assert!(!root.join("tampered/tolerance.csv").exists(), "{label}");
    }
    for (p, t) in names.iter().zip(&original) {
        std::fs::write(p, t).unwrap();
    }
}

/// `-q` is accepted by every command, so a script can pass it uniformly.
#[test]
fn every_command_takes_quiet() {
    let dir = tempfile::tempdir().unwrap();
    for command in [
        "calibrate",
        "sweep",
        "tolerance",
        "merge",
        "paper",
        "diagnose",
        "damping",
        "run",
    ] {
        let o = run(&[command, "--help"], dir.path());
        let help = text(&o.stdout);
        assert!(help.contains("-q, --quiet"), "{command}: {help}");
    }
}

/// `--samples` below 2 (no spread) or so large that the task count overflows is refused
/// before any work, with the number and what is expected.
#[test]
fn samples_are_at_least_two_and_overflow_checked() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("variants.json"), TWO_VARIANTS).unwrap();
    let case = case_dir();
    for (samples, expected) in [
        ("0", "at least 2"),
        ("1", "at least 2"),
        ("18446744073709551615", "at most 10000000 tasks"),
        ("9223372036854775807", "at most 10000000 tasks"),
    ] {
        let o = run(
            &[
                "tolerance",
                case.to_str().unwrap(),
                "--variants",
                "variants.json",
                "--paper-material",
                "--samples",
                samples,
                "-q",
                "--out",
                "t",
            ],
            dir.path(),
        );
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{samples}: {err}");
        assert!(err.contains(expected), "{samples}: {err}");
    }
}
