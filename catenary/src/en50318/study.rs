//! The spring study: runs of one catenary with each head-stage spring at each damping value
//! of its band and each speed, grouped per speed and spring, and the `report.md` table that
//! answers the study's two questions: does the spring move the contact force, and does
//! zeta within its band?
//!
//! Per speed, spring and statistic: `mid` is the run labelled `mid` (the mean of the
//! spring's runs when none is), `low` and `high` the smallest and largest over the
//! spring's runs (its damping band). Across springs the spread of the `mid` values is the
//! spring's effect; the widest band of one spring is zeta's effect. Speeds are grouped by
//! their exact value: rows carry the statistics of the runs, never recomputed speeds.

use std::fmt::Write as _;

use super::{speed_label, Statistics};

/// One run of the spring study: a head-stage spring at one damping value and speed.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringStudyRow {
    /// The spring's name (`160ECT`, `#1`, ...).
    pub spring: String,
    /// The damping value of the band (`low`, `mid`, `high`).
    pub zeta: String,
    /// The run's statistics (its `speed_km_h` groups it).
    pub statistics: Statistics,
}

/// Which statistic is looked at.
pub(crate) type Pick = fn(&Statistics) -> f64;

/// A statistic of one spring at one speed: the `mid` run and the band's extremes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Spread {
    pub(crate) mid: f64,
    pub(crate) low: f64,
    pub(crate) high: f64,
}

/// Items in order of first appearance.
fn first_seen<T: PartialEq + Clone>(items: impl Iterator<Item = T>) -> Vec<T> {
    let mut seen: Vec<T> = Vec::new();
    for item in items {
        if !seen.contains(&item) {
            seen.push(item);
        }
    }
    seen
}

/// The springs in order of first appearance.
pub(crate) fn springs(rows: &[SpringStudyRow]) -> Vec<String> {
    first_seen(rows.iter().map(|r| r.spring.clone()))
}

/// The speeds (km/h) in order of first appearance.
pub(crate) fn speeds(rows: &[SpringStudyRow]) -> Vec<f64> {
    first_seen(rows.iter().map(|r| r.statistics.speed_km_h.to_bits()))
        .into_iter()
        .map(f64::from_bits)
        .collect()
}

/// `pick` of `spring` at `speed_km_h` (module doc), if it has runs there.
pub(crate) fn band(
    rows: &[SpringStudyRow],
    spring: &str,
    speed_km_h: f64,
    pick: Pick,
) -> Option<Spread> {
    let runs: Vec<&SpringStudyRow> = rows
        .iter()
        .filter(|r| r.spring == spring && r.statistics.speed_km_h.to_bits() == speed_km_h.to_bits())
        .collect();
    if runs.is_empty() {
        return None;
    }
    let values: Vec<f64> = runs.iter().map(|r| pick(&r.statistics)).collect();
    let mid = runs
        .iter()
        .find(|r| r.zeta == "mid")
        .map_or(values.iter().sum::<f64>() / values.len() as f64, |r| {
            pick(&r.statistics)
        });
    let (low, high) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    Some(Spread { mid, low, high })
}

/// The statistics of the study's table and figure: title, short name, value.
pub(crate) const COLUMNS: [(&str, &str, Pick); 3] = [
    ("standard deviation (N)", "std", |s| s.std_n),
    ("actual minimum (N)", "min", |s| s.min_n),
    ("time without contact (%)", "loss", |s| s.loss_percent),
];

/// The `report.md` section of the study: per speed, each spring's standard deviation,
/// minimum and loss of contact (`mid` and the band `low to high`), then the spread across
/// springs beside the widest band of one spring.
pub fn markdown(rows: &[SpringStudyRow]) -> String {
    let springs = springs(rows);
    let mut s = String::new();
    for speed in speeds(rows) {
        let _ = writeln!(s, "### {}\n", speed_label(speed));
        s.push_str("| spring |");
        for (title, _, _) in COLUMNS {
            let _ = write!(s, " {title}: mid (band) |");
        }
        s.push_str("\n|---|---:|---:|---:|\n");
        for spring in &springs {
            let cells: Vec<Option<Spread>> = COLUMNS
                .iter()
                .map(|(_, _, pick)| band(rows, spring, speed, *pick))
                .collect();
            if cells.iter().all(Option::is_none) {
                continue;
            }
            let _ = write!(s, "| {spring} |");
            for cell in cells.iter().flatten() {
                let _ = write!(
                    s,
                    " {:.2} ({:.2} to {:.2}) |",
                    cell.mid, cell.low, cell.high
                );
            }
            s.push('\n');
        }
        s.push('\n');
        for (title, short, pick) in COLUMNS {
            let spreads: Vec<(String, Spread)> = springs
                .iter()
                .filter_map(|spring| band(rows, spring, speed, pick).map(|b| (spring.clone(), b)))
                .collect();
            let lowest = spreads.iter().min_by(|a, b| a.1.mid.total_cmp(&b.1.mid));
            let highest = spreads.iter().max_by(|a, b| a.1.mid.total_cmp(&b.1.mid));
            let widest = spreads
                .iter()
                .max_by(|a, b| (a.1.high - a.1.low).total_cmp(&(b.1.high - b.1.low)));
            if let (Some(lo), Some(hi), Some(wide)) = (lowest, highest, widest) {
                let _ = writeln!(
                    s,
                    "- {title}: across springs (mid) {:.2} ({}) to {:.2} ({}), a spread of {:.2}; \
                     within one spring's zeta band at most {:.2} ({}). {}",
                    lo.1.mid,
                    lo.0,
                    hi.1.mid,
                    hi.0,
                    hi.1.mid - lo.1.mid,
                    wide.1.high - wide.1.low,
                    wide.0,
                    if hi.1.mid - lo.1.mid > wide.1.high - wide.1.low {
                        format!("The spring moves {short} more than zeta does.")
                    } else {
                        format!("zeta within its band moves {short} as much as the spring does.")
                    }
                );
            }
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(spring: &str, zeta: &str, speed_km_h: f64, std_n: f64, min_n: f64) -> SpringStudyRow {
        SpringStudyRow {
            spring: spring.into(),
            zeta: zeta.into(),
            statistics: Statistics {
                speed_km_h,
                mean_n: 115.0,
                std_n,
                stat_max_n: 115.0 + 3.0 * std_n,
                stat_min_n: 115.0 - 3.0 * std_n,
                max_n: 200.0,
                min_n,
                uplift_support_mm: 50.0,
                loss_percent: 0.0,
            },
        }
    }

    #[test]
    fn the_table_gives_the_spring_and_the_zeta_effects() {
        let rows = vec![
            row("160ECT", "low", 250.0, 30.0, 60.0),
            row("160ECT", "mid", 250.0, 30.5, 59.0),
            row("160ECT", "high", 250.0, 30.6, 58.0),
            row("#3", "low", 250.0, 27.0, 70.0),
            row("#3", "mid", 250.0, 27.2, 69.0),
            row("#3", "high", 250.0, 28.0, 68.5),
            row("#2", "mid", 300.0, 40.0, 20.0),
        ];
        let b = band(&rows, "#3", 250.0, |s| s.std_n).unwrap();
        assert_eq!(
            b,
            Spread {
                mid: 27.2,
                low: 27.0,
                high: 28.0
            }
        );
        assert!(band(&rows, "#2", 250.0, |s| s.std_n).is_none());
        assert_eq!(speeds(&rows), vec![250.0, 300.0]);
        let text = markdown(&rows);
        assert!(text.contains("### 250 km/h"), "{text}");
        assert!(
            text.contains("| #3 | 27.20 (27.00 to 28.00) | 69.00 (68.50 to 70.00) |"),
            "{text}"
        );
        assert!(
            text.contains("- standard deviation (N): across springs (mid) 27.20 (#3) to 30.50 (160ECT), a spread of 3.30; within one spring's zeta band at most 1.00 (#3). The spring moves std more than zeta does."),
            "{text}"
        );
        assert!(text.contains("### 300 km/h\n\n| spring |"), "{text}");
        assert!(text.contains("| #2 | 40.00 (40.00 to 40.00) |"), "{text}");
    }
}
