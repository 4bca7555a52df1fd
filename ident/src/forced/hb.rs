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
//! Sources: T. M. Cameron, J. H. Griffin, "An alternating frequency/time domain method for
//! calculating the steady-state response of nonlinear dynamic systems", J. Appl. Mech. 56
//! (1989) 149-154; M. Krack, J. Gross, *Harmonic Balance for Nonlinear Vibration Problems*,
//! Springer 2019, chapters 2-3.

// Harmonic and sample indices are the formulation's own (x_n, tau_j, line k): the kernels
// keep them rather than zipping five slices.
#![allow(clippy::needless_range_loop)]

use super::model::Lumped;

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
        for m in 0..d {
            let col: Vec<f64> = (0..n)
                .map(|j| gz[j] * basis.phi[m][j] + W * gv[j] * basis.dphi[m][j])
                .collect();
            let p = basis.project(&col);
            for row in 0..d {
                jac[row * d + m] += p[row];
            }
        }
    }
    (r, jac, r_w)
}

/// Amplitude of the first harmonic of the coefficients `x` (`sqrt(a_1^2 + b_1^2)`).
pub fn first_harmonic(x: &[f64]) -> f64 {
    x[1].hypot(x[2])
}
