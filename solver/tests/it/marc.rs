//! Marc interchange: decks in Mentat's extended fixed format read, solve and match the
//! closed forms; the public Mentat corpus (read from /work/shared/marc-decks or
//! `COIL_MARC_DECKS`, never copied here) reads or stops at a named unsupported feature
//! (`#[ignore]`d: run with `cargo test -p coil-solver --test it marc:: -- --ignored`).

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use coil_solver::analysis::{run, CaseSolution};
use coil_solver::deck;
use coil_solver::model::Model;

fn good(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/decks/good")
        .join(name)
}

/// The static displacement of `node`, DOF `dof` (1..6), of the first load case.
fn static_disp(model: &Model, node: u32, dof: usize) -> f64 {
    let results = run(model).expect("the model solves");
    match &results[0].solution {
        CaseSolution::Static(s) => s.node_displacement(model, node).unwrap()[dof - 1],
        _ => panic!("not a static case"),
    }
}

/// Our own extended-fixed deck (tests/decks/good/mentat_cantilever.dat): a cantilever of
/// four type-52 beams, L = 100 mm, solid circle r = 2 mm from BEAM SECT, E = 2e5 MPa, a
/// named 10 N tip load and a named 0.5 N/mm DIST LOADS, both made active by the
/// history LOADCASE. Euler-Bernoulli elements with consistent loads give exact nodal
/// displacements: PL^3/3EI + qL^4/8EI, to rounding.
#[test]
fn mentat_layout_cantilever_matches_the_closed_form() {
    let (m, notes) = deck::read_file_noting(&good("mentat_cantilever.dat")).unwrap();
    let names: Vec<&str> = notes.iter().map(|n| n.card.as_str()).collect();
    for card in [
        "EXTENDED",
        "PROCESSOR",
        "OPTIMIZE",
        "POST",
        "CONTROL",
        "PARAMETERS",
    ] {
        assert!(names.contains(&card), "{card} not listed: {names:?}");
    }
    let i = PI * 2.0_f64.powi(4) / 4.0;
    let (e, l, p, q): (f64, f64, f64, f64) = (2.0e5, 100.0, 10.0, 0.5);
    let expected = -(p * l.powi(3) / (3.0 * e * i) + q * l.powi(4) / (8.0 * e * i));
    let got = static_disp(&m, 5, 3);
    assert!(
        ((got - expected) / expected).abs() < 1e-10,
        "tip deflection {got} vs {expected}"
    );
    // The tip rotation too: PL^2/2EI + qL^3/6EI (theta_y = -dw/dx > 0 for w < 0).
    let rot = p * l * l / (2.0 * e * i) + q * l.powi(3) / (6.0 * e * i);
    let got = static_disp(&m, 5, 5);
    assert!(
        ((got - rot) / rot).abs() < 1e-10,
        "tip rotation {got} vs {rot}"
    );
}

/// Our own normal fixed-format deck (5/10/10 columns, no comma anywhere, bare
/// exponents): two type-52 beams, L = 100 mm, d = 3 mm, E = 2e5 MPa, 10 N at the tip.
#[test]
fn normal_fixed_format_cantilever_matches_pl3_over_3ei() {
    let m = deck::read_file(&good("marc_normal_fixed.dat")).unwrap();
    let i = PI * 3.0_f64.powi(4) / 64.0;
    let expected = -10.0 * 100.0_f64.powi(3) / (3.0 * 2.0e5 * i);
    let got = static_disp(&m, 3, 3);
    assert!(
        ((got - expected) / expected).abs() < 1e-10,
        "{got} vs {expected}"
    );
}

fn corpus_dir() -> Option<PathBuf> {
    let dir = std::env::var("COIL_MARC_DECKS").unwrap_or_else(|_| "/work/shared/marc-decks".into());
    let dir = PathBuf::from(dir);
    dir.is_dir().then_some(dir)
}

/// Every corpus deck reads through or stops at a line naming an unsupported feature.
#[test]
#[ignore = "needs the Mentat corpus (/work/shared/marc-decks)"]
fn corpus_reads_or_names_an_unsupported_feature() {
    let Some(dir) = corpus_dir() else {
        eprintln!("no corpus: skipped");
        return;
    };
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "dat"))
        .collect();
    paths.sort();
    let mut through = 0;
    for p in &paths {
        match deck::read_file(p) {
            Ok(_) => through += 1,
            Err(e) => {
                let s = e.to_string();
                assert!(e.line().is_some(), "{s}");
                let named = ["is not supported", "user subroutine"]
                    .iter()
                    .any(|w| s.contains(w));
                assert!(named, "not an unsupported feature: {s}");
            }
        }
    }
    eprintln!("{through} of {} decks read through", paths.len());
}

/// The corpus deck `name` with its lines edited by `edit`, read from a temp dir.
fn edited(name: &str, edit: impl Fn(&mut Vec<String>)) -> Option<Model> {
    let dir = corpus_dir()?;
    let text = std::fs::read_to_string(dir.join(name)).ok()?;
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    edit(&mut lines);
    let tmp = std::env::temp_dir().join(format!("coil-marc-{}-{name}", std::process::id()));
    std::fs::write(&tmp, lines.join("\n") + "\n").unwrap();
    let m = deck::read_file(&tmp);
    let _ = std::fs::remove_file(&tmp);
    Some(m.unwrap_or_else(|e| panic!("{e}")))
}

fn find(lines: &[String], start: usize, prefix: &str) -> usize {
    start
        + lines[start..]
            .iter()
            .position(|l| l.starts_with(prefix))
            .unwrap_or_else(|| panic!("no line `{prefix}`"))
}

fn reals(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{:>20}", format!("{v:?}")))
        .collect()
}

const FORCDT_PLAIN: &str = "afe_01_Basic_01_FORCDT_non_table_driven_moving_force_job1.dat";
const FORCDT_TABLE: &str = "afe_01_Basic_01_FORCDT_table_driven_moving_force_job1.dat";

/// The beam decks stop at the user subroutine, naming it.
#[test]
#[ignore = "needs the Mentat corpus (/work/shared/marc-decks)"]
fn beam_decks_stop_at_their_user_subroutine() {
    let Some(dir) = corpus_dir() else {
        return;
    };
    for (name, sub) in [
        (FORCDT_PLAIN, "FORCDT"),
        (FORCDT_TABLE, "FORCDT"),
        ("afe_01_Basic_02_FORCEM_nonuniform_load_job1.dat", "FORCEM"),
    ] {
        let e = deck::read_file(&dir.join(name)).unwrap_err();
        assert!(e.to_string().contains(sub), "{e}");
        assert!(e.line().is_some());
        eprintln!("{e}");
    }
}

/// The tip-loaded cantilever of the FORCDT decks, the user-subroutine load replaced by
/// a POINT LOAD of P = 100 N at the tip (node 10, x = 100 mm; support node 11 at x = 0),
/// against PL^3/3EI with BEAM SECT's solid circle (radius 40 mm, E = 2e5 MPa).
#[test]
#[ignore = "needs the Mentat corpus (/work/shared/marc-decks)"]
fn forcdt_decks_with_a_point_load_match_pl3_over_3ei() {
    let (e, l, p, r): (f64, f64, f64, f64) = (2.0e5, 100.0, 100.0, 40.0);
    let i = PI * r.powi(4) / 4.0;
    let expected = -p * l.powi(3) / (3.0 * e * i);
    // Plain layout: drop the FORCDT card and its list, put the load in the history.
    let plain = edited(FORCDT_PLAIN, |lines| {
        let f = find(lines, 0, "forcdt");
        lines.drain(f..f + 2);
        let h = find(lines, find(lines, 0, "end option"), "point load");
        lines[h + 2] = reals(&[0.0, 0.0, -p, 0.0, 0.0, 0.0]);
        lines[h + 3] = format!("{:>12}", 10);
    });
    // Table-driven layout: the POINT LOAD block without its FORCDT flag, on node 10.
    let table = edited(FORCDT_TABLE, |lines| {
        let b = find(lines, find(lines, 0, "point load"), "         1         1");
        lines[b] = lines[b].replacen("         1         1", "         1         0", 1);
        lines[b + 1] = reals(&[0.0, 0.0, -p, 0.0, 0.0, 0.0]);
        lines[b + 4] = format!("{:>12}", 10);
    });
    let (Some(plain), Some(table)) = (plain, table) else {
        return;
    };
    for m in [&plain, &table] {
        let got = static_disp(m, 10, 3);
        eprintln!("tip deflection {got:.9e} vs PL^3/3EI = {expected:.9e}");
        assert!(
            ((got - expected) / expected).abs() < 1e-9,
            "{got} vs {expected}"
        );
    }
}

/// The FORCEM deck with its user-subroutine load replaced by a uniform DIST LOADS of
/// q = 1 N/mm (global y) on all five beams: the tip (node 6, x = 100 mm; support node
/// 1) deflects qL^4/8EI (radius 5 mm, E = 2e5 MPa).
#[test]
#[ignore = "needs the Mentat corpus (/work/shared/marc-decks)"]
fn forcem_deck_with_a_uniform_dist_load_matches_ql4_over_8ei() {
    let (e, l, q, r): (f64, f64, f64, f64) = (2.0e5, 100.0, 1.0, 5.0);
    let i = PI * r.powi(4) / 4.0;
    let expected = q * l.powi(4) / (8.0 * e * i);
    let Some(m) = edited("afe_01_Basic_02_FORCEM_nonuniform_load_job1.dat", |lines| {
        let b = find(lines, find(lines, 0, "dist loads"), "         1         1");
        lines[b] = lines[b].replacen("         1         1", "         1         0", 1);
        lines[b + 1] = reals(&[0.0, q, 0.0]);
        lines[b + 5] = format!("{:>12}{:>12}{:>12}", 1, "to", 5);
    }) else {
        return;
    };
    let got = static_disp(&m, 6, 2);
    eprintln!("tip deflection {got:.9e} vs qL^4/8EI = {expected:.9e}");
    assert!(
        ((got - expected) / expected).abs() < 1e-9,
        "{got} vs {expected}"
    );
}
