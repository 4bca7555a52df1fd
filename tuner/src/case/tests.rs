//! The case, record and variants readers against hand-written files.

use super::*;

const GOOD: &str = r#"{
  "name": "spring 3, rig B",
  "spring": {
"active_coils": 14.0,
"mean_diameter_mm": 24.0,
"wire_diameter_mm": 3.0,
"pitch_mm": 6.2
  },
  "material": {
"youngs_modulus_mpa": 206000.0,
"poisson_ratio": 0.3,
"density_kg_m3": 7850.0
  },
  "mass_kg": 5.3,
  "gravity_m_s2": 9.81,
  "records": { "static": ["static.csv"], "decay": ["decay.csv"] },
  "future_field": {"anything": [1, 2]}
}"#;

fn folder_with(case: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("case.json"), case).unwrap();
    std::fs::write(
        dir.path().join("static.csv"),
        "displacement_mm,force_n\n0,0\n1,3.9\n2,7.9\n",
    )
    .unwrap();
    let mut decay = String::from("time_s,accel_m_s2\n");
    for i in 0..100 {
        let t = i as f64 * 1e-3;
        decay.push_str(&format!("{t},{}\n", (27.3 * t).sin()));
    }
    std::fs::write(dir.path().join("decay.csv"), decay).unwrap();
    dir
}

/// The spec's example, verbatim plus an unknown member, is read from the folder.
#[test]
fn the_spec_example_is_read() {
    let dir = folder_with(GOOD);
    let case = read_case(dir.path()).unwrap();
    assert_eq!(case.name, "spring 3, rig B");
    assert_eq!(case.spring.pitch_mm, 6.2);
    assert_eq!(case.material.poisson_ratio, 0.3);
    assert_eq!(case.mass_kg, 5.3);
    assert_eq!(case.static_files, vec![dir.path().join("static.csv")]);
    assert_eq!(case.targets, Targets::default());
    let statics = case.static_records().unwrap();
    assert_eq!(statics[0].force_n, vec![0.0, 3.9, 7.9]);
    let decays = case.decay_records().unwrap();
    assert_eq!(decays[0].values().len(), 100);
}

/// Each broken field is named with its line and what was expected.
#[test]
fn broken_fields_are_located() {
    for (from, to, field, line) in [
        ("\"mass_kg\": 5.3,", "\"mass_kg\": -5.3,", "mass_kg", 14),
        ("\"mass_kg\": 5.3,", "", "mass_kg", 1),
        (
            "\"pitch_mm\": 6.2",
            "\"pitch_mm\": \"6.2\"",
            "spring.pitch_mm",
            7,
        ),
        (
            "\"wire_diameter_mm\": 3.0",
            "\"wire_diameter_mm\": 30.0",
            "spring.wire_diameter_mm",
            6,
        ),
        (
            "\"poisson_ratio\": 0.3",
            "\"poisson_ratio\": 0.5",
            "material.poisson_ratio",
            11,
        ),
        ("\"decay.csv\"", "\"nope.csv\"", "records.decay[0]", 16),
        ("\"active_coils\": 14.0,", "", "spring.active_coils", 3),
    ] {
        let dir = folder_with(&GOOD.replacen(from, to, 1));
        match read_case(dir.path()) {
            Err(CaseError::Field(e)) => {
                assert_eq!(e.field, field, "{e}");
                assert_eq!(e.line, line, "{e}");
                let shown = e.to_string();
                assert!(
                    shown.contains("case.json:") && shown.contains("expected"),
                    "{shown}"
                );
            }
            other => panic!("{field}: {other:?}"),
        }
    }
}

#[test]
fn syntax_errors_and_missing_files() {
    let dir = folder_with("{\"name\": \"x\",\n \"spring\": }");
    match read_case(dir.path()) {
        Err(CaseError::Syntax { line, .. }) => assert_eq!(line, 2),
        other => panic!("{other:?}"),
    }
    let empty = tempfile::tempdir().unwrap();
    assert!(matches!(read_case(empty.path()), Err(CaseError::Io { .. })));
}

#[test]
fn static_record_errors_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("static.csv");
    for (text, line, needle) in [
        ("displacement_mm,force\n0,1\n", 1, "force_n"),
        ("displacement_mm,force_n\n0,1\n1,NaN\n", 3, "not finite"),
        ("# rig B\ndisplacement_mm,force_n\n0,1\n\n1\n", 5, "fields"),
        ("displacement_mm,force_n\n0,x\n", 2, "not a number"),
        ("displacement_mm,force_n\n0,1\n", 1, "at least 2 rows"),
    ] {
        std::fs::write(&path, text).unwrap();
        match read_static_record(&path) {
            Err(CaseError::StaticRecord {
                line: l, problem, ..
            }) => {
                assert_eq!(l, line, "{text}");
                let all = format!("{problem} {}", read_static_record(&path).unwrap_err());
                assert!(all.contains(needle), "{all}");
            }
            other => panic!("{text}: {other:?}"),
        }
    }
}

/// Decay records: one of the three columns (SI once read), two at once refused
/// with both names and the header line, none refused with the header listed, time
/// stamps that go back refused with their line.
#[test]
fn decay_record_columns() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("decay.csv");
    let rows = |header: &str| {
        let mut s = format!("# rig B\n{header}\n");
        for i in 0..10 {
            s.push_str(&format!("{},{}\n", i as f64 * 0.01, 1.5 + i as f64));
        }
        s
    };
    for (column, quantity, first) in [
        ("accel_m_s2", Quantity::Acceleration, 1.5),
        ("velocity_m_s", Quantity::Velocity, 1.5),
        ("displacement_mm", Quantity::Displacement, 1.5e-3),
    ] {
        std::fs::write(&path, rows(&format!("time_s,{column}"))).unwrap();
        let r = read_decay_record(&path).unwrap();
        assert_eq!(r.quantity, quantity);
        assert_eq!(r.values[0], first);
        assert_eq!(r.lines[0], 3);
    }
    std::fs::write(
        &path,
        rows("time_s,displacement_mm,accel_m_s2").replace(",1", ",1,2"),
    )
    .unwrap();
    let e = read_decay_record(&path).unwrap_err().to_string();
    assert!(
        e.contains("decay.csv:2:") && e.contains("`accel_m_s2` and `displacement_mm`"),
        "{e}"
    );
    std::fs::write(&path, rows("time_s,accel")).unwrap();
    let e = read_decay_record(&path).unwrap_err().to_string();
    assert!(
        e.contains("decay.csv:2:") && e.contains("columns: time_s, accel"),
        "{e}"
    );
    std::fs::write(&path, "time_s,accel_m_s2\n0,1\n0.01,2\n0.005,3\n0.02,1\n").unwrap();
    let e = read_decay_record(&path).unwrap_err().to_string();
    assert!(e.contains("decay.csv:4:") && e.contains("increase"), "{e}");
}

/// The paper's case and Table 4 as shipped under `cases/160ect`.
#[test]
fn the_paper_case_and_table4_are_read() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
    let case = read_case(&root).unwrap();
    assert_eq!(case.targets.stiffness_n_mm, Some(3.9275));
    assert_eq!(case.targets.period_s, Some(0.23));
    assert_eq!(case.tested_springs.len(), 4);
    let mean: f64 = case
        .tested_springs
        .iter()
        .map(|s| s.stiffness_n_mm)
        .sum::<f64>()
        / 4.0;
    assert!(
        (mean - 3.9275).abs() < 1e-12,
        "Table 1's mean is the target"
    );
    let paper = case.paper.unwrap();
    assert_eq!(paper.youngs_modulus_mpa, Some(190708.0));
    assert_eq!(paper.rayleigh_beta, Some(0.00012));
    let table4 = read_variants(&root.join("table4.json")).unwrap();
    assert_eq!(table4.variants.len(), 6);
    assert_eq!(table4.variants[5].spring.active_coils, 16.0);
    assert_eq!(table4.variants[1].paper_damping_ratio, Some(0.00246));
}

#[test]
fn variants_need_unique_names() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("v.json");
    let one = r##"{"name": "#1", "active_coils": 14, "mean_diameter_mm": 28, "wire_diameter_mm": 3, "pitch_mm": 6.2}"##;
    std::fs::write(&path, format!("{{\"variants\": [{one},\n{one}]}}")).unwrap();
    match read_variants(&path) {
        Err(CaseError::Field(e)) => {
            assert_eq!((e.field.as_str(), e.line), ("variants[1].name", 2))
        }
        other => panic!("{other:?}"),
    }
    std::fs::write(&path, format!("{{\"variants\": [{one}]}}")).unwrap();
    let v = read_variants(&path).unwrap();
    assert_eq!(v.variants[0].spring.mean_diameter_mm, 28.0);
    assert_eq!(v.variants[0].paper_stiffness_n_mm, None);
}
