//! Every command of the procedure language, each one entry: its name, its form and meaning
//! (from which `docs/procedures.md` is written), how a line of it parses and what it does,
//! with its tests beside it (the layout of ripgrep's `crates/core/flags/defs.rs`).
//!
//! A command is a [`Command`] in [`COMMANDS`]; its `parse` turns the line's words into an
//! [`Action`], a small struct holding what the line said, whose `run` acts on the
//! [`Session`]. Parse errors are [`ProcedureError`]s (the caller adds the file and line);
//! run errors are [`TuneError`]s (the caller adds the line too).

use std::any::Any;
use std::path::Path;

use super::session::Session;
use super::settings::{apply, parse_setting, SetValue};
use super::words::{
    arity, grid_name, inside_name, optional_tolerance, target_value, usage_error, Parsed,
    TargetValue,
};
use crate::calibrate::paper_damping_point;
use crate::case::read_case;
use crate::damping::{Loop3, Simulator};
use crate::decay::measure;
use crate::error::{ProcedureError, Result, TuneError};
use crate::fe::{self, SpringState};
use crate::grid::{Axis, GridSpec};
use crate::loops::{tune_mass, tune_youngs_modulus};
use crate::output::{csv, exact, OutDir};
use coil_mesher::AnalysisKind;

/// A command of the language: its name, its form, what it does and how a line of it parses.
#[derive(Debug, Clone, Copy)]
pub struct Command {
    /// The first word of its lines.
    pub name: &'static str,
    /// Its form, for messages and the reference.
    pub usage: &'static str,
    /// What it does, for the reference.
    pub meaning: &'static str,
    /// Parses a line's words (the name first) into what the line does.
    parse: ParseFn,
}

/// How a command parses a line's words (its name first) into what the line does.
type ParseFn = fn(&Command, &[String], &mut Parsing) -> Parsed<Box<dyn Action>>;

/// What a parsed line does when the procedure runs.
pub(crate) trait Action: std::fmt::Debug {
    /// Runs the line; `say` receives each printed line.
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()>;
    /// The action itself, for tests that look inside a parsed procedure.
    #[cfg_attr(not(test), allow(dead_code))]
    fn as_any(&self) -> &dyn Any;
}

/// What parsing carries from one line to the next: the grids so far (a grid without a
/// name is `grid<N>`, N counting the file's grids; two grids may not share a name).
#[derive(Debug, Default)]
pub(crate) struct Parsing {
    grids: usize,
    grid_names: Vec<String>,
}

/// Every command, once.
pub const COMMANDS: &[Command] = &[
    CASE, OUT, SET, MESH, SOLVE, POST, TUNE, GRID, CHOOSE, PRINT, ECHO,
];

#[cfg(test)]
use super::tests::assert_parse_errors;

#[cfg(test)]
#[test]
fn every_command_is_defined_once() {
    for (i, c) in COMMANDS.iter().enumerate() {
        assert!(
            COMMANDS[i + 1..].iter().all(|t| t.name != c.name),
            "{}",
            c.name
        );
        assert!(c.usage.starts_with(c.name));
    }
}

/// Parses one line's words (not empty) into its action.
pub(crate) fn parse_line(w: &[String], parsing: &mut Parsing) -> Parsed<Box<dyn Action>> {
    let command =
        COMMANDS
            .iter()
            .find(|c| c.name == w[0])
            .ok_or_else(|| ProcedureError::UnknownCommand {
                name: w[0].clone(),
                known: COMMANDS
                    .iter()
                    .map(|c| c.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            })?;
    (command.parse)(command, w, parsing)
}

macro_rules! action_any {
    () => {
        fn as_any(&self) -> &dyn Any {
            self
        }
    };
}

// ---------------------------------------------------------------------------------------
// case PATH

const CASE: Command = Command {
    name: "case",
    usage: "case PATH",
    meaning: "read a measured case (a folder with case.json, or the file), relative to the procedure file's folder; sets the state to the case's nominal values",
    parse: |c, w, _| {
        arity(w, 2, 2, c.usage)?;
        Ok(Box::new(Case(w[1].clone())))
    },
};

/// `case PATH`.
#[derive(Debug)]
struct Case(String);

impl Action for Case {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let folder = session.path.parent().unwrap_or(Path::new(""));
        let case = read_case(&folder.join(&self.0))?;
        say(&format!("case: {} ({})", case.name, case.file.display()));
        session.state = Some(SpringState::nominal(&case));
        session.case = Some(case);
        session.model_changed();
        Ok(())
    }
    action_any!();
}

// ---------------------------------------------------------------------------------------
// out DIR

const OUT: Command = Command {
    name: "out",
    usage: "out DIR",
    meaning:
        "the output folder, relative to the working directory (`coil-tune run --out` overrides it)",
    parse: |c, w, _| {
        arity(w, 2, 2, c.usage)?;
        Ok(Box::new(Out(inside_name(
            &w[1],
            "an output folder relative to the working directory",
        )?)))
    },
};

/// `out DIR`.
#[derive(Debug)]
struct Out(String);

impl Action for Out {
    fn run(&self, session: &mut Session, _: &mut dyn FnMut(&str)) -> Result<()> {
        if !session.out_fixed {
            if let Some(out) = &session.out {
                return Err(TuneError::Invalid(format!(
                    "the output folder is {} already; put `out` once, before the \
                     first command that writes a file",
                    out.root().display()
                )));
            }
            session.out = Some(OutDir::create(&self.0)?);
        }
        Ok(())
    }
    action_any!();
}

// ---------------------------------------------------------------------------------------
// set NAME VALUE

const SET: Command = Command {
    name: "set",
    usage: "set NAME VALUE",
    meaning: "set a model value, a run setting or a tolerance (see the settings table)",
    parse: |c, w, _| {
        arity(w, 3, 3, c.usage)?;
        let (name, value) = parse_setting(&w[1], &w[2])?;
        Ok(Box::new(Set { name, value }))
    },
};

/// `set NAME VALUE` (the settings are in [`super::settings`]).
#[derive(Debug)]
struct Set {
    name: &'static str,
    value: SetValue,
}

impl Action for Set {
    fn run(&self, session: &mut Session, _: &mut dyn FnMut(&str)) -> Result<()> {
        apply(session, self.name, &self.value)
    }
    action_any!();
}

// ---------------------------------------------------------------------------------------
// mesh [FILE]

const MESH: Command = Command {
    name: "mesh",
    usage: "mesh [FILE]",
    meaning: "write the current model (static, modal and transient load cases) as a deck, default mesh.dat in the output folder",
    parse: |c, w, _| {
        arity(w, 1, 2, c.usage)?;
        let file = w
            .get(1)
            .map(|f| inside_name(f, "a deck file name inside the output folder"));
        Ok(Box::new(Mesh(file.transpose()?)))
    },
};

/// `mesh [FILE]`.
#[derive(Debug)]
struct Mesh(Option<String>);

impl Action for Mesh {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let state = *session.state()?;
        let mut spec = state.spec(
            &session.settings.fe,
            &[
                AnalysisKind::Static,
                AnalysisKind::Modal,
                AnalysisKind::Transient,
            ],
        );
        let decay = &session.settings.damping.decay;
        spec.dt_s = decay.dt_s;
        spec.duration_s = decay.duration_s;
        spec.initial_velocity_m_s = decay.initial_velocity_m_s;
        let model = spec.build()?;
        let name = self.0.clone().unwrap_or_else(|| "mesh.dat".into());
        let path = session
            .out()?
            .write(&name, coil_solver::deck::write(&model).as_bytes())?;
        say(&format!(
            "mesh: {} elements -> {}",
            model.elements.len(),
            path.display()
        ));
        Ok(())
    }
    action_any!();
}

#[cfg(test)]
#[test]
fn mesh_takes_at_most_one_file() {
    assert_parse_errors(&[("mesh a b\n", 1, "expected `mesh [FILE]`")]);
}

// ---------------------------------------------------------------------------------------
// solve static|modal|transient

const SOLVE: Command = Command {
    name: "solve",
    usage: "solve static|modal|transient",
    meaning: "run the current model: static stiffness K; the axial mode's period; a free-decay transient (kept for `post`, written to transient.csv)",
    parse: |c, w, _| {
        arity(w, 2, 2, c.usage)?;
        Ok(Box::new(Solve(match w[1].as_str() {
            "static" => AnalysisKind::Static,
            "modal" => AnalysisKind::Modal,
            "transient" => AnalysisKind::Transient,
            other => {
                return Err(ProcedureError::Analysis {
                    word: other.to_string(),
                })
            }
        })))
    },
};

/// `solve static|modal|transient`.
#[derive(Debug)]
struct Solve(AnalysisKind);

impl Action for Solve {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let state = *session.state()?;
        match self.0 {
            AnalysisKind::Static => {
                let (k, _) = fe::static_stiffness(&state, &session.settings.fe)?;
                say(&format!("static: K = {k:.6} N/mm"));
            }
            AnalysisKind::Modal => {
                let (r, _) = fe::static_and_modal(&state, &session.settings.fe)?;
                say(&format!(
                    "modal: axial mode {} at {:.6} Hz, T = {:.6} s, effective mass {:.4} kg",
                    r.axial.mode, r.axial.frequency_hz, r.axial.period_s, r.axial.effective_mass_kg
                ));
            }
            AnalysisKind::Transient => {
                let decay = session.settings.damping.decay.clone();
                let sim = Simulator::new(&state, &session.settings.fe, &decay)?;
                let record = sim.run(state.alpha, state.beta)?;
                let text = csv(
                    &["time_s", coil_mesher::WEIGHT_ACCEL_COLUMN],
                    record
                        .time_s
                        .iter()
                        .zip(&record.accel_m_s2)
                        .map(|(t, a)| vec![exact(*t), exact(*a)]),
                );
                let path = session.out()?.write("transient.csv", text.as_bytes())?;
                say(&format!(
                    "transient ({}): {} samples -> {}",
                    decay.method,
                    record.time_s.len(),
                    path.display()
                ));
                session.record = Some(record);
            }
        }
        Ok(())
    }
    action_any!();
}

#[cfg(test)]
#[test]
fn solve_names_the_analyses() {
    assert_parse_errors(&[("case x\nsolve nothing\n", 2, "static, modal or transient")]);
}

// ---------------------------------------------------------------------------------------
// post

const POST: Command = Command {
    name: "post",
    usage: "post",
    meaning: "logarithmic decrement of the last transient (every 10th crest, the paper's Eqs. 2-3): zeta and the period",
    parse: |c, w, _| {
        arity(w, 1, 1, c.usage)?;
        Ok(Box::new(Post))
    },
};

/// `post`.
#[derive(Debug)]
struct Post;

impl Action for Post {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let record = session.record.as_ref().ok_or_else(|| {
            TuneError::Invalid("no transient yet; put `solve transient` before `post`".into())
        })?;
        let m = measure(record, &session.settings.damping.decay)?;
        say(&format!(
            "post: zeta = {:.8} (span mean, every {}th crest), zeta_fit = {:.8}, T = {:.8} s, {} crests",
            m.zeta_mean, session.settings.damping.decay.every, m.zeta_fit, m.period_s, m.crests
        ));
        Ok(())
    }
    action_any!();
}

// ---------------------------------------------------------------------------------------
// tune youngs_modulus to stiffness ... | tune mass to period ...

const TUNE: Command = Command {
    name: "tune",
    usage: "tune youngs_modulus to stiffness VALUE|target [tolerance TOL] | tune mass to period VALUE|target [tolerance TOL]",
    meaning: "loop 1 (E to K) or loop 2 (the weight's mass to the axial period); `target` takes the case's targets",
    parse: |c, w, _| {
        let form: Vec<&str> = w.iter().take(4).map(String::as_str).collect();
        let (quantity, what) = match form.as_slice() {
            ["tune", "youngs_modulus", "to", "stiffness"] if w.len() >= 5 => {
                (Tuned::YoungsModulus, "stiffness in N/mm")
            }
            ["tune", "mass", "to", "period"] if w.len() >= 5 => (Tuned::Mass, "period in s"),
            _ => return Err(usage_error(w, c.usage)),
        };
        Ok(Box::new(Tune {
            quantity,
            target: target_value(&w[4], what)?,
            tolerance: optional_tolerance(&w[5..], c.usage)?,
        }))
    },
};

/// What `tune` adjusts.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tuned {
    /// Loop 1: E to the stiffness.
    YoungsModulus,
    /// Loop 2: the weight's mass to the period.
    Mass,
}

/// `tune ...`.
#[derive(Debug)]
struct Tune {
    quantity: Tuned,
    target: TargetValue,
    tolerance: Option<f64>,
}

impl Action for Tune {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let (field, default_tolerance) = match self.quantity {
            Tuned::YoungsModulus => ("stiffness_n_mm", session.settings.stiffness_tolerance),
            Tuned::Mass => ("period_s", session.settings.period_tolerance),
        };
        let target = session.target(self.target, field)?;
        let tolerance = self.tolerance.unwrap_or(default_tolerance);
        let out = session.out()?;
        let fe = session.settings.fe.clone();
        let state = session.state()?;
        let report = match self.quantity {
            Tuned::YoungsModulus => {
                let report = tune_youngs_modulus(state, &fe, target, tolerance, Some(&out))?;
                say(&format!(
                    "tune: E = {:.4} MPa -> K = {:.6} N/mm (error {:+.2e}) in {} runs",
                    report.value,
                    report.result,
                    report.relative_error,
                    report.iterations.len()
                ));
                report
            }
            Tuned::Mass => {
                let report = tune_mass(state, &fe, target, tolerance, Some(&out))?;
                say(&format!(
                    "tune: mass = {:.6} kg -> T = {:.6} s (error {:+.2e}) in {} runs",
                    report.value,
                    report.result,
                    report.relative_error,
                    report.iterations.len()
                ));
                report
            }
        };
        session.loops.push(report);
        session.model_changed();
        Ok(())
    }
    action_any!();
}

#[cfg(test)]
#[test]
fn tune_checks_its_form_target_and_tolerance() {
    assert_parse_errors(&[
        ("tune youngs_modulus to stiffness -1\n", 1, "positive"),
        (
            "tune youngs_modulus to stiffness 3.9 tolerance 2\n",
            1,
            "(0, 1)",
        ),
        ("tune mass to stiffness 3\n", 1, "expected `tune"),
    ]);
}

// ---------------------------------------------------------------------------------------
// grid alpha START:STEP:END beta START:STEP:END [name NAME]

const GRID: Command = Command {
    name: "grid",
    usage: "grid alpha START:STEP:END beta START:STEP:END [name NAME]",
    meaning: "loop 3: a decay transient and its decrement at every (alpha, beta), in parallel, journaled (resumable)",
    parse: |c, w, parsing| {
        let mut spec = grid_spec(c, w)?;
        parsing.grids += 1;
        if spec.name.is_empty() {
            spec.name = format!("grid{}", parsing.grids);
        }
        if parsing.grid_names.contains(&spec.name) {
            return Err(ProcedureError::DuplicateGrid { name: spec.name });
        }
        parsing.grid_names.push(spec.name.clone());
        Ok(Box::new(Grid(spec)))
    },
};

/// The grid of a `grid` line (an empty name when the line names none).
pub(crate) fn grid_spec(c: &Command, w: &[String]) -> Parsed<GridSpec> {
    let mut alpha = None;
    let mut beta = None;
    let mut name = None;
    for pair in w[1..].chunks(2) {
        match pair {
            [key, value] if key == "alpha" => {
                alpha = Some(Axis::parse(value).map_err(ProcedureError::Axis)?)
            }
            [key, value] if key == "beta" => {
                beta = Some(Axis::parse(value).map_err(ProcedureError::Axis)?)
            }
            [key, value] if key == "name" => name = Some(grid_name(value)?),
            _ => return Err(usage_error(w, c.usage)),
        }
    }
    for (what, axis) in [("alpha", &alpha), ("beta", &beta)] {
        if let Some(a) = axis.as_ref().filter(|a| a.start < 0.0) {
            return Err(ProcedureError::NegativeRayleigh {
                what,
                axis: a.to_string(),
            });
        }
    }
    match (alpha, beta) {
        (Some(alpha), Some(beta)) => Ok(GridSpec {
            name: name.unwrap_or_default(),
            alpha,
            beta,
        }),
        _ => Err(usage_error(w, c.usage)),
    }
}

/// Parses the words of a `grid` line without the command, e.g.
/// `alpha 0:0.1:2 beta 0:1e-5:2e-4 name domain2` (the name defaults to `grid`).
pub fn parse_grid(text: &str) -> Parsed<GridSpec> {
    let mut w = vec![GRID.name.to_string()];
    w.extend(super::words::words(text)?);
    let mut spec = grid_spec(&GRID, &w)?;
    if spec.name.is_empty() {
        spec.name = "grid".into();
    }
    Ok(spec)
}

/// `grid ...`.
#[derive(Debug)]
pub(crate) struct Grid(pub GridSpec);

impl Action for Grid {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let spec = &self.0;
        if session.loop3.is_none() {
            let state = *session.state()?;
            let target = session.case()?.targets.damping_ratio.unwrap_or(0.5);
            let out = session.out()?;
            session.loop3 = Some(Loop3::new(
                &state,
                &session.settings.fe,
                &session.settings.damping,
                target,
                Some(&out),
                &session.control,
            )?);
        }
        let loop3 = session
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
        Ok(())
    }
    action_any!();
}

#[cfg(test)]
#[test]
fn grid_checks_its_axes() {
    assert_parse_errors(&[
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
    ]);
}

#[cfg(test)]
#[test]
fn the_papers_procedure_parses() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect/figure6.proc");
    let p = super::read(&path).unwrap();
    let grids: Vec<&GridSpec> = p
        .statements
        .iter()
        .filter_map(|s| s.action.as_any().downcast_ref::<Grid>().map(|g| &g.0))
        .collect();
    assert_eq!(grids.len(), 2);
    assert_eq!(grids[0].alpha, GridSpec::paper_domain1().alpha);
    assert_eq!(grids[1].beta, GridSpec::paper_domain2().beta);
    assert_eq!(grids[1].name, "domain2");
}

// ---------------------------------------------------------------------------------------
// choose best [zeta VALUE|target]

const CHOOSE: Command = Command {
    name: "choose",
    usage: "choose best [zeta VALUE|target]",
    meaning: "set alpha and beta to the grid point closest to the target zeta over the grids so far; fit the plane, trace the valley, check by direct integration, draw the figures",
    parse: |c, w, _| {
        let zeta = match w.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
            ["choose", "best"] => TargetValue::Target,
            ["choose", "best", "zeta", value] => {
                let zeta = target_value(value, "damping ratio")?;
                if let TargetValue::Number(z) = zeta {
                    if z >= 1.0 {
                        return Err(ProcedureError::Overdamped { value: z });
                    }
                }
                zeta
            }
            _ => return Err(usage_error(w, c.usage)),
        };
        Ok(Box::new(ChooseBest { zeta }))
    },
};

/// `choose best ...`.
#[derive(Debug)]
struct ChooseBest {
    zeta: TargetValue,
}

impl Action for ChooseBest {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let target = session.target(self.zeta, "damping_ratio")?;
        let paper = paper_damping_point(session.case()?);
        let loop3 = session.loop3.as_mut().ok_or_else(|| {
            TuneError::Invalid(
                "no grid yet for this model; put `grid ...` lines before `choose best`".into(),
            )
        })?;
        loop3.set_target_zeta(target)?;
        let report = loop3.finish(paper)?;
        let state = session.state()?;
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
        session.damping = Some(report);
        Ok(())
    }
    action_any!();
}

#[cfg(test)]
#[test]
fn choose_refuses_an_overdamped_target() {
    assert_parse_errors(&[("choose best zeta 2\n", 1, "below 1")]);
}

// ---------------------------------------------------------------------------------------
// print

const PRINT: Command = Command {
    name: "print",
    usage: "print",
    meaning: "print the current values",
    parse: |c, w, _| {
        arity(w, 1, 1, c.usage)?;
        Ok(Box::new(Print))
    },
};

/// `print`.
#[derive(Debug)]
struct Print;

impl Action for Print {
    fn run(&self, session: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        let s = *session.state()?;
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
            session.settings.fe.elements_per_coil,
            session.settings.damping.decay.method
        ));
        Ok(())
    }
    action_any!();
}

// ---------------------------------------------------------------------------------------
// echo TEXT...

const ECHO: Command = Command {
    name: "echo",
    usage: "echo TEXT...",
    meaning: "print the text",
    parse: |_, w, _| Ok(Box::new(Echo(w[1..].join(" ")))),
};

/// `echo TEXT...`.
#[derive(Debug)]
struct Echo(String);

impl Action for Echo {
    fn run(&self, _: &mut Session, say: &mut dyn FnMut(&str)) -> Result<()> {
        say(&self.0);
        Ok(())
    }
    action_any!();
}
