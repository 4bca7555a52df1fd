//! The cards and layouts of decks that MSC Mentat writes (Marc's fixed and extended
//! fixed format, see [`crate::deck::lexer`]), beside coil's own: each function here is the
//! parse function of one entry of [`super::KEYWORDS`] or the Mentat branch
//! of one (ISOTROPIC, GEOMETRY, FIXED DISP, POINT LOAD).
//!
//! Three kinds of cards:
//! - cards that change nothing coil computes (`PROCESSOR`, `OPTIMIZE`, `POST`, ...):
//!   read (their data lines skipped) and listed once as "read and not needed";
//! - cards whose physics coil does not model (`LARGE STRAIN`, `PLASTICITY`, the user
//!   subroutines `FORCDT`, ...): an error naming the line and what coil supports;
//! - cards that carry the model (`BEAM SECT`, `DIST LOADS`, `LOADCASE` and the
//!   table-driven layouts of loads and supports).
//!
//! Layouts not shown in public decks are inferred from the corpus and marked so in
//! docs/deck.md. Units are the deck's (mm, N, t, s).

use crate::deck::card::{CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::{DeckError, Loc};
use crate::deck::lexer::{self};
use crate::deck::raw::{
    RawBeamSection, RawDeck, RawDistLoad, RawDofValues, RawGeometry, RawList, RawPointLoad,
};
use crate::deck::resolve::Builder;
use DeckSection::{History, Model, Parameters};

/// The `EXTENDED` card.
pub(crate) const EXTENDED: Keyword = Keyword {
    name: "EXTENDED",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's extended fixed format: from the next line on, a line without a comma is cut in columns of 10 (integers) and 20 (reals, words).",
    layout: &[("EXTENDED", "")],
    notes: "The reader switches format when it splits the deck into lines (see Fixed format above).",
    example: "EXTENDED",
    parse: parse_not_needed_line,
};

/// The `ALLOC` card.
pub(crate) const ALLOC: Keyword = Keyword {
    name: "ALLOC",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's memory allocation.",
    layout: &[("ALLOC, n", "")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "ALLOC, 25",
    parse: parse_not_needed,
};

/// The `VERSION` card.
pub(crate) const VERSION: Keyword = Keyword {
    name: "VERSION",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "The version of Marc's input format; 13 and later give each GEOMETRY block an id and a name line.",
    layout: &[("VERSION, n[, ...]", "")],
    notes: "Read; coil also recognises the GEOMETRY layout by its lines.",
    example: "VERSION, 11",
    parse: parse_version,
};

/// The `PROCESSOR` card.
pub(crate) const PROCESSOR: Keyword = Keyword {
    name: "PROCESSOR",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's processor and parallel options.",
    layout: &[("PROCESSOR, flags ...", "")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "PROCESSOR, 1, 1, 1, 0",
    parse: parse_not_needed,
};

/// The `ALL POINTS` card.
pub(crate) const ALL_POINTS: Keyword = Keyword {
    name: "ALL POINTS",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's output at all integration points.",
    layout: &[("ALL POINTS", "")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "ALL POINTS",
    parse: parse_not_needed_line,
};

/// The `NO ECHO` card.
pub(crate) const NO_ECHO: Keyword = Keyword {
    name: "NO ECHO",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's echo of the input in its output file.",
    layout: &[("NO ECHO, flags ...", "")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "NO ECHO, 1, 2, 3",
    parse: parse_not_needed,
};

/// The `SETNAME` card.
pub(crate) const SETNAME: Keyword = Keyword {
    name: "SETNAME",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's allocation of set names.",
    layout: &[("SETNAME, n", "")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "SETNAME, 9",
    parse: parse_not_needed,
};

/// The `SOLVER` card.
pub(crate) const SOLVER: Keyword = Keyword {
    name: "SOLVER",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's linear solver choice (coil chooses its own).",
    layout: &[("SOLVER", ""), ("type, flags ...", "integers")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "SOLVER\n8, 0, 0",
    parse: parse_not_needed,
};

/// The `OPTIMIZE` card.
pub(crate) const OPTIMIZE: Keyword = Keyword {
    name: "OPTIMIZE",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's bandwidth optimiser (coil orders its own unknowns).",
    layout: &[("OPTIMIZE, n[, ...]", "")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "OPTIMIZE, 11",
    parse: parse_not_needed,
};

/// The `NO PRINT` card.
pub(crate) const NO_PRINT: Keyword = Keyword {
    name: "NO PRINT",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's printed output.",
    layout: &[("NO PRINT", "")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "NO PRINT",
    parse: parse_not_needed_line,
};

/// The `POST` card.
pub(crate) const POST: Keyword = Keyword {
    name: "POST",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's post file contents (coil writes its own result files).",
    layout: &[
        ("POST", ""),
        ("flags ...", "integers; more lines may follow"),
    ],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "POST\n0, 16, 17, 0",
    parse: parse_not_needed,
};

/// The `PARAMETERS` card.
pub(crate) const PARAMETERS: Keyword = Keyword {
    name: "PARAMETERS",
    sections: &[Model, History],
    origin: Origin::Marc,
    meaning: "Marc's numerical constants (tolerances, physical constants).",
    layout: &[("PARAMETERS", ""), ("values ...", "lines of reals")],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "PARAMETERS\n1.0, 1.0e9, 100.0",
    parse: parse_not_needed,
};

/// The `CONTROL` card.
pub(crate) const CONTROL: Keyword = Keyword {
    name: "CONTROL",
    sections: &[Model, History],
    origin: Origin::Marc,
    meaning: "Marc's convergence control of nonlinear increments; a linear solve needs none.",
    layout: &[
        ("CONTROL[, qualifier]", ""),
        ("flags ...", "integers"),
        ("tolerances ...", "reals"),
    ],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "CONTROL\n99999, 10, 0\n0.1, 0.0",
    parse: parse_not_needed,
};

/// The `MAT COLOR` card.
pub(crate) const MAT_COLOR: Keyword = Keyword {
    name: "MAT COLOR",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Mentat's colours of materials.",
    layout: &[
        ("MAT COLOR", ""),
        ("", "a header line (often blank)"),
        ("id, ...", "integers"),
    ],
    notes: "Read and not needed: coil lists it once in the run's log.",
    example: "MAT COLOR\n\n1, 1, 230, 0, 0",
    parse: parse_mat_color,
};

/// The `LOADCASE` card.
pub(crate) const LOADCASE: Keyword = Keyword {
    name: "LOADCASE",
    sections: &[Model, History],
    origin: Origin::Marc,
    meaning: "Mentat's list of the named loads and supports active in the model's own load case (model definition) or in the load case it appears in (history).",
    layout: &[("LOADCASE, name", ""), ("n", "number of active blocks"), ("name", "one line per block (FIXED DISP, POINT LOAD, DIST LOADS)")],
    notes: "A named POINT LOAD or DIST LOADS acts in a load case whose LOADCASE lists it (in every load case if no history LOADCASE is given). coil's supports are the same in every load case: a named FIXED DISP missing from a history LOADCASE is an error. The model definition's LOADCASE (Marc's increment 0) is read and checked for names.",
    example: "LOADCASE, lc1\n1\nclamp",
    parse: parse_loadcase,
};

/// The `BEAM SECT` card.
pub(crate) const BEAM_SECT: Keyword = Keyword {
    name: "BEAM SECT",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Named beam cross-sections, numbered from 1 in their order, referred to by a GEOMETRY whose area is 0.",
    layout: &[("BEAM SECT", ""), ("name", "the section name"), ("0, type, dimensions", "type -2: a solid circle, dimension 1 its radius r (mm)"), ("n, ...", "integration points (not needed)"), ("LAST", "after the last section")],
    notes: "coil reads the solid circle (type -2, radius r: A = pi r^2, I = pi r^4 / 4, J = pi r^4 / 2, the polar moment, exact for a circle; shear coefficient 6(1+nu)/(7+6nu)). Other types are an error naming the type. The meaning of -2 and of its dimension (radius) is inferred from public Mentat decks, not from Marc's manual.",
    example: "BEAM SECT\nwire\n0, -2.0, 1.5\n5, 0, 0, 0\nLAST",
    parse: parse_beam_sect,
};

/// The `DIST LOADS` card.
pub(crate) const DIST_LOADS: Keyword = Keyword {
    name: "DIST LOADS",
    sections: &[Parameters, Model],
    origin: Origin::Marc,
    meaning: "As a parameter, Marc's allocation of distributed loads (not needed). In the model definition, Mentat's named blocks of a uniform load per unit length on beams, applied as the consistent nodal forces and moments of each element (qL/2 at each node, moments +-(L^2/12) e x q).",
    layout: &[("DIST LOADS", ""), ("", "a header line (blank)"), ("flags..., name", "integers then the block name; field 2 = 1 (FORCEM) is an error"), ("qx, qy, qz", "the load per unit length, global components (N/mm)"), ("0, 0, 0", "table ids, 0"), ("0, type", "load type 110 (a global load vector)"), ("1", "list kind 1: elements"), ("list", "the beams")],
    notes: "Only type 110 with three components is read (the layout of the corpus's beam deck, inferred, not from Marc's manual); every other type is an error naming it.",
    example: "DIST LOADS, 0, 0, 10",
    parse: parse_dist_loads,
};

/// The `LARGE STRAIN` card.
pub(crate) const LARGE_STRAIN: Keyword = Keyword {
    name: "LARGE STRAIN",
    sections: &[Parameters],
    origin: Origin::Unsupported,
    meaning: "Marc's large-strain (finite deformation) analysis.",
    layout: &[("LARGE STRAIN, ...", "")],
    notes: "coil solves small displacements and strains (linear analyses).",
    example: "LARGE STRAIN",
    parse: parse_unsupported,
};

/// The `LARGE DISP` card.
pub(crate) const LARGE_DISP: Keyword = Keyword {
    name: "LARGE DISP",
    sections: &[Parameters],
    origin: Origin::Unsupported,
    meaning: "Marc's large-displacement analysis.",
    layout: &[("LARGE DISP", "")],
    notes: "coil solves small displacements (linear analyses).",
    example: "LARGE DISP",
    parse: parse_unsupported,
};

/// The `UPDATE` card.
pub(crate) const UPDATE: Keyword = Keyword {
    name: "UPDATE",
    sections: &[Parameters],
    origin: Origin::Unsupported,
    meaning: "Marc's updated Lagrange formulation.",
    layout: &[("UPDATE", "")],
    notes: "coil solves small displacements (linear analyses).",
    example: "UPDATE",
    parse: parse_unsupported,
};

/// The `FINITE` card.
pub(crate) const FINITE: Keyword = Keyword {
    name: "FINITE",
    sections: &[Parameters],
    origin: Origin::Unsupported,
    meaning: "Marc's finite strain.",
    layout: &[("FINITE", "")],
    notes: "coil solves small strains (linear analyses).",
    example: "FINITE",
    parse: parse_unsupported,
};

/// The `FOLLOW FOR` card.
pub(crate) const FOLLOW_FOR: Keyword = Keyword {
    name: "FOLLOW FOR",
    sections: &[Parameters],
    origin: Origin::Unsupported,
    meaning: "Marc's follower forces.",
    layout: &[("FOLLOW FOR", "")],
    notes: "coil's loads keep their direction (linear analyses).",
    example: "FOLLOW FOR",
    parse: parse_unsupported,
};

/// The `PLASTICITY` card.
pub(crate) const PLASTICITY: Keyword = Keyword {
    name: "PLASTICITY",
    sections: &[Parameters],
    origin: Origin::Unsupported,
    meaning: "Marc's plasticity procedure.",
    layout: &[("PLASTICITY, ...", "")],
    notes: "coil's materials are linear elastic.",
    example: "PLASTICITY",
    parse: parse_unsupported,
};

/// The `WORK HARD` card.
pub(crate) const WORK_HARD: Keyword = Keyword {
    name: "WORK HARD",
    sections: &[Model],
    origin: Origin::Unsupported,
    meaning: "Marc's work-hardening data of plastic materials.",
    layout: &[("WORK HARD, ...", "")],
    notes: "coil's materials are linear elastic.",
    example: "WORK HARD",
    parse: parse_unsupported,
};

/// The `FORCDT` card.
pub(crate) const FORCDT: Keyword = Keyword {
    name: "FORCDT",
    sections: &[Model],
    origin: Origin::Unsupported,
    meaning: "Marc's user subroutine FORCDT (nodal loads and displacements computed by Fortran code).",
    layout: &[("FORCDT, n", ""), ("list", "nodes")],
    notes: "the user subroutine FORCDT is Fortran code coil cannot run; give the load as POINT LOAD values.",
    example: "FORCDT, 1",
    parse: parse_unsupported,
};

/// The `UMOTION` card.
pub(crate) const UMOTION: Keyword = Keyword {
    name: "UMOTION",
    sections: &[Model],
    origin: Origin::Unsupported,
    meaning: "Marc's user subroutine UMOTION (rigid-surface motion).",
    layout: &[("UMOTION, n", "")],
    notes: "the user subroutine UMOTION is Fortran code coil cannot run.",
    example: "UMOTION, 0",
    parse: parse_unsupported,
};

/// The `USDATA` card.
pub(crate) const USDATA: Keyword = Keyword {
    name: "USDATA",
    sections: &[Parameters, Model],
    origin: Origin::Unsupported,
    meaning: "Marc's user data for user subroutines.",
    layout: &[("USDATA, n", "")],
    notes: "user subroutines are Fortran code coil cannot run.",
    example: "USDATA, 1",
    parse: parse_unsupported,
};

/// Records a card that was read and changes nothing coil computes.
fn not_needed(c: &mut CardCtx<'_, '_>) {
    let name = c.kw.name.to_string();
    if !c.deck.not_needed.iter().any(|(n, _)| *n == name) {
        let loc = c.loc();
        c.deck.not_needed.push((name, loc));
    }
}

/// Skips the card's data lines: every following line that starts with a number.
fn skip_data(c: &mut CardCtx<'_, '_>) {
    while c.more_data() {
        c.cur.advance();
    }
}

/// A card read and not needed: its fields on the keyword line and any data lines that
/// follow (lines that start with a number) are skipped.
pub(crate) fn parse_not_needed(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    not_needed(c);
    skip_data(c);
    Ok(())
}

/// A card read and not needed that has no data lines (its next line may be a name).
pub(crate) fn parse_not_needed_line(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    not_needed(c);
    Ok(())
}

/// `MAT COLOR`: a header line (often blank) then lines of integers.
pub(crate) fn parse_mat_color(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    not_needed(c);
    c.data_line("the MAT COLOR header line")?;
    skip_data(c);
    Ok(())
}

/// A card whose physics coil does not model: an error naming it, with the reason in
/// the keyword's notes.
pub(crate) fn parse_unsupported(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    Err(c.err(
        c.loc(),
        format!("{} is not supported: {}", c.kw.name, c.kw.notes),
        "a linear elastic model of beams 52/98 (see docs/deck.md); remove the card or run the deck in Marc",
    ))
}

/// `VERSION`: the version of Marc's input format; 13 and later change the GEOMETRY
/// layout (an id/name block before the values).
pub(crate) fn parse_version(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    let v = c.uint(c.line, c.kw_fields, "the input version, an integer")?;
    c.deck.version = Some(v);
    not_needed(c);
    Ok(())
}

/// `LOADCASE, name` then the number of active boundary conditions and their names,
/// one per line. In the model definition it names those of the model's own
/// (increment 0) load case; in the history those of the load case it appears in.
pub(crate) fn parse_loadcase(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    let count_line = c.data_line("the number of active loads and supports")?;
    let n = c.uint_or(count_line, 0, 0, "the number of active loads and supports")?;
    let mut names = Vec::new();
    for k in 0..n {
        let l = c.data_line(&format!("the name of active load or support {}", k + 1))?;
        let name = l.raw.trim().to_string();
        if !lexer::is_name(&name) {
            return Err(c.err(
                l.start_loc(),
                format!("`{name}` is not a name"),
                "the name of a FIXED DISP, POINT LOAD or DIST LOADS block",
            ));
        }
        names.push((name, l.start_loc()));
    }
    if *c.section == DeckSection::History {
        c.case().active = Some(names);
    } else {
        c.deck.model_loadcase = Some(names);
    }
    Ok(())
}

/// The header line of a table-driven block: integers then the block's name
/// (`1 0 0 0 1 0Support`). Field 2 set means a user subroutine supplies the values.
fn named_header(c: &mut CardCtx<'_, '_>, subroutine: &str) -> Result<(String, Loc), DeckError> {
    let h = c.data_line("the block's header: integers, then its name")?;
    let last = h.fields.len().saturating_sub(1);
    let name = c.name(h, last, "the block's name")?;
    for i in 0..last {
        c.uint_or(h, i, 0, "the block's header flags: integers")?;
    }
    if c.uint_or(h, 1, 0, "the user-subroutine flag")? != 0 {
        return Err(c.err(
            h.loc_of(1),
            format!(
                "the {} `{name}` takes its values from the user subroutine {subroutine}, which coil cannot run",
                c.kw.name
            ),
            format!("values in the deck (field 2 of this line 0); coil supports no Fortran user subroutines ({subroutine})"),
        ));
    }
    Ok((name, h.start_loc()))
}

/// Reals of a values line, `n` of them, and the integer table ids that follow (all
/// 0: coil's table-driven loads are scaled by a coil TABLE, not Marc's).
fn values_and_tables(c: &mut CardCtx<'_, '_>, what: &str) -> Result<Vec<f64>, DeckError> {
    let v = c.data_line(what)?;
    let mut values = Vec::new();
    for i in 0..v.fields.len() {
        values.push(c.real(v, i, what)?);
    }
    let t = c.data_line("the table ids, one per value")?;
    c.field_count(t, values.len(), values.len(), "one table id per value")?;
    for i in 0..t.fields.len() {
        if c.uint_or(t, i, 0, "a table id")? != 0 {
            return Err(c.err(
                t.loc_of(i),
                "a Marc table scales this value in time",
                "table id 0 (coil reads time tables in its own TABLE card only)",
            ));
        }
    }
    Ok(values)
}

/// The list part of a table-driven block: the kind of list (1 elements, 2 nodes) and
/// one line per list.
fn block_list(c: &mut CardCtx<'_, '_>, kind: u64) -> Result<RawList, DeckError> {
    let k = c.data_line("the kind of list: 1 elements, 2 nodes")?;
    let got = c.uint_or(k, 0, 0, "the kind of list")?;
    if got != kind {
        return Err(c.err(
            k.loc_of(0),
            format!("list kind {got}"),
            if kind == 2 {
                "2 (a node list)"
            } else {
                "1 (an element list)"
            },
        ));
    }
    c.list("the list")
}

/// True if the next data line is a table-driven block header (integers, then a
/// name touching the last of them).
fn block_follows(c: &mut CardCtx<'_, '_>) -> bool {
    match c.cur.peek_significant() {
        Some(l) => {
            l.fixed.is_some()
                && l.fields.len() >= 2
                && l.fields.last().is_some_and(|f| lexer::is_name(&f.text))
                && lexer::looks_numeric(&l.fields[0].text)
        }
        None => false,
    }
}

/// Mentat's `FIXED DISP`: a header line (blank), then either table-driven named
/// blocks (header/name, values, table ids, DOFs, list kind, list) or the older
/// layout (values, DOFs, list) that coil's own card has.
pub(crate) fn fixed_disp(c: &mut CardCtx<'_, '_>) -> Result<Vec<RawDofValues>, DeckError> {
    c.data_line("the FIXED DISP header line")?;
    let mut groups = Vec::new();
    while c.more_data() {
        if !block_follows(c) {
            return Ok(groups);
        }
        let (name, loc) = named_header(c, "FORCDT")?;
        let values = values_and_tables(c, "the prescribed values (mm or rad)")?;
        let d = c.data_line("one DOF per value")?;
        c.field_count(d, values.len(), values.len(), "one DOF per value")?;
        let dofs = c.dofs(d, 0)?;
        let nodes = block_list(c, 2)?;
        c.deck.named.push((name, loc, true));
        groups.push(RawDofValues {
            dofs: dofs.into_iter().zip(values).collect(),
            loc,
            nodes,
            quasi_static: false,
        });
    }
    Ok(groups)
}

/// True if the card starts with Mentat's blank header line.
pub(crate) fn blank_header_follows(c: &mut CardCtx<'_, '_>) -> bool {
    let lines = c.cur.lines;
    let mut pos = c.cur.pos;
    while let Some(l) = lines.get(pos) {
        match l.kind {
            lexer::LineKind::Comment => pos += 1,
            lexer::LineKind::Blank => return true,
            lexer::LineKind::Text => return false,
        }
    }
    false
}

/// Mentat's table-driven `POINT LOAD` (model definition): a blank header line, then
/// named blocks (header/name, the load in DOF order, table ids, list kind, list).
pub(crate) fn point_load_blocks(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.data_line("the POINT LOAD header line")?;
    while block_follows(c) {
        let (name, loc) = named_header(c, "FORCDT")?;
        let values = values_and_tables(
            c,
            "the load in DOF order: Fx, Fy, Fz (N), Mx, My, Mz (N mm)",
        )?;
        let nodes = block_list(c, 2)?;
        let dofs = nonzero(&values);
        c.deck.named_loads.push((
            name.clone(),
            RawPointLoad {
                dofs,
                loc,
                nodes,
                table: None,
            },
        ));
        c.deck.named.push((name, loc, false));
    }
    Ok(())
}

fn nonzero(values: &[f64]) -> Vec<(u8, f64)> {
    values
        .iter()
        .enumerate()
        .filter(|(_, v)| **v != 0.0)
        .map(|(i, v)| (i as u8 + 1, *v))
        .collect()
}

/// The history `POINT LOAD` that Mentat writes without tables: `point load 0` on the
/// keyword line, a line of integers (field 2 set: the user subroutine FORCDT), the
/// load in DOF order and the node list.
pub(crate) fn history_point_load(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    for j in 0..c.args().len() {
        c.uint_or(c.line, c.kw_fields + j, 0, "integers")?;
    }
    let h = c.data_line("the POINT LOAD flags: integers")?;
    for i in 0..h.fields.len() {
        c.uint_or(h, i, 0, "integers")?;
    }
    if c.uint_or(h, 1, 0, "the user-subroutine flag")? != 0 {
        return Err(c.err(
            h.loc_of(1),
            "the point load takes its values from the user subroutine FORCDT, which coil cannot run",
            "values in the deck (field 2 of this line 0); coil supports no Fortran user subroutines (FORCDT)",
        ));
    }
    let mut loads = Vec::new();
    while c.more_data() {
        const VALUES: &str = "the load in DOF order: Fx, Fy, Fz (N), Mx, My, Mz (N mm)";
        let v = c.data_line(VALUES)?;
        c.field_count(v, 1, 6, VALUES)?;
        let mut values = Vec::new();
        for i in 0..v.fields.len() {
            values.push(c.real(v, i, VALUES)?);
        }
        let nodes = c.list("the list of nodes")?;
        loads.push(RawPointLoad {
            dofs: nonzero(&values),
            loc: v.start_loc(),
            nodes,
            table: None,
        });
    }
    // A load of zero adds nothing (Mentat writes one when FORCDT supplies the load).
    loads.retain(|l| !l.dofs.is_empty());
    c.case().point_loads.extend(loads);
    Ok(())
}

/// `DIST LOADS`: as a parameter (Marc's allocation; not needed) or, in the model
/// definition, Mentat's table-driven named blocks of a uniform load per unit length
/// on beams: header/name, the load vector (global x, y, z; N/mm), table ids, the
/// load type (110, a global load vector), list kind 1 and the element list.
pub(crate) fn parse_dist_loads(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    if *c.section == DeckSection::Parameters {
        return parse_not_needed(c);
    }
    c.data_line("the DIST LOADS header line")?;
    while block_follows(c) {
        let (name, loc) = named_header(c, "FORCEM")?;
        let values = values_and_tables(c, "the load per unit length qx, qy, qz (N/mm)")?;
        if values.len() != 3 {
            return Err(c.err(
                loc,
                format!("{} load components", values.len()),
                "3: the global components of the load per unit length (N/mm)",
            ));
        }
        let t = c.data_line("the load type line")?;
        let kind = c.uint_or(t, 1, 0, "the load type")?;
        if kind != 110 {
            return Err(c.err(
                t.loc_of(1),
                format!("distributed load type {kind} is not supported"),
                "110: a uniform load per unit length given by its global components",
            ));
        }
        let elements = block_list(c, 1)?;
        c.deck.dist_loads.push(RawDistLoad {
            name: name.clone(),
            loc,
            q: [values[0], values[1], values[2]],
            elements,
        });
        c.deck.named.push((name, loc, false));
    }
    Ok(())
}

/// `BEAM SECT` (parameter section): named sections, each a name line, a line
/// `0, type, dimensions...` (type -2: a solid circle of radius r), a line of
/// integers and reals coil does not need (integration points), until `LAST`.
pub(crate) fn parse_beam_sect(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    loop {
        let Some(l) = c.cur.peek_significant() else {
            return Err(c.err(c.cur.eof_loc(), "the file ends inside BEAM SECT", "LAST"));
        };
        if l.raw.trim().eq_ignore_ascii_case("LAST") {
            c.cur.advance();
            return Ok(());
        }
        let name_line = c.data_line("a section name, or LAST")?;
        let name = c.name(name_line, 0, "the section name")?;
        let s = c.data_line("0, section type, dimensions (mm)")?;
        let kind = c.real(s, 1, "the section type")?;
        let id = c.deck.beam_sections.len() as u32 + 1;
        let section = if kind == -2.0 {
            let r = c.real(s, 2, "the radius (mm)")?;
            let r = c.positive(r, s.loc_of(2), "the radius")?;
            crate::model::Section::SolidCircle { diameter: 2.0 * r }
        } else {
            return Err(c.err(
                s.loc_of(1),
                format!("section type {kind} is not supported"),
                "-2 (a solid circle: radius)",
            ));
        };
        // The integration-point line, then any further data lines.
        c.data_line("the section's integration-point line")?;
        skip_data(c);
        c.deck.beam_sections.push(RawBeamSection {
            id,
            name,
            loc: name_line.start_loc(),
            section,
        });
    }
}

/// A Mentat GEOMETRY block of a beam: (version 13+: an integer line and a name
/// line, then) the values `A, I1, I2, vx, vy, vz, ...` with A = 0 meaning the
/// BEAM SECT numbered by the second value, and the element list.
pub(crate) fn geometry_block(c: &mut CardCtx<'_, '_>) -> Result<RawGeometry, DeckError> {
    const VALUES: &str = "A (0 = a BEAM SECT), Ixx or section number, Iyy, vx, vy, vz";
    let mut id = None;
    let mut name = String::new();
    let first = c.data_line(VALUES)?;
    let s = if first
        .fields
        .iter()
        .all(|f| f.text.is_empty() || lexer::parse_uint(&f.text).is_ok())
    {
        id = Some(c.id(first, 0, "the geometry id")?);
        let n = c.data_line("the geometry name")?;
        name = c.name(n, 0, "the geometry name")?;
        c.data_line(VALUES)?
    } else {
        first
    };
    let area = c.real(s, 0, "the area A (mm^2)")?;
    let v: Vec<f64> = (1..6)
        .map(|i| c.real(s, i, VALUES))
        .collect::<Result<_, _>>()?;
    let orientation = [v[2], v[3], v[4]];
    if orientation.iter().all(|&x| x == 0.0) {
        return Err(c.err(
            s.loc_of(3),
            "the orientation vector (fields 4-6) is zero",
            "a non-zero vector",
        ));
    }
    let (section, has_kappa) = if area == 0.0 {
        let k = v[0];
        let found = c
            .deck
            .beam_sections
            .iter()
            .find(|b| f64::from(b.id) == k)
            .map(|b| b.section.clone());
        match found {
            Some(sec) => (sec, true),
            None => {
                return Err(c.err(
                    s.loc_of(1),
                    format!("no BEAM SECT number {k}"),
                    "the number of a section of the BEAM SECT parameter (1 for its first)",
                ))
            }
        }
    } else {
        let area = c.positive(area, s.loc_of(0), "the area A")?;
        let i1 = c.positive(v[0], s.loc_of(1), "Ixx")?;
        let i2 = c.positive(v[1], s.loc_of(2), "Iyy")?;
        // Marc's elastic beam takes J = Ixx + Iyy when no section is given.
        (
            crate::model::Section::General {
                area,
                iyy: i1,
                izz: i2,
                torsion: i1 + i2,
                shear_coefficient: 0.0,
            },
            false,
        )
    };
    let elements = c.list("the list of elements")?;
    Ok(RawGeometry {
        id,
        name,
        loc: s.start_loc(),
        section,
        has_shear_coefficient: has_kappa,
        section_loc: s.start_loc(),
        orientation,
        orientation_loc: s.loc_of(3),
        elements,
    })
}

/// The two integer lines of Mentat's model-definition `TABLE`: the first ends with
/// the number of points, the second starts with the independent variable's type.
/// Only time (type 1, inferred from public decks) scales coil's loads. Returns the
/// number of points.
pub(crate) fn table_header(c: &mut CardCtx<'_, '_>) -> Result<usize, DeckError> {
    let h = c.data_line("the table's header: integers, the last the number of points")?;
    for i in 0..h.fields.len() {
        c.uint_or(h, i, 0, "integers")?;
    }
    let last = h.fields.len() - 1;
    let n = c.count(h, last, 1, "the number of points")?;
    let v = c.data_line("the independent variable's line: integers")?;
    for i in 0..v.fields.len() {
        c.uint_or(v, i, 0, "integers")?;
    }
    let kind = c.uint_or(v, 0, 0, "the independent variable's type")?;
    if kind != 1 {
        return Err(c.err(
            v.loc_of(0),
            format!("independent variable type {kind}"),
            "1 (time): coil's tables scale loads in time",
        ));
    }
    Ok(n as usize)
}

/// Fails unless every name a `LOADCASE` lists names a Mentat block.
pub(crate) fn active_names_exist(
    b: &Builder<'_>,
    names: &[(String, Loc)],
    raw: &RawDeck,
) -> Result<(), DeckError> {
    for (name, loc) in names {
        if !raw.named.iter().any(|(n, _, _)| n == name) {
            return Err(b.err(
                *loc,
                "LOADCASE",
                format!("no load or support named `{name}`"),
                "the name of a FIXED DISP, POINT LOAD or DIST LOADS block",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::deck::cards::testing::*;

    /// Mentat's cards in extended fixed format, each with what it must do.
    #[test]
    fn mentat_cards_read_skip_or_refuse() {
        let ext = |params: &str, model: &str, history: &str| {
            format!("TITLE, t\nEXTENDED\n{params}ELEMENTS                    98\nEND\n{}{model}END OPTION\n{history}", MESH.replace("GEOMETRY\n1\n3.0\n0, 0, 1\nwire\n", "GEOMETRY\n1\n1, g\n3.0\n0, 0, 1\nwire\n"))
        };
        let static_case = "AUTO LOAD\n         1         0        10\nTIME STEP\n1.0\nCONTINUE\n";
        // Read and not needed, listed once each.
        let text = ext(
            "PROCESSOR                    1         1\nTABLE                        0         0         2\nALL POINTS\n",
            "SOLVER\n         8         0\nOPTIMIZE                    11\nNO PRINT\nPOST\n         0        16\nPARAMETERS\n 1.000000000000000+0 1.000000000000000+9\n",
            &format!("CONTROL\n     99999        10\n 1.000000000000000-1\nPARAMETERS\n 1.0\n{static_case}"),
        );
        let (m, notes) = crate::deck::read_str_noting(&text, "t.dat").unwrap();
        assert_eq!(m.load_cases.len(), 1);
        let cards: Vec<&str> = notes.iter().map(|n| n.card.as_str()).collect();
        assert_eq!(
            cards,
            [
                "EXTENDED",
                "PROCESSOR",
                "TABLE",
                "ALL POINTS",
                "SOLVER",
                "OPTIMIZE",
                "NO PRINT",
                "POST",
                "PARAMETERS",
                "CONTROL"
            ]
        );
        // Unsupported physics: the line and what coil supports.
        for card in ["LARGE STRA                   4", "PLASTICITY", "FOLLOW FOR"] {
            let e = read_str(&ext(&format!("{card}\n"), "", static_case), "t.dat").unwrap_err();
            assert!(
                e.to_string().contains("t.dat:3:1:") && e.to_string().contains("is not supported"),
                "{e}"
            );
        }
        let e = read_str(
            &ext("", "FORCDT                       1\n1\n", static_case),
            "t.dat",
        )
        .unwrap_err();
        assert!(e.to_string().contains("user subroutine FORCDT"), "{e}");
        // A history LOADCASE must keep the supports active.
        let named = "FIXED DISP\n\n         1         0         0         0         1         0clamp2\n 0.0\n         0\n         3\n         2\n3\n";
        let e = read_str(
            &ext(
                "",
                named,
                &format!("LOADCASE            lc\n         0\n{static_case}"),
            ),
            "t.dat",
        )
        .unwrap_err();
        assert!(e.to_string().contains("the support `clamp2`"), "{e}");
        let m = read_str(
            &ext(
                "",
                named,
                &format!("LOADCASE            lc\n         1\nclamp2\n{static_case}"),
            ),
            "t.dat",
        )
        .unwrap();
        assert_eq!(m.fixed_disp.len(), 2);
        // Mentat's model-definition TABLE (the parameter TABLE is above).
        let table = format!(
            "TABLE               ramp\n{}\n{}\n{:>20}{:>20}\n{:>20}{:>20}\n",
            "         1         1         0         0         2",
            "         1         2",
            "0.0",
            "0.0",
            "1.0",
            "2.0+0"
        );
        let m = read_str(&ext("", &table, static_case), "t.dat").unwrap();
        assert_eq!(m.tables[0].points, [(0.0, 0.0), (1.0, 2.0)]);
        let bad = table.replace("         1         2\n", "         3         2\n");
        let e = read_str(&ext("", &bad, static_case), "t.dat").unwrap_err();
        assert!(e.to_string().contains("independent variable type 3"), "{e}");
    }
}
