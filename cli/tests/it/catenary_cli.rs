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
    // Two spans are not the reference model's ten: its ranges are not applied.
    assert!(report.contains("## Statistics against speed"), "{report}");
    assert!(
        report.contains("Not applicable: the model is not EN 50318:2002's reference model"),
        "{report}"
    );
    assert!(
        report.contains("`catenary.spans = 2 (reference 10)`"),
        "{report}"
    );
    assert!(
        !report.contains("| miss |") && !report.contains("statistics with a range pass"),
        "{report}"
    );
    assert!(
        report.contains("## Assessment (EN 50367 / EN 50119 design criteria)"),
        "{report}"
    );
    assert_eq!(v["validation"]["applies"], false);
    assert!(runs[1]["wave_speed_ratio"].as_f64().unwrap() > 0.5);
    assert!(runs[1]["assessment"].as_array().unwrap().len() == 5);
    // The history's named columns.
    let history = std::fs::read_to_string(out.join("history_250.csv")).unwrap();
    let header = history.lines().next().unwrap();
    assert!(
        header.starts_with(
            "time_s,position_m,contact_force_n,contact_force_filtered_n,uplift_60m_mm,stage1_uz_mm"
        ),
        "{header}"
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

/// The head stage from a spring through the real binary: a SPRING.json and a variant of
/// Table 4 as a spring study (one table), and the bad inputs the issue lists: a spring
/// failing its own checks, a variant that does not exist, a speed above the wave speed.
#[test]
fn a_spring_study_and_its_bad_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case");
    std::fs::create_dir(&case).unwrap();
    std::fs::write(case.join("catenary.json"), CATENARY).unwrap();
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let json = serde_json::json!({
        "catenary": "catenary.json",
        "pantograph": {
            "stages": [
                {"mass_kg": 7.2, "stiffness_n_m": 4200.0, "damping_n_s_m": 10.0},
                {"mass_kg": 15.0, "stiffness_n_m": 50.0, "damping_n_s_m": 90.0}
            ],
            "uplift_force_n": 120.0,
            "contact_stiffness_n_m": 50000.0
        },
        "speeds_km_h": [250],
        "time_step_s": 0.002,
        "end_m": 90.0,
        "window": {"start_m": 40.0, "end_m": 80.0}
    });
    std::fs::write(case.join("case.json"), json.to_string()).unwrap();
    let run = |extra: &[&str], out: &str| {
        let mut args = vec![
            "catenary".to_string(),
            case.to_str().unwrap().to_string(),
            "--out".into(),
            dir.path().join(out).to_str().unwrap().to_string(),
            "--no-plots".into(),
            "-q".into(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        Command::new(env!("CARGO_BIN_EXE_coil-tune"))
            .args(&args)
            .output()
            .unwrap()
    };
    let spring = repo.join("cases/spring-design/160ect_spring.json");
    let variant = format!("{}:#2", repo.join("cases/160ect/table4.json").display());
    let ok = run(&["--springs", spring.to_str().unwrap(), &variant], "study");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let report = std::fs::read_to_string(dir.path().join("study/report.md")).unwrap();
    for needle in [
        "| 160ect_spring |",
        "| #2 |",
        "case's head stage",
        "Lowest standard deviation among the springs at 250 km/h",
    ] {
        assert!(report.contains(needle), "{needle}: {report}");
    }
    let study: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("study/study.json")).unwrap(),
    )
    .unwrap();
    let springs = study["springs"].as_array().unwrap();
    assert_eq!(springs.len(), 3);
    // #2: K = 4 k of coil's Table 4 value (7.2530 N/mm), a third of four springs' mass on the head.
    let k = springs[2]["head_stage"]["stiffness_n_m"].as_f64().unwrap();
    assert!((k - 29012.1).abs() < 1.0, "{k}");
    assert!(springs[2]["head_stage"]["mass_share_kg"].as_f64().unwrap() > 0.0);
    // `--speeds` runs other speeds than the case's, checked as the case's are.
    let other = run(&["--springs", &variant, "--speeds", "200"], "speeds");
    assert!(
        other.status.success(),
        "{}",
        String::from_utf8_lossy(&other.stderr)
    );
    let report = std::fs::read_to_string(dir.path().join("speeds/report.md")).unwrap();
    assert!(
        report.contains("Lowest standard deviation among the springs at 200 km/h")
            && !report.contains("at 250 km/h"),
        "{report}"
    );
    for (speeds, needle) in [
        (&["200", "200"][..], "--speeds lists 200 km/h twice"),
        (&["500"][..], "--allow-supercritical"),
    ] {
        let mut args = vec!["--speeds"];
        args.extend(speeds);
        let refused = run(&args, "bad_speeds");
        let message = String::from_utf8_lossy(&refused.stderr).to_string();
        assert!(message.contains(needle), "{needle}: {message}");
        assert!(!dir.path().join("bad_speeds").exists());
    }
    // A SPRING.json that fails its own checks (the 160ECT's second working force pressing
    // it below its minimum length).
    let mut bad: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&spring).unwrap()).unwrap();
    bad["force_2_n"] = serde_json::json!(200.0);
    let bad_path = dir.path().join("bad_spring.json");
    std::fs::write(&bad_path, bad.to_string()).unwrap();
    let refused = run(&["--springs", bad_path.to_str().unwrap()], "bad1");
    let message = String::from_utf8_lossy(&refused.stderr).to_string();
    assert_eq!(refused.status.code(), Some(1), "{message}");
    assert!(
        message.contains("fails its own EN 13906-1 checks"),
        "{message}"
    );
    assert!(!dir.path().join("bad1").exists());
    // A variant that does not exist.
    let missing = format!("{}:#9", repo.join("cases/160ect/table4.json").display());
    let refused = run(&["--springs", &missing], "bad2");
    let message = String::from_utf8_lossy(&refused.stderr).to_string();
    assert!(
        message.contains("no variant named `#9`") && message.contains("#1, #2"),
        "{message}"
    );
    // A speed above the contact wire's wave speed (438 km/h): refused unless allowed.
    let mut fast = json.clone();
    fast["speeds_km_h"] = serde_json::json!([500]);
    std::fs::write(case.join("case.json"), fast.to_string()).unwrap();
    let refused = run(&[], "bad3");
    let message = String::from_utf8_lossy(&refused.stderr).to_string();
    assert!(
        message.contains("wave speed")
            && message.contains("438.2 km/h")
            && message.contains("--allow-supercritical"),
        "{message}"
    );
    // A title with a terminal escape is refused, naming the field.
    let mut escaped = json.clone();
    escaped["title"] = serde_json::json!("x\u{1b}[2Jy");
    std::fs::write(case.join("case.json"), escaped.to_string()).unwrap();
    let refused = run(&[], "bad4");
    let message = String::from_utf8_lossy(&refused.stderr).to_string();
    assert!(
        message.contains("title") && !message.contains('\u{1b}'),
        "{message}"
    );
}
