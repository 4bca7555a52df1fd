//! The dense stepper with point laws: linear decay, Coulomb friction (loss per cycle,
//! sticking), the cubic spring's period, convergence against Runge-Kutta, static balance,
//! bad inputs.

use super::*;
use std::f64::consts::{PI, TAU};

fn sdof(m: f64, c: f64, k: f64, dt: f64, laws: &[(usize, PointLaw)]) -> DenseStepper {
    let one = |x: f64| DMatrix::from_element(1, 1, x);
    DenseStepper::new(&one(m), &one(c), &one(k), dt, laws).unwrap()
}

/// Every displacement of a run, step by step.
fn run(s: &mut DenseStepper, u0: &[f64], v0: &[f64], steps: usize) -> Vec<Vec<f64>> {
    s.set_state(u0, v0).unwrap();
    let mut out = vec![u0.to_vec()];
    for _ in 0..steps {
        s.step().unwrap();
        out.push(s.state().0.to_vec());
    }
    out
}

/// Times of the upward zero crossings, linearly interpolated.
fn up_crossings(x: &[f64], dt: f64) -> Vec<f64> {
    x.windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(i, w)| (i as f64 + w[0] / (w[0] - w[1])) * dt)
        .collect()
}

fn mean_period(x: &[f64], dt: f64) -> f64 {
    let c = up_crossings(x, dt);
    (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64
}

/// Average acceleration lengthens the period by (omega dt)^2 / 12 and does not damp:
/// the damped decay follows the exact solution with that period, to a residual far
/// below the phase error itself.
#[test]
fn linear_damped_decay_matches_the_exact_solution_with_the_known_period_error() {
    let (w, zeta) = (TAU, 0.01);
    let dt = 0.01; // omega dt = 0.0628: period error 3.3e-4
    let mut s = sdof(1.0, 2.0 * zeta * w, w * w, dt, &[]);
    let steps = 1000; // 10 periods
    let u: Vec<f64> = run(&mut s, &[1.0], &[0.0], steps)
        .iter()
        .map(|x| x[0])
        .collect();
    let exact = |t: f64, w: f64| {
        let wd = w * (1.0 - zeta * zeta).sqrt();
        (-zeta * w * t).exp() * ((wd * t).cos() + zeta * w / wd * (wd * t).sin())
    };
    let w_h = w / (1.0 + (w * dt).powi(2) / 12.0);
    let (mut err, mut err_shifted) = (0.0f64, 0.0f64);
    for (n, &x) in u.iter().enumerate() {
        let t = n as f64 * dt;
        err = err.max((x - exact(t, w)).abs());
        err_shifted = err_shifted.max((x - exact(t, w_h)).abs());
    }
    // The phase lag w t (w dt)^2/12 on the decaying envelope, at its largest.
    let phase = (0..=steps)
        .map(|n| {
            let t = n as f64 * dt;
            (-zeta * w * t).exp() * w * t * (w * dt).powi(2) / 12.0
        })
        .fold(0.0, f64::max);
    eprintln!("max error {err:e} (phase bound {phase:e}), with the period error {err_shifted:e}");
    assert!(err < 1.05 * phase && err > 0.9 * phase);
    assert!(err_shifted < 0.05 * err);
    let period = mean_period(&u, dt);
    let expected = TAU / (w * (1.0 - zeta * zeta).sqrt()) * (1.0 + (w * dt).powi(2) / 12.0);
    assert!(
        (period / expected - 1.0).abs() < 2e-5,
        "{period} vs {expected}"
    );
}

/// Coulomb friction: each half cycle loses 2F/k of amplitude (4F/k per cycle) at
/// the undamped frequency, until the spring force can no longer beat F.
#[test]
fn coulomb_friction_loses_four_f_over_k_per_cycle_and_sticks() {
    let (k, f) = (1.0, 0.01);
    let law = PointLaw {
        friction: f,
        ..Default::default()
    };
    let dt = TAU / 4000.0;
    let mut s = sdof(1.0, 0.0, k, dt, &[(0, law)]);
    let u: Vec<f64> = run(&mut s, &[1.0], &[0.0], 4000 * 30)
        .iter()
        .map(|x| x[0])
        .collect();
    let mut peaks = vec![u[0].abs()];
    for i in 1..u.len() - 1 {
        if u[i].abs() > u[i - 1].abs() && u[i].abs() >= u[i + 1].abs() && u[i].abs() > f / k {
            peaks.push(u[i].abs());
        }
    }
    // A peak sampled off its crest is low by at most A (omega dt)^2 / 8 = 2.5e-7 A
    // (A <= 1 here).
    let worst = peaks
        .windows(2)
        .map(|p| (p[0] - p[1] - 2.0 * f / k).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "coulomb: {} peaks, worst loss error {worst:e} (2F/k = {})",
        peaks.len(),
        2.0 * f / k
    );
    for pair in peaks.windows(2) {
        let loss = pair[0] - pair[1];
        assert!(
            (loss - 2.0 * f / k).abs() < 2.5e-7,
            "{loss} vs {}",
            2.0 * f / k
        );
    }
    // 1 - 2F/k per half cycle: 50 half cycles reach 0, the last peak is within 2F/k
    // of the stop and the mass comes to rest at |u| <= F/k.
    assert_eq!(peaks.len(), 50, "{peaks:?}");
    let (u_end, v_end, _) = s.state();
    assert!(u_end[0].abs() <= f / k * (1.0 + 1e-9) && v_end[0] == 0.0);
}

/// A preloaded mass held by friction stays exactly where it is.
#[test]
fn friction_holds_a_mass_that_the_spring_cannot_move() {
    let law = PointLaw {
        friction: 0.5,
        ..Default::default()
    };
    let mut s = sdof(1.0, 0.1, 1.0, 0.01, &[(0, law)]);
    let u = run(&mut s, &[0.4], &[0.0], 1000);
    assert!(u.iter().all(|x| (x[0] - 0.4).abs() < 1e-15));
    assert_eq!(s.state().1[0], 0.0);
    assert!(s.state().2[0].abs() < 1e-15, "no acceleration ringing");
    assert!((s.law_forces()[0] + 0.4).abs() < 1e-12);
    // Two coupled DOFs, both held (the projected Gauss-Seidel start): nothing moves.
    let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.3, 0.3, 1.0]);
    let k = DMatrix::from_row_slice(2, 2, &[2.0, -1.0, -1.0, 2.0]);
    let mut s = DenseStepper::new(&m, &(&k * 0.01), &k, 0.01, &[(0, law), (1, law)]).unwrap();
    let u = run(&mut s, &[0.1, 0.3], &[0.0, 0.0], 500);
    for x in &u {
        assert!(
            (x[0] - 0.1).abs() < 1e-14 && (x[1] - 0.3).abs() < 1e-14,
            "{x:?}"
        );
    }
    assert!(s.state().2.iter().all(|a| a.abs() < 1e-13));
    // DOF 1 cannot hold (spring force 1.1 > 0.5) and slides back; holding DOF 0 would
    // then take 0.4 + 0.3 * 0.6 = 0.58 > 0.5 through the mass coupling, so it slides
    // forward: M a0 = -K u - (F, -F) = (-0.1, -0.6).
    let mut s = DenseStepper::new(&m, &(&k * 0.0), &k, 0.01, &[(0, law), (1, law)]).unwrap();
    s.set_state(&[0.1, 0.6], &[0.0, 0.0]).unwrap();
    let a = s.state().2.to_vec();
    let ma = [a[0] + 0.3 * a[1], 0.3 * a[0] + a[1]];
    assert!(a[0] > 0.0 && a[1] < 0.0, "{a:?}");
    assert!(
        (ma[0] + 0.1).abs() < 1e-14 && (ma[1] + 0.6).abs() < 1e-14,
        "{ma:?}"
    );
}

/// Undamped cubic oscillator from rest at amplitude A: the period is the exact
/// quadrature `T = 4 int_0^{pi/2} dtheta / sqrt(k + k3 A^2 (1 + sin^2) / 2)` (m = 1)
/// to the scheme's (omega dt)^2/12, and the harmonic-balance backbone
/// `w^2 = w0^2 (1 + 3 k3 A^2 / 4k)` to its own O((k3 A^2/k)^2) error.
#[test]
fn cubic_spring_follows_the_exact_period_and_the_backbone() {
    let (k, k3, a) = (1.0, 0.1, 1.0);
    let law = PointLaw {
        cubic: k3,
        ..Default::default()
    };
    let dt = TAU / 2000.0;
    let mut s = sdof(1.0, 0.0, k, dt, &[(0, law)]);
    let u: Vec<f64> = run(&mut s, &[a], &[0.0], 2000 * 20)
        .iter()
        .map(|x| x[0])
        .collect();
    let period = mean_period(&u, dt);
    let n = 2000;
    let h = 0.5 * PI / n as f64;
    let g = |th: f64| 1.0 / (k + k3 * a * a * (1.0 + th.sin().powi(2)) / 2.0).sqrt();
    let simpson: f64 = (0..=n)
        .map(|i| {
            let wgt = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            wgt * g(i as f64 * h)
        })
        .sum::<f64>()
        * h
        / 3.0;
    let exact = 4.0 * simpson;
    let w = TAU / exact;
    let scheme = (w * dt).powi(2) / 12.0;
    eprintln!(
        "cubic: period {period}, exact {exact}, relative {:e} (scheme {scheme:e})",
        period / exact - 1.0
    );
    assert!((period / exact - 1.0).abs() < 1.5 * scheme);
    let backbone = TAU / (k * (1.0 + 0.75 * k3 * a * a / k)).sqrt();
    let kappa = k3 * a * a / k;
    assert!((exact / backbone - 1.0).abs() < 0.02 * kappa * kappa);
}

/// Two coupled DOFs with a cubic spring and a velocity-squared dashpot at each (the
/// Gauss-Seidel path) against a fine fourth-order Runge-Kutta reference: the error is
/// second order in dt.
#[test]
fn two_laws_converge_at_second_order_to_a_runge_kutta_reference() {
    let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.2, 0.2, 0.5]);
    let k = DMatrix::from_row_slice(2, 2, &[3.0, -1.0, -1.0, 2.0]);
    let c = &k * 0.01;
    let laws = [
        (
            0,
            PointLaw {
                cubic: 2.0,
                quadratic: 0.1,
                friction: 0.0,
            },
        ),
        (
            1,
            PointLaw {
                cubic: 1.0,
                quadratic: 0.2,
                friction: 0.0,
            },
        ),
    ];
    let (u0, v0) = ([0.8, -0.5], [0.0, 1.0]);
    let t_end = 5.0;
    // RK4 reference.
    let m_inv = m.clone().try_inverse().unwrap();
    let rhs = |x: &[f64; 4]| -> [f64; 4] {
        let (u, v) = ([x[0], x[1]], [x[2], x[3]]);
        let mut f = [0.0; 2];
        for i in 0..2 {
            f[i] = -(0..2)
                .map(|j| k[(i, j)] * u[j] + c[(i, j)] * v[j])
                .sum::<f64>();
        }
        for &(d, law) in &laws {
            f[d] -= law.force(u[d], v[d]);
        }
        let a: Vec<f64> = (0..2)
            .map(|i| (0..2).map(|j| m_inv[(i, j)] * f[j]).sum())
            .collect();
        [v[0], v[1], a[0], a[1]]
    };
    let mut x = [u0[0], u0[1], v0[0], v0[1]];
    let n_ref = 100_000;
    let h = t_end / n_ref as f64;
    for _ in 0..n_ref {
        let k1 = rhs(&x);
        let add = |x: &[f64; 4], k: &[f64; 4], s: f64| {
            [
                x[0] + s * k[0],
                x[1] + s * k[1],
                x[2] + s * k[2],
                x[3] + s * k[3],
            ]
        };
        let k2 = rhs(&add(&x, &k1, h / 2.0));
        let k3 = rhs(&add(&x, &k2, h / 2.0));
        let k4 = rhs(&add(&x, &k3, h));
        for i in 0..4 {
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    let errors: Vec<f64> = [500, 1000, 2000]
        .iter()
        .map(|&steps| {
            let mut s = DenseStepper::new(&m, &c, &k, t_end / steps as f64, &laws).unwrap();
            let u = run(&mut s, &u0, &v0, steps);
            let end = u.last().unwrap();
            (end[0] - x[0]).hypot(end[1] - x[1])
        })
        .collect();
    eprintln!("two laws: errors {errors:?}");
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 2.0).abs() < 0.1, "order {order}");
    }
    assert!(errors[2] < 1e-4);
}

#[test]
fn static_equilibrium_solves_the_cubic_balance() {
    let law = PointLaw {
        cubic: 1.0,
        ..Default::default()
    };
    let s = sdof(1.0, 0.0, 1.0, 0.01, &[(0, law)]);
    // u + u^3 = 2 at u = 1.
    let u = s.static_equilibrium(&[2.0]).unwrap();
    assert!((u[0] - 1.0).abs() < 1e-14);
    let m = DMatrix::identity(2, 2);
    let k = DMatrix::from_row_slice(2, 2, &[3.0, -1.0, -1.0, 2.0]);
    let s = DenseStepper::new(&m, &(&m * 0.0), &k, 0.01, &[(1, law)]).unwrap();
    let f = [0.5, -4.0];
    let u = s.static_equilibrium(&f).unwrap();
    let r0 = 3.0 * u[0] - u[1] - f[0];
    let r1 = -u[0] + 2.0 * u[1] + u[1].powi(3) - f[1];
    assert!(r0.abs() < 1e-13 && r1.abs() < 1e-12, "{r0} {r1}");
}

#[test]
fn bad_inputs_are_errors() {
    let one = DMatrix::from_element(1, 1, 1.0);
    let zero = DMatrix::from_element(1, 1, 0.0);
    assert!(DenseStepper::new(&one, &zero, &one, 0.0, &[]).is_err());
    assert!(DenseStepper::new(&zero, &zero, &zero, 0.1, &[]).is_err());
    // A negative dashpot (a softening cubic, k3 < 0, is a valid law).
    let law = PointLaw {
        quadratic: -1.0,
        ..Default::default()
    };
    assert!(DenseStepper::new(&one, &zero, &one, 0.1, &[(0, law)]).is_err());
    assert!(DenseStepper::new(&one, &zero, &one, 0.1, &[(1, PointLaw::default())]).is_err());
    let law = PointLaw {
        cubic: 1.0,
        ..Default::default()
    };
    assert!(matches!(
        DenseStepper::new(&one, &zero, &one, 0.1, &[(0, law), (0, law)]),
        Err(DenseError::LawTwice { dof: 0 })
    ));
    let asym = DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.0, 1.0]);
    let id = DMatrix::identity(2, 2);
    assert!(DenseStepper::new(&id, &(&id * 0.0), &asym, 0.1, &[]).is_err());
    let mut s = DenseStepper::new(&one, &zero, &one, 0.1, &[]).unwrap();
    assert!(s.set_state(&[f64::NAN], &[0.0]).is_err());
    assert!(s.simulate(&[1.0], &[0.0], 3, 0, 0).is_err());
    assert!(s.simulate(&[1.0], &[0.0], 3, 1, 1).is_err());
    let samples = s.simulate(&[1.0], &[0.0], 3, 2, 0).unwrap();
    assert_eq!(samples.len(), 3);
    assert_eq!(samples[0].u, 1.0);
}
