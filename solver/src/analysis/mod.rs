//! Analyses of a [`Model`]: the assembled [`System`] they share, linear static
//! ([`static_analysis`]), modal ([`modal`]) and transient ([`transient`]) load cases,
//! and [`run`], which executes a model's load cases in order.
//!
//! # The shared system
//! [`System::new`] builds, once per model, the [`DofMap`] (constraints), the global
//! element matrices, the [`Assembler`] with its pattern, the reduced stiffness `K`,
//! mass `M` and Rayleigh damping `C` on that one pattern, the load that prescribed
//! displacements put on the free DOFs, and the symbolic Cholesky of the pattern.
//!
//! For a transient analysis the system provides: `M`, `C`, `K` on one pattern (upper
//! triangles; [`crate::linalg::upper_to_full`] gives both triangles where an
//! integrator wants them), `M + gamma dt C + beta dt^2 K` by [`Assembler::combine`]
//! factored with [`System::symbolic`] (pattern and symbolic analysis reused), the load
//! at time t by [`System::point_load_vector`] + [`System::free_load`], and the DOF map
//! to expand free vectors to nodes ([`DofMap::expand`]) for history output.
//!
//! # Damping
//! `C = sum over DAMPING entries of (alpha M_e + beta K_e)` over the entry's elements,
//! plus `alpha M_p` for the point masses at the entry's `mass_nodes` only: a point
//! mass (the spring's weight) gets no mass-proportional damping unless an entry names
//! its node.
//!
//! # Loads
//! A load case applies the model-definition `POINT LOAD`s plus its own. A load with a
//! table is scaled by the table at the evaluation time: the end time of a static load
//! case (`Static { time }`), the current time of a transient. Tables are
//! piecewise-linear and hold their first and last values outside their range.
//!
//! Units throughout: mm, N, t, s (see [`crate::model`]).

pub mod modal;
pub mod static_analysis;
pub mod transient;

pub use modal::{ModalSolution, Mode};
pub use static_analysis::{LoadedDof, Reaction, StaticSolution};
pub use transient::{History, HistoryColumn, TransientSolution};

use crate::assembly::Assembler;
use crate::dof::{dof_name, DofMap};
use crate::element::{self, ElementError, Matrix12};
use crate::integrate::IntegrateError;
use crate::linalg::{Cholesky, FactorError, SymbolicFactor};
use crate::model::{Analysis, ElementId, Model, NodeId, PointLoad, DOFS_PER_NODE};
use faer::sparse::SparseColMat;
use nalgebra::SMatrix;

/// Errors from building or solving the finite-element system.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    /// An element's matrices cannot be formed.
    #[error("element {element}: {source}")]
    Element {
        element: ElementId,
        #[source]
        source: ElementError,
    },
    /// A node id that the model does not define.
    #[error("{context} refers to node {node}, which does not exist")]
    UnknownNode { node: NodeId, context: String },
    /// An element id that the model does not define.
    #[error("{context} refers to element {element}, which does not exist")]
    UnknownElement { element: ElementId, context: String },
    /// A DOF number outside 1..=6.
    #[error("{context} uses DOF {dof}; DOFs are numbered 1..=6 (ux, uy, uz, rx, ry, rz)")]
    BadDof { dof: u8, context: String },
    /// Two constraints on one DOF that cannot both hold.
    #[error("node {node} {}: {reason}", dof_name(*dof))]
    ConflictingConstraint {
        node: NodeId,
        dof: u8,
        reason: String,
    },
    /// The stiffness is singular: a free DOF that nothing resists.
    #[error(
        "mechanism at node {node} {} (DOF {dof}): {detail}; \
         support it (FIXED DISP), tie it (RBE2) or connect it to an element",
        dof_name(*dof)
    )]
    Mechanism {
        node: NodeId,
        dof: u8,
        detail: String,
    },
    /// A value that must be finite is not (or a state became non-finite).
    #[error("non-finite value: {what}")]
    NonFinite { what: String },
    /// An input value outside its admissible range.
    #[error("{what}")]
    BadInput { what: String },
    /// A table named by a load does not exist.
    #[error("{context} refers to table '{name}', which does not exist")]
    UnknownTable { name: String, context: String },
    /// More modes requested than the model has free DOFs.
    #[error("load case '{case}' asks for {requested} modes but the model has only {available} free DOFs")]
    TooManyModes {
        case: String,
        requested: usize,
        available: usize,
    },
    /// The eigensolver did not converge.
    #[error(
        "load case '{case}': the eigensolver converged {converged} of {requested} modes; \
         ask for fewer modes or check the model for a (near) mechanism"
    )]
    EigenNotConverged {
        case: String,
        requested: usize,
        converged: usize,
    },
    /// An analysis kind that this build does not run.
    #[error("load case '{case}': {what} is not supported yet")]
    Unsupported { case: String, what: String },
    /// Nonlinear point elements in a transient solved by modal superposition.
    #[error(
        "load case '{case}': nonlinear point elements (FRICTION, QUADRATIC DAMPER, CUBIC \
         SPRING) need --method direct; modal superposition is linear"
    )]
    NonlinearNeedsDirect { case: String },
    /// The static Newton iterations of the cubic springs did not converge.
    #[error(
        "load case '{case}': the cubic springs' Newton iterations did not converge in \
         {iterations} iterations (relative residual {residual:e})"
    )]
    NewtonNotConverged {
        case: String,
        iterations: usize,
        residual: f64,
    },
    /// A failure inside the sparse linear algebra (allocation, pattern).
    #[error("linear algebra: {0}")]
    Linalg(String),
    /// A time integrator failed (operators not positive definite, non-finite state);
    /// `location` names the node and DOF (direct) or the mode (modal) where it can.
    #[error("load case '{case}': {source}{location}")]
    Integrate {
        case: String,
        location: String,
        #[source]
        source: IntegrateError,
    },
}

impl SolveError {
    /// Maps a factorisation failure to a mechanism at the DOF of the failing equation.
    pub fn from_factor(dofs: &DofMap, error: FactorError) -> Self {
        match error {
            FactorError::Singular {
                equation,
                pivot,
                diagonal,
            } => {
                let (node, dof) = dofs.free_label(equation);
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
}

/// The assembled, constraint-reduced system of a model.
#[derive(Debug)]
pub struct System<'m> {
    pub model: &'m Model,
    pub dofs: DofMap,
    pub assembler: Assembler,
    /// Full DOFs of every block: the model's elements first (in `model.elements`
    /// order), then the point masses (in `model.point_masses` order).
    pub blocks: Vec<Vec<usize>>,
    /// Global element stiffness matrices, in `model.elements` order.
    pub element_stiffness: Vec<Matrix12>,
    /// Global element mass matrices (consistent or lumped as the model says).
    pub element_mass: Vec<Matrix12>,
    /// Point-mass blocks (6x6 diagonal), in `model.point_masses` order.
    pub point_mass_blocks: Vec<SMatrix<f64, 6, 6>>,
    /// Reduced stiffness (upper triangle).
    pub stiffness: SparseColMat<usize, f64>,
    /// Reduced mass (upper triangle).
    pub mass: SparseColMat<usize, f64>,
    /// Reduced Rayleigh damping (upper triangle).
    pub damping: SparseColMat<usize, f64>,
    /// `-T^T K g`: the load the prescribed displacements put on the free DOFs.
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
        let mut element_stiffness = Vec::with_capacity(model.elements.len());
        let mut element_mass = Vec::with_capacity(model.elements.len());
        for e in &model.elements {
            let mut k = Matrix12::zeros();
            let mut m = Matrix12::zeros();
            element::global_matrices(model, e, model.lumped_mass, &mut k, &mut m).map_err(
                |source| SolveError::Element {
                    element: e.id,
                    source,
                },
            )?;
            let context = format!("element {}", e.id);
            let mut block = node_dofs(e.nodes[0], &context)?.collect::<Vec<_>>();
            block.extend(node_dofs(e.nodes[1], &context)?);
            blocks.push(block);
            element_stiffness.push(k);
            element_mass.push(m);
        }
        let mut point_mass_blocks = Vec::with_capacity(model.point_masses.len());
        for p in &model.point_masses {
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
            blocks.push(node_dofs(p.node, "POINT MASS")?.collect());
            point_mass_blocks.push(SMatrix::<f64, 6, 6>::from_diagonal(&values.into()));
        }
        let assembler = Assembler::new(&dofs, &blocks)?;
        let n_elements = model.elements.len();

        let mut k_values = assembler.new_values();
        let mut m_values = assembler.new_values();
        let mut c_values = assembler.new_values();
        let mut prescribed_load = vec![0.0; dofs.free_len()];
        for (b, (k, m)) in element_stiffness.iter().zip(&element_mass).enumerate() {
            assembler.add_block(&mut k_values, b, k.as_slice(), 1.0);
            assembler.add_block(&mut m_values, b, m.as_slice(), 1.0);
            assembler.add_prescribed_load(&mut prescribed_load, b, k.as_slice(), 1.0);
        }
        for (p, block) in point_mass_blocks.iter().enumerate() {
            assembler.add_block(&mut m_values, n_elements + p, block.as_slice(), 1.0);
        }
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
                assembler.add_block(&mut c_values, b, element_mass[b].as_slice(), d.alpha);
                assembler.add_block(&mut c_values, b, element_stiffness[b].as_slice(), d.beta);
            }
            for &node in &d.mass_nodes {
                let mut found = false;
                for (p, pm) in model.point_masses.iter().enumerate() {
                    if pm.node == node {
                        found = true;
                        assembler.add_block(
                            &mut c_values,
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
        let stiffness = assembler.matrix(&k_values)?;
        let mass = assembler.matrix(&m_values)?;
        let damping = assembler.matrix(&c_values)?;
        let symbolic = SymbolicFactor::analyze(assembler.pattern())?;
        Ok(System {
            model,
            dofs,
            assembler,
            blocks,
            element_stiffness,
            element_mass,
            point_mass_blocks,
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
            .map_err(|e| SolveError::from_factor(&self.dofs, e))
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

    /// `K_full u - f` in the full space, element by element (for reactions).
    pub fn residual(&self, u_full: &[f64], f_full: &[f64]) -> Vec<f64> {
        let mut r: Vec<f64> = f_full.iter().map(|f| -f).collect();
        for (block, k) in self.blocks.iter().zip(&self.element_stiffness) {
            for (a, &da) in block.iter().enumerate() {
                r[da] += block
                    .iter()
                    .enumerate()
                    .map(|(b, &db)| k[(a, b)] * u_full[db])
                    .sum::<f64>();
            }
        }
        r
    }

    /// `M_full v` in the full space (elements and point masses, before constraints).
    pub fn full_mass_times(&self, v_full: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; v_full.len()];
        for (block, m) in self.blocks.iter().zip(&self.element_mass) {
            for (a, &da) in block.iter().enumerate() {
                out[da] += block
                    .iter()
                    .enumerate()
                    .map(|(b, &db)| m[(a, b)] * v_full[db])
                    .sum::<f64>();
            }
        }
        let n_elements = self.element_mass.len();
        for (block, m) in self.blocks[n_elements..]
            .iter()
            .zip(&self.point_mass_blocks)
        {
            for (a, &da) in block.iter().enumerate() {
                out[da] += m[(a, a)] * v_full[da];
            }
        }
        out
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

/// What one load case produced.
#[derive(Debug, Clone)]
pub enum CaseSolution {
    Static(StaticSolution),
    Modal(ModalSolution),
    Transient(TransientSolution),
}

/// One load case's title and solution.
#[derive(Debug, Clone)]
pub struct CaseResult {
    pub title: String,
    pub solution: CaseSolution,
}

/// Runs the model's load cases in order. The stiffness is factored at most once and
/// shared by the static, modal and modal-superposition cases (and the quasi-static
/// initial velocity); a transient case starts from the displacement of a static case run
/// immediately before it (see [`transient`]); direct transient cases share one stepper,
/// refactored only when the scheme or `dt` changes.
pub fn run(model: &Model) -> Result<Vec<CaseResult>, SolveError> {
    run_with(model, &transient::RunOptions::default())
}

/// [`run`] with reporting and limits ([`transient::RunOptions`]).
pub fn run_with(
    model: &Model,
    options: &transient::RunOptions,
) -> Result<Vec<CaseResult>, SolveError> {
    if model.nodes.is_empty() {
        return Err(SolveError::BadInput {
            what: "the model has no nodes (COORDINATES); expected a structure to solve".into(),
        });
    }
    if model.load_cases.is_empty() {
        return Err(SolveError::BadInput {
            what: "the deck has no load case (an analysis after END OPTION); expected at \
                   least one static, modal or transient case"
                .into(),
        });
    }
    let system = System::new(model)?;
    let mut factor: Option<Cholesky> = None;
    let mut context = transient::Context::default();
    context.options = options.clone();
    let mut out: Vec<CaseResult> = Vec::with_capacity(model.load_cases.len());
    for case in &model.load_cases {
        let solution = match &case.analysis {
            Analysis::Static { time, .. } => {
                let chol = match &mut factor {
                    Some(c) => c,
                    None => factor.insert(system.factor_stiffness()?),
                };
                CaseSolution::Static(static_analysis::solve(&system, chol, case, *time)?)
            }
            Analysis::Modal { modes } => {
                let chol = match &mut factor {
                    Some(c) => c,
                    None => factor.insert(system.factor_stiffness()?),
                };
                CaseSolution::Modal(modal::solve(&system, chol, &case.title, *modes as usize)?)
            }
            Analysis::Transient { method, .. } => {
                let chol = if transient::needs_stiffness_factor(model, method) {
                    Some(match &mut factor {
                        Some(c) => &*c,
                        None => &*factor.insert(system.factor_stiffness()?),
                    })
                } else {
                    None
                };
                let start = match out.last() {
                    Some(CaseResult {
                        title,
                        solution: CaseSolution::Static(solution),
                    }) => Some(transient::StaticStart { title, solution }),
                    _ => None,
                };
                CaseSolution::Transient(transient::solve(&system, &mut context, chol, case, start)?)
            }
        };
        out.push(CaseResult {
            title: case.title.clone(),
            solution,
        });
    }
    Ok(out)
}

/// Small models for the unit tests of the engine's modules.
#[cfg(test)]
pub(crate) mod test_support {
    use crate::model::*;

    /// Steel beams between consecutive `nodes` pairs given in `elements`.
    pub fn model(nodes: &[(NodeId, [f64; 3])], elements: &[[NodeId; 2]]) -> Model {
        let ids: Vec<ElementId> = (1..=elements.len() as ElementId).collect();
        Model {
            title: "unit".to_string(),
            element_types: vec![ElementType::Beam98],
            lumped_mass: false,
            nodes: nodes.iter().map(|&(id, xyz)| Node { id, xyz }).collect(),
            elements: elements
                .iter()
                .zip(&ids)
                .map(|(&nodes, &id)| Element {
                    id,
                    kind: ElementType::Beam98,
                    nodes,
                })
                .collect(),
            node_sets: Vec::new(),
            element_sets: Vec::new(),
            materials: vec![Material {
                name: "steel".to_string(),
                youngs_modulus: 2.1e5,
                poisson: 0.3,
                density: 7.85e-9,
                elements: ids.clone(),
            }],
            geometries: vec![Geometry {
                name: "wire".to_string(),
                section: Section::SolidCircle { diameter: 2.0 },
                orientation: [0.3, 0.2, 1.0],
                elements: ids,
            }],
            damping: Vec::new(),
            point_masses: Vec::new(),
            rigid_ties: Vec::new(),
            fixed_disp: Vec::new(),
            point_loads: Vec::new(),
            tables: Vec::new(),
            initial_velocities: Vec::new(),
            outputs: Vec::new(),
            load_cases: Vec::new(),
            point_laws: Vec::new(),
        }
    }

    /// A bent three-element frame 1-2-3-4, node 1 clamped, node 4 tied to reference 10
    /// (all DOFs), with reference 10 prescribed to a non-zero u_z.
    /// [`tied_frame`] with a weight (point mass with rotary inertia) on node 10 and
    /// Rayleigh damping on elements 1-3 that does not name the weight's node.
    pub fn damped_tied_frame(alpha: f64, beta: f64) -> Model {
        let mut model = tied_frame();
        model.point_masses.push(PointMass {
            node: 10,
            mass: 5e-3,
            inertia: [1.0, 2.0, 3.0],
        });
        model.damping.push(Damping {
            alpha,
            beta,
            elements: vec![1, 2, 3],
            mass_nodes: Vec::new(),
        });
        model
    }

    pub fn tied_frame() -> Model {
        let mut m = model(
            &[
                (1, [0.0, 0.0, 0.0]),
                (2, [10.0, 0.0, 0.0]),
                (3, [10.0, 8.0, 1.0]),
                (4, [12.0, 9.0, 7.0]),
                (10, [15.0, 5.0, 9.0]),
            ],
            &[[1, 2], [2, 3], [3, 4]],
        );
        m.fixed_disp.push(FixedDisp {
            dofs: (1..=6).map(|d| (d, 0.0)).collect(),
            nodes: vec![1],
        });
        m.fixed_disp.push(FixedDisp {
            dofs: vec![(3, 0.25), (4, 0.0)],
            nodes: vec![10],
        });
        m.rigid_ties.push(RigidTie {
            name: "top".to_string(),
            reference: 10,
            dofs: vec![1, 2, 3, 4, 5, 6],
            tied: vec![4],
        });
        m
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::{damped_tied_frame, tied_frame};
    use super::*;
    use crate::linalg::sym_upper_matvec;
    use crate::model::{PointMass, Table};

    fn quadratic(a: &SparseColMat<usize, f64>, x: &[f64]) -> f64 {
        let mut y = vec![0.0; x.len()];
        sym_upper_matvec(a.as_ref(), x, 1.0, &mut y);
        x.iter().zip(&y).map(|(p, q)| p * q).sum()
    }

    /// C = alpha M_e + beta K_e on the damped elements; the point mass gets alpha only
    /// when its node is named.
    #[test]
    fn rayleigh_damping_skips_unnamed_point_masses() {
        let (alpha, beta) = (0.8, 1.2e-4);
        let mut model = damped_tied_frame(alpha, beta);
        let x: Vec<f64> = (0..System::new(&model).unwrap().dim())
            .map(|i| (0.7 * i as f64).sin())
            .collect();
        let system = System::new(&model).unwrap();
        let mut bare = model.clone();
        bare.point_masses.clear();
        let bare_system = System::new(&bare).unwrap();
        let (m, m_bare, k) = (
            quadratic(&system.mass, &x),
            quadratic(&bare_system.mass, &x),
            quadratic(&system.stiffness, &x),
        );
        assert!(m > m_bare * 1.01, "the point mass moves with x");
        let c = quadratic(&system.damping, &x);
        let expected = alpha * m_bare + beta * k;
        assert!(
            (c - expected).abs() < 1e-12 * expected.abs(),
            "{c} vs {expected}"
        );
        model.damping[0].mass_nodes = vec![10];
        let named = System::new(&model).unwrap();
        let c = quadratic(&named.damping, &x);
        let expected = alpha * m + beta * k;
        assert!(
            (c - expected).abs() < 1e-12 * expected.abs(),
            "{c} vs {expected}"
        );
        // Naming a node without a point mass is an error, not a silent no-op.
        model.damping[0].mass_nodes = vec![2];
        assert!(matches!(
            System::new(&model),
            Err(SolveError::BadInput { .. })
        ));
    }

    /// Degenerate models give results or errors, never panics.
    #[test]
    fn fully_fixed_and_empty_models_do_not_panic() {
        let mut model = tied_frame();
        model.fixed_disp.push(crate::model::FixedDisp {
            dofs: (1..=6).map(|d| (d, 0.0)).collect(),
            nodes: vec![2, 3],
        });
        model.fixed_disp.push(crate::model::FixedDisp {
            dofs: [1, 2, 5, 6].map(|d| (d, 0.0)).to_vec(),
            nodes: vec![10],
        });
        for analysis in [
            Analysis::Static {
                steps: 1,
                time: 1.0,
            },
            Analysis::Modal { modes: 1 },
        ] {
            model.load_cases = vec![crate::model::LoadCase {
                title: "case".to_string(),
                analysis,
                point_loads: Vec::new(),
            }];
            match run(&model) {
                Ok(cases) => assert!(matches!(cases[0].solution, CaseSolution::Static(_))),
                Err(e) => assert!(
                    matches!(e, SolveError::TooManyModes { available: 0, .. }),
                    "{e}"
                ),
            }
        }
        let mut empty = test_support::model(&[], &[]);
        empty.load_cases = model.load_cases.clone();
        assert!(run(&empty).is_err());
        empty.load_cases[0].analysis = Analysis::Static {
            steps: 1,
            time: 1.0,
        };
        // A model without nodes is nonsense, refused (issue 9), not an empty result.
        let e = run(&empty).unwrap_err().to_string();
        assert!(e.contains("no nodes"), "{e}");
        let mut no_case = model.clone();
        no_case.load_cases.clear();
        assert!(run(&no_case)
            .unwrap_err()
            .to_string()
            .contains("no load case"));
    }

    /// Massless beams with one point mass carry three modes; a fourth is an error that
    /// says so, not an infinite frequency.
    #[test]
    fn more_modes_than_the_mass_carries_is_an_error() {
        let mut model = test_support::model(
            &[
                (1, [0.0; 3]),
                (2, [10.0, 0.0, 0.0]),
                (3, [20.0, 1.0, 0.0]),
                (4, [30.0, 0.0, 2.0]),
            ],
            &[[1, 2], [2, 3], [3, 4]],
        );
        model.materials[0].density = 0.0;
        model.fixed_disp.push(crate::model::FixedDisp {
            dofs: (1..=6).map(|d| (d, 0.0)).collect(),
            nodes: vec![1],
        });
        model.point_masses.push(PointMass {
            node: 4,
            mass: 1e-3,
            inertia: [0.0; 3],
        });
        let system = System::new(&model).unwrap();
        let factor = system.factor_stiffness().unwrap();
        let three = modal::solve(&system, &factor, "three", 3).unwrap();
        let total: f64 = three
            .modes
            .iter()
            .map(|m| m.effective_mass.iter().sum::<f64>())
            .sum();
        assert!(
            (total - 3e-3).abs() < 1e-12,
            "all the mass in three modes: {total}"
        );
        match modal::solve(&system, &factor, "four", 4) {
            Err(SolveError::BadInput { what }) => assert!(what.contains("no mass"), "{what}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn tables_interpolate_and_hold_their_ends() {
        let mut model = tied_frame();
        model.tables.push(Table {
            name: "pulse".to_string(),
            points: vec![(0.0, 0.0), (0.001, 1.0), (0.002, 0.0)],
        });
        let f = |t| table_factor(&model, "PULSE", t).unwrap();
        assert_eq!(f(-1.0), 0.0);
        assert!((f(0.0005) - 0.5).abs() < 1e-12);
        assert_eq!(f(0.001), 1.0);
        assert!((f(0.0015) - 0.5).abs() < 1e-12);
        assert_eq!(f(5.0), 0.0);
        assert!(matches!(
            table_factor(&model, "nope", 0.0),
            Err(SolveError::UnknownTable { .. })
        ));
    }

    #[test]
    fn modal_requests_beyond_the_model_are_errors() {
        let mut model = tied_frame();
        model.load_cases.push(crate::model::LoadCase {
            title: "too many".to_string(),
            analysis: Analysis::Modal { modes: 1000 },
            point_loads: Vec::new(),
        });
        match run(&model) {
            Err(SolveError::TooManyModes {
                requested,
                available,
                ..
            }) => {
                assert_eq!(requested, 1000);
                assert_eq!(available, System::new(&model).unwrap().dim());
            }
            other => panic!("{other:?}"),
        }
    }

    /// Lowest omega^2 of `K phi = omega^2 M phi` by a dense reference (nalgebra):
    /// `L_M^-1 K L_M^-T` with the Cholesky factor of M.
    fn dense_omega2(system: &System) -> Vec<f64> {
        let n = system.dim();
        let dense = |a: &SparseColMat<usize, f64>| {
            let mut out = nalgebra::DMatrix::<f64>::zeros(n, n);
            for j in 0..n {
                for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                    out[(i, j)] += v;
                    if i != j {
                        out[(j, i)] += v;
                    }
                }
            }
            out
        };
        let (k, m) = (dense(&system.stiffness), dense(&system.mass));
        let l_inv = m.clone().cholesky().unwrap().l().try_inverse().unwrap();
        let a = &l_inv * &k * l_inv.transpose();
        let eigen = ((&a + a.transpose()) * 0.5).symmetric_eigen();
        // Rayleigh quotients of the back-transformed vectors: the ill-conditioned L_M^-1
        // spoils the eigenvalues at 1e-8, the quotient is second order in that error.
        let mut w: Vec<f64> = eigen
            .eigenvectors
            .column_iter()
            .map(|y| {
                let x = l_inv.transpose() * y;
                (x.transpose() * &k * &x)[0] / (x.transpose() * &m * &x)[0]
            })
            .collect();
        w.sort_by(f64::total_cmp);
        w
    }

    /// A 3-element chain has fewer DOFs than faer's Lanczos subspace, so the dense path
    /// runs; a 40-element chain goes through Lanczos. Both must match a dense
    /// generalised eigensolution (1e-9 relative: Lanczos locks residuals at 1e-12 of
    /// the top eigenvalue) and give M-orthonormal modes.
    #[test]
    fn dense_and_lanczos_paths_match_a_dense_reference() {
        let n = 40;
        let nodes: Vec<(NodeId, [f64; 3])> = (0..=n)
            .map(|i| {
                (
                    i as NodeId + 1,
                    [i as f64 * 3.0, (i as f64 * 0.3).sin(), 0.0],
                )
            })
            .collect();
        let elements: Vec<[NodeId; 2]> = (1..=n as NodeId).map(|i| [i, i + 1]).collect();
        for (count, modes) in [(3, 5), (n, 12)] {
            let mut model = test_support::model(&nodes[..=count], &elements[..count]);
            model.fixed_disp.push(crate::model::FixedDisp {
                dofs: (1..=6).map(|d| (d, 0.0)).collect(),
                nodes: vec![1],
            });
            let system = System::new(&model).unwrap();
            let factor = system.factor_stiffness().unwrap();
            let sol = modal::solve(&system, &factor, "modes", modes).unwrap();
            let reference = dense_omega2(&system);
            assert!(sol.orthonormality_error < 1e-10);
            for (mode, w2) in sol.modes.iter().zip(&reference) {
                assert!(
                    (mode.omega_squared - w2).abs() < 1e-9 * w2,
                    "{count}: {} vs {w2}",
                    mode.omega_squared
                );
                assert!(mode.relative_residual < 1e-8, "{}", mode.relative_residual);
            }
        }
    }
}
