//! THE keyword table. Every card of the deck language is one [`Keyword`] entry in
//! [`KEYWORDS`]: its name, the sections it may appear in, whether its layout follows
//! public Marc decks or is coil's own, what it means, the layout of its lines, an
//! example, and the function that reads its data lines. One more card is one more
//! entry (and its parse function); docs/deck.md's card reference is generated from
//! this table ([`reference_markdown`]) and a test keeps the two equal.
//!
//! The parse functions check each field where it is read (a number, a count, a DOF,
//! a value's sign); references between cards (node ids, set names, tables) are
//! resolved afterwards by [`super::build`].

use super::error::DeckError;
use super::lexer::{self, Line, LIST_WORDS};
use super::mentat;
use super::raw::{
    PointLawKind, RawDamping, RawDofValues, RawElement, RawGeometry, RawMaterial, RawNode,
    RawOutput, RawPointLaw, RawPointLoad, RawPointMass, RawSet, RawTable, RawTie, SetKind,
};
use super::reader::CardCtx;
use crate::model::{ElementType, Integrator, Quantity, Section, TransientMethod};

/// The three sections of a deck, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum DeckSection {
    /// Before `END`.
    Parameters,
    /// Between `END` and `END OPTION`.
    Model,
    /// After `END OPTION`: load cases closed by `CONTINUE`.
    History,
}

impl DeckSection {
    pub fn describe(self) -> &'static str {
        match self {
            DeckSection::Parameters => "parameter section",
            DeckSection::Model => "model definition",
            DeckSection::History => "history",
        }
    }
}

/// Whose layout a card follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// The layout of public Marc decks (possibly restricted; see the card's notes).
    Marc,
    /// coil's own definition (Marc has no public layout for it, or coil's differs).
    Coil,
    /// A Marc card whose physics coil does not model: reading it is an error that
    /// names it and what coil supports.
    Unsupported,
}

pub(crate) type ParseFn = fn(&mut CardCtx<'_, '_>) -> Result<(), DeckError>;

/// One card of the deck language.
pub struct Keyword {
    /// Upper case; words separated by one blank (`FIXED DISP`).
    pub name: &'static str,
    /// Where the card may appear.
    pub sections: &'static [DeckSection],
    pub origin: Origin,
    /// What the card means, in one or two sentences.
    pub meaning: &'static str,
    /// The card's lines, keyword line first: (fields, meaning).
    pub layout: &'static [(&'static str, &'static str)],
    /// Leniency, restrictions and differences to Marc.
    pub notes: &'static str,
    /// A complete example of the card.
    pub example: &'static str,
    pub(crate) parse: ParseFn,
}

use DeckSection::{History, Model, Parameters};

/// Notes shared by the three nonlinear point cards.
const NONLINEAR_NOTES: &str = "Lines repeat until the next card. The node must exist and \
    the DOF be free (neither in FIXED DISP nor tied by RBE2); one line of a card per node \
    and DOF. FRICTION, QUADRATIC DAMPER and CUBIC SPRING on the same node and DOF add up \
    to one law f = k3 u^3 + c2 v|v| + F sgn(v). A zero value is accepted and adds nothing. \
    Transients run them by direct integration with average acceleration (NEWMARK) only; \
    STATIC load cases see the cubic spring alone (friction and the dashpot exert no static \
    force). See docs/transient.md.";

/// Every card, in the order of the deck reference.
pub static KEYWORDS: &[Keyword] = &[
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
        name: "END",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Ends the parameter section; the model definition follows.",
        layout: &[("END", "")],
        notes: "",
        example: "END",
        parse: parse_end,
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
        name: "ISOTROPIC",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Linear isotropic elastic materials: Young's modulus, Poisson's ratio and \
                  density, and the elements each applies to.",
        layout: &[
            ("ISOTROPIC", ""),
            (
                "n",
                "number of materials; 0 or blank = materials until the next card",
            ),
            (
                "id[, name]",
                "per material: a positive id and a name (the id if omitted)",
            ),
            (
                "E, nu, density[, 0 ...]",
                "E > 0 (MPa), -1 < nu < 0.5, density >= 0 (t/mm^3); Marc's further fields \
                 (thermal expansion, yield stress, ...) must be blank or 0",
            ),
            ("list", "the elements"),
        ],
        notes: "Lines 3 to 5 repeat for each material. The id/name line is coil's reading \
                of Marc's material line: coil takes only the id and the name. Where lists \
                overlap, the later material wins.",
        example: "ISOTROPIC\n1\n1, steel\n190708.0, 0.3, 7.85e-9\nwire",
        parse: parse_isotropic,
    },
    Keyword {
        name: "GEOMETRY",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Beam cross-sections and orientations, and the elements each applies to.",
        layout: &[
            ("GEOMETRY", ""),
            (
                "n",
                "number of geometries; 0 or blank = geometries until the next card",
            ),
            (
                "[id, name]",
                "optional, per geometry: a positive id and a name",
            ),
            (
                "d   or   A, I1, I2, J[, kappa]",
                "section: a solid circular wire of diameter d (mm), or area A (mm^2), \
                 second moments I1 about the orientation direction and I2 about the third \
                 axis (Marc's Ixx, Iyy; mm^4), torsion constant J (mm^4) and the \
                 Timoshenko shear coefficient kappa (shear area kappa A), all > 0",
            ),
            (
                "vx, vy, vz",
                "orientation vector (global): local x runs along the element, local y is \
                 the part of this vector normal to it, local z = x cross y",
            ),
            ("list", "the elements"),
        ],
        notes: "Lines 3 to 6 repeat for each geometry; line 3 is recognised by its second \
                field being a name. coil's own parts: the diameter form, J and kappa as fields (no Ixx + Iyy \
                default for J), and the optional name line. kappa is needed when a listed \
                element is of type 98; type 52 ignores it (recorded as 0 when omitted). \
                The orientation may not be parallel to any listed element \
                (|v x e| <= 1e-6 |v| |e|). I1 becomes the model's iyy, I2 its izz.",
        example: "GEOMETRY\n1\n1, wire\n3.0\n0.0, 0.0, 1.0\nwire",
        parse: parse_geometry,
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
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
    },
    Keyword {
        name: "FIXED DISP",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Prescribed displacements (mm) and rotations (rad).",
        layout: &[
            ("FIXED DISP", ""),
            ("value[, value ...]", "the prescribed values, 1 to 6"),
            ("dof[, dof ...]", "one DOF (1..6) per value"),
            ("list", "the nodes"),
        ],
        notes: "Groups repeat until the next card. A node's DOF may be prescribed once.",
        example: "FIXED DISP\n0.0, 0.0, 0.0, 0.0, 0.0, 0.0\n1, 2, 3, 4, 5, 6\n1",
        parse: parse_fixed_disp,
    },
    Keyword {
        name: "POINT LOAD",
        sections: &[Model, History],
        origin: Origin::Marc,
        meaning: "Concentrated forces (N) and moments (N mm) on nodes. In the model \
                  definition they act in every load case; in a load case they are added to \
                  those for that load case.",
        layout: &[
            (
                "POINT LOAD[, TABLE, name]",
                "with TABLE: every load of the card is scaled in time by that table",
            ),
            (
                "F1[, F2 ... F6]",
                "the load in DOF order: Fx, Fy, Fz (N), Mx, My, Mz (N mm); 1 to 6 values",
            ),
            ("list", "the nodes"),
        ],
        notes: "Groups repeat until the next card. The `TABLE, name` fields are coil's own. \
                The model keeps the non-zero components in DOF order.",
        example: "POINT LOAD\n0.0, 0.0, -10.0\n3",
        parse: parse_point_load,
    },
    Keyword {
        name: "TABLE",
        sections: &[Parameters, Model],
        origin: Origin::Coil,
        meaning: "A piecewise-linear load factor against time, for POINT LOAD.",
        layout: &[
            ("TABLE, name", ""),
            (
                "time, factor",
                "one line per point (s, -); times strictly increasing",
            ),
        ],
        notes: "Points repeat until the next card; at least one. In the parameter section \
                TABLE is Marc's parameter (table-driven input; read and not needed); \
                Mentat's model-definition layout is read too: two lines of integers \
                (the first ending with the number of points, the second starting with the \
                independent variable's type, 1 = time, inferred from public decks), then \
                the points.",
        example: "TABLE, ramp\n0.0, 0.0\n0.1, 1.0",
        parse: parse_table,
    },
    Keyword {
        name: "INITIAL VEL",
        sections: &[Model],
        origin: Origin::Coil,
        meaning: "Initial velocities (mm/s, rad/s) of every transient load case. Alone, \
                  only the listed DOFs move at t = 0 and every other DOF is at rest (a \
                  velocity jump). With QUASI STATIC the listed velocities are extended over \
                  all free DOFs by the quasi-static shape: the static response to forces at \
                  the listed DOFs, scaled so that the listed DOFs have exactly their values \
                  (for a weight on a spring: the linear velocity profile the weight's motion \
                  induces along the wire).",
        layout: &[
            (
                "INITIAL VEL[, QUASI STATIC]",
                "QUASI STATIC: a consistent velocity field instead of a jump (see docs/transient.md)",
            ),
            ("value[, value ...]", "the velocities, 1 to 6"),
            ("dof[, dof ...]", "one DOF (1..6) per value"),
            ("list", "the nodes"),
        ],
        notes: "Laid out like FIXED DISP. Groups repeat until the next card; a node's DOF \
                may be given once. The card may be repeated, e.g. once with and once without \
                QUASI STATIC: the quasi-static field of all QUASI STATIC groups is computed \
                first, then the plain groups set their DOFs. A listed DOF must be free: a \
                DOF prescribed by FIXED DISP may only be given 0, and a DOF tied by RBE2 is \
                given at its reference node. `QUASI STATIC` is coil's own.",
        example: "INITIAL VEL, QUASI STATIC\n-100.0\n3\n3",
        parse: parse_initial_vel,
    },
    Keyword {
        name: "HISTORY OUTPUT",
        sections: &[Model],
        origin: Origin::Coil,
        meaning: "Records quantities of nodes' DOFs every k-th step of a transient.",
        layout: &[
            ("HISTORY OUTPUT", ""),
            ("k", "every k-th step (k >= 1)"),
            ("quantity[, quantity ...]", "DISP, VEL and/or ACCEL"),
            ("dof[, dof ...]", "the DOFs (1..6)"),
            ("list", "the nodes"),
        ],
        notes: "Groups repeat until the next card.",
        example: "HISTORY OUTPUT\n1\nDISP, VEL, ACCEL\n3\n3",
        parse: parse_history_output,
    },
    Keyword {
        name: "END OPTION",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Ends the model definition; the load cases follow.",
        layout: &[("END OPTION", "")],
        notes: "",
        example: "END OPTION",
        parse: parse_end_option,
    },
    Keyword {
        name: "AUTO LOAD",
        sections: &[History],
        origin: Origin::Marc,
        meaning: "A static load case in n steps (with TIME STEP). A linear solve applies \
                  the full load once; n is kept for Marc compatibility.",
        layout: &[
            ("AUTO LOAD", ""),
            (
                "n[, 0 ...]",
                "number of steps >= 1; Marc's further fields must be blank or 0",
            ),
        ],
        notes: "A static load case needs both AUTO LOAD and TIME STEP.",
        example: "AUTO LOAD\n1",
        parse: parse_auto_load,
    },
    Keyword {
        name: "TIME STEP",
        sections: &[History],
        origin: Origin::Marc,
        meaning: "The time of each step of a static load case (s).",
        layout: &[("TIME STEP", ""), ("dt", "dt > 0 (s)")],
        notes: "A static load case needs both AUTO LOAD and TIME STEP.",
        example: "TIME STEP\n1.0",
        parse: parse_time_step,
    },
    Keyword {
        name: "MODAL SHAPE",
        sections: &[History],
        origin: Origin::Coil,
        meaning: "A modal load case: the lowest n eigenpairs of K phi = omega^2 M phi.",
        layout: &[("MODAL SHAPE", ""), ("n", "number of modes >= 1")],
        notes: "Marc takes the number of modes from its DYNAMIC parameter; coil reads it \
                here.",
        example: "MODAL SHAPE\n10",
        parse: parse_modal_shape,
    },
    Keyword {
        name: "DYNAMIC CHANGE",
        sections: &[History],
        origin: Origin::Coil,
        meaning: "A transient load case with fixed step dt up to the total time, by direct \
                  integration or modal superposition.",
        layout: &[
            ("DYNAMIC CHANGE", ""),
            (
                "dt, total[, method[, p]]",
                "dt > 0 (s), total >= dt (s); method NEWMARK (average acceleration, the \
                 default when omitted), HHT with p = alpha in [-1/3, 0], GALPHA with \
                 p = rho_inf in [0, 1], or MODAL with p = number of modes >= 1",
            ),
        ],
        notes: "dt and total are Marc's first two fields; the method fields are coil's own.",
        example: "DYNAMIC CHANGE\n1.0e-4, 0.5, HHT, -0.05",
        parse: parse_dynamic_change,
    },
    Keyword {
        name: "CONTINUE",
        sections: &[History],
        origin: Origin::Marc,
        meaning: "Closes the load case made of the history cards since the previous \
                  CONTINUE.",
        layout: &[("CONTINUE", "")],
        notes: "A load case needs exactly one analysis: AUTO LOAD with TIME STEP, MODAL \
                SHAPE, or DYNAMIC CHANGE.",
        example: "TITLE, modes\nMODAL SHAPE\n10\nCONTINUE",
        parse: parse_continue,
    },
    // ---- Cards of decks that Mentat writes (issue 12); parse functions in mentat.rs.
    Keyword {
        name: "EXTENDED",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Marc's extended fixed format: from the next line on, a line without a comma is cut in columns of 10 (integers) and 20 (reals, words).",
        layout: &[("EXTENDED", "")],
        notes: "The reader switches format when it splits the deck into lines (see Fixed format above).",
        example: "EXTENDED",
        parse: mentat::parse_not_needed_line,
    },
    Keyword {
        name: "ALLOC",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Marc's memory allocation.",
        layout: &[("ALLOC, n", "")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "ALLOC, 25",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "VERSION",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "The version of Marc's input format; 13 and later give each GEOMETRY block an id and a name line.",
        layout: &[("VERSION, n[, ...]", "")],
        notes: "Read; coil also recognises the GEOMETRY layout by its lines.",
        example: "VERSION, 11",
        parse: mentat::parse_version,
    },
    Keyword {
        name: "PROCESSOR",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Marc's processor and parallel options.",
        layout: &[("PROCESSOR, flags ...", "")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "PROCESSOR, 1, 1, 1, 0",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "ALL POINTS",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Marc's output at all integration points.",
        layout: &[("ALL POINTS", "")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "ALL POINTS",
        parse: mentat::parse_not_needed_line,
    },
    Keyword {
        name: "NO ECHO",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Marc's echo of the input in its output file.",
        layout: &[("NO ECHO, flags ...", "")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "NO ECHO, 1, 2, 3",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "SETNAME",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Marc's allocation of set names.",
        layout: &[("SETNAME, n", "")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "SETNAME, 9",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "SOLVER",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Marc's linear solver choice (coil chooses its own).",
        layout: &[("SOLVER", ""), ("type, flags ...", "integers")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "SOLVER\n8, 0, 0",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "OPTIMIZE",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Marc's bandwidth optimiser (coil orders its own unknowns).",
        layout: &[("OPTIMIZE, n[, ...]", "")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "OPTIMIZE, 11",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "NO PRINT",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Marc's printed output.",
        layout: &[("NO PRINT", "")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "NO PRINT",
        parse: mentat::parse_not_needed_line,
    },
    Keyword {
        name: "POST",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Marc's post file contents (coil writes its own result files).",
        layout: &[("POST", ""), ("flags ...", "integers; more lines may follow")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "POST\n0, 16, 17, 0",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "PARAMETERS",
        sections: &[Model, History],
        origin: Origin::Marc,
        meaning: "Marc's numerical constants (tolerances, physical constants).",
        layout: &[("PARAMETERS", ""), ("values ...", "lines of reals")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "PARAMETERS\n1.0, 1.0e9, 100.0",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "CONTROL",
        sections: &[Model, History],
        origin: Origin::Marc,
        meaning: "Marc's convergence control of nonlinear increments; a linear solve needs none.",
        layout: &[("CONTROL[, qualifier]", ""), ("flags ...", "integers"), ("tolerances ...", "reals")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "CONTROL\n99999, 10, 0\n0.1, 0.0",
        parse: mentat::parse_not_needed,
    },
    Keyword {
        name: "MAT COLOR",
        sections: &[Model],
        origin: Origin::Marc,
        meaning: "Mentat's colours of materials.",
        layout: &[("MAT COLOR", ""), ("", "a header line (often blank)"), ("id, ...", "integers")],
        notes: "Read and not needed: coil lists it once in the run's log.",
        example: "MAT COLOR\n\n1, 1, 230, 0, 0",
        parse: mentat::parse_mat_color,
    },
    Keyword {
        name: "LOADCASE",
        sections: &[Model, History],
        origin: Origin::Marc,
        meaning: "Mentat's list of the named loads and supports active in the model's own load case (model definition) or in the load case it appears in (history).",
        layout: &[("LOADCASE, name", ""), ("n", "number of active blocks"), ("name", "one line per block (FIXED DISP, POINT LOAD, DIST LOADS)")],
        notes: "A named POINT LOAD or DIST LOADS acts in a load case whose LOADCASE lists it (in every load case if no history LOADCASE is given). coil's supports are the same in every load case: a named FIXED DISP missing from a history LOADCASE is an error. The model definition's LOADCASE (Marc's increment 0) is read and checked for names.",
        example: "LOADCASE, lc1\n1\nclamp",
        parse: mentat::parse_loadcase,
    },
    Keyword {
        name: "BEAM SECT",
        sections: &[Parameters],
        origin: Origin::Marc,
        meaning: "Named beam cross-sections, numbered from 1 in their order, referred to by a GEOMETRY whose area is 0.",
        layout: &[("BEAM SECT", ""), ("name", "the section name"), ("0, type, dimensions", "type -2: a solid circle, dimension 1 its radius r (mm)"), ("n, ...", "integration points (not needed)"), ("LAST", "after the last section")],
        notes: "coil reads the solid circle (type -2, radius r: A = pi r^2, I = pi r^4 / 4, J = pi r^4 / 2, the polar moment, exact for a circle; shear coefficient 6(1+nu)/(7+6nu)). Other types are an error naming the type. The meaning of -2 and of its dimension (radius) is inferred from public Mentat decks, not from Marc's manual.",
        example: "BEAM SECT\nwire\n0, -2.0, 1.5\n5, 0, 0, 0\nLAST",
        parse: mentat::parse_beam_sect,
    },
    Keyword {
        name: "DIST LOADS",
        sections: &[Parameters, Model],
        origin: Origin::Marc,
        meaning: "As a parameter, Marc's allocation of distributed loads (not needed). In the model definition, Mentat's named blocks of a uniform load per unit length on beams, applied as the consistent nodal forces and moments of each element (qL/2 at each node, moments +-(L^2/12) e x q).",
        layout: &[("DIST LOADS", ""), ("", "a header line (blank)"), ("flags..., name", "integers then the block name; field 2 = 1 (FORCEM) is an error"), ("qx, qy, qz", "the load per unit length, global components (N/mm)"), ("0, 0, 0", "table ids, 0"), ("0, type", "load type 110 (a global load vector)"), ("1", "list kind 1: elements"), ("list", "the beams")],
        notes: "Only type 110 with three components is read (the layout of the corpus's beam deck, inferred, not from Marc's manual); every other type is an error naming it.",
        example: "DIST LOADS, 0, 0, 10",
        parse: mentat::parse_dist_loads,
    },
    Keyword {
        name: "LARGE STRAIN",
        sections: &[Parameters],
        origin: Origin::Unsupported,
        meaning: "Marc's large-strain (finite deformation) analysis.",
        layout: &[("LARGE STRAIN, ...", "")],
        notes: "coil solves small displacements and strains (linear analyses).",
        example: "LARGE STRAIN",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "LARGE DISP",
        sections: &[Parameters],
        origin: Origin::Unsupported,
        meaning: "Marc's large-displacement analysis.",
        layout: &[("LARGE DISP", "")],
        notes: "coil solves small displacements (linear analyses).",
        example: "LARGE DISP",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "UPDATE",
        sections: &[Parameters],
        origin: Origin::Unsupported,
        meaning: "Marc's updated Lagrange formulation.",
        layout: &[("UPDATE", "")],
        notes: "coil solves small displacements (linear analyses).",
        example: "UPDATE",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "FINITE",
        sections: &[Parameters],
        origin: Origin::Unsupported,
        meaning: "Marc's finite strain.",
        layout: &[("FINITE", "")],
        notes: "coil solves small strains (linear analyses).",
        example: "FINITE",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "FOLLOW FOR",
        sections: &[Parameters],
        origin: Origin::Unsupported,
        meaning: "Marc's follower forces.",
        layout: &[("FOLLOW FOR", "")],
        notes: "coil's loads keep their direction (linear analyses).",
        example: "FOLLOW FOR",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "PLASTICITY",
        sections: &[Parameters],
        origin: Origin::Unsupported,
        meaning: "Marc's plasticity procedure.",
        layout: &[("PLASTICITY, ...", "")],
        notes: "coil's materials are linear elastic.",
        example: "PLASTICITY",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "WORK HARD",
        sections: &[Model],
        origin: Origin::Unsupported,
        meaning: "Marc's work-hardening data of plastic materials.",
        layout: &[("WORK HARD, ...", "")],
        notes: "coil's materials are linear elastic.",
        example: "WORK HARD",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "FORCDT",
        sections: &[Model],
        origin: Origin::Unsupported,
        meaning: "Marc's user subroutine FORCDT (nodal loads and displacements computed by Fortran code).",
        layout: &[("FORCDT, n", ""), ("list", "nodes")],
        notes: "the user subroutine FORCDT is Fortran code coil cannot run; give the load as POINT LOAD values.",
        example: "FORCDT, 1",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "UMOTION",
        sections: &[Model],
        origin: Origin::Unsupported,
        meaning: "Marc's user subroutine UMOTION (rigid-surface motion).",
        layout: &[("UMOTION, n", "")],
        notes: "the user subroutine UMOTION is Fortran code coil cannot run.",
        example: "UMOTION, 0",
        parse: mentat::parse_unsupported,
    },
    Keyword {
        name: "USDATA",
        sections: &[Parameters, Model],
        origin: Origin::Unsupported,
        meaning: "Marc's user data for user subroutines.",
        layout: &[("USDATA, n", "")],
        notes: "user subroutines are Fortran code coil cannot run.",
        example: "USDATA, 1",
        parse: mentat::parse_unsupported,
    },
];

/// The keyword a line starts with, and how many fields its words take. The longest
/// keyword wins (`END OPTION` over `END`).
pub(crate) fn match_keyword(line: &Line) -> Option<(&'static Keyword, usize)> {
    let first = line.fields.first()?;
    if !first.text.starts_with(|c: char| c.is_ascii_alphabetic()) {
        return None;
    }
    // A fixed-format keyword field: its words, as Marc reads them (the first 10
    // characters count: `large stra` is LARGE STRAIN).
    let lead = (line.fixed.is_some() && line.lead_words > 0).then(|| {
        line.fields[..line.lead_words]
            .iter()
            .map(|f| f.text.to_ascii_uppercase())
            .collect::<Vec<_>>()
            .join(" ")
    });
    let mut best: Option<(&'static Keyword, usize, usize)> = None;
    for kw in KEYWORDS {
        let words: Vec<&str> = kw.name.split(' ').collect();
        let full = words.len() <= line.fields.len()
            && words
                .iter()
                .zip(&line.fields)
                .all(|(w, f)| f.text.eq_ignore_ascii_case(w));
        let cut = lead
            .as_deref()
            .is_some_and(|s| s.len() == 10 && kw.name.len() > 10 && kw.name.starts_with(s));
        let taken = if full {
            words.len()
        } else if cut {
            line.lead_words
        } else {
            continue;
        };
        if best.is_none_or(|(_, _, n)| words.len() > n) {
            best = Some((kw, taken, words.len()));
        }
    }
    best.map(|(kw, taken, _)| (kw, taken))
}

/// Up to `k` keywords nearest (by edit distance) to the line's first words: the best
/// match and any other within two edits of it.
pub(crate) fn nearest(words: &[&str], k: usize) -> Vec<&'static str> {
    let mut scored: Vec<(usize, &'static str)> = KEYWORDS
        .iter()
        .map(|kw| {
            // Compare a keyword of w words with the line's first w words.
            let w = kw.name.split(' ').count().min(words.len()).max(1);
            let candidate = words[..w.min(words.len())].join(" ").to_ascii_uppercase();
            (edit_distance(&candidate, kw.name), kw.name)
        })
        .collect();
    scored.sort();
    // Keep the close ones: within two edits of the best match.
    let best = scored.first().map_or(0, |s| s.0);
    scored
        .into_iter()
        .take_while(|(d, _)| *d <= best + 2)
        .take(k)
        .map(|(_, n)| n)
        .collect()
}

/// Levenshtein distance.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        cur[0] = i;
        for j in 1..=b.len() {
            let subst = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = subst.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// True if a set or table name would be read as something else: a keyword's first
/// word or a list word.
///
/// The first words of the multi-word keywords of coil's first deck language stay
/// reserved (`FIXED`, `POINT`, ...); those of Marc's further cards (`BEAM SECT`, `ALL
/// POINTS`, ...) are not, so that existing decks keep their set names: a list line
/// that spells a whole keyword is still refused where it is read.
pub(crate) fn is_reserved(name: &str) -> bool {
    const FIRST_WORDS: [&str; 11] = [
        "END",
        "FIXED",
        "POINT",
        "INITIAL",
        "HISTORY",
        "AUTO",
        "TIME",
        "MODAL",
        "DYNAMIC",
        "QUADRATIC",
        "CUBIC",
    ];
    let upper = name.to_ascii_uppercase();
    LIST_WORDS.contains(&upper.as_str())
        || FIRST_WORDS.contains(&upper.as_str())
        || KEYWORDS.iter().any(|kw| kw.name == upper)
}

// ---------------------------------------------------------------------------------
// Parse functions, one per card.

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

fn once(c: &CardCtx<'_, '_>, previous: Option<super::error::Loc>) -> Result<(), DeckError> {
    match previous {
        Some(first) => Err(c.err(
            c.loc(),
            format!(
                "a second {} (the first is at line {})",
                c.kw.name, first.line
            ),
            format!("one {}", c.kw.name),
        )),
        None => Ok(()),
    }
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
                lexer::parse_uint(t)
                    .map_err(|m| c.err(super::error::Loc::new(c.line.no, p + 1), m, WHAT))?
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

fn element_type(c: &CardCtx<'_, '_>, line: &Line, i: usize) -> Result<ElementType, DeckError> {
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

fn parse_end_option(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    c.deck.end_option = Some(c.loc());
    *c.section = History;
    Ok(())
}

/// True while another group is due: `n` groups if `n > 0`, else while data follows.
fn another(c: &mut CardCtx<'_, '_>, n: u64, done: u64) -> bool {
    if n > 0 {
        done < n
    } else {
        c.more_data()
    }
}

/// Reads a Marc header line whose first field is a count (blank = 0) and whose
/// further fields are integers coil does not use, starting at field `count_at`.
fn header_count(
    c: &mut CardCtx<'_, '_>,
    line: &Line,
    count_at: usize,
    what: &str,
) -> Result<u64, DeckError> {
    let n = c.uint_or(line, count_at, 0, what)?;
    for i in count_at + 1..line.fields.len() {
        c.uint_or(line, i, 0, "Marc's header flags: integers")?;
    }
    Ok(n)
}

/// Fails unless the keyword line has nothing after the keyword but, optionally, the
/// qualifier word Mentat writes (`isotropic           structural`).
fn qualifier(c: &CardCtx<'_, '_>, word: &str) -> Result<(), DeckError> {
    match c.args() {
        [q] if q.text.eq_ignore_ascii_case(word) => Ok(()),
        _ => c.no_args(),
    }
}

fn no_groups(c: &CardCtx<'_, '_>, layout: &str) -> DeckError {
    c.err(c.loc(), "the card has no data lines", layout)
}

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
    if is_reserved(&name) {
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

fn parse_isotropic(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const NAME_LINE: &str = "id, name";
    qualifier(c, "STRUCTURAL")?;
    let header = c.data_line("the number of materials (0 = until the next card)")?;
    if header.fixed.is_none() {
        c.field_count(header, 0, 1, "the number of materials")?;
    }
    let n = c.uint_or(header, 0, 0, "the number of materials")?;
    let n = if header.fixed.is_some() && header.fields.len() > 1 {
        0
    } else {
        n
    };
    let mut done = 0;
    while another(c, n, done) {
        let mentat = c.cur.peek_significant().is_some_and(|l| {
            l.fixed.is_some() && l.fields.len() > 2 && lexer::is_name(&l.fields[1].text)
        });
        if mentat {
            let material = mentat::isotropic_material(c)?;
            c.deck.materials.push(material);
            done += 1;
            continue;
        }
        let l = c.data_line(&format!("the line `{NAME_LINE}` of material {}", done + 1))?;
        c.field_count(l, 1, 2, NAME_LINE)?;
        let id = c.id(l, 0, "the material id")?;
        let name = match l.fields.get(1) {
            Some(f) if !f.text.is_empty() => c.name(l, 1, "the material name")?,
            _ => id.to_string(),
        };
        let [youngs_modulus, poisson, density] = material_values(c)?;
        let elements = c.list("the list of elements")?;
        c.deck.materials.push(RawMaterial {
            id,
            name,
            loc: l.start_loc(),
            youngs_modulus,
            poisson,
            density,
            elements,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(
            c,
            "a material: id, name / E, nu, density / elements",
        ));
    }
    Ok(())
}

/// The values line of a material, in coil's layout and Mentat's: `E, nu, density`
/// checked, Marc's further fields (thermal expansion, yield stress, ...) blank or 0.
pub(crate) fn material_values(c: &mut CardCtx<'_, '_>) -> Result<[f64; 3], DeckError> {
    const PROPS: &str = "E (MPa), Poisson's ratio, density (t/mm^3)";
    let p = c.data_line(PROPS)?;
    c.field_count(p, 3, usize::MAX, PROPS)?;
    let e = c.real(p, 0, "Young's modulus E (MPa)")?;
    let youngs_modulus = c.positive(e, p.loc_of(0), "Young's modulus E")?;
    let poisson = c.real(p, 1, "Poisson's ratio")?;
    if !(poisson > -1.0 && poisson < 0.5) {
        return Err(c.err(
            p.loc_of(1),
            format!("Poisson's ratio is {poisson:?}"),
            "-1 < Poisson's ratio < 0.5",
        ));
    }
    let rho = c.real(p, 2, "density (t/mm^3)")?;
    let density = c.non_negative(rho, p.loc_of(2), "density")?;
    c.zeros_from(
        p,
        3,
        "Marc's further material data (thermal expansion, yield stress, ...)",
    )?;
    Ok([youngs_modulus, poisson, density])
}

const SECTION_LINE: &str = "the section: wire diameter d, or A, I1, I2, J[, shear coefficient]";

fn parse_geometry(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let header = c.data_line("the number of geometries (0 = until the next card)")?;
    if header.fixed.is_none() {
        c.field_count(header, 0, 1, "the number of geometries")?;
    }
    let n = c.uint_or(header, 0, 0, "the number of geometries")?;
    let mut done = 0;
    while another(c, n, done) {
        // Mentat's blocks: a line of 6 or more values, or (version 13+) an integer
        // line before the name line; coil's own lines are shorter or free format.
        let mentat_block = c.cur.peek_significant().is_some_and(|l| {
            l.fixed.is_some()
                && (l.fields.len() >= 6
                    || (l.fields.len() >= 2
                        && l.fields.iter().all(|f| lexer::parse_uint(&f.text).is_ok())))
        });
        if mentat_block {
            let geometry = mentat::geometry_block(c)?;
            c.deck.geometries.push(geometry);
            done += 1;
            continue;
        }
        let first = c.data_line(&format!(
            "geometry {}: `id, name` or {SECTION_LINE}",
            done + 1
        ))?;
        let named = first.fields.len() == 2
            && !first.fields[1].text.is_empty()
            && !lexer::looks_numeric(&first.fields[1].text);
        let (id, name, s) = if named {
            let id = c.id(first, 0, "the geometry id")?;
            let name = c.name(first, 1, "the geometry name")?;
            (Some(id), name, c.data_line(SECTION_LINE)?)
        } else {
            (None, String::new(), first)
        };
        let (section, has_shear_coefficient) =
            match s.fields.len() {
                1 => {
                    let d = c.real(s, 0, "the wire diameter (mm)")?;
                    let diameter = c.positive(d, s.loc_of(0), "the wire diameter")?;
                    (Section::SolidCircle { diameter }, true)
                }
                4 | 5 => {
                    let mut v = [0.0; 5];
                    let names = [
                        "the area A",
                        "I1",
                        "I2",
                        "the torsion constant J",
                        "the shear coefficient",
                    ];
                    for (i, what) in names.iter().enumerate().take(s.fields.len()) {
                        let x = c.real(s, i, what)?;
                        v[i] = c.positive(x, s.loc_of(i), what)?;
                    }
                    let section = Section::General {
                        area: v[0],
                        iyy: v[1],
                        izz: v[2],
                        torsion: v[3],
                        shear_coefficient: v[4],
                    };
                    (section, s.fields.len() == 5)
                }
                k => return Err(c.err(
                    s.loc_of(0),
                    format!("a section line with {k} field{}", super::reader::plural(k)),
                    "1 field (wire diameter, mm) or 4-5 fields (A, I1, I2, J[, shear coefficient])",
                )),
            };
        let o = c.data_line("the orientation vector vx, vy, vz")?;
        c.field_count(o, 3, 3, "the orientation vector vx, vy, vz")?;
        let orientation = [
            c.real(o, 0, "vx")?,
            c.real(o, 1, "vy")?,
            c.real(o, 2, "vz")?,
        ];
        if orientation.iter().all(|&x| x == 0.0) {
            return Err(c.err(
                o.start_loc(),
                "the orientation vector is zero",
                "a non-zero vector",
            ));
        }
        let elements = c.list("the list of elements")?;
        c.deck.geometries.push(RawGeometry {
            id,
            name,
            loc: first.start_loc(),
            section,
            has_shear_coefficient,
            section_loc: s.start_loc(),
            orientation,
            orientation_loc: o.start_loc(),
            elements,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(
            c,
            "a geometry: [id, name] / section / orientation / elements",
        ));
    }
    Ok(())
}

fn parse_damping(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "alpha (1/s), beta (s)[, 1 if a line of point-mass nodes follows]";
    c.no_args()?;
    let mut done = 0;
    while c.more_data() {
        let l = c.data_line(LAYOUT)?;
        c.field_count(l, 2, 3, LAYOUT)?;
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
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, LAYOUT));
    }
    Ok(())
}

fn parse_point_mass(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "node, mass (t), Ixx, Iyy, Izz (t mm^2)";
    c.no_args()?;
    let mut done = 0;
    while c.more_data() {
        let l = c.data_line(LAYOUT)?;
        c.field_count(l, 5, 5, LAYOUT)?;
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
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, LAYOUT));
    }
    Ok(())
}

fn parse_friction(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    parse_point_law(c, PointLawKind::Friction)
}

fn parse_quadratic_damper(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    parse_point_law(c, PointLawKind::Quadratic)
}

fn parse_cubic_spring(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    parse_point_law(c, PointLawKind::Cubic)
}

/// `node, dof, value` lines of the nonlinear point cards.
fn parse_point_law(c: &mut CardCtx<'_, '_>, kind: PointLawKind) -> Result<(), DeckError> {
    let layout = kind.layout();
    c.no_args()?;
    let mut done = 0;
    while c.more_data() {
        let l = c.data_line(layout)?;
        c.field_count(l, 3, 3, layout)?;
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
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, layout));
    }
    Ok(())
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

/// Groups of `values / DOFs / nodes` (FIXED DISP, INITIAL VEL); the keyword line's
/// options are checked by the caller.
fn dof_value_groups(
    c: &mut CardCtx<'_, '_>,
    value: &str,
    quasi_static: bool,
) -> Result<Vec<RawDofValues>, DeckError> {
    let mut groups = Vec::new();
    while c.more_data() {
        let v = c.data_line(value)?;
        c.field_count(v, 1, 6, &format!("1 to 6 fields: {value}"))?;
        let mut values = Vec::new();
        for i in 0..v.fields.len() {
            values.push(c.real(v, i, value)?);
        }
        let n = values.len();
        let d = c.data_line(&format!(
            "{n} DOF number{}, one per value on line {}",
            super::reader::plural(n),
            v.no
        ))?;
        c.field_count(
            d,
            n,
            n,
            &format!(
                "{n} DOF number{}, one per value on line {}",
                super::reader::plural(n),
                v.no
            ),
        )?;
        let dofs = c.dofs(d, 0)?;
        let nodes = c.list("the list of nodes")?;
        if nodes.items.is_empty() {
            return Err(c.err(nodes.loc, "the node list is empty", "the list of nodes"));
        }
        groups.push(RawDofValues {
            dofs: dofs.into_iter().zip(values).collect(),
            loc: v.start_loc(),
            nodes,
            quasi_static,
        });
    }
    if groups.is_empty() {
        return Err(no_groups(c, &format!("{value} / DOFs / nodes")));
    }
    Ok(groups)
}

fn parse_fixed_disp(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    if mentat::blank_header_follows(c) {
        let groups = mentat::fixed_disp(c)?;
        if !groups.is_empty() {
            c.deck.fixed_disp.extend(groups);
            return Ok(());
        }
    }
    let groups = dof_value_groups(c, "prescribed values (mm or rad)", false)?;
    c.deck.fixed_disp.extend(groups);
    Ok(())
}

fn parse_initial_vel(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    let args = c.args();
    let quasi_static = match args {
        [] => false,
        [a, b] if a.text.eq_ignore_ascii_case("QUASI") && b.text.eq_ignore_ascii_case("STATIC") => {
            true
        }
        _ => {
            return Err(c.err(
                c.arg_loc(0),
                format!("unexpected `{}` after INITIAL VEL", args[0].text),
                "INITIAL VEL alone or INITIAL VEL, QUASI STATIC",
            ))
        }
    };
    let groups = dof_value_groups(c, "initial velocities (mm/s or rad/s)", quasi_static)?;
    c.deck.initial_velocities.extend(groups);
    Ok(())
}

fn parse_point_load(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const VALUES: &str = "the load in DOF order: Fx, Fy, Fz (N), Mx, My, Mz (N mm)";
    // Mentat's history layout: `point load 0` (an integer after the keyword).
    if *c.section == History
        && c.line.fixed.is_some()
        && c.args()
            .first()
            .is_some_and(|f| lexer::parse_uint(&f.text).is_ok())
    {
        return mentat::history_point_load(c);
    }
    if *c.section == Model && c.args().is_empty() && mentat::blank_header_follows(c) {
        return mentat::point_load_blocks(c);
    }
    let args = c.args();
    let table = match args.len() {
        0 => None,
        2 if args[0].text.eq_ignore_ascii_case("TABLE") => Some((
            c.name(c.line, c.kw_fields + 1, "the table name")?,
            c.arg_loc(1),
        )),
        _ => {
            return Err(c.err(
                c.arg_loc(0),
                format!("unexpected `{}` after POINT LOAD", args[0].text),
                "POINT LOAD alone or POINT LOAD, TABLE, name",
            ))
        }
    };
    let mut loads = Vec::new();
    while c.more_data() {
        let v = c.data_line(VALUES)?;
        c.field_count(v, 1, 6, VALUES)?;
        let mut dofs = Vec::new();
        for i in 0..v.fields.len() {
            let x = c.real(v, i, VALUES)?;
            if x != 0.0 {
                dofs.push((i as u8 + 1, x));
            }
        }
        let nodes = c.list("the list of nodes")?;
        if nodes.items.is_empty() {
            return Err(c.err(nodes.loc, "the node list is empty", "the list of nodes"));
        }
        loads.push(RawPointLoad {
            dofs,
            loc: v.start_loc(),
            nodes,
            table: table.clone(),
        });
    }
    if loads.is_empty() {
        return Err(no_groups(c, "load values / nodes"));
    }
    if *c.section == History {
        c.case().point_loads.extend(loads);
    } else {
        c.deck.point_loads.extend(loads);
    }
    Ok(())
}

fn parse_table(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const POINT: &str = "time (s), factor";
    if *c.section == Parameters {
        return mentat::parse_not_needed(c);
    }
    if c.args().len() != 1 {
        let loc = c.arg_loc(c.args().len().min(1));
        return Err(c.err(loc, "TABLE needs exactly one name", "TABLE, name"));
    }
    let name = c.name(c.line, c.kw_fields, "the table name")?;
    if is_reserved(&name) {
        return Err(c.err(
            c.arg_loc(0),
            format!("`{name}` cannot name a table: it is a keyword or a list word"),
            "another name",
        ));
    }
    let mut points: Vec<(f64, f64)> = Vec::new();
    let mentat = c.cur.peek_significant().is_some_and(|l| {
        l.fixed.is_some()
            && l.fields.len() >= 3
            && l.fields.iter().all(|f| lexer::parse_uint(&f.text).is_ok())
    });
    let expected = if mentat {
        Some(mentat::table_header(c)?)
    } else {
        None
    };
    while c.more_data() && expected.is_none_or(|n| points.len() < n) {
        let l = c.data_line(POINT)?;
        c.field_count(l, 2, 2, POINT)?;
        let t = c.real(l, 0, "the time (s)")?;
        let f = c.real(l, 1, "the factor")?;
        if let Some(&(prev, _)) = points.last() {
            if t <= prev {
                return Err(c.err(
                    l.loc_of(0),
                    format!("time {t:?} does not increase on the previous point's {prev:?}"),
                    "strictly increasing times",
                ));
            }
        }
        points.push((t, f));
    }
    if points.is_empty() {
        return Err(no_groups(c, POINT));
    }
    if let Some(n) = expected.filter(|&n| n != points.len()) {
        return Err(c.err(
            c.loc(),
            format!("the table has {} points, its header says {n}", points.len()),
            "as many `time, factor` lines as the header's last field",
        ));
    }
    c.deck.tables.push(RawTable {
        name,
        loc: c.loc(),
        points,
    });
    Ok(())
}

fn quantity(word: &str) -> Option<Quantity> {
    match word.to_ascii_uppercase().as_str() {
        "DISP" | "DISPLACEMENT" => Some(Quantity::Displacement),
        "VEL" | "VELOCITY" => Some(Quantity::Velocity),
        "ACCEL" | "ACCELERATION" => Some(Quantity::Acceleration),
        _ => None,
    }
}

fn parse_history_output(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const QUANTITIES: &str = "quantities: DISP, VEL and/or ACCEL";
    c.no_args()?;
    let mut done = 0;
    while c.more_data() {
        let e = c.data_line("every k-th step")?;
        c.field_count(e, 1, 1, "every k-th step (k >= 1)")?;
        let every = c.count(e, 0, 1, "every k-th step")?;
        let q = c.data_line(QUANTITIES)?;
        c.field_count(q, 1, 3, QUANTITIES)?;
        let mut quantities = Vec::new();
        for (i, f) in q.fields.iter().enumerate() {
            let Some(x) = quantity(&f.text) else {
                return Err(c.err(
                    q.loc_of(i),
                    format!("`{}` is not a quantity", f.text),
                    QUANTITIES,
                ));
            };
            if quantities.contains(&x) {
                return Err(c.err(
                    q.loc_of(i),
                    format!("`{}` is listed twice", f.text),
                    QUANTITIES,
                ));
            }
            quantities.push(x);
        }
        let d = c.data_line("the DOF numbers (1..6)")?;
        let dofs = c.dofs(d, 0)?;
        let nodes = c.list("the list of nodes")?;
        if nodes.items.is_empty() {
            return Err(c.err(nodes.loc, "the node list is empty", "the list of nodes"));
        }
        c.deck.outputs.push(RawOutput {
            every,
            loc: e.start_loc(),
            quantities,
            dofs,
            nodes,
        });
        done += 1;
    }
    if done == 0 {
        return Err(no_groups(c, "k / quantities / DOFs / nodes"));
    }
    Ok(())
}

/// The analysis a history card implies: static, modal or transient.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Static,
    Modal,
    Transient,
}

/// Fails if the open load case already has a card of another analysis kind.
fn one_analysis(c: &mut CardCtx<'_, '_>, kind: Kind) -> Result<(), DeckError> {
    let case = c.case();
    let others = [
        (Kind::Static, case.auto_load.map(|a| a.1), "AUTO LOAD"),
        (Kind::Static, case.time_step.map(|a| a.1), "TIME STEP"),
        (Kind::Modal, case.modal.map(|a| a.1), "MODAL SHAPE"),
        (Kind::Transient, case.dynamic.map(|a| a.3), "DYNAMIC CHANGE"),
    ];
    for (k, loc, name) in others {
        if let (true, Some(loc)) = (k != kind, loc) {
            return Err(c.err(
                c.loc(),
                format!("this load case already has {name} (line {})", loc.line),
                "one analysis per load case (close it with CONTINUE first)",
            ));
        }
    }
    Ok(())
}

fn parse_auto_load(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let previous = c.case().auto_load.map(|a| a.1);
    once(c, previous)?;
    one_analysis(c, Kind::Static)?;
    let l = c.data_line("the number of steps")?;
    let steps = c.count(l, 0, 1, "the number of steps")?;
    // Marc's further fields (Mentat writes `n 0 10`) control nonlinear increments,
    // which change nothing in a linear solve: integers, not used.
    for i in 1..l.fields.len() {
        c.uint_or(l, i, 0, "Marc's further AUTO LOAD fields: integers")?;
    }
    let loc = c.loc();
    c.case().auto_load = Some((steps, loc));
    Ok(())
}

fn parse_time_step(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let previous = c.case().time_step.map(|a| a.1);
    once(c, previous)?;
    one_analysis(c, Kind::Static)?;
    let l = c.data_line("the time step (s)")?;
    c.field_count(l, 1, 1, "the time step (s)")?;
    let dt = c.real(l, 0, "the time step (s)")?;
    let dt = c.positive(dt, l.loc_of(0), "the time step")?;
    let loc = c.loc();
    c.case().time_step = Some((dt, loc));
    Ok(())
}

fn parse_modal_shape(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let previous = c.case().modal.map(|a| a.1);
    once(c, previous)?;
    one_analysis(c, Kind::Modal)?;
    let l = c.data_line("the number of modes")?;
    c.field_count(l, 1, 1, "the number of modes")?;
    let modes = c.count(l, 0, 1, "the number of modes")?;
    let loc = c.loc();
    c.case().modal = Some((modes, loc));
    Ok(())
}

fn parse_dynamic_change(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    const LAYOUT: &str = "dt, total time[, NEWMARK | HHT, alpha | GALPHA, rho_inf | MODAL, modes]";
    c.no_args()?;
    let previous = c.case().dynamic.map(|a| a.3);
    once(c, previous)?;
    one_analysis(c, Kind::Transient)?;
    let l = c.data_line(LAYOUT)?;
    c.field_count(l, 2, 4, LAYOUT)?;
    let dt = c.real(l, 0, "the time step dt (s)")?;
    let dt = c.positive(dt, l.loc_of(0), "the time step dt")?;
    let total = c.real(l, 1, "the total time (s)")?;
    if total < dt {
        return Err(c.err(
            l.loc_of(1),
            format!("the total time {total:?} is shorter than the time step {dt:?}"),
            "total time >= dt",
        ));
    }
    let method = match l.fields.get(2).map(|f| f.text.to_ascii_uppercase()) {
        None => TransientMethod::Direct(Integrator::AverageAcceleration),
        Some(m) => {
            let param_needed = m != "NEWMARK";
            let n = if param_needed { 4 } else { 3 };
            c.field_count(l, n, n, LAYOUT)?;
            match m.as_str() {
                "NEWMARK" => TransientMethod::Direct(Integrator::AverageAcceleration),
                "HHT" => {
                    let alpha = c.real(l, 3, "HHT alpha")?;
                    if !((-1.0 / 3.0..=0.0).contains(&alpha)) {
                        return Err(c.err(
                            l.loc_of(3),
                            format!("HHT alpha is {alpha:?}"),
                            "-1/3 <= alpha <= 0",
                        ));
                    }
                    TransientMethod::Direct(Integrator::Hht { alpha })
                }
                "GALPHA" => {
                    let rho_inf = c.real(l, 3, "rho_inf")?;
                    if !((0.0..=1.0).contains(&rho_inf)) {
                        return Err(c.err(
                            l.loc_of(3),
                            format!("rho_inf is {rho_inf:?}"),
                            "0 <= rho_inf <= 1",
                        ));
                    }
                    TransientMethod::Direct(Integrator::GeneralizedAlpha { rho_inf })
                }
                "MODAL" => TransientMethod::Modal {
                    modes: c.count(l, 3, 1, "the number of modes")?,
                },
                _ => {
                    return Err(c.err(
                        l.loc_of(2),
                        format!("`{}` is not a transient method", l.fields[2].text),
                        "NEWMARK, HHT, GALPHA or MODAL",
                    ))
                }
            }
        }
    };
    let loc = c.loc();
    c.case().dynamic = Some((dt, total, method, loc));
    Ok(())
}

fn parse_continue(c: &mut CardCtx<'_, '_>) -> Result<(), DeckError> {
    c.no_args()?;
    let loc = c.loc();
    let Some(mut case) = c.deck.open_case.take() else {
        return Err(c.err(
            loc,
            "CONTINUE closes no load case",
            "history cards (TITLE, AUTO LOAD, TIME STEP, MODAL SHAPE, DYNAMIC CHANGE, POINT LOAD) before CONTINUE",
        ));
    };
    let begun = case.loc.map_or(loc.line, |l| l.line);
    let static_parts = (case.auto_load.is_some(), case.time_step.is_some());
    let message = match static_parts {
        (true, false) => Some("the static load case has AUTO LOAD but no TIME STEP"),
        (false, true) => Some("the static load case has TIME STEP but no AUTO LOAD"),
        (false, false) if case.modal.is_none() && case.dynamic.is_none() => {
            Some("the load case has no analysis")
        }
        _ => None,
    };
    if let Some(m) = message {
        return Err(c.err(
            loc,
            format!("{m} (load case begun at line {begun})"),
            "AUTO LOAD with TIME STEP, MODAL SHAPE, or DYNAMIC CHANGE",
        ));
    }
    case.end = Some(loc);
    c.deck.load_cases.push(case);
    Ok(())
}

// ---------------------------------------------------------------------------------
// The deck reference, generated from the table.

/// The card reference of docs/deck.md, generated from [`KEYWORDS`].
pub fn reference_markdown() -> String {
    let mut s = String::new();
    s.push_str("| Card | Sections | Layout | Keyword line | Data lines |\n");
    s.push_str("|---|---|---|---|---|\n");
    for kw in KEYWORDS {
        let lines: Vec<String> = kw
            .layout
            .iter()
            .skip(1)
            .map(|(f, _)| format!("`{f}`"))
            .collect();
        s.push_str(&format!(
            "| [`{}`](#{}) | {} | {} | `{}` | {} |\n",
            kw.name,
            anchor(kw.name),
            sections_text(kw),
            origin_text(kw.origin),
            kw.layout.first().map_or(kw.name, |l| l.0),
            if lines.is_empty() {
                "none".to_string()
            } else {
                lines.join(" / ")
            },
        ));
    }
    for kw in KEYWORDS {
        s.push_str(&format!("\n### {}\n\n", kw.name));
        s.push_str(&format!(
            "*{}* · {}\n\n{}\n\n",
            match kw.origin {
                Origin::Marc => "Layout of public Marc decks",
                Origin::Coil => "coil's own definition",
                Origin::Unsupported => "Marc's card, not supported: reading it is an error",
            },
            sections_text(kw),
            kw.meaning
        ));
        s.push_str("| Line | Fields | Meaning |\n|---|---|---|\n");
        for (i, (fields, meaning)) in kw.layout.iter().enumerate() {
            s.push_str(&format!("| {} | `{}` | {} |\n", i + 1, fields, meaning));
        }
        if !kw.notes.is_empty() {
            s.push_str(&format!("\n{}\n", kw.notes));
        }
        s.push_str(&format!("\n```text\n{}\n```\n", kw.example));
    }
    s
}

fn sections_text(kw: &Keyword) -> String {
    kw.sections
        .iter()
        .map(|s| s.describe())
        .collect::<Vec<_>>()
        .join(", ")
}

fn origin_text(o: Origin) -> &'static str {
    match o {
        Origin::Marc => "Marc",
        Origin::Coil => "**coil's own**",
        Origin::Unsupported => "Marc, **error**",
    }
}

fn anchor(name: &str) -> String {
    name.to_ascii_lowercase().replace(' ', "-")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::lexer::lex;
    use crate::deck::read_str;
    use crate::deck::reader::read_cards;
    use crate::model::Model;

    fn first_line(text: &str) -> Line {
        lex(text).unwrap().remove(0)
    }

    #[test]
    fn no_two_keywords_collide() {
        for (i, a) in KEYWORDS.iter().enumerate() {
            assert_eq!(
                a.name,
                a.name.to_ascii_uppercase(),
                "{} is not upper case",
                a.name
            );
            assert!(
                !a.name.contains("  ") && a.name.trim() == a.name,
                "{}",
                a.name
            );
            assert!(!a.sections.is_empty(), "{}", a.name);
            for b in &KEYWORDS[i + 1..] {
                assert_ne!(a.name, b.name, "keyword {} is defined twice", a.name);
                // Marc reads 10 characters of a keyword: cut, no two may be equal.
                let cut = |n: &str| n.chars().take(10).collect::<String>();
                assert_ne!(
                    cut(a.name),
                    cut(b.name),
                    "{} and {} collide when cut to 10 characters",
                    a.name,
                    b.name
                );
            }
            // Every keyword, in any case, reads as itself and nothing else.
            let line = first_line(&format!("{}, 1", a.name.to_ascii_lowercase()));
            let (kw, n) = match_keyword(&line).unwrap();
            assert_eq!(kw.name, a.name);
            assert_eq!(n, a.name.split(' ').count());
            assert!(!LIST_WORDS.contains(&a.name), "{} is a list word", a.name);
        }
    }

    #[test]
    fn the_longest_keyword_wins() {
        assert_eq!(
            match_keyword(&first_line("END OPTION")).unwrap().0.name,
            "END OPTION"
        );
        assert_eq!(match_keyword(&first_line("end")).unwrap().0.name, "END");
        assert_eq!(
            match_keyword(&first_line("Point Load, table, t"))
                .unwrap()
                .0
                .name,
            "POINT LOAD"
        );
        assert!(match_keyword(&first_line("POINT, 1")).is_none());
        assert!(match_keyword(&first_line("1, 2")).is_none());
    }

    #[test]
    fn nearest_keywords_by_edit_distance() {
        assert_eq!(nearest(&["FIXED", "DSP"], 1), ["FIXED DISP"]);
        assert_eq!(nearest(&["CONECTIVITY"], 1), ["CONNECTIVITY"]);
        assert_eq!(nearest(&["isotropik"], 1), ["ISOTROPIC"]);
        assert_eq!(nearest(&["ENDOPTION"], 1), ["END OPTION"]);
        assert_eq!(nearest(&["POINT", "LAOD", "1"], 1), ["POINT LOAD"]);
        assert!(!nearest(&["x"], 3).is_empty());
        assert!(nearest(&["x"], 3).len() <= 3);
    }

    #[test]
    fn reserved_names() {
        assert!(is_reserved("end"));
        assert!(is_reserved("Point"));
        assert!(is_reserved("to"));
        assert!(!is_reserved("clamp"));
    }

    /// Every example in the table reads as a card in its section.
    #[test]
    fn every_example_parses_in_its_section() {
        for kw in KEYWORDS {
            let lines = lex(kw.example).unwrap();
            let r = read_cards(&lines, "example", kw.sections[0], false);
            if kw.origin == Origin::Unsupported {
                let e = r.unwrap_err().to_string();
                assert!(e.contains(":1:1:") && e.contains("is not supported"), "{e}");
            } else {
                assert!(r.is_ok(), "{}: {}", kw.name, r.unwrap_err());
            }
        }
    }

    // A small but complete deck to embed one card's test in.
    const PARAMS: &str = "TITLE, t\nELEMENTS, 98\nEND\n";
    const MESH: &str = "COORDINATES\n3, 3\n1, 0, 0, 0\n2, 50, 0, 0\n3, 100, 0, 0\n\
        CONNECTIVITY\n0\n1, 98, 1, 2\n2, 98, 2, 3\n\
        DEFINE, ELEMENT, SET, wire\n1 TO 2\n\
        ISOTROPIC\n1\n1, steel\n2.0e5, 0.3, 7.85e-9\nwire\n\
        GEOMETRY\n1\n3.0\n0, 0, 1\nwire\n\
        FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1\n";
    const STATIC: &str = "END OPTION\nAUTO LOAD\n1\nTIME STEP\n1.0\nCONTINUE\n";

    fn with_model(extra: &str) -> Result<Model, DeckError> {
        read_str(&format!("{PARAMS}{MESH}{extra}{STATIC}"), "t.dat")
    }

    fn err_with_model(extra: &str) -> String {
        with_model(extra).unwrap_err().to_string()
    }

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

    #[test]
    fn isotropic_values_are_checked() {
        let m = with_model("").unwrap();
        assert_eq!(m.materials[0].name, "steel");
        assert_eq!(m.materials[0].youngs_modulus, 2.0e5);
        assert_eq!(m.materials[0].elements, [1, 2]);
        for (bad, what) in [
            ("0.0, 0.3, 7.85e-9", "Young's modulus"),
            ("2e5, 0.5, 0", "Poisson"),
            ("2e5, -1, 0", "Poisson"),
            ("2e5, 0.3, -1e-9", "density"),
            ("2e5, 0.3, 0, 1.2e-5", "thermal expansion"),
        ] {
            let deck = format!(
                "{PARAMS}{}{STATIC}",
                MESH.replace("2.0e5, 0.3, 7.85e-9", bad)
            );
            let e = read_str(&deck, "t.dat").unwrap_err().to_string();
            assert!(e.contains(":18:") && e.contains(what), "{bad}: {e}");
        }
    }

    #[test]
    fn geometry_forms() {
        let m = with_model("").unwrap();
        assert_eq!(
            m.geometries[0].section,
            Section::SolidCircle { diameter: 3.0 }
        );
        assert_eq!(m.geometries[0].name, "");
        let general = MESH.replace(
            "GEOMETRY\n1\n3.0\n",
            "GEOMETRY\n1\n7, g\n7.0, 4.0, 5.0, 9.0, 0.9\n",
        );
        let m = read_str(&format!("{PARAMS}{general}{STATIC}"), "t.dat").unwrap();
        assert_eq!(m.geometries[0].name, "g");
        assert_eq!(
            m.geometries[0].section,
            Section::General {
                area: 7.0,
                iyy: 4.0,
                izz: 5.0,
                torsion: 9.0,
                shear_coefficient: 0.9
            }
        );
        // Without kappa a type-98 element has no shear coefficient.
        let no_kappa = MESH.replace("GEOMETRY\n1\n3.0\n", "GEOMETRY\n1\n7.0, 4.0, 5.0, 9.0\n");
        let e = read_str(&format!("{PARAMS}{no_kappa}{STATIC}"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("shear coefficient"), "{e}");
        let parallel = MESH.replace("0, 0, 1\nwire", "2, 0, 0\nwire");
        let e = read_str(&format!("{PARAMS}{parallel}{STATIC}"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("parallel"), "{e}");
    }

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

    #[test]
    fn loads_tables_velocities_outputs() {
        let m = with_model(
            "TABLE, ramp\n0, 0\n1, 1\nPOINT LOAD, TABLE, ramp\n0, 0, -10, 0, 5\n3\nINITIAL VEL\n-100, 2\n3, 1\n3\nHISTORY OUTPUT\n10\nDISP, ACCEL\n3, 1\n2 TO 3\n",
        )
        .unwrap();
        assert_eq!(m.point_loads[0].dofs, [(3, -10.0), (5, 5.0)]);
        assert_eq!(m.point_loads[0].table.as_deref(), Some("ramp"));
        assert_eq!(m.tables[0].points, [(0.0, 0.0), (1.0, 1.0)]);
        assert_eq!(m.initial_velocities[0].dofs, [(3, -100.0), (1, 2.0)]);
        assert!(!m.initial_velocities[0].quasi_static);
        let qs =
            with_model("INITIAL VEL, quasi static\n-100\n3\n3\nINITIAL VEL\n2\n1\n3\n").unwrap();
        assert!(qs.initial_velocities[0].quasi_static);
        assert!(!qs.initial_velocities[1].quasi_static);
        let e = err_with_model("INITIAL VEL, QUASI\n-100\n3\n3\n");
        assert!(e.contains("INITIAL VEL, QUASI STATIC"), "{e}");
        assert_eq!(m.outputs[0].every, 10);
        assert_eq!(
            m.outputs[0].quantities,
            [Quantity::Displacement, Quantity::Acceleration]
        );
        assert_eq!(m.outputs[0].dofs, [3, 1]);
        assert_eq!(m.outputs[0].nodes, [2, 3]);
        let e = err_with_model("TABLE, t\n1, 0\n1, 1\n");
        assert!(e.contains("does not increase"), "{e}");
        let e = err_with_model("POINT LOAD, TABLE, nope\n1\n3\n");
        assert!(e.contains("no table named `nope`"), "{e}");
        let e = err_with_model("FIXED DISP\n0, 0\n1, 7\n2\n");
        assert!(e.contains("DOF 7 does not exist"), "{e}");
    }

    #[test]
    fn load_cases_of_every_kind() {
        let history =
            "END OPTION\nTITLE, s\nAUTO LOAD\n2\nTIME STEP\n0.5\nPOINT LOAD\n1\n3\nCONTINUE\n\
            MODAL SHAPE\n4\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1, HHT, -0.1\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1, GALPHA, 0.8\nCONTINUE\n\
            DYNAMIC CHANGE\n1e-3, 0.1, MODAL, 6\nCONTINUE\n";
        let m = read_str(&format!("{PARAMS}{MESH}{history}"), "t.dat").unwrap();
        use crate::model::Analysis;
        let a: Vec<&Analysis> = m.load_cases.iter().map(|c| &c.analysis).collect();
        assert_eq!(
            *a[0],
            Analysis::Static {
                steps: 2,
                time: 0.5
            }
        );
        assert_eq!(m.load_cases[0].point_loads[0].dofs, [(1, 1.0)]);
        assert_eq!(*a[1], Analysis::Modal { modes: 4 });
        let direct = |i| Analysis::Transient {
            dt: 1e-3,
            total_time: 0.1,
            method: TransientMethod::Direct(i),
        };
        assert_eq!(*a[2], direct(Integrator::AverageAcceleration));
        assert_eq!(*a[3], direct(Integrator::Hht { alpha: -0.1 }));
        assert_eq!(*a[4], direct(Integrator::GeneralizedAlpha { rho_inf: 0.8 }));
        assert_eq!(
            *a[5],
            Analysis::Transient {
                dt: 1e-3,
                total_time: 0.1,
                method: TransientMethod::Modal { modes: 6 }
            }
        );
        for (bad, what) in [
            ("AUTO LOAD\n1\nCONTINUE\n", "no TIME STEP"),
            ("MODAL SHAPE\n2\nAUTO LOAD\n1\n", "already has MODAL SHAPE"),
            ("CONTINUE\n", "closes no load case"),
            ("DYNAMIC CHANGE\n1e-3, 0.1, HHT, 0.5\n", "HHT alpha"),
            ("DYNAMIC CHANGE\n1e-3, 1e-4\n", "shorter than the time step"),
            (
                "DYNAMIC CHANGE\n1e-3, 0.1, RK4, 1\n",
                "not a transient method",
            ),
            ("MODAL SHAPE\n0\n", "at least 1"),
            ("TITLE, x\n", "CONTINUE"),
        ] {
            let e = read_str(&format!("{PARAMS}{MESH}END OPTION\n{bad}"), "t.dat")
                .unwrap_err()
                .to_string();
            assert!(e.contains(what), "{bad}: {e}");
        }
    }

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

    #[test]
    fn sections_are_enforced() {
        let e = read_str("CONNECTIVITY\n0\n", "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.dat:1:1: `CONNECTIVITY` is a model-definition card, but the parameter section has not ended"), "{e}");
        let e = read_str(&format!("{PARAMS}{MESH}AUTO LOAD\n1\n"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("history card, but the model definition has not ended"),
            "{e}"
        );
        let e = read_str(&format!("{PARAMS}{MESH}END OPTION\nCOORDINATES\n"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`COORDINATES` belongs to the model definition, which has already ended"),
            "{e}"
        );
        let e = read_str(&format!("{PARAMS}ELEMENTS, 52\n"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("already ended (END at line 3)"), "{e}");
    }
}
