//! Silverbox (T. Wigren, J. Schoukens, "Three free data sets for development and
//! benchmarking in nonlinear system identification", ECC 2013): the forced diagnosis on the
//! shared estimation data only, the last two multisines kept out of the fit and scored as
//! the benchmark scores its test data (`coil_tests::silverbox`, the same code the ignored
//! test `shared_data::silverbox_matches_the_docs` holds to docs/forced.md), and the speed
//! benchmarks of docs/forced.md (diagnose on the whole 65,062-sample record, simulate
//! 40,000 samples, one frc of 400 points).
//!
//! Reads `../shared/forced/silverbox/estimation.csv` relative to the repository's root
//! (never copied into the repository):
//!
//! ```sh
//! cargo run --release -p coil-tests --example silverbox
//! ```

use coil_ident::forced::commands::{frc_of, simulate_series};
use coil_ident::forced::frc::FrcSettings;
use coil_ident::forced::{diagnose_case, report, ForcedSettings};
use coil_tests::silverbox::{self, case_of, slice};
use std::time::Instant;

fn main() {
    let settings = ForcedSettings {
        progress: true,
        ..Default::default()
    };
    let t = Instant::now();
    let fit = match silverbox::fit(&silverbox::data(), &settings) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let full = &fit.full;
    println!(
        "{} samples, gaps between multisines at {:?}",
        full.input.len(),
        fit.gaps
    );
    println!(
        "fit on samples 0..{} ({:.1} s, with the scoring):",
        fit.cut(),
        t.elapsed().as_secs_f64()
    );
    println!("{}", report::summary(&fit.outcome));
    let model = fit.outcome.extended().model.clone();
    println!(
        "extended model: {}",
        serde_json::to_string(&model).unwrap_or_default()
    );
    println!("f0 = {:.1} Hz, zeta = {:.3}", fit.f0_hz(), fit.zeta());
    println!("held out (RMS simulation error from 50 initial samples, mV):");
    println!("| part | samples | linear | extended |");
    for h in &fit.held_out {
        println!(
            "| {} ({}..{}) | {} | {:.3} | {:.3} |",
            h.name,
            h.a,
            h.b,
            h.b - h.a - silverbox::INITIAL_SAMPLES,
            h.linear_mv,
            h.extended_mv
        );
    }
    println!("published on the benchmark's test multisine: gated recurrent network 1.49 mV, LSTM 1.50, 7-parameter discrete Duffing 4.62, linear 9.58");

    // Benchmarks.
    let t = Instant::now();
    let all = diagnose_case(case_of(vec![full.clone()]), &ForcedSettings::default())
        .unwrap_or_else(|e| panic!("diagnose: {e}"));
    println!(
        "benchmark: diagnose on all {} samples: {:.2} s (cause {})",
        full.input.len(),
        t.elapsed().as_secs_f64(),
        all.cause
            .map_or("none".to_string(), |i| all.candidates[i].effects[0]
                .name()
                .to_string())
    );
    let mut head = slice(full, 0, 40_000);
    head.output.truncate(silverbox::INITIAL_SAMPLES);
    let t = Instant::now();
    let sim = simulate_series(&model, &head).unwrap_or_else(|e| panic!("simulate: {e}"));
    println!(
        "benchmark: simulate {} samples: {:.3} s",
        sim.output.len(),
        t.elapsed().as_secs_f64()
    );
    let f0 = fit.f0_hz();
    let t = Instant::now();
    let frc = frc_of(
        &model,
        &FrcSettings {
            amplitude: 0.05,
            from_hz: 0.5 * f0,
            to_hz: 1.5 * f0,
            points: 400,
            harmonics: 7,
        },
    )
    .unwrap_or_else(|e| panic!("frc: {e}"));
    println!(
        "benchmark: frc of {} points (0.05 V, {:.1}-{:.1} Hz): {:.3} s, folds at {:?} Hz",
        frc.points.len(),
        0.5 * f0,
        1.5 * f0,
        t.elapsed().as_secs_f64(),
        frc.jumps
    );
}
