//! Tension-only links (`TENSION LINK`) and moving penalty contacts (`MOVING CONTACT`):
//! unilateral springs on gap functions that are linear in the free displacements.
//!
//! # Formulation
//! Each element `i` has a gap `g_i(u) = g0_i + b_i^T u` (mm; `b_i` a few free rows) and
//! exerts `lambda_i = k_i max(g_i, 0)` (N), entering the balance as the internal force
//! `s_i b_i lambda_i` (`K u + B S lambda = f`, `s_i = +-1`).
//! * A taut link is linear and sits in `K` (its pretension `-k slack` is a constant load,
//!   see [`crate::analysis::System`]); what this module adds for it is the correction of
//!   a slack one: `b = -(e_b - e_a)`, `g0 = slack`, `s = -1`, so `lambda = k max(-e, 0)`
//!   and the internal force `lambda (e_b - e_a)` cancels the linear spring's compression
//!   `k e (e_b - e_a)` exactly when `e < 0`.
//! * A contact's gap is the penetration `p = (x_h + u_h) - (x_l + w_l)(s)`: `b` has `+1`
//!   at the head and minus the cubic Hermite weights of the line's translation and
//!   rotation at the point `s` (which moves), `g0 = x_h - x_l` along the DOF.
//!
//! # Solve (static and per step)
//! With a factor `S` of the linear problem (K for a static case, the stepper's effective
//! matrix for a step), the response to the element loads is `u = u* - W S lambda`,
//! `W = A^-1 B` scaled to displacements (`A` the factored matrix), so the gaps are
//! `g = g* - G S lambda` with `G = B^T W`. The forces solve the linear complementarity
//! problem `lambda = k max(g* - G S lambda, 0)`, found by an active set: guess the closed
//! elements (last step's, or those with `g* > 0`), solve
//! `(diag(1/k) + G_AA S_AA) lambda_A = g*_A` (LU), drop an element whose force is
//! negative, add one whose gap is open-but-penetrated, repeat (at most
//! [`MAX_ACTIVE_SET`] times). For contacts alone the matrix is symmetric positive
//! definite; a slack link's `1/k - G_ii` is positive because `A` holds the link's own
//! stiffness `k` (`G_ii <= 1/k`). The set changes little from step to step, so a
//! solve takes one or two passes.
//!
//! # Memory
//! Neither solve keeps one response vector per element. In a static case the column `j`
//! of `G S` (m values, one per element) is computed when element `j` first closes (one
//! solve), and the correction `u* - u = A^-1 (sum_j s_j lambda_j b_j)` is one more solve:
//! memory `8 (n + m a)` bytes for `n` equations, `m` elements and `a` of them closed at
//! some pass (`a <= m`; on a catenary under its weight only the contact). A transient
//! keeps the links' step responses sparse and within a budget
//! (`crate::analysis::transient`, module `responses`).
//!
//! Sources: P. Wriggers, *Computational Contact Mechanics*, 2nd ed., Springer 2006,
//! sec. 6.3 (penalty method) and 6.4 (active sets); the Hermite shape functions of the
//! bending element as in [`crate::element::beam`].

use crate::analysis::system::System;
use crate::error::solve::SolveError;
use crate::model::MovingContact;
use std::cell::RefCell;

/// Most active-set passes in one solve.
pub const MAX_ACTIVE_SET: usize = 50;

/// Most elements closed at once: their dense matrix takes at most 128 MiB.
pub const MAX_CLOSED: usize = 4096;

/// One unilateral element at one instant: gap `g0 + b^T u`, force `k max(gap, 0)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Gap {
    /// `(free equation, coefficient)` of `b`.
    pub b: Vec<(usize, f64)>,
    /// `(full DOF, coefficient)` of `b` before constraints (for residuals).
    pub full: Vec<(usize, f64)>,
    /// The gap at `u = 0` (mm).
    pub g0: f64,
    /// Penalty or link stiffness (N/mm).
    pub k: f64,
    /// The direction of its internal force `sign lambda b`: `+1` for a contact, `-1`
    /// for a link's slack correction (which removes the taut link's stiffness).
    pub sign: f64,
}

impl Gap {
    /// `g0 + b^T u`.
    pub fn gap(&self, u: &[f64]) -> f64 {
        self.g0 + self.b.iter().map(|&(r, c)| c * u[r]).sum::<f64>()
    }

    /// `b^T x` (the gap's linear part).
    pub fn dot(&self, x: &[f64]) -> f64 {
        self.b.iter().map(|&(r, c)| c * x[r]).sum()
    }

    /// Adds `scale b` to the free vector `f`.
    pub fn add_to(&self, scale: f64, f: &mut [f64]) {
        for &(r, c) in &self.b {
            f[r] += scale * c;
        }
    }
}

/// A moving contact resolved against the system: the line's nodes ordered along its
/// axis, their coordinates, and the rows of the translation and rotation it reads.
#[derive(Debug, Clone)]
pub struct ContactLine {
    /// The model's contact.
    pub contact: MovingContact,
    /// The head's DOF and its reference coordinate along dof.
    head: (Rows, f64),
    /// Per line node in axis order: coordinate along the axis from the first node (mm),
    /// reference coordinate along dof, rows of the translation and of the rotation
    /// (the latter scaled so that it is `dw/ds`).
    nodes: Vec<(f64, f64, Rows, Rows)>,
}

/// The free rows a full DOF expands to, and the full DOF.
fn rows(system: &System, node: u32, dof: u8, what: &str) -> Result<Rows, SolveError> {
    let full = system.full_dof(node, dof, what)?;
    Ok(Rows {
        free: system.dofs.expansion(full).collect(),
        full,
    })
}

/// A DOF as free rows and as its full index.
#[derive(Debug, Clone)]
struct Rows {
    free: Vec<(usize, f64)>,
    full: usize,
}

impl Rows {
    /// Appends `scale` times this DOF to a gap's vectors.
    fn push_into(&self, scale: f64, gap: &mut Gap) {
        gap.b.extend(self.free.iter().map(|&(r, c)| (r, scale * c)));
        gap.full.push((self.full, scale));
    }
}

impl ContactLine {
    /// Resolves a contact: the line must be one straight wire along a global axis other
    /// than the contact's DOF ([`crate::model::line`]).
    pub fn new(system: &System, contact: &MovingContact) -> Result<Self, SolveError> {
        let model = system.model;
        let xyz = |id: u32| {
            model
                .node_index(id)
                .map(|i| model.nodes()[i].xyz)
                .ok_or_else(|| SolveError::UnknownNode {
                    node: id,
                    context: "MOVING CONTACT".into(),
                })
        };
        let d = usize::from(contact.dof - 1);
        let points = contact
            .line
            .iter()
            .map(|&n| xyz(n).map(|p| (n, p)))
            .collect::<Result<Vec<_>, _>>()?;
        // The model's check has run the same test; this keeps the analysis safe on its own.
        let pairs: std::collections::HashSet<(u32, u32)> = model
            .elements()
            .iter()
            .map(|e| (e.nodes[0].min(e.nodes[1]), e.nodes[0].max(e.nodes[1])))
            .collect();
        let joined = |a: u32, b: u32| pairs.contains(&(a.min(b), a.max(b)));
        let line = crate::model::line::contact_axis(&points, contact.dof, joined).map_err(
            |(problem, expected)| SolveError::BadInput {
                what: format!(
                    "MOVING CONTACT of head {}: {problem}; expected {expected}",
                    contact.head
                ),
            },
        )?;
        let (axis, third) = (line.axis, line.third);
        // dw/ds = eps(r, axis, d) theta_r, r the third axis.
        let eps = match (third, axis, d) {
            (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
            _ => -1.0,
        };
        let s0 = points[line.order[0]].1[axis];
        let mut nodes = Vec::with_capacity(points.len());
        for &k in &line.order {
            let (n, p) = points[k];
            let w = rows(system, n, contact.dof, "MOVING CONTACT")?;
            let mut rot = rows(system, n, (third + 4) as u8, "MOVING CONTACT")?;
            for x in &mut rot.free {
                x.1 *= eps;
            }
            // Coordinates from the line's first node in axis order.
            nodes.push((p[axis] - s0, p[d], w, rot));
        }
        let head_xyz = xyz(contact.head)?;
        let head = (
            rows(system, contact.head, contact.dof, "MOVING CONTACT")?,
            head_xyz[d],
        );
        Ok(ContactLine {
            contact: contact.clone(),
            head,
            nodes,
        })
    }

    /// The point's position along the line at time `t` (mm from the first node).
    pub fn position(&self, t: f64) -> f64 {
        self.contact.start + self.contact.speed * t
    }

    /// The contact's gap at time `t`, or `None` when the point is off the line.
    pub fn gap_at(&self, t: f64) -> Option<Gap> {
        let s = self.position(t);
        let last = self.nodes.last()?.0;
        if !(0.0..=last).contains(&s) {
            return None;
        }
        let j = self
            .nodes
            .partition_point(|n| n.0 <= s)
            .clamp(1, self.nodes.len() - 1);
        let (a, b) = (&self.nodes[j - 1], &self.nodes[j]);
        let h = b.0 - a.0;
        let xi = (s - a.0) / h;
        // Cubic Hermite shape functions (w1, w1', w2, w2').
        let n1 = 1.0 - 3.0 * xi * xi + 2.0 * xi.powi(3);
        let n2 = h * (xi - 2.0 * xi * xi + xi.powi(3));
        let n3 = 3.0 * xi * xi - 2.0 * xi.powi(3);
        let n4 = h * (xi.powi(3) - xi * xi);
        let line_x = (1.0 - xi) * a.1 + xi * b.1;
        let mut gap = Gap {
            b: Vec::with_capacity(9),
            full: Vec::with_capacity(5),
            g0: self.head.1 - line_x,
            k: self.contact.stiffness,
            sign: 1.0,
        };
        self.head.0.push_into(1.0, &mut gap);
        for (rows, wgt) in [(&a.2, n1), (&a.3, n2), (&b.2, n3), (&b.3, n4)] {
            rows.push_into(-wgt, &mut gap);
        }
        Some(gap)
    }
}

/// The slack corrections of the model's tension links (module docs).
pub fn link_gaps(system: &System) -> Result<Vec<Gap>, SolveError> {
    let mut out = Vec::with_capacity(system.model.tension_links().len());
    for l in system.model.tension_links() {
        let mut gap = Gap {
            b: Vec::new(),
            full: Vec::new(),
            g0: l.slack,
            k: l.stiffness,
            sign: -1.0,
        };
        rows(system, l.nodes[1], l.dof, "TENSION LINK")?.push_into(-1.0, &mut gap);
        rows(system, l.nodes[0], l.dof, "TENSION LINK")?.push_into(1.0, &mut gap);
        out.push(gap);
    }
    Ok(out)
}

/// Why [`solve_forces`] found no forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForcesError {
    /// The active set cycled for [`MAX_ACTIVE_SET`] passes, or its matrix is singular.
    NoConsistentSet,
    /// More than [`MAX_CLOSED`] elements closed at once (their matrix would exceed its
    /// memory bound): the count.
    TooManyClosed(usize),
}

impl ForcesError {
    /// The reason in words, for a load case's error.
    pub fn describe(self) -> String {
        match self {
            ForcesError::NoConsistentSet => format!(
                "the tension links and contacts found no consistent set of closed elements \
                 in {MAX_ACTIVE_SET} passes"
            ),
            ForcesError::TooManyClosed(a) => format!(
                "{a} tension links and contacts are closed at once; expected at most \
                 {MAX_CLOSED} (their dense matrix takes 8 a^2 bytes, docs/files.md)"
            ),
        }
    }
}

/// Solves `lambda = k max(g* - G S lambda, 0)` (module docs) for the elements `gstar`,
/// `g(i, j)` the entries of `G S` (column `j` carrying its element's sign; called for
/// closed `j` only), starting from the closed set `active`, which holds the final one on
/// return. Returns the forces; an error when the active set cycles, its matrix is
/// singular, or more than [`MAX_CLOSED`] elements close.
pub fn solve_forces(
    gstar: &[f64],
    k: &[f64],
    g: impl Fn(usize, usize) -> f64,
    active: &mut Vec<usize>,
) -> Result<Vec<f64>, ForcesError> {
    let n = gstar.len();
    let mut lambda = vec![0.0; n];
    active.retain(|&i| i < n);
    if active.is_empty() {
        active.extend((0..n).filter(|&i| gstar[i] > 0.0));
    }
    for _ in 0..MAX_ACTIVE_SET {
        lambda.fill(0.0);
        let m = active.len();
        if m > MAX_CLOSED {
            return Err(ForcesError::TooManyClosed(m));
        }
        if m > 0 {
            let a = nalgebra::DMatrix::from_fn(m, m, |p, q| {
                let (i, j) = (active[p], active[q]);
                g(i, j) + if p == q { 1.0 / k[i] } else { 0.0 }
            });
            let rhs = nalgebra::DVector::from_fn(m, |p, _| gstar[active[p]]);
            let x = a.lu().solve(&rhs).ok_or(ForcesError::NoConsistentSet)?;
            for (p, &i) in active.iter().enumerate() {
                lambda[i] = x[p];
            }
        }
        // Drop the most negative force, else add the most penetrated open element.
        let worst_closed = active
            .iter()
            .copied()
            .filter(|&i| lambda[i] < 0.0)
            .min_by(|&a, &b| lambda[a].total_cmp(&lambda[b]));
        if let Some(i) = worst_closed {
            active.retain(|&j| j != i);
            continue;
        }
        let scale = gstar
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.abs()))
            .max(1e-300);
        let worst_open = (0..n)
            .filter(|i| !active.contains(i))
            .map(|i| {
                let gi = gstar[i] - active.iter().map(|&j| g(i, j) * lambda[j]).sum::<f64>();
                (i, gi)
            })
            .filter(|&(_, gi)| gi > 1e-12 * scale)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match worst_open {
            Some((i, _)) => active.push(i),
            None => return Ok(lambda),
        }
    }
    Err(ForcesError::NoConsistentSet)
}

/// The static solution with links and contacts: `q` holds `K^-1 f` on entry (the taut
/// links in K) and the unilateral solution on return; `solve` applies `K^-1` in place.
/// Returns the elements (links' slack corrections, then the contacts at time 0) and
/// their forces.
pub fn correct_static(
    system: &System,
    solve: impl Fn(&mut [f64]),
    q: &mut [f64],
    title: &str,
) -> Result<(Vec<Gap>, Vec<f64>), SolveError> {
    let mut gaps = link_gaps(system)?;
    for c in system.model.moving_contacts() {
        if let Some(gap) = ContactLine::new(system, c)?.gap_at(0.0) {
            gaps.push(gap);
        }
    }
    if gaps.is_empty() {
        return Ok((gaps, Vec::new()));
    }
    let n = system.dim();
    // Column j of `G S` (element j's response seen by every element), computed when j
    // first closes; the response itself is not kept (module docs, "Memory").
    let columns: RefCell<Vec<Option<Vec<f64>>>> = RefCell::new(vec![None; gaps.len()]);
    let work = RefCell::new(vec![0.0; n]);
    let g = |i: usize, j: usize| {
        let mut columns = columns.borrow_mut();
        let column = columns[j].get_or_insert_with(|| {
            let mut w = work.borrow_mut();
            w.fill(0.0);
            gaps[j].add_to(1.0, &mut w);
            solve(&mut w);
            gaps.iter().map(|gap| gap.dot(&w) * gaps[j].sign).collect()
        });
        column[i]
    };
    let gstar: Vec<f64> = gaps.iter().map(|gap| gap.gap(q)).collect();
    let k: Vec<f64> = gaps.iter().map(|gap| gap.k).collect();
    let mut active = Vec::new();
    let lambda = solve_forces(&gstar, &k, g, &mut active).map_err(|e| SolveError::BadInput {
        what: format!("load case '{title}': {}", e.describe()),
    })?;
    // The correction `K^-1 sum_j s_j lambda_j b_j`: one more solve.
    if lambda.iter().any(|&l| l != 0.0) {
        let mut w = work.into_inner();
        w.fill(0.0);
        for (&l, gap) in lambda.iter().zip(&gaps) {
            if l != 0.0 {
                gap.add_to(gap.sign * l, &mut w);
            }
        }
        solve(&mut w);
        for (x, wi) in q.iter_mut().zip(&w) {
            *x -= wi;
        }
    }
    Ok((gaps, lambda))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_active_set_solves_a_two_element_complementarity_problem() {
        // G = [2 1; 1 2], k = 1: element 0 penetrated, element 1 open after coupling.
        let g = |i: usize, j: usize| if i == j { 2.0 } else { 1.0 };
        let mut active = Vec::new();
        let l = solve_forces(&[3.0, 0.5], &[1.0, 1.0], g, &mut active).unwrap();
        // Only 0 closed: (1 + 2) l0 = 3 -> l0 = 1; gap of 1: 0.5 - 1 < 0, open.
        assert!((l[0] - 1.0).abs() < 1e-14 && l[1] == 0.0);
        assert_eq!(active, [0]);
        // Both closed: (1 + G) l = g* -> [3 1; 1 3] l = [3, 3] -> l = [0.75, 0.75].
        let mut active = vec![1];
        let l = solve_forces(&[3.0, 3.0], &[1.0, 1.0], g, &mut active).unwrap();
        assert!((l[0] - 0.75).abs() < 1e-14 && (l[1] - 0.75).abs() < 1e-14);
        // Nothing penetrated: no force.
        let l = solve_forces(&[-1.0, -2.0], &[1.0, 1.0], g, &mut Vec::new()).unwrap();
        assert_eq!(l, [0.0, 0.0]);
    }
}
