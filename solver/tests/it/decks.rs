//! The deck corpus: every good deck reads, every bad deck fails at the line and with
//! the message its header names (and never panics), models round-trip through the
//! writer, and mutated decks never make the reader panic.
//!
//! Bad decks start with header comments:
//! `$ expect-stage: read|solve`, `$ expect-line: N` (read stage), `$ expect-message: text`.
//! Solve-stage decks must read; the solver's tests check their failure.

use std::fs;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use coil_solver::deck::{self, DeckError, KEYWORDS};
use coil_solver::model::*;

fn corpus(kind: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/decks")
        .join(kind);
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "dat"))
        .collect();
    files.sort();
    files
}

fn good(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/decks/good")
        .join(name)
}

/// Reads a file, turning a panic into a test failure that names the file.
fn read_no_panic(path: &Path) -> Result<Model, DeckError> {
    catch_unwind(AssertUnwindSafe(|| deck::read_file(path)))
        .unwrap_or_else(|_| panic!("{}: the reader panicked", path.display()))
}

#[test]
fn good_decks_read() {
    let files = corpus("good");
    assert!(
        files.len() >= 2,
        "the good corpus has {} decks",
        files.len()
    );
    for f in &files {
        if let Err(e) = read_no_panic(f) {
            panic!("{e}");
        }
    }
}

#[test]
fn hand_written_marc_cantilever_reads_as_meant() {
    let m = read_no_panic(&good("cantilever_marc.dat")).unwrap();
    assert_eq!(m.title(), "cantilever, type 52,");
    assert_eq!(m.element_types(), [ElementType::Beam52]);
    assert!(!m.lumped_mass());
    assert_eq!(m.nodes().len(), 11);
    assert_eq!(m.nodes()[10].xyz, [100.0, 0.0, 0.0]);
    assert_eq!(m.elements().len(), 10);
    assert!(m.elements().iter().all(|e| e.kind == ElementType::Beam52));
    assert_eq!(m.elements()[9].nodes, [10, 11]);
    // Fortran-style reals: 2.1+5 and 7.85-9.
    assert_eq!(m.materials()[0].youngs_modulus, 2.1e5);
    assert_eq!(m.materials()[0].density, 7.85e-9);
    assert_eq!(m.materials()[0].elements, (1..=10).collect::<Vec<_>>());
    let Section::General {
        area,
        iyy,
        izz,
        torsion,
        shear_coefficient,
    } = m.geometries()[0].section
    else {
        panic!("a general section was expected");
    };
    let d = 10.0_f64;
    let i = std::f64::consts::PI * d.powi(4) / 64.0;
    // The deck prints 10 decimals: the values agree to 1e-10 absolute.
    assert!((area - std::f64::consts::PI * 25.0).abs() < 1e-9);
    assert!((iyy - i).abs() < 1e-9 && (izz - i).abs() < 1e-9);
    assert!((torsion - 2.0 * i).abs() < 1e-9);
    assert_eq!(shear_coefficient, 0.0);
    assert_eq!(m.geometries()[0].orientation, [0.0, 0.0, 1.0]);
    assert_eq!(m.fixed_disp()[0].nodes, [1]);
    assert_eq!(m.fixed_disp()[0].dofs.len(), 6);
    assert_eq!(m.point_loads()[0].dofs, [(2, -100.0)]);
    assert_eq!(m.point_loads()[0].nodes, [11]);
    assert_eq!(m.load_cases().len(), 2);
    assert_eq!(
        m.load_cases()[0].analysis,
        Analysis::Static {
            steps: 1,
            time: 1.0
        }
    );
    assert_eq!(m.load_cases()[1].analysis, Analysis::Modal { modes: 5 });
}

#[test]
fn the_every_card_deck_uses_every_card() {
    // coil's cards in every_card.dat (the catenary's, which need NEWMARK, in
    // moving_contact.dat), Mentat's in mentat_cantilever.dat; the cards coil
    // refuses are tested to fail in the keyword table's tests.
    let text = fs::read_to_string(good("every_card.dat")).unwrap()
        + &fs::read_to_string(good("mentat_cantilever.dat")).unwrap()
        + &fs::read_to_string(good("moving_contact.dat")).unwrap();
    for kw in KEYWORDS
        .iter()
        .filter(|k| k.origin != coil_solver::deck::Origin::Unsupported)
    {
        let used = text.lines().any(|l| {
            let l = l.trim_start().to_ascii_uppercase();
            l.strip_prefix(kw.name)
                .is_some_and(|rest| rest.is_empty() || rest.starts_with([',', ' ']))
        });
        assert!(used, "every_card.dat does not use {}", kw.name);
    }
    let m = read_no_panic(&good("every_card.dat")).unwrap();
    assert!(m.lumped_mass());
    assert_eq!(
        m.element_types(),
        [ElementType::Beam98, ElementType::Beam52]
    );
    assert_eq!(m.nodes().last().unwrap().xyz, [100.0, 0.0, 60.0]);
    assert_eq!(
        m.node_sets()
            .iter()
            .find(|s| s.name == "odd")
            .unwrap()
            .nodes,
        [1, 3, 5]
    );
    assert_eq!(
        m.node_sets()
            .iter()
            .find(|s| s.name == "many")
            .unwrap()
            .nodes,
        [1, 2, 3, 4, 5]
    );
    assert_eq!(
        m.element_sets()
            .iter()
            .find(|s| s.name == "frame")
            .unwrap()
            .elements,
        [1, 2, 3, 4, 5, 6]
    );
    assert_eq!(m.materials()[1].youngs_modulus, 7.0e4);
    assert_eq!(m.geometries().len(), 3);
    assert_eq!(m.geometries()[1].name, "");
    assert_eq!(m.damping()[1].mass_nodes, [10]);
    assert_eq!(m.rigid_ties()[0].tied, [7]);
    assert_eq!(m.point_loads()[0].dofs, [(3, -5.0), (6, 100.0)]);
    assert_eq!(m.point_loads()[0].table.as_deref(), Some("ramp"));
    assert_eq!(m.outputs()[1].quantities, [Quantity::Displacement]);
    let methods: Vec<&Analysis> = m.load_cases().iter().map(|c| &c.analysis).collect();
    assert_eq!(methods.len(), 7);
    assert_eq!(m.load_cases()[0].point_loads[0].nodes, [10]);
    assert_eq!(
        m.point_laws()
            .iter()
            .map(|e| (e.node, e.dof, e.law().is_zero()))
            .collect::<Vec<_>>(),
        [(10, 3, true), (10, 6, true)]
    );
}

struct Expectation {
    stage: String,
    line: Option<usize>,
    column: Option<usize>,
    message: String,
}

fn expectation(path: &Path) -> Expectation {
    let bytes = fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let field = |key: &str| {
        text.lines().find_map(|l| {
            l.strip_prefix(&format!("$ expect-{key}:"))
                .map(|v| v.trim().to_string())
        })
    };
    let stage = field("stage").unwrap_or_else(|| panic!("{}: no expect-stage", path.display()));
    let line = field("line").map(|l| {
        l.parse()
            .unwrap_or_else(|_| panic!("{}: bad expect-line", path.display()))
    });
    let column = field("column").map(|c| {
        c.parse()
            .unwrap_or_else(|_| panic!("{}: bad expect-column", path.display()))
    });
    let message =
        field("message").unwrap_or_else(|| panic!("{}: no expect-message", path.display()));
    Expectation {
        stage,
        line,
        column,
        message,
    }
}

#[test]
fn bad_decks_fail_at_their_line_with_their_message() {
    let files = corpus("bad");
    assert!(
        files.len() >= 30,
        "the bad corpus has {} decks",
        files.len()
    );
    let mut read_stage = 0;
    for f in &files {
        let x = expectation(f);
        let result = read_no_panic(f);
        match x.stage.as_str() {
            "read" => {
                read_stage += 1;
                let line = x.line.unwrap_or_else(|| {
                    panic!("{}: a read-stage deck needs expect-line", f.display())
                });
                let e = match result {
                    Ok(_) => panic!("{}: read, but should fail at line {line}", f.display()),
                    Err(e) => e.to_string(),
                };
                assert!(
                    e.contains(&format!(":{line}:")),
                    "{}: expected line {line}, got: {e}",
                    f.display()
                );
                if let Some(col) = x.column {
                    assert!(
                        e.contains(&format!(":{line}:{col}:")),
                        "{}: expected line {line} column {col}, got: {e}",
                        f.display()
                    );
                }
                assert!(
                    e.contains(&x.message),
                    "{}: expected `{}`, got: {e}",
                    f.display(),
                    x.message
                );
                assert!(e.starts_with(&f.display().to_string()), "{e}");
            }
            "solve" => {
                if let Err(e) = result {
                    panic!("{}: a solve-stage deck must read: {e}", f.display());
                }
            }
            other => panic!("{}: unknown stage {other}", f.display()),
        }
    }
    assert!(read_stage >= 30, "{read_stage} read-stage decks");
}

#[test]
fn a_missing_file_is_a_deck_error() {
    let e = deck::read_file(Path::new("/nonexistent/deck.dat")).unwrap_err();
    assert_eq!(e.line(), None);
    assert!(
        e.to_string()
            .starts_with("/nonexistent/deck.dat: cannot read the file"),
        "{e}"
    );
}

/// A model that uses every field of model.rs and every enum variant.
fn every_field_model() -> Model {
    let nodes: Vec<Node> = (1..=8)
        .map(|i| Node {
            id: i,
            xyz: [12.5 * f64::from(i), 0.1 * f64::from(i * i), -1.0 / 3.0],
        })
        .chain([Node {
            id: 20,
            xyz: [50.0, 3.0, 40.0],
        }])
        .collect();
    let elements: Vec<Element> = (1..=7)
        .map(|i| Element {
            id: i,
            kind: if i <= 4 {
                ElementType::Beam98
            } else {
                ElementType::Beam52
            },
            nodes: [i, i + 1],
        })
        .collect();
    let direct = |i| Analysis::Transient {
        dt: 2.5e-5,
        total_time: 0.3,
        method: TransientMethod::Direct(i),
    };
    ModelParts {
        title: "every field, 1/3".to_string(),
        element_types: vec![ElementType::Beam98, ElementType::Beam52],
        lumped_mass: true,
        nodes,
        elements,
        node_sets: vec![
            NodeSet {
                name: "base".into(),
                nodes: vec![1],
            },
            NodeSet {
                name: "spread".into(),
                nodes: vec![2, 3, 4, 6, 8],
            },
            NodeSet {
                name: "empty".into(),
                nodes: vec![],
            },
        ],
        element_sets: vec![
            ElementSet {
                name: "coil".into(),
                elements: vec![1, 2, 3, 4],
            },
            ElementSet {
                name: "end_part".into(),
                elements: vec![5, 6, 7],
            },
        ],
        materials: vec![
            Material {
                name: "steel".into(),
                youngs_modulus: 190708.0,
                poisson: 0.3,
                density: 7.85e-9,
                elements: vec![1, 2, 3, 4],
            },
            Material {
                name: "soft".into(),
                youngs_modulus: 1.0e3,
                poisson: -0.25,
                density: 0.0,
                elements: vec![5, 6, 7],
            },
        ],
        geometries: vec![
            Geometry {
                name: "wire".into(),
                section: Section::SolidCircle { diameter: 3.0 },
                orientation: [0.0, 0.0, 1.0],
                elements: vec![1, 2],
            },
            Geometry {
                name: String::new(),
                section: Section::General {
                    area: 7.1,
                    iyy: 4.2,
                    izz: 4.3,
                    torsion: 8.4,
                    shear_coefficient: 0.886,
                },
                orientation: [0.0, 1.0e-3, 1.0],
                elements: vec![3, 4],
            },
            Geometry {
                name: "bar".into(),
                section: Section::General {
                    area: 1.0e2,
                    iyy: 833.3,
                    izz: 8.333e2,
                    torsion: 1.4e3,
                    shear_coefficient: 0.0,
                },
                orientation: [0.0, 0.0, -1.0],
                elements: vec![5, 6, 7],
            },
        ],
        damping: vec![
            Damping {
                alpha: 0.7,
                beta: 3.0e-5,
                elements: vec![1, 2, 3, 4],
                mass_nodes: vec![20],
            },
            Damping {
                alpha: 0.0,
                beta: 1.0e-6,
                elements: vec![5, 7],
                mass_nodes: vec![],
            },
            Damping {
                alpha: 1.5,
                beta: 0.0,
                elements: vec![],
                mass_nodes: vec![8, 20],
            },
        ],
        point_masses: vec![
            PointMass {
                node: 20,
                mass: 0.00231,
                inertia: [0.0, 1.25, 3.5e-2],
            },
            PointMass {
                node: 8,
                mass: 1.0e-6,
                inertia: [0.0; 3],
            },
        ],
        rigid_ties: vec![RigidTie {
            name: "top".into(),
            reference: 20,
            dofs: vec![1, 2, 3, 6],
            tied: vec![6, 7],
        }],
        fixed_disp: vec![
            FixedDisp {
                dofs: vec![(1, 0.0), (2, 0.0), (3, 0.0), (4, 0.0), (5, 0.0), (6, 0.0)],
                nodes: vec![1],
            },
            FixedDisp {
                dofs: vec![(3, 0.25), (1, -1.0e-3)],
                nodes: vec![2, 3],
            },
        ],
        point_loads: vec![
            PointLoad {
                dofs: vec![(3, -10.0)],
                nodes: vec![20],
                table: None,
            },
            PointLoad {
                dofs: vec![(1, 1.0), (5, 2.5e3)],
                nodes: vec![4, 5],
                table: Some("pulse".into()),
            },
        ],
        tables: vec![Table {
            name: "pulse".into(),
            points: vec![(0.0, 0.0), (1.0e-3, 1.0), (2.0e-3, 0.0)],
        }],
        initial_velocities: vec![
            InitialVelocity {
                dofs: vec![(3, -250.0), (6, 0.5)],
                nodes: vec![20],
                quasi_static: true,
            },
            InitialVelocity {
                dofs: vec![(1, 4.0)],
                nodes: vec![20],
                quasi_static: false,
            },
        ],
        outputs: vec![
            OutputRequest {
                nodes: vec![20],
                dofs: vec![3],
                quantities: vec![
                    Quantity::Displacement,
                    Quantity::Velocity,
                    Quantity::Acceleration,
                ],
                every: 1,
            },
            OutputRequest {
                nodes: vec![2, 3, 4, 6, 8],
                dofs: vec![1, 2, 3, 4, 5, 6],
                quantities: vec![Quantity::Acceleration],
                every: 25,
            },
        ],
        load_cases: vec![
            LoadCase {
                title: "static".into(),
                analysis: Analysis::Static {
                    steps: 3,
                    time: 0.5,
                },
                point_loads: vec![PointLoad {
                    dofs: vec![(3, -1.0)],
                    nodes: vec![20],
                    table: None,
                }],
            },
            LoadCase {
                title: String::new(),
                analysis: Analysis::Modal { modes: 12 },
                point_loads: vec![],
            },
            LoadCase {
                title: "newmark".into(),
                analysis: direct(Integrator::AverageAcceleration),
                point_loads: vec![],
            },
            LoadCase {
                title: "hht".into(),
                analysis: direct(Integrator::Hht { alpha: -1.0 / 3.0 }),
                point_loads: vec![],
            },
            LoadCase {
                title: "generalised alpha".into(),
                analysis: direct(Integrator::GeneralizedAlpha { rho_inf: 0.0 }),
                point_loads: vec![PointLoad {
                    dofs: vec![(2, 7.0)],
                    nodes: vec![20],
                    table: Some("pulse".into()),
                }],
            },
            LoadCase {
                title: "modal superposition".into(),
                analysis: Analysis::Transient {
                    dt: 1.0e-4,
                    total_time: 1.0e-4,
                    method: TransientMethod::Modal { modes: 8 },
                },
                point_loads: vec![],
            },
        ],
        point_laws: vec![
            PointElement {
                node: 20,
                dof: 3,
                cubic: 2.5e-3,
                quadratic: 1.0e-7,
                friction: 0.75,
            },
            PointElement {
                node: 20,
                dof: 6,
                cubic: 0.0,
                quadratic: 0.0,
                friction: 12.5,
            },
        ],
        dashpots: vec![Dashpot {
            node: 20,
            dof: 3,
            c: 2.5e-4,
        }],
        modal_damping: ModalDamping {
            loss_factor: 3.5e-3,
            loss_factor_modes: 12,
            ratios: vec![0.0, 0.02, 0.005],
        },
        beam_tensions: vec![BeamTension {
            force: 2.0e4,
            elements: vec![1, 2],
        }],
        tension_links: vec![TensionLink {
            nodes: [2, 3],
            dof: 3,
            stiffness: 100.0,
            slack: -1.0,
        }],
        moving_contacts: Vec::new(),
        matrix_elements: vec![MatrixElement {
            name: "head".into(),
            dofs: vec![(20, 3), (2, 1)],
            stiffness: vec![2.5, -0.5, -0.5, 1.0],
            mass: vec![1.0e-6, 0.0, 0.0, 2.0e-6],
            damping: vec![1.0e-3, 0.0, 0.0, 0.0],
        }],
    }
    .build()
    .expect("every field is valid")
}

#[test]
fn a_model_using_every_field_round_trips() {
    let m = every_field_model();
    let text = deck::write(&m);
    let back = deck::read_str(&text, "written.dat").unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(back, m);
    let mentat = deck::write_mentat(&m);
    let back = deck::read_str(&mentat, "written.dat").unwrap_or_else(|e| panic!("{e}\n{mentat}"));
    assert_eq!(back, m, "Mentat format");
    // And the writer is a fixed point of read o write.
    assert_eq!(deck::write(&back), text);
}

#[test]
fn good_decks_round_trip_through_the_writer() {
    for f in corpus("good") {
        let m = read_no_panic(&f).unwrap();
        let text = deck::write(&m);
        let back = deck::read_str(&text, "written.dat")
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", f.display()));
        assert_eq!(back, m, "{}", f.display());
        // Marc's extended fixed format reads back to the same model too.
        let text = deck::write_mentat(&m);
        let back = deck::read_str(&text, "written_mentat.dat")
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", f.display()));
        assert_eq!(back, m, "{} (Mentat format)", f.display());
    }
}

#[test]
fn written_decks_are_readable_marc_style() {
    let text = deck::write(&every_field_model());
    for needle in [
        "$ units: length mm, force N, mass t (tonne), time s",
        "END\n",
        "CONNECTIVITY\n",
        "COORDINATES\n",
        "3, 9, 0, 1\n",
        "DEFINE, ELEMENT, SET, coil\n1 TO 4\n",
        "ISOTROPIC\n",
        "190708.0, 0.3, 7.85e-9\n",
        "FIXED DISP\n",
        "POINT LOAD, TABLE, pulse\n",
        "END OPTION\n",
        "DYNAMIC CHANGE\n",
        "CONTINUE\n",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
}

/// Deterministic mutations of every deck of the corpus: truncation at every line,
/// deletion of every line, swaps of neighbouring lines and of neighbouring fields, and
/// replacements of fields by hostile tokens. The reader must answer Ok or Err, never panic.
#[test]
fn mutated_decks_never_panic() {
    let hostile = [
        "",
        "NaN",
        "-1",
        "0",
        "4294967296",
        "1e999",
        "TO",
        "C",
        "END",
        "x",
        "1 TO",
        "$",
        ",",
        "\u{7}",
    ];
    let mut count = 0usize;
    let mut check = |text: &str| {
        count += 1;
        let r = catch_unwind(AssertUnwindSafe(|| deck::read_str(text, "mutant.dat")));
        assert!(r.is_ok(), "the reader panicked on:\n{text}");
    };
    for f in corpus("good").into_iter().chain(corpus("bad")) {
        let text = String::from_utf8_lossy(&fs::read(&f).unwrap()).into_owned();
        let lines: Vec<&str> = text.lines().collect();
        for k in 0..=lines.len() {
            check(&lines[..k].join("\n"));
            if k < lines.len() {
                let mut cut = lines.clone();
                cut.remove(k);
                check(&cut.join("\n"));
            }
            if k + 1 < lines.len() {
                let mut swapped = lines.clone();
                swapped.swap(k, k + 1);
                check(&swapped.join("\n"));
            }
        }
        for (k, line) in lines.iter().enumerate() {
            let fields: Vec<&str> = line.split(',').collect();
            let rebuild = |new_line: String| {
                let mut all: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
                all[k] = new_line;
                all.join("\n")
            };
            for i in 0..fields.len() {
                if i + 1 < fields.len() {
                    let mut swapped = fields.clone();
                    swapped.swap(i, i + 1);
                    check(&rebuild(swapped.join(",")));
                }
                // Each field replaced by one hostile token, chosen by position.
                let mut replaced: Vec<String> = fields.iter().map(|s| s.to_string()).collect();
                replaced[i] = hostile[(k * 7 + i) % hostile.len()].to_string();
                check(&rebuild(replaced.join(",")));
            }
        }
    }
    assert!(count > 10_000, "only {count} mutants");
}

const BEGIN: &str = "<!-- BEGIN GENERATED CARD REFERENCE -->\n";
const END: &str = "<!-- END GENERATED CARD REFERENCE -->";

/// docs/deck.md's card reference is the keyword table's. With COIL_BLESS_DOCS=1 the
/// test rewrites it (through a temporary file) instead of failing.
#[test]
fn deck_reference_matches_the_keyword_table() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/deck.md");
    let text = fs::read_to_string(&path).unwrap();
    let start = text
        .find(BEGIN)
        .expect("docs/deck.md lacks the BEGIN marker")
        + BEGIN.len();
    let end = text.find(END).expect("docs/deck.md lacks the END marker");
    let generated = deck::reference_markdown();
    if text[start..end] == generated {
        return;
    }
    if std::env::var_os("COIL_BLESS_DOCS").is_some() {
        let updated = format!("{}{generated}{}", &text[..start], &text[end..]);
        let tmp = path.with_extension("md.tmp");
        fs::write(&tmp, updated).unwrap();
        fs::rename(&tmp, &path).unwrap();
        return;
    }
    panic!("docs/deck.md's card reference differs from the keyword table; rerun with COIL_BLESS_DOCS=1");
}
