//! `coil-tune check SPRING.json`: the EN 13906-1 sheet of a helical compression spring
//! beside coil's finite-element values on the same spring (docs/spring-design.md).
//!
//! - [`grades`]: EN 10270-1 Rm(d) of the spring-wire grades, the standard wire sizes;
//! - [`input`]: reading `SPRING.json`;
//! - [`en13906`]: the handbook formulas and checks;
//! - [`fe`]: the FE rate, surge mode and peak wire shear.

pub mod en13906;
pub mod fe;
pub mod grades;
pub mod input;

use crate::error::Result;
use crate::fe::FeSettings;
use en13906::{Sheet, Spring};
use fe::FeValues;
use serde::Serialize;

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

/// Runs the sheet and the FE model on `spring`.
pub fn check(spring: &Spring, settings: &FeSettings) -> Result<CheckReport> {
    let sheet = spring.sheet();
    let state = fe::state_of(spring, &sheet);
    let fe = fe::fe_values(&state, sheet.force_2_n, settings)?;
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
        let f = &self.fe;
        let mut t = String::new();
        let rows: [(&str, String, String); 24] = [
            (
                "D (mm)",
                format!("{:.2}", s.mean_diameter_mm),
                String::new(),
            ),
            (
                "De / Di (mm)",
                format!("{:.2} / {:.2}", s.outer_diameter_mm, s.inner_diameter_mm),
                String::new(),
            ),
            ("w = D/d", format!("{:.3}", s.spring_index), String::new()),
            (
                "R (N/mm)",
                format!("{:.4}", s.rate_n_mm),
                format!(
                    "{:.4} ({:+.2}%)",
                    f.rate_n_mm,
                    100.0 * (f.rate_n_mm / s.rate_n_mm - 1.0)
                ),
            ),
            (
                "k (correction)",
                format!(
                    "{:.4} ({:?})",
                    s.stress_correction, s.stress_correction_method
                ),
                String::new(),
            ),
            (
                "Wahl factor",
                format!("{:.4}", s.wahl_factor),
                String::new(),
            ),
            (
                "pitch m0 / gap a0 (mm)",
                format!("{:.3} / {:.3}", s.pitch_mm, s.gap_mm),
                String::new(),
            ),
            ("F1 (N)", format!("{:.2}", s.force_1_n), String::new()),
            (
                "s1 / L1 (mm)",
                format!("{:.2} / {:.2}", s.deflection_1_mm, s.length_1_mm),
                String::new(),
            ),
            ("F2 (N)", format!("{:.2}", s.force_2_n), String::new()),
            (
                "s2 / L2 (mm)",
                format!("{:.2} / {:.2}", s.deflection_2_mm, s.length_2_mm),
                String::new(),
            ),
            ("stroke (mm)", format!("{:.2}", s.stroke_mm), String::new()),
            (
                "tau1 / tau_k1 (MPa)",
                format!(
                    "{:.1} / {:.1}",
                    s.shear_stress_1_mpa, s.corrected_shear_stress_1_mpa
                ),
                String::new(),
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
                "Lc (mm)",
                format!("{:.2}", s.solid_length_mm),
                String::new(),
            ),
            (
                "Sa / Ln (mm)",
                format!("{:.2} / {:.2}", s.minimum_gap_sum_mm, s.minimum_length_mm),
                String::new(),
            ),
            ("Fc (N)", format!("{:.1}", s.solid_force_n), String::new()),
            (
                "tau_c / 0.56 Rm (MPa)",
                format!(
                    "{:.1} / {:.1}",
                    s.solid_shear_stress_mpa, s.permissible_solid_stress_mpa
                ),
                String::new(),
            ),
            (
                "Rm (MPa)",
                format!("{:.0}", s.tensile_strength_mpa),
                String::new(),
            ),
            (
                "fe, ends held (Hz)",
                format!("{:.1}", s.surge_frequency_hz),
                format!(
                    "{:.1} ({:+.2}%)",
                    f.surge_frequency_hz,
                    100.0 * (f.surge_frequency_hz / s.surge_frequency_hz - 1.0)
                ),
            ),
            (
                "buckling",
                match s.buckling_deflection_mm {
                    None => "stable".to_string(),
                    Some(sk) => format!("sk = {sk:.2} mm"),
                },
                String::new(),
            ),
            (
                "wire mass (kg)",
                format!("{:.5}", s.spring_mass_kg),
                String::new(),
            ),
            (
                "Lw (mm)",
                format!("{:.2}", s.active_length_mm),
                String::new(),
            ),
            (
                "checks",
                if s.passes() {
                    "all pass".to_string()
                } else {
                    format!("FAILED: {}", s.failed().join(", "))
                },
                String::new(),
            ),
        ];
        let _ = writeln!(t, "{:<24} {:<28} coil FE", "", "EN 13906-1");
        for (name, handbook, fe) in rows {
            let _ = writeln!(t, "{name:<24} {handbook:<28} {fe}");
        }
        if let Some(k) = self.spring.measured_rate_n_mm {
            let _ = writeln!(
                t,
                "{:<24} {k:.4}: sheet {:+.2}%, FE {:+.2}%",
                "measured R (N/mm)",
                100.0 * (s.rate_n_mm / k - 1.0),
                100.0 * (f.rate_n_mm / k - 1.0)
            );
        }
        for c in s.checks.iter().filter(|c| !c.passed) {
            let _ = writeln!(t, "  {}: {}", c.name, c.detail);
        }
        t
    }
}
