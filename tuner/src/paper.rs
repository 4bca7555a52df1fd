//! `coil-tune paper`: the README's main job. Calibrates the paper's case (Figure 6),
//! sweeps Table 4's variants with the validated material, and measures what the paper's
//! calibration hides: the mesh bias absorbed by E, and the (alpha, beta) family behind
//! the grid's "best" point. Writes `report.md`, `report.json` and the figures (Figs. 7-10
//! analogues) and prints Tables 3 and 4 beside the paper's values.
//!
//! # What is compared
//! - Table 3: K from the static run at the calibrated E; zeta and T of the validated
//!   model's decay record, by direct integration (the default modal grid's optimum is
//!   re-run by direct integration; `--method direct` runs every point so); alpha, beta
//!   the grid's best point; the weight's mass from loop 2.
//! - Table 4: K and zeta of each variant with the validated E, mass, alpha and beta, by
//!   direct integration (unless `check_direct` is off): the default and `--method
//!   direct` then print the same tables whenever their grids choose the same point.
//! - Mesh bias: loop 1 at 8, 16, 24, 48, 96 elements per coil. The chord polygon's error
//!   in K is O(theta^2) for an element angle theta = 2 pi / n, so the tuned E converges
//!   as 1/n^2; E at infinitely many elements is Richardson's `E_96 + (E_96 - E_48) / 3`,
//!   and the observed order from 24/48/96 is reported to check the assumption.

use crate::calibrate::{calibrate, CalibrateSettings, Targets};
use crate::case::{read_case, read_variants, MeasuredCase, VariantsFile};
use crate::damping::{direct_decay, RunControl, Simulator};
use crate::decay::{DecayRecord, DecaySettings, Method};
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use crate::loops::tune_youngs_modulus;
use crate::output::OutDir;
pub use crate::report::{
    FamilyMember, MeshRow, MeshStudy, PaperReport, Table3, Table3Errors, Table3Paper, Timings,
};
use crate::sweep::{sweep, Sweep};
use std::path::{Path, PathBuf};

/// Elements per coil of the mesh study.
pub const MESH_STUDY: [u32; 5] = [8, 16, 24, 48, 96];

/// Inputs of the paper command.
#[derive(Debug, Clone)]
pub struct PaperOptions {
    /// The measured case (a folder with case.json, or the file).
    pub case: PathBuf,
    /// The variants file (the paper's Table 4).
    pub variants: PathBuf,
    /// The settings.
    pub settings: CalibrateSettings,
    /// Run control.
    pub control: RunControl,
}

/// The paper's Table 3 (and Table 2) values, as the case gives them.
fn table3_paper(case: &MeasuredCase, targets: &Targets) -> Table3Paper {
    let paper = case.paper.clone().unwrap_or_default();
    Table3Paper {
        youngs_modulus_mpa: paper.youngs_modulus_mpa,
        stiffness_n_mm: targets.stiffness_n_mm,
        damping_ratio: targets.damping_ratio,
        period_s: targets.period_s,
        alpha: paper.rayleigh_alpha,
        beta: paper.rayleigh_beta,
        fe_stiffness_n_mm: paper.stiffness_n_mm,
        fe_damping_ratio: paper.damping_ratio,
        stiffness_iterations: paper.stiffness_iterations,
        mass_iterations: paper.mass_iterations,
    }
}

/// Fig. 10's analogue: the reference decay (measured, or the paper's model) beside the
/// validated model's.
fn fig10(
    state: &SpringState,
    settings: &CalibrateSettings,
    (reference_label, reference): (&str, &DecayRecord),
    validated_record: &DecayRecord,
    period_s: f64,
    out: &OutDir,
) -> Result<()> {
    let decay = &settings.damping.decay;
    let model_label = format!(
        "coil: alpha = {}, beta = {} ({})",
        state.alpha,
        state.beta,
        if decay.method == Method::Direct || settings.damping.check_direct {
            "direct integration"
        } else {
            "modal superposition"
        }
    );
    crate::plots::decay_figure(
        &crate::plots::DecayTrace {
            label: reference_label,
            time_s: &reference.time_s,
            accel_m_s2: &reference.accel_m_s2,
        },
        &crate::plots::DecayTrace {
            label: &model_label,
            time_s: &validated_record.time_s,
            accel_m_s2: &validated_record.accel_m_s2,
        },
        period_s,
        &out.staged("fig10_decay.png")?,
    )?;
    Ok(())
}

/// Loop 1 at each discretisation of [`MESH_STUDY`].
pub fn mesh_study(
    case: &MeasuredCase,
    target_k: f64,
    paper_e: f64,
    settings: &CalibrateSettings,
) -> Result<MeshStudy> {
    let rows = MESH_STUDY
        .iter()
        .map(|&n| -> Result<MeshRow> {
            let fe = FeSettings {
                elements_per_coil: n,
                ..settings.fe.clone()
            };
            let mut state = SpringState::nominal(case);
            state.youngs_modulus_mpa = paper_e;
            let (k_paper, _) = crate::fe::static_stiffness(&state, &fe)?;
            let report = tune_youngs_modulus(
                &mut state,
                &fe,
                target_k,
                settings.stiffness_tolerance,
                None,
            )?;
            Ok(MeshRow {
                elements_per_coil: n,
                stiffness_at_paper_e_n_mm: k_paper,
                tuned_youngs_modulus_mpa: report.value,
                iterations: report.iterations.len(),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let e = |n: u32| {
        rows.iter()
            .find(|r| r.elements_per_coil == n)
            .map_or(f64::NAN, |r| r.tuned_youngs_modulus_mpa)
    };
    let converged = e(96) + (e(96) - e(48)) / 3.0;
    let observed_order = ((e(24) - e(48)) / (e(48) - e(96))).log2();
    // E(n) = E_inf - c / n^2 is monotone in n: find the bracket and interpolate in 1/n^2.
    let matching = rows.windows(2).find_map(|w| {
        let (lo, hi) = (w[0].tuned_youngs_modulus_mpa, w[1].tuned_youngs_modulus_mpa);
        if (lo - paper_e) * (hi - paper_e) <= 0.0 && hi != lo {
            let (x0, x1) = (
                1.0 / f64::from(w[0].elements_per_coil).powi(2),
                1.0 / f64::from(w[1].elements_per_coil).powi(2),
            );
            let x = x0 + (paper_e - lo) * (x1 - x0) / (hi - lo);
            Some(1.0 / x.sqrt())
        } else {
            None
        }
    });
    Ok(MeshStudy {
        paper_youngs_modulus_mpa: paper_e,
        rows,
        elements_per_coil_matching_paper: matching,
        converged_youngs_modulus_mpa: converged,
        observed_order,
    })
}

/// The reference decay for Fig. 10: the case's first measured record, or the damped
/// oscillation its reduced figures describe (T and zeta of the experiment), sampled like
/// the model's record.
fn reference_decay(
    case: &MeasuredCase,
    targets: &Targets,
    initial_velocity_m_s: f64,
    model: &DecayRecord,
) -> Result<(String, DecayRecord)> {
    if let Some(signal) = case.decay_records()?.into_iter().next() {
        let label = format!("measured: {}", signal.source().display());
        let (time_s, accel_m_s2) = signal.into_parts();
        return Ok((label, DecayRecord { time_s, accel_m_s2 }));
    }
    let zeta = targets.damping_ratio;
    let omega_d = std::f64::consts::TAU / targets.period_s;
    let omega_n = omega_d / (1.0 - zeta * zeta).sqrt();
    let sigma = zeta * omega_n;
    // The weight leaves its rest position with the model's initial velocity v0:
    // x = (v0 / w_d) e^{-sigma t} sin(w_d t), a = x''.
    let scale = initial_velocity_m_s / omega_d;
    let accel: Vec<f64> = model
        .time_s
        .iter()
        .map(|&t| {
            let (s, c) = (omega_d * t).sin_cos();
            scale
                * (-sigma * t).exp()
                * ((sigma * sigma - omega_d * omega_d) * s - 2.0 * sigma * omega_d * c)
        })
        .collect();
    Ok((
        format!(
            "experiment: a damped oscillation with its T = {} s and zeta = {} (the record is not published)",
            targets.period_s, zeta
        ),
        DecayRecord {
            time_s: model.time_s.clone(),
            accel_m_s2: accel,
        },
    ))
}

/// Runs the whole paper study into `out`.
pub fn run_paper(options: &PaperOptions, out: &OutDir) -> Result<PaperReport> {
    let start = std::time::Instant::now();
    let case = read_case(&options.case)?;
    let variants: VariantsFile = read_variants(&options.variants)?;
    let targets = Targets::of(&case)?;
    let settings = &options.settings;

    let calibration = calibrate(&case, &targets, settings, Some(out), &options.control)?;
    let calibration_s = start.elapsed().as_secs_f64();
    let grid_s: f64 = calibration.damping.grids.iter().map(|g| g.elapsed_s).sum();
    let state = calibration.state;
    let decay = &settings.damping.decay;

    // The validated model's decay: direct integration (the check of the chosen point).
    let direct_settings = DecaySettings {
        method: Method::Direct,
        ..decay.clone()
    };
    let validated_record = if decay.method == Method::Direct || settings.damping.check_direct {
        direct_decay(&state, &settings.fe, &direct_settings)?
    } else {
        Simulator::new(&state, &settings.fe, decay)?.run(state.alpha, state.beta)?
    };
    let validated = crate::decay::measure(&validated_record, decay)?;

    let sweep_start = std::time::Instant::now();
    // Tables come from direct integration whenever the grid's optimum is checked so:
    // modal superposition is the grid's fast path, not the reported model.
    let table_decay = if settings.damping.check_direct {
        &direct_settings
    } else {
        decay
    };
    let table4_sweep: Sweep = sweep(&state, &variants, &settings.fe, table_decay)?;
    let sweep_s = sweep_start.elapsed().as_secs_f64();

    // Predictions along the valley: the grid's choice, the paper's point and the
    // family's ends within the grid, by modal superposition.
    let modal_decay = DecaySettings {
        method: Method::Modal,
        ..decay.clone()
    };
    let mut members: Vec<(String, f64, f64)> =
        vec![("coil's grid choice".into(), state.alpha, state.beta)];
    if let Some(v) = &calibration.damping.valley {
        for p in v.points.iter().filter(|p| p.alpha == 0.0 || p.alpha == 2.0) {
            members.push((format!("valley, alpha = {}", p.alpha), p.alpha, p.beta));
        }
    }
    if let Some(p) = &calibration.damping.paper_point {
        members.push(("the paper's point".into(), p.alpha, p.beta));
    }
    let mut family = Vec::new();
    for (label, alpha, beta) in members {
        let material = SpringState {
            alpha,
            beta,
            ..state
        };
        let s = sweep(&material, &variants, &settings.fe, &modal_decay)?;
        let base = Simulator::new(&material, &settings.fe, &modal_decay)?.run(alpha, beta)?;
        family.push(FamilyMember {
            label,
            alpha,
            beta,
            base_damping_ratio: crate::decay::measure(&base, &modal_decay)?.zeta_mean,
            variants: s
                .variants
                .iter()
                .map(|v| (v.name.clone(), v.damping_ratio, v.damping_relative_error))
                .collect(),
        });
    }

    // The band of damping laws one decay allows, with its figure.
    let damping_band =
        crate::band::band(&state, &variants, &settings.fe, targets.damping_ratio, 0.03)?;
    crate::plots::band_figure(&damping_band, &out.path("damping_band.png"))?;

    let mesh_start = std::time::Instant::now();
    let paper_e = case
        .paper
        .as_ref()
        .and_then(|p| p.youngs_modulus_mpa)
        .unwrap_or(calibration.state.youngs_modulus_mpa);
    let mesh = mesh_study(&case, targets.stiffness_n_mm, paper_e, settings)?;
    let mesh_study_s = mesh_start.elapsed().as_secs_f64();

    // Fig. 10: the reference, the simulation over it and the residual.
    let (reference_label, reference) = reference_decay(
        &case,
        &targets,
        decay.initial_velocity_m_s,
        &validated_record,
    )?;
    fig10(
        &state,
        settings,
        (&reference_label, &reference),
        &validated_record,
        targets.period_s,
        out,
    )?;

    let table3 = Table3 {
        youngs_modulus_mpa: state.youngs_modulus_mpa,
        stiffness_n_mm: calibration.stiffness.result,
        damping_ratio: validated.zeta_mean,
        period_s: validated.period_s,
        alpha: state.alpha,
        beta: state.beta,
        mass_kg: state.mass_kg,
    };
    let table3_paper = table3_paper(&case, &targets);
    let rel = |a: f64, b: f64| (a - b) / b;
    let report = PaperReport {
        case: case.name.clone(),
        table1: case.tested_springs.clone(),
        method: decay.method,
        table3,
        table3_paper,
        table3_relative_error: Table3Errors {
            stiffness: rel(table3.stiffness_n_mm, targets.stiffness_n_mm),
            damping_ratio: rel(table3.damping_ratio, targets.damping_ratio),
            period: rel(table3.period_s, targets.period_s),
        },
        table4: table4_sweep.variants.clone(),
        family,
        damping_band,
        mesh_study: mesh,
        calibration,
        timings: Timings {
            calibration_s,
            grid_s,
            sweep_s,
            mesh_study_s,
            total_s: start.elapsed().as_secs_f64(),
        },
    };
    out.write("sweep.csv", table4_sweep.csv().as_bytes())?;
    let json = serde_json::to_string_pretty(&report)
        .map_err(|e| TuneError::Invalid(format!("report.json: {e}")))?;
    out.write("report.json", json.as_bytes())?;
    out.write("report.md", crate::report::markdown(&report).as_bytes())?;
    Ok(report)
}

/// Default paths of the paper's case, relative to the working directory.
pub fn default_case() -> PathBuf {
    Path::new("cases").join("160ect")
}
