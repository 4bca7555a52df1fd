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
//! `lightest`: wire mass ascending; `stress_margin`: `1 - tau / (0.5 Rm)` descending
//! (`tau2` static, `tau_k2` dynamic). Ties go to the rate closest to the target.

use super::target::{Material, Objective, Target};
use crate::sheet::en13906::{Coiling, EndType, Sheet, Spring, Working};
use crate::sheet::grades::{tensile_strength_mpa, STANDARD_WIRE_DIAMETERS_MM};
use serde::Serialize;

/// Step of the mean-diameter grid (mm).
pub const DIAMETER_STEP_MM: f64 = 0.1;
/// Step of the pitch grid (mm).
pub const PITCH_STEP_MM: f64 = 0.05;
/// Step of the active coils.
pub const COIL_STEP: f64 = 0.25;

/// A spring that passes every handbook check, with its sheet.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    /// The spring (one of the parallel springs).
    pub spring: Spring,
    /// Its sheet.
    pub sheet: Sheet,
    /// `1 - tau / (0.5 Rm)` at the second working point.
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

/// Grid values `lo <= k step <= hi`.
fn grid(lo: f64, hi: f64, step: f64) -> impl Iterator<Item = f64> {
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(move |k| k as f64 * step)
}

/// What the search looked at: every candidate that passes, and how many were tried.
#[derive(Debug, Clone, Serialize)]
pub struct Search {
    /// The feasible springs, best first.
    pub feasible: Vec<Candidate>,
    /// Springs within the rate tolerance that were checked.
    pub tried: usize,
    /// How many failed each check (check name, count).
    pub rejections: Vec<(String, usize)>,
}

/// Searches the geometry (module docs).
pub fn search(target: &Target, material: &Material) -> Search {
    let springs = f64::from(target.springs_in_parallel);
    let rate = target.rate_n_mm / springs;
    let tolerance = target.rate_tolerance_percent / 100.0;
    let working = match target.working {
        Working::Forces(a, b) => Working::Forces(a / springs, b / springs),
        lengths => lengths,
    };
    let g = material.shear_modulus_mpa;
    let (w_lo, w_hi) = match target.coiling {
        Coiling::Cold => (4.0, 20.0),
        Coiling::Hot => (3.0, 12.0),
    };
    let inactive = match target.end_type {
        EndType::Open => 0.0,
        _ => 2.0,
    };
    let mut feasible = Vec::new();
    let mut tried = 0usize;
    let mut rejections: std::collections::BTreeMap<String, usize> = Default::default();
    for &d in &STANDARD_WIRE_DIAMETERS_MM {
        let Ok(rm) = tensile_strength_mpa(&material.grade, d) else {
            continue;
        };
        let lo = (w_lo * d).max(target.envelope.min_inner_diameter_mm.map_or(0.0, |m| m + d));
        let hi = (w_hi * d).min(
            target
                .envelope
                .max_outer_diameter_mm
                .map_or(f64::INFINITY, |m| m - d),
        );
        for mean in grid(lo, hi, DIAMETER_STEP_MM) {
            let n_star = g * d.powi(4) / (8.0 * mean.powi(3) * rate);
            let n_lo = (n_star / (1.0 + tolerance)).max(2.0);
            let n_hi = n_star / (1.0 - tolerance);
            for n in grid(n_lo, n_hi, COIL_STEP) {
                tried += 1;
                let mut spring = Spring {
                    wire_diameter_mm: d,
                    wire_tolerance_mm: 0.0,
                    mean_diameter_mm: mean,
                    active_coils: n,
                    total_coils: n + inactive,
                    free_length_mm: 0.0,
                    end_type: target.end_type,
                    coiling: target.coiling,
                    shear_modulus_mpa: g,
                    youngs_modulus_mpa: material.youngs_modulus_mpa,
                    density_kg_m3: material.density_kg_m3,
                    tensile_strength_mpa: rm,
                    seating_coefficient: target.seating_coefficient,
                    working,
                    loading: target.loading,
                    stress_correction: crate::sheet::en13906::StressCorrection::Bergstraesser,
                    measured_rate_n_mm: None,
                };
                let r = crate::sheet::en13906::rate_n_mm(g, d, mean, n);
                let shortest = match working {
                    Working::Forces(_, f2) => {
                        spring.solid_length_mm() + spring.minimum_gap_sum_mm() + f2 / r
                    }
                    Working::Lengths(l1, _) => l1,
                };
                let allowance = spring.end_allowance_mm();
                let pitch =
                    ((shortest - allowance) / n / PITCH_STEP_MM - 1e-9).ceil() * PITCH_STEP_MM;
                spring.free_length_mm = allowance + n * pitch.max(d + PITCH_STEP_MM);
                let sheet = spring.sheet();
                let mut failed: Vec<&str> = sheet.failed();
                failed.extend(
                    envelope_checks(target, &sheet, &spring)
                        .into_iter()
                        .filter(|c| !c.1)
                        .map(|c| c.0),
                );
                if (sheet.rate_n_mm / rate - 1.0).abs() > tolerance {
                    failed.push("rate");
                }
                for name in &failed {
                    *rejections.entry(name.to_string()).or_default() += 1;
                }
                if failed.is_empty() {
                    let stress = match target.loading {
                        crate::sheet::en13906::Loading::Static => sheet.shear_stress_2_mpa,
                        crate::sheet::en13906::Loading::Dynamic => {
                            sheet.corrected_shear_stress_2_mpa
                        }
                    };
                    feasible.push(Candidate {
                        stress_margin: 1.0 - stress / sheet.permissible_working_stress_mpa,
                        spring,
                        sheet,
                    });
                }
            }
        }
    }
    rank(&mut feasible, target.objective, rate);
    Search {
        feasible,
        tried,
        rejections: rejections.into_iter().collect(),
    }
}

/// Sorts best first (module docs).
pub fn rank(candidates: &mut [Candidate], objective: Objective, rate: f64) {
    let key = |c: &Candidate| match objective {
        Objective::Lightest => c.sheet.spring_mass_kg,
        Objective::StressMargin => -c.stress_margin,
    };
    let miss = |c: &Candidate| (c.sheet.rate_n_mm / rate - 1.0).abs();
    candidates.sort_by(|a, b| key(a).total_cmp(&key(b)).then(miss(a).total_cmp(&miss(b))));
}
