//! The state a time step carries: displacement, velocity and acceleration at a time,
//! one entry per operator row (units of the operators: coil's mm, mm/s, mm/s^2, s).

/// Displacement, velocity and acceleration at time `t`, one entry per operator row.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time (s).
    pub t: f64,
    /// Displacements (mm, or rad on a rotation).
    pub u: Vec<f64>,
    /// Velocities (mm/s, or rad/s on a rotation).
    pub v: Vec<f64>,
    /// Accelerations (mm/s^2, or rad/s^2 on a rotation).
    pub a: Vec<f64>,
}

impl State {
    /// The state at rest at `t`.
    pub fn zeros(n: usize, t: f64) -> Self {
        Self {
            t,
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
        }
    }
}
