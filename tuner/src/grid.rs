//! Loop 3's grids of Rayleigh (alpha, beta): every point is a decay run and its
//! logarithmic decrement, run in parallel (rayon) with progress lines ([`coil_io::Progress`]), and
//! journaled so that a killed run resumes without recomputing or losing a point.
//!
//! # Axes
//! `start:step:end`, both ends included: `0:0.1:2` is 21 values. Values are
//! `start + i step` printed to 11 significant digits and read back, so 0.1 * 3 is 0.3.
//!
//! # The journal (`<name>.journal.jsonl`)
//! Line 1 is a header: the grid's name and axes and a `model` object (the calibrated
//! values and every setting that changes a point's result). Each finished point is one
//! JSON line, appended with a single `write` on a file opened for appending, after its
//! run ends, so a kill leaves at most the last line torn. On start:
//! - no journal: one is created with the header;
//! - a journal whose header matches: its complete lines are taken as done, a torn last
//!   line (no newline, or not JSON) is cut off, only the missing points run;
//! - a journal for another grid or model: an error naming the file and what differs
//!   (remove it or choose another output folder); nothing is overwritten.
//!
//! A point whose decrement fails (too few crests at heavy damping) is a finished point
//! with an `error` text: it is journaled and never recomputed.

use crate::decay::DecayMeasure;
use crate::error::{Result, TuneError};
use crate::output::{csv, exact};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Most points of one grid (a million decay runs is days of work: a typo, not a study).
pub const MAX_POINTS: usize = 1_000_000;

/// One axis of a grid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// First value.
    pub start: f64,
    /// Step between values.
    pub step: f64,
    /// Number of values.
    pub count: usize,
}

/// Rounds to 11 significant digits, so that `0.1 * 3` reads `0.3`.
fn tidy(x: f64) -> f64 {
    format!("{x:.10e}").parse().unwrap_or(x)
}

impl Axis {
    /// Parses `start:step:end` (end included); `value` alone is a one-point axis.
    pub fn parse(text: &str) -> std::result::Result<Axis, String> {
        let parts: Vec<&str> = text.split(':').collect();
        let number = |s: &str| -> std::result::Result<f64, String> {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("`{s}` is not a finite number"))
        };
        match parts.as_slice() {
            [one] => Ok(Axis {
                start: number(one)?,
                step: 0.0,
                count: 1,
            }),
            [start, step, end] => {
                let (start, step, end) = (number(start)?, number(step)?, number(end)?);
                if step <= 0.0 || end < start {
                    return Err(format!(
                        "`{text}`: expected start:step:end with step > 0 and end >= start"
                    ));
                }
                let intervals = (end - start) / step;
                let n = intervals.round();
                if (intervals - n).abs() > 1e-6 * n.max(1.0) {
                    return Err(format!(
                        "`{text}`: (end - start) / step = {intervals}; expected a whole number of steps"
                    ));
                }
                if n > 100_000.0 {
                    return Err(format!("`{text}`: {n} steps; expected at most 100000"));
                }
                Ok(Axis {
                    start,
                    step,
                    count: n as usize + 1,
                })
            }
            _ => Err(format!(
                "`{text}`: expected start:step:end (e.g. 0:0.1:2) or one value"
            )),
        }
    }

    /// The i-th value.
    pub fn value(&self, i: usize) -> f64 {
        tidy(self.start + i as f64 * self.step)
    }

    /// All values.
    pub fn values(&self) -> Vec<f64> {
        (0..self.count).map(|i| self.value(i)).collect()
    }

    /// The last value.
    pub fn end(&self) -> f64 {
        self.value(self.count.saturating_sub(1))
    }
}

impl std::fmt::Display for Axis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.count == 1 {
            write!(f, "{}", self.start)
        } else {
            write!(f, "{}:{}:{}", self.start, self.step, self.end())
        }
    }
}

/// A named alpha x beta grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridSpec {
    /// Its name.
    pub name: String,
    /// Rayleigh alpha (mass-proportional), 1/s.
    pub alpha: Axis,
    /// Rayleigh beta (stiffness-proportional), s.
    pub beta: Axis,
}

impl GridSpec {
    /// The paper's first domain: alpha, beta in {0, 0.0001, ..., 0.0015}, 256 runs.
    pub fn paper_domain1() -> Self {
        let axis = Axis {
            start: 0.0,
            step: 1e-4,
            count: 16,
        };
        GridSpec {
            name: "domain1".into(),
            alpha: axis,
            beta: axis,
        }
    }

    /// The paper's second domain: alpha in {0, 0.1, ..., 2}, beta in {0, 1e-5, ...,
    /// 2e-4}, 441 runs (the paper's text says beta "0 - 2.0"; 441 runs means 0 - 0.0002).
    pub fn paper_domain2() -> Self {
        GridSpec {
            name: "domain2".into(),
            alpha: Axis {
                start: 0.0,
                step: 0.1,
                count: 21,
            },
            beta: Axis {
                start: 0.0,
                step: 1e-5,
                count: 21,
            },
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.alpha.count * self.beta.count
    }

    /// True for a grid without points (never built by the parsers).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One finished grid point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridPoint {
    /// Index along alpha.
    pub i: usize,
    /// Index along beta.
    pub j: usize,
    /// Rayleigh alpha (mass-proportional), 1/s.
    pub alpha: f64,
    /// Rayleigh beta (stiffness-proportional), s.
    pub beta: f64,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    /// The decrement, if it succeeded.
    pub measure: Option<DecayMeasure>,
    /// Why the point has no measure.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub error: Option<String>,
}

impl GridPoint {
    /// The paper's zeta (span mean), if the point was measured.
    pub fn zeta(&self) -> Option<f64> {
        self.measure.map(|m| m.zeta_mean)
    }
}

/// A finished grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridResult {
    /// The grid.
    pub spec: GridSpec,
    /// Every point, sorted by (i, j).
    pub points: Vec<GridPoint>,
    /// Points run by this call.
    pub computed: usize,
    /// Points taken from the journal.
    pub resumed: usize,
    /// Wall time of this call (s).
    pub elapsed_s: f64,
}

impl GridResult {
    /// The point whose zeta is closest to `target`.
    pub fn best(&self, target: f64) -> Option<&GridPoint> {
        self.points
            .iter()
            .filter(|p| p.zeta().is_some_and(f64::is_finite))
            .min_by(|a, b| {
                let d = |p: &GridPoint| (p.zeta().unwrap_or(f64::INFINITY) - target).abs();
                d(a).total_cmp(&d(b))
            })
    }

    /// Whether every point is present (a grid stopped by `max_new_points` is not).
    pub fn is_complete(&self) -> bool {
        self.points.len() == self.spec.len()
    }

    /// The grid as CSV: i, j, alpha, beta, zeta_mean, zeta_fit, period_s, crests, error.
    pub fn csv(&self) -> String {
        csv(
            &[
                "i",
                "j",
                "alpha",
                "beta",
                "zeta_mean",
                "zeta_fit",
                "period_s",
                "crests",
                "error",
            ],
            self.points.iter().map(|p| {
                let m = p.measure;
                vec![
                    p.i.to_string(),
                    p.j.to_string(),
                    exact(p.alpha),
                    exact(p.beta),
                    m.map_or(String::new(), |m| exact(m.zeta_mean)),
                    m.map_or(String::new(), |m| exact(m.zeta_fit)),
                    m.map_or(String::new(), |m| exact(m.period_s)),
                    m.map_or(String::new(), |m| m.crests.to_string()),
                    p.error
                        .clone()
                        .unwrap_or_default()
                        .replace([',', '\n'], ";"),
                ]
            }),
        )
    }
}

/// How a grid runs.
#[derive(Debug, Clone, Default)]
pub struct GridOptions {
    /// Journal file; `None` runs without one (nothing resumable).
    pub journal: Option<PathBuf>,
    /// Progress on stderr past a few seconds (a line every few seconds when stderr is
    /// not a terminal).
    pub progress: bool,
    /// Run at most this many new points, then return (the rest on a later call).
    pub max_new_points: Option<usize>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Header {
    coil_grid_journal: u32,
    grid: GridSpec,
    model: serde_json::Value,
}

/// Relative tolerance for the numbers of the journal's `model`: the solver's sparse
/// factorisation may sum in a different order from run to run (parallel), so a calibrated
/// E can differ in its last bit; a point run at E(1 + 1e-16) is the same point.
const MODEL_TOLERANCE: f64 = 1e-9;

/// Equality of two JSON values, numbers within [`MODEL_TOLERANCE`].
fn same_json(a: &serde_json::Value, b: &serde_json::Value) -> bool {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => (x - y).abs() <= MODEL_TOLERANCE * x.abs().max(y.abs()),
            _ => x == y,
        },
        (Value::Array(x), Value::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| same_json(p, q))
        }
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len()
                && x.iter()
                    .all(|(k, v)| y.get(k).is_some_and(|w| same_json(v, w)))
        }
        _ => a == b,
    }
}

/// Reads a journal: the points of its complete lines and the byte length they take.
fn read_journal(path: &Path, header: &Header) -> Result<(Vec<GridPoint>, u64)> {
    let mut text = String::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_string(&mut text))
        .map_err(|e| TuneError::io(path, e))?;
    let journal_error = |line: usize, problem: String| TuneError::Journal {
        path: path.to_path_buf(),
        line,
        problem,
        hint: "remove the journal to start this grid afresh, or write to another output folder"
            .into(),
    };
    // Only newline-terminated lines are complete; what follows the last newline is a
    // write cut short by a kill.
    let complete_len = text.rfind('\n').map_or(0, |i| i + 1);
    // (line number, text, byte offset just past its newline)
    let mut lines = Vec::new();
    let mut offset = 0;
    for (index, line) in text[..complete_len].split_inclusive('\n').enumerate() {
        offset += line.len();
        lines.push((index + 1, line.trim_end_matches(['\n', '\r']), offset));
    }
    let Some(&(_, first, header_end)) = lines.first() else {
        // Killed before the header was complete: nothing to keep.
        return Ok((Vec::new(), 0));
    };
    let found: Header = serde_json::from_str(first)
        .map_err(|e| journal_error(1, format!("the header is not a grid journal header ({e})")))?;
    if found.grid != header.grid {
        return Err(journal_error(
            1,
            format!(
                "the journal is for grid {} alpha {} beta {}, not {} alpha {} beta {}",
                found.grid.name,
                found.grid.alpha,
                found.grid.beta,
                header.grid.name,
                header.grid.alpha,
                header.grid.beta
            ),
        ));
    }
    if !same_json(&found.model, &header.model)
        || found.coil_grid_journal != header.coil_grid_journal
    {
        return Err(journal_error(
            1,
            format!(
                "the journal was written for another model or settings ({}) than this run ({})",
                found.model, header.model
            ),
        ));
    }
    let mut points: Vec<GridPoint> = Vec::new();
    let mut seen = vec![false; header.grid.len()];
    let mut keep_len = header_end;
    let last = lines.len();
    for &(number, line, end) in &lines[1..] {
        let point = match serde_json::from_str::<GridPoint>(line) {
            Ok(p) => p,
            // The last line can be garbage only if a kill fell inside one write on an
            // unusual file system: it is cut off. Anything earlier is damage.
            Err(_) if number == last => break,
            Err(e) => return Err(journal_error(number, format!("not a grid point ({e})"))),
        };
        if point.i >= header.grid.alpha.count || point.j >= header.grid.beta.count {
            return Err(journal_error(
                number,
                format!("point ({}, {}) is outside the grid", point.i, point.j),
            ));
        }
        let k = point.i * header.grid.beta.count + point.j;
        if !seen[k] {
            seen[k] = true;
            points.push(point);
        }
        keep_len = end;
    }
    Ok((points, keep_len as u64))
}

/// Runs (or resumes) a grid. `model` identifies the model and settings in the journal;
/// `evaluate(alpha, beta)` runs one point.
pub fn run_grid<F>(
    spec: &GridSpec,
    model: serde_json::Value,
    options: &GridOptions,
    evaluate: F,
) -> Result<GridResult>
where
    F: Fn(f64, f64) -> Result<DecayMeasure> + Sync,
{
    let start = std::time::Instant::now();
    if spec.len() > MAX_POINTS {
        return Err(TuneError::Invalid(format!(
            "grid {}: {} x {} = {} points; expected at most {MAX_POINTS}",
            spec.name,
            spec.alpha.count,
            spec.beta.count,
            spec.len()
        )));
    }
    let header = Header {
        coil_grid_journal: 1,
        grid: spec.clone(),
        model,
    };
    let mut done: Vec<GridPoint> = Vec::new();
    let journal = match &options.journal {
        None => None,
        Some(path) => {
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(|e| TuneError::io(parent, e))?;
            }
            let mut keep_len = 0;
            // A regular file with one link, or nothing (never through a symlink).
            let mut file = coil_io::open_journal(path)?;
            if file.metadata().map_err(|e| TuneError::io(path, e))?.len() > 0 {
                let (points, len) = read_journal(path, &header)?;
                done = points;
                keep_len = len;
            }
            file.set_len(keep_len).map_err(|e| TuneError::io(path, e))?;
            file.seek(std::io::SeekFrom::End(0))
                .map_err(|e| TuneError::io(path, e))?;
            if keep_len == 0 {
                let mut line = serde_json::to_string(&header)
                    .map_err(|e| TuneError::Invalid(format!("journal header: {e}")))?;
                line.push('\n');
                file.write_all(line.as_bytes())
                    .map_err(|e| TuneError::io(path, e))?;
            }
            Some((path.clone(), Mutex::new(file)))
        }
    };

    let mut finished = vec![false; spec.len()];
    for p in &done {
        finished[p.i * spec.beta.count + p.j] = true;
    }
    let mut pending: Vec<(usize, usize)> = (0..spec.alpha.count)
        .flat_map(|i| (0..spec.beta.count).map(move |j| (i, j)))
        .filter(|&(i, j)| !finished[i * spec.beta.count + j])
        .collect();
    if let Some(limit) = options.max_new_points {
        pending.truncate(limit);
    }
    let resumed = done.len();

    let bar = coil_io::Progress::new(format!("grid {}", spec.name), spec.len() as u64, "runs")
        .hidden(!options.progress);
    bar.set(resumed as u64);

    let new_points: Vec<GridPoint> = pending
        .par_iter()
        .map(|&(i, j)| -> Result<GridPoint> {
            let (alpha, beta) = (spec.alpha.value(i), spec.beta.value(j));
            // A requested stop (Ctrl-C from Python) ends the grid; the point is not
            // journaled, so a rerun computes it.
            let interrupted = || TuneError::Invalid(coil_io::cancel::INTERRUPTED.into());
            if coil_io::cancel::requested() {
                return Err(interrupted());
            }
            let (measure, error) = match evaluate(alpha, beta) {
                Ok(m) => (Some(m), None),
                Err(e) => (None, Some(e.to_string())),
            };
            if coil_io::cancel::requested() {
                return Err(interrupted());
            }
            let point = GridPoint {
                i,
                j,
                alpha,
                beta,
                measure,
                error,
            };
            if let Some((path, file)) = &journal {
                let mut line = serde_json::to_string(&point)
                    .map_err(|e| TuneError::Invalid(format!("journal line: {e}")))?;
                line.push('\n');
                let mut file = file.lock().map_err(|_| TuneError::Journal {
                    path: path.clone(),
                    line: 0,
                    problem: "another worker failed while writing".into(),
                    hint: "rerun to resume".into(),
                })?;
                file.write_all(line.as_bytes())
                    .map_err(|e| TuneError::io(path, e))?;
            }
            bar.inc(1);
            Ok(point)
        })
        .collect::<Result<Vec<_>>>()?;
    bar.finish();

    let computed = new_points.len();
    done.extend(new_points);
    done.sort_by_key(|p| (p.i, p.j));
    Ok(GridResult {
        spec: spec.clone(),
        points: done,
        computed,
        resumed,
        elapsed_s: start.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn fake(alpha: f64, beta: f64) -> Result<DecayMeasure> {
        if beta > 0.25 {
            return Err(TuneError::Invalid("too damped".into()));
        }
        Ok(DecayMeasure {
            zeta_mean: 1e-3 * alpha + beta,
            zeta_fit: 1e-3 * alpha + beta,
            period_s: 0.23,
            crests: 20,
        })
    }

    fn small() -> GridSpec {
        GridSpec {
            name: "small".into(),
            alpha: Axis::parse("0:1:2").unwrap(),
            beta: Axis::parse("0:0.1:0.3").unwrap(),
        }
    }

    #[test]
    fn axes_parse_and_print_clean_values() {
        let a = Axis::parse("0:0.1:2").unwrap();
        assert_eq!(a.count, 21);
        assert_eq!(a.value(3), 0.3);
        assert_eq!(a.end(), 2.0);
        assert_eq!(Axis::parse("0:1e-5:2e-4").unwrap().count, 21);
        assert_eq!(Axis::parse("0:0.0001:0.0015").unwrap().count, 16);
        assert_eq!(Axis::parse("0.8").unwrap().values(), vec![0.8]);
        for bad in ["0:0:1", "1:0.1:0", "0:0.3:1", "a:1:2", "0:1", "0:1e-9:1"] {
            assert!(Axis::parse(bad).is_err(), "{bad}");
        }
        assert_eq!(GridSpec::paper_domain1().len(), 256);
        assert_eq!(GridSpec::paper_domain2().len(), 441);
        assert_eq!(GridSpec::paper_domain2().beta.end(), 2e-4);
    }

    /// A grid stopped after 5 points (as a kill would), with a torn sixth line, resumes:
    /// the 5 journaled points are not recomputed, the other 7 are, and the result equals
    /// an uninterrupted run.
    #[test]
    fn a_stopped_grid_resumes_without_recomputing() {
        let dir = tempfile::tempdir().unwrap();
        let journal = dir.path().join("small.journal.jsonl");
        let model = serde_json::json!({"E": 1.0});
        let options = GridOptions {
            journal: Some(journal.clone()),
            progress: false,
            max_new_points: Some(5),
        };
        let first = run_grid(&small(), model.clone(), &options, fake).unwrap();
        // A model equal to the last bit or so (a parallel sum's order) is the same model.
        let model = serde_json::json!({"E": 1.0 + 1e-15});
        assert_eq!((first.computed, first.resumed), (5, 0));
        assert!(!first.is_complete());
        // A kill in the middle of the sixth write.
        let mut f = std::fs::OpenOptions::new()
            .append(true)
            .open(&journal)
            .unwrap();
        f.write_all(b"{\"i\":2,\"j\":1,\"alpha\":2.0,\"be").unwrap();
        drop(f);

        let calls = AtomicUsize::new(0);
        let counting = |a: f64, b: f64| {
            calls.fetch_add(1, Ordering::SeqCst);
            fake(a, b)
        };
        let options = GridOptions {
            max_new_points: None,
            ..options
        };
        let second = run_grid(&small(), model.clone(), &options, counting).unwrap();
        assert_eq!(calls.load(Ordering::SeqCst), 7);
        assert_eq!((second.computed, second.resumed), (7, 5));
        assert!(second.is_complete());
        let fresh = run_grid(&small(), model.clone(), &GridOptions::default(), fake).unwrap();
        assert_eq!(second.points, fresh.points);
        assert_eq!(
            second.points.iter().filter(|p| p.error.is_some()).count(),
            3
        );
        // Every line of the journal is whole: header + 12 points.
        let text = std::fs::read_to_string(&journal).unwrap();
        assert_eq!(text.lines().count(), 13);
        assert!(text.ends_with('\n'));
        // A third run computes nothing.
        let third = run_grid(&small(), model, &options, fake).unwrap();
        assert_eq!((third.computed, third.resumed), (0, 12));
        assert_eq!(
            third.best(0.2).map(|p| (p.i, p.j)),
            Some((0, 2)),
            "zeta = alpha/1000 + beta closest to 0.2"
        );
    }

    #[test]
    fn a_journal_for_another_model_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let journal = dir.path().join("j.jsonl");
        let options = GridOptions {
            journal: Some(journal.clone()),
            ..GridOptions::default()
        };
        run_grid(&small(), serde_json::json!({"E": 1.0}), &options, fake).unwrap();
        let before = std::fs::read(&journal).unwrap();
        match run_grid(&small(), serde_json::json!({"E": 2.0}), &options, fake) {
            Err(TuneError::Journal {
                line: 1, problem, ..
            }) => {
                assert!(problem.contains("another model"), "{problem}")
            }
            other => panic!("{other:?}"),
        }
        let mut other = small();
        other.beta = Axis::parse("0:0.1:0.2").unwrap();
        assert!(matches!(
            run_grid(&other, serde_json::json!({"E": 1.0}), &options, fake),
            Err(TuneError::Journal { .. })
        ));
        assert_eq!(
            std::fs::read(&journal).unwrap(),
            before,
            "journal untouched"
        );
        // Damage in the middle of the journal is reported with its line.
        let text = String::from_utf8(before).unwrap();
        let mut lines: Vec<&str> = text.lines().collect();
        lines[3] = "garbage";
        std::fs::write(&journal, lines.join("\n") + "\n").unwrap();
        match run_grid(&small(), serde_json::json!({"E": 1.0}), &options, fake) {
            Err(TuneError::Journal { line, .. }) => assert_eq!(line, 4),
            other => panic!("{other:?}"),
        }
    }
}
