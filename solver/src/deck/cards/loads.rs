//! Boundary conditions, loads and outputs: `FIXED DISP` (mm, rad), `POINT LOAD` (N,
//! N mm), `TABLE` (load factor against time in s), `INITIAL VEL` (mm/s, rad/s) and
//! `HISTORY OUTPUT`.
//!
//! Each card is one [`Keyword`] entry (its name, sections, meaning, layout, example
//! and parse function) followed by its parse function; then the family's build function
//! (raw deck -> model parts, run in order by [`crate::deck::build`]); its tests close
//! the file.

use std::collections::HashMap;

use crate::deck::card::{no_groups, plural, reserved_in, CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::{DeckError, Loc};
use crate::deck::lexer::{self};
use crate::deck::raw::{RawDeck, RawDofValues, RawOutput, RawPointLoad, RawTable, SetKind};
use crate::deck::resolve::{dof_groups, Builder};
use crate::model::check::{cross, norm, sub};
use crate::model::Quantity;
use crate::model::{FixedDisp, InitialVelocity, ModelParts, OutputRequest, PointLoad, Table};
use DeckSection::{History, Model, Parameters};

use super::mentat;
/// The `FIXED DISP` card.
pub(crate) const FIXED_DISP: Keyword = Keyword {
    name: "FIXED DISP",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Prescribed displacements (mm) and rotations (rad).",
    layout: &[
        ("FIXED DISP", ""),
        ("value[, value ...]", "the prescribed values, 1 to 6"),
        ("dof[, dof ...]", "one DOF (1..6) per value"),
        ("list", "the nodes"),
    ],
    notes: "Groups repeat until the next card. A node's DOF may be prescribed once.",
    example: "FIXED DISP\n0.0, 0.0, 0.0, 0.0, 0.0, 0.0\n1, 2, 3, 4, 5, 6\n1",
    parse: parse_fixed_disp,
};

/// The `POINT LOAD` card.
pub(crate) const POINT_LOAD: Keyword = Keyword {
    name: "POINT LOAD",
    sections: &[Model, History],
    origin: Origin::Marc,
    meaning: "Concentrated forces (N) and moments (N mm) on nodes. In the model \
              definition they act in every load case; in a load case they are added to \
              those for that load case.",
    layout: &[
        (
            "POINT LOAD[, TABLE, name]",
            "with TABLE: every load of the card is scaled in time by that table",
        ),
        (
            "F1[, F2 ... F6]",
            "the load in DOF order: Fx, Fy, Fz (N), Mx, My, Mz (N mm); 1 to 6 values",
        ),
        ("list", "the nodes"),
    ],
    notes: "Groups repeat until the next card. The `TABLE, name` fields are coil's own. \
            The model keeps the non-zero components in DOF order.",
    example: "POINT LOAD\n0.0, 0.0, -10.0\n3",
    parse: parse_point_load,
};

/// The `TABLE` card.
pub(crate) const TABLE: Keyword = Keyword {
    name: "TABLE",
    sections: &[Parameters, Model],
    origin: Origin::Coil,
    meaning: "A piecewise-linear load factor against time, for POINT LOAD.",
    layout: &[
        ("TABLE, name", ""),
        (
            "time, factor",
            "one line per point (s, -); times strictly increasing",
        ),
    ],
    notes: "Points repeat until the next card; at least one. In the parameter section \
            TABLE is Marc's parameter (table-driven input; read and not needed); \
            Mentat's model-definition layout is read too: two lines of integers \
            (the first ending with the number of points, the second starting with the \
            independent variable's type, 1 = time, inferred from public decks), then \
            the points.",
    example: "TABLE, ramp\n0.0, 0.0\n0.1, 1.0",
    parse: parse_table,
};

/// The `INITIAL VEL` card.
pub(crate) const INITIAL_VEL: Keyword = Keyword {
    name: "INITIAL VEL",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "Initial velocities (mm/s, rad/s) of every transient load case. Alone, \
              only the listed DOFs move at t = 0 and every other DOF is at rest (a \
              velocity jump). With QUASI STATIC the listed velocities are extended over \
              all free DOFs by the quasi-static shape: the static response to forces at \
              the listed DOFs, scaled so that the listed DOFs have exactly their values \
              (for a weight on a spring: the linear velocity profile the weight's motion \
              induces along the wire).",
    layout: &[
        (
            "INITIAL VEL[, QUASI STATIC]",
            "QUASI STATIC: a consistent velocity field instead of a jump (see docs/transient.md)",
        ),
        ("value[, value ...]", "the velocities, 1 to 6"),
        ("dof[, dof ...]", "one DOF (1..6) per value"),
        ("list", "the nodes"),
    ],
    notes: "Laid out like FIXED DISP. Groups repeat until the next card; a node's DOF \
            may be given once. The card may be repeated, e.g. once with and once without \
            QUASI STATIC: the quasi-static field of all QUASI STATIC groups is computed \
            first, then the plain groups set their DOFs. A listed DOF must be free: a \
            DOF prescribed by FIXED DISP may only be given 0, and a DOF tied by RBE2 is \
            given at its reference node. `QUASI STATIC` is coil's own.",
    example: "INITIAL VEL, QUASI STATIC\n-100.0\n3\n3",
    parse: parse_initial_vel,
};

/// The `HISTORY OUTPUT` card.
pub(crate) const HISTORY_OUTPUT: Keyword = Keyword {
    name: "HISTORY OUTPUT",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "Records quantities of nodes' DOFs every k-th step of a transient.",
    layout: &[
        ("HISTORY OUTPUT", ""),
        ("k", "every k-th step (k >= 1)"),
        ("quantity[, quantity ...]", "DISP, VEL and/or ACCEL"),
        ("dof[, dof ...]", "the DOFs (1..6)"),
        ("list", "the nodes"),
    ],
    notes: "Groups repeat until the next card.",
    example: "HISTORY OUTPUT\n1\nDISP, VEL, ACCEL\n3\n3",
    parse: parse_history_output,
};

/// Groups of `values / DOFs / nodes` (FIXED DISP, INITIAL VEL); the keyword line's
/// options are checked by the caller.
fn dof_value_groups(
    c: &mut CardCtx<'_, '_>,
    value: &str,
    quasi_static: bool,
) -> Result<Vec<RawDofValues>, DeckError> {
    let mut groups = Vec::new();
    while c.more_data() {
        let v = c.data_line(value)?;
        c.field_count(v, 1, 6, &format!("1 to 6 fields: {value}"))?;
        let mut values = Vec::new();
        for i in 0..v.fields.len() {
            values.push(c.real(v, i, value)?);
        }
        let n = values.len();
        let d = c.data_line(&format!(
            "{n} DOF number{}, one per value on line {}",
            plural(n),
            v.no
        ))?;
        c.field_count(
            d,
            n,
            n,
            &format!(
                "{n} DOF number{}, one per value on line {}",
                plural(n),
                v.no
            ),
        )?;
        let dofs = c.dofs(d, 0)?;
        let nodes = c.list("the list of nodes")?;
        if nodes.items.is_empty() {
            return Err(c.err(nodes.loc, "the node list is empty", "the list of nodes"));
        }
        groups.push(RawDofValues {
            dofs: dofs.into_iter().zip(values).collect(),
            loc: v.start_loc(),
            nodes,
            quasi_static,
        });
    }
    if groups.is_empty() {
        return Err(no_groups(c, &format!("{value} / DOFs / nodes")));
    }
    Ok(groups)
}

fn parse_fixed_disp(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    if mentat::blank_header_follows(c) {
        let groups = mentat::fixed_disp(c)?;
        if !groups.is_empty() {
            c.deck.fixed_disp.extend(groups);
            return Ok(());
        }
    }
    let groups = dof_value_groups(c, "prescribed values (mm or rad)", false)?;
    c.deck.fixed_disp.extend(groups);
    Ok(())
}

fn parse_initial_vel(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    let args = c.args();
    let quasi_static = match args {
        [] => false,
        [a, b] if a.text.eq_ignore_ascii_case("QUASI") && b.text.eq_ignore_ascii_case("STATIC") => {
            true
        }
        _ => {
            return Err(c.err(
                c.arg_loc(0),
                format!("unexpected `{}` after INITIAL VEL", args[0].text),
                "INITIAL VEL alone or INITIAL VEL, QUASI STATIC",
            ))
        }
    };
    let groups = dof_value_groups(c, "initial velocities (mm/s or rad/s)", quasi_static)?;
    c.deck.initial_velocities.extend(groups);
    Ok(())
}

fn parse_point_load(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const VALUES: &str = "the load in DOF order: Fx, Fy, Fz (N), Mx, My, Mz (N mm)";
    // Mentat's history layout: `point load 0` (an integer after the keyword).
    if *c.section == History
        && c.line.fixed.is_some()
        && c.args()
            .first()
            .is_some_and(|f| lexer::parse_uint(&f.text).is_ok())
    {
        return mentat::history_point_load(c);
    }
    if *c.section == Model && c.args().is_empty() && mentat::blank_header_follows(c) {
        return mentat::point_load_blocks(c);
    }
    let args = c.args();
    let table = match args.len() {
        0 => None,
        2 if args[0].text.eq_ignore_ascii_case("TABLE") => Some((
            c.name(c.line, c.kw_fields + 1, "the table name")?,
            c.arg_loc(1),
        )),
        _ => {
            return Err(c.err(
                c.arg_loc(0),
                format!("unexpected `{}` after POINT LOAD", args[0].text),
                "POINT LOAD alone or POINT LOAD, TABLE, name",
            ))
        }
    };
    let mut loads = Vec::new();
    while c.more_data() {
        let v = c.data_line(VALUES)?;
        c.field_count(v, 1, 6, VALUES)?;
        let mut dofs = Vec::new();
        for i in 0..v.fields.len() {
            let x = c.real(v, i, VALUES)?;
            if x != 0.0 {
                dofs.push((i as u8 + 1, x));
            }
        }
        let nodes = c.list("the list of nodes")?;
        if nodes.items.is_empty() {
            return Err(c.err(nodes.loc, "the node list is empty", "the list of nodes"));
        }
        loads.push(RawPointLoad {
            dofs,
            loc: v.start_loc(),
            nodes,
            table: table.clone(),
        });
    }
    if loads.is_empty() {
        return Err(no_groups(c, "load values / nodes"));
    }
    if *c.section == History {
        c.case().point_loads.extend(loads);
    } else {
        c.deck.point_loads.extend(loads);
    }
    Ok(())
}

fn parse_table(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const POINT: &str = "time (s), factor";
    if *c.section == Parameters {
        return mentat::parse_not_needed(c);
    }
    if c.args().len() != 1 {
        let loc = c.arg_loc(c.args().len().min(1));
        return Err(c.err(loc, "TABLE needs exactly one name", "TABLE, name"));
    }
    let name = c.name(c.line, c.kw_fields, "the table name")?;
    if reserved_in(c.table, &name) {
        return Err(c.err(
            c.arg_loc(0),
            format!("`{name}` cannot name a table: it is a keyword or a list word"),
            "another name",
        ));
    }
    let mut points: Vec<(f64, f64)> = Vec::new();
    let mentat = c.cur.peek_significant().is_some_and(|l| {
        l.fixed.is_some()
            && l.fields.len() >= 3
            && l.fields.iter().all(|f| lexer::parse_uint(&f.text).is_ok())
    });
    let expected = if mentat {
        Some(mentat::table_header(c)?)
    } else {
        None
    };
    while c.more_data() && expected.is_none_or(|n| points.len() < n) {
        let l = c.data_line(POINT)?;
        c.field_count(l, 2, 2, POINT)?;
        let t = c.real(l, 0, "the time (s)")?;
        let f = c.real(l, 1, "the factor")?;
        if let Some(&(prev, _)) = points.last() {
            if t <= prev {
                return Err(c.err(
                    l.loc_of(0),
                    format!("time {t:?} does not increase on the previous point's {prev:?}"),
                    "strictly increasing times",
                ));
            }
        }
        points.push((t, f));
    }
    if points.is_empty() {
        return Err(no_groups(c, POINT));
    }
    if let Some(n) = expected.filter(|&n| n != points.len()) {
        return Err(c.err(
            c.loc(),
            format!("the table has {} points, its header says {n}", points.len()),
            "as many `time, factor` lines as the header's last field",
        ));
    }
    c.deck.tables.push(RawTable {
        name,
        loc: c.loc(),
        points,
    });
    Ok(())
}

fn quantity(word: &str) -> Option<Quantity> {
    match word.to_ascii_uppercase().as_str() {
        "DISP" | "DISPLACEMENT" => Some(Quantity::Displacement),
        "VEL" | "VELOCITY" => Some(Quantity::Velocity),
        "ACCEL" | "ACCELERATION" => Some(Quantity::Acceleration),
        _ => None,
    }
}

fn parse_history_output(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const QUANTITIES: &str = "quantities: DISP, VEL and/or ACCEL";
    c.no_args()?;
    let mut done = 0;
    while c.more_data() {
        let e = c.data_line("every k-th step")?;
        c.field_count(e, 1, 1, "every k-th step (k >= 1)")?;
        let every = c.count(e, 0, 1, "every k-th step")?;
        let q = c.data_line(QUANTITIES)?;
        c.field_count(q, 1, 3, QUANTITIES)?;
        let mut quantities = Vec::new();
        for (i, f) in q.fields.iter().enumerate() {
            let Some(x) = quantity(&f.text) else {
                return Err(c.err(
                    q.loc_of(i),
                    format!("`{}` is not a quantity", f.text),
                    QUANTITIES,
                ));
            };
            if quantities.contains(&x) {
                return Err(c.err(
                    q.loc_of(i),
                    format!("`{}` is listed twice", f.text),
                    QUANTITIES,
                ));
            }
            quantities.push(x);
        }
        let d = c.data_line("the DOF numbers (1..6)")?;
        let dofs = c.dofs(d, 0)?;
        let nodes = c.list("the list of nodes")?;
        if nodes.items.is_empty() {
            return Err(c.err(nodes.loc, "the node list is empty", "the list of nodes"));
        }
        c.deck.outputs.push(RawOutput {
            every,
            loc: e.start_loc(),
            quantities,
            dofs,
            nodes,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, "k / quantities / DOFs / nodes"));
    }
    Ok(())
}

/// Tables: unique names.
pub(crate) fn build_tables(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    b.unique(
        "TABLE",
        "table name",
        raw.tables.iter().map(|t| (t.name.as_str(), t.loc)),
    )?;
    parts.tables = raw
        .tables
        .iter()
        .map(|t| Table {
            name: t.name.clone(),
            points: t.points.clone(),
        })
        .collect();
    Ok(())
}

/// Prescribed DOFs (each once); returns where each DOF was prescribed.
pub(crate) fn build_supports(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<HashMap<(u32, u8), Loc>, DeckError> {
    let mut prescribed: HashMap<(u32, u8), Loc> = HashMap::new();
    parts.fixed_disp = dof_groups(b, &raw.fixed_disp, "FIXED DISP", &mut prescribed)?
        .into_iter()
        .map(|(dofs, nodes)| FixedDisp { dofs, nodes })
        .collect();
    Ok(prescribed)
}

/// Loads (Mentat's named loads are returned, for the load cases whose `LOADCASE`
/// lists them, else added to the model's loads), initial velocities and outputs.
pub(crate) fn build<'r>(
    b: &Builder<'_>,
    raw: &'r RawDeck,
    parts: &mut ModelParts,
) -> Result<Vec<(&'r str, Vec<PointLoad>)>, DeckError> {
    parts.point_loads = raw
        .point_loads
        .iter()
        .map(|p| point_load(b, p, raw))
        .collect::<Result<Vec<_>, _>>()?;
    let mut named_loads: Vec<(&str, Vec<PointLoad>)> = Vec::new();
    for (name, p) in &raw.named_loads {
        named_loads.push((name, vec![point_load(b, p, raw)?]));
    }
    let xyz_of = |id: u32| {
        let i = parts.nodes.binary_search_by_key(&id, |n| n.id).ok()?;
        Some(parts.nodes[i].xyz)
    };
    for d in &raw.dist_loads {
        let els = b.resolve(&d.elements, SetKind::Element, "DIST LOADS")?;
        let els = b.non_empty(els, &d.elements, "DIST LOADS", "elements")?;
        let mut loads = Vec::new();
        for id in els {
            let e = &parts.elements[parts.elements.partition_point(|e| e.id < id)];
            let [a, z] = e.nodes;
            let (Some(xa), Some(xb)) = (xyz_of(a), xyz_of(z)) else {
                continue;
            };
            loads.extend(consistent_beam_loads(d.q, a, xa, z, xb));
        }
        named_loads.push((&d.name, loads));
    }
    if let Some(names) = &raw.model_loadcase {
        mentat::active_names_exist(b, names, raw)?;
    }
    let per_case = raw.load_cases.iter().any(|c| c.active.is_some());
    if !per_case {
        for (_, loads) in &named_loads {
            parts.point_loads.extend(loads.iter().cloned());
        }
    }
    let mut given: HashMap<(u32, u8), Loc> = HashMap::new();
    parts.initial_velocities = dof_groups(b, &raw.initial_velocities, "INITIAL VEL", &mut given)?
        .into_iter()
        .zip(&raw.initial_velocities)
        .map(|((dofs, nodes), g)| InitialVelocity {
            dofs,
            nodes,
            quasi_static: g.quasi_static,
        })
        .collect();
    for o in &raw.outputs {
        let nodes = b.resolve(&o.nodes, SetKind::Node, "HISTORY OUTPUT")?;
        let nodes = b.non_empty(nodes, &o.nodes, "HISTORY OUTPUT", "nodes")?;
        parts.outputs.push(OutputRequest {
            nodes,
            dofs: o.dofs.clone(),
            quantities: o.quantities.clone(),
            every: o.every,
        });
    }
    Ok(named_loads)
}

pub(crate) fn point_load(
    b: &Builder<'_>,
    p: &RawPointLoad,
    raw: &RawDeck,
) -> Result<PointLoad, DeckError> {
    let nodes = b.resolve(&p.nodes, SetKind::Node, "POINT LOAD")?;
    let nodes = b.non_empty(nodes, &p.nodes, "POINT LOAD", "nodes")?;
    if let Some((name, loc)) = &p.table {
        let found = raw.tables.iter().find(|t| &t.name == name);
        match found {
            Some(t) if t.loc.line < loc.line => {}
            Some(t) => {
                return Err(b.err(
                    *loc,
                    "POINT LOAD",
                    format!("the table `{name}` is defined later (line {})", t.loc.line),
                    "tables defined before they are used",
                ))
            }
            None => {
                return Err(b.err(
                    *loc,
                    "POINT LOAD",
                    format!("no table named `{name}`"),
                    "a TABLE defined in the model definition",
                ))
            }
        }
    }
    Ok(PointLoad {
        dofs: p.dofs.clone(),
        nodes,
        table: p.table.as_ref().map(|t| t.0.clone()),
    })
}

/// The consistent nodal loads of a uniform load per unit length `q` (global, N/mm)
/// on a straight beam from node `a` at `xa` to node `z` at `xb`: qL/2 at each node and
/// the moments +-(L^2/12) e x q (e the unit vector from a to z), the cubic Hermite
/// interpolation's work-equivalent loads (exact nodal displacements for
/// Euler-Bernoulli beams).
fn consistent_beam_loads(
    q: [f64; 3],
    a: u32,
    xa: [f64; 3],
    z: u32,
    xb: [f64; 3],
) -> Vec<PointLoad> {
    let d = sub(xb, xa);
    let l = norm(d);
    let e = [d[0] / l, d[1] / l, d[2] / l];
    let m = cross(e, q);
    let mut out = Vec::new();
    for (node, sign) in [(a, 1.0), (z, -1.0)] {
        let mut dofs = Vec::new();
        for (k, qk) in q.iter().enumerate() {
            if *qk != 0.0 {
                dofs.push((k as u8 + 1, qk * l / 2.0));
            }
        }
        for (k, mk) in m.iter().enumerate() {
            let mk = sign * mk * l * l / 12.0;
            if mk != 0.0 {
                dofs.push((k as u8 + 4, mk));
            }
        }
        if !dofs.is_empty() {
            out.push(PointLoad {
                dofs,
                nodes: vec![node],
                table: None,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::cards::testing::*;

    #[test]
    fn loads_tables_velocities_outputs() {
        let m = with_model(
            "TABLE, ramp\n0, 0\n1, 1\nPOINT LOAD, TABLE, ramp\n0, 0, -10, 0, 5\n3\nINITIAL VEL\n-100, 2\n3, 1\n3\nHISTORY OUTPUT\n10\nDISP, ACCEL\n3, 1\n2 TO 3\n",
        )
        .unwrap();
        assert_eq!(m.point_loads[0].dofs, [(3, -10.0), (5, 5.0)]);
        assert_eq!(m.point_loads[0].table.as_deref(), Some("ramp"));
        assert_eq!(m.tables[0].points, [(0.0, 0.0), (1.0, 1.0)]);
        assert_eq!(m.initial_velocities[0].dofs, [(3, -100.0), (1, 2.0)]);
        assert!(!m.initial_velocities[0].quasi_static);
        let qs =
            with_model("INITIAL VEL, quasi static\n-100\n3\n3\nINITIAL VEL\n2\n1\n3\n").unwrap();
        assert!(qs.initial_velocities[0].quasi_static);
        assert!(!qs.initial_velocities[1].quasi_static);
        let e = err_with_model("INITIAL VEL, QUASI\n-100\n3\n3\n");
        assert!(e.contains("INITIAL VEL, QUASI STATIC"), "{e}");
        assert_eq!(m.outputs[0].every, 10);
        assert_eq!(
            m.outputs[0].quantities,
            [Quantity::Displacement, Quantity::Acceleration]
        );
        assert_eq!(m.outputs[0].dofs, [3, 1]);
        assert_eq!(m.outputs[0].nodes, [2, 3]);
        let e = err_with_model("TABLE, t\n1, 0\n1, 1\n");
        assert!(e.contains("does not increase"), "{e}");
        let e = err_with_model("POINT LOAD, TABLE, nope\n1\n3\n");
        assert!(e.contains("no table named `nope`"), "{e}");
        let e = err_with_model("FIXED DISP\n0, 0\n1, 7\n2\n");
        assert!(e.contains("DOF 7 does not exist"), "{e}");
    }
}
