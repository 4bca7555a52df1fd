//! The model's data types: nodes, elements, sections, loads, analyses and the
//! [`Model`] itself (its fields crate-private) with [`ModelParts`], its pieces before
//! validation. Units and DOF numbering as in the parent module's documentation. Below
//! [`super::check`], which validates them, and the constructors in the parent.

use serde::{Deserialize, Serialize};

/// Number of DOFs per node (3 translations, 3 rotations).
pub const DOFS_PER_NODE: usize = 6;

/// A node id as written in the deck.
pub type NodeId = u32;
/// An element id as written in the deck.
pub type ElementId = u32;

/// Beam element formulations, by their Marc element type number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ElementType {
    /// Marc type 52: two-node Euler-Bernoulli beam (no transverse shear strain).
    Beam52,
    /// Marc type 98: two-node beam with transverse shear (Timoshenko).
    Beam98,
}

impl ElementType {
    /// The Marc element type number.
    pub fn number(self) -> u32 {
        match self {
            ElementType::Beam52 => 52,
            ElementType::Beam98 => 98,
        }
    }

    /// The element type for a Marc type number, if coil supports it.
    pub fn from_number(n: u32) -> Option<Self> {
        match n {
            52 => Some(ElementType::Beam52),
            98 => Some(ElementType::Beam98),
            _ => None,
        }
    }
}

/// A node: its id and coordinates (mm).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// The node id.
    pub id: NodeId,
    /// Coordinates x, y, z (mm).
    pub xyz: [f64; 3],
}

/// A two-node beam element.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Element {
    /// The element id.
    pub id: ElementId,
    /// Its formulation.
    pub kind: ElementType,
    /// Node 1 and node 2 (local x runs from 1 to 2).
    pub nodes: [NodeId; 2],
}

/// A named node set (`DEFINE NODE SET`). Ids sorted and unique.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodeSet {
    /// Its name.
    pub name: String,
    /// Node ids (sorted, unique).
    pub nodes: Vec<NodeId>,
}

/// A named element set (`DEFINE ELEMENT SET`). Ids sorted and unique.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ElementSet {
    /// Its name.
    pub name: String,
    /// Element ids (sorted, unique).
    pub elements: Vec<ElementId>,
}

/// Linear isotropic elastic material (`ISOTROPIC`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Material name (Marc's material id/name field).
    pub name: String,
    /// Young's modulus E (MPa).
    pub youngs_modulus: f64,
    /// Poisson's ratio nu (-); the shear modulus is G = E / (2 (1 + nu)).
    pub poisson: f64,
    /// Mass density (t/mm^3).
    pub density: f64,
    /// Elements the material applies to (sorted, unique).
    pub elements: Vec<ElementId>,
}

impl Material {
    /// Shear modulus G = E / (2 (1 + nu)) in MPa.
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson))
    }
}

/// Cross-section of a beam.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Section {
    /// A solid circular wire of the given diameter (mm). Area, second moments and the
    /// torsion constant follow from it; the Timoshenko shear coefficient is
    /// kappa = 6 (1 + nu) / (7 + 6 nu) (Cowper 1966).
    SolidCircle {
        /// Wire diameter d (mm).
        diameter: f64,
    },
    /// A general section given by its properties.
    General {
        /// Area A (mm^2).
        area: f64,
        /// Second moment about the element's local y axis, I_y (mm^4).
        iyy: f64,
        /// Second moment about the element's local z axis, I_z (mm^4).
        izz: f64,
        /// Torsion constant J (mm^4).
        torsion: f64,
        /// Timoshenko shear coefficient kappa (shear area = kappa A), both directions.
        /// Ignored by type 52.
        shear_coefficient: f64,
    },
}

/// Derived section properties, the same for both section kinds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionProperties {
    /// Area A (mm^2).
    pub area: f64,
    /// Second moment about local y (mm^4).
    pub iyy: f64,
    /// Second moment about local z (mm^4).
    pub izz: f64,
    /// Torsion constant J (mm^4).
    pub torsion: f64,
    /// Timoshenko shear coefficient kappa (-).
    pub shear_coefficient: f64,
}

impl Section {
    /// Area, second moments, torsion constant and shear coefficient. `poisson` is
    /// needed for the solid circle's Cowper coefficient.
    pub fn properties(&self, poisson: f64) -> SectionProperties {
        match *self {
            Section::SolidCircle { diameter } => {
                let r = 0.5 * diameter;
                let area = std::f64::consts::PI * r * r;
                let i = std::f64::consts::PI * r.powi(4) / 4.0;
                SectionProperties {
                    area,
                    iyy: i,
                    izz: i,
                    torsion: 2.0 * i,
                    shear_coefficient: 6.0 * (1.0 + poisson) / (7.0 + 6.0 * poisson),
                }
            }
            Section::General {
                area,
                iyy,
                izz,
                torsion,
                shear_coefficient,
            } => SectionProperties {
                area,
                iyy,
                izz,
                torsion,
                shear_coefficient,
            },
        }
    }
}

/// Beam geometry (`GEOMETRY`): section and orientation for a list of elements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Geometry {
    /// Its name.
    pub name: String,
    /// The cross-section.
    pub section: Section,
    /// A vector (global axes) that, with the element axis, fixes the local frame:
    /// local x runs from node 1 to node 2, local y is the part of `orientation`
    /// normal to x, local z = x cross y. Must not be parallel to any of its elements.
    pub orientation: [f64; 3],
    /// Element ids (sorted, unique).
    pub elements: Vec<ElementId>,
}

/// Rayleigh damping (`DAMPING`): C_e = alpha M_e + beta K_e on the listed elements, and
/// C = alpha M_p on the point masses of the listed nodes (none unless named).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Damping {
    /// Mass-proportional coefficient alpha (1/s).
    pub alpha: f64,
    /// Stiffness-proportional coefficient beta (s).
    pub beta: f64,
    /// Element ids (sorted, unique).
    pub elements: Vec<ElementId>,
    /// Nodes whose point masses receive alpha (beta has no meaning for a point mass).
    pub mass_nodes: Vec<NodeId>,
}

/// A point mass with rotary inertia at a node (`POINT MASS`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointMass {
    /// The node.
    pub node: NodeId,
    /// Translational mass (t), on DOFs 1-3.
    pub mass: f64,
    /// Rotary inertia about the global x, y, z axes (t mm^2), on DOFs 4-6.
    pub inertia: [f64; 3],
}

/// A rigid tie (Marc's RBE2, coil card `RBE2`): the tied nodes' listed DOFs follow the
/// reference node as a rigid body: u_s = u_r + theta_r x (x_s - x_r), theta_s = theta_r.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RigidTie {
    /// Its name.
    pub name: String,
    /// The reference (master) node.
    pub reference: NodeId,
    /// Tied DOFs of the tied nodes (1..=6, sorted, unique).
    pub dofs: Vec<u8>,
    /// The tied (slave) nodes (sorted, unique).
    pub tied: Vec<NodeId>,
}

/// Prescribed displacements (`FIXED DISP`): each listed DOF of each node gets its value
/// (mm or rad).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FixedDisp {
    /// (dof 1..=6, value) pairs.
    pub dofs: Vec<(u8, f64)>,
    /// Node ids (sorted, unique).
    pub nodes: Vec<NodeId>,
}

/// Concentrated loads (`POINT LOAD`): each listed DOF of each node gets its value
/// (N or N mm), optionally scaled in time by a table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointLoad {
    /// (dof 1..=6, value) pairs.
    pub dofs: Vec<(u8, f64)>,
    /// Node ids (sorted, unique).
    pub nodes: Vec<NodeId>,
    /// Name of a [`Table`] giving the load factor against time; `None` = constant 1.
    pub table: Option<String>,
}

/// A piecewise-linear table of (time s, factor) points, sorted by time (`TABLE`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Table {
    /// Its name.
    pub name: String,
    /// (time s, factor) points, strictly increasing in time.
    pub points: Vec<(f64, f64)>,
}

/// Initial velocities (`INITIAL VEL`): each listed DOF of each node (mm/s or rad/s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InitialVelocity {
    /// (DOF 1..=6, value) pairs.
    pub dofs: Vec<(u8, f64)>,
    /// Node ids (sorted, unique).
    pub nodes: Vec<NodeId>,
    /// `INITIAL VEL, QUASI STATIC` (added for transients, append-only): the listed
    /// velocities are extended over every free DOF by the quasi-static shape, the static
    /// response `K^-1 E c` to forces `c` at the listed DOFs scaled so that the listed DOFs
    /// have exactly their velocities (the velocity profile the listed motion induces
    /// along the structure). `false`: only the listed DOFs move, every other DOF starts
    /// at rest (a velocity jump). See `docs/transient.md`.
    #[serde(default)]
    pub quasi_static: bool,
}

/// What a history output records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Quantity {
    /// Displacement (mm or rad).
    Displacement,
    /// Velocity (mm/s or rad/s).
    Velocity,
    /// Acceleration (mm/s^2 or rad/s^2).
    Acceleration,
}

/// A history output request (coil card `HISTORY OUTPUT`): the listed quantities of the
/// listed DOFs of the listed nodes, every `every`-th step of a transient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutputRequest {
    /// Node ids (sorted, unique).
    pub nodes: Vec<NodeId>,
    /// DOFs 1..=6.
    pub dofs: Vec<u8>,
    /// What is recorded.
    pub quantities: Vec<Quantity>,
    /// Record every `every`-th step (>= 1).
    pub every: u32,
}

/// Time integration schemes for direct transient analysis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Integrator {
    /// Newmark average acceleration (beta = 1/4, gamma = 1/2): no numerical damping.
    AverageAcceleration,
    /// Hilber-Hughes-Taylor with alpha in [-1/3, 0].
    Hht {
        /// alpha in [-1/3, 0].
        alpha: f64,
    },
    /// Chung-Hulbert generalised-alpha with spectral radius at infinity rho_inf in [0, 1].
    GeneralizedAlpha {
        /// Spectral radius at infinite frequency, in [0, 1].
        rho_inf: f64,
    },
}

/// How a transient is solved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TransientMethod {
    /// Direct integration of the full system.
    Direct(Integrator),
    /// Modal superposition over the lowest `modes` modes, each integrated exactly.
    Modal {
        /// Number of modes (>= 1).
        modes: u32,
    },
}

/// The analysis a load case runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Analysis {
    /// Linear static (`AUTO LOAD` / `TIME STEP`). `steps` and `time` are kept for
    /// Marc compatibility; a linear solve applies the full load once.
    Static {
        /// Marc increments (kept for the deck; a linear solve applies the load once).
        steps: u32,
        /// Marc load-case time (s).
        time: f64,
    },
    /// Lowest `modes` eigenpairs of K phi = omega^2 M phi (`MODAL SHAPE`).
    Modal {
        /// Number of modes (>= 1).
        modes: u32,
    },
    /// Transient (`DYNAMIC CHANGE`): fixed step `dt` (s) up to `total_time` (s).
    Transient {
        /// Time step (s).
        dt: f64,
        /// Duration (s).
        total_time: f64,
        /// How it is solved.
        method: TransientMethod,
    },
}

/// One load case of the history section, closed by `CONTINUE`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoadCase {
    /// Its title.
    pub title: String,
    /// The analysis it runs.
    pub analysis: Analysis,
    /// Loads added in this load case (history-definition `POINT LOAD`), on top of the
    /// model-definition loads.
    pub point_loads: Vec<PointLoad>,
}

/// The complete, validated model.
///
/// Built only by [`Model::try_new`] (or [`ModelParts::build`]), which checks everything a
/// model must satisfy (see [`super::check`]); read through its accessors; changed only by taking
/// it apart ([`Model::into_parts`]) and building again. Deserialising validates too.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ModelParts")]
pub struct Model {
    /// The model's title (`TITLE`).
    pub(crate) title: String,
    /// Element types declared in the parameter section (`ELEMENTS`).
    pub(crate) element_types: Vec<ElementType>,
    /// Lumped instead of consistent mass (parameter `LUMP`); never a silent default.
    pub(crate) lumped_mass: bool,
    /// The nodes, sorted by id, each id once.
    pub(crate) nodes: Vec<Node>,
    /// The beam elements, sorted by id, each id once.
    pub(crate) elements: Vec<Element>,
    /// Named node sets (kept so that a written deck reads back equal).
    pub(crate) node_sets: Vec<NodeSet>,
    /// Named element sets (kept so that a written deck reads back equal).
    pub(crate) element_sets: Vec<ElementSet>,
    /// Materials; every element has one (the last listing it wins).
    pub(crate) materials: Vec<Material>,
    /// Beam geometries; every element has one (the last listing it wins).
    pub(crate) geometries: Vec<Geometry>,
    /// Rayleigh damping groups.
    pub(crate) damping: Vec<Damping>,
    /// Point masses, at most one per node.
    pub(crate) point_masses: Vec<PointMass>,
    /// Rigid ties; they neither overlap nor chain.
    pub(crate) rigid_ties: Vec<RigidTie>,
    /// Prescribed displacements; each (node, DOF) once.
    pub(crate) fixed_disp: Vec<FixedDisp>,
    /// Model-definition point loads (active in every load case).
    pub(crate) point_loads: Vec<PointLoad>,
    /// Load-factor tables against time.
    pub(crate) tables: Vec<Table>,
    /// Initial velocities of transients; each (node, DOF) once.
    pub(crate) initial_velocities: Vec<InitialVelocity>,
    /// History output requests.
    pub(crate) outputs: Vec<OutputRequest>,
    /// The load cases, in order.
    pub(crate) load_cases: Vec<LoadCase>,
    /// Nonlinear point elements (`FRICTION`, `QUADRATIC DAMPER`, `CUBIC SPRING`): one entry per (node, DOF), the cards on it combined, sorted by (node, DOF), on free DOFs.
    #[serde(default)]
    pub(crate) point_laws: Vec<PointElement>,
    /// Linear dashpots to ground (`DASHPOT`), sorted by (node, DOF), on free DOFs.
    #[serde(default)]
    pub(crate) dashpots: Vec<Dashpot>,
    /// Modal damping (`LOSS FACTOR`, `MODAL DAMPING`).
    #[serde(default)]
    pub(crate) modal_damping: ModalDamping,
    /// Axial forces of tensioned beams (`BEAM TENSION`): each element in one entry at most.
    #[serde(default)]
    pub(crate) beam_tensions: Vec<BeamTension>,
    /// Tension-only links between two nodes (`TENSION LINK`).
    #[serde(default)]
    pub(crate) tension_links: Vec<TensionLink>,
    /// Moving unilateral contacts of a node on a beam line (`MOVING CONTACT`).
    #[serde(default)]
    pub(crate) moving_contacts: Vec<MovingContact>,
    /// Matrix elements (`DMIG`): symmetric K, M, C over listed (node, DOF) pairs.
    #[serde(default)]
    pub(crate) matrix_elements: Vec<MatrixElement>,
}

/// The pieces of a [`Model`] before validation: every field public, so a caller (the
/// deck, the mesher, a test) fills them and then calls [`ModelParts::build`]. Field
/// meanings are those of the accessors of [`Model`] with the same names.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModelParts {
    /// The model's title (`TITLE`).
    pub title: String,
    /// Element types declared in the parameter section (`ELEMENTS`).
    pub element_types: Vec<ElementType>,
    /// Lumped instead of consistent mass (parameter `LUMP`); never a silent default.
    pub lumped_mass: bool,
    /// The nodes, sorted by id, each id once.
    pub nodes: Vec<Node>,
    /// The beam elements, sorted by id, each id once.
    pub elements: Vec<Element>,
    /// Named node sets (kept so that a written deck reads back equal).
    pub node_sets: Vec<NodeSet>,
    /// Named element sets (kept so that a written deck reads back equal).
    pub element_sets: Vec<ElementSet>,
    /// Materials; every element has one (the last listing it wins).
    pub materials: Vec<Material>,
    /// Beam geometries; every element has one (the last listing it wins).
    pub geometries: Vec<Geometry>,
    /// Rayleigh damping groups.
    pub damping: Vec<Damping>,
    /// Point masses, at most one per node.
    pub point_masses: Vec<PointMass>,
    /// Rigid ties; they neither overlap nor chain.
    pub rigid_ties: Vec<RigidTie>,
    /// Prescribed displacements; each (node, DOF) once.
    pub fixed_disp: Vec<FixedDisp>,
    /// Model-definition point loads (active in every load case).
    pub point_loads: Vec<PointLoad>,
    /// Load-factor tables against time.
    pub tables: Vec<Table>,
    /// Initial velocities of transients; each (node, DOF) once.
    pub initial_velocities: Vec<InitialVelocity>,
    /// History output requests.
    pub outputs: Vec<OutputRequest>,
    /// The load cases, in order.
    pub load_cases: Vec<LoadCase>,
    /// Nonlinear point elements (`FRICTION`, `QUADRATIC DAMPER`, `CUBIC SPRING`): one entry per (node, DOF), the cards on it combined, sorted by (node, DOF), on free DOFs.
    #[serde(default)]
    pub point_laws: Vec<PointElement>,
    /// Linear dashpots to ground (`DASHPOT`), sorted by (node, DOF), on free DOFs.
    #[serde(default)]
    pub dashpots: Vec<Dashpot>,
    /// Modal damping (`LOSS FACTOR`, `MODAL DAMPING`).
    #[serde(default)]
    pub modal_damping: ModalDamping,
    /// Axial forces of tensioned beams (`BEAM TENSION`): each element in one entry at most.
    #[serde(default)]
    pub beam_tensions: Vec<BeamTension>,
    /// Tension-only links between two nodes (`TENSION LINK`).
    #[serde(default)]
    pub tension_links: Vec<TensionLink>,
    /// Moving unilateral contacts of a node on a beam line (`MOVING CONTACT`).
    #[serde(default)]
    pub moving_contacts: Vec<MovingContact>,
    /// Matrix elements (`DMIG`): symmetric K, M, C over listed (node, DOF) pairs.
    #[serde(default)]
    pub matrix_elements: Vec<MatrixElement>,
}

/// A matrix element (card `DMIG`, direct matrix input): symmetric stiffness, mass and
/// damping matrices over an ordered list of (node, DOF) pairs, added to the global K, M
/// and C of every analysis before constraints are applied, as an element's matrices are.
/// A reduced model (Craig-Bampton) is one: its boundary DOFs are the physical DOFs it
/// connects to, its modal coordinates extra nodes with one free DOF each.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatrixElement {
    /// The element's name (unique among matrix elements).
    pub name: String,
    /// The (node, DOF 1..=6) of each row and column, in order, each pair once.
    pub dofs: Vec<(NodeId, u8)>,
    /// Stiffness, `n x n` row-major (N/mm, N, N mm per unit DOF), symmetric.
    pub stiffness: Vec<f64>,
    /// Mass, `n x n` row-major (t, t mm, t mm^2), symmetric positive semi-definite.
    pub mass: Vec<f64>,
    /// Damping, `n x n` row-major (N s/mm, ...), symmetric positive semi-definite;
    /// empty for none.
    #[serde(default)]
    pub damping: Vec<f64>,
}

impl MatrixElement {
    /// Number of DOFs (rows) `n`.
    pub fn size(&self) -> usize {
        self.dofs.len()
    }
}

/// A tension-only link (coil card `TENSION LINK`; a catenary's dropper): along the
/// translation `dof` its elongation is `e = u_b - u_a - slack` (displacements from the
/// reference, mm) and it pulls the two nodes together with `stiffness * max(e, 0)`;
/// slack (`e < 0`) it exerts nothing. A negative `slack` is a link pretensioned in the
/// reference configuration by `-stiffness * slack`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TensionLink {
    /// The nodes a and b (different).
    pub nodes: [NodeId; 2],
    /// The translation 1..=3 the link acts along.
    pub dof: u8,
    /// Stiffness in tension (N/mm), > 0.
    pub stiffness: f64,
    /// The elongation at which the link becomes taut (mm), finite.
    pub slack: f64,
}

/// A moving unilateral penalty contact (coil card `MOVING CONTACT`; a pantograph's head
/// on the contact wire): a point moves along a straight line of beam nodes at a constant
/// speed, and the `head` node presses on the line along the translation `dof`. The
/// penetration `p = (x_head + u_head) - (x_line + w_line)(s)` along `dof` (`w_line` the
/// line's cubic Hermite interpolation of that translation and its rotation at the point
/// `s = start + speed t` from the line's first node) gives the force `stiffness *
/// max(p, 0)`, pushing the head back and the line forward; `p <= 0` is an open contact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MovingContact {
    /// The pressing node.
    pub head: NodeId,
    /// The translation 1..=3 of the pressing.
    pub dof: u8,
    /// Penalty stiffness (N/mm), > 0.
    pub stiffness: f64,
    /// Speed along the line (mm/s), finite.
    pub speed: f64,
    /// The contact point at t = 0, from the line's first node (mm), finite.
    pub start: f64,
    /// The line's nodes (sorted, unique): collinear along a global axis other than `dof`.
    pub line: Vec<NodeId>,
}

/// A given axial force in beam elements (coil card `BEAM TENSION`): a wire under a
/// tension `N` that the model does not compute itself (a catenary's contact or messenger
/// wire, tensioned by weights at its ends). It enters every analysis as the elements'
/// geometric stiffness (`crate::element::beam::local_geometric_stiffness`), linear in the
/// displacements from the straight reference line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeamTension {
    /// Axial force N (N), positive in tension; finite.
    pub force: f64,
    /// Element ids (sorted, unique).
    pub elements: Vec<ElementId>,
}

/// A linear (viscous) dashpot between one DOF of a node and the ground (coil card
/// `DASHPOT`): the force `c v` against the DOF's velocity `v`. It is part of the viscous
/// damping matrix `C` (one diagonal entry), so every transient method and scheme runs it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Dashpot {
    /// The node.
    pub node: NodeId,
    /// 1..=6; the DOF must be free (neither prescribed nor tied).
    pub dof: u8,
    /// Damping coefficient c >= 0 (N s/mm; N mm s/rad on a rotation; 1 N s/m = 1e-3 N s/mm).
    pub c: f64,
}

/// Modal damping: mode `i` (0-based, ascending frequency) gets the damping ratio
/// `zeta_i = loss_factor / 2 + ratios[i]` (missing ratios are 0).
///
/// `loss_factor` is the hysteretic (structural) loss factor eta of `LOSS FACTOR`: its
/// standard time-domain equivalent for free vibration is viscous modal damping with
/// `zeta_i = eta / 2` in every mode (the same energy loss per cycle, `2 pi eta` times
/// the peak strain energy, at each mode's own frequency). `ratios` are the per-mode
/// ratios of `MODAL DAMPING`. Modal superposition adds `zeta_i` to each retained mode;
/// direct integration adds `C_m = M Phi diag(2 zeta_i w_i) Phi^T M` over the lowest
/// [`ModalDamping::basis_modes`] modes (docs/transient.md, "Modal damping").
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModalDamping {
    /// Loss factor eta >= 0 (-).
    pub loss_factor: f64,
    /// Modes that carry the loss factor in direct integration (>= 1 when eta > 0).
    pub loss_factor_modes: u32,
    /// Per-mode damping ratios, mode 1 first (>= 0).
    pub ratios: Vec<f64>,
}

impl ModalDamping {
    /// Whether any mode gets damping.
    pub fn is_active(&self) -> bool {
        self.loss_factor > 0.0 || self.ratios.iter().any(|&z| z > 0.0)
    }

    /// The damping ratio of mode `i` (0-based).
    pub fn zeta(&self, i: usize) -> f64 {
        0.5 * self.loss_factor + self.ratios.get(i).copied().unwrap_or(0.0)
    }

    /// The number of lowest modes direct integration damps: the loss factor's count
    /// and every mode `MODAL DAMPING` names.
    pub fn basis_modes(&self) -> usize {
        let eta = if self.loss_factor > 0.0 {
            self.loss_factor_modes as usize
        } else {
            0
        };
        let last = self
            .ratios
            .iter()
            .rposition(|&z| z > 0.0)
            .map_or(0, |i| i + 1);
        eta.max(last)
    }
}

/// A nonlinear restoring force between one DOF of a node and the ground (coil cards
/// `FRICTION`, `QUADRATIC DAMPER`, `CUBIC SPRING`): the law
/// `f = k3 u^3 + c2 v|v| + F sgn(v)` of [`crate::integrate::PointLaw`], with `u` the
/// DOF's displacement from the reference (meshed) configuration and `v` its velocity.
/// Units (solver units): `cubic` k3 in N/mm^3, `quadratic` c2 in N s^2/mm^2,
/// `friction` F in N (on a rotational DOF: N mm/rad^3, N mm s^2/rad^2, N mm). Use
/// [`super::units::cubic_stiffness_from_si`] and [`super::units::quadratic_damping_from_si`] to
/// convert SI values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PointElement {
    /// The node.
    pub node: NodeId,
    /// 1..=6; the DOF must be free (neither prescribed nor tied).
    pub dof: u8,
    /// Cubic stiffness k3 >= 0 (N/mm^3).
    pub cubic: f64,
    /// Velocity-squared damping c2 >= 0 (N s^2/mm^2).
    pub quadratic: f64,
    /// Dry friction force F >= 0 (N).
    pub friction: f64,
}

impl PointElement {
    /// The element's law.
    pub fn law(&self) -> crate::integrate::PointLaw {
        crate::integrate::PointLaw {
            cubic: self.cubic,
            quadratic: self.quadratic,
            friction: self.friction,
        }
    }
}
