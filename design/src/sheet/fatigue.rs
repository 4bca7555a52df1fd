//! Fatigue of a dynamically loaded compression spring after EN 13906-1: the stroke stress
//! against the permissible stroke stress of the wire's Goodman diagram at N = 10^7 cycles.
//!
//! # Formulation (EN 13906-1:2013, clause 9.3 and its fatigue resistance diagrams)
//! - lower and upper corrected stresses `tau_k1 = k tau1`, `tau_k2 = k tau2`
//!   (Bergsträsser's k), stroke stress `tau_kh = tau_k2 - tau_k1`;
//! - the standard's Goodman diagram of cold-coiled springs of patented drawn wire (EN
//!   10270-1 grade DH), one for springs not shot-peened and one for shot-peened springs,
//!   both at N = 10^7 cycles (the fatigue strength; the standard gives no life class
//!   beyond it for this wire), one line per wire diameter: the permissible upper stress
//!   `tau_kO` rises linearly with the lower stress `tau_kU` from `tau_kO(0)` to the
//!   diagram's corner `(tau_kU,max, tau_kO,max)`, where it meets the static limit;
//! - the permissible stroke stress `tau_kH = tau_kO(tau_k1) - tau_k1`; the spring passes
//!   when `tau_kh <= tau_kH`, `tau_k1 <= tau_kU,max` and `tau_k2 <= tau_kO,max`;
//! - the diagram's three values against d, as the open implementation springONE
//!   digitises the standard's curves (github.com/melchiorrecaruso/springone,
//!   `SpringLIB/database/MATERIAL.csv`, grade DH): `X(d) = a - b log10(d / 1 mm)` with
//!   (a, b) = tau_kO(0): (506, 175) MPa, tau_kO,max: (1118, 410), tau_kU,max: (832, 322)
//!   not shot-peened; (601, 193), (1119, 409), (698, 273) shot-peened;
//! - other EN 10270-1 grades (SL, SM, DM; SH shares DH's strength): the standard draws
//!   no diagram for them; coil scales DH's diagram by the ratio of the grades' minimum
//!   tensile strengths at d (fatigue strength of drawn wire proportional to Rm), and the
//!   verdict says so (`basis`);
//! - coil evaluates the diagrams over its Rm table's diameters, 1 to 12 mm.
//!
//! Units: MPa, mm. A pantograph head's springs see far more than 10^7 strokes; the
//! standard's 10^7-cycle strength is the endurance limit it tabulates, no more.

use serde::Serialize;

/// The diagram's three lines of one surface condition: `(a, b)` of `a - b log10 d`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Diagram {
    /// Permissible upper stress at zero lower stress, tau_kO(0).
    upper_at_zero: (f64, f64),
    /// The corner's upper stress, tau_kO,max.
    upper_max: (f64, f64),
    /// The corner's lower stress, tau_kU,max.
    lower_max: (f64, f64),
}

/// DH, not shot-peened, N = 10^7 (module docs).
const DH_NOT_PEENED: Diagram = Diagram {
    upper_at_zero: (506.0, 175.0),
    upper_max: (1118.0, 410.0),
    lower_max: (832.0, 322.0),
};

/// DH, shot-peened, N = 10^7 (module docs).
const DH_PEENED: Diagram = Diagram {
    upper_at_zero: (601.0, 193.0),
    upper_max: (1119.0, 409.0),
    lower_max: (698.0, 273.0),
};

/// The cycles the diagrams hold for.
pub const CYCLES: f64 = 1e7;

/// The Goodman line of one wire: permissible upper stress against lower stress.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GoodmanLine {
    /// tau_kO at tau_kU = 0 (MPa): the permissible stroke stress from zero.
    pub upper_at_zero_mpa: f64,
    /// The diagram's corner: the largest lower stress (MPa).
    pub lower_max_mpa: f64,
    /// The diagram's corner: the largest upper stress (MPa).
    pub upper_max_mpa: f64,
}

impl GoodmanLine {
    /// Permissible upper stress at lower stress `lower` (MPa), on the line (not
    /// clipped: the caller checks the corner).
    pub fn upper_mpa(&self, lower: f64) -> f64 {
        self.upper_at_zero_mpa
            + (self.upper_max_mpa - self.upper_at_zero_mpa) * lower / self.lower_max_mpa
    }

    /// Permissible stroke stress tau_kH at lower stress `lower` (MPa).
    pub fn stroke_mpa(&self, lower: f64) -> f64 {
        self.upper_mpa(lower) - lower
    }
}

/// The Goodman line of DH wire of diameter `d_mm`, shot-peened or not, scaled by
/// `scale` (1 for DH and SH).
pub fn dh_line(d_mm: f64, shot_peened: bool, scale: f64) -> GoodmanLine {
    let diagram = if shot_peened {
        DH_PEENED
    } else {
        DH_NOT_PEENED
    };
    let at = |(a, b): (f64, f64)| scale * (a - b * d_mm.log10());
    GoodmanLine {
        upper_at_zero_mpa: at(diagram.upper_at_zero),
        lower_max_mpa: at(diagram.lower_max),
        upper_max_mpa: at(diagram.upper_max),
    }
}

/// The fatigue check of one spring (the sheet's `fatigue`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fatigue {
    /// Lower corrected stress tau_k1 (MPa).
    pub lower_stress_mpa: f64,
    /// Upper corrected stress tau_k2 (MPa).
    pub upper_stress_mpa: f64,
    /// Stroke stress tau_kh = tau_k2 - tau_k1 (MPa).
    pub stroke_stress_mpa: f64,
    /// Permissible stroke stress tau_kH at the lower stress (MPa).
    pub permissible_stroke_stress_mpa: f64,
    /// tau_kh / tau_kH (-): at most 1 passes.
    pub utilisation: f64,
    /// The Goodman line used.
    pub line: GoodmanLine,
    /// Shot-peened or not.
    pub shot_peened: bool,
    /// The cycles the line holds for.
    pub cycles: f64,
    /// True when the spring passes (stroke, lower and upper stress within the diagram).
    pub passed: bool,
    /// Where the line comes from, in words.
    pub basis: String,
}

/// The fatigue check at lower and upper corrected stresses `tau_k1`, `tau_k2` (MPa) of a
/// `grade` wire of diameter `d_mm`, with `rm` its Rm and `rm_dh` DH's Rm at d (both MPa,
/// `None` when the grade is unknown: then DH's line is scaled by nothing and the basis
/// says the strength was given, not a grade). Without `details` the `basis` is left
/// empty (a design's search checks millions of springs and words none of them).
#[allow(clippy::too_many_arguments)]
pub fn check(
    tau_k1: f64,
    tau_k2: f64,
    d_mm: f64,
    shot_peened: bool,
    grade: Option<&str>,
    rm: f64,
    rm_dh: Option<f64>,
    details: bool,
) -> Fatigue {
    let surface = if shot_peened {
        "shot-peened"
    } else {
        "not shot-peened"
    };
    let grade = grade.map(str::trim);
    let dh = grade.is_some_and(|g| g.eq_ignore_ascii_case("DH") || g.eq_ignore_ascii_case("SH"));
    let scale = match rm_dh {
        Some(rm_dh) if !dh => rm / rm_dh,
        _ => 1.0,
    };
    let basis = if !details {
        String::new()
    } else {
        match (grade, rm_dh) {
            _ if dh => format!(
                "EN 13906-1 Goodman diagram, EN 10270-1 DH, {surface}, N = 1e7 (springONE's digitisation)"
            ),
            (Some(g), Some(dh)) => format!(
                "estimated: EN 13906-1 gives no diagram for {}; DH's ({surface}, N = 1e7) scaled by Rm {rm:.0} / {dh:.0} MPa",
                g.to_ascii_uppercase()
            ),
            (None, Some(dh)) => format!(
                "estimated: DH's diagram ({surface}, N = 1e7) scaled by the given Rm {rm:.0} / DH's {dh:.0} MPa"
            ),
            (_, None) => format!(
                "EN 13906-1 DH diagram ({surface}, N = 1e7) unscaled: d outside DH's table"
            ),
        }
    };
    let line = dh_line(d_mm, shot_peened, scale);
    let stroke = tau_k2 - tau_k1;
    let permissible = line.stroke_mpa(tau_k1.max(0.0));
    let passed =
        stroke <= permissible && tau_k1 <= line.lower_max_mpa && tau_k2 <= line.upper_max_mpa;
    Fatigue {
        lower_stress_mpa: tau_k1,
        upper_stress_mpa: tau_k2,
        stroke_stress_mpa: stroke,
        permissible_stroke_stress_mpa: permissible,
        utilisation: stroke / permissible,
        line,
        shot_peened,
        cycles: CYCLES,
        passed,
        basis,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// By hand from the module's lines: DH not shot-peened at d = 5 mm,
    /// tau_kO(0) = 506 - 175 log10 5 = 383.69, corner (606.93, 831.42); at tau_kU =
    /// 237.3 MPa, tau_kO = 383.69 + (831.42 - 383.69) 237.3 / 606.93 = 558.74, so
    /// tau_kH = 321.44 MPa.
    #[test]
    fn dh_line_by_hand() {
        let line = dh_line(5.0, false, 1.0);
        assert!((line.upper_at_zero_mpa - 383.69).abs() < 0.01, "{line:?}");
        assert!((line.upper_max_mpa - 831.42).abs() < 0.01, "{line:?}");
        assert!((line.lower_max_mpa - 606.93).abs() < 0.01, "{line:?}");
        assert!((line.stroke_mpa(237.3) - 321.44).abs() < 0.02);
        // Shot peening raises the strength at every lower stress below the corner.
        let peened = dh_line(5.0, true, 1.0);
        for lower in [0.0, 100.0, 300.0, 500.0] {
            assert!(peened.stroke_mpa(lower) > line.stroke_mpa(lower), "{lower}");
        }
        // Thicker wire is weaker.
        assert!(dh_line(8.0, false, 1.0).upper_at_zero_mpa < line.upper_at_zero_mpa);
    }

    /// A 1.4 mm wire at tau_kh = 739 MPa is far above any diagram: refused.
    #[test]
    fn a_large_stroke_stress_is_refused() {
        let f = check(
            100.0,
            839.0,
            1.4,
            false,
            Some("DH"),
            2000.0,
            Some(2000.0),
            true,
        );
        assert!(!f.passed && f.utilisation > 1.5, "{f:?}");
        let f = check(
            100.0,
            839.0,
            1.4,
            true,
            Some("DH"),
            2000.0,
            Some(2000.0),
            true,
        );
        assert!(!f.passed, "{f:?}");
    }
}
