//! Procedure files: a small line-oriented command language in the spirit of Mentat's
//! procedure files, documented in `docs/procedures.md` (written from the tables here:
//! [`COMMANDS`] and [`SETTINGS`]).
//!
//! One command per line; `#` starts a comment; words are separated by blanks; a word
//! with blanks goes in double quotes. The whole file is parsed and checked first, so a
//! typo on line 40 is reported (`file:40: ...`) before line 1 runs anything. Errors while
//! running name the line too.
//!
//! The commands call the same library functions as `coil-tune calibrate` (loops 1 and 2,
//! [`crate::damping::Loop3`] for grids and the choice), so `figure6.proc` and `calibrate`
//! give the same E, mass, alpha and beta. Grids are journaled in the output folder, so a
//! procedure rerun after a kill resumes its grids; a user can edit the file and rerun any
//! step.

use crate::calibrate::{paper_damping_point, CalibrateSettings};
use crate::case::{read_case, MeasuredCase};
use crate::damping::{DampingReport, Loop3, RunControl, Simulator};
use crate::decay::{measure, DecayRecord, Method, VelocityField};
use crate::error::{Result, TuneError};
use crate::fe::{self, SpringState};
use crate::grid::{Axis, GridSpec};
use crate::loops::{tune_mass, tune_youngs_modulus, LoopReport};
use crate::output::{csv, exact, OutDir};
use coil_mesher::AnalysisKind;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// A command of the language: its name, its form and what it does.
#[derive(Debug, Clone, Copy)]
pub struct CommandSpec {
    pub name: &'static str,
    pub usage: &'static str,
    pub meaning: &'static str,
}

/// Every command, once.
pub const COMMANDS: &[CommandSpec] = &[
    CommandSpec {
        name: "case",
        usage: "case PATH",
        meaning: "read a measured case (a folder with case.json, or the file), relative to the procedure file's folder; sets the state to the case's nominal values",
    },
    CommandSpec {
        name: "out",
        usage: "out DIR",
        meaning: "the output folder, relative to the working directory (`coil-tune run --out` overrides it)",
    },
    CommandSpec {
        name: "set",
        usage: "set NAME VALUE",
        meaning: "set a model value, a run setting or a tolerance (see the settings table)",
    },
    CommandSpec {
        name: "mesh",
        usage: "mesh [FILE]",
        meaning: "write the current model (static, modal and transient load cases) as a deck, default mesh.dat in the output folder",
    },
    CommandSpec {
        name: "solve",
        usage: "solve static|modal|transient",
        meaning: "run the current model: static stiffness K; the axial mode's period; a free-decay transient (kept for `post`, written to transient.csv)",
    },
    CommandSpec {
        name: "post",
        usage: "post",
        meaning: "logarithmic decrement of the last transient (every 10th crest, the paper's Eqs. 2-3): zeta and the period",
    },
    CommandSpec {
        name: "tune",
        usage: "tune youngs_modulus to stiffness VALUE|target [tolerance TOL] | tune mass to period VALUE|target [tolerance TOL]",
        meaning: "loop 1 (E to K) or loop 2 (the weight's mass to the axial period); `target` takes the case's targets",
    },
    CommandSpec {
        name: "grid",
        usage: "grid alpha START:STEP:END beta START:STEP:END [name NAME]",
        meaning: "loop 3: a decay transient and its decrement at every (alpha, beta), in parallel, journaled (resumable)",
    },
    CommandSpec {
        name: "choose",
        usage: "choose best [zeta VALUE|target]",
        meaning: "set alpha and beta to the grid point closest to the target zeta over the grids so far; fit the plane, trace the valley, check by direct integration, draw the figures",
    },
    CommandSpec {
        name: "print",
        usage: "print",
        meaning: "print the current values",
    },
    CommandSpec {
        name: "echo",
        usage: "echo TEXT...",
        meaning: "print the text",
    },
];

/// What a setting's value is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A number > 0.
    Positive,
    /// A number >= 0.
    NonNegative,
    /// A number in an open interval.
    Open(f64, f64),
    /// A whole number >= the minimum.
    Count(u32),
    /// One of the words.
    Choice(&'static [&'static str]),
    /// `on` or `off`.
    Switch,
    /// A number > 0 or `off`.
    PositiveOrOff,
    /// Comma-separated numbers >= 0.
    List,
}

/// A settable value: its name, what it is and its unit.
#[derive(Debug, Clone, Copy)]
pub struct SettingSpec {
    pub name: &'static str,
    pub kind: Kind,
    pub meaning: &'static str,
}

/// Every setting, once. Model values need a `case` first.
pub const SETTINGS: &[SettingSpec] = &[
    SettingSpec {
        name: "youngs_modulus_mpa",
        kind: Kind::Positive,
        meaning: "Young's modulus E (MPa)",
    },
    SettingSpec {
        name: "poisson_ratio",
        kind: Kind::Open(-1.0, 0.5),
        meaning: "Poisson's ratio",
    },
    SettingSpec {
        name: "density_kg_m3",
        kind: Kind::Positive,
        meaning: "wire density (kg/m^3)",
    },
    SettingSpec {
        name: "mass_kg",
        kind: Kind::Positive,
        meaning: "the weight's mass (kg)",
    },
    SettingSpec {
        name: "alpha",
        kind: Kind::NonNegative,
        meaning: "Rayleigh alpha on the wire (1/s)",
    },
    SettingSpec {
        name: "beta",
        kind: Kind::NonNegative,
        meaning: "Rayleigh beta on the wire (s)",
    },
    SettingSpec {
        name: "active_coils",
        kind: Kind::Positive,
        meaning: "number of active coils n",
    },
    SettingSpec {
        name: "mean_diameter_mm",
        kind: Kind::Positive,
        meaning: "mean coil diameter D (mm)",
    },
    SettingSpec {
        name: "wire_diameter_mm",
        kind: Kind::Positive,
        meaning: "wire diameter d (mm)",
    },
    SettingSpec {
        name: "pitch_mm",
        kind: Kind::Positive,
        meaning: "pitch h (mm)",
    },
    SettingSpec {
        name: "elements_per_coil",
        kind: Kind::Count(3),
        meaning: "beams per coil",
    },
    SettingSpec {
        name: "element",
        kind: Kind::Choice(&["98", "52"]),
        meaning: "Marc element type: 98 Timoshenko, 52 Euler-Bernoulli",
    },
    SettingSpec {
        name: "lumped_mass",
        kind: Kind::Switch,
        meaning: "lumped instead of consistent mass",
    },
    SettingSpec {
        name: "static_force_n",
        kind: Kind::Positive,
        meaning: "static load on the weight for K (N)",
    },
    SettingSpec {
        name: "modes",
        kind: Kind::Count(1),
        meaning: "modes computed to find the axial mode",
    },
    SettingSpec {
        name: "method",
        kind: Kind::Choice(&["modal", "direct"]),
        meaning: "how decay transients run: modal superposition or direct integration",
    },
    SettingSpec {
        name: "check_direct",
        kind: Kind::Switch,
        meaning: "re-check the chosen point by direct integration (modal method)",
    },
    SettingSpec {
        name: "dt_s",
        kind: Kind::Positive,
        meaning: "transient time step (s)",
    },
    SettingSpec {
        name: "duration_s",
        kind: Kind::Positive,
        meaning: "transient record length (s)",
    },
    SettingSpec {
        name: "initial_velocity_m_s",
        kind: Kind::Positive,
        meaning: "the weight's initial axial velocity (m/s)",
    },
    SettingSpec {
        name: "velocity_field",
        kind: Kind::Choice(&["quasi-static", "nodal"]),
        meaning:
            "initial velocity spread along the spring by the static shape, or on the weight alone",
    },
    SettingSpec {
        name: "modal_modes",
        kind: Kind::Count(1),
        meaning: "modes of the modal method",
    },
    SettingSpec {
        name: "every",
        kind: Kind::Count(1),
        meaning: "crest intervals per decrement span (the paper: 10)",
    },
    SettingSpec {
        name: "lowpass_hz",
        kind: Kind::PositiveOrOff,
        meaning: "zero-phase low-pass before crest picking (Hz), or off",
    },
    SettingSpec {
        name: "valley_alphas",
        kind: Kind::List,
        meaning: "alphas at which `choose` solves the valley's beta (comma-separated)",
    },
    SettingSpec {
        name: "valley_tolerance",
        kind: Kind::Open(0.0, 1.0),
        meaning: "relative tolerance on zeta of the valley points",
    },
    SettingSpec {
        name: "stiffness_tolerance",
        kind: Kind::Open(0.0, 1.0),
        meaning: "default tolerance of `tune youngs_modulus`",
    },
    SettingSpec {
        name: "period_tolerance",
        kind: Kind::Open(0.0, 1.0),
        meaning: "default tolerance of `tune mass`",
    },
    SettingSpec {
        name: "progress",
        kind: Kind::Switch,
        meaning: "progress bars on stderr",
    },
];

/// A parsed setting value.
#[derive(Debug, Clone, PartialEq)]
pub enum SetValue {
    Number(f64),
    Word(String),
    Switch(bool),
    Off,
    List(Vec<f64>),
}

/// A number or the case's target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TargetValue {
    Number(f64),
    Target,
}

/// One parsed command.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    Case(String),
    Out(String),
    Set {
        name: &'static str,
        value: SetValue,
    },
    Mesh(Option<String>),
    Solve(AnalysisKind),
    Post,
    TuneModulus {
        target: TargetValue,
        tolerance: Option<f64>,
    },
    TuneMass {
        target: TargetValue,
        tolerance: Option<f64>,
    },
    Grid(GridSpec),
    ChooseBest {
        zeta: TargetValue,
    },
    Print,
    Echo(String),
}

/// A parsed line.
#[derive(Debug, Clone, PartialEq)]
pub struct Statement {
    pub line: usize,
    pub step: Step,
}

/// A parsed procedure file.
#[derive(Debug, Clone, PartialEq)]
pub struct Procedure {
    pub path: PathBuf,
    pub statements: Vec<Statement>,
}

/// Splits a line into words (double quotes group blanks; `#` outside quotes ends it).
fn words(text: &str) -> std::result::Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut chars = text.chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| c.is_whitespace()) {
            chars.next();
        }
        match chars.peek() {
            None | Some('#') => return Ok(out),
            Some('"') => {
                chars.next();
                let mut word = String::new();
                loop {
                    match chars.next() {
                        Some('"') => break,
                        Some(c) => word.push(c),
                        None => {
                            return Err(
                                "a quoted word is not closed; expected a closing `\"`".into()
                            )
                        }
                    }
                }
                out.push(word);
            }
            Some(_) => {
                let mut word = String::new();
                while let Some(&c) = chars.peek() {
                    if c.is_whitespace() {
                        break;
                    }
                    word.push(c);
                    chars.next();
                }
                out.push(word);
            }
        }
    }
}

fn number(word: &str, what: &str) -> std::result::Result<f64, String> {
    word.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("`{word}` is not a number; expected {what}"))
}

fn target_value(word: &str, what: &str) -> std::result::Result<TargetValue, String> {
    if word == "target" {
        Ok(TargetValue::Target)
    } else {
        let x = number(word, &format!("{what} or `target`"))?;
        if x > 0.0 {
            Ok(TargetValue::Number(x))
        } else {
            Err(format!("{x}: expected a positive {what}"))
        }
    }
}

fn parse_setting(name: &str, value: &str) -> std::result::Result<(&'static str, SetValue), String> {
    let spec = SETTINGS.iter().find(|s| s.name == name).ok_or_else(|| {
        format!(
            "unknown setting `{name}`; expected one of: {}",
            SETTINGS
                .iter()
                .map(|s| s.name)
                .collect::<Vec<_>>()
                .join(", ")
        )
    })?;
    let bad = |expected: &str| format!("set {name} {value}: expected {expected}");
    let parsed = match spec.kind {
        Kind::Positive => match number(value, "a number > 0")? {
            x if x > 0.0 => SetValue::Number(x),
            _ => return Err(bad("a number > 0")),
        },
        Kind::NonNegative => match number(value, "a number >= 0")? {
            x if x >= 0.0 => SetValue::Number(x),
            _ => return Err(bad("a number >= 0")),
        },
        Kind::Open(lo, hi) => match number(value, "a number")? {
            x if x > lo && x < hi => SetValue::Number(x),
            _ => return Err(bad(&format!("a number strictly between {lo} and {hi}"))),
        },
        Kind::Count(min) => match value.parse::<u32>() {
            Ok(n) if n >= min => SetValue::Number(f64::from(n)),
            _ => return Err(bad(&format!("a whole number >= {min}"))),
        },
        Kind::Choice(words) => {
            if words.contains(&value) {
                SetValue::Word(value.to_string())
            } else {
                return Err(bad(&format!("one of {}", words.join(", "))));
            }
        }
        Kind::Switch => match value {
            "on" => SetValue::Switch(true),
            "off" => SetValue::Switch(false),
            _ => return Err(bad("on or off")),
        },
        Kind::PositiveOrOff => match value {
            "off" => SetValue::Off,
            _ => match number(value, "a number > 0 or off")? {
                x if x > 0.0 => SetValue::Number(x),
                _ => return Err(bad("a number > 0 or off")),
            },
        },
        Kind::List => {
            let list = value
                .split(',')
                .map(|w| number(w.trim(), "a number >= 0"))
                .collect::<std::result::Result<Vec<f64>, String>>()?;
            if list.iter().any(|x| *x < 0.0) || list.is_empty() {
                return Err(bad("comma-separated numbers >= 0"));
            }
            SetValue::List(list)
        }
    };
    Ok((spec.name, parsed))
}

fn arity(w: &[String], min: usize, max: usize, usage: &str) -> std::result::Result<(), String> {
    if w.len() < min || w.len() > max {
        Err(format!(
            "`{}` takes {}; expected `{usage}`",
            w.join(" "),
            if min + 1 == max && max - 1 == min {
                format!("{} or {} words", min - 1, max - 1)
            } else if min == max {
                format!("{} word(s) after the command", min - 1)
            } else {
                format!("{} to {} words after the command", min - 1, max - 1)
            }
        ))
    } else {
        Ok(())
    }
}

fn usage_of(name: &str) -> &'static str {
    COMMANDS
        .iter()
        .find(|c| c.name == name)
        .map_or("", |c| c.usage)
}

fn optional_tolerance(rest: &[String], usage: &str) -> std::result::Result<Option<f64>, String> {
    match rest {
        [] => Ok(None),
        [t, value] if t == "tolerance" => {
            let x = number(value, "a relative tolerance")?;
            if x > 0.0 && x < 1.0 {
                Ok(Some(x))
            } else {
                Err(format!(
                    "tolerance {x}: expected a relative tolerance in (0, 1)"
                ))
            }
        }
        _ => Err(format!(
            "unexpected `{}`; expected `{usage}`",
            rest.join(" ")
        )),
    }
}

/// Parses one line's words into a step.
fn parse_step(w: &[String]) -> std::result::Result<Step, String> {
    let name = w[0].as_str();
    let usage = usage_of(name);
    Ok(match name {
        "case" => {
            arity(w, 2, 2, usage)?;
            Step::Case(w[1].clone())
        }
        "out" => {
            arity(w, 2, 2, usage)?;
            Step::Out(inside_name(
                &w[1],
                "an output folder relative to the working directory",
            )?)
        }
        "set" => {
            arity(w, 3, 3, usage)?;
            let (name, value) = parse_setting(&w[1], &w[2])?;
            Step::Set { name, value }
        }
        "mesh" => {
            arity(w, 1, 2, usage)?;
            let file = w
                .get(1)
                .map(|f| inside_name(f, "a deck file name inside the output folder"));
            Step::Mesh(file.transpose()?)
        }
        "solve" => {
            arity(w, 2, 2, usage)?;
            Step::Solve(match w[1].as_str() {
                "static" => AnalysisKind::Static,
                "modal" => AnalysisKind::Modal,
                "transient" => AnalysisKind::Transient,
                other => {
                    return Err(format!(
                        "solve {other}: expected static, modal or transient"
                    ))
                }
            })
        }
        "post" => {
            arity(w, 1, 1, usage)?;
            Step::Post
        }
        "tune" => {
            let form: Vec<&str> = w.iter().take(4).map(String::as_str).collect();
            match form.as_slice() {
                ["tune", "youngs_modulus", "to", "stiffness"] if w.len() >= 5 => {
                    Step::TuneModulus {
                        target: target_value(&w[4], "stiffness in N/mm")?,
                        tolerance: optional_tolerance(&w[5..], usage)?,
                    }
                }
                ["tune", "mass", "to", "period"] if w.len() >= 5 => Step::TuneMass {
                    target: target_value(&w[4], "period in s")?,
                    tolerance: optional_tolerance(&w[5..], usage)?,
                },
                _ => return Err(format!("`{}`: expected `{usage}`", w.join(" "))),
            }
        }
        "grid" => {
            let mut alpha = None;
            let mut beta = None;
            let mut name = None;
            let mut rest = w[1..].chunks(2);
            for pair in &mut rest {
                match pair {
                    [key, value] if key == "alpha" => alpha = Some(Axis::parse(value)?),
                    [key, value] if key == "beta" => beta = Some(Axis::parse(value)?),
                    [key, value] if key == "name" => {
                        name = Some(grid_name(value)?);
                    }
                    _ => return Err(format!("`{}`: expected `{usage}`", w.join(" "))),
                }
            }
            for (what, axis) in [("alpha", &alpha), ("beta", &beta)] {
                if let Some(a) = axis.as_ref().filter(|a| a.start < 0.0) {
                    return Err(format!(
                        "{what} {a}: a negative Rayleigh coefficient is negative damping (energy \
                         created); expected a range starting at 0 or above"
                    ));
                }
            }
            match (alpha, beta) {
                (Some(alpha), Some(beta)) => Step::Grid(GridSpec {
                    name: name.unwrap_or_default(),
                    alpha,
                    beta,
                }),
                _ => return Err(format!("`{}`: expected `{usage}`", w.join(" "))),
            }
        }
        "choose" => match w.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
            ["choose", "best"] => Step::ChooseBest {
                zeta: TargetValue::Target,
            },
            ["choose", "best", "zeta", value] => {
                let zeta = target_value(value, "damping ratio")?;
                if let TargetValue::Number(z) = zeta {
                    if z >= 1.0 {
                        return Err(format!("zeta {z}: expected a damping ratio below 1"));
                    }
                }
                Step::ChooseBest { zeta }
            }
            _ => return Err(format!("`{}`: expected `{usage}`", w.join(" "))),
        },
        "print" => {
            arity(w, 1, 1, usage)?;
            Step::Print
        }
        "echo" => Step::Echo(w[1..].join(" ")),
        other => {
            return Err(format!(
                "unknown command `{other}`; expected one of: {}",
                COMMANDS
                    .iter()
                    .map(|c| c.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        }
    })
}

/// A file or folder name written in a procedure: relative, no `..` (the boundary rules of
/// `docs/files.md`: a procedure writes only inside its output folder).
fn inside_name(word: &str, expected: &str) -> std::result::Result<String, String> {
    coil_io::confine::check_entry(word, Path::new("the folder"))
        .map_err(|e| format!("{e}; expected {expected}"))?;
    if word.chars().any(char::is_control) {
        return Err(format!("`{}`: expected {expected}", coil_io::excerpt(word)));
    }
    Ok(word.to_string())
}

/// A grid name: it names the grid's files, so letters, digits, `_`, `-` and `.` only.
fn grid_name(word: &str) -> std::result::Result<String, String> {
    let ok = !word.is_empty()
        && word.len() <= 64
        && !word.starts_with('.')
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
    if ok {
        Ok(word.to_string())
    } else {
        Err(format!(
            "grid name `{}`: expected letters, digits, `_`, `-` or `.` (at most 64, not \
             starting with `.`): it names the grid's files inside the output folder",
            coil_io::excerpt(word)
        ))
    }
}

/// Parses the words of a `grid` line without the command, e.g.
/// `alpha 0:0.1:2 beta 0:1e-5:2e-4 name domain2` (the name defaults to `grid`).
pub fn parse_grid(text: &str) -> std::result::Result<GridSpec, String> {
    let mut w = vec!["grid".to_string()];
    w.extend(words(text)?);
    match parse_step(&w)? {
        Step::Grid(mut spec) => {
            if spec.name.is_empty() {
                spec.name = "grid".into();
            }
            Ok(spec)
        }
        _ => Err(format!("`{text}`: expected a grid")),
    }
}

/// Parses a procedure's text; `path` names it in errors.
pub fn parse(text: &str, path: &Path) -> Result<Procedure> {
    let mut statements = Vec::new();
    let mut grid_count = 0;
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let fail = |message: String| TuneError::Procedure {
            path: path.to_path_buf(),
            line,
            message,
        };
        let w = words(raw).map_err(fail)?;
        if w.is_empty() {
            continue;
        }
        let mut step = parse_step(&w).map_err(fail)?;
        if let Step::Grid(spec) = &mut step {
            grid_count += 1;
            if spec.name.is_empty() {
                spec.name = format!("grid{grid_count}");
            }
            if statements
                .iter()
                .any(|s: &Statement| matches!(&s.step, Step::Grid(g) if g.name == spec.name))
            {
                return Err(fail(format!(
                    "a grid named {} appears twice; give each grid its own `name`",
                    spec.name
                )));
            }
        }
        statements.push(Statement { line, step });
    }
    Ok(Procedure {
        path: path.to_path_buf(),
        statements,
    })
}

/// Reads and parses a procedure file.
pub fn read(path: &Path) -> Result<Procedure> {
    let text = std::fs::read_to_string(path).map_err(|e| TuneError::io(path, e))?;
    parse(&text, path)
}

/// What a procedure run leaves.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProcedureResult {
    pub procedure: String,
    pub case: Option<String>,
    /// The final values (E, mass, alpha, beta with the geometry).
    pub state: Option<SpringState>,
    pub settings: CalibrateSettings,
    /// Loops run by `tune`, in order.
    pub loops: Vec<LoopReport>,
    /// The last `choose best`.
    pub damping: Option<DampingReport>,
}

/// The interpreter's state.
struct Session<'p> {
    procedure: &'p Procedure,
    case: Option<MeasuredCase>,
    state: Option<SpringState>,
    settings: CalibrateSettings,
    out: Option<OutDir>,
    out_fixed: bool,
    loop3: Option<Loop3>,
    loops: Vec<LoopReport>,
    damping: Option<DampingReport>,
    record: Option<DecayRecord>,
    control: RunControl,
}

/// Runs a parsed procedure. `out` (from the command line) overrides the file's `out`;
/// without either, files go to `out/<procedure name>`. `say` receives each printed line.
pub fn run(
    procedure: &Procedure,
    out: Option<&Path>,
    control: &RunControl,
    say: &mut dyn FnMut(&str),
) -> Result<ProcedureResult> {
    let mut session = Session {
        procedure,
        case: None,
        state: None,
        settings: CalibrateSettings::default(),
        out: match out {
            Some(dir) => Some(OutDir::create(dir)?),
            None => None,
        },
        out_fixed: out.is_some(),
        loop3: None,
        loops: Vec::new(),
        damping: None,
        record: None,
        control: control.clone(),
    };
    for statement in &procedure.statements {
        session
            .execute(&statement.step, say)
            .map_err(|source| TuneError::AtLine {
                path: procedure.path.clone(),
                line: statement.line,
                source: Box::new(source),
            })?;
    }
    let result = ProcedureResult {
        procedure: procedure.path.display().to_string(),
        case: session.case.as_ref().map(|c| c.name.clone()),
        state: session.state,
        settings: session.settings.clone(),
        loops: session.loops.clone(),
        damping: session.damping.clone(),
    };
    let out = session.out()?;
    let json = serde_json::to_string_pretty(&result)
        .map_err(|e| TuneError::Invalid(format!("procedure.json: {e}")))?;
    out.write("procedure.json", json.as_bytes())?;
    out.commit()?;
    Ok(result)
}

impl Session<'_> {
    fn out(&mut self) -> Result<OutDir> {
        if let Some(out) = &self.out {
            return Ok(out.clone());
        }
        let stem = self
            .procedure
            .path
            .file_stem()
            .map_or("procedure".into(), |s| s.to_string_lossy().into_owned());
        let out = OutDir::create(Path::new("out").join(stem))?;
        self.out = Some(out.clone());
        Ok(out)
    }

    fn case(&self) -> Result<&MeasuredCase> {
        self.case.as_ref().ok_or_else(|| {
            TuneError::Invalid("no case yet; put `case PATH` before this line".into())
        })
    }

    fn state(&mut self) -> Result<&mut SpringState> {
        self.state.as_mut().ok_or_else(|| {
            TuneError::Invalid("no case yet; put `case PATH` before this line".into())
        })
    }

    fn target(&self, value: TargetValue, field: &'static str) -> Result<f64> {
        match value {
            TargetValue::Number(x) => Ok(x),
            TargetValue::Target => Ok(self.case()?.target(field)?),
        }
    }

    /// The model changed: grids run so far were for another model.
    fn model_changed(&mut self) {
        self.loop3 = None;
    }

    fn apply(&mut self, name: &str, value: &SetValue) -> Result<()> {
        let number = match value {
            SetValue::Number(x) => *x,
            _ => f64::NAN,
        };
        let switch = matches!(value, SetValue::Switch(true));
        let s = &mut self.settings;
        match name {
            "youngs_modulus_mpa" | "poisson_ratio" | "density_kg_m3" | "mass_kg" | "alpha"
            | "beta" | "active_coils" | "mean_diameter_mm" | "wire_diameter_mm" | "pitch_mm" => {
                let state = self.state()?;
                match name {
                    "youngs_modulus_mpa" => state.youngs_modulus_mpa = number,
                    "poisson_ratio" => state.poisson_ratio = number,
                    "density_kg_m3" => state.density_kg_m3 = number,
                    "mass_kg" => state.mass_kg = number,
                    "alpha" => state.alpha = number,
                    "beta" => state.beta = number,
                    "active_coils" => state.spring.active_coils = number,
                    "mean_diameter_mm" => state.spring.mean_diameter_mm = number,
                    "wire_diameter_mm" => state.spring.wire_diameter_mm = number,
                    _ => state.spring.pitch_mm = number,
                }
                if name != "alpha" && name != "beta" {
                    self.model_changed();
                }
                return Ok(());
            }
            "elements_per_coil" => s.fe.elements_per_coil = number as u32,
            "element" => {
                s.fe.element = if matches!(value, SetValue::Word(w) if w == "52") {
                    52
                } else {
                    98
                }
            }
            "lumped_mass" => s.fe.lumped_mass = switch,
            "static_force_n" => s.fe.static_force_n = number,
            "modes" => s.fe.modes = number as u32,
            "method" => {
                s.damping.decay.method = if matches!(value, SetValue::Word(w) if w == "direct") {
                    Method::Direct
                } else {
                    Method::Modal
                }
            }
            "check_direct" => s.damping.check_direct = switch,
            "dt_s" => s.damping.decay.dt_s = number,
            "duration_s" => s.damping.decay.duration_s = number,
            "initial_velocity_m_s" => s.damping.decay.initial_velocity_m_s = number,
            "velocity_field" => {
                s.damping.decay.velocity_field = if matches!(value, SetValue::Word(w) if w == "nodal")
                {
                    VelocityField::Nodal
                } else {
                    VelocityField::QuasiStatic
                }
            }
            "modal_modes" => s.damping.decay.modal_modes = number as u32,
            "every" => s.damping.decay.every = number as usize,
            "lowpass_hz" => {
                s.damping.decay.lowpass_hz = match value {
                    SetValue::Off => None,
                    _ => Some(number),
                }
            }
            "valley_alphas" => {
                if let SetValue::List(list) = value {
                    s.damping.valley_alphas = list.clone();
                }
                return Ok(());
            }
            "valley_tolerance" => {
                s.damping.valley_tolerance = number;
                return Ok(());
            }
            "stiffness_tolerance" => {
                s.stiffness_tolerance = number;
                return Ok(());
            }
            "period_tolerance" => {
                s.period_tolerance = number;
                return Ok(());
            }
            "progress" => {
                s.damping.progress = switch;
                return Ok(());
            }
            other => {
                return Err(TuneError::Invalid(format!(
                    "setting `{other}` has no effect here"
                )))
            }
        }
        self.model_changed();
        Ok(())
    }

    fn execute(&mut self, step: &Step, say: &mut dyn FnMut(&str)) -> Result<()> {
        match step {
            Step::Case(path) => {
                let folder = self.procedure.path.parent().unwrap_or(Path::new(""));
                let case = read_case(&folder.join(path))?;
                say(&format!("case: {} ({})", case.name, case.file.display()));
                self.state = Some(SpringState::nominal(&case));
                self.case = Some(case);
                self.model_changed();
            }
            Step::Out(dir) => {
                if !self.out_fixed {
                    if let Some(out) = &self.out {
                        return Err(TuneError::Invalid(format!(
                            "the output folder is {} already; put `out` once, before the \
                             first command that writes a file",
                            out.root().display()
                        )));
                    }
                    self.out = Some(OutDir::create(dir)?);
                }
            }
            Step::Set { name, value } => self.apply(name, value)?,
            Step::Mesh(file) => {
                let state = *self.state()?;
                let mut spec = state.spec(
                    &self.settings.fe,
                    &[
                        AnalysisKind::Static,
                        AnalysisKind::Modal,
                        AnalysisKind::Transient,
                    ],
                );
                let decay = &self.settings.damping.decay;
                spec.dt_s = decay.dt_s;
                spec.duration_s = decay.duration_s;
                spec.initial_velocity_m_s = decay.initial_velocity_m_s;
                let model = spec.build()?;
                let name = file.clone().unwrap_or_else(|| "mesh.dat".into());
                let path = self
                    .out()?
                    .write(&name, coil_solver::deck::write(&model).as_bytes())?;
                say(&format!(
                    "mesh: {} elements -> {}",
                    model.elements().len(),
                    path.display()
                ));
            }
            Step::Solve(kind) => {
                let state = *self.state()?;
                match kind {
                    AnalysisKind::Static => {
                        let (k, _) = fe::static_stiffness(&state, &self.settings.fe)?;
                        say(&format!("static: K = {k:.6} N/mm"));
                    }
                    AnalysisKind::Modal => {
                        let (r, _) = fe::static_and_modal(&state, &self.settings.fe)?;
                        say(&format!(
                            "modal: axial mode {} at {:.6} Hz, T = {:.6} s, effective mass {:.4} kg",
                            r.axial.mode, r.axial.frequency_hz, r.axial.period_s, r.axial.effective_mass_kg
                        ));
                    }
                    AnalysisKind::Transient => {
                        let decay = self.settings.damping.decay.clone();
                        let sim = Simulator::new(&state, &self.settings.fe, &decay)?;
                        let record = sim.run(state.alpha, state.beta)?;
                        let text = csv(
                            &["time_s", coil_mesher::WEIGHT_ACCEL_COLUMN],
                            record
                                .time_s
                                .iter()
                                .zip(&record.accel_m_s2)
                                .map(|(t, a)| vec![exact(*t), exact(*a)]),
                        );
                        let path = self.out()?.write("transient.csv", text.as_bytes())?;
                        say(&format!(
                            "transient ({}): {} samples -> {}",
                            decay.method,
                            record.time_s.len(),
                            path.display()
                        ));
                        self.record = Some(record);
                    }
                }
            }
            Step::Post => {
                let record = self.record.as_ref().ok_or_else(|| {
                    TuneError::Invalid(
                        "no transient yet; put `solve transient` before `post`".into(),
                    )
                })?;
                let m = measure(record, &self.settings.damping.decay)?;
                say(&format!(
                    "post: zeta = {:.8} (span mean, every {}th crest), zeta_fit = {:.8}, T = {:.8} s, {} crests",
                    m.zeta_mean, self.settings.damping.decay.every, m.zeta_fit, m.period_s, m.crests
                ));
            }
            Step::TuneModulus { target, tolerance } => {
                let target = self.target(*target, "stiffness_n_mm")?;
                let tolerance = tolerance.unwrap_or(self.settings.stiffness_tolerance);
                let out = self.out()?;
                let fe = self.settings.fe.clone();
                let report =
                    tune_youngs_modulus(self.state()?, &fe, target, tolerance, Some(&out))?;
                say(&format!(
                    "tune: E = {:.4} MPa -> K = {:.6} N/mm (error {:+.2e}) in {} runs",
                    report.value,
                    report.result,
                    report.relative_error,
                    report.iterations.len()
                ));
                self.loops.push(report);
                self.model_changed();
            }
            Step::TuneMass { target, tolerance } => {
                let target = self.target(*target, "period_s")?;
                let tolerance = tolerance.unwrap_or(self.settings.period_tolerance);
                let out = self.out()?;
                let fe = self.settings.fe.clone();
                let report = tune_mass(self.state()?, &fe, target, tolerance, Some(&out))?;
                say(&format!(
                    "tune: mass = {:.6} kg -> T = {:.6} s (error {:+.2e}) in {} runs",
                    report.value,
                    report.result,
                    report.relative_error,
                    report.iterations.len()
                ));
                self.loops.push(report);
                self.model_changed();
            }
            Step::Grid(spec) => {
                if self.loop3.is_none() {
                    let state = *self.state()?;
                    let target = self.case()?.targets.damping_ratio.unwrap_or(0.5);
                    let out = self.out()?;
                    self.loop3 = Some(Loop3::new(
                        &state,
                        &self.settings.fe,
                        &self.settings.damping,
                        target,
                        Some(&out),
                        &self.control,
                    )?);
                }
                let loop3 = self
                    .loop3
                    .as_mut()
                    .ok_or_else(|| TuneError::Invalid("no loop 3 session".into()))?;
                let result = loop3.grid(spec)?;
                say(&format!(
                    "grid {}: {} points ({} run, {} from the journal) in {:.2} s",
                    spec.name,
                    result.points.len(),
                    result.computed,
                    result.resumed,
                    result.elapsed_s
                ));
            }
            Step::ChooseBest { zeta } => {
                let target = self.target(*zeta, "damping_ratio")?;
                let paper = paper_damping_point(self.case()?);
                let loop3 = self.loop3.as_mut().ok_or_else(|| {
                    TuneError::Invalid(
                        "no grid yet for this model; put `grid ...` lines before `choose best`"
                            .into(),
                    )
                })?;
                loop3.set_target_zeta(target)?;
                let report = loop3.finish(paper)?;
                let state = self.state()?;
                state.alpha = report.chosen.alpha;
                state.beta = report.chosen.beta;
                say(&format!(
                    "choose: alpha = {}, beta = {} -> zeta = {:.6} (target {target}, error {:+.3}%)",
                    report.chosen.alpha,
                    report.chosen.beta,
                    report.chosen.zeta,
                    100.0 * (report.chosen.zeta - target) / target
                ));
                if let Some(d) = report.chosen.direct {
                    say(&format!(
                        "        direct integration: zeta = {:.6} ({:+.3}%)",
                        d.zeta_mean,
                        100.0 * report.chosen.direct_relative_difference.unwrap_or(f64::NAN)
                    ));
                }
                self.damping = Some(report);
            }
            Step::Print => {
                let s = *self.state()?;
                say(&format!(
                    "state: n = {}, D = {} mm, d = {} mm, h = {} mm, E = {:.1} MPa, nu = {}, rho = {} kg/m^3, mass = {:.5} kg, alpha = {:.4} 1/s, beta = {:.4e} s; {} elements per coil, method {}",
                    s.spring.active_coils,
                    s.spring.mean_diameter_mm,
                    s.spring.wire_diameter_mm,
                    s.spring.pitch_mm,
                    s.youngs_modulus_mpa,
                    s.poisson_ratio,
                    s.density_kg_m3,
                    s.mass_kg,
                    s.alpha,
                    s.beta,
                    self.settings.fe.elements_per_coil,
                    self.settings.damping.decay.method
                ));
            }
            Step::Echo(text) => say(text),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_err(text: &str) -> (usize, String) {
        match parse(text, Path::new("t.proc")) {
            Err(TuneError::Procedure { line, message, .. }) => (line, message),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn every_setting_and_command_is_defined_once() {
        for (i, s) in SETTINGS.iter().enumerate() {
            assert!(
                SETTINGS[i + 1..].iter().all(|t| t.name != s.name),
                "{}",
                s.name
            );
        }
        for (i, c) in COMMANDS.iter().enumerate() {
            assert!(
                COMMANDS[i + 1..].iter().all(|t| t.name != c.name),
                "{}",
                c.name
            );
            assert!(c.usage.starts_with(c.name));
        }
    }

    /// Every setting in the table is parsed and applied (none falls through to "no
    /// effect").
    #[test]
    fn every_setting_applies() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
        let procedure = Procedure {
            path: root.join("x.proc"),
            statements: vec![],
        };
        let mut session = Session {
            procedure: &procedure,
            case: None,
            state: None,
            settings: CalibrateSettings::default(),
            out: None,
            out_fixed: false,
            loop3: None,
            loops: vec![],
            damping: None,
            record: None,
            control: RunControl::default(),
        };
        let mut quiet = |_: &str| {};
        session
            .execute(&Step::Case(".".into()), &mut quiet)
            .unwrap();
        for s in SETTINGS {
            let value = match s.kind {
                Kind::Positive | Kind::NonNegative | Kind::PositiveOrOff => "1".to_string(),
                Kind::Open(lo, hi) => format!("{}", 0.5 * (lo.max(-0.5) + hi)),
                Kind::Count(_) => "8".to_string(),
                Kind::Choice(words) => words[0].to_string(),
                Kind::Switch => "on".to_string(),
                Kind::List => "0,1".to_string(),
            };
            let (name, parsed) = parse_setting(s.name, &value).unwrap();
            session.apply(name, &parsed).unwrap();
        }
        assert_eq!(session.settings.fe.elements_per_coil, 8);
        assert_eq!(session.state.unwrap().youngs_modulus_mpa, 1.0);
    }

    #[test]
    fn parse_errors_name_the_line() {
        for (text, line, needle) in [
            ("case x\nsolve nothing\n", 2, "static, modal or transient"),
            ("\n# c\nfly away\n", 3, "unknown command `fly`"),
            ("set youngs 3\n", 1, "unknown setting `youngs`"),
            ("set elements_per_coil 2\n", 1, "a whole number >= 3"),
            ("tune youngs_modulus to stiffness -1\n", 1, "positive"),
            (
                "tune youngs_modulus to stiffness 3.9 tolerance 2\n",
                1,
                "(0, 1)",
            ),
            ("tune mass to stiffness 3\n", 1, "expected `tune"),
            ("grid alpha 0:0.1:2\n", 1, "expected `grid"),
            (
                "grid alpha 0:0.3:1 beta 0:1:2\n",
                1,
                "whole number of steps",
            ),
            (
                "grid alpha 0 beta 0\ngrid alpha 1 beta 1 name grid1\n",
                2,
                "twice",
            ),
            ("echo ok\ncase \"unclosed\n", 2, "not closed"),
            ("choose best zeta 2\n", 1, "below 1"),
            ("set lowpass_hz -3\n", 1, "or off"),
            ("mesh a b\n", 1, "expected `mesh [FILE]`"),
        ] {
            let (l, message) = parse_err(text);
            assert_eq!(l, line, "{text}: {message}");
            assert!(message.contains(needle), "{text}: {message}");
        }
    }

    /// docs/procedures.md lists every command and every setting of the tables.
    #[test]
    fn the_reference_documents_every_keyword() {
        let doc = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/procedures.md"),
        )
        .unwrap();
        for c in COMMANDS {
            assert!(doc.contains(&format!("| `{}` |", c.name)), "{}", c.name);
        }
        for s in SETTINGS {
            assert!(doc.contains(&format!("| `{}` |", s.name)), "{}", s.name);
        }
    }

    #[test]
    fn the_papers_procedure_parses() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect/figure6.proc");
        let p = read(&path).unwrap();
        let grids: Vec<&GridSpec> = p
            .statements
            .iter()
            .filter_map(|s| match &s.step {
                Step::Grid(g) => Some(g),
                _ => None,
            })
            .collect();
        assert_eq!(grids.len(), 2);
        assert_eq!(grids[0].alpha, GridSpec::paper_domain1().alpha);
        assert_eq!(grids[1].beta, GridSpec::paper_domain2().beta);
        assert_eq!(grids[1].name, "domain2");
    }
}
