//! The catalogue of truth cases: the rigs, and the standard, extended, hard and fast
//! cases the tests and benchmarks run.

use super::model::*;
use std::f64::consts::{PI, TAU};

/// The handbook modulus every case.json gives (the truths are 3-7 % below it).
pub const NOMINAL_YOUNGS_MODULUS_MPA: f64 = 206_000.0;

/// A spring with its true modulus and weight (the catalogue's building block).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rig {
    pub(crate) spring: Helix,
    pub(crate) youngs_modulus_mpa: f64,
    pub(crate) mass_kg: f64,
}

pub(crate) const PAPER_RIG: Rig = Rig {
    spring: Helix::PAPER,
    youngs_modulus_mpa: 194_000.0,
    mass_kg: 5.24,
};
pub(crate) const RIG_G1: Rig = Rig {
    spring: Helix {
        active_coils: 12.0,
        mean_diameter_mm: 26.0,
        wire_diameter_mm: 3.2,
        pitch_mm: 6.8,
    },
    youngs_modulus_mpa: 196_000.0,
    mass_kg: 5.75,
};
pub(crate) const RIG_G2: Rig = Rig {
    spring: Helix {
        active_coils: 9.0,
        mean_diameter_mm: 18.0,
        wire_diameter_mm: 2.2,
        pitch_mm: 4.6,
    },
    youngs_modulus_mpa: 200_000.0,
    mass_kg: 2.8,
};
pub(crate) const RIG_G3: Rig = Rig {
    spring: Helix {
        active_coils: 8.0,
        mean_diameter_mm: 30.0,
        wire_diameter_mm: 4.0,
        pitch_mm: 8.5,
    },
    youngs_modulus_mpa: 192_000.0,
    mass_kg: 5.4,
};
pub(crate) const RIG_G4: Rig = Rig {
    spring: Helix {
        active_coils: 16.0,
        mean_diameter_mm: 22.0,
        wire_diameter_mm: 2.8,
        pitch_mm: 5.6,
    },
    youngs_modulus_mpa: 198_000.0,
    mass_kg: 6.8,
};
/// A steeper helix (pitch angle 8 degrees): a stronger axial-torsional coupling.
pub(crate) const RIG_G5: Rig = Rig {
    spring: Helix {
        active_coils: 10.0,
        mean_diameter_mm: 20.0,
        wire_diameter_mm: 2.5,
        pitch_mm: 9.0,
    },
    youngs_modulus_mpa: 197_000.0,
    mass_kg: 4.0,
};

/// Measurement settings of one catalogue entry.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Test {
    pub(crate) sample_rate_hz: f64,
    pub(crate) record_s: f64,
    pub(crate) noise_fraction: f64,
    pub(crate) damping_ratio: f64,
    /// Initial amplitude of the axial motion (m).
    pub(crate) amplitude_m: f64,
    /// Nominal mass over the true one (0.9 or 1.1).
    pub(crate) nominal_mass_ratio: f64,
    pub(crate) seed: u64,
}

/// A linear case (no effect yet) of `rig` under `test`.
pub(crate) fn linear_case(name: &str, rig: Rig, test: Test) -> TruthCase {
    let mut case = TruthCase {
        name: name.to_string(),
        spring: rig.spring,
        youngs_modulus_mpa: rig.youngs_modulus_mpa,
        nominal_youngs_modulus_mpa: NOMINAL_YOUNGS_MODULUS_MPA,
        poisson_ratio: 0.3,
        density_kg_m3: 7850.0,
        mass_kg: rig.mass_kg,
        nominal_mass_kg: (rig.mass_kg * test.nominal_mass_ratio * 1e3).round() / 1e3,
        gravity_m_s2: 9.81,
        damping_ratio: test.damping_ratio,
        effect: Effect::None,
        segments: 16,
        impulse_velocity_m_s: 0.0,
        rotation_kick_rad_s: 0.0,
        sample_rate_hz: test.sample_rate_hz,
        record_s: test.record_s,
        noise_fraction: test.noise_fraction,
        static_noise_fraction: 0.003,
        static_points: 41,
        seed: test.seed,
        also: Vec::new(),
        recording: Recording::default(),
        anomaly: Anomaly::None,
    };
    case.impulse_velocity_m_s = test.amplitude_m * TAU / rayleigh_period_s(&case);
    case
}

/// Friction that makes the amplitude at the record's end `fraction` smaller than the
/// linear decay alone. Per cycle `dA/dn = -delta A - 4F/k` (delta = 2 pi zeta) gives
/// `A(n) = (A0 + c) e^(-delta n) - c`, `c = 4F / (k delta)`, so the loss against the
/// linear decay after n cycles is `c (e^(delta n) - 1) / A0`.
pub(crate) fn friction_case(name: &str, rig: Rig, test: Test, fraction: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    let cycles = test.record_s / rayleigh_period_s(&case);
    let delta = TAU * test.damping_ratio;
    let growth = (delta * cycles).exp_m1() / delta;
    let force = fraction * test.amplitude_m * case.linear_stiffness_n_m() / (4.0 * growth);
    case.effect = Effect::CoulombFriction {
        friction_force_n: round_to(force, 4),
    };
    case
}

/// Velocity-squared drag whose equivalent viscous coefficient at the initial amplitude,
/// `8 c2 w A / (3 pi)`, is `ratio` times the linear one `2 zeta m w`.
pub(crate) fn quadratic_case(name: &str, rig: Rig, test: Test, ratio: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    let c2 = ratio * 3.0 * PI * test.damping_ratio * case.mass_kg / (4.0 * test.amplitude_m);
    case.effect = Effect::QuadraticDamping {
        quadratic_damping_n_s2_m2: round_to(c2, 4),
    };
    case
}

/// A cubic spring with `k3 x0^2 = eps k_t` at the preload x0, `k_t = k + 3 k3 x0^2` the
/// tangent stiffness there. About the preload the restoring force is
/// `k_t y + 3 k3 x0 y^2 + k3 y^3`, whose backbone (Nayfeh and Mook, Nonlinear
/// Oscillations, 4.1) is `dw/w = (A/x0)^2 (3 eps/8 - 15 eps^2/4)`: hardening up to
/// eps = 0.1, softening beyond. Without gravity, eps is `k3 A^2 / k` at the initial
/// amplitude A and the backbone `dw/w = 3 k3 A^2 / (8 k)`.
fn cubic_case(name: &str, rig: Rig, test: Test, gravity_m_s2: f64, epsilon: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    case.gravity_m_s2 = gravity_m_s2;
    let k = case.linear_stiffness_n_m();
    let k3 = if case.gravity_m_s2 > 0.0 {
        // k3 x0^2 = b k with b = eps / (1 - 3 eps), and k x0 (1 + b) = m g.
        let b = epsilon / (1.0 - 3.0 * epsilon);
        let x0 = case.mass_kg * case.gravity_m_s2 / (k * (1.0 + b));
        b * k / (x0 * x0)
    } else {
        epsilon * k / test.amplitude_m.powi(2)
    };
    case.effect = Effect::CubicStiffness {
        cubic_stiffness_n_m3: round_to(k3, 4),
    };
    case
}

/// A free-turning weight whose uncoupled torsional frequency `sqrt(K_tt / (J + J_s/3))` is
/// `1 + detuning` times the axial one `sqrt(K_zz / (m + m_s/3))`, K = C^-1.
fn coupling_case(name: &str, rig: Rig, test: Test, detuning: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    let (kzz, _, ktt) = case.compliance().stiffness();
    let m_s = case.spring_mass_kg();
    let r = 0.5e-3 * case.spring.mean_diameter_mm;
    let w_axial_sq = kzz / (case.mass_kg + m_s / 3.0);
    let j = ktt / (w_axial_sq * (1.0 + detuning).powi(2)) - m_s * r * r / 3.0;
    case.effect = Effect::AxialTorsionalCoupling {
        rotary_inertia_kg_m2: round_to(j, 4),
    };
    case
}

/// `x` to `digits` significant digits (parameters read well in truth.json).
fn round_to(x: f64, digits: i32) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// The catalogue: every effect at two or more magnitudes, and null cases, on springs other
/// than the paper's (and the paper's), with varied noise, sampling and length.
pub fn standard_cases() -> Vec<TruthCase> {
    let test = |sample_rate_hz, record_s, noise_fraction, damping_ratio, amplitude_mm, seed| Test {
        sample_rate_hz,
        record_s,
        noise_fraction,
        damping_ratio,
        amplitude_m: amplitude_mm * 1e-3,
        nominal_mass_ratio: if seed % 2 == 0 { 1.1 } else { 0.9 },
        seed,
    };
    vec![
        linear_case("null_g4", RIG_G4, test(500.0, 20.0, 0.01, 0.002, 4.0, 101)),
        linear_case(
            "null_paper",
            PAPER_RIG,
            test(1000.0, 25.0, 0.005, 0.00175, 3.0, 102),
        ),
        linear_case(
            "null_g2",
            RIG_G2,
            test(2000.0, 30.0, 0.02, 0.0025, 2.0, 103),
        ),
        linear_case(
            "null_g3",
            RIG_G3,
            test(500.0, 40.0, 0.002, 0.0015, 2.5, 104),
        ),
        friction_case(
            "friction_g1",
            RIG_G1,
            test(1000.0, 20.0, 0.005, 0.001, 3.0, 201),
            0.4,
        ),
        friction_case(
            "friction_g4_strong",
            RIG_G4,
            test(800.0, 30.0, 0.01, 0.0008, 4.0, 202),
            0.6,
        ),
        // Friction that stops the weight within the record (it sticks for the last
        // third): the decay ends in a dead band, not in noise.
        friction_case(
            "friction_paper_sticks",
            PAPER_RIG,
            test(1000.0, 30.0, 0.005, 0.00175, 3.0, 204),
            1.6,
        ),
        friction_case(
            "friction_g2_weak",
            RIG_G2,
            test(1250.0, 25.0, 0.003, 0.0012, 2.0, 203),
            0.25,
        ),
        quadratic_case(
            "quadratic_g3",
            RIG_G3,
            test(500.0, 25.0, 0.005, 0.0015, 3.0, 301),
            1.0,
        ),
        quadratic_case(
            "quadratic_g1_weak",
            RIG_G1,
            test(2000.0, 35.0, 0.002, 0.002, 4.0, 302),
            0.5,
        ),
        quadratic_case(
            "quadratic_paper_strong",
            PAPER_RIG,
            test(800.0, 30.0, 0.01, 0.00175, 3.0, 303),
            2.0,
        ),
        cubic_case(
            "cubic_g2",
            RIG_G2,
            test(1000.0, 20.0, 0.003, 0.0015, 5.0, 401),
            9.81,
            0.05,
        ),
        cubic_case(
            "cubic_g3_strong",
            RIG_G3,
            test(800.0, 30.0, 0.01, 0.0015, 2.5, 402),
            9.81,
            0.16,
        ),
        // A horizontal rig (no preload): the plain backbone 3 k3 A^2 / (8 k).
        cubic_case(
            "cubic_g1_horizontal",
            RIG_G1,
            test(1000.0, 25.0, 0.005, 0.0015, 3.0, 403),
            0.0,
            0.016,
        ),
        coupling_case(
            "coupling_g5",
            RIG_G5,
            test(1000.0, 25.0, 0.005, 0.002, 3.0, 501),
            0.03,
        ),
        coupling_case(
            "coupling_g5_far",
            RIG_G5,
            test(2000.0, 30.0, 0.01, 0.002, 3.0, 502),
            0.09,
        ),
        coupling_case(
            "coupling_paper",
            PAPER_RIG,
            test(500.0, 40.0, 0.002, 0.00175, 3.0, 503),
            0.04,
        ),
    ]
}

/// The cases shipped under `cases/measured/` (one per effect and one null).
pub const SHIPPED: [&str; 5] = [
    "null_g4",
    "friction_g1",
    "quadratic_g3",
    "cubic_g2",
    "coupling_g5",
];

/// A cubic spring (either sign) whose backbone shift at the initial amplitude
/// ([`backbone_shift`]) is `shift`: without gravity `k3 = 8 k shift / (3 A^2)`; with the
/// preload, `eps` of [`cubic_case`] by bisection on [-0.3, 0.05] (the shift rises with
/// eps there).
pub(crate) fn cubic_shift_case(
    name: &str,
    rig: Rig,
    test: Test,
    gravity_m_s2: f64,
    shift: f64,
) -> TruthCase {
    if gravity_m_s2 == 0.0 {
        let mut case = linear_case(name, rig, test);
        case.gravity_m_s2 = 0.0;
        let k3 = 8.0 * case.linear_stiffness_n_m() * shift / (3.0 * test.amplitude_m.powi(2));
        case.effect = Effect::CubicStiffness {
            cubic_stiffness_n_m3: round_to(k3, 4),
        };
        return case;
    }
    let (mut lo, mut hi) = (-0.3, 0.05);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if backbone_shift(&cubic_case(name, rig, test, gravity_m_s2, mid)) < shift {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    cubic_case(name, rig, test, gravity_m_s2, 0.5 * (lo + hi))
}

/// `case` with the effect of `other` (built on the same rig and test) acting as well;
/// the rig's orientation (gravity) is `other`'s, which its effect was sized for.
pub(crate) fn with(mut case: TruthCase, other: TruthCase) -> TruthCase {
    case.also.push(other.effect);
    case.gravity_m_s2 = other.gravity_m_s2;
    case
}

/// `case` recorded by `recording`.
pub(crate) fn recorded_by(mut case: TruthCase, recording: Recording) -> TruthCase {
    case.recording = recording;
    case
}

/// A position sensor with steps of `step_mm` (offset 37.5 mm, sign as mounted).
pub(crate) fn position(step_mm: f64) -> Recording {
    Recording {
        sensor: Sensor::Position {
            step_mm,
            offset_mm: 37.5,
            sign: 1.0,
        },
        ..Recording::default()
    }
}

/// The extended cases: records as labs write them and effects as real rigs show them.
/// Softening and hardening at several magnitudes, alone and with each damping effect;
/// two damping effects together; position sensors quantised to 0.1 and 0.01 mm and a
/// vibrometer; band-limited noise, jittered time stamps, offset and drift, a hammer
/// blow left at the start; short records (20-25 cycles at 30 Hz) and long ones (150+
/// cycles); null cases with each imperfection. Expected causes: [`TruthCase::causes`].
pub fn extended_cases() -> Vec<TruthCase> {
    let mut cases = extended_effect_cases();
    cases.extend(extended_recording_cases());
    cases
}

/// A test of the extended cases: the nominal mass 10 % high on even seeds, low on odd.
fn extended_test(
    sample_rate_hz: f64,
    record_s: f64,
    noise_fraction: f64,
    damping_ratio: f64,
    amplitude_mm: f64,
    seed: u64,
) -> Test {
    Test {
        sample_rate_hz,
        record_s,
        noise_fraction,
        damping_ratio,
        amplitude_m: amplitude_mm * 1e-3,
        nominal_mass_ratio: if seed % 2 == 0 { 1.1 } else { 0.9 },
        seed,
    }
}

/// The extended cases of effects: softening and hardening alone, each damping effect
/// with one of them, two damping effects together.
fn extended_effect_cases() -> Vec<TruthCase> {
    let test = extended_test;
    // Softening and hardening alone.
    let t = test(1000.0, 25.0, 0.005, 0.0015, 3.0, 601);
    let soft_g1 = cubic_shift_case("soft_g1_horizontal", RIG_G1, t, 0.0, -0.006);
    let t = test(500.0, 30.0, 0.005, 0.0015, 4.0, 602);
    let soft_paper = cubic_shift_case("soft_paper_strong", PAPER_RIG, t, 9.81, -0.018);
    let t = test(800.0, 25.0, 0.003, 0.0012, 4.0, 603);
    let soft_g4 = cubic_shift_case("soft_g4_weak", RIG_G4, t, 9.81, -0.004);
    let t = test(1000.0, 25.0, 0.005, 0.0015, 3.0, 604);
    let hard_g2 = cubic_shift_case("hard_g2_horizontal", RIG_G2, t, 0.0, 0.01);
    let t = test(1000.0, 25.0, 0.005, 0.0015, 3.0, 605);
    let hard_g3 = cubic_shift_case("hard_g3_horizontal_strong", RIG_G3, t, 0.0, 0.02);

    // Each damping effect with softening or hardening.
    let t = test(1000.0, 25.0, 0.005, 0.001, 3.0, 611);
    let friction_soft_g1 = with(
        friction_case("friction_soft_g1", RIG_G1, t, 0.4),
        cubic_shift_case("", RIG_G1, t, 0.0, -0.01),
    );
    let t = test(500.0, 30.0, 0.005, 0.00175, 4.0, 612);
    let friction_soft_paper = with(
        friction_case("friction_soft_paper", PAPER_RIG, t, 0.5),
        cubic_shift_case("", PAPER_RIG, t, 9.81, -0.008),
    );
    let t = test(500.0, 25.0, 0.005, 0.0015, 3.0, 613);
    let quadratic_soft_g3 = with(
        quadratic_case("quadratic_soft_g3", RIG_G3, t, 1.0),
        cubic_shift_case("", RIG_G3, t, 0.0, -0.01),
    );
    let t = test(200.0, 60.0, 0.005, 0.001, 4.0, 614);
    let quadratic_soft_paper_long = with(
        quadratic_case("quadratic_soft_paper_long", PAPER_RIG, t, 1.0),
        cubic_shift_case("", PAPER_RIG, t, 9.81, -0.012),
    );
    let t = test(1000.0, 25.0, 0.005, 0.0012, 3.0, 615);
    let friction_hard_g2 = with(
        friction_case("friction_hard_g2", RIG_G2, t, 0.4),
        cubic_shift_case("", RIG_G2, t, 0.0, 0.01),
    );
    let t = test(800.0, 25.0, 0.005, 0.0015, 4.0, 616);
    let quadratic_hard_g4 = with(
        quadratic_case("quadratic_hard_g4", RIG_G4, t, 1.0),
        cubic_shift_case("", RIG_G4, t, 0.0, 0.008),
    );

    // Two damping effects together (the viscous one strong).
    let t = test(800.0, 25.0, 0.005, 0.006, 4.0, 621);
    let viscous_friction_g4 = friction_case("viscous_friction_g4", RIG_G4, t, 0.5);
    let t = test(1000.0, 20.0, 0.005, 0.006, 2.0, 622);
    let viscous_quadratic_g2 = quadratic_case("viscous_quadratic_g2", RIG_G2, t, 1.0);
    let t = test(1000.0, 30.0, 0.005, 0.00175, 3.0, 623);
    let friction_quadratic_paper = with(
        friction_case("friction_quadratic_paper", PAPER_RIG, t, 0.4),
        quadratic_case("", PAPER_RIG, t, 1.0),
    );

    vec![
        soft_g1,
        soft_paper,
        soft_g4,
        hard_g2,
        hard_g3,
        friction_soft_g1,
        friction_soft_paper,
        quadratic_soft_g3,
        quadratic_soft_paper_long,
        friction_hard_g2,
        quadratic_hard_g4,
        viscous_friction_g4,
        viscous_quadratic_g2,
        friction_quadratic_paper,
    ]
}

/// The extended cases of recordings: other sensors, imperfections on null cases and on
/// effects, short and long records.
fn extended_recording_cases() -> Vec<TruthCase> {
    let test = extended_test;
    let band = |fc| Recording {
        band_limit_hz: Some(fc),
        ..Recording::default()
    };
    let impulse = Some(Impulse {
        rest_s: 0.3,
        duration_s: 0.004,
    });
    // Other sensors.
    let t = test(100.0, 40.0, 0.002, 0.00175, 4.0, 631);
    let null_position_coarse = recorded_by(
        linear_case("null_position_0p1mm", PAPER_RIG, t),
        position(0.1),
    );
    let t = test(200.0, 30.0, 0.002, 0.0015, 3.0, 632);
    let null_position_fine = recorded_by(
        linear_case("null_position_0p01mm", RIG_G1, t),
        position(0.01),
    );
    let t = test(100.0, 30.0, 0.002, 0.0008, 4.0, 633);
    let friction_position = recorded_by(
        friction_case("friction_position_0p01mm", RIG_G4, t, 0.6),
        position(0.01),
    );
    let t = test(100.0, 40.0, 0.002, 0.00175, 5.0, 634);
    let soft_position = recorded_by(
        cubic_shift_case("soft_position_0p1mm", PAPER_RIG, t, 9.81, -0.015),
        position(0.1),
    );
    let t = test(500.0, 25.0, 0.005, 0.0015, 3.0, 635);
    let quadratic_velocity = recorded_by(
        quadratic_case("quadratic_velocity_g3", RIG_G3, t, 1.0),
        Recording {
            sensor: Sensor::Velocity,
            ..Recording::default()
        },
    );

    // Imperfections, on null cases and on effects.
    let t = test(500.0, 25.0, 0.01, 0.00175, 3.0, 641);
    let null_band = recorded_by(linear_case("null_bandlimited", PAPER_RIG, t), band(15.0));
    let t = test(500.0, 20.0, 0.01, 0.001, 3.0, 642);
    let friction_band = recorded_by(
        friction_case("friction_bandlimited_g1", RIG_G1, t, 0.4),
        band(30.0),
    );
    let jitter = |mut r: Recording| {
        r.jitter_s = 0.001;
        r
    };
    let t = test(100.0, 40.0, 0.002, 0.00175, 4.0, 643);
    let null_jitter = recorded_by(
        linear_case("null_jitter_position", PAPER_RIG, t),
        jitter(position(0.01)),
    );
    let t = test(100.0, 30.0, 0.005, 0.0015, 3.0, 644);
    let quadratic_jitter = recorded_by(
        quadratic_case("quadratic_jitter_g3", RIG_G3, t, 1.0),
        jitter(Recording::default()),
    );
    let drift = |mut r: Recording| {
        r.offset_fraction = 0.05;
        r.drift_fraction = 0.2;
        r
    };
    let t = test(100.0, 40.0, 0.002, 0.00175, 4.0, 645);
    let null_drift = recorded_by(
        linear_case("null_drift_position", PAPER_RIG, t),
        drift(position(0.01)),
    );
    let t = test(500.0, 25.0, 0.005, 0.0015, 3.0, 646);
    let null_drift_accel = recorded_by(
        linear_case("null_drift_accel", RIG_G4, t),
        drift(Recording::default()),
    );
    let t = test(100.0, 40.0, 0.002, 0.00175, 5.0, 647);
    let soft_drift = recorded_by(
        cubic_shift_case("soft_drift_position", PAPER_RIG, t, 9.81, -0.012),
        drift(position(0.01)),
    );
    let hammer = |mut r: Recording| {
        r.impulse = impulse;
        r
    };
    let t = test(1000.0, 25.0, 0.005, 0.00175, 3.0, 648);
    let null_impulse = recorded_by(
        linear_case("null_impulse", PAPER_RIG, t),
        hammer(Recording::default()),
    );
    let t = test(200.0, 30.0, 0.002, 0.0015, 3.0, 649);
    let null_impulse_position = recorded_by(
        linear_case("null_impulse_position", RIG_G1, t),
        hammer(position(0.01)),
    );
    let t = test(1000.0, 25.0, 0.005, 0.001, 3.0, 650);
    let friction_impulse = recorded_by(
        friction_case("friction_impulse_g1", RIG_G1, t, 0.4),
        hammer(Recording::default()),
    );

    // Short records (video at 30 Hz, 24 cycles) and long ones (150+ cycles).
    let t = test(30.0, 5.5, 0.002, 0.00175, 5.0, 661);
    let null_short = recorded_by(linear_case("null_short_30hz", PAPER_RIG, t), position(0.1));
    let t = test(30.0, 5.5, 0.002, 0.00175, 8.0, 662);
    let soft_short = recorded_by(
        cubic_shift_case("soft_short_30hz", PAPER_RIG, t, 9.81, -0.02),
        position(0.1),
    );
    let t = test(200.0, 60.0, 0.002, 0.001, 3.0, 663);
    let null_long = recorded_by(linear_case("null_long", PAPER_RIG, t), position(0.01));
    let t = test(200.0, 50.0, 0.005, 0.0005, 3.0, 664);
    let friction_long = friction_case("friction_long_g4", RIG_G4, t, 0.5);

    vec![
        null_position_coarse,
        null_position_fine,
        friction_position,
        soft_position,
        quadratic_velocity,
        null_band,
        friction_band,
        null_jitter,
        quadratic_jitter,
        null_drift,
        null_drift_accel,
        soft_drift,
        null_impulse,
        null_impulse_position,
        friction_impulse,
        null_short,
        soft_short,
        null_long,
        friction_long,
    ]
}

/// A soft spring for a hanging weight: about 110 mm of static deflection under its
/// 3.2 kg, 1.5 Hz, 160 mm of free travel between the coils.
pub(crate) const RIG_SOFT: Rig = Rig {
    spring: Helix {
        active_coils: 20.0,
        mean_diameter_mm: 30.0,
        wire_diameter_mm: 2.0,
        pitch_mm: 10.0,
    },
    youngs_modulus_mpa: 197_000.0,
    mass_kg: 3.2,
};

/// Friction that stops the decay after about `cycles` cycles. Per cycle
/// `dA/dn = -delta A - 4F/k` (friction_case's law) reaches `A = 0` at
/// `n = ln(1 + A0 / c) / delta`, `c = 4F / (k delta)`; so `c = A0 / (e^(delta n) - 1)`
/// and `F = c k delta / 4`, `n` counted from the start of the simulation. The record runs on for a third of that time while the weight
/// rests in its dead band.
pub(crate) fn friction_stop_case(name: &str, rig: Rig, mut test: Test, cycles: f64) -> TruthCase {
    let probe = linear_case(name, rig, test);
    test.record_s = 1.35 * cycles * rayleigh_period_s(&probe);
    let mut case = linear_case(name, rig, test);
    // The record starts after `generate`'s random lead (its seed's first number), so the
    // weight runs that many more cycles before it stops.
    let lead_s = 0.2 + Rng::new(test.seed).uniform();
    let cycles = cycles + lead_s / rayleigh_period_s(&case);
    let delta = TAU * test.damping_ratio;
    let c = test.amplitude_m / (delta * cycles).exp_m1();
    let force = c * case.linear_stiffness_n_m() * delta / 4.0;
    case.effect = Effect::CoulombFriction {
        friction_force_n: round_to(force, 4),
    };
    case
}

/// Records from rigs outside the catalogue, the ones a new user brings: friction decays
/// that stop after 12 to 20 cycles, and a null decay of 10 cycles (the shortest records
/// the reader accepts are 8 cycles); softening decays of large amplitude whose frequency
/// sweeps 10 to 15 % over 130 cycles (a line spread over many spectral bins), and one
/// that sweeps 21 % (it starts beyond the amplitude where the tangent stiffness
/// vanishes, as a pendulum released past 90 degrees does); a hardening decay sweeping
/// 19 % the other way; a weight
/// hanging on a soft spring with 110 mm of static deflection, with each effect and
/// without. Expected causes: [`TruthCase::causes`]; the measured sweep of each softening
/// case is checked by the `truth` test.
pub fn hard_cases() -> Vec<TruthCase> {
    let test = |sample_rate_hz, record_s, noise_fraction, damping_ratio, amplitude_mm, seed| Test {
        sample_rate_hz,
        record_s,
        noise_fraction,
        damping_ratio,
        amplitude_m: amplitude_mm * 1e-3,
        nominal_mass_ratio: if seed % 2 == 0 { 1.1 } else { 0.9 },
        seed,
    };
    // Short records: friction ends them.
    let t = test(500.0, 0.0, 0.005, 0.001, 3.0, 701);
    let stop_g1 = friction_stop_case("friction_stops_12_g1", RIG_G1, t, 12.0);
    let t = test(1000.0, 0.0, 0.005, 0.0015, 3.0, 702);
    let stop_paper = friction_stop_case("friction_stops_18_paper", PAPER_RIG, t, 18.0);
    let t = test(200.0, 0.0, 0.005, 0.0008, 4.0, 703);
    let stop_g4 = recorded_by(
        friction_stop_case("friction_stops_16_position", RIG_G4, t, 16.0),
        position(0.01),
    );
    // `t` lasting `n` linear periods of `rig`.
    let lasting = |rig: Rig, n: f64, mut t: Test| {
        t.record_s = n * rayleigh_period_s(&linear_case("", rig, t));
        t
    };
    let t = lasting(RIG_G2, 10.0, test(500.0, 1.0, 0.005, 0.002, 2.0, 704));
    let null_10 = linear_case("null_10_cycles_g2", RIG_G2, t);

    // Large-amplitude softening: the frequency sweeps 10-15 % from start to end.
    let t = lasting(RIG_G1, 140.0, test(500.0, 0.0, 0.003, 0.002, 6.0, 711));
    let sweep_g1 = cubic_shift_case("soft_sweep_g1_horizontal", RIG_G1, t, 0.0, -0.1);
    let t = lasting(RIG_G3, 140.0, test(400.0, 0.0, 0.003, 0.0025, 5.0, 712));
    let sweep_g3 = cubic_shift_case("soft_sweep_g3_horizontal", RIG_G3, t, 0.0, -0.105);
    // Beyond the tangent-stiffness limit `|k3| A^2 < k / 3` at the start (0.15 of
    // frequency shift is `|k3| A^2 = 0.4 k`), inside the bounded-motion one (`k`); and
    // a hardening spring sweeping the other way.
    let sweep_strong = cubic_shift_case("soft_sweep_20_g3_horizontal", RIG_G3, t, 0.0, -0.15);
    let hard_sweep = cubic_shift_case("hard_sweep_20_g3_horizontal", RIG_G3, t, 0.0, 0.45);

    // A hanging weight with 110 mm of static deflection, with each effect.
    let t = test(100.0, 40.0, 0.005, 0.002, 10.0, 721);
    let hang_null = linear_case("hanging_null", RIG_SOFT, t);
    let hang_friction = friction_case("hanging_friction", RIG_SOFT, t, 0.4);
    let hang_quadratic = quadratic_case("hanging_quadratic", RIG_SOFT, t, 1.0);
    let hang_cubic = cubic_shift_case("hanging_cubic", RIG_SOFT, t, 9.81, -0.01);
    let hang_coupling = coupling_case("hanging_coupling", RIG_SOFT, t, 0.04);
    vec![
        stop_g1,
        stop_paper,
        stop_g4,
        null_10,
        sweep_g1,
        sweep_g3,
        sweep_strong,
        hard_sweep,
        hang_null,
        hang_friction,
        hang_quadratic,
        hang_cubic,
        hang_coupling,
    ]
}

/// Names of the [`hard_cases`] in the fast (CI) subset: the shortest friction decay, the
/// 10-cycle null decay, the preloaded softening spring (each a second or two), and the
/// softening decay that sweeps 21 % (a few seconds).
pub const FAST_HARD: [&str; 4] = [
    "friction_stops_12_g1",
    "null_10_cycles_g2",
    "hanging_cubic",
    "soft_sweep_20_g3_horizontal",
];

/// Names of the extended cases in the fast (CI) subset: one per kind of record the
/// reader conditions (a quantised position sensor, a band-limited record, a hammer blow
/// at the start, jittered time stamps), all null so that none may name a cause, and a
/// friction hidden behind a 0.01 mm position sensor.
pub const FAST: [&str; 5] = [
    "null_position_0p1mm",
    "null_bandlimited",
    "null_impulse",
    "null_jitter_position",
    "friction_position_0p01mm",
];

/// The extended cases named in [`FAST`].
pub fn fast_cases() -> Vec<TruthCase> {
    extended_cases()
        .into_iter()
        .filter(|c| FAST.contains(&c.name.as_str()))
        .collect()
}
