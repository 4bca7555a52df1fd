//! `coil-tune diagnose`: from measured records to what the paper's model gets wrong,
//! its physical cause, the extended model and the gain (`docs/measured-case.md`,
//! docs/diagnose.md).
//!
//! # Steps
//! 1. **Records** are read and checked ([`data`]) before anything is computed; nothing
//!    is written unless the whole diagnosis succeeds, and then every file goes through
//!    a temporary name ([`write`]).
//! 2. **Baseline, the paper's model**: K from the static record (the least-squares line
//!    `F = k x + s F_f` through both branches, `s = +-1`), E by the paper's loop 1 on the FE model; T and zeta
//!    by the paper's decrement (every 10th crest, Eqs. 2-3) on the decay record; the
//!    weight's mass by loop 2; damping stiffness-proportional, `alpha = 0`,
//!    `beta = 2 zeta / w`. One decay identifies one combination of alpha and beta
//!    (docs/tuner.md, "Why a variant's zeta can miss"); beta alone keeps the damping in
//!    the spring's material, acts on no rigid motion of the weight, and gives the axial
//!    mode exactly `zeta = beta w / 2`. The decay is then simulated on the reduced FE
//!    model ([`model`]), its initial state fitted by linear least squares (the record
//!    starts after the impulse). `forecast_rms` repeats all of it on the first half and
//!    predicts the second.
//! 3. **Reference, the same linear model by output error**: mass and beta refined by
//!    Levenberg-Marquardt on the raw acceleration. It isolates what any linear model
//!    can do, so the choice of a cause is not credited with the decrement estimator's
//!    bias.
//! 4. **Candidates**: every catalogue effect ([`effects`]) starts from its signature
//!    ([`evidence`]), is fitted by output error with the weight's mass, beta and the
//!    initial state, on the whole record and on its first half (forecast).
//! 5. **Choice** ([`select`]): BIC on the effective number of independent residuals,
//!    and the held-out forecast; `none` when no effect gains significantly.

pub mod data;
pub mod effects;
pub mod evidence;
pub mod fit;
pub mod lm;
pub mod model;
pub mod plots;
pub mod report;
pub mod select;
pub mod signatures;

use crate::case::{read_case, MeasuredCase};
use crate::decay::{self, DecayRecord, DecaySettings};
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use crate::loops;
use data::DecayData;
use effects::{BaselineFigures, Mount, CATALOGUE};
use evidence::Signatures;
use fit::{Fitted, Knob, Problem, StaticBlock};
use model::{Physical, ReducedSpring};
use rayon::prelude::*;
use report::Diagnosis;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

/// Settings of a diagnosis.
#[derive(Debug, Clone)]
pub struct DiagnoseSettings {
    pub fe: FeSettings,
    /// Fixed-interface modes kept beside the weight's DOFs.
    pub modes: usize,
    /// Levenberg-Marquardt iterations per fit.
    pub max_iterations: usize,
    /// Draw the figures.
    pub plots: bool,
    /// Progress on stderr.
    pub progress: bool,
}

impl Default for DiagnoseSettings {
    fn default() -> Self {
        DiagnoseSettings {
            fe: FeSettings {
                modes: 6,
                ..FeSettings::default()
            },
            modes: 4,
            max_iterations: 40,
            plots: true,
            progress: false,
        }
    }
}

/// One fitted model's figures on the full record and on the forecasts.
#[derive(Debug, Clone)]
pub struct ModelRun {
    pub full: Fitted,
    pub half: Fitted,
    pub residual_rms: f64,
    pub forecast_rms: f64,
    /// Forecast RMS (relative) of the quarter after each rolling origin
    /// (`select::ORIGINS`), fitted up to the origin; empty for the baseline.
    pub rolling: Vec<f64>,
}

/// One candidate: a set of catalogue effects (one to three), its evidence and its fit.
#[derive(Debug, Clone)]
pub struct CandidateRun {
    /// Catalogue indices, ascending.
    pub effects: Vec<usize>,
    pub evidence: String,
    /// Each effect's signature check at the fitted values (empty if the fit failed).
    pub signatures: Vec<effects::SignatureCheck>,
    pub run: std::result::Result<ModelRun, String>,
}

impl CandidateRun {
    /// The candidate's name: its effects joined by `+`.
    pub fn label(&self) -> String {
        self.effects
            .iter()
            .map(|&i| CATALOGUE[i].name())
            .collect::<Vec<_>>()
            .join("+")
    }
}

/// Everything a diagnosis computed (the report and the figures draw on it).
pub struct Outcome {
    pub case: MeasuredCase,
    pub decay: DecayData,
    pub statics: Option<(crate::case::StaticRecord, Range<usize>)>,
    pub signatures: Signatures,
    pub baseline: ModelRun,
    pub reference: ModelRun,
    pub candidates: Vec<CandidateRun>,
    pub diagnosis: Diagnosis,
    /// Measured amplitude spectrum (frequencies Hz, amplitudes m/s^2) for the figure.
    pub spectrum: Option<(Vec<f64>, Vec<f64>)>,
    /// Fixed-interface modes kept.
    pub modes: usize,
    /// Largest step as a fraction of the axial period.
    pub step_fraction: f64,
    /// Where the baseline's K came from.
    pub stiffness_source: report::StiffnessSource,
    /// The other axial decay records fitted jointly with the first: file, samples, and
    /// attached mass minus the first record's (kg).
    pub joint_records: Vec<(std::path::PathBuf, usize, f64)>,
}

fn progress(settings: &DiagnoseSettings, clock: &Instant, text: &str) {
    if settings.progress {
        eprintln!("diagnose [{:6.2} s]: {text}", clock.elapsed().as_secs_f64());
    }
}

/// Runs the whole diagnosis of the case at `path` (folder or case.json); writes nothing.
pub fn diagnose(path: &Path, settings: &DiagnoseSettings) -> Result<Outcome> {
    let clock = Instant::now();
    let case = read_case(path)?;
    let mut decays = case.measured_decays()?;
    if decays.is_empty() {
        return Err(TuneError::Invalid(format!(
            "{}: `records.decay` is missing or empty; expected at least one decay record \
             (`time_s,accel_m_s2`) to diagnose",
            case.file.display()
        )));
    }
    let mut warnings = Vec::new();
    // Every axial record is conditioned and checked; a surge record (the coil's own
    // mode) is not a decay of the weight on the spring and is left to `coil-tune damping`.
    let mut conditioned = Vec::new();
    for (k, record) in decays.drain(..).enumerate() {
        let info = case.decay_info.get(k);
        if info.is_some_and(|i| i.mode != crate::case::DecayMode::Axial) {
            warnings.push(format!(
                "{}: a surge-mode record is not a decay of the weight; diagnose leaves it to \
                 `coil-tune damping`",
                record.file.display()
            ));
            continue;
        }
        let data = data::condition_decay(record)?;
        data::check_amplitude(&data, &case)?;
        warnings.extend(data.warnings.iter().cloned());
        let mass_delta_kg = info
            .and_then(|i| i.mass_kg)
            .map_or(0.0, |m| m - case.mass_kg);
        conditioned.push((data, mass_delta_kg));
    }
    if conditioned.is_empty() {
        return Err(TuneError::Invalid(format!(
            "{}: `records.decay` holds no axial decay record (surge records are for \
             `coil-tune damping`); expected at least one",
            case.file.display()
        )));
    }
    let mut others = conditioned.split_off(1);
    let (decay, first_delta) = conditioned.remove(0);
    if first_delta != 0.0 {
        // The first record's weight is the reference the others' differ from.
        for o in &mut others {
            o.1 -= first_delta;
        }
    }
    let joint = Joint::lay_out(&decay, &others);
    let mut static_records = case.static_records()?;
    if static_records.len() > 1 {
        warnings.push(format!(
            "{} static records; only the first, {}, is used",
            static_records.len(),
            static_records[0].file.display()
        ));
    }
    let statics = match static_records.drain(..).next() {
        Some(record) => {
            let branch = data::check_static(&record)?;
            Some((record, branch))
        }
        None => None,
    };
    // Past the records' checks every failure is a model or fit failure: name the case.
    compute(case, decay, joint, statics, warnings, settings, clock).map_err(|e| match e {
        TuneError::InCase { .. } => e,
        other => TuneError::InCase {
            case: path.to_path_buf(),
            source: Box::new(other),
        },
    })
}

/// The case's decay records laid end to end for the joint fit (`fit::Segment`).
pub struct Joint {
    /// The records, each scaled by its segment's weight.
    pub measured: Vec<f64>,
    /// Their layout; the first is the diagnosed record ([`Outcome::decay`]).
    pub segments: Vec<fit::Segment>,
    /// The other records' files, in the segments' order after the first.
    pub files: Vec<std::path::PathBuf>,
}

impl Joint {
    /// The linear model's knobs: the mass and beta, and the spring's stiffness when the
    /// records were taken with different weights (two frequencies separate the two).
    fn knobs(&self) -> Vec<Knob> {
        let mut knobs = vec![Knob::Mass, Knob::Beta];
        if self.segments.iter().any(|s| s.mass_delta_kg != 0.0) {
            knobs.push(Knob::Stiffness);
        }
        knobs
    }

    /// Lays the first record and the others (each with its mass difference to the
    /// first's weight) end to end. The first record's own difference to the case's
    /// `mass_kg` is absorbed by the fitted mass.
    fn lay_out(first: &DecayData, others: &[(DecayData, f64)]) -> Joint {
        let floor = |d: &DecayData| {
            let rms = (d.measured.iter().map(|x| x * x).sum::<f64>()
                / d.measured.len().max(1) as f64)
                .sqrt();
            d.measured_noise.rms.max(1e-6 * rms).max(1e-300)
        };
        let reference = floor(first);
        let mut measured = Vec::new();
        let mut segments = Vec::new();
        let mut files = Vec::new();
        for (k, (d, delta)) in std::iter::once((first, 0.0))
            .chain(others.iter().map(|(d, m)| (d, *m)))
            .enumerate()
        {
            let weight = if k == 0 { 1.0 } else { reference / floor(d) };
            let start = measured.len();
            measured.extend(d.measured.iter().map(|x| weight * x));
            segments.push(fit::Segment {
                span: start..measured.len(),
                step_s: d.signal.step_s,
                quantity: d.quantity,
                mass_delta_kg: delta,
                weight,
            });
            if k > 0 {
                files.push(d.signal.source.clone());
            }
        }
        Joint {
            measured,
            segments,
            files,
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn compute(
    case: MeasuredCase,
    decay: DecayData,
    joint: Joint,
    statics: Option<(crate::case::StaticRecord, Range<usize>)>,
    mut warnings: Vec<String>,
    settings: &DiagnoseSettings,
    clock: Instant,
) -> Result<Outcome> {
    let n = decay.signal.values.len();
    let half = n / 2;
    let measured = decay.signal.values.clone();
    let step = decay.signal.step_s;

    progress(settings, &clock, "baseline (the paper's loops)");
    let static_fit = statics
        .as_ref()
        .map(|(r, b)| signatures::static_fit(r, b.clone()))
        .transpose()?;
    let k_measured = match (&static_fit, case.targets.stiffness_n_mm) {
        (Some(s), _) => s.linear_k_n_mm,
        (None, Some(k)) => k,
        (None, None) => crate::fe::static_stiffness(&SpringState::nominal(&case), &settings.fe)?.0,
    };
    let mut state = SpringState::nominal(&case);
    loops::tune_youngs_modulus(&mut state, &settings.fe, k_measured, 1e-6, None)?;
    let guided = ReducedSpring::build(&state, &settings.fe, Mount::Guided, settings.modes)?;

    let paper = |range: Range<usize>| -> Result<(Physical, f64, f64)> {
        let span = range.clone();
        let record = DecayRecord {
            time_s: decay.signal.time_s[range.clone()].to_vec(),
            accel_m_s2: measured[range].to_vec(),
        };
        let f_guess = decay.frequency_hz;
        // The paper's estimator after a zero-phase low-pass that keeps the axial mode;
        // a record whose crests carry jumps (dry friction reverses its force at every
        // crest) needs a lower cut-off before its crests are regular.
        // A short record (the forecast's first half of a 20-30 cycle decay) has too few
        // crests for spans of 10; spans of 5, then 3, keep the estimator's form.
        let mut attempt = Err(TuneError::Invalid("no decrement".into()));
        'search: for every in [10, 5, 3] {
            for factor in [5.0, 2.0, 1.4] {
                attempt = decay::measure(
                    &record,
                    &DecaySettings {
                        lowpass_hz: Some(factor * f_guess),
                        every,
                        ..DecaySettings::default()
                    },
                );
                if attempt.is_ok() {
                    break 'search;
                }
            }
        }
        let m = attempt.map_err(|e| {
            TuneError::Invalid(format!(
                "{}: the paper's logarithmic decrement fails on samples {}..{}: {e}",
                decay.signal.source.display(),
                span.start,
                span.end
            ))
        })?;
        let zeta = m.zeta_mean;
        let period_n = m.period_s * (1.0 - zeta * zeta).max(0.0).sqrt();
        let mut s = state;
        loops::tune_mass(&mut s, &settings.fe, period_n, 1e-6, None)?;
        let w = std::f64::consts::TAU / period_n;
        Ok((
            Physical::linear(s.mass_kg, 2.0 * zeta / w, case.gravity_m_s2),
            m.period_s,
            zeta,
        ))
    };
    let (base_phys, period_s, zeta) = paper(0..n)?;
    // A short record's first half may be too short for the decrement's filter (a 25-cycle
    // video record at 30 Hz): the baseline's forecast then starts from the whole
    // record's calibration, and the run says so.
    let half_phys = match paper(0..half) {
        Ok((p, _, _)) => p,
        Err(e) => {
            warnings.push(format!(
                "the paper's calibration fails on the first half ({e}); the baseline's \
                 forecast uses the whole record's calibration"
            ));
            base_phys
        }
    };
    let sigma = 1.0;
    let fit_target = &decay.measured;
    let quantity = decay.quantity;
    let linear_problem = |start: Physical, fraction: f64, knobs: Vec<Knob>| Problem {
        model: &guided,
        start,
        knobs,
        measured: &joint.measured,
        segments: &joint.segments,
        fraction,
        sigma,
        statics: None,
        initial_state: None,
    };
    let run = |p: &Problem<'_>| {
        fit::run(p, settings.max_iterations).map_err(|m| TuneError::Invalid(format!("fit: {m}")))
    };
    let baseline_full = run(&linear_problem(base_phys, 1.0, vec![]))?;
    let baseline_half = run(&linear_problem(half_phys, 0.5, vec![]))?;
    let baseline = model_run(baseline_full, baseline_half, &joint, &[]);

    progress(settings, &clock, "reference (linear model by output error)");
    // Continuation over growing windows (first quarter, first half, whole record): the
    // residual of an oscillator is nonlinear in its frequency through the phase it
    // accumulates, so a long window is fitted from a start that already holds the
    // phase; the quarter, half and three-quarter fits give the rolling forecasts.
    let knobs = joint.knobs();
    let quarter = run(&linear_problem(
        base_phys,
        select::ORIGINS[0],
        knobs.clone(),
    ))?;
    let reference_half = run(&linear_problem(quarter.physical, 0.5, knobs.clone()))?;
    let reference_full = run(&linear_problem(reference_half.physical, 1.0, knobs.clone()))?;
    let three = run(&linear_problem(
        reference_full.physical,
        select::ORIGINS[2],
        knobs,
    ))?;
    let rolling = [quarter, reference_half.clone(), three];
    let reference = model_run(reference_full, reference_half, &joint, &rolling);
    let noise = (reference.full.rss / joint.measured.len() as f64).sqrt();

    progress(settings, &clock, "signatures");
    let w_ref = std::f64::consts::TAU / period_s;
    let stiffness_n_m = guided.stiffness_n_m(&reference.full.physical);
    let free = ReducedSpring::build(&state, &settings.fe, Mount::FreeRotation, settings.modes)?;
    let (kz, c, kt) = free.boundary_stiffness(&reference.full.physical);
    let figures = BaselineFigures {
        mass_kg: reference.full.physical.mass_kg,
        stiffness_n_m,
        frequency_hz: 1.0 / period_s,
        // The largest displacement amplitude: peak acceleration over w^2.
        amplitude_m: measured.iter().fold(0.0_f64, |m, a| m.max(a.abs())) / (w_ref * w_ref),
        preload_m: reference.full.physical.mass_kg * case.gravity_m_s2 / stiffness_n_m,
        kz,
        c,
        kt,
    };
    let (sigs, spectrum) = signatures::compute(&decay, static_fit, &figures)?;

    let statics_block = statics
        .as_ref()
        .zip(static_fit.as_ref())
        .map(|((r, _), s)| StaticBlock {
            displacement_m: r.displacement_mm.iter().map(|x| x * 1e-3).collect(),
            force_n: r.force_n.clone(),
            sigma_n: s.cubic_rms_n.max(1e-12),
        });
    let job = Job {
        guided: &guided,
        free: &free,
        reference: &reference,
        joint: &joint,
        noise,
        statics: statics_block.as_ref(),
        static_fit: static_fit.as_ref(),
        max_iterations: settings.max_iterations,
        signatures: &sigs,
        figures: &figures,
    };
    let ctx = select::Context {
        reference: &reference,
        measured: &joint.measured,
        samples_per_period: 1.0 / (sigs.axial_hz.max(1e-9) * step),
    };

    // Every effect alone, in parallel (each fit's Jacobian columns run in parallel too).
    progress(settings, &clock, "candidates: each effect alone");
    let mut candidates: Vec<CandidateRun> = (0..effects::COUNT)
        .into_par_iter()
        .map(|i| {
            let proposal = CATALOGUE[i].propose(&sigs, &figures);
            let seeds: Vec<Physical> = proposal
                .starts
                .iter()
                .map(|&v| {
                    let mut p = job.base(&[i]);
                    p.effects[i] = v;
                    p
                })
                .collect();
            let init = reference.full.initial_state.clone();
            job.candidate(vec![i], proposal.evidence, &seeds, init)
        })
        .collect();
    // Combinations of the effects with evidence of their own, up to three: strong
    // evidence alone (dBIC above the limit), or a signature that agrees (an effect
    // masked alone by another one: friction or drag beside a softening drift, whose
    // phase error swamps their gain when fitted alone). Each combination starts from
    // its parts' fitted values.
    let mut gaining: Vec<(usize, f64)> = candidates
        .iter()
        .filter_map(|c| {
            select::score(&ctx, c)
                .filter(|s| s.delta_bic > select::DELTA_BIC || s.tests.signature.passed)
                .map(|s| (c.effects[0], s.delta_bic))
        })
        .collect();
    gaining.sort_by(|a, b| b.1.total_cmp(&a.1));
    gaining.truncate(MAX_COMBINED);
    let gaining: Vec<usize> = gaining.into_iter().map(|g| g.0).collect();
    let mut sets: Vec<Vec<usize>> = Vec::new();
    for (a, &i) in gaining.iter().enumerate() {
        for &j in &gaining[a + 1..] {
            sets.push(sorted(vec![i, j]));
        }
    }
    if !sets.is_empty() {
        progress(settings, &clock, "candidates: pairs of effects");
        let pairs: Vec<CandidateRun> = sets
            .par_iter()
            .map(|set| job.combined(set, &candidates))
            .collect();
        candidates.extend(pairs);
    }
    if gaining.len() >= 3 {
        progress(settings, &clock, "candidates: three effects");
        let triple = job.combined(&sorted(gaining.clone()), &candidates);
        candidates.push(triple);
    }

    let choice = select::choose(&ctx, &candidates);
    // The spectral noise floor of the recorded quantity (valid on band-limited
    // records, data.rs).
    let noise_abs = decay.measured_noise.rms;
    let noise_floor = noise_abs / (fit_target.iter().map(|a| a * a).sum::<f64>() / n as f64).sqrt();
    // Plausibility: what the calibration had to do to the nominal values, and a misfit
    // no catalogue effect explains.
    for (what, value, nominal) in [
        (
            "Young's modulus",
            state.youngs_modulus_mpa,
            case.material.youngs_modulus_mpa,
        ),
        ("the weight's mass", base_phys.mass_kg, case.mass_kg),
    ] {
        let ratio = value / nominal;
        if !(0.5..=2.0).contains(&ratio) {
            warnings.push(format!(
                "the calibrated {what} is {ratio:.3} times the nominal value in case.json; \
                 check the records' units (mm and N for static.csv, s and m/s^2 for decay.csv)"
            ));
        }
    }
    let unexplained = (choice.cause.is_none()
        && !matches!(
            reference
                .residual_rms
                .partial_cmp(&(UNEXPLAINED_NOISE * noise_floor)),
            Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
        ))
    .then(|| report::unexplained(&sigs, &reference, noise_floor, &candidates, &choice));
    for w in &warnings {
        progress(settings, &clock, &format!("warning: {w}"));
    }
    let k_source = match (&static_fit, case.targets.stiffness_n_mm) {
        (Some(_), _) => report::StiffnessSource::StaticRecord,
        (None, Some(_)) => report::StiffnessSource::Target,
        (None, None) => report::StiffnessSource::Nominal,
    };
    let diagnosis = report::assemble(
        &report::BaselineInputs {
            state: &state,
            physical: &base_phys,
            period_s,
            damping_ratio: zeta,
            stiffness_n_mm: guided.stiffness_n_m(&base_phys) * 1e-3,
            run: &baseline,
            stiffness_source: k_source,
        },
        &reference,
        &candidates,
        &choice,
        &sigs,
        noise_floor,
        unexplained,
        quantity,
        warnings,
        clock.elapsed().as_secs_f64(),
    );
    Ok(Outcome {
        case,
        decay,
        statics,
        signatures: sigs,
        spectrum,
        baseline,
        reference,
        candidates,
        diagnosis,
        modes: settings.modes,
        step_fraction: model::OMEGA_DT / std::f64::consts::TAU,
        stiffness_source: k_source,
        joint_records: joint
            .files
            .iter()
            .zip(&joint.segments[1..])
            .map(|(f, s)| (f.clone(), s.span.len(), s.mass_delta_kg))
            .collect(),
    })
}

/// The reference's residual RMS beyond which, with no cause named, the misfit is
/// reported as unexplained: three times the noise floor.
pub const UNEXPLAINED_NOISE: f64 = 3.0;

/// Most effects in one combination.
pub const MAX_COMBINED: usize = 3;

fn sorted(mut v: Vec<usize>) -> Vec<usize> {
    v.sort_unstable();
    v
}

/// A model's figures over every record: residual, the forecast of each record's second
/// half from the fit on the first halves, and the rolling forecasts of the quarter after
/// each origin from the fits up to it (`rolling`, one per origin; none for the baseline).
fn model_run(full: Fitted, half: Fitted, joint: &Joint, rolling: &[Fitted]) -> ModelRun {
    let measured = &joint.measured;
    if std::env::var_os("COIL_DIAGNOSE_TRACE").is_some() && joint.segments.len() > 1 {
        let each: Vec<String> = joint
            .segments
            .iter()
            .map(|s| {
                let r = fit::relative_rms(&full.simulated, measured, &[s.span.clone()]);
                format!("{r:.4}")
            })
            .collect();
        eprintln!("  residual_rms of each record: {}", each.join(", "));
    }
    let over = |f: &dyn Fn(&fit::Segment) -> Range<usize>| -> Vec<Range<usize>> {
        joint.segments.iter().map(f).collect()
    };
    ModelRun {
        residual_rms: fit::relative_rms(&full.simulated, measured, &[0..measured.len()]),
        forecast_rms: fit::relative_rms(&half.simulated, measured, &over(&|s| s.between(0.5, 1.0))),
        rolling: rolling
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let ranges = over(&|s| {
                    let o = s.window(select::ORIGINS[i]).end;
                    o..(o + s.span.len() / 4).min(s.span.end)
                });
                fit::relative_rms(&f.simulated, measured, &ranges)
            })
            .collect(),
        full,
        half,
    }
}

/// Levenberg-Marquardt iterations of each start's first-quarter fit.
const SEED_ITERATIONS: usize = 10;

/// What every candidate's fit shares.
struct Job<'a> {
    guided: &'a ReducedSpring,
    free: &'a ReducedSpring,
    reference: &'a ModelRun,
    joint: &'a Joint,
    noise: f64,
    statics: Option<&'a StaticBlock>,
    static_fit: Option<&'a evidence::StaticSummary>,
    max_iterations: usize,
    signatures: &'a Signatures,
    figures: &'a BaselineFigures,
}

impl Job<'_> {
    fn uses_static(set: &[usize]) -> bool {
        set.iter()
            .any(|&i| CATALOGUE[i].static_force(1.0, 1.0).is_some())
    }

    /// The reference's parameters, with the stiffness the set's static record gives.
    fn base(&self, set: &[usize]) -> Physical {
        let mut base = self.reference.full.physical;
        if let (true, Some(s)) = (Self::uses_static(set), self.static_fit) {
            // A cubic static fit's linear coefficient is the spring's stiffness at the
            // free length; the straight line's slope (the baseline's) is a secant.
            base.k_scale = s.k_n_mm / s.linear_k_n_mm;
        }
        base
    }

    fn model(&self, set: &[usize]) -> &ReducedSpring {
        if set
            .iter()
            .any(|&i| CATALOGUE[i].mount() == Mount::FreeRotation)
        {
            self.free
        } else {
            self.guided
        }
    }

    /// Fits the set of effects from `seeds` (and a starting initial state for a
    /// nonlinear model) and checks each effect's signature at the fitted values.
    fn candidate(
        &self,
        set: Vec<usize>,
        evidence: String,
        seeds: &[Physical],
        init: Vec<f64>,
    ) -> CandidateRun {
        let run = self.fit(&set, seeds, init);
        let signatures = run.as_ref().map_or(Vec::new(), |r| {
            set.iter()
                .map(|&i| {
                    CATALOGUE[i].signature(
                        self.signatures,
                        self.figures,
                        r.full.physical.effects[i],
                    )
                })
                .collect()
        });
        CandidateRun {
            effects: set,
            evidence,
            signatures,
            run,
        }
    }

    /// A combination, started from its parts' fitted values (the best part's mass,
    /// beta and initial state).
    fn combined(&self, set: &[usize], singles: &[CandidateRun]) -> CandidateRun {
        let mut seed = self.base(set);
        let mut best: Option<&ModelRun> = None;
        let mut evidence = Vec::new();
        for &i in set {
            let Some(single) = singles.iter().find(|c| c.effects == [i]) else {
                continue;
            };
            evidence.push(format!("{}: {}", CATALOGUE[i].name(), single.evidence));
            if let Ok(r) = &single.run {
                seed.effects[i] = r.full.physical.effects[i];
                if best.is_none_or(|b| r.full.rss < b.full.rss) {
                    best = Some(r);
                }
            }
        }
        let model = self.model(set);
        let states = 2 * if model.mount() == Mount::FreeRotation {
            2
        } else {
            1
        };
        // The initial state of a part fitted on the same mount (the coupling's carries
        // the rotation), else the best part's padded with a rotation at rest.
        let mut init = set
            .iter()
            .filter_map(|&i| singles.iter().find(|c| c.effects == [i]))
            .filter_map(|c| c.run.as_ref().ok())
            .map(|r| r.full.initial_state.clone())
            .find(|s| s.len() == states)
            .unwrap_or_else(|| {
                best.map_or(self.reference.full.initial_state.clone(), |b| {
                    b.full.initial_state.clone()
                })
            });
        // Every record's state padded the same way.
        let records = self.joint.segments.len();
        let per = init.len() / records.max(1);
        if per != states {
            init = init
                .chunks(per.max(1))
                .take(records)
                .flat_map(|c| {
                    let mut c = c.to_vec();
                    c.resize(states, 0.0);
                    c
                })
                .collect();
            init.resize(states * records, 0.0);
        }
        if let Some(b) = best {
            seed.mass_kg = b.full.physical.mass_kg;
            seed.beta_s = b.full.physical.beta_s;
        }
        self.candidate(set.to_vec(), evidence.join("; "), &[seed], init)
    }

    fn fit(
        &self,
        set: &[usize],
        seeds: &[Physical],
        init: Vec<f64>,
    ) -> std::result::Result<ModelRun, String> {
        let model = self.model(set);
        let nonlinear = seeds.iter().any(|s| model.is_nonlinear(s));
        let mut knobs: Vec<Knob> = set.iter().map(|&i| Knob::Effect(i)).collect();
        knobs.extend(self.joint.knobs());
        let statics = self.statics.filter(|_| Self::uses_static(set));
        let problem = |start: Physical, fraction: f64, init: Option<Vec<f64>>| Problem {
            model,
            start,
            knobs: knobs.clone(),
            measured: &self.joint.measured,
            segments: &self.joint.segments,
            fraction,
            sigma: self.noise.max(1e-300),
            statics,
            initial_state: init,
        };
        let state = |f: &Fitted| nonlinear.then(|| f.initial_state.clone());
        let first = nonlinear.then_some(init);
        // Each start is fitted on the first quarter for a few iterations (a seed only:
        // they tell a good start from a bad one); the best is fitted to convergence
        // there (the first rolling origin), then on the first half (the forecast's),
        // the whole record, and the first three quarters (the last rolling origin).
        let mut best: Option<Fitted> = None;
        let mut last_error = String::from("no starting value");
        for &start in seeds {
            let seed = fit::run(
                &problem(start, select::ORIGINS[0], first.clone()),
                self.max_iterations.min(SEED_ITERATIONS),
            );
            match seed {
                Ok(f) if best.as_ref().is_none_or(|b| f.rss < b.rss) => best = Some(f),
                Ok(_) => {}
                Err(e) => last_error = e,
            }
        }
        let seed = best.ok_or(last_error)?;
        let quarter = fit::run(
            &problem(seed.physical, select::ORIGINS[0], state(&seed)),
            self.max_iterations,
        )?;
        // The set nests the reference (its effects at zero): a fit that ends above the
        // reference's misfit on the same window lost the phase on the way from the
        // shorter window (a short record, a strong drift). It restarts from the
        // reference's mass, beta and initial state with the first quarter's effect
        // values, and keeps the better of the two.
        let rescue = |fitted: Fitted, fraction: f64, reference: &Fitted| -> Fitted {
            if fitted.rss <= reference.rss {
                return fitted;
            }
            let mut restart = self.base(set);
            for &i in set {
                restart.effects[i] = quarter.physical.effects[i];
            }
            let init = nonlinear.then(|| reference.initial_state.clone());
            match fit::run(&problem(restart, fraction, init), self.max_iterations) {
                Ok(again) if again.rss < fitted.rss => again,
                _ => fitted,
            }
        };
        let half_fit = fit::run(
            &problem(quarter.physical, 0.5, state(&quarter)),
            self.max_iterations,
        )?;
        let half_fit = rescue(half_fit, 0.5, &self.reference.half);
        let full = fit::run(
            &problem(half_fit.physical, 1.0, state(&half_fit)),
            self.max_iterations,
        )?;
        let full = rescue(full, 1.0, &self.reference.full);
        let three = fit::run(
            &problem(full.physical, select::ORIGINS[2], state(&full)),
            self.max_iterations,
        )?;
        if std::env::var_os("COIL_DIAGNOSE_TRACE").is_some() {
            eprintln!(
                "  {:?}: full {} iterations {} runs, half {} iterations {} runs",
                set, full.iterations, full.evaluations, half_fit.iterations, half_fit.evaluations
            );
        }
        let mut rolling = [quarter, half_fit, three];
        let first = model_run(full.clone(), rolling[1].clone(), self.joint, &rolling);
        // A window's fit whose forecast misses may sit in another local minimum of its
        // own objective than the whole record's (a short record: the mass and the
        // effect trade off over a few cycles). It is fitted again from the whole
        // record's values and kept only if that lowers its own window's misfit: a
        // better optimum of the same objective, chosen without the held-out samples.
        let mut changed = false;
        for (i, window) in rolling.iter_mut().enumerate() {
            let missed = first.rolling[i] > select::FORECAST_RATIO * self.reference.rolling[i];
            if !missed {
                continue;
            }
            let again = fit::run(
                &problem(full.physical, select::ORIGINS[i], state(&full)),
                self.max_iterations,
            );
            if let Some(again) = again.ok().filter(|a| a.rss < window.rss) {
                *window = again;
                changed = true;
            }
        }
        if !changed {
            return Ok(first);
        }
        Ok(model_run(full, rolling[1].clone(), self.joint, &rolling))
    }
}

/// Writes the outcome into `out` (locked by the caller for the whole run): figures,
/// tables, report.md and diagnosis.json, committed as one set.
pub fn write(
    outcome: &Outcome,
    out: &crate::output::OutDir,
    settings: &DiagnoseSettings,
) -> Result<()> {
    report::write(outcome, out, settings.plots)
}

/// Parameters in SI by the spec's names, of the effects in `set`.
pub fn parameters(set: &[usize], phys: &Physical) -> BTreeMap<String, f64> {
    set.iter()
        .map(|&i| (CATALOGUE[i].parameter().to_string(), phys.effects[i]))
        .collect()
}

/// A few lines for the terminal.
pub fn summary(o: &Outcome) -> String {
    let d = &o.diagnosis;
    let mut s = format!(
        "baseline: E = {:.1} MPa, mass = {:.5} kg, beta = {:.4e} s, K = {:.5} N/mm, T = {:.6} s, \
         zeta = {:.6}, residual_rms = {:.4}, forecast_rms = {:.4}\n",
        d.baseline.youngs_modulus_mpa,
        d.baseline.mass_kg,
        d.baseline.rayleigh_beta,
        d.baseline.stiffness_n_mm,
        d.baseline.period_s,
        d.baseline.damping_ratio,
        d.baseline.residual_rms,
        d.baseline.forecast_rms
    );
    for c in &d.candidates {
        let line = format!(
            "  {:<26} residual_rms {:>8} forecast_rms {:>8} dBIC {:>10} {}",
            c.effect,
            c.residual_rms.map_or("-".into(), |x| format!("{x:.4}")),
            c.forecast_rms.map_or("-".into(), |x| format!("{x:.4}")),
            c.delta_bic.map_or("-".into(), |x| format!("{x:.1}")),
            if c.significant { "significant" } else { "" }
        );
        s.push_str(line.trim_end());
        s.push('\n');
    }
    s.push_str(&format!("cause: {}", d.cause));
    if let (Some(e), g) = (&d.extended, &d.gain) {
        for (k, v) in &e.parameters {
            s.push_str(&format!(", {k} = {v:.6e}"));
        }
        s.push_str(&format!(
            "; gain: residual_rms_ratio {:.4}, forecast_rms_ratio {:.4}",
            g.residual_rms_ratio, g.forecast_rms_ratio
        ));
    }
    s.push_str(&format!(" ({:.2} s)\n", d.runtime_s));
    s
}
