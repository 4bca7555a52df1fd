//! The assembled, constraint-reduced system of a model that the static, modal and
//! transient analyses share (see the module docs of [`crate::analysis`]), and the
//! load tables they evaluate.

use crate::assembly::Assembler;
use crate::dof::{dof_name, DofMap};
use crate::element::{self, Matrix12};
use crate::error::solve::SolveError;
use crate::linalg::{Cholesky, SymbolicFactor};
use crate::model::{Dashpot, Element, Model, NodeId, PointLoad, PointMass, DOFS_PER_NODE};
use faer::sparse::SparseColMat;
use nalgebra::SMatrix;

/// The assembled, constraint-reduced system of a model.
#[derive(Debug)]
pub struct System<'m> {
    /// The model the system is assembled from.
    pub model: &'m Model,
    /// The map from the model's DOFs to free equations (constraints eliminated).
    pub dofs: DofMap,
    /// The scatter plans and shared sparsity pattern of K, M and C.
    pub assembler: Assembler,
    /// Full DOFs of every block: the model's elements first (in `model.elements`
    /// order), then the point masses (in `model.point_masses` order).
    pub blocks: Vec<Vec<usize>>,
    /// Point-mass blocks (6x6 diagonal), in `model.point_masses` order.
    pub point_mass_blocks: Vec<SMatrix<f64, 6, 6>>,
    /// Index in `blocks` of the first matrix element (`DMIG`); they are the last
    /// blocks, in `model.matrix_elements` order.
    pub matrix_first: usize,
    /// Reduced stiffness (upper triangle).
    pub stiffness: SparseColMat<usize, f64>,
    /// Reduced mass (upper triangle).
    pub mass: SparseColMat<usize, f64>,
    /// Reduced Rayleigh damping (upper triangle).
    pub damping: SparseColMat<usize, f64>,
    /// `-T^T K g`: the load the prescribed displacements put on the free DOFs, plus the
    /// tension links' force at the reference (`k slack (e_b - e_a)`).
    pub prescribed_load: Vec<f64>,
    /// Symbolic Cholesky of the pattern, shared by every factor on it.
    pub symbolic: SymbolicFactor,
}

impl<'m> System<'m> {
    /// Builds the DOF map, element matrices, pattern, K, M, C and the symbolic factor.
    pub fn new(model: &'m Model) -> Result<Self, SolveError> {
        let dofs = DofMap::new(model)?;
        let node_dofs = |id: NodeId, context: &str| -> Result<std::ops::Range<usize>, SolveError> {
            let i = model
                .node_index(id)
                .ok_or_else(|| SolveError::UnknownNode {
                    node: id,
                    context: context.to_string(),
                })?;
            Ok(i * DOFS_PER_NODE..(i + 1) * DOFS_PER_NODE)
        };

        let mut blocks: Vec<Vec<usize>> =
            Vec::with_capacity(model.elements.len() + model.point_masses.len());
        for e in &model.elements {
            element_matrices(model, e)?;
            let context = format!("element {}", e.id);
            let mut block = node_dofs(e.nodes[0], &context)?.collect::<Vec<_>>();
            block.extend(node_dofs(e.nodes[1], &context)?);
            blocks.push(block);
        }
        let mut point_mass_blocks = Vec::with_capacity(model.point_masses.len());
        for p in &model.point_masses {
            point_mass_blocks.push(point_mass_block(p)?);
            blocks.push(node_dofs(p.node, "POINT MASS")?.collect());
        }
        // Linear dashpots (`DASHPOT`): one 6x6 block per dashpot at its node, after the
        // point masses.
        let dashpot_first = blocks.len();
        let mut dashpot_blocks = Vec::with_capacity(model.dashpots.len());
        for d in &model.dashpots {
            dashpot_blocks.push(dashpot_block(d)?);
            blocks.push(node_dofs(d.node, "DASHPOT")?.collect());
        }
        // Tension links (`TENSION LINK`), taut: a 2x2 block along their DOF each.
        let link_first = blocks.len();
        for l in &model.tension_links {
            let a = node_dofs(l.nodes[0], "TENSION LINK")?.start + usize::from(l.dof - 1);
            let b = node_dofs(l.nodes[1], "TENSION LINK")?.start + usize::from(l.dof - 1);
            blocks.push(vec![a, b]);
        }
        // Matrix elements (`DMIG`): one block over their listed DOFs each, last.
        let matrix_first = blocks.len();
        for e in &model.matrix_elements {
            let mut block = Vec::with_capacity(e.size());
            for &(node, dof) in &e.dofs {
                let d = dofs.full_index(node, dof).ok_or(SolveError::BadDof {
                    dof,
                    context: format!("DMIG `{}` at node {node}", e.name),
                })?;
                block.push(d);
            }
            blocks.push(block);
        }
        let assembler = Assembler::new(&dofs, &blocks)?;
        let n_elements = model.elements.len();

        let mut k_values = assembler.new_values();
        let mut m_values = assembler.new_values();
        let mut c_values = assembler.new_values();
        let mut prescribed_load = vec![0.0; dofs.free_len()];
        for (b, e) in model.elements.iter().enumerate() {
            let (k, m) = element_matrices(model, e)?;
            assembler.add_block(&mut k_values, b, k.as_slice(), 1.0);
            assembler.add_block(&mut m_values, b, m.as_slice(), 1.0);
            assembler.add_prescribed_load(&mut prescribed_load, b, k.as_slice(), 1.0);
        }
        for (p, block) in point_mass_blocks.iter().enumerate() {
            assembler.add_block(&mut m_values, n_elements + p, block.as_slice(), 1.0);
        }
        add_rayleigh(model, &assembler, &mut c_values, &point_mass_blocks)?;
        for (k, block) in dashpot_blocks.iter().enumerate() {
            assembler.add_block(&mut c_values, dashpot_first + k, block.as_slice(), 1.0);
        }
        // A link's force at the reference, k (u_b - u_a - slack) at u = 0, is the
        // constant load k slack (e_b - e_a) on the right-hand side.
        let mut pretension = vec![0.0; dofs.full_len()];
        for (i, l) in model.tension_links.iter().enumerate() {
            let k = l.stiffness;
            let block = [k, -k, -k, k];
            assembler.add_block(&mut k_values, link_first + i, &block, 1.0);
            assembler.add_prescribed_load(&mut prescribed_load, link_first + i, &block, 1.0);
            let b = &blocks[link_first + i];
            pretension[b[0]] -= k * l.slack;
            pretension[b[1]] += k * l.slack;
        }
        for (i, e) in model.matrix_elements.iter().enumerate() {
            let b = matrix_first + i;
            assembler.add_block(&mut k_values, b, &e.stiffness, 1.0);
            assembler.add_block(&mut m_values, b, &e.mass, 1.0);
            assembler.add_prescribed_load(&mut prescribed_load, b, &e.stiffness, 1.0);
            if !e.damping.is_empty() {
                assembler.add_block(&mut c_values, b, &e.damping, 1.0);
            }
        }
        dofs.restrict_add(&pretension, &mut prescribed_load);
        let stiffness = assembler.matrix(&k_values)?;
        let mass = assembler.matrix(&m_values)?;
        let damping = assembler.matrix(&c_values)?;
        let symbolic = SymbolicFactor::analyze(assembler.pattern())?;
        Ok(System {
            model,
            dofs,
            assembler,
            blocks,
            point_mass_blocks,
            matrix_first,
            stiffness,
            mass,
            damping,
            prescribed_load,
            symbolic,
        })
    }

    /// Number of free DOFs.
    /// The full DOF index of `dof` (1..=6) at `node`, or an error naming what `context`
    /// (a card name) referred to that does not exist.
    pub fn full_dof(&self, node: NodeId, dof: u8, context: &str) -> Result<usize, SolveError> {
        self.dofs.full_index(node, dof).ok_or_else(|| {
            if self.model.node_index(node).is_none() {
                SolveError::UnknownNode {
                    node,
                    context: context.to_string(),
                }
            } else {
                SolveError::BadDof {
                    dof,
                    context: context.to_string(),
                }
            }
        })
    }

    /// Number of free DOFs (equations) of the reduced system.
    pub fn dim(&self) -> usize {
        self.dofs.free_len()
    }

    /// The model's nonlinear point elements as `(free equation, law)`, zero laws left
    /// out. Each must sit on a free DOF (the deck reader checks; a model built in code
    /// gets the error here).
    pub fn point_laws(&self) -> Result<Vec<(usize, crate::integrate::PointLaw)>, SolveError> {
        let mut out = Vec::new();
        for e in &self.model.point_laws {
            let law = e.law();
            if !law.is_valid() {
                return Err(SolveError::BadInput {
                    what: format!(
                        "the nonlinear point element at node {} {} has a negative or non-finite coefficient",
                        e.node,
                        dof_name(e.dof)
                    ),
                });
            }
            if law.is_zero() {
                continue;
            }
            let full = self.full_dof(e.node, e.dof, "a nonlinear point element")?;
            match self.dofs.status(full) {
                crate::dof::DofStatus::Free(eq) => out.push((eq, law)),
                _ => {
                    return Err(SolveError::ConflictingConstraint {
                        node: e.node,
                        dof: e.dof,
                        reason: "a nonlinear point element needs a free DOF, this one is \
                                 prescribed or tied"
                            .to_string(),
                    })
                }
            }
        }
        Ok(out)
    }

    /// Numeric Cholesky factor of the reduced stiffness; a singular K is a
    /// [`SolveError::Mechanism`] naming a free DOF.
    pub fn factor_stiffness(&self) -> Result<Cholesky, SolveError> {
        self.symbolic
            .factor(self.stiffness.as_ref())
            .map_err(|e| self.dofs.mechanism(e))
    }

    /// Full-space load vector of point loads at `time` (table factors applied).
    pub fn point_load_vector<'a>(
        &self,
        loads: impl IntoIterator<Item = &'a PointLoad>,
        time: f64,
    ) -> Result<Vec<f64>, SolveError> {
        let mut f = vec![0.0; self.dofs.full_len()];
        for load in loads {
            let factor = match &load.table {
                Some(name) => table_factor(self.model, name, time)?,
                None => 1.0,
            };
            for &node in &load.nodes {
                for &(dof, value) in &load.dofs {
                    let d = self.full_dof(node, dof, "POINT LOAD")?;
                    if !value.is_finite() {
                        return Err(SolveError::NonFinite {
                            what: format!("POINT LOAD at node {node} {}", dof_name(dof)),
                        });
                    }
                    f[d] += factor * value;
                }
            }
        }
        Ok(f)
    }

    /// The free-DOF right-hand side `T^T f - T^T K g` of a full-space load `f` (the
    /// prescribed displacements are constant in time, so this holds for transients too).
    pub fn free_load(&self, f_full: &[f64]) -> Vec<f64> {
        let mut rhs = self.prescribed_load.clone();
        self.dofs.restrict_add(f_full, &mut rhs);
        rhs
    }

    /// The global stiffness and mass matrices of element `b` (`model.elements` order).
    /// They are computed again when asked for, not kept: 2.3 KB per element, 222 MB on
    /// a 200-span catenary (docs/files.md).
    pub fn element_matrices(&self, b: usize) -> Result<(Matrix12, Matrix12), SolveError> {
        element_matrices(self.model, &self.model.elements[b])
    }

    /// `K_full u - f` in the full space, element by element (for reactions), with the
    /// tension links' forces `k max(e, 0)` (slack ones exert none).
    pub fn residual(&self, u_full: &[f64], f_full: &[f64]) -> Result<Vec<f64>, SolveError> {
        let mut r: Vec<f64> = f_full.iter().map(|f| -f).collect();
        let first =
            self.model.elements.len() + self.model.point_masses.len() + self.model.dashpots.len();
        for (e, b) in self
            .model
            .matrix_elements
            .iter()
            .zip(&self.blocks[self.matrix_first..])
        {
            matrix_times(b, &e.stiffness, u_full, &mut r);
        }
        for (l, b) in self.model.tension_links.iter().zip(&self.blocks[first..]) {
            let e = u_full[b[1]] - u_full[b[0]] - l.slack;
            let force = l.stiffness * e.max(0.0);
            r[b[1]] += force;
            r[b[0]] -= force;
        }
        for (b, block) in self.blocks[..self.model.elements.len()].iter().enumerate() {
            let (k, _) = self.element_matrices(b)?;
            for (a, &da) in block.iter().enumerate() {
                r[da] += block
                    .iter()
                    .enumerate()
                    .map(|(b, &db)| k[(a, b)] * u_full[db])
                    .sum::<f64>();
            }
        }
        Ok(r)
    }

    /// `M_full v` in the full space (elements and point masses, before constraints).
    pub fn full_mass_times(&self, v_full: &[f64]) -> Result<Vec<f64>, SolveError> {
        let mut out = vec![0.0; v_full.len()];
        let n_elements = self.model.elements.len();
        for (b, block) in self.blocks[..n_elements].iter().enumerate() {
            let (_, m) = self.element_matrices(b)?;
            for (a, &da) in block.iter().enumerate() {
                out[da] += block
                    .iter()
                    .enumerate()
                    .map(|(b, &db)| m[(a, b)] * v_full[db])
                    .sum::<f64>();
            }
        }
        for (block, m) in self.blocks[n_elements..]
            .iter()
            .zip(&self.point_mass_blocks)
        {
            for (a, &da) in block.iter().enumerate() {
                out[da] += m[(a, a)] * v_full[da];
            }
        }
        for (e, b) in self
            .model
            .matrix_elements
            .iter()
            .zip(&self.blocks[self.matrix_first..])
        {
            matrix_times(b, &e.mass, v_full, &mut out);
        }
        Ok(out)
    }
}

/// `out[block] += A x[block]` for a row-major `A` over the full DOFs `block`.
fn matrix_times(block: &[usize], a: &[f64], x: &[f64], out: &mut [f64]) {
    let n = block.len();
    for (i, &di) in block.iter().enumerate() {
        out[di] += (0..n).map(|j| a[i * n + j] * x[block[j]]).sum::<f64>();
    }
}

/// Value of table `name` at `time`: piecewise linear, constant beyond its ends.
pub fn table_factor(model: &Model, name: &str, time: f64) -> Result<f64, SolveError> {
    Ok(interpolate(table_points(model, name)?, time))
}

/// The points of table `name` (case-insensitive), checked to be non-empty and finite.
pub fn table_points<'m>(model: &'m Model, name: &str) -> Result<&'m [(f64, f64)], SolveError> {
    let table = model
        .tables
        .iter()
        .find(|t| t.name.eq_ignore_ascii_case(name))
        .ok_or_else(|| SolveError::UnknownTable {
            name: name.to_string(),
            context: "POINT LOAD".to_string(),
        })?;
    if table.points.is_empty() {
        return Err(SolveError::BadInput {
            what: format!("table '{name}' has no points"),
        });
    }
    if table
        .points
        .iter()
        .any(|(t, f)| !(t.is_finite() && f.is_finite()))
    {
        return Err(SolveError::NonFinite {
            what: format!("a point of table '{name}'"),
        });
    }
    Ok(&table.points)
}

/// Piecewise-linear interpolation in `points` (sorted by time, at least one), holding
/// the end values outside their range.
pub(crate) fn interpolate(p: &[(f64, f64)], time: f64) -> f64 {
    let (Some(first), Some(last)) = (p.first(), p.last()) else {
        return 0.0;
    };
    if time <= first.0 {
        return first.1;
    }
    if time >= last.0 {
        return last.1;
    }
    let k = p.partition_point(|&(t, _)| t <= time);
    let (t0, f0) = p[k - 1];
    let (t1, f1) = p[k];
    if t1 > t0 {
        f0 + (f1 - f0) * (time - t0) / (t1 - t0)
    } else {
        f1
    }
}

/// Adds each `DAMPING` entry's Rayleigh damping to `c_values`: alpha times the mass and
/// beta times the stiffness of its elements (blocks `0..n_elements`, in model order), and
/// alpha times the point masses at its mass nodes (blocks after the elements).
fn add_rayleigh(
    model: &Model,
    assembler: &Assembler,
    c_values: &mut [f64],
    point_mass_blocks: &[SMatrix<f64, 6, 6>],
) -> Result<(), SolveError> {
    let n_elements = model.elements.len();
    for (entry, d) in model.damping.iter().enumerate() {
        if !(d.alpha.is_finite() && d.beta.is_finite()) {
            return Err(SolveError::NonFinite {
                what: format!(
                    "DAMPING entry {} (alpha {}, beta {})",
                    entry + 1,
                    d.alpha,
                    d.beta
                ),
            });
        }
        for &id in &d.elements {
            let b = model
                .element_index(id)
                .ok_or_else(|| SolveError::UnknownElement {
                    element: id,
                    context: format!("DAMPING entry {}", entry + 1),
                })?;
            let (k, m) = element_matrices(model, &model.elements[b])?;
            assembler.add_block(c_values, b, m.as_slice(), d.alpha);
            assembler.add_block(c_values, b, k.as_slice(), d.beta);
        }
        for &node in &d.mass_nodes {
            let mut found = false;
            for (p, pm) in model.point_masses.iter().enumerate() {
                if pm.node == node {
                    found = true;
                    assembler.add_block(
                        c_values,
                        n_elements + p,
                        point_mass_blocks[p].as_slice(),
                        d.alpha,
                    );
                }
            }
            if !found {
                return Err(SolveError::BadInput {
                    what: format!(
                        "DAMPING entry {} names node {node} for mass damping, but no POINT MASS is at that node",
                        entry + 1
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The 6x6 diagonal mass block of a point mass, checked finite and non-negative.
fn point_mass_block(p: &PointMass) -> Result<SMatrix<f64, 6, 6>, SolveError> {
    let values = [
        p.mass,
        p.mass,
        p.mass,
        p.inertia[0],
        p.inertia[1],
        p.inertia[2],
    ];
    if values.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(SolveError::BadInput {
            what: format!(
                "POINT MASS at node {}: mass and rotary inertia must be finite and non-negative, got {values:?}",
                p.node
            ),
        });
    }
    Ok(SMatrix::<f64, 6, 6>::from_diagonal(&values.into()))
}

/// The 6x6 damping block of a linear dashpot (its `c` on its DOF), checked.
fn dashpot_block(d: &Dashpot) -> Result<SMatrix<f64, 6, 6>, SolveError> {
    if !(d.c.is_finite() && d.c >= 0.0 && (1..=6).contains(&d.dof)) {
        return Err(SolveError::BadInput {
            what: format!(
                "DASHPOT at node {} DOF {}: c must be finite and >= 0 on a DOF 1..6, got {}",
                d.node, d.dof, d.c
            ),
        });
    }
    let mut values = [0.0; 6];
    values[usize::from(d.dof) - 1] = d.c;
    Ok(SMatrix::<f64, 6, 6>::from_diagonal(&values.into()))
}

/// The global stiffness and mass matrices of `e` (consistent or lumped mass as the model
/// says; the geometric stiffness of its `BEAM TENSION` included).
fn element_matrices(model: &Model, e: &Element) -> Result<(Matrix12, Matrix12), SolveError> {
    let mut k = Matrix12::zeros();
    let mut m = Matrix12::zeros();
    element::global_matrices(model, e, model.lumped_mass, &mut k, &mut m).map_err(|source| {
        SolveError::Element {
            element: e.id,
            source,
        }
    })?;
    Ok((k, m))
}
