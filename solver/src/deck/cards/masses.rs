//! What hangs on the wire: `DAMPING` (Rayleigh alpha in 1/s, beta in s, per element
//! list and point-mass nodes), `POINT MASS` (t, t mm^2) and `RBE2` (rigid ties).
//!
//! Each card is one [`Keyword`] entry (its name, sections, meaning, layout, example
//! and parse function) followed by its parse function; then the family's build function
//! (raw deck -> model parts, run in order by [`crate::deck::build`]); its tests close
//! the file.

use std::collections::HashMap;

use crate::deck::card::{no_groups, CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::{DeckError, Loc};
use crate::deck::raw::{RawDamping, RawDeck, RawPointMass, RawTie, SetKind};
use crate::deck::resolve::Builder;
use crate::model::{Damping, ModelParts, PointMass, RigidTie};
use DeckSection::Model;

/// The `DAMPING` card.
pub(crate) const DAMPING: Keyword = Keyword {
    name: "DAMPING",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "Rayleigh damping C_e = alpha M_e + beta K_e on elements, and C = alpha M_p \
              on the point masses of listed nodes (none unless listed).",
    layout: &[
        ("DAMPING", ""),
        (
            "alpha, beta[, m]",
            "alpha >= 0 (1/s), beta >= 0 (s); m = 1 if a line of point-mass nodes \
             follows, 0 or blank if not",
        ),
        ("list", "the damped elements (a blank line for none)"),
        ("[list]", "only if m = 1: nodes whose POINT MASS gets alpha"),
    ],
    notes: "Groups of these lines repeat until the next card. A group must damp \
            something; every listed node must carry a POINT MASS.",
    example: "DAMPING\n0.5, 1.0e-4, 1\nwire\n3",
    parse: parse_damping,
};

/// The `POINT MASS` card.
pub(crate) const POINT_MASS: Keyword = Keyword {
    name: "POINT MASS",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A point mass with rotary inertia at a node: the mass on DOFs 1-3, the \
              inertias about the global axes on DOFs 4-6.",
    layout: &[
        ("POINT MASS", ""),
        (
            "node, mass, Ixx, Iyy, Izz",
            "one line per node: mass >= 0 (t), inertias >= 0 (t mm^2)",
        ),
    ],
    notes: "Lines repeat until the next card; one point mass per node.",
    example: "POINT MASS\n3, 1.5e-3, 0.0, 0.0, 0.0",
    parse: parse_point_mass,
};

/// The `RBE2` card.
pub(crate) const RBE2: Keyword = Keyword {
    name: "RBE2",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A rigid tie (Marc's RBE2): the listed DOFs of the tied nodes follow the \
              reference node as a rigid body, u_s = u_r + theta_r x (x_s - x_r), \
              theta_s = theta_r.",
    layout: &[
        ("RBE2", ""),
        (
            "id[, name]",
            "per tie: a positive id and a name (the id if omitted)",
        ),
        (
            "reference, dof[, dof ...]",
            "the reference node and the tied DOFs (1..6)",
        ),
        ("list", "the tied nodes"),
    ],
    notes: "Groups repeat until the next card. The reference may not be tied, a node \
            may be tied by one tie only, a reference may not be tied by another tie, \
            and a tied DOF may not also be prescribed by FIXED DISP.",
    example: "RBE2\n1, top\n4, 1, 2, 3, 4, 5, 6\n3",
    parse: parse_rbe2,
};

fn parse_damping(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "alpha (1/s), beta (s)[, 1 if a line of point-mass nodes follows]";
    c.no_args()?;
    c.each_line(LAYOUT, (2, 3), |c, l| {
        let alpha = c.real(l, 0, "alpha (1/s)")?;
        let alpha = c.non_negative(alpha, l.loc_of(0), "alpha")?;
        let beta = c.real(l, 1, "beta (s)")?;
        let beta = c.non_negative(beta, l.loc_of(1), "beta")?;
        let flag = c.uint_or(l, 2, 0, "1 or 0")?;
        if flag > 1 {
            return Err(c.err(
                l.loc_of(2),
                format!("flag {flag}"),
                "1 (a node list follows) or 0",
            ));
        }
        let elements = c.list("the list of damped elements (a blank line for none)")?;
        let mass_nodes = if flag == 1 {
            Some(c.list("the list of nodes whose point masses are damped")?)
        } else {
            None
        };
        if elements.items.is_empty() && mass_nodes.as_ref().is_none_or(|m| m.items.is_empty()) {
            return Err(c.err(
                l.start_loc(),
                "the damping group lists no element and no node",
                "elements, or point-mass nodes after `alpha, beta, 1`",
            ));
        }
        c.deck.damping.push(RawDamping {
            alpha,
            beta,
            loc: l.start_loc(),
            elements,
            mass_nodes,
        });
        Ok(())
    })
}

fn parse_point_mass(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "node, mass (t), Ixx, Iyy, Izz (t mm^2)";
    c.no_args()?;
    c.each_line(LAYOUT, (5, 5), |c, l| {
        let node = c.id(l, 0, "the node id")?;
        let m = c.real(l, 1, "the mass (t)")?;
        let mass = c.non_negative(m, l.loc_of(1), "the mass")?;
        let mut inertia = [0.0; 3];
        for (k, what) in ["Ixx", "Iyy", "Izz"].iter().enumerate() {
            let x = c.real(l, 2 + k, what)?;
            inertia[k] = c.non_negative(x, l.loc_of(2 + k), what)?;
        }
        c.deck.point_masses.push(RawPointMass {
            node,
            node_loc: l.loc_of(0),
            mass,
            inertia,
        });
        Ok(())
    })
}

fn parse_rbe2(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const DOF_LINE: &str = "reference node, tied DOFs (1..6)";
    c.no_args()?;
    let mut done = 0;
    while c.more_data() {
        let l = c.data_line("id, name")?;
        c.field_count(l, 1, 2, "id, name")?;
        let id = c.id(l, 0, "the tie id")?;
        let name = match l.fields.get(1) {
            Some(f) if !f.text.is_empty() => c.name(l, 1, "the tie name")?,
            _ => id.to_string(),
        };
        let d = c.data_line(DOF_LINE)?;
        c.field_count(d, 2, 7, DOF_LINE)?;
        let reference = c.id(d, 0, "the reference node")?;
        let mut dofs = c.dofs(d, 1)?;
        dofs.sort_unstable();
        let tied = c.list("the list of tied nodes")?;
        if tied.items.is_empty() {
            return Err(c.err(
                tied.loc,
                "the tie has no tied nodes",
                "the list of tied nodes",
            ));
        }
        c.deck.rigid_ties.push(RawTie {
            id,
            name,
            loc: l.start_loc(),
            reference,
            reference_loc: d.loc_of(0),
            dofs,
            tied,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, "id, name / reference node, DOFs / tied nodes"));
    }
    Ok(())
}

/// Point masses (one per node) and Rayleigh damping groups.
pub(crate) fn build(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    let mut mass_at: HashMap<u32, Loc> = HashMap::new();
    for p in &raw.point_masses {
        if let Some(first) = mass_at.insert(p.node, p.node_loc) {
            return Err(b.err(
                p.node_loc,
                "POINT MASS",
                format!(
                    "node {} already has a point mass (line {})",
                    p.node, first.line
                ),
                "one point mass per node",
            ));
        }
        parts.point_masses.push(PointMass {
            node: p.node,
            mass: p.mass,
            inertia: p.inertia,
        });
    }
    for d in &raw.damping {
        let elements = b.resolve(&d.elements, SetKind::Element, "DAMPING")?;
        let mass_nodes = match &d.mass_nodes {
            Some(list) => b.resolve(list, SetKind::Node, "DAMPING")?,
            None => Vec::new(),
        };
        parts.damping.push(Damping {
            alpha: d.alpha,
            beta: d.beta,
            elements,
            mass_nodes,
        });
    }
    Ok(())
}

/// Rigid ties: unique names and ids, no overlap, no chain, no tied DOF prescribed.
pub(crate) fn build_ties(
    b: &Builder<'_>,
    raw: &RawDeck,
    prescribed: &HashMap<(u32, u8), Loc>,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    b.unique(
        "RBE2",
        "tie name",
        raw.rigid_ties.iter().map(|t| (t.name.as_str(), t.loc)),
    )?;
    let tids: Vec<String> = raw.rigid_ties.iter().map(|t| t.id.to_string()).collect();
    b.unique(
        "RBE2",
        "tie id",
        tids.iter()
            .map(String::as_str)
            .zip(raw.rigid_ties.iter().map(|t| t.loc)),
    )?;
    let mut tied_by: HashMap<u32, (String, Loc)> = HashMap::new();
    for t in &raw.rigid_ties {
        let tied = b.resolve(&t.tied, SetKind::Node, "RBE2")?;
        let tied = b.non_empty(tied, &t.tied, "RBE2", "tied nodes")?;
        for &n in &tied {
            if n == t.reference {
                continue;
            }
            if let Some((other, at)) = tied_by.get(&n) {
                return Err(b.err(
                    t.tied.loc,
                    "RBE2",
                    format!("node {n} is already tied by `{other}` (line {})", at.line),
                    "each node tied by one tie",
                ));
            }
            tied_by.insert(n, (t.name.clone(), t.loc));
            for &d in &t.dofs {
                if let Some(at) = prescribed.get(&(n, d)) {
                    return Err(b.err(
                        t.tied.loc,
                        "RBE2",
                        format!(
                            "node {n} DOF {d} is tied and also prescribed by FIXED DISP (line {})",
                            at.line
                        ),
                        "a tied DOF that is not prescribed",
                    ));
                }
            }
        }
        parts.rigid_ties.push(RigidTie {
            name: t.name.clone(),
            reference: t.reference,
            dofs: t.dofs.clone(),
            tied,
        });
    }
    for t in &raw.rigid_ties {
        if let Some((other, at)) = tied_by.get(&t.reference) {
            return Err(b.err(
                t.reference_loc,
                "RBE2",
                format!(
                    "the reference node {} is tied by `{other}` (line {}); ties may not chain",
                    t.reference, at.line
                ),
                "a reference node that no tie ties",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::deck::cards::testing::*;

    #[test]
    fn damping_point_mass_and_ties() {
        let m = with_model("POINT MASS\n3, 1e-3, 1, 2, 3\nDAMPING\n0.5, 1e-4, 1\nwire\n3\n0.1, 0\n1\nRBE2\n5, top\n3, 3, 1, 2\n2\n").unwrap();
        assert_eq!(m.point_masses[0].inertia, [1.0, 2.0, 3.0]);
        assert_eq!(m.damping[0].mass_nodes, [3]);
        assert_eq!(m.damping[1].elements, [1]);
        assert!(m.damping[1].mass_nodes.is_empty());
        assert_eq!(m.rigid_ties[0].name, "top");
        assert_eq!(m.rigid_ties[0].dofs, [1, 2, 3]);
        assert_eq!(m.rigid_ties[0].tied, [2]);
        let e = err_with_model("DAMPING\n0.5, 0, 1\n\n2\n");
        assert!(e.contains("no POINT MASS"), "{e}");
        let e = err_with_model("RBE2\n1\n3, 1, 2\n1\n");
        assert!(e.contains("prescribed"), "{e}");
        let e = err_with_model("POINT MASS\n3, -1, 0, 0, 0\n");
        assert!(e.contains("mass >= 0"), "{e}");
    }
}
