//! Reading `SPRING.json`, the spring of `coil-tune check` (docs/spring-design.md): every
//! error names the file, line, column, key and what was expected.
//!
//! Keys: `wire_diameter_mm`, `mean_diameter_mm` or `outer_diameter_mm`, `active_coils`,
//! `total_coils`, `free_length_mm`, `end_type` (`closed_ground`, `closed`, `open`),
//! `coiling` (`cold`, `hot`), `shear_modulus_mpa`, `youngs_modulus_mpa`,
//! `density_kg_m3`, `tensile_strength_mpa` or `wire_grade` (EN 10270-1, see
//! [`super::grades`]), `seating_coefficient`, `force_1_n` and `force_2_n` or
//! `length_1_mm` and `length_2_mm`, `loading` (`static`, `dynamic`), optional
//! `stress_correction` (`bergstraesser`, the default, or `wahl`) and optional
//! `wire_tolerance_mm` (the upper deviation of d, 0 when absent: `dmax = d`) and
//! `measured_rate_n_mm` (a measured rate printed beside the sheet and the FE value).

use super::en13906::{Coiling, EndType, Loading, Spring, StressCorrection, Working};
use crate::case::{read_json, CaseError};
use crate::fields::{root, FieldError, Object, Range};
use std::path::Path;

/// A keyword member: one of `choices` (`(name, value)`).
pub(crate) fn choice<T: Copy>(
    o: &Object<'_>,
    key: &str,
    choices: &[(&str, T)],
    default: Option<T>,
) -> Result<T, FieldError> {
    let names = choices
        .iter()
        .map(|(n, _)| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ");
    let field = match (o.get(key), default) {
        (None, Some(d)) => return Ok(d),
        (None, None) => o.require(key, &format!("one of {names}"))?,
        (Some(f), _) => f,
    };
    let text = field.string(&format!("one of {names}"))?;
    choices
        .iter()
        .find(|(n, _)| *n == text)
        .map(|(_, v)| *v)
        .ok_or_else(|| field.error(format!("found \"{text}\""), format!("one of {names}")))
}

/// Two working points: both forces or both lengths, never a mix.
pub(crate) fn working(o: &Object<'_>) -> Result<Option<Working>, FieldError> {
    let f1 = o.opt_number(
        "force_1_n",
        Range::NonNegative,
        "the first working force (N)",
    )?;
    let f2 = o.opt_number("force_2_n", Range::Positive, "the second working force (N)")?;
    let l1 = o.opt_number(
        "length_1_mm",
        Range::Positive,
        "the first working length (mm)",
    )?;
    let l2 = o.opt_number(
        "length_2_mm",
        Range::Positive,
        "the second working length (mm)",
    )?;
    match (f1, f2, l1, l2) {
        (Some(a), Some(b), None, None) if b > a => Ok(Some(Working::Forces(a, b))),
        (None, None, Some(a), Some(b)) if a > b => Ok(Some(Working::Lengths(a, b))),
        (None, None, None, None) => Ok(None),
        _ => Err(o.error(
            "the working points are incomplete, mixed or out of order",
            "force_1_n < force_2_n, or length_1_mm > length_2_mm (not both kinds)",
        )),
    }
}

/// Reads `SPRING.json`.
pub fn read_spring(path: &Path) -> Result<Spring, CaseError> {
    let (_, node) = read_json(path)?;
    let top = root(path, &node);
    let o = top.object("a spring (docs/spring-design.md)")?;
    let d = o.number(
        "wire_diameter_mm",
        Range::Positive,
        "the wire diameter d (mm)",
    )?;
    let mean = match (
        o.opt_number(
            "mean_diameter_mm",
            Range::Positive,
            "the mean coil diameter D (mm)",
        )?,
        o.opt_number(
            "outer_diameter_mm",
            Range::Positive,
            "the outer diameter De (mm)",
        )?,
    ) {
        (Some(m), None) => m,
        (None, Some(outer)) => outer - d,
        _ => {
            return Err(o
                .error(
                    "the coil diameter is missing or given twice",
                    "exactly one of mean_diameter_mm and outer_diameter_mm",
                )
                .into())
        }
    };
    if mean <= d {
        return Err(o
            .error(
                format!("D = {mean} mm is not larger than d = {d} mm"),
                "a mean diameter larger than the wire",
            )
            .into());
    }
    let n = o.number("active_coils", Range::Positive, "the active coils n")?;
    let total_field = o.require("total_coils", "the total coils nt (>= n)")?;
    let total = total_field.number(Range::Positive, "the total coils nt")?;
    if total < n {
        return Err(total_field
            .error(format!("nt = {total} < n = {n}"), "nt >= n")
            .into());
    }
    let l0 = o.number("free_length_mm", Range::Positive, "the free length L0 (mm)")?;
    let strength = match (
        o.opt_number("tensile_strength_mpa", Range::Positive, "Rm (MPa)")?,
        o.get("wire_grade"),
    ) {
        (Some(rm), None) => rm,
        (None, Some(grade)) => {
            let name = grade.string("an EN 10270-1 grade name, e.g. \"DM\"")?;
            super::grades::tensile_strength_mpa(name, d)
                .map_err(|e| grade.error(e, "a grade and diameter coil tabulates"))?
        }
        _ => {
            return Err(o
                .error(
                    "the tensile strength is missing or given twice",
                    "exactly one of tensile_strength_mpa and wire_grade",
                )
                .into())
        }
    };
    let working = working(&o)?.ok_or_else(|| {
        o.error(
            "no working points",
            "force_1_n and force_2_n, or length_1_mm and length_2_mm",
        )
    })?;
    Ok(Spring {
        wire_diameter_mm: d,
        wire_tolerance_mm: o
            .opt_number(
                "wire_tolerance_mm",
                Range::NonNegative,
                "the upper deviation of d (mm)",
            )?
            .unwrap_or(0.0),
        mean_diameter_mm: mean,
        active_coils: n,
        total_coils: total,
        free_length_mm: l0,
        end_type: choice(&o, "end_type", &END_TYPES, None)?,
        coiling: choice(&o, "coiling", &COILING, None)?,
        shear_modulus_mpa: o.number("shear_modulus_mpa", Range::Positive, "G (MPa)")?,
        youngs_modulus_mpa: o.number("youngs_modulus_mpa", Range::Positive, "E (MPa)")?,
        density_kg_m3: o.number("density_kg_m3", Range::Positive, "the density (kg/m^3)")?,
        tensile_strength_mpa: strength,
        seating_coefficient: o.number(
            "seating_coefficient",
            Range::Positive,
            "the seating coefficient nu (0.5 both ends fixed and guided ... 2 one end free)",
        )?,
        working,
        loading: choice(&o, "loading", &LOADING, None)?,
        stress_correction: choice(
            &o,
            "stress_correction",
            &CORRECTIONS,
            Some(StressCorrection::Bergstraesser),
        )?,
        measured_rate_n_mm: o.opt_number(
            "measured_rate_n_mm",
            Range::Positive,
            "a measured rate to print beside the sheet (N/mm)",
        )?,
    })
}

/// `end_type` keywords.
pub(crate) const END_TYPES: [(&str, EndType); 3] = [
    ("closed_ground", EndType::ClosedGround),
    ("closed", EndType::Closed),
    ("open", EndType::Open),
];
/// `coiling` keywords.
pub(crate) const COILING: [(&str, Coiling); 2] = [("cold", Coiling::Cold), ("hot", Coiling::Hot)];
/// `loading` keywords.
pub(crate) const LOADING: [(&str, Loading); 2] =
    [("static", Loading::Static), ("dynamic", Loading::Dynamic)];
/// `stress_correction` keywords.
pub(crate) const CORRECTIONS: [(&str, StressCorrection); 2] = [
    ("bergstraesser", StressCorrection::Bergstraesser),
    ("wahl", StressCorrection::Wahl),
];
