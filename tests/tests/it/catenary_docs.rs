//! docs/catenary.md's and the EN 50318 case README's tables against the runs that give
//! them, read from the documents (`coil_tests::docs_tables`), in the second stage of
//! `.ci/run` (coil-catenary's own tests hold the reference case's ranges).
//!
//! The spring study, run whole (`coil_catenary::study::band`: 58 runs of
//! 51 840 or 62 208 steps, the second stage of `.ci/run`): every cell of its two tables
//! (the lumped stages with their damping band, the reduced stages against the lumped
//! ones) to half a unit of the printed last digit, the findings' figures drawn from them,
//! and the spring route (`head_spring` / `--springs`: `build_heads` with the band's mid
//! zeta and no mass share) against the study's hand-built stage for the 160ECT and
//! Table 4's #4 at 300 km/h (the same statistics to 0.01 N). The table cells fail at the
//! first miss; the findings' figures are all listed.

use coil_catenary::case::read_case;
use coil_catenary::en50318::Statistics;
use coil_catenary::head_stage::from_spring::{
    build_heads, with_head, DampingChoice, HeadSpringSpec,
};
use coil_catenary::head_stage::springs::HeadStageSettings;
use coil_catenary::run::run_speed;
use coil_catenary::study::band::{band_study, BandStudy, REFERENCE_HEAD};
use coil_tests::docs_tables::{assert_printed, misprinted, table_after};
use rayon::prelude::*;
use std::path::Path;

const SPEEDS: [f64; 2] = [250.0, 300.0];

#[test]
#[ignore = "second CI stage"]
fn claim_spring_study_gives_the_docs_tables_and_the_route_its_rows() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let case = read_case(&repo.join("cases/catenary-en50318-2002")).unwrap();
    let springs = repo.join("cases/160ect");
    let study = band_study(&case, &springs, &springs.join("table4.json"), true).unwrap();
    println!("{}", study.runs_markdown());
    println!("{}", study.reduced_markdown());
    let docs = std::fs::read_to_string(repo.join("docs/catenary.md")).unwrap();
    lumped_table(&study, &docs);
    reduced_table(&study, &docs);
    findings(&study);

    let settings = HeadStageSettings::default();
    let spec = HeadSpringSpec {
        damping: DampingChoice::ZetaMid,
        mass_share: false,
        ..HeadSpringSpec::default()
    };
    for (name, entry) in [
        ("160ECT", springs.clone()),
        ("#4", springs.join("table4.json:#4")),
    ] {
        let heads = build_heads(&[entry], &spec, &case.pantograph, &settings.fe).unwrap();
        assert_eq!(heads.len(), 1);
        let mut routed = case.clone();
        routed.pantograph = with_head(&case.pantograph, &heads[0]);
        let b = run_speed(&routed, 300.0).unwrap().1.statistics;
        let a = study.lumped(name, "mid", 300.0).unwrap();
        println!(
            "{name} at 300 km/h: by hand std {:.3} min {:.3}; route std {:.3} min {:.3}",
            a.std_n, a.min_n, b.std_n, b.min_n
        );
        for (what, x, y) in [
            ("mean", a.mean_n, b.mean_n),
            ("std", a.std_n, b.std_n),
            ("min", a.min_n, b.min_n),
            ("max", a.max_n, b.max_n),
        ] {
            assert!(
                (x - y).abs() < 0.01,
                "{name} {what}: by hand {x}, route {y}"
            );
        }
    }
}

/// The three runs of a spring's damping band at one speed.
fn band_runs<'a>(study: &'a BandStudy, spring: &str, speed: f64) -> Vec<&'a Statistics> {
    ["low", "mid", "high"]
        .iter()
        .filter_map(|z| study.lumped(spring, z, speed))
        .collect()
}

/// `| spring | K | std 250 | min 250 | std 300 | min 300 | loss |`, each statistic
/// `mid (low-high)` (the reference head: `mid` alone).
fn lumped_table(study: &BandStudy, docs: &str) {
    let rows = table_after(
        docs,
        "## Spring study: does the head-stage spring move the contact force?",
    );
    assert_eq!(rows.len(), 1 + study.stages.stages.len(), "rows");
    let picks: [fn(&Statistics) -> f64; 2] = [|s| s.std_n, |s| s.min_n];
    for row in &rows {
        let spring = row[0].as_str();
        let reference = spring == REFERENCE_HEAD;
        if !reference {
            let stage = study
                .stages
                .stages
                .iter()
                .find(|s| s.name == spring)
                .unwrap();
            assert_printed(&format!("{spring} K"), stage.stiffness_n_m, &row[1]);
        }
        for (k, speed) in SPEEDS.iter().enumerate() {
            let runs = if reference {
                vec![study.lumped(REFERENCE_HEAD, "mid", *speed).unwrap()]
            } else {
                band_runs(study, spring, *speed)
            };
            assert_eq!(runs.len(), if reference { 1 } else { 3 }, "{spring}");
            for (j, pick) in picks.iter().enumerate() {
                let cell = &row[2 + 2 * k + j];
                let what = format!("{spring} {speed} column {}", 2 + 2 * k + j);
                let mid = study.lumped(spring, "mid", *speed).map(pick).unwrap();
                let (printed_mid, range) = match cell.split_once(" (") {
                    Some((m, r)) => (m, Some(r.trim_end_matches(')'))),
                    None => (cell.as_str(), None),
                };
                assert_printed(&what, mid, printed_mid);
                if let Some(range) = range {
                    let (lo, hi) = range.split_once('-').unwrap();
                    let values: Vec<f64> = runs.iter().map(|s| pick(s)).collect();
                    let low = values.iter().cloned().fold(f64::INFINITY, f64::min);
                    let high = values.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                    assert_printed(&format!("{what} low"), low, lo);
                    assert_printed(&format!("{what} high"), high, hi);
                }
            }
            for s in &runs {
                assert_printed(&format!("{spring} {speed} loss"), s.loss_percent, &row[6]);
            }
        }
    }
}

/// `| spring | modes | std 250 l / r | d | min 250 l / r | d | std 300 ... | min 300 ... |`.
fn reduced_table(study: &BandStudy, docs: &str) {
    let rows = table_after(docs, "### The reduced head stage in the catenary run");
    assert_eq!(rows.len(), study.stages.stages.len(), "reduced rows");
    let picks: [fn(&Statistics) -> f64; 2] = [|s| s.std_n, |s| s.min_n];
    for row in &rows {
        let spring = row[0].as_str();
        let i = study
            .stages
            .stages
            .iter()
            .position(|s| s.name == spring)
            .unwrap();
        assert_eq!(row[1], study.reduced_modes[i].to_string(), "{spring} modes");
        for (k, speed) in SPEEDS.iter().enumerate() {
            let l = study.lumped(spring, "mid", *speed).unwrap();
            let r = study.reduced(spring, *speed).unwrap();
            for (j, pick) in picks.iter().enumerate() {
                let col = 2 + 4 * k + 2 * j;
                let (a, b) = row[col].split_once(" / ").unwrap();
                let what = format!("{spring} {speed} reduced column {col}");
                assert_printed(&format!("{what} lumped"), pick(l), a);
                assert_printed(&format!("{what} reduced"), pick(r), b);
                assert_printed(&format!("{what} d"), pick(r) - pick(l), &row[col + 1]);
            }
        }
    }
}

/// The findings' figures of both sections, from the runs.
fn findings(study: &BandStudy) {
    let mut misses = Vec::new();
    let mut check = |what: &str, got: f64, cell: &str| misses.extend(misprinted(what, got, cell));
    let names: Vec<&str> = study
        .stages
        .stages
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    let mid = |name: &str, speed: f64| study.lumped(name, "mid", speed).unwrap();
    let range = |values: Vec<f64>| {
        values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(*v), b.max(*v))
            })
    };
    // Across the seven springs, mid zeta: (speed, std from-to, spread, %, min from-to, spread).
    for (speed, std_lo, std_hi, std_spread, pct, min_lo, min_hi, min_spread, min_spread_1) in [
        (
            250.0, "26.7", "29.1", "2.4", "9", "42.9", "60.8", "18", "17.9",
        ),
        (
            300.0, "31.5", "35.7", "4.2", "13", "23.6", "46.2", "23", "22.6",
        ),
    ] {
        let (lo, hi) = range(names.iter().map(|n| mid(n, speed).std_n).collect());
        println!("{speed}: std {lo:.3}-{hi:.3}");
        check("std from", lo, std_lo);
        check("std to", hi, std_hi);
        check("std spread", hi - lo, std_spread);
        check("std spread %", 100.0 * (hi - lo) / lo, pct);
        let (lo, hi) = range(names.iter().map(|n| mid(n, speed).min_n).collect());
        println!("{speed}: min {lo:.3}-{hi:.3}");
        check("min from", lo, min_lo);
        check("min to", hi, min_hi);
        check("min spread", hi - lo, min_spread);
        check("min spread, reduced findings", hi - lo, min_spread_1);
    }
    // At 300 km/h #1 to #4 reach the lowest minima, 23.6-27.8 N.
    let mut by_min: Vec<&str> = names.clone();
    by_min.sort_by(|a, b| mid(a, 300.0).min_n.total_cmp(&mid(b, 300.0).min_n));
    let mut lowest: Vec<&str> = by_min[..4].to_vec();
    lowest.sort();
    assert_eq!(lowest, ["#1", "#2", "#3", "#4"]);
    let (lo, hi) = range(by_min[..4].iter().map(|n| mid(n, 300.0).min_n).collect());
    check("lowest minima from", lo, "23.6");
    check("lowest minima to", hi, "27.7");
    // One spring's band: at most 0.03 N of std and 0.16 N of minimum; dashpots 0.6-2.2 N s/m.
    let mut widest = (0.0_f64, 0.0_f64);
    for n in &names {
        for speed in SPEEDS {
            let runs = band_runs(study, n, speed);
            let (a, b) = range(runs.iter().map(|s| s.std_n).collect());
            let (c, d) = range(runs.iter().map(|s| s.min_n).collect());
            widest = (widest.0.max(b - a), widest.1.max(d - c));
        }
    }
    println!("widest band: std {:.4}, min {:.4}", widest.0, widest.1);
    check("band std", widest.0, "0.03");
    check("band min", widest.1, "0.17");
    let (lo, hi) = range(
        study
            .stages
            .stages
            .iter()
            .flat_map(|s| [s.damping_low_n_s_m, s.damping_high_n_s_m])
            .collect(),
    );
    check("dashpots from", lo, "0.6");
    check("dashpots to", hi, "2.2");
    // Reduced against lumped: std up by 0.08-0.22 N (0.3-0.8 %), min -0.73 to +0.35 N,
    // no loss of contact in the 28 runs, #3 and #6 at 250 km/h 0.01 N apart and swapped.
    let pairs: Vec<(&Statistics, &Statistics)> = names
        .iter()
        .flat_map(|n| SPEEDS.map(|v| (mid(n, v), study.reduced(n, v).unwrap())))
        .collect();
    assert_eq!(pairs.len(), 14);
    let (lo, hi) = range(pairs.iter().map(|(l, r)| r.std_n - l.std_n).collect());
    check("d std from", lo, "0.08");
    check("d std to", hi, "0.22");
    let (lo, hi) = range(
        pairs
            .iter()
            .map(|(l, r)| 100.0 * (r.std_n / l.std_n - 1.0))
            .collect(),
    );
    check("d std % from", lo, "0.3");
    check("d std % to", hi, "0.8");
    let (lo, hi) = range(pairs.iter().map(|(l, r)| r.min_n - l.min_n).collect());
    check("d min from", lo, "-0.73");
    check("d min to", hi, "0.35");
    assert!(pairs
        .iter()
        .all(|(l, r)| l.loss_percent == 0.0 && r.loss_percent == 0.0));
    let (l3, l6) = (mid("#3", 250.0).std_n, mid("#6", 250.0).std_n);
    let (r3, r6) = (
        study.reduced("#3", 250.0).unwrap().std_n,
        study.reduced("#6", 250.0).unwrap().std_n,
    );
    check("#3 against #6 lumped", (l3 - l6).abs(), "0.01");
    assert!(
        (l3 - l6) * (r3 - r6) < 0.0,
        "#3 and #6 swap: {l3} {l6} {r3} {r6}"
    );
    assert!(misses.is_empty(), "findings: {misses:#?}");
}

/// The case README's discretisation tables, run whole: the step halved from 1 ms to
/// 0.0625 ms at 0.25 m elements, the element halved from 0.5 m to 0.125 m at 0.125 ms
/// steps, at both speeds (14 distinct runs of 6 000 to 124 000 steps, in parallel: the
/// second stage of `.ci/run`). Every statistic of every row to half a unit of its printed
/// last digit, the `std change` column against the row before at the same speed, and the
/// README's summary: the standard deviation spans at most 0.4 % of itself over the steps
/// and 0.05 % over the elements, the actual minimum at most 0.25 N over either.
#[test]
#[ignore = "second CI stage"]
fn claim_en50318_discretisation_tables_of_the_case_readme() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/catenary-en50318-2002");
    let case = read_case(&root).unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let tables = [
        table_after(&readme, "Time step halved at 0.25 m elements"),
        table_after(&readme, "Element halved at 0.125 ms steps"),
    ];
    // (element m, step ms, speed km/h) of every row, each distinct one run once.
    let key = |row: &Vec<String>| -> (String, String, String) {
        (row[0].clone(), row[1].clone(), row[2].clone())
    };
    let mut jobs: Vec<(String, String, String)> = tables.iter().flatten().map(key).collect();
    jobs.sort();
    jobs.dedup();
    let runs: Vec<((String, String, String), Statistics)> = jobs
        .par_iter()
        .map(|k| {
            let mut c = case.clone();
            c.catenary.element_length_m = k.0.parse().unwrap();
            c.time_step_s = k.1.parse::<f64>().unwrap() * 1e-3;
            let (_, run) = run_speed(&c, k.2.parse().unwrap()).unwrap();
            (k.clone(), run.statistics)
        })
        .collect();
    let of = |row: &Vec<String>| &runs.iter().find(|(k, _)| *k == key(row)).unwrap().1;
    let mut spans = Vec::new();
    for table in &tables {
        let (mut std_span, mut min_span) = (0.0_f64, 0.0_f64);
        for (i, row) in table.iter().enumerate() {
            let s = of(row);
            let what = format!("{} m, {} ms, {} km/h", row[0], row[1], row[2]);
            println!(
                "{what}: mean {:.3} std {:.3} min {:.3} max {:.3} uplift {:.3} loss {:.3}",
                s.mean_n, s.std_n, s.min_n, s.max_n, s.uplift_support_mm, s.loss_percent
            );
            for (col, got) in [
                (3, s.mean_n),
                (4, s.std_n),
                (6, s.min_n),
                (7, s.max_n),
                (8, s.uplift_support_mm),
                (9, s.loss_percent),
            ] {
                assert_printed(&format!("{what} column {col}"), got, &row[col]);
            }
            let before = table[..i].iter().rev().find(|r| r[2] == row[2]);
            match before {
                Some(b) => {
                    let change = 100.0 * (s.std_n / of(b).std_n - 1.0);
                    assert_printed(&format!("{what} std change"), change, &row[5]);
                }
                None => assert_eq!(row[5], "-", "{what}"),
            }
            let same: Vec<&Statistics> = table.iter().filter(|r| r[2] == row[2]).map(&of).collect();
            let span = |pick: fn(&Statistics) -> f64| {
                let v: Vec<f64> = same.iter().map(|s| pick(s)).collect();
                let lo = v.iter().cloned().fold(f64::INFINITY, f64::min);
                let hi = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                (lo, hi)
            };
            let (lo, hi) = span(|s| s.std_n);
            std_span = std_span.max(100.0 * (hi / lo - 1.0));
            let (lo, hi) = span(|s| s.min_n);
            min_span = min_span.max(hi - lo);
        }
        println!("span: std {std_span:.4} %, min {min_span:.4} N");
        spans.push((std_span, min_span));
    }
    assert_printed("std span over the steps (%)", spans[0].0, "0.4");
    assert_printed("std span over the elements (%)", spans[1].0, "0.05");
    assert_printed("min span (N)", spans[0].1.max(spans[1].1), "0.25");
}
