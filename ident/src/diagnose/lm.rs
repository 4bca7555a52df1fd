//! Levenberg-Marquardt least squares for the output-error fits of the diagnosis.
//!
//! Minimises `S(p) = sum_i r_i(p)^2` over a parameter vector `p` (the caller chooses
//! the parameterisation; positive physical parameters are fitted as logarithms so the
//! fit cannot leave their domain). The Jacobian is by forward differences with a step
//! `h_j = 1e-6 max(|p_j|, scale_j)`, its columns evaluated in parallel (one model run
//! each). The step solves Marquardt's scaled system
//! ```text
//! (J^T J + lambda diag(J^T J)) dp = -J^T r
//! ```
//! by Cholesky (faer); `lambda` is divided by 3 after an accepted step and multiplied by
//! 4 after a rejected one (Nielsen's schedule is not needed at these sizes). The fit
//! stops when the relative decrease of `S` over an accepted step is below `1e-6`, when
//! every `|dp_j| <= 1e-8 max(|p_j|, scale_j)`, or after `max_iterations`. The models
//! are compared by `N_eff ln(S_ref / S)`, so a further relative decrease `d` would move
//! a candidate's BIC by `N_eff d`: under 0.06 for the 60 000 residuals of the longest
//! record, against the 10 units a decision needs. Where the optimum is sharp, the
//! step before that one converged quadratically anyway; where it is flat (a candidate
//! that cannot explain the record crawling along a valley), the rule stops the crawl
//! that cost most of the diagnosis's time.
//!
//! Standard errors come from `sigma^2 (J^T J)^{-1}` at the optimum, with
//! `sigma^2 = S / (n - m)`: they hold for independent residuals and are only indicative
//! otherwise (the diagnosis reports them as such).
//!
//! Source: K. Madsen, H. B. Nielsen, O. Tingleff, *Methods for Non-Linear Least Squares
//! Problems*, 2nd ed., DTU 2004, section 3.2.

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use rayon::prelude::*;

/// A model's residuals for a parameter vector, or a message when it cannot be run.
pub trait Residuals: Sync {
    /// The residuals at `p`, or why the model cannot be run there.
    fn residuals(&self, p: &[f64]) -> Result<Vec<f64>, String>;
}

impl<F> Residuals for F
where
    F: Fn(&[f64]) -> Result<Vec<f64>, String> + Sync,
{
    fn residuals(&self, p: &[f64]) -> Result<Vec<f64>, String> {
        self(p)
    }
}

/// Settings of a fit.
#[derive(Debug, Clone)]
pub struct LmOptions {
    /// Most Levenberg-Marquardt iterations (Jacobian updates).
    pub max_iterations: usize,
    /// Typical magnitude of each parameter (sets the difference step near zero).
    pub scale: Vec<f64>,
}

/// A finished fit.
#[derive(Debug, Clone)]
pub struct LmFit {
    /// The parameters at the optimum.
    pub params: Vec<f64>,
    /// Residuals at `params`.
    pub residuals: Vec<f64>,
    /// Sum of squared residuals.
    pub cost: f64,
    /// Standard errors of the parameters (NaN where `J^T J` is singular).
    pub std_errors: Vec<f64>,
    /// Levenberg-Marquardt iterations done.
    pub iterations: usize,
    /// Model runs spent.
    pub evaluations: usize,
}

fn cost(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

/// Fits `model` from `start`.
pub fn fit(model: &dyn Residuals, start: &[f64], options: &LmOptions) -> Result<LmFit, String> {
    let m = start.len();
    let scale = |j: usize, p: &[f64]| {
        p[j].abs()
            .max(options.scale.get(j).copied().unwrap_or(1.0).abs())
            .max(1e-300)
    };
    let mut p = start.to_vec();
    let mut r = model.residuals(&p)?;
    let mut s = cost(&r);
    if !s.is_finite() {
        return Err("the model's residuals at the starting point are not finite".into());
    }
    let mut evaluations = 1;
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut jac = jacobian(model, &p, &r, &scale)?;
    evaluations += m;
    while iterations < options.max_iterations {
        iterations += 1;
        let (jtj, jtr) = normal_equations(&jac, &r);
        let mut accepted = false;
        for _ in 0..12 {
            let mut a = jtj.clone();
            for j in 0..m {
                a[(j, j)] += lambda * jtj[(j, j)].max(1e-30);
            }
            let Some(dp) = solve_spd(&a, &jtr) else {
                lambda *= 4.0;
                continue;
            };
            let trial: Vec<f64> = p.iter().zip(&dp).map(|(x, d)| x - d).collect();
            let small = (0..m).all(|j| dp[j].abs() <= 1e-8 * scale(j, &p));
            evaluations += 1;
            let rt = match model.residuals(&trial) {
                Ok(rt) => rt,
                Err(_) => {
                    lambda *= 4.0;
                    continue;
                }
            };
            let st = cost(&rt);
            if st.is_finite() && st < s {
                let decrease = (s - st) / s;
                p = trial;
                r = rt;
                s = st;
                lambda = (lambda / 3.0).max(1e-12);
                accepted = true;
                if decrease < 1e-6 || small {
                    return finish(model, p, r, s, iterations, evaluations, &scale);
                }
                break;
            }
            if small {
                return finish(model, p, r, s, iterations, evaluations, &scale);
            }
            lambda *= 4.0;
        }
        if !accepted {
            break;
        }
        jac = jacobian(model, &p, &r, &scale)?;
        evaluations += m;
    }
    finish(model, p, r, s, iterations, evaluations, &scale)
}

fn finish(
    model: &dyn Residuals,
    p: Vec<f64>,
    r: Vec<f64>,
    s: f64,
    iterations: usize,
    evaluations: usize,
    scale: &(dyn Fn(usize, &[f64]) -> f64 + Sync),
) -> Result<LmFit, String> {
    let m = p.len();
    let n = r.len();
    let jac = jacobian(model, &p, &r, scale)?;
    let (jtj, _) = normal_equations(&jac, &r);
    let sigma2 = s / (n.saturating_sub(m).max(1)) as f64;
    let std_errors = (0..m)
        .map(|j| {
            let mut e = vec![0.0; m];
            e[j] = 1.0;
            solve_spd(&jtj, &e).map_or(f64::NAN, |x| (x[j] * sigma2).max(0.0).sqrt())
        })
        .collect();
    Ok(LmFit {
        params: p,
        residuals: r,
        cost: s,
        std_errors,
        iterations,
        evaluations: evaluations + m,
    })
}

/// Forward-difference Jacobian, one column per parameter, in parallel; a column whose
/// forward point the model cannot evaluate (a parameter at the edge of its valid
/// range, e.g. a softening spring at its stability limit) is taken backwards.
fn jacobian(
    model: &dyn Residuals,
    p: &[f64],
    r: &[f64],
    scale: &(dyn Fn(usize, &[f64]) -> f64 + Sync),
) -> Result<Vec<Vec<f64>>, String> {
    (0..p.len())
        .into_par_iter()
        .map(|j| {
            let mut h = 1e-6 * scale(j, p);
            let mut q = p.to_vec();
            q[j] += h;
            let rq = match model.residuals(&q) {
                Ok(rq) => rq,
                Err(_) => {
                    h = -h;
                    q[j] = p[j] + h;
                    model.residuals(&q)?
                }
            };
            if rq.len() != r.len() {
                return Err("the model changed its number of residuals".into());
            }
            Ok(rq.iter().zip(r).map(|(a, b)| (a - b) / h).collect())
        })
        .collect()
}

fn normal_equations(jac: &[Vec<f64>], r: &[f64]) -> (Mat<f64>, Vec<f64>) {
    let m = jac.len();
    let mut jtj = Mat::<f64>::zeros(m, m);
    let mut jtr = vec![0.0; m];
    for a in 0..m {
        jtr[a] = jac[a].iter().zip(r).map(|(x, y)| x * y).sum();
        for b in 0..=a {
            let v: f64 = jac[a].iter().zip(&jac[b]).map(|(x, y)| x * y).sum();
            jtj[(a, b)] = v;
            jtj[(b, a)] = v;
        }
    }
    (jtj, jtr)
}

/// Solves a small symmetric positive definite system after scaling it to unit
/// diagonal (faer's Cholesky; the parameters' units differ by many decades).
pub fn solve_spd(a: &Mat<f64>, b: &[f64]) -> Option<Vec<f64>> {
    let m = b.len();
    let d: Vec<f64> = (0..m)
        .map(|j| {
            let x = a[(j, j)];
            if x > 0.0 && x.is_finite() {
                1.0 / x.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    let scaled = Mat::<f64>::from_fn(m, m, |i, j| a[(i, j)] * d[i] * d[j]);
    let rhs = Mat::<f64>::from_fn(m, 1, |i, _| b[i] * d[i]);
    let llt = scaled.llt(Side::Lower).ok()?;
    let x = llt.solve(&rhs);
    let out: Vec<f64> = (0..m).map(|i| x[(i, 0)] * d[i]).collect();
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// Linear least squares `min |A c - y|` for a few columns (the initial state of a
/// linear model): the normal equations, scaled, by Cholesky.
pub fn linear_least_squares(columns: &[Vec<f64>], y: &[f64]) -> Option<Vec<f64>> {
    let (jtj, _) = normal_equations(columns, y);
    let rhs: Vec<f64> = columns
        .iter()
        .map(|c| c.iter().zip(y).map(|(a, b)| a * b).sum())
        .collect();
    solve_spd(&jtj, &rhs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_a_damped_sine_from_a_nearby_start() {
        // y = A exp(-d t) sin(w t + phi): a nonlinear model with a known optimum.
        let truth = [2.0, 0.3, 5.0, 0.4];
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 0.01).collect();
        let model = |p: &[f64]| -> Vec<f64> {
            t.iter()
                .map(|&t| p[0] * (-p[1] * t).exp() * (p[2] * t + p[3]).sin())
                .collect()
        };
        let y = model(&truth);
        let residuals = |p: &[f64]| -> Result<Vec<f64>, String> {
            Ok(model(p).iter().zip(&y).map(|(a, b)| a - b).collect())
        };
        let options = LmOptions {
            max_iterations: 100,
            scale: vec![1.0; 4],
        };
        let fit = fit(&residuals, &[1.5, 0.2, 5.2, 0.2], &options).unwrap();
        for (a, b) in fit.params.iter().zip(truth) {
            // Exact data: the optimum is the truth to the solver's convergence test.
            assert!((a - b).abs() < 1e-6, "{:?}", fit.params);
        }
    }

    #[test]
    fn linear_least_squares_recovers_coefficients() {
        let x: Vec<f64> = (0..50).map(|i| i as f64 / 10.0).collect();
        let c1: Vec<f64> = x.iter().map(|v| v.sin()).collect();
        let c2: Vec<f64> = x.iter().map(|v| 1e6 * v.cos()).collect();
        let y: Vec<f64> = c1
            .iter()
            .zip(&c2)
            .map(|(a, b)| 3.0 * a - 2e-6 * b)
            .collect();
        let c = linear_least_squares(&[c1, c2], &y).unwrap();
        assert!((c[0] - 3.0).abs() < 1e-10 && (c[1] + 2e-6).abs() < 1e-16);
    }
}
