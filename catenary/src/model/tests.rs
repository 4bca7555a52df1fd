//! The catenary model's unit tests: the grid, the static state, the deck's read-back.

use super::*;

/// A 2-span catenary of the EN 50318 wires, 1 m elements, 30 mm presag.
pub(crate) fn small() -> CatenaryDeckSpec {
    let mut spec = CatenaryDeckSpec::en50318_reference(2, 1.0);
    spec.catenary.presag_mm = 30.0;
    spec
}

#[test]
fn the_grid_has_nodes_at_droppers_and_supports() {
    let spec = small();
    let grid = Grid::new(&spec.catenary);
    assert_eq!(grid.droppers.len(), 18);
    assert_eq!(grid.supports.len(), 3);
    assert!((grid.x[grid.droppers[9]] - 65_000.0).abs() < 1e-9);
    assert!((grid.x[grid.supports[2]] - 120_000.0).abs() < 1e-9);
    let longest = grid.x.windows(2).fold(0.0_f64, |m, w| m.max(w[1] - w[0]));
    assert!(longest <= 1000.0 + 1e-9, "{longest}");
}

#[test]
fn the_static_state_meets_the_presag_and_balances_the_weight() {
    let spec = small();
    let built = build(&spec).unwrap();
    let s = &built.state;
    println!(
        "presag miss {:.3e} mm after {} corrections; weight {:.3} N, reactions {:.3} N; \
         dropper forces {:.2}..{:.2} N",
        s.presag_miss_mm,
        s.iterations,
        s.weight_n,
        s.support_reactions_n,
        s.dropper_force_n.iter().cloned().fold(f64::MAX, f64::min),
        s.dropper_force_n.iter().cloned().fold(f64::MIN, f64::max),
    );
    assert!(s.presag_miss_mm <= PRESAG_TOLERANCE_MM);
    // The linear construction is exact: a miss of round-off, no correction needed.
    assert_eq!(s.iterations, 0);
    let mid = s.target_mm[4];
    assert!((mid + 30.0).abs() < 1e-9, "{mid}");
    // Weight: 2 x 60 m of both wires, 18 x 2 clamps, 1 steady arm (interior support).
    let weight = 9.81 * (120.0 * (1.35 + 1.07) + 18.0 * (0.195 + 0.165) + 1.0);
    assert!(
        (s.weight_n - weight).abs() < 1e-9 * weight,
        "{} {weight}",
        s.weight_n
    );
    // Every support (ground nodes, pinned ends) together carries the weight.
    assert!(
        (s.support_reactions_n - weight).abs() < 1e-8 * weight,
        "{} against {weight}",
        s.support_reactions_n
    );
    // Each dropper carries at least the contact wire between it and its neighbours
    // less what the presag's curvature takes (positive: all taut).
    assert!(s.dropper_force_n.iter().all(|&f| f > 0.0));
}

#[test]
fn a_bad_field_is_named() {
    let mut spec = small();
    spec.catenary.droppers.positions_m = vec![5.0, 4.0];
    let e = build(&spec).unwrap_err().to_string();
    assert!(e.contains("catenary.droppers.positions_m"), "{e}");
    let mut spec = small();
    spec.pantograph.stages.clear();
    let e = build(&spec).unwrap_err().to_string();
    assert!(e.contains("pantograph.stages"), "{e}");
    let json = r#"{"catenary": {}, "pantograph": {}, "run": {}, "extra": 1}"#;
    assert!(serde_json::from_str::<CatenaryDeckSpec>(json).is_err());
}

/// The static state's pantograph displacements and a short run's contact force.
fn static_and_force(spec: &CatenaryDeckSpec) -> (Vec<f64>, Vec<f64>) {
    let built = build(spec).unwrap();
    let results = run(&built.model).unwrap();
    let CaseSolution::Static(rest) = &results[0].solution else {
        panic!("not static")
    };
    let CaseSolution::Transient(moving) = &results[1].solution else {
        panic!("not transient")
    };
    let u = (0..spec.pantograph.stages.len() as u32)
        .map(|i| {
            rest.node_displacement(&built.model, PANTOGRAPH_BASE + i)
                .unwrap()[2]
        })
        .collect();
    let force = moving
        .history
        .column(CONTACT_FORCE_COLUMN)
        .unwrap()
        .to_vec();
    (u, force)
}

#[test]
fn a_stage_matrix_equal_to_the_bar_is_the_lumped_stage() {
    // 2 spans, the head run over the first 15 m (216 steps at 250 km/h).
    let mut lumped = small();
    lumped.run.end_m = Some(15.0);
    let mut matrix = lumped.clone();
    let (k, c) = (4.2, 10e-3); // N/mm, N s/mm: the head stage's bar and dashpot
    let stage = &mut matrix.pantograph.stages[0];
    stage.damping_n_s_m = 0.0;
    stage.matrix = Some(StageMatrix {
        stiffness: vec![k, -k, -k, k],
        mass: vec![0.0; 4],
        damping: Some(vec![c, -c, -c, c]),
    });
    let built = build(&matrix).unwrap();
    assert_eq!(built.model.matrix_elements().len(), 1);
    let (u0, f0) = static_and_force(&lumped);
    let (u1, f1) = static_and_force(&matrix);
    let scale = f0.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    let worst = f0
        .iter()
        .zip(&f1)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "static u {u0:?} / {u1:?} mm; {} samples, contact force up to {scale:.2} N, \
         largest difference {worst:e} N",
        f0.len()
    );
    assert_eq!(f0.len(), f1.len());
    for (a, b) in u0.iter().zip(&u1) {
        assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{a} {b}");
    }
    assert!(worst <= 1e-9 * scale, "{worst} N of {scale} N");
    // The force moves during the run (the comparison is not of a constant).
    let spread =
        f0.iter().fold(f64::MIN, |m, &f| m.max(f)) - f0.iter().fold(f64::MAX, |m, &f| m.min(f));
    assert!(spread > 1.0, "{spread}");
}

#[test]
fn a_stage_matrix_with_modes_gets_its_nodes_and_a_bad_one_is_named() {
    // One modal coordinate: a mass-normalised mode of 100 rad/s coupled to the ends.
    let mut spec = small();
    spec.run.end_m = Some(1.0);
    let (k, w2, g) = (4.2, 1e4, 50.0);
    let stage = &mut spec.pantograph.stages[0];
    stage.damping_n_s_m = 0.0;
    // K_bm = [-g, g]: the static stiffness is k - g^2 / w2 on the upper end.
    stage.stiffness_n_m = (k - g * g / w2) * 1e3;
    stage.matrix = Some(StageMatrix {
        stiffness: vec![k, -k, -g, -k, k, g, -g, g, w2],
        mass: vec![1e-4, 0.0, 0.0, 0.0, 1e-4, 0.0, 0.0, 0.0, 1.0],
        damping: None,
    });
    let built = build(&spec).unwrap();
    let e = &built.model.matrix_elements()[0];
    assert_eq!(
        e.dofs,
        [
            (PANTOGRAPH_BASE + 1, 3),
            (PANTOGRAPH_BASE, 3),
            (PANTOGRAPH_MODAL_BASE, 1)
        ]
    );
    assert!(run(&built.model).is_ok());
    let text = coil_solver::deck::write(&built.model);
    let back = coil_solver::deck::read_str(&text, "catenary.dat").unwrap();
    assert_eq!(back, built.model);

    let bad = |f: &dyn Fn(&mut StageSpec)| {
        let mut s = spec.clone();
        f(&mut s.pantograph.stages[0]);
        build(&s).unwrap_err().to_string()
    };
    let e = bad(&|s| {
        s.matrix
            .as_mut()
            .unwrap()
            .stiffness
            .pop()
            .map(drop)
            .unwrap()
    });
    assert!(e.contains("pantograph.stages.matrix.stiffness"), "{e}");
    let e = bad(&|s| s.matrix.as_mut().unwrap().damping = Some(vec![0.0; 4]));
    assert!(e.contains("pantograph.stages.matrix.damping"), "{e}");
    let e = bad(&|s| s.stiffness_n_m = 4200.0);
    assert!(e.contains("pantograph.stages.stiffness_n_m"), "{e}");
    let e = bad(&|s| s.damping_n_s_m = 10.0);
    assert!(e.contains("pantograph.stages.damping_n_s_m"), "{e}");
    let e = bad(&|s| s.matrix.as_mut().unwrap().mass[1] = 1.0);
    assert!(
        e.contains("pantograph.stages.matrix") && e.contains("symmetric"),
        "{e}"
    );
}

#[test]
fn the_deck_reads_back_to_the_same_model() {
    let mut spec = small();
    spec.catenary.spans = 1;
    let built = build(&spec).unwrap();
    let text = coil_solver::deck::write(&built.model);
    let back = coil_solver::deck::read_str(&text, "catenary.dat").unwrap();
    assert_eq!(back, built.model);
}
