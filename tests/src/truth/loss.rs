//! Generated cases for the damping the records show, and for laws outside the
//! catalogue; built on [`crate::truth`]'s rigs, truth model, noise and sensor models.
//!
//! - [`loss_cases`]: dry friction that sticks after 8, 10, 12 and 17 cycles (position
//!   and acceleration records); velocity-squared drag carrying 60-95 % of the loss at
//!   the start beside a hardening or a softening backbone of 0.5-3 %; drag with a
//!   drifting offset; drag with a second slow mode in the record ([`slow_mode_cases`]);
//!   friction and drag together; null cases with a slow mode and with a drift. Each
//!   must be named with all its parts (`TruthCase::causes`), the nulls `none`.
//! - [`outside_cases`]: a backlash gap, a bilinear spring, hysteretic Bouc-Wen
//!   friction, a second mode close to the axial one and a clipped sensor
//!   ([`crate::truth::Anomaly`], [`crate::truth::ExtraMode`]); no catalogue effect is
//!   hidden, so any cause named is a wrong one unless its misfit is reported.
//!
//! Drag share: `quadratic_case`'s ratio `r` is the drag's equivalent viscous
//! coefficient at the initial amplitude over the linear one, so the drag carries
//! `r / (1 + r)` of the loss at the start (1.5: 60 %, 3: 75 %, 9: 90 %, 19: 95 %).

use crate::truth::{
    cubic_shift_case, friction_case, friction_stop_case, linear_case, position, quadratic_case,
    rayleigh_period_s, recorded_by, with, Anomaly, ExtraMode, Recording, Rig, Test, TruthCase,
    PAPER_RIG, RIG_G1, RIG_G2, RIG_G3, RIG_G4,
};

fn test(
    sample_rate_hz: f64,
    noise_fraction: f64,
    damping_ratio: f64,
    amplitude_mm: f64,
    seed: u64,
) -> Test {
    Test {
        sample_rate_hz,
        record_s: 0.0,
        noise_fraction,
        damping_ratio,
        amplitude_m: amplitude_mm * 1e-3,
        nominal_mass_ratio: if seed % 2 == 0 { 1.1 } else { 0.9 },
        seed,
    }
}

/// `t` lasting `n` linear periods of `rig`.
fn lasting(rig: Rig, n: f64, mut t: Test) -> Test {
    t.record_s = n * rayleigh_period_s(&linear_case("", rig, t));
    t
}

/// Drag of share `ratio` (module docs) beside a backbone shift `shift` at the initial
/// amplitude, horizontal (`gravity` 0) or hanging.
fn drag_with_backbone(
    name: &str,
    rig: Rig,
    t: Test,
    ratio: f64,
    gravity: f64,
    shift: f64,
) -> TruthCase {
    with(
        quadratic_case(name, rig, t, ratio),
        cubic_shift_case(name, rig, t, gravity, shift),
    )
}

/// A position sensor of step `step_mm` with a slow mode `slowness` times slower than
/// the axial one, of `fraction` of the record's peak.
fn with_slow_mode(step_mm: f64, slowness: f64, fraction: f64) -> Recording {
    Recording {
        extra_mode: Some(ExtraMode {
            frequency_ratio: 1.0 / slowness,
            amplitude_fraction: fraction,
            damping_ratio: 0.01,
            phase_rad: 0.7,
        }),
        ..position(step_mm)
    }
}

/// `friction_stop_case`'s cycles for a record that holds 8 full cycles before the
/// weight sticks: the law's count runs to `A = 0`, and the weight sticks a little
/// earlier, once the swing falls within the friction's dead band `F/k`; the reader
/// needs 8 counted cycles.
const STICKS_8: f64 = 8.8;

/// The damping classes of the module docs.
pub fn loss_cases() -> Vec<TruthCase> {
    let mut cases = Vec::new();
    // Friction that sticks: 8, 10, 12 and 17 cycles, both kinds of record.
    let stop = |name: &str, rig, t, cycles, recording: Option<Recording>| {
        let case = friction_stop_case(name, rig, t, cycles);
        match recording {
            Some(r) => recorded_by(case, r),
            None => case,
        }
    };
    let t = test(500.0, 0.005, 0.001, 3.0, 801);
    cases.push(stop("friction_sticks_8_g1", RIG_G1, t, STICKS_8, None));
    let t = test(200.0, 0.005, 0.0008, 4.0, 802);
    cases.push(stop(
        "friction_sticks_8_position",
        RIG_G4,
        t,
        STICKS_8,
        Some(position(0.01)),
    ));
    let t = test(500.0, 0.005, 0.0015, 2.0, 803);
    cases.push(stop(
        "friction_sticks_10_position",
        RIG_G2,
        t,
        10.0,
        Some(position(0.01)),
    ));
    let t = test(400.0, 0.005, 0.001, 3.0, 804);
    cases.push(stop("friction_sticks_12_g3", RIG_G3, t, 12.0, None));
    let t = test(1000.0, 0.005, 0.0015, 3.0, 805);
    cases.push(stop(
        "friction_sticks_17_position",
        PAPER_RIG,
        t,
        17.0,
        Some(position(0.01)),
    ));

    // Drag beside a mild backbone.
    let t = lasting(RIG_G2, 40.0, test(500.0, 0.005, 0.001, 3.0, 811));
    cases.push(drag_with_backbone(
        "drag_hard_1pc_g2",
        RIG_G2,
        t,
        3.0,
        0.0,
        0.01,
    ));
    let t = lasting(RIG_G4, 50.0, test(200.0, 0.005, 0.001, 4.0, 812));
    cases.push(recorded_by(
        drag_with_backbone("drag_hard_3pc_position", RIG_G4, t, 9.0, 0.0, 0.03),
        position(0.01),
    ));
    let t = lasting(RIG_G1, 40.0, test(500.0, 0.005, 0.0015, 3.0, 813));
    cases.push(drag_with_backbone(
        "drag_soft_2pc_g1",
        RIG_G1,
        t,
        1.5,
        0.0,
        -0.02,
    ));
    let t = lasting(RIG_G3, 60.0, test(400.0, 0.005, 0.0008, 4.0, 814));
    cases.push(recorded_by(
        drag_with_backbone("drag_soft_0p5pc_hanging", RIG_G3, t, 19.0, 9.81, -0.005),
        position(0.01),
    ));

    // Drag with a second slow mode, and with a drifting offset in the record.
    cases.extend(slow_mode_cases());
    let t = lasting(RIG_G4, 40.0, test(200.0, 0.005, 0.001, 4.0, 822));
    cases.push(recorded_by(
        quadratic_case("drag_drift_position", RIG_G4, t, 3.0),
        Recording {
            offset_fraction: 0.2,
            drift_fraction: 0.5,
            ..position(0.01)
        },
    ));
    // Friction and drag together.
    // Friction and drag together, each well above the viscous loss (a light viscous
    // part, zeta 0.0005): together they mimic a viscous decay, alone each walks to
    // zero.
    let t = lasting(RIG_G1, 40.0, test(500.0, 0.003, 0.0005, 3.0, 831));
    cases.push(with(
        friction_case("friction_drag_g1", RIG_G1, t, 0.5),
        quadratic_case("friction_drag_g1", RIG_G1, t, 4.0),
    ));
    let t = lasting(RIG_G4, 30.0, test(200.0, 0.003, 0.0005, 4.0, 832));
    cases.push(recorded_by(
        with(
            friction_case("friction_drag_position", RIG_G4, t, 0.5),
            quadratic_case("friction_drag_position", RIG_G4, t, 4.0),
        ),
        position(0.01),
    ));

    // Nulls with the slow component.
    let t = lasting(RIG_G2, 40.0, test(500.0, 0.005, 0.002, 3.0, 841));
    cases.push(recorded_by(
        linear_case("null_slow_mode_position", RIG_G2, t),
        with_slow_mode(0.01, 8.0, 0.3),
    ));
    let t = lasting(RIG_G4, 40.0, test(200.0, 0.005, 0.002, 4.0, 842));
    cases.push(recorded_by(
        linear_case("null_drift_offset_position", RIG_G4, t),
        Recording {
            offset_fraction: 0.2,
            drift_fraction: 0.5,
            ..position(0.01)
        },
    ));
    cases
}

/// Drag with a second slow component in the record: a mode 8 times slower than the axial
/// one at 30 % of a position record's peak, and 6.7 times slower at 5 % of an
/// accelerometer's. The conditioning finds the slow line and every model fits its form
/// beside it (`coil_ident::diagnose::data::slow_line`); part of [`loss_cases`], and
/// alone in the benchmark's `slow` selection.
pub fn slow_mode_cases() -> Vec<TruthCase> {
    let mut cases = Vec::new();
    let t = lasting(RIG_G2, 40.0, test(500.0, 0.005, 0.001, 3.0, 821));
    cases.push(recorded_by(
        quadratic_case("drag_slow_mode_position", RIG_G2, t, 4.0),
        with_slow_mode(0.01, 8.0, 0.3),
    ));
    let t = lasting(RIG_G1, 40.0, test(500.0, 0.005, 0.001, 3.0, 823));
    cases.push(recorded_by(
        quadratic_case("drag_slow_mode_accel", RIG_G1, t, 3.0),
        Recording {
            extra_mode: Some(ExtraMode {
                frequency_ratio: 0.15,
                amplitude_fraction: 0.05,
                damping_ratio: 0.01,
                phase_rad: 0.3,
            }),
            ..Recording::default()
        },
    ));

    cases
}

/// `case` with the anomaly `anomaly`.
fn anomalous(mut case: TruthCase, anomaly: Anomaly) -> TruthCase {
    case.anomaly = anomaly;
    case
}

/// The out-of-catalogue cases of the module docs (no catalogue effect hidden).
pub fn outside_cases() -> Vec<TruthCase> {
    let mut cases = Vec::new();
    let t = lasting(RIG_G2, 40.0, test(500.0, 0.005, 0.002, 3.0, 901));
    cases.push(anomalous(
        linear_case("backlash_g2", RIG_G2, t),
        Anomaly::Backlash {
            gap_m: 1.5e-3,
            stiffness_ratio: 0.3,
        },
    ));
    let t = lasting(RIG_G4, 40.0, test(200.0, 0.005, 0.002, 4.0, 902));
    cases.push(recorded_by(
        anomalous(
            linear_case("backlash_position", RIG_G4, t),
            Anomaly::Backlash {
                gap_m: 1.0e-3,
                stiffness_ratio: 1.0,
            },
        ),
        position(0.01),
    ));
    let t = lasting(RIG_G1, 40.0, test(500.0, 0.005, 0.002, 3.0, 903));
    cases.push(anomalous(
        linear_case("bilinear_g1", RIG_G1, t),
        Anomaly::Bilinear {
            stiffness_ratio: 0.15,
        },
    ));
    let t = lasting(RIG_G3, 40.0, test(400.0, 0.005, 0.002, 3.0, 904));
    cases.push(anomalous(
        linear_case("bilinear_g3", RIG_G3, t),
        Anomaly::Bilinear {
            stiffness_ratio: 0.5,
        },
    ));
    // Bouc-Wen friction of a force that would stop a Coulomb decay in about 30 cycles,
    // yielding over a third and over the whole of the initial amplitude.
    for (name, rig, yield_share, seed) in [
        ("bouc_wen_g2", RIG_G2, 0.3, 905),
        ("bouc_wen_g4", RIG_G4, 1.0, 906),
    ] {
        let t = lasting(rig, 40.0, test(500.0, 0.005, 0.002, 3.0, seed));
        let case = linear_case(name, rig, t);
        let force = 3e-3 * case.linear_stiffness_n_m() / (4.0 * 30.0);
        cases.push(anomalous(
            case,
            Anomaly::BoucWen {
                force_n: force,
                yield_m: yield_share * 3e-3,
            },
        ));
    }
    // A second mode 6 % and 12 % above the axial one (not the weight's rotation: no
    // torsion is free).
    for (name, rig, ratio, seed) in [
        ("close_mode_g2", RIG_G2, 1.06, 907),
        ("close_mode_g1", RIG_G1, 1.12, 908),
    ] {
        let t = lasting(rig, 40.0, test(500.0, 0.005, 0.002, 3.0, seed));
        cases.push(recorded_by(
            linear_case(name, rig, t),
            Recording {
                extra_mode: Some(ExtraMode {
                    frequency_ratio: ratio,
                    amplitude_fraction: 0.3,
                    damping_ratio: 0.003,
                    phase_rad: 1.1,
                }),
                ..Recording::default()
            },
        ));
    }
    // A sensor that saturates at 70 % and at 90 % of the peak.
    for (name, rig, clip, seed) in [
        ("clipped_70_g3", RIG_G3, 0.7, 909),
        ("clipped_90_g2", RIG_G2, 0.9, 910),
    ] {
        let t = lasting(rig, 40.0, test(500.0, 0.005, 0.002, 3.0, seed));
        cases.push(recorded_by(
            linear_case(name, rig, t),
            Recording {
                clip_fraction: Some(clip),
                ..Recording::default()
            },
        ));
    }
    cases
}

/// The name of the out-of-catalogue law of an [`outside_cases`] case.
pub fn outside_law(case: &TruthCase) -> &'static str {
    match (case.anomaly, &case.recording) {
        (Anomaly::None, r) if r.clip_fraction.is_some() => "clipped_sensor",
        (Anomaly::None, r) if r.extra_mode.is_some() => "close_second_mode",
        (a, _) => a.name(),
    }
}
