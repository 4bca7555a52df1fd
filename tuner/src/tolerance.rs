//! `coil-tune tolerance`: K and zeta of the Table 4 springs as manufactured, sampled
//! within stated tolerances (a [`crate::study::Study`]: one task per sampled spring).
//!
//! # What varies, and by how much
//! Each sample draws, independently and uniformly within the band `nominal +- half-width`
//! (every value the tolerance allows equally likely: a conservative choice, since real
//! processes centre their output):
//!
//! | quantity | default half-width | source |
//! |---|---|---|
//! | wire diameter d | 0.03 mm | the order of the diameter tolerance of patented spring wire of 2.5-3.5 mm (EN 10270-1, formerly DIN 2076 class C); the standard's table was not at hand: give the supplier's value with `--wire-tol` |
//! | mean coil diameter D | EN 15800 grade 2 (`--grade 1..3`) by D and w = D/d: 0.35-0.50 mm here | EN 15800:2008 (= DIN 2095/2097) coil-diameter table, [`crate::en15800`] |
//! | active coils n | 0.25 coil | assumption: EN 15800 tolerates force and length, not n; a coiler sets n within about a quarter coil |
//! | Young's modulus E | 2 % | assumption: spread between wire lots (EN 13906-1 gives E without a tolerance) |
//! | the weight's mass | 0.1 % | assumption: a weighed weight |
//!
//! The pitch, Poisson's ratio, density, alpha and beta stay at the validated values. The
//! EN 15800 table of the coil diameter's permissible deviation (+- mm) for grades 1, 2, 3
//! and spring index w in (4, 8], (8, 14], (14, 20] covers 0.63 mm <= D <= 31.5 mm here;
//! outside it (or for grade 3 at D > 25 mm, w > 14, which we could not read) the run asks
//! for `--coil-diameter-tol`.
//!
//! # Samples
//! Sample 0 of each spring is the nominal spring; samples 1..=S are drawn. Task
//! `k = spring * (S + 1) + sample`. Draw `q` of task `k` is [`uniform`]`(seed, k, q)`: a
//! counter-based generator (SplitMix64's finaliser applied to the seed, the task and the
//! draw), so a sample does not depend on which other tasks ran before it, in which
//! process, or in which shard. The distributions are the percentiles (linear
//! interpolation between order statistics, numpy's default) of samples 1..=S.
//!
//! Units: mm, MPa, kg, N/mm, s, as the column names say.

use crate::error::{Result, TuneError};
use crate::output::Cell;
use crate::sweep::VariantSweep;
use coil_postproc::plot::{self, Draw, Figure, FONT};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde::{Deserialize, Serialize};

/// The columns of `tolerance.csv`, in order.
pub const COLUMNS: [&str; 12] = [
    "task",
    "spring",
    "sample",
    "active_coils",
    "mean_diameter_mm",
    "wire_diameter_mm",
    "pitch_mm",
    "youngs_modulus_mpa",
    "mass_kg",
    "stiffness_n_mm",
    "damping_ratio",
    "period_s",
];

/// The percentiles reported.
pub const PERCENTILES: [f64; 7] = [1.0, 5.0, 25.0, 50.0, 75.0, 95.0, 99.0];

/// Manufacturing tolerances (half-widths of the bands).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tolerances {
    /// +- wire diameter (mm).
    pub wire_diameter_mm: f64,
    /// EN 15800 quality grade of the coil diameter (1, 2 or 3).
    pub coil_diameter_grade: u8,
    /// +- mean coil diameter (mm) instead of the EN 15800 table.
    pub coil_diameter_mm: Option<f64>,
    /// +- active coils.
    pub active_coils: f64,
    /// +- relative Young's modulus.
    pub youngs_modulus_relative: f64,
    /// +- relative mass of the weight.
    pub mass_relative: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            wire_diameter_mm: 0.03,
            coil_diameter_grade: 2,
            coil_diameter_mm: None,
            active_coils: 0.25,
            youngs_modulus_relative: 0.02,
            mass_relative: 0.001,
        }
    }
}

pub use crate::en15800::coil_diameter as en15800_coil_diameter;

/// The half-widths for one spring.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Bands {
    /// Wire diameter d, mm.
    pub wire_diameter_mm: f64,
    /// Mean coil diameter D, mm.
    pub mean_diameter_mm: f64,
    /// Number of active coils n.
    pub active_coils: f64,
    /// E sampled, relative to nominal (-).
    pub youngs_modulus_relative: f64,
    /// Mass sampled, relative to nominal (-).
    pub mass_relative: f64,
}

impl Tolerances {
    /// The bands of the spring `name` with geometry `spring`.
    pub fn bands(&self, name: &str, spring: &crate::case::SpringGeometry) -> Result<Bands> {
        let coil = match self.coil_diameter_mm {
            Some(t) => t,
            None => en15800_coil_diameter(
                self.coil_diameter_grade,
                spring.mean_diameter_mm,
                spring.wire_diameter_mm,
            )
            .ok_or_else(|| {
                TuneError::Invalid(format!(
                    "spring {name}: D = {} mm, w = D/d = {:.2}, grade {}: outside the EN 15800 coil-diameter table (0.63 <= D <= 200 mm, 4 <= w <= 20, grades 1-3); give --coil-diameter-tol in mm",
                    spring.mean_diameter_mm,
                    spring.mean_diameter_mm / spring.wire_diameter_mm,
                    self.coil_diameter_grade
                ))
            })?,
        };
        let bands = Bands {
            wire_diameter_mm: self.wire_diameter_mm,
            mean_diameter_mm: coil,
            active_coils: self.active_coils,
            youngs_modulus_relative: self.youngs_modulus_relative,
            mass_relative: self.mass_relative,
        };
        let ok = |x: f64, limit: f64| x.is_finite() && (0.0..limit).contains(&x);
        if !(ok(bands.wire_diameter_mm, spring.wire_diameter_mm)
            && ok(
                bands.mean_diameter_mm,
                spring.mean_diameter_mm - spring.wire_diameter_mm,
            )
            && ok(bands.active_coils, spring.active_coils)
            && ok(bands.youngs_modulus_relative, 1.0)
            && ok(bands.mass_relative, 1.0))
        {
            return Err(TuneError::Invalid(format!(
                "spring {name}: tolerances {bands:?}; expected half-widths >= 0 smaller than the nominal values (d, D - d, n) and relative ones below 1"
            )));
        }
        Ok(bands)
    }
}

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Draw `draw` of task `task` under `seed`: uniform on [0, 1) with 53 random bits.
/// SplitMix64's finaliser (Steele, Lea & Flood, OOPSLA 2014) on a counter made of the
/// three, so draws are independent of the order in which tasks run.
pub fn uniform(seed: u64, task: u64, draw: u64) -> f64 {
    const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;
    let counter = task.wrapping_mul(8).wrapping_add(draw).wrapping_add(1);
    let z = mix(mix(seed).wrapping_add(counter.wrapping_mul(GOLDEN)));
    (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The tolerance study of a variants list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ToleranceStudy {
    /// The validated material, the nominal springs and the run settings.
    pub sweep: VariantSweep,
    /// The tolerances.
    pub tolerances: Tolerances,
    /// Drawn samples per spring (sample 0, the nominal spring, comes on top).
    pub samples: usize,
    /// Seed of the random sampling.
    pub seed: u64,
}

/// One sampled spring's row.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToleranceRow {
    /// Task number.
    pub task: usize,
    /// The spring's name.
    pub spring: String,
    /// Sample number.
    pub sample: usize,
    /// Number of active coils n.
    pub active_coils: f64,
    /// Mean coil diameter D, mm.
    pub mean_diameter_mm: f64,
    /// Wire diameter d, mm.
    pub wire_diameter_mm: f64,
    /// Pitch h, mm.
    pub pitch_mm: f64,
    /// Young's modulus E, MPa.
    pub youngs_modulus_mpa: f64,
    /// The weight's mass, kg.
    pub mass_kg: f64,
    /// K over the samples, N/mm.
    pub stiffness_n_mm: f64,
    /// zeta over the samples (-).
    pub damping_ratio: f64,
    /// Period of the axial mode, s.
    pub period_s: f64,
}

impl ToleranceRow {
    /// The row of `tolerance.csv` ([`COLUMNS`]).
    pub fn cells(&self) -> Vec<Cell> {
        vec![
            Cell::Number(self.task as f64),
            Cell::Text(self.spring.clone()),
            Cell::Number(self.sample as f64),
            Cell::Number(self.active_coils),
            Cell::Number(self.mean_diameter_mm),
            Cell::Number(self.wire_diameter_mm),
            Cell::Number(self.pitch_mm),
            Cell::Number(self.youngs_modulus_mpa),
            Cell::Number(self.mass_kg),
            Cell::Number(self.stiffness_n_mm),
            Cell::Number(self.damping_ratio),
            Cell::Number(self.period_s),
        ]
    }
}

/// At most this many tasks: 10^5 samples of each of 100 springs.
const MAX_TASKS: usize = 10_000_000;

impl ToleranceStudy {
    /// Checks the study (bands of every spring, at least 2 samples: one sample has no
    /// spread; the task count, overflow-checked).
    pub fn check(&self) -> Result<()> {
        if self.samples < 2 {
            return Err(TuneError::Invalid(format!(
                "{} samples per spring; expected at least 2 (one sample has no spread: its standard deviation is undefined)",
                self.samples
            )));
        }
        for v in &self.sweep.variants {
            self.tolerances.bands(&v.name, &v.spring)?;
        }
        let total = self
            .samples
            .checked_add(1)
            .and_then(|per| self.sweep.variants.len().checked_mul(per));
        if total.is_none_or(|t| t > MAX_TASKS) {
            return Err(TuneError::Invalid(format!(
                "{} springs x {} samples: expected at most {MAX_TASKS} tasks",
                self.sweep.variants.len(),
                self.samples
            )));
        }
        Ok(())
    }

    /// Number of tasks: (samples + 1) per spring (saturating: [`ToleranceStudy::check`]
    /// refuses a study whose count overflows).
    pub fn tasks(&self) -> usize {
        self.sweep
            .variants
            .len()
            .saturating_mul(self.samples.saturating_add(1))
    }

    /// Task `k`'s sampled spring (its variant with the drawn geometry), material and
    /// sample number: a function of the study and `k` only.
    pub fn sampled(
        &self,
        k: usize,
    ) -> Result<(crate::case::Variant, crate::fe::SpringState, usize)> {
        let per = self.samples.saturating_add(1);
        let variant = self.sweep.variants.get(k / per).ok_or_else(|| {
            TuneError::Invalid(format!("task {k}: the study has {} tasks", self.tasks()))
        })?;
        let sample = k % per;
        let bands = self.tolerances.bands(&variant.name, &variant.spring)?;
        // u in [0, 1) -> nominal + half * (2u - 1); sample 0 is the nominal spring.
        let draw = |q: u64| {
            if sample == 0 {
                0.0
            } else {
                2.0 * uniform(self.seed, k as u64, q) - 1.0
            }
        };
        let nominal = &variant.spring;
        let spring = crate::case::SpringGeometry {
            wire_diameter_mm: nominal.wire_diameter_mm + bands.wire_diameter_mm * draw(0),
            mean_diameter_mm: nominal.mean_diameter_mm + bands.mean_diameter_mm * draw(1),
            active_coils: nominal.active_coils + bands.active_coils * draw(2),
            pitch_mm: nominal.pitch_mm,
        };
        let m = &self.sweep.material;
        let material = crate::fe::SpringState {
            youngs_modulus_mpa: m.youngs_modulus_mpa
                * (1.0 + bands.youngs_modulus_relative * draw(3)),
            mass_kg: m.mass_kg * (1.0 + bands.mass_relative * draw(4)),
            ..*m
        };
        let sampled = crate::case::Variant {
            name: variant.name.clone(),
            spring,
            paper_stiffness_n_mm: None,
            paper_damping_ratio: None,
        };
        Ok((sampled, material, sample))
    }

    /// Runs task `k`: the spring and sample it stands for, K and zeta.
    pub fn run(&self, k: usize) -> Result<ToleranceRow> {
        let (sampled, material, sample) = self.sampled(k)?;
        let spring = sampled.spring;
        let r = crate::sweep::run_variant(&material, &sampled, &self.sweep.fe, &self.sweep.decay)?;
        Ok(ToleranceRow {
            task: k,
            spring: sampled.name.clone(),
            sample,
            active_coils: spring.active_coils,
            mean_diameter_mm: spring.mean_diameter_mm,
            wire_diameter_mm: spring.wire_diameter_mm,
            pitch_mm: spring.pitch_mm,
            youngs_modulus_mpa: material.youngs_modulus_mpa,
            mass_kg: material.mass_kg,
            stiffness_n_mm: r.stiffness_n_mm,
            damping_ratio: r.damping_ratio,
            period_s: r.period_s,
        })
    }
}

/// A distribution's summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Distribution {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (n - 1).
    pub std: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
    /// `p1`, `p5`, ... (see [`PERCENTILES`]).
    pub percentiles: std::collections::BTreeMap<String, f64>,
}

/// Percentile `p` (0-100) of sorted values, linear between order statistics (numpy's
/// default, Hyndman & Fan's type 7).
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * (p / 100.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(sorted.len() - 1);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

impl Distribution {
    /// The mean, smallest and largest of `values`.
    pub fn of(values: &[f64]) -> Self {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len() as f64;
        let mean = sorted.iter().sum::<f64>() / n;
        let var = sorted.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        Distribution {
            mean,
            std: var.sqrt(),
            min: sorted.first().copied().unwrap_or(f64::NAN),
            max: sorted.last().copied().unwrap_or(f64::NAN),
            percentiles: PERCENTILES
                .iter()
                .map(|&p| (format!("p{p}"), percentile(&sorted, p)))
                .collect(),
        }
    }

    fn p(&self, p: f64) -> f64 {
        self.percentiles[&format!("p{p}")]
    }
}

/// One spring's distributions.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpringSummary {
    /// The spring's name.
    pub spring: String,
    /// The bands.
    pub bands: Bands,
    /// K of the nominal spring, N/mm.
    pub nominal_stiffness_n_mm: f64,
    /// zeta of the nominal spring (-).
    pub nominal_damping_ratio: f64,
    /// Number of samples.
    pub samples: usize,
    /// K over the samples, N/mm.
    pub stiffness_n_mm: Distribution,
    /// zeta over the samples (-).
    pub damping_ratio: Distribution,
}

/// `tolerance_summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Seed of the random sampling.
    pub seed: u64,
    /// Number of samples.
    pub samples: usize,
    /// The tolerances.
    pub tolerances: Tolerances,
    /// How values are drawn.
    pub distribution: &'static str,
    /// The springs.
    pub springs: Vec<SpringSummary>,
}

/// The summary of a study's table (rows of fields in [`COLUMNS`] order, as a single
/// run or a merge gives them: [`crate::study::Merged::rows`]). One pass; memory is two
/// numbers a row.
pub fn summarize(
    study: &ToleranceStudy,
    rows: impl IntoIterator<Item = Result<Vec<String>>>,
) -> Result<Summary> {
    let col = |name: &str| COLUMNS.iter().position(|c| *c == name).unwrap_or(0);
    let (spring_col, sample_col) = (col("spring"), col("sample"));
    let (k_col, z_col) = (col("stiffness_n_mm"), col("damping_ratio"));
    let number = |row: &Vec<String>, c: usize| {
        row.get(c)
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                TuneError::Invalid(format!(
                    "tolerance table: task {}: column `{}` is not a finite number",
                    coil_io::excerpt(row.first().map_or("?", String::as_str)),
                    COLUMNS[c]
                ))
            })
    };
    let index: std::collections::HashMap<&str, usize> = study
        .sweep
        .variants
        .iter()
        .enumerate()
        .map(|(i, v)| (v.name.as_str(), i))
        .collect();
    let n = study.sweep.variants.len();
    let mut nominal: Vec<Option<(f64, f64)>> = vec![None; n];
    let (mut ks, mut zs) = (vec![Vec::new(); n], vec![Vec::new(); n]);
    for row in rows {
        let row = row?;
        let Some(&i) = row.get(spring_col).and_then(|s| index.get(s.as_str())) else {
            continue;
        };
        let (k, z) = (number(&row, k_col)?, number(&row, z_col)?);
        if number(&row, sample_col)? == 0.0 {
            nominal[i] = Some((k, z));
        } else {
            ks[i].push(k);
            zs[i].push(z);
        }
    }
    let mut springs = Vec::new();
    for (i, v) in study.sweep.variants.iter().enumerate() {
        let (k0, z0) = nominal[i].ok_or_else(|| {
            TuneError::Invalid(format!(
                "tolerance table: spring {} has no nominal sample (sample 0)",
                v.name
            ))
        })?;
        springs.push(SpringSummary {
            spring: v.name.clone(),
            bands: study.tolerances.bands(&v.name, &v.spring)?,
            nominal_stiffness_n_mm: k0,
            nominal_damping_ratio: z0,
            samples: ks[i].len(),
            stiffness_n_mm: Distribution::of(&ks[i]),
            damping_ratio: Distribution::of(&zs[i]),
        });
    }
    Ok(Summary {
        seed: study.seed,
        samples: study.samples,
        tolerances: study.tolerances.clone(),
        distribution: "uniform within +- half-width, independent",
        springs,
    })
}

impl Summary {
    /// The terminal and report table: percentiles relative to the nominal spring.
    pub fn table(&self) -> String {
        let mut out = format!(
            "{:<6} {:>5} | {:>9} {:>8} {:>8} {:>8} {:>8} | {:>9} {:>8} {:>8} {:>8} {:>8}\n",
            "", "n", "K nominal", "p5", "p50", "p95", "std", "zeta nom", "p5", "p50", "p95", "std"
        );
        let rel = |x: f64, nominal: f64| format!("{:+.2}%", 100.0 * (x / nominal - 1.0));
        for s in &self.springs {
            let (k, z) = (&s.stiffness_n_mm, &s.damping_ratio);
            out.push_str(&format!(
                "{:<6} {:>5} | {:>9.4} {:>8} {:>8} {:>8} {:>7.2}% | {:>9.6} {:>8} {:>8} {:>8} {:>7.2}%\n",
                s.spring,
                s.samples,
                s.nominal_stiffness_n_mm,
                rel(k.p(5.0), s.nominal_stiffness_n_mm),
                rel(k.p(50.0), s.nominal_stiffness_n_mm),
                rel(k.p(95.0), s.nominal_stiffness_n_mm),
                100.0 * k.std / s.nominal_stiffness_n_mm,
                s.nominal_damping_ratio,
                rel(z.p(5.0), s.nominal_damping_ratio),
                rel(z.p(50.0), s.nominal_damping_ratio),
                rel(z.p(95.0), s.nominal_damping_ratio),
                100.0 * z.std / s.nominal_damping_ratio,
            ));
        }
        out
    }

    /// The summary as pretty JSON.
    pub fn json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

/// Writes a tolerance study's summary files into `out` beside its table
/// (`tolerance.csv`, staged by the caller): `tolerance_summary.json`, `tolerance.md` and
/// `tolerance.png`.
pub fn write(summary: &Summary, out: &crate::output::OutDir, plots: bool) -> Result<()> {
    out.write("tolerance_summary.json", summary.json().as_bytes())?;
    let md = format!(
        "# Tolerance study\n\nseed {}, {} samples per spring ({}), percentiles relative to the nominal spring:\n\n```\n{}```\n",
        summary.seed,
        summary.samples,
        summary.distribution,
        summary.table()
    );
    out.write("tolerance.md", md.as_bytes())?;
    if plots {
        let path = out.staged("tolerance.png")?;
        plot::render(&path, &SpreadFigure { summary }).map_err(|source| TuneError::Plot {
            path: path.clone(),
            message: source.to_string(),
        })?;
    }
    Ok(())
}

/// Percentile bars of K and zeta per spring, relative to the nominal spring (%).
struct SpreadFigure<'a> {
    summary: &'a Summary,
}

impl Figure for SpreadFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
        root.fill(&WHITE).map_err(e)?;
        let panels = root.split_evenly((1, 2));
        let springs = &self.summary.springs;
        let n = springs.len() as f64;
        type Pick = fn(&SpringSummary) -> (&Distribution, f64);
        let picks: [(&str, Pick); 2] = [
            ("K relative to the nominal spring (%)", |s| {
                (&s.stiffness_n_mm, s.nominal_stiffness_n_mm)
            }),
            ("zeta relative to the nominal spring (%)", |s| {
                (&s.damping_ratio, s.nominal_damping_ratio)
            }),
        ];
        for (panel, (title, pick)) in panels.iter().zip(picks) {
            let rel = |s: &SpringSummary, p: f64| {
                let (d, nominal) = pick(s);
                100.0 * (d.p(p) / nominal - 1.0)
            };
            let (lo, hi) = crate::plots::range_of(
                springs
                    .iter()
                    .flat_map(|s| [rel(s, 1.0), rel(s, 99.0), 0.0]),
            );
            let mut chart = ChartBuilder::on(panel)
                .caption(title, (FONT, 22))
                .margin(15)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(0.5..n + 0.5, lo..hi)
                .map_err(|x| x.to_string())?;
            let names: Vec<String> = springs.iter().map(|s| s.spring.clone()).collect();
            chart
                .configure_mesh()
                .x_labels(springs.len())
                .x_label_formatter(&|x| {
                    let i = x.round() as usize;
                    if (x - x.round()).abs() < 1e-6 && i >= 1 && i <= names.len() {
                        names[i - 1].clone()
                    } else {
                        String::new()
                    }
                })
                .y_label_formatter(&crate::plots::short)
                .x_desc("spring (boxes p25-p75, bars p5-p95, dots p1 and p99, line p50)")
                .label_style((FONT, 15))
                .draw()
                .map_err(|x| x.to_string())?;
            let blue = RGBColor(31, 119, 180);
            for (i, s) in springs.iter().enumerate() {
                let x = (i + 1) as f64;
                chart
                    .draw_series([
                        PathElement::new(
                            [(x, rel(s, 5.0)), (x, rel(s, 95.0))],
                            BLACK.stroke_width(2),
                        ),
                        PathElement::new(
                            [(x - 0.2, rel(s, 50.0)), (x + 0.2, rel(s, 50.0))],
                            BLACK.stroke_width(3),
                        ),
                    ])
                    .map_err(|x| x.to_string())?;
                chart
                    .draw_series([Rectangle::new(
                        [(x - 0.2, rel(s, 25.0)), (x + 0.2, rel(s, 75.0))],
                        blue.mix(0.5).filled(),
                    )])
                    .map_err(|x| x.to_string())?;
                chart
                    .draw_series(
                        [rel(s, 1.0), rel(s, 99.0)].map(|y| Circle::new((x, y), 4, BLACK.filled())),
                    )
                    .map_err(|x| x.to_string())?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_are_uniform_and_independent_of_order() {
        // 10 bins of 1e5 draws: each count is binomial(n, 0.1), sd = sqrt(n 0.1 0.9) = 95;
        // 5 sd bounds every bin (a false alarm about once in 10^5 runs).
        let n = 100_000u64;
        let mut bins = [0u64; 10];
        let mut sum = 0.0;
        for task in 0..n {
            let u = uniform(42, task, 3);
            assert!((0.0..1.0).contains(&u));
            bins[(u * 10.0) as usize] += 1;
            sum += u;
        }
        let sd = (n as f64 * 0.1 * 0.9).sqrt();
        for count in bins {
            assert!((count as f64 - 0.1 * n as f64).abs() < 5.0 * sd, "{bins:?}");
        }
        // The mean's sd is sqrt(1/12 n) = 9.1e-4.
        assert!((sum / n as f64 - 0.5).abs() < 5.0 * (1.0 / (12.0 * n as f64)).sqrt());
        // A draw is a function of (seed, task, draw) only.
        assert_eq!(uniform(7, 123, 2), uniform(7, 123, 2));
        assert_ne!(uniform(7, 123, 2), uniform(8, 123, 2));
        assert_ne!(uniform(7, 123, 2), uniform(7, 124, 2));
        assert_ne!(uniform(7, 123, 2), uniform(7, 123, 1));
    }

    #[test]
    fn percentiles_interpolate_between_order_statistics() {
        let x = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(percentile(&x, 50.0), 3.0);
        assert_eq!(percentile(&x, 25.0), 2.0);
        assert!((percentile(&x, 10.0) - 1.4).abs() < 1e-15);
        assert_eq!(percentile(&x, 100.0), 5.0);
        let d = Distribution::of(&[4.0, 1.0, 3.0, 2.0, 5.0]);
        assert_eq!((d.mean, d.min, d.max), (3.0, 1.0, 5.0));
        assert!((d.std - 2.5f64.sqrt()).abs() < 1e-15);
    }
}
