//! Synthetic decay records shared by the signature tests: a mass on a nonlinear spring
//! with dashpots (RK4), an exact Coulomb decay, measurement noise and quantisation.

use crate::signal::Signal;
use crate::test_signals::Rng;
use std::f64::consts::PI;

pub(crate) const RATE_HZ: f64 = 1000.0;

/// 1% Gaussian noise (of the largest magnitude) and a 16-bit converter whose full scale
/// is 1.25 times the largest magnitude: what every synthetic record here carries.
pub(crate) fn measured(clean: &[f64], seed: u64) -> Vec<f64> {
    let largest = clean.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let quantum = 2.0 * 1.25 * largest / 65536.0;
    let mut rng = Rng::new(seed);
    clean
        .iter()
        .map(|v| ((v + 0.01 * largest * rng.normal()) / quantum).round() * quantum)
        .collect()
}

pub(crate) fn times(n: usize) -> Vec<f64> {
    (0..n).map(|i| i as f64 / RATE_HZ).collect()
}

/// One mass on a spring `k x + k3 x^3` (x compression, m) under gravity, with dashpots
/// `c v` and `c2 v|v|`, released from `x_s + lift` at rest; returns the weight's
/// acceleration away from the base (m/s^2) by RK4 at `RATE_HZ` with 4 substeps.
#[derive(Clone, Copy)]
pub(crate) struct Sdof {
    pub mass: f64,
    pub k: f64,
    pub k3: f64,
    pub c: f64,
    pub c2: f64,
    pub gravity: f64,
}

impl Sdof {
    fn force(&self, x: f64, v: f64) -> f64 {
        self.mass * self.gravity
            - self.k * x
            - self.k3 * x.powi(3)
            - self.c * v
            - self.c2 * v * v.abs()
    }
    pub(crate) fn static_compression(&self) -> f64 {
        let mut x = self.mass * self.gravity / self.k;
        for _ in 0..50 {
            x -= (self.k * x + self.k3 * x.powi(3) - self.mass * self.gravity)
                / (self.k + 3.0 * self.k3 * x * x);
        }
        x
    }
    pub(crate) fn tangent_stiffness(&self) -> f64 {
        self.k + 3.0 * self.k3 * self.static_compression().powi(2)
    }
    pub(crate) fn accel(&self, lift: f64, seconds: f64) -> Vec<f64> {
        let n = (seconds * RATE_HZ) as usize;
        let substeps = 4;
        let h = 1.0 / (RATE_HZ * substeps as f64);
        let (mut x, mut v) = (self.static_compression() + lift, 0.0);
        let a = |x: f64, v: f64| self.force(x, v) / self.mass;
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            // x is compression: the weight moves down as x grows, so the acceleration
            // away from the base is -x''.
            out.push(-a(x, v));
            for _ in 0..substeps {
                let (k1x, k1v) = (v, a(x, v));
                let (k2x, k2v) = (v + 0.5 * h * k1v, a(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
                let (k3x, k3v) = (v + 0.5 * h * k2v, a(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
                let (k4x, k4v) = (v + h * k3v, a(x + h * k3x, v + h * k3v));
                x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            }
        }
        out
    }
}

/// Exact Coulomb decay: half-cycles of `omega` about `+-d`, `d = F / k`, from `x0` at
/// rest, sticking once `|x| <= d`. Returns the acceleration `-omega^2 (x - centre)`.
pub(crate) fn coulomb_accel(omega: f64, d: f64, x0: f64, seconds: f64) -> Vec<f64> {
    let n = (seconds * RATE_HZ) as usize;
    let half = PI / omega;
    let mut out = Vec::with_capacity(n);
    let (mut start_t, mut start_x) = (0.0, x0);
    for i in 0..n {
        let t = i as f64 / RATE_HZ;
        while start_x.abs() > d && t - start_t >= half {
            let centre = start_x.signum() * d;
            start_x = 2.0 * centre - start_x;
            start_t += half;
        }
        if start_x.abs() <= d {
            out.push(0.0);
            continue;
        }
        let centre = start_x.signum() * d;
        let x = centre + (start_x - centre) * (omega * (t - start_t)).cos();
        out.push(-omega * omega * (x - centre));
    }
    out
}

pub(crate) fn within(got: f64, exact: f64, relative: f64) -> bool {
    (got - exact).abs() <= relative * exact.abs()
}

/// An in-memory signal of these samples.
pub(crate) fn sig(time_s: &[f64], values: &[f64]) -> Signal {
    Signal::new(time_s.to_vec(), values.to_vec()).unwrap()
}
