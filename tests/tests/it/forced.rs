//! Forced records against generated truth (tests/src/truth_forced.rs: an independent RK4 at
//! 40 steps per sample): `simulate` of the truth model equals the generator's output, the
//! diagnosis names the effect and recovers its parameter within 10 % from noisy records
//! (multisine, sweeps up and down, stepped sine), and the forced response curve agrees with
//! long time integrations through a fold and with the Duffing oscillator's exact backbone.

use coil_ident::forced::commands::simulate_series;
use coil_ident::forced::model::{ForcedModel, InputQuantity, Lumped, OutputQuantity};
use coil_ident::forced::records::{ForcedEntry, ForcedRecord};
use coil_ident::forced::simulate::{self, Grid};
use coil_ident::forced::{diagnose_forced, report, ForcedSettings};
use coil_tests::truth_forced::{record, write_case, Excitation, Oscillator};
use rayon::prelude::*;
use std::f64::consts::TAU;

fn model_of(o: &Oscillator) -> ForcedModel {
    let m = o.mass_kg;
    let w0 = (o.stiffness_n_m / m).sqrt();
    let oscillator = Lumped {
        natural_frequency_rad_s: w0,
        damping_ratio: o.damping_n_s_m / (2.0 * m * w0),
        input_gain: 1.0 / m,
        cubic: o.cubic_n_m3 / m,
        friction: o.friction_n / m,
        drag: o.drag_n_s2_m2 / m,
        friction_velocity: o.friction_velocity_m_s,
        output_offset: 0.0,
        modes: Vec::new(),
    };
    ForcedModel::new(
        InputQuantity::Force,
        OutputQuantity::Displacement,
        ("N", "m"),
        None,
        oscillator,
    )
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

fn with(f: impl Fn(&mut Oscillator)) -> Oscillator {
    let mut o = Oscillator::linear();
    f(&mut o);
    o
}

const MULTISINE: Excitation = Excitation::Multisine {
    from: 3.0,
    to: 8.0,
    level: 2.0,
};
const SWEEP_UP: Excitation = Excitation::Sweep {
    from: 2.0,
    to: 9.0,
    level: 1.0,
};
const SWEEP_DOWN: Excitation = Excitation::Sweep {
    from: 9.0,
    to: 2.0,
    level: 1.0,
};
const STEPPED: Excitation = Excitation::Stepped {
    from: 3.5,
    to: 7.0,
    count: 12,
    dwell: 5.0,
    level: 1.0,
};

#[test]
fn simulate_of_the_truth_model_equals_the_generator() {
    let o = with(|o| {
        o.cubic_n_m3 = 2e6;
        o.friction_n = 0.2;
        o.drag_n_s2_m2 = 10.0;
    });
    for (k, excitation) in [MULTISINE, SWEEP_UP, STEPPED].into_iter().enumerate() {
        let r = record(&o, excitation, 30.0, 0.0, 10 + k as u64);
        let model = model_of(&o);
        // From rest, the state the generator starts from.
        let z_max = r.truth_m.iter().fold(0.0f64, |m, z| m.max(z.abs()));
        let w = model.oscillator.natural_frequency_rad_s;
        let grid = Grid {
            dt: r.dt,
            substeps: simulate::substeps(&model.oscillator, r.dt, z_max, w * z_max),
        };
        let y = simulate::output(&model, grid, &r.force_n, (0.0, 0.0), 1.0).unwrap();
        let err: Vec<f64> = y.iter().zip(&r.truth_m).map(|(a, b)| a - b).collect();
        // RK4 at w h <= 0.25 against RK4 at 40 steps per sample: RK4's phase error is
        // (w h)^5 / 120 per step, (w h)^4 w / 120 per unit time, and the damping forgets it
        // after 1 / (zeta w): a relative error below (w h)^4 / (120 zeta) = 1.6e-3.
        let bound = 0.25f64.powi(4) / (120.0 * 0.02);
        println!(
            "excitation {k}: simulate against the generator {:.2e} of the response (bound {bound:.1e})",
            rms(&err) / rms(&r.truth_m)
        );
        assert!(
            rms(&err) < bound * rms(&r.truth_m),
            "excitation {k}: {:.3e} of {:.3e}",
            rms(&err),
            rms(&r.truth_m)
        );
        // The command's path: the initial state fitted to the first 50 outputs only.
        let entry = ForcedEntry {
            file: "truth.csv".into(),
            time: "time_s".into(),
            input: "force_n".into(),
            output: "displacement_m".into(),
            input_quantity: InputQuantity::Force,
            output_quantity: OutputQuantity::Displacement,
            input_unit: "N".into(),
            output_unit: "m".into(),
        };
        let head = ForcedRecord {
            entry,
            format: String::new(),
            dt: r.dt,
            t0: 0.0,
            time_s: (0..r.force_n.len()).map(|i| i as f64 * r.dt).collect(),
            input: r.force_n.clone(),
            output: r.truth_m[..50].to_vec(),
        };
        let sim = simulate_series(&model, &head).unwrap();
        let err: Vec<f64> = sim
            .output
            .iter()
            .zip(&r.truth_m)
            .map(|(a, b)| a - b)
            .collect();
        assert!(rms(&err) < bound * rms(&r.truth_m), "{:.3e}", rms(&err));
    }
}

/// One generated case: the effect, its truth value and the records' excitations.
struct Case {
    name: &'static str,
    oscillator: Oscillator,
    excitations: &'static [Excitation],
    cause: &'static str,
    parameter: Option<(&'static str, f64)>,
}

fn cases() -> Vec<Case> {
    let cubic = |v| with(|o| o.cubic_n_m3 = v);
    let friction = with(|o| o.friction_n = 0.2);
    let drag = with(|o| o.drag_n_s2_m2 = 10.0);
    let mut out = Vec::new();
    for (tag, ex) in [
        ("multisine", &[MULTISINE][..]),
        ("sweeps", &[SWEEP_UP, SWEEP_DOWN][..]),
        ("stepped", &[STEPPED][..]),
    ] {
        out.push(Case {
            name: tag,
            oscillator: Oscillator::linear(),
            excitations: ex,
            cause: "none",
            parameter: None,
        });
        out.push(Case {
            name: tag,
            oscillator: cubic(2e6),
            excitations: ex,
            cause: "cubic_stiffness",
            parameter: Some(("cubic_stiffness_n_m3", 2e6)),
        });
        out.push(Case {
            name: tag,
            oscillator: cubic(-1e6),
            excitations: ex,
            cause: "cubic_stiffness",
            parameter: Some(("cubic_stiffness_n_m3", -1e6)),
        });
        out.push(Case {
            name: tag,
            oscillator: friction,
            excitations: ex,
            cause: "coulomb_friction",
            parameter: Some(("friction_force_n", 0.2)),
        });
        out.push(Case {
            name: tag,
            oscillator: drag,
            excitations: ex,
            cause: "quadratic_damping",
            parameter: Some(("quadratic_damping_n_s2_m2", 10.0)),
        });
    }
    out
}

fn check(case: &Case, seed: u64) -> Result<String, String> {
    let dir = tempfile::tempdir().unwrap();
    let records: Vec<_> = case
        .excitations
        .iter()
        .enumerate()
        .map(|(k, &e)| record(&case.oscillator, e, 60.0, 0.01, seed + k as u64))
        .collect();
    write_case(dir.path(), case.name, &records).unwrap();
    let outcome =
        diagnose_forced(dir.path(), &ForcedSettings::default()).map_err(|e| e.to_string())?;
    let doc = report::document(&outcome);
    let line = format!(
        "{} {}: cause {} (expected {}); {}",
        case.name,
        case.cause,
        doc["cause"],
        case.cause,
        report::summary(&outcome).replace('\n', " | ")
    );
    if doc["cause"] != case.cause {
        return Err(line);
    }
    let o = &case.oscillator;
    let b = &doc["baseline"];
    let close = |found: f64, truth: f64| ((found - truth) / truth).abs() < 0.10;
    if let Some((name, truth)) = case.parameter {
        let found = doc["extended"]["parameters"][name]
            .as_f64()
            .unwrap_or(f64::NAN);
        if !close(found, truth) {
            return Err(format!("{line}: {name} = {found} against {truth}"));
        }
    } else {
        for (name, truth) in [
            ("mass_kg", o.mass_kg),
            ("stiffness_n_m", o.stiffness_n_m),
            ("damping_n_s_m", o.damping_n_s_m),
        ] {
            let found = b[name].as_f64().unwrap_or(f64::NAN);
            if !close(found, truth) {
                return Err(format!("{line}: {name} = {found} against {truth}"));
            }
        }
    }
    Ok(line)
}

/// Every effect and the null case under every excitation (multisine, the sweep pair up
/// and down, stepped sine), with noise: the cause named and its parameter (the linear ones
/// for the null case) within 10 %. 15 diagnoses, in parallel (about 7 s of CPU).
#[test]
fn every_effect_under_every_excitation() {
    let results: Vec<Result<String, String>> = cases()
        .par_iter()
        .enumerate()
        .map(|(i, case)| check(case, 200 + 10 * i as u64))
        .collect();
    let mut failures = Vec::new();
    for r in results {
        match r {
            Ok(line) => println!("{line}"),
            Err(e) => failures.push(e),
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A hardening Duffing oscillator with a fold: 5 Hz, 1 % damping.
fn duffing() -> ForcedModel {
    let w0 = TAU * 5.0;
    let mut o = Lumped::linear(w0, 0.01, 1.0);
    o.cubic = 20.0 * w0 * w0;
    ForcedModel::new(
        InputQuantity::Force,
        OutputQuantity::Displacement,
        ("N", "m"),
        None,
        o,
    )
}

#[test]
fn frc_agrees_with_long_time_integrations_through_the_fold() {
    let (worst, j) = crate::frc_check::frc_against_time_integration(&duffing(), 2.0, 3.5, 9.0);
    println!(
        "stable branches: worst relative difference {worst:.2e}; jumps: curve {:.4} / {:.4} \
         Hz, time integration {:.4} / {:.4} Hz",
        j[0], j[1], j[2], j[3]
    );
}

/// K(m) by the arithmetic-geometric mean: K = pi / (2 AGM(1, sqrt(1 - m))).
fn elliptic_k(m: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - m).sqrt());
    while (a - b).abs() > 1e-15 * a {
        let next = (0.5 * (a + b), (a * b).sqrt());
        a = next.0;
        b = next.1;
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn backbone_matches_the_exact_duffing_period() {
    let model = duffing();
    let w0 = model.oscillator.natural_frequency_rad_s;
    let kappa = model.oscillator.cubic;
    let backbone = coil_ident::forced::frc::backbone(&model, 0.15, 30, 9).unwrap();
    let mut worst: f64 = 0.0;
    for p in &backbone {
        let a = p.peak_displacement;
        let s = w0 * w0 + kappa * a * a;
        let m = kappa * a * a / (2.0 * s);
        let exact_hz = 1.0 / (4.0 * elliptic_k(m) / s.sqrt());
        let err = ((p.frequency_hz - exact_hz) / exact_hz).abs();
        worst = worst.max(err);
    }
    let last = backbone.last().unwrap();
    println!(
        "backbone: {} points to {:.3} Hz at peak {:.3}; worst relative error {worst:.2e}",
        backbone.len(),
        last.frequency_hz,
        last.peak_displacement
    );
    // Nine harmonics of a Duffing orbit whose frequency rises about 15 %: the truncated
    // Fourier series' error (its harmonics fall by about 30 each) is far below 1e-6.
    assert!(worst < 1e-6, "{worst}");
    assert!(last.frequency_hz > 1.1 * 5.0);
}

/// The same forced record as CSV, as a MAT-file and as UFF 58 (the readers of decay
/// records, docs/measured-case.md): the same cause and the same parameters, within what
/// the text formats' printed digits move (the CSV carries 10 significant digits).
#[test]
fn a_forced_case_diagnoses_alike_from_csv_mat_and_uff() {
    let case = cases()
        .into_iter()
        .find(|c| c.cause == "cubic_stiffness")
        .expect("a hardening case");
    let r = record(&case.oscillator, case.excitations[0], 30.0, 0.01, 7);
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("csv");
    write_case(&csv, "csv", std::slice::from_ref(&r)).unwrap();
    let n = r.force_n.len();
    let time: Vec<f64> = (0..n).map(|i| i as f64 * r.dt).collect();
    let doubles = coil_postproc::record::mat::doubles;
    let (bt, bu, by) = (doubles(&time), doubles(&r.force_n), doubles(&r.measured_m));
    let mat = coil_postproc::record::mat::level5_bytes(
        &[("t", 9, &bt, n), ("force", 9, &bu, n), ("disp", 9, &by, n)],
        true,
    );
    let dataset = |node, unit: &str, values: &[f64]| coil_io::uff::Uff58 {
        description: "forced".into(),
        name: format!("channel {node}"),
        node,
        direction: 3,
        ordinate_type: 1,
        length_exponent: 0,
        ordinate_label: "forced".into(),
        ordinate_unit: unit.into(),
        start_s: 0.0,
        step_s: r.dt,
        values: values.to_vec(),
    };
    let uff = coil_io::uff::uff58_bytes(
        &[dataset(1, "N", &r.force_n), dataset(2, "m", &r.measured_m)],
        true,
    );
    let mut causes = Vec::new();
    for (name, file, bytes, time, input, output) in [
        (
            "csv",
            "record_1.csv",
            None,
            "time_s",
            "force_n",
            "displacement_m",
        ),
        ("mat", "record.mat", Some(mat), "t", "force", "disp"),
        ("uff", "record.uff", Some(uff), "time_s", "1:3", "2:3"),
    ] {
        let folder = dir.path().join(name);
        if let Some(bytes) = bytes {
            std::fs::create_dir_all(&folder).unwrap();
            std::fs::write(folder.join(file), bytes).unwrap();
            let entry = serde_json::json!({
                "file": file, "time": time, "input": input, "output": output,
                "input_quantity": "force", "output_quantity": "displacement",
                "input_unit": "N", "output_unit": "m"
            });
            let case = serde_json::json!({ "name": name, "records": { "forced": [entry] } });
            std::fs::write(folder.join("case.json"), case.to_string()).unwrap();
        }
        let outcome = diagnose_forced(&folder, &ForcedSettings::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let doc = report::document(&outcome);
        let k3 = doc["extended"]["parameters"]["cubic_stiffness_n_m3"]
            .as_f64()
            .unwrap_or(f64::NAN);
        causes.push((name, doc["cause"].clone(), k3));
    }
    let (_, cause, k3) = &causes[0];
    assert_eq!(cause, "cubic_stiffness", "{causes:?}");
    for (name, c, k) in &causes[1..] {
        assert_eq!(c, cause, "{name}: {causes:?}");
        assert!(((k - k3) / k3).abs() < 1e-4, "{name}: {causes:?}");
    }
}
