//! Tests of transient load cases against closed forms and invariants.

use super::initial::*;
use super::recording::*;
use super::*;
use crate::analysis::system::System;
use crate::analysis::test_support::tied_frame;
use crate::analysis::{run, CaseSolution};
use crate::dof::DofStatus;
use crate::error::solve::SolveError;
use crate::linalg::sym_upper_matvec;
use crate::model::{
    Analysis, InitialVelocity, Integrator, LoadCase, Model, PointLoad, Quantity, TransientMethod,
};
use crate::model::{Damping, OutputRequest, PointMass, Table};

/// The tied frame with a point mass on the reference node 10 (whose u_z and theta_x
/// are prescribed; node 4 is tied to it).
fn frame() -> Model {
    let mut model = tied_frame();
    model.point_masses.push(PointMass {
        node: 10,
        mass: 2e-3,
        inertia: [0.5, 0.5, 0.5],
    });
    model
}

fn transient_case(dt: f64, total_time: f64, method: TransientMethod) -> LoadCase {
    LoadCase {
        title: "shake".to_string(),
        analysis: Analysis::Transient {
            dt,
            total_time,
            method,
        },
        point_loads: Vec::new(),
    }
}

fn free_eq(system: &System, node: u32, dof: u8) -> usize {
    match system
        .dofs
        .status(system.dofs.full_index(node, dof).unwrap())
    {
        DofStatus::Free(eq) => eq,
        other => panic!("node {node} DOF {dof} is {other:?}"),
    }
}

#[test]
fn quasi_static_velocity_is_the_static_shape_through_the_listed_values() {
    let mut model = frame();
    model.initial_velocities = vec![
        InitialVelocity {
            dofs: vec![(2, 7.0)],
            nodes: vec![3],
            quasi_static: true,
        },
        InitialVelocity {
            dofs: vec![(1, -3.0)],
            nodes: vec![10],
            quasi_static: true,
        },
    ];
    let system = System::new(&model).unwrap();
    let factor = system.factor_stiffness().unwrap();
    let (v, field) = initial_velocity(&system, Some(&factor)).unwrap();
    assert_eq!(field, VelocityField::QuasiStatic);
    let (a, b) = (free_eq(&system, 3, 2), free_eq(&system, 10, 1));
    assert_eq!((v[a], v[b]), (7.0, -3.0));
    // K v is a force at the listed DOFs only: the static shape of two point forces.
    let mut kv = vec![0.0; v.len()];
    sym_upper_matvec(system.stiffness.as_ref(), &v, 1.0, &mut kv);
    let scale = kv[a].abs().max(kv[b].abs());
    for (eq, f) in kv.iter().enumerate() {
        if eq != a && eq != b {
            assert!(f.abs() < 1e-10 * scale, "eq {eq}: {f} vs {scale}");
        }
    }
    assert!(
        v.iter().filter(|x| **x != 0.0).count() > 2,
        "the field spreads"
    );
    // A plain group overrides its DOF after the quasi-static field.
    model.initial_velocities.push(InitialVelocity {
        dofs: vec![(6, 0.25)],
        nodes: vec![2],
        quasi_static: false,
    });
    let system = System::new(&model).unwrap();
    let (w, field) = initial_velocity(&system, Some(&factor)).unwrap();
    assert_eq!(field, VelocityField::Mixed);
    let c = free_eq(&system, 2, 6);
    assert_eq!(w[c], 0.25);
    assert_eq!(w[a], 7.0);
    // Without a factor the quasi-static field is an error, not a silent jump.
    assert!(matches!(
        initial_velocity(&system, None),
        Err(SolveError::BadInput { .. })
    ));
}

#[test]
fn initial_velocity_on_constrained_dofs() {
    let mut model = frame();
    let at = |node, dof, value| InitialVelocity {
        dofs: vec![(dof, value)],
        nodes: vec![node],
        quasi_static: false,
    };
    for (group, what) in [
        (at(10, 3, 5.0), "FIXED DISP"),
        (at(4, 1, 5.0), "RBE2"),
        (at(99, 1, 5.0), "node 99"),
        (at(2, 9, 5.0), "DOF 9"),
        (at(2, 1, f64::NAN), "non-finite"),
    ] {
        model.initial_velocities = vec![group];
        let system = System::new(&model).unwrap();
        let e = initial_velocity(&system, None).unwrap_err().to_string();
        assert!(e.contains(what), "{what}: {e}");
    }
    // Zero on a prescribed or tied DOF is consistent and accepted.
    model.initial_velocities = vec![at(10, 3, 0.0), at(4, 2, 0.0), at(2, 1, 1.0)];
    let system = System::new(&model).unwrap();
    let (v, field) = initial_velocity(&system, None).unwrap();
    assert_eq!(field, VelocityField::Nodal);
    assert_eq!(v.iter().filter(|x| **x != 0.0).count(), 1);
}

#[test]
fn history_columns_are_deduplicated_and_sampled_at_the_gcd() {
    let mut model = frame();
    model.outputs = vec![
        OutputRequest {
            nodes: vec![10],
            dofs: vec![1, 3],
            quantities: vec![Quantity::Displacement, Quantity::Velocity],
            every: 4,
        },
        OutputRequest {
            nodes: vec![10, 1, 4],
            dofs: vec![1],
            quantities: vec![Quantity::Displacement],
            every: 6,
        },
    ];
    model.initial_velocities = vec![InitialVelocity {
        dofs: vec![(1, 100.0)],
        nodes: vec![10],
        quasi_static: false,
    }];
    model.load_cases = vec![transient_case(
        1e-5,
        1e-4,
        TransientMethod::Direct(Integrator::AverageAcceleration),
    )];
    let cases = run(&model).unwrap();
    let CaseSolution::Transient(t) = &cases[0].solution else {
        panic!("transient expected")
    };
    assert_eq!(t.output_every, 2);
    assert_eq!(t.steps, 10);
    assert_eq!(t.history.time_s.len(), 6);
    assert!((t.history.time_s[5] - 1e-4).abs() < 1e-18);
    assert_eq!(
        t.history.names(),
        [
            "node10_ux_disp_m",
            "node10_ux_vel_m_s",
            "node10_uz_disp_m",
            "node10_uz_vel_m_s",
            "node1_ux_disp_m",
            "node4_ux_disp_m",
        ]
    );
    // The prescribed u_z = 0.25 mm of node 10, in m; the clamped node stays at 0.
    let uz = t.history.column("node10_uz_disp_m").unwrap();
    assert!(uz.iter().all(|&x| (x - 0.25e-3).abs() < 1e-15));
    assert!(t
        .history
        .column("node10_uz_vel_m_s")
        .unwrap()
        .iter()
        .all(|&x| x == 0.0));
    assert!(t
        .history
        .column("node1_ux_disp_m")
        .unwrap()
        .iter()
        .all(|&x| x == 0.0));
    assert_eq!(t.history.column("node10_ux_vel_m_s").unwrap()[0], 0.1);
    assert_eq!(t.velocity_field, VelocityField::Nodal);
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
}

#[test]
fn off_grid_breakpoints_and_partial_steps_warn() {
    let mut model = frame();
    model.tables.push(Table {
        name: "kick".to_string(),
        points: vec![(0.0, 0.0), (1.5e-5, 1.0), (3e-5, 0.0)],
    });
    model.point_loads.push(PointLoad {
        dofs: vec![(2, 1.0)],
        nodes: vec![3],
        table: Some("KICK".to_string()),
    });
    model.load_cases = vec![transient_case(
        1e-5,
        1.05e-4,
        TransientMethod::Direct(Integrator::Hht { alpha: -0.1 }),
    )];
    let cases = run(&model).unwrap();
    let CaseSolution::Transient(t) = &cases[0].solution else {
        panic!("transient expected")
    };
    assert_eq!(t.steps, 11);
    assert_eq!(t.warnings.len(), 3, "{:?}", t.warnings);
    assert!(t.warnings[0].contains("11 steps"), "{}", t.warnings[0]);
    assert!(
        t.warnings[1].contains("table 'kick' has 1 breakpoint(s)"),
        "{}",
        t.warnings[1]
    );
    assert!(
        t.warnings[2].contains("HISTORY OUTPUT"),
        "{}",
        t.warnings[2]
    );
    // A step count beyond reason is an error naming it.
    model.load_cases = vec![transient_case(
        1e-12,
        10.0,
        TransientMethod::Direct(Integrator::AverageAcceleration),
    )];
    assert!(run(&model).unwrap_err().to_string().contains("steps"));
}

#[test]
fn override_keeps_or_replaces_the_method() {
    let mut model = frame();
    let hht = TransientMethod::Direct(Integrator::Hht { alpha: -0.1 });
    model.load_cases = vec![
        transient_case(1e-4, 1e-3, hht),
        transient_case(1e-4, 1e-3, TransientMethod::Modal { modes: 3 }),
    ];
    let methods = |m: &Model| -> Vec<TransientMethod> {
        m.load_cases
            .iter()
            .map(|c| match c.analysis {
                Analysis::Transient { method, .. } => method,
                _ => panic!("transient expected"),
            })
            .collect()
    };
    let mut direct = model.clone();
    override_method(&mut direct, MethodOverride::Direct);
    assert_eq!(
        methods(&direct),
        [
            hht,
            TransientMethod::Direct(Integrator::AverageAcceleration)
        ]
    );
    let mut modal = model.clone();
    override_method(&mut modal, MethodOverride::Modal { modes: None });
    assert_eq!(
        methods(&modal),
        [
            TransientMethod::Modal {
                modes: DEFAULT_MODAL_MODES
            },
            TransientMethod::Modal { modes: 3 }
        ]
    );
    override_method(&mut model, MethodOverride::Modal { modes: Some(5) });
    assert_eq!(methods(&model), [TransientMethod::Modal { modes: 5 }; 2]);
}

/// Histories of the frame by modal superposition over every mode (exact: classical
/// damping, alpha and beta on every element and the point mass) and by direct
/// average acceleration at `dts`; returns the largest difference of each direct run
/// relative to the largest displacement. Outputs include a tied node (4) and a
/// prescribed DOF (node 10 u_z = 0.25 mm).
fn direct_against_exact_modal(pulse: bool, dts: &[f64]) -> Vec<f64> {
    let mut model = frame();
    model.damping.push(Damping {
        alpha: 50.0,
        beta: 2e-6,
        elements: vec![1, 2, 3],
        mass_nodes: vec![10],
    });
    if pulse {
        model.tables.push(Table {
            name: "pulse".to_string(),
            points: vec![(0.0, 0.0), (2e-4, 1.0), (4e-4, 0.0)],
        });
        model.point_loads.push(PointLoad {
            dofs: vec![(2, 3.0)],
            nodes: vec![10],
            table: Some("pulse".to_string()),
        });
    }
    model.initial_velocities = vec![InitialVelocity {
        dofs: vec![(1, 50.0)],
        nodes: vec![10],
        quasi_static: true,
    }];
    model.outputs = vec![OutputRequest {
        nodes: vec![4, 10],
        dofs: vec![1, 2, 3],
        quantities: vec![Quantity::Displacement],
        every: 1,
    }];
    let n = System::new(&model).unwrap().dim() as u32;
    let fine = dts.iter().copied().fold(f64::INFINITY, f64::min);
    let history = |dt: f64, method| {
        let mut m = model.clone();
        // The static case puts the frame in equilibrium under the prescribed u_z, so
        // the motion starts smoothly from the initial velocity (and the pulse).
        m.load_cases = vec![
            LoadCase {
                title: "rest".to_string(),
                analysis: Analysis::Static {
                    steps: 1,
                    time: 1.0,
                },
                point_loads: Vec::new(),
            },
            transient_case(dt, 4e-3, method),
        ];
        let cases = run(&m).unwrap();
        match &cases[1].solution {
            CaseSolution::Transient(t) => t.clone(),
            _ => panic!("transient expected"),
        }
    };
    let exact = history(fine, TransientMethod::Modal { modes: n });
    let summary = exact.modal.as_ref().unwrap();
    assert!(summary.capture.max_damping_coupling < 1e-9);
    assert!((summary.capture.initial_velocity_captured.unwrap() - 1.0).abs() < 1e-9);
    if pulse {
        assert!((summary.capture.load_captured.unwrap() - 1.0).abs() < 1e-9);
    }
    let uz = exact.history.column("node10_uz_disp_m").unwrap();
    assert!(uz.iter().all(|&x| (x - 0.25e-3).abs() < 1e-15));
    dts.iter()
        .map(|&dt| {
            let direct = history(dt, TransientMethod::Direct(Integrator::AverageAcceleration));
            let stride = (dt / fine).round() as usize;
            let mut worst: f64 = 0.0;
            let mut size: f64 = 0.0;
            for (a, b) in direct.history.columns.iter().zip(&exact.history.columns) {
                assert_eq!(a.name, b.name);
                for (k, x) in a.values.iter().enumerate() {
                    worst = worst.max((x - b.values[k * stride]).abs());
                    size = size.max(x.abs());
                }
            }
            worst / size
        })
        .collect()
}

#[test]
fn modal_with_every_mode_matches_direct_integration() {
    let smooth = direct_against_exact_modal(false, &[4e-5, 2e-5, 1e-5]);
    let pulse = direct_against_exact_modal(true, &[4e-5, 2e-5, 1e-5]);
    eprintln!("direct vs exact modal: smooth {smooth:?}, pulse {pulse:?}");
    // Halving dt divides the error by 4: second order, also through the pulse, whose
    // breakpoints lie on every step grid (measured 3.6e-6, 9.0e-7, 2.2e-7).
    for errors in [&smooth, &pulse] {
        for pair in errors.windows(2) {
            assert!((pair[0] / pair[1] - 4.0).abs() < 0.2, "{errors:?}");
        }
        assert!(errors[2] < 1e-6, "{errors:?}");
    }
}

#[test]
fn column_names_carry_si_units() {
    assert_eq!(
        column_name(1, 3, Quantity::Acceleration),
        "node1_uz_accel_m_s2"
    );
    assert_eq!(
        column_name(12, 1, Quantity::Displacement),
        "node12_ux_disp_m"
    );
    assert_eq!(column_name(7, 5, Quantity::Velocity), "node7_ry_vel_rad_s");
    assert_eq!(
        column_name(7, 6, Quantity::Acceleration),
        "node7_rz_accel_rad_s2"
    );
    assert_eq!(
        column_name(7, 4, Quantity::Displacement),
        "node7_rx_disp_rad"
    );
}

#[test]
fn csv_round_trips_values_exactly() {
    let history = History {
        time_s: vec![0.0, 0.001, 0.002],
        columns: vec![HistoryColumn {
            name: "node1_uz_disp_m".to_string(),
            values: vec![1.0 / 3.0, -2.5e-300, 0.0],
        }],
    };
    let csv = history.to_csv();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("time_s,node1_uz_disp_m"));
    for (row, line) in lines.enumerate() {
        let fields: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(fields[0], history.time_s[row]);
        assert_eq!(fields[1], history.columns[0].values[row]);
    }
}
