//! The reduced spring model the diagnosis fits: the linear FE spring of the case
//! (coil-mesher, calibrated E) reduced by Craig-Bampton to the weight's DOFs plus a few
//! fixed-interface modes (`coil_solver::reduce`), with the catalogue's nonlinear element
//! at the weight, integrated by the dense average-acceleration stepper
//! (`coil_solver::integrate::dense`).
//!
//! # Mounts and reduced coordinates
//! - [`Mount::Guided`] (the paper's model): the weight moves along the axis only;
//!   boundary `q_0 = u_z` of node 1 (mm).
//! - [`Mount::FreeRotation`]: the weight also turns about the axis; boundary
//!   `q_0 = u_z`, `q_1 = r_z` (rad). The axial-torsional coupling comes from the helix's
//!   own stiffness (the off-diagonal of the reduced boundary stiffness), never from a
//!   fitted constant.
//!
//! # Parameters ([`Physical`], SI) and their place in the operators (solver units)
//! `M = M_wire + M_points + diag(dm, dJ)` with `dm` the weight's mass minus the mass the
//! model was meshed with and `dJ` the weight's rotary inertia (1 kg m^2 = 1e3 t mm^2);
//! `C = beta K` (alpha = 0, see the diagnosis docs); `K = s K_0` (`s` rescales E). The
//! point law at `u_z` (`coil_solver::integrate::PointLaw`): Coulomb `F` (N), velocity
//! squared `c2` (1 N s^2/m^2 = 1e-6 N s^2/mm^2), cubic `k3` (1 N/m^3 = 1e-9 N/mm^3).
//!
//! # Gravity and the cubic spring
//! The cubic law acts on the displacement from the free length (the mesh's reference),
//! so a model with a cubic spring carries the weight's gravity load `-m g` along the
//! axis; the record's initial state is taken about the static equilibrium
//! (`DenseStepper::static_equilibrium`). Linear models need no preload: their decay
//! about the equilibrium does not depend on it.
//!
//! # Step
//! The step divides the record's sample interval into `substeps` so that
//! `w dt <= OMEGA_DT` (0.1, about 63 steps per period) for the axial mode, `w` the
//! weight on the spring's boundary stiffness. The average-acceleration rule runs a mode
//! of frequency `w` at `(2 / dt) atan(w dt / 2)`, a period long by `(w dt)^2 / 12`
//! (8.3e-4 here, which the fitted mass would absorb as a bias of twice that). The mass
//! matrix is therefore divided by [`period_warp`] `s = (tan(w dt/2) / (w dt/2))^2`,
//! which makes the discrete frequency of a mode at `w` exact; the axial mode, whose
//! frequency is `w` lowered by the spring's own mass (a few per cent), keeps an error
//! of `(w dt)^2 / 6` times that shift (below 1e-4 of the period), and a coupled pair 9 %
//! apart 1.5e-4. The acceleration of a law force over the divided mass is `s` times
//! larger (1.7e-3 relative at most): a bias of that size on the fitted law's parameter,
//! far below every record's noise and the 15 % of the confusion table. The rule is
//! energy-conserving, so the step adds no numerical damping to the decay, and a
//! law's loss per cycle is integrated to `O((w dt)^2)`. Measured on the 61 generated
//! cases against the former `w dt <= 0.03`: every parameter moved by at most 0.2 % of
//! its value (docs/diagnose.md), for 3.3 times fewer steps.
//!
//! A record sampled finer than that (`w h < OMEGA_DT / 2`, `h` the sample interval:
//! 2 000 samples per second on a 4.5 Hz spring is `w h` = 0.014) is stepped every
//! `stride = floor(OMEGA_DT / (w h))` samples instead, at the same `w dt <= 0.1`, and
//! the samples between two steps are read off the cubic through the four nearest
//! steps (`interpolate`: within `(w dt)^4 / 24` = 4.2e-6 of a sinusoid's amplitude, far
//! below the step's own error above). Friction makes the velocity kink and the
//! acceleration jump at every reversal, which no cubic follows: a model with friction
//! steps at every sample of a velocity or acceleration record (a displacement stays
//! smooth through a reversal). So does the free-rotation model: its two lines a few per
//! cent apart can be fitted from either side of their crossing (the mass and `J`
//! swapped between the modes, the free initial rotation giving each line its
//! amplitude), and on `cases/measured/coupling_g5` the coarser step tipped the fit to
//! the other side (`J` +4.2 % and the mass -6 %, for a residual lower by 4e-5 of it).

use super::effects::{self, Extension, Mount, COUNT};
use crate::case::Quantity;
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use coil_mesher::{Top, WEIGHT_NODE};
use coil_solver::integrate::dense::{DenseStepper, Sample};
use coil_solver::model::units;
use coil_solver::reduce::{craig_bampton, Reduction};
use nalgebra::{DMatrix, DVector};

/// Largest `w dt` of the axial mode.
pub const OMEGA_DT: f64 = 0.1;

/// The factor `s = (tan(w dt / 2) / (w dt / 2))^2` that divides the mass matrix so that
/// the average-acceleration rule runs a mode of frequency `w` at exactly `w`: the rule
/// runs a mode of stiffness `k` and mass `m / s` at `(2 / dt) atan(sqrt(s) w dt / 2)`,
/// which is `w` (module docs, "Step").
pub fn period_warp(omega_dt: f64) -> f64 {
    let half = 0.5 * omega_dt;
    if half == 0.0 {
        1.0
    } else {
        (half.tan() / half).powi(2)
    }
}

/// A sample's value of the recorded `quantity` (SI).
fn quantity_of(quantity: Quantity, s: &Sample) -> f64 {
    units::length_to_si(match quantity {
        Quantity::Acceleration => s.a,
        Quantity::Velocity => s.v,
        Quantity::Displacement => s.u,
    })
}

/// How a record's samples map onto the stepper's steps: `substeps` steps per sample
/// (a coarse record), or one step every `stride` samples (a record sampled finer than
/// the step needs); one of the two is 1.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Stepping {
    substeps: usize,
    stride: usize,
}

/// The `n` samples of a signal known at every `stride`-th sample (`stepped[j]` at
/// sample `j stride`): the known samples as they are, the others by the cubic through
/// the four nearest known ones (the interval's two and one on either side; the first
/// and last four at the ends). A sinusoid stepped at `w stride dt = x` is read within
/// `(9 / 16) x^4 / 24` of its amplitude between the middle nodes (2.3e-6 at
/// `x = 0.1`), at most `x^4 / 24` in the end intervals; fewer than four steps are
/// joined by straight lines.
fn interpolate(stepped: &[f64], stride: usize, n: usize) -> Vec<f64> {
    if stride <= 1 {
        return stepped[..n.min(stepped.len())].to_vec();
    }
    let nc = stepped.len();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let (j, r) = (i / stride, i % stride);
        if r == 0 || j + 1 >= nc {
            out.push(stepped[j.min(nc - 1)]);
            continue;
        }
        let s = r as f64 / stride as f64;
        if nc < 4 {
            out.push(stepped[j] + s * (stepped[j + 1] - stepped[j]));
            continue;
        }
        // The stencil's first node, and the point's place in it (0..3).
        let b = j.saturating_sub(1).min(nc - 4);
        let t = (j - b) as f64 + s;
        let y = &stepped[b..b + 4];
        // Lagrange weights on the nodes 0, 1, 2, 3.
        let (t0, t1, t2, t3) = (t, t - 1.0, t - 2.0, t - 3.0);
        let w0 = -t1 * t2 * t3 / 6.0;
        let w1 = t0 * t2 * t3 / 2.0;
        let w2 = -t0 * t1 * t3 / 2.0;
        let w3 = t0 * t1 * t2 / 6.0;
        out.push(w0 * y[0] + w1 * y[1] + w2 * y[2] + w3 * y[3]);
    }
    out
}

/// The fitted physical parameters (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Physical {
    /// The weight's mass (kg).
    pub mass_kg: f64,
    /// Rayleigh beta on the spring (s).
    pub beta_s: f64,
    /// Stiffness scale against the calibrated E.
    pub k_scale: f64,
    /// Each catalogue effect's magnitude in its SI unit (0: absent), indexed as
    /// `effects::CATALOGUE`.
    pub effects: [f64; COUNT],
    /// Gravity along the spring axis (m/s^2); it preloads a model with a cubic spring.
    pub gravity_m_s2: f64,
}

impl Physical {
    /// The paper's linear model.
    pub fn linear(mass_kg: f64, beta_s: f64, gravity_m_s2: f64) -> Self {
        Physical {
            mass_kg,
            beta_s,
            k_scale: 1.0,
            effects: [0.0; COUNT],
            gravity_m_s2,
        }
    }

    /// What the effects add to the model.
    pub fn extension(&self) -> Extension {
        effects::extension(&self.effects)
    }
}

/// The linear operators `(M, K)` and the base-acceleration load of a reduced spring.
pub type LinearOperators = (DMatrix<f64>, DMatrix<f64>, DVector<f64>);

/// A reduced spring ready to simulate decays.
#[derive(Debug, Clone)]
pub struct ReducedSpring {
    reduction: Reduction,
    mount: Mount,
    /// The weight's mass the model was meshed with (kg).
    meshed_mass_kg: f64,
}

fn reduce_error(e: impl std::fmt::Display) -> TuneError {
    TuneError::Invalid(format!("reduced model: {e}"))
}

impl ReducedSpring {
    /// Meshes the spring of `state` with `fe` and reduces it.
    pub fn build(state: &SpringState, fe: &FeSettings, mount: Mount, modes: usize) -> Result<Self> {
        let mut spec = state.spec(fe, &[]);
        let boundary: Vec<(u32, u8)> = match mount {
            Mount::Guided => {
                spec.top = Top::Guided;
                vec![(WEIGHT_NODE, 3)]
            }
            Mount::FreeRotation => {
                spec.top = Top::FreeRotation;
                vec![(WEIGHT_NODE, 3), (WEIGHT_NODE, 6)]
            }
        };
        let model = spec.build()?;
        let reduction = craig_bampton(&model, &boundary, modes).map_err(reduce_error)?;
        Ok(ReducedSpring {
            reduction,
            mount,
            meshed_mass_kg: state.mass_kg,
        })
    }

    /// True when the parameters put a nonlinear force on the weight.
    pub fn is_nonlinear(&self, p: &Physical) -> bool {
        !p.extension().law.is_zero()
    }

    /// The mount the model was built with.
    pub fn mount(&self) -> Mount {
        self.mount
    }

    fn extra_mass(&self, p: &Physical, e: &Extension) -> Vec<f64> {
        let mut extra = vec![units::mass_from_si(p.mass_kg - self.meshed_mass_kg)];
        if self.mount == Mount::FreeRotation {
            extra.push(units::inertia_from_si(e.rotary_inertia_kg_m2));
        }
        extra
    }

    /// The linear operators `(M, K)` (solver units: t, N/mm) with the weight's mass
    /// `mass_kg`, its rotary inertia `rotary_inertia_kg_m2` (free rotation only) and the
    /// stiffness scale `k_scale`, and the reduced inertial load of a unit axial base
    /// acceleration (t; `coil_solver::reduce::Reduction::translation_load`).
    pub fn linear_operators(
        &self,
        mass_kg: f64,
        rotary_inertia_kg_m2: f64,
        k_scale: f64,
    ) -> std::result::Result<LinearOperators, String> {
        let mut extra = vec![0.0; self.reduction.boundary.len()];
        extra[0] = units::mass_from_si(mass_kg - self.meshed_mass_kg);
        if self.mount == Mount::FreeRotation {
            extra[1] = units::inertia_from_si(rotary_inertia_kg_m2);
        }
        let ops = self
            .reduction
            .operators(k_scale, &extra, 0.0, 0.0)
            .map_err(|e| e.to_string())?;
        let load = self
            .reduction
            .translation_load(3, &extra)
            .map_err(|e| e.to_string())?;
        Ok((ops.m, ops.k, load))
    }

    /// Static boundary stiffness of the guided axial DOF (N/m).
    pub fn stiffness_n_m(&self, p: &Physical) -> f64 {
        self.reduction.k[(0, 0)] * p.k_scale * 1e3
    }

    /// The free-rotation boundary stiffness: axial (N/m), coupling (N/rad), torsional
    /// (N m/rad). For a guided model the last two are zero.
    pub fn boundary_stiffness(&self, p: &Physical) -> (f64, f64, f64) {
        let k = &self.reduction.k;
        let s = p.k_scale;
        if self.mount == Mount::FreeRotation {
            (k[(0, 0)] * s * 1e3, k[(0, 1)] * s, k[(1, 1)] * s * 1e-3)
        } else {
            (k[(0, 0)] * s * 1e3, 0.0, 0.0)
        }
    }

    fn stepper(
        &self,
        p: &Physical,
        step_s: f64,
        quantity: Quantity,
    ) -> std::result::Result<(DenseStepper, Stepping), String> {
        let e = p.extension();
        if !(p.mass_kg > 0.0
            && p.beta_s >= 0.0
            && p.k_scale > 0.0
            && e.law.is_valid()
            && e.rotary_inertia_kg_m2 >= 0.0)
        {
            return Err(format!("parameters out of range: {p:?}"));
        }
        let ops = self
            .reduction
            .operators(p.k_scale, &self.extra_mass(p, &e), 0.0, p.beta_s)
            .map_err(|e| e.to_string())?;
        let omega = (self.stiffness_n_m(p) / p.mass_kg).sqrt();
        // A trial beyond the record's Nyquist frequency cannot be what the record shows,
        // and would cost unbounded substeps (a fit stepping its mass towards zero).
        if omega.is_nan() || omega * step_s > std::f64::consts::PI {
            return Err(format!(
                "the trial's axial frequency {:.4e} Hz is beyond the record's Nyquist \
                 frequency {:.4e} Hz",
                omega / std::f64::consts::TAU,
                0.5 / step_s
            ));
        }
        let substeps = ((omega * step_s / OMEGA_DT).ceil() as usize).max(1);
        // A record sampled finer than the step needs is stepped every `stride` samples
        // (module docs, "Step"): not through friction's jumps in a velocity or an
        // acceleration, nor on the free-rotation mount.
        let smooth = e.law.friction == 0.0 || quantity == Quantity::Displacement;
        let stride = if substeps == 1 && smooth && self.mount == Mount::Guided {
            ((OMEGA_DT / (omega * step_s)).floor() as usize).max(1)
        } else {
            1
        };
        let dt = step_s * stride as f64 / substeps as f64;
        let law = e.law;
        let laws = if law.is_zero() {
            vec![]
        } else {
            vec![(0, law)]
        };
        // The axial mode's period error of the scheme, removed (module docs, "Step").
        let m = &ops.m / period_warp(omega * dt);
        let stepper =
            DenseStepper::new(&m, &ops.c, &ops.k, dt, &laws).map_err(|e| e.to_string())?;
        Ok((stepper, Stepping { substeps, stride }))
    }

    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        p: &Physical,
        stepper: &mut DenseStepper,
        stepping: Stepping,
        u0: &[f64],
        v0: &[f64],
        n: usize,
        quantity: Quantity,
    ) -> std::result::Result<Vec<f64>, String> {
        let Stepping { substeps, stride } = stepping;
        // Every `stride`-th sample is a step (the last at or past the record's end).
        let steps = if stride > 1 {
            n.saturating_sub(1).div_ceil(stride) + 1
        } else {
            n
        };
        let samples = stepper.simulate(u0, v0, steps, substeps, 0).map_err(|e| {
            let cubic = p.extension().law.cubic;
            if cubic < 0.0 {
                format!(
                    "{e}: the softening spring (k3 = {:.4e} N/m^3) lost stability",
                    cubic * 1e9
                )
            } else {
                e.to_string()
            }
        })?;
        // A softening spring's free motion stays bounded while its energy is below the
        // potential's saddle; past `k x + k3 x^3 = 0` (x from the free length) the
        // spring pushes outwards and the weight cannot come back: a trial that gets
        // there is an error naming the point, not a NaN or a spring that snaps
        // through. (A motion through the region of negative tangent stiffness,
        // `k + 3 k3 x^2 < 0`, turns back: it is allowed.)
        let law = p.extension().law;
        let k = self.reduction.k[(0, 0)] * p.k_scale;
        let limit_mm = law.escape_displacement(k);
        if let Some(s) = samples.iter().find(|s| s.u.abs() >= limit_mm) {
            return Err(format!(
                "the softening spring (k3 = {:.4e} N/m^3) snaps through: beyond {:.4} mm from \
                 the free length (k x + k3 x^3 = 0) it pushes outwards; the motion reaches {:.4} mm",
                law.cubic * 1e9,
                limit_mm,
                s.u.abs()
            ));
        }
        // A weight held by friction reads a = 0 (the stepper zeroes a held DOF's
        // acceleration from its second held step).
        let stepped: Vec<f64> = samples.iter().map(|s| quantity_of(quantity, s)).collect();
        Ok(interpolate(&stepped, stride, n))
    }

    /// The weight's axial `quantity` (SI) at `n` samples `step_s` apart for unit
    /// initial states about the equilibrium: per boundary DOF, 1 mm (or 1 rad) of
    /// displacement, then 1 mm/s (or 1 rad/s) of velocity. The response of a linear
    /// model to the state `x` is `sum x_k basis_k`.
    pub fn basis(
        &self,
        p: &Physical,
        step_s: f64,
        n: usize,
        quantity: Quantity,
    ) -> std::result::Result<Vec<Vec<f64>>, String> {
        let (mut stepper, stepping) = self.stepper(p, step_s, quantity)?;
        let r = stepper.dim();
        let nb = self.reduction.boundary.len();
        let mut out = Vec::with_capacity(2 * nb);
        for b in 0..nb {
            for velocity in [false, true] {
                let mut u = vec![0.0; r];
                let mut v = vec![0.0; r];
                if velocity {
                    v[b] = 1.0;
                } else {
                    u[b] = 1.0;
                }
                out.push(self.run(p, &mut stepper, stepping, &u, &v, n, quantity)?);
            }
        }
        // Order: u_b0, v_b0, u_b1, v_b1 ... ; report it as [u, v] pairs per DOF.
        Ok(out)
    }

    /// The weight's axial `quantity` (SI) for the initial state
    /// `[u_0 (mm), v_0 (mm/s), ...]` about the static equilibrium.
    pub fn simulate(
        &self,
        p: &Physical,
        state: &[f64],
        step_s: f64,
        n: usize,
        quantity: Quantity,
    ) -> std::result::Result<Vec<f64>, String> {
        let (mut stepper, stepping) = self.stepper(p, step_s, quantity)?;
        let r = stepper.dim();
        let nb = self.reduction.boundary.len();
        if state.len() != 2 * nb {
            return Err(format!(
                "initial state of {} values; expected {}",
                state.len(),
                2 * nb
            ));
        }
        let mut u = vec![0.0; r];
        let mut v = vec![0.0; r];
        if p.extension().law.cubic != 0.0 && p.gravity_m_s2 != 0.0 {
            let mut f = vec![0.0; r];
            // Gravity pulls the weight toward the base (-z): m g in N.
            f[0] = -p.mass_kg * p.gravity_m_s2;
            stepper.set_load(&f).map_err(|e| e.to_string())?;
            u = stepper.static_equilibrium(&f).map_err(|e| e.to_string())?;
        }
        for b in 0..nb {
            u[b] += state[2 * b];
            v[b] = state[2 * b + 1];
        }
        self.run(p, &mut stepper, stepping, &u, &v, n, quantity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use coil_solver::integrate::dense::DenseStepper;
    use nalgebra::DMatrix;

    /// An undamped oscillator stepped at `w dt = OMEGA_DT`: the samples obey
    /// `u_{n-1} + u_{n+1} = 2 cos(w_d dt) u_n`, which gives the discrete frequency `w_d`.
    /// The plain rule runs slow by `(w dt)^2 / 12` (8.3e-4; the next term of
    /// `(2 / x) atan(x / 2) - 1` is `x^4 / 80` = 1.25e-6);
    /// with the mass divided by `period_warp` it runs at `w` to rounding (1e-10).
    /// A sinusoid known at every 7th sample, `w dt = 0.1` between known samples, read
    /// at every sample: the known samples exact, the others within the cubic's
    /// remainder `max |prod (t - k)| x^4 / 24` (0.5625 between the middle nodes, 1 in
    /// the end intervals, x = 0.1), and a stride of 1 hands the samples back as they are.
    #[test]
    fn the_stepped_samples_are_read_between_by_the_cubic() {
        let (stride, n) = (7, 700);
        let w = 0.1 / stride as f64;
        let at = |i: usize| (w * i as f64 + 0.3).sin();
        let exact: Vec<f64> = (0..n).map(at).collect();
        // As `ReducedSpring::run` steps: the last step at or past the last sample.
        let steps = (n - 1).div_ceil(stride) + 1;
        let stepped: Vec<f64> = (0..steps).map(|j| at(j * stride)).collect();
        let read = interpolate(&stepped, stride, n);
        let last = (steps - 1) * stride;
        let x4 = 0.1f64.powi(4) / 24.0;
        for (i, (r, e)) in read.iter().zip(&exact).enumerate() {
            let bound = if i % stride == 0 {
                0.0
            } else if i < stride || i > last - stride {
                x4
            } else {
                0.5625 * x4
            };
            assert!((r - e).abs() <= bound * 1.0001, "sample {i}: {r} vs {e}");
        }
        assert_eq!(interpolate(&exact, 1, n), exact);
    }

    #[test]
    fn the_warped_mass_removes_the_period_error() {
        let w = std::f64::consts::TAU * 3.0;
        let dt = OMEGA_DT / w;
        let frequency = |warp: f64| {
            let m = DMatrix::from_element(1, 1, 1.0 / warp);
            let k = DMatrix::from_element(1, 1, w * w);
            let c = DMatrix::zeros(1, 1);
            let mut s = DenseStepper::new(&m, &c, &k, dt, &[]).unwrap();
            let u: Vec<f64> = s
                .simulate(&[1.0], &[0.0], 400, 1, 0)
                .unwrap()
                .iter()
                .map(|x| x.u)
                .collect();
            // The sample of largest |u| after the first period, for a well-posed ratio.
            let n = (210..399)
                .max_by(|&i, &j| u[i].abs().total_cmp(&u[j].abs()))
                .unwrap();
            ((u[n - 1] + u[n + 1]) / (2.0 * u[n])).acos() / dt
        };
        let plain = frequency(1.0) / w - 1.0;
        let warped = frequency(period_warp(OMEGA_DT)) / w - 1.0;
        let next = OMEGA_DT.powi(4) / 80.0;
        assert!(
            (plain + OMEGA_DT.powi(2) / 12.0 - next).abs() < 0.1 * next,
            "{plain}"
        );
        assert!(warped.abs() < 1e-10, "{warped}");
    }
}
