//! What a catenary adds to a deck of beams: `BEAM TENSION`, a given axial force N (N)
//! in wire elements, which the analyses see as the elements' geometric stiffness.
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

use crate::deck::card::{no_groups, CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::DeckError;
use crate::deck::raw::{RawBeamTension, RawDeck, SetKind};
use crate::deck::resolve::Builder;
use crate::model::{BeamTension, ModelParts};
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

fn parse_beam_tension(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "force (N) / the list of tensioned elements";
    c.no_args()?;
    let mut done = 0;
    while c.more_data() {
        let l = c.data_line(LAYOUT)?;
        c.field_count(l, 1, 1, LAYOUT)?;
        let force = c.real(l, 0, "the axial force (N)")?;
        let elements = c.list("the list of tensioned elements")?;
        c.deck.beam_tensions.push(RawBeamTension {
            force,
            loc: l.start_loc(),
            elements,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, LAYOUT));
    }
    Ok(())
}

/// Beam tensions: the element lists resolved (non-empty); the model checks that each
/// element is in one group.
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
}
