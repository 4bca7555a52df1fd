//! The trial's classes of hostile input on the newer surfaces, as a seeded generated set
//! with the fixed budget of [`super::fuzz`] (`COIL_FUZZ_INPUTS=N` per family for a
//! nightly run; the default is small):
//! - **catenary and matrix cards** through `coil-solve`: a `MOVING CONTACT` pressing
//!   along its own line, a line list naming both wires or nodes not joined one to the
//!   next, up to 20,000 identical `TENSION LINK`s, a `DMIG` announcing 4e9 DOFs, and
//!   random edits of the catenary and every-card decks;
//! - **record readers** through `coil-tune calibrate` (which reads every decay record
//!   first): the same decay as UFF 58 (ASCII and binary), MAT-file v6 and v7, and a
//!   semicolon / decimal-comma CSV; an unknown UFF unit label, a UFF file behind a byte
//!   order mark, a 1 MB MAT-file whose compressed arrays inflate to 180 MiB (named or
//!   not), and random edits and byte flips of each.
//!
//! Every input is checked as in [`super::fuzz::check`] (no panic, abort or hang past
//! [`super::fuzz::HANG_S`], nothing outside the output folder touched, no half set, a
//! short message without control characters). On top: a targeted class must end as
//! stated (refused naming its card or field, or read); every refusal must name the file
//! and a line, field or variable (`d.dat:12:`, `decay.mat:variable ...`); each class's
//! peak memory (the child's `ru_maxrss`) and slowest input are printed, and the bounded
//! ones are asserted (the MAT-file bomb under 200 MB, the identical links under 5 s).

use std::collections::BTreeMap;
use std::process::Command;

use super::fuzz::{bin, budget, calibrate_first_point, mutate, repo, run, Outcome, Rng};

/// Per class: inputs, refused, silent acceptances, refusals without a location, peak
/// memory (KiB), slowest input (s).
#[derive(Default)]
struct Tally {
    inputs: usize,
    refused: usize,
    silent: usize,
    unlocated: usize,
    peak_kib: i64,
    slowest_s: f64,
}

/// What a class's input must give.
#[derive(Clone, Copy, PartialEq)]
enum Expect {
    /// Refused, the message holding this text.
    Refused(&'static str),
    /// Read (exit 0).
    Read,
    /// Either; a refusal must be located.
    Any,
}

struct Surface {
    name: &'static str,
    /// The input file's name, which a located message starts with.
    file: &'static str,
    classes: BTreeMap<&'static str, Tally>,
}

impl Surface {
    fn new(name: &'static str, file: &'static str) -> Surface {
        Surface {
            name,
            file,
            classes: BTreeMap::new(),
        }
    }

    /// Records one outcome of `class`.
    fn add(&mut self, class: &'static str, expect: Expect, o: &Outcome) {
        let t = self.classes.entry(class).or_default();
        t.inputs += 1;
        t.peak_kib = t.peak_kib.max(o.peak_kib);
        t.slowest_s = t.slowest_s.max(o.seconds);
        if o.code != 0 {
            t.refused += 1;
            // `file:12:` or `file:variable ...` or `file:dataset 1 ...`: a place in it.
            let located = o
                .stderr
                .find(&format!("{}:", self.file))
                .map(|at| &o.stderr[at + self.file.len() + 1..])
                .is_some_and(|rest| {
                    rest.starts_with(|c: char| c.is_ascii_digit())
                        || rest.starts_with("variable")
                        || rest.starts_with("dataset")
                        || rest.starts_with("byte")
                });
            if !located {
                t.unlocated += 1;
                eprintln!("  unlocated ({class}): {}", o.stderr.trim());
            }
        }
        let silent = match expect {
            Expect::Refused(text) => o.code == 0 || !o.stderr.contains(text),
            Expect::Read => o.code != 0,
            Expect::Any => false,
        };
        if silent {
            t.silent += 1;
            eprintln!(
                "  not as stated ({class}): exit {}: {}",
                o.code,
                o.stderr.trim()
            );
        }
    }

    /// Prints the table and asserts the targets: no silent acceptance, every refusal
    /// located.
    fn finish(self) {
        eprintln!(
            "fuzz {}: class, inputs, refused, silent, unlocated, peak MB, slowest s",
            self.name
        );
        let (mut silent, mut unlocated) = (0, 0);
        for (class, t) in &self.classes {
            eprintln!(
                "  {class:<28} {:>5} {:>5} {:>3} {:>3} {:>8.1} {:>7.2}",
                t.inputs,
                t.refused,
                t.silent,
                t.unlocated,
                t.peak_kib as f64 / 1024.0,
                t.slowest_s
            );
            silent += t.silent;
            unlocated += t.unlocated;
        }
        assert_eq!(silent, 0, "{}: inputs not ending as stated", self.name);
        assert_eq!(unlocated, 0, "{}: refusals that name no place", self.name);
    }
}

/// The catenary-in-miniature deck with one of the trial's edits, its class and what it
/// must give.
fn contact_deck(base: &str, every: &str, rng: &mut Rng) -> (String, &'static str, Expect) {
    let contact = "10, 3, 50.0, 2.0e4, 500.0\n1 TO 4\n";
    match rng.below(7) {
        0 => (
            // The wire runs along x: pressing along DOF 1.
            base.replace(contact, "10, 1, 50.0, 2.0e4, 500.0\n1 TO 4\n"),
            "contact along its line",
            Expect::Refused("own direction"),
        ),
        1 => {
            let list = rng.pick(&["1 TO 8", "1 TO 4 5 TO 8", "1, 2, 6, 7", "1 TO 4 6"]);
            (
                base.replace(contact, &format!("10, 3, 50.0, 2.0e4, 500.0\n{list}\n")),
                "both wires in one line",
                Expect::Refused("not on one straight line"),
            )
        }
        2 => (
            base.replace(contact, "10, 3, 50.0, 2.0e4, 500.0\n1, 3, 4\n"),
            "line nodes not joined",
            Expect::Refused("no element joins nodes 1 and 3"),
        ),
        3 => {
            let n = [2, 10, 1000, 20_000][rng.below(4)];
            let links = "2, 6, 3, 100.0, -0.5\n".repeat(n);
            (
                base.replacen("2, 6, 3, 100.0, -0.5\n", &links, 1),
                "identical tension links",
                Expect::Refused("already links nodes 2 and 6"),
            )
        }
        4 => (
            every.replacen("1, 1, 1, pad\n", "1, 4000000000, 1, pad\n", 1),
            "DMIG of 4e9 DOFs",
            Expect::Refused("DMIG"),
        ),
        5 => (mutate(every, rng), "every card, edited", Expect::Any),
        _ => (mutate(base, rng), "catenary deck, edited", Expect::Any),
    }
}

#[test]
fn the_trials_classes_on_the_new_surfaces() {
    let Some(solve) = bin("coil-solve") else {
        eprintln!("fuzz cards: coil-solve not built beside coil-tune; skipped");
        return records();
    };
    let read = |f: &str| std::fs::read_to_string(repo().join("tests/decks/good").join(f)).unwrap();
    let (base, every) = (read("moving_contact.dat"), read("every_card.dat"));
    let mut surface = Surface::new("catenary and matrix cards", "d.dat");
    let mut rng = Rng(0x5851f42d4c957f2d);
    for i in 0..budget() * 2 {
        let sandbox = tempfile::tempdir().unwrap();
        let (deck, class, expect) = contact_deck(&base, &every, &mut rng);
        std::fs::write(sandbox.path().join("d.dat"), deck).unwrap();
        let mut c = Command::new(&solve);
        c.args(["d.dat", "--out", "out", "--quiet"]);
        let o = run(
            &format!("{class} {i}"),
            c,
            sandbox.path(),
            &sandbox.path().join("out"),
        );
        if class == "identical tension links" {
            assert!(o.seconds < 5.0, "{class} {i}: {} s", o.seconds);
        }
        surface.add(class, expect, &o);
    }
    surface.finish();
    records();
}

/// The decay record of `friction_g1` (3000 samples) as `(time, acceleration)`.
fn decay() -> (Vec<f64>, Vec<f64>) {
    let text =
        std::fs::read_to_string(repo().join("cases/measured/friction_g1/decay.csv")).unwrap();
    text.lines()
        .skip(1)
        .take(3000)
        .map(|l| {
            let (t, a) = l.split_once(',').unwrap();
            (t.parse::<f64>().unwrap(), a.parse::<f64>().unwrap())
        })
        .unzip()
}

fn uff(values: &[f64], step: f64, unit: &str, binary: bool) -> Vec<u8> {
    let d = coil_io::uff::Uff58 {
        description: "decay".into(),
        name: "a".into(),
        node: 1,
        direction: 3,
        ordinate_type: 12,
        length_exponent: 1,
        ordinate_label: "acceleration".into(),
        ordinate_unit: unit.into(),
        start_s: 0.0,
        step_s: step,
        values: values.to_vec(),
    };
    coil_io::uff::uff58_bytes(&[d], binary)
}

/// One record file of a class: `(file name, bytes, record entry, class, expectation)`.
type RecordInput = (
    &'static str,
    Vec<u8>,
    serde_json::Value,
    &'static str,
    Expect,
);

fn record_input(rng: &mut Rng, t: &[f64], a: &[f64], bomb: &[u8]) -> RecordInput {
    use coil_postproc::record::mat::{doubles, level5_bytes};
    use serde_json::json;
    let step = t[1] - t[0];
    let (t8, a8) = (doubles(t), doubles(a));
    let mat = |compressed| {
        level5_bytes(
            &[("time_s", 9, &t8, t.len()), ("acc", 9, &a8, a.len())],
            compressed,
        )
    };
    // A MAT-file's variables state no unit: the entry does.
    let entry = |file: &str, channel: &str| match file.ends_with(".mat") {
        true => json!({"file": file, "channel": channel, "unit": "m/s^2"}),
        false => json!({"file": file, "channel": channel}),
    };
    let flip = |mut bytes: Vec<u8>, rng: &mut Rng| {
        for _ in 0..1 + rng.below(4) {
            let at = rng.below(bytes.len());
            match rng.below(3) {
                0 => bytes[at] ^= 1 << rng.below(8),
                1 => bytes.truncate(at.max(1)),
                _ => bytes[at] = 0xff,
            }
        }
        bytes
    };
    match rng.below(9) {
        0 => {
            let unit = rng.pick(&["ft/s^2", "furlong", "m/s^3", "N"]);
            (
                "decay.uff",
                uff(a, step, unit, rng.below(2) == 0),
                entry("decay.uff", "1"),
                "UFF unknown unit",
                Expect::Refused("is not a unit coil knows"),
            )
        }
        1 => {
            let mut bytes = b"\xef\xbb\xbf".to_vec();
            bytes.extend(uff(a, step, "m/s^2", false));
            (
                "decay.uff",
                bytes,
                entry("decay.uff", "1"),
                "UFF behind a BOM",
                Expect::Read,
            )
        }
        2 => (
            "decay.mat",
            bomb.to_vec(),
            entry("decay.mat", "acc"),
            "MAT bomb, not named",
            Expect::Read,
        ),
        3 => {
            let name = rng.pick(&["z1", "z2", "z3"]);
            (
                "decay.mat",
                bomb.to_vec(),
                entry("decay.mat", name),
                "MAT bomb, named",
                Expect::Refused("values a variable"),
            )
        }
        4 => {
            let text = String::from_utf8(uff(a, step, "m/s^2", false)).unwrap();
            (
                "decay.uff",
                mutate(&text, rng).into_bytes(),
                entry("decay.uff", "1"),
                "UFF ASCII, edited",
                Expect::Any,
            )
        }
        5 => (
            "decay.uff",
            flip(uff(a, step, "m/s^2", true), rng),
            entry("decay.uff", "1"),
            "UFF binary, flipped",
            Expect::Any,
        ),
        6 => {
            let compressed = rng.below(2) == 0;
            (
                "decay.mat",
                flip(mat(compressed), rng),
                entry("decay.mat", "acc"),
                "MAT, flipped",
                Expect::Any,
            )
        }
        7 => {
            let mut text = String::from("% logger\nZeit [s];Beschl. [m/s^2]\n");
            for (x, y) in t.iter().zip(a) {
                text.push_str(&format!("{x};{y}\n").replace('.', ","));
            }
            (
                "decay.csv",
                mutate(&text, rng).into_bytes(),
                json!("decay.csv"),
                "CSV dialect, edited",
                Expect::Any,
            )
        }
        _ => (
            "decay.mat",
            mat(true),
            entry("decay.mat", "acc"),
            "MAT v7, as written",
            Expect::Read,
        ),
    }
}

/// A compressed MAT array of `n` zero bytes (a multiple of 1 MiB) named `name`, built a
/// MiB at a time: the test process never holds the 60 MiB, so that its own memory stays
/// below what the children's peaks measure (a child's `ru_maxrss` starts from it).
fn zero_array(name: &str, n: usize) -> Vec<u8> {
    use miniz_oxide::deflate::core::{
        compress_to_output, create_comp_flags_from_zip_params, CompressorOxide, TDEFLFlush,
    };
    let word = |x: usize| (x as u32).to_le_bytes();
    let mut padded = name.as_bytes().to_vec();
    padded.resize(name.len().div_ceil(8) * 8, 0);
    let mut head = Vec::new();
    for part in [word(14), word(40 + padded.len() + 8 + n)] {
        head.extend(part);
    }
    for part in [
        word(6),
        word(8),
        word(6),
        word(0),
        word(5),
        word(8),
        word(1),
        word(n),
    ] {
        head.extend(part);
    }
    head.extend(word(1));
    head.extend(word(name.len()));
    head.extend(padded);
    head.extend(word(2));
    head.extend(word(n));
    let mut c = CompressorOxide::new(create_comp_flags_from_zip_params(6, 15, 0));
    let mut z = Vec::new();
    let mut put = |input: &[u8], flush| {
        compress_to_output(&mut c, input, flush, |b| {
            z.extend_from_slice(b);
            true
        });
    };
    put(&head, TDEFLFlush::None);
    let zeros = vec![0u8; 1 << 20];
    for _ in 0..n >> 20 {
        put(&zeros, TDEFLFlush::None);
    }
    put(&[], TDEFLFlush::Finish);
    let mut out = word(15).to_vec();
    out.extend(word(z.len()));
    out.extend(z);
    out
}

/// The record readers' family (module docs).
fn records() {
    let (t, a) = decay();
    // Three arrays of 60 MiB of zeros beside the record: about 180 KB compressed.
    let (t8, a8) = (
        coil_postproc::record::mat::doubles(&t),
        coil_postproc::record::mat::doubles(&a),
    );
    let mut bomb = coil_postproc::record::mat::level5_bytes(
        &[("time_s", 9, &t8, t.len()), ("acc", 9, &a8, a.len())],
        true,
    );
    for name in ["z1", "z2", "z3"] {
        bomb.extend(zero_array(name, 60 << 20));
    }
    let case = repo().join("cases/measured/friction_g1");
    let mut case_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(case.join("case.json")).unwrap()).unwrap();
    // calibrate tunes to targets: the paper's figures (only the records are under test).
    case_json["targets"] = serde_json::json!({
        "stiffness_n_mm": 3.9275, "damping_ratio": 0.00175, "period_s": 0.23
    });
    let static_csv = std::fs::read(case.join("static.csv")).unwrap();
    let mut surfaces: BTreeMap<&str, Surface> = BTreeMap::new();
    let mut rng = Rng(0x2545f4914f6cdd1d ^ 0xa5a5);
    for i in 0..budget() {
        let sandbox = tempfile::tempdir().unwrap();
        let dir = sandbox.path().join("case");
        std::fs::create_dir(&dir).unwrap();
        let (file, bytes, entry, class, expect) = record_input(&mut rng, &t, &a, &bomb);
        std::fs::write(dir.join(file), bytes).unwrap();
        std::fs::write(dir.join("static.csv"), &static_csv).unwrap();
        let mut json = case_json.clone();
        json["records"]["decay"] = serde_json::json!([entry]);
        std::fs::write(dir.join("case.json"), json.to_string()).unwrap();
        let o = run(
            &format!("{class} {i}"),
            calibrate_first_point(),
            sandbox.path(),
            &sandbox.path().join("cal"),
        );
        if class.starts_with("MAT bomb") {
            assert!(o.peak_kib < 200 * 1024, "{class} {i}: {} KiB", o.peak_kib);
        }
        let surface = match file {
            "decay.uff" => "UFF 58",
            "decay.mat" => "MAT-file",
            _ => "CSV dialects",
        };
        surfaces
            .entry(surface)
            .or_insert_with(|| Surface::new(surface, file))
            .add(class, expect, &o);
    }
    for s in surfaces.into_values() {
        s.finish();
    }
}
