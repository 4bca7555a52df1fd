//! `coil-tune check SPRING.json`: the EN 13906-1 sheet of a helical compression spring
//! beside coil's finite-element values on the same spring (docs/spring-design.md).
//!
//! - [`grades`]: EN 10270-1 Rm(d) of the spring-wire grades, the standard wire sizes;
//! - [`input`]: reading `SPRING.json`;
//! - [`en13906`]: the handbook formulas and checks; [`fatigue`]: the stroke stress
//!   against the Goodman diagram (EN 13906-1, 10^7 cycles); EN 15800's tolerances come
//!   from `coil_tuner::en15800`;
//! - [`fe`]: the FE rate (on a converged mesh), surge mode and peak wire shear.

pub mod en13906;
pub mod fatigue;
pub mod fe;
pub mod grades;
pub mod input;

use crate::error::Result;
use crate::fe::FeSettings;
use en13906::{Sheet, Spring};
use fe::FeValues;
use serde::Serialize;

/// A number with `digits` significant digits, no trailing zeros ("5.3", "0.06694").
pub fn sig(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i64;
    let decimals = (digits as i64 - 1 - magnitude).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The sheet and the FE values of one spring (`coil-tune check --json`).
#[derive(Debug, Clone, Serialize)]
pub struct CheckReport {
    /// The spring as read (D resolved from De, Rm from the grade).
    pub spring: Spring,
    /// The handbook sheet (its keys flattened into the report).
    #[serde(flatten)]
    pub sheet: Sheet,
    /// coil's FE values on the same spring.
    pub fe: FeValues,
}

/// Runs the sheet and the FE model on `spring`: the FE rate refined from `settings`'
/// beams per coil until it moves less than 0.1 % ([`fe::Mesh::Converged`]).
pub fn check(spring: &Spring, settings: &FeSettings) -> Result<CheckReport> {
    let sheet = spring.sheet();
    let state = fe::state_of(spring, &sheet);
    let fe = fe::fe_values(&state, sheet.force_2_n, settings, fe::Mesh::Converged)?;
    Ok(CheckReport {
        spring: spring.clone(),
        sheet,
        fe,
    })
}

impl CheckReport {
    /// The report as pretty JSON (the `--json` keys).
    pub fn json(&self) -> Result<String> {
        serde_json::to_string_pretty(self)
            .map_err(|e| crate::TuneError::Invalid(format!("sheet.json: {e}")))
    }

    /// `sheet.md`: the table, every check and where the formulas are documented.
    pub fn markdown(&self, file: &std::path::Path) -> String {
        use std::fmt::Write as _;
        let mut s = format!(
            "# EN 13906-1 sheet: {}\n\nFormulas: docs/spring-design.md. FE: coil's beam model on the same \
             spring (active coils at the free pitch, G through nu = E/(2G) - 1).\n\n```\n{}```\n\n## Checks\n\n",
            file.display(),
            self.table()
        );
        for c in &self.sheet.checks {
            let _ = writeln!(
                s,
                "- {} {}: {}",
                if c.passed { "pass" } else { "FAIL" },
                c.name,
                c.detail
            );
        }
        s
    }

    /// The sheet as a text table, handbook beside FE where both exist.
    pub fn table(&self) -> String {
        use std::fmt::Write as _;
        let s = &self.sheet;
        let mut t = String::new();
        let _ = writeln!(t, "{:<26} {:<30} coil FE", "", "EN 13906-1");
        for (name, handbook, fe) in self.rows() {
            let _ = writeln!(t, "{name:<26} {handbook:<30} {fe}");
        }
        if let Some(k) = self.spring.measured_rate_n_mm {
            let _ = writeln!(
                t,
                "{:<26} {k:.4}: sheet {:+.2} %, FE {:+.2} %",
                "measured R (N/mm)",
                100.0 * (s.rate_n_mm / k - 1.0),
                100.0 * (self.fe.rate_n_mm / k - 1.0)
            );
        }
        for c in s.checks.iter().filter(|c| !c.passed) {
            let _ = writeln!(t, "  {}: {}", c.name, c.detail);
        }
        t
    }

    /// The FE mesh in words.
    fn mesh_words(&self) -> String {
        let m = &self.fe.mesh;
        let last = m.elements_per_coil.last().copied().unwrap_or(0);
        match (m.method, m.last_change_percent) {
            ("converged", Some(change)) if m.extrapolated => format!(
                "extrapolated from {} beams/coil (Richardson; last change {change:+.3} %, the next mesh above {} beams)",
                m.elements_per_coil
                    .iter()
                    .map(u32::to_string)
                    .collect::<Vec<_>>()
                    .join(", "),
                fe::MAX_BEAMS
            ),
            ("converged", Some(change)) => format!(
                "{last} beams/coil ({} after {}; last change {change:+.3} %)",
                if m.converged {
                    "converged"
                } else {
                    "NOT converged"
                },
                m.elements_per_coil
                    .iter()
                    .map(u32::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            ("converged", None) => format!(
                "{last} beams/coil (NOT converged: the next mesh is above {} beams)",
                fe::MAX_BEAMS
            ),
            _ => format!("{last} beams/coil (fixed)"),
        }
    }

    /// The rows of the table: (name, handbook, FE).
    fn rows(&self) -> Vec<(&'static str, String, String)> {
        let s = &self.sheet;
        let f = &self.fe;
        let pct = |a: f64, b: f64| format!("{:+.2} %", 100.0 * (a / b - 1.0));
        let none = String::new;
        let correction = match s.stress_correction_method {
            en13906::StressCorrection::Bergstraesser => "Bergstraesser",
            en13906::StressCorrection::Wahl => "Wahl",
        };
        let mut rows = vec![
            (
                "wire",
                match &s.wire_grade {
                    Some(g) => format!("EN 10270-1 {g}, Rm {:.0} MPa", s.tensile_strength_mpa),
                    None => format!("Rm {:.0} MPa (given)", s.tensile_strength_mpa),
                },
                none(),
            ),
            ("D (mm)", format!("{:.2}", s.mean_diameter_mm), none()),
            (
                "De / Di (mm)",
                format!("{:.2} / {:.2}", s.outer_diameter_mm, s.inner_diameter_mm),
                none(),
            ),
            ("w = D/d", format!("{:.3}", s.spring_index), none()),
            (
                "R (N/mm)",
                format!("{:.4}", s.rate_n_mm),
                format!("{:.4} ({})", f.rate_n_mm, pct(f.rate_n_mm, s.rate_n_mm)),
            ),
            ("FE mesh", String::new(), self.mesh_words()),
            (
                "k (correction)",
                format!("{:.4} ({correction})", s.stress_correction),
                none(),
            ),
            ("Wahl factor", format!("{:.4}", s.wahl_factor), none()),
            (
                "pitch m0 / gap a0 (mm)",
                format!("{:.3} / {:.3}", s.pitch_mm, s.gap_mm),
                none(),
            ),
            (
                "L0 / Lw (mm)",
                format!(
                    "{:.2} / {:.2}",
                    self.spring.free_length_mm, s.active_length_mm
                ),
                none(),
            ),
            (
                "F1 / F2 (N)",
                format!("{:.2} / {:.2}", s.force_1_n, s.force_2_n),
                none(),
            ),
            (
                "s1 / L1 (mm)",
                format!("{:.2} / {:.2}", s.deflection_1_mm, s.length_1_mm),
                none(),
            ),
            (
                "s2 / L2 (mm)",
                format!("{:.2} / {:.2}", s.deflection_2_mm, s.length_2_mm),
                none(),
            ),
            ("stroke (mm)", format!("{:.2}", s.stroke_mm), none()),
            (
                "tau1 / tau_k1 (MPa)",
                format!(
                    "{:.1} / {:.1}",
                    s.shear_stress_1_mpa, s.corrected_shear_stress_1_mpa
                ),
                none(),
            ),
            (
                "tau2 / tau_k2 (MPa)",
                format!(
                    "{:.1} / {:.1}",
                    s.shear_stress_2_mpa, s.corrected_shear_stress_2_mpa
                ),
                format!(
                    "{:.1} (peak torsion + direct shear)",
                    f.max_shear_stress_2_mpa
                ),
            ),
            (
                "tau_kh / tau_kH (MPa)",
                format!(
                    "{:.1} / {:.1} ({})",
                    s.stroke_stress_mpa,
                    s.fatigue.permissible_stroke_stress_mpa,
                    if s.fatigue.passed { "passes" } else { "FAILS" }
                ),
                none(),
            ),
            ("fatigue basis", s.fatigue.basis.clone(), none()),
            ("Lc (mm)", format!("{:.2}", s.solid_length_mm), none()),
            (
                "Sa / Ln (mm)",
                format!("{:.2} / {:.2}", s.minimum_gap_sum_mm, s.minimum_length_mm),
                none(),
            ),
            ("Fc (N)", format!("{:.1}", s.solid_force_n), none()),
            (
                "tau_c / 0.56 Rm (MPa)",
                format!(
                    "{:.1} / {:.1}",
                    s.solid_shear_stress_mpa, s.permissible_solid_stress_mpa
                ),
                none(),
            ),
            (
                "fe, ends held (Hz)",
                format!("{:.1}", s.surge_frequency_hz),
                format!(
                    "{:.1} ({})",
                    f.surge_frequency_hz,
                    pct(f.surge_frequency_hz, s.surge_frequency_hz)
                ),
            ),
            (
                "buckling",
                match s.buckling_deflection_mm {
                    None => "stable".to_string(),
                    Some(sk) => format!("sk = {sk:.2} mm"),
                },
                none(),
            ),
            (
                "De growth at Lc (mm)",
                format!("{:.3}", s.outer_diameter_growth_mm),
                none(),
            ),
            (
                "transverse rate (N/mm)",
                format!("{:.3} (free, ends parallel)", s.transverse_rate_n_mm),
                none(),
            ),
            ("wire mass (kg)", format!("{:.5}", s.spring_mass_kg), none()),
        ];
        rows.extend(self.closing_rows());
        rows
    }

    /// The sheet's last rows: the head mass's bounce, EN 15800's tolerances, the checks.
    fn closing_rows(&self) -> Vec<(&'static str, String, String)> {
        let s = &self.sheet;
        let none = String::new;
        let mut rows = Vec::new();
        if let (Some(m), Some(fb)) = (s.head_mass_kg, s.bounce_frequency_hz) {
            rows.push((
                "bounce of head mass (Hz)",
                format!("{fb:.2} ({} kg)", sig(m, 4)),
                none(),
            ));
        }
        if let Some(tol) = &s.tolerances {
            rows.push((
                "EN 15800 grade",
                format!(
                    "{}: De +-{}, L0 +-{:.2} mm",
                    tol.grade,
                    tol.coil_diameter_mm
                        .map_or("(outside table)".to_string(), |v| format!("{v:.2}")),
                    tol.free_length_mm
                ),
                none(),
            ));
            rows.push((
                "EN 15800 F1 / F2 (N)",
                format!("+-{:.2} / +-{:.2}", tol.force_1_n, tol.force_2_n),
                none(),
            ));
            rows.push((
                "EN 15800 e1 / e2 (mm)",
                format!("{:.2} / {:.2}", tol.perpendicularity_mm, tol.parallelism_mm),
                none(),
            ));
        }
        rows.push((
            "checks",
            if s.passes() {
                "all pass".to_string()
            } else {
                format!("FAILED: {}", s.failed().join(", "))
            },
            none(),
        ));
        rows
    }
}
