//! Stage two of reading: the located [`RawDeck`] -> a validated [`Model`].
//!
//! Resolves ids, ranges and set names to sorted, unique id lists and checks what
//! involves more than one card: unique ids and names, declared element types, the
//! SIZING bounds, existing nodes and elements, no zero-length element, a material and
//! a geometry for every element, orientations not parallel to their elements, the
//! shear coefficient of type-98 sections, point masses under damped nodes, tables that
//! exist, each DOF prescribed once and not both tied and prescribed, rigid ties
//! that neither overlap nor chain, and nonlinear point elements on existing, free
//! DOFs (one line per card, node and DOF; the cards on one DOF combine). Every error names the line of the card at fault.
//!
//! Sets and tables must be defined on an earlier line than the list that uses them,
//! so a set can never contain itself.

use std::collections::HashMap;

use super::error::{DeckError, Loc};
use super::lexer::ListItem;
use super::raw::{
    PointLawKind, RawDeck, RawDofValues, RawList, RawLoadCase, RawPointLoad, SetKind,
};
use crate::model::{
    Analysis, Damping, Element, ElementSet, ElementType, FixedDisp, Geometry, InitialVelocity,
    LoadCase, Material, Model, Node, NodeSet, OutputRequest, PointElement, PointLoad, PointMass,
    RigidTie, Table,
};

/// Relative tolerance under which an element counts as zero-length: its length over
/// the model's largest coordinate. Far above round-off (1e-16), far below any mesh.
const ZERO_LENGTH: f64 = 1e-12;
/// |v x e| <= PARALLEL |v| |e|: the orientation fixes no plane (angle below 1e-6 rad).
const PARALLEL: f64 = 1e-6;

struct Builder<'a> {
    file: &'a str,
    node_ids: Vec<u32>,
    element_ids: Vec<u32>,
    /// Sets resolved so far, in deck order: kind, name, definition line, ids.
    sets: Vec<(SetKind, String, Loc, Vec<u32>)>,
    /// Every set's definition, to tell "defined later" from "not defined".
    all_sets: Vec<(SetKind, String, Loc)>,
}

impl Builder<'_> {
    fn err(
        &self,
        loc: Loc,
        card: &str,
        msg: impl Into<String>,
        expected: impl Into<String>,
    ) -> DeckError {
        DeckError::new(self.file, loc, Some(card), msg, expected)
    }

    /// Rejects the second occurrence of a name or id among `items` (e.g. two materials
    /// called `steel`), naming the line of the first.
    fn unique<'n>(
        &self,
        card: &'static str,
        what: &'static str,
        items: impl Iterator<Item = (&'n str, Loc)>,
    ) -> Result<(), DeckError> {
        match duplicate(items) {
            None => Ok(()),
            Some((name, first, loc)) => Err(self.err(
                loc,
                card,
                format!(
                    "{what} `{name}` is used twice (first at line {})",
                    first.line
                ),
                format!("a unique {what}"),
            )),
        }
    }

    /// `items` sorted by id; a repeated id is an error at its later definition.
    fn sorted_by_id<T: Clone>(
        &self,
        items: &[T],
        key: impl Fn(&T) -> (u32, Loc),
        card: &'static str,
        what: &'static str,
    ) -> Result<Vec<T>, DeckError> {
        let mut sorted = items.to_vec();
        sorted.sort_by_key(|x| key(x).0);
        for w in sorted.windows(2) {
            let ((id, a), (other, b)) = (key(&w[0]), key(&w[1]));
            if id == other {
                let (first, second) = if a < b { (a, b) } else { (b, a) };
                return Err(self.err(
                    second,
                    card,
                    format!(
                        "{what} {id} is defined twice (first at line {})",
                        first.line
                    ),
                    format!("unique {what} ids"),
                ));
            }
        }
        Ok(sorted)
    }

    /// The sorted, unique ids a list names.
    fn resolve(&self, list: &RawList, kind: SetKind, card: &str) -> Result<Vec<u32>, DeckError> {
        let ids = match kind {
            SetKind::Node => &self.node_ids,
            SetKind::Element => &self.element_ids,
        };
        let defined_in = match kind {
            SetKind::Node => "COORDINATES",
            SetKind::Element => "CONNECTIVITY",
        };
        let word = kind.word();
        let mut out = Vec::new();
        for (item, loc) in &list.items {
            match item {
                ListItem::Id(id) => {
                    if ids.binary_search(id).is_err() {
                        return Err(self.err(
                            *loc,
                            card,
                            format!("{word} {id} does not exist"),
                            format!("a {word} defined in {defined_in}"),
                        ));
                    }
                    out.push(*id);
                }
                ListItem::Range { from, to, by } => {
                    let lo = ids.partition_point(|&x| x < *from);
                    let mut next = u64::from(*from);
                    for &id in ids[lo..].iter().take_while(|&&x| x <= *to) {
                        if (id - from) % by != 0 {
                            continue;
                        }
                        if u64::from(id) != next {
                            break;
                        }
                        out.push(id);
                        next += u64::from(*by);
                    }
                    if next <= u64::from(*to) {
                        let step = if *by == 1 {
                            String::new()
                        } else {
                            format!(" BY {by}")
                        };
                        return Err(self.err(
                            *loc,
                            card,
                            format!(
                                "{word} {next} of the range {from} TO {to}{step} does not exist"
                            ),
                            format!("a range of {word}s that all exist"),
                        ));
                    }
                }
                ListItem::All => out.extend_from_slice(ids),
                ListItem::Set(name) => {
                    let found = self
                        .sets
                        .iter()
                        .find(|(k, n, at, _)| *k == kind && n == name && at.line < loc.line);
                    if let Some((_, _, _, members)) = found {
                        out.extend_from_slice(members);
                        continue;
                    }
                    let same_kind = self
                        .all_sets
                        .iter()
                        .find(|(k, n, _)| *k == kind && n == name);
                    let other_kind = self
                        .all_sets
                        .iter()
                        .find(|(k, n, _)| *k != kind && n == name);
                    let (msg, expected) = match (same_kind, other_kind) {
                        (Some((_, _, at)), _) if at.line < loc.line => (
                            format!("the {word} set `{name}` refers to itself"),
                            "sets made of ids, ranges and earlier sets".to_string(),
                        ),
                        (Some((_, _, at)), _) => (
                            format!(
                                "the {word} set `{name}` is defined later (line {})",
                                at.line
                            ),
                            "sets defined before they are used".to_string(),
                        ),
                        (None, Some((k, _, _))) => (
                            format!(
                                "`{name}` names {} set, not a {word} set",
                                if k.word() == "node" {
                                    "a node"
                                } else {
                                    "an element"
                                }
                            ),
                            format!("a {word} set"),
                        ),
                        (None, None) => (
                            format!("no {word} set named `{name}`"),
                            format!(
                                "a set defined earlier with DEFINE, {}, SET, {name}",
                                word.to_ascii_uppercase()
                            ),
                        ),
                    };
                    return Err(self.err(*loc, card, msg, expected));
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        Ok(out)
    }

    fn non_empty(
        &self,
        ids: Vec<u32>,
        list: &RawList,
        card: &str,
        what: &str,
    ) -> Result<Vec<u32>, DeckError> {
        if ids.is_empty() {
            return Err(self.err(
                list.loc,
                card,
                format!("the list of {what} is empty"),
                format!("at least one {what}"),
            ));
        }
        Ok(ids)
    }
}

/// First duplicate name among `(name, loc)` pairs, reported at the later one.
fn duplicate<'n>(items: impl Iterator<Item = (&'n str, Loc)>) -> Option<(&'n str, Loc, Loc)> {
    let mut seen: HashMap<&str, Loc> = HashMap::new();
    for (name, loc) in items {
        if let Some(first) = seen.get(name) {
            return Some((name, *first, loc));
        }
        seen.insert(name, loc);
    }
    None
}

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

    // Nodes and elements, sorted by id, each id once.
    let nodes = b.sorted_by_id(&raw.nodes, |n| (n.id, n.loc), "COORDINATES", "node")?;
    let elements = b.sorted_by_id(&raw.elements, |e| (e.id, e.loc), "CONNECTIVITY", "element")?;
    b.node_ids = nodes.iter().map(|n| n.id).collect();
    b.element_ids = elements.iter().map(|e| e.id).collect();
    let xyz_of = |id: u32| -> Option<[f64; 3]> {
        nodes
            .binary_search_by_key(&id, |n| n.id)
            .ok()
            .map(|i| nodes[i].xyz)
    };

    if let Some((max_elements, max_nodes, loc)) = raw.sizing {
        for (count, max, what) in [
            (elements.len(), max_elements, "elements"),
            (nodes.len(), max_nodes, "nodes"),
        ] {
            if max > 0 && count as u64 > max {
                return Err(b.err(
                    loc,
                    "SIZING",
                    format!("the model has {count} {what}, more than the {max} SIZING allows"),
                    format!("SIZING's number of {what} >= {count}, or 0"),
                ));
            }
        }
    }

    // Elements: declared type, existing distinct nodes, non-zero length.
    let declared: Vec<ElementType> = raw.element_types.iter().map(|t| t.0).collect();
    let scale = nodes
        .iter()
        .flat_map(|n| n.xyz)
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    for e in &raw.elements {
        if !declared.contains(&e.kind) {
            return Err(b.err(
                e.type_loc,
                "CONNECTIVITY",
                format!("element type {} is not declared", e.kind.number()),
                format!("ELEMENTS, {} in the parameter section", e.kind.number()),
            ));
        }
        let mut ends = [[0.0; 3]; 2];
        for (k, (n, loc)) in e.nodes.iter().enumerate() {
            ends[k] = xyz_of(*n).ok_or_else(|| {
                b.err(
                    *loc,
                    "CONNECTIVITY",
                    format!("element {} refers to node {n}, which does not exist", e.id),
                    "a node defined in COORDINATES",
                )
            })?;
        }
        if e.nodes[0].0 == e.nodes[1].0 {
            return Err(b.err(
                e.nodes[1].1,
                "CONNECTIVITY",
                format!("element {} joins node {} to itself", e.id, e.nodes[0].0),
                "two different nodes",
            ));
        }
        let length = norm(sub(ends[1], ends[0]));
        if length <= ZERO_LENGTH * scale {
            return Err(b.err(
                e.loc,
                "CONNECTIVITY",
                format!(
                    "element {} has zero length (nodes {} and {} coincide)",
                    e.id, e.nodes[0].0, e.nodes[1].0
                ),
                "an element of non-zero length",
            ));
        }
    }
    let element_axis = |id: u32| -> [f64; 3] {
        let e = &elements[elements.binary_search_by_key(&id, |e| e.id).unwrap_or(0)];
        let a = xyz_of(e.nodes[0].0).unwrap_or_default();
        let c = xyz_of(e.nodes[1].0).unwrap_or_default();
        sub(c, a)
    };
    let kind_of = |id: u32| {
        elements
            .binary_search_by_key(&id, |e| e.id)
            .map(|i| elements[i].kind)
            .ok()
    };

    // Sets, in deck order (a set may use the sets before it).
    let mut node_sets = Vec::new();
    let mut element_sets = Vec::new();
    for s in &raw.sets {
        if let Some((_, _, first, _)) = b
            .sets
            .iter()
            .find(|(k, n, _, _)| *k == s.kind && *n == s.name)
        {
            return Err(b.err(
                s.loc,
                "DEFINE",
                format!(
                    "the {} set `{}` is defined twice (first at line {})",
                    s.kind.word(),
                    s.name,
                    first.line
                ),
                "unique set names",
            ));
        }
        let ids = b.resolve(&s.list, s.kind, "DEFINE")?;
        match s.kind {
            SetKind::Node => node_sets.push(NodeSet {
                name: s.name.clone(),
                nodes: ids.clone(),
            }),
            SetKind::Element => element_sets.push(ElementSet {
                name: s.name.clone(),
                elements: ids.clone(),
            }),
        }
        b.sets.push((s.kind, s.name.clone(), s.loc, ids));
    }

    // Tables.
    b.unique(
        "TABLE",
        "table name",
        raw.tables.iter().map(|t| (t.name.as_str(), t.loc)),
    )?;
    let tables: Vec<Table> = raw
        .tables
        .iter()
        .map(|t| Table {
            name: t.name.clone(),
            points: t.points.clone(),
        })
        .collect();

    // Materials.
    b.unique(
        "ISOTROPIC",
        "material name",
        raw.materials.iter().map(|m| (m.name.as_str(), m.loc)),
    )?;
    let ids: Vec<String> = raw.materials.iter().map(|m| m.id.to_string()).collect();
    b.unique(
        "ISOTROPIC",
        "material id",
        ids.iter()
            .map(String::as_str)
            .zip(raw.materials.iter().map(|m| m.loc)),
    )?;
    let mut materials = Vec::new();
    for m in &raw.materials {
        let list = b.resolve(&m.elements, SetKind::Element, "ISOTROPIC")?;
        let elements = b.non_empty(list, &m.elements, "ISOTROPIC", "elements")?;
        materials.push(Material {
            name: m.name.clone(),
            youngs_modulus: m.youngs_modulus,
            poisson: m.poisson,
            density: m.density,
            elements,
        });
    }

    // Geometries.
    b.unique(
        "GEOMETRY",
        "geometry name",
        raw.geometries
            .iter()
            .filter(|g| !g.name.is_empty())
            .map(|g| (g.name.as_str(), g.loc)),
    )?;
    let gids: Vec<(String, Loc)> = raw
        .geometries
        .iter()
        .filter_map(|g| g.id.map(|i| (i.to_string(), g.loc)))
        .collect();
    b.unique(
        "GEOMETRY",
        "geometry id",
        gids.iter().map(|(s, l)| (s.as_str(), *l)),
    )?;
    let mut geometries = Vec::new();
    for g in &raw.geometries {
        let list = b.resolve(&g.elements, SetKind::Element, "GEOMETRY")?;
        let elements = b.non_empty(list, &g.elements, "GEOMETRY", "elements")?;
        for &id in &elements {
            if !g.has_shear_coefficient && kind_of(id) == Some(ElementType::Beam98) {
                return Err(b.err(g.section_loc, "GEOMETRY", format!("element {id} is of type 98 (Timoshenko), which needs the shear coefficient"), "A, I1, I2, J, shear coefficient"));
            }
            let axis = element_axis(id);
            let v = g.orientation;
            if norm(cross(v, axis)) <= PARALLEL * norm(v) * norm(axis) {
                return Err(b.err(
                    g.orientation_loc,
                    "GEOMETRY",
                    format!("the orientation vector {v:?} is parallel to element {id}"),
                    "a vector not parallel to any listed element",
                ));
            }
        }
        geometries.push(Geometry {
            name: g.name.clone(),
            section: g.section.clone(),
            orientation: g.orientation,
            elements,
        });
    }

    // Every element has a material and a geometry.
    for e in &raw.elements {
        if !materials
            .iter()
            .any(|m| m.elements.binary_search(&e.id).is_ok())
        {
            return Err(b.err(
                e.loc,
                "CONNECTIVITY",
                format!("element {} has no material", e.id),
                "the element in the list of an ISOTROPIC material",
            ));
        }
        if !geometries
            .iter()
            .any(|g| g.elements.binary_search(&e.id).is_ok())
        {
            return Err(b.err(
                e.loc,
                "CONNECTIVITY",
                format!("element {} has no geometry", e.id),
                "the element in the list of a GEOMETRY",
            ));
        }
    }

    // Point masses.
    let mut point_masses = Vec::new();
    let mut mass_at: HashMap<u32, Loc> = HashMap::new();
    for p in &raw.point_masses {
        if b.node_ids.binary_search(&p.node).is_err() {
            return Err(b.err(
                p.node_loc,
                "POINT MASS",
                format!("node {} does not exist", p.node),
                "a node defined in COORDINATES",
            ));
        }
        if let Some(first) = mass_at.insert(p.node, p.node_loc) {
            return Err(b.err(
                p.node_loc,
                "POINT MASS",
                format!(
                    "node {} already has a point mass (line {})",
                    p.node, first.line
                ),
                "one point mass per node",
            ));
        }
        point_masses.push(PointMass {
            node: p.node,
            mass: p.mass,
            inertia: p.inertia,
        });
    }

    // Damping.
    let mut damping = Vec::new();
    for d in &raw.damping {
        let elements = b.resolve(&d.elements, SetKind::Element, "DAMPING")?;
        let mass_nodes = match &d.mass_nodes {
            Some(list) => {
                let ids = b.resolve(list, SetKind::Node, "DAMPING")?;
                if let Some(n) = ids.iter().find(|n| !mass_at.contains_key(n)) {
                    return Err(b.err(
                        list.loc,
                        "DAMPING",
                        format!("node {n} has no POINT MASS to damp"),
                        "nodes that carry a POINT MASS",
                    ));
                }
                ids
            }
            None => Vec::new(),
        };
        damping.push(Damping {
            alpha: d.alpha,
            beta: d.beta,
            elements,
            mass_nodes,
        });
    }

    // Prescribed DOFs (each once).
    let mut prescribed: HashMap<(u32, u8), Loc> = HashMap::new();
    let fixed_disp = dof_groups(&b, &raw.fixed_disp, "FIXED DISP", &mut prescribed)?
        .into_iter()
        .map(|(dofs, nodes)| FixedDisp { dofs, nodes })
        .collect();

    // Rigid ties.
    b.unique(
        "RBE2",
        "tie name",
        raw.rigid_ties.iter().map(|t| (t.name.as_str(), t.loc)),
    )?;
    let tids: Vec<String> = raw.rigid_ties.iter().map(|t| t.id.to_string()).collect();
    b.unique(
        "RBE2",
        "tie id",
        tids.iter()
            .map(String::as_str)
            .zip(raw.rigid_ties.iter().map(|t| t.loc)),
    )?;
    let mut rigid_ties: Vec<RigidTie> = Vec::new();
    let mut tied_by: HashMap<u32, (String, Loc)> = HashMap::new();
    for t in &raw.rigid_ties {
        if b.node_ids.binary_search(&t.reference).is_err() {
            return Err(b.err(
                t.reference_loc,
                "RBE2",
                format!("the reference node {} does not exist", t.reference),
                "a node defined in COORDINATES",
            ));
        }
        let tied = b.resolve(&t.tied, SetKind::Node, "RBE2")?;
        let tied = b.non_empty(tied, &t.tied, "RBE2", "tied nodes")?;
        if tied.binary_search(&t.reference).is_ok() {
            return Err(b.err(
                t.tied.loc,
                "RBE2",
                format!("the reference node {} is in its own tied list", t.reference),
                "tied nodes other than the reference",
            ));
        }
        for &n in &tied {
            if let Some((other, at)) = tied_by.get(&n) {
                return Err(b.err(
                    t.tied.loc,
                    "RBE2",
                    format!("node {n} is already tied by `{other}` (line {})", at.line),
                    "each node tied by one tie",
                ));
            }
            tied_by.insert(n, (t.name.clone(), t.loc));
            for &d in &t.dofs {
                if let Some(at) = prescribed.get(&(n, d)) {
                    return Err(b.err(
                        t.tied.loc,
                        "RBE2",
                        format!(
                            "node {n} DOF {d} is tied and also prescribed by FIXED DISP (line {})",
                            at.line
                        ),
                        "a tied DOF that is not prescribed",
                    ));
                }
            }
        }
        rigid_ties.push(RigidTie {
            name: t.name.clone(),
            reference: t.reference,
            dofs: t.dofs.clone(),
            tied,
        });
    }
    for t in &raw.rigid_ties {
        if let Some((other, at)) = tied_by.get(&t.reference) {
            return Err(b.err(
                t.reference_loc,
                "RBE2",
                format!(
                    "the reference node {} is tied by `{other}` (line {}); ties may not chain",
                    t.reference, at.line
                ),
                "a reference node that no tie ties",
            ));
        }
    }

    // Nonlinear point elements: free DOFs only, one line per card, node and DOF.
    let mut point_laws: Vec<PointElement> = Vec::new();
    let mut law_lines: HashMap<(u32, u8, PointLawKind), Loc> = HashMap::new();
    for p in &raw.point_laws {
        let card = p.kind.card();
        if b.node_ids.binary_search(&p.node).is_err() {
            return Err(b.err(
                p.node_loc,
                card,
                format!("node {} does not exist", p.node),
                "a node defined in COORDINATES",
            ));
        }
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
            .zip(&rigid_ties)
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
        let at = match point_laws
            .iter()
            .position(|e| (e.node, e.dof) == (p.node, p.dof))
        {
            Some(i) => i,
            None => {
                point_laws.push(PointElement {
                    node: p.node,
                    dof: p.dof,
                    cubic: 0.0,
                    quadratic: 0.0,
                    friction: 0.0,
                });
                point_laws.len() - 1
            }
        };
        let e = &mut point_laws[at];
        match p.kind {
            PointLawKind::Friction => e.friction = p.value,
            PointLawKind::Quadratic => e.quadratic = p.value,
            PointLawKind::Cubic => e.cubic = p.value,
        }
    }
    point_laws.sort_by_key(|e| (e.node, e.dof));

    // Loads, initial velocities, outputs.
    let mut point_loads = raw
        .point_loads
        .iter()
        .map(|p| point_load(&b, p, &raw))
        .collect::<Result<Vec<_>, _>>()?;
    // Mentat's named loads: per load case where a LOADCASE lists them, else global.
    let mut named_loads: Vec<(&str, Vec<PointLoad>)> = Vec::new();
    for (name, p) in &raw.named_loads {
        named_loads.push((name, vec![point_load(&b, p, &raw)?]));
    }
    for d in &raw.dist_loads {
        let els = b.resolve(&d.elements, SetKind::Element, "DIST LOADS")?;
        let els = b.non_empty(els, &d.elements, "DIST LOADS", "elements")?;
        let mut loads = Vec::new();
        for id in els {
            let e = &elements[elements.partition_point(|e| e.id < id)];
            let (a, z) = (e.nodes[0].0, e.nodes[1].0);
            let (Some(xa), Some(xb)) = (xyz_of(a), xyz_of(z)) else {
                continue;
            };
            loads.extend(consistent_beam_loads(d.q, a, xa, z, xb));
        }
        named_loads.push((&d.name, loads));
    }
    if let Some(names) = &raw.model_loadcase {
        active_names_exist(&b, names, &raw)?;
    }
    let per_case = raw.load_cases.iter().any(|c| c.active.is_some());
    if !per_case {
        for (_, loads) in &named_loads {
            point_loads.extend(loads.iter().cloned());
        }
    }
    let mut given: HashMap<(u32, u8), Loc> = HashMap::new();
    let initial_velocities = dof_groups(&b, &raw.initial_velocities, "INITIAL VEL", &mut given)?
        .into_iter()
        .zip(&raw.initial_velocities)
        .map(|((dofs, nodes), g)| InitialVelocity {
            dofs,
            nodes,
            quasi_static: g.quasi_static,
        })
        .collect();
    let mut outputs = Vec::new();
    for o in &raw.outputs {
        let nodes = b.resolve(&o.nodes, SetKind::Node, "HISTORY OUTPUT")?;
        let nodes = b.non_empty(nodes, &o.nodes, "HISTORY OUTPUT", "nodes")?;
        outputs.push(OutputRequest {
            nodes,
            dofs: o.dofs.clone(),
            quantities: o.quantities.clone(),
            every: o.every,
        });
    }

    let mut load_cases = Vec::new();
    for c in &raw.load_cases {
        let mut case = load_case(&b, c, &raw)?;
        if let Some(active) = &c.active {
            active_names_exist(&b, active, &raw)?;
            for (name, _) in active {
                for (n, loads) in &named_loads {
                    if n == name {
                        case.point_loads.extend(loads.iter().cloned());
                    }
                }
            }
            let begun = c.loc.unwrap_or(Loc::new(1, 1));
            for (name, at, support) in &raw.named {
                if *support && !active.iter().any(|(n, _)| n == name) {
                    return Err(b.err(
                        begun,
                        "LOADCASE",
                        format!(
                            "the support `{name}` (line {}) is not active in this load case",
                            at.line
                        ),
                        "every FIXED DISP active in every load case (coil's supports do not change between load cases)",
                    ));
                }
            }
        }
        load_cases.push(case);
    }

    Ok(Model {
        title: raw.title.map(|t| t.0).unwrap_or_default(),
        element_types: declared,
        lumped_mass: raw.lump.is_some(),
        nodes: nodes
            .iter()
            .map(|n| Node {
                id: n.id,
                xyz: n.xyz,
            })
            .collect(),
        elements: elements
            .iter()
            .map(|e| Element {
                id: e.id,
                kind: e.kind,
                nodes: [e.nodes[0].0, e.nodes[1].0],
            })
            .collect(),
        node_sets,
        element_sets,
        materials,
        geometries,
        damping,
        point_masses,
        rigid_ties,
        fixed_disp,
        point_loads,
        tables,
        initial_velocities,
        outputs,
        load_cases,
        point_laws,
    })
}

/// Resolves `values / DOFs / nodes` groups; each (node, DOF) once across `seen`.
#[allow(clippy::type_complexity)]
fn dof_groups(
    b: &Builder<'_>,
    groups: &[RawDofValues],
    card: &str,
    seen: &mut HashMap<(u32, u8), Loc>,
) -> Result<Vec<(Vec<(u8, f64)>, Vec<u32>)>, DeckError> {
    let mut out = Vec::new();
    for g in groups {
        let nodes = b.resolve(&g.nodes, SetKind::Node, card)?;
        let nodes = b.non_empty(nodes, &g.nodes, card, "nodes")?;
        for &n in &nodes {
            for &(d, _) in &g.dofs {
                if let Some(first) = seen.insert((n, d), g.loc) {
                    return Err(b.err(
                        g.loc,
                        card,
                        format!("node {n} DOF {d} is already given at line {}", first.line),
                        "each DOF of a node given once",
                    ));
                }
            }
        }
        out.push((g.dofs.clone(), nodes));
    }
    Ok(out)
}

fn point_load(b: &Builder<'_>, p: &RawPointLoad, raw: &RawDeck) -> Result<PointLoad, DeckError> {
    let nodes = b.resolve(&p.nodes, SetKind::Node, "POINT LOAD")?;
    let nodes = b.non_empty(nodes, &p.nodes, "POINT LOAD", "nodes")?;
    if let Some((name, loc)) = &p.table {
        let found = raw.tables.iter().find(|t| &t.name == name);
        match found {
            Some(t) if t.loc.line < loc.line => {}
            Some(t) => {
                return Err(b.err(
                    *loc,
                    "POINT LOAD",
                    format!("the table `{name}` is defined later (line {})", t.loc.line),
                    "tables defined before they are used",
                ))
            }
            None => {
                return Err(b.err(
                    *loc,
                    "POINT LOAD",
                    format!("no table named `{name}`"),
                    "a TABLE defined in the model definition",
                ))
            }
        }
    }
    Ok(PointLoad {
        dofs: p.dofs.clone(),
        nodes,
        table: p.table.as_ref().map(|t| t.0.clone()),
    })
}

fn load_case(b: &Builder<'_>, c: &RawLoadCase, raw: &RawDeck) -> Result<LoadCase, DeckError> {
    let end = c.end.or(c.loc).unwrap_or(Loc::new(1, 1));
    let analysis = if let Some((modes, _)) = c.modal {
        Analysis::Modal { modes }
    } else if let Some((dt, total_time, method, _)) = c.dynamic {
        Analysis::Transient {
            dt,
            total_time,
            method,
        }
    } else if let (Some((steps, _)), Some((time, _))) = (c.auto_load, c.time_step) {
        Analysis::Static { steps, time }
    } else {
        // The CONTINUE card already refuses this; kept as an error, not a panic.
        return Err(b.err(
            end,
            "CONTINUE",
            "the load case has no analysis",
            "AUTO LOAD with TIME STEP, MODAL SHAPE, or DYNAMIC CHANGE",
        ));
    };
    let point_loads = c
        .point_loads
        .iter()
        .map(|p| point_load(b, p, raw))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(LoadCase {
        title: c.title.as_ref().map(|t| t.0.clone()).unwrap_or_default(),
        analysis,
        point_loads,
    })
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Fails unless every name a `LOADCASE` lists names a Mentat block.
fn active_names_exist(
    b: &Builder<'_>,
    names: &[(String, Loc)],
    raw: &RawDeck,
) -> Result<(), DeckError> {
    for (name, loc) in names {
        if !raw.named.iter().any(|(n, _, _)| n == name) {
            return Err(b.err(
                *loc,
                "LOADCASE",
                format!("no load or support named `{name}`"),
                "the name of a FIXED DISP, POINT LOAD or DIST LOADS block",
            ));
        }
    }
    Ok(())
}

/// The consistent nodal loads of a uniform load per unit length `q` (global, N/mm)
/// on a straight beam from node `a` at `xa` to node `z` at `xb`: qL/2 at each node and
/// the moments +-(L^2/12) e x q (e the unit vector from a to z), the cubic Hermite
/// interpolation's work-equivalent loads (exact nodal displacements for
/// Euler-Bernoulli beams).
fn consistent_beam_loads(
    q: [f64; 3],
    a: u32,
    xa: [f64; 3],
    z: u32,
    xb: [f64; 3],
) -> Vec<PointLoad> {
    let d = sub(xb, xa);
    let l = norm(d);
    let e = [d[0] / l, d[1] / l, d[2] / l];
    let m = cross(e, q);
    let mut out = Vec::new();
    for (node, sign) in [(a, 1.0), (z, -1.0)] {
        let mut dofs = Vec::new();
        for (k, qk) in q.iter().enumerate() {
            if *qk != 0.0 {
                dofs.push((k as u8 + 1, qk * l / 2.0));
            }
        }
        for (k, mk) in m.iter().enumerate() {
            let mk = sign * mk * l * l / 12.0;
            if mk != 0.0 {
                dofs.push((k as u8 + 4, mk));
            }
        }
        if !dofs.is_empty() {
            out.push(PointLoad {
                dofs,
                nodes: vec![node],
                table: None,
            });
        }
    }
    out
}
