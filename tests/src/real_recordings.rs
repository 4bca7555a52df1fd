//! `coil-tune diagnose` on the shared real recordings (a spring with a disk in air,
//! position at 100 Hz, 0.1 mm resolution; `shared/real/README.md`), with the length
//! test: each record is diagnosed whole and cut to its first half. The cases of one rig
//! (the same spring, mass and material in case.json: run2 and run3 of the shared rig)
//! are also diagnosed as one case holding all their decay records, the joint fit of one
//! mass and one spring.
//!
//! One piece of code for the example that prints the runs
//! (`cargo run --release -p coil-tests --example real_recordings`) and the ignored test
//! that holds them to docs/diagnose.md's "Real recordings" and the README
//! (`tests/tests/it/shared_data.rs`). The recordings carry no licence: they are read
//! where they are (`../shared/real` beside the repository, or `$COIL_REAL_DIR`) and never
//! copied into the repository; the half-length cuts and the joint case are written to a
//! temporary folder that is removed when the run is dropped.

use coil_ident::diagnose::{self, DiagnoseSettings, Outcome};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The shared recordings: `$COIL_REAL_DIR`, else `../shared/real` beside the repository.
pub fn folder() -> PathBuf {
    std::env::var_os("COIL_REAL_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/real"))
}

fn settings() -> DiagnoseSettings {
    DiagnoseSettings {
        plots: false,
        ..DiagnoseSettings::default()
    }
}

/// One case diagnosed whole and cut to its first half.
pub struct RealRun {
    /// The case folder's name (`joint-A+B` for a rig's joint case).
    pub name: String,
    /// The whole records' diagnosis, or the error's text.
    pub whole: Result<Outcome, String>,
    /// Its wall time (s).
    pub whole_s: f64,
    /// The first halves' diagnosis, or why it was not run; `None` when the whole failed.
    pub half: Option<Result<Outcome, String>>,
    /// Its wall time (s).
    pub half_s: f64,
}

/// Every case under `root` (every subfolder with a `case.json`, sorted), then the joint
/// case of each rig, each diagnosed whole and cut to its first half. An absent or
/// unreadable `root` is an error naming it.
pub fn run_all(root: &Path) -> Result<Vec<RealRun>, String> {
    let entries = std::fs::read_dir(root).map_err(|e| {
        format!(
            "{}: {e} (the shared recordings; set COIL_REAL_DIR)",
            root.display()
        )
    })?;
    let mut cases: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("case.json").is_file())
        .collect();
    cases.sort();
    if cases.is_empty() {
        return Err(format!("{}: no folder with a case.json", root.display()));
    }
    let tmp = tempfile::tempdir().map_err(|e| format!("a temporary folder: {e}"))?;
    cases.extend(joint_cases(&cases, tmp.path())?);
    let mut runs = Vec::new();
    for case in &cases {
        let name = case
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let start = Instant::now();
        let whole = diagnose::diagnose(case, &settings()).map_err(|e| e.to_string());
        let whole_s = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let half = whole.is_ok().then(|| {
            first_half(case, &tmp.path().join("half").join(&name))
                .and_then(|cut| diagnose::diagnose(&cut, &settings()).map_err(|e| e.to_string()))
        });
        let half_s = start.elapsed().as_secs_f64();
        runs.push(RealRun {
            name,
            whole,
            whole_s,
            half,
            half_s,
        });
    }
    Ok(runs)
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
        let keep = 1 + lines.len().saturating_sub(1) / 2;
        std::fs::write(dir.join(file), lines[..keep].join("\n") + "\n")
            .map_err(|e| e.to_string())?;
    }
    Ok(dir.to_path_buf())
}

/// Cases of one rig (the same `spring`, `mass_kg` and `material` in case.json) written
/// as one case whose decay records are all of theirs, for the joint fit: one folder per
/// rig with two or more cases, under `dir`.
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
        out.push(joint_case(&members, dir)?);
    }
    Ok(out)
}

/// One rig's joint case (see [`joint_cases`]).
fn joint_case(members: &[(PathBuf, serde_json::Value)], dir: &Path) -> Result<PathBuf, String> {
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
    Ok(folder)
}

/// The named causes of a diagnosis, largest share first (`none` for none).
pub fn causes(o: &Outcome) -> Vec<String> {
    let d = &o.diagnosis;
    if d.causes.is_empty() {
        vec![d.cause.clone()]
    } else {
        d.causes.iter().map(|c| c.effect.clone()).collect()
    }
}

/// A run as the example prints it: the terminal summary, every candidate's tests
/// (held / failed with their numbers), the causes with their parameters, standard
/// errors and shares, `unexplained` or the misfit left, and the first half's verdict.
pub fn describe(run: &RealRun) -> String {
    let mut s = format!("==== {}\n", run.name);
    let full = match &run.whole {
        Ok(o) => o,
        Err(e) => return s + &format!("diagnose failed: {e}\n"),
    };
    s.push_str(&diagnose::summary(full));
    let d = &full.diagnosis;
    for w in &d.warnings {
        s.push_str(&format!("warning: {w}\n"));
    }
    for c in &d.candidates {
        s.push_str(&format!("  -- {} (named: {})\n", c.effect, c.significant));
        for note in &c.bounds {
            s.push_str(&format!("     bound: {note}\n"));
        }
        match &c.tests {
            Some(t) => {
                for (test, v) in t.each() {
                    let verdict = if v.passed { "held" } else { "FAILED" };
                    s.push_str(&format!("     {test}: {verdict} — {}\n", v.text));
                }
            }
            None => s.push_str(&format!(
                "     fit failed: {}\n",
                c.fit_error.clone().unwrap_or_default()
            )),
        }
    }
    for c in &d.causes {
        s.push_str(&format!(
            "cause {} share {:.2} parameters {:?} se {:?}\n",
            c.effect, c.share, c.parameters, c.parameters_se
        ));
    }
    if let Some(u) = &d.unexplained {
        s.push_str(&format!("unexplained: {u}\n"));
    }
    if let Some(m) = &d.remaining_misfit {
        s.push_str(&format!("misfit left: {m}\n"));
    }
    match &run.half {
        Some(Ok(half)) => {
            s.push_str(&format!(
                "first half: causes {:?}; whole record: {:?}\n",
                causes(half),
                causes(full)
            ));
            for c in &half.diagnosis.candidates {
                s.push_str(&format!(
                    "  first half {}: dBIC {:.1}, failed {:?}\n",
                    c.effect,
                    c.delta_bic.unwrap_or(f64::NAN),
                    c.tests.as_ref().map(|t| t.failed()).unwrap_or_default()
                ));
            }
        }
        Some(Err(e)) => s.push_str(&format!("first half: {e}\n")),
        None => {}
    }
    s
}

/// The wall times and the length test of every run, as the example ends its output.
pub fn length_tests(runs: &[RealRun]) -> String {
    let mut times: Vec<f64> = runs
        .iter()
        .filter(|r| r.whole.is_ok())
        .map(|r| r.whole_s)
        .chain(
            runs.iter()
                .filter(|r| matches!(r.half, Some(Ok(_))))
                .map(|r| r.half_s),
        )
        .collect();
    times.sort_by(f64::total_cmp);
    let mut s = String::new();
    if let Some(worst) = times.last() {
        s.push_str(&format!(
            "\nwall time per diagnosis: median {:.2} s, worst {worst:.2} s over {} runs\n",
            times[times.len() / 2],
            times.len()
        ));
    }
    for r in runs {
        if let (Ok(whole), Some(Ok(half))) = (&r.whole, &r.half) {
            let (w, h) = (causes(whole), causes(half));
            s.push_str(&format!(
                "length test {}: whole {}, first half {}: {}\n",
                r.name,
                w.join(" + "),
                h.join(" + "),
                if w == h { "same" } else { "DIFFERENT" }
            ));
        }
    }
    s
}
