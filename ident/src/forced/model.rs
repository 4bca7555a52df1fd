//! The lumped single-mode oscillator that forced records identify, and its file
//! (`model.json`).
//!
//! # Formulation
//! The weight's displacement `z` (relative to the base when the input is a base
//! acceleration) obeys, per unit mass,
//! ```text
//! z'' + 2 zeta w0 z' + w0^2 z + kappa z^3 + phi s(z') + delta z' |z'| = b u(t)
//! ```
//! with `w0` the linear natural frequency (rad/s), `zeta` the viscous damping ratio, `b`
//! the input gain (output unit / s^2 per input unit), `kappa` the cubic spring
//! (1 / (s^2 output unit^2), `> 0` hardening), `phi` the dry friction (output unit / s^2)
//! and `delta` the velocity-squared drag (1 / output unit). Dry friction's sign function is
//! regularised, `s(v) = tanh(v / v_f)`, with `v_f` stored in the model (a smooth law keeps
//! the explicit integrator and the harmonic balance well posed; below `v_f` the weight
//! creeps instead of sticking, so `v_f` is chosen small against the records' velocities).
//!
//! The measured output is `y = z + y0` (displacement), `z' + y0` (velocity) or the absolute
//! acceleration `z'' + y0` (force input) / `z'' - b u + y0` (base acceleration: the base's
//! own acceleration `-b u` in the output's unit added back), `y0` the sensor's offset.
//!
//! # Units and what is identified
//! Only ratios are measured: the equation divided by the mass. With the input a force in N
//! and the output in m, `m = 1 / b` and the physical parameters follow (`k = m w0^2`,
//! `c = 2 zeta w0 m`, `k3 = m kappa`, `F_f = m phi`, `c2 = m delta`); in other units (volts)
//! they are the same ratios in the input's unit per the output's. A base-acceleration
//! input identifies `b = -1` times the units' ratio, and the physical parameters use the
//! case's `mass_kg` (1 when it gives none).
//!
//! # The reduced FE spring in modal form (`kind: reduced_spring`)
//! A case that gives a spring drives the reduced FE model of the decay diagnosis
//! (module `super::spring`): its `N` modes, decoupled by the linear part (Rayleigh
//! damping `C = beta K` is diagonal in them), are coupled only through the law at the
//! weight. With `q_i` mode `i`'s part of the weight's displacement, `z = sum q_i`,
//! ```text
//! q_i'' + 2 zeta_i w_i q_i' + w_i^2 q_i = b_i u(t) - a_i g(z, z')
//! ```
//! `g` the law of the first equation per unit reference mass `m_ref`, `a_i = phi_i^2 /
//! phi_1^2` (`phi_i` the mass-normalised mode's value at the weight, `a_1 = 1`), `b_i =
//! phi_i^2` for a force, `-phi_i gamma_i` for a base acceleration (`gamma_i` the mode's
//! share of the inertial load `M r`). Mode 1 (the weight bouncing on the spring, the
//! largest `phi_i`) is the `oscillator`, the others are its `modes`; the lumped oscillator
//! is the case `N = 1`. The output's absolute acceleration under a base input is
//! `z'' + u` (the records are in SI units).

use serde::{Deserialize, Serialize};

/// What drives the weight.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InputQuantity {
    /// A force on the weight.
    Force,
    /// The acceleration of the base the spring stands on.
    BaseAcceleration,
}

/// What the output measures on the weight.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OutputQuantity {
    /// Displacement (relative to the base for a base input).
    Displacement,
    /// Velocity (relative to the base for a base input).
    Velocity,
    /// Absolute acceleration.
    Acceleration,
}

impl InputQuantity {
    /// The name a case uses.
    pub fn name(self) -> &'static str {
        match self {
            InputQuantity::Force => "force",
            InputQuantity::BaseAcceleration => "base_acceleration",
        }
    }
    /// The quantity a case names.
    pub fn from_name(name: &str) -> Option<Self> {
        [InputQuantity::Force, InputQuantity::BaseAcceleration]
            .into_iter()
            .find(|q| q.name() == name)
    }
}

impl OutputQuantity {
    /// The name a case uses.
    pub fn name(self) -> &'static str {
        match self {
            OutputQuantity::Displacement => "displacement",
            OutputQuantity::Velocity => "velocity",
            OutputQuantity::Acceleration => "acceleration",
        }
    }
    /// The quantity a case names.
    pub fn from_name(name: &str) -> Option<Self> {
        [
            OutputQuantity::Displacement,
            OutputQuantity::Velocity,
            OutputQuantity::Acceleration,
        ]
        .into_iter()
        .find(|q| q.name() == name)
    }
}

/// A further mode of a reduced FE spring (module docs, "modal form").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// Natural frequency w_i, rad/s.
    pub natural_frequency_rad_s: f64,
    /// Damping ratio zeta_i.
    pub damping_ratio: f64,
    /// Input gain b_i (output unit / s^2 per input unit).
    pub input_gain: f64,
    /// The law's share a_i.
    pub law_gain: f64,
}

/// The lumped oscillator (module docs), with the further modes of a reduced FE spring.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Lumped {
    /// Linear natural frequency w0, rad/s.
    pub natural_frequency_rad_s: f64,
    /// Viscous damping ratio.
    pub damping_ratio: f64,
    /// Input gain b: output unit / s^2 per input unit.
    pub input_gain: f64,
    /// Cubic spring per unit mass kappa, 1/(s^2 output unit^2).
    pub cubic: f64,
    /// Dry friction per unit mass phi, output unit / s^2.
    pub friction: f64,
    /// Velocity-squared drag per unit mass delta, 1/output unit.
    pub drag: f64,
    /// Velocity scale of the friction's regularisation v_f, output unit / s.
    pub friction_velocity: f64,
    /// Sensor offset y0 of the output, output unit.
    pub output_offset: f64,
    /// The further modes of a reduced FE spring (none for the lumped oscillator).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub modes: Vec<Mode>,
}

impl Lumped {
    /// A linear oscillator.
    pub fn linear(w0: f64, zeta: f64, b: f64) -> Lumped {
        Lumped {
            natural_frequency_rad_s: w0,
            damping_ratio: zeta,
            input_gain: b,
            cubic: 0.0,
            friction: 0.0,
            drag: 0.0,
            friction_velocity: 1.0,
            output_offset: 0.0,
            modes: Vec::new(),
        }
    }

    /// The acceleration z'' at state (z, v) under input u.
    #[inline]
    pub fn acceleration(&self, z: f64, v: f64, u: f64) -> f64 {
        let w = self.natural_frequency_rad_s;
        self.input_gain * u - self.restoring(z, v) - 2.0 * self.damping_ratio * w * v - w * w * z
    }

    /// The nonlinear part of the restoring force per unit mass.
    #[inline]
    pub fn restoring(&self, z: f64, v: f64) -> f64 {
        let mut f = self.cubic * z * z * z;
        if self.friction != 0.0 {
            f += self.friction * (v / self.friction_velocity).tanh();
        }
        if self.drag != 0.0 {
            f += self.drag * v * v.abs();
        }
        f
    }

    /// The derivatives of the nonlinear restoring force with respect to z and v.
    pub fn restoring_slopes(&self, z: f64, v: f64) -> (f64, f64) {
        let dz = 3.0 * self.cubic * z * z;
        let mut dv = 2.0 * self.drag * v.abs();
        if self.friction != 0.0 {
            let t = (v / self.friction_velocity).tanh();
            dv += self.friction * (1.0 - t * t) / self.friction_velocity;
        }
        (dz, dv)
    }

    /// Whether any nonlinear term is present.
    pub fn is_linear(&self) -> bool {
        self.cubic == 0.0 && self.friction == 0.0 && self.drag == 0.0
    }
}

/// A model file: the oscillator with what its input and output are (self-contained:
/// `coil-tune simulate` and `frc` need nothing else).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ForcedModel {
    /// Always `lumped_oscillator`.
    pub kind: String,
    /// What drives the weight.
    pub input_quantity: InputQuantity,
    /// What the output measures.
    pub output_quantity: OutputQuantity,
    /// The input's unit label.
    pub input_unit: String,
    /// The output's unit label.
    pub output_unit: String,
    /// The physical mass the ratios are scaled with (1 / b for a force input, the case's
    /// `mass_kg` for a base input), in the input unit s^2 per output unit.
    pub mass: f64,
    /// The oscillator.
    pub oscillator: Lumped,
    /// A reduced FE spring's figures (none for the lumped oscillator).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring: Option<SpringFigures>,
}

/// The model kind of the lumped oscillator's file.
pub const KIND: &str = "lumped_oscillator";

/// The model kind of a reduced FE spring's file (module docs, "modal form").
pub const SPRING_KIND: &str = "reduced_spring";

/// What a reduced FE spring's fit found, in the case's terms (kept in the model file for
/// the report; the simulation reads only the modes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpringFigures {
    /// The weight's mass, kg.
    pub mass_kg: f64,
    /// Young's modulus, MPa (the case's nominal times the fitted stiffness scale).
    pub youngs_modulus_mpa: f64,
    /// Rayleigh beta on the spring, s.
    pub rayleigh_beta_s: f64,
    /// The static stiffness at the weight, N/m.
    pub stiffness_n_m: f64,
    /// The spring wire's mass, kg.
    pub spring_mass_kg: f64,
}

impl ForcedModel {
    /// The model with its physical mass set from the oscillator's gain.
    pub fn new(
        input_quantity: InputQuantity,
        output_quantity: OutputQuantity,
        units: (&str, &str),
        base_mass: Option<f64>,
        oscillator: Lumped,
    ) -> ForcedModel {
        let mass = match input_quantity {
            InputQuantity::Force => 1.0 / oscillator.input_gain,
            InputQuantity::BaseAcceleration => base_mass.unwrap_or(1.0),
        };
        ForcedModel {
            kind: KIND.into(),
            input_quantity,
            output_quantity,
            input_unit: units.0.into(),
            output_unit: units.1.into(),
            mass,
            oscillator,
            spring: None,
        }
    }

    /// Whether the model is a reduced FE spring.
    pub fn is_spring(&self) -> bool {
        self.kind == SPRING_KIND
    }

    /// The output's offset from the weight's relative acceleration under a base input:
    /// the base's own acceleration (`-b u` for the lumped oscillator, whose gain carries
    /// the units' ratio; `u` for a spring, in SI units).
    #[inline]
    pub fn base_feedthrough(&self) -> f64 {
        if self.is_spring() {
            1.0
        } else {
            -self.oscillator.input_gain
        }
    }

    /// The measured output from the displacement, velocity and acceleration of the
    /// weight (relative to the base under a base input) and the input.
    #[inline]
    pub fn output(&self, z: f64, v: f64, a: f64, u: f64) -> f64 {
        self.oscillator.output_offset
            + match self.output_quantity {
                OutputQuantity::Displacement => z,
                OutputQuantity::Velocity => v,
                OutputQuantity::Acceleration => match self.input_quantity {
                    InputQuantity::Force => a,
                    InputQuantity::BaseAcceleration => a + self.base_feedthrough() * u,
                },
            }
    }

    /// Checks a model read from a file: every number finite, the linear part stable.
    pub fn check(&self) -> Result<(), String> {
        let o = &self.oscillator;
        if self.kind != KIND && self.kind != SPRING_KIND {
            return Err(format!(
                "`kind` is \"{}\"; expected \"{KIND}\" or \"{SPRING_KIND}\"",
                coil_io::excerpt(&self.kind)
            ));
        }
        if self.kind == KIND && !o.modes.is_empty() {
            return Err(format!(
                "`oscillator.modes` holds {} modes; expected none for a \"{KIND}\" (further \
                 modes belong to a \"{SPRING_KIND}\")",
                o.modes.len()
            ));
        }
        for (i, m) in o.modes.iter().enumerate() {
            let ok = m.natural_frequency_rad_s.is_finite()
                && m.natural_frequency_rad_s > 0.0
                && m.damping_ratio.is_finite()
                && m.damping_ratio >= 0.0
                && m.input_gain.is_finite()
                && m.law_gain.is_finite();
            if !ok {
                return Err(format!(
                    "`oscillator.modes[{i}]` is {m:?}; expected a finite positive \
                     natural_frequency_rad_s, a finite non-negative damping_ratio and finite \
                     gains"
                ));
            }
        }
        let fields = [
            ("natural_frequency_rad_s", o.natural_frequency_rad_s, true),
            ("damping_ratio", o.damping_ratio, false),
            ("input_gain", o.input_gain, false),
            ("cubic", o.cubic, false),
            ("friction", o.friction, false),
            ("drag", o.drag, false),
            ("friction_velocity", o.friction_velocity, true),
            ("output_offset", o.output_offset, false),
            ("mass", self.mass, false),
        ];
        for (name, value, positive) in fields {
            if !value.is_finite() || (positive && value <= 0.0) {
                return Err(format!(
                    "`oscillator.{name}` is {value}; expected a finite{} number",
                    if positive { " positive" } else { "" }
                ));
            }
        }
        if o.damping_ratio < 0.0 || o.friction < 0.0 || o.drag < 0.0 {
            return Err(
                "`oscillator.damping_ratio`, `friction` and `drag` must not be negative \
                        (a model that creates energy)"
                    .into(),
            );
        }
        if o.input_gain == 0.0 {
            return Err("`oscillator.input_gain` is 0: the input would not drive the model".into());
        }
        Ok(())
    }

    /// The physical parameters in the diagnosis's names (SI when the records are in N and m).
    pub fn physical(&self) -> Vec<(&'static str, f64)> {
        let o = &self.oscillator;
        let m = self.mass;
        let w = o.natural_frequency_rad_s;
        if let Some(s) = &self.spring {
            return vec![
                ("mass_kg", s.mass_kg),
                ("stiffness_n_m", s.stiffness_n_m),
                ("youngs_modulus_mpa", s.youngs_modulus_mpa),
                ("rayleigh_beta_s", s.rayleigh_beta_s),
                ("spring_mass_kg", s.spring_mass_kg),
                ("modal_mass_kg", m),
                ("natural_frequency_hz", w / std::f64::consts::TAU),
                ("damping_ratio", o.damping_ratio),
            ];
        }
        vec![
            ("mass_kg", m),
            ("stiffness_n_m", m * w * w),
            ("damping_n_s_m", 2.0 * o.damping_ratio * w * m),
            ("natural_frequency_hz", w / std::f64::consts::TAU),
            ("damping_ratio", o.damping_ratio),
            ("input_gain", o.input_gain),
        ]
    }
}
