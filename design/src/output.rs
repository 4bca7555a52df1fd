//! A design's files, one output set: `design.json` (the target, the material, the
//! search's counts, `candidates` best first, the FE-rejected ones, the damping
//! verdict), `report.md`, `design.png` (rate against mass: the feasible set, the short
//! list by handbook and by FE, the target band) and `decks/candidate_NN.dat` (each
//! short-listed spring with the weight: static at the second working force, modal).

use super::verify::{candidate_settings, candidate_state, Verified};
use super::{zeta_line, Design};
use crate::error::{Result, TuneError};
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

/// The candidates as a markdown table.
pub fn table(design: &Design) -> String {
    let mut s = String::from(
        "| rank | d (mm) | D (mm) | n | pitch (mm) | L0 (mm) | R handbook | K FE | K FE vs target | mass (kg) | stress margin | surge FE (Hz) | zeta by law |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for v in &design.candidates {
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {} | {:.2} | {:.2} | {:.4} | {:.4} | {:+.2}% | {:.5} | {:.3} | {:.1} | {} |",
            v.rank,
            v.wire_diameter_mm,
            v.mean_diameter_mm,
            v.active_coils,
            v.pitch_mm,
            v.free_length_mm,
            v.rate_n_mm,
            v.fe_rate_n_mm,
            v.fe_rate_error_percent,
            v.spring_mass_kg,
            v.stress_margin,
            v.fe.surge_frequency_hz,
            zeta_line(&v.damping_ratio)
        );
    }
    s
}

/// `report.md`.
pub fn report(design: &Design) -> String {
    let t = &design.target;
    let mut s = format!(
        "# Spring design\n\nTarget: K = {} N/mm +- {} % ({} spring(s) in parallel), working points {:?}, weight {}, objective {:?}.\n\nMaterial: {}.\n\n",
        t.rate_n_mm,
        t.rate_tolerance_percent,
        t.springs_in_parallel,
        t.working,
        design
            .weight_kg
            .map_or("not given".to_string(), |w| format!("{w} kg")),
        t.objective,
        design.material.source
    );
    let _ = writeln!(
        s,
        "Search (EN 13906-1 checks and the envelope, docs/spring-design.md): {} springs within the rate tolerance tried, {} feasible; rejections by check: {}.\n",
        design.tried,
        design.feasible,
        design
            .rejections
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        s,
        "## Candidates (FE-verified, best first)\n\n{}",
        table(design)
    );
    if design.candidates.is_empty() {
        s.push_str("No spring passes every check and the FE verification: widen the envelope or the tolerance.\n\n");
    }
    for v in &design.rejected {
        let _ = writeln!(
            s,
            "- rejected by FE: rank {} (d {} D {:.1} n {}): {}",
            v.rank,
            v.wire_diameter_mm,
            v.mean_diameter_mm,
            v.active_coils,
            v.fe_rejection.as_deref().unwrap_or("")
        );
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
                    "| {} | {:.5} | {:.5} - {:.5} | {:+.1}% |",
                    l.law, l.best, l.min, l.max, l.gap_percent
                );
            }
        }
        None => s.push_str(if design.material.damping.is_none() {
            "No damping law: the material is a wire grade; give a calibration.json for the zeta band.\n"
        } else {
            "No target zeta given: the table lists each candidate's zeta under every law.\n"
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
            "#{:<2} d {:<5} D {:<5.1} n {:<6} pitch {:.2}: R {:.4}, K_FE {:.4} ({:+.2}%), mass {:.5} kg, margin {:.3}{}",
            v.rank,
            v.wire_diameter_mm,
            v.mean_diameter_mm,
            v.active_coils,
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
    if let Some(d) = &design.damping {
        let _ = writeln!(s, "{}", d.text);
    }
    s
}
