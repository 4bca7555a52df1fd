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
    /// How many springs the FE model verified (short list, rejected, corrected).
    pub fe_runs: usize,
    /// Feasible springs passed over because their FE model would have more than
    /// [`sheet::fe::MAX_BEAMS`] beams.
    pub fe_skipped: usize,
    /// How many failed each check.
    pub rejections: Vec<(String, usize)>,
    /// The FE-verified short list, best first.
    pub candidates: Vec<Verified>,
    /// Short-listed springs the FE model rejected.
    pub rejected: Vec<Verified>,
    /// What geometry can buy of the target zeta (with a target zeta and a damping law).
    pub damping: Option<DampingVerdict>,
    /// (mass kg, handbook rate N/mm) of the feasible springs for the figure: all of them,
    /// or every k-th when there are more than [`MAX_FIGURE_POINTS`].
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
    /// Replaces the target's short-list length (1 to [`target::MAX_SHORT_LIST`]).
    pub short_list: Option<usize>,
    /// The starting beams per coil of a grade's converged FE check; with a calibration,
    /// refused (its E belongs to its mesh).
    pub elements_per_coil: Option<u32>,
}

/// The most springs the FE verification runs in one design (the short list, the
/// springs rejected on the way down the ranking and their FE-corrected versions).
pub const MAX_VERIFIED: usize = 64;

/// The most feasible springs design.png draws (every k-th of a larger set).
pub const MAX_FIGURE_POINTS: usize = 20_000;

/// The most short-listed springs of one wire diameter.
pub const PER_WIRE: usize = 2;

/// Applies the command line's overrides to `target`, refusing values the file would
/// refuse.
fn overridden(target: &Target, settings: &DesignSettings) -> Result<Target> {
    let mut target = target.clone();
    if let Some(o) = settings.objective {
        target.objective = o;
    }
    if let Some(n) = settings.short_list {
        if n == 0 || n as f64 > target::MAX_SHORT_LIST {
            return Err(TuneError::Invalid(format!(
                "--short-list {n}: how many candidates the FE verifies, a whole number from 1 to {}",
                target::MAX_SHORT_LIST
            )));
        }
        target.short_list = n;
    }
    Ok(target)
}

/// The material with the command line's mesh.
fn material_with_mesh(target: &Target, settings: &DesignSettings) -> Result<Material> {
    let mut material = target::material(target)?;
    if let Some(m) = settings.elements_per_coil {
        if material.damping.is_some() {
            return Err(TuneError::Invalid(format!(
                "--elements-per-coil {m}: the calibration's E belongs to its own mesh ({} beams per coil); leave the flag out with a calibration",
                material.fe.elements_per_coil
            )));
        }
        if !(4..=512).contains(&m) {
            return Err(TuneError::Invalid(format!(
                "--elements-per-coil {m}: the starting beams per coil, from 4 to 512"
            )));
        }
        material.fe.elements_per_coil = m;
    }
    Ok(material)
}

/// The FE-corrected version of a spring the FE model put outside the rate tolerance:
/// the active coils scaled by `K_FE / K_target` (K ~ 1/n) to the nearest quarter turn,
/// when that is another spring that passes every handbook check.
fn corrected(
    target: &Target,
    material: &Material,
    v: &Verified,
) -> Option<(search::Candidate, String)> {
    let rate = target.rate_n_mm / f64::from(target.springs_in_parallel);
    let n = v.active_coils * v.fe_rate_n_mm / rate;
    let n = (n / search::COIL_STEP).round() * search::COIL_STEP;
    if (n - v.active_coils).abs() < 1e-9 || n < 2.0 {
        return None;
    }
    let wire = (v.wire_diameter_mm, v.sheet.tensile_strength_mpa);
    let (c, failed) = search::candidate(target, material, wire, v.mean_diameter_mm, n);
    // The handbook rate of the corrected spring is off by the FE offset on purpose.
    let failed: Vec<_> = failed.into_iter().filter(|f| *f != "rate").collect();
    failed.is_empty().then(|| {
        (
            c,
            format!(
                "n {} -> {n} (FE rate {:.4} N/mm against {rate:.4})",
                v.active_coils, v.fe_rate_n_mm
            ),
        )
    })
}

/// The next batch of at most `want` springs down the ranking: the best untried ones
/// whose wire diameter has fewer than [`PER_WIRE`] springs accepted or in the batch. A
/// spring passed over because its wire was full with springs still being verified is
/// taken up again once one of those is rejected; `first` is the first untried index.
#[allow(clippy::too_many_arguments)]
fn next_batch(
    feasible: &[search::Feasible],
    target: &Target,
    material: &Material,
    tried: &mut [bool],
    first: &mut usize,
    per_wire: &BTreeMap<u64, usize>,
    seen: &mut std::collections::BTreeSet<Geometry>,
    skipped: &mut usize,
    want: usize,
) -> Vec<(usize, search::Candidate, Option<String>)> {
    while *first < feasible.len() && tried[*first] {
        *first += 1;
    }
    let mut batch = Vec::new();
    let mut pending: BTreeMap<u64, usize> = BTreeMap::new();
    for i in *first..feasible.len() {
        if batch.len() == want {
            break;
        }
        if tried[i] {
            continue;
        }
        let f = &feasible[i];
        if f.active_coils * f64::from(material.fe.elements_per_coil) > sheet::fe::MAX_BEAMS {
            // Its FE model is above the limit (docs/files.md): counted, not run.
            tried[i] = true;
            *skipped += 1;
            continue;
        }
        let spring = (f.wire_diameter_mm, f.mean_diameter_mm, f.active_coils);
        if seen.contains(&geometry(spring)) {
            // Already verified as another spring's FE correction.
            tried[i] = true;
            continue;
        }
        let k = wire_key(f.wire_diameter_mm);
        if per_wire.get(&k).copied().unwrap_or(0) + pending.get(&k).copied().unwrap_or(0) < PER_WIRE
        {
            *pending.entry(k).or_default() += 1;
            tried[i] = true;
            seen.insert(geometry(spring));
            batch.push((i + 1, f.candidate(target, material), None));
        }
    }
    batch
}

/// A spring's wire, mean diameter and active coils (micrometres, quarter turns): the same
/// spring reached twice (down the ranking and as a correction) is verified once.
type Geometry = (u64, u64, u64);

fn geometry((d, mean, n): (f64, f64, f64)) -> Geometry {
    (wire_key(d), wire_key(mean), (n * 4.0).round() as u64)
}

/// The key of a wire diameter in the per-wire counts (micrometres).
fn wire_key(d: f64) -> u64 {
    (d * 1000.0).round() as u64
}

/// Verifies down the ranking (module docs of [`verify`]): batches of the best springs
/// not yet tried, at most [`PER_WIRE`] per wire diameter, until the short list is full,
/// the feasible set is exhausted or [`MAX_VERIFIED`] springs ran; a spring off the rate
/// by FE is retried once with its coils corrected by the FE rate.
fn verify_down(
    feasible: &[search::Feasible],
    target: &Target,
    material: &Material,
    weight_kg: Option<f64>,
    band: Option<&band::LawBand>,
) -> Result<(Vec<Verified>, Vec<Verified>, usize, usize)> {
    let mut accepted: Vec<Verified> = Vec::new();
    let mut rejected: Vec<Verified> = Vec::new();
    let mut per_wire: BTreeMap<u64, usize> = BTreeMap::new();
    let mut tried = vec![false; feasible.len()];
    let mut seen = std::collections::BTreeSet::new();
    let mut skipped = 0usize;
    let mut first = 0usize;
    let mut ran = 0usize;
    while accepted.len() < target.short_list && ran < MAX_VERIFIED {
        let want = (target.short_list - accepted.len()).min(MAX_VERIFIED - ran);
        let batch = next_batch(
            feasible,
            target,
            material,
            &mut tried,
            &mut first,
            &per_wire,
            &mut seen,
            &mut skipped,
            want,
        );
        if batch.is_empty() {
            break;
        }
        ran += batch.len();
        let mut retry = Vec::new();
        for v in verify::verify(&batch, target, material, weight_kg, band)? {
            if v.fe_verified {
                *per_wire.entry(wire_key(v.wire_diameter_mm)).or_default() += 1;
                accepted.push(v);
            } else {
                if v.corrected_from.is_none() {
                    if let Some((c, why)) = corrected(target, material, &v) {
                        let s = &c.spring;
                        let small = s.active_coils * f64::from(material.fe.elements_per_coil)
                            <= sheet::fe::MAX_BEAMS;
                        if small
                            && seen.insert(geometry((
                                s.wire_diameter_mm,
                                s.mean_diameter_mm,
                                s.active_coils,
                            )))
                        {
                            retry.push((v.search_rank, c, Some(why)));
                        }
                    }
                }
                rejected.push(v);
            }
        }
        if !retry.is_empty() && ran < MAX_VERIFIED {
            retry.truncate(MAX_VERIFIED - ran);
            ran += retry.len();
            for v in verify::verify(&retry, target, material, weight_kg, band)? {
                let k = wire_key(v.wire_diameter_mm);
                if v.fe_verified && per_wire.get(&k).copied().unwrap_or(0) < PER_WIRE {
                    *per_wire.entry(k).or_default() += 1;
                    accepted.push(v);
                } else {
                    rejected.push(v);
                }
            }
        }
    }
    let rate = target.rate_n_mm / f64::from(target.springs_in_parallel);
    let order = |v: &Verified| match target.objective {
        Objective::Lightest => v.spring_mass_kg,
        Objective::StressMargin => -v.stress_margin,
    };
    accepted.sort_by(|a, b| {
        order(a).total_cmp(&order(b)).then(
            (a.fe_rate_n_mm / rate - 1.0)
                .abs()
                .total_cmp(&(b.fe_rate_n_mm / rate - 1.0).abs()),
        )
    });
    accepted.truncate(target.short_list);
    for (i, v) in accepted.iter_mut().enumerate() {
        v.rank = i + 1;
        v.deck = verify::deck_name(i + 1, true);
    }
    for (i, v) in rejected.iter_mut().enumerate() {
        v.deck = verify::deck_name(i + 1, false);
    }
    Ok((accepted, rejected, ran, skipped))
}

/// Runs a design (module docs).
pub fn design(target: &Target, settings: &DesignSettings) -> Result<Design> {
    let clock = std::time::Instant::now();
    let target = overridden(target, settings)?;
    let material = material_with_mesh(&target, settings)?;
    let found = search::search(&target, &material).map_err(TuneError::Invalid)?;
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
    let (candidates, rejected, fe_runs, fe_skipped) = verify_down(
        &found.feasible,
        &target,
        &material,
        weight_kg,
        band.as_ref(),
    )?;
    let damping = target
        .damping_ratio
        .and_then(|z| verdict(z, &candidates, &target));
    Ok(Design {
        feasible: found.feasible.len(),
        feasible_points: found
            .feasible
            .iter()
            .step_by(found.feasible.len().div_ceil(MAX_FIGURE_POINTS).max(1))
            .map(|c| (c.spring_mass_kg, c.rate_n_mm))
            .collect(),
        tried: found.tried,
        fe_runs,
        fe_skipped,
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
            "zeta = {} lies within the verified candidates' range under {}: the geometry can deliver it if that law holds",
            output::sig(target_zeta, 4),
            laws.iter()
                .filter(|l| l.reachable)
                .map(|l| l.law.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )
    } else {
        format!(
            "zeta = {} at K = {} N/mm cannot be met by the wire alone: at this rate and weight a stiffness-proportional law puts zeta on the sqrt(K) curve, a dashpot at the weight on 1/sqrt(K), a loss factor leaves it where it is, so every candidate lands at {:.5} to {:.5} (closest: {}, the target {:+.1} % from it); a damper or another material would have to supply the difference",
            output::sig(target_zeta, 4),
            output::sig(target.rate_n_mm, 6),
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
