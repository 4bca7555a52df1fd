//! Reading `SPRING.json`, the spring of `coil-tune check` (docs/spring-design.md): every
//! error names the file, line, column, key and what was expected; an unknown key is
//! refused with the list of [`SPRING_KEYS`], an explicit `null` as case.json refuses one.
//!
//! Required: `wire_diameter_mm`; `mean_diameter_mm` or `outer_diameter_mm`;
//! `active_coils`; `total_coils`; `free_length_mm` or `pitch_mm` (the pitch of the active
//! coils of the free spring, m0: then `L0 = Lc - (n - 1) dmax + n m0`); `end_type`
//! (`closed_ground`, `closed`, `open`); `coiling` (`cold`, `hot`); `wire_grade` (EN
//! 10270-1, see [`super::grades`]) or `tensile_strength_mpa`; `force_1_n` and `force_2_n`
//! or `length_1_mm` and `length_2_mm`; `loading` (`static`, `dynamic`).
//! `shear_modulus_mpa`, `youngs_modulus_mpa` and `density_kg_m3` are required with
//! `tensile_strength_mpa`; with a grade they default to EN 13906-1's handbook values
//! for EN 10270-1 wire (81500 MPa, 206000 MPa, 7850 kg/m^3).
//! Optional: `seating_coefficient` (0.5; 0.5 to 2), `stress_correction` (`bergstraesser`, the
//! default, or `wahl`), `wire_tolerance_mm` (0: `dmax = d`), `measured_rate_n_mm`,
//! `shot_peened` (false), `quality_grade` (EN 15800 grade 1, 2 or 3; 2),
//! `head_mass_kg` (the bounce frequency of that mass on the spring), `source` and
//! `notes` (free text).

use super::en13906::{Coiling, EndType, Loading, Spring, StressCorrection, Working};
use crate::case::{read_json, CaseError};
use crate::fields::{root, Field, FieldError, Object, Range};
use coil_tuner::json::Value;
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

/// The keys of `SPRING.json`.
pub const SPRING_KEYS: [&str; 29] = [
    "wire_diameter_mm",
    "mean_diameter_mm",
    "outer_diameter_mm",
    "active_coils",
    "total_coils",
    "free_length_mm",
    "pitch_mm",
    "end_type",
    "coiling",
    "shear_modulus_mpa",
    "youngs_modulus_mpa",
    "density_kg_m3",
    "tensile_strength_mpa",
    "wire_grade",
    "seating_coefficient",
    "force_1_n",
    "force_2_n",
    "length_1_mm",
    "length_2_mm",
    "loading",
    "stress_correction",
    "wire_tolerance_mm",
    "measured_rate_n_mm",
    "shot_peened",
    "quality_grade",
    "head_mass_kg",
    "source",
    "notes",
    "name",
];

/// EN 13906-1's handbook moduli and density of EN 10270-1 wire: E, G (MPa), rho (kg/m^3).
pub const HANDBOOK_STEEL: (f64, f64, f64) = (206000.0, 81500.0, 7850.0);

/// An optional boolean member.
pub(crate) fn opt_bool(
    o: &Object<'_>,
    key: &str,
    meaning: &str,
) -> Result<Option<bool>, FieldError> {
    match o.get(key) {
        None => Ok(None),
        Some(f) => match f.node.value {
            Value::Bool(b) => Ok(Some(b)),
            _ => Err(f.error("not true or false", format!("{meaning}: true or false"))),
        },
    }
}

/// A number for a message: plain when short, else in exponent form (1e300, not 301 digits).
pub(crate) fn num(x: f64) -> String {
    if x != 0.0 && !(1e-4..1e7).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// EN 13906-1's seating coefficient nu of the buckling formula, 0.5 when absent: 0.5
/// (both ends fixed and guided) to 2 (one end free); outside that range it is no seating.
pub(crate) fn seating_coefficient(o: &Object<'_>) -> Result<f64, FieldError> {
    let meaning = "the seating coefficient nu of EN 13906-1's buckling formula: 0.5 (both ends fixed and guided), 0.7, 1, up to 2 (one end free)";
    match o.get("seating_coefficient") {
        None => Ok(0.5),
        Some(f) => {
            let nu = f.number(Range::Positive, meaning)?;
            if !(0.5..=2.0).contains(&nu) {
                return Err(f.error(format!("{} is out of range", num(nu)), meaning));
            }
            Ok(nu)
        }
    }
}

/// Free-text members (`source`, `notes`, ...): a JSON string when present (a number or
/// an object there is a slip, not a note).
pub(crate) fn free_text(o: &Object<'_>, keys: &[&str]) -> Result<(), FieldError> {
    for key in keys {
        if let Some(f) = o.get(key) {
            if !matches!(f.node.value, Value::String(_)) {
                return Err(f.error(
                    format!("found {}", f.node.value.kind()),
                    "free text (a JSON string)",
                ));
            }
        }
    }
    Ok(())
}

/// EN 15800's quality grade (1, 2 or 3), 2 when absent.
pub(crate) fn quality_grade(o: &Object<'_>) -> Result<u8, FieldError> {
    match o.get("quality_grade") {
        None => Ok(super::en13906::default_quality_grade()),
        Some(f) => {
            let g = f.number(Range::Count, "the EN 15800 quality grade")?;
            if g > 3.0 {
                return Err(f.error(
                    format!("found {}", num(g)),
                    "the EN 15800 quality grade: 1, 2 or 3",
                ));
            }
            Ok(g as u8)
        }
    }
}

/// The coil diameter D: `mean_diameter_mm`, or `outer_diameter_mm` - d.
fn mean_diameter(o: &Object<'_>, d: f64) -> Result<f64, FieldError> {
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
            return Err(o.error(
                "the coil diameter is missing or given twice",
                "exactly one of mean_diameter_mm and outer_diameter_mm",
            ))
        }
    };
    if mean <= d {
        let key = if o.get("mean_diameter_mm").is_some() {
            "mean_diameter_mm"
        } else {
            "outer_diameter_mm"
        };
        let field = o.require(key, "")?;
        return Err(field.error(
            format!("D = {} mm is not larger than d = {} mm", num(mean), num(d)),
            "a mean diameter larger than the wire (outer diameter larger than 2 d)",
        ));
    }
    Ok(mean)
}

/// Rm and the grade's name: `tensile_strength_mpa`, or `wire_grade`'s Rm at d.
fn strength(o: &Object<'_>, d: f64) -> Result<(f64, Option<String>), FieldError> {
    match (
        o.opt_number("tensile_strength_mpa", Range::Positive, "Rm (MPa)")?,
        o.get("wire_grade"),
    ) {
        (Some(rm), None) => Ok((rm, None)),
        (None, Some(grade)) => grade_strength(&grade, d),
        _ => Err(o.error(
            "the tensile strength is missing or given twice",
            "exactly one of tensile_strength_mpa and wire_grade",
        )),
    }
}

/// A `wire_grade` field's Rm at d and its name as the standard spells it.
pub(crate) fn grade_strength(
    grade: &Field<'_>,
    d: f64,
) -> Result<(f64, Option<String>), FieldError> {
    let name = grade.string("an EN 10270-1 grade name, e.g. \"DM\"")?;
    let rm = super::grades::tensile_strength_mpa(name, d).map_err(|e| {
        grade.error(
            e,
            format!("one of {} at 1 to 12 mm", super::grades::GRADES.join(", ")),
        )
    })?;
    Ok((rm, Some(super::grades::canonical(name))))
}

/// G, E and rho: given, or EN 13906-1's handbook values when a grade names the wire.
fn moduli(o: &Object<'_>, graded: bool) -> Result<(f64, f64, f64), FieldError> {
    let (e, g, rho) = HANDBOOK_STEEL;
    let value = |key: &str, meaning: &str, handbook: f64| {
        if graded {
            Ok(o.opt_number(key, Range::Positive, meaning)?
                .unwrap_or(handbook))
        } else {
            o.number(key, Range::Positive, &format!("{meaning} (required with tensile_strength_mpa; a wire_grade gives the handbook value)"))
        }
    };
    Ok((
        value("shear_modulus_mpa", "G (MPa)", g)?,
        value("youngs_modulus_mpa", "E (MPa)", e)?,
        value("density_kg_m3", "the density (kg/m^3)", rho)?,
    ))
}

/// Reads `SPRING.json`.
pub fn read_spring(path: &Path) -> Result<Spring, CaseError> {
    let (_, node) = read_json(path)?;
    let top = root(path, &node);
    let o = top.object("a spring (docs/spring-design.md)")?;
    o.strict(&SPRING_KEYS)?;
    free_text(&o, &["source", "notes", "name"])?;
    let d = o.number(
        "wire_diameter_mm",
        Range::Positive,
        "the wire diameter d (mm)",
    )?;
    let mean = mean_diameter(&o, d)?;
    let n = o.number("active_coils", Range::Positive, "the active coils n")?;
    let total_field = o.require("total_coils", "the total coils nt (>= n)")?;
    let total = total_field.number(Range::Positive, "the total coils nt")?;
    if total < n {
        return Err(total_field
            .error(format!("nt = {} < n = {}", num(total), num(n)), "nt >= n")
            .into());
    }
    let (strength, grade) = strength(&o, d)?;
    let (g, e, rho) = moduli(&o, grade.is_some())?;
    let working = working(&o)?.ok_or_else(|| {
        o.error(
            "no working points",
            "force_1_n and force_2_n, or length_1_mm and length_2_mm",
        )
    })?;
    let mut spring = Spring {
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
        free_length_mm: 0.0,
        end_type: choice(&o, "end_type", &END_TYPES, None)?,
        coiling: choice(&o, "coiling", &COILING, None)?,
        shear_modulus_mpa: g,
        youngs_modulus_mpa: e,
        density_kg_m3: rho,
        tensile_strength_mpa: strength,
        seating_coefficient: seating_coefficient(&o)?,
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
        wire_grade: grade,
        shot_peened: opt_bool(&o, "shot_peened", "whether the spring is shot-peened")?
            .unwrap_or(false),
        quality_grade: quality_grade(&o)?,
        head_mass_kg: o.opt_number(
            "head_mass_kg",
            Range::Positive,
            "a head mass for the bounce frequency (kg)",
        )?,
    };
    spring.free_length_mm = free_length(&o, &spring)?;
    model_domain(&o, &spring)?;
    Ok(spring)
}

/// The material and geometry coil's FE model beside the sheet takes, refused naming the
/// key: moduli and density of a spring metal in their units (a unit slip, 206 for
/// 206000 MPa or 7.85 for 7850 kg/m^3, is caught), Poisson's ratio `E / (2 G) - 1` of an
/// isotropic metal (0 to 0.5), at least [`coil_mesher::MIN_COILS`] active coil, the
/// spring index within [`coil_mesher::SPRING_INDEX`] and a free pitch below 2 pi D.
fn model_domain(o: &Object<'_>, spring: &Spring) -> Result<(), FieldError> {
    let field = |keys: &[&str]| {
        keys.iter()
            .find_map(|k| o.get(k))
            .map_or_else(|| o.error("", ""), |f| f.error("", ""))
    };
    let refuse = |keys: &[&str], problem: String, expected: &str| {
        let mut e = field(keys);
        e.problem = problem;
        e.expected = expected.to_string();
        Err(e)
    };
    let (e, g, rho) = (
        spring.youngs_modulus_mpa,
        spring.shear_modulus_mpa,
        spring.density_kg_m3,
    );
    if !(1e3..=1e6).contains(&e) {
        return refuse(
            &["youngs_modulus_mpa"],
            format!("E = {} MPa", num(e)),
            "a spring metal's E in MPa, 1e3 to 1e6 (steel 206000)",
        );
    }
    if !(1e3..=1e6).contains(&g) {
        return refuse(
            &["shear_modulus_mpa"],
            format!("G = {} MPa", num(g)),
            "a spring metal's G in MPa, 1e3 to 1e6 (steel 81500)",
        );
    }
    let nu = e / (2.0 * g) - 1.0;
    if !(0.0..0.5).contains(&nu) {
        return refuse(
            &["shear_modulus_mpa", "youngs_modulus_mpa"],
            format!(
                "E = {} and G = {} MPa give Poisson's ratio E / (2 G) - 1 = {nu:.4}",
                num(e),
                num(g)
            ),
            "an isotropic metal's G between E / 3 and E / 2 (Poisson's ratio 0 to 0.5; steel 0.26)",
        );
    }
    if !(1e3..=25e3).contains(&rho) {
        return refuse(
            &["density_kg_m3"],
            format!("{} kg/m^3", num(rho)),
            "a spring metal's density in kg/m^3, 1000 to 25000 (steel 7850; 7.85 would be kg/dm^3)",
        );
    }
    let n = spring.active_coils;
    if n < coil_mesher::MIN_COILS {
        return refuse(&["active_coils"], format!("n = {}", num(n)), "at least 1 active coil for coil's FE model (EN 13906-1 asks for 2; the sheet checks it)");
    }
    let (lo, hi) = coil_mesher::SPRING_INDEX;
    let w = spring.mean_diameter_mm / spring.wire_diameter_mm;
    if !(lo..=hi).contains(&w) {
        return refuse(
            &["mean_diameter_mm", "outer_diameter_mm"],
            format!("D / d = {}", num(w)),
            "a spring index from 3 to 100 for coil's FE model (EN 13906-1 recommends 4 to 20; below 3 the wire is too curved for beams, above 100 the figures are likely a unit slip)",
        );
    }
    let pitch = (spring.free_length_mm - spring.end_allowance_mm()) / n;
    if pitch >= 2.0 * std::f64::consts::PI * spring.mean_diameter_mm {
        return refuse(
            &["free_length_mm", "pitch_mm"],
            format!(
                "the free coils' pitch m0 = {} mm is above 2 pi D",
                num(pitch)
            ),
            "a pitch below 2 pi D (a pitch angle under 63 degrees: a helical spring)",
        );
    }
    Ok(())
}

/// L0: `free_length_mm`, or from `pitch_mm` (`L0 = Lc - (n - 1) dmax + n m0`); the
/// pitch must exceed the wire (a positive gap) and the free length the solid length.
fn free_length(o: &Object<'_>, spring: &Spring) -> Result<f64, FieldError> {
    let dmax = spring.max_wire_diameter_mm();
    match (o.get("free_length_mm"), o.get("pitch_mm")) {
        (Some(f), None) => {
            let l0 = f.number(Range::Positive, "the free length L0 (mm)")?;
            let lc = spring.solid_length_mm();
            if l0 <= lc {
                return Err(f.error(
                    format!(
                        "L0 = {} mm is not longer than the solid length Lc = {} mm",
                        num(l0),
                        num(lc)
                    ),
                    "a free length above the solid length (nt, d and the end type set Lc)",
                ));
            }
            Ok(l0)
        }
        (None, Some(f)) => {
            let pitch = f.number(
                Range::Positive,
                "the pitch m0 of the free active coils (mm)",
            )?;
            if pitch <= dmax {
                return Err(f.error(
                    format!(
                        "m0 = {} mm is not larger than dmax = {} mm",
                        num(pitch),
                        num(dmax)
                    ),
                    "a pitch larger than the wire (a gap between the free coils)",
                ));
            }
            Ok(spring.end_allowance_mm() + spring.active_coils * pitch)
        }
        _ => Err(o.error(
            "the free length is missing or given twice",
            "exactly one of free_length_mm and pitch_mm",
        )),
    }
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
