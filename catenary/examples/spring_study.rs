//! The spring study: the EN 50318 reference catenary and pantograph with the head stage
//! replaced by each of coil's springs (the 160ECT and Table 4's #1-#6, four in parallel),
//! at each damping value of the spring's zeta band, beside the reference head stage, and
//! each spring once more with its reduced stage (`coil_catenary::study::band`). Prints the
//! head stages, every run's statistics, the study's table
//! (`coil_catenary::en50318::study`) and the reduced-against-lumped table, and draws the
//! study's figure (lumped stages).
//!
//! `cargo run --release -p coil-catenary --example spring_study [CATENARY_CASE] [SPRING_CASE] [FIGURE] [--lumped-only]`
//! (defaults `cases/catenary-en50318-2002`, `cases/160ect` with its `table4.json`,
//! `out/spring_study.png`; `--lumped-only` leaves the reduced stages out). 29 runs per
//! speed (22 with `--lumped-only`), in parallel.

use coil_catenary::case::read_case;
use coil_catenary::en50318::study::markdown;
use coil_catenary::study::band::band_study;
use std::path::{Path, PathBuf};

fn fail(e: impl std::fmt::Display) -> ! {
    eprintln!("spring_study: {e}");
    std::process::exit(1);
}

fn main() {
    let all: Vec<String> = std::env::args().collect();
    let lumped_only = all.iter().any(|a| a == "--lumped-only");
    let args: Vec<String> = all.into_iter().filter(|a| !a.starts_with("--")).collect();
    let catenary = args
        .get(1)
        .map_or("cases/catenary-en50318-2002", String::as_str);
    let springs = PathBuf::from(args.get(2).map_or("cases/160ect", String::as_str));
    let figure = PathBuf::from(args.get(3).map_or("out/spring_study.png", String::as_str));
    let case = read_case(Path::new(catenary)).unwrap_or_else(|e| fail(e));
    let study = band_study(&case, &springs, &springs.join("table4.json"), !lumped_only)
        .unwrap_or_else(|e| fail(e));
    println!("| spring | K (N/m) | c low / mid / high (N s/m) |\n|---|---:|---:|");
    if let Some(reference) = case.pantograph.stages.first() {
        println!(
            "| EN 50318 head | {} | {} (reference) |",
            reference.stiffness_n_m, reference.damping_n_s_m
        );
    }
    for s in &study.stages.stages {
        println!(
            "| {} | {:.1} | {:.3} / {:.3} / {:.3} |",
            s.name, s.stiffness_n_m, s.damping_low_n_s_m, s.damping_mid_n_s_m, s.damping_high_n_s_m
        );
    }
    println!("\n{}", study.runs_markdown());
    println!("{}", markdown(&study.rows));
    if !study.reduced.is_empty() {
        println!(
            "\nReduced (surge modes, springs' mass, Rayleigh law on the wire) against lumped (K, c at mid zeta):\n"
        );
        println!("{}", study.reduced_markdown());
    }
    if let Some(parent) = figure.parent() {
        std::fs::create_dir_all(parent).unwrap_or_else(|e| fail(e));
    }
    coil_catenary::en50318::figures::spring_study(&figure, &study.rows).unwrap_or_else(|e| fail(e));
    println!("figure: {}", figure.display());
}
