//! `coil-tune diagnose`: from measured records to what the paper's model gets wrong,
//! its physical cause, the extended model and the gain (`docs/measured-case.md`,
//! docs/diagnose.md).
//!
//! # Steps
//! 1. **Records** are read and checked ([`data`]) before anything is computed; nothing
//!    is written unless the whole diagnosis succeeds, and then every file goes through
//!    a temporary name ([`write()`]).
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
pub mod document;
pub mod effects;
pub mod evidence;
pub mod fit;
pub mod halfcycle;
pub mod law_evidence;
pub mod lm;
pub mod model;
pub mod outcome;
pub mod plots;
pub mod report;
pub mod run;
pub mod search;
pub mod select;
pub mod signatures;

pub use outcome::{summary, Outcome};
pub use report::UNEXPLAINED_NOISE;
pub use run::{parameters, CandidateRun, Joint, ModelRun};
pub use search::MAX_COMBINED;

use crate::case::{read_case, MeasuredCase};
use crate::decay::{self, DecayRecord, DecaySettings};
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use crate::loops;
use data::DecayData;
use effects::{BaselineFigures, Mount};
use fit::{Knob, Problem, StaticBlock};
use model::{Physical, ReducedSpring};
use std::f64::consts::LN_2;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

/// Settings of a diagnosis.
#[derive(Debug, Clone)]
pub struct DiagnoseSettings {
    /// FE settings of the spring's model for the paper's loops and the reduction.
    pub fe: FeSettings,
    /// Fixed-interface modes kept beside the weight's DOFs.
    pub modes: usize,
    /// Levenberg-Marquardt iterations per fit.
    pub max_iterations: usize,
    /// Draw the figures.
    pub plots: bool,
    /// Progress on stderr.
    pub progress: bool,
    /// Also write the fits as `fits.uff` (UFF dataset 58, ASCII or 58b).
    pub fits_uff: Option<coil_io::uff::UffForm>,
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
            fits_uff: None,
        }
    }
}

fn progress(settings: &DiagnoseSettings, clock: &Instant, text: &str) {
    if settings.progress {
        eprintln!("diagnose [{:6.2} s]: {text}", clock.elapsed().as_secs_f64());
    }
}

/// Most fixed-interface modes of the reduced model. The axial frequency has converged
/// to 1e-7 with 4 (docs/diagnose.md, section 4); each step costs about `(modes + 2)^2`,
/// so 8 modes take about three times the default's time, and more would break the
/// 15 s budget while changing no fitted figure.
pub const MAX_MODES: usize = 8;

/// Runs the whole diagnosis of the case at `path` (folder or case.json); writes nothing.
pub fn diagnose(path: &Path, settings: &DiagnoseSettings) -> Result<Outcome> {
    let clock = Instant::now();
    if settings.modes > MAX_MODES {
        return Err(TuneError::Invalid(format!(
            "{} fixed-interface modes; expected 0 to {MAX_MODES} (the axial frequency has converged to 1e-7 with the default 4, and the time grows with the square of the modes)",
            settings.modes
        )));
    }
    let case = read_case(path)?;
    let mut decays = case.measured_decays_with_format()?;
    if decays.is_empty() {
        return Err(TuneError::Invalid(format!(
            "{}: `records.decay` is missing or empty; expected at least one decay record \
             (`time_s,accel_m_s2`) to diagnose",
            case.file.display()
        )));
    }
    let mut warnings = Vec::new();
    let decays: Vec<crate::case::MeasuredDecay> = decays
        .drain(..)
        .map(|(decay, format)| {
            warnings.extend(crate::case::format_note(&decay.file, &format));
            decay
        })
        .collect();
    // Every axial record is conditioned and checked; a surge record (the coil's own
    // mode) is not a decay of the weight on the spring and is left to `coil-tune damping`.
    let mut conditioned = Vec::new();
    for (k, record) in decays.into_iter().enumerate() {
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
        warnings.extend(case.unit_warning(data.signal.values(), data.frequency_hz));
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
    let n = decay.signal.values().len();
    let measured = decay.signal.values().to_vec();
    let step = decay.signal.step_s();

    progress(settings, &clock, "baseline (the paper's loops)");
    let Calibration {
        static_fit,
        state,
        guided,
        base_phys,
        half_phys,
        period_s,
        zeta,
    } = calibrate(&case, &decay, statics.as_ref(), settings, &mut warnings)?;
    let fit_target = &decay.measured;
    let quantity = decay.quantity;
    progress(settings, &clock, "reference (linear model by output error)");
    let (baseline, reference) = linear_fits(&guided, &joint, base_phys, half_phys, settings)?;
    let noise = (reference.full.rss / joint.measured.len() as f64).sqrt();

    progress(settings, &clock, "signatures");
    let free = ReducedSpring::build(&state, &settings.fe, Mount::FreeRotation, settings.modes)?;
    let figures = baseline_figures(&guided, &free, &reference, &measured, period_s, &case);
    let (sigs, spectrum) = signatures::compute(&decay, static_fit, &figures)?;

    let statics_block = statics
        .as_ref()
        .zip(static_fit.as_ref())
        .map(|((r, _), s)| StaticBlock {
            displacement_m: r.displacement_mm.iter().map(|x| x * 1e-3).collect(),
            force_n: r.force_n.clone(),
            sigma_n: s.cubic_rms_n.max(1e-12),
        });
    let job = search::Job {
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
        decrement_beta_s: baseline.full.physical.beta_s,
    };
    let ctx = select::Context {
        reference: &reference,
        measured: &joint.measured,
        samples_per_period: 1.0 / (sigs.axial_hz.max(1e-9) * step),
    };

    let candidates = search::candidates(&job, &ctx, &|text| progress(settings, &clock, text));
    let choice = select::choose(&ctx, &candidates);
    // The spectral noise floor of the recorded quantity (valid on band-limited
    // records, data/mod.rs).
    let noise_abs = decay.measured_noise.rms;
    let noise_floor = noise_abs / (fit_target.iter().map(|a| a * a).sum::<f64>() / n as f64).sqrt();
    plausibility(&state, &base_phys, &case, &mut warnings);
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
    let k_source =
        report::StiffnessSource::of(static_fit.is_some(), case.targets.stiffness_n_mm.is_some());
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
        joint_records: joint.others(),
    })
}

/// The paper's model calibrated to the records (module docs, step 2): the static fit,
/// the spring at the calibrated E and its guided reduced model, the linear model on the
/// whole record and on its first half, the decrement's damped period and zeta.
struct Calibration {
    static_fit: Option<evidence::StaticSummary>,
    state: SpringState,
    guided: ReducedSpring,
    base_phys: Physical,
    half_phys: Physical,
    period_s: f64,
    zeta: f64,
}

/// The baseline's calibration ([`Calibration`]): E from the static record's stiffness
/// (or the case's target, or the nominal spring's), then the paper's decrement and
/// mass loop on the moving part of the record and on its first half.
fn calibrate(
    case: &MeasuredCase,
    decay: &DecayData,
    statics: Option<&(crate::case::StaticRecord, Range<usize>)>,
    settings: &DiagnoseSettings,
    warnings: &mut Vec<String>,
) -> Result<Calibration> {
    let n = decay.signal.values().len();
    let static_fit = statics
        .map(|(r, b)| signatures::static_fit(r, b.clone()))
        .transpose()?;
    let k_measured = match (&static_fit, case.targets.stiffness_n_mm) {
        (Some(s), _) => s.linear_k_n_mm,
        (None, Some(k)) => k,
        (None, None) => crate::fe::static_stiffness(&SpringState::nominal(case), &settings.fe)?.0,
    };
    let mut state = SpringState::nominal(case);
    loops::tune_youngs_modulus(&mut state, &settings.fe, k_measured, 1e-6, None)?;
    let guided = ReducedSpring::build(&state, &settings.fe, Mount::Guided, settings.modes)?;

    let paper = |range: Range<usize>| paper_calibration(decay, range, &state, case, settings);
    // A decay that sticks (dry friction) rests after its last crest: the paper's
    // decrement reads the crests while the weight moves, not the sensor's noise after.
    let moving = moving_samples(decay);
    if moving < n {
        warnings.push(format!(
            "the oscillation stops at {:.3} s ({} of {n} samples): the weight rests after its \
             last crest, and the paper's decrement reads the crests before it",
            decay.signal.time_s()[moving - 1],
            moving
        ));
    }
    let (base_phys, period_s, zeta) = paper(0..moving)?;
    let half_phys = first_half(paper(0..(n / 2).min(moving)), base_phys, warnings);
    Ok(Calibration {
        static_fit,
        state,
        guided,
        base_phys,
        half_phys,
        period_s,
        zeta,
    })
}

/// The paper's calibration on the first half, for the baseline's forecast; the whole
/// record's (with a warning) when the first half gives none or an implausible one.
fn first_half(
    attempt: Result<(Physical, f64, f64)>,
    base_phys: Physical,
    warnings: &mut Vec<String>,
) -> Physical {
    // A short record's first half may be too short for the decrement's filter (a 25-cycle
    // video record at 30 Hz): the baseline's forecast then starts from the whole
    // record's calibration, and the run says so.
    match attempt {
        // A first half of a few cycles can give the decrement a negative damping or
        // a period far from the whole record's: no calibration to forecast from.
        Ok((p, _, z)) if z <= 0.0 || (p.mass_kg / base_phys.mass_kg).ln().abs() > LN_2 => {
            warnings.push(format!(
                "the paper's calibration on the first half gives zeta = {z:.3e} and a mass of \
                 {:.4} kg against {:.4} kg on the whole record; the baseline's forecast uses \
                 the whole record's calibration",
                p.mass_kg, base_phys.mass_kg
            ));
            base_phys
        }
        Ok((p, _, _)) => p,
        Err(e) => {
            warnings.push(format!(
                "the paper's calibration fails on the first half ({e}); the baseline's \
                 forecast uses the whole record's calibration"
            ));
            base_phys
        }
    }
}

/// What the effects read of the calibrated linear reference (`effects::BaselineFigures`).
fn baseline_figures(
    guided: &ReducedSpring,
    free: &ReducedSpring,
    reference: &ModelRun,
    measured: &[f64],
    period_s: f64,
    case: &MeasuredCase,
) -> BaselineFigures {
    let w_ref = std::f64::consts::TAU / period_s;
    let stiffness_n_m = guided.stiffness_n_m(&reference.full.physical);
    let (kz, c, kt) = free.boundary_stiffness(&reference.full.physical);
    BaselineFigures {
        mass_kg: reference.full.physical.mass_kg,
        stiffness_n_m,
        frequency_hz: 1.0 / period_s,
        // The largest displacement amplitude: peak acceleration over w^2.
        amplitude_m: measured.iter().fold(0.0_f64, |m, a| m.max(a.abs())) / (w_ref * w_ref),
        preload_m: reference.full.physical.mass_kg * case.gravity_m_s2 / stiffness_n_m,
        damping_ratio: 0.5 * reference.full.physical.beta_s * w_ref,
        kz,
        c,
        kt,
    }
}

/// The linear model on every record: the baseline (the paper's calibration on the whole
/// record and on its first half, only the initial states fitted) and the reference (the
/// same model with mass and beta, and the stiffness for records at several weights,
/// fitted by output error).
fn linear_fits(
    guided: &ReducedSpring,
    joint: &Joint,
    base_phys: Physical,
    half_phys: Physical,
    settings: &DiagnoseSettings,
) -> Result<(ModelRun, ModelRun)> {
    let sigma = 1.0;
    let linear_problem = |start: Physical, fraction: f64, knobs: Vec<Knob>| Problem {
        model: guided,
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
    let baseline = run::model_run(baseline_full, baseline_half, joint, &[]);

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
    let reference = run::model_run(reference_full, reference_half, joint, &rolling);
    Ok((baseline, reference))
}

/// Plausibility: what the calibration had to do to the nominal values (a factor beyond
/// two is a unit slip more often than a material).
fn plausibility(
    state: &SpringState,
    base_phys: &Physical,
    case: &MeasuredCase,
    warnings: &mut Vec<String>,
) {
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
}

/// The paper's calibration on `range` of the first record: T and zeta by the
/// logarithmic decrement, the weight's mass by loop 2 on the FE model of `state`;
/// returns the linear model (beta = 2 zeta / w), the damped period and zeta.
/// The samples up to a quarter period after the record's last crest
/// ([`halfcycle::crests`]) when the motion stopped there (the weight sticks) and rests
/// for more than two periods after it; else the whole record.
fn moving_samples(decay: &DecayData) -> usize {
    let s = &decay.signal;
    let n = s.values().len();
    let crests = halfcycle::crests(s.values(), s.step_s(), decay.frequency_hz, decay.noise.rms);
    let period = 1.0 / (decay.frequency_hz * s.step_s());
    let Some(&last) = crests.time_s.last() else {
        return n;
    };
    let end = ((last - s.time_s()[0]) / s.step_s() + 0.25 * period).ceil() as usize;
    if crests.stopped && (n as f64 - end as f64) > 2.0 * period {
        end.min(n)
    } else {
        n
    }
}

fn paper_calibration(
    decay: &DecayData,
    range: Range<usize>,
    state: &SpringState,
    case: &MeasuredCase,
    settings: &DiagnoseSettings,
) -> Result<(Physical, f64, f64)> {
    let measured = &decay.signal.values();
    let span = range.clone();
    let record = DecayRecord {
        time_s: decay.signal.time_s()[range.clone()].to_vec(),
        accel_m_s2: measured[range].to_vec(),
    };
    let f_guess = decay.frequency_hz;
    // The paper's estimator after a zero-phase low-pass that keeps the axial mode;
    // a record whose crests carry jumps (dry friction reverses its force at every
    // crest) needs a lower cut-off before its crests are regular.
    // A short record (an 8-cycle decay, or the forecast's first half of one) has too
    // few crests for spans of 10; spans of 5, 3, 2, then 1 keep the estimator's form.
    let mut attempt = Err(TuneError::Invalid("no decrement".into()));
    'search: for every in [10, 5, 3, 2, 1] {
        for factor in [5.0, 2.0, 1.4] {
            attempt = decay::measure(
                &record,
                &DecaySettings {
                    lowpass_hz: Some(factor * f_guess),
                    every,
                    ..DecaySettings::default()
                },
            );
            // A decrement whose period disagrees with the record's zero-crossing rate
            // by more than 30 %, or whose damping is not positive, read noise as crests
            // (a decay that sticks and rests); the next settings are tried.
            match &attempt {
                Ok(m) if m.zeta_mean > 0.0 && (m.period_s * f_guess - 1.0).abs() < 0.3 => {
                    break 'search;
                }
                Ok(m) => {
                    attempt = Err(TuneError::Invalid(format!(
                        "period {:.4} s against the zero crossings' {:.4} s, zeta {:.3e}",
                        m.period_s,
                        1.0 / f_guess,
                        m.zeta_mean
                    )))
                }
                Err(_) => {}
            }
        }
    }
    let m = attempt.map_err(|e| {
        TuneError::Invalid(format!(
            "{}: the paper's logarithmic decrement fails on samples {}..{}: {e}",
            decay.signal.source().display(),
            span.start,
            span.end
        ))
    })?;
    let zeta = m.zeta_mean;
    let period_n = m.period_s * (1.0 - zeta * zeta).max(0.0).sqrt();
    let mut s = *state;
    loops::tune_mass(&mut s, &settings.fe, period_n, 1e-6, None)?;
    let w = std::f64::consts::TAU / period_n;
    Ok((
        Physical::linear(s.mass_kg, 2.0 * zeta / w, case.gravity_m_s2),
        m.period_s,
        zeta,
    ))
}

/// Writes the outcome into `out` (locked by the caller for the whole run): figures,
/// tables, report.md and diagnosis.json (and `fits.uff` when asked), committed as one set.
pub fn write(
    outcome: &Outcome,
    out: &crate::output::OutDir,
    settings: &DiagnoseSettings,
) -> Result<()> {
    if let Some(form) = settings.fits_uff {
        out.write("fits.uff", &document::fits_uff(outcome, form))?;
    }
    document::write(outcome, out, settings.plots)
}
