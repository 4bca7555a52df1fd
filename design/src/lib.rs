//! coil-design: which spring? The EN 13906-1 sheet of a helical compression spring and
//! design to a target (docs/spring-design.md). It owns the standards' tables, the sheet,
//! the search, the FE verification and the design's files; it imports the tuner's FE
//! model, case fields and damping band (`coil_tuner`), nothing imports it but the CLI
//! and Python.
//!
//! - [`sheet`]: `coil-tune check SPRING.json`, the sheet beside coil's FE values;
//! - [`target`]: the target and its material (a grade, or a calibration with its E,
//!   mesh and damping);
//! - [`search`]: the handbook search over standard wires, mean diameters, quarter
//!   turns and the pitch, every EN 13906-1 check and the envelope, ranked;
//! - [`verify`]: the short list through the FE model (rate within the tolerance,
//!   surge mode clear of a band), in parallel;
//! - [`band`]: each candidate's zeta under every damping law calibrated to the same
//!   decay, and what the geometry can and cannot buy;
//! - [`output`]: `design.json`, `report.md` and the short list's decks; [`plot`]:
//!   `design.png`;
//! - [`cli`]: the `check` and `design` commands of `coil-tune`.

#![warn(missing_docs)]

// The tuner's modules the spring design builds on, under the names the modules here use.
pub(crate) use coil_tuner::{case, error, fe, fields};

pub mod band;
pub mod cli;
pub mod output;
pub mod plot;
pub mod search;
pub mod sheet;
pub mod target;
pub mod verify;

pub use coil_tuner::error::{Result, TuneError};

use serde::Serialize;
use std::collections::BTreeMap;
use target::{Material, Objective, Target};
use verify::Verified;

/// One law's verdict on a target zeta.
#[derive(Debug, Clone, Serialize)]
pub struct LawVerdict {
    /// The law.
    pub law: String,
    /// zeta of the best verified candidate (-).
    pub best: f64,
    /// Smallest zeta over the verified candidates (-).
    pub min: f64,
    /// Largest (-).
    pub max: f64,
    /// True when the target lies within [min, max].
    pub reachable: bool,
    /// Target against the best candidate's zeta (%).
    pub gap_percent: f64,
}

/// What the geometry can buy of a target zeta.
#[derive(Debug, Clone, Serialize)]
pub struct DampingVerdict {
    /// The target zeta (-).
    pub target: f64,
    /// Per law.
    pub laws: Vec<LawVerdict>,
    /// True when some law puts the target within the verified candidates' range.
    pub reachable: bool,
    /// The verdict in words, with its numbers.
    pub text: String,
}

/// A finished design.
#[derive(Debug, Clone, Serialize)]
pub struct Design {
    /// The target as read (objective after any override).
    pub target: Target,
    /// The material used.
    pub material: Material,
    /// The weight of the zeta band and the decks, all springs together (kg).
    pub weight_kg: Option<f64>,
    /// Springs within the rate tolerance that the search checked.
    pub tried: usize,
    /// How many passed every handbook and envelope check.
    pub feasible: usize,
    /// How many failed each check.
    pub rejections: Vec<(String, usize)>,
    /// The FE-verified short list, best first.
    pub candidates: Vec<Verified>,
    /// Short-listed springs the FE model rejected.
    pub rejected: Vec<Verified>,
    /// What geometry can buy of the target zeta (with a target zeta and a damping law).
    pub damping: Option<DampingVerdict>,
    /// (mass kg, handbook rate N/mm) of every feasible spring, for the figure.
    #[serde(skip)]
    pub feasible_points: Vec<(f64, f64)>,
    /// Wall time (s).
    pub elapsed_s: f64,
}

/// Overrides of the target from the command line.
#[derive(Debug, Clone, Default)]
pub struct DesignSettings {
    /// Replaces the target's objective.
    pub objective: Option<Objective>,
    /// Replaces the target's short-list length.
    pub short_list: Option<usize>,
}

/// Runs a design (module docs).
pub fn design(target: &Target, settings: &DesignSettings) -> Result<Design> {
    let clock = std::time::Instant::now();
    let mut target = target.clone();
    if let Some(o) = settings.objective {
        target.objective = o;
    }
    if let Some(n) = settings.short_list {
        target.short_list = n;
    }
    let material = target::material(&target)?;
    let found = search::search(&target, &material);
    let short = &found.feasible[..found.feasible.len().min(target.short_list)];
    let weight_kg = target.weight_kg.or(material
        .damping
        .map(|d| d.state.mass_kg * f64::from(target.springs_in_parallel)));
    let band = material
        .damping
        .as_ref()
        .map(|reference| {
            band::LawBand::calibrate(reference, &material.fe, material.identified_law.as_ref())
        })
        .transpose()?;
    let (candidates, rejected): (Vec<_>, Vec<_>) =
        verify::verify(short, &target, &material, weight_kg, band.as_ref())?
            .into_iter()
            .partition(|v| v.fe_verified);
    let damping = target
        .damping_ratio
        .and_then(|z| verdict(z, &candidates, &target));
    Ok(Design {
        feasible: found.feasible.len(),
        feasible_points: found
            .feasible
            .iter()
            .map(|c| (c.sheet.spring_mass_kg, c.sheet.rate_n_mm))
            .collect(),
        tried: found.tried,
        rejections: found.rejections,
        candidates,
        rejected,
        damping,
        weight_kg,
        material,
        target,
        elapsed_s: clock.elapsed().as_secs_f64(),
    })
}

/// What the verified candidates' zeta bands say about a target zeta.
fn verdict(target_zeta: f64, candidates: &[Verified], target: &Target) -> Option<DampingVerdict> {
    let best = candidates.first()?;
    let laws: Vec<LawVerdict> = best
        .damping_ratio
        .iter()
        .map(|(law, &z)| {
            let values = candidates
                .iter()
                .filter_map(|c| c.damping_ratio.get(law).copied());
            let (min, max) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
            LawVerdict {
                law: law.clone(),
                best: z,
                min,
                max,
                reachable: (min..=max).contains(&target_zeta),
                gap_percent: 100.0 * (target_zeta / z - 1.0),
            }
        })
        .collect();
    if laws.is_empty() {
        return None;
    }
    let reachable = laws.iter().any(|l| l.reachable);
    let nearest = laws
        .iter()
        .min_by(|a, b| a.gap_percent.abs().total_cmp(&b.gap_percent.abs()))?;
    let text = if reachable {
        format!(
            "zeta = {target_zeta} lies within the verified candidates' range under {}: the geometry can deliver it if that law holds",
            laws.iter()
                .filter(|l| l.reachable)
                .map(|l| l.law.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )
    } else {
        format!(
            "zeta = {target_zeta} at K = {} N/mm cannot be met by the wire alone: at this rate and weight a stiffness-proportional law puts zeta on the sqrt(K) curve, a dashpot at the weight on 1/sqrt(K), a loss factor leaves it where it is, so every candidate lands at {:.5} to {:.5} (closest: {}, the target {:+.1} % from it); a damper or another material would have to supply the difference",
            target.rate_n_mm,
            laws.iter().map(|l| l.min).fold(f64::INFINITY, f64::min),
            laws.iter().map(|l| l.max).fold(f64::NEG_INFINITY, f64::max),
            nearest.law,
            nearest.gap_percent
        )
    };
    Some(DampingVerdict {
        target: target_zeta,
        laws,
        reachable,
        text,
    })
}

/// The zeta of each law as one line (`law = value, ...`).
pub fn zeta_line(zeta: &BTreeMap<String, f64>) -> String {
    zeta.iter()
        .map(|(k, v)| format!("{k} {v:.5}"))
        .collect::<Vec<_>>()
        .join(", ")
}
