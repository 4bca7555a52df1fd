//! A spring study from the command line (`coil-tune catenary CASE --springs A.json B.json
//! ...`): the same case with each spring's head stage (`crate::head_stage::from_spring`),
//! every spring at every speed (in parallel), beside the case's own head stage, in one
//! table, so that "which spring gives the lowest sigma at 300 km/h" is one command.
//!
//! Output: `study.json` (per spring the stage built and per speed the statistics, the
//! assessment and the whole run's losses), `report.md` (the table per speed with the
//! assessment's verdict and the lowest standard deviation named) and, with figures,
//! `spring_study.png` (standard deviation, minimum and loss per spring and speed).

pub mod band;

use crate::case::Case;
use crate::en50318::{self, study::SpringStudyRow};
use crate::head_stage::from_spring::BuiltHead;
use crate::output::{run_summary, tag, RunSummary};
use crate::run::{run_speed_with, SpeedRun};
use crate::{assess, Result, TuneError};
use coil_tuner::output::OutDir;
use rayon::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;

/// The name of the case's own head stage in the study.
pub const CASE_HEAD: &str = "case's head stage";

/// One spring's runs.
#[derive(Debug, Clone)]
pub struct StudyEntry {
    /// The head stage built (`None`: the case's own).
    pub head: Option<BuiltHead>,
    /// One run per speed, in the case's order.
    pub runs: Vec<SpeedRun>,
}

impl StudyEntry {
    /// The spring's name.
    pub fn name(&self) -> &str {
        self.head.as_ref().map_or(CASE_HEAD, |h| h.name.as_str())
    }
}

/// The study.
#[derive(Debug, Clone)]
pub struct Study {
    /// The case.
    pub case: Case,
    /// The case's own head stage first, then each spring.
    pub entries: Vec<StudyEntry>,
}

/// Runs the case with its own head stage and with each of `heads`, at every speed.
pub fn run_study(case: &Case, heads: &[BuiltHead], progress: bool) -> Result<Study> {
    let stages: Vec<Option<&BuiltHead>> = std::iter::once(None)
        .chain(heads.iter().map(Some))
        .collect();
    let jobs: Vec<(usize, f64)> = (0..stages.len())
        .flat_map(|i| case.speeds_km_h.iter().map(move |&v| (i, v)))
        .collect();
    let runs: Vec<(usize, SpeedRun)> = jobs
        .par_iter()
        .map(|&(i, v)| {
            let pantograph = match stages[i] {
                Some(h) => crate::head_stage::from_spring::with_head(&case.pantograph, h),
                None => case.pantograph.clone(),
            };
            run_speed_with(case, &pantograph, v, progress).map(|(_, run)| (i, run))
        })
        .collect::<Result<_>>()?;
    let mut entries: Vec<StudyEntry> = stages
        .iter()
        .map(|h| StudyEntry {
            head: h.cloned(),
            runs: Vec::new(),
        })
        .collect();
    for (i, run) in runs {
        entries[i].runs.push(run);
    }
    Ok(Study {
        case: case.clone(),
        entries,
    })
}

#[derive(Serialize)]
struct EntryJson<'a> {
    spring: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    head_stage: Option<&'a BuiltHead>,
    runs: Vec<RunSummary<'a>>,
}

#[derive(Serialize)]
struct StudyJson<'a> {
    case: &'a str,
    springs: Vec<EntryJson<'a>>,
}

/// The study's table per speed (markdown) with the lowest standard deviation named.
pub fn markdown(study: &Study) -> String {
    let mut s = String::new();
    let case = &study.case;
    let _ = writeln!(
        s,
        "# Spring study: {}\n\nThe case's catenary and pantograph, the head stage (stage 1) \
         built from each spring (docs/catenary.md, \"The head stage from a spring\"), beside \
         the case's own head stage; statistics over {} to {} m after the {} Hz low-pass; \
         assessment against EN 50367 / EN 50119 (values not read from the standards, see \
         catenary.json's sources).\n",
        case.title,
        case.settings.window.start_m,
        case.settings.window.end_m,
        case.settings.cutoff_hz
    );
    s.push_str("## Head stages\n\n| spring | source | k (N/mm) | n | K (N/m) | stage mass (kg) | c (N s/m) | zeta | stage |\n|---|---|---:|---:|---:|---:|---:|---:|---|\n");
    let head0 = &case.pantograph.stages[0];
    let _ = writeln!(
        s,
        "| {CASE_HEAD} | the case | - | - | {:.1} | {:.4} | {:.3} | {:.5} | lumped |",
        head0.stiffness_n_m,
        head0.mass_kg,
        head0.damping_n_s_m,
        head0.damping_n_s_m / (2.0 * (head0.stiffness_n_m * head0.mass_kg).sqrt())
    );
    for h in study.entries.iter().filter_map(|e| e.head.as_ref()) {
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} | {} | {:.1} | {:.4} | {:.3} | {:.5} | {} |",
            h.name,
            h.source,
            h.spring_rate_n_mm,
            h.springs_in_parallel,
            h.stiffness_n_m,
            h.stage_mass_kg,
            h.damping_n_s_m,
            h.zeta,
            h.reduced_modes
                .map_or("lumped".to_string(), |m| format!("reduced, {m} modes"))
        );
    }
    for (k, &v) in case.speeds_km_h.iter().enumerate() {
        let _ = writeln!(
            s,
            "\n## {}\n\n| spring | mean (N) | std (N) | max (N) | min (N) | mean - 3 std (N) | uplift (mm) | loss (%) | losses, whole run | assessment |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
            en50318::speed_label(v)
        );
        let mut best: Option<(f64, &str)> = None;
        for e in &study.entries {
            let Some(run) = e.runs.get(k) else { continue };
            let st = &run.statistics;
            let _ = writeln!(
                s,
                "| {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {} | {} |",
                e.name(),
                st.mean_n,
                st.std_n,
                st.max_n,
                st.min_n,
                st.stat_min_n,
                st.uplift_support_mm,
                st.loss_percent,
                run.whole.loss_intervals,
                assess::summary(&run.assessment)
            );
            if e.head.is_some() && best.is_none_or(|(b, _)| st.std_n < b) {
                best = Some((st.std_n, e.name()));
            }
        }
        if let Some((std, name)) = best {
            let _ = writeln!(
                s,
                "\nLowest standard deviation among the springs at {}: `{name}`, {std:.2} N.",
                en50318::speed_label(v)
            );
        }
    }
    s
}

/// Writes `study.json`, `report.md` and (with `plots`) `spring_study.png`.
pub fn write(study: &Study, out: &OutDir, plots: bool) -> Result<()> {
    let json = StudyJson {
        case: &study.case.title,
        springs: study
            .entries
            .iter()
            .map(|e| EntryJson {
                spring: e.name(),
                head_stage: e.head.as_ref(),
                runs: e.runs.iter().map(run_summary).collect(),
            })
            .collect(),
    };
    let text = serde_json::to_string_pretty(&json)
        .map_err(|e| TuneError::Invalid(format!("study.json: {e}")))?;
    out.write("study.json", text.as_bytes())?;
    out.write("report.md", markdown(study).as_bytes())?;
    if plots {
        let rows: Vec<SpringStudyRow> = study
            .entries
            .iter()
            .flat_map(|e| {
                e.runs.iter().map(|r| SpringStudyRow {
                    spring: e.name().to_string(),
                    zeta: "mid".into(),
                    statistics: r.statistics,
                })
            })
            .collect();
        out.produce("spring_study.png", |path| {
            en50318::figures::spring_study(path, &rows).map_err(|source| TuneError::Post {
                context: "the spring study's figure".into(),
                source,
            })
        })?;
    }
    Ok(())
}

/// The short summary printed by the command: per speed the lowest standard deviation.
pub fn summary(study: &Study) -> String {
    let mut s = String::new();
    for (k, &v) in study.case.speeds_km_h.iter().enumerate() {
        for e in &study.entries {
            if let Some(run) = e.runs.get(k) {
                let st = &run.statistics;
                let _ = writeln!(
                    s,
                    "{} km/h {}: std {:.2} N, min {:.2} N, loss {:.2} %; {}",
                    tag(v),
                    e.name(),
                    st.std_n,
                    st.min_n,
                    st.loss_percent,
                    assess::summary(&run.assessment)
                );
            }
        }
    }
    s
}
