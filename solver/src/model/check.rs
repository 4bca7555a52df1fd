//! Validation of a [`Model`]: the one place that decides what a valid model is.
//!
//! [`Model::try_new`] runs [`check`] on the caller's [`ModelParts`]. It normalises
//! (nodes and elements sorted by id, id lists sorted and de-duplicated, point elements
//! and dashpots sorted by (node, DOF)) and then checks, in this order:
//! 1. unique node and element ids; every element of a declared type, joining two
//!    different existing nodes, of non-zero length;
//! 2. sets: unique names per kind, existing members;
//! 3. materials (E > 0, -1 < nu < 0.5, density >= 0) and geometries (positive section
//!    values, a non-zero orientation not parallel to any of its elements, the shear
//!    coefficient of every type-98 element) on existing elements, non-empty lists;
//! 4. every element has a material and a geometry;
//! 5. point masses (existing node, one per node, non-negative values), Rayleigh
//!    damping (non-negative alpha, beta; damped point-mass nodes carry a point mass),
//!    beam tensions (finite force, existing elements, each element once), tension
//!    links and moving contacts (existing nodes, a translation, stiffness > 0, one link
//!    per node pair and DOF, a contact line that is one straight wire), matrix
//!    elements (unique names, existing nodes, DOFs 1..=6 once each, n x n finite
//!    matrices, symmetric to [`SYMMETRY`], mass and damping positive semi-definite to
//!    [`SEMI_DEFINITE`]);
//! 6. constraints: prescribed DOFs 1..=6 once each, rigid ties (existing reference not
//!    in its own list, no overlap, no chain, no tied DOF also prescribed), nonlinear
//!    point elements and dashpots on existing, free DOFs with non-negative values;
//! 7. loads, tables, initial velocities, outputs and load cases (existing nodes and
//!    tables, positive steps and times, at least one mode).
//!
//! Every error is a [`ModelError`]: the [`Site`] of the item at fault (ids, or indices
//! into the [`ModelParts`] vectors), what is wrong and what was expected. The deck reader
//! maps a site back to the card and line that produced the item; the deck itself checks
//! only what needs its text (syntax, list resolution, "first defined at line N").

use std::collections::{HashMap, HashSet};

pub use super::error::{ModelError, Site};
use super::parts::{
    Analysis, ElementId, ElementType, ModelParts, NodeId, PointLoad, Section, TransientMethod,
};

/// Relative tolerance under which an element counts as zero-length: its length over
/// the model's largest coordinate. Far above round-off (1e-16), far below any mesh.
pub const ZERO_LENGTH: f64 = 1e-12;
/// A matrix element's `|a_ij - a_ji| <= SYMMETRY max|a|`: written matrices are exactly
/// symmetric; this lets through a matrix printed with 10 significant digits, not a
/// wrong entry.
pub const SYMMETRY: f64 = 1e-9;
/// A matrix element's mass or damping is positive semi-definite when its smallest
/// eigenvalue is `>= -SEMI_DEFINITE` times its largest magnitude (rounding of a
/// singular matrix, not a negative mass).
pub const SEMI_DEFINITE: f64 = 1e-9;
/// |v x e| <= PARALLEL |v| |e|: the orientation fixes no plane (angle below 1e-6 rad).
pub const PARALLEL: f64 = 1e-6;

fn fail<T>(
    site: Site,
    message: impl Into<String>,
    expected: impl Into<String>,
) -> Result<T, ModelError> {
    Err(ModelError {
        site,
        message: message.into(),
        expected: expected.into(),
    })
}

fn sort_unique<T: Ord>(ids: &mut Vec<T>) {
    ids.sort_unstable();
    ids.dedup();
}

/// Validates and normalises `p` (see the module doc for what is checked).
pub(crate) fn check(mut p: ModelParts) -> Result<ModelParts, ModelError> {
    normalise(&mut p);
    let ids = Ids::of(&p)?;
    check_elements(&p, &ids)?;
    check_sets(&p, &ids)?;
    check_materials(&p, &ids)?;
    check_geometries(&p, &ids)?;
    check_coverage(&p)?;
    check_masses_and_damping(&p, &ids)?;
    check_beam_tensions(&p, &ids)?;
    check_links_and_contacts(&p, &ids)?;
    check_matrix_elements(&p, &ids)?;
    let fixed = check_constraints(&p, &ids)?;
    check_point_elements(&p, &ids, &fixed)?;
    check_loads_and_cases(&p, &ids)?;
    Ok(p)
}

fn normalise(p: &mut ModelParts) {
    p.nodes.sort_by_key(|n| n.id);
    p.elements.sort_by_key(|e| e.id);
    for s in &mut p.node_sets {
        sort_unique(&mut s.nodes);
    }
    for s in &mut p.element_sets {
        sort_unique(&mut s.elements);
    }
    for m in &mut p.materials {
        sort_unique(&mut m.elements);
    }
    for g in &mut p.geometries {
        sort_unique(&mut g.elements);
    }
    for t in &mut p.beam_tensions {
        sort_unique(&mut t.elements);
    }
    for c in &mut p.moving_contacts {
        sort_unique(&mut c.line);
    }
    for d in &mut p.damping {
        sort_unique(&mut d.elements);
        sort_unique(&mut d.mass_nodes);
    }
    for t in &mut p.rigid_ties {
        sort_unique(&mut t.tied);
        sort_unique(&mut t.dofs);
    }
    for f in &mut p.fixed_disp {
        sort_unique(&mut f.nodes);
    }
    for l in p.point_loads.iter_mut().chain(
        p.load_cases
            .iter_mut()
            .flat_map(|c| c.point_loads.iter_mut()),
    ) {
        sort_unique(&mut l.nodes);
    }
    for v in &mut p.initial_velocities {
        sort_unique(&mut v.nodes);
    }
    for o in &mut p.outputs {
        sort_unique(&mut o.nodes);
    }
    p.point_laws.sort_by_key(|e| (e.node, e.dof));
    p.dashpots.sort_by_key(|d| (d.node, d.dof));
}

/// The sorted node and element ids, each once.
struct Ids {
    nodes: Vec<NodeId>,
    elements: Vec<ElementId>,
}

impl Ids {
    fn of(p: &ModelParts) -> Result<Ids, ModelError> {
        let nodes: Vec<NodeId> = p.nodes.iter().map(|n| n.id).collect();
        let elements: Vec<ElementId> = p.elements.iter().map(|e| e.id).collect();
        if let Some(w) = nodes.windows(2).find(|w| w[0] == w[1]) {
            return fail(
                Site::Node(w[0]),
                format!("node {} is defined twice", w[0]),
                "unique node ids",
            );
        }
        if let Some(w) = elements.windows(2).find(|w| w[0] == w[1]) {
            return fail(
                Site::Element(w[0]),
                format!("element {} is defined twice", w[0]),
                "unique element ids",
            );
        }
        for n in &p.nodes {
            if n.xyz.iter().any(|x| !x.is_finite()) {
                return fail(
                    Site::Node(n.id),
                    format!("node {} has coordinates {:?}", n.id, n.xyz),
                    "finite coordinates (mm)",
                );
            }
        }
        Ok(Ids { nodes, elements })
    }

    fn has_node(&self, id: NodeId) -> bool {
        self.nodes.binary_search(&id).is_ok()
    }

    /// Fails unless every node of `list` exists.
    fn nodes_exist(&self, list: &[NodeId], site: Site) -> Result<(), ModelError> {
        match list.iter().find(|n| !self.has_node(**n)) {
            Some(n) => fail(
                site,
                format!("node {n} does not exist"),
                "a node defined in COORDINATES",
            ),
            None => Ok(()),
        }
    }

    /// Fails unless every element of `list` exists.
    fn elements_exist(&self, list: &[ElementId], site: Site) -> Result<(), ModelError> {
        match list
            .iter()
            .find(|e| self.elements.binary_search(e).is_err())
        {
            Some(e) => fail(
                site,
                format!("element {e} does not exist"),
                "an element defined in CONNECTIVITY",
            ),
            None => Ok(()),
        }
    }
}

fn non_empty<T>(list: &[T], site: Site, what: &str) -> Result<(), ModelError> {
    if list.is_empty() {
        return fail(
            site,
            format!("the list of {what} is empty"),
            format!("at least one {}", what.trim_end_matches('s')),
        );
    }
    Ok(())
}

fn xyz(p: &ModelParts, id: NodeId) -> Option<[f64; 3]> {
    p.nodes
        .binary_search_by_key(&id, |n| n.id)
        .ok()
        .map(|i| p.nodes[i].xyz)
}

/// The vector from an element's first node to its second (zero if one is missing).
fn element_axis(p: &ModelParts, id: ElementId) -> [f64; 3] {
    match p.elements.binary_search_by_key(&id, |e| e.id) {
        Ok(i) => {
            let [a, b] = p.elements[i].nodes;
            sub(xyz(p, b).unwrap_or_default(), xyz(p, a).unwrap_or_default())
        }
        Err(_) => [0.0; 3],
    }
}

fn check_elements(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let scale = p
        .nodes
        .iter()
        .flat_map(|n| n.xyz)
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    for e in &p.elements {
        if !p.element_types.contains(&e.kind) {
            return fail(
                Site::ElementType(e.id),
                format!("element type {} is not declared", e.kind.number()),
                format!("ELEMENTS, {} in the parameter section", e.kind.number()),
            );
        }
        for (k, n) in e.nodes.iter().enumerate() {
            if !ids.has_node(*n) {
                return fail(
                    Site::ElementNode(e.id, k),
                    format!("element {} refers to node {n}, which does not exist", e.id),
                    "a node defined in COORDINATES",
                );
            }
        }
        if e.nodes[0] == e.nodes[1] {
            return fail(
                Site::ElementNode(e.id, 1),
                format!("element {} joins node {} to itself", e.id, e.nodes[0]),
                "two different nodes",
            );
        }
        if norm(element_axis(p, e.id)) <= ZERO_LENGTH * scale {
            return fail(
                Site::Element(e.id),
                format!(
                    "element {} has zero length (nodes {} and {} coincide)",
                    e.id, e.nodes[0], e.nodes[1]
                ),
                "an element of non-zero length",
            );
        }
    }
    Ok(())
}

fn check_sets(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let mut names = HashSet::new();
    for (i, s) in p.node_sets.iter().enumerate() {
        if !names.insert(s.name.as_str()) {
            return fail(
                Site::NodeSet(i),
                format!("the node set `{}` is defined twice", s.name),
                "unique set names",
            );
        }
        ids.nodes_exist(&s.nodes, Site::NodeSet(i))?;
    }
    names.clear();
    for (i, s) in p.element_sets.iter().enumerate() {
        if !names.insert(s.name.as_str()) {
            return fail(
                Site::ElementSet(i),
                format!("the element set `{}` is defined twice", s.name),
                "unique set names",
            );
        }
        ids.elements_exist(&s.elements, Site::ElementSet(i))?;
    }
    Ok(())
}

fn check_materials(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let mut names = HashSet::new();
    for (i, m) in p.materials.iter().enumerate() {
        let site = Site::Material(i);
        if !names.insert(m.name.as_str()) {
            return fail(
                site,
                format!("material name `{}` is used twice", m.name),
                "a unique material name",
            );
        }
        if !(m.youngs_modulus > 0.0 && m.youngs_modulus.is_finite()) {
            return fail(
                site,
                format!("Young's modulus E is {:?}", m.youngs_modulus),
                "E > 0 (MPa)",
            );
        }
        if !(m.poisson > -1.0 && m.poisson < 0.5) {
            return fail(
                site,
                format!("Poisson's ratio is {:?}", m.poisson),
                "-1 < Poisson's ratio < 0.5",
            );
        }
        if !(m.density >= 0.0 && m.density.is_finite()) {
            return fail(
                site,
                format!("the density is {:?}", m.density),
                "density >= 0 (t/mm^3)",
            );
        }
        non_empty(&m.elements, site, "elements")?;
        ids.elements_exist(&m.elements, site)?;
    }
    Ok(())
}

fn positive(x: f64) -> bool {
    x > 0.0 && x.is_finite()
}

fn check_geometries(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    for (i, g) in p.geometries.iter().enumerate() {
        let values = match g.section {
            Section::SolidCircle { diameter } => vec![diameter],
            Section::General {
                area,
                iyy,
                izz,
                torsion,
                ..
            } => vec![area, iyy, izz, torsion],
        };
        if !values.iter().all(|&x| positive(x)) {
            return fail(
                Site::GeometrySection(i),
                format!(
                    "the section {:?} has a value that is not positive",
                    g.section
                ),
                "positive section values (mm, mm^2, mm^4)",
            );
        }
        let v = g.orientation;
        if !(norm(v) > 0.0 && norm(v).is_finite()) {
            return fail(
                Site::GeometryOrientation(i),
                "the orientation vector is zero",
                "a non-zero vector",
            );
        }
        non_empty(&g.elements, Site::Geometry(i), "elements")?;
        ids.elements_exist(&g.elements, Site::Geometry(i))?;
        for &id in &g.elements {
            let kind = p
                .elements
                .binary_search_by_key(&id, |e| e.id)
                .map(|k| p.elements[k].kind);
            let shear = match g.section {
                Section::General {
                    shear_coefficient, ..
                } => positive(shear_coefficient),
                Section::SolidCircle { .. } => true,
            };
            if !shear && kind == Ok(ElementType::Beam98) {
                return fail(
                    Site::GeometrySection(i),
                    format!("element {id} is of type 98 (Timoshenko), which needs the shear coefficient"),
                    "A, I1, I2, J, shear coefficient",
                );
            }
            let axis = element_axis(p, id);
            if norm(cross(v, axis)) <= PARALLEL * norm(v) * norm(axis) {
                return fail(
                    Site::GeometryOrientation(i),
                    format!("the orientation vector {v:?} is parallel to element {id}"),
                    "a vector not parallel to any listed element",
                );
            }
        }
    }
    Ok(())
}

fn check_coverage(p: &ModelParts) -> Result<(), ModelError> {
    for e in &p.elements {
        let listed = |list: &[ElementId]| list.binary_search(&e.id).is_ok();
        if !p.materials.iter().any(|m| listed(&m.elements)) {
            return fail(
                Site::Element(e.id),
                format!("element {} has no material", e.id),
                "the element in the list of an ISOTROPIC material",
            );
        }
        if !p.geometries.iter().any(|g| listed(&g.elements)) {
            return fail(
                Site::Element(e.id),
                format!("element {} has no geometry", e.id),
                "the element in the list of a GEOMETRY",
            );
        }
    }
    Ok(())
}

fn check_masses_and_damping(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let mut mass_at = HashSet::new();
    for (i, m) in p.point_masses.iter().enumerate() {
        let site = Site::PointMass(i);
        if !ids.has_node(m.node) {
            return fail(
                site,
                format!("node {} does not exist", m.node),
                "a node defined in COORDINATES",
            );
        }
        if !mass_at.insert(m.node) {
            return fail(
                site,
                format!("node {} already has a point mass", m.node),
                "one point mass per node",
            );
        }
        let values = std::iter::once(m.mass).chain(m.inertia);
        if !values.into_iter().all(|x| x >= 0.0 && x.is_finite()) {
            return fail(
                site,
                format!(
                    "the point mass at node {} has mass {:?} and inertia {:?}",
                    m.node, m.mass, m.inertia
                ),
                "mass (t) and rotary inertia (t mm^2) >= 0",
            );
        }
    }
    for (i, d) in p.damping.iter().enumerate() {
        if !(d.alpha >= 0.0 && d.alpha.is_finite() && d.beta >= 0.0 && d.beta.is_finite()) {
            return fail(
                Site::Damping(i),
                format!("alpha = {:?}, beta = {:?}", d.alpha, d.beta),
                "alpha >= 0 (1/s) and beta >= 0 (s)",
            );
        }
        ids.elements_exist(&d.elements, Site::Damping(i))?;
        if let Some(n) = d.mass_nodes.iter().find(|n| !mass_at.contains(n)) {
            return fail(
                Site::DampingMassNodes(i),
                format!("node {n} has no POINT MASS to damp"),
                "nodes that carry a POINT MASS",
            );
        }
    }
    Ok(())
}

/// Beam tensions: a finite force on existing elements, each element in one entry.
fn check_beam_tensions(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let mut seen = HashSet::new();
    for (i, t) in p.beam_tensions.iter().enumerate() {
        let site = Site::BeamTension(i);
        if !t.force.is_finite() {
            return fail(
                site,
                format!("axial force {:?}", t.force),
                "a finite force (N)",
            );
        }
        non_empty(&t.elements, site, "elements")?;
        ids.elements_exist(&t.elements, site)?;
        if let Some(e) = t.elements.iter().find(|e| !seen.insert(**e)) {
            return fail(
                site,
                format!("element {e} already has a tension"),
                "each element in one BEAM TENSION entry",
            );
        }
    }
    Ok(())
}

/// Tension links and moving contacts: existing nodes, a translation, a positive finite
/// stiffness, finite slack, speed and start, one link per node pair and DOF (checked in
/// one pass, linear), a line of two nodes or more without the head that is one straight
/// wire across the contact's DOF ([`super::line`]).
fn check_links_and_contacts(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let translation = "a translation DOF 1..3";
    let mut linked: HashMap<(NodeId, NodeId, u8), usize> = HashMap::new();
    for (i, l) in p.tension_links.iter().enumerate() {
        let site = Site::TensionLink(i);
        ids.nodes_exist(&l.nodes, site)?;
        if l.nodes[0] == l.nodes[1] {
            return fail(
                site,
                format!("both ends are node {}", l.nodes[0]),
                "two different nodes",
            );
        }
        if !(1..=3).contains(&l.dof) {
            return fail(site, format!("DOF {}", l.dof), translation);
        }
        if !(l.stiffness > 0.0 && l.stiffness.is_finite() && l.slack.is_finite()) {
            return fail(
                site,
                format!("stiffness {:?}, slack {:?}", l.stiffness, l.slack),
                "a stiffness > 0 (N/mm) and a finite slack (mm)",
            );
        }
        let pair = (
            l.nodes[0].min(l.nodes[1]),
            l.nodes[0].max(l.nodes[1]),
            l.dof,
        );
        if let Some(first) = linked.insert(pair, i) {
            return fail(
                site,
                format!(
                    "tension link {} already links nodes {} and {} along DOF {}",
                    first + 1,
                    pair.0,
                    pair.1,
                    l.dof
                ),
                "one TENSION LINK per node pair and DOF (two links on one pair act as one \
                 spring: merge them)",
            );
        }
    }
    // Node pairs joined by an element, for the contact lines (built once, linear).
    let joined: HashSet<(NodeId, NodeId)> = if p.moving_contacts.is_empty() {
        HashSet::new()
    } else {
        p.elements
            .iter()
            .map(|e| (e.nodes[0].min(e.nodes[1]), e.nodes[0].max(e.nodes[1])))
            .collect()
    };
    for (i, c) in p.moving_contacts.iter().enumerate() {
        let site = Site::MovingContact(i);
        ids.nodes_exist(&[c.head], site)?;
        ids.nodes_exist(&c.line, site)?;
        if c.line.len() < 2 || c.line.contains(&c.head) {
            return fail(
                site,
                format!("a line of {} nodes (head {})", c.line.len(), c.head),
                "a line of at least two nodes, not including the head",
            );
        }
        if !(1..=3).contains(&c.dof) {
            return fail(site, format!("DOF {}", c.dof), translation);
        }
        let finite = c.speed.is_finite() && c.start.is_finite();
        if !(c.stiffness > 0.0 && c.stiffness.is_finite() && finite) {
            return fail(
                site,
                format!(
                    "stiffness {:?}, speed {:?}, start {:?}",
                    c.stiffness, c.speed, c.start
                ),
                "a stiffness > 0 (N/mm), a finite speed (mm/s) and start (mm)",
            );
        }
        let nodes: Vec<(NodeId, [f64; 3])> = c
            .line
            .iter()
            .map(|&n| (n, xyz(p, n).unwrap_or_default()))
            .collect();
        if let Err((message, expected)) =
            super::line::contact_axis(&nodes, c.dof, |a, b| joined.contains(&(a.min(b), a.max(b))))
        {
            return fail(site, message, expected);
        }
    }
    Ok(())
}

/// Matrix elements: unique names, existing nodes, DOFs 1..=6 once each, finite
/// `n x n` matrices (damping empty or `n x n`), symmetric, mass and damping positive
/// semi-definite.
fn check_matrix_elements(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let mut names = HashSet::new();
    for (i, e) in p.matrix_elements.iter().enumerate() {
        let site = Site::MatrixElement(i);
        if e.name.is_empty() || !names.insert(e.name.to_ascii_lowercase()) {
            return fail(
                site,
                format!("name `{}` is empty or used twice", e.name),
                "a unique name per matrix element",
            );
        }
        let n = e.dofs.len();
        if n == 0 {
            return fail(site, "no DOF", "at least one (node, DOF) pair");
        }
        let mut seen = HashSet::new();
        for &(node, dof) in &e.dofs {
            ids.nodes_exist(&[node], site)?;
            if !dof_ok(dof) {
                return fail(site, format!("node {node} DOF {dof}"), "DOFs 1..6");
            }
            if !seen.insert((node, dof)) {
                return fail(
                    site,
                    format!("node {node} DOF {dof} is listed twice"),
                    "each (node, DOF) once",
                );
            }
        }
        let matrices = [("stiffness", &e.stiffness), ("mass", &e.mass)];
        let damping = (!e.damping.is_empty()).then_some(("damping", &e.damping));
        for (what, a) in matrices.into_iter().chain(damping) {
            if a.len() != n * n {
                return fail(
                    site,
                    format!("a {what} matrix of {} entries", a.len()),
                    format!("{n} x {n} = {} entries", n * n),
                );
            }
            if let Some(k) = a.iter().position(|x| !x.is_finite()) {
                return fail(
                    site,
                    format!("{what} entry ({}, {}) is {}", k / n + 1, k % n + 1, a[k]),
                    "finite entries",
                );
            }
            let scale = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            for r in 0..n {
                for c in r + 1..n {
                    if (a[r * n + c] - a[c * n + r]).abs() > SYMMETRY * scale {
                        return fail(
                            site,
                            format!(
                                "{what} entries ({}, {}) = {} and ({}, {}) = {} differ",
                                r + 1,
                                c + 1,
                                a[r * n + c],
                                c + 1,
                                r + 1,
                                a[c * n + r]
                            ),
                            "a symmetric matrix",
                        );
                    }
                }
            }
            if what != "stiffness" {
                let m = nalgebra::DMatrix::from_row_slice(n, n, a);
                let eig = ((&m + m.transpose()) * 0.5).symmetric_eigenvalues();
                let lowest = eig.iter().copied().fold(f64::INFINITY, f64::min);
                let largest = eig.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
                if lowest < -SEMI_DEFINITE * largest {
                    return fail(
                        site,
                        format!("the {what} matrix has the eigenvalue {lowest:e}"),
                        format!("a positive semi-definite {what} matrix"),
                    );
                }
            }
        }
    }
    Ok(())
}

fn dof_ok(d: u8) -> bool {
    (1..=6).contains(&d)
}

/// Non-empty, existing nodes and DOFs 1..=6 with finite values.
fn dof_values(
    dofs: &[(u8, f64)],
    nodes: &[NodeId],
    site: Site,
    ids: &Ids,
) -> Result<(), ModelError> {
    non_empty(nodes, site, "nodes")?;
    ids.nodes_exist(nodes, site)?;
    match dofs.iter().find(|(d, v)| !dof_ok(*d) || !v.is_finite()) {
        Some((d, v)) => fail(
            site,
            format!("DOF {d} with value {v:?}"),
            "DOFs 1..6 with finite values",
        ),
        None => Ok(()),
    }
}

/// [`dof_values`] of each group, and each (node, DOF) once across `groups`.
fn dof_groups<'g>(
    groups: impl Iterator<Item = (&'g [(u8, f64)], &'g [NodeId], Site)>,
    ids: &Ids,
) -> Result<HashSet<(NodeId, u8)>, ModelError> {
    let mut seen = HashSet::new();
    for (dofs, nodes, site) in groups {
        dof_values(dofs, nodes, site, ids)?;
        for &(d, _) in dofs {
            for &n in nodes {
                if !seen.insert((n, d)) {
                    return fail(
                        site,
                        format!("node {n} DOF {d} is given twice"),
                        "each DOF of a node given once",
                    );
                }
            }
        }
    }
    Ok(seen)
}

/// Prescribed DOFs and rigid ties; returns the prescribed (node, DOF) pairs.
fn check_constraints(p: &ModelParts, ids: &Ids) -> Result<HashSet<(NodeId, u8)>, ModelError> {
    let groups = p.fixed_disp.iter().enumerate();
    let fixed = dof_groups(
        groups.map(|(i, f)| (&f.dofs[..], &f.nodes[..], Site::FixedDisp(i))),
        ids,
    )?;
    let mut tied_by: HashMap<NodeId, usize> = HashMap::new();
    for (i, t) in p.rigid_ties.iter().enumerate() {
        if !ids.has_node(t.reference) {
            return fail(
                Site::RigidTieReference(i),
                format!("the reference node {} does not exist", t.reference),
                "a node defined in COORDINATES",
            );
        }
        non_empty(&t.tied, Site::RigidTieTied(i), "tied nodes")?;
        ids.nodes_exist(&t.tied, Site::RigidTieTied(i))?;
        if t.dofs.is_empty() || !t.dofs.iter().all(|&d| dof_ok(d)) {
            return fail(
                Site::RigidTie(i),
                format!("the tied DOFs are {:?}", t.dofs),
                "DOFs 1..6",
            );
        }
        if t.tied.binary_search(&t.reference).is_ok() {
            return fail(
                Site::RigidTieTied(i),
                format!("the reference node {} is in its own tied list", t.reference),
                "tied nodes other than the reference",
            );
        }
        for &n in &t.tied {
            if let Some(other) = tied_by.insert(n, i) {
                let name = &p.rigid_ties[other].name;
                return fail(
                    Site::RigidTieTied(i),
                    format!("node {n} is already tied by `{name}`"),
                    "each node tied by one tie",
                );
            }
            if let Some(d) = t.dofs.iter().find(|&&d| fixed.contains(&(n, d))) {
                return fail(
                    Site::RigidTieTied(i),
                    format!("node {n} DOF {d} is tied and also prescribed by FIXED DISP"),
                    "a tied DOF that is not prescribed",
                );
            }
        }
    }
    for (i, t) in p.rigid_ties.iter().enumerate() {
        if let Some(&other) = tied_by.get(&t.reference) {
            let name = &p.rigid_ties[other].name;
            return fail(
                Site::RigidTieReference(i),
                format!(
                    "the reference node {} is tied by `{name}`; ties may not chain",
                    t.reference
                ),
                "a reference node that no tie ties",
            );
        }
    }
    Ok(fixed)
}

/// Nonlinear point elements and dashpots: existing nodes, free DOFs, values >= 0.
fn check_point_elements(
    p: &ModelParts,
    ids: &Ids,
    fixed: &HashSet<(NodeId, u8)>,
) -> Result<(), ModelError> {
    let laws = p.point_laws.iter().enumerate().map(|(i, e)| {
        let values = [e.cubic, e.quadratic, e.friction];
        (e.node, e.dof, values.to_vec(), Site::PointLaw(i))
    });
    let dashpots = p.dashpots.iter().enumerate();
    let dashpots = dashpots.map(|(i, d)| (d.node, d.dof, vec![d.c], Site::Dashpot(i)));
    for (node, dof, values, site) in laws.chain(dashpots) {
        if !ids.has_node(node) {
            return fail(
                site,
                format!("node {node} does not exist"),
                "a node defined in COORDINATES",
            );
        }
        if !dof_ok(dof) || fixed.contains(&(node, dof)) {
            return fail(
                site,
                format!("node {node} DOF {dof} is not a free DOF"),
                "a DOF 1..6 that FIXED DISP does not prescribe",
            );
        }
        let tie = p
            .rigid_ties
            .iter()
            .find(|t| t.dofs.contains(&dof) && t.tied.binary_search(&node).is_ok());
        if let Some(t) = tie {
            return fail(
                site,
                format!(
                    "node {node} DOF {dof} is tied by `{}`; put the element on the \
                     reference node {}",
                    t.name, t.reference
                ),
                "a free DOF",
            );
        }
        if !values.iter().all(|x| *x >= 0.0 && x.is_finite()) {
            return fail(
                site,
                format!("node {node} DOF {dof} has the values {values:?}"),
                "non-negative values",
            );
        }
    }
    for w in p.point_laws.windows(2) {
        if (w[0].node, w[0].dof) == (w[1].node, w[1].dof) {
            return fail(
                Site::Model,
                format!("node {} DOF {} has two point elements", w[0].node, w[0].dof),
                "one point element per node and DOF (the laws combined)",
            );
        }
    }
    for w in p.dashpots.windows(2) {
        if (w[0].node, w[0].dof) == (w[1].node, w[1].dof) {
            return fail(
                Site::Model,
                format!("node {} DOF {} has two dashpots", w[0].node, w[0].dof),
                "one dashpot per node and DOF",
            );
        }
    }
    let md = &p.modal_damping;
    let ratios_ok = md.ratios.iter().all(|z| *z >= 0.0 && z.is_finite());
    let eta_ok = md.loss_factor >= 0.0 && md.loss_factor.is_finite();
    if !ratios_ok || !eta_ok || (md.loss_factor > 0.0 && md.loss_factor_modes == 0) {
        return fail(
            Site::ModalDamping,
            format!("{md:?}"),
            "a loss factor >= 0 on at least one mode, and damping ratios >= 0",
        );
    }
    Ok(())
}

fn check_loads_and_cases(p: &ModelParts, ids: &Ids) -> Result<(), ModelError> {
    let mut names = HashSet::new();
    for (i, t) in p.tables.iter().enumerate() {
        let sorted = t.points.windows(2).all(|w| w[0].0 < w[1].0);
        let finite = t.points.iter().all(|(x, y)| x.is_finite() && y.is_finite());
        if !names.insert(t.name.as_str()) || t.points.is_empty() || !sorted || !finite {
            return fail(
                Site::Table(i),
                format!("the table `{}` is repeated, empty or not sorted", t.name),
                "a uniquely named table of finite points with increasing times",
            );
        }
    }
    let mut loads: Vec<(&PointLoad, Site)> = p
        .point_loads
        .iter()
        .enumerate()
        .map(|(i, l)| (l, Site::PointLoad(i)))
        .collect();
    for (case, c) in p.load_cases.iter().enumerate() {
        for (load, l) in c.point_loads.iter().enumerate() {
            loads.push((l, Site::CasePointLoad { case, load }));
        }
    }
    for (l, site) in loads {
        dof_values(&l.dofs, &l.nodes, site, ids)?;
        if let Some(name) = &l.table {
            if !names.contains(name.as_str()) {
                return fail(
                    site,
                    format!("no table named `{name}`"),
                    "a TABLE defined in the model definition",
                );
            }
        }
    }
    let groups = p.initial_velocities.iter().enumerate();
    dof_groups(
        groups.map(|(i, v)| (&v.dofs[..], &v.nodes[..], Site::InitialVelocity(i))),
        ids,
    )?;
    for (i, o) in p.outputs.iter().enumerate() {
        non_empty(&o.nodes, Site::Output(i), "nodes")?;
        ids.nodes_exist(&o.nodes, Site::Output(i))?;
        if o.every == 0 || o.dofs.is_empty() || !o.dofs.iter().all(|&d| dof_ok(d)) {
            return fail(
                Site::Output(i),
                format!("DOFs {:?} every {} steps", o.dofs, o.every),
                "DOFs 1..6, every >= 1 step",
            );
        }
    }
    for (i, c) in p.load_cases.iter().enumerate() {
        check_analysis(&c.analysis, Site::LoadCase(i))?;
    }
    Ok(())
}

fn check_analysis(a: &Analysis, site: Site) -> Result<(), ModelError> {
    let ok = match *a {
        Analysis::Static { time, .. } => time >= 0.0 && time.is_finite(),
        Analysis::Modal { modes } => modes >= 1,
        Analysis::Transient {
            dt,
            total_time,
            method,
        } => {
            let method_ok = match method {
                TransientMethod::Modal { modes } => modes >= 1,
                TransientMethod::Direct(_) => true,
            };
            positive(dt) && positive(total_time) && method_ok
        }
    };
    if !ok {
        return fail(
            site,
            format!("the analysis {a:?}"),
            "positive times and steps, at least one mode",
        );
    }
    Ok(())
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

#[cfg(test)]
mod tests;
