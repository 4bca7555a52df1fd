//! Wall-clock benchmark of the whole `coil-tune diagnose` process, one truth case at a
//! time, with the confusion table and parameter errors:
//! `cargo build --release -p coil-tune && cargo run --release -p coil-tests --example bench_diagnose [standard|extended|hard|loss|outside|slow|large|real|all] [NAME...]`
//!
//! `loss` is the damping classes (`coil_tests::truth::loss::loss_cases`: friction that
//! sticks after 8-17 cycles, drag beside a mild backbone, drag with a slow component,
//! friction with drag); `outside` the laws outside the catalogue (scored against the
//! hidden `none`: a named cause there shows as a miss in the table; the test
//! `outside_catalogue` tells an honest named cause from a false one).
//!
//! `large` is every standard case sampled at the rate that gives 30 000 samples over its
//! record, the largest record the wall-time budget covers. `real` is every shared real
//! recording (each subfolder with a `case.json` of `$COIL_REAL_DIR`, else
//! `../shared/real` beside the repository; read where they are, never copied); `all`
//! (the default) is every generated case of the confusion table and the real recordings.
//!
//! The budget a lab engineer can wait for between two records: the median wall time within [`MEDIAN_BUDGET_S`]
//! and the worst within [`WORST_BUDGET_S`] on the 2-core machine.
//!
//! Every selected case (`coil_tests::truth::standard_cases()`, one effect each;
//! `extended_cases()`, the columns and artefacts labs record; `hard_cases()`: short,
//! strongly nonlinear and heavily preloaded records; all by default, or only the cases named) is written to a
//! temporary folder, then the release binary runs
//! `coil-tune diagnose <case> --out <tmp>/out/<name> -q` (process start, FE reduction,
//! fits, figures, report) and is timed with `std::time::Instant`. Its `diagnosis.json`
//! is scored by `coil_tests::scoring` (named effects against the hidden ones, each
//! parameter's error, the gains); the confusion table, the per-case table and the
//! median and worst wall times against the budget are printed. Cases run one after
//! another so each has the machine to itself (the diagnosis runs its own candidates in
//! parallel). `COIL_BENCH_DIR=DIR` keeps the cases and outputs in DIR instead of a
//! temporary folder, to profile one case.

use coil_tests::scoring::{self, Score};
use coil_tests::truth::loss::{loss_cases, outside_cases, slow_mode_cases};
use coil_tests::truth::{extended_cases, hard_cases, standard_cases, write_case, TruthCase};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

/// The median wall time's budget (s).
const MEDIAN_BUDGET_S: f64 = 3.0;

/// The worst wall time's budget (s).
const WORST_BUDGET_S: f64 = 10.0;

/// Samples per record in the `large` selection (the budget's largest record).
const LARGE_SAMPLES: f64 = 30_000.0;

/// The release `coil-tune`: `$CARGO_TARGET_DIR/release` when that is set, else the
/// workspace's `target/release`.
fn binary() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    target
        .join("release")
        .join(format!("coil-tune{}", std::env::consts::EXE_SUFFIX))
}

/// The shared real recordings' folders (module docs), sorted; empty when absent.
fn real_cases() -> Vec<PathBuf> {
    let root = std::env::var_os("COIL_REAL_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/real"));
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&root)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join("case.json").is_file())
        .collect();
    cases.sort();
    cases
}

/// The CPU time (user and system, s) of this process's finished children, from
/// `/proc/self/stat` (fields 16 and 17, in clock ticks of 1/100 s); NaN elsewhere.
fn children_cpu_s() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // The command name (field 2) may hold spaces: count the fields after its `)`.
    let Some(rest) = stat.rfind(')').map(|i| &stat[i + 1..]) else {
        return f64::NAN;
    };
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // `rest` starts at field 3, so field k is `fields[k - 3]`.
    let tick = |k: usize| fields.get(k - 3).and_then(|v| v.parse::<f64>().ok());
    match (tick(16), tick(17)) {
        (Some(u), Some(s)) => (u + s) / 100.0,
        _ => f64::NAN,
    }
}

/// Runs the binary on one case folder; returns its `diagnosis.json`, the wall time and
/// the process's CPU time (s).
fn diagnose(
    exe: &Path,
    folder: &Path,
    out: &Path,
) -> Result<(serde_json::Value, f64, f64), String> {
    let cpu_before = children_cpu_s();
    let start = Instant::now();
    let output = Command::new(exe)
        .arg("diagnose")
        .arg(folder)
        .arg("--out")
        .arg(out)
        .arg("-q")
        .output()
        .map_err(|e| format!("running {}: {e}", exe.display()))?;
    let wall_s = start.elapsed().as_secs_f64();
    let cpu_s = children_cpu_s() - cpu_before;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(format!(
            "coil-tune diagnose failed ({}): {}",
            output.status,
            stderr.trim()
        ));
    }
    let path = out.join("diagnosis.json");
    let text =
        std::fs::read_to_string(&path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let d: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("parsing {}: {e}", path.display()))?;
    Ok((d, wall_s, cpu_s))
}

/// Writes a truth case, runs the binary on it and scores its `diagnosis.json`.
fn bench(exe: &Path, tmp: &Path, case: &TruthCase) -> Result<(Score, f64), String> {
    let folder = tmp.join("cases").join(&case.name);
    write_case(&folder, case).map_err(|e| format!("writing {}: {e}", folder.display()))?;
    let (d, wall_s, cpu_s) = diagnose(exe, &folder, &tmp.join("out").join(&case.name))?;
    Ok((scoring::score(case, &d, wall_s), cpu_s))
}

/// The named causes and their parameters of a diagnosis, in one line.
fn verdict(d: &serde_json::Value) -> String {
    let causes: Vec<String> = d["causes"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|c| {
            let parameters: Vec<String> = c["parameters"]
                .as_object()
                .into_iter()
                .flatten()
                .map(|(k, v)| {
                    let se = c["parameters_se"][k].as_f64();
                    match (v.as_f64(), se) {
                        (Some(v), Some(se)) => format!("{k} = {v:.4e} +- {se:.2e}"),
                        (Some(v), None) => format!("{k} = {v:.4e}"),
                        _ => format!("{k} = {v}"),
                    }
                })
                .collect();
            format!(
                "{} ({:.0} %: {})",
                c["effect"].as_str().unwrap_or("?"),
                100.0 * c["share"].as_f64().unwrap_or(f64::NAN),
                parameters.join(", ")
            )
        })
        .collect();
    if causes.is_empty() {
        "none".into()
    } else {
        causes.join(" with ")
    }
}

/// The median and the worst of `times` (s).
fn median_worst(times: &[f64]) -> (f64, f64) {
    let mut t = times.to_vec();
    t.sort_by(f64::total_cmp);
    let median = match t.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => t[n / 2],
        n => 0.5 * (t[n / 2 - 1] + t[n / 2]),
    };
    (median, t.last().copied().unwrap_or(f64::NAN))
}

/// The cases the arguments select (module docs).
fn selected() -> Vec<TruthCase> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let all = || {
        standard_cases()
            .into_iter()
            .chain(extended_cases())
            .chain(hard_cases())
            .chain(loss_cases())
    };
    let named = |c: &TruthCase| args.len() == 1 || args.contains(&c.name);
    match args.first().map(String::as_str) {
        None | Some("all") => all().collect(),
        Some("real") => Vec::new(),
        Some("standard") => standard_cases().into_iter().filter(named).collect(),
        Some("extended") => extended_cases().into_iter().filter(named).collect(),
        Some("hard") => hard_cases().into_iter().filter(named).collect(),
        Some("loss") => loss_cases().into_iter().filter(named).collect(),
        Some("outside") => outside_cases().into_iter().filter(named).collect(),
        Some("slow") => slow_mode_cases().into_iter().filter(named).collect(),
        Some("large") => standard_cases()
            .into_iter()
            .filter(named)
            .map(|mut c| {
                c.sample_rate_hz = LARGE_SAMPLES / c.record_s;
                c.name.push_str("_30k");
                c
            })
            .collect(),
        Some(_) => all()
            .chain(outside_cases())
            .filter(|c| args.contains(&c.name))
            .collect(),
    }
}

fn main() -> ExitCode {
    let exe = binary();
    if !exe.is_file() {
        eprintln!(
            "error: no release binary at {}\nrun `cargo build --release -p coil-tune` first",
            exe.display()
        );
        return ExitCode::FAILURE;
    }
    let tmp = match tempfile::tempdir() {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: temporary folder: {e}");
            return ExitCode::FAILURE;
        }
    };
    // `COIL_BENCH_DIR` keeps the cases and their outputs there (for profiling one case).
    let kept = std::env::var_os("COIL_BENCH_DIR").map(PathBuf::from);
    let root = kept.as_deref().unwrap_or(tmp.path());
    println!("binary: {}", exe.display());
    let mut scores = Vec::new();
    let mut cpu = Vec::new();
    let mut failures = Vec::new();
    for case in selected() {
        match bench(&exe, root, &case) {
            Ok((s, cpu_s)) => {
                println!(
                    "{:<28} {:<40} {:<40} {:>7} samples {:>7.2} s (CPU {:.2} s)",
                    s.name,
                    s.truth,
                    s.named,
                    (case.record_s * case.sample_rate_hz).round(),
                    s.runtime_s,
                    cpu_s
                );
                scores.push(s);
                cpu.push(cpu_s);
            }
            Err(e) => {
                println!("{:<28} FAILED: {e}", case.name);
                failures.push(case.name.clone());
            }
        }
    }
    if !scores.is_empty() {
        println!("\n{}", scoring::report(&scores));
    }
    let mut times: Vec<f64> = scores.iter().map(|s| s.runtime_s).collect();
    let generated = median_worst(&times);
    let args: Vec<String> = std::env::args().skip(1).collect();
    let real = match args.first().map(String::as_str) {
        None | Some("all") | Some("real") => real_cases(),
        _ => Vec::new(),
    };
    let mut real_times = Vec::new();
    for folder in &real {
        let name = folder
            .file_name()
            .map_or("?".into(), |n| n.to_string_lossy().into_owned());
        match diagnose(&exe, folder, &root.join("out").join(&name)) {
            Ok((d, wall_s, cpu_s)) => {
                println!(
                    "{name:<28} real recording: {} ({wall_s:.2} s, CPU {cpu_s:.2} s)",
                    verdict(&d)
                );
                real_times.push(wall_s);
                cpu.push(cpu_s);
            }
            Err(e) => {
                println!("{name:<28} FAILED: {e}");
                failures.push(name);
            }
        }
    }
    times.extend(&real_times);
    let (median, worst) = median_worst(&times);
    let show = |what: &str, n: usize, (m, w): (f64, f64)| {
        if n > 0 {
            println!("{what:<24} {n:>3} runs: median {m:.2} s, worst {w:.2} s");
        }
    };
    show("generated cases", scores.len(), generated);
    show(
        "real recordings",
        real_times.len(),
        median_worst(&real_times),
    );
    show("all", times.len(), (median, worst));
    // The load-independent figure: on two idle cores a run's wall time lies between its
    // CPU time over two (every step parallel) and its CPU time (none).
    show("CPU time, all", cpu.len(), median_worst(&cpu));
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "load average at the end: {}",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    println!(
        "budget (median {MEDIAN_BUDGET_S} s, worst {WORST_BUDGET_S} s): {}",
        if median <= MEDIAN_BUDGET_S && worst <= WORST_BUDGET_S {
            "held"
        } else {
            "NOT held"
        }
    );
    if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        eprintln!("failed: {}", failures.join(", "));
        ExitCode::FAILURE
    }
}
