//! The handbook search of a design: every standard wire diameter, mean diameters on a
//! 0.1 mm grid, active coils in quarter turns, and for each the pitch; kept when every
//! check of the EN 13906-1 sheet and of the envelope passes; ranked by the objective.
//!
//! # Search
//! For a wire d (EN 10270-1 sizes where the grade's Rm is tabulated) the mean diameter
//! runs over `max(4 d, Di_min + d) <= D <= min(20 d, De_max - d)` (cold coiled index
//! range 4-20; hot 3-12). The rate fixes the coils: `n* = G d^4 / (8 D^3 R)`, and every
//! quarter turn with `G d^4 / (8 D^3 n)` within the rate tolerance is a candidate (at
//! least 2 active coils; one inactive coil at each closed end, `nt = n + 2`; `nt = n`
//! for open ends). The pitch is searched on a 0.05 mm grid: with working forces, the
//! shortest free length that keeps `L2 >= Ln = Lc + Sa` is `L0 = Lc + Sa + F2 / R`;
//! every other check either does not depend on the pitch (rate, stresses at F1 and F2)
//! or gets worse with a longer spring (solid stress, buckling, free length), so the
//! smallest pitch on the grid at or above that length is the spring's best, and the
//! only one kept. With working lengths the free length is the shortest on the grid not
//! below L1 (the spring just touches at L1).
//!
//! # Ranking
//! `lightest`: wire mass ascending; `stress_margin` descending: `1 - tau2 / (0.5 Rm)`
//! static, `1 - tau_kh / tau_kH` dynamic (the fatigue check's margin). Only springs that
//! pass every check (fatigue included under dynamic loading) are ranked. Ties go to the
//! rate closest to the target.
//!
//! # Work
//! The active coils stop at EN 15800's longest free length (630 mm: `n <= 630 / d - 2`).
//! The springs to check are counted before the search starts (a sum over the grid, no
//! sheet evaluated) and a search over [`MAX_TRIED`] is refused with the count.

use super::target::{Material, Objective, Target};
use crate::sheet::en13906::{
    rate_n_mm, Coiling, EndType, Loading, Sheet, Spring, StressCorrection, Working,
};
use crate::sheet::grades::{tensile_strength_mpa, STANDARD_WIRE_DIAMETERS_MM};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// Step of the mean-diameter grid (mm).
pub const DIAMETER_STEP_MM: f64 = 0.1;
/// Step of the pitch grid (mm).
pub const PITCH_STEP_MM: f64 = 0.05;
/// Step of the active coils.
pub const COIL_STEP: f64 = 0.25;
/// The most springs a search checks (about 1.4 s of CPU; counted before it starts).
pub const MAX_TRIED: usize = 2_000_000;
/// EN 15800's longest free length (mm): the active coils stop below it.
pub const MAX_FREE_LENGTH_MM: f64 = 630.0;

/// A spring that passes every handbook check, with its sheet.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    /// The spring (one of the parallel springs).
    pub spring: Spring,
    /// Its sheet.
    pub sheet: Sheet,
    /// Static: `1 - tau2 / (0.5 Rm)`; dynamic: `1 - tau_kh / tau_kH`.
    pub stress_margin: f64,
}

impl Candidate {
    /// The pitch of the free spring (mm).
    pub fn pitch_mm(&self) -> f64 {
        self.sheet.pitch_mm
    }
}

/// The envelope checks of `sheet` (name, passed, detail).
fn envelope_checks(target: &Target, sheet: &Sheet, spring: &Spring) -> Vec<(&'static str, bool)> {
    let e = &target.envelope;
    let band_clear = target
        .surge_band_hz
        .is_none_or(|(lo, hi)| !(lo..=hi).contains(&sheet.surge_frequency_hz));
    vec![
        (
            "max_outer_diameter",
            e.max_outer_diameter_mm
                .is_none_or(|m| sheet.outer_diameter_mm <= m + 1e-9),
        ),
        (
            "min_inner_diameter",
            e.min_inner_diameter_mm
                .is_none_or(|m| sheet.inner_diameter_mm >= m - 1e-9),
        ),
        (
            "max_free_length",
            e.max_free_length_mm
                .is_none_or(|m| spring.free_length_mm <= m + 1e-9),
        ),
        (
            "max_solid_length",
            e.max_solid_length_mm
                .is_none_or(|m| sheet.solid_length_mm <= m + 1e-9),
        ),
        ("surge_band", band_clear),
    ]
}

/// Grid values `lo <= k step <= hi`, each the double nearest `k step` (`k / (1 / step)`
/// for the grids' steps 0.1, 0.05 and 0.25: 24.7, not 24.700000000000003).
fn grid(lo: f64, hi: f64, step: f64) -> impl Iterator<Item = f64> {
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let per_unit = (1.0 / step).round();
    (first..=last).map(move |k| k as f64 / per_unit)
}

/// What the search looked at: every candidate that passes, and how many were tried.
#[derive(Debug, Clone, Serialize)]
pub struct Search {
    /// The feasible springs, best first.
    pub feasible: Vec<Feasible>,
    /// Springs within the rate tolerance that were checked.
    pub tried: usize,
    /// How many failed each check (check name, count).
    pub rejections: Vec<(String, usize)>,
}

/// The search's grid for one target: the rate of one spring, its working points and
/// the wires, diameters and coils to try.
struct Grid<'a> {
    target: &'a Target,
    material: &'a Material,
    rate: f64,
    tolerance: f64,
    working: Working,
    index: (f64, f64),
    inactive: f64,
}

impl<'a> Grid<'a> {
    fn new(target: &'a Target, material: &'a Material) -> Self {
        let springs = f64::from(target.springs_in_parallel);
        Grid {
            target,
            material,
            rate: target.rate_n_mm / springs,
            tolerance: target.rate_tolerance_percent / 100.0,
            working: match target.working {
                Working::Forces(a, b) => Working::Forces(a / springs, b / springs),
                lengths => lengths,
            },
            index: match target.coiling {
                Coiling::Cold => (4.0, 20.0),
                Coiling::Hot => (3.0, 12.0),
            },
            inactive: match target.end_type {
                EndType::Open => 0.0,
                _ => 2.0,
            },
        }
    }

    /// The wires with their Rm.
    fn wires(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        STANDARD_WIRE_DIAMETERS_MM.iter().filter_map(|&d| {
            tensile_strength_mpa(&self.material.grade, d)
                .ok()
                .map(|rm| (d, rm))
        })
    }

    /// The mean diameters of wire d.
    fn means(&self, d: f64) -> impl Iterator<Item = f64> {
        let e = &self.target.envelope;
        let lo = (self.index.0 * d).max(e.min_inner_diameter_mm.map_or(0.0, |m| m + d));
        let hi = (self.index.1 * d).min(e.max_outer_diameter_mm.map_or(f64::INFINITY, |m| m - d));
        grid(lo, hi, DIAMETER_STEP_MM)
    }

    /// The active coils' range of (d, D): the rate within the tolerance, at least 2,
    /// at most what 630 mm of free length holds.
    fn coils(&self, d: f64, mean: f64) -> (f64, f64) {
        let n_star = self.material.shear_modulus_mpa * d.powi(4) / (8.0 * mean.powi(3) * self.rate);
        let n_lo = (n_star / (1.0 + self.tolerance)).max(2.0);
        let n_hi = (n_star / (1.0 - self.tolerance)).min(MAX_FREE_LENGTH_MM / d - self.inactive);
        (n_lo, n_hi)
    }

    /// How many springs the search would check (no sheet evaluated).
    fn count(&self) -> usize {
        let mut count = 0usize;
        for (d, _) in self.wires() {
            for mean in self.means(d) {
                let (lo, hi) = self.coils(d, mean);
                let first = (lo / COIL_STEP - 1e-9).ceil();
                let last = (hi / COIL_STEP + 1e-9).floor();
                if last >= first {
                    count = count.saturating_add((last - first) as usize + 1);
                }
            }
        }
        count
    }
}

/// The spring of wire d (Rm `rm`), mean diameter D and n active coils of the target at
/// its shortest free length on the pitch grid (module docs), with its sheet and the
/// names of the checks it fails (handbook, envelope, rate).
pub fn candidate(
    target: &Target,
    material: &Material,
    wire: (f64, f64),
    mean: f64,
    n: f64,
) -> (Candidate, Vec<&'static str>) {
    candidate_with(target, material, wire, mean, n, true)
}

/// [`candidate`]; without `details` the sheet's words are left out (the search).
fn candidate_with(
    target: &Target,
    material: &Material,
    (d, rm): (f64, f64),
    mean: f64,
    n: f64,
    details: bool,
) -> (Candidate, Vec<&'static str>) {
    let grid = Grid::new(target, material);
    let g = material.shear_modulus_mpa;
    let mut spring = Spring {
        wire_diameter_mm: d,
        wire_tolerance_mm: 0.0,
        mean_diameter_mm: mean,
        active_coils: n,
        total_coils: n + grid.inactive,
        free_length_mm: 0.0,
        end_type: target.end_type,
        coiling: target.coiling,
        shear_modulus_mpa: g,
        youngs_modulus_mpa: material.youngs_modulus_mpa,
        density_kg_m3: material.density_kg_m3,
        tensile_strength_mpa: rm,
        seating_coefficient: target.seating_coefficient,
        working: grid.working,
        loading: target.loading,
        stress_correction: StressCorrection::Bergstraesser,
        measured_rate_n_mm: None,
        wire_grade: Some(material.grade.clone()),
        shot_peened: target.shot_peened,
        quality_grade: target.quality_grade,
        head_mass_kg: None,
    };
    let r = rate_n_mm(g, d, mean, n);
    let shortest = match grid.working {
        Working::Forces(_, f2) => spring.solid_length_mm() + spring.minimum_gap_sum_mm() + f2 / r,
        Working::Lengths(l1, _) => l1,
    };
    let allowance = spring.end_allowance_mm();
    let pitch =
        ((shortest - allowance) / n / PITCH_STEP_MM - 1e-9).ceil() / (1.0 / PITCH_STEP_MM).round();
    spring.free_length_mm = allowance + n * pitch.max(d + PITCH_STEP_MM);
    let sheet = spring.sheet_with(details);
    let mut failed: Vec<&'static str> = sheet.failed();
    failed.extend(
        envelope_checks(target, &sheet, &spring)
            .into_iter()
            .filter(|c| !c.1)
            .map(|c| c.0),
    );
    if (sheet.rate_n_mm / grid.rate - 1.0).abs() > grid.tolerance {
        failed.push("rate");
    }
    let stress_margin = match target.loading {
        Loading::Static => 1.0 - sheet.shear_stress_2_mpa / sheet.permissible_working_stress_mpa,
        Loading::Dynamic => 1.0 - sheet.fatigue.utilisation,
    };
    (
        Candidate {
            stress_margin,
            spring,
            sheet,
        },
        failed,
    )
}

/// A feasible spring as the search keeps it: its wire, mean diameter and coils and the
/// numbers it is ranked and drawn by (56 bytes; the sheet is rebuilt, by [`candidate`],
/// for the springs the FE verification runs), so the search's memory is bounded by its
/// count, not by the sheets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Feasible {
    /// d (mm).
    pub wire_diameter_mm: f64,
    /// Rm of the wire (MPa).
    pub tensile_strength_mpa: f64,
    /// D (mm).
    pub mean_diameter_mm: f64,
    /// n.
    pub active_coils: f64,
    /// Wire mass (kg).
    pub spring_mass_kg: f64,
    /// Handbook rate (N/mm).
    pub rate_n_mm: f64,
    /// The ranking's stress margin.
    pub stress_margin: f64,
}

impl Feasible {
    /// The spring with its sheet, as the search built it.
    pub fn candidate(&self, target: &Target, material: &Material) -> Candidate {
        let wire = (self.wire_diameter_mm, self.tensile_strength_mpa);
        candidate(
            target,
            material,
            wire,
            self.mean_diameter_mm,
            self.active_coils,
        )
        .0
    }
}

/// The springs of one wire: the feasible ones, how many were tried, the failed checks.
fn search_wire(
    grid: &Grid<'_>,
    wire: (f64, f64),
) -> (Vec<Feasible>, usize, BTreeMap<&'static str, usize>) {
    let mut feasible = Vec::new();
    let mut tried = 0usize;
    let mut rejections = BTreeMap::new();
    for mean in grid.means(wire.0) {
        let (n_lo, n_hi) = grid.coils(wire.0, mean);
        for n in self::grid(n_lo, n_hi, COIL_STEP) {
            tried += 1;
            let (c, failed) = candidate_with(grid.target, grid.material, wire, mean, n, false);
            for name in &failed {
                *rejections.entry(*name).or_default() += 1;
            }
            if failed.is_empty() {
                feasible.push(Feasible {
                    wire_diameter_mm: wire.0,
                    tensile_strength_mpa: wire.1,
                    mean_diameter_mm: mean,
                    active_coils: n,
                    spring_mass_kg: c.sheet.spring_mass_kg,
                    rate_n_mm: c.sheet.rate_n_mm,
                    stress_margin: c.stress_margin,
                });
            }
        }
    }
    (feasible, tried, rejections)
}

/// Searches the geometry (module docs), the wires in parallel (rayon); refuses a search
/// of more than [`MAX_TRIED`] springs before it starts.
pub fn search(target: &Target, material: &Material) -> Result<Search, String> {
    let grid = Grid::new(target, material);
    let count = grid.count();
    if count > MAX_TRIED {
        return Err(format!(
            "the search would check {count} springs (rate {:.4} N/mm per spring within {} %, every standard wire and mean diameter the envelope admits, up to {MAX_FREE_LENGTH_MM} mm of free length); the limit is {MAX_TRIED}: narrow the envelope (max_outer_diameter_mm, min_inner_diameter_mm) or the rate tolerance (rate_tolerance_percent)",
            grid.rate, target.rate_tolerance_percent
        ));
    }
    let wires: Vec<(f64, f64)> = grid.wires().collect();
    let per_wire: Vec<_> = wires.par_iter().map(|&w| search_wire(&grid, w)).collect();
    let mut feasible = Vec::new();
    let mut tried = 0usize;
    let mut rejections: BTreeMap<String, usize> = BTreeMap::new();
    for (f, t, r) in per_wire {
        feasible.extend(f);
        tried += t;
        for (name, k) in r {
            *rejections.entry(name.to_string()).or_default() += k;
        }
    }
    rank(&mut feasible, target.objective, grid.rate);
    Ok(Search {
        feasible,
        tried,
        rejections: rejections.into_iter().collect(),
    })
}

/// Sorts best first (module docs).
pub fn rank(candidates: &mut [Feasible], objective: Objective, rate: f64) {
    let key = |c: &Feasible| match objective {
        Objective::Lightest => c.spring_mass_kg,
        Objective::StressMargin => -c.stress_margin,
    };
    let miss = |c: &Feasible| (c.rate_n_mm / rate - 1.0).abs();
    candidates.sort_by(|a, b| key(a).total_cmp(&key(b)).then(miss(a).total_cmp(&miss(b))));
}
