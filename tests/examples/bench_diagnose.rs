//! Wall-clock benchmark of the whole `coil-tune diagnose` process, one truth case at a
//! time, with the confusion table and parameter errors:
//! `cargo build --release -p coil-tune && cargo run --release -p coil-tests --example bench_diagnose [standard|extended|hard|loss|outside|slow|large|all] [NAME...]`
//!
//! `loss` is the damping classes (`coil_tests::truth::loss::loss_cases`: friction that
//! sticks after 8-17 cycles, drag beside a mild backbone, drag with a slow component,
//! friction with drag); `outside` the laws outside the catalogue (scored against the
//! hidden `none`: a named cause there shows as a miss in the table; the test
//! `outside_catalogue` tells an honest named cause from a false one).
//!
//! `large` is every standard case sampled at the rate that gives 30 000 samples over its
//! record, the largest record the wall-time budget covers.
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

/// Wall-time budget per case (s: 15 s per record up to 30 000 samples).
const BUDGET_S: f64 = 15.0;

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

/// Runs the binary on one case and scores its `diagnosis.json`.
fn bench(exe: &Path, tmp: &Path, case: &TruthCase) -> Result<Score, String> {
    let folder = tmp.join("cases").join(&case.name);
    write_case(&folder, case).map_err(|e| format!("writing {}: {e}", folder.display()))?;
    let out = tmp.join("out").join(&case.name);
    let start = Instant::now();
    let output = Command::new(exe)
        .arg("diagnose")
        .arg(&folder)
        .arg("--out")
        .arg(&out)
        .arg("-q")
        .output()
        .map_err(|e| format!("running {}: {e}", exe.display()))?;
    let wall_s = start.elapsed().as_secs_f64();
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
    Ok(scoring::score(case, &d, wall_s))
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
    let mut failures = Vec::new();
    for case in selected() {
        match bench(&exe, root, &case) {
            Ok(s) => {
                println!(
                    "{:<28} {:<40} {:<40} {:>7} samples {:>7.2} s",
                    s.name,
                    s.truth,
                    s.named,
                    (case.record_s * case.sample_rate_hz).round(),
                    s.runtime_s
                );
                scores.push(s);
            }
            Err(e) => {
                println!("{:<28} FAILED: {e}", case.name);
                failures.push(case.name.clone());
            }
        }
    }
    println!("\n{}", scoring::report(&scores));
    let worst = scores.iter().map(|s| s.runtime_s).fold(0.0, f64::max);
    println!(
        "all within the {BUDGET_S} s budget: {}",
        if worst <= BUDGET_S { "yes" } else { "no" }
    );
    if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        eprintln!("failed: {}", failures.join(", "));
        ExitCode::FAILURE
    }
}
