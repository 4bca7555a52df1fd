//! Point laws and modal damping: the nonlinear point elements
//! `FRICTION` (N), `QUADRATIC DAMPER` (N s^2/mm^2), `CUBIC SPRING` (N/mm^3), the linear
//! `DASHPOT` (N s/mm), and `LOSS FACTOR` and `MODAL DAMPING` (dimensionless).
//! Their checks across cards (free DOFs) are the model's, see `docs/transient.md`.
//!
//! Each card is one [`Keyword`] entry (its name, sections, meaning, layout, example
//! and parse function) followed by its parse function; then the family's build function
//! (raw deck -> model parts, run in order by [`crate::deck::build`]); its tests close
//! the file.

use std::collections::HashMap;

use crate::deck::card::{CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::{DeckError, Loc};
use crate::deck::raw::{PointLawKind, RawDeck, RawPointLaw};
use crate::deck::resolve::Builder;
use crate::model::{Dashpot, ModalDamping, ModelParts, PointElement};
use DeckSection::Model;

/// The `FRICTION` card.
pub(crate) const FRICTION: Keyword = Keyword {
    name: "FRICTION",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "Dry (Coulomb) friction between one DOF of a node and the ground: a force \
              F sgn(v) against the DOF's velocity v, any value in [-F, F] while the DOF \
              sticks (v = 0).",
    layout: &[
        ("FRICTION", ""),
        (
            "node, dof, force",
            "one line per DOF: dof 1..6, force F >= 0 (N; N mm on a rotation)",
        ),
    ],
    notes: NONLINEAR_NOTES,
    example: "FRICTION\n10, 3, 0.25",
    parse: parse_friction,
};

/// The `QUADRATIC DAMPER` card.
pub(crate) const QUADRATIC_DAMPER: Keyword = Keyword {
    name: "QUADRATIC DAMPER",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A velocity-squared dashpot between one DOF of a node and the ground: the \
              drag force c2 v |v|.",
    layout: &[
        ("QUADRATIC DAMPER", ""),
        (
            "node, dof, c2",
            "one line per DOF: dof 1..6, c2 >= 0 (N s^2/mm^2; 1 N s^2/m^2 = 1e-6 \
             N s^2/mm^2)",
        ),
    ],
    notes: NONLINEAR_NOTES,
    example: "QUADRATIC DAMPER\n10, 3, 2.0e-6",
    parse: parse_quadratic_damper,
};

/// The `CUBIC SPRING` card.
pub(crate) const CUBIC_SPRING: Keyword = Keyword {
    name: "CUBIC SPRING",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A cubic spring between one DOF of a node and the ground: the restoring \
              force k3 u^3, u the DOF's displacement from the reference (meshed) \
              configuration, so a spring meshed at its free length feels it from the \
              free length on, gravity preload included.",
    layout: &[
        ("CUBIC SPRING", ""),
        (
            "node, dof, k3",
            "one line per DOF: dof 1..6, k3 >= 0 (N/mm^3; 1 N/m^3 = 1e-9 N/mm^3)",
        ),
    ],
    notes: NONLINEAR_NOTES,
    example: "CUBIC SPRING\n10, 3, 1.0e-4",
    parse: parse_cubic_spring,
};

/// The `DASHPOT` card.
pub(crate) const DASHPOT: Keyword = Keyword {
    name: "DASHPOT",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "A linear (viscous) dashpot between one DOF of a node and the ground: the \
              force c v against the DOF's velocity v (e.g. air or a guide acting on the \
              weight).",
    layout: &[
        ("DASHPOT", ""),
        (
            "node, dof, c",
            "one line per DOF: dof 1..6, c >= 0 (N s/mm; 1 N s/m = 1e-3 N s/mm; N mm s \
             on a rotation)",
        ),
    ],
    notes: "Lines repeat until the next card; one line per node and DOF. The node must \
            exist and the DOF be free (neither in FIXED DISP nor tied by RBE2). The \
            dashpot is part of the viscous damping matrix C, so every transient method \
            and scheme runs it; modal superposition takes its diagonal modal part \
            (reported as coupling like Rayleigh damping on part of a model).",
    example: "DASHPOT\n10, 3, 1.0e-3",
    parse: parse_dashpot,
};

/// The `LOSS FACTOR` card.
pub(crate) const LOSS_FACTOR: Keyword = Keyword {
    name: "LOSS FACTOR",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "Hysteretic (structural) damping with a constant loss factor eta, in its \
              time-domain equivalent for free vibration: modal damping zeta_i = eta / 2 \
              in every mode.",
    layout: &[
        ("LOSS FACTOR", ""),
        (
            "eta, modes",
            "eta >= 0 (-); modes >= 1: how many of the lowest modes carry it in direct \
             integration",
        ),
    ],
    notes: "One line, once per deck. Modal superposition damps each retained mode with \
            eta / 2 (plus any MODAL DAMPING ratio and the modal part of C). Direct \
            integration (any scheme; not with non-zero nonlinear point elements) adds C_m = M Phi diag(2 zeta_i w_i) Phi^T M over \
            the lowest `modes` modes; modes above them get no hysteretic damping. The \
            equivalence holds per mode for free decay (the same loss per cycle); it is \
            not the causal, frequency-independent loss of a forced response. See \
            docs/transient.md.",
    example: "LOSS FACTOR\n3.5e-3, 20",
    parse: parse_loss_factor,
};

/// The `MODAL DAMPING` card.
pub(crate) const MODAL_DAMPING: Keyword = Keyword {
    name: "MODAL DAMPING",
    sections: &[Model],
    origin: Origin::Coil,
    meaning: "Damping ratios per mode (as in modal transient runs): mode i, counted from \
              the lowest frequency, gets the damping ratio zeta_i.",
    layout: &[
        ("MODAL DAMPING", ""),
        ("mode, zeta", "one line per mode: mode >= 1, 0 <= zeta < 1"),
    ],
    notes: "Lines repeat until the next card; each mode once; modes not listed get none. \
            Adds to LOSS FACTOR's eta / 2. Modal superposition applies it to the retained \
            modes; direct integration (any scheme; not with non-zero nonlinear point elements) \
            adds C_m = M Phi diag(2 zeta_i w_i) Phi^T M over the modes up to the highest one \
            listed. See docs/transient.md.",
    example: "MODAL DAMPING\n1, 0.002\n2, 0.01",
    parse: parse_modal_damping,
};

/// Notes shared by the three nonlinear point cards.
const NONLINEAR_NOTES: &str = "Lines repeat until the next card. The node must exist and \
    the DOF be free (neither in FIXED DISP nor tied by RBE2); one line of a card per node \
    and DOF. FRICTION, QUADRATIC DAMPER and CUBIC SPRING on the same node and DOF add up \
    to one law f = k3 u^3 + c2 v|v| + F sgn(v). A zero value is accepted and adds nothing. \
    Transients run them by direct integration with average acceleration (NEWMARK) only; \
    STATIC load cases see the cubic spring alone (friction and the dashpot exert no static \
    force). See docs/transient.md.";

fn parse_friction(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    parse_point_law(c, PointLawKind::Friction)
}

fn parse_quadratic_damper(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    parse_point_law(c, PointLawKind::Quadratic)
}

fn parse_cubic_spring(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    parse_point_law(c, PointLawKind::Cubic)
}

fn parse_dashpot(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    parse_point_law(c, PointLawKind::Dashpot)
}

fn parse_loss_factor(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "eta (-), modes (>= 1)";
    c.no_args()?;
    let l = c.data_line(LAYOUT)?;
    c.field_count(l, 2, 2, LAYOUT)?;
    let x = c.real(l, 0, "the loss factor eta")?;
    let eta = c.non_negative(x, l.loc_of(0), "the loss factor eta")?;
    let modes = c.count(
        l,
        1,
        1,
        "the number of modes carrying eta in direct integration",
    )?;
    if let Some((_, _, first)) = c.deck.loss_factor {
        return Err(c.err(
            l.start_loc(),
            format!("LOSS FACTOR is already given at line {}", first.line),
            "one LOSS FACTOR per deck",
        ));
    }
    c.deck.loss_factor = Some((eta, modes, l.start_loc()));
    Ok(())
}

fn parse_modal_damping(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "mode (>= 1), zeta (0 <= zeta < 1)";
    c.no_args()?;
    c.each_line(LAYOUT, (2, 2), |c, l| {
        let mode = c.count(l, 0, 1, "the mode number")?;
        let x = c.real(l, 1, "the damping ratio zeta")?;
        let zeta = c.non_negative(x, l.loc_of(1), "the damping ratio zeta")?;
        if mode > 100_000 {
            return Err(c.err(
                l.loc_of(0),
                format!("mode {mode}"),
                "a mode number 1..100000",
            ));
        }
        if zeta >= 1.0 {
            return Err(c.err(
                l.loc_of(1),
                format!("zeta {zeta}"),
                "an underdamped ratio 0 <= zeta < 1",
            ));
        }
        if let Some(&(_, _, first)) = c.deck.modal_ratios.iter().find(|r| r.0 == mode) {
            return Err(c.err(
                l.start_loc(),
                format!("mode {mode} is already given at line {}", first.line),
                "each mode once",
            ));
        }
        c.deck.modal_ratios.push((mode, zeta, l.start_loc()));
        Ok(())
    })
}

/// `node, dof, value` lines of the nonlinear point cards.
fn parse_point_law(c: &mut CardCtx<'_, '_>, kind: PointLawKind) -> Result<(), DeckError> {
    let layout = kind.layout();
    c.no_args()?;
    c.each_line(layout, (3, 3), |c, l| {
        let node = c.id(l, 0, "the node id")?;
        let dof = c.dof(l, 1)?;
        let x = c.real(l, 2, kind.what())?;
        let value = c.non_negative(x, l.loc_of(2), kind.what())?;
        c.deck.point_laws.push(RawPointLaw {
            kind,
            node,
            loc: l.start_loc(),
            node_loc: l.loc_of(0),
            dof,
            dof_loc: l.loc_of(1),
            value,
        });
        Ok(())
    })
}

/// Nonlinear point elements and dashpots: free DOFs only, one line per card, node and
/// DOF (the cards on one DOF combine); the modal damping of `LOSS FACTOR` and `MODAL
/// DAMPING`.
pub(crate) fn build(
    b: &Builder<'_>,
    raw: &RawDeck,
    prescribed: &HashMap<(u32, u8), Loc>,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    let mut law_lines: HashMap<(u32, u8, PointLawKind), Loc> = HashMap::new();
    for p in &raw.point_laws {
        let card = p.kind.card();
        if let Some(at) = prescribed.get(&(p.node, p.dof)) {
            return Err(b.err(
                p.dof_loc,
                card,
                format!(
                    "node {} DOF {} is prescribed by FIXED DISP (line {})",
                    p.node, p.dof, at.line
                ),
                "a free DOF",
            ));
        }
        let tie = raw
            .rigid_ties
            .iter()
            .zip(&parts.rigid_ties)
            .find(|(_, t)| t.dofs.contains(&p.dof) && t.tied.binary_search(&p.node).is_ok());
        if let Some((raw_tie, tie)) = tie {
            return Err(b.err(
                p.dof_loc,
                card,
                format!(
                    "node {} DOF {} is tied by `{}` (line {}); put the element on the \
                     reference node {}",
                    p.node, p.dof, tie.name, raw_tie.loc.line, tie.reference
                ),
                "a free DOF",
            ));
        }
        if let Some(first) = law_lines.insert((p.node, p.dof, p.kind), p.loc) {
            return Err(b.err(
                p.loc,
                card,
                format!(
                    "node {} DOF {} is already given at line {}",
                    p.node, p.dof, first.line
                ),
                "each DOF of a node once per card",
            ));
        }
        if p.kind == PointLawKind::Dashpot {
            parts.dashpots.push(Dashpot {
                node: p.node,
                dof: p.dof,
                c: p.value,
            });
            continue;
        }
        let laws = &mut parts.point_laws;
        let at = match laws.iter().position(|e| (e.node, e.dof) == (p.node, p.dof)) {
            Some(i) => i,
            None => {
                laws.push(PointElement {
                    node: p.node,
                    dof: p.dof,
                    cubic: 0.0,
                    quadratic: 0.0,
                    friction: 0.0,
                });
                laws.len() - 1
            }
        };
        let e = &mut laws[at];
        match p.kind {
            PointLawKind::Friction => e.friction = p.value,
            PointLawKind::Quadratic => e.quadratic = p.value,
            PointLawKind::Cubic => e.cubic = p.value,
            PointLawKind::Dashpot => {}
        }
    }
    let mut modal_damping = ModalDamping::default();
    if let Some((eta, modes, _)) = raw.loss_factor {
        modal_damping.loss_factor = eta;
        modal_damping.loss_factor_modes = modes;
    }
    for &(mode, zeta, _) in &raw.modal_ratios {
        let i = mode as usize - 1;
        if modal_damping.ratios.len() <= i {
            modal_damping.ratios.resize(i + 1, 0.0);
        }
        modal_damping.ratios[i] = zeta;
    }
    while modal_damping.ratios.last() == Some(&0.0) {
        modal_damping.ratios.pop();
    }
    parts.modal_damping = modal_damping;
    Ok(())
}
