//! `coil-tune check` and `coil-tune design` end to end on the springs of
//! `cases/spring-design`: HeliSpring's verification spring read from its case file, the
//! 160ECT sheet beside coil's FE and the measured K, and the three designs of the
//! acceptance (the 160ECT spring, Table 4 #2 and #4 as targets) with every short-listed
//! deck read back and solved. The calibration is loops 1 and 2 of the paper's case
//! (E to K, mass to T, seconds) with the paper's Rayleigh pair, written as the
//! calibration.json `coil-tune calibrate` writes (its `state`, `targets`, `settings`).

use coil_design::sheet::{check, input::read_spring};
use coil_design::target::{read_target, MaterialSource, Objective};
use coil_design::{design, output, DesignSettings};
use coil_tuner::case::{read_case, read_variants};
use coil_tuner::fe::{self, FeSettings, SpringState};
use coil_tuner::loops::{tune_mass, tune_youngs_modulus};
use coil_tuner::output::OutDir;
use std::path::{Path, PathBuf};

fn cases() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases")
}

/// The paper's case calibrated by loops 1 and 2 (the tuner test's settings), with the
/// paper's alpha and beta: a calibration.json in `dir`.
fn calibration(dir: &Path) -> (PathBuf, SpringState) {
    let case = read_case(&cases().join("160ect")).unwrap();
    let mut state = SpringState::nominal(&case);
    let settings = FeSettings::default();
    tune_youngs_modulus(&mut state, &settings, 3.9275, 1e-9, None).unwrap();
    tune_mass(&mut state, &settings, 0.23, 1e-9, None).unwrap();
    state.alpha = 0.8;
    state.beta = 0.00012;
    let json = serde_json::json!({
        "state": state,
        "targets": { "stiffness_n_mm": 3.9275, "period_s": 0.23, "damping_ratio": 0.00175 },
        "settings": { "fe": settings },
    });
    let path = dir.join("calibration.json");
    std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    (path, state)
}

/// The case file reproduces the unit test's sheet (HeliSpring's printed fields).
#[test]
fn helispring_case_file_gives_the_printed_sheet() {
    let spring = read_spring(&cases().join("spring-design/helispring.json")).unwrap();
    let s = spring.sheet();
    assert_eq!(format!("{:.3}", s.rate_n_mm), "16.181");
    assert_eq!(format!("{:.1}", s.minimum_gap_sum_mm), "12.3");
    assert_eq!(format!("{:.2}", s.solid_length_mm), "57.79");
    assert_eq!(format!("{:.1}", s.surge_frequency_hz), "159.5");
    assert_eq!(s.tensile_strength_mpa, 1460.0);
}

/// The 160ECT sheet: Eq. (1) gives 3.8373 N/mm with the paper's G, coil's converged FE
/// 3.8056 (refined from 24 to 192 beams per coil, the helix and its pitch: Castigliano
/// with the chords' stiffening), measured 3.9275; the JSON has every
/// key the command line promises.
#[test]
fn the_160ect_sheet_beside_fe_and_measured() {
    let spring = read_spring(&cases().join("spring-design/160ect_spring.json")).unwrap();
    let report = check(&spring, &FeSettings::default()).unwrap();
    assert!(
        (report.sheet.rate_n_mm - 3.8373).abs() < 5e-5,
        "{}",
        report.sheet.rate_n_mm
    );
    // The FE rate against the closed form: Castigliano times the chords' stiffening on
    // the finest mesh the converged check ran (the rate is taken there), plus the end
    // regions' 0 to 0.3 % (tests/tests/it/paper_spring.rs).
    let mesh = &report.fe.mesh;
    assert!(mesh.converged, "{mesh:?}");
    assert!(
        mesh.last_change_percent.is_some_and(|c| c.abs() < 0.1),
        "{mesh:?}"
    );
    let finest = *mesh.elements_per_coil.last().expect("one mesh at least");
    let chorded = coil_mesher::closed_form::HelixStiffness::new(
        &coil_tests::paper_spec().geometry(),
        coil_tests::PAPER_YOUNGS_MODULUS_MPA,
        0.3,
    )
    .guided(true)
        * coil_tests::chord_stiffening(finest as usize, 0.3);
    let excess = report.fe.rate_n_mm / chorded - 1.0;
    assert!(
        (-3e-4..3.3e-3).contains(&excess),
        "{} ({excess:+e})",
        report.fe.rate_n_mm
    );
    assert_eq!(spring.measured_rate_n_mm, Some(3.9275));
    // The FE surge mode (top held) is the handbook's within 1 %: the beam model adds
    // bending and the pitch, the standard's constant rounds.
    let surge = report.fe.surge_frequency_hz / report.sheet.surge_frequency_hz - 1.0;
    assert!(surge.abs() < 0.01, "{surge}");
    // The FE peak shear (torsion + direct shear, no curvature) lies between tau2 and
    // tau_k2.
    let peak = report.fe.max_shear_stress_2_mpa;
    assert!(
        peak > report.sheet.shear_stress_2_mpa && peak < report.sheet.corrected_shear_stress_2_mpa
    );
    let json: serde_json::Value = serde_json::from_str(&report.json().unwrap()).unwrap();
    for key in [
        "rate_n_mm",
        "spring_index",
        "stress_correction",
        "wahl_factor",
        "deflection_1_mm",
        "length_1_mm",
        "deflection_2_mm",
        "length_2_mm",
        "stroke_mm",
        "shear_stress_1_mpa",
        "shear_stress_2_mpa",
        "corrected_shear_stress_1_mpa",
        "corrected_shear_stress_2_mpa",
        "solid_length_mm",
        "minimum_gap_sum_mm",
        "solid_force_n",
        "solid_shear_stress_mpa",
        "permissible_solid_stress_mpa",
        "surge_frequency_hz",
        "buckling_stable",
        "buckling_deflection_mm",
    ] {
        assert!(json.get(key).is_some(), "{key}");
    }
    assert!(json["buckling_deflection_mm"].is_null());
    for key in ["rate_n_mm", "surge_frequency_hz", "max_shear_stress_2_mpa"] {
        assert!(json["fe"].get(key).is_some(), "fe.{key}");
    }
}

/// The three designs of the acceptance: the short list meets K within the tolerance by
/// FE and holds the target spring (or one within 1 % of its K and mass); every
/// candidate rebuilt from its deck and solved gives its printed FE K.
#[test]
fn designs_hold_the_papers_springs_and_their_decks_rebuild() {
    let dir = tempfile::tempdir().unwrap();
    let (file, state) = calibration(dir.path());
    let table4 = read_variants(&cases().join("160ect/table4.json")).unwrap();
    let geometry = |name: &str| {
        table4
            .variants
            .iter()
            .find(|v| v.name == name)
            .map(|v| v.spring)
            .unwrap_or(state.spring)
    };
    for (target_file, spring) in [
        ("160ect_target.json", state.spring),
        ("table4_2_target.json", geometry("#2")),
        ("table4_4_target.json", geometry("#4")),
    ] {
        let mut target = read_target(&cases().join("spring-design").join(target_file)).unwrap();
        target.material = MaterialSource::Calibration {
            calibration: file.clone(),
            grade: None,
            damping: None,
        };
        let result = design(&target, &DesignSettings::default()).unwrap();
        assert!(!result.candidates.is_empty(), "{target_file}: no candidate");
        let tolerance = target.rate_tolerance_percent / 100.0;
        for c in &result.candidates {
            assert!((c.fe_rate_n_mm / target.rate_n_mm - 1.0).abs() <= tolerance);
        }
        // The target spring's K by FE (the calibrated E, its own pitch) and its mass
        // by the sheet's formula (nt = n + 2).
        let (k, _) =
            fe::static_stiffness(&state.with_spring(spring), &FeSettings::default()).unwrap();
        let mass = 7850.0 * std::f64::consts::PI.powi(2) * spring.wire_diameter_mm.powi(2) / 4.0
            * (spring.active_coils + 2.0)
            * spring.mean_diameter_mm
            * 1e-9;
        let near = result.candidates.iter().find(|c| {
            (c.fe_rate_n_mm / k - 1.0).abs() <= 0.01
                && (c.spring_mass_kg / mass - 1.0).abs() <= 0.01
        });
        assert!(
            near.is_some(),
            "{target_file}: no candidate within 1 % of K {k} and mass {mass}"
        );
        // README: "the best candidate is the paper's spring each time".
        assert!(
            std::ptr::eq(near.unwrap(), &result.candidates[0]),
            "{target_file}: the paper's spring is not ranked first"
        );
        // docs/spring-design.md: #2's and #4's printed zeta are about 4 % above the
        // highest law's at those K and weight, out of the wire's reach; 0.00175 is within.
        let verdict = result.damping.as_ref().expect("a damping verdict");
        let nearest = verdict
            .laws
            .iter()
            .min_by(|a, b| a.gap_percent.abs().total_cmp(&b.gap_percent.abs()))
            .unwrap();
        if target_file == "160ect_target.json" {
            assert!(verdict.reachable, "{}", verdict.text);
        } else {
            assert!(!verdict.reachable, "{target_file}: {}", verdict.text);
            assert!(
                (3.5..=4.5).contains(&nearest.gap_percent),
                "{target_file}: {} {:+.2} %",
                nearest.law,
                nearest.gap_percent
            );
        }
        let out_dir = dir.path().join(target_file);
        let out = OutDir::create(&out_dir).unwrap();
        output::write(&result, &out, false).unwrap();
        out.commit().unwrap();
        for c in &result.candidates {
            let model = coil_solver::deck::read_file(&out_dir.join(&c.deck)).unwrap();
            let results = coil_solver::analysis::run(&model).unwrap();
            let rebuilt = fe::stiffness_of(&results, "deck").unwrap();
            assert!(
                (rebuilt / c.fe_rate_n_mm - 1.0).abs() < 1e-9,
                "{}: {rebuilt} vs {}",
                c.deck,
                c.fe_rate_n_mm
            );
        }
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out_dir.join("design.json")).unwrap())
                .unwrap();
        let first = &json["candidates"][0];
        for key in [
            "wire_diameter_mm",
            "mean_diameter_mm",
            "active_coils",
            "pitch_mm",
            "rate_n_mm",
            "fe_rate_n_mm",
            "spring_mass_kg",
            "damping_ratio",
            "deck",
        ] {
            assert!(
                first.get(key).is_some(),
                "{target_file}: candidates[0].{key}"
            );
        }
        assert!(first["damping_ratio"]["hysteretic"].as_f64().is_some());
    }
}

/// A target zeta off what the laws give at this K and weight is reported as out of
/// reach, with the gap; the loss factor's zeta is the calibrated one for every spring.
#[test]
fn an_off_curve_damping_target_is_reported_not_met() {
    let dir = tempfile::tempdir().unwrap();
    let (file, _) = calibration(dir.path());
    let mut target = read_target(&cases().join("spring-design/160ect_target.json")).unwrap();
    target.material = MaterialSource::Calibration {
        calibration: file,
        grade: None,
        damping: None,
    };
    target.damping_ratio = Some(0.0035);
    let result = design(&target, &DesignSettings::default()).unwrap();
    let verdict = result.damping.expect("a verdict");
    assert!(!verdict.reachable);
    assert!(verdict.text.contains("cannot be met"), "{}", verdict.text);
    for c in &result.candidates {
        assert!((c.damping_ratio["hysteretic"] - 0.00175).abs() < 1e-12);
    }
    let beta = verdict
        .laws
        .iter()
        .find(|l| l.law == "rayleigh_beta_only")
        .unwrap();
    assert!(beta.gap_percent > 90.0, "{}", beta.gap_percent);
}

/// A damping.json's identified law is predicted beside the band (a loss factor gives
/// eta / 2 for every spring), and a damping coefficient at the weight is read as
/// zeta = c / (2 sqrt(K m)).
#[test]
fn an_identified_law_and_a_damping_coefficient_are_used() {
    let dir = tempfile::tempdir().unwrap();
    let (file, _) = calibration(dir.path());
    let damping = dir.path().join("damping.json");
    std::fs::write(
        &damping,
        r#"{"law": "hysteretic", "parameters": {"loss_factor": 0.0035}}"#,
    )
    .unwrap();
    let mut json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(cases().join("spring-design/160ect_target.json")).unwrap(),
    )
    .unwrap();
    json["material"] = serde_json::json!({ "calibration": file, "damping": damping });
    json.as_object_mut().unwrap().remove("damping_ratio");
    json["damping_coefficient_n_s_m"] = 5.0.into();
    let path = dir.path().join("target.json");
    std::fs::write(&path, json.to_string()).unwrap();
    let target = read_target(&path).unwrap();
    let zeta = 5.0 / (2.0 * (3.9275e3 * 5.3f64).sqrt());
    assert!((target.damping_ratio.unwrap() / zeta - 1.0).abs() < 1e-12);
    let result = design(&target, &DesignSettings::default()).unwrap();
    for c in &result.candidates {
        assert!((c.damping_ratio["identified_hysteretic"] - 0.00175).abs() < 1e-12);
    }
}

/// Text a person reads: no Rust debug text (`Some(`, `Forces(`, `StressMargin`, ...) and
/// no number printed with more than six decimals.
fn assert_plain(name: &str, text: &str) {
    for debug in [
        "Some(",
        "None",
        "Forces(",
        "Lengths(",
        "StressMargin",
        "Lightest",
        "ClosedGround",
        "Bergstraesser,",
        "Dynamic",
        "Static",
        "{ ",
        "\\u{",
    ] {
        assert!(!text.contains(debug), "{name}: `{debug}` in\n{text}");
    }
    let mut decimals = 0usize;
    let mut after_point = false;
    for c in text.chars() {
        match c {
            '.' => {
                after_point = true;
                decimals = 0;
            }
            '0'..='9' if after_point => {
                decimals += 1;
                assert!(
                    decimals <= 6,
                    "{name}: a number with 7+ decimals in\n{text}"
                );
            }
            _ => after_point = false,
        }
    }
}

/// The acceptance's 160ECT target on the calibration (K 3.9275 N/mm +- 1 %, working
/// forces 51.4 and 77 N, the envelope of `160ect_target.json` that admits the paper's
/// spring, dynamic loading): `lightest` returns a short list of springs each verified
/// by FE within 1 % and passing the fatigue check; `stress_margin` holds the paper's
/// spring or one within 1 % of its FE K and its mass; report.md and the sheet read as
/// plain text.
#[test]
fn the_acceptance_target_lightest_and_stress_margin() {
    let dir = tempfile::tempdir().unwrap();
    let (file, state) = calibration(dir.path());
    let mut target = read_target(&cases().join("spring-design/160ect_target.json")).unwrap();
    target.material = MaterialSource::Calibration {
        calibration: file,
        grade: None,
        damping: None,
    };
    target.rate_tolerance_percent = 1.0;
    target.working = coil_design::sheet::en13906::Working::Forces(51.4, 77.0);
    let (k, _) = fe::static_stiffness(&state, &FeSettings::default()).unwrap();
    let mass = 7850.0 * std::f64::consts::PI.powi(2) * 9.0 / 4.0 * 16.0 * 24.0 * 1e-9;
    for objective in [Objective::Lightest, Objective::StressMargin] {
        target.objective = objective;
        let result = design(&target, &DesignSettings::default()).unwrap();
        assert!(
            result.candidates.len() >= 2,
            "{objective:?}: {} candidates",
            result.candidates.len()
        );
        for c in &result.candidates {
            assert!(c.fe_verified && c.fatigue_passed, "{objective:?}: {c:?}");
            assert!((c.fe_rate_n_mm / 3.9275 - 1.0).abs() <= 0.01, "{c:?}");
            assert!(c.stroke_stress_mpa <= c.permissible_stroke_stress_mpa);
        }
        let ranks: Vec<usize> = result.candidates.iter().map(|c| c.rank).collect();
        assert_eq!(ranks, (1..=ranks.len()).collect::<Vec<_>>());
        if objective == Objective::StressMargin {
            assert!(
                result.candidates.iter().any(|c| {
                    (c.fe_rate_n_mm / k - 1.0).abs() <= 0.01
                        && (c.spring_mass_kg / mass - 1.0).abs() <= 0.01
                }),
                "no candidate within 1 % of K {k} and mass {mass}: {}",
                output::summary(&result)
            );
        }
        eprintln!("{objective:?}:\n{}", output::summary(&result));
        assert_plain("report.md", &output::report(&result));
    }
    let spring = read_spring(&cases().join("spring-design/160ect_spring.json")).unwrap();
    let report = check(&spring, &FeSettings::default()).unwrap();
    assert_plain(
        "sheet.md",
        &report.markdown(Path::new("160ect_spring.json")),
    );
}
