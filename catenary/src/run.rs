//! One catenary case at each of its speeds: the model (static state first), the STATIC
//! case and the Newmark transient from it, the EN 50318 statistics over the window, and
//! the output set (`catenary.json`, `report.md`, figures, histories).
//!
//! Per speed: `coil_mesher::catenary::build_parts` meshes the model and solves the
//! catenary's static state; `coil_solver::analysis::run` solves the deck's two cases; the
//! transient's history gives the contact force (`contact1_force_n`, N), the head's
//! position `x = s0 + v t` and each interior support's contact-wire displacement (mm,
//! its static value from the STATIC case); `coil_postproc::en50318::evaluate` takes the
//! statistics. Speeds run in parallel (rayon), each run on one thread.

use crate::case::Case;
use crate::{Result, TuneError};
use coil_mesher::catenary::{build_parts, CatenaryModel, StaticState, CONTACT_FORCE_COLUMN};
use coil_postproc::en50318::{self, Evaluation, Record, Settings, Statistics, Support, Track};
use coil_solver::analysis::{run as solve, CaseSolution, History};
use coil_solver::model::Quantity;
use coil_tuner::output::OutDir;
use rayon::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;

/// One speed's run.
#[derive(Debug, Clone)]
pub struct SpeedRun {
    /// The statistics.
    pub statistics: Statistics,
    /// What the statistics were computed from.
    pub evaluation: Evaluation,
    /// The transient's history (SI units).
    pub history: History,
    /// Interior support positions (m).
    pub support_x_m: Vec<f64>,
    /// Their static displacement (mm).
    pub support_static_mm: Vec<f64>,
    /// Their displacement histories (mm).
    pub support_mm: Vec<Vec<f64>>,
    /// The head's start (m).
    pub start_m: f64,
    /// Speed (m/s).
    pub speed_m_s: f64,
    /// The static contact force at the start (N).
    pub static_contact_n: f64,
    /// The unfiltered contact force's mean over the window (N).
    pub window_mean_n: f64,
    /// Its closed form over the same samples: the uplift less the frame spring's mean
    /// force, `F0 - k mean(u)` of the pantograph's lowest stage (N).
    pub closed_form_mean_n: f64,
    /// Wall time of the solve (s).
    pub solve_s: f64,
    /// Time steps.
    pub steps: usize,
}

impl SpeedRun {
    /// The record the statistics read.
    pub fn record(&self) -> (Vec<Support<'_>>, f64) {
        let supports = self
            .support_x_m
            .iter()
            .zip(&self.support_static_mm)
            .zip(&self.support_mm)
            .map(|((&position_m, &static_mm), d)| Support {
                position_m,
                static_mm,
                displacement_mm: d,
            })
            .collect();
        (supports, self.speed_m_s)
    }
}

/// The case's runs.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The case.
    pub case: Case,
    /// The static state of the catenary (the same at every speed).
    pub state: StaticState,
    /// Nodes per wire.
    pub wire_nodes: usize,
    /// One run per speed, in the case's order.
    pub runs: Vec<SpeedRun>,
}

fn missing(context: &str, what: String) -> TuneError {
    TuneError::Missing {
        context: context.into(),
        what,
    }
}

/// Runs a built model and evaluates it.
pub fn run_model(built: &CatenaryModel, settings: &Settings) -> Result<SpeedRun> {
    let context = format!("catenary run at {:.1} km/h", built.speed_m_s * 3.6);
    let started = std::time::Instant::now();
    let results = solve(&built.model).map_err(|source| TuneError::Solve {
        context: context.clone(),
        source: Box::new(source),
    })?;
    let solve_s = started.elapsed().as_secs_f64();
    let (Some(CaseSolution::Static(rest)), Some(CaseSolution::Transient(moving))) = (
        results.first().map(|r| &r.solution),
        results.get(1).map(|r| &r.solution),
    ) else {
        return Err(missing(
            &context,
            "expected a STATIC case and a transient".into(),
        ));
    };
    let history = moving.history.clone();
    let column = |name: &str| {
        history
            .column(name)
            .map(<[f64]>::to_vec)
            .ok_or_else(|| missing(&context, format!("no history column `{name}`")))
    };
    let force = column(CONTACT_FORCE_COLUMN)?;
    let mut support_mm = Vec::new();
    let mut support_static_mm = Vec::new();
    for &node in &built.support_nodes {
        let name = coil_solver::analysis::transient::column_name(node, 3, Quantity::Displacement);
        support_mm.push(column(&name)?.iter().map(|u| u * 1e3).collect::<Vec<f64>>());
        let u = rest
            .node_displacement(&built.model, node)
            .ok_or_else(|| missing(&context, format!("node {node} in the static state")))?;
        support_static_mm.push(u[2]);
    }
    let static_contact_n = force.first().copied().unwrap_or(f64::NAN);
    let supports: Vec<Support<'_>> = built
        .support_x_m
        .iter()
        .zip(&support_static_mm)
        .zip(&support_mm)
        .map(|((&position_m, &static_mm), d)| Support {
            position_m,
            static_mm,
            displacement_mm: d,
        })
        .collect();
    let record = Record {
        time_s: &history.time_s,
        force_n: &force,
        track: Track::Uniform {
            start_m: built.start_m,
        },
        speed_m_s: built.speed_m_s,
        supports: &supports,
    };
    let evaluation = en50318::evaluate(&record, settings).map_err(|source| TuneError::Post {
        context: context.clone(),
        source,
    })?;
    drop(supports);
    // The closed form of the mean contact force over the window (tests/it/closed_form.rs).
    let panto = &built.pantograph;
    let lowest = panto.stages.len() - 1;
    let frame = column(&coil_solver::analysis::transient::column_name(
        built.head + lowest as u32,
        3,
        Quantity::Displacement,
    ))?;
    let window = evaluation.window_indices.clone();
    let samples = window.clone().count() as f64;
    let window_mean_n = force[window.clone()].iter().sum::<f64>() / samples;
    let frame_mean_m = frame[window].iter().sum::<f64>() / samples;
    let closed_form_mean_n =
        panto.uplift_force_n - panto.stages[lowest].stiffness_n_m * frame_mean_m;
    Ok(SpeedRun {
        window_mean_n,
        closed_form_mean_n,
        statistics: evaluation.statistics,
        evaluation,
        support_x_m: built.support_x_m.clone(),
        support_static_mm,
        support_mm,
        start_m: built.start_m,
        speed_m_s: built.speed_m_s,
        static_contact_n,
        solve_s,
        steps: moving.steps,
        history,
    })
}

/// Builds and runs the case at one speed.
pub fn run_speed(case: &Case, speed_km_h: f64) -> Result<(CatenaryModel, SpeedRun)> {
    let built = build_parts(&case.catenary, &case.pantograph, &case.run_spec(speed_km_h))
        .map_err(|e| TuneError::Invalid(format!("{}: {e}", case.path.display())))?;
    let run = run_model(&built, &case.settings)?;
    Ok((built, run))
}

/// Runs the case at all its speeds (in parallel).
pub fn run_case(case: &Case) -> Result<Outcome> {
    let runs: Vec<(CatenaryModel, SpeedRun)> = case
        .speeds_km_h
        .par_iter()
        .map(|&v| run_speed(case, v))
        .collect::<Result<_>>()?;
    let (state, wire_nodes) = runs
        .first()
        .map(|(b, _)| (b.state.clone(), b.wire_nodes))
        .ok_or_else(|| missing("catenary case", "no speed".into()))?;
    Ok(Outcome {
        case: case.clone(),
        state,
        wire_nodes,
        runs: runs.into_iter().map(|(_, r)| r).collect(),
    })
}

/// `catenary.json`.
#[derive(Debug, Serialize)]
struct Summary<'a> {
    case: &'a str,
    model: ModelSummary,
    window: en50318::Window,
    filter: FilterSummary,
    static_state: StateSummary,
    runs: Vec<Statistics>,
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

/// The short summary printed by the command.
pub fn summary(outcome: &Outcome) -> String {
    let mut s = String::new();
    for run in &outcome.runs {
        let st = &run.statistics;
        let _ = writeln!(
            s,
            "{:.0} km/h: mean {:.1} N, std {:.1} N, max {:.1} N, min {:.1} N, uplift {:.1} mm, \
             loss {:.2} % ({} steps, {:.1} s)",
            st.speed_km_h,
            st.mean_n,
            st.std_n,
            st.max_n,
            st.min_n,
            st.uplift_support_mm,
            st.loss_percent,
            run.steps,
            run.solve_s
        );
    }
    s
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
         ({} nodes per wire, about {} DOFs); pantograph of {} stages, static uplift {} N, \
         contact stiffness {} N/m; Newmark average acceleration, time step {} s.\n",
        c.spans,
        c.span_length_m,
        c.system_height_m,
        c.presag_mm,
        c.element_length_m,
        outcome.wire_nodes,
        2 * outcome.wire_nodes,
        p.stages.len(),
        p.uplift_force_n,
        p.contact_stiffness_n_m,
        case.time_step_s
    );
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
    s.push_str("## Statistics against the reference ranges\n\n");
    let stats: Vec<Statistics> = outcome.runs.iter().map(|r| r.statistics).collect();
    s.push_str(&en50318::report::markdown(&stats, &case.reference));
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
    s.push_str("\nFigures: `contact_force_<speed>.png` (raw and filtered along the track, window shaded), `uplift_<speed>.png` (the supports' uplift); histories: `history_<speed>.csv` (SI units).\n");
    s
}

fn tag(speed_km_h: f64) -> String {
    format!("{}", (speed_km_h * 1000.0).round() / 1000.0)
}

/// Writes the output set: `catenary.json`, `report.md`, per speed the figures (unless
/// `plots` is false) and the history.
pub fn write(outcome: &Outcome, out: &OutDir, plots: bool) -> Result<()> {
    let case = &outcome.case;
    let c = &case.catenary;
    let head = &case.pantograph.stages[0];
    let st = &outcome.state;
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
        runs: outcome.runs.iter().map(|r| r.statistics).collect(),
    };
    let json = serde_json::to_string_pretty(&summary)
        .map_err(|e| TuneError::Invalid(format!("catenary.json: {e}")))?;
    out.write("catenary.json", json.as_bytes())?;
    out.write("report.md", report(outcome).as_bytes())?;
    for run in &outcome.runs {
        let speed = tag(run.statistics.speed_km_h);
        out.write(
            format!("history_{speed}.csv"),
            run.history.to_csv().as_bytes(),
        )?;
        if plots {
            let (supports, speed_m_s) = run.record();
            let force = run.history.column(CONTACT_FORCE_COLUMN).unwrap_or_default();
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
    Ok(())
}
