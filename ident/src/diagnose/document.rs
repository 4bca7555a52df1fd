//! The diagnosis as a person reads it: report.md, the figures and the CSV tables,
//! written into the locked output folder and committed as one set.

use super::outcome::Outcome;
use super::plots::{self, Panel, Series};
use super::report::*;
use crate::case::Quantity;
use crate::error::{Result, TuneError};
use crate::output::{csv, OutDir};
use std::path::Path;

fn f(x: f64) -> String {
    if !x.is_finite() {
        "-".into()
    } else if x == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&x.abs()) {
        format!("{x:.5}")
    } else {
        format!("{x:.4e}")
    }
}

fn opt(x: Option<f64>) -> String {
    x.map_or("-".into(), f)
}

/// report.md's text: the headline, then the four sections (the damping law's evidence
/// before the last when the case has several decay records).
fn markdown(o: &Outcome, figures: &[(&str, &str)]) -> String {
    let mut m = String::new();
    headline(o, &mut m);
    baseline_section(o, &mut m);
    misses_section(o, figures, &mut m);
    candidates_section(o, &mut m);
    super::law_evidence::section(&o.case, &mut m);
    honesty_section(o, &mut m);
    m
}

/// The title, the records, the cause with its numbers, unexplained and warnings.
fn headline(o: &Outcome, m: &mut String) {
    let d = &o.diagnosis;
    let b = &d.baseline;
    m.push_str(&format!("# Diagnosis of `{}`\n\n", o.case.name));
    m.push_str(&format!(
        "Case file `{}`; decay record `{}` ({} samples at {:.1} Hz, {:.2} s, {} cycles).\n\n",
        o.case.file.display(),
        o.decay.signal.source().display(),
        o.decay.signal.values().len(),
        1.0 / o.decay.signal.step_s(),
        o.decay.signal.time_s().last().unwrap_or(&0.0) - o.decay.signal.time_s()[0],
        o.decay.cycles
    ));
    if !o.joint_records.is_empty() {
        m.push_str(
            "Fitted jointly with (one mass, one spring, the same effects; each record its \
             own initial state, and its own offset and drift when it records a position or \
             a velocity; figures, signatures and tables show the first record):\n",
        );
        for (file, samples, delta) in &o.joint_records {
            m.push_str(&format!(
                "- `{}` ({samples} samples, attached mass {delta:+.4} kg from the first \
                 record's)\n",
                file.display()
            ));
        }
        m.push('\n');
    }
    m.push_str(&format!("**Cause: `{}`**", d.cause));
    if let (Some(e), g) = (&d.extended, &d.gain) {
        if d.causes.len() > 1 {
            m.push_str(&format!(
                " (several effects together: {})",
                d.causes
                    .iter()
                    .map(|c| format!(
                        "`{}` {:.0} % of the explained misfit",
                        c.effect,
                        100.0 * c.share
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        for (name, value) in &e.parameters {
            m.push_str(&format!(
                ", `{name}` = {} +- {} (standard error inflated for the residuals' correlation)",
                f(*value),
                e.parameters_se.get(name).map_or("-".into(), |x| f(*x))
            ));
        }
        m.push_str(&format!(
            ". Residual RMS {} -> {} (ratio {:.3}); forecast RMS {} -> {} (ratio {:.3}). The \
             record's noise floor is {}: the extension leaves {:.1} % of the baseline's model \
             error.\n\n",
            f(b.residual_rms),
            f(e.residual_rms),
            g.residual_rms_ratio,
            f(b.forecast_rms),
            f(e.forecast_rms),
            g.forecast_rms_ratio,
            f(d.noise_floor_rms),
            100.0 * g.model_error_ratio
        ));
    } else {
        m.push_str(
            ": no effect or combination of the catalogue passes every test (section 3).\n\n",
        );
    }
    if let Some(u) = &d.unexplained {
        m.push_str(&format!("**Unexplained:** {u}\n\n"));
    }
    if let Some(u) = &d.remaining_misfit {
        m.push_str(&format!("**Misfit left:** {u}\n\n"));
    }
    if !d.warnings.is_empty() {
        m.push_str("**Check:**\n\n");
        for w in &d.warnings {
            m.push_str(&format!("- {w}\n"));
        }
        m.push('\n');
    }
}

/// Section 1: the paper's model as calibrated.
fn baseline_section(o: &Outcome, m: &mut String) {
    let d = &o.diagnosis;
    let b = &d.baseline;
    m.push_str("## 1. Baseline: the paper's model\n\n");
    m.push_str(match o.stiffness_source {
        StiffnessSource::StaticRecord => {
            "K from the static record (the line F = k x +- F_f through both branches), E by loop 1. "
        }
        StiffnessSource::Target => "K from the case's target `stiffness_n_mm` (no static record), E by loop 1. ",
        StiffnessSource::Nominal => {
            "There is no static record and no target K: E stays nominal, so K is the FE \
             model's at the nominal E, and the weight's mass is tuned to the period (mass and \
             frequency fix the dynamic stiffness; only their ratio is measured). "
        }
    });
    m.push_str(
        "T and \
                zeta by the logarithmic decrement (every 10th crest), the weight's mass by loop 2, \
                damping stiffness-proportional (alpha = 0, beta = 2 zeta / w: one decay identifies \
                one combination of alpha and beta). The decay is simulated on the reduced FE model \
                with its initial state fitted; the forecast repeats the calibration on the first \
                half and predicts the second.\n\n",
    );
    m.push_str("| quantity | value |\n|---|---|\n");
    for (k, v) in [
        ("youngs_modulus_mpa", b.youngs_modulus_mpa),
        ("mass_kg", b.mass_kg),
        ("rayleigh_alpha", b.rayleigh_alpha),
        ("rayleigh_beta (s)", b.rayleigh_beta),
        ("stiffness_n_mm", b.stiffness_n_mm),
        ("period_s", b.period_s),
        ("damping_ratio", b.damping_ratio),
        ("residual_rms", b.residual_rms),
        ("forecast_rms", b.forecast_rms),
    ] {
        m.push_str(&format!("| {k} | {} |\n", f(v)));
    }
    m.push_str(&format!(
        "\nThe same linear model fitted by output error (mass and beta free): mass {} kg, beta {} s, \
         residual RMS {}, forecast RMS {}. Candidates are judged against it, so they are not \
         credited with the decrement estimator's bias.\n\n",
        f(d.reference.mass_kg),
        f(d.reference.rayleigh_beta),
        f(d.reference.residual_rms),
        f(d.reference.forecast_rms)
    ));
}

/// Section 2: what the linear model misses, with the figures.
fn misses_section(o: &Outcome, figures: &[(&str, &str)], m: &mut String) {
    let d = &o.diagnosis;
    let s = &d.signatures;
    m.push_str("## 2. What the linear model misses\n\n");
    if let Some(l) = &s.loss {
        m.push_str(&format!(
            "- Loss per cycle dA = a0 + a1 A + a2 A^2: a0 = {} m (+- {}), a1 = {} (+- {}), a2 = {} 1/m \
             (+- {}). Viscous damping alone gives a0 = a2 = 0 and a1 = 2 pi zeta.\n",
            f(l.a0_m), f(l.a0_se), f(l.a1), f(l.a1_se), f(l.a2_per_m), f(l.a2_se)
        ));
    }
    if let Some(bb) = &s.backbone {
        m.push_str(&format!(
            "- Backbone f^2 = f0^2 (1 + b A^2): f0 = {} Hz, b = {} 1/m^2 (+- {}).\n",
            f(bb.f0_hz),
            f(bb.b_per_m2),
            f(bb.b_se)
        ));
    }
    m.push_str(&format!(
        "- Envelope: {} (R^2 exponential {}, linear {}{}).\n",
        s.envelope.kind,
        f(s.envelope.r2_exponential),
        f(s.envelope.r2_linear),
        s.envelope
            .beat_period_s
            .map_or(String::new(), |t| format!(", beat period {} s", f(t)))
    ));
    match &s.second_peak {
        Some(p) => m.push_str(&format!(
            "- Spectrum: a second line at {} Hz beside the axial {} Hz, {} % of its amplitude.\n",
            f(p.frequency_hz),
            f(s.axial_hz),
            f(100.0 * p.relative_amplitude)
        )),
        None => m.push_str(&format!("- Spectrum: one line at {} Hz.\n", f(s.axial_hz))),
    }
    if let Some(st) = &s.statics {
        m.push_str(&format!(
            "- Static record: straight line {} N/mm (residual RMS {} N); k x + k3 x^3 +- Ff: k = {} N/mm, \
             k3 = {} N/m^3 (+- {}), hysteresis half-width Ff = {} N (+- {}), residual RMS {} N.\n",
            f(st.linear_k_n_mm), f(st.linear_rms_n), f(st.k_n_mm), f(st.k3_n_m3), f(st.k3_se),
            f(st.friction_n), f(st.friction_se), f(st.cubic_rms_n)
        ));
    }
    m.push('\n');
    for (file, caption) in figures {
        m.push_str(&format!("![{caption}]({file})\n\n"));
    }
}

/// Section 3: every candidate's fit and tests.
fn candidates_section(o: &Outcome, m: &mut String) {
    let d = &o.diagnosis;
    m.push_str("## 3. Candidates\n\n");
    m.push_str(&format!(
        "Each effect starts from its signature and is fitted by output error (Levenberg-Marquardt) \
         with the weight's mass, beta and the initial state{} on the reduced FE model with the \
         effect's element at the weight; effects that gain on their own are then combined (up to \
         three). A candidate is named only if it passes four tests against the linear model \
         (docs/diagnose.md): significance (dBIC > {} on the effective number of residuals from \
         their autocorrelation, residual below {} of the linear model's), forecasts from rolling \
         origins (below {} of the linear model's on at least {} of 3), identified parameters \
         (relative standard error at most {:.2}) and its own signature in the records; a \
         combination must also need every part.\n\n",
        if d.quantity == Quantity::Acceleration { "" } else { ", the sensor's offset and drift" },
        super::select::DELTA_BIC,
        super::select::RESIDUAL_RATIO,
        super::select::FORECAST_RATIO,
        super::select::FORECASTS_NEEDED,
        super::select::REL_SE_LIMIT
    ));
    m.push_str("| candidate | parameters (+- standard error) | residual_rms | forecast_rms | dBIC | N_eff | named |\n|---|---|---|---|---|---|---|\n");
    for c in &d.candidates {
        let p = c
            .parameters
            .iter()
            .map(|(k, v)| {
                format!(
                    "{k} = {} +- {}",
                    f(*v),
                    c.parameters_se.get(k).map_or("-".into(), |x| f(*x))
                )
            })
            .collect::<Vec<_>>()
            .join(", ");
        m.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} |\n",
            c.effect,
            if p.is_empty() {
                c.fit_error.clone().unwrap_or_default()
            } else {
                p
            },
            opt(c.residual_rms),
            opt(c.forecast_rms),
            opt(c.delta_bic),
            c.effective_samples
                .map_or_else(|| "-".to_string(), |n| format!("{n:.0}")),
            if c.significant { "yes" } else { "no" },
        ));
    }
    m.push_str("\nThe tests of every candidate (held / failed, with the numbers):\n\n");
    for c in &d.candidates {
        m.push_str(&format!("- **{}** — evidence: {}\n", c.effect, c.evidence));
        for note in &c.bounds {
            m.push_str(&format!("  - {note}\n"));
        }
        match &c.tests {
            Some(t) => {
                for (name, test) in t.each() {
                    m.push_str(&format!(
                        "  - {name}: {} — {}\n",
                        if test.passed { "held" } else { "FAILED" },
                        test.text
                    ));
                }
            }
            None => m.push_str(&format!(
                "  - the fit failed: {}\n",
                c.fit_error.clone().unwrap_or_default()
            )),
        }
    }
    m.push('\n');
}

/// Section 4: what the integrator, the mesh and the estimators do to the numbers.
fn honesty_section(o: &Outcome, m: &mut String) {
    let d = &o.diagnosis;
    m.push_str(&format!(
        "## 4. Numerical honesty\n\nThe reduced model keeps the weight's DOFs and {} fixed-interface \
         modes; it is integrated by average acceleration at a step of at most {:.2e} of the axial \
         period, whose period error (w dt)^2/12 is below {:.1e}: the fitted mass absorbs it (twice \
         that, relative). Runtime {:.2} s.\n",
        o.modes,
        o.step_fraction,
        (std::f64::consts::TAU * o.step_fraction).powi(2) / 12.0,
        d.runtime_s
    ));
}

fn sampled(time: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    time.iter().copied().zip(values.iter().copied()).collect()
}

fn figures(o: &Outcome, dir: &Path) -> Result<Vec<(&'static str, &'static str)>> {
    let mut list = Vec::new();
    fit_figure(o, dir, &mut list)?;
    cycles_figure(o, dir, &mut list)?;
    static_figure(o, dir, &mut list)?;
    spectrum_figure(o, dir, &mut list)?;
    Ok(list)
}

/// The record against the baseline and the chosen model, their residuals and the last cycles.
fn fit_figure(o: &Outcome, dir: &Path, list: &mut Vec<(&'static str, &'static str)>) -> Result<()> {
    let t = &o.decay.signal.time_s();
    let meas = &o.decay.measured;
    let unit = o.diagnosis.quantity.si_unit();
    let chosen = o
        .diagnosis
        .extended
        .as_ref()
        .and_then(|e| o.candidates.iter().find(|c| c.label() == e.effect))
        .and_then(|c| c.run.as_ref().ok());
    let mut fit_series = vec![
        Series {
            label: "measured".into(),
            points: sampled(t, meas),
            markers: false,
        },
        Series {
            label: "baseline".into(),
            points: sampled(t, &o.baseline.full.simulated),
            markers: false,
        },
    ];
    let res = |sim: &[f64]| -> Vec<(f64, f64)> {
        t.iter()
            .zip(sim.iter().zip(meas))
            .map(|(t, (s, m))| (*t, s - m))
            .collect()
    };
    let mut res_series = vec![Series {
        label: "baseline - measured".into(),
        points: res(&o.baseline.full.simulated),
        markers: false,
    }];
    if let Some(run) = chosen {
        fit_series.push(Series {
            label: "extended".into(),
            points: sampled(t, &run.full.simulated),
            markers: false,
        });
        res_series.push(Series {
            label: "extended - measured".into(),
            points: res(&run.full.simulated),
            markers: false,
        });
    }
    // The last four cycles, where a wrong frequency or damping shows as a phase or an
    // amplitude error the full view hides.
    let tail_start = t.len().saturating_sub(
        ((4.0 / o.signatures.axial_hz.max(1e-9)) / o.decay.signal.step_s()) as usize,
    );
    let zoom: Vec<Series> = fit_series
        .iter()
        .map(|s| Series {
            label: s.label.clone(),
            points: s.points[tail_start..].to_vec(),
            markers: false,
        })
        .collect();
    plots::draw(
        &dir.join("decay_fit.png"),
        vec![
            Panel {
                title: "the weight's recorded quantity: measured and simulated".into(),
                x: "time (s)".into(),
                y: unit.into(),
                series: fit_series,
            },
            Panel {
                title: "the last four cycles".into(),
                x: "time (s)".into(),
                y: unit.into(),
                series: zoom,
            },
            Panel {
                title: "residual".into(),
                x: "time (s)".into(),
                y: unit.into(),
                series: res_series,
            },
        ],
    )?;
    list.push((
        "decay_fit.png",
        "measured against simulated, and the residual",
    ));

    Ok(())
}

/// Per cycle: amplitude, frequency and loss against amplitude (the signatures).
fn cycles_figure(
    o: &Outcome,
    dir: &Path,
    list: &mut Vec<(&'static str, &'static str)>,
) -> Result<()> {
    let cyc = &o.signatures.per_cycle;
    if cyc.len() > 2 {
        let amp: Vec<(f64, f64)> = cyc
            .iter()
            .map(|c| (c.time_s, 1e3 * c.amplitude_m))
            .collect();
        let freq: Vec<(f64, f64)> = cyc
            .iter()
            .map(|c| (1e3 * c.amplitude_m, c.frequency_hz))
            .collect();
        let loss: Vec<(f64, f64)> = cyc
            .windows(2)
            .map(|w| {
                (
                    1e3 * 0.5 * (w[0].amplitude_m + w[1].amplitude_m),
                    1e3 * (w[0].amplitude_m - w[1].amplitude_m),
                )
            })
            .collect();
        let zeta: Vec<(f64, f64)> = cyc
            .windows(2)
            .filter(|w| w[1].amplitude_m > 0.0 && w[0].amplitude_m > 0.0)
            .map(|w| {
                let delta = (w[0].amplitude_m / w[1].amplitude_m).ln();
                (
                    1e3 * 0.5 * (w[0].amplitude_m + w[1].amplitude_m),
                    delta / std::f64::consts::TAU,
                )
            })
            .collect();
        plots::draw(
            &dir.join("cycles.png"),
            vec![
                Panel {
                    title: "per-cycle amplitude of the band-passed axial mode (envelope shape)"
                        .into(),
                    x: "time [s]".into(),
                    y: "displacement amplitude [mm]".into(),
                    series: vec![Series {
                        label: "per cycle".into(),
                        points: amp,
                        markers: true,
                    }],
                },
                Panel {
                    title: "backbone: frequency against amplitude".into(),
                    x: "amplitude [mm]".into(),
                    y: "frequency [Hz]".into(),
                    series: vec![Series {
                        label: "per cycle".into(),
                        points: freq,
                        markers: true,
                    }],
                },
                Panel {
                    title: "damping curve: amplitude loss per cycle".into(),
                    x: "amplitude [mm]".into(),
                    y: "loss per cycle [mm]".into(),
                    series: vec![Series {
                        label: "per cycle".into(),
                        points: loss,
                        markers: true,
                    }],
                },
                Panel {
                    title: "decrement against amplitude (delta / 2 pi per cycle)".into(),
                    x: "amplitude [mm]".into(),
                    y: "zeta per cycle [-]".into(),
                    series: vec![Series {
                        label: "per cycle".into(),
                        points: zeta,
                        markers: true,
                    }],
                },
            ],
        )?;
        list.push((
            "cycles.png",
            "per-cycle amplitude, backbone, damping curve and decrement against amplitude",
        ));
    }
    Ok(())
}

/// The static record: force against compression and the residual of the line.
fn static_figure(
    o: &Outcome,
    dir: &Path,
    list: &mut Vec<(&'static str, &'static str)>,
) -> Result<()> {
    if let Some((record, _)) = &o.statics {
        if let Some(st) = &o.signatures.statics {
            let k = st.linear_k_n_mm;
            let offset = record
                .displacement_mm
                .iter()
                .zip(&record.force_n)
                .map(|(x, f)| f - k * x)
                .sum::<f64>()
                / record.force_n.len() as f64;
            let points: Vec<(f64, f64)> = record
                .displacement_mm
                .iter()
                .zip(&record.force_n)
                .map(|(x, f)| (*x, f - k * x - offset))
                .collect();
            // Loading runs to the largest compression, unloading after it (the order the
            // record was measured in): two colours show the hysteresis loop.
            let turn = points
                .iter()
                .enumerate()
                .max_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
                .map_or(points.len(), |(i, _)| i + 1);
            let (loading, unloading) = points.split_at(turn.min(points.len()));
            let mut series = vec![Series {
                label: "loading (to the largest compression)".into(),
                points: loading.to_vec(),
                markers: true,
            }];
            if !unloading.is_empty() {
                series.push(Series {
                    label: "unloading".into(),
                    points: unloading.to_vec(),
                    markers: true,
                });
            }
            plots::draw(
                &dir.join("static.png"),
                vec![Panel {
                    title: "Static record minus its straight line: curvature and hysteresis".into(),
                    x: "compression [mm]".into(),
                    y: "force - k x [N]".into(),
                    series,
                }],
            )?;
            list.push(("static.png", "static residual: curvature and hysteresis"));
        }
    }
    Ok(())
}

/// The measured spectrum with its lines labelled.
fn spectrum_figure(
    o: &Outcome,
    dir: &Path,
    list: &mut Vec<(&'static str, &'static str)>,
) -> Result<()> {
    if let Some(spec) = &o.spectrum {
        let peak = spec.1.iter().cloned().fold(0.0, f64::max).max(1e-300);
        let points: Vec<(f64, f64)> = spec
            .0
            .iter()
            .zip(&spec.1)
            .filter(|(fr, _)| **fr <= 3.0 * o.signatures.axial_hz)
            .map(|(fr, a)| (*fr, (a / peak).max(1e-6).log10()))
            .collect();
        // Label the lines that stand 1.5 decades above the median level (the noise
        // floor), away from the drift at 0 Hz: the axial line and any second line.
        let mut level: Vec<f64> = points.iter().map(|p| p.1).collect();
        level.sort_by(f64::total_cmp);
        let floor = level.get(level.len() / 2).copied().unwrap_or(-6.0);
        let mut peaks: Vec<(f64, f64)> = points
            .windows(3)
            .filter(|w| {
                w[1].1 >= w[0].1
                    && w[1].1 > w[2].1
                    && w[1].1 > floor + 1.5
                    && w[1].0 > 0.25 * o.signatures.axial_hz
            })
            .map(|w| w[1])
            .collect();
        peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
        let mut kept: Vec<(f64, f64)> = Vec::new();
        for p in peaks {
            if kept.len() < 3
                && kept
                    .iter()
                    .all(|q| (q.0 - p.0).abs() > 0.03 * o.signatures.axial_hz)
            {
                kept.push(p);
            }
        }
        let mut series = vec![Series {
            label: "measured".into(),
            points,
            markers: false,
        }];
        series.extend(kept.iter().map(|&(f, a)| Series {
            label: format!(
                "line at {f:.3} Hz ({:.0} % of the largest)",
                100.0 * 10f64.powf(a)
            ),
            points: vec![(f, a)],
            markers: true,
        }));
        plots::draw(
            &dir.join("spectrum.png"),
            vec![Panel {
                title: "Amplitude spectrum of the decay, relative to the axial line".into(),
                x: "frequency [Hz]".into(),
                y: "log10 amplitude [-]".into(),
                series,
            }],
        )?;
        list.push((
            "spectrum.png",
            "spectral peaks: a second line beside the axial one",
        ));
    }
    Ok(())
}

/// The fits of `fits.csv` as UFF datasets 58 (`coil_io::uff`): the measured record, the
/// baseline, the linear output-error reference and the extended model when one was
/// chosen, each on the record's uniform grid, in SI (node 1, direction 3: the weight,
/// axially).
pub fn fits_uff(o: &Outcome, form: coil_io::uff::UffForm) -> Vec<u8> {
    use coil_io::uff::{uff58_bytes, Uff58};
    let signal = &o.decay.signal;
    let quantity = o.diagnosis.quantity;
    let (ordinate_type, length_exponent) = Uff58::ordinate_kind(quantity.name());
    let chosen = o
        .diagnosis
        .extended
        .as_ref()
        .and_then(|e| o.candidates.iter().find(|c| c.label() == e.effect))
        .and_then(|c| c.run.as_ref().ok());
    let mut series: Vec<(&str, &[f64])> = vec![
        ("measured", &o.decay.measured),
        ("baseline", &o.baseline.full.simulated),
        ("linear_output_error", &o.reference.full.simulated),
    ];
    if let Some(run) = chosen {
        series.push(("extended", &run.full.simulated));
    }
    let datasets: Vec<Uff58> = series
        .into_iter()
        .map(|(name, values)| Uff58 {
            description: format!("coil-tune diagnose: {name} {}", quantity.name()),
            name: name.to_string(),
            node: 1,
            direction: 3,
            ordinate_type,
            length_exponent,
            ordinate_label: quantity.name().to_string(),
            ordinate_unit: quantity.si_unit().to_string(),
            start_s: signal.time_s()[0],
            step_s: signal.step_s(),
            values: values.to_vec(),
        })
        .collect();
    uff58_bytes(&datasets, form == coil_io::uff::UffForm::Binary)
}

/// Writes the outcome into `out` (created): figures and tables first, report.md, then
/// diagnosis.json, each via a temporary file.
pub fn write(o: &Outcome, dir: &OutDir, plots_too: bool) -> Result<()> {
    let figs = if plots_too {
        figures(o, &dir.staging_folder()?)?
    } else {
        Vec::new()
    };
    let t = &o.decay.signal.time_s();
    let chosen = o
        .diagnosis
        .extended
        .as_ref()
        .and_then(|e| o.candidates.iter().find(|c| c.label() == e.effect))
        .and_then(|c| c.run.as_ref().ok());
    // Column unit suffix: m/s^2 -> m_s2, m/s -> m_s, m -> m.
    let suffix = o
        .diagnosis
        .quantity
        .si_unit()
        .replace("/s^2", "_s2")
        .replace("/s", "_s");
    let rows = (0..t.len()).map(|i| {
        vec![
            format!("{}", t[i]),
            format!("{}", o.decay.measured[i]),
            format!("{}", o.baseline.full.simulated[i]),
            format!("{}", o.reference.full.simulated[i]),
            chosen.map_or(String::new(), |r| format!("{}", r.full.simulated[i])),
        ]
    });
    dir.write(
        "fits.csv",
        csv(
            &[
                "time_s",
                &format!("measured_{suffix}"),
                &format!("baseline_{suffix}"),
                &format!("linear_output_error_{suffix}"),
                &format!("extended_{suffix}"),
            ],
            rows,
        )
        .as_bytes(),
    )?;
    let cycles = o.signatures.per_cycle.iter().map(|c| {
        vec![
            format!("{}", c.time_s),
            format!("{}", c.amplitude_m),
            format!("{}", c.frequency_hz),
        ]
    });
    dir.write(
        "cycles.csv",
        csv(&["time_s", "amplitude_m", "frequency_hz"], cycles).as_bytes(),
    )?;
    dir.write("report.md", markdown(o, &figs).as_bytes())?;
    let json = serde_json::to_string_pretty(&o.diagnosis)
        .map_err(|e| TuneError::Invalid(format!("diagnosis.json: {e}")))?;
    dir.write("diagnosis.json", json.as_bytes())?;
    dir.commit()
}
