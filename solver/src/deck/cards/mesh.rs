//! The mesh: `CONNECTIVITY` (elements), `COORDINATES` (nodes, mm) and `DEFINE` (named
//! node and element sets).
//!
//! Each card is one [`Keyword`] entry (its name, sections, meaning, layout, example
//! and parse function) followed by its parse function; then the family's build function
//! (raw deck -> model parts, run in order by [`crate::deck::build`]); its tests close
//! the file.

use crate::deck::card::{
    another, header_count, no_groups, reserved_in, CardCtx, DeckSection, Keyword, Origin,
};
use crate::deck::error::DeckError;
use crate::deck::raw::{RawDeck, RawElement, RawNode, RawSet, SetKind};
use crate::deck::resolve::Builder;
use crate::model::{Element, ElementSet, ModelParts, Node, NodeSet};
use DeckSection::Model;

use super::parameters::element_type;
/// The `CONNECTIVITY` card.
pub(crate) const CONNECTIVITY: Keyword = Keyword {
    name: "CONNECTIVITY",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "The elements: id, type and the two nodes of each beam.",
    layout: &[
        ("CONNECTIVITY", ""),
        (
            "n[, flags ...]",
            "header: n = number of element lines, 0 or blank = element lines until \
             the next card; Marc's further header fields are integers coil does not use",
        ),
        (
            "element, type, node 1, node 2",
            "one line per element; type 52 or 98; local x runs from node 1 to node 2",
        ),
    ],
    notes: "Ids are positive and unique; an element may not join a node to itself or \
            two nodes at the same place. The card may be repeated.",
    example: "CONNECTIVITY\n2\n1, 98, 1, 2\n2, 98, 2, 3",
    parse: parse_connectivity,
};

/// The `COORDINATES` card.
pub(crate) const COORDINATES: Keyword = Keyword {
    name: "COORDINATES",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "The nodes and their global coordinates (mm).",
    layout: &[
        ("COORDINATES", ""),
        (
            "3, n[, 0, 1]",
            "header: 3 coordinates per node; n = number of node lines, 0 or blank = \
             node lines until the next card; Marc's further header fields are \
             integers coil does not use",
        ),
        ("node, x, y, z", "one line per node (mm)"),
    ],
    notes: "Ids are positive and unique. The card may be repeated.",
    example: "COORDINATES\n3, 3, 0, 1\n1, 0.0, 0.0, 0.0\n2, 50.0, 0.0, 0.0\n3, 100.0, 0.0, 0.0",
    parse: parse_coordinates,
};

/// The `DEFINE` card.
pub(crate) const DEFINE: Keyword = Keyword {
    name: "DEFINE",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "A named set of nodes or elements, usable in every later list.",
    layout: &[
        ("DEFINE, NODE or ELEMENT, SET, name", ""),
        (
            "list",
            "ids, `a TO b` and `a TO b BY k` ranges, names of sets defined earlier; \
             a last field C continues the list on the next line",
        ),
    ],
    notes: "A set must be defined before it is used. Names are case-sensitive, may not \
            repeat within nodes or within elements, and may not be a keyword's first \
            word or TO, BY, C. Every id of a range must exist. A blank list line is an \
            empty set.",
    example: "DEFINE, ELEMENT, SET, wire\n1 TO 2",
    parse: parse_define,
};

const ELEMENT_LINE: &str = "element, type (52 or 98), node 1, node 2";

fn parse_connectivity(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let header =
        c.data_line("the header line: number of element lines (0 = until the next card)")?;
    let n = header_count(c, header, 0, "the number of element lines")?;
    let mut done = 0;
    while another(c, n, done) {
        let l = c.data_line(&format!("element line {} of {n}: {ELEMENT_LINE}", done + 1))?;
        c.field_count(l, 4, 4, ELEMENT_LINE)?;
        let id = c.id(l, 0, "the element id")?;
        let kind = element_type(c, l, 1)?;
        let n1 = c.id(l, 2, "node 1")?;
        let n2 = c.id(l, 3, "node 2")?;
        c.deck.elements.push(RawElement {
            id,
            kind,
            type_loc: l.loc_of(1),
            nodes: [(n1, l.loc_of(2)), (n2, l.loc_of(3))],
            loc: l.start_loc(),
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, ELEMENT_LINE));
    }
    Ok(())
}

const NODE_LINE: &str = "node, x, y, z (mm)";

fn parse_coordinates(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let header = c.data_line("the header line: 3, number of node lines")?;
    let dims = c.uint(header, 0, "3 coordinates per node")?;
    if dims != 3 {
        return Err(c.err(
            header.loc_of(0),
            format!("{dims} coordinates per node"),
            "3 (coil models are three-dimensional)",
        ));
    }
    let n = header_count(c, header, 1, "the number of node lines")?;
    let mut done = 0;
    while another(c, n, done) {
        let l = c.data_line(&format!("node line {} of {n}: {NODE_LINE}", done + 1))?;
        c.field_count(l, 4, 4, NODE_LINE)?;
        let id = c.id(l, 0, "the node id")?;
        let xyz = [
            c.real(l, 1, "x (mm)")?,
            c.real(l, 2, "y (mm)")?,
            c.real(l, 3, "z (mm)")?,
        ];
        c.deck.nodes.push(RawNode {
            id,
            xyz,
            loc: l.start_loc(),
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, NODE_LINE));
    }
    Ok(())
}

fn parse_define(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "DEFINE, NODE or ELEMENT, SET, name";
    let args = c.args();
    if args.len() != 3 {
        let loc = if args.len() > 3 {
            c.arg_loc(3)
        } else {
            c.line.end_loc()
        };
        return Err(c.err(loc, format!("{} fields after DEFINE", args.len()), LAYOUT));
    }
    let kind = match args[0].text.to_ascii_uppercase().as_str() {
        "NODE" => SetKind::Node,
        "ELEMENT" => SetKind::Element,
        _ => {
            return Err(c.err(
                c.arg_loc(0),
                format!("`{}` is not a kind of set", args[0].text),
                "NODE or ELEMENT",
            ))
        }
    };
    if !args[1].text.eq_ignore_ascii_case("SET") {
        return Err(c.err(
            c.arg_loc(1),
            format!("`{}` instead of SET", args[1].text),
            LAYOUT,
        ));
    }
    let name = c.name(c.line, c.kw_fields + 2, "the set name")?;
    if reserved_in(c.table, &name) {
        return Err(c.err(
            c.arg_loc(2),
            format!(
                "`{name}` cannot name a set: the reader would take it for a keyword or a list word"
            ),
            "another name",
        ));
    }
    let list = c.list(&format!("the list of {}s", kind.word()))?;
    c.deck.sets.push(RawSet {
        kind,
        name,
        loc: c.loc(),
        list,
    });
    Ok(())
}

/// Nodes and elements, sorted by id, each id once; the SIZING bounds.
pub(crate) fn build_mesh(
    b: &mut Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    let nodes = b.sorted_by_id(&raw.nodes, |n| (n.id, n.loc), "COORDINATES", "node")?;
    let elements = b.sorted_by_id(&raw.elements, |e| (e.id, e.loc), "CONNECTIVITY", "element")?;
    b.node_ids = nodes.iter().map(|n| n.id).collect();
    b.element_ids = elements.iter().map(|e| e.id).collect();
    if let Some((max_elements, max_nodes, loc)) = raw.sizing {
        for (count, max, what) in [
            (elements.len(), max_elements, "elements"),
            (nodes.len(), max_nodes, "nodes"),
        ] {
            if max > 0 && count as u64 > max {
                return Err(b.err(
                    loc,
                    "SIZING",
                    format!("the model has {count} {what}, more than the {max} SIZING allows"),
                    format!("SIZING's number of {what} >= {count}, or 0"),
                ));
            }
        }
    }
    parts.nodes = nodes
        .iter()
        .map(|n| Node {
            id: n.id,
            xyz: n.xyz,
        })
        .collect();
    parts.elements = elements
        .iter()
        .map(|e| Element {
            id: e.id,
            kind: e.kind,
            nodes: [e.nodes[0].0, e.nodes[1].0],
        })
        .collect();
    Ok(())
}

/// Sets, in deck order (a set may use the sets before it).
pub(crate) fn build_sets(
    b: &mut Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    for s in &raw.sets {
        if let Some((_, _, first, _)) = b
            .sets
            .iter()
            .find(|(k, n, _, _)| *k == s.kind && *n == s.name)
        {
            return Err(b.err(
                s.loc,
                "DEFINE",
                format!(
                    "the {} set `{}` is defined twice (first at line {})",
                    s.kind.word(),
                    s.name,
                    first.line
                ),
                "unique set names",
            ));
        }
        let ids = b.resolve(&s.list, s.kind, "DEFINE")?;
        match s.kind {
            SetKind::Node => parts.node_sets.push(NodeSet {
                name: s.name.clone(),
                nodes: ids.clone(),
            }),
            SetKind::Element => parts.element_sets.push(ElementSet {
                name: s.name.clone(),
                elements: ids.clone(),
            }),
        }
        b.sets.push((s.kind, s.name.clone(), s.loc, ids));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::deck::cards::testing::*;

    #[test]
    fn connectivity_and_coordinates() {
        let m = with_model("").unwrap();
        assert_eq!(m.nodes.len(), 3);
        assert_eq!(m.nodes[2].xyz, [100.0, 0.0, 0.0]);
        assert_eq!(m.elements[1].nodes, [2, 3]);
        assert_eq!(m.elements[1].kind, ElementType::Beam98);
        // A header count shorter than the lines that follow: the extra line is data
        // where a keyword belongs.
        let e = read_str(
            &format!(
                "{PARAMS}{}",
                MESH.replace("CONNECTIVITY\n0", "CONNECTIVITY\n1")
            ),
            "t.dat",
        )
        .unwrap_err();
        assert!(
            e.to_string().contains(":12:1: data line `2, 98, 2, 3`"),
            "{e}"
        );
        let e = read_str(
            &format!("{PARAMS}{}", MESH.replace("3, 3\n", "2, 3\n")),
            "t.dat",
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("t.dat:5:1: COORDINATES: 2 coordinates per node"),
            "{e}"
        );
    }

    #[test]
    fn define_sets_resolve_ranges_and_other_sets() {
        let m = with_model("DEFINE, NODE, SET, ends\n1, 3\nDEFINE, NODE, SET, every\nends 2\n")
            .unwrap();
        assert_eq!(m.node_sets[0].nodes, [1, 3]);
        assert_eq!(m.node_sets[1].nodes, [1, 2, 3]);
        assert_eq!(m.element_sets[0].elements, [1, 2]);
        let e = err_with_model("DEFINE, NODE, SET, end\n1\n");
        assert!(e.contains("cannot name a set"), "{e}");
        let e = err_with_model("DEFINE, NODE, SET, a\nlater\nDEFINE, NODE, SET, later\n1\n");
        assert!(e.contains("defined later"), "{e}");
    }
}
