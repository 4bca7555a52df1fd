//! A survey of the generated cases, without diagnosing them: each case's axial period,
//! cycles in the record, samples, the cubic backbone shift at the initial amplitude, the
//! hidden causes, the record's peak and quantisation step, how close a softening spring
//! comes to giving way (`(x0 + A) / x_limit`), where the free decay starts after a
//! hammer blow, and the generation time.
//! `cargo run --release -p coil-tests --example truth_survey [standard|extended]`

use coil_tests::truth::{
    axial_mode, backbone_shift, extended_cases, generate, standard_cases, TruthCase,
};
use std::f64::consts::TAU;

fn main() {
    let cases: Vec<TruthCase> = match std::env::args().nth(1).as_deref() {
        Some("standard") => standard_cases(),
        Some("extended") | None => extended_cases(),
        Some(other) => {
            eprintln!("error: unknown set `{other}`; expected `standard` or `extended`");
            std::process::exit(2);
        }
    };
    for c in cases {
        let start = std::time::Instant::now();
        let g = generate(&c);
        let period = axial_mode(&c).map_or(f64::NAN, |m| TAU / m.omega);
        let amplitude = c.impulse_velocity_m_s * period / TAU;
        let x0 = c.equilibrium_compression_m();
        let causes: Vec<String> = c
            .causes()
            .iter()
            .map(|(_, name, value)| format!("{name} = {value:e}"))
            .collect();
        println!(
            "{:28} T {:.3} s, {:4.0} cycles, {:6} samples of {:16}, shift {:+.4}, \
             peak {:.3e}, step {:.2e}, (x0+A)/limit {:.2}, free from sample {}, {:.2} s: {}",
            c.name,
            period,
            c.record_s / period,
            g.decay.len(),
            g.column,
            backbone_shift(&c),
            g.peak_m_s2,
            g.quantisation_m_s2,
            (x0 + amplitude) / c.softening_limit_m(),
            g.free_decay_start,
            start.elapsed().as_secs_f64(),
            if causes.is_empty() {
                "none".to_string()
            } else {
                causes.join(", ")
            }
        );
    }
}
