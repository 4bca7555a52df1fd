//! Benchmark of `coil-tune design`: calibrates the paper's case once (`coil-tune
//! calibrate`, timed apart), then times the release binary on the three design targets
//! of `cases/spring-design` (the 160ECT spring, Table 4 #2 and #4), each pointed at that
//! calibration, and prints the best candidate and the wall time (the acceptance asks
//! under 30 s on 2 cores).
//!
//! `cargo build --release -p coil-tune && cargo run --release -p coil-tests --example bench_design`

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn run(binary: &Path, args: &[&str]) -> (f64, String) {
    let clock = Instant::now();
    let output = Command::new(binary)
        .args(args)
        .output()
        .expect("coil-tune runs (build it first: cargo build --release -p coil-tune)");
    let seconds = clock.elapsed().as_secs_f64();
    assert!(
        output.status.success(),
        "coil-tune {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    (
        seconds,
        String::from_utf8_lossy(&output.stdout).into_owned(),
    )
}

fn main() {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let binary = repo.join("target/release/coil-tune");
    let temp = tempfile::tempdir().expect("a temporary folder");
    let calibration = temp.path().join("calibrate");
    let case = repo.join("cases/160ect");
    let (seconds, _) = run(
        &binary,
        &[
            "calibrate",
            &case.to_string_lossy(),
            "--out",
            &calibration.to_string_lossy(),
            "-q",
        ],
    );
    println!("calibrate cases/160ect: {seconds:.2} s");
    for name in ["160ect_target", "table4_2_target", "table4_4_target"] {
        let text = std::fs::read_to_string(repo.join(format!("cases/spring-design/{name}.json")))
            .expect("the target file");
        let mut target: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        target["material"]["calibration"] = calibration
            .join("calibration.json")
            .to_string_lossy()
            .into_owned()
            .into();
        let file = temp.path().join(format!("{name}.json"));
        std::fs::write(&file, target.to_string()).expect("write the target");
        let out = temp.path().join(name);
        let (seconds, stdout) = run(
            &binary,
            &[
                "design",
                &file.to_string_lossy(),
                "--out",
                &out.to_string_lossy(),
            ],
        );
        let best = stdout.lines().nth(1).unwrap_or("");
        println!(
            "{name}: {seconds:.2} s ({})\n  {best}",
            stdout.lines().next().unwrap_or("")
        );
    }
}
