//! The design surface under a seeded generated set of bad input: `SPRING.json` through
//! `coil-tune check`, `TARGET.json` through `coil-tune design`, and their flags, by class,
//! through the real binary with every check of [`super::fuzz::run`] (no panic, abort or
//! hang past [`super::fuzz::HANG_S`], nothing outside the output folder touched, no half
//! set, a short message without control characters). On top, per class:
//! - **misspelled**: a key (at the top, inside `envelope` or `material`) with one typing
//!   slip; refused, the message naming the key as written;
//! - **missing**: a key left out; a required one (or one of a required pair or choice) is
//!   refused naming it, an optional one is read;
//! - **wrong type**: a string, a boolean, an array or an object where a number is due (or
//!   the reverse); refused naming the key;
//! - **out of range**: a value outside the key's stated domain (docs/spring-design.md:
//!   positive lengths and forces, whole counts, a quality grade of 1 to 3, a seating
//!   coefficient of 0.5 to 2, a tolerance below 50 %, 1 to 64 springs in parallel, a
//!   short list of 1 to 32, ordered working points, a keyword of its list); refused
//!   naming the key;
//! - **null**: an explicit `null` (refused naming the key, as case.json refuses one);
//! - **unknown grade**: refused naming the grade as written and the known ones;
//! - **zeta**: a target damping ratio outside (0, 1) refused naming `damping_ratio`, one
//!   inside read;
//! - **work**: a low or high rate, a wide tolerance, no envelope, up to 10^9 springs in
//!   parallel: read within [`WORK_S`] or refused naming the bound (work is checked
//!   before it starts, docs/files.md);
//! - **flags**: `--short-list`, `--elements-per-coil`, `--objective` out of range,
//!   refused naming the flag, as the file refuses the same value;
//! - **in domain**: a value inside its domain but extreme or inconsistent with the others
//!   (a wire thicker than the coil, 10^6 coils, a free length below solid): read, or
//!   refused naming a key of the file.
//!
//! The counts per class (inputs, refused, silent acceptances, refusals not naming the
//! field, slowest input) are printed; the test fails on any silent acceptance or unnamed
//! refusal. The default budget is [`DEFAULT_PER_CLASS`] inputs per class (seconds);
//! `COIL_FUZZ_INPUTS=N` takes N per class (a nightly run: e.g. 200).

use super::fuzz::{repo, run, Outcome, Rng};
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// Inputs per class in the default run.
const DEFAULT_PER_CLASS: usize = 4;

/// The longest a design or a check of the work class may run (s): the search is bounded
/// by its count before it starts, the FE verification by its number of runs and beams.
const WORK_S: f64 = 20.0;

fn per_class() -> usize {
    std::env::var("COIL_FUZZ_INPUTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_PER_CLASS)
}

/// What a key must hold (the test's own reading of docs/spring-design.md).
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// A number; the out-of-domain values to try.
    Number(&'static [f64]),
    /// A keyword of the list.
    Keyword,
    /// Free text.
    Text,
    /// true or false.
    Bool,
    /// `[lo, hi]`.
    Band,
    /// An object (`envelope`, `material`).
    Object,
}

/// Whether a key may be left out.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Need {
    Required,
    Optional,
}

/// One key of a file: its path (`envelope.max_free_length_mm`), kind and need.
#[derive(Clone, Copy, Debug)]
struct Key {
    path: &'static str,
    kind: Kind,
    need: Need,
}

const POSITIVE: &[f64] = &[-1.0, 0.0, -1e-300];
const NON_NEGATIVE: &[f64] = &[-1.0, -1e-9];

/// The keys of the base SPRING.json ([`base_spring`]).
fn spring_keys() -> Vec<Key> {
    use Kind::*;
    use Need::*;
    let k = |path, kind, need| Key { path, kind, need };
    vec![
        k("wire_diameter_mm", Number(POSITIVE), Required),
        k("mean_diameter_mm", Number(&[-1.0, 0.0, 2.0, 3.0]), Required),
        k("active_coils", Number(POSITIVE), Required),
        k("total_coils", Number(&[-1.0, 0.0, 10.0]), Required),
        k("free_length_mm", Number(&[-1.0, 0.0, 30.0]), Required),
        k("end_type", Keyword, Required),
        k("coiling", Keyword, Required),
        k("shear_modulus_mpa", Number(POSITIVE), Optional),
        k("youngs_modulus_mpa", Number(POSITIVE), Optional),
        k("density_kg_m3", Number(POSITIVE), Optional),
        k("wire_grade", Keyword, Required),
        k(
            "seating_coefficient",
            Number(&[-1.0, 0.0, 0.3, 2.5, 1e9]),
            Optional,
        ),
        k("force_1_n", Number(&[-1.0, 120.0, 500.0]), Required),
        k("force_2_n", Number(&[-1.0, 0.0, 40.0, 10.0]), Required),
        k("loading", Keyword, Required),
        k("stress_correction", Keyword, Optional),
        k("wire_tolerance_mm", Number(NON_NEGATIVE), Optional),
        k("measured_rate_n_mm", Number(POSITIVE), Optional),
        k("shot_peened", Bool, Optional),
        k("quality_grade", Number(&[0.0, 4.0, 2.5, -1.0]), Optional),
        k("head_mass_kg", Number(POSITIVE), Optional),
        k("source", Text, Optional),
    ]
}

/// The keys of the base TARGET.json ([`base_target`]).
fn target_keys() -> Vec<Key> {
    use Kind::*;
    use Need::*;
    let k = |path, kind, need| Key { path, kind, need };
    vec![
        k("rate_n_mm", Number(POSITIVE), Required),
        k(
            "rate_tolerance_percent",
            Number(&[-1.0, 0.0, 50.0, 80.0]),
            Required,
        ),
        k("weight_kg", Number(POSITIVE), Optional),
        k("force_1_n", Number(&[-1.0, 77.0, 300.0]), Required),
        k("force_2_n", Number(&[-1.0, 0.0, 51.4, 10.0]), Required),
        k(
            "springs_in_parallel",
            Number(&[0.0, -1.0, 1.5, 65.0, 1e9]),
            Optional,
        ),
        k("envelope", Object, Optional),
        k("envelope.max_outer_diameter_mm", Number(POSITIVE), Optional),
        k("envelope.min_inner_diameter_mm", Number(POSITIVE), Optional),
        k("envelope.max_free_length_mm", Number(POSITIVE), Optional),
        k("envelope.max_solid_length_mm", Number(POSITIVE), Optional),
        k("material", Object, Required),
        k("material.grade", Keyword, Required),
        k("objective", Keyword, Required),
        k("end_type", Keyword, Optional),
        k("coiling", Keyword, Optional),
        k("loading", Keyword, Optional),
        k(
            "seating_coefficient",
            Number(&[-1.0, 0.0, 0.3, 2.5]),
            Optional,
        ),
        k("surge_band_hz", Band, Optional),
        k("short_list", Number(&[0.0, 33.0, 1.5, -1.0]), Optional),
        k("shot_peened", Bool, Optional),
        k("quality_grade", Number(&[0.0, 4.0, 2.5]), Optional),
        k("source", Text, Optional),
    ]
}

/// The 160ECT spring of `cases/spring-design` (a wire grade, forces, dynamic loading).
fn base_spring() -> Value {
    let text =
        std::fs::read_to_string(repo().join("cases/spring-design/160ect_spring.json")).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    let o = v.as_object_mut().unwrap();
    o.insert("stress_correction".into(), "bergstraesser".into());
    o.insert("wire_tolerance_mm".into(), 0.0.into());
    o.insert("shot_peened".into(), false.into());
    o.insert("quality_grade".into(), 2.into());
    o.insert("head_mass_kg".into(), 5.3.into());
    v
}

/// The acceptance's 160ECT target on a wire grade (no calibration to run first).
fn base_target() -> Value {
    json!({
        "source": "the generated set's base target",
        "rate_n_mm": 3.9275,
        "rate_tolerance_percent": 1.0,
        "weight_kg": 5.3,
        "force_1_n": 51.4,
        "force_2_n": 77,
        "springs_in_parallel": 1,
        "envelope": {
            "max_outer_diameter_mm": 27.0,
            "min_inner_diameter_mm": 21.0,
            "max_free_length_mm": 100.0,
            "max_solid_length_mm": 50.0
        },
        "material": { "grade": "DM" },
        "objective": "lightest",
        "end_type": "closed_ground",
        "coiling": "cold",
        "loading": "dynamic",
        "seating_coefficient": 0.5,
        "surge_band_hz": [40, 60],
        "short_list": 1,
        "shot_peened": false,
        "quality_grade": 2
    })
}

/// The object holding `path`'s last part, and that part.
fn parent<'a>(v: &'a mut Value, path: &'a str) -> (&'a mut Map<String, Value>, &'a str) {
    match path.split_once('.') {
        Some((outer, inner)) => (v[outer].as_object_mut().unwrap(), inner),
        None => (v.as_object_mut().unwrap(), path),
    }
}

/// One typing slip in `name`: a letter dropped, doubled or swapped, a dash for an
/// underscore, a capital, an `s` at the end.
fn misspell(name: &str, rng: &mut Rng) -> String {
    let chars: Vec<char> = name.chars().collect();
    let i = rng.below(chars.len());
    let mut out = chars.clone();
    match rng.below(6) {
        0 if chars.len() > 2 => {
            out.remove(i);
        }
        1 => out.insert(i, chars[i]),
        2 if i + 1 < chars.len() && chars[i] != chars[i + 1] => out.swap(i, i + 1),
        3 if name.contains('_') => return name.replacen('_', "-", 1),
        4 => return name[..1].to_uppercase() + &name[1..],
        _ => out.push('s'),
    }
    out.into_iter().collect()
}

/// A value of another kind than `kind` holds.
fn wrong_type(kind: Kind, rng: &mut Rng) -> Value {
    let pick = rng.below(4);
    match kind {
        Kind::Number(_) => [json!("3"), json!(true), json!([1]), json!({"x": 1})][pick].clone(),
        Kind::Keyword | Kind::Text => {
            [json!(3), json!(false), json!(["a"]), json!({})][pick].clone()
        }
        Kind::Bool => [json!("yes"), json!(1), json!([true]), json!({})][pick].clone(),
        Kind::Band => [json!("40-60"), json!(50), json!(true), json!({"lo": 40})][pick].clone(),
        Kind::Object => [json!("DM"), json!(1), json!([1]), json!(true)][pick].clone(),
    }
}

/// A value outside `key`'s domain (none for free text and objects). A number that
/// overflows a double (`1e400`) is refused by the JSON reader, by line, column and the
/// member's name (its tests), before any key is read: it is not generated here.
fn out_of_range(key: &Key, rng: &mut Rng) -> Option<Value> {
    match key.kind {
        Kind::Number(bad) => Some(Value::from(bad[rng.below(bad.len())])),
        Kind::Keyword if leaf(key.path).ends_with("grade") => {
            Some(Value::from(["", "XX", "squared"][rng.below(3)]))
        }
        Kind::Keyword => {
            let words = ["", "squared", "CLOSED", "xx", "lightest ", "wahl2"];
            Some(Value::from(words[rng.below(words.len())]))
        }
        Kind::Band => {
            let bands = [
                json!([60, 40]),
                json!([5]),
                json!([-1, 5]),
                json!([1, 2, 3]),
            ];
            Some(bands[rng.below(bands.len())].clone())
        }
        Kind::Bool | Kind::Text | Kind::Object => None,
    }
}

/// Per class: inputs, refused, silent acceptances, refusals not naming the field, slowest.
#[derive(Default)]
struct Tally {
    inputs: usize,
    refused: usize,
    silent: usize,
    unnamed: usize,
    slowest_s: f64,
}

/// What an input must give.
enum Expect {
    /// Refused, the message holding every one of these words.
    Refused(Vec<String>),
    /// Read (exit 0).
    Read,
    /// Either; a refusal must name one of these words.
    Any(Vec<String>),
}

struct Surface {
    name: &'static str,
    classes: BTreeMap<&'static str, Tally>,
}

impl Surface {
    fn add(&mut self, class: &'static str, expect: &Expect, o: &Outcome, input: &str) {
        let t = self.classes.entry(class).or_default();
        t.inputs += 1;
        t.slowest_s = t.slowest_s.max(o.seconds);
        if o.code != 0 {
            t.refused += 1;
        }
        let (silent, unnamed) = match expect {
            Expect::Refused(words) => (
                o.code == 0,
                o.code != 0 && !words.iter().all(|w| o.stderr.contains(w.as_str())),
            ),
            Expect::Read => (false, o.code != 0),
            Expect::Any(words) => (
                false,
                o.code != 0 && !words.iter().any(|w| o.stderr.contains(w.as_str())),
            ),
        };
        if silent {
            t.silent += 1;
            eprintln!("  silent ({class}): {input}");
        }
        if unnamed {
            t.unnamed += 1;
            eprintln!(
                "  not as stated ({class}): exit {}: {}\n    input: {input}",
                o.code,
                o.stderr.trim()
            );
        }
    }

    fn finish(self) {
        eprintln!(
            "fuzz {}: class, inputs, refused, silent, unnamed, slowest s (0 panics, 0 aborts, 0 hangs: each run checked)",
            self.name
        );
        let (mut silent, mut unnamed) = (0, 0);
        for (class, t) in &self.classes {
            eprintln!(
                "  {class:<16} {:>5} {:>5} {:>3} {:>3} {:>7.2}",
                t.inputs, t.refused, t.silent, t.unnamed, t.slowest_s
            );
            silent += t.silent;
            unnamed += t.unnamed;
        }
        assert_eq!(silent, 0, "{}: silent acceptances", self.name);
        assert_eq!(unnamed, 0, "{}: refusals not naming the field", self.name);
    }
}

/// A generated input: the file's text, extra flags, its class and what it must give.
struct Input {
    text: String,
    flags: Vec<String>,
    class: &'static str,
    expect: Expect,
}

fn words(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| s.to_string()).collect()
}

/// Every key either file knows (a slip must not land on one).
fn every_key() -> impl Iterator<Item = &'static str> {
    use coil_design::target::{ENVELOPE_KEYS, MATERIAL_KEYS, TARGET_KEYS};
    coil_design::sheet::input::SPRING_KEYS
        .into_iter()
        .chain(TARGET_KEYS)
        .chain(ENVELOPE_KEYS)
        .chain(MATERIAL_KEYS)
}

/// The last part of a key's path (what a message names).
fn leaf(path: &str) -> &str {
    path.rsplit('.').next().unwrap_or(path)
}

/// One input of `class` from `base` with its `keys`.
fn generate(class: &'static str, base: &Value, keys: &[Key], rng: &mut Rng) -> Input {
    let mut v = base.clone();
    let key = keys[rng.below(keys.len())];
    let input = |v: Value, expect| Input {
        text: v.to_string(),
        flags: Vec::new(),
        class,
        expect,
    };
    match class {
        "misspelled" => {
            let (o, name) = parent(&mut v, key.path);
            let known: Vec<&str> = keys
                .iter()
                .map(|k| leaf(k.path))
                .chain(every_key())
                .collect();
            let slip = loop {
                let s = misspell(name, rng);
                if !known.contains(&s.as_str()) && !s.is_empty() {
                    break s;
                }
            };
            let value = o.remove(name).unwrap();
            o.insert(slip.clone(), value);
            input(v, Expect::Refused(vec![format!("`{slip}`")]))
        }
        "missing" => {
            let (o, name) = parent(&mut v, key.path);
            o.remove(name);
            let expect = if key.need == Need::Required {
                Expect::Refused(vec![name.to_string()])
            } else if key.path == "envelope" || key.path.starts_with("envelope.") {
                // An envelope bound left out widens the search: read, or refused by the
                // search's bound naming it.
                Expect::Any(words(&["envelope", "springs"]))
            } else {
                Expect::Read
            };
            input(v, expect)
        }
        "wrong type" => {
            let (o, name) = parent(&mut v, key.path);
            let name = name.to_string();
            o.insert(name.clone(), wrong_type(key.kind, rng));
            input(v, Expect::Refused(vec![name]))
        }
        "out of range" => {
            let numeric: Vec<&Key> = keys
                .iter()
                .filter(|k| matches!(k.kind, Kind::Number(_) | Kind::Keyword | Kind::Band))
                .collect();
            let key = numeric[rng.below(numeric.len())];
            let bad = out_of_range(key, rng).unwrap();
            let (o, name) = parent(&mut v, key.path);
            let name = name.to_string();
            o.insert(name.clone(), bad);
            // A working point out of order is named by the pair; a grade by its key.
            let expect = if name.starts_with("force_") {
                Expect::Refused(vec!["force_".into()])
            } else {
                Expect::Refused(vec![name])
            };
            input(v, expect)
        }
        "null" => {
            let (o, name) = parent(&mut v, key.path);
            let name = name.to_string();
            o.insert(name.clone(), Value::Null);
            input(v, Expect::Refused(vec![format!("`{}`", key.path)]))
        }
        "unknown grade" => {
            let grade = ["XX", "DHH", "EN 10270-2 VDSiCr", "S L", "1.4310"][rng.below(5)];
            match v.get_mut("material") {
                Some(m) => m["grade"] = grade.into(),
                None => v["wire_grade"] = grade.into(),
            }
            input(
                v,
                Expect::Refused(vec![format!("\"{grade}\""), "SL, SM, DM, SH, DH".into()]),
            )
        }
        "zeta" => {
            let values = [346.0, -0.1, 0.0, 1.0, 2.0, 1.000001, 1e-4, 0.5, 0.99];
            let z = values[rng.below(values.len())];
            v["damping_ratio"] = z.into();
            let expect = if z > 0.0 && z < 1.0 {
                Expect::Read
            } else {
                Expect::Refused(words(&["damping_ratio"]))
            };
            input(v, expect)
        }
        "work" => {
            let rates = [1e-6, 1e-4, 1e-3, 0.01, 0.1, 30.0, 1e3, 1e6];
            v["rate_n_mm"] = rates[rng.below(rates.len())].into();
            v["rate_tolerance_percent"] = [1.0, 5.0, 20.0, 49.0][rng.below(4)].into();
            let springs = [1.0, 2.0, 7.0, 64.0, 65.0, 1e3, 1e9][rng.below(7)];
            v["springs_in_parallel"] = springs.into();
            if rng.below(2) == 0 {
                v.as_object_mut().unwrap().remove("envelope");
            }
            v["short_list"] = [1, 8, 32][rng.below(3)].into();
            let expect = if springs > 64.0 {
                Expect::Refused(words(&["springs_in_parallel"]))
            } else {
                Expect::Any(words(&[
                    "springs",
                    "rate_n_mm",
                    "rate_tolerance_percent",
                    "envelope",
                ]))
            };
            input(v, expect)
        }
        "flags" => {
            let (flag, values, name): (&str, &[&str], &str) = match rng.below(3) {
                0 => (
                    "--short-list",
                    &["0", "33", "-1", "1.5", "many"],
                    "--short-list",
                ),
                1 => (
                    "--elements-per-coil",
                    &["0", "3", "513", "-24", "x"],
                    "--elements-per-coil",
                ),
                _ => ("--objective", &["cheapest", "", "Lightest"], "--objective"),
            };
            Input {
                text: v.to_string(),
                flags: vec![
                    flag.to_string(),
                    values[rng.below(values.len())].to_string(),
                ],
                class,
                expect: Expect::Refused(vec![name.to_string()]),
            }
        }
        _ => {
            // In domain, extreme or inconsistent with the rest.
            let numbers: Vec<&Key> = keys
                .iter()
                .filter(|k| matches!(k.kind, Kind::Number(_)))
                .collect();
            let key = numbers[rng.below(numbers.len())];
            let x = [1e-9, 1e-3, 0.7, 2.0, 47.0, 1e3, 1e6, 1e12, 1e300][rng.below(9)];
            let (o, name) = parent(&mut v, key.path);
            o.insert(name.to_string(), x.into());
            let names: Vec<String> = every_key().map(str::to_string).collect();
            input(v, Expect::Any(names))
        }
    }
}

/// Runs one input through `command` (`check` or `design`) in a fresh sandbox.
fn one(surface: &mut Surface, command: &str, file: &str, input: &Input, i: usize) {
    let sandbox = tempfile::tempdir().unwrap();
    std::fs::write(sandbox.path().join(file), &input.text).unwrap();
    let mut c = Command::new(env!("CARGO_BIN_EXE_coil-tune"));
    c.args([command, file, "--out", "out"]);
    if command == "design" {
        c.arg("--no-plots");
    }
    c.args(&input.flags);
    let label = format!("{command} {} {i}", input.class);
    let o = run(&label, c, sandbox.path(), &sandbox.path().join("out"));
    if o.code != 0 {
        assert!(
            !Path::new(&sandbox.path().join("out")).exists(),
            "{label}: a refused run wrote its output folder"
        );
    }
    if input.class == "work" {
        assert!(
            o.seconds < WORK_S,
            "{label}: {:.1} s: {}",
            o.seconds,
            input.text
        );
    }
    let shown = format!("{} {}", input.flags.join(" "), input.text);
    surface.add(input.class, &input.expect, &o, &shown);
}

const SPRING_CLASSES: [&str; 7] = [
    "misspelled",
    "missing",
    "wrong type",
    "out of range",
    "null",
    "unknown grade",
    "in domain",
];

const TARGET_CLASSES: [&str; 10] = [
    "misspelled",
    "missing",
    "wrong type",
    "out of range",
    "null",
    "unknown grade",
    "zeta",
    "work",
    "flags",
    "in domain",
];

/// Every class of `classes` on `base`, `per_class()` inputs each, through `command`
/// reading them as `file`; the surface's table and verdict at the end.
fn surface_under_generated_bad_input(
    name: &'static str,
    command: &str,
    file: &str,
    classes: &[&'static str],
    (base, keys): (Value, Vec<Key>),
    seed: u64,
) {
    let mut surface = Surface {
        name,
        classes: BTreeMap::new(),
    };
    let mut rng = Rng(seed);
    for &class in classes {
        for i in 0..per_class() {
            let input = generate(class, &base, &keys, &mut rng);
            one(&mut surface, command, file, &input, i);
        }
    }
    surface.finish();
}

/// SPRING.json through `coil-tune check`, class by class.
#[test]
fn spring_files_under_generated_bad_input() {
    surface_under_generated_bad_input(
        "SPRING.json (check)",
        "check",
        "spring.json",
        &SPRING_CLASSES,
        (base_spring(), spring_keys()),
        0x2545f4914f6cdd1d,
    );
}

/// TARGET.json (and the design flags) through `coil-tune design`, class by class.
#[test]
fn target_files_under_generated_bad_input() {
    surface_under_generated_bad_input(
        "TARGET.json (design)",
        "design",
        "target.json",
        &TARGET_CLASSES,
        (base_target(), target_keys()),
        0x9e3779b97f4a7c15,
    );
}
