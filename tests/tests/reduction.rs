//! The Craig-Bampton reduced model (`coil_solver::reduce`) and the dense stepper
//! (`coil_solver::integrate::dense`) on the paper's spring, against the full FE model
//! (static, modal, transient) and the helix closed forms.
//!
//! Spring: coil-mesh's paper spring (n = 14, D = 24 mm, d = 3 mm, h = 6.2 mm,
//! E = 190708 MPa, nu = 0.3, 7850 kg/m^3, type 98, 24 elements per coil), weight
//! 5.27 kg on node 1 (period ~0.23 s). Numbers print with `--nocapture`; docs/reduction.md
//! quotes them.

use coil_mesher::closed_form::HelixStiffness;
use coil_mesher::{AnalysisKind, SpringSpec, Top, WEIGHT_ACCEL_COLUMN, WEIGHT_NODE};
use coil_solver::analysis::{run, CaseSolution, ModalSolution, System};
use coil_solver::dof::DofStatus;
use coil_solver::integrate::DenseStepper;
use coil_solver::model::{units, Model};
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
    stiffer.materials[0].youngs_modulus *= 1.1;
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
    for fixed in &mut model.fixed_disp {
        if fixed.nodes == [base] {
            fixed.dofs.retain(|&(d, _)| d != 3);
        }
    }
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
