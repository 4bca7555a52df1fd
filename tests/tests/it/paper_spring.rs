//! End-to-end checks on the paper's spring (n = 14, D = 24 mm, d = 3 mm, h = 6.2 mm,
//! E = 190708 MPa, nu = 0.3, weight guided): mesher -> deck text -> reader -> solver,
//! against the Castigliano helix stiffness, the paper's Table 4 ratios and the closed-form
//! mass-spring and surge frequencies.

use coil_mesher::closed_form::{
    rayleigh_period_s, simple_stiffness, surge_frequency_hz, HelixStiffness,
};
use coil_mesher::{AnalysisKind, SpringSpec, Top, WEIGHT_NODE};
use coil_solver::analysis::{run, CaseSolution, ModalSolution};
use coil_solver::model::units;

use coil_tests::{chord_stiffening, paper_spec, through_deck, PAPER_YOUNGS_MODULUS_MPA as E_PAPER};

/// Meshes, writes the deck, reads it back (so the whole text path is exercised) and runs.
fn solve(spec: &SpringSpec) -> Vec<CaseSolution> {
    run(&through_deck(spec))
        .expect("solves")
        .into_iter()
        .map(|c| c.solution)
        .collect()
}

fn static_k(spec: &SpringSpec) -> f64 {
    let spec = SpringSpec {
        analyses: vec![AnalysisKind::Static],
        ..spec.clone()
    };
    match &solve(&spec)[0] {
        CaseSolution::Static(s) => {
            assert_eq!(s.reference_node, Some(WEIGHT_NODE));
            s.stiffness_n_mm.expect("stiffness at the weight")
        }
        other => panic!("expected a static case, got {other:?}"),
    }
}

fn modal(spec: &SpringSpec) -> ModalSolution {
    match solve(spec).pop() {
        Some(CaseSolution::Modal(m)) => m,
        other => panic!("expected a modal case, got {other:?}"),
    }
}

/// The mode with the largest effective mass along the spring axis (global z).
fn axial_mode(m: &ModalSolution) -> &coil_solver::analysis::Mode {
    m.modes
        .iter()
        .max_by(|a, b| a.effective_mass[2].total_cmp(&b.effective_mass[2]))
        .expect("at least one mode")
}

#[test]
fn stiffness_converges_monotonically_to_castigliano() {
    let geometry = paper_spec().geometry();
    let closed = HelixStiffness::new(&geometry, E_PAPER, 0.3);
    for (element, reference) in [(98, closed.guided(true)), (52, closed.guided(false))] {
        let ks: Vec<f64> = [8, 16, 24, 48, 96, 192]
            .iter()
            .map(|&m| {
                static_k(&SpringSpec {
                    elements_per_coil: m,
                    element,
                    ..paper_spec()
                })
            })
            .collect();
        eprintln!("type {element}: K = {ks:?}, Castigliano (guided) = {reference}");
        // docs/formulation.md's mesh table prints these K to four decimals (and the
        // README's quickstart the type-98 column): the page must say what the code gives.
        let printed: [f64; 6] = if element == 98 {
            [4.3762, 3.9397, 3.8641, 3.8195, 3.8084, 3.8056]
        } else {
            [4.4193, 3.9753, 3.8985, 3.8531, 3.8419, 3.8391]
        };
        for (k, p) in ks.iter().zip(printed) {
            assert!(
                (k - p).abs() <= 5e-5 + 1e-12,
                "type {element}: K = {k} prints as {p} in docs/formulation.md"
            );
        }
        // An inscribed polygon has a shorter wire than the helix, so K falls as the mesh
        // is refined: strictly monotone.
        assert!(ks.windows(2).all(|w| w[1] < w[0]), "not monotone: {ks:?}");
        // The chord bias shrinks as (pi/m)^2: at 192 elements per coil it is ~1e-4, so the
        // finest mesh must sit within 0.5 % of the closed form (which neglects the end
        // effects of the clamped base and the rigid tie, well under 0.5 %).
        let finest = ks[ks.len() - 1];
        assert!(
            (finest / reference - 1.0).abs() < 5e-3,
            "type {element}: K = {finest} vs Castigliano {reference}"
        );
        // The independent reference at every mesh: Castigliano times the chord factor
        // (`coil_tests::chord_stiffening`, geometry alone), times one end-region factor
        // (the clamped base and the rigid arm of the tie, which the closed form leaves
        // out) that does not depend on the mesh. Measured: the excess is 0.04, 0.13, 0.145,
        // 0.155, 0.157, 0.158 % from 8 to 192 elements per coil for type 98, 0.146 to
        // 0.159 % for type 52. From 24 elements per coil on, the chord series' next term,
        // O(theta^4) ~ (pi/12)^4 / 20 = 2.3e-4, bounds how far the excess may move from
        // the finest mesh's; the end regions must stiffen (excess > 0) by less than 0.3 %.
        let excess: Vec<f64> = [8, 16, 24, 48, 96, 192]
            .iter()
            .zip(&ks)
            .map(|(&m, k)| k / (reference * chord_stiffening(m, 0.3)) - 1.0)
            .collect();
        eprintln!("type {element}: K / (Castigliano x chord factor) - 1 = {excess:?}");
        let end_region = excess[excess.len() - 1];
        assert!(
            (0.0..3e-3).contains(&end_region),
            "type {element}: {excess:?}"
        );
        for (m, e) in [8, 16, 24, 48, 96, 192].iter().zip(&excess).skip(2) {
            assert!(
                (e - end_region).abs() < 3e-4,
                "type {element}, {m} elements per coil: excess {e} vs {end_region} at 192"
            );
        }
    }
}

/// The closed forms docs/formulation.md prints for the paper's spring, at its precision:
/// Castigliano with the end guided, 3.7987 N/mm with direct shear (type 98) and 3.8320
/// without (type 52); guiding the end stiffens by +0.05 %; the paper's Eq. (1) 3.837.
/// Each is a formula of `coil_mesher::closed_form`; the test keeps the page's numbers
/// equal to what the formulas give (and the README's 3.7987 and 3.8373 with them).
#[test]
fn the_closed_forms_print_as_docs_formulation_states() {
    let geometry = paper_spec().geometry();
    let helix = HelixStiffness::new(&geometry, E_PAPER, 0.3);
    let near = |value: f64, quoted: f64, unit: f64| (value - quoted).abs() <= unit / 2.0 + 1e-12;
    let (with_shear, without) = (helix.guided(true), helix.guided(false));
    assert!(
        near(with_shear, 3.7987, 1e-4),
        "type 98 Castigliano {with_shear}"
    );
    assert!(near(without, 3.8320, 1e-4), "type 52 Castigliano {without}");
    let guided_gain = 100.0 * (with_shear / helix.free(true) - 1.0);
    assert!(near(guided_gain, 0.05, 0.01), "guided end +{guided_gain} %");
    let eq1 = simple_stiffness(&geometry, E_PAPER / 2.6);
    assert!(near(eq1, 3.8373, 1e-4), "Eq. (1) {eq1}");
}

/// The K quoted across the README and the docs, 3.8641 N/mm (24 type-98 elements per
/// coil, E = 190708 MPa), against the independent reference of the test above:
/// Castigliano (guided end, with shear, 3.7987 N/mm) times the chord factor (1.01573),
/// times the end regions' stiffening, bounded by 0 and 0.3 %; the chord series' remainder
/// (3e-4) widens the bracket: 3.8573 to 3.8700 N/mm. (The finest mesh puts the end
/// regions at 0.16 %, which leaves 3.8645.)
#[test]
fn the_quoted_k_at_24_elements_per_coil_is_castigliano_with_the_chord_correction() {
    let geometry = paper_spec().geometry();
    let castigliano = HelixStiffness::new(&geometry, E_PAPER, 0.3).guided(true);
    let chorded = castigliano * chord_stiffening(24, 0.3);
    let bracket = chorded * (1.0 - 3e-4)..chorded * (1.0 + 3e-3 + 3e-4);
    let k = static_k(&paper_spec());
    eprintln!("K(24) = {k}, Castigliano x chord factor {chorded}, bracket {bracket:?}");
    assert!(bracket.contains(&k), "K = {k} outside {bracket:?}");
    assert!(
        bracket.contains(&3.8641),
        "the quoted 3.8641 outside {bracket:?}"
    );
    // The one regression pin of that number (coil's own output when it was written, not a
    // reference): the README, docs/formulation.md and docs/transient.md quote it.
    assert!(
        (k - 3.8641).abs() <= 5e-5,
        "K = {k} no longer prints as the quoted 3.8641"
    );
}

#[test]
fn table4_stiffness_ratios_match_the_paper() {
    // K of each variant over K of the base spring, with the same E: the paper's Table 4
    // values divided by its validated base K = 3.927506 N/mm (Table 3).
    let table = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../cases/160ect/table4.json"
    ))
    .expect("cases/160ect/table4.json");
    let table: serde_json::Value = serde_json::from_str(&table).expect("valid JSON");
    let base = static_k(&paper_spec());
    for v in table["variants"].as_array().expect("variants") {
        let f = |key: &str| v[key].as_f64().expect(key);
        let spec = SpringSpec {
            coils: f("active_coils"),
            mean_diameter_mm: f("mean_diameter_mm"),
            wire_diameter_mm: f("wire_diameter_mm"),
            pitch_mm: f("pitch_mm"),
            ..paper_spec()
        };
        let ratio = static_k(&spec) / base;
        let paper = f("paper_stiffness_n_mm") / 3.927506;
        eprintln!("{}: coil {ratio:.5}, paper {paper:.5}", v["name"]);
        // The paper prints K to 4 significant figures (<= 0.03 % rounding); 0.5 % is the
        // issue's bound.
        assert!(
            (ratio / paper - 1.0).abs() < 5e-3,
            "{}: ratio {ratio} vs paper {paper}",
            v["name"]
        );
    }
}

#[test]
fn axial_mode_period_matches_rayleigh_mass_correction() {
    let k = static_k(&paper_spec());
    // The weight for 2 pi sqrt(m/K) = 0.23 s.
    let mass_kg = k * 1000.0 * (0.23 / (2.0 * std::f64::consts::PI)).powi(2);
    let spec = SpringSpec {
        mass_kg,
        analyses: vec![AnalysisKind::Modal],
        modes: 6,
        ..paper_spec()
    };
    let m = modal(&spec);
    let axial = axial_mode(&m);
    let spring_kg = spec.geometry().spring_mass_kg(7850.0);
    let expected = rayleigh_period_s(k, mass_kg, spring_kg);
    eprintln!(
        "axial mode T = {} s, Rayleigh {} s, effective mass {} kg",
        axial.period_s,
        expected,
        units::mass_to_si(axial.effective_mass[2])
    );
    // Rayleigh's m/3 is exact to O((m_s/m)^2) ~ 1e-4 relative in the period here.
    assert!((axial.period_s / expected - 1.0).abs() < 5e-4);
    // The axial mode carries (almost) all of the moving mass.
    assert!(units::mass_to_si(axial.effective_mass[2]) > mass_kg);
}

#[test]
fn surge_mode_of_the_held_bare_spring() {
    let spec = SpringSpec {
        top: Top::Held,
        mass_kg: 0.0,
        analyses: vec![AnalysisKind::Modal],
        modes: 30,
        ..paper_spec()
    };
    let k = HelixStiffness::new(&spec.geometry(), E_PAPER, 0.3).guided(true);
    let expected = surge_frequency_hz(k, spec.geometry().spring_mass_kg(7850.0));
    let m = modal(&spec);
    let surge = axial_mode(&m);
    eprintln!(
        "surge f = {} Hz, closed form {} Hz",
        surge.frequency_hz, expected
    );
    // The closed form treats the spring as a uniform axial rod; the helix's axial-torsional
    // coupling and the discrete coils shift it slightly: 3 % is the bound.
    assert!((surge.frequency_hz / expected - 1.0).abs() < 0.03);
}
