//! Marc's control cards (MSC Marc, Volume C: parameter, model-definition and history
//! cards) that change nothing coil computes: memory, printed output, output order,
//! formulation switches of element families coil does not have (continuum and shell
//! elements, which stop a deck at `ELEMENTS`), checks. Each is read, its data lines
//! (lines that start with a number) skipped, and listed once in the run's log as "read
//! and not needed", so that a deck stops only at physics coil does not model. The
//! reason for each is its entry's notes (docs/deck.md). A card whose effect could change
//! a result (`RESTART`, which may read an earlier run; `SCALE`; `FEATURE`) is not here:
//! it stays an unknown card, named with its line.

use super::mentat::{parse_not_needed, parse_not_needed_line};
use crate::deck::card::{DeckSection, Keyword, Origin};
use DeckSection::{History, Model, Parameters};

/// The `ASSUMED` card.
pub(crate) const ASSUMED: Keyword = Keyword {
    name: "ASSUMED",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's assumed-strain formulation of lower-order continuum elements (types 3, 7, 11, ...).",
    layout: &[("ASSUMED[, flags]", "")],
    notes: "Read and not needed: it changes only continuum elements, and coil's elements are beams (a continuum element stops the deck at ELEMENTS).",
    example: "ASSUMED",
    parse: parse_not_needed,
};

/// The `CONSTANT DILATATION` card.
pub(crate) const CONSTANT_DIL: Keyword = Keyword {
    name: "CONSTANT DILATATION",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's constant-dilatation formulation of lower-order continuum elements.",
    layout: &[("CONSTANT DILATATION", "")],
    notes: "Read and not needed: it changes only continuum elements; coil's elements are beams.",
    example: "CONSTANT DILATATION",
    parse: parse_not_needed,
};

/// The `CENTROID` card.
pub(crate) const CENTROID: Keyword = Keyword {
    name: "CENTROID",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's element output at the centroid only (its printed and post-file results).",
    layout: &[("CENTROID", "")],
    notes: "Read and not needed: an output choice; coil writes its own results.",
    example: "CENTROID",
    parse: parse_not_needed,
};

/// The `COMMENT` card.
pub(crate) const COMMENT: Keyword = Keyword {
    name: "COMMENT",
    sections: &[Parameters, Model, History],
    origin: Origin::Marc,
    meaning: "A comment card (its data lines are text).",
    layout: &[("COMMENT[, text]", "")],
    notes: "Read and not needed: nothing is computed from it. Its own line only (a comment's text lines should start with `$`).",
    example: "COMMENT, written by Mentat",
    parse: parse_not_needed_line,
};

/// The `ELSTO` card.
pub(crate) const ELSTO: Keyword = Keyword {
    name: "ELSTO",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's out-of-core storage of element matrices.",
    layout: &[("ELSTO[, n]", "")],
    notes: "Read and not needed: memory management.",
    example: "ELSTO, 1000",
    parse: parse_not_needed,
};

/// The `MPC-CHECK` card.
pub(crate) const MPC_CHECK: Keyword = Keyword {
    name: "MPC-CHECK",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's consistency check of its tying equations before the analysis.",
    layout: &[("MPC-CHECK", "")],
    notes:
        "Read and not needed: a check only; coil checks its rigid ties when it builds the DOF map.",
    example: "MPC-CHECK",
    parse: parse_not_needed,
};

/// The `PRINT` card.
pub(crate) const PRINT: Keyword = Keyword {
    name: "PRINT",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's printout of internal information (element and solver details).",
    layout: &[("PRINT, flags ...", "")],
    notes: "Read and not needed: printed output.",
    example: "PRINT, 5",
    parse: parse_not_needed,
};

/// The `SHELL SECT` card.
pub(crate) const SHELL_SECT: Keyword = Keyword {
    name: "SHELL SECT",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's number of integration layers through shells.",
    layout: &[("SHELL SECT, n", "")],
    notes: "Read and not needed: it changes only shell elements; coil's elements are beams.",
    example: "SHELL SECT, 11",
    parse: parse_not_needed,
};

/// The `STATE VARS` card.
pub(crate) const STATE_VARS: Keyword = Keyword {
    name: "STATE VARS",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Marc's number of state variables stored per integration point.",
    layout: &[("STATE VARS, n", "")],
    notes: "Read and not needed: storage; coil's beams are linear elastic.",
    example: "STATE VARS, 2",
    parse: parse_not_needed,
};

/// The `AUTOMSET` card.
pub(crate) const AUTOMSET: Keyword = Keyword {
    name: "AUTOMSET",
    sections: &[Parameters],
    origin: Origin::Marc,
    meaning: "Mentat's automatic generation of sets for its contact bodies.",
    layout: &[("AUTOMSET", "")],
    notes: "Read and not needed: sets for contact; contact itself stops the deck at CONTACT.",
    example: "AUTOMSET",
    parse: parse_not_needed,
};

/// The `PRINT CHOICE` card.
pub(crate) const PRINT_CHOICE: Keyword = Keyword {
    name: "PRINT CHOICE",
    sections: &[Model, History],
    origin: Origin::Marc,
    meaning: "Marc's selection of the elements, nodes and integration points it prints.",
    layout: &[("PRINT CHOICE", ""), ("ids ...", "lines of numbers")],
    notes: "Read and not needed: printed output.",
    example: "PRINT CHOICE\n1, 0, 0",
    parse: parse_not_needed,
};

/// The `PRINT ELEM` card.
pub(crate) const PRINT_ELEM: Keyword = Keyword {
    name: "PRINT ELEM",
    sections: &[Model, History],
    origin: Origin::Marc,
    meaning: "Marc's printed element quantities.",
    layout: &[("PRINT ELEM", ""), ("flags ...", "lines of numbers")],
    notes: "Read and not needed: printed output.",
    example: "PRINT ELEM\n1, 0",
    parse: parse_not_needed,
};

/// The `PRINT NODE` card.
pub(crate) const PRINT_NODE: Keyword = Keyword {
    name: "PRINT NODE",
    sections: &[Model, History],
    origin: Origin::Marc,
    meaning: "Marc's printed nodal quantities.",
    layout: &[("PRINT NODE", ""), ("flags ...", "lines of numbers")],
    notes: "Read and not needed: printed output.",
    example: "PRINT NODE\n1, 0",
    parse: parse_not_needed,
};

/// The `PRINT VMASS` card.
pub(crate) const PRINT_VMASS: Keyword = Keyword {
    name: "PRINT VMASS",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's printout of volumes and masses.",
    layout: &[("PRINT VMASS", "")],
    notes: "Read and not needed: printed output (coil-solve prints its own masses).",
    example: "PRINT VMASS",
    parse: parse_not_needed,
};

/// The `SUMMARY` card.
pub(crate) const SUMMARY: Keyword = Keyword {
    name: "SUMMARY",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's timing summary.",
    layout: &[("SUMMARY[, flags]", "")],
    notes: "Read and not needed: printed output.",
    example: "SUMMARY",
    parse: parse_not_needed,
};

/// The `ELEMENT SORT` card.
pub(crate) const ELEMENT_SORT: Keyword = Keyword {
    name: "ELEMENT SORT",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's order of elements in its printed output.",
    layout: &[("ELEMENT SORT", ""), ("flags ...", "lines of numbers")],
    notes: "Read and not needed: output order.",
    example: "ELEMENT SORT\n1, 0",
    parse: parse_not_needed,
};

/// The `NODE SORT` card.
pub(crate) const NODE_SORT: Keyword = Keyword {
    name: "NODE SORT",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's order of nodes in its printed output.",
    layout: &[("NODE SORT", ""), ("flags ...", "lines of numbers")],
    notes: "Read and not needed: output order.",
    example: "NODE SORT\n1, 0",
    parse: parse_not_needed,
};

/// The `RESTART LAST` card.
pub(crate) const RESTART_LAST: Keyword = Keyword {
    name: "RESTART LAST",
    sections: &[Model],
    origin: Origin::Marc,
    meaning: "Marc's restart file, keeping the last increment only.",
    layout: &[("RESTART LAST", ""), ("flags ...", "lines of numbers")],
    notes: "Read and not needed: coil writes no restart file. (`RESTART`, which may also read one, is not read: a run continued from a file would miss its earlier increments.)",
    example: "RESTART LAST\n1",
    parse: parse_not_needed,
};

/// The `POST INCREMENT` card.
pub(crate) const POST_INCREMENT: Keyword = Keyword {
    name: "POST INCREMENT",
    sections: &[History],
    origin: Origin::Marc,
    meaning: "Marc's post-file frequency in a load case.",
    layout: &[("POST INCREMENT", ""), ("n", "")],
    notes: "Read and not needed: coil records every history sample its HISTORY OUTPUT asks for.",
    example: "POST INCREMENT\n5",
    parse: parse_not_needed,
};

#[cfg(test)]
mod tests {
    use super::super::testing::{with_model, MESH, PARAMS, STATIC};
    use super::*;
    use crate::deck::read_str;

    /// Every card of this family, in the order of the deck reference.
    const CARDS: &[Keyword] = &[
        ASSUMED,
        CONSTANT_DIL,
        CENTROID,
        COMMENT,
        ELSTO,
        MPC_CHECK,
        PRINT,
        SHELL_SECT,
        STATE_VARS,
        AUTOMSET,
        PRINT_CHOICE,
        PRINT_ELEM,
        PRINT_NODE,
        PRINT_VMASS,
        SUMMARY,
        ELEMENT_SORT,
        NODE_SORT,
        RESTART_LAST,
        POST_INCREMENT,
    ];

    /// Every control card, in each section it belongs to, reads and changes nothing:
    /// the model equals the one without it.
    #[test]
    fn control_cards_are_read_and_change_nothing() {
        let plain = with_model("").unwrap();
        for kw in CARDS {
            for section in kw.sections {
                let text = match section {
                    Parameters => format!(
                        "TITLE, t\n{}\nELEMENTS, 98\nEND\n{MESH}{STATIC}",
                        kw.example
                    ),
                    Model => format!("{PARAMS}{MESH}{}\n{STATIC}", kw.example),
                    History => format!(
                        "{PARAMS}{MESH}END OPTION\nAUTO LOAD\n1\n{}\nTIME STEP\n1.0\nCONTINUE\n",
                        kw.example
                    ),
                };
                let m = read_str(&text, "t.dat").unwrap_or_else(|e| panic!("{}: {e}", kw.name));
                assert_eq!(m, plain, "{}", kw.name);
            }
        }
    }
}
