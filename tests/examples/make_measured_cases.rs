//! Writes the truth model's standard, extended and hard measured cases (coil_tests::truth), one folder each:
//! `cargo run -p coil-tests --example make_measured_cases -- OUT_DIR [--only NAME]...`
//! (`--shipped` writes only the cases kept under cases/measured/).

use coil_tests::truth::{extended_cases, hard_cases, standard_cases, write_case, SHIPPED};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let mut out: Option<PathBuf> = None;
    let mut only: Vec<String> = Vec::new();
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--only" => match args.next() {
                Some(name) => only.push(name),
                None => return usage("--only needs a case name"),
            },
            "--shipped" => only.extend(SHIPPED.iter().map(|s| s.to_string())),
            _ if out.is_none() => out = Some(PathBuf::from(arg)),
            _ => return usage(&format!("unexpected argument `{arg}`")),
        }
    }
    let Some(out) = out else {
        return usage("missing OUT_DIR");
    };
    let cases: Vec<_> = standard_cases()
        .into_iter()
        .chain(extended_cases())
        .chain(hard_cases())
        .collect();
    for name in &only {
        if !cases.iter().any(|c| &c.name == name) {
            let names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
            return usage(&format!("no case `{name}` (cases: {})", names.join(", ")));
        }
    }
    for case in cases
        .iter()
        .filter(|c| only.is_empty() || only.contains(&c.name))
    {
        let start = Instant::now();
        let dir = out.join(&case.name);
        if let Err(e) = write_case(&dir, case) {
            eprintln!("error: {}: {e}", dir.display());
            return ExitCode::FAILURE;
        }
        println!(
            "{:<24} {:<25} {:>6} Hz {:>4} s noise {:>5.1} %  {:.2} s",
            case.name,
            case.effect.name(),
            case.sample_rate_hz,
            case.record_s,
            case.noise_fraction * 100.0,
            start.elapsed().as_secs_f64()
        );
    }
    ExitCode::SUCCESS
}

fn usage(problem: &str) -> ExitCode {
    eprintln!("error: {problem}");
    eprintln!("usage: make_measured_cases OUT_DIR [--only NAME]... [--shipped]");
    ExitCode::from(2)
}
