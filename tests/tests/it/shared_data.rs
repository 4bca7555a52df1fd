//! The numbers the README and the docs state for the shared data, held to their text
//! (one unit of the last printed digit): the real recordings (docs/diagnose.md, "Real
//! recordings"; the README's k3 and c2) and Silverbox (docs/forced.md's table; the
//! README's 1.02 mV). The data sit in `../shared` beside the repository and are never
//! copied into it, so CI (a fresh clone) cannot run these: they are ignored, and FAIL
//! when the data are absent. They run the same code as the examples that print the
//! numbers (`coil_tests::real_recordings`, `coil_tests::silverbox`):
//!
//! ```sh
//! cargo test --release -p coil-tests --test it shared_data -- --ignored --nocapture
//! ```

use coil_ident::diagnose::effects::CATALOGUE;
use coil_ident::diagnose::Outcome;
use coil_ident::forced::{report, ForcedSettings};
use coil_tests::real_recordings::{self, causes, RealRun};
use coil_tests::silverbox;

/// `actual` against the docs' `stated`, printed to `unit` (one unit of its last digit).
fn near(actual: f64, stated: f64, unit: f64, what: &str) {
    assert!(
        (actual - stated).abs() <= unit * (1.0 + 1e-9),
        "{what}: measured {actual}, the docs state {stated} (to {unit})"
    );
}

/// Some number printed in `text` is `stated` to one `unit`.
fn prints(text: &str, stated: f64, unit: f64, what: &str) {
    let numbers: Vec<f64> = text
        .split(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e')))
        .filter_map(|w| w.trim_end_matches('.').parse().ok())
        .collect();
    assert!(
        numbers
            .iter()
            .any(|x| (x - stated).abs() <= unit * (1.0 + 1e-9)),
        "{what}: the text does not print {stated}: {text}"
    );
}

/// The forecast test's ratios over the reference, from its text ("... from origins at
/// 0.25, 0.5, 0.75: 0.891, 0.920, 0.956 (1 of 3 below 0.9, 2 needed)").
fn forecast_ratios(text: &str) -> Vec<f64> {
    let tail = text.rsplit_once(": ").map_or("", |t| t.1);
    let list = tail.split_once(" (").map_or(tail, |t| t.0);
    list.split(", ")
        .filter_map(|x| x.trim().parse().ok())
        .collect()
}

fn whole<'a>(runs: &'a [RealRun], name: &str) -> &'a Outcome {
    let run = runs
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no case {name}"));
    run.whole
        .as_ref()
        .unwrap_or_else(|e| panic!("{name}: diagnose failed: {e}"))
}

fn half<'a>(runs: &'a [RealRun], name: &str) -> &'a Outcome {
    match &runs.iter().find(|r| r.name == name).expect("the case").half {
        Some(Ok(o)) => o,
        other => panic!(
            "{name}: no first-half diagnosis: {:?}",
            other.as_ref().map(|r| r.as_ref().err())
        ),
    }
}

/// A cause's parameter, standard error and share (%; NaN: not stated), against the
/// docs'.
fn cause(o: &Outcome, effect: &str, stated: [(f64, f64); 3], what: &str) {
    let c = o
        .diagnosis
        .causes
        .iter()
        .find(|c| c.effect == effect)
        .unwrap_or_else(|| panic!("{what}: {effect} not named"));
    let p = CATALOGUE
        .iter()
        .find(|e| e.name() == effect)
        .expect("a catalogue effect")
        .parameter();
    let [(value, vu), (se, su), (share, shu)] = stated;
    near(c.parameters[p], value, vu, &format!("{what} {p}"));
    near(
        c.parameters_se[p],
        se,
        su,
        &format!("{what} {p} standard error"),
    );
    if !share.is_nan() {
        near(
            100.0 * c.share,
            share,
            shu,
            &format!("{what} {effect} share (%)"),
        );
    }
}

/// One row of docs/diagnose.md's run 2 table.
struct Row {
    effect: &'static str,
    dbic: f64,
    n_eff: f64,
    forecasts: [f64; 3],
    /// Relative standard errors, in the candidate's effect order (NaN: not stated).
    rel_se: &'static [f64],
    /// The signature's standard errors as printed (empty: "fails" without a number).
    signature: &'static [f64],
    named: bool,
}

const RUN2: [Row; 5] = [
    Row {
        effect: "coulomb_friction",
        dbic: -2.8,
        n_eff: 17.0,
        forecasts: [1.00, 1.00, 1.00],
        rel_se: &[f64::NAN],
        signature: &[-0.2],
        named: false,
    },
    Row {
        effect: "quadratic_damping",
        dbic: 2.4,
        n_eff: 18.0,
        forecasts: [0.89, 0.92, 0.96],
        rel_se: &[0.39],
        signature: &[14.4],
        named: false,
    },
    Row {
        effect: "cubic_stiffness",
        dbic: 12.7,
        n_eff: 18.0,
        forecasts: [0.67, 0.69, 0.69],
        rel_se: &[0.16],
        signature: &[11.2],
        named: true,
    },
    Row {
        effect: "axial_torsional_coupling",
        dbic: -7.5,
        n_eff: 17.0,
        forecasts: [0.98, 0.98, 0.99],
        rel_se: &[0.57],
        signature: &[],
        named: false,
    },
    Row {
        effect: "quadratic_damping+cubic_stiffness",
        dbic: 69.2,
        n_eff: 35.0,
        forecasts: [0.40, 0.43, 0.44],
        rel_se: &[0.10, 0.05],
        signature: &[14.4, 11.2],
        named: true,
    },
];

fn run2_table(o: &Outcome) {
    for row in &RUN2 {
        let c = o
            .diagnosis
            .candidates
            .iter()
            .find(|c| c.effect == row.effect)
            .unwrap_or_else(|| panic!("run2: no candidate {}", row.effect));
        let what = format!("run2 {}", row.effect);
        near(
            c.delta_bic.expect("fitted"),
            row.dbic,
            0.1,
            &format!("{what} dBIC"),
        );
        near(
            c.effective_samples.expect("fitted"),
            row.n_eff,
            1.0,
            &format!("{what} N_eff"),
        );
        let tests = c.tests.as_ref().expect("tested");
        let ratios = forecast_ratios(&tests.forecasts.text);
        assert_eq!(
            ratios.len(),
            3,
            "{what}: three origins in {}",
            tests.forecasts.text
        );
        for (f, s) in ratios.iter().zip(row.forecasts) {
            near(
                *f,
                s,
                0.01,
                &format!("{what} rolling forecast over the reference's"),
            );
        }
        for (effect, stated) in c.effects.iter().zip(row.rel_se) {
            let p = CATALOGUE
                .iter()
                .find(|e| e.name() == effect)
                .expect("a catalogue effect")
                .parameter();
            if stated.is_nan() {
                assert!(
                    !c.parameters_se.contains_key(p),
                    "{what}: {p} has a standard error"
                );
            } else {
                let rel = c.parameters_se[p] / c.parameters[p].abs();
                near(
                    rel,
                    *stated,
                    0.01,
                    &format!("{what} {p} relative standard error"),
                );
            }
        }
        for s in row.signature {
            prints(&tests.signature.text, *s, 0.1, &format!("{what} signature"));
        }
        assert_eq!(c.significant, row.named, "{what}: named");
    }
    let chosen = o.diagnosis.extended.as_ref().expect("a cause");
    assert_eq!(
        chosen.effect, "quadratic_damping+cubic_stiffness",
        "run2: chosen"
    );
    let pair = o
        .diagnosis
        .candidates
        .iter()
        .find(|c| c.effect == chosen.effect)
        .and_then(|c| c.tests.as_ref())
        .and_then(|t| t.every_part_needed.as_ref())
        .expect("the pair's every-part test");
    // Removing drag costs 42.4, removing the cubic 62.6.
    prints(&pair.text, 42.4, 0.1, "run2 removing drag");
    prints(&pair.text, 62.6, 0.1, "run2 removing the cubic");
    let d = &o.diagnosis;
    near(
        d.baseline.residual_rms,
        0.0083,
        1e-4,
        "run2 baseline residual",
    );
    near(chosen.residual_rms, 0.0023, 1e-4, "run2 extended residual");
    near(d.gain.residual_rms_ratio, 0.27, 0.01, "run2 residual ratio");
    near(
        d.baseline.forecast_rms,
        0.0098,
        1e-4,
        "run2 baseline forecast",
    );
    near(chosen.forecast_rms, 0.0060, 1e-4, "run2 extended forecast");
}

/// docs/diagnose.md, "Real recordings", and the README's k3 and c2 of run 2.
#[test]
#[ignore = "needs ../shared/real (never copied into the repository): cargo test --release -p coil-tests --test it shared_data::real -- --ignored --nocapture"]
fn real_recordings_match_the_docs() {
    let runs =
        real_recordings::run_all(&real_recordings::folder()).unwrap_or_else(|e| panic!("{e}"));
    for run in &runs {
        print!("{}", real_recordings::describe(run));
    }
    print!("{}", real_recordings::length_tests(&runs));
    let both = ["cubic_stiffness", "quadratic_damping"];
    let run2 = whole(&runs, "air-disk-run2");
    assert_eq!(causes(run2), both, "run2 causes");
    cause(
        run2,
        "cubic_stiffness",
        [(-31.7, 0.1), (1.7, 0.1), (67.0, 1.0)],
        "run2",
    );
    cause(
        run2,
        "quadratic_damping",
        [(0.0246, 1e-4), (0.0025, 1e-4), (33.0, 1.0)],
        "run2",
    );
    run2_table(run2);
    let run3 = whole(&runs, "air-disk-run3");
    assert_eq!(causes(run3), both, "run3 causes");
    cause(
        run3,
        "cubic_stiffness",
        [(-24.8, 0.1), (0.75, 0.01), (75.0, 1.0)],
        "run3",
    );
    cause(
        run3,
        "quadratic_damping",
        [(0.0187, 1e-4), (0.0013, 1e-4), (25.0, 1.0)],
        "run3",
    );
    // "161 isolated sensor glitches replaced by the reader".
    assert!(
        run3.diagnosis
            .warnings
            .iter()
            .any(|w| w.contains(": 161 isolated outliers")),
        "run3: the glitches replaced: {:?}",
        run3.diagnosis.warnings
    );
    let joint = whole(&runs, "joint-air-disk-run2+air-disk-run3");
    let mut named = causes(joint);
    named.sort();
    assert_eq!(
        named,
        ["cubic_stiffness", "quadratic_damping"],
        "joint causes"
    );
    cause(
        joint,
        "cubic_stiffness",
        [(-30.5, 0.1), (1.3, 0.1), (f64::NAN, 0.0)],
        "joint",
    );
    cause(
        joint,
        "quadratic_damping",
        [(0.0233, 1e-4), (0.0019, 1e-4), (f64::NAN, 0.0)],
        "joint",
    );
    // "The backbone alone also admits the other root, +114 N/m^3 at this preload."
    let pair = joint
        .diagnosis
        .candidates
        .iter()
        .find(|c| c.effect == "quadratic_damping+cubic_stiffness")
        .and_then(|c| c.tests.as_ref())
        .expect("the joint pair's tests");
    prints(&pair.signature.text, 114.0, 1.0, "joint: the other root");
    // The length test: run2's and the joint case's first halves name the same set,
    // run3's names none.
    let mut same = causes(half(&runs, "air-disk-run2"));
    same.sort();
    assert_eq!(
        same,
        ["cubic_stiffness", "quadratic_damping"],
        "run2 first half"
    );
    let mut same = causes(half(&runs, "joint-air-disk-run2+air-disk-run3"));
    same.sort();
    assert_eq!(
        same,
        ["cubic_stiffness", "quadratic_damping"],
        "joint first half"
    );
    let run3_half = half(&runs, "air-disk-run3");
    assert_eq!(causes(run3_half), ["none"], "run3 first half");
    // "The cubic's fit gains (dBIC 198 ...), but the backbone's slope over that half is
    // not its signature."
    let cubic = run3_half
        .diagnosis
        .candidates
        .iter()
        .find(|c| c.effect == "cubic_stiffness")
        .expect("run3 first half: the cubic");
    near(
        cubic.delta_bic.expect("fitted"),
        198.0,
        1.0,
        "run3 first half: the cubic's dBIC",
    );
    let failed = cubic.tests.as_ref().map(|t| t.failed()).unwrap_or_default();
    assert_eq!(
        failed,
        ["signature"],
        "run3 first half: the cubic fails only its signature"
    );
}

/// docs/forced.md's Silverbox table and the README's 1.02 mV.
#[test]
#[ignore = "needs ../shared/forced/silverbox (never copied into the repository): cargo test --release -p coil-tests --test it shared_data::silverbox -- --ignored --nocapture"]
fn silverbox_matches_the_docs() {
    let fit = silverbox::fit(&silverbox::data(), &ForcedSettings::default())
        .unwrap_or_else(|e| panic!("{e}"));
    for h in &fit.held_out {
        println!(
            "{} ({}..{}): linear {:.3} mV, extended {:.3} mV",
            h.name, h.a, h.b, h.linear_mv, h.extended_mv
        );
    }
    println!("f0 {:.2} Hz, zeta {:.4}", fit.f0_hz(), fit.zeta());
    assert_eq!(fit.full.input.len(), 65_062, "samples");
    assert_eq!(fit.cut(), 43_306, "the fit's end");
    assert_eq!(fit.gaps[0], 8528, "the first gap");
    let stated = [
        (43_306, 51_997, 6.96, 1.02),
        (51_997, 60_687, 5.40, 1.03),
        (43_306, 60_687, 6.24, 1.02),
    ];
    for (h, (a, b, linear, extended)) in fit.held_out.iter().zip(stated) {
        assert_eq!((h.a, h.b), (a, b), "{}: samples", h.name);
        near(h.linear_mv, linear, 0.01, &format!("{} linear mV", h.name));
        near(
            h.extended_mv,
            extended,
            0.01,
            &format!("{} extended mV", h.name),
        );
    }
    let o = &fit.outcome;
    let c = &o.candidates[o.cause.expect("a cause")];
    assert_eq!(
        report::first_cause(o, c).name(),
        "cubic_stiffness",
        "the cause"
    );
    near(
        c.residual_rms / o.baseline_residual,
        0.146,
        0.001,
        "residual_rms_ratio",
    );
    near(fit.f0_hz(), 68.3, 0.1, "f0 (Hz)");
    near(fit.zeta(), 0.048, 0.001, "zeta");
}
