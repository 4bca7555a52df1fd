//! Which damping law? `coil-tune damping CASE --out DIR`: fits the three damping
//! laws of docs/measured-case.md to all decay records of a case at once, chooses by
//! an information criterion and held-out prediction, and says when the records cannot
//! decide.
//!
//! # Formulation
//! Each record r is one free decay of one mode (the weight bouncing on the spring at the
//! record's attached mass, or the coil's own surge mode with the weight held). It is
//! reduced to its undamped circular frequency `w_r` and damping ratio `zeta_r` with a
//! standard error, by a least-squares fit of a damped sinusoid plus offset
//! `y = exp(-s t) (c1 cos w_d t + c2 sin w_d t) + c3` (variable projection: the linear
//! `c` are solved inside every evaluation of the two nonlinear `(w_d, s)`; Levenberg-
//! Marquardt, `diagnose::lm`); `w = sqrt(w_d^2 + s^2)`, `zeta = s / w`.
//!
//! For small damping every law gives the mode a damping ratio linear in its parameters
//! (first-order modal damping, the mode shape `phi` mass-normalised):
//!
//! | law | zeta of mode r |
//! |---|---|
//! | `rayleigh` | `alpha d_r / (2 w_r) + beta w_r / 2`, `d_r = phi^T M_wire phi` |
//! | `hysteretic` | `loss_factor / 2` |
//! | `external_viscous` | `c phi_w^2 / (2 w_r)` (`phi_w` the weight's axial entry) |
//!
//! `beta w / 2` is exact because all the stiffness is the wire's. `d_r` and `phi_w` come
//! from coil's FE model of the case's spring at the record's mass; mode shapes do not
//! depend on Young's modulus (scaling K scales every `w^2`), so E needs no calibration
//! here and `w_r` is the measured one. A surge record is the fixed-fixed coil: `d = 1`
//! and `phi_w = 0` exactly (the held weight takes no part).
//!
//! **What the records can separate.** For the weight mode `w^2 = K / m_eff`, so
//! `beta w / 2 = beta sqrt(K / m_eff) / 2`, `c / (2 m_eff w) = c / (2 sqrt(K m_eff))` and
//! `alpha d / (2 w) = alpha (m_s / 3) / (2 sqrt(K m_eff))`: all three viscous forms fall as
//! `m_eff^{-1/2}` and are the same law to first order (a dashpot across a massless
//! spring is a dashpot to ground). Records at several masses therefore separate the
//! hysteretic law (zeta independent of the mass) from the viscous family, not the
//! members of that family from each other; a surge record does (beta gives it
//! `beta w_s / 2`, about 30 times the weight mode's zeta; the dashpot nothing).
//!
//! # Fit and choice
//! Each law is fitted by weighted non-negative least squares to all records at once,
//! weights `1 / s_r^2` with `s_r^2 = se_r^2 + (s zeta_r)^2`: the record's fit error and the
//! repeat scatter `s` of one test (default 3 %, the paper's Table 1: 0.0017-0.0018 around
//! 0.00175). A record's own fit error understates how far a repeat test lands (mounting,
//! amplitude, temperature), so the scatter dominates and sets what a mass ratio can
//! decide. `chi2 = sum ((zeta_r - zeta_hat_r) / s_r)^2`, `BIC = chi2 + k ln n`. Held
//! out: each record predicted from the others (when they still determine the law),
//! `loo = mean ((zeta_r - pred_r) / sqrt(s_r^2 + var pred_r))^2`. A law is chosen only
//! when it is consistent with the records (chi2 below the 99.9 % point of its chi-square
//! distribution, and the held-out score below 9 where it exists) and every other law's
//! BIC is at least 10 higher (very strong evidence); otherwise `law` is null,
//! `identifiable` false. Parameter standard errors from the weighted normal matrix,
//! scaled by `sqrt(chi2 / (n - k))` when that exceeds 1.
//!
//! Units: `rayleigh_alpha` 1/s, `rayleigh_beta` s, `loss_factor` -, `dashpot_n_s_m` N s/m.

mod fit;
mod report;
#[cfg(test)]
mod tests;

pub use fit::{
    choose, fit_decay, fit_law, sigma2, Candidate, RecordFit, HELD_OUT_LIMIT, IDENTIFIED_SE,
};
pub use report::{
    report_json, report_markdown, summary, write, DampingReport, DecidingTest, VariantPrediction,
};

use crate::case::{read_case, read_variants, DecayMode, MeasuredCase, VariantsFile};
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use crate::scatter::{chi2_999, RepeatScatter};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The laws and their modal coefficients live below identification, in the tuner (the
/// paper's band uses them too).
pub use coil_tuner::band::{
    band, band_markdown, mode_coefficients, spread_percent, Band, Coefficients, Law, LAWS,
};

/// Settings of the damping command.
#[derive(Debug, Clone)]
pub struct DampingSettings {
    /// FE settings of the spring's modal runs.
    pub fe: FeSettings,
    /// Table 4 variants (None: none predicted).
    pub variants: Option<PathBuf>,
    /// Repeat scatter of one test's zeta (relative) when the case has no repeated tests
    /// (the paper's Table 1: 0.0017-0.0018 around 0.00175, about 3 %); with repeats, their
    /// estimate replaces it.
    pub scatter: f64,
}

impl Default for DampingSettings {
    fn default() -> Self {
        DampingSettings {
            fe: FeSettings::default(),
            variants: None,
            scatter: 0.03,
        }
    }
}

/// Largest damping ratio the laws' first-order modal forms are used for (-).
pub const MAX_DAMPING_RATIO: f64 = 0.2;

/// Largest share of a record the damped sinusoid may leave unexplained (RMS ratio).
pub const MAX_RESIDUAL: f64 = 0.5;

/// How far the Young's modulus a record's frequency implies may lie from the case's
/// nominal one (factor), and from the other records' (relative).
pub const MODULUS_FACTOR: f64 = 2.0;
/// See [`MODULUS_FACTOR`].
pub const MODULUS_AGREEMENT: f64 = 0.25;

/// A mass for a message: plain where plain reads well, else in exponent form.
fn kg(x: f64) -> String {
    if (1e-3..1e6).contains(&x.abs()) {
        format!("{x} kg")
    } else {
        format!("{x:.3e} kg")
    }
}

/// `records.decay[k] (file)` of `case`, for messages.
fn entry(case: &MeasuredCase, k: usize) -> String {
    let name = case
        .decay_files
        .get(k)
        .and_then(|f| f.file_name())
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_default();
    format!("{}: records.decay[{k}] ({name})", case.file.display())
}

/// Refuses a record listed twice: the same file, or another file with identical content
/// (a repeat test is a new recording; one listed twice would count its evidence twice).
fn refuse_duplicates(case: &MeasuredCase) -> Result<()> {
    let mut seen: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    for (k, file) in case.decay_files.iter().enumerate() {
        let canonical = std::fs::canonicalize(file).unwrap_or_else(|_| file.clone());
        let bytes = std::fs::read(file).map_err(|source| TuneError::Io {
            path: file.clone(),
            source,
        })?;
        if let Some(j) = seen
            .iter()
            .position(|(p, b)| *p == canonical || *b == bytes)
        {
            let how = if seen[j].0 == canonical {
                "the same file"
            } else {
                "identical content"
            };
            return Err(TuneError::Invalid(format!(
                "{} and records.decay[{j}] are one recording ({how}); expected each decay record \
                 once: a repeat test is a recording of its own, and a record listed twice would \
                 count as two tests",
                entry(case, k)
            )));
        }
        seen.push((canonical, bytes));
    }
    Ok(())
}

/// The closed-form circular frequency of a record's mode on the case's spring at nominal
/// E: `sqrt(K / (m + m_s / 3))` for the weight mode, `pi sqrt(K / m_s)` for the surge mode
/// (K = G d^4 / 8 n D^3; mesher's closed forms).
fn closed_form_omega(case: &MeasuredCase, mode: DecayMode, mass_kg: f64) -> f64 {
    use coil_mesher::closed_form;
    let state = SpringState::nominal(case);
    let geometry = state.spec(&FeSettings::default(), &[]).geometry();
    let g = state.youngs_modulus_mpa / (2.0 * (1.0 + state.poisson_ratio));
    let k = closed_form::simple_stiffness(&geometry, g);
    let m_s = geometry.spring_mass_kg(state.density_kg_m3);
    std::f64::consts::TAU
        * match mode {
            DecayMode::Axial => 1.0 / closed_form::rayleigh_period_s(k, mass_kg, m_s),
            DecayMode::Surge => closed_form::surge_frequency_hz(k, m_s),
        }
}

/// Checks one record's fit against what a free decay of its mode can be: zeta light and
/// not growing, the sinusoid explaining the record, the frequency one the case's spring has
/// at the record's mass. Returns the Young's modulus the frequency implies over nominal.
fn check_record(
    case: &MeasuredCase,
    k: usize,
    mode: DecayMode,
    mass_kg: f64,
    fit: (f64, f64, f64, f64),
) -> Result<f64> {
    let (w, zeta, se, residual) = fit;
    let bad = |what: String| Err(TuneError::Invalid(format!("{}: {what}", entry(case, k))));
    if residual > MAX_RESIDUAL {
        return bad(format!(
            "a damped sinusoid leaves {:.0} % of the record unexplained (at {:.4} Hz); expected \
             the free decay of one mode (noise, several modes or a forced record cannot tell a \
             damping law)",
            100.0 * residual,
            w / std::f64::consts::TAU
        ));
    }
    if zeta + 3.0 * se < 0.0 {
        return bad(format!(
            "the oscillation grows (zeta = {zeta:.3e} +- {se:.1e}); expected a free decay"
        ));
    }
    if zeta >= MAX_DAMPING_RATIO {
        return bad(format!(
            "zeta = {zeta:.3}; expected light damping (below {MAX_DAMPING_RATIO}), which the laws' \
             first-order modal forms assume"
        ));
    }
    let expected = closed_form_omega(case, mode, mass_kg);
    let ratio = (w / expected).powi(2);
    if !(ratio.is_finite() && (1.0 / MODULUS_FACTOR..=MODULUS_FACTOR).contains(&ratio)) {
        let what = match mode {
            DecayMode::Axial => format!("the weight mode with {} attached", kg(mass_kg)),
            DecayMode::Surge => "the surge mode (weight held)".to_string(),
        };
        return bad(format!(
            "the record oscillates at {:.4} Hz, but the case's spring has {what} near {:.4} Hz \
             (closed form at the nominal E): it would take {:.3} times that E; expected a \
             record of that mode (check the record's mass_kg and mode)",
            w / std::f64::consts::TAU,
            expected / std::f64::consts::TAU,
            ratio
        ));
    }
    Ok(ratio)
}

/// Reduces every decay record of `case` (module docs), each checked against its mode
/// ([`check_record`]) and all against one another: the Young's modulus each frequency
/// implies agrees within [`MODULUS_AGREEMENT`] of their median (one spring).
pub fn record_fits(case: &MeasuredCase, fe: &FeSettings) -> Result<Vec<RecordFit>> {
    refuse_duplicates(case)?;
    let signals = case.decay_records()?;
    let nominal = SpringState::nominal(case);
    let mut cache: Vec<((u64, DecayMode), Coefficients)> = Vec::new();
    let mut out = Vec::with_capacity(signals.len());
    let mut implied = Vec::with_capacity(signals.len());
    for (k, signal) in signals.iter().enumerate() {
        let info = case.decay_info.get(k).cloned().unwrap_or_default();
        let mass_kg = info.mass_kg.unwrap_or(case.mass_kg);
        let fit = fit_decay(signal)?;
        implied.push(check_record(case, k, info.mode, mass_kg, fit)?);
        let (w, zeta, se, residual_rms) = fit;
        let key = (mass_kg.to_bits(), info.mode);
        let coefficients = match cache.iter().find(|(k, _)| *k == key) {
            Some((_, c)) => *c,
            None => {
                let state = SpringState { mass_kg, ..nominal };
                let c = mode_coefficients(&state, fe, info.mode)?;
                cache.push((key, c));
                c
            }
        };
        out.push(RecordFit {
            file: case.decay_files.get(k).cloned().unwrap_or_default(),
            mode: info.mode,
            mass_kg,
            frequency_hz: w / std::f64::consts::TAU,
            damping_ratio: zeta,
            damping_ratio_se: se,
            residual_rms,
            coefficients: Coefficients {
                omega_rad_s: w,
                ..coefficients
            },
        });
    }
    let mut sorted = implied.clone();
    sorted.sort_by(f64::total_cmp);
    if let Some(&median) = sorted.get(sorted.len() / 2) {
        if let Some(k) = implied
            .iter()
            .position(|e| (e / median - 1.0).abs() > MODULUS_AGREEMENT)
        {
            return Err(TuneError::Invalid(format!(
                "{}: its frequency {:.4} Hz at {} ({:?} mode) implies E = {:.3} times nominal, \
                 the records' median {:.3}: one spring has one E; expected the record's mass_kg \
                 and mode as tested (a mass off by a factor moves the frequency by its root)",
                entry(case, k),
                out[k].frequency_hz,
                kg(out[k].mass_kg),
                out[k].mode,
                implied[k],
                median
            )));
        }
    }
    Ok(out)
}

/// Groups of records taken as nominally identical tests: the same mode at the same
/// attached mass (to 1e-9).
pub fn repeat_groups(records: &[RecordFit]) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, r) in records.iter().enumerate() {
        match groups.iter_mut().find(|g| {
            let q = &records[g[0]];
            q.mode == r.mode && (q.mass_kg - r.mass_kg).abs() <= 1e-9 * q.mass_kg.abs()
        }) {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
}

/// The repeat scatter of `records`: estimated from their repeated tests, `default`
/// without ([`RepeatScatter::estimate`]).
pub fn repeat_scatter(records: &[RecordFit], default: f64) -> RepeatScatter {
    let zeta: Vec<f64> = records.iter().map(|r| r.damping_ratio).collect();
    let se: Vec<f64> = records.iter().map(|r| r.damping_ratio_se).collect();
    let names: Vec<String> = records.iter().map(RecordFit::name).collect();
    RepeatScatter::estimate(&zeta, &se, &repeat_groups(records), &names, default)
}

/// The law's verdict from a case's decay records, before any prediction.
#[derive(Debug, Clone)]
pub struct Verdict {
    /// Every decay record reduced to its frequency and damping ratio.
    pub records: Vec<RecordFit>,
    /// The repeat scatter the records were judged with.
    pub scatter: RepeatScatter,
    /// Every law fitted to all the records.
    pub candidates: Vec<Candidate>,
    /// The chosen law; `None` when the records cannot decide.
    pub law: Option<Law>,
    /// Why the law was chosen, or why none could be.
    pub reason: String,
}

/// Reduces, checks and judges the decay records of `case` (module docs): the records,
/// their repeat scatter (`default_scatter` without repeats), every law fitted and the
/// choice.
pub fn verdict(case: &MeasuredCase, fe: &FeSettings, default_scatter: f64) -> Result<Verdict> {
    let records = record_fits(case, fe)?;
    if records.is_empty() {
        return Err(TuneError::Invalid(format!(
            "{}: no decay record; expected records.decay with at least one file",
            case.file.display()
        )));
    }
    let scatter = repeat_scatter(&records, default_scatter);
    let candidates: Vec<Candidate> = LAWS
        .iter()
        .filter_map(|&law| fit_law(law, &records, &scatter))
        .collect();
    let (law, reason) = choose(&candidates, records.len());
    Ok(Verdict {
        records,
        scatter,
        candidates,
        law,
        reason,
    })
}

/// Runs the damping-law identification on a case folder.
pub fn identify(case_path: &Path, settings: &DampingSettings) -> Result<DampingReport> {
    let scatter = settings.scatter;
    if !(scatter.is_finite() && scatter > 0.0 && scatter < 1.0) {
        return Err(TuneError::Invalid(format!(
            "scatter {scatter}; expected a relative repeat scatter of zeta in (0, 1), e.g. 0.03"
        )));
    }
    let case = read_case(case_path)?;
    let Verdict {
        records,
        scatter,
        candidates,
        law,
        reason,
    } = verdict(&case, &settings.fe, settings.scatter)?;
    let chosen = law.and_then(|l| candidates.iter().find(|c| c.law == l));
    let variants = match &settings.variants {
        Some(p) => Some(read_variants(p)?),
        None => None,
    };
    let table4 = match &variants {
        Some(v) => predict_variants(&case, &records, &candidates, chosen, v, &settings.fe)?,
        None => Vec::new(),
    };
    let (deciding_test, band) = if law.is_none() {
        let state = calibrated_state(&case, &records, &settings.fe)?;
        let base = records
            .iter()
            .find(|r| r.mode == DecayMode::Axial)
            .unwrap_or(&records[0]);
        let none = VariantsFile {
            file: PathBuf::new(),
            source: None,
            variants: Vec::new(),
        };
        let band = band(
            &SpringState {
                mass_kg: base.mass_kg,
                ..state
            },
            variants.as_ref().unwrap_or(&none),
            &settings.fe,
            base.damping_ratio,
            scatter.relative,
        )?;
        (
            Some(deciding_test(
                &case,
                &records,
                scatter.relative,
                &settings.fe,
            )?),
            Some(band),
        )
    } else {
        (None, None)
    };
    Ok(DampingReport {
        case: case.name.clone(),
        law,
        parameters: chosen.map(|c| c.parameters.clone()).unwrap_or_default(),
        parameters_se: chosen.map(|c| c.parameters_se.clone()).unwrap_or_default(),
        identifiable: law.is_some(),
        reason,
        scatter,
        records,
        candidates,
        table4,
        deciding_test,
        band,
    })
}

/// The state of the case's spring whose weight mode has the frequency of the first axial
/// record at its mass (E scaled: `w^2` is proportional to E at fixed shape).
fn calibrated_state(
    case: &MeasuredCase,
    records: &[RecordFit],
    fe: &FeSettings,
) -> Result<SpringState> {
    let nominal = SpringState::nominal(case);
    let Some(base) = records.iter().find(|r| r.mode == DecayMode::Axial) else {
        return Ok(nominal);
    };
    let state = SpringState {
        mass_kg: base.mass_kg,
        ..nominal
    };
    let c = mode_coefficients(&state, fe, DecayMode::Axial)?;
    let scale = (base.coefficients.omega_rad_s / c.omega_rad_s).powi(2);
    Ok(SpringState {
        youngs_modulus_mpa: nominal.youngs_modulus_mpa * scale,
        mass_kg: case.mass_kg,
        ..nominal
    })
}

fn predict_variants(
    case: &MeasuredCase,
    records: &[RecordFit],
    candidates: &[Candidate],
    chosen: Option<&Candidate>,
    variants: &VariantsFile,
    fe: &FeSettings,
) -> Result<Vec<VariantPrediction>> {
    let state = calibrated_state(case, records, fe)?;
    let mut out = Vec::new();
    for v in &variants.variants {
        let c = mode_coefficients(&state.with_spring(v.spring), fe, DecayMode::Axial)?;
        let mut by_law = BTreeMap::new();
        // A law's zeta is linear in its parameters: the row of coefficients times them.
        let zeta_of = |cand: &Candidate, row: &[f64]| -> f64 {
            let names = cand.law.parameters();
            row.iter()
                .zip(names)
                .map(|(a, n)| a * cand.parameters[*n])
                .sum()
        };
        for cand in candidates {
            by_law.insert(cand.law.name().to_string(), zeta_of(cand, &c.row(cand.law)));
        }
        let (zeta, se) = match chosen {
            Some(cand) => {
                let row = c.row(cand.law);
                let z = zeta_of(cand, &row);
                let k = row.len();
                let var: f64 = (0..k)
                    .flat_map(|i| (0..k).map(move |j| (i, j)))
                    .map(|(i, j)| row[i] * cand.covariance[i][j] * row[j])
                    .sum();
                (Some(z), Some(var.max(0.0).sqrt()))
            }
            None => (None, None),
        };
        out.push(VariantPrediction {
            name: v.name.clone(),
            spread_percent: spread_percent(by_law.values().copied()),
            by_law,
            damping_ratio: zeta,
            damping_ratio_se: se,
            paper_damping_ratio: v.paper_damping_ratio,
        });
    }
    Ok(out)
}

/// Standard deviations a relative difference between two mean zetas must stand for the
/// verdict to decide: the test of fit's 99.9 % point (3.29) plus two, so that a test sized
/// by [`repeats_needed`] decides in 97.7 % of repeats of the whole experiment.
pub fn deciding_sigmas() -> f64 {
    chi2_999(1).sqrt() + 2.0
}

/// Repeats per mass so that a relative difference `delta` between two mean zetas stands at
/// [`deciding_sigmas`] when each test scatters by `scatter`:
/// `z scatter sqrt(2 / n) <= delta`.
pub fn repeats_needed(delta: f64, scatter: f64) -> usize {
    ((2.0 * (deciding_sigmas() * scatter / delta).powi(2)).ceil() as usize).max(1)
}

fn deciding_test(
    case: &MeasuredCase,
    records: &[RecordFit],
    scatter: f64,
    fe: &FeSettings,
) -> Result<DecidingTest> {
    let base = records
        .iter()
        .find(|r| r.mode == DecayMode::Axial)
        .unwrap_or(&records[0]);
    let m_eff = |m: f64| m + SpringState::nominal(case).spring_mass_kg() / 3.0;
    let second_mass = [1.5, 2.0, 3.0]
        .iter()
        .map(|&ratio| {
            let r = (m_eff(base.mass_kg * ratio) / m_eff(base.mass_kg)).powf(-0.5);
            (ratio, r, repeats_needed(1.0 - r, scatter))
        })
        .collect();
    let surge_state = calibrated_state(case, records, fe)?;
    let surge = mode_coefficients(&surge_state, fe, DecayMode::Surge)?;
    let mut surge_zeta = BTreeMap::new();
    // Each law calibrated to the base record alone (Rayleigh at both ends of its valley).
    let zeta = base.damping_ratio;
    let c = &base.coefficients;
    let alpha_only = zeta / c.row(Law::Rayleigh)[0];
    let beta_only = zeta / c.row(Law::Rayleigh)[1];
    surge_zeta.insert(
        "rayleigh_beta_only".to_string(),
        beta_only * surge.row(Law::Rayleigh)[1],
    );
    surge_zeta.insert(
        "rayleigh_alpha_only".to_string(),
        alpha_only * surge.row(Law::Rayleigh)[0],
    );
    surge_zeta.insert("hysteretic".to_string(), zeta);
    surge_zeta.insert("external_viscous".to_string(), 0.0);
    let (r2, q2, n2) = [1.5, 2.0, 3.0]
        .iter()
        .map(|&ratio| {
            let r = (m_eff(base.mass_kg * ratio) / m_eff(base.mass_kg)).powf(-0.5);
            (ratio, r, repeats_needed(1.0 - r, scatter))
        })
        .nth(1)
        .unwrap_or((2.0, 0.7, 1));
    let text = format!(
        "A second attached mass separates the hysteretic law (zeta independent of the mass) from \
         the viscous ones (zeta falls as m_eff^-1/2): at {r2} times the mass ({:.2} kg) a viscous law \
         gives {q2:.3} times the zeta, {:.1} % lower; against a repeat scatter of {:.0} % that needs \
         {n2} decay test(s) per mass. No mass ratio separates beta from a dashpot at the weight \
         (both give zeta proportional to w for the weight mode: a dashpot across a massless spring \
         is a dashpot to ground). The surge mode does: hold the weight and record the coil's own \
         first axial mode at mid-coil ({:.1} Hz): beta alone predicts zeta = {:.4}, alpha alone {:.4}, \
         the hysteretic law {:.5}, a dashpot at the weight 0.",
        base.mass_kg * r2,
        100.0 * (1.0 - q2),
        100.0 * scatter,
        surge.omega_rad_s / std::f64::consts::TAU,
        surge_zeta["rayleigh_beta_only"],
        surge_zeta["rayleigh_alpha_only"],
        zeta
    );
    Ok(DecidingTest {
        scatter,
        second_mass,
        surge_frequency_hz: surge.omega_rad_s / std::f64::consts::TAU,
        surge_zeta,
        text,
    })
}

/// The variants file `coil-tune damping` predicts by default: `table4.json` beside the
/// case's case.json, when there is one.
pub fn variants_beside(case: &Path) -> Option<PathBuf> {
    let beside = crate::case::case_file(case).with_file_name("table4.json");
    beside.is_file().then_some(beside)
}
