//! The Newmark-family steppers on one damped DOF: decay against the closed form, period
//! error, order in dt, algorithmic damping of HHT and generalised-alpha, the schemes'
//! coefficients.

use super::*;
use crate::integrate::tests::{free_history, log_decay_per_step, period_in_steps, sparse};
use std::f64::consts::PI;

/// One DOF: m = 1, k = w^2, c = 2 zeta w.
fn sdof(omega: f64, zeta: f64) -> [faer::sparse::SparseColMat<usize, f64>; 3] {
    [
        sparse(&[&[1.0]]),
        sparse(&[&[2.0 * zeta * omega]]),
        sparse(&[&[omega * omega]]),
    ]
}

fn ops(mats: &[faer::sparse::SparseColMat<usize, f64>; 3]) -> Operators<'_> {
    let c = mats[1].as_ref();
    let has_c = c.val().iter().any(|&x| x != 0.0);
    Operators {
        m: mats[0].as_ref(),
        c: has_c.then_some(c),
        k: mats[2].as_ref(),
    }
}

/// Closed-form free decay of an under-damped oscillator from u0 = 1, v0 = 0.
fn exact_decay(omega: f64, zeta: f64, t: f64) -> f64 {
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    (-zeta * omega * t).exp() * ((wd * t).cos() + zeta * omega / wd * (wd * t).sin())
}

const SCHEMES: [Scheme; 5] = [
    Scheme::AverageAcceleration,
    Scheme::Hht { alpha: -0.05 },
    Scheme::Hht { alpha: -1.0 / 3.0 },
    Scheme::GeneralizedAlpha { rho_inf: 0.5 },
    Scheme::GeneralizedAlpha { rho_inf: 0.8 },
];

#[test]
fn damped_sdof_decay_converges_to_the_closed_form_for_every_scheme() {
    let (omega, zeta, t_end) = (2.0 * PI, 0.05, 3.0);
    let mats = sdof(omega, zeta);
    for scheme in SCHEMES {
        let coefficients = scheme.coefficients().unwrap();
        let mut errors = Vec::new();
        for steps_per_period in [40usize, 80, 160] {
            let dt = 1.0 / steps_per_period as f64;
            let n = (t_end / dt).round() as usize;
            let u = free_history(ops(&mats), scheme, dt, n, &[1.0], &[0.0], 0);
            let e = u
                .iter()
                .enumerate()
                .map(|(k, x)| (x - exact_decay(omega, zeta, k as f64 * dt)).abs())
                .fold(0.0, f64::max);
            // Leading-order phase and amplitude drift over t_end, factor 2 for the
            // physical damping's own O(dt^2) terms.
            let w_dt = omega * dt;
            let bound = 2.0
                * omega
                * t_end
                * (coefficients.period_elongation(w_dt).abs()
                    + coefficients.algorithmic_damping(w_dt))
                + 2.0 * (zeta * w_dt).powi(2);
            eprintln!(
                "{scheme:?}: dt = T/{steps_per_period}: max error {e:.3e} (bound {bound:.3e})"
            );
            assert!(
                e < bound,
                "{scheme:?}, dt = T/{steps_per_period}: error {e} above {bound}"
            );
            errors.push(e);
        }
        for w in errors.windows(2) {
            let slope = (w[0] / w[1]).log2();
            assert!((1.8..=2.2).contains(&slope), "{scheme:?}: slope {slope}");
        }
    }
}

#[test]
fn average_acceleration_has_no_amplitude_decay() {
    // w dt = 0.1, 1000 cycles.
    let (omega, dt) = (1.0, 0.1);
    let mats = sdof(omega, 0.0);
    let n = (1000.0 * 2.0 * PI / dt) as usize;
    let u = free_history(
        ops(&mats),
        Scheme::AverageAcceleration,
        dt,
        n,
        &[1.0],
        &[0.0],
        0,
    );
    let theta = 2.0 * PI / period_in_steps(&u);
    let zeta_num = -log_decay_per_step(&u, 1, n - 1) / theta;
    eprintln!("average acceleration, w dt = 0.1, {n} steps: zeta_num = {zeta_num:.3e}");
    assert!(zeta_num.abs() < 1e-6, "zeta_num = {zeta_num}");
    // The trapezoidal rule conserves this exactly; round-off is all that is left.
    assert!(zeta_num.abs() < 1e-12, "zeta_num = {zeta_num}");
}

#[test]
fn average_acceleration_period_error_is_w_dt_squared_over_twelve() {
    let omega = 1.0;
    let mats = sdof(omega, 0.0);
    for w_dt in [0.05, 0.1, 0.2, 0.4] {
        let n = (50.0 * 2.0 * PI / w_dt) as usize;
        let u = free_history(
            ops(&mats),
            Scheme::AverageAcceleration,
            w_dt / omega,
            n,
            &[1.0],
            &[0.0],
            0,
        );
        let measured = period_in_steps(&u) * w_dt / (2.0 * PI) - 1.0;
        let leading = w_dt * w_dt / 12.0;
        let exact = w_dt / (2.0 * (w_dt / 2.0).atan()) - 1.0;
        eprintln!("average acceleration, w dt = {w_dt}: period error {measured:.6e}, (w dt)^2/12 = {leading:.6e}, ratio {:.4}", measured / leading);
        assert!(
            (measured / leading - 1.0).abs() < 0.10,
            "w dt = {w_dt}: {measured} vs {leading}"
        );
        // The zero-crossing measurement itself is far more precise than 10%.
        assert!(
            (measured / exact - 1.0).abs() < 1e-3,
            "w dt = {w_dt}: {measured} vs exact {exact}"
        );
    }
}

#[test]
fn average_acceleration_error_is_second_order_in_dt() {
    let (omega, t_end) = (2.0 * PI, 10.0);
    let mats = sdof(omega, 0.0);
    let mut errors = Vec::new();
    for steps_per_period in [50usize, 100, 200, 400] {
        let dt = 1.0 / steps_per_period as f64;
        let n = (t_end / dt).round() as usize;
        let u = free_history(
            ops(&mats),
            Scheme::AverageAcceleration,
            dt,
            n,
            &[1.0],
            &[0.0],
            0,
        );
        let e = u
            .iter()
            .enumerate()
            .map(|(k, x)| (x - (omega * k as f64 * dt).cos()).abs())
            .fold(0.0, f64::max);
        // Phase lag after t_end: w t (w dt)^2/12, plus 5% for the O((w dt)^4) term.
        let bound = 1.05 * omega * t_end * (omega * dt).powi(2) / 12.0;
        eprintln!("average acceleration, dt = T/{steps_per_period}: max error {e:.4e} (bound {bound:.4e})");
        assert!(e < bound, "dt = T/{steps_per_period}: {e} above {bound}");
        errors.push(e);
    }
    for w in errors.windows(2) {
        let slope = (w[0] / w[1]).log2();
        eprintln!("average acceleration: refinement slope {slope:.4}");
        assert!((1.9..=2.1).contains(&slope), "slope {slope}");
    }
}

#[test]
fn hht_algorithmic_damping_matches_the_leading_order_theory() {
    let scheme = Scheme::Hht { alpha: -0.05 };
    let coefficients = scheme.coefficients().unwrap();
    let mats = sdof(1.0, 0.0);
    // Relative size of the next term, from the exact roots of the characteristic
    // polynomial: 0.45% at w dt = 0.1, 1.8% at 0.2 (docs/integrators.md).
    for (w_dt, tolerance) in [(0.1, 0.01), (0.2, 0.03)] {
        let n = 40_000;
        let u = free_history(ops(&mats), scheme, w_dt, n, &[1.0], &[0.0], 0);
        let theta = 2.0 * PI / period_in_steps(&u);
        // Skip 100 steps: the spurious root (|L| ~ 0.05) is gone by then.
        let measured = -log_decay_per_step(&u, 100, n - 1) / theta;
        let theory = coefficients.algorithmic_damping(w_dt);
        eprintln!("HHT alpha = -0.05, w dt = {w_dt}: zeta_num = {measured:.5e}, leading order {theory:.5e}, ratio {:.4}", measured / theory);
        assert!(
            (measured / theory - 1.0).abs() < tolerance,
            "w dt = {w_dt}: {measured} vs {theory}"
        );
    }
}

#[test]
fn generalized_alpha_with_rho_one_is_average_acceleration() {
    let m = sparse(&[&[2.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[0.0, 0.0, 0.5]]);
    let k = sparse(&[
        &[400.0, -200.0, 0.0],
        &[-200.0, 300.0, -100.0],
        &[0.0, -100.0, 100.0],
    ]);
    let c = sparse(&[&[0.8, -0.2, 0.0], &[-0.2, 0.5, -0.1], &[0.0, -0.1, 0.15]]);
    let ops = Operators {
        m: m.as_ref(),
        c: Some(c.as_ref()),
        k: k.as_ref(),
    };
    let run = |scheme| {
        let mut out = Vec::new();
        integrate(
            ops,
            scheme,
            0.01,
            500,
            &[0.01, 0.0, -0.01],
            &[0.0, 0.2, 0.0],
            &mut |t, f| f[2] = (5.0 * t).sin(),
            &mut |_, _, s| out.extend_from_slice(&s.u),
        )
        .unwrap();
        out
    };
    let (aa, ga) = (
        run(Scheme::AverageAcceleration),
        run(Scheme::GeneralizedAlpha { rho_inf: 1.0 }),
    );
    let scale = aa.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    let diff = aa
        .iter()
        .zip(&ga)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "generalised-alpha rho_inf = 1 vs average acceleration: max |du| / max |u| = {:.3e}",
        diff / scale
    );
    assert!(diff < 1e-12 * scale, "{diff} vs scale {scale}");
}

#[test]
fn stiff_mode_is_damped_per_step_by_rho_inf() {
    let w_dt = 100.0;
    let mats = sdof(1.0, 0.0);
    let schemes = [
        Scheme::AverageAcceleration,
        Scheme::Hht { alpha: -0.05 },
        Scheme::Hht { alpha: -1.0 / 3.0 },
        Scheme::GeneralizedAlpha { rho_inf: 0.5 },
        Scheme::GeneralizedAlpha { rho_inf: 0.8 },
    ];
    for scheme in schemes {
        let u = free_history(ops(&mats), scheme, w_dt, 101, &[1.0], &[0.0], 0);
        // From step 60 on, the spurious root's share is below (0.74/0.83)^60 ~ 1e-3.
        let ratio = log_decay_per_step(&u, 60, 100).exp();
        let rho_inf = scheme.rho_infinity();
        eprintln!(
            "{scheme:?}, w dt = 100: per-step amplitude ratio {ratio:.4} (rho_inf {rho_inf:.4})"
        );
        // At finite w dt the double root at -rho_inf splits by O(1/(w dt)); the
        // characteristic polynomial gives 0.537 for rho_inf = 0.5, 0.835 for 0.8.
        assert!(
            (ratio - rho_inf).abs() < 0.05,
            "{scheme:?}: {ratio} vs {rho_inf}"
        );
        if scheme == Scheme::AverageAcceleration {
            assert!(
                (ratio - 1.0).abs() < 1e-9,
                "average acceleration damped a stiff mode: {ratio}"
            );
        }
    }
}

#[test]
fn scheme_coefficients_follow_the_papers() {
    let aa = Scheme::AverageAcceleration.coefficients().unwrap();
    assert_eq!(
        aa,
        Coefficients {
            alpha_m: 0.0,
            alpha_f: 0.0,
            beta: 0.25,
            gamma: 0.5
        }
    );
    assert_eq!(Scheme::Hht { alpha: 0.0 }.coefficients().unwrap(), aa);
    let ga1 = Scheme::GeneralizedAlpha { rho_inf: 1.0 }
        .coefficients()
        .unwrap();
    assert_eq!((ga1.beta, ga1.gamma), (0.25, 0.5));
    // HHT-alpha = -1/3 and generalised-alpha rho_inf = 1/2 coincide (alpha_m = 0).
    let hht = Scheme::Hht { alpha: -1.0 / 3.0 }.coefficients().unwrap();
    let ga = Scheme::GeneralizedAlpha { rho_inf: 0.5 }
        .coefficients()
        .unwrap();
    for (x, y) in [
        (hht.alpha_m, ga.alpha_m),
        (hht.alpha_f, ga.alpha_f),
        (hht.beta, ga.beta),
        (hht.gamma, ga.gamma),
    ] {
        assert!((x - y).abs() < 1e-15);
    }
    // Leading-order damping formulas of the docs.
    let w = 0.3;
    let alpha: f64 = -0.05;
    let hht = Scheme::Hht { alpha }.coefficients().unwrap();
    assert!(
        (hht.algorithmic_damping(w) - (-alpha * (1.0 + alpha).powi(2) * w.powi(3) / 8.0)).abs()
            < 1e-15
    );
    let rho: f64 = 0.6;
    let ga = Scheme::GeneralizedAlpha { rho_inf: rho }
        .coefficients()
        .unwrap();
    let expected = 0.5 * ((1.0 - rho) / (1.0 + rho)).powi(3) * w.powi(3);
    assert!((ga.algorithmic_damping(w) - expected).abs() < 1e-15);
    assert!((aa.period_elongation(w) - w * w / 12.0).abs() < 1e-15);
    assert_eq!(aa.algorithmic_damping(w), 0.0);
    let model = crate::model::Integrator::Hht { alpha: -0.1 };
    assert_eq!(Scheme::from(model), Scheme::Hht { alpha: -0.1 });
}
