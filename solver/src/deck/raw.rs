//! The deck as read, before validation: every value with the location it came from,
//! lists not yet resolved to ids. The card parsers in [`super::keywords`] fill it;
//! [`super::build`] turns it into a [`crate::model::Model`].

use super::error::Loc;
use super::lexer::ListItem;
use crate::model::{ElementType, Quantity, Section, TransientMethod};

/// An unresolved node or element list: items with their locations, and where the list
/// starts (for errors about the list as a whole).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawList {
    pub items: Vec<(ListItem, Loc)>,
    pub loc: Loc,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SetKind {
    Node,
    Element,
}

impl SetKind {
    pub fn word(self) -> &'static str {
        match self {
            SetKind::Node => "node",
            SetKind::Element => "element",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawNode {
    pub id: u32,
    pub xyz: [f64; 3],
    pub loc: Loc,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawElement {
    pub id: u32,
    pub kind: ElementType,
    pub type_loc: Loc,
    pub nodes: [(u32, Loc); 2],
    pub loc: Loc,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawSet {
    pub kind: SetKind,
    pub name: String,
    pub loc: Loc,
    pub list: RawList,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawMaterial {
    pub id: u32,
    pub name: String,
    pub loc: Loc,
    pub youngs_modulus: f64,
    pub poisson: f64,
    pub density: f64,
    pub elements: RawList,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawGeometry {
    /// `(id, name)` from the optional name line.
    pub id: Option<u32>,
    pub name: String,
    pub loc: Loc,
    pub section: Section,
    /// False when a general section omitted the shear coefficient (type 52 only).
    pub has_shear_coefficient: bool,
    pub section_loc: Loc,
    pub orientation: [f64; 3],
    pub orientation_loc: Loc,
    pub elements: RawList,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawDamping {
    pub alpha: f64,
    pub beta: f64,
    pub loc: Loc,
    pub elements: RawList,
    pub mass_nodes: Option<RawList>,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawPointMass {
    pub node: u32,
    pub node_loc: Loc,
    pub mass: f64,
    pub inertia: [f64; 3],
}

/// Which nonlinear point card a line came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum PointLawKind {
    Friction,
    Quadratic,
    Cubic,
    /// `DASHPOT`: linear, so it goes to the model's dashpots, not its laws.
    Dashpot,
}

impl PointLawKind {
    pub fn card(self) -> &'static str {
        match self {
            PointLawKind::Friction => "FRICTION",
            PointLawKind::Quadratic => "QUADRATIC DAMPER",
            PointLawKind::Cubic => "CUBIC SPRING",
            PointLawKind::Dashpot => "DASHPOT",
        }
    }

    /// The value's name in error messages.
    pub fn what(self) -> &'static str {
        match self {
            PointLawKind::Friction => "the friction force (N)",
            PointLawKind::Quadratic => "c2 (N s^2/mm^2)",
            PointLawKind::Cubic => "k3 (N/mm^3)",
            PointLawKind::Dashpot => "c (N s/mm)",
        }
    }

    pub fn layout(self) -> &'static str {
        match self {
            PointLawKind::Friction => "node, dof, friction force (N)",
            PointLawKind::Quadratic => "node, dof, c2 (N s^2/mm^2)",
            PointLawKind::Cubic => "node, dof, k3 (N/mm^3)",
            PointLawKind::Dashpot => "node, dof, c (N s/mm)",
        }
    }
}

/// One line of `FRICTION`, `QUADRATIC DAMPER` or `CUBIC SPRING`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawPointLaw {
    pub kind: PointLawKind,
    pub node: u32,
    pub loc: Loc,
    pub node_loc: Loc,
    pub dof: u8,
    pub dof_loc: Loc,
    pub value: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawTie {
    pub id: u32,
    pub name: String,
    pub loc: Loc,
    pub reference: u32,
    pub reference_loc: Loc,
    pub dofs: Vec<u8>,
    pub tied: RawList,
}

/// A `FIXED DISP` or `INITIAL VEL` group: (DOF, value) pairs on a node list.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawDofValues {
    pub dofs: Vec<(u8, f64)>,
    pub loc: Loc,
    pub nodes: RawList,
    /// `INITIAL VEL, QUASI STATIC`; always false for `FIXED DISP`.
    pub quasi_static: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawPointLoad {
    pub dofs: Vec<(u8, f64)>,
    pub loc: Loc,
    pub nodes: RawList,
    pub table: Option<(String, Loc)>,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawTable {
    pub name: String,
    pub loc: Loc,
    pub points: Vec<(f64, f64)>,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawOutput {
    pub every: u32,
    pub loc: Loc,
    pub quantities: Vec<Quantity>,
    pub dofs: Vec<u8>,
    pub nodes: RawList,
}

/// One history load case while it is being read.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct RawLoadCase {
    /// The first card of the load case.
    pub loc: Option<Loc>,
    pub title: Option<(String, Loc)>,
    pub auto_load: Option<(u32, Loc)>,
    pub time_step: Option<(f64, Loc)>,
    pub modal: Option<(u32, Loc)>,
    pub dynamic: Option<(f64, f64, TransientMethod, Loc)>,
    pub point_loads: Vec<RawPointLoad>,
    /// Mentat's `LOADCASE` in this load case: the names of its active blocks.
    pub active: Option<Vec<(String, Loc)>>,
    /// The `CONTINUE` line.
    pub end: Option<Loc>,
}

/// How Marc's `DYNAMIC` parameter card sets a transient's method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum MarcDynamic {
    /// Code 1: modal superposition over this many modes (0: none given).
    Modal { modes: u32 },
    /// Code 2: Newmark, average acceleration.
    Newmark,
}

/// Everything read from a deck.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct RawDeck {
    pub title: Option<(String, Loc)>,
    /// `SIZING`: upper bounds for elements and nodes (0 = no bound).
    pub sizing: Option<(u64, u64, Loc)>,
    pub element_types: Vec<(ElementType, Loc)>,
    pub lump: Option<Loc>,
    pub nodes: Vec<RawNode>,
    pub elements: Vec<RawElement>,
    pub sets: Vec<RawSet>,
    pub materials: Vec<RawMaterial>,
    pub geometries: Vec<RawGeometry>,
    pub damping: Vec<RawDamping>,
    /// `BEAM TENSION` groups.
    pub beam_tensions: Vec<RawBeamTension>,
    /// `TENSION LINK` lines: the link and where.
    pub tension_links: Vec<(crate::model::TensionLink, Loc)>,
    /// `MOVING CONTACT` groups.
    pub moving_contacts: Vec<RawMovingContact>,
    /// `DMIG` groups: the matrix element and where its group starts.
    pub matrix_elements: Vec<(crate::model::MatrixElement, Loc)>,
    pub point_masses: Vec<RawPointMass>,
    pub point_laws: Vec<RawPointLaw>,
    /// `LOSS FACTOR`: (eta, modes, where).
    pub loss_factor: Option<(f64, u32, Loc)>,
    /// `MODAL DAMPING` lines: (mode 1.., zeta, where).
    pub modal_ratios: Vec<(u32, f64, Loc)>,
    pub rigid_ties: Vec<RawTie>,
    pub fixed_disp: Vec<RawDofValues>,
    pub point_loads: Vec<RawPointLoad>,
    pub tables: Vec<RawTable>,
    pub initial_velocities: Vec<RawDofValues>,
    pub outputs: Vec<RawOutput>,
    pub load_cases: Vec<RawLoadCase>,
    /// The load case being read (history cards seen, `CONTINUE` not yet).
    pub open_case: Option<RawLoadCase>,
    /// Cards read that change nothing coil computes: name and first line.
    pub not_needed: Vec<(String, Loc)>,
    /// Marc's input version (`VERSION`).
    pub version: Option<u64>,
    /// Marc's `DYNAMIC` parameter: the method it gives a transient, and where.
    pub marc_dynamic: Option<(MarcDynamic, Loc)>,
    /// `BEAM SECT` sections, numbered from 1.
    pub beam_sections: Vec<RawBeamSection>,
    /// Mentat's named blocks (name, line, true for a FIXED DISP block).
    pub named: Vec<(String, Loc, bool)>,
    /// Mentat's named point loads, active where a `LOADCASE` lists them.
    pub named_loads: Vec<(String, RawPointLoad)>,
    /// Mentat's named distributed loads on beams.
    pub dist_loads: Vec<RawDistLoad>,
    /// The model definition's `LOADCASE` (Marc's increment 0).
    pub model_loadcase: Option<Vec<(String, Loc)>>,
    /// Where `END` and `END OPTION` were.
    pub end: Option<Loc>,
    pub end_option: Option<Loc>,
}

/// A `BEAM TENSION` group: an axial force (N) on a list of elements.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawBeamTension {
    pub force: f64,
    pub loc: Loc,
    pub elements: RawList,
}

/// A `MOVING CONTACT` group: its first line's values, where, and the line's nodes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawMovingContact {
    pub head: u32,
    pub dof: u8,
    pub stiffness: f64,
    pub speed: f64,
    pub start: f64,
    pub loc: Loc,
    pub line: RawList,
}

/// A `BEAM SECT` section.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawBeamSection {
    pub id: u32,
    pub name: String,
    pub loc: Loc,
    pub section: Section,
}

/// A uniform load per unit length (global components, N/mm) on beam elements.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawDistLoad {
    pub name: String,
    pub loc: Loc,
    pub q: [f64; 3],
    pub elements: RawList,
}
