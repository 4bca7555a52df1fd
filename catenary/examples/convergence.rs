//! Convergence of the EN 50318 reference case: element length and time step halved until
//! the contact force's standard deviation moves less than 2 % at every speed. Prints a
//! table of the statistics per level and speed.
//!
//! `cargo run --release -p coil-catenary --example convergence [CASE] [LEVELS] [MODE]`
//! (default `cases/catenary-en50318-2002`, at most 4 levels). MODE `both` (default)
//! halves both from 0.5 m and 1 ms; `dt` halves the step from 1 ms at the case's element
//! length; `h` halves the element from 0.5 m at the case's step. `--all` (anywhere
//! after the case) runs every level, past the one that converged.

use coil_catenary::case::read_case;
use coil_catenary::run::run_speed;

fn main() {
    let all = std::env::args().any(|a| a == "--all");
    let args: Vec<String> = std::env::args().filter(|a| a != "--all").collect();
    let path = args
        .get(1)
        .map_or("cases/catenary-en50318-2002", String::as_str);
    let levels: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(4);
    let mode = args.get(3).map_or("both", String::as_str);
    if !["both", "dt", "h"].contains(&mode) {
        eprintln!("convergence: mode `{mode}`; expected both, dt or h");
        std::process::exit(2);
    }
    let mut case = match read_case(std::path::Path::new(path)) {
        Ok(case) => case,
        Err(e) => {
            eprintln!("convergence: {e}");
            std::process::exit(1);
        }
    };
    println!("| element (m) | dt (ms) | speed (km/h) | mean (N) | std (N) | std change | min (N) | max (N) | uplift (mm) | loss (%) | solve (s) |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut last: Vec<Option<f64>> = vec![None; case.speeds_km_h.len()];
    for level in 0..levels {
        let scale = 0.5_f64.powi(level as i32);
        if mode != "dt" {
            case.catenary.element_length_m = 0.5 * scale;
        }
        if mode != "h" {
            case.time_step_s = 1e-3 * scale;
        }
        let mut converged = true;
        for (k, &v) in case.speeds_km_h.clone().iter().enumerate() {
            let (_, run) = match run_speed(&case, v) {
                Ok(r) => r,
                Err(e) => {
                    eprintln!("convergence: {e}");
                    std::process::exit(1);
                }
            };
            let s = run.statistics;
            let change = last[k].map(|p| s.std_n / p - 1.0);
            converged &= change.is_some_and(|c| c.abs() < 0.02);
            println!(
                "| {} | {} | {v} | {:.2} | {:.2} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} |",
                case.catenary.element_length_m,
                case.time_step_s * 1e3,
                s.mean_n,
                s.std_n,
                change.map_or("-".into(), |c| format!("{:+.2} %", 100.0 * c)),
                s.min_n,
                s.max_n,
                s.uplift_support_mm,
                s.loss_percent,
                run.solve_s
            );
            last[k] = Some(s.std_n);
        }
        if converged && !all {
            println!(
                "\nstd moved less than 2 % at every speed from the previous level: converged."
            );
            return;
        }
    }
    if !all {
        println!("\nnot converged to 2 % within {levels} levels.");
    }
}
