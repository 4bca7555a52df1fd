//! A reduced (matrix) element: `DMIG`, direct matrix input, symmetric stiffness, mass
//! and (optionally) damping matrices over an ordered list of (node, DOF) pairs, added to
//! the global K, M and C before constraints, in every analysis (static, modal, transient,
//! the unilateral solves of `TENSION LINK` and `MOVING CONTACT` included), exactly as a
//! beam element's matrices are.
//!
//! # Why this name and layout
//! Nastran and the solvers that read its decks (OptiStruct among them) call such input
//! `DMIG`, *Direct Matrix Input at Grid points*: a named matrix given by columns of
//! (grid, component, value) triples, symmetric for stiffness, mass and damping
//! (`IFO = 6`), added "to the structural matrices before constraints are applied", with
//! modal coordinates as scalar points. Reduced (superelement) matrices travel between
//! programs of the MSC family under that name, so a user meeting it in a coil deck knows
//! what it is. The layout is coil's, in the comma-separated lines of a Marc deck: one
//! group per element, the DOF list once, then each matrix row by row (full rows, so
//! that a wrong entry shows as an asymmetry instead of being silently mirrored).
//!
//! # Formulation and units
//! For the element's DOFs `d_1..d_n` (global DOF indices of `(node, dof)`) its matrices
//! `K_e, M_e, C_e` (`n x n`) are scattered into `K, M, C` at rows and columns `d_i`; a
//! prescribed DOF among them loads the free ones through `-K_e g` like any element. Units
//! are the deck's: N/mm (N, N mm for rotations), t (t mm^2), N s/mm. Rayleigh `DAMPING`
//! does not act on a matrix element: its damping is its own `C_e`.
//!
//! A Craig-Bampton model (`crate::reduce`) is such an element: its boundary rows are the
//! physical DOFs it connects to (`q_b` *is* their displacement), its modal amplitudes
//! `eta` are extra nodes with one free DOF each (the other five held by `FIXED DISP`).
//!
//! Checks (file and line of the group): counts and numbers here; the model's checks
//! ([`crate::model::check`]) refuse an unknown node, a DOF out of 1..6 or listed twice,
//! a non-symmetric matrix, and a mass or damping that is not positive semi-definite.

use crate::deck::card::{CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::DeckError;
use crate::deck::raw::RawDeck;
use crate::model::{MatrixElement, ModelParts};
use DeckSection::Model;

/// The `DMIG` card.
pub(crate) const DMIG: Keyword = Keyword {
    name: "DMIG",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A matrix element (direct matrix input, Nastran's name): symmetric \
              stiffness, mass and optionally damping matrices over listed (node, DOF) \
              pairs, added to the global K, M, C in every analysis, as a reduced \
              (Craig-Bampton) model is.",
    layout: &[
        ("DMIG", ""),
        (
            "id, n, c[, name]",
            "per element: a positive id, n >= 1 DOFs, c = 1 if a damping matrix \
             follows (0 or blank if not), a name (the id if omitted)",
        ),
        (
            "node, dof",
            "n lines: the DOF of each row and column, in order",
        ),
        (
            "k_i1, ..., k_in",
            "n lines: the stiffness, row by row (N/mm; N, N mm with rotations)",
        ),
        (
            "m_i1, ..., m_in",
            "n lines: the mass, row by row (t; t mm^2)",
        ),
        (
            "[c_i1, ..., c_in]",
            "only if c = 1, n lines: the damping, row by row (N s/mm)",
        ),
    ],
    notes: "Groups repeat until the next card. Each (node, DOF) appears once per \
            element; the matrices must be symmetric (to 1e-9 of their largest entry) \
            and the mass and damping positive semi-definite. A reduced model's modal \
            coordinates are extra nodes with one free DOF each (the others in FIXED \
            DISP). Rayleigh DAMPING does not act on the element.",
    example: "DMIG\n1, 2, 0, link\n2, 3\n3, 3\n200.0, -200.0\n-200.0, 200.0\n\
              1.0e-6, 0.0\n0.0, 1.0e-6",
    parse: parse_dmig,
};

fn parse_dmig(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const HEADER: &str = "id, n (DOFs), c (1: a damping matrix follows)[, name]";
    const PAIR: &str = "node, dof (1..6)";
    c.no_args()?;
    c.each_line(HEADER, (2, 4), |c, l| {
        let id = c.id(l, 0, "the element id")?;
        let n = c.count(l, 1, 1, "the number of DOFs n")? as usize;
        let flag = c.uint_or(l, 2, 0, "1 or 0")?;
        if flag > 1 {
            return Err(c.err(
                l.loc_of(2),
                format!("flag {flag}"),
                "1 (a damping matrix follows) or 0",
            ));
        }
        let name = match l.fields.get(3) {
            Some(f) if !f.text.is_empty() => c.name(l, 3, "the element name")?,
            _ => id.to_string(),
        };
        let mut dofs = Vec::with_capacity(n.min(1 << 16));
        for _ in 0..n {
            let d = c.data_line(PAIR)?;
            c.field_count(d, 2, 2, PAIR)?;
            dofs.push((c.id(d, 0, "the node id")?, c.dof(d, 1)?));
        }
        let stiffness = rows(c, n, "stiffness")?;
        let mass = rows(c, n, "mass")?;
        let damping = if flag == 1 {
            rows(c, n, "damping")?
        } else {
            Vec::new()
        };
        c.deck.matrix_elements.push((
            MatrixElement {
                name,
                dofs,
                stiffness,
                mass,
                damping,
            },
            l.start_loc(),
        ));
        Ok(())
    })
}

/// `n` lines of `n` reals: one matrix, row-major.
fn rows(c: &mut CardCtx<'_, '_>, n: usize, what: &str) -> Result<Vec<f64>, DeckError> {
    let layout = format!("a row of the {what} matrix: {n} values");
    let mut a = Vec::with_capacity((n * n).min(1 << 20));
    for _ in 0..n {
        let l = c.data_line(&layout)?;
        c.field_count(l, n, n, &layout)?;
        for j in 0..n {
            a.push(c.real(l, j, &layout)?);
        }
    }
    Ok(a)
}

/// The matrix elements, in deck order (every check is the model's).
pub(crate) fn build(raw: &RawDeck, parts: &mut ModelParts) {
    parts
        .matrix_elements
        .extend(raw.matrix_elements.iter().map(|(m, _)| m.clone()));
}

#[cfg(test)]
mod tests {
    use crate::deck::cards::testing::*;

    /// A 2x2 element on the u_z of nodes 2 and 3.
    fn dmig(k: &str, m: &str) -> String {
        format!("DMIG\n7, 2, 0, head\n2, 3\n3, 3\n{k}{m}")
    }

    #[test]
    fn reads_a_matrix_element() {
        let m = with_model(&dmig("2, -2\n-2, 2\n", "1e-3, 0\n0, 1e-3\n")).unwrap();
        let e = &m.matrix_elements()[0];
        assert_eq!(e.name, "head");
        assert_eq!(e.dofs, [(2, 3), (3, 3)]);
        assert_eq!(e.stiffness, [2.0, -2.0, -2.0, 2.0]);
        assert!(e.damping.is_empty());
        let with_c = "DMIG\n1, 1, 1\n3, 3\n5\n1e-3\n0.5\n";
        let m = with_model(with_c).unwrap();
        assert_eq!(m.matrix_elements()[0].damping, [0.5]);
        assert_eq!(m.matrix_elements()[0].name, "1");
    }

    #[test]
    fn refuses_bad_matrices_by_line() {
        let e = err_with_model(&dmig("2, -2\n-2.1, 2\n", "1e-3, 0\n0, 1e-3\n"));
        assert!(e.contains("symmetric") && e.contains("DMIG"), "{e}");
        assert!(e.contains("t.dat:30:"), "the group header line: {e}");
        let e = err_with_model(&dmig("2, -2\n-2, 2\n", "1e-3, 2e-3\n2e-3, 1e-3\n"));
        assert!(e.contains("positive semi-definite mass"), "{e}");
        let e = err_with_model(&dmig("2, -2\n-2, 2\n", "1e-3, 0\n"));
        assert!(e.contains("row of the mass matrix"), "{e}");
        let e = err_with_model(&dmig("2, -2, 0\n-2, 2\n", "1e-3, 0\n0, 1e-3\n"));
        assert!(e.contains("one too many"), "{e}");
        let e = err_with_model("DMIG\n1, 1, 0\n44, 3\n1\n1\n");
        assert!(e.contains("node 44 does not exist"), "{e}");
        let e = err_with_model("DMIG\n1, 1, 0\n3, 7\n1\n1\n");
        assert!(e.contains("DOF 7 does not exist"), "{e}");
        let e = err_with_model("DMIG\n1, 2, 0\n3, 3\n3, 3\n1, 0\n0, 1\n1, 0\n0, 1\n");
        assert!(e.contains("listed twice"), "{e}");
        let e = err_with_model("DMIG\n1, 1, 2\n3, 3\n1\n1\n");
        assert!(e.contains("flag 2"), "{e}");
        let e = err_with_model("DMIG\n1, 1, 1\n3, 3\n1\n1\n-1\n");
        assert!(e.contains("positive semi-definite damping"), "{e}");
    }
}
