//! What a catenary adds to a deck of beams: `BEAM TENSION`, a given axial force N (N)
//! in wire elements, which the analyses see as the elements' geometric stiffness;
//! `TENSION LINK`, a dropper (N/mm, mm) that pulls in tension and goes slack in
//! compression; `MOVING CONTACT`, a node (a pantograph's head) pressed on a line of beam
//! nodes by a penalty spring (N/mm) at a point moving at a constant speed (mm/s), the
//! contact free to open. How the analyses run the last two: `crate::analysis::unilateral`.
//!
//! A contact or messenger wire is held straight by weights at its ends: its bending
//! stiffness EI is small and its transverse stiffness comes from the tension. For a
//! beam element of length `L` under the axial force `N` the consistent geometric
//! stiffness of each bending plane (`w_1, theta_1, w_2, theta_2`, `theta = dw/dx`) is
//! ```text
//! K_g = N / (30 L) [36, 3L, -36, 3L; 3L, 4L^2, -3L, -L^2; -36, -3L, 36, -3L; 3L, -L^2, -3L, 4L^2]
//! ```
//! (Przemieniecki 1968, *Theory of Matrix Structural Analysis*, sec. 15.3; the cubic
//! Hermite interpolation of the bending element), so that a wire with `EI -> 0` is the
//! taut string `rho w_tt = N w_xx`, whose waves travel at `c = sqrt(N / rho)`. The force
//! is given, not computed: the model stays linear, the reference line straight, and the
//! sag under gravity is the static solution of `(K_e + K_g) u = f`.
//!
//! Each card is one [`Keyword`] entry followed by its parse function; then the family's
//! build function (raw deck -> model parts, run in order by [`crate::deck::build`]); its
//! tests close the file.

use crate::deck::card::{CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::DeckError;
use crate::deck::raw::{RawBeamTension, RawDeck, RawMovingContact, SetKind};
use crate::deck::resolve::Builder;
use crate::model::{BeamTension, ModelParts, MovingContact, TensionLink};
use DeckSection::Model;

/// The `BEAM TENSION` card.
pub(crate) const BEAM_TENSION: Keyword = Keyword {
    name: "BEAM TENSION",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A given axial force N in beam elements (a wire tensioned by weights at its \
              ends): its geometric stiffness N/(30 L) [36, 3L, -36, 3L; ...] in both \
              bending planes is added to each element's stiffness in every analysis.",
    layout: &[
        ("BEAM TENSION", ""),
        ("force", "the axial force N (N), positive in tension"),
        ("list", "the tensioned elements"),
    ],
    notes: "Groups of these two lines repeat until the next card; an element may be in \
            one group only. The force is held constant (the model stays linear, about a \
            straight reference line): a taut string's waves travel at sqrt(N / rho A). \
            A compressive force (N < 0) softens the elements; the stiffness factor fails \
            at buckling.",
    example: "BEAM TENSION\n2.0e4\nwire",
    parse: parse_beam_tension,
};

/// The `TENSION LINK` card.
pub(crate) const TENSION_LINK: Keyword = Keyword {
    name: "TENSION LINK",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A tension-only link between two nodes along one translation (a catenary's \
              dropper): with the elongation e = u_b - u_a - slack it pulls the nodes \
              together with k max(e, 0), and exerts nothing while slack (e < 0).",
    layout: &[
        ("TENSION LINK", ""),
        (
            "node a, node b, dof, k, slack",
            "one line per link: node b lies on the +dof side of node a (a dropper: a on \
             the contact wire, b on the messenger); dof 1..3, k > 0 (N/mm), slack (mm; \
             negative: the link is pretensioned by -k slack in the reference \
             configuration)",
        ),
    ],
    notes: "Lines repeat until the next card. The taut link's stiffness k is part of K \
            in every analysis and its force at the reference, -k slack, a constant load; \
            STATIC cases and direct transients correct for slack links exactly \
            (docs/catenary.md). Modal analyses see every link taut.",
    example: "TENSION LINK\n11, 211, 3, 100.0, -3.2",
    parse: parse_tension_link,
};

/// The `MOVING CONTACT` card.
pub(crate) const MOVING_CONTACT: Keyword = Keyword {
    name: "MOVING CONTACT",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A unilateral penalty contact of a node (a pantograph's head) on a straight \
              line of beam nodes, at a point moving at constant speed: the penetration p \
              of the head through the line along dof gives the force k max(p, 0); the \
              contact opens when p <= 0.",
    layout: &[
        ("MOVING CONTACT", ""),
        (
            "head, dof, k, speed, start",
            "dof 1..3, k > 0 (N/mm), speed (mm/s), start: the point at t = 0, from the \
             line's first node (mm)",
        ),
        (
            "list",
            "the line's nodes: one wire, straight along a global axis other than dof, \
             each node joined to the next by an element",
        ),
    ],
    notes: "Groups repeat until the next card. The line is checked when the deck is \
            read: its nodes collinear (off-axis spread at most 1e-9 of the length), the \
            axis not dof (a contact along the wire has no penetration), no two nodes at \
            one point, each node joined to the next along the axis by an element (a list \
            naming two wires fails the first or the last test). The line's deflection at the point is the \
            cubic Hermite interpolation of its nodes' translation dof and rotation, on \
            the segment between the two line nodes around it (nodes ordered by their \
            coordinate along the line); off the line's ends the contact is open. \
            p = (x_head + u_head) - (x_line + w_line) along dof, reference coordinates \
            included. STATIC cases place the point at start; direct transients \
            (NEWMARK only) move it, the force found exactly at each step's end \
            (docs/catenary.md). Modal analyses ignore the contact.",
    example: "MOVING CONTACT\n9001, 3, 50.0, 83333.3, 10000.0\ncontact_wire",
    parse: parse_moving_contact,
};

fn parse_tension_link(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "node a, node b, dof (1..3), k (N/mm), slack (mm)";
    c.no_args()?;
    c.each_line(LAYOUT, (5, 5), |c, l| {
        let a = c.id(l, 0, "node a")?;
        let b = c.id(l, 1, "node b")?;
        let dof = c.dof(l, 2)?;
        let k = c.real(l, 3, "the stiffness k (N/mm)")?;
        let slack = c.real(l, 4, "the slack (mm)")?;
        c.deck.tension_links.push((
            TensionLink {
                nodes: [a, b],
                dof,
                stiffness: k,
                slack,
            },
            l.start_loc(),
        ));
        Ok(())
    })
}

fn parse_moving_contact(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "head, dof (1..3), k (N/mm), speed (mm/s), start (mm) / the line's nodes";
    c.no_args()?;
    c.each_line(LAYOUT, (5, 5), |c, l| {
        let head = c.id(l, 0, "the head node")?;
        let dof = c.dof(l, 1)?;
        let stiffness = c.real(l, 2, "the penalty stiffness k (N/mm)")?;
        let speed = c.real(l, 3, "the speed (mm/s)")?;
        let start = c.real(l, 4, "the start (mm)")?;
        let line = c.list("the line's nodes")?;
        c.deck.moving_contacts.push(RawMovingContact {
            head,
            dof,
            stiffness,
            speed,
            start,
            loc: l.start_loc(),
            line,
        });
        Ok(())
    })
}

fn parse_beam_tension(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "force (N) / the list of tensioned elements";
    c.no_args()?;
    c.each_line(LAYOUT, (1, 1), |c, l| {
        let force = c.real(l, 0, "the axial force (N)")?;
        let elements = c.list("the list of tensioned elements")?;
        c.deck.beam_tensions.push(RawBeamTension {
            force,
            loc: l.start_loc(),
            elements,
        });
        Ok(())
    })
}

/// Beam tensions, links and contacts: lists resolved (non-empty); the model checks the
/// rest (each element in one tension group, nodes, values).
pub(crate) fn build(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    for t in &raw.beam_tensions {
        let elements = b.resolve(&t.elements, SetKind::Element, "BEAM TENSION")?;
        let elements = b.non_empty(elements, &t.elements, "BEAM TENSION", "elements")?;
        parts.beam_tensions.push(BeamTension {
            force: t.force,
            elements,
        });
    }
    parts
        .tension_links
        .extend(raw.tension_links.iter().map(|(l, _)| *l));
    for m in &raw.moving_contacts {
        let line = b.resolve(&m.line, SetKind::Node, "MOVING CONTACT")?;
        let line = b.non_empty(line, &m.line, "MOVING CONTACT", "line nodes")?;
        parts.moving_contacts.push(MovingContact {
            head: m.head,
            dof: m.dof,
            stiffness: m.stiffness,
            speed: m.speed,
            start: m.start,
            line,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::deck::cards::testing::*;
    use crate::deck::write;

    #[test]
    fn beam_tension_reads_checks_and_writes_back() {
        let m = with_model("BEAM TENSION\n2.0e4\nwire\n").unwrap();
        assert_eq!(m.tension_of(1), 2.0e4);
        assert_eq!(m.tension_of(2), 2.0e4);
        let m = with_model("BEAM TENSION\n2.0e4\n1\n-5\n2\n").unwrap();
        assert_eq!(m.beam_tensions().len(), 2);
        assert_eq!(m.tension_of(2), -5.0);
        let m = with_model("BEAM TENSION\n1.5e3\n1\n").unwrap();
        assert_eq!(m.tension_of(1), 1.5e3);
        assert_eq!(m.tension_of(2), 0.0);
        let back = read_str(&write(&m), "back.dat").unwrap();
        assert_eq!(back, m);
        let e = err_with_model("BEAM TENSION\n1.0\nwire\n2.0\n2\n");
        assert!(
            e.contains("already has a tension") && e.contains("BEAM TENSION"),
            "{e}"
        );
        let e = err_with_model("BEAM TENSION\n1.0\n7\n");
        assert!(e.contains('7'), "{e}");
        let e = err_with_model("BEAM TENSION\n1.0, 2.0\nwire\n");
        assert!(e.contains("force (N)"), "{e}");
        let e = err_with_model("BEAM TENSION\n");
        assert!(e.contains("no data lines"), "{e}");
    }

    #[test]
    fn links_and_contacts_read_check_and_write_back() {
        let m = with_model(
            "TENSION LINK\n2, 3, 3, 100.0, -2.5\nMOVING CONTACT\n1, 3, 50.0, 1.0e4, 10.0\n2 TO 3\n",
        )
        .unwrap();
        let l = m.tension_links()[0];
        assert_eq!(
            (l.nodes, l.dof, l.stiffness, l.slack),
            ([2, 3], 3, 100.0, -2.5)
        );
        let c = &m.moving_contacts()[0];
        assert_eq!(
            (c.head, c.dof, c.stiffness, c.speed, c.start),
            (1, 3, 50.0, 1.0e4, 10.0)
        );
        assert_eq!(c.line, [2, 3]);
        let back = read_str(&write(&m), "back.dat").unwrap();
        assert_eq!(back, m);
        let e = err_with_model("TENSION LINK\n2, 2, 3, 100.0, 0\n");
        assert!(
            e.contains("two different nodes") && e.contains("TENSION LINK"),
            "{e}"
        );
        let e = err_with_model("TENSION LINK\n2, 3, 5, 100.0, 0\n");
        assert!(e.contains("translation"), "{e}");
        let e = err_with_model("TENSION LINK\n2, 3, 3, 0.0, 0\n");
        assert!(e.contains("stiffness > 0"), "{e}");
        let e = err_with_model("MOVING CONTACT\n2, 3, 50.0, 1.0, 0.0\n2 TO 3\n");
        assert!(e.contains("not including the head"), "{e}");
        let e = err_with_model("MOVING CONTACT\n1, 3, 50.0, 1.0\n2 TO 3\n");
        assert!(e.contains("start (mm)"), "{e}");
    }

    /// A contact along its line's own axis, a line that is not one wire and a second
    /// link on one node pair are refused at the card's line (the model's check).
    #[test]
    fn contact_lines_and_duplicate_links_are_refused_where_written() {
        // The wire runs along x (DOF 1): pressing along it.
        let e = err_with_model("MOVING CONTACT\n1, 1, 50.0, 1.0, 0.0\n2 TO 3\n");
        assert!(
            e.contains("t.dat:") && e.contains("MOVING CONTACT") && e.contains("own direction"),
            "{e}"
        );
        // Nodes 1 and 3 of the wire, not joined to each other.
        let e = err_with_model("MOVING CONTACT\n2, 3, 50.0, 1.0, 0.0\n1, 3\n");
        assert!(e.contains("no element joins nodes 1 and 3"), "{e}");
        let e = err_with_model("TENSION LINK\n2, 3, 3, 100.0, 0\n3, 2, 3, 50.0, 1\n");
        assert!(
            e.contains("tension link 1 already links nodes 2 and 3 along DOF 3")
                && e.contains("TENSION LINK"),
            "{e}"
        );
        // Another DOF of the same pair is another link.
        with_model("TENSION LINK\n2, 3, 3, 100.0, 0\n2, 3, 2, 50.0, 1\n").unwrap();
    }
}
