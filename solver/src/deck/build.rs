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
use std::collections::HashMap;

use super::error::{DeckError, Loc};
use super::lexer::ListItem;
use super::raw::{
    PointLawKind, RawDeck, RawDofValues, RawList, RawLoadCase, RawPointLoad, SetKind,
};
use crate::model::check::{cross, norm, sub};
use crate::model::{
    Analysis, Damping, Dashpot, Element, ElementSet, FixedDisp, Geometry, InitialVelocity,
    LoadCase, Material, ModalDamping, Model, ModelError, ModelParts, Node, NodeSet, OutputRequest,
    PointElement, PointLoad, PointMass, RigidTie, Site, Table,
};

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
    let mut parts = ModelParts {
        title: raw.title.clone().map(|t| t.0).unwrap_or_default(),
        element_types: raw.element_types.iter().map(|t| t.0).collect(),
        lumped_mass: raw.lump.is_some(),
        ..ModelParts::default()
    };
    mesh(&mut b, &raw, &mut parts)?;
    sets(&mut b, &raw, &mut parts)?;
    properties(&b, &raw, &mut parts)?;
    masses_and_damping(&b, &raw, &mut parts)?;
    let prescribed = constraints(&b, &raw, &mut parts)?;
    point_elements(&b, &raw, &prescribed, &mut parts)?;
    loads_and_cases(&b, &raw, &mut parts)?;
    let keys = PointKeys::of(&parts);
    Model::try_new(parts).map_err(|e| locate(&b, &raw, &keys, e))
}

/// Nodes and elements, sorted by id, each id once; the SIZING bounds.
fn mesh(b: &mut Builder<'_>, raw: &RawDeck, parts: &mut ModelParts) -> Result<(), DeckError> {
    let nodes = b.sorted_by_id(&raw.nodes, |n| (n.id, n.loc), "COORDINATES", "node")?;
    let elements = b.sorted_by_id(&raw.elements, |e| (e.id, e.loc), "CONNECTIVITY", "element")?;
    b.node_ids = nodes.iter().map(|n| n.id).collect();
    b.element_ids = elements.iter().map(|e| e.id).collect();
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
    parts.nodes = nodes
        .iter()
        .map(|n| Node {
            id: n.id,
            xyz: n.xyz,
        })
        .collect();
    parts.elements = elements
        .iter()
        .map(|e| Element {
            id: e.id,
            kind: e.kind,
            nodes: [e.nodes[0].0, e.nodes[1].0],
        })
        .collect();
    Ok(())
}

/// Sets, in deck order (a set may use the sets before it).
fn sets(b: &mut Builder<'_>, raw: &RawDeck, parts: &mut ModelParts) -> Result<(), DeckError> {
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
            SetKind::Node => parts.node_sets.push(NodeSet {
                name: s.name.clone(),
                nodes: ids.clone(),
            }),
            SetKind::Element => parts.element_sets.push(ElementSet {
                name: s.name.clone(),
                elements: ids.clone(),
            }),
        }
        b.sets.push((s.kind, s.name.clone(), s.loc, ids));
    }
    Ok(())
}

/// Tables, materials and geometries: unique names and ids, element lists resolved.
fn properties(b: &Builder<'_>, raw: &RawDeck, parts: &mut ModelParts) -> Result<(), DeckError> {
    b.unique(
        "TABLE",
        "table name",
        raw.tables.iter().map(|t| (t.name.as_str(), t.loc)),
    )?;
    parts.tables = raw
        .tables
        .iter()
        .map(|t| Table {
            name: t.name.clone(),
            points: t.points.clone(),
        })
        .collect();
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
    for m in &raw.materials {
        let list = b.resolve(&m.elements, SetKind::Element, "ISOTROPIC")?;
        let elements = b.non_empty(list, &m.elements, "ISOTROPIC", "elements")?;
        parts.materials.push(Material {
            name: m.name.clone(),
            youngs_modulus: m.youngs_modulus,
            poisson: m.poisson,
            density: m.density,
            elements,
        });
    }
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
    for g in &raw.geometries {
        let list = b.resolve(&g.elements, SetKind::Element, "GEOMETRY")?;
        let elements = b.non_empty(list, &g.elements, "GEOMETRY", "elements")?;
        parts.geometries.push(Geometry {
            name: g.name.clone(),
            section: g.section.clone(),
            orientation: g.orientation,
            elements,
        });
    }
    Ok(())
}

/// Point masses (one per node) and Rayleigh damping groups.
fn masses_and_damping(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    let mut mass_at: HashMap<u32, Loc> = HashMap::new();
    for p in &raw.point_masses {
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
        parts.point_masses.push(PointMass {
            node: p.node,
            mass: p.mass,
            inertia: p.inertia,
        });
    }
    for d in &raw.damping {
        let elements = b.resolve(&d.elements, SetKind::Element, "DAMPING")?;
        let mass_nodes = match &d.mass_nodes {
            Some(list) => b.resolve(list, SetKind::Node, "DAMPING")?,
            None => Vec::new(),
        };
        parts.damping.push(Damping {
            alpha: d.alpha,
            beta: d.beta,
            elements,
            mass_nodes,
        });
    }
    Ok(())
}

/// Prescribed DOFs (each once) and rigid ties; returns where each DOF was prescribed.
fn constraints(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<HashMap<(u32, u8), Loc>, DeckError> {
    let mut prescribed: HashMap<(u32, u8), Loc> = HashMap::new();
    parts.fixed_disp = dof_groups(b, &raw.fixed_disp, "FIXED DISP", &mut prescribed)?
        .into_iter()
        .map(|(dofs, nodes)| FixedDisp { dofs, nodes })
        .collect();
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
    let mut tied_by: HashMap<u32, (String, Loc)> = HashMap::new();
    for t in &raw.rigid_ties {
        let tied = b.resolve(&t.tied, SetKind::Node, "RBE2")?;
        let tied = b.non_empty(tied, &t.tied, "RBE2", "tied nodes")?;
        for &n in &tied {
            if n == t.reference {
                continue;
            }
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
        parts.rigid_ties.push(RigidTie {
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
    Ok(prescribed)
}

/// Nonlinear point elements and dashpots: free DOFs only, one line per card, node and
/// DOF (the cards on one DOF combine); the modal damping of `LOSS FACTOR` and `MODAL
/// DAMPING`.
fn point_elements(
    b: &Builder<'_>,
    raw: &RawDeck,
    prescribed: &HashMap<(u32, u8), Loc>,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    let mut law_lines: HashMap<(u32, u8, PointLawKind), Loc> = HashMap::new();
    for p in &raw.point_laws {
        let card = p.kind.card();
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
            .zip(&parts.rigid_ties)
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
        if p.kind == PointLawKind::Dashpot {
            parts.dashpots.push(Dashpot {
                node: p.node,
                dof: p.dof,
                c: p.value,
            });
            continue;
        }
        let laws = &mut parts.point_laws;
        let at = match laws.iter().position(|e| (e.node, e.dof) == (p.node, p.dof)) {
            Some(i) => i,
            None => {
                laws.push(PointElement {
                    node: p.node,
                    dof: p.dof,
                    cubic: 0.0,
                    quadratic: 0.0,
                    friction: 0.0,
                });
                laws.len() - 1
            }
        };
        let e = &mut laws[at];
        match p.kind {
            PointLawKind::Friction => e.friction = p.value,
            PointLawKind::Quadratic => e.quadratic = p.value,
            PointLawKind::Cubic => e.cubic = p.value,
            PointLawKind::Dashpot => {}
        }
    }
    let mut modal_damping = ModalDamping::default();
    if let Some((eta, modes, _)) = raw.loss_factor {
        modal_damping.loss_factor = eta;
        modal_damping.loss_factor_modes = modes;
    }
    for &(mode, zeta, _) in &raw.modal_ratios {
        let i = mode as usize - 1;
        if modal_damping.ratios.len() <= i {
            modal_damping.ratios.resize(i + 1, 0.0);
        }
        modal_damping.ratios[i] = zeta;
    }
    while modal_damping.ratios.last() == Some(&0.0) {
        modal_damping.ratios.pop();
    }
    parts.modal_damping = modal_damping;
    Ok(())
}

/// Loads (Mentat's named loads per load case where a `LOADCASE` lists them, else
/// global), initial velocities, outputs and load cases.
fn loads_and_cases(
    b: &Builder<'_>,
    raw: &RawDeck,
    parts: &mut ModelParts,
) -> Result<(), DeckError> {
    parts.point_loads = raw
        .point_loads
        .iter()
        .map(|p| point_load(b, p, raw))
        .collect::<Result<Vec<_>, _>>()?;
    let mut named_loads: Vec<(&str, Vec<PointLoad>)> = Vec::new();
    for (name, p) in &raw.named_loads {
        named_loads.push((name, vec![point_load(b, p, raw)?]));
    }
    let xyz_of = |id: u32| {
        let i = parts.nodes.binary_search_by_key(&id, |n| n.id).ok()?;
        Some(parts.nodes[i].xyz)
    };
    for d in &raw.dist_loads {
        let els = b.resolve(&d.elements, SetKind::Element, "DIST LOADS")?;
        let els = b.non_empty(els, &d.elements, "DIST LOADS", "elements")?;
        let mut loads = Vec::new();
        for id in els {
            let e = &parts.elements[parts.elements.partition_point(|e| e.id < id)];
            let [a, z] = e.nodes;
            let (Some(xa), Some(xb)) = (xyz_of(a), xyz_of(z)) else {
                continue;
            };
            loads.extend(consistent_beam_loads(d.q, a, xa, z, xb));
        }
        named_loads.push((&d.name, loads));
    }
    if let Some(names) = &raw.model_loadcase {
        active_names_exist(b, names, raw)?;
    }
    let per_case = raw.load_cases.iter().any(|c| c.active.is_some());
    if !per_case {
        for (_, loads) in &named_loads {
            parts.point_loads.extend(loads.iter().cloned());
        }
    }
    let mut given: HashMap<(u32, u8), Loc> = HashMap::new();
    parts.initial_velocities = dof_groups(b, &raw.initial_velocities, "INITIAL VEL", &mut given)?
        .into_iter()
        .zip(&raw.initial_velocities)
        .map(|((dofs, nodes), g)| InitialVelocity {
            dofs,
            nodes,
            quasi_static: g.quasi_static,
        })
        .collect();
    for o in &raw.outputs {
        let nodes = b.resolve(&o.nodes, SetKind::Node, "HISTORY OUTPUT")?;
        let nodes = b.non_empty(nodes, &o.nodes, "HISTORY OUTPUT", "nodes")?;
        parts.outputs.push(OutputRequest {
            nodes,
            dofs: o.dofs.clone(),
            quantities: o.quantities.clone(),
            every: o.every,
        });
    }
    for c in &raw.load_cases {
        let mut case = load_case(b, c, raw)?;
        if let Some(active) = &c.active {
            active_loads(b, raw, c, active, &named_loads, &mut case)?;
        }
        parts.load_cases.push(case);
    }
    Ok(())
}

/// The named loads a Mentat `LOADCASE` activates, added to its load case; every
/// support must be active (coil's supports do not change between load cases).
fn active_loads(
    b: &Builder<'_>,
    raw: &RawDeck,
    c: &RawLoadCase,
    active: &[(String, Loc)],
    named_loads: &[(&str, Vec<PointLoad>)],
    case: &mut LoadCase,
) -> Result<(), DeckError> {
    active_names_exist(b, active, raw)?;
    for (name, _) in active {
        for (n, loads) in named_loads {
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
    Ok(())
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
