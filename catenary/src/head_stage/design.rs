//! A design candidate as the head stage's spring: `design.json` (`coil-tune design`'s
//! output, docs/spring-design.md) read as untrusted input, its FE-verified candidate of
//! a rank (`design.json:RANK`) or all of them, rank 1 first.
//!
//! The spring is the candidate's geometry (active coils, D, d, the free pitch) with the
//! design's material (E, Poisson's ratio, density) on the design's FE model: the
//! material's FE settings with the candidate's finest mesh (`fe.mesh.elements_per_coil`,
//! the last), so that the head stage's rate is the candidate's `fe_rate_n_mm`. Its
//! damping law is the design's calibration's Rayleigh law (`material.damping.state`
//! alpha and beta) when the design has one; a design on a wire grade names none, so the
//! 160ECT's calibrated law is assumed and said so ([`super::source::ASSUMED_RAYLEIGH`]).
//! A rank that is not a verified candidate's, a candidate without a finite positive
//! geometry, and a file without verified candidates are refused, naming the file and
//! what was expected.

use super::source::{invalid, stem, Spring, ASSUMED_RAYLEIGH, MAX_SOURCE_BYTES};
use crate::{Result, TuneError};
use coil_tuner::case::SpringGeometry;
use coil_tuner::fe::{FeSettings, SpringState};
use serde::Deserialize;
use std::path::Path;

/// Most modes a design's FE settings may ask for.
const MAX_MODES: u32 = 64;

#[derive(Deserialize)]
struct File {
    material: Material,
    candidates: Vec<Candidate>,
}

#[derive(Deserialize)]
struct Material {
    youngs_modulus_mpa: f64,
    poisson_ratio: f64,
    density_kg_m3: f64,
    fe: FeSettings,
    #[serde(default)]
    damping: Option<Damping>,
}

#[derive(Deserialize)]
struct Damping {
    state: SpringState,
}

#[derive(Deserialize)]
struct Candidate {
    rank: usize,
    wire_diameter_mm: f64,
    mean_diameter_mm: f64,
    active_coils: f64,
    pitch_mm: f64,
    fe_rate_n_mm: f64,
    fe: CandidateFe,
}

#[derive(Deserialize)]
struct CandidateFe {
    mesh: Mesh,
}

#[derive(Deserialize)]
struct Mesh {
    elements_per_coil: Vec<u32>,
}

/// Refuses a value that is not finite and positive, naming the field.
fn positive(file: &Path, field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(format!(
            "{}: {field} = {v}; expected a finite positive value",
            file.display()
        )))
    }
}

/// The springs of `design.json` at `path`: the candidate of rank `rank` (the text after
/// the colon), or every candidate.
pub(super) fn design_springs(path: &Path, rank: Option<&str>) -> Result<Vec<Spring>> {
    let text = coil_io::read_bounded(path, MAX_SOURCE_BYTES, "design.json")?;
    let file: File = serde_json::from_str(&text).map_err(|e| TuneError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!(
            "{e}; expected a design.json written by `coil-tune design` (material, candidates)"
        ),
    })?;
    let ranks: Vec<usize> = file.candidates.iter().map(|c| c.rank).collect();
    if ranks.is_empty() {
        return Err(invalid(format!(
            "{}: the design has no FE-verified candidate; expected at least one in `candidates`",
            path.display()
        )));
    }
    let listed = || {
        ranks
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let wanted: Vec<&Candidate> = match rank {
        None => file.candidates.iter().collect(),
        Some(text) => {
            let r: usize = text.trim().parse().map_err(|_| {
                invalid(format!(
                    "{}: `:{}` is not a rank; expected a whole number, one of {}",
                    path.display(),
                    coil_io::confine::excerpt_n(text, 60),
                    listed()
                ))
            })?;
            let found: Vec<&Candidate> = file.candidates.iter().filter(|c| c.rank == r).collect();
            if found.is_empty() {
                return Err(invalid(format!(
                    "{}: no candidate of rank {r}; expected one of {} (the FE-verified candidates)",
                    path.display(),
                    listed()
                )));
            }
            found
        }
    };
    let m = &file.material;
    for (field, v) in [
        ("material.youngs_modulus_mpa", m.youngs_modulus_mpa),
        ("material.density_kg_m3", m.density_kg_m3),
    ] {
        positive(path, field, v)?;
    }
    if !(m.poisson_ratio.is_finite() && m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5) {
        return Err(invalid(format!(
            "{}: material.poisson_ratio = {}; expected a value in (-1, 0.5)",
            path.display(),
            m.poisson_ratio
        )));
    }
    let fe = &m.fe;
    if !(matches!(fe.element, 52 | 98)
        && (1..=MAX_MODES).contains(&fe.modes)
        && fe.static_force_n.is_finite()
        && fe.static_force_n > 0.0)
    {
        return Err(invalid(format!(
            "{}: material.fe = {{element {}, modes {}, static_force_n {}}}; expected element 52 or 98, 1 to {MAX_MODES} modes and a finite positive force",
            path.display(),
            fe.element,
            fe.modes,
            fe.static_force_n
        )));
    }
    let (rayleigh, note) = match &m.damping {
        Some(d) => {
            let [a, b] = [d.state.alpha, d.state.beta];
            if !(a.is_finite() && a >= 0.0 && b.is_finite() && b >= 0.0) {
                return Err(invalid(format!(
                    "{}: material.damping.state alpha = {a}, beta = {b}; expected finite values >= 0",
                    path.display()
                )));
            }
            (
                [a, b],
                format!(
                    "the Rayleigh law of the design's calibration (alpha = {a} 1/s, beta = {b:e} s; {})",
                    path.display()
                ),
            )
        }
        None => (
            ASSUMED_RAYLEIGH,
            format!(
                "assumed: the 160ECT's calibrated Rayleigh law (alpha = {} 1/s, beta = {:e} s), the design (a wire grade, no calibration) names none",
                ASSUMED_RAYLEIGH[0], ASSUMED_RAYLEIGH[1]
            ),
        ),
    };
    let mut springs = Vec::with_capacity(wanted.len());
    for c in wanted {
        let at = |field: &str| format!("candidates[rank {}].{field}", c.rank);
        for (field, v) in [
            ("wire_diameter_mm", c.wire_diameter_mm),
            ("mean_diameter_mm", c.mean_diameter_mm),
            ("active_coils", c.active_coils),
            ("pitch_mm", c.pitch_mm),
            ("fe_rate_n_mm", c.fe_rate_n_mm),
        ] {
            positive(path, &at(field), v)?;
        }
        let elements = c.fe.mesh.elements_per_coil.last().copied().ok_or_else(|| {
            invalid(format!(
                "{}: {} is empty; expected the beams per coil of the design's FE runs",
                path.display(),
                at("fe.mesh.elements_per_coil")
            ))
        })?;
        springs.push(Spring {
            name: format!("{} rank {}", stem(path), c.rank),
            source: format!(
                "candidate of rank {} of design {} (design FE rate {} N/mm)",
                c.rank,
                path.display(),
                c.fe_rate_n_mm
            ),
            state: SpringState {
                spring: SpringGeometry {
                    active_coils: c.active_coils,
                    mean_diameter_mm: c.mean_diameter_mm,
                    wire_diameter_mm: c.wire_diameter_mm,
                    pitch_mm: c.pitch_mm,
                },
                youngs_modulus_mpa: m.youngs_modulus_mpa,
                poisson_ratio: m.poisson_ratio,
                density_kg_m3: m.density_kg_m3,
                mass_kg: 0.0,
                alpha: rayleigh[0],
                beta: rayleigh[1],
            },
            rayleigh,
            rayleigh_note: note.clone(),
            band: None,
            fe: Some(FeSettings {
                elements_per_coil: elements,
                ..m.fe.clone()
            }),
        });
    }
    Ok(springs)
}
