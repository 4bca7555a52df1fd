//! What `coil-tune damping` found and how it is written: the report's types, `report.md`,
//! `damping.json` and the terminal summary.

use super::fit::{Candidate, RecordFit};
use crate::error::{Result, TuneError};
use crate::scatter::RepeatScatter;
use coil_tuner::band::{band_markdown, Band, Law};
use serde::Serialize;
use std::collections::BTreeMap;

/// A variant's zeta predicted by a law.
#[derive(Debug, Clone, Serialize)]
pub struct VariantPrediction {
    /// The variant's name.
    pub name: String,
    /// zeta of the variant's weight mode under each candidate law (its own fit).
    pub by_law: BTreeMap<String, f64>,
    /// The chosen law's zeta and its standard error (when a law is chosen).
    pub damping_ratio: Option<f64>,
    /// Standard error of the chosen law's zeta (-).
    pub damping_ratio_se: Option<f64>,
    /// `(max - min) / min` over the laws, in percent.
    pub spread_percent: f64,
    /// The paper's printed zeta of the variant, when given (-).
    pub paper_damping_ratio: Option<f64>,
}

/// The deciding test proposed when the law is not identifiable.
#[derive(Debug, Clone, Serialize)]
pub struct DecidingTest {
    /// The repeat-to-repeat scatter of one zeta measurement assumed (relative, 1 sigma).
    pub scatter: f64,
    /// Second mass: (mass ratio, hysteretic/viscous zeta ratio, repeats per mass for a
    /// separation the verdict decides on, [`repeats_needed`]). Separates hysteretic from
    /// viscous only.
    pub second_mass: Vec<(f64, f64, usize)>,
    /// Surge-mode zeta (weight held) each calibrated law predicts.
    pub surge_zeta: BTreeMap<String, f64>,
    /// The surge mode's frequency on the calibrated spring with the weight held (Hz).
    pub surge_frequency_hz: f64,
    /// The proposal in words with its numbers.
    pub text: String,
}

/// Everything `coil-tune damping` found.
#[derive(Debug, Clone, Serialize)]
pub struct DampingReport {
    /// The case's name.
    pub case: String,
    /// The chosen law; `None` when the records cannot decide.
    pub law: Option<Law>,
    /// The chosen law's parameters by the spec's names (empty when none is chosen).
    pub parameters: BTreeMap<String, f64>,
    /// Their standard errors (empty when no law is chosen).
    pub parameters_se: BTreeMap<String, f64>,
    /// True when a law was chosen.
    pub identifiable: bool,
    /// Why the law was chosen, or why none could be.
    pub reason: String,
    /// The repeat scatter of one test's zeta the records were judged with.
    pub scatter: RepeatScatter,
    /// Every decay record reduced to its frequency and damping ratio.
    pub records: Vec<RecordFit>,
    /// Every law fitted to all the records.
    pub candidates: Vec<Candidate>,
    /// The Table 4 variants' zeta under each law (empty without a variants file).
    pub table4: Vec<VariantPrediction>,
    /// The measurement that would decide, when no law is chosen.
    pub deciding_test: Option<DecidingTest>,
    /// When not identifiable: the band of section 2 for the case's spring (each law
    /// calibrated to the first weight-mode record; the variants when given, and the
    /// surge mode).
    pub band: Option<Band>,
}

/// Writes report.md and damping.json into `out` and commits them as one set.
pub fn write(r: &DampingReport, out: &crate::output::OutDir) -> Result<()> {
    let json = serde_json::to_string_pretty(&report_json(r))
        .map_err(|e| TuneError::Invalid(format!("damping.json: {e}")))?;
    out.write("report.md", report_markdown(r).as_bytes())?;
    out.write("damping.json", json.as_bytes())?;
    out.commit()
}

/// damping.json (the spec's fields first, then the evidence).
pub fn report_json(r: &DampingReport) -> serde_json::Value {
    let candidates: Vec<serde_json::Value> = r
        .candidates
        .iter()
        .map(|c| {
            serde_json::json!({
                "law": c.law.name(),
                "parameters": c.parameters,
                "parameters_se": c.parameters_se,
                "parameters_identified": c.parameters_identified,
                "residual_rms": c.residual_rms,
                "chi2": c.chi2,
                "dof": c.dof,
                "at_bound": c.at_bound,
                "test": c.test,
                "bic": c.bic,
                "held_out": c.held_out,
                "consistent": c.consistent,
                "predicted_damping_ratio": c.predicted,
            })
        })
        .collect();
    serde_json::json!({
        "law": r.law.map(Law::name),
        "parameters": r.parameters,
        "parameters_se": r.parameters_se,
        "identifiable": r.identifiable,
        "candidates": candidates,
        "reason": r.reason,
        "repeat_scatter": r.scatter,
        "case": r.case,
        "records": r.records,
        "table4": r.table4,
        "deciding_test": r.deciding_test,
        "band": r.band,
    })
}

/// A terminal summary.
pub fn summary(r: &DampingReport) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for rec in &r.records {
        let _ = writeln!(
            s,
            "record {} ({:?}, {:.3} kg): f = {:.4} Hz, zeta = {:.6} +- {:.6}",
            rec.name(),
            rec.mode,
            rec.mass_kg,
            rec.frequency_hz,
            rec.damping_ratio,
            rec.damping_ratio_se
        );
    }
    for c in &r.candidates {
        let _ = writeln!(
            s,
            "  {:17} chi2 {:10.2} BIC {:10.2} held-out {:>9} {}  {}",
            c.law.name(),
            c.chi2,
            c.bic,
            c.held_out_text(),
            if c.consistent {
                "consistent  "
            } else {
                "inconsistent"
            },
            c.parameters_text()
        );
    }
    let _ = writeln!(s, "repeat scatter of zeta: {}", r.scatter.text());
    let _ = writeln!(
        s,
        "law: {} ({})",
        r.law.map_or("null (not identifiable)", Law::name),
        r.reason
    );
    for v in &r.table4 {
        let laws: Vec<String> = v
            .by_law
            .iter()
            .map(|(k, z)| format!("{k} {z:.5}"))
            .collect();
        let _ = writeln!(
            s,
            "  {:4} {}{}  spread {:.1}%",
            v.name,
            laws.join("  "),
            match (v.damping_ratio, v.damping_ratio_se) {
                (Some(z), Some(e)) => format!("  chosen {z:.5} +- {e:.5}"),
                _ => String::new(),
            },
            v.spread_percent
        );
    }
    if let Some(t) = &r.deciding_test {
        let _ = writeln!(s, "deciding test: {}", t.text);
    }
    s
}

/// report.md: the records, the candidates, the verdict, Table 4 and the deciding test.
pub fn report_markdown(r: &DampingReport) -> String {
    use std::fmt::Write as _;
    let mut s = format!("# Which damping law? ({})\n\n", r.case);
    s.push_str("| record | mode | mass (kg) | f (Hz) | zeta | se | fit residual |\n|---|---|---:|---:|---:|---:|---:|\n");
    for rec in &r.records {
        let _ = writeln!(
            s,
            "| {} | {:?} | {:.3} | {:.4} | {:.6} | {:.2e} | {:.3} |",
            rec.name(),
            rec.mode,
            rec.mass_kg,
            rec.frequency_hz,
            rec.damping_ratio,
            rec.damping_ratio_se,
            rec.residual_rms
        );
    }
    let _ = writeln!(
        s,
        "\nRepeat scatter of one test's zeta: {}. Each record's zeta is uncertain by its fit \
         error and this scatter; a law is named when it fits within it and every other law \
         misses beyond it (test: chi-square with the default scatter, the lack-of-fit F \
         against the repeats' pure error with an estimated one; 99.9 % points).",
        r.scatter.text()
    );
    s.push_str("\n| law | parameters (+- se) | chi2 | dof | test (99.9 % point) | held at 0 | BIC | held-out | consistent |\n|---|---|---:|---:|---:|---|---:|---:|---|\n");
    for c in &r.candidates {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {} | {} | {} | {:.2} | {} | {} |",
            c.law.name(),
            c.parameters_text(),
            c.chi2,
            c.dof,
            if c.test.dof == 0 {
                "exactly determined".to_string()
            } else {
                format!("{:.2} ({:.2})", c.test.statistic, c.test.critical)
            },
            if c.at_bound.is_empty() {
                "-".to_string()
            } else {
                c.at_bound.join(", ")
            },
            c.bic,
            c.held_out_text(),
            c.consistent
        );
    }
    let _ = writeln!(
        s,
        "\n**Law: {}.** {}\n",
        r.law.map_or("not identifiable", Law::name),
        r.reason
    );
    if !r.table4.is_empty() {
        s.push_str("| variant | rayleigh | hysteretic | external_viscous | spread | chosen law (+- se) | paper |\n|---|---:|---:|---:|---:|---:|---:|\n");
        for v in &r.table4 {
            let g = |k: &str| {
                v.by_law
                    .get(k)
                    .map_or("-".to_string(), |z| format!("{z:.5}"))
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.1}% | {} | {} |",
                v.name,
                g("rayleigh"),
                g("hysteretic"),
                g("external_viscous"),
                v.spread_percent,
                match (v.damping_ratio, v.damping_ratio_se) {
                    (Some(z), Some(e)) => format!("{z:.5} +- {e:.5}"),
                    _ => "-".to_string(),
                },
                v.paper_damping_ratio
                    .map_or("-".to_string(), |z| format!("{z}"))
            );
        }
    }
    if let Some(b) = &r.band {
        let _ = writeln!(
            s,
            "\n## The band these records allow\n\n{}",
            band_markdown(b)
        );
    }
    if let Some(t) = &r.deciding_test {
        let _ = writeln!(s, "\n## The test that would decide\n\n{}", t.text);
    }
    s
}
