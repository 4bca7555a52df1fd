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
//! 160ECT's calibrated law is assumed and said so ([`super::from_spring::ASSUMED_RAYLEIGH`]).
//! A rank that is not a verified candidate's, a candidate without a finite positive
//! geometry, and a file without verified candidates are refused, naming the file and
//! what was expected.

use super::from_spring::{invalid, stem, Spring, ASSUMED_RAYLEIGH, MAX_SOURCE_BYTES};
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

#[cfg(test)]
mod tests {
    use super::super::from_spring::{build_heads, HeadSpringSpec};
    use crate::model::CatenaryDeckSpec;
    use coil_design::target::{read_target, MaterialSource};
    use coil_design::{design, DesignSettings};
    use coil_tuner::fe::FeSettings;
    use std::path::{Path, PathBuf};

    /// A design on a wire grade (the 160ECT target, two candidates), written as
    /// `coil-tune design` writes it.
    fn design_file(dir: &Path) -> (PathBuf, Vec<f64>) {
        let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/spring-design");
        let mut target = read_target(&cases.join("160ect_target.json")).unwrap();
        target.material = MaterialSource::Grade { grade: "DM".into() };
        let settings = DesignSettings {
            short_list: Some(2),
            ..DesignSettings::default()
        };
        let result = design(&target, &settings).unwrap();
        let file = dir.join("design.json");
        std::fs::write(&file, coil_design::output::json(&result).unwrap()).unwrap();
        (
            file,
            result.candidates.iter().map(|c| c.fe_rate_n_mm).collect(),
        )
    }

    #[test]
    fn a_design_rank_is_the_head_stage_at_the_designs_fe_rate() {
        let dir = tempfile::tempdir().unwrap();
        let (file, rates) = design_file(dir.path());
        assert!(rates.len() >= 2, "{rates:?}");
        let pantograph = CatenaryDeckSpec::en50318_reference(2, 0.25).pantograph;
        let spec = HeadSpringSpec::default();
        let fe = FeSettings::default();
        let entry = |rank: &str| PathBuf::from(format!("{}:{rank}", file.display()));
        // Rank 2: one stage, K = 4 k with k the design's FE rate of that candidate (the
        // same model: the design's material on the candidate's finest mesh).
        let heads = build_heads(&[entry("2")], &spec, &pantograph, &fe).unwrap();
        assert_eq!(heads.len(), 1);
        let h = &heads[0];
        println!(
            "{}: k = {} N/mm (design {} N/mm), K = {} N/m, c = {} N s/m, {}",
            h.name, h.spring_rate_n_mm, rates[1], h.stiffness_n_m, h.damping_n_s_m, h.damping_law
        );
        assert!((h.spring_rate_n_mm / rates[1] - 1.0).abs() < 1e-9);
        assert_eq!(h.stiffness_n_m, 4.0 * h.spring_rate_n_mm * 1e3);
        assert_eq!(
            h.name,
            format!(
                "{} rank 2",
                dir.path().file_name().unwrap().to_string_lossy()
            )
        );
        // A grade names no damping law: the assumed one, said so.
        assert!(
            h.assumptions.iter().any(|a| a.starts_with("assumed")),
            "{:?}",
            h.assumptions
        );
        // No rank: every candidate, rank 1 first.
        let all = build_heads(&[file.clone()], &spec, &pantograph, &fe).unwrap();
        assert_eq!(all.len(), rates.len());
        assert!((all[0].spring_rate_n_mm / rates[0] - 1.0).abs() < 1e-9);
        // A rank that does not exist, and one that is not a number, name the file and
        // the ranks there are.
        let listed: Vec<String> = (1..=rates.len()).map(|r| r.to_string()).collect();
        for (rank, says) in [
            ("9", "no candidate of rank 9"),
            ("best", "`:best` is not a rank"),
        ] {
            let e = build_heads(&[entry(rank)], &spec, &pantograph, &fe)
                .unwrap_err()
                .to_string();
            println!("{e}");
            assert!(e.contains(says) && e.contains("design.json"), "{e}");
            assert!(e.contains(&format!("one of {}", listed.join(", "))), "{e}");
        }
    }

    #[test]
    fn a_damaged_design_is_refused_naming_the_field() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("design.json");
        let pantograph = CatenaryDeckSpec::en50318_reference(2, 0.25).pantograph;
        let fe = FeSettings::default();
        let candidate = |pitch: &str| {
            format!(
                r#"{{"rank": 1, "wire_diameter_mm": 3.0, "mean_diameter_mm": 24.0, "active_coils": 14.0,
                   "pitch_mm": {pitch}, "fe_rate_n_mm": 3.9, "fe": {{"mesh": {{"elements_per_coil": [24]}}}}}}"#
            )
        };
        let material = r#"{"youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0,
            "fe": {"elements_per_coil": 24, "element": 98, "lumped_mass": false, "static_force_n": 10.0, "modes": 3}}"#;
        for (candidates, says) in [
            ("[]".to_string(), "no FE-verified candidate"),
            (
                format!("[{}]", candidate("-6.2")),
                "candidates[rank 1].pitch_mm = -6.2",
            ),
        ] {
            std::fs::write(
                &file,
                format!(
                    r#"{{"target": {{}}, "material": {material}, "candidates": {candidates}}}"#
                ),
            )
            .unwrap();
            let e = build_heads(
                &[file.clone()],
                &HeadSpringSpec::default(),
                &pantograph,
                &fe,
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains(says) && e.contains("design.json"), "{e}");
        }
    }
}
