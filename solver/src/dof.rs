//! The DOF map: how every DOF of the model relates to the unknowns of the linear
//! systems. One map serves static, modal and transient analyses.
//!
//! # Full and free DOFs
//! The full DOF vector has six entries per node, `node_index * 6 + (dof - 1)`, in the
//! order `u_x, u_y, u_z, theta_x, theta_y, theta_z` (global axes; mm and rad). Each
//! full DOF is exactly one of
//! - **free**: an unknown with an equation number `0..free_len()`, numbered in full-DOF
//!   order (the sparse Cholesky applies its own fill-reducing ordering);
//! - **prescribed**: `FIXED DISP` gives its value (mm or rad);
//! - **dependent**: a tied DOF of a rigid tie (RBE2), exactly
//!   `u_s = u_r + theta_r x (x_s - x_r)` for translations and `theta_s = theta_r` for
//!   rotations (small rotations, linear kinematics), where the reference DOFs may
//!   themselves be free, prescribed or dependent (chains are resolved).
//!
//! # Elimination
//! Every full DOF is written as `u_d = sum_e T[d, e] q_e + g_d`, with `q` the free
//! unknowns and `g` the contribution of prescribed values. Element matrices are then
//! reduced exactly: `K_r = T^T K T`, `f_r = T^T (f - K g)`, `M_r = T^T M T`. This is
//! master-slave elimination: no penalty numbers and no "diagonal one" rows, which
//! would put fake eigenpairs into a modal analysis (see the style guide). Reactions at
//! prescribed DOFs are `T_p^T (K u - f)` with `T_p` the map onto prescribed masters.
//!
//! # Errors
//! Conflicting constraints (a DOF both prescribed and tied, tied twice, two different
//! prescribed values), references to unknown nodes or DOF numbers outside 1..=6, cyclic
//! ties, and nodes that no element or tie touches (their free DOFs are mechanisms) are
//! reported with the node and DOF.

use crate::error::solve::SolveError;
pub use crate::error::solve::{dof_name, DOF_NAMES};
use crate::linalg::FactorError;
use crate::model::{Model, NodeId, DOFS_PER_NODE};

/// What a full DOF is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DofStatus {
    /// An unknown with this equation number.
    Free(usize),
    /// A prescribed value (mm or rad).
    Prescribed(f64),
    /// Follows other DOFs through a rigid tie.
    Dependent,
}

/// The map from full DOFs to free unknowns and prescribed values.
#[derive(Debug, Clone)]
pub struct DofMap {
    node_ids: Vec<NodeId>,
    status: Vec<DofStatus>,
    free_to_full: Vec<usize>,
    /// Expansion of each full DOF onto master full DOFs (free or prescribed) in CSR
    /// form: `masters[offsets[d]..offsets[d + 1]]` holds `(master, coefficient)`.
    offsets: Vec<usize>,
    masters: Vec<(usize, f64)>,
}

/// A raw tie dependency before chains are resolved: `(reference full DOF, coefficient)`.
type Terms = Vec<(usize, f64)>;

impl DofMap {
    /// Maps a factorisation failure of a matrix on the free DOFs to a
    /// [`SolveError::Mechanism`] at the DOF of the failing equation.
    pub fn mechanism(&self, error: FactorError) -> SolveError {
        match error {
            FactorError::Singular {
                equation,
                pivot,
                diagonal,
            } => {
                let (node, dof) = self.free_label(equation);
                let detail = if pivot.is_nan() {
                    "the stiffness matrix has a non-positive pivot there".to_string()
                } else {
                    format!(
                        "the stiffness left at this DOF is {:.1e} of its own diagonal (pivot {pivot:.3e}, diagonal {diagonal:.3e})",
                        pivot / diagonal
                    )
                };
                SolveError::Mechanism { node, dof, detail }
            }
            FactorError::Other(s) => SolveError::Linalg(s),
        }
    }

    /// Builds the map from the model's `FIXED DISP` and rigid ties.
    pub fn new(model: &Model) -> Result<Self, SolveError> {
        let n_full = model.dof_count();
        let node_ids: Vec<NodeId> = model.nodes.iter().map(|n| n.id).collect();
        let index_of = |node: NodeId, context: &str| {
            model
                .node_index(node)
                .ok_or_else(|| SolveError::UnknownNode {
                    node,
                    context: context.to_string(),
                })
        };
        let check_dof = |dof: u8, context: &str| {
            if (1..=6).contains(&dof) {
                Ok(dof as usize - 1)
            } else {
                Err(SolveError::BadDof {
                    dof,
                    context: context.to_string(),
                })
            }
        };

        let mut status = vec![DofStatus::Free(usize::MAX); n_full];
        let mut prescribed = vec![false; n_full];
        for fixed in &model.fixed_disp {
            for &node in &fixed.nodes {
                let i = index_of(node, "FIXED DISP")?;
                for &(dof, value) in &fixed.dofs {
                    let d = i * DOFS_PER_NODE + check_dof(dof, "FIXED DISP")?;
                    if !value.is_finite() {
                        return Err(SolveError::NonFinite {
                            what: format!("FIXED DISP value at node {node} {}", dof_name(dof)),
                        });
                    }
                    if prescribed[d] {
                        if let DofStatus::Prescribed(old) = status[d] {
                            if old != value {
                                return Err(SolveError::ConflictingConstraint {
                                    node,
                                    dof,
                                    reason: format!(
                                        "prescribed twice with different values ({old} and {value})"
                                    ),
                                });
                            }
                        }
                    }
                    prescribed[d] = true;
                    status[d] = DofStatus::Prescribed(value);
                }
            }
        }

        // Raw tie dependencies; resolved onto free/prescribed masters below.
        let mut raw: Vec<Option<Terms>> = vec![None; n_full];
        let mut touched = vec![false; model.nodes.len()];
        for element in &model.elements {
            for &node in &element.nodes {
                touched[index_of(node, &format!("element {}", element.id))?] = true;
            }
        }
        for e in &model.matrix_elements {
            for &(node, _) in &e.dofs {
                touched[index_of(node, &format!("DMIG `{}`", e.name))?] = true;
            }
        }
        for tie in &model.rigid_ties {
            let context = format!("rigid tie '{}'", tie.name);
            let r = index_of(tie.reference, &context)?;
            touched[r] = true;
            let xr = model.nodes[r].xyz;
            for &slave in &tie.tied {
                let s = index_of(slave, &context)?;
                touched[s] = true;
                if s == r {
                    return Err(SolveError::ConflictingConstraint {
                        node: slave,
                        dof: tie.dofs.first().copied().unwrap_or(1),
                        reason: format!("{context} ties its reference node to itself"),
                    });
                }
                let xs = model.nodes[s].xyz;
                let arm = [xs[0] - xr[0], xs[1] - xr[1], xs[2] - xr[2]];
                for &dof in &tie.dofs {
                    let k = check_dof(dof, &context)?;
                    let d = s * DOFS_PER_NODE + k;
                    if prescribed[d] {
                        return Err(SolveError::ConflictingConstraint {
                            node: slave,
                            dof,
                            reason: format!("tied by {context} and prescribed by FIXED DISP"),
                        });
                    }
                    if raw[d].is_some() {
                        return Err(SolveError::ConflictingConstraint {
                            node: slave,
                            dof,
                            reason: format!("tied twice (again by {context})"),
                        });
                    }
                    raw[d] = Some(rigid_terms(r * DOFS_PER_NODE, k, arm));
                    status[d] = DofStatus::Dependent;
                }
            }
        }

        let (offsets, masters) = resolve(&raw, &node_ids)?;

        let mut free_to_full = Vec::new();
        for (d, s) in status.iter_mut().enumerate() {
            if let DofStatus::Free(eq) = s {
                *eq = free_to_full.len();
                free_to_full.push(d);
            }
        }
        for (i, &t) in touched.iter().enumerate() {
            if t {
                continue;
            }
            if let Some(k) = (0..DOFS_PER_NODE)
                .find(|&k| matches!(status[i * DOFS_PER_NODE + k], DofStatus::Free(_)))
            {
                return Err(SolveError::Mechanism {
                    node: node_ids[i],
                    dof: k as u8 + 1,
                    detail: "the node belongs to no element and no rigid tie".to_string(),
                });
            }
        }
        Ok(DofMap {
            node_ids,
            status,
            free_to_full,
            offsets,
            masters,
        })
    }

    /// Number of full DOFs (6 per node).
    pub fn full_len(&self) -> usize {
        self.status.len()
    }

    /// Number of free DOFs (equations).
    pub fn free_len(&self) -> usize {
        self.free_to_full.len()
    }

    /// Status of a full DOF.
    pub fn status(&self, full: usize) -> DofStatus {
        self.status[full]
    }

    /// Full DOF index of `(node id, dof 1..=6)`.
    pub fn full_index(&self, node: NodeId, dof: u8) -> Option<usize> {
        let i = self.node_ids.binary_search(&node).ok()?;
        (1..=6)
            .contains(&dof)
            .then(|| i * DOFS_PER_NODE + dof as usize - 1)
    }

    /// `(node id, dof 1..=6)` of a full DOF.
    pub fn label(&self, full: usize) -> (NodeId, u8) {
        (
            self.node_ids[full / DOFS_PER_NODE],
            (full % DOFS_PER_NODE) as u8 + 1,
        )
    }

    /// Full DOF of an equation.
    pub fn free_to_full(&self, equation: usize) -> usize {
        self.free_to_full[equation]
    }

    /// `(node id, dof 1..=6)` of an equation.
    pub fn free_label(&self, equation: usize) -> (NodeId, u8) {
        self.label(self.free_to_full[equation])
    }

    /// The masters (free or prescribed full DOFs) a full DOF is made of, with their
    /// coefficients. A free or prescribed DOF is its own single master.
    pub fn masters(&self, full: usize) -> &[(usize, f64)] {
        &self.masters[self.offsets[full]..self.offsets[full + 1]]
    }

    /// Row `d` of `T`: `(equation, coefficient)` pairs.
    pub fn expansion(&self, full: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.masters(full)
            .iter()
            .filter_map(|&(m, c)| match self.status[m] {
                DofStatus::Free(eq) => Some((eq, c)),
                _ => None,
            })
    }

    /// `g_d`: the displacement a full DOF gets from prescribed values alone.
    pub fn prescribed_part(&self, full: usize) -> f64 {
        self.masters(full)
            .iter()
            .map(|&(m, c)| match self.status[m] {
                DofStatus::Prescribed(v) => c * v,
                _ => 0.0,
            })
            .sum()
    }

    /// Full vector `u = T q + scale g` from free values `q`; `scale` is 1 for
    /// displacements and 0 for velocities, accelerations and mode shapes.
    pub fn expand(&self, free: &[f64], prescribed_scale: f64) -> Vec<f64> {
        let mut full = vec![0.0; self.full_len()];
        self.expand_into(free, prescribed_scale, &mut full);
        full
    }

    /// In-place form of [`DofMap::expand`].
    pub fn expand_into(&self, free: &[f64], prescribed_scale: f64, full: &mut [f64]) {
        for (d, out) in full.iter_mut().enumerate() {
            *out = self
                .masters(d)
                .iter()
                .map(|&(m, c)| match self.status[m] {
                    DofStatus::Free(eq) => c * free[eq],
                    DofStatus::Prescribed(v) => c * prescribed_scale * v,
                    DofStatus::Dependent => 0.0,
                })
                .sum();
        }
    }

    /// Adds `T^T f` to `free_out` (a full-space force to the free equations).
    pub fn restrict_add(&self, full: &[f64], free_out: &mut [f64]) {
        for (d, &f) in full.iter().enumerate() {
            if f != 0.0 {
                for (eq, c) in self.expansion(d) {
                    free_out[eq] += c * f;
                }
            }
        }
    }

    /// Reactions at the prescribed DOFs from the full-space residual `K u - f`:
    /// `(full prescribed DOF, force or moment)`, sorted by DOF.
    pub fn reactions(&self, residual: &[f64]) -> Vec<(usize, f64)> {
        let mut out: Vec<(usize, f64)> = self
            .status
            .iter()
            .enumerate()
            .filter(|(_, s)| matches!(s, DofStatus::Prescribed(_)))
            .map(|(d, _)| (d, 0.0))
            .collect();
        for (d, &r) in residual.iter().enumerate() {
            for &(m, c) in self.masters(d) {
                if let DofStatus::Prescribed(_) = self.status[m] {
                    if let Ok(k) = out.binary_search_by_key(&m, |&(p, _)| p) {
                        out[k].1 += c * r;
                    }
                }
            }
        }
        out
    }
}

/// Rigid-body terms of tied DOF `k` (0-based) of a slave at `arm = x_s - x_r` from the
/// reference whose first full DOF is `r0`: translations `u_r + theta_r x arm`,
/// rotations `theta_r`.
fn rigid_terms(r0: usize, k: usize, arm: [f64; 3]) -> Terms {
    let [dx, dy, dz] = arm;
    let (t_x, t_y, t_z) = (r0 + 3, r0 + 4, r0 + 5);
    let terms = match k {
        // (theta x arm)_x = theta_y dz - theta_z dy, and cyclically.
        0 => vec![(r0, 1.0), (t_y, dz), (t_z, -dy)],
        1 => vec![(r0 + 1, 1.0), (t_z, dx), (t_x, -dz)],
        2 => vec![(r0 + 2, 1.0), (t_x, dy), (t_y, -dx)],
        _ => vec![(r0 + k, 1.0)],
    };
    // Exact zeros (a slave on an axis through the reference) add nothing to the pattern.
    terms.into_iter().filter(|&(_, c)| c != 0.0).collect()
}

/// Resolves tie chains into expansions onto free or prescribed masters (CSR), with an
/// explicit stack so that long chains cannot overflow the call stack.
fn resolve(raw: &[Option<Terms>], node_ids: &[NodeId]) -> Result<(Vec<usize>, Terms), SolveError> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Active,
        Done,
    }
    let n = raw.len();
    let mut resolved: Vec<Option<Terms>> = vec![None; n];
    let mut mark = vec![Mark::New; n];
    for start in 0..n {
        if mark[start] == Mark::Done {
            continue;
        }
        let mut stack = vec![start];
        while let Some(&d) = stack.last() {
            match &raw[d] {
                None => {
                    resolved[d] = Some(vec![(d, 1.0)]);
                    mark[d] = Mark::Done;
                    stack.pop();
                }
                Some(terms) => {
                    if mark[d] == Mark::New {
                        mark[d] = Mark::Active;
                    }
                    let pending: Vec<usize> = terms
                        .iter()
                        .map(|&(m, _)| m)
                        .filter(|&m| mark[m] != Mark::Done)
                        .collect();
                    if let Some(&m) = pending.iter().find(|&&m| mark[m] == Mark::Active) {
                        let (node, dof) =
                            (node_ids[m / DOFS_PER_NODE], (m % DOFS_PER_NODE) as u8 + 1);
                        return Err(SolveError::ConflictingConstraint {
                            node,
                            dof,
                            reason: "rigid ties form a cycle through this DOF".to_string(),
                        });
                    }
                    if pending.is_empty() {
                        let mut merged: Terms = Vec::new();
                        for &(m, c) in terms {
                            for &(mm, cc) in resolved[m].as_deref().unwrap_or(&[]) {
                                merged.push((mm, c * cc));
                            }
                        }
                        merged.sort_by_key(|&(m, _)| m);
                        let mut out: Terms = Vec::with_capacity(merged.len());
                        for (m, c) in merged {
                            match out.last_mut() {
                                Some(last) if last.0 == m => last.1 += c,
                                _ => out.push((m, c)),
                            }
                        }
                        out.retain(|&(_, c)| c != 0.0);
                        resolved[d] = Some(out);
                        mark[d] = Mark::Done;
                        stack.pop();
                    } else {
                        stack.extend(pending);
                    }
                }
            }
        }
    }
    let mut offsets = Vec::with_capacity(n + 1);
    let mut masters = Vec::new();
    offsets.push(0);
    for r in resolved {
        masters.extend(r.unwrap_or_default());
        offsets.push(masters.len());
    }
    Ok((offsets, masters))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::test_support::{model, tied_frame};
    use crate::model::{FixedDisp, RigidTie};

    fn tie(reference: NodeId, tied: &[NodeId], dofs: &[u8]) -> RigidTie {
        RigidTie {
            name: format!("tie{reference}"),
            reference,
            dofs: dofs.to_vec(),
            tied: tied.to_vec(),
        }
    }

    #[test]
    fn tied_dofs_follow_the_reference_as_a_rigid_body() {
        let mut m = model(
            &[
                (1, [1.0, 1.0, 1.0]),
                (2, [2.0, 3.0, 4.0]),
                (3, [9.0, 9.0, 9.0]),
            ],
            &[[1, 3]],
        );
        m.rigid_ties.push(tie(1, &[2], &[1, 2, 3, 4, 5, 6]));
        let map = DofMap::new(&m).unwrap();
        // A small rigid motion of the reference: u = (0.1, -0.2, 0.3), theta = (0.01, 0.02, -0.03).
        let mut q = vec![0.0; map.free_len()];
        let reference = [0.1, -0.2, 0.3, 0.01, 0.02, -0.03];
        for (k, v) in reference.iter().enumerate() {
            let DofStatus::Free(eq) = map.status(k) else {
                panic!("free")
            };
            q[eq] = *v;
        }
        let u = map.expand(&q, 1.0);
        let arm = [1.0, 2.0, 3.0];
        let t = &reference[3..];
        let cross = [
            t[1] * arm[2] - t[2] * arm[1],
            t[2] * arm[0] - t[0] * arm[2],
            t[0] * arm[1] - t[1] * arm[0],
        ];
        for c in 0..3 {
            assert!((u[6 + c] - (reference[c] + cross[c])).abs() < 1e-15);
            assert_eq!(u[9 + c], reference[3 + c]);
            assert_eq!(map.status(6 + c), DofStatus::Dependent);
        }
        assert_eq!(map.free_len(), 12);
    }

    #[test]
    fn tie_chains_resolve_and_cycles_are_errors() {
        let nodes = [
            (1, [0.0; 3]),
            (2, [1.0, 0.0, 0.0]),
            (3, [1.0, 1.0, 0.0]),
            (4, [5.0, 5.0, 5.0]),
        ];
        let mut m = model(&nodes, &[[1, 4]]);
        m.rigid_ties.push(tie(2, &[3], &[1, 2, 3, 4, 5, 6]));
        m.rigid_ties.push(tie(1, &[2], &[1, 2, 3, 4, 5, 6]));
        let map = DofMap::new(&m).unwrap();
        // Node 3 hangs on node 1 through node 2; u_y of node 3 = u_y1 + theta_z1 * 1.
        let terms = map.masters(2 * 6 + 1);
        assert_eq!(terms, &[(1, 1.0), (5, 1.0)]);
        m.rigid_ties.push(tie(3, &[1], &[1]));
        let err = DofMap::new(&m).unwrap_err();
        assert!(
            matches!(err, SolveError::ConflictingConstraint { .. }),
            "{err}"
        );
        assert!(err.to_string().contains("cycle"));
    }

    #[test]
    fn conflicting_constraints_are_errors() {
        let mut m = model(&[(1, [0.0; 3]), (2, [1.0, 0.0, 0.0])], &[[1, 2]]);
        m.fixed_disp.push(FixedDisp {
            dofs: vec![(2, 0.0)],
            nodes: vec![2],
        });
        m.rigid_ties.push(tie(1, &[2], &[2]));
        let err = DofMap::new(&m).unwrap_err();
        assert!(
            matches!(
                err,
                SolveError::ConflictingConstraint {
                    node: 2,
                    dof: 2,
                    ..
                }
            ),
            "{err}"
        );

        let mut m = model(&[(1, [0.0; 3]), (2, [1.0, 0.0, 0.0])], &[[1, 2]]);
        for value in [0.0, 1.0] {
            m.fixed_disp.push(FixedDisp {
                dofs: vec![(1, value)],
                nodes: vec![1],
            });
        }
        assert!(matches!(
            DofMap::new(&m),
            Err(SolveError::ConflictingConstraint {
                node: 1,
                dof: 1,
                ..
            })
        ));
        m.fixed_disp[1].dofs[0].0 = 7;
        assert!(matches!(
            DofMap::new(&m),
            Err(SolveError::BadDof { dof: 7, .. })
        ));
        m.fixed_disp[1].nodes[0] = 99;
        assert!(matches!(
            DofMap::new(&m),
            Err(SolveError::UnknownNode { node: 99, .. })
        ));
    }

    #[test]
    fn prescribed_masters_give_the_slaves_their_motion() {
        let m = tied_frame();
        let map = DofMap::new(&m).unwrap();
        // Reference 10 has u_z = 0.25 prescribed and theta_x = 0; node 4 (tied) gets
        // u_z = 0.25 + theta_x dy - theta_y dx with theta_x prescribed to 0.
        let uz4 = map.full_index(4, 3).unwrap();
        assert_eq!(map.prescribed_part(uz4), 0.25);
        let expansion: Vec<(usize, f64)> = map.expansion(uz4).collect();
        // theta_y of node 10 is free: coefficient -dx = -(12 - 15) = 3.
        let ry10 = map.full_index(10, 5).unwrap();
        let DofStatus::Free(eq) = map.status(ry10) else {
            panic!("free")
        };
        assert_eq!(expansion, vec![(eq, 3.0)]);
        // Reactions project the slave residual onto the prescribed masters.
        let mut residual = vec![0.0; map.full_len()];
        residual[uz4] = 2.0;
        let reactions = map.reactions(&residual);
        let at = |node, dof| {
            reactions
                .iter()
                .find(|r| r.0 == map.full_index(node, dof).unwrap())
                .unwrap()
                .1
        };
        assert_eq!(at(10, 3), 2.0);
        // theta_x of node 10 carries u_z4 through dy = 9 - 5 = 4.
        assert_eq!(at(10, 4), 8.0);
        assert_eq!(at(1, 3), 0.0);
    }

    #[test]
    fn an_untouched_node_is_a_mechanism() {
        let m = model(
            &[(1, [0.0; 3]), (2, [1.0, 0.0, 0.0]), (3, [7.0, 0.0, 0.0])],
            &[[1, 2]],
        );
        let err = DofMap::new(&m).unwrap_err();
        assert!(
            matches!(
                err,
                SolveError::Mechanism {
                    node: 3,
                    dof: 1,
                    ..
                }
            ),
            "{err}"
        );
        // Fully prescribed, it is harmless.
        let mut m = m;
        m.fixed_disp.push(FixedDisp {
            dofs: (1..=6).map(|d| (d, 0.0)).collect(),
            nodes: vec![3],
        });
        assert!(DofMap::new(&m).is_ok());
    }
}
