//! The damping-band spring study of docs/catenary.md ("Spring study"): the case with its
//! head stage (stage 1) replaced by each spring's lumped `(K, c)`
//! ([`crate::head_stage::springs`]: `K = 4 k`, `c = 2 zeta sqrt(K m_head)`) at the low, mid
//! and high zeta of the spring's damping-law band, beside the case's own head stage; and,
//! unless left out, each spring once more with its Craig-Bampton reduced stage
//! ([`crate::head_stage::with_reduced_head`]: surge modes, the springs' mass, the paper's
//! Rayleigh law on the wire) beside its lumped stage at mid zeta. Every run at every speed
//! of the case, in parallel.
//!
//! The example `spring_study` prints it; a second-stage test compares it with the docs'
//! tables. Statistics in N and % as [`crate::en50318::Statistics`].

use crate::case::Case;
use crate::en50318::study::SpringStudyRow;
use crate::en50318::Statistics;
use crate::head_stage::springs::{head_stages_of_files, HeadStageSettings, HeadStages, ZetaLevel};
use crate::head_stage::{reduced_head_stages, with_reduced_head};
use crate::run::run_speed;
use crate::Result;
use coil_tuner::case::read_variants;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// The name of the case's own head stage in the study's rows.
pub const REFERENCE_HEAD: &str = "EN 50318 head";

/// The study's runs.
#[derive(Debug, Clone)]
pub struct BandStudy {
    /// Each spring's lumped head stage (the case's spring first, then the variants).
    pub stages: HeadStages,
    /// The number of surge modes kept in each spring's reduced stage (the stages' order;
    /// empty when the reduced stages are left out).
    pub reduced_modes: Vec<usize>,
    /// The lumped runs: the case's head stage (`mid`), then each spring at `low`, `mid`,
    /// `high`, each at every speed.
    pub rows: Vec<SpringStudyRow>,
    /// The reduced runs (zeta `mid`), each spring at every speed.
    pub reduced: Vec<SpringStudyRow>,
}

/// Runs the study on `case` with the springs of the case folder `springs` and its variants
/// file `variants` (`table4.json` for `cases/160ect`), with the reduced stages when
/// `with_reduced`.
pub fn band_study(
    case: &Case,
    springs: &Path,
    variants: &Path,
    with_reduced: bool,
) -> Result<BandStudy> {
    let head_mass = case.pantograph.stages.first().map_or(0.0, |s| s.mass_kg);
    let settings = HeadStageSettings::default();
    let stages = head_stages_of_files(springs, variants, head_mass, &settings)?;
    let reduced_stages = if with_reduced {
        reduced_head_stages(&stages, &read_variants(variants)?, &settings.fe)?
    } else {
        Vec::new()
    };
    let reference = case.pantograph.stages.first().cloned();
    // (spring, zeta label, K, c) for every lumped run.
    let mut variants_run: Vec<(String, &'static str, f64, f64)> = reference
        .iter()
        .map(|r| {
            (
                REFERENCE_HEAD.into(),
                "mid",
                r.stiffness_n_m,
                r.damping_n_s_m,
            )
        })
        .collect();
    for s in &stages.stages {
        for level in ZetaLevel::ALL {
            variants_run.push((
                s.name.clone(),
                level.name(),
                s.stiffness_n_m,
                s.damping_n_s_m(level),
            ));
        }
    }
    let jobs: Vec<(bool, usize, f64)> = (0..variants_run.len())
        .map(|i| (false, i))
        .chain((0..reduced_stages.len()).map(|i| (true, i)))
        .flat_map(|(r, i)| case.speeds_km_h.iter().map(move |&v| (r, i, v)))
        .collect();
    let runs: Vec<(bool, SpringStudyRow)> = jobs
        .par_iter()
        .map(|&(is_reduced, i, speed)| {
            let mut case = case.clone();
            let (name, zeta) = if is_reduced {
                case.pantograph = with_reduced_head(&case.pantograph, &reduced_stages[i]);
                (stages.stages[i].name.clone(), "mid")
            } else {
                let (name, zeta, k, c) = &variants_run[i];
                if let Some(head) = case.pantograph.stages.first_mut() {
                    head.stiffness_n_m = *k;
                    head.damping_n_s_m = *c;
                }
                (name.clone(), *zeta)
            };
            let (_, run) = run_speed(&case, speed)?;
            Ok((
                is_reduced,
                SpringStudyRow {
                    spring: name,
                    zeta: zeta.into(),
                    statistics: run.statistics,
                },
            ))
        })
        .collect::<Result<_>>()?;
    let (reduced, rows): (Vec<_>, Vec<_>) = runs.into_iter().partition(|(r, _)| *r);
    Ok(BandStudy {
        reduced_modes: reduced_stages.iter().map(|s| s.modes_hz.len()).collect(),
        stages,
        rows: rows.into_iter().map(|(_, row)| row).collect(),
        reduced: reduced.into_iter().map(|(_, row)| row).collect(),
    })
}

impl BandStudy {
    /// The lumped run of `spring` at `zeta` and `speed_km_h`.
    pub fn lumped(&self, spring: &str, zeta: &str, speed_km_h: f64) -> Option<&Statistics> {
        find(&self.rows, spring, zeta, speed_km_h)
    }

    /// The reduced run of `spring` at `speed_km_h`.
    pub fn reduced(&self, spring: &str, speed_km_h: f64) -> Option<&Statistics> {
        find(&self.reduced, spring, "mid", speed_km_h)
    }

    /// Every run's statistics, one markdown row each.
    pub fn runs_markdown(&self) -> String {
        let mut s = String::from(
            "| spring | zeta | speed (km/h) | mean (N) | std (N) | min (N) | max (N) | uplift (mm) | loss (%) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        for r in &self.rows {
            let t = &r.statistics;
            let _ = writeln!(
                s,
                "| {} | {} | {:.0} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} |",
                r.spring,
                r.zeta,
                t.speed_km_h,
                t.mean_n,
                t.std_n,
                t.min_n,
                t.max_n,
                t.uplift_support_mm,
                t.loss_percent
            );
        }
        s
    }

    /// The reduced stage beside the lumped one (mid zeta) per spring and speed: sigma, the
    /// actual minimum and the loss of contact, and reduced less lumped.
    pub fn reduced_markdown(&self) -> String {
        let mut s = String::from(
            "| spring | speed (km/h) | std lumped / reduced (N) | d std (N) | min lumped / reduced (N) | d min (N) | loss lumped / reduced (%) | d loss (%) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        let picks: [fn(&Statistics) -> f64; 3] = [|t| t.std_n, |t| t.min_n, |t| t.loss_percent];
        for r in &self.reduced {
            let speed = r.statistics.speed_km_h;
            let Some(l) = self.lumped(&r.spring, "mid", speed) else {
                continue;
            };
            let _ = write!(s, "| {} | {speed:.0} |", r.spring);
            for pick in picks {
                let (a, b) = (pick(l), pick(&r.statistics));
                let _ = write!(s, " {a:.2} / {b:.2} | {:+.2} |", b - a);
            }
            s.push('\n');
        }
        s
    }
}

fn find<'a>(
    rows: &'a [SpringStudyRow],
    spring: &str,
    zeta: &str,
    speed_km_h: f64,
) -> Option<&'a Statistics> {
    rows.iter()
        .find(|r| r.spring == spring && r.zeta == zeta && r.statistics.speed_km_h == speed_km_h)
        .map(|r| &r.statistics)
}
