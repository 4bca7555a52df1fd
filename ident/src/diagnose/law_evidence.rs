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
