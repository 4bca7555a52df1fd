//! `coil-tune diagnose` on the shared real recordings (a spring with a disk in air,
//! position at 100 Hz, 0.1 mm resolution; `shared/real/README.md`), with the length
//! test: each record is diagnosed whole and cut to its first half, and the named causes
//! are compared.
//!
//! `cargo run --release -p coil-tests --example real_recordings [-- <folder>]`
//!
//! The folder defaults to `$COIL_REAL_DIR`, else `/work/shared/real`; every subfolder
//! with a `case.json` is a case. The recordings carry no licence: they are read where
//! they are and never copied into the repository (the half-length cut is written to a
//! temporary folder that is removed on exit). When the folder is absent the example
//! says so and exits 0.
//!
//! The cases of one rig (the same spring, mass and material in case.json; run2 and run3
//! of the shared rig) are also diagnosed as one case holding all their decay records:
//! the joint fit of one mass and one spring (copied into the temporary folder).
//!
//! Printed per case: the terminal summary, every candidate's tests (held / failed with
//! their numbers), `unexplained` when no cause is named, the half-length verdict and
//! the wall time of each diagnosis (library call, release build).

use coil_ident::diagnose::{self, DiagnoseSettings};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn settings() -> DiagnoseSettings {
    DiagnoseSettings {
        plots: false,
        ..DiagnoseSettings::default()
    }
}

/// Writes `case` with its decay records cut to their first half into `dir`.
fn first_half(case: &Path, dir: &Path) -> Result<PathBuf, String> {
    let text = std::fs::read_to_string(case.join("case.json")).map_err(|e| e.to_string())?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("case.json"), &text).map_err(|e| e.to_string())?;
    for record in json["records"]["decay"].as_array().into_iter().flatten() {
        let Some(file) = record.as_str().or(record["file"].as_str()) else {
            continue;
        };
        let csv = std::fs::read_to_string(case.join(file)).map_err(|e| e.to_string())?;
        let lines: Vec<&str> = csv.lines().collect();
        let keep = 1 + (lines.len() - 1) / 2;
        std::fs::write(dir.join(file), lines[..keep].join("\n") + "\n")
            .map_err(|e| e.to_string())?;
    }
    Ok(dir.to_path_buf())
}

/// Cases of one rig (the same `spring` and `mass_kg` in case.json) written as one case
/// whose decay records are all of theirs, for the joint fit: one
/// folder per rig with two or more cases, under `dir`.
fn joint_cases(cases: &[PathBuf], dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut rigs: Vec<(serde_json::Value, Vec<(PathBuf, serde_json::Value)>)> = Vec::new();
    for case in cases {
        let text = std::fs::read_to_string(case.join("case.json")).map_err(|e| e.to_string())?;
        let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
        let key = serde_json::json!([json["spring"], json["mass_kg"], json["material"]]);
        match rigs.iter_mut().find(|r| r.0 == key) {
            Some(r) => r.1.push((case.clone(), json)),
            None => rigs.push((key, vec![(case.clone(), json)])),
        }
    }
    let mut out = Vec::new();
    for (_, members) in rigs.into_iter().filter(|r| r.1.len() > 1) {
        let names: Vec<String> = members
            .iter()
            .map(|(p, _)| {
                p.file_name()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned()
            })
            .collect();
        let folder = dir.join(format!("joint-{}", names.join("+")));
        std::fs::create_dir_all(&folder).map_err(|e| e.to_string())?;
        let mut json = members[0].1.clone();
        let mut decay = Vec::new();
        for ((path, case), name) in members.iter().zip(&names) {
            for record in case["records"]["decay"].as_array().into_iter().flatten() {
                let Some(file) = record.as_str().or(record["file"].as_str()) else {
                    continue;
                };
                let renamed = format!("{name}-{file}");
                std::fs::copy(path.join(file), folder.join(&renamed)).map_err(|e| e.to_string())?;
                let mut entry = record.clone();
                match entry.as_object_mut() {
                    Some(o) => {
                        o.insert("file".into(), renamed.into());
                    }
                    None => entry = renamed.into(),
                }
                decay.push(entry);
            }
        }
        json["name"] = format!("joint {}", names.join(" + ")).into();
        json["records"]["decay"] = decay.into();
        if let Some(statics) = json["records"]["static"].as_array().cloned() {
            for s in statics.iter().filter_map(|s| s.as_str()) {
                std::fs::copy(members[0].0.join(s), folder.join(s)).map_err(|e| e.to_string())?;
            }
        }
        let text = serde_json::to_string_pretty(&json).map_err(|e| e.to_string())?;
        std::fs::write(folder.join("case.json"), text).map_err(|e| e.to_string())?;
        out.push(folder);
    }
    Ok(out)
}

fn main() {
    let root = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("COIL_REAL_DIR").map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from("/work/shared/real"));
    let Ok(entries) = std::fs::read_dir(&root) else {
        println!("{}: absent; nothing to diagnose", root.display());
        return;
    };
    let mut cases: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("case.json").is_file())
        .collect();
    cases.sort();
    let tmp = tempfile::tempdir().expect("a temporary folder");
    // The recordings of one rig, diagnosed together as well (written to the temporary
    // folder, never into the repository).
    match joint_cases(&cases, tmp.path()) {
        Ok(joint) => cases.extend(joint),
        Err(e) => println!("joint cases not written: {e}"),
    }
    let mut times = Vec::new();
    let mut verdicts = Vec::new();
    for case in &cases {
        let name = case.file_name().unwrap_or_default().to_string_lossy();
        println!("==== {name}");
        let start = Instant::now();
        let full = match diagnose::diagnose(case, &settings()) {
            Ok(o) => o,
            Err(e) => {
                println!("diagnose failed: {e}");
                continue;
            }
        };
        times.push(start.elapsed().as_secs_f64());
        print!("{}", diagnose::summary(&full));
        let d = &full.diagnosis;
        for w in &d.warnings {
            println!("warning: {w}");
        }
        for c in &d.candidates {
            println!("  -- {} (named: {})", c.effect, c.significant);
            for note in &c.bounds {
                println!("     bound: {note}");
            }
            match &c.tests {
                Some(t) => {
                    for (test, v) in t.each() {
                        println!(
                            "     {test}: {} — {}",
                            if v.passed { "held" } else { "FAILED" },
                            v.text
                        );
                    }
                }
                None => println!(
                    "     fit failed: {}",
                    c.fit_error.clone().unwrap_or_default()
                ),
            }
        }
        for c in &d.causes {
            println!(
                "cause {} share {:.2} parameters {:?} se {:?}",
                c.effect, c.share, c.parameters, c.parameters_se
            );
        }
        if let Some(u) = &d.unexplained {
            println!("unexplained: {u}");
        }
        if let Some(m) = &d.remaining_misfit {
            println!("misfit left: {m}");
        }
        let cut = match first_half(case, &tmp.path().join("half").join(name.as_ref())) {
            Ok(p) => p,
            Err(e) => {
                println!("first half not written: {e}");
                continue;
            }
        };
        let start = Instant::now();
        match diagnose::diagnose(&cut, &settings()) {
            Ok(half) => {
                times.push(start.elapsed().as_secs_f64());
                println!(
                    "first half: cause {} (causes {:?}); whole record: {}",
                    half.diagnosis.cause,
                    half.diagnosis
                        .causes
                        .iter()
                        .map(|c| c.effect.clone())
                        .collect::<Vec<_>>(),
                    d.cause
                );
                for c in &half.diagnosis.candidates {
                    println!(
                        "  first half {}: dBIC {:.1}, failed {:?}",
                        c.effect,
                        c.delta_bic.unwrap_or(f64::NAN),
                        c.tests.as_ref().map(|t| t.failed()).unwrap_or_default()
                    );
                }
                verdicts.push((
                    name.to_string(),
                    d.cause.clone(),
                    half.diagnosis.cause.clone(),
                ));
            }
            Err(e) => println!("first half: diagnose failed: {e}"),
        }
    }
    if !times.is_empty() {
        let mut sorted = times.clone();
        sorted.sort_by(f64::total_cmp);
        println!(
            "\nwall time per diagnosis: median {:.2} s, worst {:.2} s over {} runs",
            sorted[sorted.len() / 2],
            sorted[sorted.len() - 1],
            sorted.len()
        );
    }
    for (name, whole, half) in &verdicts {
        println!(
            "length test {name}: whole {whole}, first half {half}: {}",
            if whole == half { "same" } else { "DIFFERENT" }
        );
    }
}
