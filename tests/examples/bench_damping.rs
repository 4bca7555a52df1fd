//! Benchmark of `coil-tune damping`: writes generated cases from the damping
//! truth model (`coil_tests::truth_damping`) into a temporary folder and times the
//! release binary on each, printing the verdict beside the hidden law and what the design
//! can decide (each test's damping scattered by `SCATTER`, 3 % by default).
//!
//! `cargo build --release -p coil-tune && cargo run --release -p coil-tests --example bench_damping`
//! (`-- --keep DIR` writes the cases into DIR and keeps them).

use coil_tests::truth_damping::{DampingTruth, TruthLaw};
use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let keep = args
        .iter()
        .position(|a| a == "--keep")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    let temp = tempfile::tempdir().expect("a temporary folder");
    let root = keep.unwrap_or_else(|| temp.path().to_path_buf());
    let binary = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/release/coil-tune");
    let m = 5.24;
    // (name, law, masses (a mass listed again is a repeated test), surge records)
    let cases = [
        (
            "hysteretic_2m",
            TruthLaw::Hysteretic { eta: 0.0035 },
            vec![m, 2.0 * m],
            0,
        ),
        (
            "beta_2m_surge",
            TruthLaw::Rayleigh {
                alpha: 0.0,
                beta: 1.28e-4,
            },
            vec![m, 1.5 * m],
            1,
        ),
        (
            "alpha_beta_3m_surge",
            TruthLaw::Rayleigh {
                alpha: 1.6,
                beta: 1.2e-4,
            },
            vec![m, 1.7 * m, 2.5 * m],
            1,
        ),
        ("dashpot_1m_surge", TruthLaw::Dashpot { c: 0.5 }, vec![m], 1),
        (
            "dashpot_3m",
            TruthLaw::Dashpot { c: 0.5 },
            vec![m, 2.0 * m, 3.0 * m],
            0,
        ),
        (
            "hysteretic_close",
            TruthLaw::Hysteretic { eta: 0.0035 },
            vec![m, 1.02 * m],
            0,
        ),
        (
            "beta_axial_surge",
            TruthLaw::Rayleigh {
                alpha: 0.0,
                beta: 1.28e-4,
            },
            vec![m],
            1,
        ),
        (
            "hysteretic_2m_4_repeats",
            TruthLaw::Hysteretic { eta: 0.0035 },
            vec![m, m, m, m, 2.0 * m, 2.0 * m, 2.0 * m, 2.0 * m],
            0,
        ),
        (
            "beta_axial_surge_3_repeats",
            TruthLaw::Rayleigh {
                alpha: 0.0,
                beta: 1.28e-4,
            },
            vec![m, m, m],
            3,
        ),
    ];
    let mut times = Vec::new();
    let scatter = std::env::var("SCATTER")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.03);
    for (seed, (name, law, masses, surges)) in cases.into_iter().enumerate() {
        let dir = root.join(name);
        let truth = DampingTruth {
            name: name.to_string(),
            law,
            masses_kg: masses,
            surges,
            scatter,
            noise: std::env::var("NOISE")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(0.005),
            seed: std::env::var("SEED")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(seed as u64 + 1),
        };
        truth.write(&dir).expect("the case is written");
        if !binary.is_file() {
            println!(
                "{name}: written to {} (no release binary to time)",
                dir.display()
            );
            continue;
        }
        let start = Instant::now();
        let out = Command::new(&binary)
            .arg("damping")
            .arg(&dir)
            .arg("--out")
            .arg(dir.join("out"))
            .output()
            .expect("coil-tune runs");
        let wall = start.elapsed().as_secs_f64();
        times.push(wall);
        let text = String::from_utf8_lossy(&out.stdout);
        let verdict = text
            .lines()
            .find(|l| l.starts_with("law:"))
            .unwrap_or("(no verdict)");
        let scatter_line = text
            .lines()
            .find(|l| l.starts_with("repeat scatter"))
            .unwrap_or("");
        println!(
            "{name:28} {wall:6.2} s  hidden {law:?} ({:?})\n    {scatter_line}\n    {verdict}",
            truth.decidability()
        );
        if !out.status.success() {
            println!("    failed: {}", String::from_utf8_lossy(&out.stderr));
        }
    }
    if !times.is_empty() {
        let max = times.iter().copied().fold(0.0, f64::max);
        println!(
            "coil-tune damping: {} cases, max {max:.2} s per case",
            times.len()
        );
    }
}
