//! Verification of the nonlinear point elements (`FRICTION`, `QUADRATIC DAMPER`,
//! `CUBIC SPRING`) against closed forms, end to end: deck -> model -> `analysis::run`.
//!
//! The single-DOF oscillator is `tests/decks/good/friction_sdof.dat`: a massless bar of
//! k = 1000 N/mm carrying m = 1e-3 t on its only free DOF (node 2, u_x), so
//! w0 = 1000 rad/s, T0 = 6.283 ms, dt = 1e-5 s (w0 dt = 0.01). The other laws are put
//! on the same DOF by editing the read model. The paper spring comes from the mesher.
//!
//! Numbers are printed with `--nocapture`; docs/transient.md quotes them.

use coil_mesher::{AnalysisKind, SpringSpec, WEIGHT_NODE};
use coil_solver::analysis::{run, CaseSolution, StaticSolution, TransientSolution};
use coil_solver::model::{units, Analysis, Model, PointElement, PointLoad};
use coil_tests::{paper_spec, through_deck};
use std::f64::consts::PI;
use std::path::PathBuf;

const K: f64 = 1000.0; // N/mm
const M: f64 = 1.0e-3; // t
const W0: f64 = 1000.0; // rad/s, sqrt(K/M)
const DT: f64 = 1.0e-5; // s, the deck's

fn deck(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("decks/good")
        .join(name)
}

fn read(name: &str) -> Model {
    coil_solver::deck::read_file(&deck(name)).expect("the deck reads")
}

fn transient(model: &Model) -> TransientSolution {
    let results = run(model).expect("the model solves");
    results
        .into_iter()
        .find_map(|r| match r.solution {
            CaseSolution::Transient(t) => Some(t),
            _ => None,
        })
        .expect("a transient case")
}

fn statics(model: &Model) -> Vec<StaticSolution> {
    run(model)
        .expect("the model solves")
        .into_iter()
        .filter_map(|r| match r.solution {
            CaseSolution::Static(s) => Some(s),
            _ => None,
        })
        .collect()
}

/// The SDOF deck with `law` instead of its friction, the initial velocity `v0`
/// (mm/s) and `duration` (s).
fn sdof(law: PointElement, v0: f64, duration: f64) -> Model {
    let mut m = read("friction_sdof.dat");
    m.edit(|m| {
        m.point_laws = vec![PointElement {
            node: 2,
            dof: 1,
            ..law
        }];
        m.initial_velocities[0].dofs = vec![(1, v0)];
        if let Analysis::Transient { total_time, .. } = &mut m.load_cases[0].analysis {
            *total_time = duration;
        }
    })
    .unwrap();
    m
}

fn law(cubic: f64, quadratic: f64, friction: f64) -> PointElement {
    PointElement {
        node: 2,
        dof: 1,
        cubic,
        quadratic,
        friction,
    }
}

/// Displacement (mm) and time (s) of the SDOF's history.
fn sdof_history(t: &TransientSolution) -> (Vec<f64>, Vec<f64>) {
    let u = t
        .history
        .column("node2_ux_disp_m")
        .expect("displacement column")
        .iter()
        .map(|&x| units::length_from_si(x))
        .collect();
    (t.history.time_s.clone(), u)
}

/// Turning points `(time, value)` of a sampled signal: local extrema of `|u|` refined
/// by the parabola through the three samples around each (error O((w dt)^3 A)).
fn turning_points(time: &[f64], u: &[f64]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for i in 1..u.len() - 1 {
        let (a, b, c) = (u[i - 1], u[i], u[i + 1]);
        let is_max = b > a && b >= c;
        let is_min = b < a && b <= c;
        if !(is_max || is_min) {
            continue;
        }
        let curvature = a - 2.0 * b + c;
        let shift = if curvature != 0.0 {
            0.5 * (a - c) / curvature
        } else {
            0.0
        };
        let value = b - 0.25 * (a - c) * shift;
        let dt = time[i + 1] - time[i];
        out.push((time[i] + shift * dt, value));
    }
    out
}

/// Zero up-crossings (linear interpolation).
fn up_crossings(time: &[f64], u: &[f64]) -> Vec<f64> {
    (1..u.len())
        .filter(|&i| u[i - 1] < 0.0 && u[i] >= 0.0)
        .map(|i| time[i - 1] + (time[i] - time[i - 1]) * u[i - 1] / (u[i - 1] - u[i]))
        .collect()
}

/// Least-squares slope of `y` against its index.
fn slope(y: &[f64]) -> f64 {
    let n = y.len() as f64;
    let mx = (n - 1.0) / 2.0;
    let my = y.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &v) in y.iter().enumerate() {
        let dx = i as f64 - mx;
        sxy += dx * (v - my);
        sxx += dx * dx;
    }
    sxy / sxx
}

#[test]
fn coulomb_friction_loses_four_f_over_k_per_cycle_and_sticks() {
    let model = read("friction_sdof.dat");
    let f = model.point_laws()[0].friction;
    let v0 = model.initial_velocities()[0].dofs[0].1;
    let t = transient(&model);
    let (time, u) = sdof_history(&t);
    // Once stuck the velocity is exactly zero: the turning points are those before.
    let v = t.history.column("node2_ux_vel_m_s").unwrap();
    // (round-off of the stick solve: 1e-12 m/s is far below any sliding velocity)
    let moving = v.iter().rposition(|&x| x.abs() > 1e-12).unwrap_or(0) + 1;
    let peaks = turning_points(&time[..=moving], &u[..=moving]);
    // While sliding the motion is harmonic about -+F/k and average acceleration
    // conserves that shifted energy exactly; the scheme's only errors are the period
    // (w dt)^2/12 and the reversal step, where friction takes its new sign for the whole
    // step: an energy error of at most 2F times a step's travel at the turning point,
    // A w^2 dt^2, i.e. an amplitude error of 2 (F/k) (w dt)^2 per reversal.
    let w_dt = W0 * DT;
    let per_reversal = 2.0 * (f / K) * w_dt * w_dt;
    let magnitudes: Vec<f64> = peaks.iter().map(|p| p.1.abs()).collect();
    let loss_per_cycle = -2.0 * slope(&magnitudes);
    let theory = 4.0 * f / K;
    let error = (loss_per_cycle - theory).abs();
    println!(
        "friction SDOF: loss per cycle {loss_per_cycle:.9e} mm, 4F/k = {theory:.9e} mm, relative error {:.2e} (bound {:.2e}); {} turning points",
        error / theory,
        2.0 * per_reversal / theory,
        peaks.len()
    );
    assert!(error <= 2.0 * per_reversal, "{loss_per_cycle} vs {theory}");
    // First turning point: u1 = -F/k + sqrt((F/k)^2 + (v0/w)^2), then 2F/k less each
    // half-cycle until |k u| <= F at a turning point: there it sticks.
    let u1 = -f / K + ((f / K).powi(2) + (v0 / W0).powi(2)).sqrt();
    let reversals = ((u1 - f / K) / (2.0 * f / K)).ceil();
    // Turning point j sits at (-1)^(j+1) (u1 - (j-1) 2F/k) (a negative bracket: the
    // last slide did not cross the centre); it sticks at j - 1 = `reversals`.
    let sign = if reversals as usize % 2 == 0 {
        1.0
    } else {
        -1.0
    };
    let rest = sign * (u1 - reversals * 2.0 * f / K);
    let u_end = *u.last().unwrap();
    let v_end = t.history.column("node2_ux_vel_m_s").unwrap();
    let v_end = *v_end.last().unwrap();
    println!(
        "friction SDOF: rest at {u_end:.9e} mm after {reversals} reversals, predicted {rest:.9e} mm (F/k = {:.3e}), final velocity {v_end:.1e} m/s",
        f / K
    );
    assert!(u_end.abs() <= f / K, "rest {u_end} outside F/k");
    assert!(
        (u_end - rest).abs() <= reversals * per_reversal,
        "rest {u_end} vs {rest}"
    );
    assert!(v_end.abs() < 1e-12, "still moving: {v_end}");
    // The half period is pi/w exactly with friction; average acceleration lengthens it
    // by (w dt)^2/12 (+ O((w dt)^4)), timing measured to O(dt^3) by the parabolas.
    let half_periods: Vec<f64> = peaks.windows(2).map(|p| p[1].0 - p[0].0).collect();
    let mean_half = half_periods.iter().sum::<f64>() / half_periods.len() as f64;
    // The parabolas assume a smooth signal, but the friction force jumps at each
    // turning point: each end of the span may be off by up to a step, so the mean is
    // good to 2 dt over the span.
    let expected = PI / W0 * (1.0 + w_dt * w_dt / 12.0);
    let span = peaks[peaks.len() - 1].0 - peaks[0].0;
    let timing = 2.0 * DT / span;
    println!(
        "friction SDOF: half period {mean_half:.9e} s, pi/w (1 + (w dt)^2/12) = {expected:.9e} s, relative difference {:.2e} (bound {timing:.2e})",
        mean_half / expected - 1.0
    );
    assert!((mean_half / expected - 1.0).abs() < timing);
}

#[test]
fn friction_at_rest_holds_a_preload_below_its_limit() {
    // Starting at rest under a constant load F/2 < F: the initial acceleration takes
    // the static friction the balance needs, and nothing ever moves.
    let f = 10.0;
    let mut m = sdof(law(0.0, 0.0, f), 0.0, 0.005);
    m.edit(|m| {
        m.initial_velocities.clear();
        m.point_loads.push(PointLoad {
            dofs: vec![(1, 0.5 * f)],
            nodes: vec![2],
            table: None,
        });
    })
    .unwrap();
    let t = transient(&m);
    let (_, u) = sdof_history(&t);
    let moved = u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    println!("friction at rest under F/2: largest displacement {moved:.1e} mm");
    assert!(moved == 0.0, "moved by {moved}");
    // Above the limit it slides from the start: F_load - F = m a0.
    m.edit(|m| m.point_loads[0].dofs = vec![(1, 2.5 * f)])
        .unwrap();
    let t = transient(&m);
    let (_, u) = sdof_history(&t);
    // Static offset (2.5F - F)/k, reached from rest: it overshoots to twice that at
    // t = pi/w, where |k u - 2.5F| = F/2 < F: it sticks there.
    let offset = 1.5 * f / K;
    let peak = u.iter().fold(0.0f64, |a, &x| a.max(x));
    println!(
        "friction under 2.5F: peak {peak:.9e} mm, 2 (2.5F - F)/k = {:.9e} mm",
        2.0 * offset
    );
    // The reversal step's error, 2 (F/k) (w dt)^2 (see the decay test).
    assert!((peak - 2.0 * offset).abs() < 2.0 * f / K * (W0 * DT).powi(2));
    // It comes to rest within a step's travel of the turning point, a_max dt^2 with
    // a_max = (|k u - 2.5F| + F)/m, and stays there.
    let last = *u.last().unwrap();
    let travel = (0.5 * f + f) / M * DT * DT;
    assert!(
        (last - peak).abs() < travel,
        "did not stick: {last} vs {peak}"
    );
    let quarter = u.len() * 3 / 4;
    let drift = u[quarter..]
        .iter()
        .fold(0.0f64, |a, &x| a.max((x - last).abs()));
    println!("friction under 2.5F: drift after sticking {drift:.1e} mm");
    assert!(drift < 1e-12 * peak, "moves after sticking: {drift}");
}

#[test]
fn cubic_spring_backbone_follows_harmonic_balance() {
    // u'' + w0^2 (u + lambda u^3) = 0, lambda = k3/k; first-order harmonic balance:
    // w^2 = w0^2 (1 + eps), eps = 3 k3 A^2 / (4 k). Lindstedt's series gives
    // w/w0 = 1 + 3/8 lA^2 - 21/256 (lA^2)^2, harmonic balance 1 + 3/8 lA^2 - 9/128 (lA^2)^2:
    // the neglected term is 3/256 (lA^2)^2 in w, 3/128 (lA^2)^2 in w^2.
    let amplitude = 1.0; // mm
    let eps = 0.01;
    let k3 = 4.0 * K * eps / (3.0 * amplitude * amplitude);
    // The energy 1/2 m v0^2 = 1/2 k A^2 + 1/4 k3 A^4 sets the amplitude exactly.
    let v0 = ((K * amplitude.powi(2) + 0.5 * k3 * amplitude.powi(4)) / M).sqrt();
    let periods = 20.0;
    let duration = periods * 2.0 * PI / W0;
    let measured_period = |k3: f64, v0: f64| {
        let t = transient(&sdof(law(k3, 0.0, 0.0), v0, duration));
        let (time, u) = sdof_history(&t);
        let x = up_crossings(&time, &u);
        let peak = u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        ((x[x.len() - 1] - x[0]) / (x.len() - 1) as f64, peak)
    };
    // The linear run with the same dt carries the same Newmark period error
    // (w dt)^2/12, which cancels in the ratio up to eps (w dt)^2/6.
    let (t_lin, _) = measured_period(0.0, v0);
    let (t_cubic, peak) = measured_period(k3, v0);
    let eps_measured = (t_lin / t_cubic).powi(2) - 1.0;
    let l_a2 = k3 / K * amplitude * amplitude;
    let w_dt = W0 * DT;
    // 20% above the neglected term covers the next one, O((l A^2)^3) (1.3% of it here),
    // and the zero-crossing timing.
    let neglected = 3.0 / 128.0 * l_a2 * l_a2;
    let bound = 1.2 * neglected + eps * w_dt * w_dt / 3.0;
    println!(
        "cubic backbone: A = {peak:.6} mm, (w/w0)^2 - 1 = {eps_measured:.6e}, harmonic balance {eps:.6e}, difference {:.2e} (bound {bound:.2e})",
        eps_measured - eps
    );
    assert!((peak - amplitude).abs() < 1e-3 * amplitude);
    assert!(
        (eps_measured - eps).abs() < bound,
        "{eps_measured} vs {eps}"
    );
    // And the sign: harmonic balance overestimates the stiffening.
    assert!(eps_measured < eps);
}

#[test]
fn quadratic_damping_decays_as_one_over_amplitude() {
    // Energy balance over one cycle of u = A cos(w t): the drag dissipates
    // (8/3) c2 w^2 A^3, so d(1/A)/dn = (8/3) c2 / m per cycle. The averaging is exact
    // to first order in the decrement delta = (8/3) c2 A / m per cycle; the neglected
    // terms change the per-cycle increment of 1/A by O(delta) relative.
    let amplitude = 1.0; // mm
    let delta = 0.01;
    let c2 = delta * 3.0 / 8.0 * M / amplitude;
    let cycles = 20.0;
    let t = transient(&sdof(
        law(0.0, c2, 0.0),
        W0 * amplitude,
        cycles * 2.0 * PI / W0,
    ));
    let (time, u) = sdof_history(&t);
    let maxima: Vec<f64> = turning_points(&time, &u)
        .into_iter()
        .filter(|p| p.1 > 0.0)
        .map(|p| 1.0 / p.1)
        .collect();
    let measured = slope(&maxima);
    let theory = 8.0 / 3.0 * c2 / M;
    let relative = measured / theory - 1.0;
    println!(
        "quadratic damping: d(1/A)/dn = {measured:.6e} 1/mm per cycle, (8/3) c2/m = {theory:.6e}, relative error {relative:.2e} (bound delta = {delta})"
    );
    assert!(relative.abs() < delta, "{measured} vs {theory}");
}

#[test]
fn modal_superposition_and_other_schemes_refuse_point_elements() {
    use coil_solver::analysis::transient::{override_method, MethodOverride};
    use coil_solver::model::{Integrator, TransientMethod};
    let mut m = read("friction_sdof.dat");
    override_method(&mut m, MethodOverride::Modal { modes: Some(1) });
    let e = run(&m).unwrap_err().to_string();
    assert!(e.contains("need --method direct"), "{e}");
    let mut m = read("friction_sdof.dat");
    m.edit(|m| {
        if let Analysis::Transient { method, .. } = &mut m.load_cases[0].analysis {
            *method = TransientMethod::Direct(Integrator::Hht { alpha: -0.1 });
        }
    })
    .unwrap();
    let e = run(&m).unwrap_err().to_string();
    assert!(
        e.contains("average acceleration") && e.contains("HHT"),
        "{e}"
    );
}

/// The paper's spring, coarse enough for a fast test: 12 elements per coil, type 98,
/// E = 190708 MPa, a 5.26 kg weight on the guided top.
fn coarse_paper_spec() -> SpringSpec {
    SpringSpec {
        elements_per_coil: 12,
        mass_kg: 5.26,
        ..paper_spec()
    }
}

#[test]
fn paper_spring_with_friction_loses_four_f_over_k_per_cycle() {
    let linear = statics(&through_deck(&coarse_paper_spec()));
    let k_fe = linear[0].stiffness_n_mm.expect("stiffness");
    let friction_n = 0.5;
    let spec = SpringSpec {
        analyses: vec![AnalysisKind::Transient],
        friction_n,
        initial_velocity_m_s: 0.1,
        dt_s: 1e-3,
        duration_s: 1.2,
        ..coarse_paper_spec()
    };
    let model = through_deck(&spec);
    assert_eq!(model.point_laws()[0].node, WEIGHT_NODE);
    let t = transient(&model);
    let time = &t.history.time_s;
    let u: Vec<f64> = t
        .history
        .column("node1_uz_disp_m")
        .unwrap()
        .iter()
        .map(|&x| units::length_from_si(x))
        .collect();
    let peaks = turning_points(time, &u);
    // Turning points of the axial mode: the largest extremum of each half-cycle (the
    // quasi-static start excites the wire's own modes only weakly).
    let magnitudes: Vec<f64> = peaks
        .iter()
        .filter(|p| p.1.abs() > 4.0 * friction_n / k_fe)
        .map(|p| p.1.abs())
        .collect();
    let loss = -2.0 * slope(&magnitudes);
    let theory = 4.0 * friction_n / k_fe;
    println!(
        "paper spring, F = {friction_n} N: loss per cycle {loss:.6e} mm, 4F/k_FE = {theory:.6e} mm (k_FE = {k_fe:.6} N/mm), relative error {:.2e} over {} turning points",
        loss / theory - 1.0,
        magnitudes.len()
    );
    // The axial mode's modal stiffness differs from the static k_FE by the wire's share
    // of the mass (m_wire / 3M ~ 0.5%), the higher modes ride on the peaks: 3%.
    assert!(magnitudes.len() >= 6, "{} turning points", magnitudes.len());
    assert!((loss / theory - 1.0).abs() < 0.03, "{loss} vs {theory}");
}

#[test]
fn paper_spring_with_cubic_stiffness_solves_k_x_plus_k3_x3_under_gravity() {
    let gravity = 9.81;
    let weight_n = coarse_paper_spec().mass_kg * gravity;
    let linear = statics(&through_deck(&coarse_paper_spec()));
    let k_fe = linear[0].stiffness_n_mm.expect("stiffness");
    // k3 such that the cubic carries a tenth of the load at the linear deflection.
    let x_lin = weight_n / k_fe;
    let k3 = 0.1 * weight_n / x_lin.powi(3); // N/mm^3
    let spec = SpringSpec {
        analyses: vec![AnalysisKind::Static],
        force_n: weight_n,
        cubic_stiffness_n_m3: units::cubic_stiffness_to_si(k3),
        ..coarse_paper_spec()
    };
    let model = through_deck(&spec);
    let solution = &statics(&model)[0];
    let x = -solution.node_displacement(&model, WEIGHT_NODE).unwrap()[2];
    // Newton on the scalar k x + k3 x^3 = m g.
    let mut expected = x_lin;
    for _ in 0..50 {
        expected -= (k_fe * expected + k3 * expected.powi(3) - weight_n)
            / (k_fe + 3.0 * k3 * expected * expected);
    }
    println!(
        "paper spring, k3 = {k3:.6e} N/mm^3: deflection {x:.12} mm, k x + k3 x^3 = m g gives {expected:.12} mm (linear {x_lin:.6} mm), {} Newton iterations, residual {:.1e}",
        solution.iterations, solution.relative_residual
    );
    // The condensed stiffness at the weight is k_FE exactly, so only round-off (the
    // factor's, ~1e-12 relative) separates the two.
    assert!((x / expected - 1.0).abs() < 1e-9, "{x} vs {expected}");
    assert!(solution.relative_residual < 1e-10);
    assert!(solution.iterations >= 2 && solution.iterations <= 20);
}

#[test]
fn every_nonlinear_deck_checks_its_headline_number() {
    // friction_sdof.dat: at rest within F/k (the decay itself is checked above).
    let t = transient(&read("friction_sdof.dat"));
    let (_, u) = sdof_history(&t);
    assert!(u.last().unwrap().abs() <= 10.0 / K);
    // cubic_spring_static.dat: k x + k3 x^3 = F on the SDOF bar.
    let model = read("cubic_spring_static.dat");
    let e = model.point_laws()[0];
    let s = &statics(&model)[0];
    let x = s.node_displacement(&model, 2).unwrap()[0];
    let f = 100.0;
    let residual = K * x + e.cubic * x.powi(3) - f;
    println!(
        "cubic_spring_static.dat: u = {x:.12} mm, k u + k3 u^3 - F = {residual:.1e} N ({} iterations)",
        s.iterations
    );
    assert!(residual.abs() < 1e-10 * f);
    // quadratic_damper_sdof.dat: the first peak of the decay, from the energy balance
    // over the first quarter cycle: 1/A1 = 1/A0 + (2/3) c2/m to first order.
    let model = read("quadratic_damper_sdof.dat");
    let c2 = model.point_laws()[0].quadratic;
    let t = transient(&model);
    let (time, u) = sdof_history(&t);
    let first = turning_points(&time, &u)[0].1;
    let a0 = model.initial_velocities()[0].dofs[0].1 / W0;
    let expected = 1.0 / (1.0 / a0 + 2.0 / 3.0 * c2 / M);
    println!("quadratic_damper_sdof.dat: first peak {first:.6} mm, expected {expected:.6} mm");
    // First-order energy balance: error O(delta^2) with delta = (2/3) c2 A0/m = 0.0025.
    assert!((first / expected - 1.0).abs() < 1e-4);
}
