//! The spring spec's checks and the model it builds: nodes on the helix, ids, field errors,
//! deck round trip, transient and nonlinear options.

use super::*;

#[test]
fn titles_are_one_printable_line() {
    for bad in ["x\nEND OPTION", "a\rb", "esc \u{1b}[2J", "\u{202e}rev"] {
        let spec = SpringSpec {
            title: bad.into(),
            ..Default::default()
        };
        let e = spec.validate().unwrap_err().to_string();
        assert!(e.starts_with("title = "), "{e}");
        assert!(!e.contains('\n') && !e.contains('\u{1b}'), "{e}");
    }
    let long = SpringSpec {
        title: "t".repeat(201),
        ..Default::default()
    };
    assert!(long.validate().is_err());
    let fine = SpringSpec {
        title: "spring #3, rig \"B\"".into(),
        ..Default::default()
    };
    fine.validate().unwrap();
}

#[test]
fn every_node_lies_on_the_helix() {
    let spec = SpringSpec {
        elements_per_coil: 7,
        coils: 3.5,
        ..SpringSpec::default()
    };
    let model = spec.build().unwrap();
    let r = 12.0;
    assert_eq!(model.elements().len(), 25); // round(3.5 * 7) = 24.5 -> 25 (round half away)
    for node in model.nodes().iter().skip(1) {
        let [x, y, z] = node.xyz;
        assert!(((x * x + y * y).sqrt() - r).abs() < 1e-12);
        // Angle recovered from z must match the angle of (x, y).
        let t = 2.0 * PI * z / 6.2;
        assert!((r * t.cos() - x).abs() < 1e-9 && (r * t.sin() - y).abs() < 1e-9);
    }
    let top = model.nodes().last().unwrap().xyz;
    assert!((top[2] - 3.5 * 6.2).abs() < 1e-12);
    assert_eq!(model.nodes()[0].xyz, [0.0, 0.0, 3.5 * 6.2]);
}

#[test]
fn the_spring_index_range_admits_soft_laboratory_springs_and_refuses_unit_slips() {
    // D = 30 mm, d = 1 mm (index 30): a soft laboratory spring, above EN 13906-1's 20.
    let index = |mean_diameter_mm: f64, wire_diameter_mm: f64| SpringSpec {
        mean_diameter_mm,
        wire_diameter_mm,
        pitch_mm: 2.0 * wire_diameter_mm.max(1.0),
        ..SpringSpec::default()
    };
    assert!(index(30.0, 1.0).validate().is_ok());
    assert!(index(100.0, 1.0).validate().is_ok());
    for (mean, wire) in [(24.0, 23.976), (24.0, 8.5), (150.0, 1.0)] {
        let err = index(mean, wire).validate().unwrap_err();
        assert_eq!(err.field, "spring index D/d", "{mean}/{wire}");
    }
}

#[test]
fn ids_are_sorted_and_elements_chain() {
    let model = SpringSpec::default().build().unwrap();
    assert!(model.nodes().windows(2).all(|w| w[0].id < w[1].id));
    for e in model.elements() {
        assert_eq!(e.nodes[1], e.nodes[0] + 1);
    }
    assert_eq!(model.elements().len(), 14 * 24);
}

#[test]
fn bad_specs_name_the_field() {
    for (spec, field) in [
        (
            SpringSpec {
                wire_diameter_mm: 30.0,
                ..SpringSpec::default()
            },
            "wire_diameter_mm",
        ),
        (
            SpringSpec {
                coils: f64::NAN,
                ..SpringSpec::default()
            },
            "coils",
        ),
        (
            SpringSpec {
                element: 5,
                ..SpringSpec::default()
            },
            "element",
        ),
        (
            SpringSpec {
                elements_per_coil: 2,
                ..SpringSpec::default()
            },
            "elements_per_coil",
        ),
        (
            SpringSpec {
                coils: 1e9,
                ..SpringSpec::default()
            },
            "elements_per_coil",
        ),
        (
            SpringSpec {
                elements_per_coil: 4_000_000_000,
                ..SpringSpec::default()
            },
            "elements_per_coil",
        ),
    ] {
        assert_eq!(spec.build().unwrap_err().field, field);
    }
}

#[test]
fn written_deck_reads_back_equal() {
    for analyses in [
        vec![AnalysisKind::Static],
        vec![
            AnalysisKind::Static,
            AnalysisKind::Modal,
            AnalysisKind::Transient,
        ],
    ] {
        let spec = SpringSpec {
            analyses,
            mass_kg: 5.26,
            rotary_inertia_kg_m2: 1e-3,
            alpha: 0.8,
            beta: 1.2e-4,
            top: Top::FreeRotation,
            elements_per_coil: 8,
            ..SpringSpec::default()
        };
        let model = spec.build().unwrap();
        let text = coil_solver::deck::write(&model);
        let back = coil_solver::deck::read_str(&text, "mesh.dat").unwrap();
        assert_eq!(back, model);
        // Marc's extended fixed format (coil-mesh --format mentat) too.
        let text = coil_solver::deck::write_mentat(&model);
        assert!(text.contains("\nEXTENDED\n"));
        let back = coil_solver::deck::read_str(&text, "mesh_mentat.dat").unwrap();
        assert_eq!(back, model);
    }
}

#[test]
fn transient_choices_reach_the_model() {
    let spec = SpringSpec {
        analyses: vec![AnalysisKind::Transient],
        mass_kg: 5.0,
        alpha: 0.8,
        ..SpringSpec::default()
    };
    let model = spec.build().unwrap();
    assert!(
        model.initial_velocities()[0].quasi_static,
        "the default field"
    );
    assert_eq!(
        model.load_cases()[0].analysis,
        Analysis::Transient {
            dt: 1e-3,
            total_time: 20.0,
            method: TransientMethod::Direct(Integrator::AverageAcceleration)
        }
    );
    let model = SpringSpec {
        initial_velocity_field: VelocityField::Nodal,
        transient_method: TransientScheme::Hht,
        alpha_on_weight: true,
        ..spec.clone()
    }
    .build()
    .unwrap();
    assert!(!model.initial_velocities()[0].quasi_static);
    assert_eq!(model.damping()[0].mass_nodes, [WEIGHT_NODE]);
    assert!(matches!(
        model.load_cases()[0].analysis,
        Analysis::Transient {
            method: TransientMethod::Direct(Integrator::Hht { alpha }),
            ..
        } if alpha == -0.05
    ));
    for (bad, field) in [
        (
            SpringSpec {
                transient_method: TransientScheme::Hht,
                hht_alpha: 0.1,
                ..spec.clone()
            },
            "hht_alpha",
        ),
        (
            SpringSpec {
                transient_method: TransientScheme::Modal,
                transient_modes: 0,
                ..spec.clone()
            },
            "transient_modes",
        ),
        (
            SpringSpec {
                alpha_on_weight: true,
                mass_kg: 0.0,
                ..spec.clone()
            },
            "alpha_on_weight",
        ),
    ] {
        assert_eq!(bad.build().unwrap_err().field, field);
    }
}

#[test]
fn weight_gets_no_alpha() {
    let spec = SpringSpec {
        alpha: 0.8,
        beta: 1.2e-4,
        mass_kg: 5.0,
        ..SpringSpec::default()
    };
    let model = spec.build().unwrap();
    assert_eq!(model.damping().len(), 1);
    assert!(model.damping()[0].mass_nodes.is_empty());
    assert_eq!(model.point_masses()[0].mass, 5e-3);
}

#[test]
fn nonlinear_extras_become_cards_on_the_weight_in_solver_units() {
    let spec = SpringSpec {
        mass_kg: 5.0,
        rotary_inertia_kg_m2: 2e-3,
        friction_n: 0.4,
        quadratic_damping_n_s2_m2: 3.0,
        cubic_stiffness_n_m3: 2e9,
        analyses: vec![AnalysisKind::Static, AnalysisKind::Transient],
        ..SpringSpec::default()
    };
    let model = spec.build().unwrap();
    assert_eq!(model.point_laws().len(), 1);
    let e = model.point_laws()[0];
    assert_eq!((e.node, e.dof), (WEIGHT_NODE, 3));
    assert_eq!(e.friction, 0.4);
    // 3 N s^2/m^2 = 3e-6 N s^2/mm^2; 2e9 N/m^3 = 2 N/mm^3.
    assert!((e.quadratic - 3e-6).abs() < 1e-20);
    assert!((e.cubic - 2.0).abs() < 1e-15);
    assert_eq!(model.point_masses()[0].inertia, [0.0, 0.0, 2.0]);
    let text = coil_solver::deck::write(&model);
    assert_eq!(coil_solver::deck::read_str(&text, "spec").unwrap(), model);
    let text = coil_solver::deck::write_mentat(&model);
    assert_eq!(coil_solver::deck::read_str(&text, "spec").unwrap(), model);
    // Old specs (no such fields) still read, and get no cards.
    let old: SpringSpec = serde_json::from_str(r#"{"coils": 10.0}"#).unwrap();
    assert!(old.build().unwrap().point_laws().is_empty());
    for bad in [
        SpringSpec {
            friction_n: -1.0,
            ..SpringSpec::default()
        },
        SpringSpec {
            cubic_stiffness_n_m3: 1.0,
            top: Top::Held,
            ..SpringSpec::default()
        },
        SpringSpec {
            friction_n: 1.0,
            analyses: vec![AnalysisKind::Transient],
            transient_method: TransientScheme::Hht,
            ..SpringSpec::default()
        },
    ] {
        assert!(bad.build().is_err(), "{bad:?}");
    }
}
