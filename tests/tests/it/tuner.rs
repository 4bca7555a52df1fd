//! The tuner end to end on the paper's case (cases/160ect), at reduced settings so the
//! whole file runs in seconds: the loops' convergence, a grid of real decay transients
//! stopped and resumed from its journal, the valley against the modal theory, and the
//! calibration's headline numbers; then the README's Tables 3 and 4 from the full paper run
//! (modal grids, about 2 s) at the README's printed digits. The same run with every grid
//! transient integrated directly is the second CI stage (`claim_`, `#[ignore]`d):
//! `cargo test --release -p coil-tests --test it claim_paper -- --ignored --nocapture`.

use coil_tuner::calibrate::{calibrate, CalibrateSettings, Targets};
use coil_tuner::case::read_case;
use coil_tuner::damping::{Loop3, RunControl};
use coil_tuner::decay::Method;
use coil_tuner::fe::{self, FeSettings, SpringState};
use coil_tuner::grid::{Axis, GridSpec};
use coil_tuner::loops::{tune_mass, tune_youngs_modulus};
use coil_tuner::output::OutDir;
use std::path::{Path, PathBuf};

fn case_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect")
}

fn coarse() -> FeSettings {
    FeSettings {
        elements_per_coil: 8,
        ..FeSettings::default()
    }
}

/// Loop 1 on the paper's case at the default mesh: K is linear in E, so 2 runs reach
/// 1e-5 (the paper's 0.001% took 19); the error left is the solve's rounding.
#[test]
fn loop1_converges_in_two_runs() {
    let case = read_case(&case_dir()).unwrap();
    let mut state = SpringState::nominal(&case);
    let (k_nominal, _) = fe::static_stiffness(&state, &FeSettings::default()).unwrap();
    let e_nominal = state.youngs_modulus_mpa;
    let report =
        tune_youngs_modulus(&mut state, &FeSettings::default(), 3.9275, 1e-5, None).unwrap();
    assert!(report.iterations.len() <= 3, "{:?}", report.iterations);
    assert!(report.relative_error.abs() < 1e-10);
    // K is proportional to E (a linear model with nu fixed), so the tuned E is
    // E_nominal * 3.9275 / K(E_nominal) to the loop's tolerance.
    let expected = e_nominal * 3.9275 / k_nominal;
    assert!(
        (state.youngs_modulus_mpa / expected - 1.0).abs() < 1e-9,
        "{} vs {expected}",
        state.youngs_modulus_mpa
    );
}

/// Loop 2 hits the axial mode's period to 1e-9 in at most 4 runs.
#[test]
fn loop2_hits_the_period() {
    let case = read_case(&case_dir()).unwrap();
    let mut state = SpringState::nominal(&case);
    tune_youngs_modulus(&mut state, &coarse(), 3.9275, 1e-9, None).unwrap();
    let report = tune_mass(&mut state, &coarse(), 0.23, 1e-9, None).unwrap();
    assert!(report.iterations.len() <= 4);
    let (run, _) = fe::static_and_modal(&state, &coarse()).unwrap();
    assert!((run.axial.period_s - 0.23).abs() <= 0.23e-9);
    // T^2 = 4 pi^2 (m + c) / K: c, the wire's share, is about a third of its mass.
    let share = run.stiffness_n_mm * 1e3 * (0.23 / std::f64::consts::TAU).powi(2) - state.mass_kg;
    let third = state.spring_mass_kg() / 3.0;
    assert!((share - third).abs() / third < 0.05, "{share} vs {third}");
}

/// A 3 x 3 grid of modal decay transients, stopped after 4 points (as a kill leaves it),
/// resumes from its journal: 5 points run, 4 read, the result equal to an uninterrupted
/// grid's; the measured zeta follows the modal theory zeta = alpha d/2w + beta w/2.
#[test]
fn a_small_grid_resumes_from_its_journal() {
    let case = read_case(&case_dir()).unwrap();
    let mut state = SpringState::nominal(&case);
    tune_youngs_modulus(&mut state, &coarse(), 3.9275, 1e-9, None).unwrap();
    tune_mass(&mut state, &coarse(), 0.23, 1e-9, None).unwrap();
    let mut settings = CalibrateSettings::default();
    settings.damping.decay.method = Method::Modal;
    settings.damping.check_direct = false;
    let spec = GridSpec {
        name: "small".into(),
        alpha: Axis::parse("0:1:2").unwrap(),
        beta: Axis::parse("0.0001:0.00002:0.00014").unwrap(),
    };
    let dir = tempfile::tempdir().unwrap();
    let out = OutDir::create(dir.path()).unwrap();
    let stop = RunControl {
        max_new_points: Some(4),
    };
    let mut first = Loop3::new(
        &state,
        &coarse(),
        &settings.damping,
        0.00175,
        Some(&out),
        &stop,
    )
    .unwrap();
    let partial = first.grid(&spec).unwrap();
    assert_eq!((partial.computed, partial.resumed), (4, 0));
    let mut resumed = Loop3::new(
        &state,
        &coarse(),
        &settings.damping,
        0.00175,
        Some(&out),
        &RunControl::default(),
    )
    .unwrap();
    let whole = resumed.grid(&spec).unwrap().clone();
    assert_eq!((whole.computed, whole.resumed), (5, 4));
    let mut fresh = Loop3::new(
        &state,
        &coarse(),
        &settings.damping,
        0.00175,
        None,
        &RunControl::default(),
    )
    .unwrap();
    let reference = fresh.grid(&spec).unwrap();
    for (a, b) in whole.points.iter().zip(&reference.points) {
        let (za, zb) = (a.zeta().unwrap(), b.zeta().unwrap());
        // The same runs, read back from JSON: equal to the printed digits.
        assert!((za - zb).abs() <= 1e-15 * zb, "{za} vs {zb}");
    }
    let report = resumed.finish(None).unwrap();
    let valley = report.valley.unwrap();
    // The fitted slopes are the modal theory's to the decrement's accuracy (1e-4).
    assert!((valley.plane.b - valley.modal.dzeta_dbeta).abs() / valley.modal.dzeta_dbeta < 1e-4);
    assert!(
        (valley.plane.a - valley.modal.dzeta_dalpha).abs() / valley.modal.dzeta_dalpha < 1e-2,
        "{} vs {}",
        valley.plane.a,
        valley.modal.dzeta_dalpha
    );
    for p in &valley.points {
        assert!((p.zeta - 0.00175).abs() / 0.00175 <= 1e-4, "{p:?}");
    }
}

/// The same decay by modal superposition and by direct integration (average
/// acceleration, the solver's transient load case): the period differs by the
/// integrator's (w dt)^2/12 (within 10%), zeta by less than 1e-3 relative.
#[test]
fn direct_and_modal_decays_agree() {
    let case = read_case(&case_dir()).unwrap();
    let mut state = SpringState::nominal(&case);
    tune_youngs_modulus(&mut state, &coarse(), 3.9275, 1e-9, None).unwrap();
    tune_mass(&mut state, &coarse(), 0.23, 1e-9, None).unwrap();
    state.alpha = 1.6;
    state.beta = 1.2e-4;
    let decay = coil_tuner::decay::DecaySettings::default();
    let modal = coil_tuner::decay::ModalDecay::new(&state, &coarse(), &decay).unwrap();
    let m = coil_tuner::decay::measure(&modal.simulate(1.6, 1.2e-4).unwrap(), &decay).unwrap();
    let record = coil_tuner::damping::direct_decay(&state, &coarse(), &decay).unwrap();
    let d = coil_tuner::decay::measure(&record, &decay).unwrap();
    let w_dt = std::f64::consts::TAU / 0.23 * decay.dt_s;
    let elongation = d.period_s / m.period_s - 1.0;
    assert!(
        (elongation / (w_dt * w_dt / 12.0) - 1.0).abs() < 0.1,
        "period elongation {elongation:e} vs (w dt)^2/12 = {:e}",
        w_dt * w_dt / 12.0
    );
    let dz = (d.zeta_mean - m.zeta_mean) / m.zeta_mean;
    assert!(
        dz.abs() < 1e-3,
        "direct {} vs modal {}",
        d.zeta_mean,
        m.zeta_mean
    );
    // The modal record's period is the axial mode's own (damped: T / sqrt(1 - zeta^2)).
    assert!((m.period_s - 0.23).abs() / 0.23 < 1e-5, "{}", m.period_s);
}

/// The calibration's headline numbers on the paper's case at reduced settings: K and T
/// on target, the chosen zeta within half a grid step of the target.
#[test]
fn calibrate_the_papers_case_reduced() {
    let case = read_case(&case_dir()).unwrap();
    let targets = Targets::of(&case).unwrap();
    let mut settings = CalibrateSettings {
        fe: coarse(),
        ..CalibrateSettings::default()
    };
    settings.damping.check_direct = false;
    settings.damping.grids = vec![GridSpec {
        name: "d2".into(),
        alpha: Axis::parse("0:0.5:2").unwrap(),
        beta: Axis::parse("0.0001:0.00001:0.00014").unwrap(),
    }];
    let c = calibrate(&case, &targets, &settings, None, &RunControl::default()).unwrap();
    assert!(c.stiffness.relative_error.abs() <= 1e-5);
    assert!(c.period.relative_error.abs() <= 1e-6);
    // Neighbouring grid points differ by 0.5 a = 3.4e-5 in zeta (alpha) or 1.4e-4
    // (beta), so the best is within 2% of the target.
    assert!(
        (c.damping.chosen.zeta - 0.00175).abs() / 0.00175 < 0.02,
        "{}",
        c.damping.chosen.zeta
    );
    let paper = c.damping.paper_point.unwrap();
    assert_eq!((paper.alpha, paper.beta), (0.8, 0.00012));
}

/// The README's Table 3 and Table 4, as `coil-tune paper` prints them (modal grids, the
/// optimum checked by direct integration): each of coil's numbers within one unit of the
/// README's last printed digit, and the README's prose claims about them. The run takes
/// 1-2 s idle (about 6 s beside other builds), so it runs with the README's test command.
#[test]
fn paper_tables_match_the_readme() {
    let r = paper_run(Method::Modal);
    let t = &r.table3;
    within("Table 3 K (N/mm)", t.stiffness_n_mm, 3.927500, 1e-6);
    within("Table 3 zeta", t.damping_ratio, 0.001747, 1e-6);
    within("Table 3 T (s)", t.period_s, 0.230058, 1e-6);
    within("Table 3 E (MPa)", t.youngs_modulus_mpa, 193837.8, 0.1);
    within("Table 3 alpha (1/s)", t.alpha, 1.6, 0.1);
    within("Table 3 beta (s)", t.beta, 0.00012, 0.00001);
    let e = &r.table3_relative_error;
    within("Table 3 K vs experiment", e.stiffness, 0.0, 1e-6);
    within(
        "Table 3 zeta vs experiment",
        e.damping_ratio,
        -0.001562,
        1e-6,
    );
    within("Table 3 T vs experiment", e.period, 0.000250, 1e-6);
    // (name, K coil 4 decimals, K error %, zeta coil 6 decimals, zeta error %)
    let readme = [
        ("#1", 2.4799, 0.20, 0.001462, 2.92),
        ("#2", 7.2530, -0.27, 0.002333, -5.16),
        ("#3", 1.8992, 0.17, 0.001249, 1.55),
        ("#4", 6.7567, -0.34, 0.002218, -6.81),
        ("#5", 4.5844, 0.01, 0.001857, -4.29),
        ("#6", 3.4354, 0.01, 0.001665, -1.48),
    ];
    assert_eq!(r.table4.len(), readme.len());
    for (v, (name, k, k_err, zeta, zeta_err)) in r.table4.iter().zip(readme) {
        assert_eq!(v.name, name);
        within(&format!("Table 4 {name} K"), v.stiffness_n_mm, k, 1e-4);
        within(&format!("Table 4 {name} zeta"), v.damping_ratio, zeta, 1e-6);
        let pct = |x: Option<f64>| 100.0 * x.expect("the paper's value");
        within(
            &format!("Table 4 {name} K error (%)"),
            pct(v.stiffness_relative_error),
            k_err,
            0.01,
        );
        within(
            &format!("Table 4 {name} zeta error (%)"),
            pct(v.damping_relative_error),
            zeta_err,
            0.01,
        );
    }
    // "mesh bias: the paper's E = 190708 MPa at ~16.8 elements per coil; mesh-converged E
    // = 196862 MPa", converging at second order (the chords of the helix).
    let m = &r.mesh_study;
    within(
        "elements per coil matching the paper's E",
        m.elements_per_coil_matching_paper.unwrap(),
        16.8,
        0.1,
    );
    within(
        "mesh-converged E (MPa)",
        m.converged_youngs_modulus_mpa,
        196862.0,
        1.0,
    );
    assert!(
        (m.observed_order - 2.0).abs() < 0.1,
        "order {}",
        m.observed_order
    );
    // "every pair on the line 6.815e-5 alpha + 13.659 beta = zeta fits".
    let valley = r.calibration.damping.valley.as_ref().expect("the valley");
    within(
        "valley d zeta / d alpha",
        valley.plane.a,
        6.815e-5,
        0.001e-5,
    );
    within("valley d zeta / d beta", valley.plane.b, 13.659, 0.001);
    // "alpha acts only through the wire's 0.37 % share of the modal mass": against
    // Rayleigh's estimate for a uniform spring under a weight, (m_s / 3) / (m + m_s / 3),
    // with m_s = rho (pi d^2 / 4) n sqrt((pi D)^2 + h^2), within its 1 % (the weight's mode
    // is not exactly the linear static shape).
    let share = valley.modal.wire_mass_share;
    within(
        "wire's share of the axial mode's mass (%)",
        100.0 * share,
        0.37,
        0.01,
    );
    let wire_m = 14.0 * (std::f64::consts::PI * 24.0f64).hypot(6.2) * 1e-3;
    let spring_kg = 7850.0 * std::f64::consts::PI * 0.0015f64.powi(2) * wire_m;
    let rayleigh = spring_kg / 3.0 / (t.mass_kg + spring_kg / 3.0);
    assert!(
        (share / rayleigh - 1.0).abs() < 0.01,
        "share {share} vs Rayleigh {rayleigh}"
    );
    // "#2 and #4 differ from the paper's printed zeta by more than 5 %; with the alpha = 0
    // member of the valley all six are within 3.6 % (the worst, #4, -3.53 %)."
    for v in &r.table4 {
        let off = v.damping_relative_error.unwrap().abs();
        assert_eq!(
            off > 0.05,
            v.name == "#2" || v.name == "#4",
            "{}: {off}",
            v.name
        );
    }
    let beta_only = r
        .family
        .iter()
        .find(|f| f.alpha == 0.0)
        .expect("the alpha = 0 member");
    for (name, zeta, error) in &beta_only.variants {
        assert!(
            error.unwrap().abs() < 0.036,
            "alpha = 0: {name} zeta {zeta} ({error:?})"
        );
    }
    let worst = beta_only
        .variants
        .iter()
        .max_by(|a, b| a.2.unwrap().abs().total_cmp(&b.2.unwrap().abs()))
        .expect("six variants");
    assert_eq!(worst.0, "#4", "alpha = 0: the worst is {worst:?}");
    within("alpha = 0: #4 (%)", 100.0 * worst.2.unwrap(), -3.53, 0.01);
    // docs/tuner.md, "The paper's point": (0.8, 0.00012) gives zeta = 0.001694 here
    // (modal), -3.2 % from the target.
    let paper = r
        .family
        .iter()
        .find(|f| f.alpha == 0.8 && f.beta == 0.00012)
        .expect("the paper's point");
    within(
        "the paper's point's zeta",
        paper.base_damping_ratio,
        0.001694,
        1e-6,
    );
    within(
        "the paper's point against the target (%)",
        100.0 * (paper.base_damping_ratio / 0.00175 - 1.0),
        -3.2,
        0.1,
    );
    docs_tables_match(&r);
}

/// docs/tuner.md's four-choice table (each valley member's Table 4 zeta against the
/// paper's, %), its mesh-bias table, python.md's "too stiff by 11 %" at 8 elements per
/// coil, and docs/damping.md's band table (each law's zeta per variant and for the surge
/// mode, the spread), each to one unit of its printed last digit.
fn docs_tables_match(r: &coil_tuner::report::PaperReport) {
    let rows: [(&str, f64, Option<f64>, [f64; 6]); 3] = [
        (
            "alpha = 0",
            0.0,
            None,
            [-2.10, -3.39, -1.01, -3.53, -2.52, -3.18],
        ),
        (
            "alpha = 2",
            2.0,
            None,
            [4.35, -5.37, 2.35, -7.40, -4.53, -0.87],
        ),
        (
            "the paper's point",
            0.8,
            Some(0.00012),
            [-2.68, -7.30, -2.85, -8.18, -6.46, -5.38],
        ),
    ];
    for (label, alpha, beta, errors) in rows {
        let member = r
            .family
            .iter()
            .find(|f| f.alpha == alpha && beta.is_none_or(|b| f.beta == b))
            .unwrap_or_else(|| panic!("{label}: no such member"));
        assert_eq!(member.variants.len(), 6, "{label}");
        for ((name, _, error), printed) in member.variants.iter().zip(errors) {
            within(
                &format!("{label}: {name} (%)"),
                100.0 * error.unwrap(),
                printed,
                0.01,
            );
        }
    }
    let mesh = [
        (8, 4.37617, 171155.0),
        (16, 3.93969, 190118.0),
        (24, 3.86408, 193838.0),
        (48, 3.81947, 196102.0),
        (96, 3.80840, 196672.0),
    ];
    assert_eq!(r.mesh_study.rows.len(), mesh.len());
    for (row, (n, k, e)) in r.mesh_study.rows.iter().zip(mesh) {
        assert_eq!(row.elements_per_coil, n);
        within(
            &format!("K at the paper's E, {n} per coil"),
            row.stiffness_at_paper_e_n_mm,
            k,
            1e-5,
        );
        within(
            &format!("E tuned, {n} per coil"),
            row.tuned_youngs_modulus_mpa,
            e,
            1.0,
        );
    }
    within(
        "8 elements per coil too stiff by (%)",
        100.0 * (r.mesh_study.rows[0].stiffness_at_paper_e_n_mm / 3.9275 - 1.0),
        11.0,
        0.5,
    );
    // (beta only, alpha only, hysteretic, dashpot; spread %).
    let band: [([f64; 4], f64); 6] = [
        ([0.00139, 0.00257, 0.00175, 0.00220], 84.6),
        ([0.00238, 0.00175, 0.00175, 0.00129], 84.7),
        ([0.00122, 0.00175, 0.00175, 0.00252], 106.8),
        ([0.00230, 0.00111, 0.00175, 0.00133], 106.2),
        ([0.00189, 0.00139, 0.00175, 0.00162], 36.1),
        ([0.00164, 0.00214, 0.00175, 0.00187], 30.6),
    ];
    let b = &r.damping_band;
    assert_eq!(b.variants.len(), band.len());
    for (row, (zetas, spread)) in b.variants.iter().zip(band) {
        for (law, (got, printed)) in b.laws.iter().zip(row.zeta.iter().zip(zetas)) {
            within(&format!("band {} {law}", row.name), *got, printed, 1e-5);
        }
        within(
            &format!("band {} spread (%)", row.name),
            row.spread_percent,
            spread,
            0.1,
        );
    }
    within("surge frequency (Hz)", b.surge_frequency_hz, 129.8, 0.1);
    for (law, (got, printed)) in b
        .laws
        .iter()
        .zip(b.surge_zeta.iter().zip([0.05225, 0.01574, 0.00175, 0.0]))
    {
        within(&format!("surge {law}"), *got, printed, 1e-5);
    }
}

/// `--method direct`: all 697 grid transients integrated directly (18 s idle, about a
/// minute beside other builds). Average acceleration shortens the decay's zeta by
/// `(w dt)^2 / 6` = 1.2e-4 relative (docs/transient.md) and lengthens T by `(w dt)^2 / 12`,
/// both below the README's printed digits, so the direct tables print the modal ones:
/// the same grid optimum and the same numbers within one unit of the last digit.
/// `cargo test --release -p coil-tests --test it claim_paper -- --ignored --nocapture`
#[test]
#[ignore = "second CI stage"]
fn claim_paper_tables_direct_match_the_modal_ones() {
    let direct = paper_run(Method::Direct);
    let modal = paper_run(Method::Modal);
    let (d, m) = (&direct.table3, &modal.table3);
    assert_eq!((d.alpha, d.beta), (m.alpha, m.beta), "the grid optimum");
    within("Table 3 K (N/mm)", d.stiffness_n_mm, m.stiffness_n_mm, 1e-6);
    within("Table 3 zeta", d.damping_ratio, m.damping_ratio, 1e-6);
    within("Table 3 T (s)", d.period_s, m.period_s, 1e-6);
    for (a, b) in direct.table4.iter().zip(&modal.table4) {
        within(
            &format!("Table 4 {} K", a.name),
            a.stiffness_n_mm,
            b.stiffness_n_mm,
            1e-4,
        );
        within(
            &format!("Table 4 {} zeta", a.name),
            a.damping_ratio,
            b.damping_ratio,
            1e-6,
        );
    }
}

/// `a` within `unit` (one unit of the last printed digit) of the printed `printed`.
fn within(what: &str, a: f64, printed: f64, unit: f64) {
    assert!(
        (a - printed).abs() <= unit * (1.0 + 1e-9),
        "{what}: coil gives {a}, the README prints {printed} (one unit of its last digit: {unit})"
    );
}

fn paper_run(method: Method) -> coil_tuner::report::PaperReport {
    let dir = tempfile::tempdir().unwrap();
    let out = OutDir::create(dir.path()).unwrap();
    let mut settings = CalibrateSettings::default();
    settings.damping.decay.method = method;
    settings.damping.check_direct = method == Method::Modal;
    let options = coil_tuner::paper::PaperOptions {
        case: case_dir(),
        variants: case_dir().join("table4.json"),
        settings,
        control: RunControl::default(),
    };
    let start = std::time::Instant::now();
    let r = coil_tuner::paper::run_paper(&options, &out).unwrap();
    println!("{}", coil_tuner::report::table3(&r));
    println!("{}", coil_tuner::report::table4(&r));
    println!("method {method}: {:.1} s", start.elapsed().as_secs_f64());
    r
}
