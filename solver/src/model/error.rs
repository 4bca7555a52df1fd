//! Why a model is invalid: [`ModelError`] with the [`Site`] of the item at fault (an id,
//! or an index into a [`ModelParts`](super::ModelParts) vector). Below the model's types' validation
//! ([`super::check`]) and everything that reports its errors (the deck reader maps a
//! site back to its card and line).

use std::fmt;

use super::parts::{ElementId, NodeId};

/// Where in a [`ModelParts`](super::ModelParts) a [`ModelError`] is: an id, or an index into the vector of
/// that name (after normalisation for nodes, elements, point laws and dashpots).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Site {
    /// The model as a whole.
    Model,
    /// The node with this id.
    Node(NodeId),
    /// The element with this id.
    Element(ElementId),
    /// The type of the element with this id.
    ElementType(ElementId),
    /// Node `k` (0 or 1) of the element with this id.
    ElementNode(ElementId, usize),
    /// `node_sets[i]`.
    NodeSet(usize),
    /// `element_sets[i]`.
    ElementSet(usize),
    /// `materials[i]`.
    Material(usize),
    /// `geometries[i]`.
    Geometry(usize),
    /// The section of `geometries[i]`.
    GeometrySection(usize),
    /// The orientation vector of `geometries[i]`.
    GeometryOrientation(usize),
    /// `damping[i]`.
    Damping(usize),
    /// The point-mass nodes of `damping[i]`.
    DampingMassNodes(usize),
    /// `point_masses[i]`.
    PointMass(usize),
    /// `rigid_ties[i]`.
    RigidTie(usize),
    /// The reference node of `rigid_ties[i]`.
    RigidTieReference(usize),
    /// The tied nodes of `rigid_ties[i]`.
    RigidTieTied(usize),
    /// `fixed_disp[i]`.
    FixedDisp(usize),
    /// `point_loads[i]`.
    PointLoad(usize),
    /// `load_cases[case].point_loads[load]`.
    CasePointLoad {
        /// Index of the load case.
        case: usize,
        /// Index of the load in the case.
        load: usize,
    },
    /// `tables[i]`.
    Table(usize),
    /// `initial_velocities[i]`.
    InitialVelocity(usize),
    /// `outputs[i]`.
    Output(usize),
    /// `load_cases[i]`.
    LoadCase(usize),
    /// `point_laws[i]`.
    PointLaw(usize),
    /// `dashpots[i]`.
    Dashpot(usize),
    /// `modal_damping`.
    ModalDamping,
    /// `beam_tensions[i]`.
    BeamTension(usize),
    /// `tension_links[i]`.
    TensionLink(usize),
    /// `moving_contacts[i]`.
    MovingContact(usize),
    /// `matrix_elements[i]`.
    MatrixElement(usize),
}

impl fmt::Display for Site {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Site::Model => write!(f, "the model"),
            Site::Node(id) => write!(f, "node {id}"),
            Site::Element(id) | Site::ElementType(id) | Site::ElementNode(id, _) => {
                write!(f, "element {id}")
            }
            Site::NodeSet(i) => write!(f, "node set {}", i + 1),
            Site::ElementSet(i) => write!(f, "element set {}", i + 1),
            Site::Material(i) => write!(f, "material {}", i + 1),
            Site::Geometry(i) | Site::GeometrySection(i) | Site::GeometryOrientation(i) => {
                write!(f, "geometry {}", i + 1)
            }
            Site::Damping(i) | Site::DampingMassNodes(i) => write!(f, "damping {}", i + 1),
            Site::PointMass(i) => write!(f, "point mass {}", i + 1),
            Site::RigidTie(i) | Site::RigidTieReference(i) | Site::RigidTieTied(i) => {
                write!(f, "rigid tie {}", i + 1)
            }
            Site::FixedDisp(i) => write!(f, "fixed displacement {}", i + 1),
            Site::PointLoad(i) => write!(f, "point load {}", i + 1),
            Site::CasePointLoad { case, load } => {
                write!(f, "point load {} of load case {}", load + 1, case + 1)
            }
            Site::Table(i) => write!(f, "table {}", i + 1),
            Site::InitialVelocity(i) => write!(f, "initial velocity {}", i + 1),
            Site::Output(i) => write!(f, "output request {}", i + 1),
            Site::LoadCase(i) => write!(f, "load case {}", i + 1),
            Site::PointLaw(i) => write!(f, "point element {}", i + 1),
            Site::Dashpot(i) => write!(f, "dashpot {}", i + 1),
            Site::ModalDamping => write!(f, "modal damping"),
            Site::BeamTension(i) => write!(f, "beam tension {}", i + 1),
            Site::TensionLink(i) => write!(f, "tension link {}", i + 1),
            Site::MovingContact(i) => write!(f, "moving contact {}", i + 1),
            Site::MatrixElement(i) => write!(f, "matrix element {}", i + 1),
        }
    }
}

/// Why a [`ModelParts`](super::ModelParts) is not a valid [`Model`](super::Model).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{site}: {message}; expected {expected}")]
pub struct ModelError {
    /// The item at fault.
    pub site: Site,
    /// What is wrong.
    pub message: String,
    /// What was expected instead.
    pub expected: String,
}
