//! The reduced FE spring a case with a `spring` drives with its forced records: the
//! decay diagnosis's model (the case's geometry and material meshed by coil-mesher,
//! reduced by Craig-Bampton to the weight's axial DOF plus [`MODES`] fixed-interface
//! modes, `crate::diagnose::model::ReducedSpring`, guided mount), put in modal form for
//! the forced model (module `super::model`, "modal form").
//!
//! # Parameters and what they set
//! As the decay route fits them: the weight's mass `m` (kg; fixed at the case's
//! `mass_kg` under a base input, which measures only the frequency's ratio to it), the
//! stiffness scale `s` of the nominal Young's modulus (`K = s K_0`) and Rayleigh beta
//! (`C = beta K`, so mode `i` has `zeta_i = beta w_i / 2`). The law at the weight (cubic,
//! friction, drag) acts on the weight's axial displacement from its static position.
//!
//! # Modal form
//! `M = L L^T`, the eigenvectors `Y` of `L^-1 K L^-T` give the mass-normalised modes
//! `Phi = L^-T Y` (solver units: t, mm, N). For mode `i`, `phi_i = Phi[0, i]` (the weight's
//! axial DOF) and `gamma_i = Phi_i^T M r` (`r` the rigid axial translation,
//! `coil_solver::reduce::Reduction::translation_load`). In SI (records in N or m/s^2 in,
//! m, m/s or m/s^2 out) `b_i = 1e-3 phi_i^2` (1/kg) for a force, `b_i = -phi_i gamma_i` for a
//! base acceleration, `a_i = phi_i^2 / phi_1^2`, and the law per unit reference mass
//! `m_ref = 1 / (1e-3 phi_1^2)`, mode 1 the one of largest `phi_i^2`. Modes with
//! `phi_i^2` below 1e-12 of the largest (lateral modes the guided weight does not feel) drop
//! out: they neither move the weight nor feel its law.

use super::model::{InputQuantity, Lumped, Mode, SpringFigures};
use crate::diagnose::effects::Mount;
use crate::diagnose::model::ReducedSpring;
use crate::error::Result;
use crate::fe::{FeSettings, SpringState};
use std::path::Path;

/// Fixed-interface modes kept (the decay diagnosis's default).
pub const MODES: usize = 4;

/// The fitted quantities of a spring model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringParameters {
    /// The weight's mass, kg.
    pub mass_kg: f64,
    /// Stiffness scale against the nominal Young's modulus.
    pub k_scale: f64,
    /// Rayleigh beta, s.
    pub beta_s: f64,
}

/// The case's spring, reduced (module docs).
#[derive(Debug, Clone)]
pub struct SpringStructure {
    reduced: ReducedSpring,
    /// The case's nominal mass, kg.
    pub nominal_mass_kg: f64,
    /// The case's nominal Young's modulus, MPa.
    pub youngs_modulus_mpa: f64,
    /// The wire's mass, kg.
    pub spring_mass_kg: f64,
    /// What drives the model.
    pub input: InputQuantity,
}

/// A spring model in modal form: the oscillator (mode 1 and the further modes) and its
/// reference mass `m_ref` (kg).
pub type Modal = (Lumped, f64);

impl SpringStructure {
    /// Meshes and reduces the spring of the case at `path` (folder or case.json).
    pub fn build(path: &Path, input: InputQuantity) -> Result<Self> {
        let case = crate::case::read_case(path)?;
        let state = SpringState::nominal(&case);
        let reduced = ReducedSpring::build(&state, &FeSettings::default(), Mount::Guided, MODES)?;
        Ok(SpringStructure {
            reduced,
            nominal_mass_kg: case.mass_kg,
            youngs_modulus_mpa: case.material.youngs_modulus_mpa,
            spring_mass_kg: state.spring_mass_kg(),
            input,
        })
    }

    /// The linear model in modal form at `p` (module docs): the oscillator's law is zero,
    /// its offset 0 and its friction velocity 1.
    pub fn modal(&self, p: &SpringParameters) -> std::result::Result<Modal, String> {
        if !(p.mass_kg > 0.0 && p.k_scale > 0.0 && p.beta_s >= 0.0) {
            return Err(format!("spring parameters out of range: {p:?}"));
        }
        let (m, k, load) = self.reduced.linear_operators(p.mass_kg, p.k_scale)?;
        let l = m
            .cholesky()
            .ok_or("the reduced mass is not positive definite")?
            .l();
        let linv = l.try_inverse().ok_or("the reduced mass is singular")?;
        let a = &linv * &k * linv.transpose();
        let a = (&a + a.transpose()) * 0.5;
        let eigen = a.symmetric_eigen();
        let phi = linv.transpose() * eigen.eigenvectors;
        let n = phi.ncols();
        let shares: Vec<f64> = (0..n).map(|i| phi[(0, i)].powi(2)).collect();
        let first = (0..n)
            .max_by(|&i, &j| shares[i].total_cmp(&shares[j]))
            .ok_or("the reduced model has no mode")?;
        let mode = |i: usize| -> Mode {
            let w = eigen.eigenvalues[i].max(0.0).sqrt();
            let gamma: f64 = phi.column(i).dot(&load);
            Mode {
                natural_frequency_rad_s: w,
                damping_ratio: 0.5 * p.beta_s * w,
                input_gain: match self.input {
                    InputQuantity::Force => 1e-3 * shares[i],
                    InputQuantity::BaseAcceleration => -phi[(0, i)] * gamma,
                },
                law_gain: shares[i] / shares[first],
            }
        };
        let one = mode(first);
        if one.natural_frequency_rad_s.is_nan() || one.natural_frequency_rad_s <= 0.0 {
            return Err("the spring's first axial mode has no positive frequency".into());
        }
        let mut oscillator = Lumped::linear(
            one.natural_frequency_rad_s,
            one.damping_ratio,
            one.input_gain,
        );
        let floor = 1e-12 * shares[first];
        oscillator.modes = (0..n)
            .filter(|&i| i != first && shares[i] > floor)
            .map(mode)
            .collect();
        Ok((oscillator, 1.0 / (1e-3 * shares[first])))
    }

    /// The figures of `p` in the case's terms.
    pub fn figures(&self, p: &SpringParameters) -> SpringFigures {
        let (_, k, _) = self
            .reduced
            .linear_operators(p.mass_kg, p.k_scale)
            .unwrap_or_default();
        let k00 = if k.nrows() > 0 { k[(0, 0)] } else { f64::NAN };
        SpringFigures {
            mass_kg: p.mass_kg,
            youngs_modulus_mpa: self.youngs_modulus_mpa * p.k_scale,
            rayleigh_beta_s: p.beta_s,
            stiffness_n_m: k00 * 1e3,
            spring_mass_kg: self.spring_mass_kg,
        }
    }

    /// The parameters whose first mode has the frequency `w0` (rad/s), damping ratio
    /// `zeta` and, under a force, the reference mass `1 / gain` (the linear start, from
    /// the lumped oscillator's fit): the mass moved by the difference between the target
    /// reference mass and the nominal model's, the stiffness scaled to the frequency.
    pub fn matching(
        &self,
        w0: f64,
        zeta: f64,
        gain: f64,
    ) -> std::result::Result<SpringParameters, String> {
        let nominal = SpringParameters {
            mass_kg: self.nominal_mass_kg,
            k_scale: 1.0,
            beta_s: 0.0,
        };
        let (o, m_ref) = self.modal(&nominal)?;
        let mass_kg = match self.input {
            InputQuantity::Force if gain > 0.0 => {
                (1.0 / gain - (m_ref - self.nominal_mass_kg)).max(0.05 * self.nominal_mass_kg)
            }
            _ => self.nominal_mass_kg,
        };
        let at_mass = SpringParameters { mass_kg, ..nominal };
        let (o2, _) = self.modal(&at_mass).unwrap_or((o, m_ref));
        let k_scale = (w0 / o2.natural_frequency_rad_s).powi(2);
        Ok(SpringParameters {
            mass_kg,
            k_scale,
            beta_s: 2.0 * zeta / w0,
        })
    }
}
