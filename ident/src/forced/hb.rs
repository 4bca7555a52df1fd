//! Harmonic balance of the lumped oscillator under `u = A cos(W t)`, the nonlinear terms by
//! alternating frequency-time (AFT).
//!
//! # Formulation
//! With `tau = W t`, the periodic response is the truncated Fourier series
//! ```text
//! z(tau) = x_0 + sum_{k=1..H} ( x_{2k-1} cos k tau + x_{2k} sin k tau )
//! ```
//! and the residual is the Galerkin projection of the equation of motion (model docs) on
//! the same basis. The linear part is exact in the coefficients (harmonic `k`:
//! `(w0^2 - k^2 W^2) a_k + 2 zeta w0 k W b_k` and `(w0^2 - k^2 W^2) b_k - 2 zeta w0 k W a_k`);
//! the nonlinear force `g(z, z')` is evaluated at `N` equally spaced `tau_j` and projected
//! back (AFT), its Jacobian the projection of `g_z phi_m + W g_v phi'_m`. A cubic term
//! produces harmonics up to `3 H`: `N = 16 (H + 1)` samples keep them from aliasing onto the
//! retained ones, and friction's and drag's non-polynomial terms are resolved to the
//! harmonics their smooth forms carry at that sampling.
//!
//! # A reduced FE spring (model docs, "modal form")
//! The further modes are linear: harmonic `k` of mode `i` is `Q_ik = (b_i U_k - a_i G_k) /
//! D_i(k W)`, `D_i(w) = w_i^2 - w^2 + 2 i zeta_i w_i w`, `U`, `G` the complex harmonics of the
//! input and the law (`X = x_cos - i x_sin`). With them eliminated the unknowns stay the
//! harmonics of `z = sum q_i`, and the balance above (mode 1's, multiplied by `D_1`) gains
//! `D_1(k W) sum_{i>1} (a_i G_k - b_i U_k) / D_i(k W)`, exact for any number of modes.
//!
//! Sources: T. M. Cameron, J. H. Griffin, "An alternating frequency/time domain method for
//! calculating the steady-state response of nonlinear dynamic systems", J. Appl. Mech. 56
//! (1989) 149-154; M. Krack, J. Gross, *Harmonic Balance for Nonlinear Vibration Problems*,
//! Springer 2019, chapters 2-3.

// Harmonic and sample indices are the formulation's own (x_n, tau_j, line k): the kernels
// keep them rather than zipping five slices.
#![allow(clippy::needless_range_loop)]

use super::model::Lumped;
use nalgebra::Complex;

/// The harmonic basis sampled at the AFT points.
#[derive(Debug, Clone)]
pub struct Basis {
    /// Harmonics kept, H.
    pub harmonics: usize,
    /// Samples per period, N.
    pub samples: usize,
    /// `phi[n][j]`: basis function n at tau_j.
    phi: Vec<Vec<f64>>,
    /// `dphi[n][j]`: its derivative in tau.
    dphi: Vec<Vec<f64>>,
}

impl Basis {
    /// The basis of `harmonics` harmonics (module docs for the sampling).
    pub fn new(harmonics: usize) -> Basis {
        let samples = 16 * (harmonics + 1);
        let d = 2 * harmonics + 1;
        let mut phi = vec![vec![0.0; samples]; d];
        let mut dphi = vec![vec![0.0; samples]; d];
        for j in 0..samples {
            let tau = std::f64::consts::TAU * j as f64 / samples as f64;
            phi[0][j] = 1.0;
            for k in 1..=harmonics {
                let kf = k as f64;
                let (s, c) = (kf * tau).sin_cos();
                phi[2 * k - 1][j] = c;
                phi[2 * k][j] = s;
                dphi[2 * k - 1][j] = -kf * s;
                dphi[2 * k][j] = kf * c;
            }
        }
        Basis {
            harmonics,
            samples,
            phi,
            dphi,
        }
    }

    /// Unknowns per solution, 2 H + 1.
    pub fn size(&self) -> usize {
        2 * self.harmonics + 1
    }

    /// `z` and `dz/dtau` at every sample.
    pub fn synthesise(&self, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut z = vec![0.0; self.samples];
        let mut dz = vec![0.0; self.samples];
        for (n, &c) in x.iter().enumerate() {
            if c == 0.0 {
                continue;
            }
            for j in 0..self.samples {
                z[j] += c * self.phi[n][j];
                dz[j] += c * self.dphi[n][j];
            }
        }
        (z, dz)
    }

    /// Projection weight of unknown `n` (mean 1/N, harmonics 2/N).
    fn weight(&self, n: usize) -> f64 {
        if n == 0 {
            1.0 / self.samples as f64
        } else {
            2.0 / self.samples as f64
        }
    }

    /// Fourier coefficients of samples `f`.
    pub fn project(&self, f: &[f64]) -> Vec<f64> {
        (0..self.size())
            .map(|n| self.weight(n) * self.phi[n].iter().zip(f).map(|(p, v)| p * v).sum::<f64>())
            .collect()
    }
}

/// The residual `R(x, W)` of the balance, its Jacobian in `x` (row-major `D x D`) and its
/// derivative in `W`, for the forcing amplitude `force = b A` (per unit mass).
#[allow(non_snake_case)]
pub fn residual(
    model: &Lumped,
    basis: &Basis,
    x: &[f64],
    W: f64,
    force: f64,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let d = basis.size();
    let w0 = model.natural_frequency_rad_s;
    let c = 2.0 * model.damping_ratio * w0;
    let mut r = vec![0.0; d];
    let mut jac = vec![0.0; d * d];
    let mut r_w = vec![0.0; d];
    // Linear part.
    r[0] = w0 * w0 * x[0];
    jac[0] = w0 * w0;
    for k in 1..=basis.harmonics {
        let (ic, is) = (2 * k - 1, 2 * k);
        let kf = k as f64;
        let stiff = w0 * w0 - kf * kf * W * W;
        r[ic] = stiff * x[ic] + c * kf * W * x[is];
        r[is] = stiff * x[is] - c * kf * W * x[ic];
        jac[ic * d + ic] = stiff;
        jac[ic * d + is] = c * kf * W;
        jac[is * d + is] = stiff;
        jac[is * d + ic] = -c * kf * W;
        r_w[ic] = -2.0 * kf * kf * W * x[ic] + c * kf * x[is];
        r_w[is] = -2.0 * kf * kf * W * x[is] - c * kf * x[ic];
    }
    r[1] -= force;
    let mut law = None;
    if !model.is_linear() {
        let (z, dz) = basis.synthesise(x);
        let n = basis.samples;
        let mut g = vec![0.0; n];
        let mut gz = vec![0.0; n];
        let mut gv = vec![0.0; n];
        for j in 0..n {
            let v = W * dz[j];
            g[j] = model.restoring(z[j], v);
            let (a, b) = model.restoring_slopes(z[j], v);
            gz[j] = a;
            gv[j] = b;
        }
        let gp = basis.project(&g);
        let gw: Vec<f64> = (0..n).map(|j| gv[j] * dz[j]).collect();
        let gwp = basis.project(&gw);
        for row in 0..d {
            r[row] += gp[row];
            r_w[row] += gwp[row];
        }
        // Jacobian: sum_j phi_n(tau_j) (gz_j phi_m(tau_j) + W gv_j phi'_m(tau_j)).
        let mut columns = Vec::with_capacity(d);
        for m in 0..d {
            let col: Vec<f64> = (0..n)
                .map(|j| gz[j] * basis.phi[m][j] + W * gv[j] * basis.dphi[m][j])
                .collect();
            let p = basis.project(&col);
            for row in 0..d {
                jac[row * d + m] += p[row];
            }
            columns.push(p);
        }
        law = Some((gp, gwp, columns));
    }
    if !model.modes.is_empty() {
        let amplitude = force / model.input_gain;
        further_modes(
            model,
            basis.harmonics,
            W,
            amplitude,
            law.as_ref(),
            &mut r,
            &mut jac,
            &mut r_w,
        );
    }
    (r, jac, r_w)
}

/// `D(w) = w_i^2 - w^2 + 2 i zeta_i w_i w` and its derivative in `w`.
fn dynamic_stiffness(wi: f64, zeta: f64, w: f64) -> (Complex<f64>, Complex<f64>) {
    (
        Complex::new(wi * wi - w * w, 2.0 * zeta * wi * w),
        Complex::new(-2.0 * w, 2.0 * zeta * wi),
    )
}

/// Adds the further modes of a reduced FE spring to the balance (module docs): per
/// harmonic `k`, `Q G - P U` with `Q = D_1 sum a_i / D_i`, `P = D_1 sum b_i / D_i`, to the
/// residual, `Q dG/dx` to the Jacobian and the `W` derivatives to `r_w`. `law` holds the
/// law's harmonics `G`, their `W` derivatives and the columns `dG/dx_m` (none when the
/// model is linear).
#[allow(non_snake_case, clippy::too_many_arguments, clippy::type_complexity)]
fn further_modes(
    model: &Lumped,
    harmonics: usize,
    W: f64,
    amplitude: f64,
    law: Option<&(Vec<f64>, Vec<f64>, Vec<Vec<f64>>)>,
    r: &mut [f64],
    jac: &mut [f64],
    r_w: &mut [f64],
) {
    let d = 2 * harmonics + 1;
    let (w1, z1) = (model.natural_frequency_rad_s, model.damping_ratio);
    for k in 0..=harmonics {
        let kf = k as f64;
        let (d1, d1p) = dynamic_stiffness(w1, z1, kf * W);
        let (mut s, mut sp, mut t, mut tp) = (
            Complex::new(0.0, 0.0),
            Complex::new(0.0, 0.0),
            Complex::new(0.0, 0.0),
            Complex::new(0.0, 0.0),
        );
        for m in &model.modes {
            let (di, dip) = dynamic_stiffness(m.natural_frequency_rad_s, m.damping_ratio, kf * W);
            s += m.law_gain / di;
            sp -= m.law_gain * dip / (di * di);
            t += m.input_gain / di;
            tp -= m.input_gain * dip / (di * di);
        }
        // d/dW of a function of k W is k times its derivative in the argument.
        let q = d1 * s;
        let qw = (d1p * s + d1 * sp) * kf;
        let p = d1 * t;
        let pw = (d1p * t + d1 * tp) * kf;
        // Rows of harmonic k: (cos, sin); a complex C times X = (x_c - i x_s) adds
        // (Re C x_c + Im C x_s, Re C x_s - Im C x_c).
        let add =
            |rows: &mut [f64], c: Complex<f64>, xc: f64, xs: f64, stride: usize, col: usize| {
                if k == 0 {
                    rows[col] += c.re * xc;
                } else {
                    rows[(2 * k - 1) * stride + col] += c.re * xc + c.im * xs;
                    rows[(2 * k) * stride + col] += c.re * xs - c.im * xc;
                }
            };
        if k == 1 {
            add(r, -p, amplitude, 0.0, 1, 0);
            add(r_w, -pw, amplitude, 0.0, 1, 0);
        }
        let Some((g, gw, columns)) = law else {
            continue;
        };
        let (gc, gs) = if k == 0 {
            (g[0], 0.0)
        } else {
            (g[2 * k - 1], g[2 * k])
        };
        let (gwc, gws) = if k == 0 {
            (gw[0], 0.0)
        } else {
            (gw[2 * k - 1], gw[2 * k])
        };
        add(r, q, gc, gs, 1, 0);
        add(r_w, qw, gc, gs, 1, 0);
        add(r_w, q, gwc, gws, 1, 0);
        for (m, col) in columns.iter().enumerate() {
            let (cc, cs) = if k == 0 {
                (col[0], 0.0)
            } else {
                (col[2 * k - 1], col[2 * k])
            };
            add(jac, q, cc, cs, d, m);
        }
    }
}

/// Amplitude of the first harmonic of the coefficients `x` (`sqrt(a_1^2 + b_1^2)`).
pub fn first_harmonic(x: &[f64]) -> f64 {
    x[1].hypot(x[2])
}
