//! `coil-tune catenary` through the real binary on a small case (two 60 m spans of the
//! EN 50318 reference wires, 1 m elements, 2 ms steps): the output set, the contract's
//! keys of catenary.json, the report's table, and a case field it does not know.

use std::process::Command;

const CATENARY: &str = r#"{
  "spans": 2, "span_length_m": 60.0, "system_height_m": 1.2, "presag_mm": 0.0,
  "contact_wire": {"mass_kg_m": 1.35, "tension_n": 20000.0, "ei_n_m2": 195.0},
  "messenger_wire": {"mass_kg_m": 1.07, "tension_n": 16000.0, "ei_n_m2": 131.7},
  "droppers": {"positions_m": [5.0, 10.5, 17.0, 23.5, 30.0, 36.5, 43.0, 49.5, 55.0],
               "stiffness_n_m": 100000.0, "contact_clamp_mass_kg": 0.195,
               "messenger_clamp_mass_kg": 0.165},
  "steady_arm": {"stiffness_n_m": 300.0, "mass_kg": 1.0},
  "messenger_support": {"stiffness_n_m": 50000.0, "mass_kg": 0.0},
  "damping": {"ratio": 0.005, "frequencies_hz": [1.0, 20.0]},
  "element_length_m": 1.0
}"#;

#[test]
fn the_command_writes_catenary_json_with_the_contract_keys() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case");
    std::fs::create_dir(&case).unwrap();
    std::fs::write(case.join("catenary.json"), CATENARY).unwrap();
    let pantograph = serde_json::json!({
        "stages": [
            {"mass_kg": 7.2, "stiffness_n_m": 4200.0, "damping_n_s_m": 10.0},
            {"mass_kg": 15.0, "stiffness_n_m": 50.0, "damping_n_s_m": 90.0}
        ],
        "uplift_force_n": 120.0,
        "contact_stiffness_n_m": 50000.0
    });
    let json = serde_json::json!({
        "catenary": "catenary.json",
        "pantograph": pantograph,
        "speeds_km_h": [200, 250],
        "time_step_s": 0.002,
        "window": {"start_m": 30.0, "end_m": 90.0},
        "reference": {"250": {"mean_n": [100, 130], "loss_percent": [0, 0]}}
    });
    std::fs::write(case.join("case.json"), json.to_string()).unwrap();
    let out = dir.path().join("out");
    let status = Command::new(env!("CARGO_BIN_EXE_coil-tune"))
        .args([
            "catenary",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--no-plots",
            "-q",
        ])
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let text = std::fs::read_to_string(out.join("catenary.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    for key in [
        "speed_km_h",
        "mean_n",
        "std_n",
        "stat_max_n",
        "stat_min_n",
        "max_n",
        "min_n",
        "uplift_support_mm",
        "loss_percent",
    ] {
        assert!(runs[1][key].is_number(), "{key}");
    }
    assert_eq!(runs[1]["speed_km_h"].as_f64().unwrap(), 250.0);
    assert!(v["window"]["start_m"].is_number() && v["filter"]["cutoff_hz"].is_number());
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("| mean contact force (N) | `mean_n` |"),
        "{report}"
    );
    // A field the case does not know is refused, naming it.
    std::fs::write(case.join("case.json"), r#"{"speed": 1}"#).unwrap();
    let bad = Command::new(env!("CARGO_BIN_EXE_coil-tune"))
        .args([
            "catenary",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("speed"));
}
