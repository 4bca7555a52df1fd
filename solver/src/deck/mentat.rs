//! The cards and layouts of decks that MSC Mentat writes (Marc's fixed and extended
//! fixed format, see [`super::lexer`]), beside coil's own: each function here is the
//! parse function of one entry of [`super::keywords::KEYWORDS`] or the Mentat branch
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

use super::error::{DeckError, Loc};
use super::keywords::DeckSection;
use super::lexer::{self, ListItem};
use super::raw::{
    RawBeamSection, RawDistLoad, RawDofValues, RawGeometry, RawList, RawMaterial, RawPointLoad,
};
use super::reader::CardCtx;

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

/// A Mentat ISOTROPIC material: `id`+`elastic` ... name, the values, an optional line
/// of table ids (all 0), and the element list (blank = every element).
pub(crate) fn isotropic_material(c: &mut CardCtx<'_, '_>) -> Result<RawMaterial, DeckError> {
    let l = c.data_line("the material line: id, type, ..., name")?;
    let id = c.id(l, 0, "the material id")?;
    let kind = &l.fields[1].text;
    if !kind.eq_ignore_ascii_case("elastic") {
        return Err(c.err(
            l.loc_of(1),
            format!("material type `{kind}` is not supported"),
            "elastic (coil models linear elastic isotropic materials only)",
        ));
    }
    let last = l.fields.len() - 1;
    let name = if lexer::is_name(&l.fields[last].text) && last > 1 {
        l.fields[last].text.clone()
    } else {
        id.to_string()
    };
    let [e, nu, rho] = super::keywords::material_values(c)?;
    // Table ids: a line of integers only (a list line has `to` or a name).
    if let Some(t) = c.cur.peek_significant() {
        let ints = t.fixed.is_some()
            && t.fields.len() > 1
            && t.fields
                .iter()
                .all(|f| !f.text.is_empty() && lexer::parse_uint(&f.text).is_ok());
        if ints {
            let t = c.data_line("the table ids")?;
            c.zeros_from(t, 0, "Marc tables on material data")?;
        }
    }
    let mut elements = c.list("the list of elements (blank = every element)")?;
    if elements.items.is_empty() {
        elements.items.push((ListItem::All, elements.loc));
    }
    Ok(RawMaterial {
        id,
        name,
        loc: l.start_loc(),
        youngs_modulus: e,
        poisson: nu,
        density: rho,
        elements,
    })
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
