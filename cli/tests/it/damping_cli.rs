//! `coil-tune damping` through the real binary: a two-mass case whose records decay at the
//! same zeta (a loss factor, written here as closed-form damped cosines with the
//! frequencies `sqrt(K / m_eff)` of the two masses) is named hysteretic in damping.json
//! with the spec's fields; a bad decay entry fails with file, line and field and writes
//! nothing; one record gives law null and the deciding test; records that cannot be tests
//! (listed twice, an impossible mass, growing, noise) are refused.

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

/// Runs `damping` on `decay` and expects exit 1, nothing written, and every `needles` in the
/// message.
fn refused(dir: &Path, decay: &str, needles: &[&str]) {
    case(dir, decay);
    let out = dir.join("out");
    let o = damping(dir, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{decay}: {err}");
    for n in needles {
        assert!(err.contains(n), "{decay}: expected {n:?} in {err}");
    }
    assert!(!out.exists(), "{decay}: an output was written");
}

/// A record listed twice (the same file, or a copy), a mass of 1e-300 kg or null, a
/// growing oscillation and pure noise are refused with the entry and the reason, and
/// nothing is written: pseudo-replication and impossible records never reach damping.json.
#[test]
fn records_that_cannot_be_tests_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    record(&d.join("a.csv"), 5.24);
    record(&d.join("b.csv"), 10.48);
    std::fs::copy(d.join("b.csv"), d.join("b_copy.csv")).unwrap();
    refused(
        d,
        r#"["a.csv", "b.csv", "a.csv"]"#,
        &[
            "records.decay[2] (a.csv)",
            "records.decay[0]",
            "the same file",
        ],
    );
    refused(
        d,
        r#"["a.csv", {"file": "b.csv", "mass_kg": 10.48}, {"file": "b_copy.csv", "mass_kg": 10.48}]"#,
        &[
            "records.decay[2] (b_copy.csv)",
            "records.decay[1]",
            "identical content",
        ],
    );
    refused(
        d,
        r#"["a.csv", {"file": "b.csv", "mass_kg": 1e-300}]"#,
        &["records.decay[1] (b.csv)", "Hz", "mass_kg"],
    );
    refused(
        d,
        r#"["a.csv", {"file": "b.csv", "mass_kg": null}]"#,
        &["case.json:", "records.decay[1].mass_kg", "null"],
    );
    // Growing: the decay reversed in time.
    let text = std::fs::read_to_string(d.join("a.csv")).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    let values: Vec<&str> = rows
        .iter()
        .rev()
        .map(|r| r.split(',').nth(1).unwrap())
        .collect();
    let times: Vec<&str> = rows.iter().map(|r| r.split(',').next().unwrap()).collect();
    let mut grown = String::from("time_s,accel_m_s2\n");
    for (t, v) in times.iter().zip(&values) {
        grown.push_str(&format!("{t},{v}\n"));
    }
    std::fs::write(d.join("grows.csv"), grown).unwrap();
    refused(
        d,
        r#"["a.csv", "grows.csv"]"#,
        &["records.decay[1] (grows.csv)", "grows"],
    );
    // Pure noise: seeded uniform values at 1 kHz.
    let mut state = 12345u64;
    let mut noise = String::from("time_s,accel_m_s2\n");
    for i in 0..8000 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let v = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        noise.push_str(&format!("{},{v}\n", i as f64 * 1e-3));
    }
    std::fs::write(d.join("noise.csv"), noise).unwrap();
    refused(
        d,
        r#"["a.csv", "noise.csv"]"#,
        &["records.decay[1] (noise.csv)", "unexplained"],
    );
}
