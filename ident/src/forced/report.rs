//! The files of a forced diagnosis: `diagnosis.json` (the keys of docs/measured-case.md
//! plus `forced_records`), `report.md` with its figures and tables, `model.json` (the
//! extended model) and `model_linear.json` (the linear baseline), all in one output set.

use super::fit::{Effect, Fitted};
use super::frf;
use super::model::{ForcedModel, OutputQuantity};
use super::run::{Candidate, ForcedOutcome};
use super::simulate::{self, Grid};
use crate::diagnose::plots::{self, Panel, Series};
use crate::error::{Result, TuneError};
use crate::output::OutDir;
use serde_json::{json, Map, Value};

fn parameters(fitted: &Fitted) -> (Map<String, Value>, Map<String, Value>) {
    let m = fitted.model.mass;
    let mut p = Map::new();
    let mut se = Map::new();
    for &(e, value, s) in &fitted.effects {
        p.insert(e.parameter().into(), json!(value * m));
        se.insert(e.parameter().into(), json!(s * m.abs()));
    }
    (p, se)
}

fn name_of(effects: &[Effect]) -> String {
    effects
        .iter()
        .map(|e| e.name())
        .collect::<Vec<_>>()
        .join("+")
}

/// Each record's RMS simulation error with `fitted`, output unit.
fn record_errors(fitted: &Fitted) -> Vec<f64> {
    fitted.rms.clone()
}

/// Shares of a pair: each effect's part of the pair's gain over the other alone.
fn shares(o: &ForcedOutcome, cause: &Candidate) -> Vec<(Effect, f64)> {
    if cause.effects.len() == 1 {
        return vec![(cause.effects[0], 1.0)];
    }
    let pair_cost = cause.fitted.as_ref().map_or(f64::NAN, |f| f.cost);
    let parts: Vec<(Effect, f64)> = cause
        .effects
        .iter()
        .map(|&e| {
            // The pair without e is the other effect alone.
            let other = cause.effects.iter().find(|&&x| x != e).copied();
            let alone = o
                .candidates
                .iter()
                .find(|c| c.effects.len() == 1 && Some(c.effects[0]) == other)
                .and_then(|c| c.fitted.as_ref())
                .map_or(f64::NAN, |f| f.cost);
            (e, (alone - pair_cost).max(0.0))
        })
        .collect();
    let total: f64 = parts.iter().map(|p| p.1).sum();
    let mut out: Vec<(Effect, f64)> = parts
        .into_iter()
        .map(|(e, v)| (e, if total > 0.0 { v / total } else { 0.5 }))
        .collect();
    out.sort_by(|a, b| b.1.total_cmp(&a.1));
    out
}

/// The effect of largest share: the report's `cause`.
pub fn first_cause(o: &ForcedOutcome, cause: &Candidate) -> Effect {
    shares(o, cause)[0].0
}

/// diagnosis.json.
pub fn document(o: &ForcedOutcome) -> Value {
    let b = &o.baseline;
    let mut baseline = Map::new();
    for (k, v) in b.model.physical() {
        baseline.insert(k.into(), json!(v));
    }
    baseline.insert("residual_rms".into(), json!(o.baseline_residual));
    baseline.insert("forecast_rms".into(), json!(o.baseline_forecast));
    let candidates: Vec<Value> = o
        .candidates
        .iter()
        .map(|c| {
            let (p, se) = c.fitted.as_ref().map(parameters).unwrap_or_default();
            json!({
                "effect": name_of(&c.effects),
                "parameters": p,
                "parameters_se": se,
                "residual_rms": c.residual_rms,
                "forecast_rms": c.forecast_rms,
                "dbic": c.dbic,
                "tests": {
                    "significant": c.tests.significant,
                    "forecasts": c.tests.forecasts,
                    "identified": c.tests.identified,
                    "signature": c.tests.signature,
                },
                "evidence": c.evidence,
            })
        })
        .collect();
    let cause = o.cause.map(|i| &o.candidates[i]);
    let (extended, causes, gain) = match cause.and_then(|c| c.fitted.as_ref().map(|f| (c, f))) {
        Some((c, f)) => {
            let (p, se) = parameters(f);
            let causes: Vec<Value> = shares(o, c)
                .into_iter()
                .map(|(e, share)| {
                    let value = f
                        .effects
                        .iter()
                        .find(|x| x.0 == e)
                        .map_or(f64::NAN, |x| x.1 * f.model.mass);
                    json!({"effect": e.name(), "parameters": {e.parameter(): value}, "share": share})
                })
                .collect();
            (
                json!({
                    "effect": first_cause(o, c).name(),
                    "parameters": p,
                    "parameters_se": se,
                    "residual_rms": c.residual_rms,
                    "forecast_rms": c.forecast_rms,
                }),
                json!(causes),
                json!({
                    "residual_rms_ratio": c.residual_rms / o.baseline_residual,
                    "forecast_rms_ratio": c.forecast_rms / o.baseline_forecast,
                }),
            )
        }
        None => (Value::Null, json!([]), Value::Null),
    };
    let extended_fit = o.extended();
    let lin_err = record_errors(b);
    let ext_err = record_errors(extended_fit);
    let records: Vec<Value> = o
        .case
        .records
        .iter()
        .enumerate()
        .map(|(k, r)| {
            json!({
                "file": r.entry.file.file_name().map(|f| f.to_string_lossy().to_string()),
                "samples": r.output.len(),
                "sample_rate_hz": 1.0 / r.dt,
                "input_rms": (r.input.iter().map(|u| u * u).sum::<f64>() / r.input.len() as f64).sqrt(),
                "output_unit": r.entry.output_unit,
                "rms_simulation_error_linear": lin_err[k],
                "rms_simulation_error": ext_err[k],
            })
        })
        .collect();
    let mut doc = json!({
        "kind": "forced",
        "model": b.model.kind,
        "cause": cause.map_or("none", |c| first_cause(o, c).name()),
        "baseline": baseline,
        "extended": extended,
        "candidates": candidates,
        "causes": causes,
        "gain": gain,
        "forced_records": records,
        "warnings": o.warnings,
        "seconds": o.seconds,
    });
    if let Some(u) = &o.unexplained {
        doc["unexplained"] = json!(u);
    }
    doc
}

/// A model file's text.
pub fn model_text(model: &ForcedModel) -> String {
    let mut s = serde_json::to_string_pretty(model).unwrap_or_default();
    s.push('\n');
    s
}

fn yes(b: bool) -> &'static str {
    if b {
        "pass"
    } else {
        "fail"
    }
}

/// report.md.
fn markdown(o: &ForcedOutcome, figures: &[(&str, &str)]) -> String {
    let b = &o.baseline;
    let unit = &o.case.records[0].entry.output_unit;
    let mut s = format!("# Forced diagnosis: {}\n\n", o.case.name);
    s.push_str(&format!(
        "Cause: **{}**. {} forced record(s), {} samples, {:.1} s of computing.\n\n",
        o.cause
            .map_or("none".to_string(), |i| name_of(&o.candidates[i].effects)),
        o.case.records.len(),
        o.case.records.iter().map(|r| r.output.len()).sum::<usize>(),
        o.seconds
    ));
    s.push_str("## Linear model (output error, initial state fitted)\n\n| quantity | value |\n| --- | --- |\n");
    for (k, v) in b.model.physical() {
        s.push_str(&format!("| {k} | {v:.6e} |\n"));
    }
    s.push_str(&format!(
        "| residual_rms (relative) | {:.5} |\n| forecast_rms (relative) | {:.5} |\n\n",
        o.baseline_residual, o.baseline_forecast
    ));
    s.push_str("## Candidates (the four tests)\n\n| effect | residual_rms | forecast_rms | dBIC | significant | forecasts | identified | signature |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for c in &o.candidates {
        s.push_str(&format!(
            "| {} | {:.5} | {:.5} | {:.1} | {} | {} | {} | {} |\n",
            name_of(&c.effects),
            c.residual_rms,
            c.forecast_rms,
            c.dbic,
            yes(c.tests.significant),
            yes(c.tests.forecasts),
            yes(c.tests.identified),
            c.tests.signature.map_or("n/a", yes)
        ));
    }
    s.push('\n');
    for c in &o.candidates {
        s.push_str(&format!("- {}: {}\n", name_of(&c.effects), c.evidence));
    }
    s.push_str(&format!(
        "\n## RMS simulation error per record ({unit})\n\n| record | linear | extended |\n| --- | --- | --- |\n"
    ));
    let e = o.extended();
    for (k, r) in o.case.records.iter().enumerate() {
        s.push_str(&format!(
            "| {} | {:.5e} | {:.5e} |\n",
            r.entry.file.display(),
            b.rms[k],
            e.rms[k]
        ));
    }
    if !o.levels.is_empty() {
        s.push_str("\n## H1 per input level\n\n| input RMS | H1 peak (Hz) | lines |\n| --- | --- | --- |\n");
        for l in &o.levels {
            s.push_str(&format!(
                "| {:.4e} | {:.4} | {} |\n",
                l.input_rms,
                l.peak_hz,
                l.lines.len()
            ));
        }
    }
    if let Some(u) = &o.unexplained {
        s.push_str(&format!("\n## Unexplained\n\n{u}\n"));
    }
    if !o.warnings.is_empty() {
        s.push_str("\n## Warnings\n\n");
        for w in &o.warnings {
            s.push_str(&format!("- {w}\n"));
        }
    }
    if !figures.is_empty() {
        s.push_str("\n## Figures\n\n");
        for (f, what) in figures {
            s.push_str(&format!("![{what}]({f})\n\n"));
        }
    }
    s.push_str("\nModels: `model.json` (extended), `model_linear.json` (linear baseline); run them with `coil-tune simulate` and `coil-tune frc` (docs/forced.md).\n");
    s
}

fn simulated(f: &Fitted, k: usize, o: &ForcedOutcome) -> Vec<f64> {
    let r = &o.case.records[k];
    let grid = Grid {
        dt: r.dt,
        substeps: f.scales.substeps,
    };
    simulate::output(
        &f.model,
        grid,
        &r.input,
        f.initial[k],
        simulate::bound_for(1e3 * f.scales.z),
    )
    .unwrap_or_default()
}

fn figures(o: &ForcedOutcome, dir: &std::path::Path) -> Result<Vec<(&'static str, &'static str)>> {
    let mut list = Vec::new();
    let r = &o.case.records[0];
    let unit = r.entry.output_unit.clone();
    let lin = simulated(&o.baseline, 0, o);
    let ext = simulated(o.extended(), 0, o);
    let t = |i: usize| r.t0 + i as f64 * r.dt;
    let line = |label: &str, y: &[f64]| Series {
        label: label.into(),
        points: plots::decimate(
            &y.iter()
                .enumerate()
                .map(|(i, v)| (t(i), *v))
                .collect::<Vec<_>>(),
        ),
        markers: false,
    };
    let n = r.output.len();
    let zoom_from = n.saturating_sub(400);
    let zoom = |label: &str, y: &[f64]| Series {
        label: label.into(),
        points: (zoom_from..y.len().min(n)).map(|i| (t(i), y[i])).collect(),
        markers: false,
    };
    let res_lin: Vec<f64> = lin.iter().zip(&r.output).map(|(a, b)| a - b).collect();
    let res_ext: Vec<f64> = ext.iter().zip(&r.output).map(|(a, b)| a - b).collect();
    plots::draw(
        &dir.join("forced_fit.png"),
        vec![
            Panel {
                title: "output: measured and simulated".into(),
                x: "time (s)".into(),
                y: unit.clone(),
                series: vec![line("measured", &r.output), line("extended", &ext)],
            },
            Panel {
                title: "the last 400 samples".into(),
                x: "time (s)".into(),
                y: unit.clone(),
                series: vec![
                    zoom("measured", &r.output),
                    zoom("linear", &lin),
                    zoom("extended", &ext),
                ],
            },
            Panel {
                title: "simulation error".into(),
                x: "time (s)".into(),
                y: unit.clone(),
                series: vec![line("linear", &res_lin), line("extended", &res_ext)],
            },
        ],
    )?;
    list.push((
        "forced_fit.png",
        "measured against simulated, and the errors",
    ));
    if !o.levels.is_empty() {
        let series: Vec<Series> = o
            .levels
            .iter()
            .map(|l| Series {
                label: format!("input RMS {:.3e}", l.input_rms),
                points: l.lines.iter().map(|x| (x.0, x.1)).collect(),
                markers: false,
            })
            .collect();
        plots::draw(
            &dir.join("frf_levels.png"),
            vec![Panel {
                title: "H1 per input level".into(),
                x: "frequency (Hz)".into(),
                y: format!("|H1| ({unit} per {})", r.entry.input_unit),
                series,
            }],
        )?;
        list.push(("frf_levels.png", "H1 frequency response per input level"));
    }
    if o.baseline.model.output_quantity == OutputQuantity::Displacement {
        let stride = (n / 3000).max(1);
        let points = frf::restoring_force(&o.baseline.model, r.dt, &r.input, &r.output, stride);
        let e = &o.extended().model.oscillator;
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.0), b.max(p.0))
            });
        let curve: Vec<(f64, f64)> = (0..=100)
            .map(|i| {
                let z = lo + (hi - lo) * i as f64 / 100.0;
                let w = e.natural_frequency_rad_s;
                (z, w * w * z + e.cubic * z * z * z)
            })
            .collect();
        plots::draw(
            &dir.join("restoring_force.png"),
            vec![Panel {
                title: "restoring force per unit mass, less the linear damping".into(),
                x: format!("displacement ({unit})"),
                y: format!("{unit}/s^2"),
                series: vec![
                    Series {
                        label: "from the record".into(),
                        points,
                        markers: true,
                    },
                    Series {
                        label: "extended model's spring".into(),
                        points: curve,
                        markers: false,
                    },
                ],
            }],
        )?;
        list.push((
            "restoring_force.png",
            "restoring force against displacement",
        ));
    }
    Ok(list)
}

/// Writes every file of a forced diagnosis into `out` (one set).
pub fn write(o: &ForcedOutcome, out: &OutDir, plots_wanted: bool) -> Result<()> {
    let json_err = |e: serde_json::Error| TuneError::Invalid(format!("diagnosis.json: {e}"));
    let doc = serde_json::to_string_pretty(&document(o)).map_err(json_err)?;
    out.write("diagnosis.json", format!("{doc}\n").as_bytes())?;
    out.write("model.json", model_text(&o.extended().model).as_bytes())?;
    out.write(
        "model_linear.json",
        model_text(&o.baseline.model).as_bytes(),
    )?;
    let figures = if plots_wanted {
        let dir = out.staging_folder()?;
        figures(o, &dir)?
    } else {
        Vec::new()
    };
    out.write("report.md", markdown(o, &figures).as_bytes())?;
    out.commit()
}

/// The console summary.
pub fn summary(o: &ForcedOutcome) -> String {
    let b = &o.baseline;
    let w = b.model.oscillator.natural_frequency_rad_s / std::f64::consts::TAU;
    let mut s = format!(
        "linear (output error): f0 = {w:.5} Hz, zeta = {:.5}, gain = {:.5e}, residual_rms = {:.5}, forecast_rms = {:.5}\n",
        b.model.oscillator.damping_ratio, b.model.oscillator.input_gain, o.baseline_residual, o.baseline_forecast
    );
    for c in &o.candidates {
        s.push_str(&format!(
            "  {:<36} residual_rms {:8.5} forecast_rms {:8.5} dBIC {:10.1}{}\n",
            name_of(&c.effects),
            c.residual_rms,
            c.forecast_rms,
            c.dbic,
            if c.tests.pass() { " passes" } else { "" }
        ));
    }
    match o.cause {
        Some(i) => {
            let c = &o.candidates[i];
            let (p, _) = c.fitted.as_ref().map(parameters).unwrap_or_default();
            let words: Vec<String> = p
                .iter()
                .map(|(k, v)| match v.as_f64() {
                    Some(x) => format!("{k} = {x:.6e}"),
                    None => format!("{k} = {v}"),
                })
                .collect();
            s.push_str(&format!(
                "cause: {} ({}), {}; gain: residual_rms_ratio {:.4}, forecast_rms_ratio {:.4}",
                first_cause(o, c).name(),
                name_of(&c.effects),
                words.join(", "),
                c.residual_rms / o.baseline_residual,
                c.forecast_rms / o.baseline_forecast
            ));
        }
        None => s.push_str(&format!(
            "cause: none; {}",
            o.unexplained.clone().unwrap_or_default()
        )),
    }
    s
}
