//! The real `coil-mesh` binary: flags and a JSON spec give the same deck, flags override
//! the spec, and bad input exits non-zero with a message naming what is wrong.

use std::path::Path;
use std::process::Command;

fn coil_mesh(args: &[&str], cwd: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_coil-mesh"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("coil-mesh runs")
}

#[test]
fn flags_and_spec_file_give_the_same_deck() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let flags = [
        "--coils",
        "12",
        "--mean-diameter",
        "24",
        "--wire-diameter",
        "3",
        "--pitch",
        "6.2",
        "--elements-per-coil",
        "16",
        "--youngs-modulus",
        "190708",
        "--mass",
        "5.2",
        "--analysis",
        "static,modal",
        "--modes",
        "5",
    ];
    let mut a: Vec<&str> = flags.to_vec();
    a.extend(["-o", "flags.dat", "--write-spec", "spec.json"]);
    let run = coil_mesh(&a, d);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let run = coil_mesh(&["spec.json", "-o", "spec.dat"], d);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let from_flags = std::fs::read_to_string(d.join("flags.dat")).unwrap();
    let from_spec = std::fs::read_to_string(d.join("spec.dat")).unwrap();
    assert_eq!(from_flags, from_spec);
    let model = coil_solver::deck::read_str(&from_spec, "spec.dat").unwrap();
    assert_eq!(model.elements().len(), 12 * 16);
    assert_eq!(model.load_cases().len(), 2);

    // A flag overrides the file.
    let run = coil_mesh(&["spec.json", "--elements-per-coil", "8", "-o", "o.dat"], d);
    assert!(run.status.success());
    let text = std::fs::read_to_string(d.join("o.dat")).unwrap();
    let model = coil_solver::deck::read_str(&text, "o.dat").unwrap();
    assert_eq!(model.elements().len(), 12 * 8);
}

#[test]
fn bad_input_names_the_problem_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("typo.json"),
        "{\n  \"coils\": 14,\n  \"wire_diam\": 3\n}\n",
    )
    .unwrap();
    std::fs::write(d.join("broken.json"), "{ \"coils\": 14,").unwrap();
    for (args, needle) in [
        (
            vec!["--wire-diameter", "30", "-o", "x.dat"],
            "wire_diameter_mm",
        ),
        (vec!["--coils", "NaN", "-o", "x.dat"], "coils"),
        (vec!["--element", "7", "-o", "x.dat"], "element"),
        (vec!["typo.json", "-o", "x.dat"], "typo.json:3"),
        (vec!["broken.json", "-o", "x.dat"], "broken.json:1"),
        (vec!["missing.json", "-o", "x.dat"], "missing.json"),
    ] {
        let run = coil_mesh(&args, d);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{args:?}");
        assert_ne!(run.status.code(), Some(101), "{args:?} panicked: {stderr}");
        assert!(
            stderr.contains(needle),
            "{args:?}: no '{needle}' in {stderr}"
        );
        assert!(!d.join("x.dat").exists(), "{args:?}: wrote a deck");
    }
}

#[test]
fn format_mentat_writes_the_same_model_in_extended_fixed_format() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let common = [
        "--mass",
        "5.12",
        "--alpha",
        "0.8",
        "--analysis",
        "static,modal",
    ];
    let free = coil_mesh(&[&common[..], &["-o", "free.dat"]].concat(), d);
    let mentat = coil_mesh(
        &[&common[..], &["--format", "mentat", "-o", "mentat.dat"]].concat(),
        d,
    );
    assert!(free.status.success() && mentat.status.success());
    let read = |f: &str| {
        let text = std::fs::read_to_string(d.join(f)).unwrap();
        (coil_solver::deck::read_str(&text, f).unwrap(), text)
    };
    let (a, _) = read("free.dat");
    let (b, text) = read("mentat.dat");
    assert!(text.contains("\nEXTENDED\n"), "no EXTENDED parameter");
    assert_eq!(a, b);
}

/// `coil-mesh catenary`: a 2-span spec gives a deck that reads back with its links,
/// contact and tensions, and the static state; a bad field is named; the spring command
/// still wants its output.
#[test]
fn catenary_writes_a_deck_and_its_static_state() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spec = r#"{
      "catenary": {
        "spans": 2, "span_length_m": 60.0, "system_height_m": 1.2, "presag_mm": 30.0,
        "contact_wire": {"mass_kg_m": 1.35, "tension_n": 20000.0, "ei_n_m2": 195.0},
        "messenger_wire": {"mass_kg_m": 1.07, "tension_n": 16000.0, "ei_n_m2": 131.7},
        "droppers": {"positions_m": [5.0, 17.0, 30.0, 43.0, 55.0], "stiffness_n_m": 100000.0,
                     "contact_clamp_mass_kg": 0.195, "messenger_clamp_mass_kg": 0.165},
        "steady_arm": {"stiffness_n_m": 300.0, "mass_kg": 1.0},
        "messenger_support": {"stiffness_n_m": 50000.0, "mass_kg": 0.0},
        "damping": {"ratio": 0.005, "frequencies_hz": [1.0, 20.0]},
        "element_length_m": 2.0
      },
      "pantograph": {"stages": [{"mass_kg": 7.2, "stiffness_n_m": 4200.0, "damping_n_s_m": 10.0},
                                {"mass_kg": 15.0, "stiffness_n_m": 50.0, "damping_n_s_m": 90.0}],
                     "uplift_force_n": 120.0, "contact_stiffness_n_m": 50000.0},
      "run": {"speed_km_h": 250.0, "time_step_s": 0.002}
    }"#;
    std::fs::write(d.join("spec.json"), spec).unwrap();
    let out = coil_mesh(
        &[
            "catenary",
            "spec.json",
            "-o",
            "cat.dat",
            "--state",
            "state.json",
        ],
        d,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(d.join("cat.dat")).unwrap();
    let model = coil_solver::deck::read_str(&text, "cat.dat").unwrap();
    assert_eq!(model.tension_links().len(), 10);
    assert_eq!(model.moving_contacts().len(), 1);
    let state: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("state.json")).unwrap()).unwrap();
    assert!(state["presag_miss_mm"].as_f64().unwrap() < 1e-3);

    std::fs::write(
        d.join("bad.json"),
        spec.replace("\"spans\": 2", "\"spans\": 0"),
    )
    .unwrap();
    let out = coil_mesh(&["catenary", "bad.json", "-o", "bad.dat"], d);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("catenary.spans"));
    assert!(!d.join("bad.dat").exists());
    let out = coil_mesh(&["--coils", "12"], d);
    assert_eq!(out.status.code(), Some(2));
}
