//! The parameter section's cards: `TITLE` (also a load case's), `SIZING`, `ELEMENTS`,
//! `LUMP`, `DYNAMIC` (Marc's choice of transient method, read for codes 1 and 2), `END`,
//! and `UNIT`, which is refused (it may change what the numbers mean).
//!
//! Each card is one [`Keyword`] entry (its name, sections, meaning, layout, example
//! and parse function) followed by its parse function; then the family's build function
//! (raw deck -> model parts, run in order by [`crate::deck::build`]); its tests close
//! the file.

use crate::deck::card::{once, CardCtx, DeckSection, Keyword, Origin};
use crate::deck::error::{DeckError, Loc};
use crate::deck::lexer::{self, Line};
use crate::deck::raw::MarcDynamic;
use crate::model::ElementType;
use DeckSection::{History, Model, Parameters};

/// The `TITLE` card.
pub(crate) const TITLE: Keyword = Keyword {
    name: "TITLE",
    sections: &[Parameters, History],
    origin: Origin::Marc,
    meaning: "The job title (parameter section) or the title of the load case it \
              appears in (history).",
    layout: &[(
        "TITLE, text",
        "the rest of the line, blanks at both ends removed",
    )],
    notes: "At most one per job and one per load case. A title is one line.",
    example: "TITLE, paper spring, n = 14",
    parse: parse_title,
};

/// The `SIZING` card.
pub(crate) const SIZING: Keyword = Keyword {
    name: "SIZING",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's allocation sizes. coil allocates on demand and only checks that \
              the model fits the maximum numbers of elements and nodes given.",
    layout: &[(
        "SIZING, memory, elements, nodes, boundary conditions",
        "non-negative integers, any of them blank or 0 (no bound); further fields \
         (newer Marc versions) must be integers too",
    )],
    notes: "Optional.",
    example: "SIZING, 0, 336, 337, 0",
    parse: parse_sizing,
};

/// The `ELEMENTS` card.
pub(crate) const ELEMENTS: Keyword = Keyword {
    name: "ELEMENTS",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Declares the element types the model uses: 52 (elastic Euler-Bernoulli \
              beam) and/or 98 (elastic beam with transverse shear, Timoshenko).",
    layout: &[(
        "ELEMENTS, type[, type]",
        "52 and/or 98; the card may be repeated",
    )],
    notes: "Every element of CONNECTIVITY must have a declared type.",
    example: "ELEMENTS, 98",
    parse: parse_elements,
};

/// The `LUMP` card.
pub(crate) const LUMP: Keyword = Keyword {
    name: "LUMP",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Lumped instead of consistent mass matrices, for every element. Without \
              LUMP the mass is consistent; there is no silent default.",
    layout: &[(
        "LUMP[, 1[, 0 ...]]",
        "nothing, or Mentat's `1, 0` (lumped mass for every element)",
    )],
    notes: "coil supports only the fully lumped form: a first field other than 1 or \
            a further field other than 0 is an error.",
    example: "LUMP",
    parse: parse_lump,
};

/// The `END` card.
pub(crate) const END: Keyword = Keyword {
    name: "END",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Ends the parameter section; the model definition follows.",
    layout: &[("END", "")],
    notes: "",
    example: "END",
    parse: parse_end,
};

/// The `DYNAMIC` card.
pub(crate) const DYNAMIC: Keyword = Keyword {
    name: "DYNAMIC",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's dynamic analysis and its transient method: 1 modal (eigenvalues, \
              and modal superposition for a transient), 2 Newmark; Marc's other codes \
              are other integrators.",
    layout: &[(
        "DYNAMIC, code[, modes]",
        "code 1 or 2; modes (code 1) the number of modes a transient superposes, \
         blank or 0 when the deck has no transient",
    )],
    notes: "It sets the method of a DYNAMIC CHANGE that names none: code 1 modal \
            superposition over `modes` modes, code 2 Newmark average acceleration \
            (beta = 1/4, gamma = 1/2, Marc's default). A DYNAMIC CHANGE that names a \
            method of the other kind (modal against direct) is refused as a \
            contradiction. Marc's other codes (3 Houbolt, 4 and 5 central difference, \
            6 single-step Houbolt, 7 and 8 generalized alpha) are integrators coil does \
            not run under those names and are refused, since the same K and M would give \
            another transient; coil's own HHT and GALPHA are named on DYNAMIC CHANGE. \
            Sources: Marc's common block `concom` (its `idyn` codes 1 to 5 and the \
            `(dynamic,7)`, `(dynamic,8)` options); the codes 6 to 8 from Marc Volume C, \
            not verified against a public copy.",
    example: "DYNAMIC, 1, 10",
    parse: parse_dynamic,
};

fn parse_dynamic(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    let previous = c.deck.marc_dynamic.map(|d| d.1);
    once(c, previous)?;
    let (line, first) = (c.line, c.kw_fields);
    c.field_count(line, first + 1, first + 2, "DYNAMIC, code[, modes]")?;
    let code = c.uint(line, first, "the dynamic code, 1 (modal) or 2 (Newmark)")?;
    let dynamic = match code {
        1 => {
            let modes = c.uint_or(line, first + 1, 0, "the number of modes")?;
            let modes = u32::try_from(modes).map_err(|_| {
                c.err(
                    line.loc_of(first + 1),
                    format!("{modes} modes"),
                    "a number of modes that fits 32 bits",
                )
            })?;
            MarcDynamic::Modal { modes }
        }
        2 => MarcDynamic::Newmark,
        _ => {
            let name = match code {
                3 => "Houbolt",
                4 | 5 => "central difference",
                6 => "single-step Houbolt",
                7 | 8 => "generalized alpha (Marc's)",
                _ => "not a Marc transient method",
            };
            return Err(c.err(
                line.loc_of(first),
                format!("dynamic code {code} ({name}) is not run by coil"),
                "code 1 (modal) or 2 (Newmark); coil's own HHT or GALPHA go on DYNAMIC \
                 CHANGE's method field",
            ));
        }
    };
    c.deck.marc_dynamic = Some((dynamic, c.loc()));
    Ok(())
}

/// The `UNIT` card.
pub(crate) const UNIT: Keyword = Keyword {
    name: "UNIT",
    sections: &[Parameters],
    origin: Origin::Unsupported,
    meaning: "A statement of the deck's unit system (Mentat writes it in the parameter \
              section).",
    layout: &[("UNIT[, ...]", "")],
    notes: "Refused, because it may change what every number means: coil reads a deck \
            in one consistent system (mm, N, t, s; see Units above) and converts \
            nothing, so a deck in another system would be misread without a word. \
            When the deck is in mm, N, t, s, remove the card; otherwise convert the \
            deck.",
    example: "UNIT",
    parse: parse_unit,
};

fn parse_unit(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    Err(c.err(
        c.loc(),
        "UNIT is not supported: the card may state a unit system other than coil's \
         (mm, N, t, s), and coil converts nothing",
        "a deck in mm, N, t, s without the card (remove it when the deck is in mm, N, \
         t, s; otherwise convert the deck)",
    ))
}

fn parse_title(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    let text = c.rest_of_line();
    let loc = c.loc();
    let previous = match *c.section {
        Parameters => c.deck.title.as_ref().map(|t| t.1),
        _ => c.case().title.as_ref().map(|t| t.1),
    };
    if let Some(first) = previous {
        return Err(c.err(
            loc,
            format!("a second TITLE (the first is at line {})", first.line),
            "one TITLE per job and one per load case",
        ));
    }
    match *c.section {
        Parameters => c.deck.title = Some((text, loc)),
        _ => c.case().title = Some((text, loc)),
    }
    Ok(())
}

fn parse_sizing(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    once(c, c.deck.sizing.map(|s| s.2))?;
    const WHAT: &str =
        "non-negative integers: SIZING, memory, elements, nodes, boundary conditions";
    let mut values = Vec::new();
    if let Some(w) = c.line.fixed {
        // Fixed format: the memory field is two integer fields wide.
        let chars: Vec<char> = c.line.raw.chars().collect();
        let mut p = w.word;
        let mut width = 2 * w.int;
        while p < chars.len() {
            let end = (p + width).min(chars.len());
            let t: String = chars[p..end].iter().collect();
            let t = t.trim();
            let v = if t.is_empty() {
                0
            } else {
                lexer::parse_uint(t).map_err(|m| c.err(Loc::new(c.line.no, p + 1), m, WHAT))?
            };
            values.push(v);
            p = end;
            width = w.int;
        }
    } else {
        for j in 0..c.args().len() {
            values.push(c.uint_or(c.line, c.kw_fields + j, 0, WHAT)?);
        }
    }
    let get = |i: usize| values.get(i).copied().unwrap_or(0);
    c.deck.sizing = Some((get(1), get(2), c.loc()));
    Ok(())
}

pub(crate) fn element_type(
    c: &CardCtx<'_, '_>,
    line: &Line,
    i: usize,
) -> Result<ElementType, DeckError> {
    let t = c.uint(line, i, "an element type number")?;
    u32::try_from(t)
        .ok()
        .and_then(ElementType::from_number)
        .ok_or_else(|| {
            c.err(
                line.loc_of(i),
                format!("element type {t} is not supported"),
                "52 (Euler-Bernoulli beam) or 98 (Timoshenko beam)",
            )
        })
}

fn parse_elements(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    if c.args().is_empty() {
        return Err(c.err(
            c.line.end_loc(),
            "no element type",
            "ELEMENTS, 52 and/or 98",
        ));
    }
    for j in 0..c.args().len() {
        let i = c.kw_fields + j;
        let kind = element_type(c, c.line, i)?;
        if let Some((_, first)) = c.deck.element_types.iter().find(|(k, _)| *k == kind) {
            return Err(c.err(
                c.line.loc_of(i),
                format!(
                    "type {} is declared twice (first at line {})",
                    kind.number(),
                    first.line
                ),
                "each type once",
            ));
        }
        c.deck.element_types.push((kind, c.line.loc_of(i)));
    }
    Ok(())
}

fn parse_lump(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    once(c, c.deck.lump)?;
    if !c.args().is_empty() {
        let first = c.uint_or(c.line, c.kw_fields, 1, "1 (lumped mass for every element)")?;
        if first != 1 {
            return Err(c.err(
                c.arg_loc(0),
                format!("LUMP option {first} is not supported"),
                "LUMP alone or LUMP, 1 (lumped mass for every element)",
            ));
        }
        c.zeros_from(c.line, c.kw_fields + 1, "Marc's further LUMP options")?;
    }
    c.deck.lump = Some(c.loc());
    Ok(())
}

fn parse_end(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    c.deck.end = Some(c.loc());
    *c.section = Model;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::cards::testing::*;

    #[test]
    fn title_in_both_sections() {
        let m = read_str(
            &format!("TITLE   my job, part 2\nELEMENTS, 98\nEND\n{MESH}END OPTION\nTITLE, lc1\nMODAL SHAPE\n3\nCONTINUE\n"),
            "t.dat",
        )
        .unwrap();
        assert_eq!(m.title, "my job, part 2");
        assert_eq!(m.load_cases[0].title, "lc1");
        let e = read_str(&format!("TITLE, a\nTITLE, b\n{PARAMS}"), "t.dat").unwrap_err();
        assert!(
            e.to_string().contains("t.dat:2:1: TITLE: a second TITLE"),
            "{e}"
        );
    }

    /// `DYNAMIC` sets the method of a `DYNAMIC CHANGE` that names none; a contradiction
    /// and Marc's other integrators are refused where written.
    #[test]
    fn a_dynamic_card_sets_the_transient_method() {
        use crate::model::{Integrator, TransientMethod};
        let deck = |param: &str, method: &str| {
            format!(
                "TITLE, t\n{param}ELEMENTS, 98\nEND\n{MESH}END OPTION\nTITLE, lc\n\
                 DYNAMIC CHANGE\n1e-3, 0.01{method}\nCONTINUE\n"
            )
        };
        let method = |param: &str, method: &str| {
            let m = read_str(&deck(param, method), "t.dat").unwrap();
            match &m.load_cases[0].analysis {
                crate::model::Analysis::Transient { method, .. } => *method,
                a => panic!("{a:?}"),
            }
        };
        let newmark = TransientMethod::Direct(Integrator::AverageAcceleration);
        assert_eq!(method("", ""), newmark);
        assert_eq!(method("DYNAMIC, 2\n", ""), newmark);
        assert_eq!(
            method("dynamic, 1, 6\n", ""),
            TransientMethod::Modal { modes: 6 }
        );
        assert_eq!(
            method("DYNAMIC, 2\n", ", HHT, -0.1"),
            TransientMethod::Direct(Integrator::Hht { alpha: -0.1 })
        );
        // `None`: the error is on DYNAMIC CHANGE's data line.
        for (param, method, line, needle) in [
            ("DYNAMIC, 3\n", "", Some(2), "dynamic code 3 (Houbolt)"),
            ("DYNAMIC, 4\n", "", Some(2), "central difference"),
            ("DYNAMIC, 9\n", "", Some(2), "not a Marc transient method"),
            ("DYNAMIC, 2\nDYNAMIC, 2\n", "", Some(3), "DYNAMIC"),
            ("DYNAMIC, 1\n", "", None, "modes"),
            ("DYNAMIC, 1, 4\n", ", NEWMARK", None, "contradicts"),
            ("DYNAMIC, 2\n", ", MODAL, 4", None, "contradicts"),
        ] {
            let text = deck(param, method);
            let data = 1 + text
                .lines()
                .position(|l| l.starts_with("1e-3, 0.01"))
                .unwrap();
            let e = read_str(&text, "t.dat").unwrap_err().to_string();
            let line = line.unwrap_or(data);
            assert!(
                e.contains(&format!("t.dat:{line}:")),
                "{param} {method}: {e}"
            );
            assert!(e.contains(needle), "{param} {method}: {e}");
        }
    }

    #[test]
    fn a_unit_card_is_refused_where_written() {
        for card in ["UNIT", "unit, 1", "UNIT, 2, 1, 3"] {
            let e = read_str(&format!("TITLE, t\n{card}\nELEMENTS, 98\nEND\n"), "t.dat")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("t.dat:2:1: UNIT:") && e.contains("mm, N, t, s"),
                "{e}"
            );
        }
    }

    #[test]
    fn sizing_bounds_are_checked() {
        let ok = read_str(
            &format!("SIZING, 0, 2, 3, 0\n{PARAMS}{MESH}{STATIC}"),
            "t.dat",
        );
        assert!(ok.is_ok(), "{}", ok.unwrap_err());
        let e = read_str(
            &format!("SIZING, 0, 1, 3, 0\n{PARAMS}{MESH}{STATIC}"),
            "t.dat",
        )
        .unwrap_err();
        assert!(e.to_string().contains("t.dat:1:1: SIZING:"), "{e}");
        let e = read_str(&format!("SIZING, 0, -1\n{PARAMS}"), "t.dat").unwrap_err();
        assert!(e.to_string().contains(":1:12: SIZING:"), "{e}");
    }

    #[test]
    fn elements_and_lump() {
        let m = read_str(
            &format!("ELEMENTS, 52, 98\nLUMP, 1, 0\n{PARAMS}{MESH}{STATIC}")
                .replace("ELEMENTS, 98\n", ""),
            "t.dat",
        )
        .unwrap();
        assert_eq!(m.element_types, [ElementType::Beam52, ElementType::Beam98]);
        assert!(m.lumped_mass);
        let m = with_model("").unwrap();
        assert!(!m.lumped_mass);
        let e = read_str("ELEMENTS, 7\nEND\n", "t.dat").unwrap_err();
        assert!(
            e.to_string()
                .contains("t.dat:1:11: ELEMENTS: element type 7 is not supported"),
            "{e}"
        );
        let e = read_str("LUMP, 2\nEND\n", "t.dat").unwrap_err();
        assert!(e.to_string().contains("LUMP option 2"), "{e}");
    }
}
