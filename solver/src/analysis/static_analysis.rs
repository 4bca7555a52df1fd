//! Linear static analysis: `K_r q = T^T f - T^T K g`, then `u = T q + g`.
//!
//! Outputs, all in model units (mm, rad, N, N mm):
//! - the full displacement vector (every node, including tied and prescribed DOFs);
//! - reactions at the prescribed DOFs, `T_p^T (K u - f)` (see [`crate::dof`]), so a
//!   reaction includes what rigid ties carry to a supported reference node;
//! - for every loaded DOF the load F, the displacement u and the stiffness F/u;
//! - the spring stiffness `stiffness_n_mm`: F/u of the loaded DOF at the reference
//!   node of a rigid tie (the spring's weight node), or of the only loaded DOF when no
//!   reference node is loaded. It is positive when force and displacement have the same
//!   sign, so a compressive force with its compressive displacement gives K > 0.
//!
//! # Cubic springs (`CUBIC SPRING`)
//! With cubic springs `f_i = k3_i u_i^3` at free DOFs `i` (unit vectors `E`), the
//! balance `K q + E f(E^T q) = r` is nonlinear in the `L` spring DOFs only. Newton's
//! method on it, with the tangent `K + E D E^T`, `D = diag(3 k3 u^2)`, inverted by the
//! Sherman-Morrison-Woodbury formula on the already factored `K`, reduces exactly to
//! `L` unknowns: with `q_lin = K^{-1} r`, `Z = K^{-1} E` (`L` solves) and
//! `G = E^T Z`, every iterate is `q = q_lin - Z f`, and the spring displacements solve
//! ```text
//! u + G f(u) = E^T q_lin,      Newton step: (I + G D) du = -(u + G f(u) - E^T q_lin)
//! ```
//! iterated from `u = E^T q_lin` (halving a step that does not reduce the residual)
//! until the residual is below 1e-12 of `|E^T q_lin|`, at most [`MAX_NEWTON`]
//! iterations; the iterations are reported in [`StaticSolution::iterations`]. The
//! reported `relative_residual` includes the springs' forces, and a loaded DOF's F/u
//! (`stiffness_n_mm`) is then the secant stiffness. Friction and the
//! velocity-squared dashpot exert no static force: a quasi-static friction path (the
//! hysteresis of a slow load cycle) is not modelled in a static load case.

use super::system::System;
use super::unilateral;
use crate::error::solve::SolveError;
use crate::linalg::Cholesky;
use crate::model::{LoadCase, Model, NodeId, DOFS_PER_NODE};

/// A reaction force (N) or moment (N mm) at a prescribed DOF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reaction {
    /// The node's id.
    pub node: NodeId,
    /// The DOF number (1..=6: ux, uy, uz, rx, ry, rz).
    pub dof: u8,
    /// The reaction (N on a translation, N mm on a rotation).
    pub value: f64,
}

/// A loaded DOF with its load (N or N mm), displacement (mm or rad) and F/u.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadedDof {
    /// The node's id.
    pub node: NodeId,
    /// The DOF number (1..=6: ux, uy, uz, rx, ry, rz).
    pub dof: u8,
    /// The applied load (N on a translation, N mm on a rotation).
    pub load: f64,
    /// The displacement there (mm on a translation, rad on a rotation).
    pub displacement: f64,
    /// `load / displacement`, `None` when the displacement is exactly zero.
    pub stiffness: Option<f64>,
}

/// Result of a static load case.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// Full displacement vector (6 per node, mm and rad).
    pub displacement: Vec<f64>,
    /// The reactions at the prescribed DOFs.
    pub reactions: Vec<Reaction>,
    /// Every loaded DOF with its load, displacement and F/u.
    pub loaded: Vec<LoadedDof>,
    /// The loaded reference node whose F/u is the stiffness, if one is identified.
    pub reference_node: Option<NodeId>,
    /// F/u at the reference node's loaded translational DOF (N/mm).
    pub stiffness_n_mm: Option<f64>,
    /// Equilibrium check `|T^T (K u + E f_cubic - f)| / |T^T f|` over the free DOFs.
    pub relative_residual: f64,
    /// Newton iterations of the cubic springs (0 for a linear model).
    pub iterations: usize,
}

/// Most Newton iterations for the cubic springs of a static case.
pub const MAX_NEWTON: usize = 100;

impl StaticSolution {
    /// The six displacements of a node (mm, mm, mm, rad, rad, rad).
    pub fn node_displacement(&self, model: &Model, node: NodeId) -> Option<[f64; 6]> {
        let i = model.node_index(node)?;
        let mut out = [0.0; 6];
        out.copy_from_slice(&self.displacement[i * DOFS_PER_NODE..(i + 1) * DOFS_PER_NODE]);
        Some(out)
    }
}

/// Solves one static load case with a factor of the system's stiffness.
pub fn solve(
    system: &System,
    factor: &Cholesky,
    case: &LoadCase,
    time: f64,
) -> Result<StaticSolution, SolveError> {
    let model = system.model;
    let dofs = &system.dofs;
    let f_full =
        system.point_load_vector(model.point_loads.iter().chain(&case.point_loads), time)?;
    let rhs = system.free_load(&f_full);
    let mut q = rhs.clone();
    factor.solve_in_place(&mut q);
    let springs: Vec<(usize, f64)> = system
        .point_laws()?
        .into_iter()
        .filter(|(_, law)| law.cubic > 0.0)
        .map(|(eq, law)| (eq, law.cubic))
        .collect();
    let spring_forces = cubic_springs(factor, &springs, &mut q, &case.title)?;
    let unilateral = !(model.tension_links().is_empty() && model.moving_contacts().is_empty());
    if unilateral && !springs.is_empty() {
        return Err(SolveError::BadInput {
            what: format!(
                "load case '{}': CUBIC SPRING together with TENSION LINK or MOVING \
                 CONTACT in a STATIC case is not supported",
                case.title
            ),
        });
    }
    let (gaps, gap_forces) = unilateral::correct_static(
        system,
        |x: &mut [f64]| factor.solve_in_place(x),
        &mut q,
        &case.title,
    )?;
    if q.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite {
            what: format!("static displacements of load case '{}'", case.title),
        });
    }
    let displacement = dofs.expand(&q, 1.0);
    let mut residual = system.residual(&displacement, &f_full)?;
    for (&(eq, _), f) in springs.iter().zip(&spring_forces.forces) {
        residual[dofs.free_to_full(eq)] += f;
    }
    // Contacts (links are in `residual` already, slack ones at zero force).
    let n_links = model.tension_links().len();
    for (gap, f) in gaps.iter().zip(&gap_forces).skip(n_links) {
        for &(d, c) in &gap.full {
            residual[d] += c * f;
        }
    }

    // Equilibrium of the free equations, relative to the applied load.
    let mut free_residual = vec![0.0; dofs.free_len()];
    dofs.restrict_add(&residual, &mut free_residual);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let load_norm = norm(&rhs);
    let relative_residual = if load_norm > 0.0 {
        norm(&free_residual) / load_norm
    } else {
        0.0
    };

    let reactions = dofs
        .reactions(&residual)
        .into_iter()
        .map(|(d, value)| {
            let (node, dof) = dofs.label(d);
            Reaction { node, dof, value }
        })
        .collect();
    let loaded: Vec<LoadedDof> = f_full
        .iter()
        .enumerate()
        .filter(|(_, f)| **f != 0.0)
        .map(|(d, &load)| {
            let (node, dof) = dofs.label(d);
            let u = displacement[d];
            LoadedDof {
                node,
                dof,
                load,
                displacement: u,
                stiffness: (u != 0.0).then(|| load / u),
            }
        })
        .collect();

    let is_reference = |node: NodeId| model.rigid_ties.iter().any(|t| t.reference == node);
    let at_reference: Vec<&LoadedDof> = loaded.iter().filter(|l| is_reference(l.node)).collect();
    let chosen = match (at_reference.as_slice(), loaded.as_slice()) {
        ([one], _) => Some(*one),
        ([], [one]) => Some(one),
        _ => None,
    };
    let reference_node = chosen.map(|l| l.node);
    let stiffness_n_mm = chosen.filter(|l| l.dof <= 3).and_then(|l| l.stiffness);
    Ok(StaticSolution {
        displacement,
        reactions,
        loaded,
        reference_node,
        stiffness_n_mm,
        relative_residual,
        iterations: spring_forces.iterations,
    })
}

/// The cubic springs' forces at equilibrium and the Newton iterations taken.
struct SpringForces {
    forces: Vec<f64>,
    iterations: usize,
}

/// Newton's method for the cubic springs `(free equation, k3)` (module docs): `q`
/// holds `K^{-1} r` on entry and the nonlinear solution on return.
fn cubic_springs(
    factor: &Cholesky,
    springs: &[(usize, f64)],
    q: &mut [f64],
    case: &str,
) -> Result<SpringForces, SolveError> {
    let l = springs.len();
    if l == 0 {
        return Ok(SpringForces {
            forces: Vec::new(),
            iterations: 0,
        });
    }
    let n = q.len();
    // Z = K^{-1} E, G = E^T Z.
    let mut z = vec![0.0; l * n];
    for (j, &(eq, _)) in springs.iter().enumerate() {
        let column = &mut z[j * n..(j + 1) * n];
        column[eq] = 1.0;
        factor.solve_in_place(column);
    }
    let g = |i: usize, j: usize| z[j * n + springs[i].0];
    let target: Vec<f64> = springs.iter().map(|&(eq, _)| q[eq]).collect();
    let force = |u: &[f64]| -> Vec<f64> {
        springs
            .iter()
            .zip(u)
            .map(|(&(_, k3), &x)| k3 * x * x * x)
            .collect()
    };
    let residual = |u: &[f64]| -> Vec<f64> {
        let f = force(u);
        (0..l)
            .map(|i| u[i] + (0..l).map(|j| g(i, j) * f[j]).sum::<f64>() - target[i])
            .collect()
    };
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = norm(&target);
    let mut u = target.clone();
    let mut r = residual(&u);
    let mut iterations = 0;
    while norm(&r) > 1e-12 * scale {
        if iterations >= MAX_NEWTON || !norm(&r).is_finite() {
            return Err(SolveError::NewtonNotConverged {
                case: case.to_string(),
                iterations,
                residual: norm(&r) / scale,
            });
        }
        iterations += 1;
        // Jacobian I + G D, D = diag(3 k3 u^2).
        let mut jac = vec![0.0; l * l];
        for i in 0..l {
            for j in 0..l {
                let d = 3.0 * springs[j].1 * u[j] * u[j];
                jac[i * l + j] = f64::from(u8::from(i == j)) + g(i, j) * d;
            }
        }
        let mut step: Vec<f64> = r.iter().map(|x| -x).collect();
        solve_dense(&mut jac, &mut step, l).ok_or_else(|| SolveError::NewtonNotConverged {
            case: case.to_string(),
            iterations,
            residual: norm(&r) / scale,
        })?;
        // Halve a step that does not reduce the residual (the cubic's Newton steps
        // overshoot from the wrong side of an inflection).
        let mut t = 1.0;
        loop {
            let trial: Vec<f64> = u.iter().zip(&step).map(|(a, b)| a + t * b).collect();
            let r_trial = residual(&trial);
            if norm(&r_trial) < norm(&r) || t < 1e-6 {
                u = trial;
                r = r_trial;
                break;
            }
            t *= 0.5;
        }
    }
    let forces = force(&u);
    for (j, f) in forces.iter().enumerate() {
        for (qi, zi) in q.iter_mut().zip(&z[j * n..(j + 1) * n]) {
            *qi -= f * zi;
        }
    }
    Ok(SpringForces { forces, iterations })
}

/// Solves the small dense system `a x = b` (row-major `l x l`) in place by Gaussian
/// elimination with partial pivoting; `None` when a pivot vanishes.
fn solve_dense(a: &mut [f64], b: &mut [f64], l: usize) -> Option<()> {
    for k in 0..l {
        let p = (k..l).max_by(|&i, &j| a[i * l + k].abs().total_cmp(&a[j * l + k].abs()))?;
        if a[p * l + k] == 0.0 || !a[p * l + k].is_finite() {
            return None;
        }
        if p != k {
            for c in 0..l {
                a.swap(k * l + c, p * l + c);
            }
            b.swap(k, p);
        }
        for i in k + 1..l {
            let m = a[i * l + k] / a[k * l + k];
            for c in k..l {
                a[i * l + c] -= m * a[k * l + c];
            }
            b[i] -= m * b[k];
        }
    }
    for k in (0..l).rev() {
        let s: f64 = (k + 1..l).map(|c| a[k * l + c] * b[c]).sum();
        b[k] = (b[k] - s) / a[k * l + k];
    }
    Some(())
}
