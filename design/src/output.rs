//! A design's files, one output set: `design.json` (the target, the material, the
//! search's counts, `candidates` best first, the FE-rejected ones, the damping
//! verdict), `report.md`, `design.png` (rate against mass: the feasible set, the short
//! list by handbook and by FE, the target band) and `decks/candidate_NN.dat` (each
//! short-listed spring with the weight: static at the second working force, modal).

use super::target::Objective;
use super::verify::{candidate_settings, candidate_state, Verified};
use super::{zeta_line, Design};
use crate::error::{Result, TuneError};
use crate::sheet::en13906::{Loading, Working};
use coil_mesher::AnalysisKind;
use coil_tuner::output::OutDir;
use std::fmt::Write as _;

/// `design.json`'s text.
pub fn json(design: &Design) -> Result<String> {
    serde_json::to_string_pretty(design)
        .map_err(|e| TuneError::Invalid(format!("design.json: {e}")))
}

/// The deck of a verified spring (the same model the FE verification ran, with the
/// weight on the guided top).
pub fn deck(design: &Design, v: &Verified) -> Result<String> {
    let springs = f64::from(design.target.springs_in_parallel);
    let weight = design.weight_kg.map_or(0.0, |w| w / springs);
    let candidate = super::search::Candidate {
        spring: v.spring.clone(),
        sheet: v.sheet.clone(),
        stress_margin: v.stress_margin,
    };
    let state = candidate_state(&candidate, &design.material, weight);
    let settings = candidate_settings(&candidate, &design.material);
    let model = state.model(&settings, &[AnalysisKind::Static, AnalysisKind::Modal])?;
    Ok(coil_solver::deck::write(&model))
}

/// Writes every file of the design into `out` (not committed).
pub fn write(design: &Design, out: &OutDir, figure: bool) -> Result<()> {
    for v in design.candidates.iter().chain(&design.rejected) {
        out.write(&v.deck, deck(design, v)?.as_bytes())?;
    }
    if figure {
        let short: Vec<(f64, f64, f64, bool)> = design
            .candidates
            .iter()
            .chain(&design.rejected)
            .map(|v| (v.spring_mass_kg, v.rate_n_mm, v.fe_rate_n_mm, v.fe_verified))
            .collect();
        let rate = design.target.rate_n_mm / f64::from(design.target.springs_in_parallel);
        crate::plot::design_figure(
            &crate::plot::DesignPlot {
                feasible: &design.feasible_points,
                short_list: &short,
                rate_n_mm: rate,
                tolerance: design.target.rate_tolerance_percent / 100.0,
            },
            &out.staged("design.png")?,
        )?;
    }
    out.write("report.md", report(design).as_bytes())?;
    out.write("design.json", json(design)?.as_bytes())?;
    Ok(())
}

pub use crate::sheet::sig;

/// The working points in words.
pub fn working_words(w: &Working) -> String {
    match *w {
        Working::Forces(a, b) => format!("F1 = {} N, F2 = {} N", sig(a, 4), sig(b, 4)),
        Working::Lengths(a, b) => format!("L1 = {} mm, L2 = {} mm", sig(a, 4), sig(b, 4)),
    }
}

/// The objective in words.
pub fn objective_words(o: Objective) -> &'static str {
    match o {
        Objective::Lightest => "lightest",
        Objective::StressMargin => "stress margin",
    }
}

/// The candidates as a markdown table.
pub fn table(design: &Design) -> String {
    let dynamic = design.target.loading == Loading::Dynamic;
    let mut s = format!(
        "| rank | d (mm) | D (mm) | n | pitch (mm) | L0 (mm) | R handbook (N/mm) | K FE (N/mm) | K FE vs target | mass (kg) | {} | margin | surge FE (Hz) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        if dynamic { "tau_kh / tau_kH (MPa)" } else { "tau2 / 0.5 Rm (MPa)" }
    );
    for v in &design.candidates {
        let stress = if dynamic {
            format!(
                "{:.0} / {:.0}",
                v.stroke_stress_mpa, v.permissible_stroke_stress_mpa
            )
        } else {
            format!(
                "{:.0} / {:.0}",
                v.sheet.shear_stress_2_mpa, v.sheet.permissible_working_stress_mpa
            )
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {} | {:.2} | {:.2} | {:.4} | {:.4} | {:+.2} % | {:.5} | {stress} | {:.3} | {:.1} |",
            v.rank,
            sig(v.wire_diameter_mm, 3),
            v.mean_diameter_mm,
            sig(v.active_coils, 4),
            v.pitch_mm,
            v.free_length_mm,
            v.rate_n_mm,
            v.fe_rate_n_mm,
            v.fe_rate_error_percent,
            v.spring_mass_kg,
            v.stress_margin,
            v.fe.surge_frequency_hz,
        );
    }
    s
}

/// The candidates' zeta, one column per law.
pub fn zeta_table(design: &Design) -> Option<String> {
    let laws: Vec<&String> = design.candidates.first()?.damping_ratio.keys().collect();
    if laws.is_empty() {
        return None;
    }
    let mut s = format!(
        "| rank | {} |\n|---|{}\n",
        laws.iter()
            .map(|l| l.replace('_', " "))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(laws.len())
    );
    for v in &design.candidates {
        let values: Vec<String> = laws
            .iter()
            .map(|l| {
                v.damping_ratio
                    .get(*l)
                    .map_or("-".into(), |z| format!("{z:.5}"))
            })
            .collect();
        let _ = writeln!(s, "| {} | {} |", v.rank, values.join(" | "));
    }
    Some(s)
}

/// `report.md`.
pub fn report(design: &Design) -> String {
    let t = &design.target;
    let mut s = format!(
        "# Spring design\n\nTarget: K = {} N/mm +- {} % ({} in parallel), {}, {} loading{}, weight {}, objective: {}.\n\nMaterial: {}.\n\n",
        sig(t.rate_n_mm, 6),
        sig(t.rate_tolerance_percent, 3),
        if t.springs_in_parallel == 1 { "1 spring".to_string() } else { format!("{} springs", t.springs_in_parallel) },
        working_words(&t.working),
        match t.loading {
            Loading::Static => "static",
            Loading::Dynamic => "dynamic",
        },
        if t.loading == Loading::Dynamic {
            if t.shot_peened { " (shot-peened)" } else { " (not shot-peened)" }
        } else {
            ""
        },
        design
            .weight_kg
            .map_or("not given".to_string(), |w| format!("{} kg", sig(w, 4))),
        objective_words(t.objective),
        design.material.source
    );
    let fe_mesh = match design.candidates.first().or(design.rejected.first()) {
        Some(v) if v.fe.mesh.method == "converged" => format!(
            "converged mesh (beams per coil doubled from {} until the rate moved less than 0.1 %)",
            v.fe.mesh.elements_per_coil.first().copied().unwrap_or(0)
        ),
        Some(v) => format!(
            "the calibration's mesh, {} beams per coil (its E absorbs the chord stiffening)",
            v.fe.mesh.elements_per_coil.first().copied().unwrap_or(0)
        ),
        None => "none run".to_string(),
    };
    let _ = writeln!(
        s,
        "Search (EN 13906-1 checks{}, the envelope; docs/spring-design.md): {} springs within the rate tolerance tried, {} feasible; failed checks (a spring may fail several): {}.\n\nFE verification: {} springs run down the ranking, at most {} per wire diameter; FE on the {fe_mesh}.{}\n",
        if t.loading == Loading::Dynamic { " with fatigue at 10^7 cycles" } else { "" },
        design.tried,
        design.feasible,
        if design.rejections.is_empty() {
            "none".to_string()
        } else {
            design
                .rejections
                .iter()
                .map(|(k, n)| format!("{} {n}", k.replace('_', " ")))
                .collect::<Vec<_>>()
                .join(", ")
        },
        design.fe_runs,
        crate::PER_WIRE,
        if design.fe_skipped > 0 {
            format!(
                " {} feasible springs not verified: their FE model would have more than {} beams (docs/files.md).",
                design.fe_skipped,
                crate::sheet::fe::MAX_BEAMS
            )
        } else {
            String::new()
        },
    );
    let _ = writeln!(
        s,
        "## Candidates (FE-verified, best first)\n\n{}",
        table(design)
    );
    if design.tried == 0 {
        s.push_str("No standard wire and mean diameter gives this rate within the tolerance with 2 to 630 / d - 2 active coils (EN 15800's longest free length, 630 mm) inside the envelope: the rate, the tolerance or the envelope is outside what one spring of this grade can give.\n\n");
    } else if design.candidates.is_empty() {
        s.push_str("No spring passes every check and the FE verification: widen the envelope or the tolerance.\n\n");
    }
    for v in design
        .candidates
        .iter()
        .filter(|v| v.corrected_from.is_some())
    {
        let _ = writeln!(
            s,
            "- rank {}: corrected by its FE rate: {}",
            v.rank,
            v.corrected_from.as_deref().unwrap_or("")
        );
    }
    for v in &design.rejected {
        let _ = writeln!(
            s,
            "- rejected by FE: d {} mm, D {:.1} mm, n {}: {}",
            sig(v.wire_diameter_mm, 3),
            v.mean_diameter_mm,
            sig(v.active_coils, 4),
            v.fe_rejection.as_deref().unwrap_or("")
        );
    }
    if let Some(z) = zeta_table(design) {
        let _ = writeln!(s, "\n## zeta of the weight mode by damping law\n\n{z}");
    }
    s.push_str("\n## What geometry can buy\n\n");
    s.push_str("At a fixed weight a stiffness-proportional law (Rayleigh beta) gives zeta ~ sqrt(K) (the paper's Table 4 shows it), a dashpot at the weight ~ 1/sqrt(K), a loss factor the same zeta whatever the spring; the candidates all have nearly the target K, so within a law their zeta differ only through the weight mode's shape (the wire's share of the modal mass), and the spread between laws is what one decay cannot decide (docs/damping.md).\n\n");
    match &design.damping {
        Some(d) => {
            let _ = writeln!(s, "{}\n", d.text);
            s.push_str("| law | best candidate | range over candidates | target vs best |\n|---|---|---|---|\n");
            for l in &d.laws {
                let _ = writeln!(
                    s,
                    "| {} | {:.5} | {:.5} to {:.5} | {:+.1} % |",
                    l.law.replace('_', " "), l.best, l.min, l.max, l.gap_percent
                );
            }
        }
        None => s.push_str(if design.material.damping.is_none() {
            "No damping law: the material is a wire grade; give a calibration.json for the zeta band.\n"
        } else {
            "No target zeta given: the table above lists each candidate's zeta under every law.\n"
        }),
    }
    let _ = writeln!(
        s,
        "\nFigure: design.png (rate against mass). Decks: decks/. Wall time {:.2} s.",
        design.elapsed_s
    );
    s
}

/// One line per candidate for the terminal.
pub fn summary(design: &Design) -> String {
    let mut s = format!(
        "{} tried, {} feasible, {} verified by FE ({} rejected)\n",
        design.tried,
        design.feasible,
        design.candidates.len(),
        design.rejected.len()
    );
    for v in &design.candidates {
        let _ = writeln!(
            s,
            "#{:<2} d {:<5} D {:<5.1} n {:<6} pitch {:.2}: R {:.4}, K_FE {:.4} ({:+.2} %), mass {:.5} kg, margin {:.3}{}",
            v.rank,
            sig(v.wire_diameter_mm, 3),
            v.mean_diameter_mm,
            sig(v.active_coils, 4),
            v.pitch_mm,
            v.rate_n_mm,
            v.fe_rate_n_mm,
            v.fe_rate_error_percent,
            v.spring_mass_kg,
            v.stress_margin,
            if v.damping_ratio.is_empty() {
                String::new()
            } else {
                format!("; zeta {}", zeta_line(&v.damping_ratio))
            }
        );
    }
    if design.tried == 0 {
        s.push_str("no spring of this grade gives the rate within the tolerance with 2 to 630 / d - 2 active coils inside the envelope (report.md)\n");
    }
    if let Some(d) = &design.damping {
        let _ = writeln!(s, "{}", d.text);
    }
    s
}
