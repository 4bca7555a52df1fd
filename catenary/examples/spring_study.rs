//! The spring study: the EN 50318 reference catenary and pantograph with the head stage
//! replaced by each of coil's springs (the 160ECT and Table 4's #1-#6, four in parallel:
//! `coil_tuner::head_stage`), at each damping value of the spring's zeta band (low, mid,
//! high: `c = 2 zeta sqrt(K m_head)`) and each speed of the case; the reference head stage
//! (4200 N/m, 10 N s/m) runs beside them. Prints the head stages, every run's statistics
//! and the study's table (`coil_postproc::en50318::study`), and draws the study's figure.
//!
//! `cargo run --release -p coil-catenary --example spring_study [CATENARY_CASE] [SPRING_CASE] [FIGURE]`
//! (defaults `cases/catenary-en50318-2002`, `cases/160ect` with its `table4.json`,
//! `out/spring_study.png`). 22 runs per speed, in parallel.

use coil_catenary::case::read_case;
use coil_catenary::run::run_speed;
use coil_postproc::en50318::study::{markdown, SpringStudyRow};
use coil_tuner::head_stage::{head_stages_of_files, HeadStageSettings, ZetaLevel};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

fn fail(e: impl std::fmt::Display) -> ! {
    eprintln!("spring_study: {e}");
    std::process::exit(1);
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let catenary = args
        .get(1)
        .map_or("cases/catenary-en50318-2002", String::as_str);
    let springs = PathBuf::from(args.get(2).map_or("cases/160ect", String::as_str));
    let figure = PathBuf::from(args.get(3).map_or("out/spring_study.png", String::as_str));
    let case = read_case(Path::new(catenary)).unwrap_or_else(|e| fail(e));
    let head_mass = case.pantograph.stages[0].mass_kg;
    let stages = head_stages_of_files(
        &springs,
        &springs.join("table4.json"),
        head_mass,
        &HeadStageSettings::default(),
    )
    .unwrap_or_else(|e| fail(e));
    println!("| spring | K (N/m) | c low / mid / high (N s/m) |\n|---|---:|---:|");
    let reference = case.pantograph.stages[0].clone();
    println!(
        "| EN 50318 head | {} | {} (reference) |",
        reference.stiffness_n_m, reference.damping_n_s_m
    );
    // (spring, zeta label, K, c) for every run.
    let mut variants: Vec<(String, &'static str, f64, f64)> = vec![(
        "EN 50318 head".into(),
        "mid",
        reference.stiffness_n_m,
        reference.damping_n_s_m,
    )];
    for s in &stages.stages {
        println!(
            "| {} | {:.1} | {:.3} / {:.3} / {:.3} |",
            s.name, s.stiffness_n_m, s.damping_low_n_s_m, s.damping_mid_n_s_m, s.damping_high_n_s_m
        );
        for level in ZetaLevel::ALL {
            variants.push((
                s.name.clone(),
                level.name(),
                s.stiffness_n_m,
                s.damping_n_s_m(level),
            ));
        }
    }
    let jobs: Vec<(usize, f64)> = (0..variants.len())
        .flat_map(|i| case.speeds_km_h.iter().map(move |&v| (i, v)))
        .collect();
    let rows: Vec<SpringStudyRow> = jobs
        .par_iter()
        .map(|&(i, speed)| {
            let (name, zeta, k, c) = &variants[i];
            let mut case = case.clone();
            case.pantograph.stages[0].stiffness_n_m = *k;
            case.pantograph.stages[0].damping_n_s_m = *c;
            let (_, run) = run_speed(&case, speed).unwrap_or_else(|e| fail(e));
            SpringStudyRow {
                spring: name.clone(),
                zeta: (*zeta).into(),
                statistics: run.statistics,
            }
        })
        .collect();
    println!("\n| spring | zeta | speed (km/h) | mean (N) | std (N) | min (N) | max (N) | uplift (mm) | loss (%) |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for r in &rows {
        let s = &r.statistics;
        println!(
            "| {} | {} | {:.0} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} |",
            r.spring,
            r.zeta,
            s.speed_km_h,
            s.mean_n,
            s.std_n,
            s.min_n,
            s.max_n,
            s.uplift_support_mm,
            s.loss_percent
        );
    }
    println!("\n{}", markdown(&rows));
    if let Some(parent) = figure.parent() {
        std::fs::create_dir_all(parent).unwrap_or_else(|e| fail(e));
    }
    coil_postproc::en50318::figures::spring_study(&figure, &rows).unwrap_or_else(|e| fail(e));
    println!("figure: {}", figure.display());
}
