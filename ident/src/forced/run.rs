//! The diagnosis of forced records: the linear oscillator by output error, then each
//! effect of the catalogue refitted with it and judged by the same four tests as the decay
//! diagnosis (docs/diagnose.md, section 6; docs/forced.md):
//!
//! 1. **significance**: `dBIC = N_eff ln(S_lin / S) - ln(N_eff) > 10`, `N_eff` the
//!    candidate's residual count shrunk by their lag-one correlation `r`,
//!    `N (1 - r) / (1 + r)` (output-error residuals are coloured);
//! 2. **forecast**: the candidate must forecast better than the linear model does: each
//!    record by the fit on the others when there are two or more, else the next quarter
//!    of the record by fits on its first quarter, half and three quarters
//!    (`fit::forecast` says why records first);
//! 3. **identified**: its parameter three standard errors from zero (the errors inflated by
//!    `sqrt(N / N_eff)`), and admissible (no negative friction or drag);
//! 4. **signature**: on a displacement output, the linear model's force residual regressed
//!    on the effect's term beside its linear counterpart (module `frf`) has the fitted sign
//!    with `|t| >= 2`; on other outputs the test is not available and says so.
//!
//! A case that gives a `spring` is fitted on its reduced FE model (module `super::spring`):
//! the lumped oscillator's linear start gives the spring's first parameters (the mass from
//! the gain, the stiffness scale from the frequency, beta from the damping), and every fit
//! after it is the spring's. Its records must be in SI units (the FE model is physical).
//!
//! The cause is the passing candidate of largest `dBIC`; two passing effects are then
//! fitted together and kept when the pair gains another 10 BIC units with both parameters
//! identified. `none` otherwise, with what the records show in `unexplained`.

use super::fit::{self, Effect, Fitted, Series, Setup};
use super::frf;
use super::model::{ForcedModel, OutputQuantity};
use super::records::{read_forced_case, ForcedCase};
use super::simulate;
use super::spring::SpringStructure;
use crate::error::{Result, TuneError};
use std::path::Path;
use std::time::Instant;

/// Settings of a forced diagnosis.
#[derive(Debug, Clone)]
pub struct ForcedSettings {
    /// Levenberg-Marquardt iterations per fit.
    pub max_iterations: usize,
    /// Draw the figures.
    pub plots: bool,
    /// Progress on stderr.
    pub progress: bool,
}

impl Default for ForcedSettings {
    fn default() -> Self {
        ForcedSettings {
            max_iterations: 60,
            plots: true,
            progress: false,
        }
    }
}

/// The four tests of a candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct Tests {
    /// dBIC > 10.
    pub significant: bool,
    /// Forecasts better than the linear model.
    pub forecasts: bool,
    /// Parameters identified and admissible.
    pub identified: bool,
    /// The signature in the records, `None` where it cannot be measured.
    pub signature: Option<bool>,
}

impl Tests {
    /// Every test passed (an unavailable signature does not block).
    pub fn pass(&self) -> bool {
        self.significant && self.forecasts && self.identified && self.signature != Some(false)
    }
}

/// A candidate extension.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The effects fitted (one, or a pair).
    pub effects: Vec<Effect>,
    /// The fit (`None` when it failed, with the reason in `evidence`).
    pub fitted: Option<Fitted>,
    /// Residual RMS relative to the measured output's RMS.
    pub residual_rms: f64,
    /// Forecast RMS (relative).
    pub forecast_rms: f64,
    /// dBIC against the linear model.
    pub dbic: f64,
    /// The four tests.
    pub tests: Tests,
    /// What was seen, in words.
    pub evidence: String,
}

/// A finished forced diagnosis.
#[derive(Debug, Clone)]
pub struct ForcedOutcome {
    /// The case.
    pub case: ForcedCase,
    /// The linear model by output error.
    pub baseline: Fitted,
    /// Its forecast RMS (relative).
    pub baseline_forecast: f64,
    /// Its residual RMS (relative).
    pub baseline_residual: f64,
    /// The candidates: the single effects, then a pair if one was tried.
    pub candidates: Vec<Candidate>,
    /// The chosen candidate.
    pub cause: Option<usize>,
    /// H1 per input level (of the measured records).
    pub levels: Vec<frf::LevelFrf>,
    /// Warnings for the report.
    pub warnings: Vec<String>,
    /// What the records show when no cause is named.
    pub unexplained: Option<String>,
    /// Wall time, s.
    pub seconds: f64,
}

impl ForcedOutcome {
    /// The extended model (the cause's fit) or the baseline.
    pub fn extended(&self) -> &Fitted {
        self.cause
            .and_then(|i| self.candidates[i].fitted.as_ref())
            .unwrap_or(&self.baseline)
    }
}

fn series_of(case: &ForcedCase) -> Vec<Series<'_>> {
    case.records
        .iter()
        .map(|r| Series {
            dt: r.dt,
            input: &r.input,
            output: &r.output,
        })
        .collect()
}

fn relative(fitted: &Fitted, series: &[Series<'_>]) -> f64 {
    let total: f64 = series
        .iter()
        .flat_map(|s| s.output.iter())
        .map(|y| y * y)
        .sum();
    (fitted.cost / total.max(1e-300)).sqrt()
}

/// Effective count of residuals: `N (1 - r) / (1 + r)` per record, `r` the lag-one
/// correlation (at least 1 per record).
fn effective_count(fitted: &Fitted) -> f64 {
    fitted
        .residuals
        .iter()
        .map(|r| {
            let n = r.len() as f64;
            let c0: f64 = r.iter().map(|x| x * x).sum();
            let c1: f64 = r.windows(2).map(|w| w[0] * w[1]).sum();
            let rho = if c0 > 0.0 {
                (c1 / c0).clamp(0.0, 0.999)
            } else {
                0.0
            };
            (n * (1.0 - rho) / (1.0 + rho)).max(1.0)
        })
        .sum()
}

fn note(progress: bool, text: &str) {
    if progress {
        eprintln!("{text}");
    }
}

/// Diagnoses the forced records of the case at `path`.
pub fn diagnose_forced(path: &Path, settings: &ForcedSettings) -> Result<ForcedOutcome> {
    let case = read_forced_case(path)?;
    diagnose_case(case, settings)
}

/// Diagnoses forced records already read (a case built in memory: part of a record held
/// out, say).
pub fn diagnose_case(case: ForcedCase, settings: &ForcedSettings) -> Result<ForcedOutcome> {
    let started = Instant::now();
    let first = &case.records[0].entry;
    for r in &case.records[1..] {
        let e = &r.entry;
        if (
            e.input_quantity,
            e.output_quantity,
            &e.input_unit,
            &e.output_unit,
        ) != (
            first.input_quantity,
            first.output_quantity,
            &first.input_unit,
            &first.output_unit,
        ) {
            return Err(TuneError::Invalid(format!(
                "{}: the forced records `{}` and `{}` measure different quantities or units; \
                 expected every forced record of a case to share its input and output \
                 quantities and units",
                case.file.display(),
                first.file.display(),
                e.file.display()
            )));
        }
    }
    let mut warnings: Vec<String> = case
        .records
        .iter()
        .filter(|r| !r.format.starts_with("CSV: delimiter ',', decimal point"))
        .map(|r| format!("{}: read as {}", r.entry.file.display(), r.format))
        .collect();
    let spring = if case.has_spring {
        check_si_units(&case)?;
        warnings.push(
            "the case gives a spring: its forced records drive the reduced FE model (the \
             weight guided along the axis, so the axial-torsional coupling is not a candidate \
             on forced records; gravity only sets the static position the law acts about)"
                .into(),
        );
        Some(SpringStructure::build(&case.file, first.input_quantity)?)
    } else {
        None
    };
    let spring = spring.as_ref();
    let fail = |e: String| TuneError::InCase {
        case: case.file.clone(),
        source: Box::new(TuneError::Invalid(e)),
    };
    let setup = Setup {
        input: first.input_quantity,
        output: first.output_quantity,
        base_mass: case.mass_kg,
    };
    let units = (first.input_unit.as_str(), first.output_unit.as_str());
    let series = series_of(&case);
    let (mut start, initial, mut scales) =
        fit::linear_start(&series, &setup, units).map_err(fail)?;
    if let Some(s) = spring {
        start = spring_start(s, &start, &series, &mut scales).map_err(fail)?;
    }
    note(settings.progress, "forced: linear model by output error");
    let mut baseline = fit::fit(
        &series,
        &start,
        &initial,
        &scales,
        &[],
        settings.max_iterations,
        spring,
    )
    .map_err(fail)?;
    scales.z = baseline_scale(&baseline, &series);
    let baseline_forecast =
        fit::forecast(&series, &baseline, &[], settings.max_iterations, spring).map_err(fail)?;
    let baseline_residual = relative(&baseline, &series);
    baseline.scales = scales;

    let mut candidates: Vec<Candidate> = Vec::new();
    for effect in Effect::ALL {
        note(
            settings.progress,
            &format!("forced: candidate {}", effect.name()),
        );
        candidates.push(candidate(
            &series,
            &case,
            &baseline,
            baseline_forecast,
            &[effect],
            settings,
            spring,
        ));
    }
    let mut order: Vec<usize> = (0..candidates.len())
        .filter(|&i| candidates[i].tests.pass())
        .collect();
    order.sort_by(|&a, &b| candidates[b].dbic.total_cmp(&candidates[a].dbic));
    let mut cause = order.first().copied();
    if order.len() >= 2 {
        let pair = vec![
            candidates[order[0]].effects[0],
            candidates[order[1]].effects[0],
        ];
        note(
            settings.progress,
            "forced: the two passing effects together",
        );
        let c = candidate(
            &series,
            &case,
            &baseline,
            baseline_forecast,
            &pair,
            settings,
            spring,
        );
        let best = candidates[order[0]].dbic;
        let keep = c.tests.pass() && c.dbic > best + 10.0;
        candidates.push(c);
        if keep {
            cause = Some(candidates.len() - 1);
        }
    }
    let records: Vec<(f64, &[f64], &[f64])> =
        series.iter().map(|s| (s.dt, s.input, s.output)).collect();
    let levels = frf::levels(&records);
    let unexplained = match cause {
        Some(_) => None,
        None => Some(unexplained(&baseline, &series, &levels)),
    };
    Ok(ForcedOutcome {
        case,
        baseline,
        baseline_forecast,
        baseline_residual,
        candidates,
        cause,
        levels,
        warnings,
        unexplained,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// Records of a spring case must be in SI units: the input in N (force) or m/s^2 (base
/// acceleration), the output in m, m/s or m/s^2 as its quantity says.
fn check_si_units(case: &ForcedCase) -> Result<()> {
    for r in &case.records {
        let e = &r.entry;
        let input_ok = match e.input_quantity {
            super::model::InputQuantity::Force => e.input_unit.trim() == "N",
            super::model::InputQuantity::BaseAcceleration => {
                coil_postproc::record::units::parse(&e.input_unit).is_some_and(|u| {
                    u.quantity == coil_postproc::record::units::Quantity::Acceleration
                        && u.to_si == 1.0
                })
            }
        };
        let output_ok = coil_postproc::record::units::parse(&e.output_unit)
            .is_some_and(|u| u.quantity.name() == e.output_quantity.name() && u.to_si == 1.0);
        if !(input_ok && output_ok) {
            return Err(TuneError::Invalid(format!(
                "{}: the forced record `{}` states input_unit \"{}\" and output_unit \"{}\"; \
                 a case with a `spring` drives its physical FE model, so expected SI units: \
                 \"N\" for a force or \"m/s^2\" for a base acceleration in, and \"m\", \"m/s\" \
                 or \"m/s^2\" out (as output_quantity says)",
                case.file.display(),
                e.file.display(),
                coil_io::excerpt(&e.input_unit),
                coil_io::excerpt(&e.output_unit)
            )));
        }
    }
    Ok(())
}

/// The spring model that starts the fits: the lumped start's frequency, damping and gain
/// matched by the spring's parameters, its offset, friction velocity and sub-steps for
/// the spring's stiffest mode.
fn spring_start(
    spring: &SpringStructure,
    lumped: &super::model::ForcedModel,
    series: &[Series<'_>],
    scales: &mut fit::Scales,
) -> std::result::Result<super::model::ForcedModel, String> {
    let o = &lumped.oscillator;
    let p = spring.matching(o.natural_frequency_rad_s, o.damping_ratio, o.input_gain)?;
    let mut structural = vec![p.k_scale.ln(), p.beta_s.max(1e-12).ln()];
    if spring.input == super::model::InputQuantity::Force {
        structural.push((p.mass_kg / spring.nominal_mass_kg).ln());
    }
    let model = fit::spring_model(spring, lumped, &structural)?;
    let dt = series.iter().map(|s| s.dt).fold(0.0, f64::max);
    let w = model.oscillator.natural_frequency_rad_s;
    scales.substeps = simulate::substeps(&model.oscillator, dt, scales.z, w * scales.z);
    Ok(model)
}

/// The displacement scale of the fitted linear model (RMS of its displacement).
fn baseline_scale(fitted: &Fitted, series: &[Series<'_>]) -> f64 {
    let bound = simulate::bound_for(1e3 * fitted.scales.z);
    let mut sum = 0.0;
    let mut n = 0usize;
    for (s, &x0) in series.iter().zip(&fitted.initial) {
        let grid = simulate::Grid {
            dt: s.dt,
            substeps: fitted.scales.substeps,
        };
        if let Ok((z, _)) = simulate::states(&fitted.model.oscillator, grid, s.input, x0, bound) {
            sum += z.iter().map(|v| v * v).sum::<f64>();
            n += z.len();
        }
    }
    if n > 0 && sum > 0.0 {
        (sum / n as f64).sqrt()
    } else {
        fitted.scales.z
    }
}

fn candidate(
    series: &[Series<'_>],
    case: &ForcedCase,
    baseline: &Fitted,
    baseline_forecast: f64,
    effects: &[Effect],
    settings: &ForcedSettings,
    spring: Option<&SpringStructure>,
) -> Candidate {
    let failed = |why: String| Candidate {
        effects: effects.to_vec(),
        fitted: None,
        residual_rms: f64::NAN,
        forecast_rms: f64::NAN,
        dbic: f64::NAN,
        tests: Tests {
            significant: false,
            forecasts: false,
            identified: false,
            signature: None,
        },
        evidence: format!("the fit failed: {why}"),
    };
    let fitted = match fit_refined(series, baseline, effects, settings.max_iterations, spring) {
        Ok(f) => f,
        Err(e) => return failed(e),
    };
    let forecast = fit::forecast(series, &fitted, effects, settings.max_iterations, spring)
        .unwrap_or(f64::INFINITY);
    let n = fitted.count as f64;
    let n_eff = effective_count(&fitted);
    let dbic = n_eff * (baseline.cost / fitted.cost).ln() - effects.len() as f64 * n_eff.ln();
    let inflate = (n / n_eff).sqrt();
    let identified = fitted.effects.iter().all(|&(e, value, se)| {
        let admissible = e == Effect::Cubic || value > 0.0;
        admissible && value.abs() > 3.0 * se * inflate
    });
    let signature = signature(case, &baseline.model, &fitted);
    let tests = Tests {
        significant: dbic > 10.0,
        forecasts: forecast < baseline_forecast,
        identified,
        signature: signature.0,
    };
    let mut words: Vec<String> = fitted
        .effects
        .iter()
        .map(|&(e, value, se)| {
            format!(
                "{} = {:.4e} +- {:.2e} (per unit mass, se inflated x{:.1} for correlated residuals)",
                e.name(),
                value,
                se * inflate,
                inflate
            )
        })
        .collect();
    words.push(signature.1);
    Candidate {
        effects: effects.to_vec(),
        residual_rms: relative(&fitted, series),
        forecast_rms: forecast,
        dbic,
        tests,
        evidence: words.join("; "),
        fitted: Some(fitted),
    }
}

/// Fits `effects` from the baseline, and again with finer sub-steps when the fitted
/// nonlinearity needs them (simulate module, "Step size").
fn fit_refined(
    series: &[Series<'_>],
    baseline: &Fitted,
    effects: &[Effect],
    max_iterations: usize,
    spring: Option<&SpringStructure>,
) -> std::result::Result<Fitted, String> {
    let mut scales = baseline.scales;
    let run = |scales: &fit::Scales| {
        fit::fit(
            series,
            &baseline.model,
            &baseline.initial,
            scales,
            effects,
            max_iterations,
            spring,
        )
    };
    for _ in 0..3 {
        let f = run(&scales)?;
        let z_max = series
            .iter()
            .map(|s| s.output.iter().fold(0.0f64, |m, y| m.max(y.abs())))
            .fold(0.0, f64::max)
            .max(3.0 * scales.z);
        let w = f.model.oscillator.natural_frequency_rad_s;
        let dt = series.iter().map(|s| s.dt).fold(0.0, f64::max);
        let needed = simulate::substeps(&f.model.oscillator, dt, z_max, w * z_max);
        if needed <= scales.substeps {
            return Ok(f);
        }
        scales.substeps = needed;
    }
    run(&scales)
}

/// The signature test (module docs, test 4) and its words.
fn signature(case: &ForcedCase, linear: &ForcedModel, fitted: &Fitted) -> (Option<bool>, String) {
    if linear.output_quantity != OutputQuantity::Displacement {
        return (
            None,
            "signature: not available (the restoring force needs a displacement output)".into(),
        );
    }
    let vf = fitted.model.oscillator.friction_velocity;
    let mut all = true;
    let mut words = Vec::new();
    for &(effect, value, _) in &fitted.effects {
        let term: Box<dyn Fn(f64, f64) -> f64> = match effect {
            Effect::Cubic => Box::new(|z: f64, _| z * z * z),
            Effect::Friction => Box::new(move |_, v: f64| (v / vf).tanh()),
            Effect::Drag => Box::new(|_, v: f64| v * v.abs()),
        };
        let velocity_like = effect != Effect::Cubic;
        let (mut num, mut den, mut t2) = (0.0, 0.0, 0.0);
        for r in &case.records {
            let (c, t) = frf::signature(linear, r.dt, &r.input, &r.output, &*term, velocity_like);
            num += c * r.output.len() as f64;
            den += r.output.len() as f64;
            t2 += t * t * t.signum();
        }
        let coef = num / den.max(1.0);
        let t = t2.signum() * t2.abs().sqrt();
        let pass = coef.signum() == value.signum() && t.abs() >= 2.0;
        all &= pass;
        words.push(format!(
            "signature of {}: restoring-force regression {coef:.3e} (t = {t:.1}) against the \
             fit's {value:.3e}: {}",
            effect.name(),
            if pass { "agrees" } else { "does not agree" }
        ));
    }
    (Some(all), words.join("; "))
}

/// What the records show when no cause is named.
fn unexplained(baseline: &Fitted, series: &[Series<'_>], levels: &[frf::LevelFrf]) -> String {
    let noise: f64 = {
        let (mut s, mut n) = (0.0, 0usize);
        for r in series {
            let sigma = coil_postproc::stats::noise_rms(r.output);
            s += sigma * sigma * r.output.len() as f64;
            n += r.output.len();
        }
        (s / n.max(1) as f64).sqrt()
    };
    let misfit = (baseline.cost / baseline.count.max(1) as f64).sqrt();
    let mut text = format!(
        "the linear model misses the outputs by {misfit:.4e} RMS against a noise of {noise:.4e} \
         (fourth differences)"
    );
    if misfit < 1.5 * noise {
        text.push_str(": within the noise, nothing to explain");
    } else {
        text.push_str(": beyond the noise, and no effect of the catalogue passes the four tests");
    }
    if levels.len() >= 2 {
        let lo = &levels[0];
        let hi = &levels[levels.len() - 1];
        text.push_str(&format!(
            "; the H1 peak moves from {:.4} Hz at input RMS {:.4e} to {:.4} Hz at {:.4e}",
            lo.peak_hz, lo.input_rms, hi.peak_hz, hi.input_rms
        ));
    }
    text
}
