//! Writes `cases/forced/hardening/`: a generated shaker test of a 2 kg weight on a
//! hardening spring (2000 N/m, k3 = 2e6 N/m^3, 2 % damping) under a 3-8 Hz multisine of
//! 2 N RMS, 40 s at 100 Hz, the displacement with 1 % noise (tests/src/truth_forced.rs), and
//! its `truth.json` (coil never reads it); and `cases/forced/spring/`: a 0.2 kg weight on
//! a helical spring (its reduced FE model, tests/src/truth_forced_spring.rs) with a
//! hardening law at the weight (k3 = 3e7 N/m^3), driven at the base by a 15-32 Hz
//! multisine of 5 m/s^2 RMS, 12 s at 500 Hz, the relative displacement with 1 % noise.
//!
//! ```sh
//! cargo run --release -p coil-tests --example make_forced_cases
//! ```

use coil_tests::truth_forced::{record, write_case, Excitation, Oscillator};
use coil_tests::truth_forced_spring::{spring_record, write_spring_case, SpringTruth};
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

    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/forced/spring");
    let t = SpringTruth {
        cubic_n_m3: 3e7,
        base: true,
        ..SpringTruth::linear()
    };
    let excitation = Excitation::Multisine {
        from: 15.0,
        to: 32.0,
        level: 5.0,
    };
    let r = spring_record(&t, excitation, 0.002, 12.0, 0.01, 11);
    write_spring_case(&folder, &t, t.mass_kg, &[r])?;
    let truth = serde_json::json!({
        "generator": "tests/src/truth_forced_spring.rs (the reduced FE spring, 6 fixed-interface modes, RK4 in its reduced coordinates)",
        "mass_kg": t.mass_kg,
        "youngs_modulus_mpa": t.youngs_modulus_mpa,
        "rayleigh_beta_s": t.beta_s,
        "cubic_stiffness_n_m3": t.cubic_n_m3,
        "excitation": "base acceleration, multisine 15-32 Hz, 5 m/s^2 RMS, 12 s at 500 Hz, seed 11",
        "noise": "1 % of the displacement RMS"
    });
    std::fs::write(
        folder.join("truth.json"),
        serde_json::to_string_pretty(&truth).unwrap_or_default() + "\n",
    )?;
    println!("wrote {}", folder.display());
    Ok(())
}
