//! Scoring a diagnosis against the truth that generated its case, for the generated-case
//! test (`tests/tests/it/diagnose.rs`) and the benchmark (`examples/bench_diagnose.rs`).
//!
//! A diagnosis is read from its `diagnosis.json` value (the spec's fields), so the
//! scoring does not depend on the engine's Rust types: the named causes are `causes[*]
//! .effect` when the report has several (`docs/measured-case.md`, "Several
//! effects at once"), else `cause` (nothing for `none`); parameters come from
//! `extended.parameters`, which holds those of every effect kept.
//!
//! A case is **named right** when the set of named effects equals the set of hidden ones
//! ([`TruthCase::causes`]; empty for a null case). Each hidden parameter must then be
//! within [`PARAMETER_TOLERANCE`] (the 15 %).

use crate::truth::TruthCase;
use std::collections::BTreeMap;

/// Largest relative parameter error accepted.
pub const PARAMETER_TOLERANCE: f64 = 0.15;

/// One scored case.
#[derive(Debug, Clone)]
pub struct Score {
    pub name: String,
    /// The hidden effects, sorted, joined with `+` (`none` for a null case).
    pub truth: String,
    /// The named effects, sorted, joined with `+` (`none` when nothing is named).
    pub named: String,
    /// (parameter, relative error) for each hidden parameter (NaN when not reported).
    pub parameter_errors: Vec<(String, f64)>,
    pub residual_rms_ratio: Option<f64>,
    pub model_error_ratio: Option<f64>,
    /// The baseline misses by less than 2.5 times the noise (no model can halve it).
    pub noise_limited: bool,
    /// Wall time of the diagnosis (s).
    pub runtime_s: f64,
    /// The report's warnings (the conditioning's cut and resampling among them).
    pub warnings: Vec<String>,
    /// Combinations whose residual exceeds a part's on the same mount ([`nesting`]).
    pub nesting: Vec<String>,
    /// Combinations compared with their parts (for the table's count).
    pub nested_pairs: usize,
}

impl Score {
    /// Named right (see the module docs).
    pub fn named_right(&self) -> bool {
        self.truth == self.named
    }

    /// What is wrong with this case, if anything: the named set, a parameter beyond the
    /// tolerance, and the gain where the baseline stands clear of the noise.
    pub fn failures(&self) -> Vec<String> {
        let mut out = self.nesting.clone();
        if !self.named_right() {
            out.push(format!(
                "{}: named {} for {}",
                self.name, self.named, self.truth
            ));
            return out;
        }
        for (name, error) in &self.parameter_errors {
            if error.is_nan() || error.abs() >= PARAMETER_TOLERANCE {
                out.push(format!("{}: {name} error {error:+.3}", self.name));
            }
        }
        if self.truth != "none" {
            if let Some(m) = self.model_error_ratio {
                if m.is_nan() || m >= 0.5 {
                    out.push(format!("{}: model error ratio {m:.3}", self.name));
                }
            }
            if let Some(r) = self.residual_rms_ratio {
                if !self.noise_limited && (r.is_nan() || r >= 0.5) {
                    out.push(format!("{}: residual ratio {r:.3}", self.name));
                }
            }
        }
        out
    }
}

fn label(mut names: Vec<String>) -> String {
    names.sort();
    names.dedup();
    if names.is_empty() {
        "none".into()
    } else {
        names.join("+")
    }
}

/// The effects a diagnosis names (module docs).
pub fn named_effects(diagnosis: &serde_json::Value) -> Vec<String> {
    if let Some(causes) = diagnosis["causes"].as_array() {
        return causes
            .iter()
            .filter_map(|c| c["effect"].as_str().map(str::to_string))
            .filter(|e| e != "none")
            .collect();
    }
    match diagnosis["cause"].as_str() {
        Some("none") | None => Vec::new(),
        Some(cause) => vec![cause.to_string()],
    }
}

/// Scores one diagnosis (its `diagnosis.json` as a value) against its case.
pub fn score(case: &TruthCase, diagnosis: &serde_json::Value, runtime_s: f64) -> Score {
    let truth = label(case.causes().iter().map(|c| c.0.to_string()).collect());
    let named = label(named_effects(diagnosis));
    let parameters = &diagnosis["extended"]["parameters"];
    let parameter_errors = case
        .causes()
        .iter()
        .map(|(_, name, value)| {
            let found = parameters[*name].as_f64().unwrap_or(f64::NAN);
            (name.to_string(), found / value - 1.0)
        })
        .collect();
    let has_extension = !diagnosis["extended"].is_null();
    let gain = |key: &str| {
        has_extension
            .then(|| diagnosis["gain"][key].as_f64())
            .flatten()
    };
    let noise = diagnosis["noise_floor_rms"].as_f64().unwrap_or(0.0);
    let baseline = diagnosis["baseline"]["residual_rms"]
        .as_f64()
        .unwrap_or(f64::INFINITY);
    let (nesting, nested_pairs) = nesting(diagnosis);
    Score {
        name: case.name.clone(),
        nesting,
        nested_pairs,
        truth,
        named,
        parameter_errors,
        residual_rms_ratio: gain("residual_rms_ratio"),
        model_error_ratio: gain("model_error_ratio"),
        noise_limited: noise >= 0.4 * baseline,
        runtime_s,
        warnings: diagnosis["warnings"]
            .as_array()
            .map(|w| {
                w.iter()
                    .filter_map(|s| s.as_str().map(str::to_string))
                    .collect()
            })
            .unwrap_or_default(),
    }
}

/// Relative slack of the nesting check: the residuals are computed from the same
/// simulation of the same point, so equal up to rounding.
pub const NESTING_SLACK: f64 = 1e-9;

/// The nesting invariant over a diagnosis's candidates: a combination's
/// `residual_rms` never exceeds that of any of its parts (a candidate whose effects
/// are a proper subset of it) fitted on the same mount (the coupling frees the
/// weight's rotation, so a part with it and a part without it are different models).
/// Returns the violations, in words, and the number of (combination, part) pairs
/// compared.
pub fn nesting(diagnosis: &serde_json::Value) -> (Vec<String>, usize) {
    let Some(list) = diagnosis["candidates"].as_array() else {
        return (Vec::new(), 0);
    };
    let parsed: Vec<(Vec<String>, Option<f64>)> = list
        .iter()
        .map(|c| {
            let effects = c["effects"]
                .as_array()
                .map(|e| {
                    e.iter()
                        .filter_map(|x| x.as_str().map(str::to_string))
                        .collect()
                })
                .unwrap_or_default();
            (effects, c["residual_rms"].as_f64())
        })
        .collect();
    let free = |e: &[String]| e.iter().any(|x| x == "axial_torsional_coupling");
    let mut out = Vec::new();
    let mut pairs = 0;
    for (set, rms) in &parsed {
        if set.len() < 2 {
            continue;
        }
        for (part, part_rms) in &parsed {
            let proper = part.len() < set.len() && part.iter().all(|e| set.contains(e));
            if !proper || free(part) != free(set) {
                continue;
            }
            let Some(p) = part_rms else { continue };
            pairs += 1;
            match rms {
                Some(r) if *r <= p * (1.0 + NESTING_SLACK) => {}
                _ => out.push(format!(
                    "{}: combination {} has residual {:?} above its part {}'s {p:.6}",
                    diagnosis["cause"],
                    set.join("+"),
                    rms,
                    part.join("+")
                )),
            }
        }
    }
    (out, pairs)
}

/// How a diagnosis answers a record outside the catalogue (no catalogue effect
/// hidden): an honest answer is `refused` (the reader's checks stopped it, with the
/// reason), `unexplained` (cause `none`, the misfit described), `none` (the linear
/// model fits within three times the noise) or a cause whose `remaining_misfit` is
/// reported; a cause named without it is a **false cause**.
#[derive(Debug, Clone)]
pub struct OutsideScore {
    pub name: String,
    /// The law outside the catalogue.
    pub anomaly: String,
    /// `refused`, `unexplained`, `none`, `named X, misfit reported` or `FALSE CAUSE X`.
    pub verdict: String,
    /// True for a confident wrong cause.
    pub false_cause: bool,
    /// The reason given (the error, the unexplained text or the misfit), shortened.
    pub reason: String,
    pub runtime_s: f64,
}

/// Scores the answer to an out-of-catalogue case: `Err` is the run's error text.
pub fn score_outside(
    case: &TruthCase,
    anomaly: &str,
    diagnosis: Result<&serde_json::Value, &str>,
    runtime_s: f64,
) -> OutsideScore {
    let short = |t: &str| t.chars().take(160).collect::<String>();
    let (verdict, false_cause, reason) = match diagnosis {
        Err(e) => ("refused".to_string(), false, short(e)),
        Ok(d) => {
            let named = label(named_effects(d));
            match (
                named.as_str(),
                d["unexplained"].as_str(),
                d["remaining_misfit"].as_str(),
            ) {
                ("none", Some(u), _) => ("unexplained".to_string(), false, short(u)),
                ("none", None, _) => ("none".to_string(), false, String::new()),
                (x, _, Some(m)) => (format!("named {x}, misfit reported"), false, short(m)),
                (x, _, None) => (format!("FALSE CAUSE {x}"), true, String::new()),
            }
        }
    };
    OutsideScore {
        name: case.name.clone(),
        anomaly: anomaly.to_string(),
        verdict,
        false_cause,
        reason,
        runtime_s,
    }
}

/// The out-of-catalogue table as text, with the count of false causes.
pub fn outside_report(scores: &[OutsideScore]) -> String {
    let mut out = format!(
        "{:24} {:18} {:48} {:>7}\n",
        "case", "law", "answer", "time s"
    );
    for s in scores {
        out.push_str(&format!(
            "{:24} {:18} {:48} {:>7.2}\n",
            s.name, s.anomaly, s.verdict, s.runtime_s
        ));
        if !s.reason.is_empty() {
            out.push_str(&format!("    {}\n", s.reason));
        }
    }
    let false_causes = scores.iter().filter(|s| s.false_cause).count();
    let unexplained = scores.iter().filter(|s| s.verdict == "unexplained").count();
    out.push_str(&format!(
        "\n{} cases: {false_causes} false causes, {unexplained} unexplained\n",
        scores.len()
    ));
    out
}

/// The confusion table (rows: hidden effects, columns: named effects; counts), the
/// per-case table (parameter errors, gains, runtime) and the runtimes' median and
/// worst, as text.
pub fn report(scores: &[Score]) -> String {
    let mut out = String::new();
    let mut truths: Vec<&str> = scores.iter().map(|s| s.truth.as_str()).collect();
    truths.sort_unstable();
    truths.dedup();
    let mut columns: Vec<&str> = scores.iter().map(|s| s.named.as_str()).collect();
    columns.extend(truths.iter().copied());
    columns.sort_unstable();
    columns.dedup();
    let mut counts: BTreeMap<(&str, &str), usize> = BTreeMap::new();
    for s in scores {
        *counts.entry((&s.truth, &s.named)).or_default() += 1;
    }
    out.push_str("confusion table (rows: hidden effects; columns: named effects)\n");
    out.push_str(&format!("| {:48} |", "hidden \\ named"));
    for (i, _) in columns.iter().enumerate() {
        out.push_str(&format!(" c{i:<2} |"));
    }
    out.push('\n');
    for t in &truths {
        out.push_str(&format!("| {t:48} |"));
        for c in &columns {
            let n = counts.get(&(*t, *c)).copied().unwrap_or(0);
            let cell = if n == 0 {
                ".".to_string()
            } else {
                n.to_string()
            };
            let cell = if t == c { format!("[{cell}]") } else { cell };
            out.push_str(&format!(" {cell:>3} |"));
        }
        out.push('\n');
    }
    for (i, c) in columns.iter().enumerate() {
        out.push_str(&format!("  c{i} = {c}\n"));
    }
    let right = scores.iter().filter(|s| s.named_right()).count();
    out.push_str(&format!(
        "named right: {right} of {} ([n] on the diagonal)\n\n",
        scores.len()
    ));
    out.push_str(&format!(
        "{:28} {:44} {:44} {:>32} {:>7} {:>7} {:>5} {:>7}\n",
        "case", "hidden", "named", "parameter errors", "res", "model", "noise", "time s"
    ));
    for s in scores {
        let errors: Vec<String> = s
            .parameter_errors
            .iter()
            .map(|(_, e)| format!("{:+.2}%", 100.0 * e))
            .collect();
        out.push_str(&format!(
            "{:28} {:44} {:44} {:>32} {:>7} {:>7} {:>5} {:>7.2}{}\n",
            s.name,
            s.truth,
            s.named,
            if errors.is_empty() {
                "-".into()
            } else {
                errors.join(" ")
            },
            s.residual_rms_ratio
                .map_or("-".into(), |x| format!("{x:.3}")),
            s.model_error_ratio
                .map_or("-".into(), |x| format!("{x:.3}")),
            if s.noise_limited { "yes" } else { "no" },
            s.runtime_s,
            if s.named_right() { "" } else { "  *" }
        ));
    }
    let pairs: usize = scores.iter().map(|s| s.nested_pairs).sum();
    let broken: usize = scores.iter().map(|s| s.nesting.len()).sum();
    out.push_str(&format!(
        "\nnesting: {pairs} (combination, part) pairs compared, {broken} with the combination's \
         residual above its part's\n"
    ));
    let worst = scores
        .iter()
        .flat_map(|s| {
            s.parameter_errors
                .iter()
                .map(move |(p, e)| (e.abs(), &s.name, p))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((e, name, p)) = worst {
        out.push_str(&format!(
            "worst parameter error: {:.2} % ({name}, {p})\n",
            100.0 * e
        ));
    }
    let mut times: Vec<f64> = scores.iter().map(|s| s.runtime_s).collect();
    times.sort_by(f64::total_cmp);
    if let Some(&worst) = times.last() {
        let n = times.len();
        let median = if n % 2 == 1 {
            times[n / 2]
        } else {
            0.5 * (times[n / 2 - 1] + times[n / 2])
        };
        out.push_str(&format!(
            "\nruntime over {n} cases: median {median:.2} s, worst {worst:.2} s\n"
        ));
    }
    out
}
