//! Wall-clock benchmark of the whole `coil-tune diagnose` process, one truth case at a
//! time:
//! `cargo build --release -p coil-tuner && cargo run --release -p coil-tests --example bench_diagnose [-- extended [NAME...]]`
//!
//! With `extended`, the cases are `coil_tests::truth::extended_cases()` (softening and
//! hardening, combined effects, other sensors, record imperfections, short and long
//! records; optionally only those NAMEd): the expected causes are every hidden effect
//! (`TruthCase::causes`), the named set is `diagnosis.json`'s `causes`, and the error is
//! the largest over the expected parameters.
//!
//! Every case of `coil_tests::truth::standard_cases()` is written to a temporary folder,
//! then the release binary runs `coil-tune diagnose <case> --out <tmp>/out/<name> -q`
//! (process start, FE reduction, fits, figures, report) and is timed with
//! `std::time::Instant`. The table gives the hidden effect, the named cause, the named
//! parameter's error against the truth, `gain.residual_rms_ratio` from
//! `diagnosis.json`, and the wall time; then the largest and median times against the
//! 15 s budget per case. Cases run one after another so each has the machine to
//! itself (the diagnosis runs its own candidates in parallel).

use coil_tests::truth::{extended_cases, standard_cases, write_case, TruthCase};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

/// Wall-time budget per case (s), issue 14.
const BUDGET_S: f64 = 15.0;

/// One case's outcome.
struct Row {
    name: String,
    truth: String,
    cause: String,
    parameter_error: Option<f64>,
    residual_rms_ratio: Option<f64>,
    wall_s: f64,
}

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

/// Runs the binary on one case and reads its `diagnosis.json`.
fn bench(exe: &Path, tmp: &Path, case: &TruthCase) -> Result<Row, String> {
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
    // The named set: every kept cause, joined by `+` in catalogue order of the truth's
    // naming (sorted), `none` when there is none.
    let mut named: Vec<String> = d["causes"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|c| c["effect"].as_str().map(String::from))
        .collect();
    named.sort();
    let cause = if named.is_empty() {
        "none".to_string()
    } else {
        named.join("+")
    };
    let expected = case.causes();
    let mut truth: Vec<&str> = expected.iter().map(|c| c.0).collect();
    truth.sort();
    let truth = if truth.is_empty() {
        "none".to_string()
    } else {
        truth.join("+")
    };
    // The largest parameter error over the expected causes the diagnosis named.
    let parameter_error = expected
        .iter()
        .filter_map(|(_, name, value)| {
            d["extended"]["parameters"][*name]
                .as_f64()
                .map(|p| p / value - 1.0)
        })
        .max_by(|a, b| a.abs().total_cmp(&b.abs()));
    Ok(Row {
        name: case.name.clone(),
        truth,
        cause,
        parameter_error,
        residual_rms_ratio: d["gain"]["residual_rms_ratio"].as_f64(),
        wall_s,
    })
}

fn main() -> ExitCode {
    let exe = binary();
    if !exe.is_file() {
        eprintln!(
            "error: no release binary at {}\nrun `cargo build --release -p coil-tuner` first",
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
    // COIL_BENCH_KEEP=<folder> keeps the cases and their diagnoses there.
    let keep = std::env::var_os("COIL_BENCH_KEEP").map(PathBuf::from);
    let work: &Path = keep.as_deref().unwrap_or(tmp.path());
    println!("binary: {}", exe.display());
    println!(
        "{:<26} {:<45} {:<45} {:>10} {:>10} {:>8}",
        "case", "truth effect", "named cause", "param err", "res ratio", "wall s"
    );
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cases = if args.first().is_some_and(|a| a == "extended") {
        let only = &args[1..];
        extended_cases()
            .into_iter()
            .filter(|c| only.is_empty() || only.contains(&c.name))
            .collect()
    } else {
        standard_cases()
    };
    for case in cases {
        match bench(&exe, work, &case) {
            Ok(r) => {
                let mark = if r.cause == r.truth { ' ' } else { '*' };
                println!(
                    "{:<26} {:<45} {:<44}{mark} {:>10} {:>10} {:>8.2}",
                    r.name,
                    r.truth,
                    r.cause,
                    r.parameter_error
                        .map_or("-".into(), |e| format!("{:+.2} %", 100.0 * e)),
                    r.residual_rms_ratio
                        .map_or("-".into(), |x| format!("{x:.3}")),
                    r.wall_s
                );
                rows.push(r);
            }
            Err(e) => {
                println!("{:<26} FAILED: {e}", case.name);
                failures.push(case.name.clone());
            }
        }
    }
    let mut times: Vec<f64> = rows.iter().map(|r| r.wall_s).collect();
    times.sort_by(f64::total_cmp);
    if let Some(&max) = times.last() {
        let n = times.len();
        let median = if n % 2 == 1 {
            times[n / 2]
        } else {
            0.5 * (times[n / 2 - 1] + times[n / 2])
        };
        let named = rows.iter().filter(|r| r.cause == r.truth).count();
        println!(
            "\n{n} cases: wall time max {max:.2} s, median {median:.2} s; all <= {BUDGET_S} s: {}",
            if max <= BUDGET_S { "yes" } else { "no" }
        );
        println!("named cause = hidden effect in {named} of {n} (* marks the others)");
    }
    if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        eprintln!("failed: {}", failures.join(", "));
        ExitCode::FAILURE
    }
}
