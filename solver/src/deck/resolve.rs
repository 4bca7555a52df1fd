//! The deck's side of building a model: resolving the located lists of the raw deck
//! (ids, `FROM TO BY` ranges, `ALL`, set names) to sorted, unique id lists, and the
//! checks that name deck lines ("defined twice, first at line N"). Each card family's
//! build function (in `cards/`) uses it; [`super::build`] runs them in order.

use std::collections::HashMap;

use super::error::{DeckError, Loc};
use super::lexer::ListItem;
use super::raw::{RawDofValues, RawList, SetKind};

pub(crate) struct Builder<'a> {
    pub(crate) file: &'a str,
    pub(crate) node_ids: Vec<u32>,
    pub(crate) element_ids: Vec<u32>,
    /// Sets resolved so far, in deck order: kind, name, definition line, ids.
    pub(crate) sets: Vec<(SetKind, String, Loc, Vec<u32>)>,
    /// Every set's definition, to tell "defined later" from "not defined".
    pub(crate) all_sets: Vec<(SetKind, String, Loc)>,
}

impl Builder<'_> {
    pub(crate) fn err(
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
    pub(crate) fn unique<'n>(
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
    pub(crate) fn sorted_by_id<T: Clone>(
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
    pub(crate) fn resolve(
        &self,
        list: &RawList,
        kind: SetKind,
        card: &str,
    ) -> Result<Vec<u32>, DeckError> {
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

    pub(crate) fn non_empty(
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

/// Resolves `values / DOFs / nodes` groups; each (node, DOF) once across `seen`.
#[allow(clippy::type_complexity)]
pub(crate) fn dof_groups(
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
