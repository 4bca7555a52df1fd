//! The damping-law evidence in diagnose's report: when a case has several decay records
//! (other masses, a surge record, repeats), the same verdict `coil-tune damping` gives
//! ([`crate::law::verdict`]: each record reduced to its mode's frequency and zeta, every law
//! fitted to all of them and judged against the repeat scatter of zeta), as one section of
//! report.md. It is evidence beside the diagnosis, never a reason to fail it: records the
//! law comparison refuses (a nonlinear decay a damped sinusoid does not explain, a record
//! listed twice) are named with the reason instead.

use crate::case::MeasuredCase;
use crate::fe::FeSettings;
use crate::law::{self, Law};

/// report.md's section on the damping law, or nothing with fewer than two decay records.
pub fn section(case: &MeasuredCase, m: &mut String) {
    if case.decay_files.len() < 2 {
        return;
    }
    m.push_str("## Damping law (all decay records)\n\n");
    let fe = FeSettings::default();
    let v = match law::verdict(case, &fe, law::DampingSettings::default().scatter) {
        Ok(v) => v,
        Err(e) => {
            m.push_str(&format!(
                "The records cannot be compared by damping law: {e}\n\n"
            ));
            return;
        }
    };
    m.push_str(
        "| record | mode | mass (kg) | f (Hz) | zeta | se |\n|---|---|---:|---:|---:|---:|\n",
    );
    for r in &v.records {
        m.push_str(&format!(
            "| {} | {:?} | {:.3} | {:.4} | {:.6} | {:.2e} |\n",
            r.name(),
            r.mode,
            r.mass_kg,
            r.frequency_hz,
            r.damping_ratio,
            r.damping_ratio_se
        ));
    }
    m.push_str(&format!(
        "\nRepeat scatter of one test's zeta: {}.\n\n| law | parameters (+- se) | consistent |\n|---|---|---|\n",
        v.scatter.text()
    ));
    for c in &v.candidates {
        m.push_str(&format!(
            "| {} | {} | {} |\n",
            c.law.name(),
            c.parameters_text(),
            c.consistent
        ));
    }
    m.push_str(&format!(
        "\n**Law: {}.** {} (`coil-tune damping` gives the same verdict with the band, the \
         Table 4 predictions and the deciding test.)\n\n",
        v.law.map_or("not identifiable", Law::name),
        v.reason
    ));
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// A free decay at `zeta` of the paper's spring with `mass_kg` attached (closed-form
    /// damped cosine at `sqrt(K / m_eff)`, K = 3927.5 N/m, a third of the 0.0586 kg wire).
    fn record(path: &Path, mass_kg: f64, zeta: f64) {
        let w = (3927.5 / (mass_kg + 0.0586 / 3.0)).sqrt();
        let wd = w * (1.0 - zeta * zeta).sqrt();
        let mut s = String::from("time_s,accel_m_s2\n");
        for i in 0..8000 {
            let t = i as f64 * 1e-3;
            s.push_str(&format!("{t},{}\n", (-zeta * w * t).exp() * (wd * t).cos()));
        }
        std::fs::write(path, s).unwrap();
    }

    fn case(dir: &Path, decay: &str) -> MeasuredCase {
        std::fs::write(
            dir.join("case.json"),
            format!(
                r#"{{"name": "two masses",
  "spring": {{"active_coils": 14.0, "mean_diameter_mm": 24.0, "wire_diameter_mm": 3.0, "pitch_mm": 6.2}},
  "material": {{"youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0}},
  "mass_kg": 5.24, "gravity_m_s2": 0.0, "records": {{"decay": {decay}}}}}"#
            ),
        )
        .unwrap();
        crate::case::read_case(dir).unwrap()
    }

    /// One zeta at two masses: the section names the loss factor with the scatter used;
    /// one record: no section; a record listed twice: the refusal, not a failure.
    #[test]
    fn the_section_gives_the_damping_verdict() {
        let dir = tempfile::tempdir().unwrap();
        record(&dir.path().join("a.csv"), 5.24, 0.00175);
        record(&dir.path().join("b.csv"), 10.48, 0.00175);
        let mut m = String::new();
        section(
            &case(
                dir.path(),
                r#"["a.csv", {"file": "b.csv", "mass_kg": 10.48}]"#,
            ),
            &mut m,
        );
        assert!(m.contains("**Law: hysteretic.**"), "{m}");
        assert!(m.contains("the stated default"), "{m}");
        let mut one = String::new();
        section(&case(dir.path(), r#"["a.csv"]"#), &mut one);
        assert!(one.is_empty());
        let mut twice = String::new();
        section(&case(dir.path(), r#"["a.csv", "a.csv"]"#), &mut twice);
        assert!(
            twice.contains("cannot be compared") && twice.contains("the same file"),
            "{twice}"
        );
    }
}
