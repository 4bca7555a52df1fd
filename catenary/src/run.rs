//! One catenary case at each of its speeds: the model (static state first), the STATIC
//! case and the Newmark transient from it, the EN 50318 statistics over the window, the
//! whole run's extremes and losses of contact, and the design assessment.
//!
//! Per speed: `crate::model::build_parts` meshes the model and solves the catenary's
//! static state; `coil_solver::analysis::run_with` solves the deck's two cases (with the
//! transient work limit and, on the command line, progress); the transient's history
//! gives the contact force (`contact1_force_n`, N), the head's position `x = s0 + v t`
//! and each interior support's contact-wire displacement (mm, its static value from the
//! STATIC case); `crate::en50318::evaluate` takes the statistics, [`crate::whole_run`]
//! the whole run, [`crate::assess`] the criteria. Speeds run in parallel (rayon), each
//! run on one thread. Writing the output set is [`crate::output`].

use crate::assess::{assess, Criterion};
use crate::case::Case;
use crate::en50318::{self, Evaluation, Record, Settings, Statistics, Support, Track};
use crate::head_stage::from_spring::BuiltHead;
use crate::model::{build_parts, CatenaryModel, PantographSpec, StaticState, CONTACT_FORCE_COLUMN};
use crate::whole_run::{whole_run, WholeRun};
use crate::{Result, TuneError};
use coil_solver::analysis::transient::RunOptions;
use coil_solver::analysis::{run_with as solve, CaseSolution, History};
use coil_solver::model::Quantity;
use rayon::prelude::*;

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
    /// The pantograph's masses' displacement histories, the head first (mm).
    pub pantograph_mm: Vec<Vec<f64>>,
    /// The head's start (m).
    pub start_m: f64,
    /// Speed (m/s).
    pub speed_m_s: f64,
    /// The speed's share of the contact wire's wave speed (-).
    pub wave_speed_ratio: f64,
    /// The static contact force at the start (N).
    pub static_contact_n: f64,
    /// The unfiltered contact force's mean over the window (N).
    pub window_mean_n: f64,
    /// Its closed form over the same samples: the uplift less the frame spring's mean
    /// force, `F0 - k mean(u)` of the pantograph's lowest stage (N).
    pub closed_form_mean_n: f64,
    /// The whole run's extremes and losses of contact.
    pub whole: WholeRun,
    /// The design criteria (filled by [`run_case`]; empty from [`run_model`]).
    pub assessment: Vec<Criterion>,
    /// Wall time of the solve (s).
    pub solve_s: f64,
    /// Time steps.
    pub steps: usize,
}

impl SpeedRun {
    /// The record the statistics read.
    pub fn record(&self) -> (Vec<Support<'_>>, f64) {
        (
            supports(&self.support_x_m, &self.support_static_mm, &self.support_mm),
            self.speed_m_s,
        )
    }
}

fn supports<'a>(x: &[f64], static_mm: &[f64], d: &'a [Vec<f64>]) -> Vec<Support<'a>> {
    x.iter()
        .zip(static_mm)
        .zip(d)
        .map(|((&position_m, &static_mm), d)| Support {
            position_m,
            static_mm,
            displacement_mm: d,
        })
        .collect()
}

/// Whether EN 50318's reference ranges apply to the case's model.
#[derive(Debug, Clone, PartialEq)]
pub enum Validation {
    /// The model is the reference model and the case gives ranges.
    Applies,
    /// The case gives no ranges.
    NoRanges,
    /// The model is not the reference model: the fields that differ.
    NotReference(Vec<String>),
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
    /// The head stage built from a spring, if the case names one.
    pub head: Option<BuiltHead>,
    /// Whether the reference ranges apply.
    pub validation: Validation,
}

fn missing(context: &str, what: String) -> TuneError {
    TuneError::Missing {
        context: context.into(),
        what,
    }
}

/// Runs a built model and evaluates it (no work limit, no progress).
pub fn run_model(built: &CatenaryModel, settings: &Settings) -> Result<SpeedRun> {
    run_model_with(built, settings, &RunOptions::default())
}

/// [`run_model`] with the solver's options (work limit, progress).
pub fn run_model_with(
    built: &CatenaryModel,
    settings: &Settings,
    options: &RunOptions,
) -> Result<SpeedRun> {
    let context = format!("catenary run at {:.1} km/h", built.speed_m_s * 3.6);
    let started = std::time::Instant::now();
    let results = solve(&built.model, options).map_err(|source| TuneError::Solve {
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
    let uz = |node| coil_solver::analysis::transient::column_name(node, 3, Quantity::Displacement);
    let force = column(CONTACT_FORCE_COLUMN)?;
    let mut support_mm = Vec::new();
    let mut support_static_mm = Vec::new();
    for &node in &built.support_nodes {
        support_mm.push(
            column(&uz(node))?
                .iter()
                .map(|u| u * 1e3)
                .collect::<Vec<f64>>(),
        );
        let u = rest
            .node_displacement(&built.model, node)
            .ok_or_else(|| missing(&context, format!("node {node} in the static state")))?;
        support_static_mm.push(u[2]);
    }
    let panto = &built.pantograph;
    let mut pantograph_mm: Vec<Vec<f64>> = Vec::new();
    for i in 0..panto.stages.len() {
        pantograph_mm.push(
            column(&uz(built.head + i as u32))?
                .iter()
                .map(|u| u * 1e3)
                .collect(),
        );
    }
    let static_contact_n = force.first().copied().unwrap_or(f64::NAN);
    let evaluation = {
        let supports = supports(&built.support_x_m, &support_static_mm, &support_mm);
        let record = Record {
            time_s: &history.time_s,
            force_n: &force,
            track: Track::Uniform {
                start_m: built.start_m,
            },
            speed_m_s: built.speed_m_s,
            supports: &supports,
        };
        en50318::evaluate(&record, settings).map_err(|source| TuneError::Post {
            context: context.clone(),
            source,
        })?
    };
    // The closed form of the mean contact force over the window (tests/it/closed_form.rs).
    let lowest = panto.stages.len() - 1;
    let frame = &pantograph_mm[lowest];
    let window = evaluation.window_indices.clone();
    let samples = window.clone().count() as f64;
    let window_mean_n = force[window.clone()].iter().sum::<f64>() / samples;
    let frame_mean_m = frame[window].iter().sum::<f64>() / samples * 1e-3;
    let closed_form_mean_n =
        panto.uplift_force_n - panto.stages[lowest].stiffness_n_m * frame_mean_m;
    let step_s = match history.time_s.as_slice() {
        [a, b, ..] => b - a,
        _ => f64::INFINITY,
    };
    let settle = (evaluation.settle_s / step_s).round() as usize;
    let whole = whole_run(
        &history.time_s,
        &evaluation.position_m,
        &force,
        &evaluation.filtered_n,
        settle,
        settings.window,
    )
    .ok_or_else(|| missing(&context, "an empty history".into()))?;
    Ok(SpeedRun {
        window_mean_n,
        closed_form_mean_n,
        statistics: evaluation.statistics,
        evaluation,
        support_x_m: built.support_x_m.clone(),
        support_static_mm,
        support_mm,
        pantograph_mm,
        start_m: built.start_m,
        speed_m_s: built.speed_m_s,
        wave_speed_ratio: f64::NAN,
        static_contact_n,
        whole,
        assessment: Vec::new(),
        solve_s,
        steps: moving.steps,
        history,
    })
}

/// Builds and runs the case at one speed with `pantograph` (the case's, or one with a
/// head stage from a spring).
pub fn run_speed_with(
    case: &Case,
    pantograph: &PantographSpec,
    speed_km_h: f64,
    progress: bool,
) -> Result<(CatenaryModel, SpeedRun)> {
    let built = build_parts(&case.catenary, pantograph, &case.run_spec(speed_km_h))
        .map_err(|e| TuneError::Invalid(format!("{}: {e}", case.path.display())))?;
    let options = RunOptions {
        progress,
        allow_large: Some(case.allow_large),
    };
    let mut run = run_model_with(&built, &case.settings, &options)?;
    run.wave_speed_ratio = case.catenary.wave_speed_ratio(speed_km_h);
    run.assessment = assess(&run.statistics, &case.assessment);
    Ok((built, run))
}

/// Builds and runs the case at one speed.
pub fn run_speed(case: &Case, speed_km_h: f64) -> Result<(CatenaryModel, SpeedRun)> {
    run_speed_with(case, &case.pantograph, speed_km_h, false)
}

/// The fields of `case`'s model that differ from EN 50318:2002's reference model
/// ([`crate::model::CatenaryDeckSpec::en50318_reference`] on 10 spans; the element length
/// is the discretisation's, not the model's).
pub fn reference_differences(case: &Case, pantograph: &PantographSpec) -> Vec<String> {
    let reference =
        crate::model::CatenaryDeckSpec::en50318_reference(10, case.catenary.element_length_m);
    let mut out = Vec::new();
    let pairs = [
        (
            "catenary",
            serde_json::to_value(&case.catenary),
            serde_json::to_value(&reference.catenary),
        ),
        (
            "pantograph",
            serde_json::to_value(pantograph),
            serde_json::to_value(&reference.pantograph),
        ),
    ];
    for (name, a, b) in pairs {
        if let (Ok(a), Ok(b)) = (a, b) {
            diff(name, &a, &b, &mut out);
        }
    }
    out
}

fn diff(path: &str, a: &serde_json::Value, b: &serde_json::Value, out: &mut Vec<String>) {
    use serde_json::Value;
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                let (u, v) = (
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                );
                diff(&format!("{path}.{k}"), u, v, out);
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                diff(&format!("{path}[{i}]"), u, v, out);
            }
        }
        (Value::Number(x), Value::Number(y)) if x.as_f64() == y.as_f64() => {}
        _ if a == b => {}
        _ => out.push(format!("{path} = {a} (reference {b})")),
    }
}

/// Runs the case at all its speeds (in parallel), with `head` in the pantograph's head
/// stage when given.
pub fn run_case_with(case: &Case, head: Option<&BuiltHead>, progress: bool) -> Result<Outcome> {
    let pantograph = match head {
        Some(h) => crate::head_stage::from_spring::with_head(&case.pantograph, h),
        None => case.pantograph.clone(),
    };
    let runs: Vec<(CatenaryModel, SpeedRun)> = case
        .speeds_km_h
        .par_iter()
        .map(|&v| run_speed_with(case, &pantograph, v, progress))
        .collect::<Result<_>>()?;
    let (state, wire_nodes) = runs
        .first()
        .map(|(b, _)| (b.state.clone(), b.wire_nodes))
        .ok_or_else(|| missing("catenary case", "no speed".into()))?;
    let validation = if case.reference.speeds.is_empty() {
        Validation::NoRanges
    } else {
        let differences = reference_differences(case, &pantograph);
        if differences.is_empty() {
            Validation::Applies
        } else {
            Validation::NotReference(differences)
        }
    };
    Ok(Outcome {
        case: case.clone(),
        state,
        wire_nodes,
        runs: runs.into_iter().map(|(_, r)| r).collect(),
        head: head.cloned(),
        validation,
    })
}

/// Runs the case at all its speeds (in parallel).
pub fn run_case(case: &Case) -> Result<Outcome> {
    run_case_with(case, None, false)
}
