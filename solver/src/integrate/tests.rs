//! Tests across the integrators (modal superposition against direct integration,
//! error paths) and the helpers shared with the per-module tests.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

use super::modal_superposition::{
    integrate_modal, modal_coordinates, modal_damping_ratios, project, rayleigh_damping_ratios,
    ModalBasis, ModalState,
};
use super::*;

/// Mass, damping and stiffness matrices of a test system.
pub(crate) type Mck = (
    SparseColMat<usize, f64>,
    SparseColMat<usize, f64>,
    SparseColMat<usize, f64>,
);

/// A sparse matrix from a dense row-major table, zeros left out.
pub(crate) fn sparse(rows: &[&[f64]]) -> SparseColMat<usize, f64> {
    let n = rows.len();
    let mut t = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            if v != 0.0 {
                t.push(Triplet::new(i, j, v));
            }
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
}

/// A banded chain of `nodes` 6-DOF nodes (full 12x12 coupling blocks), plus one
/// "hub" DOF numbered first and coupled to the last node's DOFs, as a rigid tie's
/// reference DOF is. SPD (diagonally dominant). Returns the full matrix.
pub(crate) fn chain_with_hub(nodes: usize, seed: u64) -> SparseColMat<usize, f64> {
    let mut state = seed;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % 1000) as f64 / 1000.0 - 0.5
    };
    let n = 1 + 6 * nodes;
    let mut t = Vec::new();
    let mut diag = vec![0.0; n];
    let mut couple = |t: &mut Vec<Triplet<usize, usize, f64>>, i: usize, j: usize, v: f64| {
        t.push(Triplet::new(i, j, v));
        t.push(Triplet::new(j, i, v));
        diag[i] += v.abs();
        diag[j] += v.abs();
    };
    for node in 0..nodes.saturating_sub(1) {
        let base = 1 + 6 * node;
        for p in 0..12 {
            for q in 0..p {
                couple(&mut t, base + p, base + q, next());
            }
        }
    }
    for k in 0..6 {
        couple(&mut t, 0, n - 6 + k, next());
    }
    for (i, d) in diag.iter().enumerate() {
        t.push(Triplet::new(i, i, d + 1.0));
    }
    SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
}

pub(crate) fn lower(a: &SparseColMat<usize, f64>) -> SparseColMat<usize, f64> {
    let n = a.nrows();
    let mut t = Vec::new();
    for j in 0..n {
        for (&i, &v) in a
            .symbolic()
            .row_idx_of_col_raw(j)
            .iter()
            .zip(a.val_of_col(j))
        {
            if i >= j {
                t.push(Triplet::new(i, j, v));
            }
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
}

pub(crate) fn mul(a: &SparseColMat<usize, f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    for (j, &xj) in x.iter().enumerate() {
        for (&i, &v) in a
            .symbolic()
            .row_idx_of_col_raw(j)
            .iter()
            .zip(a.val_of_col(j))
        {
            y[i] += v * xj;
        }
    }
    y
}

/// Runs `scheme` on `ops` from `u0`, `v0` without load and returns the history of
/// DOF `dof`.
pub(super) fn free_history(
    ops: Operators<'_>,
    scheme: Scheme,
    dt: f64,
    n_steps: usize,
    u0: &[f64],
    v0: &[f64],
    dof: usize,
) -> Vec<f64> {
    let mut history = Vec::with_capacity(n_steps + 1);
    integrate(
        ops,
        scheme,
        dt,
        n_steps,
        u0,
        v0,
        &mut |_, _| {},
        &mut |_, _, s| history.push(s.u[dof]),
    )
    .unwrap();
    history
}

/// Upward zero crossings, linearly interpolated, as fractional step indices.
pub(super) fn upward_crossings(u: &[f64]) -> Vec<f64> {
    u.windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(n, w)| n as f64 + w[0] / (w[0] - w[1]))
        .collect()
}

/// Mean period in steps between the first and last upward crossing.
pub(super) fn period_in_steps(u: &[f64]) -> f64 {
    let c = upward_crossings(u);
    (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64
}

/// `ln |L|` per step of a sampled damped sinusoid `u_n = A r^n cos(theta n + phi)`,
/// from the Casorati invariant `u_n^2 - u_{n-1} u_{n+1} = A^2 r^{2n} sin^2(theta)`,
/// which is exactly geometric whatever the phase (no peak picking, no interpolation).
pub(super) fn log_decay_per_step(u: &[f64], from: usize, to: usize) -> f64 {
    let e = |n: usize| u[n] * u[n] - u[n - 1] * u[n + 1];
    (e(to) / e(from)).ln() / (2.0 * (to - from) as f64)
}

/// Two-DOF chain with classical Rayleigh damping: the test system of the modal
/// comparison. Returns (M, K, alpha, beta).
fn two_dof() -> (SparseColMat<usize, f64>, SparseColMat<usize, f64>, f64, f64) {
    let m = sparse(&[&[2.0, 0.0], &[0.0, 1.0]]);
    let k = sparse(&[&[600.0, -200.0], &[-200.0, 200.0]]);
    (m, k, 0.5, 1e-3)
}

/// Eigenpairs of the 2x2 problem `K phi = w^2 M phi` (M diagonal), shapes mass-normalised.
fn two_dof_modes(m: [f64; 2], k: [[f64; 2]; 2]) -> (Vec<f64>, Mat<f64>) {
    // det(K - l M) = m0 m1 l^2 - (k00 m1 + k11 m0) l + det K
    let (a, b, c) = (
        m[0] * m[1],
        -(k[0][0] * m[1] + k[1][1] * m[0]),
        k[0][0] * k[1][1] - k[0][1] * k[1][0],
    );
    let disc = (b * b - 4.0 * a * c).sqrt();
    let lambdas = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
    let mut shapes = Mat::zeros(2, 2);
    let mut omega = Vec::new();
    for (j, &l) in lambdas.iter().enumerate() {
        // First row of (K - l M) phi = 0.
        let phi = [-k[0][1], k[0][0] - l * m[0]];
        let norm = (m[0] * phi[0] * phi[0] + m[1] * phi[1] * phi[1]).sqrt();
        shapes[(0, j)] = phi[0] / norm;
        shapes[(1, j)] = phi[1] / norm;
        omega.push(l.sqrt());
    }
    (omega, shapes)
}

/// A triangular pulse on DOF 1: 0 -> 100 -> 0 over [0, 0.02] s, kinks at sample
/// times for the steps used, so both methods see it exactly as piecewise linear.
fn pulse(t: f64) -> f64 {
    let peak = 100.0;
    if t <= 0.01 {
        peak * t / 0.01
    } else if t <= 0.02 {
        peak * (0.02 - t) / 0.01
    } else {
        0.0
    }
}

#[test]
fn modal_superposition_matches_direct_integration_to_second_order() {
    let (m, k, alpha, beta) = two_dof();
    let c = sparse(&[
        &[alpha * 2.0 + beta * 600.0, -beta * 200.0],
        &[-beta * 200.0, alpha * 1.0 + beta * 200.0],
    ]);
    let (omega, shapes) = two_dof_modes([2.0, 1.0], [[600.0, -200.0], [-200.0, 200.0]]);
    let zeta = rayleigh_damping_ratios(&omega, alpha, beta);
    // Classical damping: the general phi^T C phi / 2w must agree with Rayleigh's formula.
    let zeta_general = modal_damping_ratios(shapes.as_ref(), &omega, c.as_ref()).unwrap();
    for (z, zg) in zeta.iter().zip(&zeta_general) {
        assert!((z - zg).abs() < 1e-14, "{z} vs {zg}");
    }

    let u0 = [0.01, 0.02];
    let v0 = [0.0, 0.5];
    let t_end = 1.0;
    let modal = |dt: f64| -> Vec<[f64; 2]> {
        let n_steps = (t_end / dt).round() as usize;
        let initial = ModalState {
            t: 0.0,
            q: modal_coordinates(shapes.as_ref(), m.as_ref(), &u0).unwrap(),
            qd: modal_coordinates(shapes.as_ref(), m.as_ref(), &v0).unwrap(),
        };
        let basis = ModalBasis {
            shapes: shapes.as_ref(),
            omega: &omega,
            zeta: &zeta,
        };
        let mut out = Vec::new();
        let mut f = [0.0; 2];
        integrate_modal(
            basis,
            dt,
            n_steps,
            &initial,
            &[0, 1],
            &mut |t, p| {
                f[1] = pulse(t);
                project(shapes.as_ref(), &f, p).unwrap();
            },
            &mut |_, _, r| out.push([r.u[0], r.u[1]]),
        )
        .unwrap();
        out
    };
    let direct = |dt: f64| -> Vec<[f64; 2]> {
        let n_steps = (t_end / dt).round() as usize;
        let ops = Operators {
            m: m.as_ref(),
            c: Some(c.as_ref()),
            k: k.as_ref(),
        };
        let mut out = Vec::new();
        integrate(
            ops,
            Scheme::AverageAcceleration,
            dt,
            n_steps,
            &u0,
            &v0,
            &mut |t, f| f[1] = pulse(t),
            &mut |_, _, s| out.push([s.u[0], s.u[1]]),
        )
        .unwrap();
        out
    };
    let error = |dt: f64| -> (f64, f64) {
        let (a, b) = (modal(dt), direct(dt));
        let amplitude = a
            .iter()
            .flat_map(|x| x.iter())
            .fold(0.0f64, |s, x| s.max(x.abs()));
        let e = a
            .iter()
            .zip(&b)
            .flat_map(|(x, y)| [(x[0] - y[0]).abs(), (x[1] - y[1]).abs()])
            .fold(0.0, f64::max);
        (e, amplitude)
    };
    let dts = [1e-3, 5e-4, 2.5e-4];
    let errors: Vec<(f64, f64)> = dts.iter().map(|&dt| error(dt)).collect();
    let w_max = omega[1];
    for (i, &(e, amplitude)) in errors.iter().enumerate() {
        // Phase error of the fastest mode after t_end, the dominant term:
        // amplitude * w t (w dt)^2 / 12; a factor 2 covers the mode mix.
        let bound = 2.0 * amplitude * w_max * t_end * (w_max * dts[i]).powi(2) / 12.0;
        eprintln!("modal vs direct: dt = {:e}: max |du| = {e:.3e} (bound {bound:.3e}, amplitude {amplitude:.3e})", dts[i]);
        assert!(e < bound, "dt = {}: error {e} above {bound}", dts[i]);
    }
    for w in errors.windows(2) {
        let slope = (w[0].0 / w[1].0).log2();
        eprintln!("modal vs direct: slope {slope:.4}");
        assert!((1.9..=2.1).contains(&slope), "slope {slope}");
    }
}

#[test]
fn rejects_a_bad_time_step_and_parameters() {
    let m = sparse(&[&[1.0]]);
    let k = sparse(&[&[1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k.as_ref(),
    };
    for dt in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        assert!(
            matches!(
                Stepper::new(ops, Scheme::default(), dt),
                Err(IntegrateError::InvalidTimeStep { .. })
            ),
            "dt = {dt}"
        );
    }
    for scheme in [
        Scheme::Hht { alpha: 0.1 },
        Scheme::Hht { alpha: -0.5 },
        Scheme::GeneralizedAlpha { rho_inf: 1.5 },
        Scheme::GeneralizedAlpha { rho_inf: f64::NAN },
    ] {
        assert!(
            matches!(
                Stepper::new(ops, scheme, 1e-3),
                Err(IntegrateError::InvalidParameter { .. })
            ),
            "{scheme:?}"
        );
    }
}

#[test]
fn rejects_a_non_finite_state() {
    let m = sparse(&[&[1.0, 0.0], &[0.0, 1.0]]);
    let k = sparse(&[&[2.0, -1.0], &[-1.0, 1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k.as_ref(),
    };
    let result = integrate(
        ops,
        Scheme::default(),
        0.01,
        100,
        &[0.0, 0.0],
        &[0.0, 1.0],
        &mut |t, f| {
            if t > 0.5 {
                f[0] = f64::NAN;
            }
        },
        &mut |_, _, _| {},
    );
    match result {
        Err(IntegrateError::NonFiniteState { step, time, .. }) => {
            assert_eq!(step, 51);
            assert!((time - 0.51).abs() < 1e-12);
        }
        other => panic!("expected a non-finite state error, got {other:?}"),
    }
    let bad_u0 = integrate(
        ops,
        Scheme::default(),
        0.01,
        1,
        &[f64::NAN, 0.0],
        &[0.0, 0.0],
        &mut |_, _| {},
        &mut |_, _, _| {},
    );
    assert!(matches!(
        bad_u0,
        Err(IntegrateError::NonFiniteInput { index: 0, .. })
    ));
}

#[test]
fn rejects_a_singular_effective_matrix_and_names_the_dof() {
    // DOF 1 has neither mass nor stiffness: S is singular whatever dt.
    let m = sparse(&[&[1.0, 0.0, 0.0], &[0.0, 0.0, 0.0], &[0.0, 0.0, 1.0]]);
    let k = sparse(&[&[1.0, 0.0, 0.0], &[0.0, 0.0, 0.0], &[0.0, 0.0, 1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k.as_ref(),
    };
    match Stepper::new(ops, Scheme::default(), 1e-3) {
        Err(IntegrateError::NotPositiveDefinite { dof, .. }) => assert_eq!(dof, 1),
        other => panic!("expected a singular effective matrix, got {other:?}"),
    }
    // A negative stiffness large enough to beat the inertia at this dt.
    let k = sparse(&[&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[0.0, 0.0, -1e9]]);
    let m = sparse(&[&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[0.0, 0.0, 1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k.as_ref(),
    };
    match Stepper::new(ops, Scheme::default(), 1e-3) {
        Err(IntegrateError::NotPositiveDefinite { dof, .. }) => assert_eq!(dof, 2),
        other => panic!("expected an indefinite effective matrix, got {other:?}"),
    }
}

#[test]
fn rejects_asymmetric_and_mismatched_operators() {
    let m = sparse(&[&[1.0, 0.0], &[0.0, 1.0]]);
    let k = sparse(&[&[2.0, -1.0], &[-1.5, 1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k.as_ref(),
    };
    assert!(matches!(
        Stepper::new(ops, Scheme::default(), 1e-3),
        Err(IntegrateError::NotSymmetric { row: 1, col: 0, .. })
    ));
    let k3 = sparse(&[&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[0.0, 0.0, 1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k3.as_ref(),
    };
    assert!(matches!(
        Stepper::new(ops, Scheme::default(), 1e-3),
        Err(IntegrateError::DimensionMismatch { .. })
    ));
}

#[test]
fn massless_dof_gets_zero_initial_acceleration_and_steps() {
    // DOF 1 is massless but stiff (a rotation without rotary inertia): static
    // condensation makes DOF 0 an oscillator with k_eff = 3 - 1/1 = 2, m = 1.
    let m = sparse(&[&[1.0, 0.0], &[0.0, 0.0]]);
    let k = sparse(&[&[3.0, -1.0], &[-1.0, 1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k.as_ref(),
    };
    let mut stepper = Stepper::new(ops, Scheme::default(), 1e-3).unwrap();
    let state = stepper
        .initial_state(0.0, &[1.0, 1.0], &[0.0, 0.0], &[0.0, 0.0])
        .unwrap();
    assert_eq!(state.a[1], 0.0);
    assert!((state.a[0] - (-2.0)).abs() < 1e-14, "a0 = {}", state.a[0]);
    // The massless DOF follows its constraint u1 = u0 in displacement and velocity;
    // under average acceleration its acceleration carries the initial mismatch
    // a1(0) - a0(0) as a ripple alternating every step (documented).
    let mut state = state;
    for k in 1..=6 {
        stepper.step(&mut state, &[0.0; 2], &[0.0; 2], k).unwrap();
        assert!((state.u[1] - state.u[0]).abs() < 1e-14, "u: {:?}", state.u);
        assert!((state.v[1] - state.v[0]).abs() < 1e-12, "v: {:?}", state.v);
        let ripple = state.a[1] - state.a[0];
        let expected = if k % 2 == 1 { -2.0 } else { 2.0 };
        assert!(
            (ripple - expected).abs() < 1e-6,
            "step {k}: a1 - a0 = {ripple}"
        );
    }
    let history = free_history(
        ops,
        Scheme::default(),
        1e-3,
        20_000,
        &[1.0, 1.0],
        &[0.0, 0.0],
        0,
    );
    let period = period_in_steps(&history) * 1e-3;
    let expected = 2.0 * std::f64::consts::PI / 2f64.sqrt();
    // Period error of average acceleration, (w dt)^2/12 ~ 2e-7, plus crossing noise.
    assert!(
        (period / expected - 1.0).abs() < 1e-5,
        "period {period} vs {expected}"
    );

    // A DOF whose mass column is non-zero but singular is reported by index.
    let m = sparse(&[&[1.0, 0.0, 0.0], &[0.0, 1.0, 1.0], &[0.0, 1.0, 1.0]]);
    let k = sparse(&[&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[0.0, 0.0, 1.0]]);
    let ops = Operators {
        m: m.as_ref(),
        c: None,
        k: k.as_ref(),
    };
    let mut stepper = Stepper::new(ops, Scheme::default(), 1e-3).unwrap();
    match stepper.initial_state(0.0, &[0.0; 3], &[0.0; 3], &[0.0; 3]) {
        Err(IntegrateError::NotPositiveDefinite { dof, .. }) => {
            assert!(dof == 1 || dof == 2, "dof {dof}")
        }
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
}

#[test]
fn set_step_refactors_and_matches_a_fresh_stepper() {
    let m = sparse(&[&[1.0, 0.0], &[0.0, 2.0]]);
    let k = sparse(&[&[300.0, -100.0], &[-100.0, 100.0]]);
    let c = sparse(&[&[0.3, -0.1], &[-0.1, 0.1]]);
    let ops = Operators {
        m: m.as_ref(),
        c: Some(c.as_ref()),
        k: k.as_ref(),
    };
    let scheme = Scheme::GeneralizedAlpha { rho_inf: 0.7 };
    let mut reused = Stepper::new(ops, Scheme::default(), 1e-2).unwrap();
    reused.set_step(scheme, 2e-3).unwrap();
    let mut fresh = Stepper::new(ops, scheme, 2e-3).unwrap();
    let zero = [0.0, 0.0];
    let mut s1 = reused
        .initial_state(0.0, &[0.01, 0.0], &[0.0, 1.0], &zero)
        .unwrap();
    let mut s2 = fresh
        .initial_state(0.0, &[0.01, 0.0], &[0.0, 1.0], &zero)
        .unwrap();
    for k in 1..=200 {
        reused.step(&mut s1, &zero, &zero, k).unwrap();
        fresh.step(&mut s2, &zero, &zero, k).unwrap();
    }
    assert_eq!(s1, s2);
}

#[test]
fn empty_operators_step_trivially() {
    let empty = SparseColMat::<usize, f64>::try_new_from_triplets(0, 0, &[]).unwrap();
    let ops = Operators {
        m: empty.as_ref(),
        c: Some(empty.as_ref()),
        k: empty.as_ref(),
    };
    for scheme in COMPARED {
        let mut count = 0;
        let last = integrate(
            ops,
            scheme,
            1e-3,
            3,
            &[],
            &[],
            &mut |_, _| {},
            &mut |_, _, _| count += 1,
        )
        .unwrap();
        assert_eq!(count, 4);
        assert!(last.u.is_empty() && (last.t - 3e-3).abs() < 1e-15);
    }
}

/// Average acceleration with smooth point laws on dense matrices, the step's balance
/// `M a + C v + K u + E f(u, v) = f(t)` solved for `a_{n+1}` by Newton's method on
/// the whole system (tangent `S + E (beta dt^2 df/du + gamma dt df/dv) E^T`): an
/// independent reference for the stepper's end-of-step correction.
#[allow(clippy::too_many_arguments)]
fn dense_nonlinear_reference(
    (m, c, k): &Mck,
    laws: &[(usize, PointLaw)],
    dt: f64,
    n_steps: usize,
    u0: &[f64],
    v0: &[f64],
    load: &dyn Fn(f64, &mut [f64]),
) -> Vec<State> {
    let n = k.nrows();
    let (md, cd, kd) = (m.to_dense(), c.to_dense(), k.to_dense());
    let (beta, gamma) = (0.25, 0.5);
    let mul = |a: &Mat<f64>, x: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|i| (0..n).map(|j| a[(i, j)] * x[j]).sum())
            .collect()
    };
    let law_force = |u: &[f64], v: &[f64], out: &mut [f64]| {
        for &(d, law) in laws {
            out[d] += law.force(u[d], v[d]);
        }
    };
    let mut f0 = vec![0.0; n];
    load(0.0, &mut f0);
    let (cv, ku) = (mul(&cd, v0), mul(&kd, u0));
    let mut fl = vec![0.0; n];
    law_force(u0, v0, &mut fl);
    let r = Mat::from_fn(n, 1, |i, _| f0[i] - cv[i] - ku[i] - fl[i]);
    let a0 = md.llt(faer::Side::Lower).unwrap().solve(&r);
    let mut state = State {
        t: 0.0,
        u: u0.to_vec(),
        v: v0.to_vec(),
        a: (0..n).map(|i| a0[(i, 0)]).collect(),
    };
    let mut out = vec![state.clone()];
    let mut f_next = vec![0.0; n];
    for step in 1..=n_steps {
        let t = step as f64 * dt;
        f_next.fill(0.0);
        load(t, &mut f_next);
        let ut: Vec<f64> = (0..n)
            .map(|i| state.u[i] + dt * state.v[i] + dt * dt * (0.5 - beta) * state.a[i])
            .collect();
        let vt: Vec<f64> = (0..n)
            .map(|i| state.v[i] + dt * (1.0 - gamma) * state.a[i])
            .collect();
        let mut a = state.a.clone();
        for _ in 0..50 {
            let u: Vec<f64> = (0..n).map(|i| ut[i] + beta * dt * dt * a[i]).collect();
            let v: Vec<f64> = (0..n).map(|i| vt[i] + gamma * dt * a[i]).collect();
            let (ma, cv, ku) = (mul(&md, &a), mul(&cd, &v), mul(&kd, &u));
            let mut fl = vec![0.0; n];
            law_force(&u, &v, &mut fl);
            let residual: Vec<f64> = (0..n)
                .map(|i| ma[i] + cv[i] + ku[i] + fl[i] - f_next[i])
                .collect();
            let mut jac = Mat::from_fn(n, n, |i, j| {
                md[(i, j)] + gamma * dt * cd[(i, j)] + beta * dt * dt * kd[(i, j)]
            });
            for &(d, law) in laws {
                jac[(d, d)] += beta * dt * dt * law.tangent_stiffness(u[d])
                    + gamma * dt * 2.0 * law.quadratic * v[d].abs();
            }
            let rhs = Mat::from_fn(n, 1, |i, _| -residual[i]);
            let da = jac.llt(faer::Side::Lower).unwrap().solve(&rhs);
            let size = (0..n).fold(0.0f64, |s, i| s.max(da[(i, 0)].abs()));
            for (i, ai) in a.iter_mut().enumerate() {
                *ai += da[(i, 0)];
            }
            if size <= 1e-15 * a.iter().fold(1.0f64, |s, x| s.max(x.abs())) {
                break;
            }
        }
        for i in 0..n {
            state.u[i] = ut[i] + beta * dt * dt * a[i];
            state.v[i] = vt[i] + gamma * dt * a[i];
            state.a[i] = a[i];
        }
        state.t = t;
        out.push(state.clone());
    }
    out
}

/// Cubic springs and velocity-squared dashpots at three DOFs of the helix (the hub
/// among them): the Gauss-Seidel over the laws' Schur matrix against Newton on the
/// whole system.
#[test]
fn point_laws_match_a_monolithic_newton_reference() {
    let (nodes, dt, n_steps) = (8, 0.02, 200);
    let mck = helix_like(nodes, false);
    let n = mck.2.nrows();
    let laws = [
        (
            0,
            PointLaw {
                cubic: 50.0,
                quadratic: 2.0,
                friction: 0.0,
            },
        ),
        (
            7,
            PointLaw {
                cubic: 400.0,
                ..Default::default()
            },
        ),
        (
            8,
            PointLaw {
                quadratic: 5.0,
                ..Default::default()
            },
        ),
    ];
    let load = |t: f64, f: &mut [f64]| f[0] = 2.0 * (3.0 * t).sin();
    let u0: Vec<f64> = (0..n).map(|i| 0.05 * (0.3 * i as f64).sin()).collect();
    let mut v0 = vec![0.0; n];
    v0[0] = 1.0;
    let reference = dense_nonlinear_reference(&mck, &laws, dt, n_steps, &u0, &v0, &load);
    let ops = Operators {
        m: mck.0.as_ref(),
        c: Some(mck.1.as_ref()),
        k: mck.2.as_ref(),
    };
    for banded in [true, false] {
        let mut stepper = if banded {
            Stepper::new(ops, Scheme::AverageAcceleration, dt).unwrap()
        } else {
            Stepper::new_sparse(ops, Scheme::AverageAcceleration, dt).unwrap()
        };
        stepper.set_point_laws(&laws).unwrap();
        let errors = relative_differences(&mut stepper, &reference, &u0, &v0, &load);
        let forces = stepper.point_law_forces();
        eprintln!(
            "point laws, banded {banded}: max |du|, |dv|, |da| relative {:.2e} {:.2e} {:.2e}; final forces {forces:?}",
            errors[0], errors[1], errors[2]
        );
        // Both solve the same discrete equations, each to round-off (the Gauss-Seidel
        // stops at 1e-12 of the largest force).
        assert!(errors.iter().all(|&e| e <= 1e-11), "{errors:?}");
        assert_eq!(forces.len(), 3);
    }
}

#[test]
fn point_laws_need_average_acceleration_and_valid_coefficients() {
    let (m, c, k) = two_dof_mck();
    let ops = Operators {
        m: m.as_ref(),
        c: Some(c.as_ref()),
        k: k.as_ref(),
    };
    let friction = PointLaw {
        friction: 1.0,
        ..Default::default()
    };
    let mut hht = Stepper::new(ops, Scheme::Hht { alpha: -0.1 }, 0.01).unwrap();
    assert!(matches!(
        hht.set_point_laws(&[(0, friction)]),
        Err(IntegrateError::PointLawScheme {
            scheme: "HHT-alpha"
        })
    ));
    // HHT with alpha = 0 is average acceleration.
    let mut zero = Stepper::new(ops, Scheme::Hht { alpha: 0.0 }, 0.01).unwrap();
    zero.set_point_laws(&[(0, friction)]).unwrap();
    let mut stepper = Stepper::new(ops, Scheme::AverageAcceleration, 0.01).unwrap();
    stepper.set_point_laws(&[(1, friction)]).unwrap();
    assert!(matches!(
        stepper.set_step(Scheme::GeneralizedAlpha { rho_inf: 0.8 }, 0.01),
        Err(IntegrateError::PointLawScheme { .. })
    ));
    for (dof, law) in [
        (2, friction),
        (
            0,
            // A negative friction force (a softening cubic, k3 < 0, is a valid law).
            PointLaw {
                friction: -1.0,
                ..Default::default()
            },
        ),
        (
            0,
            PointLaw {
                quadratic: f64::NAN,
                ..Default::default()
            },
        ),
    ] {
        assert!(matches!(
            stepper.set_point_laws(&[(dof, law)]),
            Err(IntegrateError::InvalidPointLaw { .. })
        ));
    }
}

#[test]
fn without_laws_the_step_is_bitwise_the_linear_one() {
    let (m, c, k) = two_dof_mck();
    let ops = Operators {
        m: m.as_ref(),
        c: Some(c.as_ref()),
        k: k.as_ref(),
    };
    let run = |laws: Option<&[(usize, PointLaw)]>| {
        let mut stepper = Stepper::new(ops, Scheme::AverageAcceleration, 0.01).unwrap();
        if let Some(laws) = laws {
            stepper
                .set_point_laws(&[(
                    0,
                    PointLaw {
                        cubic: 3.0,
                        ..Default::default()
                    },
                )])
                .unwrap();
            stepper.set_point_laws(laws).unwrap();
        }
        let mut state = stepper
            .initial_state(0.0, &[0.01, -0.02], &[0.3, 0.0], &[0.0, 1.0])
            .unwrap();
        stepper
            .run(&mut state, 100, &mut |t, f| f[1] = t.cos(), &mut |_, _| {})
            .unwrap();
        state
    };
    let linear = run(None);
    // Cleared laws, and a law that does nothing, leave the linear step.
    assert_eq!(run(Some(&[])), linear);
    assert_eq!(run(Some(&[(1, PointLaw::default())])), linear);
}

fn two_dof_mck() -> Mck {
    (
        sparse(&[&[2.0, 0.0], &[0.0, 1.0]]),
        sparse(&[&[0.4, -0.1], &[-0.1, 0.2]]),
        sparse(&[&[300.0, -100.0], &[-100.0, 100.0]]),
    )
}

/// A helix-like system: 6-DOF nodes in a chain (full 12x12 coupling blocks, `K` from
/// [`chain_with_hub`]) and a hub DOF 0 (a weight tied to the far end) coupled to the
/// last node. Light rotational inertia (1e-4) puts those modes at `w dt ~ 5` at the
/// test's `dt`, translations near `w dt ~ 0.05`. Lumped or consistent mass, Rayleigh
/// damping without the weight's mass term (as coil's `DAMPING` on the wire only).
pub(crate) fn helix_like(nodes: usize, lumped: bool) -> Mck {
    let k = chain_with_hub(nodes, 21);
    let n = k.nrows();
    let inertia = |i: usize| match i {
        0 => 10.0,
        i if (i - 1) % 6 < 3 => 1.0,
        _ => 1e-4,
    };
    let mut m_t: Vec<Triplet<usize, usize, f64>> =
        (0..n).map(|i| Triplet::new(i, i, inertia(i))).collect();
    if !lumped {
        // A small SPD coupling on the same pattern (diagonally dominant, scaled).
        let coupling = chain_with_hub(nodes, 5);
        for j in 0..n {
            for (&i, &v) in coupling
                .symbolic()
                .row_idx_of_col_raw(j)
                .iter()
                .zip(coupling.val_of_col(j))
            {
                let scale = 1e-2 * (inertia(i) * inertia(j)).sqrt();
                m_t.push(Triplet::new(i, j, scale * v));
            }
        }
    }
    let m = SparseColMat::try_new_from_triplets(n, n, &m_t).unwrap();
    let (alpha, beta) = (0.3, 0.01);
    let mut c_t = Vec::new();
    for (a, factor, skip_weight) in [(&m, alpha, true), (&k, beta, false)] {
        for j in 0..n {
            for (&i, &v) in a
                .symbolic()
                .row_idx_of_col_raw(j)
                .iter()
                .zip(a.val_of_col(j))
            {
                if !(skip_weight && i == 0 && j == 0) {
                    c_t.push(Triplet::new(i, j, factor * v));
                }
            }
        }
    }
    let c = SparseColMat::try_new_from_triplets(n, n, &c_t).unwrap();
    (m, c, k)
}

/// The three schemes of the comparisons.
pub(crate) const COMPARED: [Scheme; 3] = [
    Scheme::AverageAcceleration,
    Scheme::Hht { alpha: -0.05 },
    Scheme::GeneralizedAlpha { rho_inf: 0.8 },
];

/// Runs `stepper` like [`dense_reference`] and returns the largest differences of
/// `u`, `v`, `a` from `reference`, each relative to the largest value in the reference.
pub(crate) fn relative_differences(
    stepper: &mut Stepper,
    reference: &[State],
    u0: &[f64],
    v0: &[f64],
    load: &dyn Fn(f64, &mut [f64]),
) -> [f64; 3] {
    let n = u0.len();
    let mut f0 = vec![0.0; n];
    load(0.0, &mut f0);
    let mut state = stepper.initial_state(0.0, u0, v0, &f0).unwrap();
    let mut history = Vec::new();
    stepper
        .run(
            &mut state,
            reference.len() - 1,
            &mut |t, f| load(t, f),
            &mut |_, s| history.push(s.clone()),
        )
        .unwrap();
    let pick: [fn(&State) -> &[f64]; 3] = [|s| &s.u, |s| &s.v, |s| &s.a];
    pick.map(|get| {
        let scale = reference
            .iter()
            .flat_map(|s| get(s).iter())
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let diff = history
            .iter()
            .zip(reference)
            .flat_map(|(s, r)| get(s).iter().zip(get(r)).map(|(x, y)| (x - y).abs()))
            .fold(0.0f64, f64::max);
        diff / scale
    })
}

/// Average acceleration from rest: the response to an end load is `(u, 2u/dt,
/// 4u/dt^2)` (`u = dt^2/4 a`, `v = dt/2 a`), on the dense, sparse and banded engines
/// alike, with and without damping. The contacts' and tension links' correction
/// (`crate::analysis::transient::contact`) keeps only `u` on that account.
#[test]
fn a_step_from_rest_is_its_displacement_scaled() {
    let diagonal = |n: usize, value: &dyn Fn(usize) -> f64| {
        let t: Vec<_> = (0..n).map(|i| Triplet::new(i, i, value(i))).collect();
        SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
    };
    let small = (
        sparse(&[&[2.0, 0.0], &[0.0, 1.0]]),
        sparse(&[&[600.0, -200.0], &[-200.0, 200.0]]),
    );
    let chain = chain_with_hub(60, 7);
    let mass = diagonal(chain.nrows(), &|i| 1.0 + (i % 3) as f64);
    for (m, k) in [small, (mass, chain)] {
        let n = m.nrows();
        for damped in [false, true] {
            let c = diagonal(n, &|_| if damped { 0.5 } else { 0.0 });
            let ops = Operators {
                m: m.as_ref(),
                c: damped.then(|| c.as_ref()),
                k: k.as_ref(),
            };
            let dt = 2.5e-3;
            let mut stepper = Stepper::new(ops, Scheme::AverageAcceleration, dt).unwrap();
            let zero = vec![0.0; n];
            let mut load = vec![0.0; n];
            load[n - 1] = 1.0;
            load[n / 2] = -0.3;
            let mut state = State::zeros(n, 0.0);
            stepper.step(&mut state, &zero, &load, 0).unwrap();
            let scale = state.a.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
            assert!(scale > 0.0);
            for i in 0..n {
                let u = state.u[i];
                assert!(
                    (state.v[i] - 2.0 * u / dt).abs() <= 1e-12 * scale * dt,
                    "v at {i}"
                );
                assert!(
                    (state.a[i] - 4.0 * u / (dt * dt)).abs() <= 1e-12 * scale,
                    "a at {i}"
                );
            }
        }
    }
}
