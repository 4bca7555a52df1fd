//! Writes `cases/forced/hardening/`: a generated shaker test of a 2 kg weight on a
//! hardening spring (2000 N/m, k3 = 2e6 N/m^3, 2 % damping) under a 3-8 Hz multisine of
//! 2 N RMS, 40 s at 100 Hz, the displacement with 1 % noise (tests/src/truth_forced.rs), and
//! its `truth.json` (coil never reads it).
//!
//! ```sh
//! cargo run --release -p coil-tests --example make_forced_cases
//! ```

use coil_tests::truth_forced::{record, write_case, Excitation, Oscillator};
use std::path::Path;

fn main() -> std::io::Result<()> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/forced/hardening");
    let mut o = Oscillator::linear();
    o.cubic_n_m3 = 2e6;
    let excitation = Excitation::Multisine {
        from: 3.0,
        to: 8.0,
        level: 2.0,
    };
    let r = record(&o, excitation, 40.0, 0.01, 7);
    write_case(&folder, "hardening spring on a shaker (generated)", &[r])?;
    let truth = serde_json::json!({
        "generator": "tests/src/truth_forced.rs (RK4, 40 steps per sample)",
        "mass_kg": o.mass_kg,
        "stiffness_n_m": o.stiffness_n_m,
        "damping_n_s_m": o.damping_n_s_m,
        "cubic_stiffness_n_m3": o.cubic_n_m3,
        "excitation": "multisine 3-8 Hz, 2 N RMS, 40 s at 100 Hz, seed 7",
        "noise": "1 % of the displacement RMS"
    });
    std::fs::write(
        folder.join("truth.json"),
        serde_json::to_string_pretty(&truth).unwrap_or_default() + "\n",
    )?;
    println!("wrote {}", folder.display());
    Ok(())
}
