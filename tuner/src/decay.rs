//! Free-decay runs and their logarithmic decrement: the measurement behind Loop 3.
//!
//! A decay run gives the weight an initial axial velocity and records its axial
//! acceleration (m/s^2, + away from the base), as the paper's accelerometer did; the
//! damping ratio is then the paper's estimator, the logarithmic decrement over every
//! 10th crest averaged over the spans (Eqs. 2-3, `coil_postproc::decrement`), never a
//! formula in alpha and beta.
//!
//! # Two ways to run the transient
//! - [`Method::Modal`]: modal superposition on the lowest `modal_modes` modes of the
//!   undamped model, each integrated exactly (`coil_solver::integrate::modal`, Nigam &
//!   Jennings). The modes do not depend on alpha and beta, so one eigensolution serves a
//!   whole grid ([`ModalDecay`]). Modal damping ratios are `zeta_i = phi_i^T C phi_i /
//!   (2 w_i)` with `C = alpha M_wire + beta K` (mass-normalised shapes): `phi_i^T K phi_i =
//!   w_i^2` exactly, and `d_i = phi_i^T M_wire phi_i` is computed once. The beta part is
//!   classical damping and exact; the alpha part acts on the wire only, not on the weight,
//!   so it couples modes; the diagonal keeps its first-order effect on each mode and drops
//!   coupling terms of relative size alpha d_ij / (w_i - w_j), tiny here. The grid's
//!   optimum is checked by direct integration for that reason.
//! - [`Method::Direct`]: the full model with `C` as assembled, integrated by the
//!   solver's transient load case (average acceleration), one run per point.
//!
//! Units: s, m/s^2 for the records; alpha in 1/s, beta in s.

use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use coil_mesher::{AnalysisKind, WEIGHT_NODE};
use coil_postproc::decrement::{self, DecrementOptions, Lowpass};
use coil_postproc::signal::Signal;
use coil_solver::analysis::{modal, System};
use coil_solver::integrate::modal::{integrate_modal, ModalBasis, ModalState};
use coil_solver::linalg::sym_upper_matvec;
use coil_solver::model::units;
use faer::Mat;
use serde::{Deserialize, Serialize};

/// How a decay transient is integrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Modal superposition, modes computed once per model.
    Modal,
    /// Direct integration of the full model (average acceleration).
    Direct,
}

impl std::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "modal" => Ok(Method::Modal),
            "direct" => Ok(Method::Direct),
            other => Err(format!("`{other}`; expected `modal` or `direct`")),
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Modal => "modal",
            Method::Direct => "direct",
        })
    }
}

/// How the weight's initial velocity is spread over the spring (as the solver's
/// `INITIAL VEL`): the quasi-static profile (no velocity jump, so no stiff-mode ripple),
/// or the weight alone (a jump against a spring at rest).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum VelocityField {
    /// Initial velocity spread along the spring by the static shape.
    QuasiStatic,
    /// Initial velocity on the weight alone.
    Nodal,
}

/// Settings of a decay run and of its decrement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DecaySettings {
    /// How decay transients run.
    pub method: Method,
    /// Time step (s); also the record's sampling step.
    pub dt_s: f64,
    /// Record length (s).
    pub duration_s: f64,
    /// The weight's initial axial velocity (m/s).
    pub initial_velocity_m_s: f64,
    /// How the initial velocity is spread over the spring.
    pub velocity_field: VelocityField,
    /// Modes kept by the modal method.
    pub modal_modes: u32,
    /// Crest intervals per decrement span (the paper: every 10th peak).
    pub every: usize,
    /// Zero-phase low-pass before crest picking (Hz); removes the spring's own modes
    /// without biasing zeta (docs/postproc.md).
    pub lowpass_hz: Option<f64>,
}

impl Default for DecaySettings {
    fn default() -> Self {
        DecaySettings {
            method: Method::Modal,
            // 115 samples per period of the paper's 4.35 Hz mode. Average acceleration's
            // period error (w dt)^2/12 is 2.5e-4 and its zeta error -5e-4 (relative) at
            // this step; halving it doubles the 697 direct runs' cost for 4e-4 on zeta.
            dt_s: 2e-3,
            duration_s: 6.0,
            initial_velocity_m_s: 0.1,
            velocity_field: VelocityField::QuasiStatic,
            modal_modes: 20,
            every: 10,
            lowpass_hz: Some(30.0),
        }
    }
}

impl DecaySettings {
    /// Number of steps of a run.
    pub fn steps(&self) -> Result<usize> {
        let n = (self.duration_s / self.dt_s).round();
        // 1e7 samples of a record are 80 MB; more is a typo (dt in ms?), not a study.
        if !(self.dt_s > 0.0 && self.dt_s.is_finite() && (1.0..=1e7).contains(&n)) {
            return Err(TuneError::Invalid(format!(
                "decay run: dt = {} s, duration = {} s; expected 0 < dt <= duration and at most 1e7 steps",
                self.dt_s, self.duration_s
            )));
        }
        Ok(n as usize)
    }

    fn options(&self) -> DecrementOptions {
        DecrementOptions {
            every: self.every,
            lowpass: self.lowpass_hz.map(|cutoff_hz| Lowpass {
                cutoff_hz,
                order: 4,
            }),
            ..DecrementOptions::default()
        }
    }
}

/// The weight's axial acceleration over time.
#[derive(Debug, Clone, PartialEq)]
pub struct DecayRecord {
    /// Time, s.
    pub time_s: Vec<f64>,
    /// Acceleration, m/s^2.
    pub accel_m_s2: Vec<f64>,
}

/// What the decrement measured on a record.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DecayMeasure {
    /// The paper's estimator: mean of the span decrements' zeta (Eqs. 2-3).
    pub zeta_mean: f64,
    /// Weighted exponential fit of all crests.
    pub zeta_fit: f64,
    /// Damped period from the crest times (s).
    pub period_s: f64,
    /// Crests used.
    pub crests: usize,
}

/// The decrement of a record.
pub fn measure(record: &DecayRecord, settings: &DecaySettings) -> Result<DecayMeasure> {
    let r = Signal::new(record.time_s.clone(), record.accel_m_s2.clone())
        .and_then(|signal| decrement::analyze(&signal, &settings.options()))
        .map_err(|source| TuneError::Post {
            context: "logarithmic decrement of the weight's acceleration".into(),
            source,
        })?;
    Ok(DecayMeasure {
        zeta_mean: r.zeta_mean,
        zeta_fit: r.zeta_fit,
        period_s: r.period_s,
        crests: r.peak_count,
    })
}

/// The free equation of the weight's axial DOF.
fn weight_equation(system: &System<'_>) -> Result<usize> {
    (0..system.dim())
        .find(|&e| system.dofs.free_label(e) == (WEIGHT_NODE, 3))
        .ok_or_else(|| TuneError::Missing {
            context: "decay run".into(),
            what: "the weight's axial DOF is not free".into(),
        })
}

/// Modal data of one model (geometry, E, mass), reused for any alpha and beta.
#[derive(Debug, Clone)]
pub struct ModalDecay {
    shapes: Mat<f64>,
    omega: Vec<f64>,
    /// `phi_i^T M_wire phi_i`: the wire's share of each mode's unit modal mass.
    wire_mass: Vec<f64>,
    /// Initial modal velocities for the weight's initial velocity (mm/s).
    initial_qd: Vec<f64>,
    weight: usize,
    steps: usize,
    dt_s: f64,
}

/// The axial mode's figures behind the valley: `zeta = alpha d / (2 w) + beta w / 2`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AxialDamping {
    /// Angular frequency of the axial mode, rad/s.
    pub omega_rad_s: f64,
    /// `d = phi^T M_wire phi` for the mass-normalised axial mode (-).
    pub wire_mass_share: f64,
    /// `d zeta / d alpha = d / (2 w)` (s).
    pub dzeta_dalpha: f64,
    /// `d zeta / d beta = w / 2` (1/s).
    pub dzeta_dbeta: f64,
}

impl ModalDecay {
    /// Computes the modes of `state` (alpha, beta ignored) and the initial conditions.
    pub fn new(state: &SpringState, fe: &FeSettings, decay: &DecaySettings) -> Result<Self> {
        let steps = decay.steps()?;
        // alpha = 1, beta = 0 makes the assembled C equal to the wire's mass matrix.
        let wire_only = SpringState {
            alpha: 1.0,
            beta: 0.0,
            ..*state
        };
        let model = wire_only.model(fe, &[AnalysisKind::Modal])?;
        let solve_err = |source| TuneError::Solve {
            context: "modal basis of the decay runs".into(),
            source: Box::new(source),
        };
        let system = System::new(&model).map_err(solve_err)?;
        let factor = system.factor_stiffness().map_err(solve_err)?;
        let n_modes = (decay.modal_modes as usize).min(system.dim());
        let solution = modal::solve(&system, &factor, "decay modes", n_modes).map_err(solve_err)?;
        let n = system.dim();
        let shapes = Mat::from_fn(n, solution.modes.len(), |i, j| {
            solution.modes[j].shape_free[i]
        });
        let omega: Vec<f64> = solution
            .modes
            .iter()
            .map(|m| m.omega_squared.sqrt())
            .collect();
        let mut c_phi = vec![0.0; n];
        let wire_mass = solution
            .modes
            .iter()
            .map(|m| {
                c_phi.iter_mut().for_each(|x| *x = 0.0);
                sym_upper_matvec(system.damping.as_ref(), &m.shape_free, 1.0, &mut c_phi);
                m.shape_free.iter().zip(&c_phi).map(|(a, b)| a * b).sum()
            })
            .collect();
        let weight = weight_equation(&system)?;
        let v_weight = units::length_from_si(decay.initial_velocity_m_s);
        let mut v0 = vec![0.0; n];
        v0[weight] = 1.0;
        if decay.velocity_field == VelocityField::QuasiStatic {
            // v0 = K^-1 e_w scaled so that the weight has its velocity exactly.
            factor.solve_in_place(&mut v0);
            let at_weight = v0[weight];
            v0.iter_mut().for_each(|v| *v *= v_weight / at_weight);
        } else {
            v0[weight] = v_weight;
        }
        let mut m_v0 = vec![0.0; n];
        sym_upper_matvec(system.mass.as_ref(), &v0, 1.0, &mut m_v0);
        let initial_qd = solution
            .modes
            .iter()
            .map(|m| m.shape_free.iter().zip(&m_v0).map(|(a, b)| a * b).sum())
            .collect();
        Ok(ModalDecay {
            shapes,
            omega,
            wire_mass,
            initial_qd,
            weight,
            steps,
            dt_s: decay.dt_s,
        })
    }

    /// The axial mode: the one whose initial velocity moves the weight most.
    fn axial_index(&self) -> usize {
        (0..self.omega.len())
            .max_by(|&a, &b| {
                let weight = |j: usize| (self.shapes[(self.weight, j)] * self.initial_qd[j]).abs();
                weight(a).total_cmp(&weight(b))
            })
            .unwrap_or(0)
    }

    /// The axial mode's damping sensitivities.
    pub fn axial_damping(&self) -> AxialDamping {
        let j = self.axial_index();
        let w = self.omega[j];
        AxialDamping {
            omega_rad_s: w,
            wire_mass_share: self.wire_mass[j],
            dzeta_dalpha: self.wire_mass[j] / (2.0 * w),
            dzeta_dbeta: w / 2.0,
        }
    }

    /// Modal damping ratios for Rayleigh alpha (wire only) and beta.
    pub fn modal_zeta(&self, alpha: f64, beta: f64) -> Vec<f64> {
        self.omega
            .iter()
            .zip(&self.wire_mass)
            .map(|(&w, &d)| (alpha * d + beta * w * w) / (2.0 * w))
            .collect()
    }

    /// The weight's acceleration in a free decay with damping (alpha, beta).
    pub fn simulate(&self, alpha: f64, beta: f64) -> Result<DecayRecord> {
        let zeta = self.modal_zeta(alpha, beta);
        let basis = ModalBasis {
            shapes: self.shapes.as_ref(),
            omega: &self.omega,
            zeta: &zeta,
        };
        let initial = ModalState {
            t: 0.0,
            q: vec![0.0; self.omega.len()],
            qd: self.initial_qd.clone(),
        };
        let mut time_s = Vec::with_capacity(self.steps + 1);
        let mut accel_m_s2 = Vec::with_capacity(self.steps + 1);
        integrate_modal(
            basis,
            self.dt_s,
            self.steps,
            &initial,
            &[self.weight],
            &mut |_, _| {},
            &mut |_, t, response| {
                time_s.push(t);
                accel_m_s2.push(units::length_to_si(response.a[0]));
            },
        )
        .map_err(|source| TuneError::Integrate {
            context: format!("modal decay run (alpha {alpha}, beta {beta})"),
            source,
        })?;
        Ok(DecayRecord { time_s, accel_m_s2 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::SpringGeometry;

    fn state() -> SpringState {
        SpringState {
            spring: SpringGeometry {
                active_coils: 14.0,
                mean_diameter_mm: 24.0,
                wire_diameter_mm: 3.0,
                pitch_mm: 6.2,
            },
            youngs_modulus_mpa: 193000.0,
            poisson_ratio: 0.3,
            density_kg_m3: 7850.0,
            mass_kg: 5.25,
            alpha: 0.0,
            beta: 0.0,
        }
    }

    /// The decrement of a modal decay returns the axial mode's modal zeta: the estimator
    /// has no bias of its own (docs/postproc.md) and the low-pass removes the spring's
    /// modes, so the two agree to the decrement's accuracy on a clean record (1e-4).
    #[test]
    fn modal_decay_returns_the_modal_zeta() {
        let fe = FeSettings {
            elements_per_coil: 8,
            ..FeSettings::default()
        };
        let settings = DecaySettings::default();
        let decay = ModalDecay::new(&state(), &fe, &settings).unwrap();
        let axial = decay.axial_damping();
        // The wire carries a third of its mass in the axial mode (Rayleigh):
        // d ~ (m_s/3) / (m + m_s/3), with m_s the mass of the polygon of chords that
        // the 8-per-coil mesh is (2.5% shorter than the helix); 1% covers the departure
        // of the mode shape from the linear profile.
        let (r, h, theta) = (12.0_f64, 6.2_f64, std::f64::consts::TAU / 8.0);
        let pitch_part = h * theta / std::f64::consts::TAU;
        let chord = ((2.0 * r * (theta / 2.0).sin()).powi(2) + pitch_part.powi(2)).sqrt();
        let arc = ((r * theta).powi(2) + pitch_part.powi(2)).sqrt();
        let wire = state().spring_mass_kg() * chord / arc;
        let share = wire / 3.0 / (5.25 + wire / 3.0);
        assert!(
            (axial.wire_mass_share - share).abs() / share < 0.01,
            "{} vs {share}",
            axial.wire_mass_share
        );
        for (alpha, beta) in [(0.8, 1.2e-4), (0.0, 1.3e-4), (2.0, 0.0)] {
            let record = decay.simulate(alpha, beta).unwrap();
            let m = measure(&record, &settings).unwrap();
            let expected = alpha * axial.dzeta_dalpha + beta * axial.dzeta_dbeta;
            assert!(
                (m.zeta_mean - expected).abs() / expected < 1e-4,
                "({alpha}, {beta}): {} vs {expected}",
                m.zeta_mean
            );
        }
    }
}
