//! The output set of a catenary case (`docs/files.md`): `catenary.json`, `report.md`, per
//! speed the history with named columns and the figures, and for a speed sweep the
//! statistics against speed.
//!
//! Two verdicts, never mixed (`crate::assess`): the validation against EN 50318's reference
//! ranges only when the model is the reference model (else the report says which fields
//! differ and prints no pass or miss), and the design assessment of every run.
//!
//! History columns (`history_<speed>.csv`, SI but for the displacements): `time_s`,
//! `position_m` (the head along the track), `contact_force_n` (raw),
//! `contact_force_filtered_n` (the statistics' low-pass), per interior support
//! `uplift_<x>m_mm` (its contact-wire displacement less the static one, mm), per
//! pantograph mass `stage<i>_uz_mm` (the head is stage 1, mm, up). A speed's file tag is
//! the speed's shortest exact decimal (`250`, `250.0001`): distinct speeds never share a
//! file.

use crate::assess;
use crate::en50318::{self, Record, Statistics, Track};
use crate::model::EN50119_WAVE_SPEED_SHARE;
use crate::run::{Outcome, SpeedRun, Validation};
use crate::whole_run::WholeRun;
use crate::{Result, TuneError};
use coil_tuner::output::OutDir;
use serde::Serialize;
use std::fmt::Write as _;

/// `catenary.json`.
#[derive(Debug, Serialize)]
struct Summary<'a> {
    case: &'a str,
    model: ModelSummary,
    window: en50318::Window,
    filter: FilterSummary,
    static_state: StateSummary,
    #[serde(skip_serializing_if = "Option::is_none")]
    head_stage: Option<&'a crate::head_stage::from_spring::BuiltHead>,
    validation: ValidationSummary,
    runs: Vec<RunSummary<'a>>,
}

#[derive(Debug, Serialize)]
struct ValidationSummary {
    applies: bool,
    reason: String,
    differences: Vec<String>,
}

/// One speed in `catenary.json`: the statistics' contract keys and what else the run
/// found beside them.
#[derive(Debug, Serialize)]
pub struct RunSummary<'a> {
    #[serde(flatten)]
    statistics: Statistics,
    wave_speed_ratio: f64,
    wave_speed_flag: &'static str,
    assessment: &'a [assess::Criterion],
    assessment_verdict: String,
    whole_run: &'a WholeRun,
}

#[derive(Debug, Serialize)]
struct ModelSummary {
    spans: u32,
    span_length_m: f64,
    element_length_m: f64,
    time_step_s: f64,
    nodes_per_wire: usize,
    presag_mm: f64,
    uplift_force_n: f64,
    contact_stiffness_n_m: f64,
    head_stiffness_n_m: f64,
    head_damping_n_s_m: f64,
    wave_speed_km_h: f64,
}

#[derive(Debug, Serialize)]
struct FilterSummary {
    kind: &'static str,
    cutoff_hz: f64,
    order_per_pass: usize,
}

#[derive(Debug, Serialize)]
struct StateSummary {
    presag_miss_mm: f64,
    corrections: usize,
    weight_n: f64,
    support_reactions_n: f64,
    dropper_force_min_n: f64,
    dropper_force_max_n: f64,
}

fn fold(values: &[f64], f: fn(f64, f64) -> f64, start: f64) -> f64 {
    values.iter().copied().fold(start, f)
}

/// The wave-speed flag of a run: `ok`, `above EN 50119's 70 %` or `supercritical`.
pub fn wave_flag(ratio: f64) -> &'static str {
    if ratio >= 1.0 {
        "supercritical"
    } else if ratio > EN50119_WAVE_SPEED_SHARE {
        "above EN 50119's 70 %"
    } else {
        "ok"
    }
}

/// The short summary printed by the command.
pub fn summary(outcome: &Outcome) -> String {
    let mut s = String::new();
    for run in &outcome.runs {
        let st = &run.statistics;
        let _ = writeln!(
            s,
            "{:.0} km/h: mean {:.1} N, std {:.1} N, max {:.1} N, min {:.1} N, uplift {:.1} mm, \
             loss {:.2} % ({} steps, {:.1} s); v/c {:.3}; assessment: {}",
            st.speed_km_h,
            st.mean_n,
            st.std_n,
            st.max_n,
            st.min_n,
            st.uplift_support_mm,
            st.loss_percent,
            run.steps,
            run.solve_s,
            run.wave_speed_ratio,
            assess::summary(&run.assessment)
        );
    }
    s
}

/// The statistics against speed as a markdown table.
pub fn speed_table(runs: &[&SpeedRun]) -> String {
    let mut s = String::from(
        "| speed (km/h) | v / c | mean (N) | std (N) | mean + 3 std (N) | mean - 3 std (N) | max (N) | min (N) | uplift (mm) | loss (%) | loss, whole run (%) |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for run in runs {
        let st = &run.statistics;
        let flag = match wave_flag(run.wave_speed_ratio) {
            "ok" => String::new(),
            other => format!(" ({other})"),
        };
        let _ = writeln!(
            s,
            "| {} | {:.3}{flag} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} |",
            tag(st.speed_km_h),
            run.wave_speed_ratio,
            st.mean_n,
            st.std_n,
            st.stat_max_n,
            st.stat_min_n,
            st.max_n,
            st.min_n,
            st.uplift_support_mm,
            st.loss_percent,
            run.whole.loss_percent
        );
    }
    s
}

fn validation_section(outcome: &Outcome, s: &mut String) {
    let case = &outcome.case;
    s.push_str("## Validation (EN 50318 reference ranges)\n\n");
    match &outcome.validation {
        Validation::NoRanges => s.push_str(
            "Not applicable: the case gives no reference ranges. EN 50318's ranges validate a \
             simulation method on the standard's reference model; see the assessment below \
             for the design criteria.\n\n",
        ),
        Validation::NotReference(differences) => {
            let _ = writeln!(
                s,
                "Not applicable: the model is not EN 50318:2002's reference model, so its \
                 ranges say nothing about it (no pass or miss is printed). It differs in {} \
                 field(s):\n",
                differences.len()
            );
            for d in differences.iter().take(20) {
                let _ = writeln!(s, "- `{d}`");
            }
            if differences.len() > 20 {
                let _ = writeln!(s, "- ... {} more", differences.len() - 20);
            }
            s.push_str("\nThe design criteria below apply to any model.\n\n");
        }
        Validation::Applies => {
            let (ranged, other): (Vec<&SpeedRun>, Vec<&SpeedRun>) =
                outcome.runs.iter().partition(|r| {
                    en50318::KEYS[1..]
                        .iter()
                        .any(|k| case.reference.range(r.statistics.speed_km_h, k).is_some())
                });
            s.push_str(
                "The model is EN 50318:2002's reference model (the element length aside): its \
                 statistics against the standard's ranges.\n\n",
            );
            let stats: Vec<Statistics> = ranged.iter().map(|r| r.statistics).collect();
            s.push_str(&en50318::report::markdown(&stats, &case.reference));
            if !other.is_empty() {
                let speeds: Vec<String> = other
                    .iter()
                    .map(|r| en50318::speed_label(r.statistics.speed_km_h))
                    .collect();
                let _ = writeln!(
                    s,
                    "No reference range at {}: not validated there (the statistics are in the \
                     table above and assessed below).\n",
                    speeds.join(", ")
                );
            }
        }
    }
}

fn head_section(outcome: &Outcome, s: &mut String) {
    let Some(h) = &outcome.head else { return };
    s.push_str("## The head stage, built from a spring\n\n");
    let _ = writeln!(
        s,
        "Spring `{}` ({}): one spring's rate {:.4} N/mm from coil's FE model, {} in parallel: \
         K = {:.1} N/m; one spring's wire mass {:.4} kg, {} on the head ({:.4} kg with its \
         own {:.3} kg); damping law: {}; {}.\n",
        h.name,
        h.source,
        h.spring_rate_n_mm,
        h.springs_in_parallel,
        h.stiffness_n_m,
        h.spring_mass_kg,
        if h.mass_share_kg > 0.0 {
            format!("a third of the springs' mass, {:.4} kg,", h.mass_share_kg)
        } else {
            "none of the springs' mass".to_string()
        },
        h.stage_mass_kg,
        h.head_mass_kg,
        h.damping_law,
        match h.reduced_modes {
            Some(m) => format!(
                "the stage reduced (Craig-Bampton, {m} modes kept, the springs' mass and damping in its matrices)"
            ),
            None => format!(
                "lumped dashpot c = {:.3} N s/m ({:?}), zeta of the head mode {:.5}",
                h.damping_n_s_m, h.damping, h.zeta
            ),
        }
    );
    for a in &h.assumptions {
        let _ = writeln!(s, "- **assumption**: {a}");
    }
    if !h.assumptions.is_empty() {
        s.push('\n');
    }
}

/// `report.md`.
pub fn report(outcome: &Outcome) -> String {
    let case = &outcome.case;
    let c = &case.catenary;
    let p = &case.pantograph;
    let st = &outcome.state;
    let w = case.settings.window;
    let mut s = String::new();
    let _ = writeln!(s, "# {}\n", case.title);
    let _ = writeln!(
        s,
        "Catenary: {} spans of {} m, system height {} m, presag {} mm, elements <= {} m \
         ({} nodes per wire, about {} DOFs), contact wire's wave speed {:.1} km/h; \
         pantograph of {} stages, static uplift {} N, contact stiffness {} N/m; Newmark \
         average acceleration, time step {} s.\n",
        c.spans,
        c.span_length_m,
        c.system_height_m,
        c.presag_mm,
        c.element_length_m,
        outcome.wire_nodes,
        2 * outcome.wire_nodes,
        c.wave_speed_m_s() * 3.6,
        p.stages.len(),
        p.uplift_force_n,
        p.contact_stiffness_n_m,
        case.time_step_s
    );
    head_section(outcome, &mut s);
    let _ = writeln!(
        s,
        "Static state: the contact wire meets its prescribed heights to {:.2e} mm ({} \
         dropper-length corrections); dropper forces {:.2} to {:.2} N; the supports carry \
         {:.3} N of the catenary's {:.3} N weight.\n",
        st.presag_miss_mm,
        st.iterations,
        fold(&st.dropper_force_n, f64::min, f64::INFINITY),
        fold(&st.dropper_force_n, f64::max, f64::NEG_INFINITY),
        st.support_reactions_n,
        st.weight_n
    );
    let _ = writeln!(
        s,
        "Statistics (EN 50318) over the pantograph's positions {} to {} m, after a \
         zero-phase Butterworth low-pass at {} Hz (order {} per pass, applied to the whole \
         record); loss of contact from the unfiltered force; uplift of the contact wire at \
         the steady arms in the window, from the static state.\n",
        w.start_m, w.end_m, case.settings.cutoff_hz, case.settings.order
    );
    s.push_str("## Statistics against speed\n\n");
    let runs: Vec<&SpeedRun> = outcome.runs.iter().collect();
    s.push_str(&speed_table(&runs));
    let _ = writeln!(
        s,
        "\nv / c: the speed over the contact wire's wave speed sqrt(T / rho A); EN 50119 asks \
         for at most {:.0} % (flagged above it); at or above 1 the model is outside its \
         regime and runs only with `--allow-supercritical`.\n",
        EN50119_WAVE_SPEED_SHARE * 100.0
    );
    validation_section(outcome, &mut s);
    s.push_str("## Assessment (EN 50367 / EN 50119 design criteria)\n\n");
    s.push_str(
        "Every value below is as quoted in secondary sources, **not read from the standards** \
         (we had no copy); each row names its source.\n\n",
    );
    for run in &outcome.runs {
        let _ = writeln!(
            s,
            "### {}: {}\n\n{}",
            en50318::speed_label(run.statistics.speed_km_h),
            assess::summary(&run.assessment),
            assess::markdown(&run.assessment)
        );
    }
    s.push_str("## The whole run\n\n");
    for run in &outcome.runs {
        let _ = writeln!(
            s,
            "**{}.** {}",
            en50318::speed_label(run.statistics.speed_km_h),
            run.whole.markdown()
        );
    }
    s.push_str("## Runs\n\nThe mean contact force's closed form: the uplift less the frame spring's mean force, `F0 - k2 mean(u2)`, over the window's samples (unfiltered; it holds up to the pantograph's momentum and frame drift between the window's ends over its duration).\n\n| speed (km/h) | steps | static contact force (N) | window mean, unfiltered (N) | F0 - k2 mean(u2) (N) | solve (s) | window clear of the filter's ends |\n|---:|---:|---:|---:|---:|---:|---|\n");
    for run in &outcome.runs {
        let _ = writeln!(
            s,
            "| {:.0} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {} |",
            run.statistics.speed_km_h,
            run.steps,
            run.static_contact_n,
            run.window_mean_n,
            run.closed_form_mean_n,
            run.solve_s,
            if run.evaluation.clear_of_ends {
                "yes"
            } else {
                "no"
            }
        );
    }
    s.push_str("\nFigures: `contact_force_<speed>.png` (raw and filtered along the track, window shaded, mean and mean +- 3 std), `uplift_<speed>.png` (the supports' uplift), `speeds.png` (the statistics against speed, three speeds or more); histories: `history_<speed>.csv` (named columns: `time_s`, `position_m`, `contact_force_n`, `contact_force_filtered_n`, `uplift_<x>m_mm` per support, `stage<i>_uz_mm` per pantograph mass).\n");
    s
}

/// A speed's file tag: its shortest exact decimal (module doc).
pub fn tag(speed_km_h: f64) -> String {
    format!("{speed_km_h}")
}

/// The history of one run with named columns (module doc).
pub fn history_csv(run: &SpeedRun) -> String {
    let mut s = String::from("time_s,position_m,contact_force_n,contact_force_filtered_n");
    for x in &run.support_x_m {
        let _ = write!(s, ",uplift_{}m_mm", (x * 1000.0).round() / 1000.0);
    }
    for i in 0..run.pantograph_mm.len() {
        let _ = write!(s, ",stage{}_uz_mm", i + 1);
    }
    s.push('\n');
    let force = run
        .history
        .column(crate::model::CONTACT_FORCE_COLUMN)
        .unwrap_or_default();
    let e = &run.evaluation;
    for (i, t) in run.history.time_s.iter().enumerate() {
        let _ = write!(
            s,
            "{t},{},{},{}",
            e.position_m[i],
            force.get(i).copied().unwrap_or(f64::NAN),
            e.filtered_n[i]
        );
        for (d, d0) in run.support_mm.iter().zip(&run.support_static_mm) {
            let _ = write!(s, ",{}", d[i] - d0);
        }
        for u in &run.pantograph_mm {
            let _ = write!(s, ",{}", u[i]);
        }
        s.push('\n');
    }
    s
}

fn summary_json(outcome: &Outcome) -> Result<String> {
    let case = &outcome.case;
    let c = &case.catenary;
    let head = outcome
        .head
        .as_ref()
        .map_or(&case.pantograph.stages[0], |h| &h.stage);
    let st = &outcome.state;
    let (applies, reason, differences) = match &outcome.validation {
        Validation::Applies => (true, "the reference model".to_string(), Vec::new()),
        Validation::NoRanges => (
            false,
            "no reference ranges in the case".to_string(),
            Vec::new(),
        ),
        Validation::NotReference(d) => (false, "not the reference model".to_string(), d.clone()),
    };
    let summary = Summary {
        case: &case.title,
        model: ModelSummary {
            spans: c.spans,
            span_length_m: c.span_length_m,
            element_length_m: c.element_length_m,
            time_step_s: case.time_step_s,
            nodes_per_wire: outcome.wire_nodes,
            presag_mm: c.presag_mm,
            uplift_force_n: case.pantograph.uplift_force_n,
            contact_stiffness_n_m: case.pantograph.contact_stiffness_n_m,
            head_stiffness_n_m: head.stiffness_n_m,
            head_damping_n_s_m: head.damping_n_s_m,
            wave_speed_km_h: c.wave_speed_m_s() * 3.6,
        },
        window: case.settings.window,
        filter: FilterSummary {
            kind: "zero-phase Butterworth low-pass (forward and backward)",
            cutoff_hz: case.settings.cutoff_hz,
            order_per_pass: case.settings.order,
        },
        static_state: StateSummary {
            presag_miss_mm: st.presag_miss_mm,
            corrections: st.iterations,
            weight_n: st.weight_n,
            support_reactions_n: st.support_reactions_n,
            dropper_force_min_n: fold(&st.dropper_force_n, f64::min, f64::INFINITY),
            dropper_force_max_n: fold(&st.dropper_force_n, f64::max, f64::NEG_INFINITY),
        },
        head_stage: outcome.head.as_ref(),
        validation: ValidationSummary {
            applies,
            reason,
            differences,
        },
        runs: outcome.runs.iter().map(run_summary).collect(),
    };
    serde_json::to_string_pretty(&summary)
        .map_err(|e| TuneError::Invalid(format!("catenary.json: {e}")))
}

/// One run's entry of `catenary.json` (and of a spring study's `study.json`).
pub fn run_summary(run: &SpeedRun) -> RunSummary<'_> {
    RunSummary {
        statistics: run.statistics,
        wave_speed_ratio: run.wave_speed_ratio,
        wave_speed_flag: wave_flag(run.wave_speed_ratio),
        assessment: &run.assessment,
        assessment_verdict: assess::summary(&run.assessment),
        whole_run: &run.whole,
    }
}

/// Writes the output set: `catenary.json`, `report.md`, per speed the figures (unless
/// `plots` is false) and the history, `speeds.png` for three speeds or more.
pub fn write(outcome: &Outcome, out: &OutDir, plots: bool) -> Result<()> {
    let case = &outcome.case;
    out.write("catenary.json", summary_json(outcome)?.as_bytes())?;
    out.write("report.md", report(outcome).as_bytes())?;
    for run in &outcome.runs {
        let speed = tag(run.statistics.speed_km_h);
        out.write(format!("history_{speed}.csv"), history_csv(run).as_bytes())?;
        if plots {
            let (supports, speed_m_s) = run.record();
            let force = run
                .history
                .column(crate::model::CONTACT_FORCE_COLUMN)
                .unwrap_or_default();
            let record = Record {
                time_s: &run.history.time_s,
                force_n: force,
                track: Track::Uniform {
                    start_m: run.start_m,
                },
                speed_m_s,
                supports: &supports,
            };
            let post = |source| TuneError::Post {
                context: format!("figures at {speed} km/h"),
                source,
            };
            out.produce(format!("contact_force_{speed}.png"), |path| {
                en50318::figures::contact_force(path, &record, &case.settings, &run.evaluation)
                    .map_err(post)
            })?;
            out.produce(format!("uplift_{speed}.png"), |path| {
                en50318::figures::uplift(path, &record, &case.settings, &run.evaluation)
                    .map_err(post)
            })?;
        }
    }
    if plots && outcome.runs.len() >= 3 {
        let stats: Vec<Statistics> = outcome.runs.iter().map(|r| r.statistics).collect();
        out.produce("speeds.png", |path| {
            en50318::figures::speeds(path, &stats).map_err(|source| TuneError::Post {
                context: "the statistics against speed".into(),
                source,
            })
        })?;
    }
    Ok(())
}
