//! Runtime benchmark: one 10-span run of the EN 50318 reference case at 300 km/h (the
//! case's element length and time step), the static state and the transient, timed.
//!
//! `cargo run --release -p coil-catenary --example bench_catenary [CASE]`
//! Target: under 10 s on 2 cores.

use coil_catenary::case::read_case;
use coil_catenary::run::run_speed;
use std::time::Instant;

fn main() {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "cases/catenary-en50318-2002".into());
    let case = match read_case(std::path::Path::new(&path)) {
        Ok(case) => case,
        Err(e) => {
            eprintln!("bench_catenary: {e}");
            std::process::exit(1);
        }
    };
    let started = Instant::now();
    let (built, run) = match run_speed(&case, 300.0) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("bench_catenary: {e}");
            std::process::exit(1);
        }
    };
    let total = started.elapsed().as_secs_f64();
    let s = run.statistics;
    println!(
        "{} spans, {} nodes per wire, {} steps of {} s: static state and model {:.2} s, \
         solve {:.2} s, total {:.2} s (target < 10 s); std {:.2} N",
        case.catenary.spans,
        built.wire_nodes,
        run.steps,
        case.time_step_s,
        total - run.solve_s,
        run.solve_s,
        total,
        s.std_n
    );
}
