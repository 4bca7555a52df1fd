//! Generated truth for forced records on a spring: the case's reduced FE spring
//! (Craig-Bampton, guided weight, [`GENERATOR_MODES`] fixed-interface modes: two more than
//! the diagnosis keeps) integrated in its own reduced coordinates, not in the modal form
//! coil-ident's forced model uses: `M q'' + beta K q' + K q = l(t) - e_0 f(q_0, q_0')`
//! by classical RK4 on `M^-1` (solver units: t, mm, N), each sample interval cut so that
//! `w_max h <= 0.1` at the reduced model's highest frequency, the input joined linearly
//! between its samples. `l = e_0 F` for a force on the weight, `l = -M r a_b` (the inertial
//! load of a base acceleration, relative coordinates) for a base input. The law at the
//! weight: `f = k3 x^3 + F_f tanh(v / v_f) + c2 v |v|` (SI, `x`, `v` the weight's axial
//! displacement and velocity about its static position).
//!
//! The spring: the paper-like example of `cases/measured/cubic_g2` (9 active coils, D 18
//! mm, d 2.2 mm, pitch 4.6 mm, steel) with a 0.2 kg weight, so that the spring's own mass
//! (15 g) lowers the axial frequency by a few per cent: a lumped model with the weight's
//! mass alone would be off by that much, the FE model is not.

// The generator indexes DOFs and sub-steps as the textbook recurrence does.
#![allow(clippy::needless_range_loop)]

use crate::truth::Rng;
use crate::truth_forced::{force, Excitation};
use coil_ident::diagnose::effects::Mount;
use coil_ident::diagnose::model::ReducedSpring;
use coil_tuner::case::SpringGeometry;
use coil_tuner::fe::{FeSettings, SpringState};
use std::path::Path;

/// Fixed-interface modes of the generator's reduction.
pub const GENERATOR_MODES: usize = 6;

/// The spring's geometry (module docs).
pub fn geometry() -> SpringGeometry {
    SpringGeometry {
        active_coils: 9.0,
        mean_diameter_mm: 18.0,
        wire_diameter_mm: 2.2,
        pitch_mm: 4.6,
    }
}

/// The truth: the weight on the spring with Rayleigh beta and the law at the weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringTruth {
    /// The weight's mass, kg.
    pub mass_kg: f64,
    /// Young's modulus, MPa.
    pub youngs_modulus_mpa: f64,
    /// Rayleigh beta, s.
    pub beta_s: f64,
    /// Cubic stiffness, N/m^3.
    pub cubic_n_m3: f64,
    /// Dry friction, N.
    pub friction_n: f64,
    /// Velocity-squared drag, N s^2/m^2.
    pub drag_n_s2_m2: f64,
    /// Friction's regularisation velocity, m/s.
    pub friction_velocity_m_s: f64,
    /// Whether the input is a base acceleration (m/s^2) instead of a force (N).
    pub base: bool,
}

impl SpringTruth {
    /// 0.2 kg on the spring at the nominal E (200 GPa here, the case states 206), beta
    /// giving about 1.5 % damping on the axial mode, no effect, a force input.
    pub fn linear() -> SpringTruth {
        SpringTruth {
            mass_kg: 0.2,
            youngs_modulus_mpa: 200_000.0,
            beta_s: 2e-4,
            cubic_n_m3: 0.0,
            friction_n: 0.0,
            drag_n_s2_m2: 0.0,
            friction_velocity_m_s: 1e-4,
            base: false,
        }
    }

    fn state(&self) -> SpringState {
        SpringState {
            spring: geometry(),
            youngs_modulus_mpa: self.youngs_modulus_mpa,
            poisson_ratio: 0.3,
            density_kg_m3: 7850.0,
            mass_kg: self.mass_kg,
            alpha: 0.0,
            beta: 0.0,
        }
    }

    /// The weight's axial displacement (m) at every sample of `input` (N or m/s^2,
    /// sampled at `dt`, joined linearly), from rest (module docs).
    pub fn respond(&self, input: &[f64], dt: f64) -> Vec<f64> {
        let reduced = ReducedSpring::build(
            &self.state(),
            &FeSettings::default(),
            Mount::Guided,
            GENERATOR_MODES,
        )
        .expect("the generator's spring reduces");
        let (m, k, load) = reduced
            .linear_operators(self.mass_kg, 1.0)
            .expect("the generator's operators");
        let n = m.nrows();
        let minv = m.clone().try_inverse().expect("M is invertible");
        let c = &k * self.beta_s;
        let w_max = (&minv * &k)
            .complex_eigenvalues()
            .iter()
            .map(|l| l.norm().sqrt())
            .fold(0.0, f64::max);
        let steps = ((w_max * dt / 0.1).ceil() as usize).max(1);
        let h = dt / steps as f64;
        // The load per unit input (N): e_0 for a force, -M r (mm/s^2 per m/s^2) for a base.
        let per_input: Vec<f64> = if self.base {
            load.iter().map(|l| -1e3 * l).collect()
        } else {
            (0..n).map(|i| if i == 0 { 1.0 } else { 0.0 }).collect()
        };
        let law = |x_mm: f64, v_mm: f64| {
            let (x, v) = (1e-3 * x_mm, 1e-3 * v_mm);
            self.cubic_n_m3 * x.powi(3)
                + self.friction_n * (v / self.friction_velocity_m_s).tanh()
                + self.drag_n_s2_m2 * v * v.abs()
        };
        let accel = |q: &[f64], p: &[f64], u: f64| -> Vec<f64> {
            let mut f: Vec<f64> = (0..n)
                .map(|i| {
                    per_input[i] * u
                        - (0..n)
                            .map(|j| c[(i, j)] * p[j] + k[(i, j)] * q[j])
                            .sum::<f64>()
                })
                .collect();
            f[0] -= law(q[0], p[0]);
            (0..n)
                .map(|i| (0..n).map(|j| minv[(i, j)] * f[j]).sum())
                .collect()
        };
        let (mut q, mut p) = (vec![0.0; n], vec![0.0; n]);
        let mut out = Vec::with_capacity(input.len());
        for i in 0..input.len() {
            out.push(1e-3 * q[0]);
            if i + 1 == input.len() {
                break;
            }
            for s in 0..steps {
                let u = |frac: f64| {
                    input[i] + (input[i + 1] - input[i]) * (s as f64 + frac) / steps as f64
                };
                let a1 = accel(&q, &p, u(0.0));
                let q2: Vec<f64> = (0..n).map(|j| q[j] + 0.5 * h * p[j]).collect();
                let p2: Vec<f64> = (0..n).map(|j| p[j] + 0.5 * h * a1[j]).collect();
                let a2 = accel(&q2, &p2, u(0.5));
                let q3: Vec<f64> = (0..n).map(|j| q[j] + 0.5 * h * p2[j]).collect();
                let p3: Vec<f64> = (0..n).map(|j| p[j] + 0.5 * h * a2[j]).collect();
                let a3 = accel(&q3, &p3, u(0.5));
                let q4: Vec<f64> = (0..n).map(|j| q[j] + h * p3[j]).collect();
                let p4: Vec<f64> = (0..n).map(|j| p[j] + h * a3[j]).collect();
                let a4 = accel(&q4, &p4, u(1.0));
                for j in 0..n {
                    q[j] += h / 6.0 * (p[j] + 2.0 * p2[j] + 2.0 * p3[j] + p4[j]);
                    p[j] += h / 6.0 * (a1[j] + 2.0 * a2[j] + 2.0 * a3[j] + a4[j]);
                }
            }
        }
        out
    }
}

/// A forced record on the spring: input, true displacement, measured displacement.
#[derive(Debug, Clone)]
pub struct SpringRecord {
    /// Sample interval, s.
    pub dt: f64,
    /// Input (N or m/s^2).
    pub input: Vec<f64>,
    /// The generator's displacement, m.
    pub truth_m: Vec<f64>,
    /// With noise, m.
    pub measured_m: Vec<f64>,
}

/// Generates a record of `truth` under `excitation` (`dt` s, `duration` s) with output
/// noise `noise` (a fraction of the displacement's RMS).
pub fn spring_record(
    truth: &SpringTruth,
    excitation: Excitation,
    dt: f64,
    duration: f64,
    noise: f64,
    seed: u64,
) -> SpringRecord {
    let mut rng = Rng::new(seed);
    let input = force(excitation, dt, duration, &mut rng);
    let truth_m = truth.respond(&input, dt);
    let rms = (truth_m.iter().map(|z| z * z).sum::<f64>() / truth_m.len() as f64).sqrt();
    let measured_m = truth_m
        .iter()
        .map(|z| z + noise * rms * rng.normal())
        .collect();
    SpringRecord {
        dt,
        input,
        truth_m,
        measured_m,
    }
}

/// Writes `records` as a spring case with forced records in `folder` (`case.json` with the
/// spring, steel at 206 GPa nominal, `mass_kg` the nominal mass, no gravity;
/// `record_K.csv` with `time_s,input,displacement_m`).
pub fn write_spring_case(
    folder: &Path,
    truth: &SpringTruth,
    mass_kg: f64,
    records: &[SpringRecord],
) -> std::io::Result<()> {
    std::fs::create_dir_all(folder)?;
    let (column, quantity, unit) = if truth.base {
        ("base_accel_m_s2", "base_acceleration", "m/s^2")
    } else {
        ("force_n", "force", "N")
    };
    let mut entries = Vec::new();
    for (k, r) in records.iter().enumerate() {
        let file = format!("record_{}.csv", k + 1);
        let mut text = format!("time_s,{column},displacement_m\n");
        for i in 0..r.input.len() {
            text.push_str(&format!(
                "{:.6},{:.9e},{:.9e}\n",
                i as f64 * r.dt,
                r.input[i],
                r.measured_m[i]
            ));
        }
        std::fs::write(folder.join(&file), text)?;
        entries.push(serde_json::json!({
            "file": file, "time": "time_s", "input": column, "output": "displacement_m",
            "input_quantity": quantity, "output_quantity": "displacement",
            "input_unit": unit, "output_unit": "m"
        }));
    }
    let g = geometry();
    let case = serde_json::json!({
        "name": "spring on a shaker (generated)",
        "spring": {
            "active_coils": g.active_coils, "mean_diameter_mm": g.mean_diameter_mm,
            "wire_diameter_mm": g.wire_diameter_mm, "pitch_mm": g.pitch_mm
        },
        "material": { "youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0 },
        "mass_kg": mass_kg,
        "gravity_m_s2": 0.0,
        "records": { "forced": entries }
    });
    std::fs::write(
        folder.join("case.json"),
        serde_json::to_string_pretty(&case).unwrap_or_default() + "\n",
    )
}
