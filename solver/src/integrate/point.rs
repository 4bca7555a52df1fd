//! Nonlinear forces concentrated at one DOF, and their implicit solve inside a step.
//!
//! # Law
//! A [`PointLaw`] is a restoring force on one DOF with displacement `u` (from the
//! model's reference configuration, which for coil's springs is the free length) and
//! velocity `v`:
//! ```text
//! f(u, v) = k3 u^3 + c2 v |v| + F sgn(v)        (F sgn(0) is any value in [-F, F])
//! ```
//! `k3` is a cubic spring of either sign (`k3 < 0` softens), `c2 >= 0` a
//! velocity-squared dashpot and `F >= 0` a dry (Coulomb) friction force that sticks
//! while the other forces on the DOF cannot overcome it. The force enters the balance as `M a + C v + K u + B f = f_ext`, `B`
//! the unit vector of the DOF. Units are the operator's: in coil's solver units `k3`
//! is N/mm^3, `c2` N s^2/mm^2, `F` N.
//!
//! # Implicit solve (return mapping)
//! In a Newmark-type step every other quantity is linear, so the DOF's end-of-step
//! displacement and velocity are affine in the law's end-of-step force:
//! ```text
//! u = u* - h f,     v = v* - g f,     h, g > 0
//! ```
//! `u*`, `v*` are the predictor (the step computed with `f = 0` at its end), `h` the
//! DOF's entry of the inverse effective matrix scaled to a displacement and
//! `g = gamma/(beta dt) h` for Newmark. The step's force solves the scalar inclusion
//! `f in f(u* - h f, v* - g f)`. With `k3 >= 0` its right-hand side is non-increasing
//! in `f` and the left increasing, so the root is unique ([`PointLaw::solve`]). A
//! softening spring (`k3 < 0`) keeps that monotonicity only while
//! `1 + 3 k3 h u^2 > 0`, i.e. for `|u| < u_h = 1/sqrt(3 |k3| h)`: the solve is confined
//! to that interval (the root the step continues from), and when the interval holds no
//! root the law has lost stability within the step and the solve returns `None`
//! (callers turn it into an error; never a NaN). The physical limit of a softening
//! spring in a model, where the total tangent stiffness `k + 3 k3 u^2` vanishes, is the
//! caller's check (it knows `k`):
//! * stick test: at `v = 0`, `f0 = v*/g`; if `|f0 - k3 u(f0)^3| <= F` the DOF sticks;
//! * otherwise it slides with `sgn(v) = sgn(f0 - k3 u(f0)^3)`, and the smooth monotone
//!   equation on that side is solved by Newton's method safeguarded by bisection;
//!   without a cubic spring it is a quadratic in the end-of-step velocity, solved in
//!   closed form (`g c2 sgn(v) v^2 + v = v* - g F sgn(v)`, the root without
//!   cancellation), to rounding and about 5 times cheaper than the iteration.
//!
//! Sources: J. C. Simo & T. J. R. Hughes, *Computational Inelasticity*, Springer 1998,
//! ch. 1 (return mapping for one-dimensional friction); the Newmark update as in
//! [`super::stepper`].

/// A nonlinear restoring force at one DOF: `k3 u^3 + c2 v|v| + F sgn(v)`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PointLaw {
    /// Cubic stiffness `k3`, either sign (force / length^3).
    pub cubic: f64,
    /// Velocity-squared damping `c2 >= 0` (force time^2 / length^2).
    pub quadratic: f64,
    /// Dry friction force `F >= 0`.
    pub friction: f64,
}

/// Result of [`PointLaw::solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSolve {
    /// The law's force at the end of the step.
    pub force: f64,
    /// True when the friction holds the DOF at rest (`v = 0`).
    pub stuck: bool,
}

impl PointLaw {
    /// True when every coefficient is zero (the law does nothing).
    pub fn is_zero(&self) -> bool {
        self.cubic == 0.0 && self.quadratic == 0.0 && self.friction == 0.0
    }

    /// True when every coefficient is finite, and the dashpot and the friction are
    /// non-negative (the cubic spring takes either sign).
    pub fn is_valid(&self) -> bool {
        self.cubic.is_finite()
            && [self.quadratic, self.friction]
                .iter()
                .all(|c| c.is_finite() && *c >= 0.0)
    }

    /// The largest `|u|` (from the reference) at which a softening spring in parallel
    /// with a linear stiffness `k` keeps a positive tangent stiffness,
    /// `k + 3 k3 u^2 > 0`: `sqrt(k / (3 |k3|))`; infinite for `k3 >= 0`.
    pub fn stable_displacement(&self, k: f64) -> f64 {
        if self.cubic < 0.0 {
            (k / (3.0 * -self.cubic)).sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// The `|u|` (from the reference) beyond which a softening spring in parallel with
    /// a linear stiffness `k` pushes outwards, `k u + k3 u^3 = 0`: `sqrt(k / |k3|)`;
    /// infinite for `k3 >= 0`. A bounded free motion never reaches it, whatever the
    /// preload: its energy is below the potential's saddle, which lies inside it
    /// (`ident`'s diagnosis refuses a trial that gets there). Between
    /// [`PointLaw::stable_displacement`] and it, the tangent stiffness is negative and a
    /// motion passing through turns back, as a pendulum beyond 90 degrees does.
    pub fn escape_displacement(&self, k: f64) -> f64 {
        if self.cubic < 0.0 {
            (k / -self.cubic).sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// The smooth part `k3 u^3 + c2 v|v|`.
    pub fn smooth_force(&self, u: f64, v: f64) -> f64 {
        self.cubic * u * u * u + self.quadratic * v * v.abs()
    }

    /// The force for a moving DOF (`v != 0`); at `v = 0` the friction term is taken
    /// as zero (its value there is set by the balance, see [`PointLaw::solve`]).
    pub fn force(&self, u: f64, v: f64) -> f64 {
        let sign = if v > 0.0 {
            1.0
        } else if v < 0.0 {
            -1.0
        } else {
            0.0
        };
        self.smooth_force(u, v) + self.friction * sign
    }

    /// Tangent stiffness `df/du = 3 k3 u^2`.
    pub fn tangent_stiffness(&self, u: f64) -> f64 {
        3.0 * self.cubic * u * u
    }

    /// Solves `f in law(u* - h f, v* - g f)` for the end-of-step force (module docs).
    /// `h >= 0`, `g > 0`. Returns `None` only if an input is not finite.
    pub fn solve(&self, u_star: f64, v_star: f64, h: f64, g: f64) -> Option<PointSolve> {
        self.solve_from(u_star, v_star, h, g, None)
    }

    /// As [`PointLaw::solve`], with Newton's iteration started from `guess` (e.g. the
    /// previous step's force) when it is on the sliding branch's side. The root is the
    /// same; only the work to reach it changes.
    pub fn solve_from(
        &self,
        u_star: f64,
        v_star: f64,
        h: f64,
        g: f64,
        guess: Option<f64>,
    ) -> Option<PointSolve> {
        if !(u_star.is_finite() && v_star.is_finite() && h.is_finite() && g.is_finite())
            || h < 0.0
            || g <= 0.0
        {
            return None;
        }
        // phi(f) = f - smooth(u(f), v(f)) - F sigma, increasing in f.
        let smooth_at = |f: f64| self.smooth_force(u_star - h * f, v_star - g * f);
        let f0 = v_star / g;
        // A softening spring: the interval where phi stays increasing (module docs).
        let (soft_lo, soft_hi) = if self.cubic < 0.0 && h > 0.0 {
            let u_h = 1.0 / (3.0 * -self.cubic * h).sqrt();
            ((u_star - u_h) / h, (u_star + u_h) / h)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        };
        let (lo, hi, sigma) = if self.friction > 0.0 {
            let excess = f0 - smooth_at(f0);
            if excess.abs() <= self.friction {
                return Some(PointSolve {
                    force: f0,
                    stuck: true,
                });
            }
            // f < f0 <=> v > 0: sliding forward has the root below f0.
            if excess > 0.0 {
                (f64::NEG_INFINITY, f0, 1.0)
            } else {
                (f0, f64::INFINITY, -1.0)
            }
        } else {
            (f64::NEG_INFINITY, f64::INFINITY, 0.0)
        };
        if self.cubic == 0.0 {
            return Some(PointSolve {
                force: self.without_cubic(v_star, g, sigma),
                stuck: false,
            });
        }
        let phi = |f: f64| f - smooth_at(f) - self.friction * sigma;
        let dphi = |f: f64| {
            let u = u_star - h * f;
            let v = v_star - g * f;
            1.0 + 3.0 * self.cubic * u * u * h + 2.0 * self.quadratic * v.abs() * g
        };
        let (lo, hi) = (lo.max(soft_lo), hi.min(soft_hi));
        if lo >= hi {
            return None;
        }
        if self.cubic < 0.0 && h > 0.0 && (phi(lo) > 0.0 || phi(hi) < 0.0) {
            // No root where the softening law is monotone: it lost stability.
            return None;
        }
        let start = guess
            .filter(|x| x.is_finite())
            .unwrap_or(sigma * self.friction);
        let force = solve_increasing(phi, dphi, lo, hi, start)?;
        Some(PointSolve {
            force,
            stuck: false,
        })
    }
}

impl PointLaw {
    /// The sliding force of a law without a cubic spring, in closed form: on the
    /// branch `sgn(v) = sigma` (0 without friction, where the sign is `v*`'s), the
    /// end-of-step velocity solves `g c2 sigma v^2 + v = w`, `w = v* - g F sigma`, and
    /// the root of the sliding side is `v = 2 w / (1 + sqrt(1 + 4 g c2 |w|))` (the
    /// form without cancellation); the force is `c2 v |v| + F sigma`, to rounding.
    fn without_cubic(&self, v_star: f64, g: f64, sigma: f64) -> f64 {
        let w = v_star - g * self.friction * sigma;
        let v = 2.0 * w / (1.0 + (1.0 + 4.0 * g * self.quadratic * w.abs()).sqrt());
        self.quadratic * v * v.abs() + self.friction * sigma
    }
}

/// Relative change of the law forces at which the Gauss-Seidel sweeps over several
/// laws of one step stop: a few hundred ulp of the largest force.
pub const SWEEP_TOLERANCE: f64 = 1e-13;

/// Most Gauss-Seidel sweeps over several laws in one step.
pub const MAX_SWEEPS: usize = 200;

/// Why the laws of one step could not be solved ([`solve_step`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepLawError {
    /// Law `law`'s scalar solve failed: a non-finite input, or a softening spring with
    /// no stable root (it lost stability within the step).
    Unsolvable {
        /// The law's position in the step's list (0-based).
        law: usize,
    },
    /// The sweeps did not converge; the last change of a force.
    NotConverged {
        /// Number of sweeps run.
        sweeps: usize,
        /// The last sweep's largest change of a law force (N in coil).
        change: f64,
    },
}

/// The end-of-step forces of the laws of one step, shared by every stepper (the banded
/// and sparse Newmark engines and the dense reduced-model stepper): with `linear(j)` the
/// end-of-step displacement and velocity at law `j`'s DOF when every law force is zero,
/// `schur` the `p x p` matrix `G = E^T S^-1 E` (row-major; `S` the effective matrix, `E`
/// the laws' unit columns) and `h`, `g` the scheme's displacement and velocity factors
/// (`beta dt^2`, `gamma dt`), law `j`'s DOF ends at `u_j - h sum_k G_jk f_k`,
/// `v_j - g sum_k G_jk f_k`. One law is solved exactly; several by nonlinear
/// Gauss-Seidel (each law exactly with the others' current forces; `G` is symmetric
/// positive definite and each law monotone, so the sweeps converge) from `forces` (the
/// previous step's, a warm start), to a relative change of [`SWEEP_TOLERANCE`] within
/// [`MAX_SWEEPS`] sweeps, else an error. `forces` and `stuck` are overwritten.
pub fn solve_step(
    laws: &[PointLaw],
    linear: impl Fn(usize) -> (f64, f64),
    schur: &[f64],
    h: f64,
    g: f64,
    forces: &mut [f64],
    stuck: &mut [bool],
) -> Result<(), StepLawError> {
    let p = laws.len();
    let mut sweeps = 0;
    loop {
        sweeps += 1;
        let mut change: f64 = 0.0;
        let mut size: f64 = 0.0;
        for j in 0..p {
            let (ul, vl) = linear(j);
            let others: f64 = (0..p)
                .filter(|&k| k != j)
                .map(|k| schur[j * p + k] * forces[k])
                .sum();
            let gjj = schur[j * p + j];
            let sol = laws[j]
                .solve_from(
                    ul - h * others,
                    vl - g * others,
                    h * gjj,
                    g * gjj,
                    Some(forces[j]),
                )
                .ok_or(StepLawError::Unsolvable { law: j })?;
            change = change.max((sol.force - forces[j]).abs());
            size = size.max(sol.force.abs());
            forces[j] = sol.force;
            stuck[j] = sol.stuck;
        }
        if p == 1 || change <= SWEEP_TOLERANCE * size || size == 0.0 {
            return Ok(());
        }
        if sweeps >= MAX_SWEEPS {
            return Err(StepLawError::NotConverged { sweeps, change });
        }
    }
}

/// The friction forces that hold laws at rest at an initial state, shared by both
/// steppers: `count` friction laws whose DOFs start at rest, `coupling(p, q)` the entry
/// of `E^T M^-1 E` between their DOFs, `a_free(p)` the acceleration at law `p`'s DOF
/// without these forces and `friction(p)` its `F`. Each force is the one that keeps its
/// DOF at rest (`a = 0`) clamped to `[-F, F]` (`F` against the net force when it
/// cannot hold), by projected Gauss-Seidel from `held` (overwritten; one sweep for one
/// law) until the largest change is at most `tolerance` of the largest force, or, with
/// `stop_when_zero`, every force is zero. Returns whether that happened within
/// [`MAX_SWEEPS`] sweeps; each stepper decides what non-convergence means (module docs
/// of `stepper` and `dense`).
pub(crate) fn hold_at_rest(
    count: usize,
    coupling: impl Fn(usize, usize) -> f64,
    a_free: impl Fn(usize) -> f64,
    friction: impl Fn(usize) -> f64,
    tolerance: f64,
    stop_when_zero: bool,
    held: &mut [f64],
) -> bool {
    for _ in 0..MAX_SWEEPS {
        let (mut change, mut size) = (0.0f64, 0.0f64);
        for p in 0..count {
            let others: f64 = (0..count)
                .filter(|&q| q != p)
                .map(|q| coupling(p, q) * held[q])
                .sum();
            let f_max = friction(p);
            let f = ((a_free(p) - others) / coupling(p, p)).clamp(-f_max, f_max);
            change = change.max((f - held[p]).abs());
            size = size.max(f.abs());
            held[p] = f;
        }
        if count <= 1 || change <= tolerance * size || (stop_when_zero && size == 0.0) {
            return true;
        }
    }
    false
}

/// Root of an increasing function on `(lo, hi)` (either end may be infinite), from
/// the start `x0`: the bracket is grown until it holds a sign change, then Newton's
/// steps are kept inside it and replaced by bisection when they leave it.
fn solve_increasing(
    phi: impl Fn(f64) -> f64,
    dphi: impl Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    x0: f64,
) -> Option<f64> {
    let x0 = x0.clamp(
        if lo.is_finite() { lo } else { f64::MIN },
        if hi.is_finite() { hi } else { f64::MAX },
    );
    let mut x = x0;
    let mut lo = lo;
    let mut hi = hi;
    let mut p = phi(x);
    if p == 0.0 {
        return Some(x);
    }
    // Newton starts from `x0` when it lies in the bracket: its value is known.
    let p0 = p;
    // Grow the bracket on the side of the root.
    let mut step = x.abs().max(1.0);
    for _ in 0..2100 {
        if p > 0.0 {
            hi = x;
            if lo.is_finite() {
                break;
            }
            let trial = x - step;
            let pt = phi(trial);
            if !pt.is_finite() {
                return None;
            }
            if pt <= 0.0 {
                lo = trial;
                break;
            }
            x = trial;
            p = pt;
        } else {
            lo = x;
            if hi.is_finite() {
                break;
            }
            let trial = x + step;
            let pt = phi(trial);
            if !pt.is_finite() {
                return None;
            }
            if pt >= 0.0 {
                hi = trial;
                break;
            }
            x = trial;
            p = pt;
        }
        step *= 2.0;
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    // Newton from the start when it lies in the bracket (a warm start from the last
    // step's force converges in one or two steps), else from the bracket's middle.
    let mut x = if x0 >= lo && x0 <= hi {
        x0
    } else {
        0.5 * (lo + hi)
    };
    let mut known = (x == x0).then_some(p0);
    for _ in 0..200 {
        let p = known.take().unwrap_or_else(|| phi(x));
        if !p.is_finite() {
            return None;
        }
        if p > 0.0 {
            hi = x;
        } else if p < 0.0 {
            lo = x;
        } else {
            return Some(x);
        }
        let d = dphi(x);
        let newton = x - p / d;
        let next = if d > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let scale = x.abs().max(next.abs()).max(f64::MIN_POSITIVE);
        if (next - x).abs() <= 4.0 * f64::EPSILON * scale || hi - lo <= 4.0 * f64::EPSILON * scale {
            return Some(next);
        }
        x = next;
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn residual(law: &PointLaw, s: PointSolve, u: f64, v: f64, h: f64, g: f64) -> f64 {
        let ue = u - h * s.force;
        let ve = v - g * s.force;
        if s.stuck {
            assert!(ve.abs() <= 1e-12 * v.abs().max(1.0));
            let rest = s.force - law.smooth_force(ue, 0.0);
            assert!(rest.abs() <= law.friction * (1.0 + 1e-12));
            0.0
        } else {
            s.force - law.force(ue, ve)
        }
    }

    #[test]
    fn each_law_satisfies_its_equation() {
        let laws = [
            PointLaw {
                cubic: 2.0,
                ..Default::default()
            },
            PointLaw {
                quadratic: 0.7,
                ..Default::default()
            },
            PointLaw {
                friction: 0.3,
                ..Default::default()
            },
            PointLaw {
                cubic: 1.5,
                quadratic: 0.2,
                friction: 0.1,
            },
        ];
        for law in &laws {
            for &(u, v) in &[
                (0.3, 1.2),
                (-2.0, 0.05),
                (1.0, -3.0),
                (0.0, 0.0),
                (5.0, -0.01),
            ] {
                for &(h, g) in &[(0.01, 2.0), (1.0, 0.5), (0.0, 1.0)] {
                    let s = law.solve(u, v, h, g).expect("finite");
                    let r = residual(law, s, u, v, h, g);
                    assert!(r.abs() <= 1e-10 * s.force.abs().max(1.0), "{law:?} {r}");
                }
            }
        }
    }

    #[test]
    fn linear_law_is_exact() {
        // No friction, no cubic: f = c2 v|v| has the closed-form root.
        let law = PointLaw {
            quadratic: 0.5,
            ..Default::default()
        };
        let (v, g) = (2.0, 0.8);
        let s = law.solve(0.0, v, 0.0, g).unwrap();
        // v_end solves v_end + g c2 v_end^2 = v.
        let c = g * 0.5;
        let v_end = (-1.0 + (1.0 + 4.0 * c * v).sqrt()) / (2.0 * c);
        assert!((s.force - (v - v_end) / g).abs() < 1e-14);
    }

    #[test]
    fn friction_sticks_below_its_limit() {
        let law = PointLaw {
            friction: 1.0,
            ..Default::default()
        };
        let s = law.solve(0.0, 0.5, 0.1, 1.0).unwrap();
        assert!(s.stuck && (s.force - 0.5).abs() < 1e-15);
        let s = law.solve(0.0, 1.5, 0.1, 1.0).unwrap();
        assert!(!s.stuck && (s.force - 1.0).abs() < 1e-15);
        let s = law.solve(0.0, -1.5, 0.1, 1.0).unwrap();
        assert!(!s.stuck && (s.force + 1.0).abs() < 1e-15);
    }

    #[test]
    fn softening_spring_is_solved_where_stable_and_refused_beyond() {
        let law = PointLaw {
            cubic: -2.0,
            ..Default::default()
        };
        // Small h: the monotone interval is wide, the root near the predictor.
        let (u, v, h, g) = (0.4, 0.3, 0.01, 0.2);
        let s = law.solve(u, v, h, g).expect("stable");
        let r = residual(&law, s, u, v, h, g);
        assert!(r.abs() < 1e-12, "{r}");
        // Far beyond u_h = 1/sqrt(3 |k3| h) = 4.08 the law has no stable root.
        assert!(law.solve(50.0, 0.0, h, g).is_none());
        assert!((law.stable_displacement(6.0) - 1.0).abs() < 1e-15);
        assert!((law.escape_displacement(2.0) - 1.0).abs() < 1e-15);
        assert!(PointLaw::default().stable_displacement(1.0).is_infinite());
        assert!(law.is_valid());
    }

    #[test]
    fn several_laws_converge_and_one_law_is_exact() {
        let laws = [
            PointLaw {
                friction: 0.2,
                ..Default::default()
            },
            PointLaw {
                quadratic: 0.5,
                cubic: -0.3,
                ..Default::default()
            },
        ];
        let schur = [1.0, 0.2, 0.2, 0.8];
        let lin = [(0.1, 1.0), (0.2, -0.7)];
        let (h, g) = (1e-4, 1e-2);
        let mut forces = [0.0; 2];
        let mut stuck = [false; 2];
        solve_step(&laws, |j| lin[j], &schur, h, g, &mut forces, &mut stuck).unwrap();
        // Each law satisfies its own equation with the other's force held.
        for j in 0..2 {
            let k = 1 - j;
            let (ul, vl) = lin[j];
            let gjj = schur[j * 2 + j];
            let (u, v) = (
                ul - h * schur[j * 2 + k] * forces[k],
                vl - g * schur[j * 2 + k] * forces[k],
            );
            let s = PointSolve {
                force: forces[j],
                stuck: stuck[j],
            };
            let r = residual(&laws[j], s, u, v, h * gjj, g * gjj);
            assert!(r.abs() < 1e-11, "law {j}: {r}");
        }
        // A non-finite input is an error naming the law, never a NaN force.
        let bad = solve_step(
            &laws[..1],
            |_| (f64::NAN, 0.0),
            &[1.0],
            h,
            g,
            &mut [0.0],
            &mut [false],
        );
        assert_eq!(bad, Err(StepLawError::Unsolvable { law: 0 }));
    }

    #[test]
    fn bad_inputs_are_refused() {
        let law = PointLaw::default();
        assert!(law.solve(f64::NAN, 0.0, 1.0, 1.0).is_none());
        assert!(law.solve(0.0, 0.0, 1.0, 0.0).is_none());
        assert!(law.solve(0.0, 0.0, -1.0, 1.0).is_none());
    }
}
