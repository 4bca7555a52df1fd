//! The statistics beside reference ranges: `pass`/`miss` per statistic and the markdown
//! table of `report.md`.
//!
//! # Reference ranges (the `reference` object of a case file)
//! ```json
//! "reference": {
//!   "250": { "mean_n": [110, 120], "std_n": [26, 31], "loss_percent": [0, 0] },
//!   "300": { "mean_n": [110, 120], "stat_min_n": [-5, 20] }
//! }
//! ```
//! The outer keys are speeds in km/h (a number written as a JSON string, matched to a run's
//! `speed_km_h` within 1e-6 km/h); the inner keys are the statistics' keys
//! ([`super::KEYS`] but `speed_km_h`); each range is `[lo, hi]` with `lo <= hi`, both ends
//! included: a value passes when `lo <= value <= hi`. A speed or a statistic without a
//! range prints `-` in the range and verdict columns. [`Reference::check`] refuses unknown
//! keys, unparsable speeds and reversed or non-finite ranges, naming the entry.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use super::{speed_label, Statistics, KEYS};
use coil_postproc::error::{PostError, Result};

/// Reference ranges per speed (km/h, as text) and statistic key (module doc).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Reference {
    /// `speed -> key -> [lo, hi]`.
    pub speeds: BTreeMap<String, BTreeMap<String, [f64; 2]>>,
}

/// How close a run's speed must be to a reference speed (km/h).
pub const SPEED_MATCH_KM_H: f64 = 1e-6;

impl Reference {
    /// Checks every entry (module doc); errors name it as `reference."250".std_n`.
    pub fn check(&self) -> Result<()> {
        for (speed, ranges) in &self.speeds {
            let parsed: Option<f64> = speed.trim().parse().ok();
            if !parsed.is_some_and(|v: f64| v.is_finite() && v > 0.0) {
                return Err(PostError::InvalidOption(format!(
                    "reference.\"{speed}\": expected a speed in km/h written as a positive number, e.g. \"250\""
                )));
            }
            for (key, [lo, hi]) in ranges {
                if key == "speed_km_h" || !KEYS.contains(&key.as_str()) {
                    return Err(PostError::InvalidOption(format!(
                        "reference.\"{speed}\".{key}: unknown statistic; expected one of {}",
                        KEYS[1..].join(", ")
                    )));
                }
                if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                    return Err(PostError::InvalidOption(format!(
                        "reference.\"{speed}\".{key}: range [{lo}, {hi}]; expected finite [lo, hi] with lo <= hi"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The range of `key` at `speed_km_h`, if given.
    pub fn range(&self, speed_km_h: f64, key: &str) -> Option<[f64; 2]> {
        self.speeds
            .iter()
            .find(|(speed, _)| {
                speed
                    .trim()
                    .parse::<f64>()
                    .is_ok_and(|v| (v - speed_km_h).abs() <= SPEED_MATCH_KM_H)
            })
            .and_then(|(_, ranges)| ranges.get(key).copied())
    }
}

/// A statistic against its range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Inside the range (ends included).
    Pass,
    /// Outside it.
    Miss,
    /// No range given.
    #[serde(rename = "-")]
    NoRange,
}

impl Verdict {
    /// `pass`, `miss` or `-`.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Miss => "miss",
            Verdict::NoRange => "-",
        }
    }
}

/// One statistic of one run beside its range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The statistic's key.
    pub key: String,
    /// coil's value.
    pub value: f64,
    /// The reference range, if any.
    pub range: Option<[f64; 2]>,
    /// Pass, miss or no range.
    pub verdict: Verdict,
}

/// Every statistic of `statistics` but the speed, in [`KEYS`] order, beside its range.
pub fn verdicts(statistics: &Statistics, reference: &Reference) -> Vec<Row> {
    KEYS[1..]
        .iter()
        .map(|&key| {
            let value = statistics.get(key).unwrap_or(f64::NAN);
            let range = reference.range(statistics.speed_km_h, key);
            let verdict = match range {
                None => Verdict::NoRange,
                Some([lo, hi]) if (lo..=hi).contains(&value) => Verdict::Pass,
                Some(_) => Verdict::Miss,
            };
            Row {
                key: key.to_string(),
                value,
                range,
                verdict,
            }
        })
        .collect()
}

/// What a key measures, for the table's first column.
fn describe(key: &str) -> &'static str {
    match key {
        "mean_n" => "mean contact force (N)",
        "std_n" => "standard deviation (N)",
        "stat_max_n" => "statistical maximum, mean + 3 std (N)",
        "stat_min_n" => "statistical minimum, mean - 3 std (N)",
        "max_n" => "actual maximum (N)",
        "min_n" => "actual minimum (N)",
        "uplift_support_mm" => "largest uplift at a support (mm)",
        "loss_percent" => "time without contact (%)",
        _ => "",
    }
}

/// The `report.md` section: per run (speed), a table of every statistic beside its range
/// with `pass`/`miss`, and a count of the passes.
pub fn markdown(runs: &[Statistics], reference: &Reference) -> String {
    let mut s = String::new();
    for run in runs {
        let rows = verdicts(run, reference);
        let _ = writeln!(s, "### {}\n", speed_label(run.speed_km_h));
        s.push_str("| statistic | key | coil | reference | verdict |\n|---|---|---:|---:|---|\n");
        for row in &rows {
            let range = row
                .range
                .map_or("-".to_string(), |[lo, hi]| format!("{lo} to {hi}"));
            let _ = writeln!(
                s,
                "| {} | `{}` | {:.2} | {} | {} |",
                describe(&row.key),
                row.key,
                row.value,
                range,
                row.verdict.as_str()
            );
        }
        let ranged = rows
            .iter()
            .filter(|r| r.verdict != Verdict::NoRange)
            .count();
        let passed = rows.iter().filter(|r| r.verdict == Verdict::Pass).count();
        let missed: Vec<&str> = rows
            .iter()
            .filter(|r| r.verdict == Verdict::Miss)
            .map(|r| r.key.as_str())
            .collect();
        let _ = writeln!(
            s,
            "\n{passed} of {ranged} statistics with a range pass{}.\n",
            if missed.is_empty() {
                String::new()
            } else {
                format!("; missed: {}", missed.join(", "))
            }
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(speed_km_h: f64) -> Statistics {
        Statistics {
            speed_km_h,
            mean_n: 115.0,
            std_n: 33.0,
            stat_max_n: 214.0,
            stat_min_n: 16.0,
            max_n: 190.0,
            min_n: 55.5,
            uplift_support_mm: 48.0,
            loss_percent: 0.0,
        }
    }

    fn reference() -> Reference {
        serde_json::from_str(
            r#"{
                "250": {"mean_n": [110, 120], "std_n": [26, 31], "loss_percent": [0, 0],
                        "uplift_support_mm": [48, 55]},
                "300.0": {"stat_min_n": [-5, 20], "min_n": [30, 55]}
            }"#,
        )
        .unwrap()
    }

    #[test]
    fn verdicts_include_the_ends_and_missing_ranges_print_a_dash() {
        let reference = reference();
        reference.check().unwrap();
        let rows = verdicts(&run(250.0), &reference);
        let verdict = |key: &str| rows.iter().find(|r| r.key == key).unwrap().verdict;
        assert_eq!(rows.len(), 8);
        assert_eq!(verdict("mean_n"), Verdict::Pass);
        assert_eq!(verdict("std_n"), Verdict::Miss);
        assert_eq!(verdict("loss_percent"), Verdict::Pass);
        assert_eq!(verdict("uplift_support_mm"), Verdict::Pass);
        assert_eq!(verdict("max_n"), Verdict::NoRange);
        let at_300 = verdicts(&run(300.0), &reference);
        assert_eq!(at_300[3].key, "stat_min_n");
        assert_eq!(at_300[3].verdict, Verdict::Pass);
        assert_eq!(at_300[5].verdict, Verdict::Miss);
        assert!(verdicts(&run(200.0), &reference)
            .iter()
            .all(|r| r.verdict == Verdict::NoRange));

        let text = markdown(&[run(250.0), run(300.0)], &reference);
        assert!(text.contains("### 250 km/h"), "{text}");
        assert!(
            text.contains("| standard deviation (N) | `std_n` | 33.00 | 26 to 31 | miss |"),
            "{text}"
        );
        assert!(
            text.contains("| actual maximum (N) | `max_n` | 190.00 | - | - |"),
            "{text}"
        );
        assert!(text.contains("3 of 4 statistics with a range pass; missed: std_n."));
        assert!(
            text.contains("| `stat_min_n` | 16.00 | -5 to 20 | pass |"),
            "{text}"
        );
        assert_eq!(serde_json::to_value(Verdict::NoRange).unwrap(), "-");
        assert_eq!(serde_json::to_value(Verdict::Miss).unwrap(), "miss");
    }

    #[test]
    fn bad_references_are_refused_naming_the_entry() {
        let bad = |json: &str| {
            let r: Reference = serde_json::from_str(json).unwrap();
            r.check().unwrap_err().to_string()
        };
        assert!(bad(r#"{"fast": {"mean_n": [1, 2]}}"#).contains("reference.\"fast\""));
        assert!(bad(r#"{"250": {"mean": [1, 2]}}"#).contains("reference.\"250\".mean: unknown"));
        assert!(bad(r#"{"250": {"std_n": [3, 2]}}"#).contains("lo <= hi"));
        assert!(bad(r#"{"250": {"speed_km_h": [3, 4]}}"#).contains("unknown statistic"));
    }
}
