//! One shared real recording diagnosed from four files holding the same numbers: its
//! original CSV, a UFF dataset 58 copy (ASCII, even abscissa, in mm), a MATLAB level 5
//! copy (`time_s` and `displacement_mm` vectors) and a semicolon / decimal-comma copy
//! with units in the header (`Zeit [s];Weg [mm]`). The four `diagnosis.json` contents
//! are compared number by number (all but the run's wall time `runtime_s`) and the
//! largest relative difference is printed.
//!
//! `cargo run --release -p coil-tests --example interchange_real [-- <case-folder>]`
//!
//! The case defaults to `$COIL_REAL_DIR/air-disk-run2`, else
//! `/work/shared/real/air-disk-run2`. The recording carries no licence: the copies are
//! written to a temporary folder removed on exit, never into the repository. When the
//! folder is absent the example says so and exits 0. Exits 1 when a diagnosis differs
//! by more than 1e-6 relative (the UFF copy's time grid `start + i step` may differ from
//! the CSV's printed stamps in the last bit; everything else is the same f64).

use coil_ident::diagnose::{self, DiagnoseSettings};
use coil_io::uff::{uff58_bytes, Uff58};
use std::path::{Path, PathBuf};

fn settings() -> DiagnoseSettings {
    DiagnoseSettings {
        plots: false,
        ..DiagnoseSettings::default()
    }
}

/// A MATLAB level 5 file (uncompressed, little-endian) of named row vectors of doubles.
fn mat_file(vars: &[(&str, &[f64])]) -> Vec<u8> {
    let mut out = vec![b' '; 116];
    let text = b"MATLAB 5.0 MAT-file, written by coil's interchange example";
    out[..text.len()].copy_from_slice(text);
    out.extend_from_slice(&[0; 8]);
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    let element = |kind: u32, data: &[u8]| {
        let mut e = Vec::new();
        e.extend_from_slice(&kind.to_le_bytes());
        e.extend_from_slice(&(data.len() as u32).to_le_bytes());
        e.extend_from_slice(data);
        while e.len() % 8 != 0 {
            e.push(0);
        }
        e
    };
    for (name, values) in vars {
        let mut body = Vec::new();
        let mut flags = 6u32.to_le_bytes().to_vec();
        flags.extend_from_slice(&[0; 4]);
        body.extend(element(6, &flags));
        let mut dims = 1i32.to_le_bytes().to_vec();
        dims.extend_from_slice(&(values.len() as i32).to_le_bytes());
        body.extend(element(5, &dims));
        body.extend(element(1, name.as_bytes()));
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        body.extend(element(9, &data));
        out.extend(element(14, &body));
    }
    out
}

/// Every number of a JSON value with its path.
fn numbers(v: &serde_json::Value, path: String, out: &mut Vec<(String, f64)>) {
    match v {
        serde_json::Value::Number(n) => out.push((path, n.as_f64().unwrap_or(f64::NAN))),
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                numbers(x, format!("{path}[{i}]"), out);
            }
        }
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                numbers(x, format!("{path}.{k}"), out);
            }
        }
        _ => {}
    }
}

fn copies(case: &Path, dir: &Path) -> Result<Vec<(String, PathBuf)>, String> {
    let text = std::fs::read_to_string(case.join("case.json")).map_err(|e| e.to_string())?;
    let mut json: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let file = json["records"]["decay"][0]
        .as_str()
        .ok_or("the case's first decay record is not a plain file name")?
        .to_string();
    let csv = std::fs::read_to_string(case.join(&file)).map_err(|e| e.to_string())?;
    let rows: Vec<(&str, &str)> = csv
        .lines()
        .skip(1)
        .filter_map(|l| l.split_once(','))
        .collect();
    let t: Vec<f64> = rows
        .iter()
        .map(|r| r.0.trim().parse().unwrap_or(f64::NAN))
        .collect();
    let x: Vec<f64> = rows
        .iter()
        .map(|r| r.1.trim().parse().unwrap_or(f64::NAN))
        .collect();
    let mut out = Vec::new();
    let mut write_case = |name: &str, record: serde_json::Value, file: &str, bytes: &[u8]| {
        let folder = dir.join(name);
        std::fs::create_dir_all(&folder).map_err(|e| e.to_string())?;
        std::fs::write(folder.join(file), bytes).map_err(|e| e.to_string())?;
        json["records"]["decay"] = serde_json::json!([record]);
        std::fs::write(folder.join("case.json"), json.to_string()).map_err(|e| e.to_string())?;
        out.push((name.to_string(), folder));
        Ok::<(), String>(())
    };
    write_case(
        "csv",
        serde_json::json!("position.csv"),
        "position.csv",
        csv.as_bytes(),
    )?;
    let uff = Uff58 {
        description: "measured position".into(),
        name: "displacement_mm".into(),
        node: 1,
        direction: 3,
        ordinate_type: 8,
        length_exponent: 1,
        ordinate_label: "displacement".into(),
        ordinate_unit: "mm".into(),
        start_s: t[0],
        step_s: t[1] - t[0],
        values: x.clone(),
    };
    write_case(
        "uff",
        serde_json::json!("position.uff"),
        "position.uff",
        &uff58_bytes(&[uff], false),
    )?;
    write_case(
        "mat",
        serde_json::json!({"file": "position.mat", "channel": "displacement_mm", "time": "time_s"}),
        "position.mat",
        &mat_file(&[("time_s", &t), ("displacement_mm", &x)]),
    )?;
    let european: String =
        std::iter::once("# logger export, semicolons and decimal commas".to_string())
            .chain(std::iter::once("Zeit [s];Weg [mm]".to_string()))
            .chain(
                rows.iter()
                    .map(|(a, b)| format!("{};{}", a.replace('.', ","), b.replace('.', ","))),
            )
            .map(|l| l + "\n")
            .collect();
    write_case(
        "semicolon",
        serde_json::json!("position.csv"),
        "position.csv",
        european.as_bytes(),
    )?;
    Ok(out)
}

fn main() {
    let case = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let root =
                std::env::var("COIL_REAL_DIR").unwrap_or_else(|_| "/work/shared/real".into());
            Path::new(&root).join("air-disk-run2")
        });
    if !case.join("case.json").is_file() {
        println!("{}: no case.json; nothing to compare", case.display());
        return;
    }
    let dir = std::env::temp_dir().join(format!("coil-interchange-{}", std::process::id()));
    let result = run(&case, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    match result {
        Ok(worst) if worst <= 1e-6 => {
            println!("same diagnosis from the four files (largest relative difference {worst:.3e})")
        }
        Ok(worst) => {
            println!("the diagnoses differ: largest relative difference {worst:.3e}");
            std::process::exit(1);
        }
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}

fn run(case: &Path, dir: &Path) -> Result<f64, String> {
    let mut reference: Option<Vec<(String, f64)>> = None;
    let mut worst = 0.0_f64;
    for (name, folder) in copies(case, dir)? {
        let outcome =
            diagnose::diagnose(&folder, &settings()).map_err(|e| format!("{name}: {e}"))?;
        let json = serde_json::to_value(&outcome.diagnosis).map_err(|e| e.to_string())?;
        let mut found = Vec::new();
        numbers(&json, String::new(), &mut found);
        // The wall time of the run is the only figure that is not the data's.
        found.retain(|(key, _)| !key.contains("runtime"));
        let cause = json["cause"].as_str().unwrap_or("?").to_string();
        for w in &outcome.diagnosis.warnings {
            if w.contains("read as") {
                println!("  {w}");
            }
        }
        match &reference {
            None => {
                println!("{name:>10}: cause {cause}, {} numbers", found.len());
                reference = Some(found);
            }
            Some(r) => {
                if r.len() != found.len() || r.iter().zip(&found).any(|(a, b)| a.0 != b.0) {
                    return Err(format!(
                        "{name}: diagnosis.json has other keys than the CSV's"
                    ));
                }
                let mut local = 0.0_f64;
                let mut at = String::new();
                for ((key, a), (_, b)) in r.iter().zip(&found) {
                    let d = (a - b).abs() / a.abs().max(b.abs()).max(1e-300);
                    if d > local {
                        local = d;
                        at = key.clone();
                    }
                }
                println!("{name:>10}: cause {cause}, largest relative difference {local:.3e} {at}");
                worst = worst.max(local);
            }
        }
    }
    Ok(worst)
}
