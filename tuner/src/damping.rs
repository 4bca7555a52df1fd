//! Loop 3 of the paper's Figure 6: Rayleigh alpha and beta to the target damping ratio,
//! by grids of decay transients as the paper did, then past the grid: the valley of pairs
//! that give the target, what of it is identifiable, and where zeta comes from.
//!
//! # The grid
//! Each point is a decay run and the paper's logarithmic decrement ([`crate::decay`]),
//! never a formula. The paper's domains: 16 x 16 points in {0, ..., 0.0015} for both,
//! then alpha in {0, ..., 2} x beta in {0, ..., 0.0002}. The best point is the one whose
//! zeta is closest to the target over all domains.
//!
//! # Why a valley, and what is identifiable
//! For the axial mode (mass-normalised shape phi, circular frequency w) Rayleigh damping
//! on the wire gives, to first order,
//!
//! ```text
//! zeta = alpha d / (2 w) + beta w / 2,        d = phi^T M_wire phi
//! ```
//!
//! `phi^T K phi = w^2` (all the stiffness is the wire's), while alpha acts only on the
//! wire's mass, a share `d` (about m_wire / 3 / m_total, 0.4% here) of the modal mass:
//! the weight carries no material damping. One decay of one mode measures one number,
//! `sigma = zeta w`; every (alpha, beta) on the line `a alpha + b beta = zeta*` (a = d /
//! 2w, b = w / 2) reproduces it. So the grid's "best" point is one point of a family; what
//! the record identifies is the combination, e.g. the beta that gives zeta* alone. The
//! family is traced here with transient runs (beta solved at fixed alpha by Newton's
//! method on the measured zeta, slope b) and the plane `z0 + a alpha + b beta` is fitted to
//! every grid point, so `a` and `b` are measured, then compared with the modal values.
//! Separating alpha from beta would take a second mode or a second weight (another w).
//!
//! # Files (in the output folder)
//! `loop3_<grid>.csv` (every point), `loop3_<grid>.journal.jsonl` (resumable journal),
//! `fig8_<grid>.png` / `fig9_<grid>.png` (heat maps), `loop3_valley.csv` and
//! `loop3_valley.png`, `loop3_log.csv` (every run with its relative error: the analogue of
//! Fig. 7), `loop3/<what>.dat` (decks of the chosen point, the paper's point and the
//! valley's transients with the grid's method, and `chosen_direct.dat` when the choice is
//! checked by direct integration; a grid point's deck is the chosen deck with its DAMPING
//! line changed). `coil-solve` runs them: `chosen.dat` reproduces the grid's zeta.

use crate::decay::VelocityField;
use crate::decay::{
    measure, AxialDamping, DecayMeasure, DecayRecord, DecaySettings, Method, ModalDecay,
};
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use crate::grid::{run_grid, GridOptions, GridPoint, GridResult, GridSpec};
use crate::output::{csv, exact, OutDir};
use crate::plots::{self, HeatMapMarks, ValleyPlot};
use coil_mesher::{AnalysisKind, TransientScheme, WEIGHT_ACCEL_COLUMN};
use coil_solver::analysis::{self, CaseSolution};
use serde::Serialize;

/// Settings of loop 3.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DampingSettings {
    /// Decay-transient settings.
    pub decay: DecaySettings,
    /// The grids, in order (the paper's two domains by default).
    pub grids: Vec<GridSpec>,
    /// Alphas at which the valley's beta is solved by transient runs.
    pub valley_alphas: Vec<f64>,
    /// Relative tolerance on zeta for the valley points.
    pub valley_tolerance: f64,
    /// With the modal method: re-run the chosen point (and the paper's) by direct
    /// integration.
    pub check_direct: bool,
    /// Progress bars on stderr.
    #[serde(skip)]
    pub progress: bool,
}

impl Default for DampingSettings {
    fn default() -> Self {
        DampingSettings {
            decay: DecaySettings::default(),
            grids: vec![GridSpec::paper_domain1(), GridSpec::paper_domain2()],
            valley_alphas: vec![0.0, 0.5, 1.0, 1.5, 2.0],
            valley_tolerance: 1e-4,
            check_direct: true,
            progress: false,
        }
    }
}

/// Runs decay transients of one model (geometry, E, mass) for any alpha and beta.
#[derive(Debug)]
pub enum Simulator {
    /// Modal superposition.
    Modal(Box<ModalDecay>),
    /// Direct integration.
    Direct {
        /// The model values.
        state: SpringState,
        /// Mesh and solver settings.
        fe: FeSettings,
        /// Decay-transient settings.
        decay: DecaySettings,
    },
}

impl Simulator {
    /// Prepares runs of `state` by `decay.method`.
    pub fn new(state: &SpringState, fe: &FeSettings, decay: &DecaySettings) -> Result<Self> {
        Ok(match decay.method {
            Method::Modal => Simulator::Modal(Box::new(ModalDecay::new(state, fe, decay)?)),
            Method::Direct => {
                decay.steps()?;
                Simulator::Direct {
                    state: *state,
                    fe: fe.clone(),
                    decay: decay.clone(),
                }
            }
        })
    }

    /// The decay settings this simulator measures with.
    pub fn method(&self) -> Method {
        match self {
            Simulator::Modal(_) => Method::Modal,
            Simulator::Direct { .. } => Method::Direct,
        }
    }

    /// The weight's acceleration in a decay with (alpha, beta).
    pub fn run(&self, alpha: f64, beta: f64) -> Result<DecayRecord> {
        match self {
            Simulator::Modal(m) => m.simulate(alpha, beta),
            Simulator::Direct { state, fe, decay } => direct_decay(
                &SpringState {
                    alpha,
                    beta,
                    ..*state
                },
                fe,
                decay,
            ),
        }
    }
}

/// A decay run's deck: the transient load case with the settings' step, length, initial
/// velocity field and method (average acceleration for direct integration).
pub fn decay_model(
    state: &SpringState,
    fe: &FeSettings,
    decay: &DecaySettings,
) -> Result<coil_solver::Model> {
    let mut spec = state.spec(fe, &[AnalysisKind::Transient]);
    spec.dt_s = decay.dt_s;
    spec.duration_s = decay.duration_s;
    spec.initial_velocity_m_s = decay.initial_velocity_m_s;
    spec.initial_velocity_field = match decay.velocity_field {
        VelocityField::QuasiStatic => coil_mesher::VelocityField::QuasiStatic,
        VelocityField::Nodal => coil_mesher::VelocityField::Nodal,
    };
    spec.transient_method = match decay.method {
        Method::Direct => TransientScheme::Newmark,
        Method::Modal => TransientScheme::Modal,
    };
    spec.transient_modes = decay.modal_modes;
    Ok(spec.build()?)
}

/// A direct-integration decay run through the solver's transient load case
/// (`analysis::run`), returning the weight's axial acceleration.
pub fn direct_decay(
    state: &SpringState,
    fe: &FeSettings,
    decay: &DecaySettings,
) -> Result<DecayRecord> {
    let settings = DecaySettings {
        method: Method::Direct,
        ..decay.clone()
    };
    let model = decay_model(state, fe, &settings)?;
    let context = || {
        format!(
            "direct decay run (alpha {}, beta {})",
            state.alpha, state.beta
        )
    };
    let results = analysis::run(&model).map_err(|source| TuneError::Solve {
        context: context(),
        source: Box::new(source),
    })?;
    let history = results
        .into_iter()
        .find_map(|r| match r.solution {
            CaseSolution::Transient(t) => Some(t.history),
            _ => None,
        })
        .ok_or_else(|| TuneError::Missing {
            context: context(),
            what: "no transient case in the run".into(),
        })?;
    let accel = history
        .column(WEIGHT_ACCEL_COLUMN)
        .ok_or_else(|| TuneError::Missing {
            context: context(),
            what: format!("no column {WEIGHT_ACCEL_COLUMN} in the history"),
        })?
        .to_vec();
    Ok(DecayRecord {
        time_s: history.time_s,
        accel_m_s2: accel,
    })
}

/// The least-squares plane `zeta = z0 + a alpha + b beta` through measured points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Plane {
    /// zeta at alpha = beta = 0 (-).
    pub z0: f64,
    /// d zeta / d alpha (s).
    pub a: f64,
    /// d zeta / d beta (1/s).
    pub b: f64,
    /// RMS of the residuals relative to the RMS zeta.
    pub relative_rms_residual: f64,
    /// Points fitted.
    pub points: usize,
}

/// Fits the plane to (alpha, beta, zeta) triples (normal equations, 3 x 3, solved by
/// Cramer's rule on centred data so the columns' scales do not matter).
pub fn fit_plane(points: &[(f64, f64, f64)]) -> Option<Plane> {
    let n = points.len() as f64;
    if points.len() < 3 {
        return None;
    }
    let mean = |f: fn(&(f64, f64, f64)) -> f64| points.iter().map(f).sum::<f64>() / n;
    let (ma, mb, mz) = (mean(|p| p.0), mean(|p| p.1), mean(|p| p.2));
    let (mut saa, mut sab, mut sbb, mut saz, mut sbz) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(al, be, z) in points {
        let (x, y, w) = (al - ma, be - mb, z - mz);
        saa += x * x;
        sab += x * y;
        sbb += y * y;
        saz += x * w;
        sbz += y * w;
    }
    let det = saa * sbb - sab * sab;
    // Collinear points (det small against the product of the spreads) fix no plane.
    if det.is_nan() || det <= 1e-12 * saa * sbb {
        return None;
    }
    let a = (saz * sbb - sbz * sab) / det;
    let b = (saa * sbz - sab * saz) / det;
    let z0 = mz - a * ma - b * mb;
    let rms = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
        (points.iter().map(|p| f(p).powi(2)).sum::<f64>() / n).sqrt()
    };
    let residual = rms(&|p| p.2 - (z0 + a * p.0 + b * p.1));
    let size = rms(&|p| p.2);
    Some(Plane {
        z0,
        a,
        b,
        relative_rms_residual: if size > 0.0 { residual / size } else { 0.0 },
        points: points.len(),
    })
}

/// One finished grid, summarised.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridSummary {
    /// The grid's name.
    pub name: String,
    /// Rayleigh alpha, 1/s.
    pub alpha: String,
    /// Rayleigh beta, s.
    pub beta: String,
    /// Transient runs.
    pub runs: usize,
    /// Points run now.
    pub computed: usize,
    /// Points read from the journal.
    pub resumed: usize,
    /// Points whose decrement failed (with the reason in the CSV).
    pub failed: usize,
    /// Wall time, s.
    pub elapsed_s: f64,
    /// The grid's point closest to the target.
    pub best: GridPoint,
    /// The grid's CSV file.
    pub csv: String,
    /// The heat map, if drawn.
    pub heat_map: Option<String>,
}

/// A point of the valley, found by transient runs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ValleyPoint {
    /// Rayleigh alpha, 1/s.
    pub alpha: f64,
    /// Rayleigh beta, s.
    pub beta: f64,
    /// Measured zeta (span mean).
    pub zeta: f64,
    /// Share of zeta from alpha (a alpha / zeta, with the fitted a).
    pub alpha_share: f64,
    /// Transient runs.
    pub runs: usize,
}

/// The family of (alpha, beta) pairs with the target zeta.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Valley {
    /// The damping ratio aimed at (-).
    pub target_zeta: f64,
    /// The plane fitted to all grid points.
    pub plane: Plane,
    /// The axial mode's modal figures: d, w and the first-order slopes.
    pub modal: AxialDamping,
    /// beta with alpha = 0 (the identifiable combination expressed as a beta).
    pub beta_alone: f64,
    /// alpha with beta = 0 (alpha alone would need this).
    pub alpha_alone: f64,
    /// d beta / d alpha along the valley (s^2): -a / b.
    pub beta_per_alpha: f64,
    /// Points fitted.
    pub points: Vec<ValleyPoint>,
    /// What a single decay identifies, in words with the numbers.
    pub identifiable: String,
}

/// A checked point: zeta by the grid's method and by direct integration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CheckedPoint {
    /// Rayleigh alpha, 1/s.
    pub alpha: f64,
    /// Rayleigh beta, s.
    pub beta: f64,
    /// How decay transients run.
    pub method: Method,
    /// Damping ratio (-).
    pub zeta: f64,
    /// Damped period of the decay, s.
    pub period_s: f64,
    /// Damping ratio of the exponential fit (-).
    pub zeta_fit: f64,
    /// The same by direct integration, when run.
    pub direct: Option<DecayMeasure>,
    /// (direct - method) / method for zeta.
    pub direct_relative_difference: Option<f64>,
    /// Share of zeta from alpha at this point (fitted slopes).
    pub alpha_share: f64,
    /// Share of zeta from beta (-).
    pub beta_share: f64,
}

/// Loop 3's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DampingReport {
    /// The damping ratio aimed at (-).
    pub target_zeta: f64,
    /// How decay transients run.
    pub method: Method,
    /// The grids.
    pub grids: Vec<GridSummary>,
    /// The chosen (grid-best) point, checked.
    pub chosen: CheckedPoint,
    /// The paper's point, if given, measured the same way.
    pub paper_point: Option<CheckedPoint>,
    /// The valley past the grid, if traced.
    pub valley: Option<Valley>,
    /// Modal period (s) of the axial mode against the transient's measured period.
    pub transient_period_s: f64,
    /// Whether every grid finished (a grid stopped by `max_new_points` leaves this false
    /// and the report describes what was done so far).
    pub complete: bool,
}

fn measure_with(
    sim: &Simulator,
    decay: &DecaySettings,
    alpha: f64,
    beta: f64,
) -> Result<DecayMeasure> {
    measure(&sim.run(alpha, beta)?, decay)
}

/// Options that only concern how loop 3 runs, not what it computes.
#[derive(Debug, Clone, Default)]
pub struct RunControl {
    /// Stop each grid after this many new points (the journal keeps them).
    pub max_new_points: Option<usize>,
}

/// Loop 3 as a session: grids run one by one ([`Loop3::grid`]), then [`Loop3::finish`]
/// chooses the best point, fits the plane, traces the valley, checks the chosen point
/// and draws the figures. `calibrate` runs the settings' grids; a procedure file runs its
/// own `grid` lines; both go through these same calls, so they agree.
pub struct Loop3 {
    state: SpringState,
    fe: FeSettings,
    settings: DampingSettings,
    target_zeta: f64,
    sim: Simulator,
    modal: AxialDamping,
    fingerprint: serde_json::Value,
    results: Vec<GridResult>,
    out: Option<OutDir>,
    control: RunControl,
}

impl Loop3 {
    /// Prepares decay runs of `state` (its alpha and beta are ignored).
    pub fn new(
        state: &SpringState,
        fe: &FeSettings,
        settings: &DampingSettings,
        target_zeta: f64,
        out: Option<&OutDir>,
        control: &RunControl,
    ) -> Result<Self> {
        if !(target_zeta > 0.0 && target_zeta < 1.0) {
            return Err(TuneError::Invalid(format!(
                "loop 3: target damping ratio {target_zeta}; expected 0 < zeta < 1"
            )));
        }
        let decay = &settings.decay;
        let sim = Simulator::new(state, fe, decay)?;
        // The modal figures of the axial mode, for the valley's theory (cheap).
        let modal = match &sim {
            Simulator::Modal(m) => m.axial_damping(),
            Simulator::Direct { .. } => ModalDecay::new(state, fe, decay)?.axial_damping(),
        };
        let base = SpringState {
            alpha: 0.0,
            beta: 0.0,
            ..*state
        };
        let fingerprint = serde_json::json!({ "state": base, "fe": fe, "decay": decay });
        Ok(Loop3 {
            state: base,
            fe: fe.clone(),
            settings: settings.clone(),
            target_zeta,
            sim,
            modal,
            fingerprint,
            results: Vec::new(),
            out: out.cloned(),
            control: control.clone(),
        })
    }

    /// The decay simulator (one modal basis for every point).
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }

    /// The model (alpha, beta zeroed) the grids run on.
    pub fn state(&self) -> &SpringState {
        &self.state
    }

    /// The target damping ratio.
    pub fn target_zeta(&self) -> f64 {
        self.target_zeta
    }

    /// Changes the target (the grids do not depend on it, only the choice does).
    pub fn set_target_zeta(&mut self, target_zeta: f64) -> Result<()> {
        if !(target_zeta > 0.0 && target_zeta < 1.0) {
            return Err(TuneError::Invalid(format!(
                "loop 3: target damping ratio {target_zeta}; expected 0 < zeta < 1"
            )));
        }
        self.target_zeta = target_zeta;
        Ok(())
    }

    /// The grids run so far.
    pub fn grids(&self) -> &[GridResult] {
        &self.results
    }

    /// Runs (or resumes) one grid; its CSV and journal go to the output folder.
    pub fn grid(&mut self, spec: &GridSpec) -> Result<&GridResult> {
        if self.results.iter().any(|g| g.spec.name == spec.name) {
            return Err(TuneError::Invalid(format!(
                "loop 3: a grid named {} was already run; give this one another name",
                spec.name
            )));
        }
        let options = GridOptions {
            journal: self
                .out
                .as_ref()
                .map(|o| o.journal(format!("loop3_{}.journal.jsonl", spec.name)))
                .transpose()?,
            progress: self.settings.progress,
            max_new_points: self.control.max_new_points,
        };
        let (sim, decay) = (&self.sim, &self.settings.decay);
        let result = run_grid(spec, self.fingerprint.clone(), &options, |alpha, beta| {
            measure_with(sim, decay, alpha, beta)
        })?;
        if let Some(out) = &self.out {
            out.write(format!("loop3_{}.csv", spec.name), result.csv().as_bytes())?;
        }
        self.results.push(result);
        self.results.last().ok_or_else(|| TuneError::Missing {
            context: "loop 3".into(),
            what: "the grid just run".into(),
        })
    }

    /// The grid point closest to the target over every grid run so far.
    pub fn best(&self) -> Option<GridPoint> {
        let target = self.target_zeta;
        self.results
            .iter()
            .filter_map(|g| g.best(target))
            .min_by(|x, y| {
                let d = |p: &GridPoint| (p.zeta().unwrap_or(f64::INFINITY) - target).abs();
                d(x).total_cmp(&d(y))
            })
            .cloned()
    }

    /// Chooses the best point, fits the plane, traces the valley, measures the paper's
    /// point, checks by direct integration and writes the figures.
    pub fn finish(&self, paper_point: Option<(f64, f64)>) -> Result<DampingReport> {
        let target_zeta = self.target_zeta;
        let (sim, decay, settings, out) = (
            &self.sim,
            &self.settings.decay,
            &self.settings,
            self.out.as_ref(),
        );
        let results = &self.results;
        let complete = results.iter().all(GridResult::is_complete);
        let best = self.best().ok_or_else(|| TuneError::Missing {
            context: "loop 3".into(),
            what: "no grid point gave a damping ratio (no grid run, or every decrement failed; \
                   see the grid CSVs)"
                .into(),
        })?;
        let triples: Vec<(f64, f64, f64)> = results
            .iter()
            .flat_map(|g| g.points.iter())
            .filter_map(|p| p.zeta().map(|z| (p.alpha, p.beta, z)))
            .collect();
        let plane = fit_plane(&triples);

        let grids = self.grid_summaries(&best, plane, paper_point)?;

        let state = &self.state;
        let fe = &self.fe;
        let shares = |alpha: f64, beta: f64, zeta: f64| match plane {
            Some(p) if zeta > 0.0 => (p.a * alpha / zeta, p.b * beta / zeta),
            _ => (f64::NAN, f64::NAN),
        };
        let check =
            |alpha: f64, beta: f64, measured: Option<DecayMeasure>| -> Result<CheckedPoint> {
                let m = match measured {
                    Some(m) => m,
                    None => measure_with(sim, decay, alpha, beta)?,
                };
                let direct = if sim.method() == Method::Modal && settings.check_direct {
                    let direct_settings = DecaySettings {
                        method: Method::Direct,
                        ..decay.clone()
                    };
                    Some(measure(
                        &direct_decay(
                            &SpringState {
                                alpha,
                                beta,
                                ..*state
                            },
                            fe,
                            &direct_settings,
                        )?,
                        decay,
                    )?)
                } else {
                    None
                };
                let (alpha_share, beta_share) = shares(alpha, beta, m.zeta_mean);
                Ok(CheckedPoint {
                    alpha,
                    beta,
                    method: sim.method(),
                    zeta: m.zeta_mean,
                    zeta_fit: m.zeta_fit,
                    period_s: m.period_s,
                    direct,
                    direct_relative_difference: direct
                        .map(|d| (d.zeta_mean - m.zeta_mean) / m.zeta_mean),
                    alpha_share,
                    beta_share,
                })
            };
        let chosen = check(best.alpha, best.beta, best.measure)?;
        let paper = match paper_point {
            Some((a, b)) => Some(check(a, b, None)?),
            None => None,
        };

        let valley = match plane {
            Some(plane) if plane.b > 0.0 && plane.a.is_finite() => Some(trace_valley(
                sim,
                decay,
                settings,
                target_zeta,
                plane,
                self.modal,
            )?),
            _ => None,
        };

        if let Some(out) = out {
            if let Some(v) = &valley {
                out.write(
                    "loop3_valley.csv",
                    csv(
                        &["alpha", "beta", "zeta_mean", "alpha_share", "runs"],
                        v.points.iter().map(|p| {
                            vec![
                                exact(p.alpha),
                                exact(p.beta),
                                exact(p.zeta),
                                exact(p.alpha_share),
                                p.runs.to_string(),
                            ]
                        }),
                    )
                    .as_bytes(),
                )?;
                let measured: Vec<(f64, f64, f64)> =
                    v.points.iter().map(|p| (p.alpha, p.beta, p.zeta)).collect();
                let alpha_max = v.points.iter().fold(best.alpha, |m, p| m.max(p.alpha));
                plots::valley_figure(
                    &ValleyPlot {
                        target_zeta,
                        plane: (v.plane.z0, v.plane.a, v.plane.b),
                        points: &measured,
                        alpha_max: alpha_max.max(1e-6),
                    },
                    &out.staged("loop3_valley.png")?,
                )?;
            }
            self.write_decks(
                out,
                &best,
                paper_point,
                valley.as_ref(),
                chosen.direct.is_some(),
            )?;
            write_log(out, results, valley.as_ref(), target_zeta)?;
        }

        Ok(DampingReport {
            target_zeta,
            method: sim.method(),
            grids,
            chosen,
            paper_point: paper,
            valley,
            transient_period_s: best.measure.map_or(f64::NAN, |m| m.period_s),
            complete,
        })
    }

    /// Each grid's summary, with its heat map drawn when there is an output folder.
    fn grid_summaries(
        &self,
        best: &GridPoint,
        plane: Option<Plane>,
        paper_point: Option<(f64, f64)>,
    ) -> Result<Vec<GridSummary>> {
        let (target_zeta, out) = (self.target_zeta, self.out.as_ref());
        let mut grids = Vec::new();
        for (index, result) in self.results.iter().enumerate() {
            let spec = &result.spec;
            let heat_map = match out {
                Some(out) => {
                    let name = match index {
                        0 => format!("fig8_{}.png", spec.name),
                        1 => format!("fig9_{}.png", spec.name),
                        _ => format!("fig_{}.png", spec.name),
                    };
                    let marks = HeatMapMarks {
                        target_zeta,
                        paper: paper_point,
                        valley: plane.map(|p| (p.z0, p.a, p.b)),
                    };
                    plots::heat_map(result, &marks, &out.staged(&name)?)?;
                    Some(name)
                }
                None => None,
            };
            grids.push(GridSummary {
                name: spec.name.clone(),
                alpha: spec.alpha.to_string(),
                beta: spec.beta.to_string(),
                runs: result.points.len(),
                computed: result.computed,
                resumed: result.resumed,
                failed: result.points.iter().filter(|p| p.measure.is_none()).count(),
                elapsed_s: result.elapsed_s,
                best: result
                    .best(target_zeta)
                    .cloned()
                    .unwrap_or_else(|| best.clone()),
                csv: format!("loop3_{}.csv", spec.name),
                heat_map,
            });
        }
        Ok(grids)
    }

    /// Writes the decks of the transients that matter (`loop3/*.dat`).
    fn write_decks(
        &self,
        out: &OutDir,
        best: &GridPoint,
        paper_point: Option<(f64, f64)>,
        valley: Option<&Valley>,
        chosen_direct: bool,
    ) -> Result<()> {
        let (state, fe, decay) = (&self.state, &self.fe, &self.settings.decay);
        // Decks of the transients that matter: the chosen point, the paper's point,
        // the valley's points (a grid point's deck is the chosen one with its DAMPING
        // line changed).
        let mut decks = vec![("chosen".to_string(), best.alpha, best.beta)];
        if let Some((a, b)) = paper_point {
            decks.push(("paper_point".to_string(), a, b));
        }
        if let Some(v) = valley {
            for (k, p) in v.points.iter().enumerate() {
                decks.push((format!("valley_{:02}", k + 1), p.alpha, p.beta));
            }
        }
        for (name, alpha, beta) in decks {
            let model = decay_model(
                &SpringState {
                    alpha,
                    beta,
                    ..*state
                },
                fe,
                decay,
            )?;
            out.write(
                format!("loop3/{name}.dat"),
                coil_solver::deck::write(&model).as_bytes(),
            )?;
        }
        if chosen_direct {
            let direct = DecaySettings {
                method: Method::Direct,
                ..decay.clone()
            };
            let at = SpringState {
                alpha: best.alpha,
                beta: best.beta,
                ..*state
            };
            out.write(
                "loop3/chosen_direct.dat",
                coil_solver::deck::write(&decay_model(&at, fe, &direct)?).as_bytes(),
            )?;
        }
        Ok(())
    }
}

/// Writes `loop3_log.csv`, the analogue of Fig. 7: every run of loop 3 with its relative
/// error, then the valley's points.
fn write_log(
    out: &OutDir,
    results: &[GridResult],
    valley: Option<&Valley>,
    target_zeta: f64,
) -> Result<()> {
    // The loop's log, the analogue of Fig. 7: every run with its relative error.
    let mut rows = Vec::new();
    for g in results {
        for p in &g.points {
            rows.push(vec![
                g.spec.name.clone(),
                exact(p.alpha),
                exact(p.beta),
                p.zeta().map_or(String::new(), exact),
                p.zeta()
                    .map_or(String::new(), |z| exact((z - target_zeta) / target_zeta)),
            ]);
        }
    }
    if let Some(v) = valley {
        for p in &v.points {
            rows.push(vec![
                "valley".into(),
                exact(p.alpha),
                exact(p.beta),
                exact(p.zeta),
                exact((p.zeta - target_zeta) / target_zeta),
            ]);
        }
    }
    out.write(
        "loop3_log.csv",
        csv(
            &["stage", "alpha", "beta", "zeta_mean", "relative_error"],
            rows,
        )
        .as_bytes(),
    )?;
    Ok(())
}

/// Loop 3 with the settings' grids: sets `state.alpha` and `state.beta` to the best grid
/// point and reports the valley. `paper_point` is measured alongside when given.
pub fn tune_damping(
    state: &mut SpringState,
    fe: &FeSettings,
    settings: &DampingSettings,
    target_zeta: f64,
    paper_point: Option<(f64, f64)>,
    out: Option<&OutDir>,
    control: &RunControl,
) -> Result<DampingReport> {
    if settings.grids.is_empty() {
        return Err(TuneError::Invalid("loop 3: no grid to run".into()));
    }
    let mut session = Loop3::new(state, fe, settings, target_zeta, out, control)?;
    for spec in &settings.grids {
        session.grid(spec)?;
    }
    let report = session.finish(paper_point)?;
    state.alpha = report.chosen.alpha;
    state.beta = report.chosen.beta;
    Ok(report)
}

/// Solves beta on the valley at each of `settings.valley_alphas` by Newton's method on
/// the measured zeta (slope b of the fitted plane; zeta is linear in beta, so 1 or 2
/// runs), then states what the record identifies.
fn trace_valley(
    sim: &Simulator,
    decay: &DecaySettings,
    settings: &DampingSettings,
    target: f64,
    plane: Plane,
    modal: AxialDamping,
) -> Result<Valley> {
    let mut points = Vec::new();
    for &alpha in &settings.valley_alphas {
        let mut beta = (target - plane.z0 - plane.a * alpha) / plane.b;
        if beta.is_nan() || beta < 0.0 {
            continue;
        }
        let mut runs = 0;
        let mut zeta = f64::NAN;
        for _ in 0..8 {
            zeta = measure_with(sim, decay, alpha, beta)?.zeta_mean;
            runs += 1;
            if ((zeta - target) / target).abs() <= settings.valley_tolerance {
                break;
            }
            beta += (target - zeta) / plane.b;
        }
        points.push(ValleyPoint {
            alpha,
            beta,
            zeta,
            alpha_share: plane.a * alpha / zeta,
            runs,
        });
    }
    let beta_alone = (target - plane.z0) / plane.b;
    let mut alpha_alone = (target - plane.z0) / plane.a;
    // The other end of the family: alpha alone (beta = 0), solved the same way.
    if plane.a > 0.0 && alpha_alone.is_finite() && alpha_alone > 0.0 && alpha_alone < 1e4 {
        let mut runs = 0;
        let mut zeta = f64::NAN;
        for _ in 0..8 {
            zeta = measure_with(sim, decay, alpha_alone, 0.0)?.zeta_mean;
            runs += 1;
            if ((zeta - target) / target).abs() <= settings.valley_tolerance {
                break;
            }
            alpha_alone += (target - zeta) / plane.a;
        }
        points.push(ValleyPoint {
            alpha: alpha_alone,
            beta: 0.0,
            zeta,
            alpha_share: plane.a * alpha_alone / zeta,
            runs,
        });
    }
    let identifiable = format!(
        "One free decay of the axial mode measures one number, sigma = zeta w = {sigma:.5} 1/s. \
         Every (alpha, beta) with {a:.4e} alpha + {b:.4} beta = {target} gives it: alpha acts \
         only through the wire's share d = {d:.4} of the modal mass (the weight carries no \
         material damping), so one unit of alpha (1/s) is worth {ratio:.3e} s of beta. The \
         record identifies the combination, e.g. beta = {beta_alone:.5e} s with alpha = 0, or \
         alpha = {alpha_alone:.1} 1/s with beta = 0; the paper's whole alpha range 0-2 moves \
         zeta by {span:.2e} ({span_pct:.1}% of the target). Separating alpha from beta needs \
         another frequency: a second mode or a second weight. Modal slopes: d zeta/d alpha = \
         d/2w = {ma:.4e} s, d zeta/d beta = w/2 = {mb:.4} 1/s (fitted: {a:.4e}, {b:.4}).",
        sigma = target * modal.omega_rad_s,
        a = plane.a,
        b = plane.b,
        d = modal.wire_mass_share,
        ratio = plane.a / plane.b,
        span = 2.0 * plane.a,
        span_pct = 200.0 * plane.a / target,
        ma = modal.dzeta_dalpha,
        mb = modal.dzeta_dbeta,
    );
    Ok(Valley {
        target_zeta: target,
        plane,
        modal,
        beta_alone,
        alpha_alone,
        beta_per_alpha: -plane.a / plane.b,
        points,
        identifiable,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_fit_recovers_a_plane() {
        let pts: Vec<(f64, f64, f64)> = (0..4)
            .flat_map(|i| (0..3).map(move |j| (i as f64 * 0.5, j as f64 * 1e-4)))
            .map(|(a, b)| (a, b, 1e-6 + 6.8e-5 * a + 13.6 * b))
            .collect();
        let p = fit_plane(&pts).unwrap();
        assert!(
            (p.a - 6.8e-5).abs() < 1e-15 && (p.b - 13.6).abs() < 1e-9,
            "{p:?}"
        );
        assert!((p.z0 - 1e-6).abs() < 1e-15);
        assert!(p.relative_rms_residual < 1e-12);
        assert!(fit_plane(&pts[..2]).is_none());
        // All points on one line: the plane is not determined.
        let line: Vec<_> = (0..5).map(|i| (i as f64, 0.0, i as f64)).collect();
        assert!(fit_plane(&line).is_none());
    }
}
