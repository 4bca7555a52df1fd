//! `coil-tune damping` through the real binary: a two-mass case whose records decay at the
//! same zeta (a loss factor, written here as closed-form damped cosines with the
//! frequencies `sqrt(K / m_eff)` of the two masses) is named hysteretic in damping.json
//! with the spec's fields; a bad decay entry fails with file, line and field and writes
//! nothing; one record gives law null and the deciding test.

use std::path::Path;
use std::process::{Command, Output};

fn coil_tune(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_coil-tune"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn damping(case: &Path, out: &Path) -> Output {
    coil_tune(&[
        "damping",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

const ZETA: f64 = 0.00175;

fn record(path: &Path, mass_kg: f64) {
    // K of the paper's spring (N/m) and a third of its 0.0586 kg wire.
    let w = (3927.5 / (mass_kg + 0.0586 / 3.0)).sqrt();
    let wd = w * (1.0 - ZETA * ZETA).sqrt();
    let mut s = String::from("time_s,accel_m_s2\n");
    for i in 0..8000 {
        let t = i as f64 * 1e-3;
        s.push_str(&format!("{t},{}\n", (-ZETA * w * t).exp() * (wd * t).cos()));
    }
    std::fs::write(path, s).unwrap();
}

fn case(dir: &Path, decay: &str) {
    std::fs::write(
        dir.join("case.json"),
        format!(
            r#"{{
  "name": "two masses",
  "spring": {{"active_coils": 14.0, "mean_diameter_mm": 24.0, "wire_diameter_mm": 3.0, "pitch_mm": 6.2}},
  "material": {{"youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0}},
  "mass_kg": 5.24,
  "gravity_m_s2": 0.0,
  "records": {{"decay": {decay}}}
}}
"#
        ),
    )
    .unwrap();
}

#[test]
fn two_masses_with_one_zeta_are_hysteretic() {
    let dir = tempfile::tempdir().unwrap();
    record(&dir.path().join("a.csv"), 5.24);
    record(&dir.path().join("b.csv"), 10.48);
    case(
        dir.path(),
        r#"["a.csv", {"file": "b.csv", "mass_kg": 10.48, "location": "weight"}]"#,
    );
    let out = dir.path().join("out");
    let o = damping(dir.path(), &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("damping.json")).unwrap()).unwrap();
    assert_eq!(json["law"], "hysteretic");
    assert_eq!(json["identifiable"], true);
    let eta = json["parameters"]["loss_factor"].as_f64().unwrap();
    assert!((eta / (2.0 * ZETA) - 1.0).abs() < 1e-3, "{eta}");
    assert!(json["parameters_se"]["loss_factor"].as_f64().unwrap() > 0.0);
    let laws: Vec<&str> = json["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["law"].as_str().unwrap())
        .collect();
    assert_eq!(laws, ["rayleigh", "hysteretic", "external_viscous"]);
    assert!(json["candidates"][0]["residual_rms"].as_f64().unwrap() > 0.05);
    assert!(out.join("report.md").is_file());
}

#[test]
fn one_record_is_not_identifiable_and_names_the_deciding_test() {
    let dir = tempfile::tempdir().unwrap();
    record(&dir.path().join("a.csv"), 5.24);
    case(dir.path(), r#"["a.csv"]"#);
    let out = dir.path().join("out");
    let o = damping(dir.path(), &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("damping.json")).unwrap()).unwrap();
    assert!(json["law"].is_null());
    assert_eq!(json["identifiable"], false);
    let test = &json["deciding_test"];
    assert!(test["text"].as_str().unwrap().contains("surge"));
    let beta = test["surge_zeta"]["rayleigh_beta_only"].as_f64().unwrap();
    assert!((0.045..0.06).contains(&beta), "{beta}");
}

#[test]
fn a_bad_decay_entry_is_located_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    record(&dir.path().join("a.csv"), 5.24);
    case(dir.path(), r#"[{"file": "a.csv", "mode": "sideways"}]"#);
    let out = dir.path().join("out");
    let o = damping(dir.path(), &out);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("case.json:7:") && err.contains("records.decay[0].mode"),
        "{err}"
    );
    assert!(err.contains("\"axial\" or \"surge\""), "{err}");
    assert!(!out.exists());
    case(dir.path(), r#"[{"mass_kg": 3.0}]"#);
    let o = damping(dir.path(), &out);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("records.decay[0]") && err.contains("file"),
        "{err}"
    );
    assert!(!out.exists());
}
