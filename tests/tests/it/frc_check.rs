//! A forced response curve against long time integrations of the same model, shared by
//! the lumped and the spring tests of `frc`: at 20 frequencies up and down through the
//! fold each steady amplitude (300 periods, the last 20 read off as the first harmonic)
//! within 1 % of a stable branch, and the jumps of a slow stepped sweep (0.1 % steps near
//! the jump, each run continued from the last state) within 0.5 % of the curve's.

use coil_ident::forced::commands::frc_of;
use coil_ident::forced::frc::FrcSettings;
use coil_ident::forced::model::ForcedModel;
use coil_ident::forced::simulate::{self, Grid};
use std::f64::consts::TAU;

/// Steady first-harmonic displacement amplitude of `model` under `amplitude cos(2 pi f t)`
/// from `state` (mode 1's; the others start at rest), integrated over 300 periods; the end
/// state.
pub(crate) fn steady(
    model: &ForcedModel,
    amplitude: f64,
    f: f64,
    state: (f64, f64),
) -> (f64, (f64, f64)) {
    let per = 128usize;
    let periods = 300usize;
    let dt = 1.0 / (f * per as f64);
    let n = per * periods;
    let u: Vec<f64> = (0..=n)
        .map(|i| amplitude * (TAU * f * i as f64 * dt).cos())
        .collect();
    let w = model.oscillator.natural_frequency_rad_s;
    let grid = Grid {
        dt,
        substeps: simulate::substeps(&model.oscillator, dt, 0.02, 0.02 * w),
    };
    let m = simulate::motion(&model.oscillator, grid, &u, state, 1e6).unwrap();
    let last = &m.z[n - 20 * per..n];
    let (mut c, mut s) = (0.0, 0.0);
    for (j, zj) in last.iter().enumerate() {
        let phase = TAU * j as f64 / per as f64;
        c += zj * phase.cos();
        s += zj * phase.sin();
    }
    let norm = 2.0 / last.len() as f64;
    ((c * norm).hypot(s * norm), (m.z[n], m.v[n]))
}

/// The forced response curve of `model` under `amplitude` from `from_hz` to `to_hz`
/// against long time integrations of the same model at 20 frequencies up and down through
/// the fold: every steady amplitude within 1 % of a stable branch, and the jumps of a slow
/// stepped sweep within 0.5 % of the curve's. Returns the worst branch difference and the
/// jumps (curve, time integration).
pub(crate) fn frc_against_time_integration(
    model: &ForcedModel,
    amplitude: f64,
    from_hz: f64,
    to_hz: f64,
) -> (f64, [f64; 4]) {
    let settings = FrcSettings {
        amplitude,
        from_hz,
        to_hz,
        points: 400,
        harmonics: 7,
    };
    let result = frc_of(model, &settings).unwrap();
    assert_eq!(result.jumps.len(), 2, "{:?}", result.jumps);
    let (jump_up, jump_down) = (
        result.jumps.iter().copied().fold(f64::INFINITY, f64::min),
        result.jumps.iter().copied().fold(0.0, f64::max),
    );
    let stable_at = |f: f64| -> Vec<f64> {
        result
            .points
            .windows(2)
            .filter(|p| p[0].stable && p[1].stable)
            .filter(|p| (p[0].frequency_hz - f) * (p[1].frequency_hz - f) <= 0.0)
            .map(|p| {
                let s = (f - p[0].frequency_hz) / (p[1].frequency_hz - p[0].frequency_hz);
                p[0].amplitude + s * (p[1].amplitude - p[0].amplitude)
            })
            .collect()
    };
    let (lo, hi) = (0.9 * jump_up, 1.03 * jump_down);
    let freqs: Vec<f64> = (0..20).map(|i| lo + (hi - lo) * i as f64 / 19.0).collect();
    let mut state = (0.0, 0.0);
    let mut worst: f64 = 0.0;
    for sweep in [freqs.clone(), freqs.iter().rev().copied().collect()] {
        for &f in &sweep {
            let (a, end) = steady(model, amplitude, f, state);
            state = end;
            let branches = stable_at(f);
            let err = branches
                .iter()
                .map(|b| ((a - b) / b).abs())
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(err);
            assert!(
                err < 0.01,
                "{f} Hz: time integration {a}, curve {branches:?}"
            );
        }
    }
    // The jumps by a slow stepped sweep (0.1 % steps within 3 % of the curve's jump).
    let jump = |near: f64, up: bool| -> f64 {
        let mut f = if up { 0.9 * jump_up } else { 1.05 * jump_down };
        let mut s = (0.0, 0.0);
        let mut a0 = 0.0;
        loop {
            let (a, end) = steady(model, amplitude, f, s);
            let close = (f - near).abs() < 0.03 * near;
            if close && (if up { a < 0.7 * a0 } else { a > 1.3 * a0 }) {
                let back = if up { f / 1.001 } else { f * 1.001 };
                return 0.5 * (f + back);
            }
            assert!(
                if up { f < 1.05 * near } else { f > 0.95 * near },
                "no jump near {near} Hz"
            );
            a0 = a;
            s = end;
            let step = if close { 0.001 * f } else { 0.01 * near };
            f += if up { step } else { -step };
        }
    };
    let down_jump_td = jump(jump_down, true);
    let up_jump_td = jump(jump_up, false);
    assert!(((down_jump_td - jump_down) / jump_down).abs() < 0.005);
    assert!(((up_jump_td - jump_up) / jump_up).abs() < 0.005);
    (worst, [jump_down, jump_up, down_jump_td, up_jump_td])
}
