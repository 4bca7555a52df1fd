//! Silverbox (T. Wigren, J. Schoukens, "Three free data sets for development and
//! benchmarking in nonlinear system identification", ECC 2013): the forced diagnosis on the
//! shared estimation data only, the last two multisines kept out of the fit and scored as
//! the benchmark scores its test data (the model simulated under the measured input from
//! the first 50 measured outputs only; RMS error in mV over the rest), and the speed
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
use coil_ident::forced::model::{InputQuantity, OutputQuantity};
use coil_ident::forced::records::{read_record, ForcedCase, ForcedEntry, ForcedRecord};
use coil_ident::forced::{diagnose_case, report, ForcedSettings};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/forced/silverbox/estimation.csv")
}

/// The gaps between the multisines: runs of at least 40 samples over which the input moves
/// by less than 2 mV per sample (the generator's pause at its DC level). Returns their starts.
fn gaps(u: &[f64]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut i = 1;
    while i < u.len() {
        let mut j = i;
        while j < u.len() && (u[j] - u[j - 1]).abs() < 0.002 {
            j += 1;
        }
        if j - i + 1 >= 40 {
            out.push(i - 1);
        }
        i = j + 1;
    }
    out
}

fn slice(r: &ForcedRecord, a: usize, b: usize) -> ForcedRecord {
    ForcedRecord {
        t0: r.time_s[a],
        time_s: r.time_s[a..b].to_vec(),
        input: r.input[a..b].to_vec(),
        output: r.output[a..b].to_vec(),
        ..r.clone()
    }
}

fn case_of(records: Vec<ForcedRecord>) -> ForcedCase {
    ForcedCase {
        file: data(),
        name: "Silverbox estimation data".into(),
        has_spring: false,
        mass_kg: None,
        records,
    }
}

fn main() {
    let entry = ForcedEntry {
        file: data(),
        time: "time_s".into(),
        input: "u_v".into(),
        output: "y_v".into(),
        input_quantity: InputQuantity::Force,
        output_quantity: OutputQuantity::Displacement,
        input_unit: "V".into(),
        output_unit: "V".into(),
    };
    let (full, _) = match read_record(&entry, None) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("silverbox: {e} (the shared data sit at ../shared/forced/silverbox/)");
            std::process::exit(1);
        }
    };
    let g = gaps(&full.input);
    println!(
        "{} samples, gaps between multisines at {:?}",
        full.input.len(),
        g
    );
    assert!(g.len() >= 3, "expected the multisines' gaps");
    // The last two complete multisines: from the third-last gap to the last.
    let (cut, mid, end) = (g[g.len() - 3], g[g.len() - 2], g[g.len() - 1]);
    let settings = ForcedSettings {
        progress: true,
        ..Default::default()
    };

    // Fit on everything before the held-out multisines.
    let t = Instant::now();
    let outcome = diagnose_case(case_of(vec![slice(&full, 0, cut)]), &settings)
        .unwrap_or_else(|e| panic!("diagnose: {e}"));
    println!(
        "fit on samples 0..{cut} ({:.1} s):",
        t.elapsed().as_secs_f64()
    );
    println!("{}", report::summary(&outcome));
    let model = outcome.extended().model.clone();
    let linear = outcome.baseline.model.clone();
    println!(
        "extended model: {}",
        serde_json::to_string(&model).unwrap_or_default()
    );

    // Score the held-out multisines as the benchmark does: 50 initial outputs only.
    println!("held out (RMS simulation error from 50 initial samples, mV):");
    println!("| part | samples | linear | extended |");
    for (name, a, b) in [
        ("multisine 1 of 2", cut, mid),
        ("multisine 2 of 2", mid, end),
        ("both", cut, end),
    ] {
        let part = slice(&full, a, b);
        let score = |m: &coil_ident::forced::model::ForcedModel| {
            let mut head = part.clone();
            head.output.truncate(50);
            let sim = simulate_series(m, &head).unwrap_or_else(|e| panic!("simulate: {e}"));
            let n = part.output.len() - 50;
            let sse: f64 = (50..part.output.len())
                .map(|i| (sim.output[i] - part.output[i]).powi(2))
                .sum();
            1e3 * (sse / n as f64).sqrt()
        };
        println!(
            "| {name} ({a}..{b}) | {} | {:.3} | {:.3} |",
            b - a - 50,
            score(&linear),
            score(&model)
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
    let mut head = slice(&full, 0, 40_000);
    head.output.truncate(50);
    let t = Instant::now();
    let sim = simulate_series(&model, &head).unwrap_or_else(|e| panic!("simulate: {e}"));
    println!(
        "benchmark: simulate {} samples: {:.3} s",
        sim.output.len(),
        t.elapsed().as_secs_f64()
    );
    let f0 = model.oscillator.natural_frequency_rad_s / std::f64::consts::TAU;
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
