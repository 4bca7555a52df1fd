//! `coil-tune diagnose` on forced records, `simulate` and `frc` through the real binary: a
//! generated hardening oscillator (closed-form free of any coil code: a linear recurrence
//! would not show the cubic, so the record is written by a small RK4 here) is diagnosed
//! with its files; `simulate` reads only the first --init outputs and writes one row per
//! input sample; `frc` writes its curve and backbone; and every bad input named by the
//! forced-record contract fails with the file, line or field and writes nothing.

use std::path::Path;
use std::process::{Command, Output};

fn coil_tune(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_coil-tune"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// `coil-tune diagnose CASE --out OUT --quiet --no-plots`, which must succeed.
fn diagnose_ok(case: &Path, out: &Path) {
    let o = coil_tune(&[
        "diagnose",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--no-plots",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `OUT/NAME` read as JSON.
fn read_json(out: &Path, name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join(name)).unwrap()).unwrap()
}

/// z'' + 2 zeta w z' + w^2 z + kappa z^3 = u / m, RK4 at 20 steps per sample, u a sum of
/// sines around the 5 Hz resonance; `(time, u, y)` at 100 Hz.
fn generate(n: usize) -> Vec<(f64, f64, f64)> {
    let (w, zeta, kappa, m) = (std::f64::consts::TAU * 5.0, 0.02, 4e5, 2.0);
    let u = |t: f64| {
        (1..=30)
            .map(|k| {
                let f = 3.0 + 0.17 * k as f64;
                0.4 * (std::f64::consts::TAU * f * t + k as f64 * k as f64).sin()
            })
            .sum::<f64>()
    };
    let acc =
        |z: f64, v: f64, t: f64| u(t) / m - 2.0 * zeta * w * v - w * w * z - kappa * z.powi(3);
    let (mut z, mut v) = (0.0f64, 0.0f64);
    let dt = 0.01;
    let h = dt / 20.0;
    let mut out = Vec::new();
    for i in 0..n {
        let t0 = i as f64 * dt;
        out.push((t0, u(t0), z));
        for s in 0..20 {
            let t = t0 + s as f64 * h;
            let a1 = acc(z, v, t);
            let (z2, v2) = (z + 0.5 * h * v, v + 0.5 * h * a1);
            let a2 = acc(z2, v2, t + 0.5 * h);
            let (z3, v3) = (z + 0.5 * h * v2, v + 0.5 * h * a2);
            let a3 = acc(z3, v3, t + 0.5 * h);
            let (z4, v4) = (z + h * v3, v + h * a3);
            let a4 = acc(z4, v4, t + h);
            z += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
            v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
        }
    }
    out
}

fn write_record(path: &Path, rows: &[(f64, f64, f64)]) {
    let mut s = String::from("time_s,force_n,displacement_m\n");
    for (t, u, y) in rows {
        s.push_str(&format!("{t:.4},{u:.9e},{y:.9e}\n"));
    }
    std::fs::write(path, s).unwrap();
}

fn write_case(dir: &Path, entry: &str) {
    std::fs::write(
        dir.join("case.json"),
        format!("{{\"name\": \"shaker\", \"records\": {{\"forced\": [{entry}]}}}}\n"),
    )
    .unwrap();
}

const ENTRY: &str = r#"{"file": "run.csv", "time": "time_s", "input": "force_n", "output": "displacement_m",
  "input_quantity": "force", "output_quantity": "displacement", "input_unit": "N", "output_unit": "m"}"#;

#[test]
fn diagnose_simulate_and_frc_on_a_forced_case() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case");
    std::fs::create_dir(&case).unwrap();
    let rows = generate(3000);
    write_record(&case.join("run.csv"), &rows);
    write_case(&case, ENTRY);
    let out = dir.path().join("out");
    diagnose_ok(&case, &out);
    let doc = read_json(&out, "diagnosis.json");
    assert_eq!(doc["cause"], "cubic_stiffness", "{doc:#}");
    let k3 = doc["extended"]["parameters"]["cubic_stiffness_n_m3"]
        .as_f64()
        .unwrap();
    // kappa m = 8e5 N/m^3, from noise-free data.
    assert!((k3 / 8e5 - 1.0).abs() < 0.02, "{k3}");
    assert!(
        doc["forced_records"][0]["rms_simulation_error"]
            .as_f64()
            .unwrap()
            >= 0.0
    );
    for f in ["report.md", "model.json", "model_linear.json"] {
        assert!(out.join(f).is_file(), "{f}");
    }

    // simulate: only the first 40 outputs are given; the rest of the column is empty.
    let mut s = String::from("time_s,force_n,displacement_m\n");
    for (i, (t, u, y)) in rows.iter().enumerate() {
        if i < 40 {
            s.push_str(&format!("{t:.4},{u:.9e},{y:.9e}\n"));
        } else {
            s.push_str(&format!("{t:.4},{u:.9e},\n"));
        }
    }
    let record = dir.path().join("drive.csv");
    std::fs::write(&record, s).unwrap();
    let sim = dir.path().join("sim");
    let model = out.join("model.json");
    let o = coil_tune(&[
        "simulate",
        model.to_str().unwrap(),
        "--record",
        record.to_str().unwrap(),
        "--time",
        "time_s",
        "--input",
        "force_n",
        "--output",
        "displacement_m",
        "--init",
        "40",
        "--out",
        sim.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(sim.join("simulated.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("time_s,output"));
    let values: Vec<f64> = lines
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(values.len(), rows.len());
    let err = values
        .iter()
        .zip(&rows)
        .map(|(a, r)| (a - r.2).powi(2))
        .sum::<f64>()
        .sqrt();
    let norm = rows.iter().map(|r| r.2 * r.2).sum::<f64>().sqrt();
    assert!(err < 0.02 * norm, "{err} of {norm}");

    let frc = dir.path().join("frc");
    let o = coil_tune(&[
        "frc",
        model.to_str().unwrap(),
        "--amplitude",
        "1",
        "--from",
        "3",
        "--to",
        "8",
        "--out",
        frc.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(frc.join("frc.csv")).unwrap();
    assert!(text.starts_with("frequency_hz,amplitude,stable\n"));
    assert!(text.lines().count() > 100);
    assert!(frc.join("backbone.csv").is_file());
}

fn fails(args: &[&str], out: &Path, words: &[&str]) {
    let o = coil_tune(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    for w in words {
        assert!(err.contains(w), "{args:?}: `{w}` not in: {err}");
    }
    assert!(!out.exists(), "{args:?} wrote {}", out.display());
}

#[test]
fn bad_forced_input_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let rows = generate(200);
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    // A model to drive.
    let model = dir.path().join("model.json");
    std::fs::write(
        &model,
        r#"{"kind": "lumped_oscillator", "input_quantity": "force", "output_quantity": "displacement",
  "input_unit": "N", "output_unit": "m", "mass": 2.0,
  "oscillator": {"natural_frequency_rad_s": 31.4, "damping_ratio": 0.02, "input_gain": 0.5,
    "cubic": 0.0, "friction": 0.0, "drag": 0.0, "friction_velocity": 1.0, "output_offset": 0.0}}"#,
    )
    .unwrap();
    let model_s = model.to_str().unwrap();
    let record = dir.path().join("run.csv");
    write_record(&record, &rows);
    let record_s = record.to_str().unwrap();
    let simulate = |input: &str, init: &str, file: &str| {
        vec![
            "simulate".to_string(),
            model_s.to_string(),
            "--record".into(),
            file.to_string(),
            "--input".into(),
            input.to_string(),
            "--output".into(),
            "displacement_m".into(),
            "--init".into(),
            init.to_string(),
            "--out".into(),
            out_s.to_string(),
        ]
    };
    let run = |v: Vec<String>, words: &[&str]| {
        let args: Vec<&str> = v.iter().map(String::as_str).collect();
        fails(&args, &out, words);
    };
    // An input column that does not exist.
    run(
        simulate("thrust_n", "20", record_s),
        &["run.csv", "thrust_n"],
    );
    // --init longer than the record.
    run(
        simulate("force_n", "500", record_s),
        &["run.csv", "--init", "200 rows"],
    );
    // NaN in the input.
    let nan = dir.path().join("nan.csv");
    let mut text = std::fs::read_to_string(&record).unwrap();
    text = text.replacen(&format!("{:.9e}", rows[7].1), "NaN", 1);
    std::fs::write(&nan, text).unwrap();
    run(
        simulate("force_n", "20", nan.to_str().unwrap()),
        &["nan.csv:9", "force_n"],
    );

    // Diagnose: records of different lengths (the output stops early).
    let case = dir.path().join("case");
    std::fs::create_dir(&case).unwrap();
    let mut s = String::from("time_s,force_n,displacement_m\n");
    for (i, (t, u, y)) in rows.iter().enumerate() {
        if i < 150 {
            s.push_str(&format!("{t:.4},{u:.9e},{y:.9e}\n"));
        } else {
            s.push_str(&format!("{t:.4},{u:.9e},\n"));
        }
    }
    std::fs::write(case.join("run.csv"), s).unwrap();
    write_case(&case, ENTRY);
    let case_s = case.to_str().unwrap();
    fails(
        &["diagnose", case_s, "--out", out_s],
        &out,
        &["run.csv:152", "shorter", "same length"],
    );
    // A forced case with no input.
    write_record(&case.join("run.csv"), &rows);
    write_case(&case, &ENTRY.replace(r#""input": "force_n", "#, ""));
    fails(
        &["diagnose", case_s, "--out", out_s],
        &out,
        &["case.json", "records.forced[0].input"],
    );
    // A model file that is not one.
    std::fs::write(&model, "{\"kind\": \"beam\"}").unwrap();
    run(simulate("force_n", "20", record_s), &["model.json"]);
}

const SPRING: &str = r#""spring": {"active_coils": 9.0, "mean_diameter_mm": 18.0, "wire_diameter_mm": 2.2, "pitch_mm": 4.6},
  "material": {"youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0},
  "mass_kg": 2.0, "gravity_m_s2": 0.0"#;

fn write_spring_case(dir: &Path, entry: &str) {
    std::fs::write(
        dir.join("case.json"),
        format!(
            "{{\"name\": \"spring on a shaker\", {SPRING}, \"records\": {{\"forced\": [{entry}]}}}}\n"
        ),
    )
    .unwrap();
}

/// The forced-record errors hold for a case with a spring too (its records are read and
/// checked before the spring is meshed), and its records must be in SI units; `simulate`
/// refuses `--init` longer than the record on a spring model (`kind: reduced_spring`).
#[test]
fn bad_forced_input_on_a_spring_case_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let rows = generate(200);
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    let case = dir.path().join("case");
    std::fs::create_dir(&case).unwrap();
    let case_s = case.to_str().unwrap();
    let diagnose = ["diagnose", case_s, "--out", out_s];
    write_record(&case.join("run.csv"), &rows);
    // An input column that does not exist.
    write_spring_case(&case, &ENTRY.replace("\"force_n\"", "\"thrust_n\""));
    fails(&diagnose, &out, &["run.csv", "thrust_n"]);
    // A forced case with no input.
    write_spring_case(&case, &ENTRY.replace(r#""input": "force_n", "#, ""));
    fails(&diagnose, &out, &["case.json", "records.forced[0].input"]);
    // Units that are not SI.
    write_spring_case(
        &case,
        &ENTRY.replace(r#""output_unit": "m""#, r#""output_unit": "mm""#),
    );
    fails(
        &diagnose,
        &out,
        &["run.csv", "\"mm\"", "SI units", "\"m/s^2\""],
    );
    write_spring_case(
        &case,
        &ENTRY.replace(r#""input_unit": "N""#, r#""input_unit": "V""#),
    );
    fails(&diagnose, &out, &["run.csv", "\"V\"", "SI units"]);
    // NaN in the input.
    write_spring_case(&case, ENTRY);
    let mut text = std::fs::read_to_string(case.join("run.csv")).unwrap();
    text = text.replacen(&format!("{:.9e}", rows[7].1), "NaN", 1);
    std::fs::write(case.join("run.csv"), text).unwrap();
    fails(&diagnose, &out, &["run.csv:9", "force_n"]);
    // Records of different lengths (the output stops early).
    let mut s = String::from("time_s,force_n,displacement_m\n");
    for (i, (t, u, y)) in rows.iter().enumerate() {
        if i < 150 {
            s.push_str(&format!("{t:.4},{u:.9e},{y:.9e}\n"));
        } else {
            s.push_str(&format!("{t:.4},{u:.9e},\n"));
        }
    }
    std::fs::write(case.join("run.csv"), s).unwrap();
    fails(&diagnose, &out, &["run.csv:152", "shorter", "same length"]);

    // A spring model: --init longer than the record, and a lumped kind with modes.
    let model = dir.path().join("model.json");
    let spring_model = r#"{"kind": "reduced_spring", "input_quantity": "force", "output_quantity": "displacement",
  "input_unit": "N", "output_unit": "m", "mass": 2.0,
  "oscillator": {"natural_frequency_rad_s": 31.4, "damping_ratio": 0.02, "input_gain": 0.5,
    "cubic": 0.0, "friction": 0.0, "drag": 0.0, "friction_velocity": 1.0, "output_offset": 0.0,
    "modes": [{"natural_frequency_rad_s": 1600.0, "damping_ratio": 0.16, "input_gain": 0.007, "law_gain": 0.014}]}}"#;
    std::fs::write(&model, spring_model).unwrap();
    write_record(&dir.path().join("run.csv"), &rows);
    let record = dir.path().join("run.csv");
    let simulate = |init: &str| {
        let args = [
            "simulate",
            model.to_str().unwrap(),
            "--record",
            record.to_str().unwrap(),
            "--input",
            "force_n",
            "--output",
            "displacement_m",
            "--init",
            init,
            "--out",
            out_s,
        ];
        args.map(String::from)
    };
    let a = simulate("500");
    let args: Vec<&str> = a.iter().map(String::as_str).collect();
    fails(&args, &out, &["run.csv", "--init", "200 rows"]);
    std::fs::write(
        &model,
        spring_model.replace("reduced_spring", "lumped_oscillator"),
    )
    .unwrap();
    let a = simulate("20");
    let args: Vec<&str> = a.iter().map(String::as_str).collect();
    fails(&args, &out, &["model.json", "modes"]);
    // The spring model runs.
    std::fs::write(&model, spring_model).unwrap();
    let o = coil_tune(
        &simulate("20")
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("simulated.csv")).unwrap();
    assert_eq!(text.lines().count(), rows.len() + 1);
}

/// docs/forced.md's worked spring example, `cases/forced/spring`, through the binary: the
/// cause `cubic_stiffness`, k3 2.9994e7 N/m^3 (truth 3e7), the extended model's Young's
/// modulus 200,002 MPa (truth 200,000) and beta 2.0003e-4 s (truth 2e-4), each to half a
/// unit of its printed last digit. About 9 s of CPU: the second stage of `.ci/run`.
#[test]
#[ignore = "second CI stage"]
fn claim_the_spring_example_gives_the_docs_figures() {
    let dir = tempfile::tempdir().unwrap();
    let case = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/forced/spring");
    let out = dir.path().join("out");
    diagnose_ok(&case, &out);
    let doc = read_json(&out, "diagnosis.json");
    assert_eq!(doc["cause"], "cubic_stiffness", "{doc:#}");
    let model = read_json(&out, "model.json");
    for (what, got, printed, unit) in [
        (
            "k3 (N/m^3)",
            doc["extended"]["parameters"]["cubic_stiffness_n_m3"].as_f64(),
            2.9994e7,
            1e3,
        ),
        (
            "E (MPa)",
            model["spring"]["youngs_modulus_mpa"].as_f64(),
            200_002.0,
            1.0,
        ),
        (
            "beta (s)",
            model["spring"]["rayleigh_beta_s"].as_f64(),
            2.0003e-4,
            1e-8,
        ),
    ] {
        let got = got.unwrap_or_else(|| panic!("{what} missing"));
        assert!(
            (got - printed).abs() <= 0.5 * unit * (1.0 + 1e-9),
            "{what}: {got}, docs/forced.md prints {printed}"
        );
    }
}
