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
//! It writes `part-IIII-of-NNNN.csv`: three comment lines, the header, its rows and the
//! rows' digest,
//!
//! ```text
//! # coil-tune part 2/4 of a tolerance study: 501 of 2004 tasks
//! # study {"study":"tolerance",...}
//! # study-sha256 5d41...
//! task,spring,sample,...
//! 1,#1,1,...
//! # rows-sha256 9f86...
//! ```
//!
//! the second line carrying the whole study (material, variants, settings, tolerances,
//! seed) as JSON, the third its SHA-256, the last the SHA-256 of the study line's JSON, a
//! line end and the table (header and rows, each with its line end). Cells are CSV fields
//! quoted as needed (RFC 4180: a name with a comma or a quote).
//!
//! # What `merge` trusts
//! Nothing it has not checked. [`merge`] reads the heads of all parts first (shard, study,
//! the study's digest), then streams each part's rows, and refuses, naming the file and
//! line: a missing shard, a shard given twice, parts of different studies or splits, a
//! study or rows that do not match their digests (an edit, a truncation: the digest line
//! is last), a study that fails [`Study::check`] (counts are bounded before anything is
//! allocated from them), a row whose task is not the next of its shard, and a row that
//! fails [`Study::check_row`] (every number finite and in range; what follows from the
//! study alone equal to the last digit). A digest proves a part is the one written, not
//! who wrote it: whoever edits a part and recomputes both digests is not stopped (the
//! row checks still refuse a drawn value or a name that the study does not give, and a
//! K, zeta or period out of its physical range). The merged table is the single run's,
//! byte for byte (numbers are written with all their digits and read back exactly), and
//! merging needs memory for the merged table only.

pub use crate::case::{check_name, MAX_NAME_CHARS};
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

    /// Reads a study written by [`Study::to_json`] and checks it like any input
    /// ([`Study::check`]: counts bounded before anything is allocated from them);
    /// `origin` names where the text came from in the error.
    pub fn from_json(text: &str, origin: &str) -> Result<Self> {
        let study: Study = serde_json::from_str(text).map_err(|e| {
            TuneError::Invalid(format!(
                "{origin}: column {}: {}; expected a study written by coil-tune or coil",
                e.column(),
                coil_io::confine::sanitise_message(&e.to_string(), 300)
            ))
        })?;
        study
            .check()
            .map_err(|e| TuneError::Invalid(format!("{origin}: {e}")))?;
        Ok(study)
    }

    /// Checks a study as an input: 1 to [`MAX_VARIANTS`] variants with valid names and
    /// positive finite geometry, a physical material, and (tolerance studies) bands
    /// within the nominal values, at least 2 samples and at most 10^7 tasks.
    pub fn check(&self) -> Result<()> {
        let sweep = match self {
            Study::Sweep(s) => s,
            Study::Tolerance(t) => &t.sweep,
        };
        let n = sweep.variants.len();
        if n == 0 || n > MAX_VARIANTS {
            return Err(TuneError::Invalid(format!(
                "{n} variants; expected 1 to {MAX_VARIANTS}"
            )));
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        for v in &sweep.variants {
            check_name(&v.name).map_err(TuneError::Invalid)?;
            let g = &v.spring;
            if ![
                g.active_coils,
                g.mean_diameter_mm,
                g.wire_diameter_mm,
                g.pitch_mm,
            ]
            .into_iter()
            .all(positive)
            {
                return Err(TuneError::Invalid(format!(
                    "variant {}: geometry {g:?}; expected positive finite numbers",
                    v.name
                )));
            }
        }
        let m = &sweep.material;
        let material_ok = positive(m.youngs_modulus_mpa)
            && positive(m.density_kg_m3)
            && positive(m.mass_kg)
            && m.poisson_ratio > -1.0
            && m.poisson_ratio < 0.5
            && m.alpha.is_finite()
            && m.alpha >= 0.0
            && m.beta.is_finite()
            && m.beta >= 0.0;
        if !material_ok {
            return Err(TuneError::Invalid(format!(
                "material {m:?}; expected positive E, density and mass, Poisson's ratio in (-1, 0.5), alpha and beta >= 0"
            )));
        }
        match self {
            Study::Sweep(_) => Ok(()),
            Study::Tolerance(t) => t.check(),
        }
    }

    /// Checks row `k` of the study's table as read back (`cells` in [`Study::columns`]
    /// order): every number finite and in its physical range, and every value that
    /// follows from the study alone (names, sample numbers, the drawn geometry, E and
    /// mass, the paper's values and the relative errors) equal to it to the last digit.
    /// K, zeta and the period cannot be recomputed without the solver: K must lie within
    /// a factor 3 of the Castigliano stiffness of the row's geometry (a beam helix is
    /// within 15 % of it from 8 elements per coil; a gross screen, the digest is what
    /// catches a small edit), zeta in [0, 1), the period within a factor 2 of the
    /// Rayleigh period of K and the masses.
    pub fn check_row(&self, k: usize, cells: &[String]) -> std::result::Result<(), String> {
        let column = |name: &str| -> std::result::Result<&str, String> {
            self.columns()
                .iter()
                .position(|c| *c == name)
                .and_then(|i| cells.get(i))
                .map(String::as_str)
                .ok_or_else(|| format!("no `{name}` column"))
        };
        let number = |name: &str| -> std::result::Result<f64, String> {
            let text = column(name)?;
            match text.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(format!(
                    "{name} `{}`; expected a finite number",
                    coil_io::excerpt(text)
                )),
            }
        };
        let same = |name: &str, value: Option<f64>| -> std::result::Result<(), String> {
            let text = column(name)?;
            let expected = value.map_or(String::new(), crate::output::exact);
            if text == expected {
                Ok(())
            } else {
                Err(format!(
                    "{name} `{}`; the study gives `{expected}` (the part was edited?)",
                    coil_io::excerpt(text)
                ))
            }
        };
        let (variant, state) = match self {
            Study::Sweep(s) => {
                let v = s.variants.get(k).ok_or("no such task")?;
                (v.clone(), s.material)
            }
            Study::Tolerance(t) => {
                let (v, state, sample) = t.sampled(k).map_err(|e| e.to_string())?;
                same("task", Some(k as f64))?;
                same("sample", Some(sample as f64))?;
                same("youngs_modulus_mpa", Some(state.youngs_modulus_mpa))?;
                same("mass_kg", Some(state.mass_kg))?;
                (v, state)
            }
        };
        let name = column(match self {
            Study::Sweep(_) => "name",
            Study::Tolerance(_) => "spring",
        })?;
        if name != variant.name {
            return Err(format!(
                "spring `{}`; the study gives `{}`",
                coil_io::excerpt(name),
                variant.name
            ));
        }
        let g = &variant.spring;
        same("active_coils", Some(g.active_coils))?;
        same("mean_diameter_mm", Some(g.mean_diameter_mm))?;
        same("wire_diameter_mm", Some(g.wire_diameter_mm))?;
        same("pitch_mm", Some(g.pitch_mm))?;
        let (stiffness, zeta, period) = (
            number("stiffness_n_mm")?,
            number("damping_ratio")?,
            number("period_s")?,
        );
        let helix = coil_mesher::closed_form::HelixGeometry {
            coils: g.active_coils,
            mean_diameter_mm: g.mean_diameter_mm,
            wire_diameter_mm: g.wire_diameter_mm,
            pitch_mm: g.pitch_mm,
        };
        let castigliano = coil_mesher::closed_form::HelixStiffness::new(
            &helix,
            state.youngs_modulus_mpa,
            state.poisson_ratio,
        )
        .free(true);
        if !(stiffness > castigliano / 3.0 && stiffness < castigliano * 3.0) {
            return Err(format!(
                "stiffness_n_mm {stiffness}; expected within a factor 3 of the closed form {castigliano:.4} N/mm of this spring"
            ));
        }
        if !(0.0..1.0).contains(&zeta) {
            return Err(format!("damping_ratio {zeta}; expected 0 <= zeta < 1"));
        }
        let rayleigh = coil_mesher::closed_form::rayleigh_period_s(
            stiffness,
            state.mass_kg,
            helix.spring_mass_kg(state.density_kg_m3),
        );
        if !(period > rayleigh / 2.0 && period < rayleigh * 2.0) {
            return Err(format!(
                "period_s {period}; expected within a factor 2 of the Rayleigh period {rayleigh:.5} s of K and the masses"
            ));
        }
        if let Study::Sweep(_) = self {
            let relative = |coil: f64, paper: Option<f64>| paper.map(|p| (coil - p) / p);
            same("paper_stiffness_n_mm", variant.paper_stiffness_n_mm)?;
            same("paper_damping_ratio", variant.paper_damping_ratio)?;
            same(
                "stiffness_relative_error",
                relative(stiffness, variant.paper_stiffness_n_mm),
            )?;
            same(
                "damping_relative_error",
                relative(zeta, variant.paper_damping_ratio),
            )?;
        }
        Ok(())
    }
}

/// At most this many variants in a study.
pub const MAX_VARIANTS: usize = 100_000;
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
const STUDY_DIGEST_TAG: &str = "# study-sha256 ";
const ROWS_DIGEST_TAG: &str = "# rows-sha256 ";

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
    let json = study.to_json();
    format!(
        "{PART_TAG}{shard} of a {} study: {} of {} tasks\n{STUDY_TAG}{json}\n{STUDY_DIGEST_TAG}{}\n{body}{ROWS_DIGEST_TAG}{}\n",
        study.kind(),
        tasks.len(),
        study.tasks(),
        coil_io::digest::sha256_hex(json.as_bytes()),
        rows_digest(&json, body.as_bytes()),
    )
}

/// The rows' digest: of the study and the table (header and rows), so that a study
/// edited with its own digest recomputed no longer matches its rows.
fn rows_digest(study_json: &str, table: &[u8]) -> String {
    let mut d = rows_digest_start(study_json);
    d.update(table);
    d.hex()
}

fn rows_digest_start(study_json: &str) -> coil_io::digest::Sha256 {
    let mut d = coil_io::digest::Sha256::new();
    d.update(study_json.as_bytes());
    d.update(b"\n");
    d
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

/// A part larger than this is not one (10^6 rows of a tolerance study are 0.3 GB).
const MAX_PART_BYTES: u64 = 1 << 30;
/// The longest line of a part other than the study's: a row is about 250 bytes.
const MAX_ROW_BYTES: usize = 64 << 10;

fn part_error(path: &Path, line: usize, message: impl std::fmt::Display) -> TuneError {
    TuneError::Invalid(format!("{}:{line}: {message}", path.display()))
}

/// A part file read line by line, each line bounded, the whole bounded.
struct PartReader {
    path: PathBuf,
    reader: std::io::BufReader<std::io::Take<std::fs::File>>,
    line: usize,
    buffer: Vec<u8>,
}

impl PartReader {
    fn open(path: &Path) -> Result<Self> {
        let file = std::fs::File::open(path).map_err(|e| TuneError::io(path, e))?;
        let meta = file.metadata().map_err(|e| TuneError::io(path, e))?;
        if !meta.is_file() {
            return Err(part_error(
                path,
                0,
                "not a regular file; expected a part file",
            ));
        }
        if meta.len() > MAX_PART_BYTES {
            return Err(part_error(
                path,
                0,
                format!(
                    "{} bytes; a part file holds at most {MAX_PART_BYTES} (split the study into more shards)",
                    meta.len()
                ),
            ));
        }
        use std::io::Read;
        Ok(PartReader {
            path: path.to_path_buf(),
            reader: std::io::BufReader::new(file.take(MAX_PART_BYTES + 1)),
            line: 0,
            buffer: Vec::new(),
        })
    }

    /// The next line without its `\n` (None at the end), at most `limit` bytes.
    fn next(&mut self, limit: usize) -> Result<Option<String>> {
        use std::io::{BufRead, Read};
        self.buffer.clear();
        self.line += 1;
        let n = (&mut self.reader)
            .take(limit as u64 + 1)
            .read_until(b'\n', &mut self.buffer)
            .map_err(|e| TuneError::io(&self.path, e))?;
        if n == 0 {
            return Ok(None);
        }
        if self.buffer.last() != Some(&b'\n') {
            let message = if self.buffer.len() > limit {
                format!("a line longer than {limit} bytes; expected a part file written by `--shard I/N`")
            } else {
                "the last line has no line end: the part is truncated; run its shard again".into()
            };
            return Err(part_error(&self.path, self.line, message));
        }
        self.buffer.pop();
        match std::str::from_utf8(&self.buffer) {
            Ok(text) => Ok(Some(text.to_string())),
            Err(_) => Err(part_error(
                &self.path,
                self.line,
                "not UTF-8 text; expected a part file",
            )),
        }
    }

    fn error(&self, message: impl std::fmt::Display) -> TuneError {
        part_error(&self.path, self.line, message)
    }
}

/// A part file's head: its shard and study, their digest checked.
#[derive(Debug, Clone)]
pub struct PartHead {
    /// The part file.
    pub path: PathBuf,
    /// The shard.
    pub shard: Shard,
    /// The study as JSON.
    pub study_json: String,
}

/// Reads a part's first three lines: the shard, the study and the study's digest.
fn read_head(reader: &mut PartReader) -> Result<PartHead> {
    let expected_first =
        "not a part file; expected `# coil-tune part I/N of a ... study` (written by `--shard I/N`)";
    let first = reader
        .next(4096)?
        .ok_or_else(|| reader.error("empty; expected a part file"))?;
    let shard = first
        .strip_prefix(PART_TAG)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|s| s.parse::<Shard>().ok())
        .ok_or_else(|| reader.error(expected_first))?;
    let study_json = reader
        .next(coil_io::MAX_JSON_BYTES as usize * 2)?
        .and_then(|l| l.strip_prefix(STUDY_TAG).map(str::to_string))
        .ok_or_else(|| reader.error("expected `# study {...}`, the study as JSON"))?;
    let digest = reader
        .next(4096)?
        .and_then(|l| l.strip_prefix(STUDY_DIGEST_TAG).map(str::to_string))
        .ok_or_else(|| {
            reader.error(
                "expected `# study-sha256 ...`, the study's digest (a part written by an older coil-tune, or edited: run its shard again)",
            )
        })?;
    if coil_io::digest::sha256_hex(study_json.as_bytes()) != digest {
        return Err(part_error(
            &reader.path,
            2,
            "the study does not match its digest on line 3: the part was edited or damaged; run its shard again",
        ));
    }
    Ok(PartHead {
        path: reader.path.clone(),
        shard,
        study_json,
    })
}

/// Reads a part's rows after its head, checking the header, each row (its task, its
/// numbers: [`Study::check_row`]) and the rows' digest; `keep(task, row)` receives
/// each row as the single run's CSV record (without the part's task column).
fn read_rows(
    reader: &mut PartReader,
    head: &PartHead,
    study: &Study,
    mut keep: impl FnMut(usize, String),
) -> Result<()> {
    let mut columns = vec!["task"];
    columns.extend(study.columns());
    let header = columns.join(",");
    let mut digest = rows_digest_start(&head.study_json);
    match reader.next(MAX_ROW_BYTES)? {
        Some(line) if line == header => {
            digest.update(line.as_bytes());
            digest.update(b"\n");
        }
        Some(line) => {
            let line = coil_io::excerpt(&line);
            return Err(reader.error(format!("header `{line}`; expected `{header}`")));
        }
        None => return Err(reader.error(format!("no header; expected `{header}`"))),
    }
    let expected = head.shard.tasks(study.tasks());
    let mut next = expected.iter().copied();
    let written = loop {
        let Some(line) = reader.next(MAX_ROW_BYTES)? else {
            return Err(reader.error(
                "the part ends without its `# rows-sha256` line: it is truncated; run its shard again",
            ));
        };
        if let Some(d) = line.strip_prefix(ROWS_DIGEST_TAG) {
            break d.to_string();
        }
        let cells = crate::output::split_csv_record(&line).map_err(|e| reader.error(e))?;
        let Some(task) = cells.first().and_then(|t| t.parse::<usize>().ok()) else {
            return Err(reader.error("expected a task number in the first column"));
        };
        if cells.len() != columns.len() {
            return Err(reader.error(format!(
                "{} cells; expected {} ({header})",
                cells.len(),
                columns.len()
            )));
        }
        match next.next() {
            Some(k) if k == task => {}
            Some(k) => {
                return Err(reader.error(format!(
                    "task {task}; expected task {k} (shard {} holds tasks {} to {} in steps of {}, in order)",
                    head.shard,
                    expected.first().copied().unwrap_or(0),
                    expected.last().copied().unwrap_or(0),
                    head.shard.count
                )))
            }
            None => {
                return Err(reader.error(format!(
                    "task {task} after the shard's last task {}",
                    expected.last().map_or("-".into(), usize::to_string)
                )))
            }
        }
        study
            .check_row(task, &cells[1..])
            .map_err(|e| reader.error(format!("task {task}: {e}")))?;
        digest.update(line.as_bytes());
        digest.update(b"\n");
        let record = line.split_once(',').map_or("", |(_, r)| r).to_string();
        keep(task, record);
    };
    if let Some(k) = next.next() {
        return Err(reader.error(format!(
            "shard {} ends before its task {k} ({} tasks expected): run its shard again",
            head.shard,
            expected.len()
        )));
    }
    if digest.hex() != written {
        return Err(reader.error(
            "the rows (or the study) do not match the rows' digest: the part was edited or damaged; run its shard again",
        ));
    }
    if reader.next(MAX_ROW_BYTES)?.is_some() {
        return Err(reader.error("text after the rows' digest; expected the end of the part"));
    }
    Ok(())
}

/// One part file as read and checked whole (its rows as the single run's records).
#[derive(Debug, Clone)]
pub struct Part {
    /// The part's head.
    pub head: PartHead,
    /// The study.
    pub study: Study,
    /// (task, the row's CSV record without the task column).
    pub rows: Vec<(usize, String)>,
}

/// Reads and checks one part file: head, digests, every row.
pub fn read_part(path: &Path) -> Result<Part> {
    let mut reader = PartReader::open(path)?;
    let head = read_head(&mut reader)?;
    let study = Study::from_json(&head.study_json, &format!("{}:2", path.display()))?;
    let mut rows = Vec::new();
    read_rows(&mut reader, &head, &study, |k, r| rows.push((k, r)))?;
    Ok(Part { head, study, rows })
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

/// A study's table: its columns and its rows as CSV records, in task order.
#[derive(Debug, Clone)]
pub struct Merged {
    /// The study.
    pub study: Study,
    /// The column names.
    pub columns: Vec<&'static str>,
    /// The rows, each one CSV record (fields quoted as needed, no line end).
    pub records: Vec<String>,
}

impl Merged {
    /// The table of rows of cells (a single run, or rows sent back by workers).
    pub fn of_cells(study: Study, rows: &[Vec<Cell>]) -> Self {
        Merged {
            columns: study.columns(),
            records: rows
                .iter()
                .map(|r| crate::output::csv_record(r.iter().map(Cell::csv)))
                .collect(),
            study,
        }
    }

    /// Writes the table as the single run does: the header, then one record a line.
    pub fn write_csv(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        writeln!(w, "{}", crate::output::csv_record(&self.columns))?;
        for r in &self.records {
            w.write_all(r.as_bytes())?;
            w.write_all(b"\n")?;
        }
        Ok(())
    }

    /// The table as text (for small tables and tests; [`Merged::write_csv`] streams).
    pub fn csv(&self) -> String {
        let mut out = Vec::new();
        // Writing into a Vec cannot fail.
        let _ = self.write_csv(&mut out);
        String::from_utf8_lossy(&out).into_owned()
    }

    /// Each row's fields.
    pub fn rows(&self) -> impl Iterator<Item = Result<Vec<String>>> + '_ {
        self.records.iter().enumerate().map(|(k, r)| {
            crate::output::split_csv_record(r).map_err(|e| {
                TuneError::Invalid(format!("{} row {}: {e}", self.study.kind(), k + 1))
            })
        })
    }
}

/// Joins the parts of one study; refuses missing, repeated or foreign shards, parts
/// whose digests do not match, and rows that fail [`Study::check_row`]. Reads each part
/// twice, line by line: first the heads of all (so a missing shard is found before any
/// row is read), then the rows; memory is the merged table, not a multiple of the parts.
pub fn merge(files: &[PathBuf]) -> Result<Merged> {
    let mut heads = Vec::with_capacity(files.len());
    for f in files {
        heads.push(read_head(&mut PartReader::open(f)?)?);
    }
    let first = &heads[0];
    let study = Study::from_json(&first.study_json, &format!("{}:2", first.path.display()))?;
    let count = first.shard.count;
    let mut by_index: BTreeMap<usize, &PartHead> = BTreeMap::new();
    for head in &heads {
        if head.shard.count != count {
            return Err(TuneError::Invalid(format!(
                "{}: shard {} belongs to a split into {}; {} is a split into {count}: merge the parts of one split",
                head.path.display(),
                head.shard,
                head.shard.count,
                first.path.display()
            )));
        }
        if head.study_json != first.study_json {
            return Err(TuneError::Invalid(format!(
                "{}:2: shard {} is a part of another study than {} (their `# study` lines differ); merge the parts of one study",
                head.path.display(),
                head.shard,
                first.path.display()
            )));
        }
        if let Some(other) = by_index.insert(head.shard.index, head) {
            return Err(TuneError::Invalid(format!(
                "shard {} is given twice: {} and {}; expected each shard once",
                head.shard,
                other.path.display(),
                head.path.display()
            )));
        }
    }
    let missing: Vec<String> = (1..=count)
        .filter(|i| !by_index.contains_key(i))
        .take(11)
        .map(|i| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        let absent = count - by_index.len();
        let shown: Vec<&str> = missing.iter().take(10).map(String::as_str).collect();
        return Err(TuneError::Invalid(format!(
            "shard{} {}{} missing (found {} of {count} parts in {}); run {} with --shard and merge again",
            if absent > 1 { "s" } else { "" },
            shown.join(", "),
            if absent > shown.len() {
                format!(" and {} more", absent - shown.len())
            } else {
                String::new()
            },
            heads.len(),
            first
                .path
                .parent()
                .map_or(".".into(), |p| p.display().to_string()),
            study.kind(),
        )));
    }
    // The task count is bounded by Study::from_json's check.
    let mut records: Vec<Option<String>> = vec![None; study.tasks()];
    for head in by_index.values() {
        let mut reader = PartReader::open(&head.path)?;
        let again = read_head(&mut reader)?;
        if again.study_json != head.study_json || again.shard != head.shard {
            return Err(reader.error("the part changed while it was merged; merge again"));
        }
        read_rows(&mut reader, head, &study, |k, r| records[k] = Some(r))?;
    }
    Ok(Merged {
        columns: study.columns(),
        // read_rows checked each part's tasks, and every shard is present once.
        records: records.into_iter().flatten().collect(),
        study,
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
