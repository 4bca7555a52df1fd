//! The spring study: the EN 50318 reference catenary and pantograph with the head stage
//! replaced by each of coil's springs (the 160ECT and Table 4's #1-#6, four in parallel:
//! `coil_catenary::head_stage::springs`), at each damping value of the spring's zeta band (low, mid,
//! high: `c = 2 zeta sqrt(K m_head)`) and each speed of the case; the reference head stage
//! (4200 N/m, 10 N s/m) runs beside them. Each spring also runs with its reduced stage
//! (`coil_catenary::head_stage`: the four springs Craig-Bampton reduced, surge modes,
//! own mass and the paper's Rayleigh law on the wire) beside its lumped stage at mid
//! zeta. Prints the head stages, every run's statistics, the study's table
//! (`coil_catenary::en50318::study`) and the reduced-against-lumped table, and draws the
//! study's figure (lumped stages).
//!
//! `cargo run --release -p coil-catenary --example spring_study [CATENARY_CASE] [SPRING_CASE] [FIGURE] [--lumped-only]`
//! (defaults `cases/catenary-en50318-2002`, `cases/160ect` with its `table4.json`,
//! `out/spring_study.png`; `--lumped-only` leaves the reduced stages out). 29 runs per
//! speed (22 with `--lumped-only`), in parallel.

use coil_catenary::case::read_case;
use coil_catenary::en50318::study::{markdown, SpringStudyRow};
use coil_catenary::en50318::Statistics;
use coil_catenary::head_stage::springs::{head_stages_of_files, HeadStageSettings, ZetaLevel};
use coil_catenary::head_stage::{reduced_head_stages, with_reduced_head};
use coil_catenary::run::run_speed;
use coil_tuner::case::read_variants;
use rayon::prelude::*;
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
    let head_mass = case.pantograph.stages[0].mass_kg;
    let settings = HeadStageSettings::default();
    let table4 = springs.join("table4.json");
    let stages =
        head_stages_of_files(&springs, &table4, head_mass, &settings).unwrap_or_else(|e| fail(e));
    let reduced = if lumped_only {
        Vec::new()
    } else {
        let variants = read_variants(&table4).unwrap_or_else(|e| fail(e));
        reduced_head_stages(&stages, &variants, &settings.fe).unwrap_or_else(|e| fail(e))
    };
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
    // Lumped runs (variant index) and reduced runs (spring index), at every speed.
    let jobs: Vec<(bool, usize, f64)> = (0..variants.len())
        .map(|i| (false, i))
        .chain((0..reduced.len()).map(|i| (true, i)))
        .flat_map(|(r, i)| case.speeds_km_h.iter().map(move |&v| (r, i, v)))
        .collect();
    let runs: Vec<(bool, SpringStudyRow)> = jobs
        .par_iter()
        .map(|&(is_reduced, i, speed)| {
            let mut case = case.clone();
            let (name, zeta) = if is_reduced {
                case.pantograph = with_reduced_head(&case.pantograph, &reduced[i]);
                (stages.stages[i].name.clone(), "mid")
            } else {
                let (name, zeta, k, c) = &variants[i];
                case.pantograph.stages[0].stiffness_n_m = *k;
                case.pantograph.stages[0].damping_n_s_m = *c;
                (name.clone(), *zeta)
            };
            let (_, run) = run_speed(&case, speed).unwrap_or_else(|e| fail(e));
            let row = SpringStudyRow {
                spring: name,
                zeta: zeta.into(),
                statistics: run.statistics,
            };
            (is_reduced, row)
        })
        .collect();
    let (reduced_runs, rows): (Vec<_>, Vec<_>) = runs.into_iter().partition(|(r, _)| *r);
    let rows: Vec<SpringStudyRow> = rows.into_iter().map(|(_, row)| row).collect();
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
    if !reduced_runs.is_empty() {
        print_reduced(&rows, &reduced_runs);
    }
    if let Some(parent) = figure.parent() {
        std::fs::create_dir_all(parent).unwrap_or_else(|e| fail(e));
    }
    coil_catenary::en50318::figures::spring_study(&figure, &rows).unwrap_or_else(|e| fail(e));
    println!("figure: {}", figure.display());
}

/// The reduced stage beside the lumped one (mid zeta) per spring and speed: sigma, the
/// actual minimum and the loss of contact, and reduced less lumped.
fn print_reduced(rows: &[SpringStudyRow], reduced: &[(bool, SpringStudyRow)]) {
    println!(
        "\nReduced (surge modes, springs' mass, Rayleigh law on the wire) against lumped (K, c at mid zeta):\n"
    );
    println!("| spring | speed (km/h) | std lumped / reduced (N) | d std (N) | min lumped / reduced (N) | d min (N) | loss lumped / reduced (%) | d loss (%) |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let pairs = [
        (|s: &Statistics| s.std_n) as fn(&Statistics) -> f64,
        |s| s.min_n,
        |s| s.loss_percent,
    ];
    for (_, r) in reduced {
        let speed = r.statistics.speed_km_h;
        let Some(l) = rows
            .iter()
            .find(|l| l.spring == r.spring && l.zeta == "mid" && l.statistics.speed_km_h == speed)
        else {
            continue;
        };
        let mut line = format!("| {} | {speed:.0} |", r.spring);
        for pick in pairs {
            let (a, b) = (pick(&l.statistics), pick(&r.statistics));
            line.push_str(&format!(" {a:.2} / {b:.2} | {:+.2} |", b - a));
        }
        println!("{line}");
    }
}
