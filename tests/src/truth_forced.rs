//! Generated truth for forced records: a mass on a spring driven by a force, integrated
//! independently of coil-ident's simulator (its own RK4 on the physical parameters, at 40
//! steps per sample, friction as `F_f tanh(v / v_f)` with `v_f` a thousandth of the
//! velocity scale), the excitation a first-order hold of its samples (the lab's DAC
//! convention, the same one coil's simulator assumes).
//!
//! Excitations: a random-phase multisine over a band around the resonance, linear sweeps
//! up and down, and stepped sines (dwells at frequencies through the resonance). The
//! measured output is the displacement plus white noise of a given fraction of its RMS.

// The generator indexes samples and sub-steps as the textbook recurrence does.
#![allow(clippy::needless_range_loop)]

use crate::truth::Rng;
use std::f64::consts::TAU;
use std::path::Path;

/// The physical oscillator: `m z'' + c z' + k z + k3 z^3 + F_f tanh(z'/v_f) + c2 z'|z'| = f`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Stiffness, N/m.
    pub stiffness_n_m: f64,
    /// Viscous damping, N s/m.
    pub damping_n_s_m: f64,
    /// Cubic stiffness, N/m^3.
    pub cubic_n_m3: f64,
    /// Dry friction force, N.
    pub friction_n: f64,
    /// Velocity-squared drag, N s^2/m^2.
    pub drag_n_s2_m2: f64,
    /// Friction's regularisation velocity, m/s.
    pub friction_velocity_m_s: f64,
}

impl Oscillator {
    /// 2 kg on 2000 N/m (5.03 Hz), 2 % damping, no effect.
    pub fn linear() -> Oscillator {
        let (m, k) = (2.0, 2000.0);
        Oscillator {
            mass_kg: m,
            stiffness_n_m: k,
            damping_n_s_m: 2.0 * 0.02 * (k * m).sqrt(),
            cubic_n_m3: 0.0,
            friction_n: 0.0,
            drag_n_s2_m2: 0.0,
            friction_velocity_m_s: 1e-4,
        }
    }

    fn acceleration(&self, z: f64, v: f64, f: f64) -> f64 {
        let mut force =
            f - self.damping_n_s_m * v - self.stiffness_n_m * z - self.cubic_n_m3 * z.powi(3);
        if self.friction_n != 0.0 {
            force -= self.friction_n * (v / self.friction_velocity_m_s).tanh();
        }
        force -= self.drag_n_s2_m2 * v * v.abs();
        force / self.mass_kg
    }

    /// The displacement at every sample of the force `f` (sampled at `dt`, joined
    /// linearly), from rest, `steps` RK4 steps per sample.
    pub fn respond(&self, f: &[f64], dt: f64, steps: usize) -> Vec<f64> {
        let h = dt / steps as f64;
        let (mut z, mut v) = (0.0f64, 0.0f64);
        let mut out = Vec::with_capacity(f.len());
        for i in 0..f.len() {
            out.push(z);
            if i + 1 == f.len() {
                break;
            }
            for s in 0..steps {
                let force = |frac: f64| f[i] + (f[i + 1] - f[i]) * (s as f64 + frac) / steps as f64;
                let (fa, fm, fb) = (force(0.0), force(0.5), force(1.0));
                let a1 = self.acceleration(z, v, fa);
                let (z2, v2) = (z + 0.5 * h * v, v + 0.5 * h * a1);
                let a2 = self.acceleration(z2, v2, fm);
                let (z3, v3) = (z + 0.5 * h * v2, v + 0.5 * h * a2);
                let a3 = self.acceleration(z3, v3, fm);
                let (z4, v4) = (z + h * v3, v + h * a3);
                let a4 = self.acceleration(z4, v4, fb);
                z += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
                v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
            }
        }
        out
    }
}

/// An excitation of a record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Excitation {
    /// Random-phase multisine, lines every 0.05 Hz from `from` to `to` Hz, RMS `level` N.
    Multisine { from: f64, to: f64, level: f64 },
    /// Linear sweep of amplitude `level` N from `from` to `to` Hz (down when from > to).
    Sweep { from: f64, to: f64, level: f64 },
    /// Dwells of `dwell` s at `count` frequencies from `from` to `to` Hz, amplitude `level`.
    Stepped {
        from: f64,
        to: f64,
        count: usize,
        dwell: f64,
        level: f64,
    },
}

/// The force samples of `excitation` over `duration` s at `dt` (seeded phases).
pub fn force(excitation: Excitation, dt: f64, duration: f64, rng: &mut Rng) -> Vec<f64> {
    let n = (duration / dt).round() as usize;
    let t = |i: usize| i as f64 * dt;
    // A quarter-second fade-in keeps the start from ringing.
    let ramp = |i: usize| (t(i) / 0.25).min(1.0);
    match excitation {
        Excitation::Multisine { from, to, level } => {
            let lines: Vec<(f64, f64)> = (0..)
                .map(|k| from + 0.05 * k as f64)
                .take_while(|&f| f <= to)
                .map(|f| (f, TAU * rng.uniform()))
                .collect();
            let amp = level * (2.0 / lines.len() as f64).sqrt();
            (0..n)
                .map(|i| {
                    ramp(i)
                        * amp
                        * lines
                            .iter()
                            .map(|(f, p)| (TAU * f * t(i) + p).cos())
                            .sum::<f64>()
                })
                .collect()
        }
        Excitation::Sweep { from, to, level } => {
            let rate = (to - from) / duration;
            (0..n)
                .map(|i| ramp(i) * level * (TAU * (from * t(i) + 0.5 * rate * t(i) * t(i))).sin())
                .collect()
        }
        Excitation::Stepped {
            from,
            to,
            count,
            dwell,
            level,
        } => (0..n)
            .map(|i| {
                let step = ((t(i) / dwell) as usize).min(count - 1);
                let f = from + (to - from) * step as f64 / (count - 1).max(1) as f64;
                ramp(i) * level * (TAU * f * t(i)).sin()
            })
            .collect(),
    }
}

/// A forced record: force, true displacement, measured displacement.
#[derive(Debug, Clone)]
pub struct ForcedRecord {
    /// Sample interval, s.
    pub dt: f64,
    /// Force, N.
    pub force_n: Vec<f64>,
    /// The generator's displacement, m.
    pub truth_m: Vec<f64>,
    /// With noise, m.
    pub measured_m: Vec<f64>,
}

/// Generates a record of `oscillator` under `excitation` with output noise `noise` (a
/// fraction of the displacement's RMS).
pub fn record(
    oscillator: &Oscillator,
    excitation: Excitation,
    duration: f64,
    noise: f64,
    seed: u64,
) -> ForcedRecord {
    let dt = 0.01;
    let mut rng = Rng::new(seed);
    let force_n = force(excitation, dt, duration, &mut rng);
    let truth_m = oscillator.respond(&force_n, dt, 40);
    let rms = (truth_m.iter().map(|z| z * z).sum::<f64>() / truth_m.len() as f64).sqrt();
    let measured_m = truth_m
        .iter()
        .map(|z| z + noise * rms * rng.normal())
        .collect();
    ForcedRecord {
        dt,
        force_n,
        truth_m,
        measured_m,
    }
}

/// Writes `records` as a forced case in `folder` (`case.json`, `record_K.csv` with
/// `time_s,force_n,displacement_m`).
pub fn write_case(folder: &Path, name: &str, records: &[ForcedRecord]) -> std::io::Result<()> {
    std::fs::create_dir_all(folder)?;
    let mut entries = Vec::new();
    for (k, r) in records.iter().enumerate() {
        let file = format!("record_{}.csv", k + 1);
        let mut text = String::from("time_s,force_n,displacement_m\n");
        for i in 0..r.force_n.len() {
            text.push_str(&format!(
                "{:.4},{:.9e},{:.9e}\n",
                i as f64 * r.dt,
                r.force_n[i],
                r.measured_m[i]
            ));
        }
        std::fs::write(folder.join(&file), text)?;
        entries.push(serde_json::json!({
            "file": file, "time": "time_s", "input": "force_n", "output": "displacement_m",
            "input_quantity": "force", "output_quantity": "displacement",
            "input_unit": "N", "output_unit": "m"
        }));
    }
    let case = serde_json::json!({
        "name": name,
        "records": { "forced": entries }
    });
    std::fs::write(
        folder.join("case.json"),
        serde_json::to_string_pretty(&case).unwrap_or_default() + "\n",
    )
}
