//! Modal superposition transient: each mode integrated exactly.
//!
//! # Formulation
//! With mass-normalised mode shapes `Phi` (`Phi^T M Phi = I`, `Phi^T K Phi =
//! diag(w_i^2)`) and `u = Phi q`, a classically damped system decouples into
//! ```text
//! q_i'' + 2 zeta_i w_i q_i' + w_i^2 q_i = p_i(t),    p = Phi^T f(t)
//! ```
//! Modal damping: `zeta_i = (alpha / w_i + beta w_i) / 2` for Rayleigh `C = alpha M +
//! beta K` ([`rayleigh_damping_ratios`], exact); for a general `C` (e.g. Rayleigh per
//! element set) the diagonal `zeta_i = phi_i^T C phi_i / (2 w_i)`
//! ([`modal_damping_ratios`]), which neglects the off-diagonal modal coupling.
//!
//! # Exact recursion (Nigam & Jennings 1969)
//! For a load linear between samples, `p(t_n + s) = p_n + (p_{n+1} - p_n) s/dt`, the
//! state `x = (q, q')` advances exactly (N. C. Nigam, P. C. Jennings, "Calculation of
//! response spectra from strong-motion earthquake records", Bull. Seismol. Soc. Am. 59
//! (2), 909-922, 1969):
//! ```text
//! x_{n+1} = A x_n + b0 p_n + b1 p_{n+1},   A = exp(F dt),  F = [[0, 1], [-w^2, -2 zeta w]]
//! ```
//! With `h(t)` the unit impulse response (`h(0) = 0, h'(0) = 1`), `e^{Ft} [0; 1] =
//! [h; h']`, and, writing `a = zeta w`,
//! ```text
//! A  = [[g + a h, h], [-w^2 h, g - a h]],   g = e^{-a t} c(t),  h = e^{-a t} s(t)
//! c, s = cos(w_d t), sin(w_d t)/w_d          zeta < 1, w_d^2 = w^2 (1 - zeta^2)
//!        1, t                                zeta = 1
//!        cosh(mu t), sinh(mu t)/mu           zeta > 1, mu^2 = w^2 (zeta^2 - 1)
//! I0 = int_0^dt h,  I1 = int_0^dt s h(s) ds
//! b1 = (I0 - I1/dt, I0/dt),   b0 = (I1/dt, h(dt) - I0/dt)
//! ```
//! `s(t)` is evaluated as `t sinc(w_d t)` so that one formula spans the damping
//! regimes without cancellation near `zeta = 1`; over-damped exponentials are written
//! with the slow and fast rates `w / (zeta + sqrt(zeta^2 - 1))` and
//! `w (zeta + sqrt(zeta^2 - 1))` so nothing overflows. `I0`, `I1` come from
//! integrating the oscillator equation (`I0 = (1 - A_11)/w^2`, `I1 = (h - dt h' -
//! 2a (dt h - I0))/w^2` at `dt`) unless that cancels: when the largest rate times `dt`
//! is at most 1 (including `w = 0`, a rigid-body mode) they are summed from the Taylor
//! series of `h`, and for well-separated over-damped rates from the two exponentials.
//! The recursion has no discretisation error; what remains is round-off.
//!
//! Accelerations are taken from the equation of motion at the sample:
//! `q'' = p - 2 zeta w q' - w^2 q`.
//!
//! # Conventions
//! Units are those of the operators (coil: mm, N, tonne, s; `w` in rad/s). Mode
//! shapes are an `n_dofs x n_modes` dense matrix, rows in the operators' DOF order.

use faer::sparse::SparseColMatRef;
use faer::MatRef;

use super::scheme::check_dt;
use crate::error::integrate::IntegrateError;

/// Displacement and velocity of one modal coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SdofState {
    /// Modal coordinate (sqrt(t) mm in coil: the shapes are mass-normalised).
    pub q: f64,
    /// Modal velocity (sqrt(t) mm/s in coil).
    pub v: f64,
}

/// The exact one-step map of `q'' + 2 zeta w q' + w^2 q = p(t)` for a load linear
/// over the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactSdof {
    omega: f64,
    zeta: f64,
    dt: f64,
    transition: [[f64; 2]; 2],
    /// Response to the load at the start of the step.
    b0: [f64; 2],
    /// Response to the load at the end of the step.
    b1: [f64; 2],
}

impl ExactSdof {
    /// The map over `dt` for circular frequency `omega >= 0` and damping ratio
    /// `zeta >= 0` (under-, critically or over-damped).
    pub fn new(omega: f64, zeta: f64, dt: f64) -> Result<Self, IntegrateError> {
        check_dt(dt)?;
        for (name, value) in [("omega", omega), ("zeta", zeta)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(IntegrateError::InvalidMode {
                    mode: 0,
                    name,
                    value,
                });
            }
        }
        let (g, h) = free_response_functions(omega, zeta, dt);
        let a = zeta * omega;
        let transition = [[g + a * h, h], [-omega * omega * h, g - a * h]];
        let (i0, i1) = load_integrals(omega, zeta, dt, &transition);
        Ok(Self {
            omega,
            zeta,
            dt,
            transition,
            b0: [i1 / dt, h - i0 / dt],
            b1: [i0 - i1 / dt, i0 / dt],
        })
    }

    /// Circular frequency omega (rad/s).
    pub fn omega(&self) -> f64 {
        self.omega
    }

    /// Damping ratio zeta.
    pub fn zeta(&self) -> f64 {
        self.zeta
    }

    /// Time step (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The state-transition matrix `exp(F dt)`.
    pub fn transition(&self) -> [[f64; 2]; 2] {
        self.transition
    }

    /// Advances `x` by `dt` under a load going linearly from `p0` to `p1`.
    #[inline]
    pub fn step(&self, x: &mut SdofState, p0: f64, p1: f64) {
        let [[a11, a12], [a21, a22]] = self.transition;
        let q = a11 * x.q + a12 * x.v + self.b0[0] * p0 + self.b1[0] * p1;
        let v = a21 * x.q + a22 * x.v + self.b0[1] * p0 + self.b1[1] * p1;
        *x = SdofState { q, v };
    }

    /// The acceleration from the equation of motion under load `p`.
    #[inline]
    pub fn acceleration(&self, x: SdofState, p: f64) -> f64 {
        p - 2.0 * self.zeta * self.omega * x.v - self.omega * self.omega * x.q
    }
}

/// `g = e^{-a t} c(t)` and `h = e^{-a t} s(t)` of the module docs.
fn free_response_functions(omega: f64, zeta: f64, t: f64) -> (f64, f64) {
    let a = zeta * omega;
    // (1 - zeta)(1 + zeta) keeps the sign and relative accuracy of w_d^2 near zeta = 1.
    let wd2 = omega * omega * (1.0 - zeta) * (1.0 + zeta);
    if wd2 >= 0.0 {
        let x = wd2.sqrt() * t;
        let sinc = if x == 0.0 { 1.0 } else { x.sin() / x };
        let decay = (-a * t).exp();
        (decay * x.cos(), decay * t * sinc)
    } else {
        let root = ((zeta - 1.0) * (zeta + 1.0)).sqrt();
        let mu = omega * root;
        let x = mu * t;
        if x < 1.0 {
            let decay = (-a * t).exp();
            (decay * x.cosh(), decay * t * (x.sinh() / x))
        } else {
            let (slow, fast) = (omega / (zeta + root), omega * (zeta + root));
            let (es, ef) = ((-slow * t).exp(), (-fast * t).exp());
            (0.5 * (es + ef), 0.5 * (es - ef) / mu)
        }
    }
}

/// `I0 = int_0^dt h` and `I1 = int_0^dt s h(s) ds`, by the branch that does not cancel.
fn load_integrals(omega: f64, zeta: f64, dt: f64, transition: &[[f64; 2]; 2]) -> (f64, f64) {
    let a = zeta * omega;
    let over = zeta > 1.0;
    let root = if over {
        ((zeta - 1.0) * (zeta + 1.0)).sqrt()
    } else {
        0.0
    };
    // Largest |eigenvalue of F| times dt.
    let rho = if over {
        omega * (zeta + root) * dt
    } else {
        omega * dt
    };
    if rho <= 1.0 {
        return load_integrals_series(omega, a, dt);
    }
    if over && (zeta + root) * (zeta + root) >= 2.0 {
        // Rates differ by at least a factor 2: the difference of the two exponential
        // integrals does not cancel.
        let (slow, fast) = (omega / (zeta + root), omega * (zeta + root));
        let scale = 1.0 / (fast - slow);
        let i0 = dt * (phi1(-slow * dt) - phi1(-fast * dt)) * scale;
        let i1 = dt * dt * (psi(-slow * dt) - psi(-fast * dt)) * scale;
        return (i0, i1);
    }
    let w2 = omega * omega;
    let (h, hd) = (transition[0][1], transition[1][1]);
    let i0 = (1.0 - transition[0][0]) / w2;
    let i1 = (h - dt * hd - 2.0 * a * (dt * h - i0)) / w2;
    (i0, i1)
}

/// Taylor series of the impulse response, `e_k = h^(k)(0) dt^k / k!`, with
/// `h'' = -2a h' - w^2 h`. Converges like `rho^k / k!` with `rho <= 1`; 30 terms
/// reach round-off.
fn load_integrals_series(omega: f64, a: f64, dt: f64) -> (f64, f64) {
    let (two_a_dt, w2_dt2) = (2.0 * a * dt, omega * omega * dt * dt);
    let (mut e_prev, mut e) = (0.0, dt);
    let (mut i0, mut i1) = (0.0, 0.0);
    for k in 1..32 {
        let kf = k as f64;
        i0 += e * dt / (kf + 1.0);
        i1 += e * dt * dt / (kf + 2.0);
        let next = -two_a_dt * e / (kf + 1.0) - w2_dt2 * e_prev / (kf * (kf + 1.0));
        e_prev = e;
        e = next;
    }
    (i0, i1)
}

/// `(e^z - 1)/z`.
fn phi1(z: f64) -> f64 {
    if z == 0.0 {
        1.0
    } else {
        z.exp_m1() / z
    }
}

/// `int_0^1 s e^{z s} ds = ((z - 1) e^z + 1)/z^2`, by its series where that cancels.
fn psi(z: f64) -> f64 {
    if z.abs() < 1.0 {
        // sum_k z^k / (k! (k + 2))
        let (mut term, mut sum) = (1.0, 0.0);
        for k in 0..30 {
            sum += term / (k as f64 + 2.0);
            term *= z / (k as f64 + 1.0);
        }
        sum
    } else {
        ((z - 1.0) * z.exp() + 1.0) / (z * z)
    }
}

/// Mode shapes with their frequencies and damping ratios.
#[derive(Debug, Clone, Copy)]
pub struct ModalBasis<'a> {
    /// Mass-normalised mode shapes, `n_dofs x n_modes` (`Phi^T M Phi = I`).
    pub shapes: MatRef<'a, f64>,
    /// Circular frequencies `w_i` (rad/s), one per mode.
    pub omega: &'a [f64],
    /// Modal damping ratios `zeta_i`, one per mode.
    pub zeta: &'a [f64],
}

/// Modal coordinates and velocities at time `t`.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalState {
    /// Time (s).
    pub t: f64,
    /// Modal coordinates, one per mode (sqrt(t) mm in coil).
    pub q: Vec<f64>,
    /// Modal velocities, one per mode (sqrt(t) mm/s in coil).
    pub qd: Vec<f64>,
}

/// Displacement, velocity and acceleration at the requested DOFs, in request order.
#[derive(Debug, Clone, Copy)]
pub struct DofResponse<'a> {
    /// Displacements at the requested DOFs (mm or rad in coil).
    pub u: &'a [f64],
    /// Velocities at the requested DOFs (mm/s or rad/s in coil).
    pub v: &'a [f64],
    /// Accelerations at the requested DOFs (mm/s^2 or rad/s^2 in coil).
    pub a: &'a [f64],
}

/// `zeta_i = (alpha / w_i + beta w_i) / 2` for Rayleigh damping `C = alpha M + beta K`.
pub fn rayleigh_damping_ratios(omega: &[f64], alpha: f64, beta: f64) -> Vec<f64> {
    omega
        .iter()
        .map(|&w| 0.5 * (alpha / w + beta * w))
        .collect()
}

/// `zeta_i = phi_i^T C phi_i / (2 w_i)` with mass-normalised `phi_i`; exact for
/// classical damping, the diagonal approximation otherwise.
pub fn modal_damping_ratios(
    shapes: MatRef<'_, f64>,
    omega: &[f64],
    c: SparseColMatRef<'_, usize, f64>,
) -> Result<Vec<f64>, IntegrateError> {
    let n = shapes.nrows();
    check_len("omega", omega.len(), shapes.ncols())?;
    check_len("damping matrix C rows", c.nrows(), n)?;
    check_len("damping matrix C columns", c.ncols(), n)?;
    let mut phi = vec![0.0; n];
    let mut c_phi = vec![0.0; n];
    let mut zeta = Vec::with_capacity(omega.len());
    for (mode, &w) in omega.iter().enumerate() {
        if !(w.is_finite() && w > 0.0) {
            return Err(IntegrateError::InvalidMode {
                mode,
                name: "omega (must be > 0 for a damping ratio)",
                value: w,
            });
        }
        for (i, p) in phi.iter_mut().enumerate() {
            *p = shapes[(i, mode)];
        }
        sparse_mul(c, &phi, &mut c_phi);
        let quadratic: f64 = phi.iter().zip(&c_phi).map(|(p, cp)| p * cp).sum();
        zeta.push(quadratic / (2.0 * w));
    }
    Ok(zeta)
}

/// `out = Phi^T x` (e.g. modal loads `p = Phi^T f`).
pub fn project(shapes: MatRef<'_, f64>, x: &[f64], out: &mut [f64]) -> Result<(), IntegrateError> {
    check_len("vector to project", x.len(), shapes.nrows())?;
    check_len("modal output", out.len(), shapes.ncols())?;
    for (mode, o) in out.iter_mut().enumerate() {
        *o = (0..shapes.nrows()).map(|i| shapes[(i, mode)] * x[i]).sum();
    }
    Ok(())
}

/// Modal coordinates of a physical field: `q = Phi^T M x` (exact when `x` lies in the
/// span of the modes, the M-orthogonal projection otherwise).
pub fn modal_coordinates(
    shapes: MatRef<'_, f64>,
    m: SparseColMatRef<'_, usize, f64>,
    x: &[f64],
) -> Result<Vec<f64>, IntegrateError> {
    let n = shapes.nrows();
    check_len("mass matrix M rows", m.nrows(), n)?;
    check_len("mass matrix M columns", m.ncols(), n)?;
    check_len("field to decompose", x.len(), n)?;
    let mut mx = vec![0.0; n];
    sparse_mul(m, x, &mut mx);
    let mut q = vec![0.0; shapes.ncols()];
    project(shapes, &mx, &mut q)?;
    Ok(q)
}

/// Runs the modal superposition for `n_steps` steps of `dt` from `initial`.
/// `modal_load(t, p)` writes the modal loads `Phi^T f(t)` into the zeroed `p`
/// (the load is taken linear between samples). `observer(k, t, response)` sees the
/// response at `dofs` for `k = 0..=n_steps`. Returns the final modal state.
pub fn integrate_modal(
    basis: ModalBasis<'_>,
    dt: f64,
    n_steps: usize,
    initial: &ModalState,
    dofs: &[usize],
    modal_load: &mut dyn FnMut(f64, &mut [f64]),
    observer: &mut dyn FnMut(usize, f64, &DofResponse<'_>),
) -> Result<ModalState, IntegrateError> {
    let n_modes = basis.shapes.ncols();
    let n_dofs = basis.shapes.nrows();
    check_len("omega", basis.omega.len(), n_modes)?;
    check_len("zeta", basis.zeta.len(), n_modes)?;
    check_len("initial q", initial.q.len(), n_modes)?;
    check_len("initial qd", initial.qd.len(), n_modes)?;
    if let Some(&dof) = dofs.iter().find(|&&d| d >= n_dofs) {
        return Err(IntegrateError::DofOutOfRange { dof, n_dofs });
    }
    let maps = basis
        .omega
        .iter()
        .zip(basis.zeta)
        .enumerate()
        .map(|(mode, (&w, &z))| {
            ExactSdof::new(w, z, dt).map_err(|e| match e {
                IntegrateError::InvalidMode { name, value, .. } => {
                    IntegrateError::InvalidMode { mode, name, value }
                }
                other => other,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    // Rows of Phi at the output DOFs, row-major, so each output is one dot product.
    let phi_out: Vec<f64> = dofs
        .iter()
        .flat_map(|&d| (0..n_modes).map(move |j| basis.shapes[(d, j)]))
        .collect();

    let mut x: Vec<SdofState> = initial
        .q
        .iter()
        .zip(&initial.qd)
        .map(|(&q, &v)| SdofState { q, v })
        .collect();
    let mut p_n = vec![0.0; n_modes];
    let mut p_next = vec![0.0; n_modes];
    let mut qdd = vec![0.0; n_modes];
    let n_out = dofs.len();
    let (mut u, mut v, mut a) = (vec![0.0; n_out], vec![0.0; n_out], vec![0.0; n_out]);
    let t0 = initial.t;
    modal_load(t0, &mut p_n);

    let mut emit = |k: usize,
                    t: f64,
                    x: &[SdofState],
                    p: &[f64],
                    qdd: &mut [f64]|
     -> Result<(), IntegrateError> {
        for (j, ((map, xj), pj)) in maps.iter().zip(x).zip(p).enumerate() {
            qdd[j] = map.acceleration(*xj, *pj);
        }
        for r in 0..n_out {
            let row = &phi_out[r * n_modes..(r + 1) * n_modes];
            let (mut ur, mut vr, mut ar) = (0.0, 0.0, 0.0);
            for ((&phi, xj), &aj) in row.iter().zip(x).zip(qdd.iter()) {
                ur += phi * xj.q;
                vr += phi * xj.v;
                ar += phi * aj;
            }
            u[r] = ur;
            v[r] = vr;
            a[r] = ar;
        }
        if let Some(mode) = x.iter().position(|s| !(s.q.is_finite() && s.v.is_finite())) {
            return Err(IntegrateError::NonFiniteState {
                step: k,
                time: t,
                dof: mode,
            });
        }
        observer(
            k,
            t,
            &DofResponse {
                u: &u,
                v: &v,
                a: &a,
            },
        );
        Ok(())
    };

    emit(0, t0, &x, &p_n, &mut qdd)?;
    for k in 1..=n_steps {
        if k % 64 == 0 && coil_io::cancel::requested() {
            return Err(IntegrateError::Interrupted { step: k });
        }
        let t = t0 + k as f64 * dt;
        p_next.fill(0.0);
        modal_load(t, &mut p_next);
        for (((map, xj), &p0), &p1) in maps.iter().zip(x.iter_mut()).zip(&p_n).zip(&p_next) {
            map.step(xj, p0, p1);
        }
        emit(k, t, &x, &p_next, &mut qdd)?;
        std::mem::swap(&mut p_n, &mut p_next);
    }
    Ok(ModalState {
        t: t0 + n_steps as f64 * dt,
        q: x.iter().map(|s| s.q).collect(),
        qd: x.iter().map(|s| s.v).collect(),
    })
}

fn check_len(what: &'static str, found: usize, expected: usize) -> Result<(), IntegrateError> {
    if found == expected {
        Ok(())
    } else {
        Err(IntegrateError::DimensionMismatch {
            what,
            expected,
            found,
        })
    }
}

/// `y = A x` for a CSC matrix holding both triangles.
fn sparse_mul(a: SparseColMatRef<'_, usize, f64>, x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    for (j, &xj) in x.iter().enumerate().take(a.ncols()) {
        for (&i, &v) in a
            .symbolic()
            .row_idx_of_col_raw(j)
            .iter()
            .zip(a.val_of_col(j))
        {
            y[i] += v * xj;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Textbook free response from (q0, v0), written per regime independently of the
    /// unified formulas above.
    fn analytic_free(omega: f64, zeta: f64, q0: f64, v0: f64, t: f64) -> (f64, f64) {
        let a = zeta * omega;
        if zeta < 1.0 {
            let wd = omega * (1.0 - zeta * zeta).sqrt();
            let (c1, c2) = (q0, (v0 + a * q0) / wd);
            let e = (-a * t).exp();
            let (s, c) = (wd * t).sin_cos();
            let q = e * (c1 * c + c2 * s);
            let v = e * (-a * (c1 * c + c2 * s) + wd * (-c1 * s + c2 * c));
            (q, v)
        } else if zeta == 1.0 {
            let e = (-omega * t).exp();
            let b = v0 + omega * q0;
            (e * (q0 + b * t), e * (b - omega * (q0 + b * t)))
        } else {
            let mu = omega * (zeta * zeta - 1.0).sqrt();
            let (r1, r2) = (-a + mu, -a - mu);
            let c1 = (v0 - r2 * q0) / (r1 - r2);
            let c2 = q0 - c1;
            let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
            (c1 * e1 + c2 * e2, c1 * r1 * e1 + c2 * r2 * e2)
        }
    }

    #[test]
    fn exact_recursion_matches_the_analytic_free_decay() {
        // Up to w t = 94 (15 periods; critical damping has then decayed by e^-94,
        // nowhere near underflow). Round-off grows like n eps for distinct roots but like
        // n^2 eps at critical damping (a Jordan block: a perturbation splits the double
        // root by sqrt(eps)); this horizon keeps it below 1e-12 with a margin (measured
        // 2.5e-13 here, 5e-12 after 2000 steps at w dt = 0.19).
        let omega = 2.0 * PI * 3.0;
        for (zeta, dt) in [0.0, 0.001, 1.0, 2.0]
            .into_iter()
            .flat_map(|z| [(z, 0.01), (z, 0.1)])
        {
            let n = (94.0 / (omega * dt)).round() as usize;
            let map = ExactSdof::new(omega, zeta, dt).unwrap();
            let (q0, v0) = (1.0, -5.0);
            let mut x = SdofState { q: q0, v: v0 };
            let mut worst = 0.0f64;
            for k in 1..=n {
                map.step(&mut x, 0.0, 0.0);
                let (q, v) = analytic_free(omega, zeta, q0, v0, k as f64 * dt);
                // Relative to the state's size in the energy norm at that time
                // (pointwise relative error is meaningless at zero crossings).
                let size = q.abs() + v.abs() / omega;
                worst = worst.max(((x.q - q).abs() + (x.v - v).abs() / omega) / size);
            }
            eprintln!("exact SDOF, zeta = {zeta}, w dt = {:.2}: worst relative error over {n} steps {worst:.2e}", omega * dt);
            assert!(worst < 1e-12, "zeta = {zeta}: {worst}");
        }
    }

    #[test]
    fn transition_is_continuous_through_critical_damping() {
        let (omega, dt) = (10.0, 0.05);
        let critical = ExactSdof::new(omega, 1.0, dt).unwrap().transition();
        for zeta in [1.0 - 1e-9, 1.0 + 1e-9] {
            let near = ExactSdof::new(omega, zeta, dt).unwrap().transition();
            for i in 0..2 {
                for j in 0..2 {
                    // dA/dzeta is O(omega dt) here: a 1e-9 change moves A by ~1e-9.
                    assert!(
                        (near[i][j] - critical[i][j]).abs() < 1e-8,
                        "zeta {zeta}: A[{i}][{j}]"
                    );
                }
            }
        }
    }

    #[test]
    fn recursion_is_exact_for_piecewise_linear_loads() {
        // One step of dt and 64 sub-steps of dt/64 under the same linear load must agree:
        // the recursion has no discretisation error. The big step and the sub-steps
        // take different branches (closed form, two exponentials, Taylor series).
        for (omega, zeta, dt) in [
            (3.0, 0.0, 1.0),
            (3.0, 0.05, 1.0),
            (3.0, 1.0, 1.0),
            (3.0, 2.0, 1.0),
            (3.0, 30.0, 1.0),
            (3.0, 1.02, 1.0),
            (50.0, 0.3, 0.1),
            (0.0, 0.0, 0.5),
        ] {
            let (p0, p1) = (2.0, -7.0);
            let big = ExactSdof::new(omega, zeta, dt).unwrap();
            let mut x_big = SdofState { q: 0.3, v: -1.0 };
            big.step(&mut x_big, p0, p1);
            let n = 64;
            let small = ExactSdof::new(omega, zeta, dt / n as f64).unwrap();
            let mut x = SdofState { q: 0.3, v: -1.0 };
            for k in 0..n {
                let load = |k: usize| p0 + (p1 - p0) * k as f64 / n as f64;
                small.step(&mut x, load(k), load(k + 1));
            }
            let scale = x_big.q.abs() + x_big.v.abs() * dt + (p0.abs() + p1.abs()) * dt * dt;
            let e = (x.q - x_big.q).abs() + (x.v - x_big.v).abs() * dt;
            assert!(
                e < 1e-12 * scale,
                "w = {omega}, zeta = {zeta}: {e:e} vs scale {scale:e}"
            );
        }
    }

    #[test]
    fn closed_forms_of_special_loads() {
        // Rigid-body mode (w = 0): q = q0 + v0 t + p t^2 / 2 under a constant load.
        let map = ExactSdof::new(0.0, 0.0, 0.1).unwrap();
        let mut x = SdofState { q: 1.0, v: 2.0 };
        for _ in 0..10 {
            map.step(&mut x, 3.0, 3.0);
        }
        assert!(
            (x.q - (1.0 + 2.0 + 1.5)).abs() < 1e-13 && (x.v - 5.0).abs() < 1e-13,
            "{x:?}"
        );
        // A held load on a damped oscillator settles at p / w^2.
        let map = ExactSdof::new(4.0, 0.2, 0.05).unwrap();
        let mut x = SdofState::default();
        for _ in 0..4000 {
            map.step(&mut x, 8.0, 8.0);
        }
        assert!((x.q - 0.5).abs() < 1e-13 && x.v.abs() < 1e-13, "{x:?}");
        // Ramp from rest, under-damped: the particular solution p_1 (t - 2 zeta/w)/w^2
        // plus the free response that cancels it at t = 0.
        let (omega, zeta, rate) = (5.0, 0.1, 3.0);
        let map = ExactSdof::new(omega, zeta, 0.02).unwrap();
        let mut x = SdofState::default();
        for k in 0..100 {
            map.step(&mut x, rate * k as f64 * 0.02, rate * (k + 1) as f64 * 0.02);
        }
        let t = 2.0;
        let w2 = omega * omega;
        let (q_free, _) =
            analytic_free(omega, zeta, 2.0 * zeta * rate / (omega * w2), -rate / w2, t);
        let q = rate * (t - 2.0 * zeta / omega) / w2 + q_free;
        assert!((x.q - q).abs() < 1e-13, "{} vs {q}", x.q);
    }

    #[test]
    fn rejects_invalid_modes() {
        assert!(matches!(
            ExactSdof::new(-1.0, 0.0, 0.1),
            Err(IntegrateError::InvalidMode { .. })
        ));
        assert!(matches!(
            ExactSdof::new(1.0, f64::NAN, 0.1),
            Err(IntegrateError::InvalidMode { .. })
        ));
        assert!(matches!(
            ExactSdof::new(1.0, 0.0, 0.0),
            Err(IntegrateError::InvalidTimeStep { .. })
        ));
        let shapes = faer::Mat::<f64>::identity(2, 2);
        let basis = ModalBasis {
            shapes: shapes.as_ref(),
            omega: &[1.0, 2.0],
            zeta: &[0.0, 0.0],
        };
        let initial = ModalState {
            t: 0.0,
            q: vec![0.0; 2],
            qd: vec![0.0; 2],
        };
        let out_of_range = integrate_modal(
            basis,
            0.1,
            1,
            &initial,
            &[2],
            &mut |_, _| {},
            &mut |_, _, _| {},
        );
        assert!(matches!(
            out_of_range,
            Err(IntegrateError::DofOutOfRange { dof: 2, .. })
        ));
        let basis = ModalBasis {
            shapes: shapes.as_ref(),
            omega: &[1.0, f64::INFINITY],
            zeta: &[0.0, 0.0],
        };
        let bad = integrate_modal(
            basis,
            0.1,
            1,
            &initial,
            &[0],
            &mut |_, _| {},
            &mut |_, _, _| {},
        );
        assert!(matches!(
            bad,
            Err(IntegrateError::InvalidMode { mode: 1, .. })
        ));
    }
}
