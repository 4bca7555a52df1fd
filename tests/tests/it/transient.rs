//! Acceptance tests of the transient load case on the paper's spring: mesher ->
//! deck text -> reader -> `analysis::run` -> history -> the paper's decrement
//! (`coil_postproc::decrement`, every 10th crest).
//!
//! The peer model: 24 elements per coil, type 98, E = 190708 MPa, nu = 0.3, 7850 kg/m^3,
//! weight guided, weight mass `K (0.23 / 2 pi)^2` with K the model's static stiffness,
//! Rayleigh alpha = 0.8, beta = 0.00012 on the spring's elements only, 0.1 m/s on the
//! weight, dt = 1 ms, 20 s. One direct 20 s run is shared by the tests that need it;
//! the other records are as short as their measurement allows (see each test).
//!
//! Numbers are printed with `--nocapture`; docs/transient.md quotes them.

use coil_mesher::{
    AnalysisKind, SpringSpec, TransientScheme, VelocityField, WEIGHT_ACCEL_COLUMN, WEIGHT_NODE,
};
use coil_postproc::decrement::{analyze, DecrementOptions, DecrementReport, Lowpass};
use coil_postproc::signal::Signal;
use coil_postproc::PostError;
use coil_solver::analysis::transient::{override_method, MethodOverride};
use coil_solver::analysis::{modal, run, CaseSolution, Mode, System, TransientSolution};
use coil_solver::integrate::Scheme;
use coil_solver::linalg::sym_upper_matvec;
use coil_solver::model::{units, Analysis, Integrator, Model, PointLoad, Table, TransientMethod};
use coil_tests::{paper_spec, through_deck as model_of};
use std::f64::consts::TAU;
use std::sync::OnceLock;

/// The peer's numbers, second-hand: the specification of the transient load case stated
/// that "an established open FE code, run here on the same model" gave zeta = 0.001691 and
/// T = 0.23045 s, and "about 0.0163" with alpha on the weight's mass too. The code's name,
/// version, input and output did not come with them, and CalculiX 2.20 (the open code this
/// machine's distribution packages) cannot rebuild them: its beams are wrong on a helix
/// (tests/peer/README.md, with the decks and what it printed). The verification rests on
/// the references beside them: the exact `phi^T C phi / 2w` of coil's matrices and, with
/// alpha on the weight too (classical Rayleigh damping), the closed form
/// `alpha / 2w + beta w / 2`. The peer's values stay as the agreement the specification
/// asked for.
const PEER_ZETA: f64 = 0.001691;
const PEER_PERIOD_S: f64 = 0.23045;
const PEER_ZETA_ALPHA_ON_WEIGHT: f64 = 0.0163;

const WEIGHT_DISP_COLUMN: &str = "node1_uz_disp_m";

/// The model's static stiffness at the weight (N/mm) and the peer's weight mass (kg).
fn stiffness_and_mass() -> (f64, f64) {
    static CELL: OnceLock<(f64, f64)> = OnceLock::new();
    *CELL.get_or_init(|| {
        let spec = SpringSpec {
            analyses: vec![AnalysisKind::Static],
            ..paper_spec()
        };
        let cases = run(&model_of(&spec)).expect("static solve");
        let k = match &cases[0].solution {
            CaseSolution::Static(s) => s.stiffness_n_mm.expect("stiffness at the weight"),
            other => panic!("expected a static case, got {other:?}"),
        };
        // K in N/mm is 1000 K in N/m: m = K (T / 2 pi)^2 in kg.
        (k, k * 1000.0 * (0.23 / TAU).powi(2))
    })
}

/// The peer's transient spec (direct average acceleration, quasi-static velocity field).
fn peer_spec() -> SpringSpec {
    let (_, mass_kg) = stiffness_and_mass();
    SpringSpec {
        mass_kg,
        alpha: 0.8,
        beta: 1.2e-4,
        initial_velocity_m_s: 0.1,
        dt_s: 1e-3,
        duration_s: 20.0,
        output_every: 1,
        analyses: vec![AnalysisKind::Transient],
        ..paper_spec()
    }
}

fn transient(model: &Model) -> TransientSolution {
    let mut cases = run(model).expect("transient solve");
    match cases.pop().map(|c| c.solution) {
        Some(CaseSolution::Transient(t)) => t,
        other => panic!("expected a transient case, got {other:?}"),
    }
}

fn decrement(
    t: &TransientSolution,
    column: &str,
    lowpass_hz: Option<f64>,
) -> Result<DecrementReport, PostError> {
    let values = t.history.column(column).expect("recorded column");
    let signal = Signal::new(t.history.time_s.clone(), values.to_vec())?;
    analyze(
        &signal,
        &DecrementOptions {
            every: 10,
            lowpass: lowpass_hz.map(|cutoff_hz| Lowpass {
                cutoff_hz,
                order: 4,
            }),
            ..DecrementOptions::default()
        },
    )
}

/// The shared 20 s direct run of the peer case.
fn peer_direct() -> &'static (TransientSolution, DecrementReport) {
    static CELL: OnceLock<(TransientSolution, DecrementReport)> = OnceLock::new();
    CELL.get_or_init(|| {
        let t = transient(&model_of(&peer_spec()));
        let report = decrement(&t, WEIGHT_ACCEL_COLUMN, None).expect("decrement of the peer run");
        (t, report)
    })
}

/// The modes of a model and its system, for exact references.
fn modes_of(model: &Model, count: usize) -> (Vec<Mode>, f64) {
    let system = System::new(model).expect("system");
    let factor = system.factor_stiffness().expect("K factors");
    let modes = modal::solve(&system, &factor, "reference", count)
        .expect("modes")
        .modes;
    let axial = axial(&modes);
    // zeta = phi^T C phi / (2 w), phi mass-normalised (the exact reference).
    let mut c_phi = vec![0.0; system.dim()];
    sym_upper_matvec(system.damping.as_ref(), &axial.shape_free, 1.0, &mut c_phi);
    let quadratic: f64 = axial
        .shape_free
        .iter()
        .zip(&c_phi)
        .map(|(a, b)| a * b)
        .sum();
    let zeta = quadratic / (2.0 * axial.omega_squared.sqrt());
    (modes, zeta)
}

/// The mode with the largest effective mass along the spring axis.
fn axial(modes: &[Mode]) -> &Mode {
    modes
        .iter()
        .max_by(|a, b| a.effective_mass[2].total_cmp(&b.effective_mass[2]))
        .expect("a mode")
}

fn rel(a: f64, b: f64) -> f64 {
    a / b - 1.0
}

#[test]
fn peer_case_matches_the_exact_modal_damping_and_the_peer() {
    let (t, report) = peer_direct();
    let (modes, zeta_exact) = modes_of(&model_of(&peer_spec()), 10);
    let period_modal = axial(&modes).period_s;
    let w_dt = TAU / period_modal * t.dt_s;
    eprintln!(
        "peer case, direct average acceleration, quasi-static field: zeta_mean {:.7e} \
         (exact phi^T C phi / 2w {zeta_exact:.7e}, {:+.3e}; peer {PEER_ZETA}, {:+.3e}); \
         zeta_fit {:.7e}; T {:.8} s (peer {PEER_PERIOD_S}, {:+.3e}; modal {period_modal:.8}, \
         {:+.3e} against (w dt)^2/12 = {:.3e})",
        report.zeta_mean,
        rel(report.zeta_mean, zeta_exact),
        rel(report.zeta_mean, PEER_ZETA),
        report.zeta_fit,
        report.period_s,
        rel(report.period_s, PEER_PERIOD_S),
        rel(report.period_s, period_modal),
        w_dt * w_dt / 12.0
    );
    assert_eq!(t.steps, 20_000);
    assert_eq!(t.history.time_s.len(), 20_001);
    assert!(report.spans.len() >= 8, "{} spans", report.spans.len());
    // The bounds: 0.5 % of the exact modal damping and of the peer's zeta, 0.02 %
    // of the peer's period.
    assert!(rel(report.zeta_mean, zeta_exact).abs() < 5e-3);
    assert!(rel(report.zeta_mean, PEER_ZETA).abs() < 5e-3);
    assert!(rel(report.period_s, PEER_PERIOD_S).abs() < 2e-4);
    // The quasi-static field starts without a velocity jump: no ripple alternating every
    // step rides on the acceleration (the smooth signal alone gives (w dt)^4 = 5.5e-7 of
    // its amplitude in the measure below).
    let a = t.history.column(WEIGHT_ACCEL_COLUMN).expect("accel");
    let (ripple, amplitude) = ripple_and_amplitude(a);
    eprintln!(
        "quasi-static field: step-alternating part {ripple:.3e} m/s^2 ({:.2e} of the \
         amplitude {amplitude:.4} m/s^2)",
        ripple / amplitude
    );
    assert!(ripple < 1e-5 * amplitude);
}

/// The part of a signal that alternates every step and its largest magnitude once that
/// part is averaged out. An alternating `+-r` has a fourth difference of `16 r`; a smooth
/// oscillation of amplitude `A` has at most `(w dt)^4 A`, so the mean absolute fourth
/// difference over 16 measures the ripple.
fn ripple_and_amplitude(x: &[f64]) -> (f64, f64) {
    let fourth: f64 = x
        .windows(5)
        .map(|w| (w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4]).abs())
        .sum::<f64>()
        / (x.len() - 4) as f64;
    let smooth = x
        .windows(2)
        .map(|w| (0.5 * (w[0] + w[1])).abs())
        .fold(0.0, f64::max);
    (fourth / 16.0, smooth)
}

#[test]
fn modal_superposition_agrees_with_direct_integration() {
    let (_, direct) = peer_direct();
    let mut model = model_of(&peer_spec());
    override_method(&mut model, MethodOverride::Modal { modes: Some(20) });
    let t = transient(&model);
    let report = decrement(&t, WEIGHT_ACCEL_COLUMN, None).expect("decrement");
    let summary = t.modal.as_ref().expect("modal summary");
    eprintln!(
        "modal superposition, 20 modes: zeta_mean {:.7e} ({:+.3e} vs direct), T {:.8} s \
         ({:+.3e} vs direct); damping coupling neglected {:.3e} (modes {:?}), largest zeta \
         shift {:.3e}; kinetic energy captured {:.9}",
        report.zeta_mean,
        rel(report.zeta_mean, direct.zeta_mean),
        report.period_s,
        rel(report.period_s, direct.period_s),
        summary.capture.max_damping_coupling,
        summary.capture.coupling_pair,
        summary.capture.max_zeta_shift.unwrap_or(f64::NAN),
        summary
            .capture
            .initial_velocity_captured
            .unwrap_or(f64::NAN),
    );
    // The bound: 0.1 % in zeta and T.
    assert!(rel(report.zeta_mean, direct.zeta_mean).abs() < 1e-3);
    assert!(rel(report.period_s, direct.period_s).abs() < 1e-3);
    // What the superposition leaves out is small and reported: the quasi-static field puts
    // its kinetic energy into the low modes, and the neglected coupling moves no retained
    // mode's damping ratio by more than 1e-6 of itself.
    assert!(summary.capture.initial_velocity_captured.expect("velocity") > 0.9999);
    assert!(summary.capture.max_zeta_shift.expect("shift") < 1e-6);
    assert!(
        summary.capture.max_damping_coupling > 0.0,
        "alpha on the wire only is not classical"
    );
    assert_eq!(summary.modes.len(), 20);
}

#[test]
fn alpha_reaches_the_weight_only_when_a_damping_entry_names_it() {
    // Modal superposition gives the same zeta as direct integration (previous test) in a
    // fraction of the time.
    let modal_spec = SpringSpec {
        transient_method: TransientScheme::Modal,
        transient_modes: 20,
        ..peer_spec()
    };
    let default = model_of(&modal_spec);
    assert!(
        default.damping()[0].mass_nodes.is_empty(),
        "the weight gets no alpha unless asked"
    );
    let plain = decrement(&transient(&default), WEIGHT_ACCEL_COLUMN, None).expect("decrement");
    let asked = model_of(&SpringSpec {
        alpha_on_weight: true,
        ..modal_spec
    });
    assert_eq!(asked.damping()[0].mass_nodes, [WEIGHT_NODE]);
    let on_weight = decrement(&transient(&asked), WEIGHT_ACCEL_COLUMN, None).expect("decrement");
    eprintln!(
        "alpha on the wire only: zeta {:.6e}; alpha on the weight too: zeta {:.6e} (peer about \
         {PEER_ZETA_ALPHA_ON_WEIGHT}, {:+.3e})",
        plain.zeta_mean,
        on_weight.zeta_mean,
        rel(on_weight.zeta_mean, PEER_ZETA_ALPHA_ON_WEIGHT)
    );
    assert!(rel(plain.zeta_mean, PEER_ZETA).abs() < 5e-3);
    // The peer gives "about 0.0163" (three figures): within 1 %.
    assert!(rel(on_weight.zeta_mean, PEER_ZETA_ALPHA_ON_WEIGHT).abs() < 1e-2);
    // With alpha on every mass and beta on every stiffness, C = alpha M + beta K: every
    // mode keeps its shape and the weight's mode has zeta = alpha / 2w + beta w / 2
    // exactly (w its undamped frequency, here the decrement's natural frequency). The
    // decrement of a 20-mode superposition reads it within the other modes' share of the
    // record, under 1e-4 (docs/transient.md): 1e-3 here.
    let w = TAU * on_weight.natural_frequency_hz;
    let closed = 0.8 / (2.0 * w) + 1.2e-4 * w / 2.0;
    eprintln!("closed form alpha / 2w + beta w / 2 = {closed:.6e}");
    assert!(
        rel(on_weight.zeta_mean, closed).abs() < 1e-3,
        "{} vs {closed}",
        on_weight.zeta_mean
    );
}

/// The undamped spring with the quasi-static field, direct integration, 3 s.
fn undamped(scheme: TransientScheme, dt_s: f64) -> DecrementReport {
    let spec = SpringSpec {
        alpha: 0.0,
        beta: 0.0,
        dt_s,
        duration_s: 3.0,
        transient_method: scheme,
        hht_alpha: -0.05,
        ..peer_spec()
    };
    let t = transient(&model_of(&spec));
    assert!(t.modal.is_none());
    // The displacement is the cleanest record of the weight's mode: the higher modes enter
    // it with (w_1 / w_i)^3 of their share of the velocity.
    decrement(&t, WEIGHT_DISP_COLUMN, None).expect("decrement")
}

#[test]
fn average_acceleration_is_undamped_with_second_order_period_error() {
    let (modes, _) = modes_of(&model_of(&peer_spec()), 6);
    let period = axial(&modes).period_s;
    let omega = TAU / period;
    let dts = [8e-3, 4e-3, 2e-3, 1e-3];
    let mut errors = Vec::new();
    for &dt in &dts {
        let report = undamped(TransientScheme::Newmark, dt);
        let error = rel(report.period_s, period);
        let expected = (omega * dt).powi(2) / 12.0;
        eprintln!(
            "average acceleration, undamped, dt = {dt} s (w dt = {:.4}): zeta {:.3e}, period \
             error {error:.5e} vs (w dt)^2/12 = {expected:.5e} (ratio {:.4})",
            omega * dt,
            report.zeta_mean,
            error / expected
        );
        // Average acceleration keeps the amplitude exactly: what the decrement reads is
        // its own crest error (1e-7 of the amplitude at 230 samples per period, 1e-5 at
        // 29, over 10 cycles of 2 pi).
        assert!(report.zeta_mean.abs() < 1e-6, "zeta {}", report.zeta_mean);
        // The period elongation is (w dt)^2/12 to leading order; the next term is
        // -(w dt)^4/720 relative, 1e-3 at the largest step: 10 % is the issue's bound.
        assert!((error / expected - 1.0).abs() < 0.1);
        errors.push(error);
    }
    let slopes: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    eprintln!("period error slopes under dt halving: {slopes:?}");
    for s in slopes {
        assert!((s - 2.0).abs() < 0.1, "slope {s}");
    }
}

#[test]
fn hht_numerical_damping_measured_on_the_paper_spring() {
    let (modes, _) = modes_of(&model_of(&peer_spec()), 6);
    let omega = TAU / axial(&modes).period_s;
    let coefficients = Scheme::Hht { alpha: -0.05 }
        .coefficients()
        .expect("valid HHT alpha");
    for dt in [4e-3, 1e-3] {
        let report = undamped(TransientScheme::Hht, dt);
        let theory = coefficients.algorithmic_damping(omega * dt);
        eprintln!(
            "HHT alpha = -0.05, undamped, dt = {dt} s (w dt = {:.4}): measured zeta {:.4e}, \
             leading-order theory {theory:.4e} (ratio {:.4}); {:.3e} of the peer's zeta",
            omega * dt,
            report.zeta_mean,
            report.zeta_mean / theory,
            report.zeta_mean / PEER_ZETA
        );
        // The leading-order formula is within 0.5 % of the exact root at w dt = 0.1; the
        // decrement reads zeta to about 2e-9 here (crest scatter 1e-7 over 10 cycles).
        assert!((report.zeta_mean / theory - 1.0).abs() < 0.1);
    }
}

#[test]
fn a_nodal_velocity_jump_rings_and_the_low_pass_cures_it() {
    let (_, reference) = peer_direct();
    let spec = SpringSpec {
        initial_velocity_field: VelocityField::Nodal,
        duration_s: 5.0,
        ..peer_spec()
    };
    let model = model_of(&spec);
    assert!(!model.initial_velocities()[0].quasi_static);
    let t = transient(&model);
    let a = t.history.column(WEIGHT_ACCEL_COLUMN).expect("accel");
    let (ripple, amplitude) = ripple_and_amplitude(a);
    let raw = decrement(&t, WEIGHT_ACCEL_COLUMN, None);
    let filtered = decrement(&t, WEIGHT_ACCEL_COLUMN, Some(50.0)).expect("low-passed decrement");
    let displacement = decrement(&t, WEIGHT_DISP_COLUMN, None).expect("displacement decrement");
    eprintln!(
        "nodal jump: ripple alternating every step {ripple:.4e} m/s^2 on an amplitude of \
         {amplitude:.4} m/s^2; raw crests: {}; low-pass 50 Hz: zeta {:.7e} ({:+.3e} vs the \
         quasi-static run), T {:.8}; displacement column: zeta {:.7e} ({:+.3e})",
        match &raw {
            Ok(r) => format!(
                "zeta {:.7e} ({:+.3e})",
                r.zeta_mean,
                rel(r.zeta_mean, reference.zeta_mean)
            ),
            Err(e) => format!("no estimate ({e})"),
        },
        filtered.zeta_mean,
        rel(filtered.zeta_mean, reference.zeta_mean),
        filtered.period_s,
        displacement.zeta_mean,
        rel(displacement.zeta_mean, reference.zeta_mean),
    );
    // The trap: the jump leaves a ripple alternating every step that average acceleration
    // never damps, larger than the signal itself; raw crest picking cannot read zeta.
    assert!(
        ripple > amplitude,
        "ripple {ripple} vs amplitude {amplitude}"
    );
    assert!(raw.map_or(true, |r| rel(r.zeta_mean, reference.zeta_mean).abs() > 5e-3));
    // The cures: a zero-phase low-pass, or reading the displacement, give the quasi-static
    // run's zeta and period (same physics; the ripple lives in the acceleration only).
    assert!(rel(filtered.zeta_mean, reference.zeta_mean).abs() < 1e-4);
    assert!(rel(filtered.period_s, reference.period_s).abs() < 1e-5);
    assert!(rel(displacement.zeta_mean, reference.zeta_mean).abs() < 1e-4);
}

/// The undamped peer spring with one static load case before a transient one.
fn static_then_transient(weight_load_in_model: bool) -> (f64, TransientSolution) {
    let (k, mass_kg) = stiffness_and_mass();
    let spec = SpringSpec {
        alpha: 0.0,
        beta: 0.0,
        initial_velocity_m_s: 0.0,
        duration_s: 0.3,
        analyses: vec![AnalysisKind::Static, AnalysisKind::Transient],
        ..peer_spec()
    };
    let mut model = model_of(&spec);
    // The weight's own weight, -m g along the axis (N).
    let weight = PointLoad {
        dofs: vec![(3, -mass_kg * 9.81)],
        nodes: vec![WEIGHT_NODE],
        table: None,
    };
    model
        .edit(|m| {
            m.load_cases[0].point_loads.clear();
            if weight_load_in_model {
                m.point_loads.push(weight);
            } else {
                m.load_cases[0].point_loads.push(weight);
            }
        })
        .unwrap();
    let cases = run(&model).expect("static + transient");
    let u_static = match &cases[0].solution {
        CaseSolution::Static(s) => s
            .node_displacement(&model, WEIGHT_NODE)
            .expect("weight node")[2],
        other => panic!("expected static, got {other:?}"),
    };
    // -m g / K with the model's stiffness (mm).
    assert!(rel(u_static, -mass_kg * 9.81 / k).abs() < 1e-9);
    match &cases[1].solution {
        CaseSolution::Transient(t) => (u_static, t.clone()),
        other => panic!("expected transient, got {other:?}"),
    }
}

#[test]
fn a_static_case_sets_the_initial_displacement() {
    // Gravity as a model-definition load acts in both cases: the transient starts in
    // equilibrium under it and stays there.
    let (u_static, t) = static_then_transient(true);
    assert_eq!(
        t.initial_displacement_from.as_deref(),
        Some("static axial force 10 N")
    );
    let u = t.history.column(WEIGHT_DISP_COLUMN).expect("disp");
    let drift = u
        .iter()
        .map(|x| (units::length_from_si(*x) - u_static).abs())
        .fold(0.0, f64::max);
    eprintln!("preloaded start: static u = {u_static:.6} mm, largest drift {drift:.3e} mm");
    // Equilibrium to round-off: the static residual (below 1e-12 of the load) at most
    // doubled by the dynamic response to it.
    assert!(drift < 1e-8 * u_static.abs(), "drift {drift}");

    // The static case's own load is not part of the transient: released at t = 0, the
    // undamped weight swings from u_s to -u_s.
    let (u_static, t) = static_then_transient(false);
    let u = t.history.column(WEIGHT_DISP_COLUMN).expect("disp");
    let top = u.iter().copied().fold(f64::MIN, f64::max);
    eprintln!(
        "released start: u_s = {u_static:.6} mm, largest u {:.6} mm",
        units::length_from_si(top)
    );
    assert!(rel(units::length_from_si(u[0]), u_static).abs() < 1e-12);
    // The sampled maximum of a 230-samples-per-period cosine is within (pi/230)^2 / 2 =
    // 1e-4 of the crest; the wire's own modes add less than that.
    assert!(rel(units::length_from_si(top), -u_static).abs() < 2e-4);
}

#[test]
fn an_impulse_from_a_pulse_table_moves_the_weight_by_i_phi_squared_over_w() {
    let (_, mass_kg) = stiffness_and_mass();
    let spec = SpringSpec {
        alpha: 0.0,
        beta: 0.0,
        initial_velocity_m_s: 0.0,
        duration_s: 0.3,
        ..peer_spec()
    };
    let mut model = model_of(&spec);
    // A triangular pulse, 10 N peak, 4 ms long, breakpoints on the 1 ms grid: the
    // impulse is I = 10 N * 2 ms = 0.02 N s.
    model
        .edit(|m| {
            m.tables.push(Table {
                name: "pulse".to_string(),
                points: vec![(0.0, 0.0), (2e-3, 1.0), (4e-3, 0.0)],
            });
            m.load_cases[0].point_loads.push(PointLoad {
                dofs: vec![(3, 10.0)],
                nodes: vec![WEIGHT_NODE],
                table: Some("pulse".to_string()),
            });
        })
        .unwrap();
    let impulse = 10.0 * 2e-3;
    let (modes, _) = modes_of(&model, 6);
    let mode = axial(&modes);
    let system = System::new(&model).expect("system");
    let weight_dof = (0..system.dim())
        .find(|&eq| system.dofs.free_label(eq) == (WEIGHT_NODE, 3))
        .expect("the weight's u_z is free");
    let phi = mode.shape_free[weight_dof];
    let omega = mode.omega_squared.sqrt();
    // u = phi^2 I sin(w t) / w for an ideal impulse; a symmetric triangle of length tau
    // scales it by sinc^2(w tau / 4) = 1 - 2.5e-4 here. In mm: 1 N s = 1 t mm/s.
    let expected = phi * phi * impulse / omega;
    let direct = transient(&model);
    assert!(direct.warnings.is_empty(), "{:?}", direct.warnings);
    override_method(&mut model, MethodOverride::Modal { modes: Some(20) });
    let modal = transient(&model);
    let peak = |t: &TransientSolution| {
        t.history
            .column(WEIGHT_DISP_COLUMN)
            .expect("disp")
            .iter()
            .map(|x| units::length_from_si(*x))
            .fold(f64::MIN, f64::max)
    };
    let (d, m) = (peak(&direct), peak(&modal));
    eprintln!(
        "impulse {impulse} N s on a {mass_kg:.4} kg weight: peak u direct {d:.6e} mm, modal \
         {m:.6e} mm, phi^2 I / w = {expected:.6e} mm"
    );
    // The triangle's sinc^2 factor (2.5e-4) and the sampled maximum (1e-4) are the only
    // departures from the ideal impulse response.
    assert!(rel(d, expected).abs() < 1e-3);
    assert!(rel(m, expected).abs() < 1e-3);
    assert!(rel(d, m).abs() < 5e-4);
}

#[test]
fn history_files_read_in_coil_post_and_name_further_cases() {
    let spec = SpringSpec {
        transient_method: TransientScheme::Modal,
        duration_s: 5.0,
        output_every: 10,
        analyses: vec![AnalysisKind::Transient, AnalysisKind::Transient],
        ..peer_spec()
    };
    let mut model = model_of(&spec);
    model
        .edit(|m| {
            m.load_cases[1].analysis = Analysis::Transient {
                dt: 1e-3,
                total_time: 1.0,
                method: TransientMethod::Direct(Integrator::Hht { alpha: -0.05 }),
            };
            m.load_cases[1].title = "second".to_string();
        })
        .unwrap();
    let cases = run(&model).expect("two transients");
    let dir = tempfile::tempdir().expect("temp dir");
    let written = coil_solver::results::write_all(dir.path(), &model, &cases).expect("write");
    let first = dir.path().join("history.csv");
    assert!(dir.path().join("case2_history.csv").is_file());
    let signal = coil_postproc::signal::read_signal(&first, WEIGHT_ACCEL_COLUMN).expect("read");
    assert_eq!(signal.time_s().len(), 501, "every 10th step of 5000");
    let report = analyze(
        &signal,
        &DecrementOptions {
            every: 10,
            ..DecrementOptions::default()
        },
    )
    .expect("coil-post decrement on the history file");
    eprintln!(
        "history.csv every 10th step, modal: zeta {:.6e}, T {:.6}",
        report.zeta_mean, report.period_s
    );
    assert!(rel(report.zeta_mean, PEER_ZETA).abs() < 5e-3);
    let json = serde_json::to_value(&written).expect("json");
    let entry = &json["load_cases"][0];
    assert_eq!(entry["kind"], "transient");
    assert_eq!(entry["method"], "modal");
    assert_eq!(entry["history_file"], "history.csv");
    assert_eq!(entry["initial_velocity_field"], "quasi-static");
    assert_eq!(entry["columns"][2], WEIGHT_ACCEL_COLUMN);
    let second = &json["load_cases"][1];
    assert_eq!(second["method"], "hht");
    assert_eq!(second["hht_alpha"], -0.05);
    assert_eq!(second["history_file"], "case2_history.csv");
}
