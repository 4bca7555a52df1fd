//! A sweep as a list of independent tasks, and its split across processes and machines.
//!
//! A [`Study`] is a variant sweep (Table 4: one task per variant) or a tolerance study
//! ([`crate::tolerance`]: one task per sampled spring). Task `k` (0-based) gives one row of
//! the study's table, and that row depends only on the study and `k`:
//! - every random draw is a function of the seed, `k` and the draw's number
//!   ([`crate::tolerance::uniform`]), never of a generator's state shared between tasks;
//! - the solver's factorisations and eigensolver run sequentially inside a task (faer
//!   `Par::Seq`), and no reduction crosses tasks.
//!
//! So a task gives the same bits wherever it runs: in this process's thread pool, in the
//! I-th of N shards of `coil-tune ... --shard I/N`, or on a Dask worker through the Python
//! package. The split-invariance tests compare the tables byte for byte.
//!
//! # Shards and parts
//! Shard `I/N` (1 <= I <= N) runs the tasks `k` with `k mod N = I - 1` (round robin: the
//! springs of a tolerance study differ in cost, so contiguous blocks would balance worse).
//! It writes `part-IIII-of-NNNN.csv`: two comment lines, the header and its rows,
//!
//! ```text
//! # coil-tune part 2/4 of a tolerance study: 501 of 2004 tasks
//! # study {"study":"tolerance",...}
//! task,spring,sample,...
//! 1,#1,1,...
//! ```
//!
//! the second line carrying the whole study (material, variants, settings, tolerances,
//! seed) as JSON. [`merge`] reads the parts and refuses, naming the shard and the file:
//! a missing shard, a shard given twice, parts of different studies or splits, and a part
//! whose tasks are not exactly its shard's. The merged table is the single run's, byte for
//! byte (numbers are written with all their digits and read back exactly).

use crate::error::{Result, TuneError};
pub use crate::output::{csv_table, Cell};
pub use crate::sweep::VariantSweep;
use crate::tolerance::ToleranceStudy;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A list of independent tasks with its table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "study", rename_all = "lowercase")]
pub enum Study {
    /// Table 4's sweep.
    Sweep(VariantSweep),
    /// A tolerance study.
    Tolerance(ToleranceStudy),
}

impl Study {
    /// `sweep` or `tolerance`.
    pub fn kind(&self) -> &'static str {
        match self {
            Study::Sweep(_) => "sweep",
            Study::Tolerance(_) => "tolerance",
        }
    }

    /// The file a single run writes the table to (`sweep.csv`, `tolerance.csv`).
    pub fn table_file(&self) -> String {
        format!("{}.csv", self.kind())
    }

    /// Number of tasks.
    pub fn tasks(&self) -> usize {
        match self {
            Study::Sweep(s) => s.variants.len(),
            Study::Tolerance(t) => t.tasks(),
        }
    }

    /// The table's columns.
    pub fn columns(&self) -> Vec<&'static str> {
        match self {
            Study::Sweep(_) => crate::sweep::COLUMNS.to_vec(),
            Study::Tolerance(_) => crate::tolerance::COLUMNS.to_vec(),
        }
    }

    /// Runs task `k`: its row of the table.
    pub fn run_task(&self, k: usize) -> Result<Vec<Cell>> {
        if k >= self.tasks() {
            return Err(TuneError::Invalid(format!(
                "task {k}: the {} study has {} tasks (0 to {})",
                self.kind(),
                self.tasks(),
                self.tasks().saturating_sub(1)
            )));
        }
        match self {
            Study::Sweep(s) => {
                Ok(
                    crate::sweep::run_variant(&s.material, &s.variants[k], &s.fe, &s.decay)?
                        .cells(),
                )
            }
            Study::Tolerance(t) => Ok(t.run(k)?.cells()),
        }
    }

    /// Runs the given tasks in parallel (this process's thread pool); rows in the given
    /// order. The first failing task's error names it.
    pub fn run_tasks(&self, tasks: &[usize]) -> Result<Vec<Vec<Cell>>> {
        tasks
            .par_iter()
            .map(|&k| {
                self.run_task(k)
                    .map_err(|e| TuneError::Invalid(format!("{} task {k}: {e}", self.kind())))
            })
            .collect()
    }

    /// Runs every task: the single run's rows, in task order.
    pub fn run_all(&self) -> Result<Vec<Vec<Cell>>> {
        let all: Vec<usize> = (0..self.tasks()).collect();
        self.run_tasks(&all)
    }

    /// The study as one line of JSON (what a part file and a Dask task carry).
    pub fn to_json(&self) -> String {
        // Plain structs of numbers and strings: serialisation cannot fail (non-finite
        // numbers would be written as null and refused when read back).
        serde_json::to_string(self).unwrap_or_default()
    }

    /// Reads a study written by [`Study::to_json`]; `origin` names where the text came
    /// from in the error.
    pub fn from_json(text: &str, origin: &str) -> Result<Self> {
        serde_json::from_str(text).map_err(|e| {
            TuneError::Invalid(format!(
                "{origin}: column {}: {e}; expected a study written by coil-tune or coil",
                e.column()
            ))
        })
    }
}

/// Shard `index` of `count` (1-based), written `I/N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Shard {
    /// This shard (1-based).
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

/// More shards than this is a typo, not a cluster.
const MAX_SHARDS: usize = 1_000_000;

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(text: &str) -> std::result::Result<Self, String> {
        let expected = "expected I/N with 1 <= I <= N <= 1000000, e.g. 3/8";
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| format!("`{text}`: {expected}"))?;
        let parse = |s: &str| s.trim().parse::<usize>().ok();
        match (parse(i), parse(n)) {
            (Some(index), Some(count)) if index >= 1 && index <= count && count <= MAX_SHARDS => {
                Ok(Shard { index, count })
            }
            _ => Err(format!("`{text}`: {expected}")),
        }
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// The tasks of this shard out of `total` (round robin).
    pub fn tasks(&self, total: usize) -> Vec<usize> {
        (self.index - 1..total).step_by(self.count).collect()
    }

    /// `part-IIII-of-NNNN.csv` (at least 4 digits, sorting in shard order).
    pub fn file_name(&self) -> String {
        let width = self.count.to_string().len().max(4);
        format!("part-{:0width$}-of-{:0width$}.csv", self.index, self.count)
    }
}

const PART_TAG: &str = "# coil-tune part ";
const STUDY_TAG: &str = "# study ";

/// The text of shard `shard`'s part file.
pub fn part_text(study: &Study, shard: Shard, tasks: &[usize], rows: &[Vec<Cell>]) -> String {
    let mut columns = vec!["task"];
    columns.extend(study.columns());
    let body = crate::output::csv(
        &columns,
        tasks.iter().zip(rows).map(|(k, row)| {
            std::iter::once(k.to_string())
                .chain(row.iter().map(Cell::csv))
                .collect()
        }),
    );
    format!(
        "{PART_TAG}{shard} of a {} study: {} of {} tasks\n{STUDY_TAG}{}\n{body}",
        study.kind(),
        tasks.len(),
        study.tasks(),
        study.to_json()
    )
}

/// Runs shard `shard` of `study` and writes its part into `folder` (created); returns
/// the path. The part is one file written atomically on its own, not an output set: the
/// shards of a study write into one shared folder, concurrently, from many machines.
pub fn run_shard(study: &Study, shard: Shard, folder: &Path) -> Result<PathBuf> {
    let tasks = shard.tasks(study.tasks());
    let rows = study.run_tasks(&tasks)?;
    std::fs::create_dir_all(folder).map_err(|e| TuneError::io(folder, e))?;
    let path = folder.join(shard.file_name());
    let text = part_text(study, shard, &tasks, &rows);
    coil_io::write_file(&path, text.as_bytes()).map_err(|e| TuneError::Invalid(e.to_string()))?;
    Ok(path)
}

/// One part file as read.
#[derive(Debug, Clone)]
pub struct Part {
    /// The part file.
    pub path: PathBuf,
    /// The shard.
    pub shard: Shard,
    /// The study as JSON.
    pub study_json: String,
    /// The study.
    pub study: Study,
    /// (task, the row's CSV cells without the task column).
    pub rows: Vec<(usize, Vec<String>)>,
}

/// A part larger than this is not one (10^6 rows of a tolerance study are 0.3 GB).
const MAX_PART_BYTES: u64 = 1 << 30;

fn part_error(path: &Path, line: usize, message: impl std::fmt::Display) -> TuneError {
    TuneError::Invalid(format!("{}:{line}: {message}", path.display()))
}

/// Reads and checks one part file.
pub fn read_part(path: &Path) -> Result<Part> {
    let text = coil_io::read_bounded(path, MAX_PART_BYTES, "a part file")
        .map_err(|e| TuneError::Invalid(e.to_string()))?;
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (_, first) = lines.next().unwrap_or((1, ""));
    let shard = first
        .strip_prefix(PART_TAG)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|s| s.parse::<Shard>().ok())
        .ok_or_else(|| {
            part_error(
                path,
                1,
                "not a part file; expected `# coil-tune part I/N of a ... study` (written by `--shard I/N`)",
            )
        })?;
    let (_, second) = lines.next().unwrap_or((2, ""));
    let study_json = second
        .strip_prefix(STUDY_TAG)
        .ok_or_else(|| part_error(path, 2, "expected `# study {...}`, the study as JSON"))?
        .to_string();
    let study = Study::from_json(&study_json, &format!("{}:2", path.display()))?;
    let mut columns = vec!["task"];
    columns.extend(study.columns());
    let header = columns.join(",");
    match lines.next() {
        Some((_, line)) if line == header => {}
        Some((n, line)) => {
            return Err(part_error(
                path,
                n,
                format!("header `{line}`; expected `{header}`"),
            ))
        }
        None => {
            return Err(part_error(
                path,
                3,
                format!("no header; expected `{header}`"),
            ))
        }
    }
    let mut rows = Vec::new();
    for (n, line) in lines {
        let mut cells = line.split(',');
        let task = cells
            .next()
            .and_then(|t| t.parse::<usize>().ok())
            .ok_or_else(|| part_error(path, n, "expected a task number in the first column"))?;
        let rest: Vec<String> = cells.map(str::to_string).collect();
        if rest.len() != columns.len() - 1 {
            return Err(part_error(
                path,
                n,
                format!(
                    "{} cells; expected {} ({header})",
                    rest.len() + 1,
                    columns.len()
                ),
            ));
        }
        rows.push((task, rest));
    }
    let expected = shard.tasks(study.tasks());
    let found: Vec<usize> = rows.iter().map(|(k, _)| *k).collect();
    if found != expected {
        let missing = expected.iter().find(|k| !found.contains(k));
        let stray = found.iter().find(|k| !expected.contains(k));
        return Err(part_error(
            path,
            3,
            format!(
                "shard {shard} has {} rows; expected its {} tasks {} to {} in order{}{}",
                found.len(),
                expected.len(),
                expected.first().map_or("-".into(), usize::to_string),
                expected.last().map_or("-".into(), usize::to_string),
                missing.map_or(String::new(), |k| format!(" (task {k} is missing)")),
                stray.map_or(String::new(), |k| format!(
                    " (task {k} is not this shard's or is repeated)"
                )),
            ),
        ));
    }
    Ok(Part {
        path: path.to_path_buf(),
        shard,
        study_json,
        study,
        rows,
    })
}

/// The part files named by `inputs`: files as given, folders by their `part-*.csv`.
pub fn part_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .map_err(|e| TuneError::io(input, e))?
                .filter_map(|entry| entry.ok().map(|e| e.path()))
                .filter(|p| {
                    p.is_file()
                        && p.file_name()
                            .and_then(|n| n.to_str())
                            .is_some_and(|n| n.starts_with("part-") && n.ends_with(".csv"))
                })
                .collect();
            found.sort();
            if found.is_empty() {
                return Err(TuneError::Invalid(format!(
                    "{}: no part-*.csv in this folder; expected the parts written by `--shard I/N`",
                    input.display()
                )));
            }
            files.extend(found);
        } else {
            files.push(input.clone());
        }
    }
    if files.is_empty() {
        return Err(TuneError::Invalid(
            "merge: no parts given; expected part files or folders holding them".into(),
        ));
    }
    Ok(files)
}

/// The merged study: its table's columns and rows (CSV cells) in task order.
#[derive(Debug, Clone)]
pub struct Merged {
    /// The study.
    pub study: Study,
    /// The column names.
    pub columns: Vec<&'static str>,
    /// The rows as CSV cells.
    pub rows: Vec<Vec<String>>,
}

impl Merged {
    /// The table, as the single run writes it.
    pub fn csv(&self) -> String {
        crate::output::csv(&self.columns, self.rows.iter().cloned())
    }
}

/// Joins the parts of one study; refuses missing, repeated or foreign shards.
pub fn merge(files: &[PathBuf]) -> Result<Merged> {
    let parts = files
        .iter()
        .map(|f| read_part(f))
        .collect::<Result<Vec<_>>>()?;
    let first = &parts[0];
    let count = first.shard.count;
    let mut by_index: BTreeMap<usize, &Part> = BTreeMap::new();
    for part in &parts {
        if part.shard.count != count {
            return Err(TuneError::Invalid(format!(
                "{}: shard {} belongs to a split into {}; {} is a split into {count}: merge the parts of one split",
                part.path.display(),
                part.shard,
                part.shard.count,
                first.path.display()
            )));
        }
        if part.study_json != first.study_json {
            return Err(TuneError::Invalid(format!(
                "{}: shard {} is a part of another study than {} (their `# study` lines differ); merge the parts of one study",
                part.path.display(),
                part.shard,
                first.path.display()
            )));
        }
        if let Some(other) = by_index.insert(part.shard.index, part) {
            return Err(TuneError::Invalid(format!(
                "shard {} is given twice: {} and {}; expected each shard once",
                part.shard,
                other.path.display(),
                part.path.display()
            )));
        }
    }
    let missing: Vec<String> = (1..=count)
        .filter(|i| !by_index.contains_key(i))
        .map(|i| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        let shown: Vec<&str> = missing.iter().take(10).map(String::as_str).collect();
        return Err(TuneError::Invalid(format!(
            "shard{} {}{} missing (found {} of {count} parts in {}); run {} with --shard and merge again",
            if missing.len() > 1 { "s" } else { "" },
            shown.join(", "),
            if missing.len() > shown.len() {
                format!(" and {} more", missing.len() - shown.len())
            } else {
                String::new()
            },
            parts.len(),
            first
                .path
                .parent()
                .map_or(".".into(), |p| p.display().to_string()),
            first.study.kind(),
        )));
    }
    let total = first.study.tasks();
    let mut rows: Vec<Option<Vec<String>>> = vec![None; total];
    for part in by_index.values() {
        for (k, row) in &part.rows {
            rows[*k] = Some(row.clone());
        }
    }
    Ok(Merged {
        study: first.study.clone(),
        columns: first.study.columns(),
        // read_part checked each part's tasks, and every shard is present once.
        rows: rows.into_iter().flatten().collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_tasks() {
        for total in [0, 1, 5, 6, 17] {
            for count in 1..=7 {
                let mut all: Vec<usize> = (1..=count)
                    .flat_map(|index| Shard { index, count }.tasks(total))
                    .collect();
                all.sort_unstable();
                assert_eq!(all, (0..total).collect::<Vec<_>>(), "{total} in {count}");
            }
        }
    }

    #[test]
    fn shard_parsing_names_what_is_expected() {
        assert_eq!("3/8".parse::<Shard>(), Ok(Shard { index: 3, count: 8 }));
        for bad in ["0/4", "5/4", "4", "a/b", "1/0", "-1/4", "1/2000000"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert!(e.contains("expected I/N"), "{bad}: {e}");
        }
        assert_eq!(
            Shard {
                index: 3,
                count: 12
            }
            .file_name(),
            "part-0003-of-0012.csv"
        );
    }
}
