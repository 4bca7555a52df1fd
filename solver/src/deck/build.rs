//! Stage two of reading: the located [`RawDeck`] -> [`ModelParts`] -> a validated
//! [`Model`] through [`Model::try_new`].
//!
//! The deck does what needs its text: it resolves ids, ranges and set names to sorted,
//! unique id lists (sets and tables must be defined on an earlier line than the list
//! that uses them, so a set can never contain itself), and it refuses what it can name
//! by line: a repeated id or name ("first at line N"), the SIZING bounds, a second
//! point mass on a node, a DOF given twice, ties that overlap, chain or meet a
//! prescribed DOF, nonlinear point elements on prescribed or tied DOFs, Mentat's load
//! case names. Everything else about a valid model (declared types, existing nodes,
//! no zero-length element, a material and a geometry for every element, orientations,
//! shear coefficients, damped point masses, ...) is [`crate::model::check`]'s; its
//! [`ModelError`] names a [`Site`] that [`locate`] maps back to the card and line.
//!
//! The build functions live with their cards (`cards/<family>.rs`); list resolution
//! and the line-named checks they share are in [`super::resolve`].

use super::cards::{catenary, history, loads, masses, mesh, point_laws, properties, superelement};
use super::error::{DeckError, Loc};
use super::raw::{PointLawKind, RawDeck, SetKind};
use super::resolve::Builder;
use crate::model::{Model, ModelError, ModelParts, Site};

/// Builds the model: each card family's build function in the order their references
/// need (nodes and elements, then sets, properties, masses, supports, ties, point
/// elements, loads, load cases), then the model's own checks.
pub(crate) fn build(raw: RawDeck, file: &str) -> Result<Model, DeckError> {
    let mut b = Builder {
        file,
        node_ids: Vec::new(),
        element_ids: Vec::new(),
        sets: Vec::new(),
        all_sets: raw
            .sets
            .iter()
            .map(|s| (s.kind, s.name.clone(), s.loc))
            .collect(),
    };
    let mut parts = ModelParts {
        title: raw.title.clone().map(|t| t.0).unwrap_or_default(),
        element_types: raw.element_types.iter().map(|t| t.0).collect(),
        lumped_mass: raw.lump.is_some(),
        ..ModelParts::default()
    };
    mesh::build_mesh(&mut b, &raw, &mut parts)?;
    mesh::build_sets(&mut b, &raw, &mut parts)?;
    loads::build_tables(&b, &raw, &mut parts)?;
    properties::build(&b, &raw, &mut parts)?;
    masses::build(&b, &raw, &mut parts)?;
    catenary::build(&b, &raw, &mut parts)?;
    superelement::build(&raw, &mut parts);
    let prescribed = loads::build_supports(&b, &raw, &mut parts)?;
    masses::build_ties(&b, &raw, &prescribed, &mut parts)?;
    point_laws::build(&b, &raw, &prescribed, &mut parts)?;
    let named_loads = loads::build(&b, &raw, &mut parts)?;
    history::build(&b, &raw, &named_loads, &mut parts)?;
    let keys = PointKeys::of(&parts);
    Model::try_new(parts).map_err(|e| locate(&b, &raw, &keys, e))
}

/// The (node, DOF) of each point element and dashpot the deck built, to map a
/// [`Site::PointLaw`] or [`Site::Dashpot`] back to its line.
struct PointKeys {
    laws: Vec<(u32, u8)>,
    dashpots: Vec<(u32, u8)>,
}

impl PointKeys {
    fn of(parts: &ModelParts) -> PointKeys {
        let mut laws: Vec<(u32, u8)> = parts.point_laws.iter().map(|e| (e.node, e.dof)).collect();
        let mut dashpots: Vec<(u32, u8)> = parts.dashpots.iter().map(|d| (d.node, d.dof)).collect();
        laws.sort_unstable();
        dashpots.sort_unstable();
        PointKeys { laws, dashpots }
    }
}

/// A [`ModelError`] as a [`DeckError`] at the card and line that produced its item.
fn locate(b: &Builder<'_>, raw: &RawDeck, keys: &PointKeys, e: ModelError) -> DeckError {
    let element = |id: u32| raw.elements.iter().find(|x| x.id == id);
    let node_set = |i: usize| raw.sets.iter().filter(|s| s.kind == SetKind::Node).nth(i);
    let element_set = |i: usize| {
        raw.sets
            .iter()
            .filter(|s| s.kind == SetKind::Element)
            .nth(i)
    };
    let point = |key: Option<&(u32, u8)>, dashpot: bool| {
        let (node, dof) = *key?;
        let p = raw.point_laws.iter().find(|p| {
            (p.node, p.dof) == (node, dof) && (p.kind == PointLawKind::Dashpot) == dashpot
        })?;
        Some((p.kind.card(), p.node_loc))
    };
    let at: Option<(&str, Loc)> = match e.site {
        Site::Model => None,
        Site::Node(id) => raw
            .nodes
            .iter()
            .find(|n| n.id == id)
            .map(|n| ("COORDINATES", n.loc)),
        Site::Element(id) => element(id).map(|x| ("CONNECTIVITY", x.loc)),
        Site::ElementType(id) => element(id).map(|x| ("CONNECTIVITY", x.type_loc)),
        Site::ElementNode(id, k) => element(id).map(|x| ("CONNECTIVITY", x.nodes[k.min(1)].1)),
        Site::NodeSet(i) => node_set(i).map(|s| ("DEFINE", s.loc)),
        Site::ElementSet(i) => element_set(i).map(|s| ("DEFINE", s.loc)),
        Site::Material(i) => raw.materials.get(i).map(|m| ("ISOTROPIC", m.loc)),
        Site::Geometry(i) => raw.geometries.get(i).map(|g| ("GEOMETRY", g.loc)),
        Site::GeometrySection(i) => raw.geometries.get(i).map(|g| ("GEOMETRY", g.section_loc)),
        Site::GeometryOrientation(i) => raw
            .geometries
            .get(i)
            .map(|g| ("GEOMETRY", g.orientation_loc)),
        Site::Damping(i) => raw.damping.get(i).map(|d| ("DAMPING", d.loc)),
        Site::DampingMassNodes(i) => raw.damping.get(i).map(|d| {
            let list = d.mass_nodes.as_ref().map_or(d.loc, |l| l.loc);
            ("DAMPING", list)
        }),
        Site::BeamTension(i) => raw.beam_tensions.get(i).map(|t| ("BEAM TENSION", t.loc)),
        Site::TensionLink(i) => raw.tension_links.get(i).map(|t| ("TENSION LINK", t.1)),
        Site::MovingContact(i) => raw
            .moving_contacts
            .get(i)
            .map(|c| ("MOVING CONTACT", c.loc)),
        Site::MatrixElement(i) => raw.matrix_elements.get(i).map(|m| ("DMIG", m.1)),
        Site::PointMass(i) => raw.point_masses.get(i).map(|p| ("POINT MASS", p.node_loc)),
        Site::RigidTie(i) => raw.rigid_ties.get(i).map(|t| ("RBE2", t.loc)),
        Site::RigidTieReference(i) => raw.rigid_ties.get(i).map(|t| ("RBE2", t.reference_loc)),
        Site::RigidTieTied(i) => raw.rigid_ties.get(i).map(|t| ("RBE2", t.tied.loc)),
        Site::FixedDisp(i) => raw.fixed_disp.get(i).map(|f| ("FIXED DISP", f.loc)),
        Site::PointLoad(i) => raw.point_loads.get(i).map(|p| ("POINT LOAD", p.loc)),
        Site::CasePointLoad { case, load } => raw
            .load_cases
            .get(case)
            .and_then(|c| c.point_loads.get(load))
            .map(|p| ("POINT LOAD", p.loc)),
        Site::Table(i) => raw.tables.get(i).map(|t| ("TABLE", t.loc)),
        Site::InitialVelocity(i) => raw
            .initial_velocities
            .get(i)
            .map(|v| ("INITIAL VEL", v.loc)),
        Site::Output(i) => raw.outputs.get(i).map(|o| ("HISTORY OUTPUT", o.loc)),
        Site::LoadCase(i) => raw
            .load_cases
            .get(i)
            .and_then(|c| c.end.or(c.loc))
            .map(|l| ("CONTINUE", l)),
        Site::PointLaw(i) => point(keys.laws.get(i), false),
        Site::Dashpot(i) => point(keys.dashpots.get(i), true),
        Site::ModalDamping => raw
            .loss_factor
            .map(|(_, _, l)| ("LOSS FACTOR", l))
            .or_else(|| {
                raw.modal_ratios
                    .first()
                    .map(|(_, _, l)| ("MODAL DAMPING", *l))
            }),
    };
    match at {
        Some((card, loc)) => b.err(loc, card, e.message, e.expected),
        None => DeckError::file_level(b.file, e.to_string(), e.expected),
    }
}
