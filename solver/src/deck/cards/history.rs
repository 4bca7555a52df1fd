//! The history section: `END OPTION` opens it; a load case is one analysis card
//! (`AUTO LOAD` with `TIME STEP`, `MODAL SHAPE` or `DYNAMIC CHANGE`, times in s)
//! closed by `CONTINUE`.
//!
//! Each card is one [`Keyword`] entry (its name, sections, meaning, layout, example
//! and parse function) followed by its parse function; then the family's build function
//! (raw deck -> model parts, run in order by [`crate::deck::build`]); its tests close
//! the file.

use super::loads::point_load;
use super::mentat::active_names_exist;
use crate::deck::card::{once, CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::{DeckError, Loc};
use crate::deck::raw::{MarcDynamic, RawDeck, RawLoadCase};
use crate::deck::resolve::Builder;
use crate::model::{Analysis, LoadCase, ModelParts, PointLoad};
use crate::model::{Integrator, TransientMethod};
use DeckSection::{History, Model};

/// The `END OPTION` card.
pub(crate) const END_OPTION: Keyword = Keyword {
    name: "END OPTION",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Ends the model definition; the load cases follow.",
    layout: &[("END OPTION", "")],
    notes: "",
    example: "END OPTION",
    parse: parse_end_option,
};

/// The `AUTO LOAD` card.
pub(crate) const AUTO_LOAD: Keyword = Keyword {
    name: "AUTO LOAD",
    sections: &[History],
    origin: Origin::Marc,
    meaning: "A static load case in n steps (with TIME STEP). A linear solve applies \
              the full load once; n is kept for Marc compatibility.",
    layout: &[
        ("AUTO LOAD", ""),
        (
            "n[, 0 ...]",
            "number of steps >= 1; Marc's further fields must be blank or 0",
        ),
    ],
    notes: "A static load case needs both AUTO LOAD and TIME STEP.",
    example: "AUTO LOAD\n1",
    parse: parse_auto_load,
};

/// The `TIME STEP` card.
pub(crate) const TIME_STEP: Keyword = Keyword {
    name: "TIME STEP",
    sections: &[History],
    origin: Origin::Marc,
    meaning: "The time of each step of a static load case (s).",
    layout: &[("TIME STEP", ""), ("dt", "dt > 0 (s)")],
    notes: "A static load case needs both AUTO LOAD and TIME STEP.",
    example: "TIME STEP\n1.0",
    parse: parse_time_step,
};

/// The `MODAL SHAPE` card.
pub(crate) const MODAL_SHAPE: Keyword = Keyword {
    name: "MODAL SHAPE",
    sections: &[History],
    origin: Origin::Coil,
    meaning: "A modal load case: the lowest n eigenpairs of K phi = omega^2 M phi.",
    layout: &[("MODAL SHAPE", ""), ("n", "number of modes >= 1")],
    notes: "Marc takes the number of modes from its DYNAMIC parameter; coil reads it \
            here.",
    example: "MODAL SHAPE\n10",
    parse: parse_modal_shape,
};

/// The `DYNAMIC CHANGE` card.
pub(crate) const DYNAMIC_CHANGE: Keyword = Keyword {
    name: "DYNAMIC CHANGE",
    sections: &[History],
    origin: Origin::Coil,
    meaning: "A transient load case with fixed step dt up to the total time, by direct \
              integration or modal superposition.",
    layout: &[
        ("DYNAMIC CHANGE", ""),
        (
            "dt, total[, method[, p]]",
            "dt > 0 (s), total >= dt (s); method NEWMARK (average acceleration, the \
             default when omitted, unless a DYNAMIC, 1 parameter card asks for modal \
             superposition), HHT with p = alpha in [-1/3, 0], GALPHA with \
             p = rho_inf in [0, 1], or MODAL with p = number of modes >= 1",
        ),
    ],
    notes: "dt and total are Marc's first two fields; the method fields are coil's own.",
    example: "DYNAMIC CHANGE\n1.0e-4, 0.5, HHT, -0.05",
    parse: parse_dynamic_change,
};

/// The `CONTINUE` card.
pub(crate) const CONTINUE: Keyword = Keyword {
    name: "CONTINUE",
    sections: &[History],
    origin: Origin::Marc,
    meaning: "Closes the load case made of the history cards since the previous \
              CONTINUE.",
    layout: &[("CONTINUE", "")],
    notes: "A load case needs exactly one analysis: AUTO LOAD with TIME STEP, MODAL \
            SHAPE, or DYNAMIC CHANGE.",
    example: "TITLE, modes\nMODAL SHAPE\n10\nCONTINUE",
    parse: parse_continue,
};

fn parse_end_option(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    c.deck.end_option = Some(c.loc());
    *c.section = History;
    Ok(())
}

/// The analysis a history card implies: static, modal or transient.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Static,
    Modal,
    Transient,
}

/// Fails if the open load case already has a card of another analysis kind.
fn one_analysis(c: &mut CardCtx<'_, '_>, kind: Kind) -> Result<(), DeckError> {
    let case = c.case();
    let others = [
        (Kind::Static, case.auto_load.map(|a| a.1), "AUTO LOAD"),
        (Kind::Static, case.time_step.map(|a| a.1), "TIME STEP"),
        (Kind::Modal, case.modal.map(|a| a.1), "MODAL SHAPE"),
        (Kind::Transient, case.dynamic.map(|a| a.3), "DYNAMIC CHANGE"),
    ];
    for (k, loc, name) in others {
        if let (true, Some(loc)) = (k != kind, loc) {
            return Err(c.err(
                c.loc(),
                format!("this load case already has {name} (line {})", loc.line),
                "one analysis per load case (close it with CONTINUE first)",
            ));
        }
    }
    Ok(())
}

fn parse_auto_load(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let previous = c.case().auto_load.map(|a| a.1);
    once(c, previous)?;
    one_analysis(c, Kind::Static)?;
    let l = c.data_line("the number of steps")?;
    let steps = c.count(l, 0, 1, "the number of steps")?;
    // Marc's further fields (Mentat writes `n 0 10`) control nonlinear increments,
    // which change nothing in a linear solve: integers, not used.
    for i in 1..l.fields.len() {
        c.uint_or(l, i, 0, "Marc's further AUTO LOAD fields: integers")?;
    }
    let loc = c.loc();
    c.case().auto_load = Some((steps, loc));
    Ok(())
}

fn parse_time_step(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let previous = c.case().time_step.map(|a| a.1);
    once(c, previous)?;
    one_analysis(c, Kind::Static)?;
    let l = c.data_line("the time step (s)")?;
    c.field_count(l, 1, 1, "the time step (s)")?;
    let dt = c.real(l, 0, "the time step (s)")?;
    let dt = c.positive(dt, l.loc_of(0), "the time step")?;
    let loc = c.loc();
    c.case().time_step = Some((dt, loc));
    Ok(())
}

fn parse_modal_shape(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let previous = c.case().modal.map(|a| a.1);
    once(c, previous)?;
    one_analysis(c, Kind::Modal)?;
    let l = c.data_line("the number of modes")?;
    c.field_count(l, 1, 1, "the number of modes")?;
    let modes = c.count(l, 0, 1, "the number of modes")?;
    let loc = c.loc();
    c.case().modal = Some((modes, loc));
    Ok(())
}

fn parse_dynamic_change(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "dt, total time[, NEWMARK | HHT, alpha | GALPHA, rho_inf | MODAL, modes]";
    c.no_args()?;
    let previous = c.case().dynamic.map(|a| a.3);
    once(c, previous)?;
    one_analysis(c, Kind::Transient)?;
    let l = c.data_line(LAYOUT)?;
    c.field_count(l, 2, 4, LAYOUT)?;
    let dt = c.real(l, 0, "the time step dt (s)")?;
    let dt = c.positive(dt, l.loc_of(0), "the time step dt")?;
    let total = c.real(l, 1, "the total time (s)")?;
    if total < dt {
        return Err(c.err(
            l.loc_of(1),
            format!("the total time {total:?} is shorter than the time step {dt:?}"),
            "total time >= dt",
        ));
    }
    let marc = c.deck.marc_dynamic;
    let method = match l.fields.get(2).map(|f| f.text.to_ascii_uppercase()) {
        None => match marc {
            None | Some((MarcDynamic::Newmark, _)) => {
                TransientMethod::Direct(Integrator::AverageAcceleration)
            }
            Some((MarcDynamic::Modal { modes: 0 }, at)) => {
                return Err(c.err(
                    l.loc_of(0),
                    format!(
                        "DYNAMIC, 1 (line {}) asks for modal superposition and gives no \
                         number of modes",
                        at.line
                    ),
                    "the number of modes as DYNAMIC's second field, or `MODAL, modes` here",
                ))
            }
            Some((MarcDynamic::Modal { modes }, _)) => TransientMethod::Modal { modes },
        },
        Some(m) => {
            let param_needed = m != "NEWMARK";
            let n = if param_needed { 4 } else { 3 };
            c.field_count(l, n, n, LAYOUT)?;
            match m.as_str() {
                "NEWMARK" => TransientMethod::Direct(Integrator::AverageAcceleration),
                "HHT" => {
                    let alpha = c.real(l, 3, "HHT alpha")?;
                    if !((-1.0 / 3.0..=0.0).contains(&alpha)) {
                        return Err(c.err(
                            l.loc_of(3),
                            format!("HHT alpha is {alpha:?}"),
                            "-1/3 <= alpha <= 0",
                        ));
                    }
                    TransientMethod::Direct(Integrator::Hht { alpha })
                }
                "GALPHA" => {
                    let rho_inf = c.real(l, 3, "rho_inf")?;
                    if !((0.0..=1.0).contains(&rho_inf)) {
                        return Err(c.err(
                            l.loc_of(3),
                            format!("rho_inf is {rho_inf:?}"),
                            "0 <= rho_inf <= 1",
                        ));
                    }
                    TransientMethod::Direct(Integrator::GeneralizedAlpha { rho_inf })
                }
                "MODAL" => TransientMethod::Modal {
                    modes: c.count(l, 3, 1, "the number of modes")?,
                },
                _ => {
                    return Err(c.err(
                        l.loc_of(2),
                        format!("`{}` is not a transient method", l.fields[2].text),
                        "NEWMARK, HHT, GALPHA or MODAL",
                    ))
                }
            }
        }
    };
    if let (Some((marc, at)), Some(named)) = (marc, l.fields.get(2)) {
        let modal = matches!(method, TransientMethod::Modal { .. });
        if modal != matches!(marc, MarcDynamic::Modal { .. }) {
            return Err(c.err(
                l.loc_of(2),
                format!(
                    "method {} contradicts DYNAMIC, {} (line {})",
                    named.text,
                    if modal { 2 } else { 1 },
                    at.line
                ),
                "a method of DYNAMIC's kind (modal for code 1, direct for code 2), or none",
            ));
        }
    }
    let loc = c.loc();
    c.case().dynamic = Some((dt, total, method, loc));
    Ok(())
}

fn parse_continue(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let loc = c.loc();
    let Some(mut case) = c.deck.open_case.take() else {
        return Err(c.err(
            loc,
            "CONTINUE closes no load case",
            "history cards (TITLE, AUTO LOAD, TIME STEP, MODAL SHAPE, DYNAMIC CHANGE, POINT LOAD) before CONTINUE",
        ));
    };
    let begun = case.loc.map_or(loc.line, |l| l.line);
    let static_parts = (case.auto_load.is_some(), case.time_step.is_some());
    let message = match static_parts {
        (true, false) => Some("the static load case has AUTO LOAD but no TIME STEP"),
        (false, true) => Some("the static load case has TIME STEP but no AUTO LOAD"),
        (false, false) if case.modal.is_none() && case.dynamic.is_none() => {
            Some("the load case has no analysis")
        }
        _ => None,
    };
    if let Some(m) = message {
        return Err(c.err(
            loc,
            format!("{m} (load case begun at line {begun})"),
            "AUTO LOAD with TIME STEP, MODAL SHAPE, or DYNAMIC CHANGE",
        ));
    }
    case.end = Some(loc);
    c.deck.load_cases.push(case);
    Ok(())
}

// The deck reference, generated from the table.

/// The load cases, each with the named loads its `LOADCASE` activates.
pub(crate) fn build(
    b: &Builder<'_>,
    raw: &RawDeck,
    named_loads: &[(&str, Vec<PointLoad>)],
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    for c in &raw.load_cases {
        let mut case = load_case(b, c, raw)?;
        if let Some(active) = &c.active {
            active_loads(b, raw, c, active, named_loads, &mut case)?;
        }
        parts.load_cases.push(case);
    }
    Ok(())
}

fn load_case(b: &Builder<'_>, c: &RawLoadCase, raw: &RawDeck) -> Result<LoadCase, DeckError> {
    let end = c.end.or(c.loc).unwrap_or(Loc::new(1, 1));
    let analysis = if let Some((modes, _)) = c.modal {
        Analysis::Modal { modes }
    } else if let Some((dt, total_time, method, _)) = c.dynamic {
        Analysis::Transient {
            dt,
            total_time,
            method,
        }
    } else if let (Some((steps, _)), Some((time, _))) = (c.auto_load, c.time_step) {
        Analysis::Static { steps, time }
    } else {
        // The CONTINUE card already refuses this; kept as an error, not a panic.
        return Err(b.err(
            end,
            "CONTINUE",
            "the load case has no analysis",
            "AUTO LOAD with TIME STEP, MODAL SHAPE, or DYNAMIC CHANGE",
        ));
    };
    let point_loads = c
        .point_loads
        .iter()
        .map(|p| point_load(b, p, raw))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(LoadCase {
        title: c.title.as_ref().map(|t| t.0.clone()).unwrap_or_default(),
        analysis,
        point_loads,
    })
}

/// The named loads a Mentat `LOADCASE` activates, added to its load case; every
/// support must be active (coil's supports do not change between load cases).
fn active_loads(
    b: &Builder<'_>,
    raw: &RawDeck,
    c: &RawLoadCase,
    active: &[(String, Loc)],
    named_loads: &[(&str, Vec<PointLoad>)],
    case: &mut LoadCase,
) -> Result<(), DeckError> {
    active_names_exist(b, active, raw)?;
    for (name, _) in active {
        for (n, loads) in named_loads {
            if n == name {
                case.point_loads.extend(loads.iter().cloned());
            }
        }
    }
    let begun = c.loc.unwrap_or(Loc::new(1, 1));
    for (name, at, support) in &raw.named {
        if *support && !active.iter().any(|(n, _)| n == name) {
            return Err(b.err(
                begun,
                "LOADCASE",
                format!(
                    "the support `{name}` (line {}) is not active in this load case",
                    at.line
                ),
                "every FIXED DISP active in every load case (coil's supports do not change between load cases)",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::cards::testing::*;

    #[test]
    fn load_cases_of_every_kind() {
        let history =
            "END OPTION\nTITLE, s\nAUTO LOAD\n2\nTIME STEP\n0.5\nPOINT LOAD\n1\n3\nCONTINUE\n\
            MODAL SHAPE\n4\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1, HHT, -0.1\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1, GALPHA, 0.8\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1, MODAL, 6\nCONTINUE\n";
        let m = read_str(&format!("{PARAMS}{MESH}{history}"), "t.dat").unwrap();
        use crate::model::Analysis;
        let a: Vec<&Analysis> = m.load_cases.iter().map(|c| &c.analysis).collect();
        assert_eq!(
            *a[0],
            Analysis::Static {
                steps: 2,
                time: 0.5
            }
        );
        assert_eq!(m.load_cases[0].point_loads[0].dofs, [(1, 1.0)]);
        assert_eq!(*a[1], Analysis::Modal { modes: 4 });
        let direct = |i| Analysis::Transient {
            dt: 1e-3,
            total_time: 0.1,
            method: TransientMethod::Direct(i),
        };
        assert_eq!(*a[2], direct(Integrator::AverageAcceleration));
        assert_eq!(*a[3], direct(Integrator::Hht { alpha: -0.1 }));
        assert_eq!(*a[4], direct(Integrator::GeneralizedAlpha { rho_inf: 0.8 }));
        assert_eq!(
            *a[5],
            Analysis::Transient {
                dt: 1e-3,
                total_time: 0.1,
                method: TransientMethod::Modal { modes: 6 }
            }
        );
        for (bad, what) in [
            ("AUTO LOAD\n1\nCONTINUE\n", "no TIME STEP"),
            ("MODAL SHAPE\n2\nAUTO LOAD\n1\n", "already has MODAL SHAPE"),
            ("CONTINUE\n", "closes no load case"),
            ("DYNAMIC CHANGE\n1e-3, 0.1, HHT, 0.5\n", "HHT alpha"),
            ("DYNAMIC CHANGE\n1e-3, 1e-4\n", "shorter than the time step"),
            (
                "DYNAMIC CHANGE\n1e-3, 0.1, RK4, 1\n",
                "not a transient method",
            ),
            ("MODAL SHAPE\n0\n", "at least 1"),
            ("TITLE, x\n", "CONTINUE"),
        ] {
            let e = read_str(&format!("{PARAMS}{MESH}END OPTION\n{bad}"), "t.dat")
                .unwrap_err()
                .to_string();
            assert!(e.contains(what), "{bad}: {e}");
        }
    }
}
