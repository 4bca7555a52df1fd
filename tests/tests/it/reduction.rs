//! The Craig-Bampton reduced model (`coil_solver::reduce`) and the dense stepper
//! (`coil_solver::integrate::dense`) on the paper's spring, against the full FE model
//! (static, modal, transient) and the helix closed forms, and with the nonlinear point
//! laws (friction, velocity-squared drag, a cubic spring under gravity) at the weight
//! against the full transient with the same deck cards.
//!
//! Spring: coil-mesh's paper spring (n = 14, D = 24 mm, d = 3 mm, h = 6.2 mm,
//! E = 190708 MPa, nu = 0.3, 7850 kg/m^3, type 98, 24 elements per coil), weight
//! 5.27 kg on node 1 (period ~0.23 s). Numbers print with `--nocapture`; docs/reduction.md
//! quotes them.

use coil_mesher::closed_form::HelixStiffness;
use coil_mesher::{AnalysisKind, SpringSpec, Top, WEIGHT_ACCEL_COLUMN, WEIGHT_NODE};
use coil_solver::analysis::{run, CaseSolution, ModalSolution, System};
use coil_solver::dof::DofStatus;
use coil_solver::integrate::dense::Sample;
use coil_solver::integrate::{DenseStepper, PointLaw};
use coil_solver::model::{units, Model, PointLoad};
use coil_solver::reduce::{craig_bampton, Reduction};
use std::f64::consts::PI;

const MASS_KG: f64 = 5.27;

fn spec(elements_per_coil: u32, top: Top, analyses: Vec<AnalysisKind>) -> SpringSpec {
    SpringSpec {
        youngs_modulus_mpa: 190_708.0,
        poisson: 0.3,
        density_kg_m3: 7850.0,
        elements_per_coil,
        element: 98,
        mass_kg: MASS_KG,
        top,
        analyses,
        modes: 6,
        ..SpringSpec::default()
    }
}

fn static_and_modal(model: &Model) -> (f64, ModalSolution) {
    let cases = run(model).expect("solves");
    let k = match &cases[0].solution {
        CaseSolution::Static(s) => s.stiffness_n_mm.expect("stiffness at the weight"),
        other => panic!("expected a static case, got {other:?}"),
    };
    match &cases[1].solution {
        CaseSolution::Modal(m) => (k, m.clone()),
        other => panic!("expected a modal case, got {other:?}"),
    }
}

fn reduce(model: &Model, boundary: &[(u32, u8)], n_modes: usize) -> Reduction {
    craig_bampton(model, boundary, n_modes).expect("reduces")
}

fn rel(a: f64, b: f64) -> f64 {
    a / b - 1.0
}

/// The diagonal entry of the full model's free-DOF stiffness at a DOF.
fn stiffness_diagonal(model: &Model, node: u32, dof: u8) -> f64 {
    let system = System::new(model).expect("system");
    let full = system.dofs.full_index(node, dof).expect("dof");
    let DofStatus::Free(eq) = system.dofs.status(full) else {
        panic!("not free")
    };
    let k = &system.stiffness;
    k.row_idx_of_col_raw(eq)
        .iter()
        .zip(k.val_of_col(eq))
        .filter(|(i, _)| **i == eq)
        .map(|(_, v)| *v)
        .sum()
}

/// Guided weight, boundary = the weight's u_z:
/// - the reduced static stiffness is the full model's (constraint modes are exact in
///   statics). Both are Schur complements computed in floating point: the weight's own
///   diagonal stiffness K_bb cancels down to K, so each carries a rounding error of about
///   `eps K_bb / K` times a growth of order sqrt(n); the tolerance is `100 eps K_bb / K`;
/// - reduced eigenfrequencies are upper bounds of the full ones and fall monotonically
///   with n_modes (nested bases); the axial mode is within 1.4e-6 with Guyan's
///   condensation (0 modes) and 1.0e-7 with 4 modes (measured table in
///   docs/reduction.md; the first fixed-interface surge mode, the third mode at 129 Hz,
///   takes the error from 1.3e-6 to 1.1e-7);
/// - the second frequency converges onto the full one the same way;
/// - scaling E is scaling the reduced K (`operators(k_scale)`), as reducing again.
#[test]
fn guided_reduction_matches_the_full_static_and_modal_model() {
    let model = spec(
        24,
        Top::Guided,
        vec![AnalysisKind::Static, AnalysisKind::Modal],
    )
    .build()
    .expect("valid spec");
    let (k_full, modal) = static_and_modal(&model);
    let f_full: Vec<f64> = modal.modes.iter().map(|m| m.frequency_hz).collect();
    let red = reduce(&model, &[(WEIGHT_NODE, 3)], 4);
    let k_red = red.k[(0, 0)];
    let k_bb = stiffness_diagonal(&model, WEIGHT_NODE, 3);
    let tolerance = 100.0 * f64::EPSILON * k_bb / k_full;
    eprintln!(
        "static K: full {k_full:.10} N/mm, reduced {k_red:.10}, relative {:e} (K_bb {k_bb:e}, tolerance {tolerance:e})",
        rel(k_red, k_full)
    );
    assert!(rel(k_red, k_full).abs() < tolerance);

    let f_red = red.frequencies_hz(1.0, &[0.0]).expect("frequencies");
    eprintln!("full f = {f_full:?}\nreduced (4 modes) f = {f_red:?}");
    eprintln!("fixed-interface f = {:?}", red.fixed_interface_hz);
    // docs/reduction.md prints them to 0.01 Hz: 108.71, 109.15, 128.75, 146.00 (the
    // third is the held spring's first surge mode).
    for (f, printed) in red
        .fixed_interface_hz
        .iter()
        .zip([108.71, 109.15, 128.75, 146.00])
    {
        assert!(
            (f - printed).abs() <= 0.005 + 1e-9,
            "fixed-interface {f} Hz prints as {printed} in docs/reduction.md"
        );
    }
    let axial_error = rel(f_red[0], f_full[0]);
    eprintln!("axial mode, 4 modes: relative error {axial_error:e}");
    assert!(axial_error > -1e-12 && axial_error < 2e-7);

    let counts = [0, 1, 2, 3, 4, 6, 8];
    let (mut first, mut second) = (Vec::new(), Vec::new());
    for n_modes in counts {
        let r = reduce(&model, &[(WEIGHT_NODE, 3)], n_modes);
        let f = r.frequencies_hz(1.0, &[0.0]).expect("frequencies");
        first.push(rel(f[0], f_full[0]));
        if f.len() > 1 {
            second.push(rel(f[1], f_full[1]));
        }
    }
    eprintln!("n_modes {counts:?}\n  axial relative errors {first:?}\n  second {second:?}");
    for errors in [&first, &second] {
        assert!(errors.iter().all(|e| *e > -1e-12), "{errors:?}");
        for pair in errors.windows(2) {
            assert!(pair[1] <= pair[0] + 1e-12, "{errors:?}");
        }
    }
    assert!(first[0] < 2e-6 && *first.last().unwrap() < 5e-8);
    assert!(*second.last().unwrap() < 1e-6);

    // Re-parameterising E by k_scale is reducing again at the new E: same frequencies,
    // to the rounding of the Schur complement (the tolerance above).
    let mut stiffer = model.clone();
    stiffer
        .edit(|m| m.materials[0].youngs_modulus *= 1.1)
        .unwrap();
    let again = reduce(&stiffer, &[(WEIGHT_NODE, 3)], 4)
        .frequencies_hz(1.0, &[0.0])
        .expect("frequencies");
    let scaled = red.frequencies_hz(1.1, &[0.0]).expect("frequencies");
    let worst = again
        .iter()
        .zip(&scaled)
        .map(|(a, b)| rel(*b, *a).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "E x 1.1: reduced again vs k_scale 1.1: worst relative frequency difference {worst:e}"
    );
    assert!(worst < tolerance);
}

/// The mass the reduction carries. With the base's axial translation freed and made a
/// second boundary DOF, a unit displacement of both boundaries is the rigid axial
/// translation (it is the static response to it, and costs no energy): the reduced
/// mass must give it the spring's wire mass (inscribed polygon, consistent beam mass is
/// exact for rigid motion) plus the weight, and the reduced stiffness zero force.
/// On the guided model the weight's reduced mass is the weight plus the spring's
/// effective mass, which Rayleigh's estimate puts at a third of the wire mass.
#[test]
fn the_reduced_mass_carries_the_spring_and_the_weight() {
    let s = spec(24, Top::Guided, vec![]);
    let mut model = s.build().expect("valid spec");
    let guided = reduce(&model, &[(WEIGHT_NODE, 3)], 4);

    let base = coil_mesher::BASE_NODE;
    model
        .edit(|m| {
            for fixed in &mut m.fixed_disp {
                if fixed.nodes == [base] {
                    fixed.dofs.retain(|&(d, _)| d != 3);
                }
            }
        })
        .unwrap();
    let red = reduce(&model, &[(base, 3), (WEIGHT_NODE, 3)], 3);
    let m = red.mass();
    // e = (1, 1, 0, ...): e^T M e and K e from the first two rows and columns.
    let rigid_mass = m[(0, 0)] + m[(0, 1)] + m[(1, 0)] + m[(1, 1)];
    let n_el = s.element_count() as f64;
    let r = 0.5 * s.mean_diameter_mm;
    let dt = 2.0 * PI * s.coils / n_el;
    let chord = (2.0 * r * (0.5 * dt).sin()).hypot(s.pitch_mm * dt / (2.0 * PI));
    let area = PI * s.wire_diameter_mm.powi(2) / 4.0;
    let wire = units::density_from_si(s.density_kg_m3) * area * chord * n_el;
    let expected = wire + units::mass_from_si(MASS_KG);
    eprintln!(
        "rigid axial translation: reduced mass {rigid_mass:e} t, wire + weight {expected:e} t, relative {:e}",
        rel(rigid_mass, expected)
    );
    assert!(rel(rigid_mass, expected).abs() < 1e-12);
    let force = (0..red.dim())
        .map(|i| (red.k[(i, 0)] + red.k[(i, 1)]).abs())
        .fold(0.0, f64::max)
        / red.k.amax();
    eprintln!("rigid axial translation: |K e| / |K| = {force:e}");
    assert!(force < 1e-10);

    let effective = guided.m_elements[(0, 0)];
    eprintln!(
        "guided: M_bb = weight + {:.5} x wire mass (Rayleigh: 1/3)",
        effective / wire
    );
    assert_eq!(
        guided.m_points[(0, 0)],
        units::mass_from_si(MASS_KG),
        "the weight's point mass sits on the boundary row"
    );
    assert!((effective / wire - 1.0 / 3.0).abs() < 0.01);
}

/// The helix's axial-torsional coupling: the 2x2 static compliance of the free end
/// (u_z, theta_z) from the reduced boundary stiffness against Castigliano's
/// `C_uu = R^2 L (c^2/GJ + s^2/EI) (+ shear and axial terms)`,
/// `C_uθ = R L s c (1/GJ - 1/EI)`, `C_θθ = L (s^2/GJ + c^2/EI)`. The FE differs by its
/// inscribed-polygon wire (shorter, stiffer by O(1/n^2) per element) and by the held
/// lateral DOFs of the end; the difference falls with mesh refinement.
#[test]
fn free_rotation_reproduces_the_helix_coupling() {
    let mut errors = Vec::new();
    for elements_per_coil in [12, 24, 48] {
        let s = spec(elements_per_coil, Top::FreeRotation, vec![]);
        let model = s.build().expect("valid spec");
        let red = reduce(&model, &[(WEIGHT_NODE, 3), (WEIGHT_NODE, 6)], 0);
        let c = red.k.clone().try_inverse().expect("invertible");
        let geometry = s.geometry();
        let (e, nu) = (s.youngs_modulus_mpa, s.poisson);
        let g = e / (2.0 * (1.0 + nu));
        let i = PI * s.wire_diameter_mm.powi(4) / 64.0;
        let (gj, ei) = (g * 2.0 * i, e * i);
        let a = geometry.pitch_angle();
        let (sn, cs) = (a.sin(), a.cos());
        let l = geometry.wire_length_mm();
        let r = 0.5 * s.mean_diameter_mm;
        let hs = HelixStiffness::new(&geometry, e, nu);
        let c_uu = 1.0 / hs.free(true);
        let c_ut = r * l * sn * cs * (1.0 / gj - 1.0 / ei);
        let c_tt = l * (sn * sn / gj + cs * cs / ei);
        let err = [
            rel(c[(0, 0)], c_uu),
            rel(c[(0, 1)], c_ut),
            rel(c[(1, 1)], c_tt),
        ];
        eprintln!(
            "{elements_per_coil} el/coil: C_uu {:e} ({:+.3e}), C_ut {:e} ({:+.3e}), C_tt {:e} ({:+.3e})",
            c[(0, 0)],
            err[0],
            c[(0, 1)],
            err[1],
            c[(1, 1)],
            err[2]
        );
        errors.push(err);
    }
    for k in 0..3 {
        assert!(errors[1][k].abs() < 0.02, "{errors:?}");
        assert!(errors[2][k].abs() < errors[0][k].abs(), "{errors:?}");
    }
}

/// Free rotation with a rotary inertia J that nearly tunes the torsional mode to the
/// axial one: the two lowest frequencies (a coupled pair) of the reduced model against
/// the full modal analysis (upper bounds; within 2e-7 with 4 modes, as the guided axial
/// mode).
#[test]
fn free_rotation_pair_matches_the_full_modal_analysis() {
    let model = SpringSpec {
        rotary_inertia_kg_m2: 1.0e-3,
        ..spec(
            24,
            Top::FreeRotation,
            vec![AnalysisKind::Static, AnalysisKind::Modal],
        )
    }
    .build()
    .expect("valid spec");
    let (_, modal) = static_and_modal(&model);
    let red = reduce(&model, &[(WEIGHT_NODE, 3), (WEIGHT_NODE, 6)], 4);
    let f_red = red.frequencies_hz(1.0, &[0.0, 0.0]).expect("frequencies");
    for (k, (mode, f)) in modal.modes.iter().zip(&f_red).take(2).enumerate() {
        let full = mode.frequency_hz;
        let err = rel(*f, full);
        eprintln!(
            "free rotation mode {}: full {full} Hz, reduced {f} Hz, relative {err:e}, axial effective mass {:.4} of the weight",
            k + 1,
            mode.effective_mass[2] / units::mass_from_si(MASS_KG)
        );
        assert!(err > -1e-12 && err < 2e-7);
    }
    // A coupled pair: both modes move the weight axially.
    assert!(modal.modes[0].effective_mass[2] > 0.05 * units::mass_from_si(MASS_KG));
    assert!(modal.modes[1].effective_mass[2] > 0.05 * units::mass_from_si(MASS_KG));
}

/// The dense stepper on the reduced spring against the full FE transient (same
/// average-acceleration scheme, same dt = 1 ms, Rayleigh alpha = 0.8, beta = 1.2e-4 on
/// the wire, 0.1 m/s on the weight with the quasi-static field, which is the constraint
/// mode: the initial state lies in the reduced space exactly). What differs is the
/// reduction alone: the part of the full response outside span(T), the higher surge and
/// coil modes, which the full model carries and the reduced one does not. The axial
/// mode's own error (1e-7 in frequency, a phase of 5e-6 rad over the 2 s) is below it.
/// Measured: 9.7e-5 of the peak acceleration with Guyan's condensation, 3.9e-5 with 4
/// modes, 1.8e-5 with 12: it falls with n_modes and is 50 times below the lowest noise
/// level a measured case carries (0.2 % of peak).
#[test]
fn dense_stepper_on_the_reduced_spring_follows_the_full_transient() {
    let s = SpringSpec {
        alpha: 0.8,
        beta: 1.2e-4,
        initial_velocity_m_s: 0.1,
        dt_s: 1e-3,
        duration_s: 2.0,
        ..spec(24, Top::Guided, vec![AnalysisKind::Transient])
    };
    let model = s.build().expect("valid spec");
    let cases = run(&model).expect("transient");
    let history = match &cases[0].solution {
        CaseSolution::Transient(t) => t.history.clone(),
        other => panic!("expected a transient, got {other:?}"),
    };
    let full = history.column(WEIGHT_ACCEL_COLUMN).expect("weight accel");

    let peak = full.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut errors = Vec::new();
    for n_modes in [0, 4, 12] {
        let red = reduce(&model, &[(WEIGHT_NODE, 3)], n_modes);
        let ops = red
            .operators(1.0, &[0.0], s.alpha, s.beta)
            .expect("operators");
        let mut stepper = DenseStepper::new(&ops.m, &ops.c, &ops.k, s.dt_s, &[]).expect("stepper");
        let mut v0 = vec![0.0; red.dim()];
        v0[0] = units::length_from_si(s.initial_velocity_m_s);
        let samples = stepper
            .simulate(&vec![0.0; red.dim()], &v0, full.len(), 1, 0)
            .expect("simulates");
        let worst = samples
            .iter()
            .zip(full)
            .map(|(r, f)| (r.a * 1e-3 - f).abs())
            .fold(0.0f64, f64::max);
        eprintln!(
            "transient, {n_modes} modes: {} samples, peak accel {peak:.6} m/s^2, max |reduced - full| = {worst:e} ({:e} of peak)",
            full.len(),
            worst / peak
        );
        errors.push(worst / peak);
    }
    assert!(errors[1] < 1e-4 && errors[2] < errors[1] && errors[1] < errors[0]);
}

/// The weight's axial law of a spec in solver units (N, N s^2/mm^2, N/mm^3), as the
/// mesher writes it into the deck.
fn point_law(s: &SpringSpec) -> PointLaw {
    PointLaw {
        cubic: units::cubic_stiffness_from_si(s.cubic_stiffness_n_m3),
        quadratic: units::quadratic_damping_from_si(s.quadratic_damping_n_s2_m2),
        friction: s.friction_n,
    }
}

/// The weight's axial motion in the full FE transient and in the reduced model.
struct LawRun {
    /// Full model: acceleration (m/s^2), velocity (m/s) and displacement (m) of the
    /// weight.
    full_a: Vec<f64>,
    full_v: Vec<f64>,
    full_u: Vec<f64>,
    /// Reduced model, in solver units (mm, mm/s, mm/s^2).
    reduced: Vec<Sample>,
    /// Relative difference of the reduced and full static preloads (0 without gravity).
    preload_error: f64,
}

impl LawRun {
    /// `max |reduced - full| / max |full|` of the acceleration over the samples where
    /// `held(k)` is `held`.
    fn accel_error(&self, held: bool) -> f64 {
        let peak = self.full_a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        (0..self.full_a.len())
            .filter(|&k| self.held(k) == held)
            .map(|k| (self.reduced[k].a * 1e-3 - self.full_a[k]).abs())
            .fold(0.0f64, f64::max)
            / peak
    }

    fn error(&self) -> f64 {
        self.accel_error(false).max(self.accel_error(true))
    }

    /// Friction holds the weight at sample `k` in the reduced model (its velocity is
    /// set to exactly zero).
    fn held(&self, k: usize) -> bool {
        self.reduced[k].v == 0.0
    }

    /// Samples where one model holds the weight and the other does not. The full
    /// model's held velocity is a rounding residue of the sparse correction (~1e-21 m/s
    /// measured), against 0.1 m/s at the start.
    fn held_mismatches(&self) -> usize {
        (0..self.full_a.len())
            .filter(|&k| self.held(k) != (self.full_v[k].abs() < 1e-15))
            .count()
    }
}

/// The full FE transient of `s` (with its point law on node 1 DOF 3) against the dense
/// stepper on `craig_bampton(model, [(1, 3)], 4)` with the same law, scheme and dt.
/// With `gravity_m_s2 > 0` the weight's own weight is a model-definition load and a
/// static case runs first, so the full transient starts at the (nonlinear, for a cubic)
/// static equilibrium and oscillates about it; the reduced model starts at its own
/// static equilibrium under the same load, which is the full one exactly (the static
/// response to a load at the weight is the constraint mode), to the two Newton
/// tolerances.
fn run_with_law(s: &SpringSpec, gravity_m_s2: f64) -> LawRun {
    let mut model = s.build().expect("valid spec");
    let weight = units::mass_from_si(s.mass_kg) * units::length_from_si(gravity_m_s2);
    if gravity_m_s2 > 0.0 {
        // Gravity pulls the weight toward the base (-z). As a model-definition load it
        // acts in the static case and in the transient (solver/src/analysis/transient.rs,
        // "Initial state"); the static case's own test load is dropped.
        model
            .edit(|m| {
                m.point_loads.push(PointLoad {
                    dofs: vec![(3, -weight)],
                    nodes: vec![WEIGHT_NODE],
                    table: None,
                });
                for case in &mut m.load_cases {
                    case.point_loads.clear();
                }
            })
            .unwrap();
    }
    let cases = run(&model).expect("solves");
    let history = match &cases.last().expect("a transient case").solution {
        CaseSolution::Transient(t) => t.history.clone(),
        other => panic!("expected a transient, got {other:?}"),
    };
    let full_a = history.column(WEIGHT_ACCEL_COLUMN).expect("weight accel");
    let full_v = history.column("node1_uz_vel_m_s").expect("weight vel");
    let full_u = history.column("node1_uz_disp_m").expect("weight disp");

    let red = reduce(&model, &[(WEIGHT_NODE, 3)], 4);
    let ops = red
        .operators(1.0, &[0.0], s.alpha, s.beta)
        .expect("operators");
    let mut stepper =
        DenseStepper::new(&ops.m, &ops.c, &ops.k, s.dt_s, &[(0, point_law(s))]).expect("stepper");
    let mut u0 = vec![0.0; red.dim()];
    let mut preload_error = 0.0;
    if gravity_m_s2 > 0.0 {
        let mut f = vec![0.0; red.dim()];
        f[0] = -weight;
        stepper.set_load(&f).expect("load");
        u0 = stepper.static_equilibrium(&f).expect("static equilibrium");
        let full_static = full_u[0] * 1e3;
        preload_error = rel(u0[0], full_static);
        eprintln!(
            "  preload: full {full_static:.9} mm, reduced {:.9} mm, relative {:e}; other reduced coordinates {:e}",
            u0[0],
            rel(u0[0], full_static),
            u0[1..].iter().fold(0.0f64, |m, x| m.max(x.abs()))
        );
    }
    // The quasi-static velocity field is the constraint mode: v0 = [v, 0, 0, 0, 0].
    let mut v0 = vec![0.0; red.dim()];
    v0[0] = units::length_from_si(s.initial_velocity_m_s);
    let reduced = stepper
        .simulate(&u0, &v0, full_a.len(), 1, 0)
        .expect("simulates");
    LawRun {
        full_a: full_a.to_vec(),
        full_v: full_v.to_vec(),
        full_u: full_u.to_vec(),
        reduced,
        preload_error,
    }
}

/// `max |a - b| / max |b|`.
fn relative_max_difference(a: &[f64], b: &[f64]) -> f64 {
    let peak = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f64, f64::max)
        / peak
}

/// Peak |a| over the last 0.25 s (about one period) over that of the first.
fn decay(a: &[f64]) -> f64 {
    let window = 250;
    let peak = |w: &[f64]| w.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    peak(&a[a.len() - window..]) / peak(&a[..window])
}

/// The transient spec shared by the point-law tests: the linear transient test's
/// damping, step and initial velocity, over 3 s (about 13 periods).
fn law_spec() -> SpringSpec {
    SpringSpec {
        alpha: 0.8,
        beta: 1.2e-4,
        initial_velocity_m_s: 0.1,
        dt_s: 1e-3,
        duration_s: 3.0,
        ..spec(24, Top::Guided, vec![AnalysisKind::Transient])
    }
}

/// The reduced model with a dissipative law at the weight against the full FE
/// transient with the same card. The spring (k ~ 3.9 N/mm, T ~ 0.23 s) starts with
/// 0.1 m/s, an amplitude A ~ 3.7 mm:
/// - friction F = 0.05 N takes `4F/k` ~ 0.05 mm, 1.4 % of A, per cycle (it never
///   sticks in 3 s: the amplitude stays far above `F/k`);
/// - velocity-squared drag c2 = 8 N s^2/m^2 takes `(8/3) c2 A / m` ~ 1.5 % of A per
///   cycle (the energy `(8/3) c2 w^2 A^3` per cycle against `k A^2 / 2`);
/// - friction F = 0.4 N (11 % of A per cycle) holds the weight for a step at its last
///   reversals and for good after ~2 s.
///
/// Tolerance. Both models solve the same scalar law with the same return mapping
/// (`PointLaw::solve`, converged to 4 ulp of the force), so the law adds no error of
/// its own; what differs is the reduction, as in the linear test (3.9e-5 of the peak
/// with 4 modes, bound 1e-4). The law acts on the boundary DOF, which the reduction
/// keeps exactly, and is a few percent of the spring force, so it changes that error
/// by a few percent: the bound stays 1e-4 while the weight slides. A velocity reversal
/// that the two models put in different steps would add a jump of `2F/m` (3.5e-3 of the
/// peak for 0.05 N) in one sample, which that bound would catch.
///
/// While friction holds the weight, the acceleration a step records is not a force
/// balance but the trapezoidal rule's kinematics: `v_{n+1} = v_n + dt/2 (a_n +
/// a_{n+1}) = 0` gives `a_{n+1} = -(2 v_n/dt + a_n)` (and, held for good, `+-a_s` for
/// ever, in both integrators). That amplifies the models' velocity difference at the
/// sticking step by `2 / (w dt)` ~ 73 relative to the peak, so held samples get
/// `2/(w dt)` times the sliding bound; the two models must hold the weight at the same
/// samples, and the final rest position must agree within 1e-4 of the amplitude.
#[test]
fn dense_stepper_with_friction_or_drag_follows_the_full_transient() {
    let linear = run_with_law(&law_spec(), 0.0);
    eprintln!(
        "no law: max |reduced - full| = {:e} of the peak; last/first cycle peak {:.4}",
        linear.error(),
        decay(&linear.full_a)
    );
    for (name, s) in [
        (
            "friction 0.05 N",
            SpringSpec {
                friction_n: 0.05,
                ..law_spec()
            },
        ),
        (
            "quadratic damping 8 N s^2/m^2",
            SpringSpec {
                quadratic_damping_n_s2_m2: 8.0,
                ..law_spec()
            },
        ),
        (
            "friction 0.4 N (sticks)",
            SpringSpec {
                friction_n: 0.4,
                ..law_spec()
            },
        ),
    ] {
        let r = run_with_law(&s, 0.0);
        let n = r.full_a.len();
        let effect = relative_max_difference(&r.full_a, &linear.full_a);
        let held = (0..n).filter(|&k| r.held(k)).count();
        let sliding = r.accel_error(false);
        eprintln!(
            "{name}: max |reduced - full| = {sliding:e} of the peak while sliding \
             ({} of {n} samples); the law moves the full response by {effect:.4} of the \
             peak; last/first cycle peak {:.4}",
            n - held,
            decay(&r.full_a)
        );
        assert!(sliding < 1e-4, "{name}: {sliding:e}");
        // The comparison can fail: the law's own effect is far above the bound.
        assert!(effect > 0.05, "{name}: {effect}");
        assert_eq!(r.held_mismatches(), 0, "{name}: held at different samples");
        if held > 0 {
            let first = (0..n).find(|&k| r.held(k)).unwrap_or(n);
            let amplitude = r.full_u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let rest = (r.reduced[n - 1].u * 1e-3 - r.full_u[n - 1]).abs() / amplitude;
            let stuck = r.accel_error(true);
            let (w, dt) = (2.0 * PI / 0.23, s.dt_s);
            eprintln!(
                "  held at {held} samples from {:.3} s; rest position {:.6} mm (full), \
                 differs by {rest:e} of the amplitude; held acceleration differs by \
                 {stuck:e} of the peak (bound {:e})",
                first as f64 * dt,
                r.full_u[n - 1] * 1e3,
                2.0 / (w * dt) * 1e-4
            );
            assert!(rest < 1e-4, "{name}: rest {rest:e}");
            assert!(stuck < 2.0 / (w * dt) * 1e-4, "{name}: held {stuck:e}");
            // Held for a second sample in a row, the weight has no acceleration in
            // either model: the steppers zero a held DOF's acceleration after the step
            // that stopped it (without that, the trapezoidal rule flips its sign at
            // every step).
            for k in 1..n {
                if r.held(k) && r.held(k - 1) {
                    assert_eq!(r.full_a[k], 0.0, "{name}: full a at held sample {k}");
                    assert_eq!(r.reduced[k].a, 0.0, "{name}: reduced a at held sample {k}");
                }
            }
        }
    }
}

/// The reduced model with a cubic spring at the weight under gravity against the full
/// FE transient with the same card: a static case under the weight's own weight first
/// (the full model's Newton on the cubic, to 1e-12; the dense stepper's Newton on the
/// reduced energy), then the free decay about that preload (x0 ~ 12.4 mm). k3 =
/// 1.5e6 N/m^3 makes `k3 x0^2` ~ 6 % of k: the tangent stiffness 18 % above k, and the
/// quadratic term of the restoring force about the preload, `3 k3 x0 y^2`, ~4 % of
/// the linear one at the amplitude (the spec's cubic_stiffness with eps ~ 0.05).
/// Tolerance as for the dissipative laws: the law is solved exactly in both, so what
/// is left is the reduction's 3.9e-5: bound 1e-4. The preloads agree to 7e-11 with or
/// without the cubic (measured): the rounding of the Schur complement that the static
/// test bounds by `100 eps K_bb / K`, not the Newton tolerances; asserted below 1e-8,
/// an offset whose spring force, `1e-8 k x0`, is 1e-8 x 5 of the peak inertia force.
#[test]
fn dense_stepper_with_a_cubic_spring_under_gravity_follows_the_full_transient() {
    let g = 9.81;
    // The static case first: the transient starts from its displacement.
    let preloaded = || SpringSpec {
        analyses: vec![AnalysisKind::Static, AnalysisKind::Transient],
        ..law_spec()
    };
    let linear = run_with_law(&preloaded(), g);
    eprintln!(
        "gravity, no law: max |reduced - full| = {:e} of the peak",
        linear.error()
    );
    let s = SpringSpec {
        cubic_stiffness_n_m3: 1.5e6,
        ..preloaded()
    };
    let r = run_with_law(&s, g);
    let effect = relative_max_difference(&r.full_a, &linear.full_a);
    let error = r.error();
    eprintln!(
        "gravity, cubic 1.5e6 N/m^3: max |reduced - full| = {error:e} of the peak; the law \
         moves the full response by {effect:.4} of the peak"
    );
    assert!(error < 1e-4, "{error:e}");
    assert!(effect > 0.05, "{effect}");
    for (name, r) in [("no law", &linear), ("cubic", &r)] {
        assert!(
            r.preload_error.abs() < 1e-8,
            "{name}: {:e}",
            r.preload_error
        );
    }
}
