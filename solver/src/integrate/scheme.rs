//! The generalised-alpha family's schemes and the one place their step coefficients
//! are derived: [`Scheme`] (average acceleration, HHT-alpha, generalised-alpha) to
//! [`Coefficients`] (`alpha_m`, `alpha_f`, `beta`, `gamma`, Chung & Hulbert's
//! notation), the effective-matrix scale factors of `S = cm M + cc C + ck K`, and the
//! leading-order algorithmic damping and period error. The formulation, the parameter
//! ranges and the references are in the module docs of [`super::stepper`]; every
//! stepper (the sparse operator [`super::Stepper`] with its banded and sparse engines,
//! and the dense [`super::DenseStepper`]) takes its coefficients from here.

use crate::error::integrate::IntegrateError;

/// A time integration scheme. [`Scheme::default`] is average acceleration.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Scheme {
    /// Newmark average acceleration: no numerical damping, period error `W^2/12`.
    #[default]
    AverageAcceleration,
    /// Hilber-Hughes-Taylor with `alpha` in `[-1/3, 0]` (`0` is average acceleration).
    Hht {
        /// HHT's alpha, in `[-1/3, 0]`.
        alpha: f64,
    },
    /// Chung-Hulbert generalised-alpha with spectral radius at infinity `rho_inf` in
    /// `[0, 1]` (`1` is average acceleration).
    GeneralizedAlpha {
        /// Spectral radius at infinite frequency, in `[0, 1]`.
        rho_inf: f64,
    },
}

impl Scheme {
    /// The scheme's Newmark and alpha parameters, after checking its parameter range.
    pub fn coefficients(self) -> Result<Coefficients, IntegrateError> {
        match self {
            Scheme::AverageAcceleration => Ok(AVERAGE_ACCELERATION),
            Scheme::Hht { alpha } => {
                if !(-1.0 / 3.0..=0.0).contains(&alpha) {
                    return Err(IntegrateError::InvalidParameter {
                        scheme: "HHT-alpha",
                        name: "alpha",
                        value: alpha,
                        min: -1.0 / 3.0,
                        max: 0.0,
                    });
                }
                Ok(Coefficients {
                    alpha_m: 0.0,
                    alpha_f: -alpha,
                    beta: 0.25 * (1.0 - alpha) * (1.0 - alpha),
                    gamma: 0.5 - alpha,
                })
            }
            Scheme::GeneralizedAlpha { rho_inf } => {
                if !(0.0..=1.0).contains(&rho_inf) {
                    return Err(IntegrateError::InvalidParameter {
                        scheme: "generalised-alpha",
                        name: "rho_inf",
                        value: rho_inf,
                        min: 0.0,
                        max: 1.0,
                    });
                }
                let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
                let alpha_f = rho_inf / (rho_inf + 1.0);
                let shift = 1.0 - alpha_m + alpha_f;
                Ok(Coefficients {
                    alpha_m,
                    alpha_f,
                    beta: 0.25 * shift * shift,
                    gamma: 0.5 - alpha_m + alpha_f,
                })
            }
        }
    }

    /// Spectral radius of the amplification matrix as `w dt -> inf`: the factor by
    /// which a fully unresolved mode shrinks per step.
    pub fn rho_infinity(self) -> f64 {
        match self {
            Scheme::AverageAcceleration => 1.0,
            Scheme::Hht { alpha } => (1.0 + alpha) / (1.0 - alpha),
            Scheme::GeneralizedAlpha { rho_inf } => rho_inf,
        }
    }
}

/// Newmark average acceleration: `beta = 1/4`, `gamma = 1/2`, `alpha_m = alpha_f = 0`
/// (the coefficients of [`Scheme::AverageAcceleration`]; a constant so that the dense
/// stepper's step folds them at compile time).
pub const AVERAGE_ACCELERATION: Coefficients = Coefficients {
    alpha_m: 0.0,
    alpha_f: 0.0,
    beta: 0.25,
    gamma: 0.5,
};

/// Parameters of a generalised-alpha step (Chung & Hulbert's notation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficients {
    /// Weight of `a_n` in the inertia term (`M a_{n+1-alpha_m}`).
    pub alpha_m: f64,
    /// Weight of the old state in the damping, stiffness and load terms.
    pub alpha_f: f64,
    /// Newmark beta.
    pub beta: f64,
    /// Newmark gamma.
    pub gamma: f64,
}

impl Coefficients {
    /// Leading-order algorithmic damping ratio of an undamped mode with
    /// `omega_dt = w dt` (see the module docs): `(af - am)(beta - af(1 - am)) W^3 / 2`.
    pub fn algorithmic_damping(&self, omega_dt: f64) -> f64 {
        let (am, af) = (self.alpha_m, self.alpha_f);
        0.5 * (af - am) * (self.beta - af * (1.0 - am)) * omega_dt.powi(3)
    }

    /// Leading-order relative period elongation `T_num/T - 1` of an undamped mode
    /// with `omega_dt = w dt`: `(beta/2 - 1/24 - af(af - am)/2) W^2`.
    pub fn period_elongation(&self, omega_dt: f64) -> f64 {
        let (am, af) = (self.alpha_m, self.alpha_f);
        (0.5 * self.beta - 1.0 / 24.0 - 0.5 * af * (af - am)) * omega_dt * omega_dt
    }

    /// Scale factors `(cm, cc, ck)` of the effective matrix `S = cm M + cc C + ck K`:
    /// `(1 - am, (1 - af) gamma dt, (1 - af) beta dt^2)`.
    pub(crate) fn effective(&self, dt: f64) -> (f64, f64, f64) {
        let (am, af, beta, gamma) = (self.alpha_m, self.alpha_f, self.beta, self.gamma);
        (
            1.0 - am,
            (1.0 - af) * gamma * dt,
            (1.0 - af) * beta * dt * dt,
        )
    }
}

/// The one check of a time step every integrator applies (the sparse stepper, the
/// dense stepper, the exact modal step): finite and positive, else
/// [`IntegrateError::InvalidTimeStep`]. A deck's `dt` is parsed positive by the deck
/// reader and checked against the total time by the transient analysis; this guards
/// the integrators' own callers.
pub(crate) fn check_dt(dt: f64) -> Result<(), IntegrateError> {
    if dt.is_finite() && dt > 0.0 {
        Ok(())
    } else {
        Err(IntegrateError::InvalidTimeStep { dt })
    }
}
