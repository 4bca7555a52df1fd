//! A pantograph-catenary model as a deck: a catenary spec and a pantograph spec -> one
//! coil [`Model`] with its static state (`coil-mesh catenary SPEC.json -o DECK`;
//! docs/catenary.md, "The catenary spec").
//!
//! # Model
//! Planar (x along the track, z up), two DOFs per wire node (u_z and theta_y; u_x, u_y,
//! theta_x, theta_z fixed): the contact and messenger wires are straight lines of type-52
//! beams at z = 0 and z = system height, each under `BEAM TENSION` (the taut string
//! `rho w_tt = N w_xx` stiffened by EI). Both wires share one grid in x: every span is cut
//! at its droppers, each piece into equal elements no longer than `element_length_m`.
//! Droppers are `TENSION LINK`s (contact-wire node a, messenger node b, u_z); steady arms
//! and messenger supports are vertical bars (axial stiffness `EA / L = k`, L = 1 m) to a
//! ground node, with point masses on the wire nodes; the wires' ends are pinned at the
//! first and last support. The pantograph is a chain of lumped stages from the head down
//! (stage i's spring and damper join mass i to mass i+1, the last to the ground), on bars
//! (springs) and Rayleigh `beta = c / k` on each bar (its dashpot), the static uplift force
//! on the lowest mass; the head presses on the contact wire by a `MOVING CONTACT`. A
//! stage given as matrices ([`StageMatrix`], a reduced spring model) gets no bar and no
//! dashpot but one `DMIG` over its two ends' u_z and its modal coordinates (DOF 1 of
//! extra nodes, the other DOFs held).
//! Gravity acts on the catenary (lumped nodal weights `q h / 2` per element end and the
//! point masses' weights), not on the pantograph, whose uplift force is the net static
//! force of the standard's models.
//!
//! # Static state (the classical construction, exact for the linear model)
//! 1. The contact wire's heights are prescribed: 0 at the supports, the presag parabola
//!    `-presag 4 xi (1 - xi)` (`xi` the position in the span) at the droppers. The contact
//!    wire alone (its weight, its clamps, the steady arms' masses) with those heights
//!    prescribed gives, as reactions, each dropper's force `F_j` and each steady arm's.
//! 2. The messenger alone, loaded by its weight, its clamps and the dropper forces, its
//!    supports at 0, gives the messenger's deflection at each dropper and the support
//!    forces.
//! 3. Dropper lengths: `slack_j = u_m,j - u_c,j - F_j / k` (a pretensioned link); the
//!    steady arms' and messenger supports' ground nodes are set at `R / k` (the hinge
//!    height that holds the wire at its support height under its static force).
//! 4. The full catenary's STATIC case is solved; where the contact wire misses a
//!    prescribed height by more than [`PRESAG_TOLERANCE_MM`], the dropper lengths are
//!    corrected by the miss and the case solved again (at most [`MAX_PRESAG_ITERATIONS`]).
//!    The linear model meets the heights after step 3 up to round-off.
//!
//! The deck's first load case is the STATIC case of the whole model with the head pressed
//! on the wire at the start (the pinned first support by default, so the pantograph does
//! not move the catenary there); the transient (`NEWMARK`) starts from it.
//!
//! # Units
//! Spec fields carry their units in the name (`_m`, `_mm`, `_kg`, `_n`, `_n_m`,
//! `_n_s_m`, `_km_h`, `_s`); the deck is in mm, N, t, s.
//!
//! # Numbering (stable)
//! Contact-wire nodes and elements from [`CONTACT_BASE`] (+ grid index), messenger from
//! [`MESSENGER_BASE`], steady-arm ground nodes and bars from [`STEADY_ARM_BASE`] (+ support
//! index), messenger-support ground nodes and bars from [`SUPPORT_BASE`], the pantograph's
//! masses from [`PANTOGRAPH_BASE`] (the head first; the ground node last), its bars from
//! [`PANTOGRAPH_BASE`] (stage index), a stage matrix's modal nodes from
//! [`PANTOGRAPH_MODAL_BASE`] (+ 1000 stage index + mode index).

mod spec;
#[cfg(test)]
mod tests;

pub use spec::*;

use coil_mesher::SpecError;
use coil_solver::analysis::{run, CaseSolution, StaticSolution};
use coil_solver::model::{
    Analysis, BeamTension, Damping, Dashpot, Element, ElementType, FixedDisp, Geometry, Integrator,
    LoadCase, Material, MatrixElement, Model, ModelParts, MovingContact, Node, NodeId, NodeSet,
    OutputRequest, PointLoad, PointMass, Quantity, Section, TensionLink, TransientMethod,
};

/// Length of every spring bar (mm).
const BAR_MM: f64 = 1000.0;
/// Section of the wires' beams (mm^2, mm^4): E and the density carry EI and rho A.
const WIRE_AREA: f64 = 100.0;
const WIRE_INERTIA: f64 = 1000.0;

/// The wires' common grid along x (mm), with the droppers' and supports' grid indices.
struct Grid {
    x: Vec<f64>,
    droppers: Vec<usize>,
    supports: Vec<usize>,
}

impl Grid {
    fn new(spec: &CatenarySpec) -> Grid {
        let span = spec.span_length_m * 1e3;
        let h = spec.element_length_m * 1e3;
        let mut keys = vec![0.0];
        keys.extend(spec.droppers.positions_m.iter().map(|x| x * 1e3));
        keys.push(span);
        let mut grid = Grid {
            x: vec![0.0],
            droppers: Vec::new(),
            supports: vec![0],
        };
        for s in 0..spec.spans {
            let x0 = f64::from(s) * span;
            for (k, pair) in keys.windows(2).enumerate() {
                let (a, b) = (pair[0], pair[1]);
                let n = ((b - a) / h - 1e-9).ceil().max(1.0) as usize;
                for i in 1..=n {
                    grid.x.push(x0 + a + (b - a) * i as f64 / n as f64);
                }
                if k + 2 < keys.len() {
                    grid.droppers.push(grid.x.len() - 1);
                }
            }
            grid.supports.push(grid.x.len() - 1);
        }
        grid
    }
}

fn kg_to_t(kg: f64) -> f64 {
    kg * 1e-3
}

fn n_m_to_n_mm(k: f64) -> f64 {
    k * 1e-3
}

/// Which parts of the catenary a model holds.
#[derive(Clone, Copy, PartialEq)]
enum Part {
    /// The contact wire alone, its heights prescribed at the droppers and supports.
    ContactWire,
    /// The messenger alone, loaded by the dropper forces, its supports prescribed.
    Messenger,
    /// Both wires with droppers, steady arms and supports.
    Catenary,
}

/// What the construction has found so far: dropper forces and slack, support offsets.
struct Setting {
    slack_mm: Vec<f64>,
    dropper_force_n: Vec<f64>,
    steady_arm_offset_mm: Vec<f64>,
    support_offset_mm: Vec<f64>,
}

/// Parts shared by every model of the construction, in ModelParts's fields.
#[derive(Default)]
struct Pieces {
    nodes: Vec<Node>,
    elements: Vec<Element>,
    materials: Vec<Material>,
    geometries: Vec<Geometry>,
    damping: Vec<Damping>,
    point_masses: Vec<PointMass>,
    fixed_disp: Vec<FixedDisp>,
    point_loads: Vec<PointLoad>,
    beam_tensions: Vec<BeamTension>,
    tension_links: Vec<TensionLink>,
    node_sets: Vec<NodeSet>,
    dashpots: Vec<Dashpot>,
    matrix_elements: Vec<MatrixElement>,
}

impl Pieces {
    /// A wire along the grid at height `z` (mm), node and element ids from `base`.
    fn wire(&mut self, grid: &Grid, base: u32, z: f64, wire: &WireSpec, name: &str, gravity: f64) {
        let ids: Vec<u32> = (0..grid.x.len() as u32).map(|i| base + i).collect();
        for (&id, &x) in ids.iter().zip(&grid.x) {
            self.nodes.push(Node {
                id,
                xyz: [x, 0.0, z],
            });
        }
        let elements: Vec<u32> = (0..ids.len() as u32 - 1).map(|i| base + i).collect();
        for (i, &e) in elements.iter().enumerate() {
            self.elements.push(Element {
                id: e,
                kind: ElementType::Beam52,
                nodes: [ids[i], ids[i + 1]],
            });
        }
        let rho_a = kg_to_t(wire.mass_kg_m) * 1e-3; // t/mm
        self.materials.push(Material {
            name: name.into(),
            youngs_modulus: wire.ei_n_m2 * 1e6 / WIRE_INERTIA,
            poisson: 0.3,
            density: rho_a / WIRE_AREA,
            elements: elements.clone(),
        });
        self.geometries.push(Geometry {
            name: name.into(),
            section: Section::General {
                area: WIRE_AREA,
                iyy: WIRE_INERTIA,
                izz: WIRE_INERTIA,
                torsion: 2.0 * WIRE_INERTIA,
                shear_coefficient: 0.0,
            },
            orientation: [0.0, 0.0, 1.0],
            elements: elements.clone(),
        });
        self.beam_tensions.push(BeamTension {
            force: wire.tension_n,
            elements,
        });
        // Planar: u_z and theta_y free; the ends pinned.
        self.fixed_disp.push(FixedDisp {
            dofs: vec![(1, 0.0), (2, 0.0), (4, 0.0), (6, 0.0)],
            nodes: ids.clone(),
        });
        self.fixed_disp.push(FixedDisp {
            dofs: vec![(3, 0.0)],
            nodes: vec![ids[0], ids[ids.len() - 1]],
        });
        // Lumped weights q h / 2 at each element end.
        let q = wire.mass_kg_m * gravity * 1e-3; // N/mm
        let mut w = vec![0.0; ids.len()];
        for i in 0..ids.len() - 1 {
            let half = 0.5 * q * (grid.x[i + 1] - grid.x[i]);
            w[i] += half;
            w[i + 1] += half;
        }
        for (&id, &wi) in ids.iter().zip(&w) {
            self.point_loads.push(PointLoad {
                dofs: vec![(3, -wi)],
                nodes: vec![id],
                table: None,
            });
        }
        self.node_sets.push(NodeSet {
            name: name.into(),
            nodes: ids,
        });
    }

    /// A point mass with its weight.
    fn mass(&mut self, node: NodeId, kg: f64, gravity: f64) {
        if kg > 0.0 {
            self.point_masses.push(PointMass {
                node,
                mass: kg_to_t(kg),
                inertia: [0.0; 3],
            });
            if gravity > 0.0 {
                self.point_loads.push(PointLoad {
                    dofs: vec![(3, -kg * gravity)],
                    nodes: vec![node],
                    table: None,
                });
            }
        }
    }

    /// A spring bar of axial stiffness `k` (N/mm) between two nodes `BAR_MM` apart: EA / L
    /// = k with A = 1 mm^2; I = 1e-3 mm^4 leaves its bending negligible beside the wires'
    /// (4 E I / L below 1e-3 of theirs). No mass.
    fn bar(&mut self, id: u32, nodes: [NodeId; 2], k: f64, name: String) {
        self.elements.push(Element {
            id,
            kind: ElementType::Beam52,
            nodes,
        });
        self.materials.push(Material {
            name: name.clone(),
            youngs_modulus: k * BAR_MM,
            poisson: 0.3,
            density: 0.0,
            elements: vec![id],
        });
        self.geometries.push(Geometry {
            name,
            section: Section::General {
                area: 1.0,
                iyy: 1e-3,
                izz: 1e-3,
                torsion: 2e-3,
                shear_coefficient: 0.0,
            },
            orientation: [1.0, 0.0, 0.0],
            elements: vec![id],
        });
    }

    /// Stage `stage`'s matrix on the u_z of `ends` (lower, upper) and its modal
    /// coordinates on DOF 1 of new nodes from [`PANTOGRAPH_MODAL_BASE`] (the other DOFs
    /// held), as one matrix element `pantograph_stage_<stage + 1>`.
    fn stage_matrix(&mut self, stage: u32, ends: [NodeId; 2], matrix: &StageMatrix) {
        let n = matrix.order().unwrap_or(2);
        let modal: Vec<NodeId> = (0..n as u32 - 2)
            .map(|j| PANTOGRAPH_MODAL_BASE + 1000 * stage + j)
            .collect();
        for (j, &id) in modal.iter().enumerate() {
            self.nodes.push(Node {
                id,
                xyz: [
                    -5000.0,
                    BAR_MM * (j + 1) as f64,
                    -BAR_MM * (f64::from(stage) + 0.5),
                ],
            });
        }
        if !modal.is_empty() {
            self.fixed_disp.push(FixedDisp {
                dofs: (2..=6).map(|d| (d, 0.0)).collect(),
                nodes: modal.clone(),
            });
        }
        let mut dofs = vec![(ends[0], 3), (ends[1], 3)];
        dofs.extend(modal.iter().map(|&id| (id, 1)));
        self.matrix_elements.push(MatrixElement {
            name: format!("pantograph_stage_{}", stage + 1),
            dofs,
            stiffness: matrix.stiffness.clone(),
            mass: matrix.mass.clone(),
            damping: matrix.damping.clone().unwrap_or_default(),
        });
    }

    /// A vertical spring bar of `k` (N/mm) from `node` at `xyz` to a ground node `ground`
    /// `BAR_MM` above (`up`) or below it, the ground at `offset` (mm) along z.
    #[allow(clippy::too_many_arguments)]
    fn spring(
        &mut self,
        id: u32,
        node: NodeId,
        xyz: [f64; 3],
        ground: NodeId,
        up: bool,
        k: f64,
        offset: f64,
        name: String,
    ) {
        let dz = if up { BAR_MM } else { -BAR_MM };
        self.nodes.push(Node {
            id: ground,
            xyz: [xyz[0], xyz[1], xyz[2] + dz],
        });
        self.bar(id, [node, ground], k, name);
        self.fixed_disp.push(FixedDisp {
            dofs: vec![
                (1, 0.0),
                (2, 0.0),
                (3, offset),
                (4, 0.0),
                (5, 0.0),
                (6, 0.0),
            ],
            nodes: vec![ground],
        });
    }
}

/// The presag parabola at `x` mm (mm, up positive: <= 0).
fn target_height(spec: &CatenarySpec, x_mm: f64) -> f64 {
    let span = spec.span_length_m * 1e3;
    let xi = (x_mm / span).fract();
    -spec.presag_mm * 4.0 * xi * (1.0 - xi)
}

/// The catenary's pieces (no pantograph) for `part`.
fn catenary_pieces(spec: &CatenarySpec, grid: &Grid, part: Part, setting: &Setting) -> Pieces {
    let g = spec.gravity_m_s2;
    let mut p = Pieces::default();
    let height = spec.system_height_m * 1e3;
    let interior = &grid.supports[1..grid.supports.len() - 1];
    // Each wire with its clamps and support masses; the contact wire is left out of the
    // messenger's model and the messenger out of the contact wire's.
    let wires = [
        (
            Part::Messenger,
            CONTACT_BASE,
            0.0,
            &spec.contact_wire,
            "contact_wire",
            spec.droppers.contact_clamp_mass_kg,
            spec.steady_arm.mass_kg,
        ),
        (
            Part::ContactWire,
            MESSENGER_BASE,
            height,
            &spec.messenger_wire,
            "messenger",
            spec.droppers.messenger_clamp_mass_kg,
            spec.messenger_support.mass_kg,
        ),
    ];
    for (without, base, z, wire, name, clamp_kg, support_kg) in wires {
        if part == without {
            continue;
        }
        p.wire(grid, base, z, wire, name, g);
        for &i in &grid.droppers {
            p.mass(base + i as u32, clamp_kg, g);
        }
        for &i in interior {
            p.mass(base + i as u32, support_kg, g);
        }
    }
    match part {
        Part::ContactWire => {
            let dofs: Vec<(u32, f64)> = grid
                .droppers
                .iter()
                .map(|&i| (CONTACT_BASE + i as u32, target_height(spec, grid.x[i])))
                .chain(interior.iter().map(|&i| (CONTACT_BASE + i as u32, 0.0)))
                .collect();
            for (node, z) in dofs {
                p.fixed_disp.push(FixedDisp {
                    dofs: vec![(3, z)],
                    nodes: vec![node],
                });
            }
        }
        Part::Messenger => {
            for (&i, &f) in grid.droppers.iter().zip(&setting.dropper_force_n) {
                p.point_loads.push(PointLoad {
                    dofs: vec![(3, -f)],
                    nodes: vec![MESSENGER_BASE + i as u32],
                    table: None,
                });
            }
            for &i in interior {
                p.fixed_disp.push(FixedDisp {
                    dofs: vec![(3, 0.0)],
                    nodes: vec![MESSENGER_BASE + i as u32],
                });
            }
        }
        Part::Catenary => {
            for (j, &i) in grid.droppers.iter().enumerate() {
                p.tension_links.push(TensionLink {
                    nodes: [CONTACT_BASE + i as u32, MESSENGER_BASE + i as u32],
                    dof: 3,
                    stiffness: n_m_to_n_mm(spec.droppers.stiffness_n_m),
                    slack: setting.slack_mm[j],
                });
            }
            for (s, &i) in interior.iter().enumerate() {
                let x = grid.x[i];
                p.spring(
                    STEADY_ARM_BASE + s as u32,
                    CONTACT_BASE + i as u32,
                    [x, 0.0, 0.0],
                    STEADY_ARM_BASE + s as u32,
                    false,
                    n_m_to_n_mm(spec.steady_arm.stiffness_n_m),
                    setting.steady_arm_offset_mm[s],
                    format!("steady_arm_{}", s + 1),
                );
                p.spring(
                    SUPPORT_BASE + s as u32,
                    MESSENGER_BASE + i as u32,
                    [x, 0.0, height],
                    SUPPORT_BASE + s as u32,
                    true,
                    n_m_to_n_mm(spec.messenger_support.stiffness_n_m),
                    setting.support_offset_mm[s],
                    format!("messenger_support_{}", s + 1),
                );
            }
        }
    }
    // Damping of the wires and of the catenary's point masses (Rayleigh).
    let (alpha, beta) = spec.damping.rayleigh();
    if alpha > 0.0 || beta > 0.0 {
        let wires: Vec<u32> = p
            .elements
            .iter()
            .filter(|e| e.id < STEADY_ARM_BASE)
            .map(|e| e.id)
            .collect();
        let mut mass_nodes: Vec<u32> = if alpha > 0.0 {
            p.point_masses.iter().map(|m| m.node).collect()
        } else {
            Vec::new()
        };
        mass_nodes.sort_unstable();
        p.damping.push(Damping {
            alpha,
            beta,
            elements: wires,
            mass_nodes,
        });
    }
    p
}

fn parts(
    title: String,
    p: Pieces,
    load_cases: Vec<LoadCase>,
    outputs: Vec<OutputRequest>,
    contacts: Vec<MovingContact>,
) -> ModelParts {
    let mut nodes = p.nodes;
    nodes.sort_by_key(|n| n.id);
    let mut elements = p.elements;
    elements.sort_by_key(|e| e.id);
    let mut point_masses = p.point_masses;
    point_masses.sort_by_key(|m| m.node);
    ModelParts {
        title,
        element_types: vec![ElementType::Beam52],
        lumped_mass: false,
        nodes,
        elements,
        node_sets: p.node_sets,
        element_sets: Vec::new(),
        materials: p.materials,
        geometries: p.geometries,
        damping: p.damping,
        point_masses,
        rigid_ties: Vec::new(),
        fixed_disp: p.fixed_disp,
        point_loads: p.point_loads,
        tables: Vec::new(),
        initial_velocities: Vec::new(),
        outputs,
        load_cases,
        point_laws: Vec::new(),
        dashpots: p.dashpots,
        modal_damping: Default::default(),
        beam_tensions: p.beam_tensions,
        tension_links: p.tension_links,
        moving_contacts: contacts,
        matrix_elements: p.matrix_elements,
    }
}

fn static_case(title: &str) -> LoadCase {
    LoadCase {
        title: title.into(),
        analysis: Analysis::Static {
            steps: 1,
            time: 1.0,
        },
        point_loads: Vec::new(),
    }
}

fn model_of(parts: ModelParts) -> Result<Model, CatenaryError> {
    Model::try_new(parts).map_err(|e| {
        if let coil_solver::model::Site::MatrixElement(_) = e.site {
            // The catenary's only matrix elements are the pantograph's stage matrices.
            return CatenaryError::Spec(SpecError {
                field: "pantograph.stages.matrix",
                value: e.to_string(),
                expected: "symmetric matrices, the mass and damping positive semi-definite",
            });
        }
        CatenaryError::State(format!(
            "the mesh is not a valid model ({e}); expected a spec whose mesh is one"
        ))
    })
}

fn solve_static(model: &Model, stage: &'static str) -> Result<StaticSolution, CatenaryError> {
    let results = run(model).map_err(|source| CatenaryError::Solve {
        stage,
        source: Box::new(source),
    })?;
    match results.into_iter().next().map(|r| r.solution) {
        Some(CaseSolution::Static(s)) => Ok(s),
        _ => Err(CatenaryError::State(format!("{stage}: no static solution"))),
    }
}

fn reaction(solution: &StaticSolution, node: NodeId) -> f64 {
    solution
        .reactions
        .iter()
        .filter(|r| r.node == node && r.dof == 3)
        .map(|r| r.value)
        .sum()
}

fn uz(solution: &StaticSolution, model: &Model, node: NodeId) -> f64 {
    solution
        .node_displacement(model, node)
        .map_or(f64::NAN, |u| u[2])
}

/// The static solution of `part` of the catenary (a model of its own with one STATIC
/// case).
fn solve_part(
    spec: &CatenarySpec,
    grid: &Grid,
    part: Part,
    setting: &Setting,
) -> Result<(Model, StaticSolution), CatenaryError> {
    let (title, stage) = match part {
        Part::ContactWire => ("contact wire at its prescribed heights", "contact wire"),
        Part::Messenger => ("messenger under the dropper forces", "messenger"),
        Part::Catenary => ("catenary at rest", "catenary"),
    };
    let p = catenary_pieces(spec, grid, part, setting);
    let model = model_of(parts(
        title.into(),
        p,
        vec![static_case(title)],
        vec![],
        vec![],
    ))?;
    let solution = solve_static(&model, stage)?;
    Ok((model, solution))
}

/// The static state of the catenary alone (module doc, steps 1-4): dropper forces and
/// lengths, support offsets, and the full catenary's static check.
fn static_state(spec: &CatenarySpec, grid: &Grid) -> Result<(Setting, StaticState), CatenaryError> {
    let interior: Vec<usize> = grid.supports[1..grid.supports.len() - 1].to_vec();
    let n_d = grid.droppers.len();
    let mut setting = Setting {
        slack_mm: vec![0.0; n_d],
        dropper_force_n: vec![0.0; n_d],
        steady_arm_offset_mm: vec![0.0; interior.len()],
        support_offset_mm: vec![0.0; interior.len()],
    };
    // 1. The contact wire with its heights prescribed.
    let (_, sol) = solve_part(spec, grid, Part::ContactWire, &setting)?;
    let targets: Vec<f64> = grid
        .droppers
        .iter()
        .map(|&i| target_height(spec, grid.x[i]))
        .collect();
    for (j, &i) in grid.droppers.iter().enumerate() {
        let f = reaction(&sol, CONTACT_BASE + i as u32);
        if f <= 0.0 {
            return Err(CatenaryError::State(format!(
                "the dropper at {:.3} m would push the contact wire ({f:.2} N): a dropper \
                 only pulls; expected a presag the wire's weight can hang in (a smaller \
                 catenary.presag_mm)",
                grid.x[i] * 1e-3
            )));
        }
        setting.dropper_force_n[j] = f;
    }
    let k_sa = n_m_to_n_mm(spec.steady_arm.stiffness_n_m);
    let steady_arm_force: Vec<f64> = interior
        .iter()
        .map(|&i| reaction(&sol, CONTACT_BASE + i as u32))
        .collect();
    for (s, f) in steady_arm_force.iter().enumerate() {
        // The bar pulls the node up by k (u_ground - u_node), the node at 0.
        setting.steady_arm_offset_mm[s] = f / k_sa;
    }
    // 2. The messenger under the dropper forces.
    let (model, sol) = solve_part(spec, grid, Part::Messenger, &setting)?;
    let k_ms = n_m_to_n_mm(spec.messenger_support.stiffness_n_m);
    let support_force: Vec<f64> = interior
        .iter()
        .map(|&i| reaction(&sol, MESSENGER_BASE + i as u32))
        .collect();
    for (s, f) in support_force.iter().enumerate() {
        // The ground node is above: the bar pulls the node up by k (u_ground - u_node).
        setting.support_offset_mm[s] = f / k_ms;
    }
    // 3. Dropper lengths.
    let k_d = n_m_to_n_mm(spec.droppers.stiffness_n_m);
    for (j, &i) in grid.droppers.iter().enumerate() {
        let u_m = uz(&sol, &model, MESSENGER_BASE + i as u32);
        setting.slack_mm[j] = u_m - targets[j] - setting.dropper_force_n[j] / k_d;
    }
    // 4. The whole catenary, corrected until it meets the heights.
    let mut iterations = 0;
    loop {
        let (model, sol) = solve_part(spec, grid, Part::Catenary, &setting)?;
        let heights: Vec<f64> = grid
            .droppers
            .iter()
            .map(|&i| uz(&sol, &model, CONTACT_BASE + i as u32))
            .collect();
        let mut miss = heights
            .iter()
            .zip(&targets)
            .fold(0.0_f64, |m, (h, t)| m.max((h - t).abs()));
        for &i in &interior {
            miss = miss.max(uz(&sol, &model, CONTACT_BASE + i as u32).abs());
        }
        if miss <= PRESAG_TOLERANCE_MM || iterations == MAX_PRESAG_ITERATIONS {
            if miss > PRESAG_TOLERANCE_MM || !miss.is_finite() {
                return Err(CatenaryError::State(format!(
                    "the contact wire misses its prescribed heights by {miss:.3e} mm after \
                     {iterations} dropper-length corrections; expected at most \
                     {PRESAG_TOLERANCE_MM} mm (a slack dropper? check the presag and the \
                     dropper stiffness)"
                )));
            }
            let weight = model
                .point_loads()
                .iter()
                .flat_map(|l| {
                    l.dofs.iter().map(move |&(d, v)| {
                        if d == 3 {
                            -v * l.nodes.len() as f64
                        } else {
                            0.0
                        }
                    })
                })
                .sum::<f64>();
            let reactions = sol
                .reactions
                .iter()
                .filter(|r| r.dof == 3)
                .map(|r| r.value)
                .sum::<f64>();
            let forces: Vec<f64> = grid
                .droppers
                .iter()
                .zip(&setting.slack_mm)
                .map(|(&i, &slack)| {
                    let e = uz(&sol, &model, MESSENGER_BASE + i as u32)
                        - uz(&sol, &model, CONTACT_BASE + i as u32)
                        - slack;
                    k_d * e.max(0.0)
                })
                .collect();
            let state = StaticState {
                dropper_x_m: grid.droppers.iter().map(|&i| grid.x[i] * 1e-3).collect(),
                dropper_force_n: forces,
                dropper_slack_mm: setting.slack_mm.clone(),
                target_mm: targets,
                contact_wire_mm: heights,
                presag_miss_mm: miss,
                iterations,
                steady_arm_force_n: steady_arm_force,
                messenger_support_force_n: support_force,
                weight_n: weight,
                support_reactions_n: reactions,
            };
            return Ok((setting, state));
        }
        // Too low (h < t): a shorter dropper (smaller slack) lifts the wire.
        for (j, (h, t)) in heights.iter().zip(&targets).enumerate() {
            setting.slack_mm[j] += h - t;
        }
        iterations += 1;
    }
}

/// Builds the pantograph-catenary model of `spec`: the static state first (module doc),
/// then the deck's model with its STATIC case (head pressed at the start) and the
/// transient at `run`'s speed.
pub fn build(spec: &CatenaryDeckSpec) -> Result<CatenaryModel, CatenaryError> {
    build_parts(&spec.catenary, &spec.pantograph, &spec.run)
}

/// [`build`] from the three parts.
pub fn build_parts(
    catenary: &CatenarySpec,
    pantograph: &PantographSpec,
    run_spec: &RunSpec,
) -> Result<CatenaryModel, CatenaryError> {
    catenary.validate()?;
    pantograph.validate()?;
    let length = catenary.length_m();
    run_spec.validate(length)?;
    check_wave_speed(catenary, run_spec).map_err(CatenaryError::Regime)?;
    let grid = Grid::new(catenary);
    let (setting, state) = static_state(catenary, &grid)?;
    let mut p = catenary_pieces(catenary, &grid, Part::Catenary, &setting);
    // The pantograph: masses from the head down at x = -5 m, 1 m apart, then the ground.
    let n = pantograph.stages.len() as u32;
    let head = PANTOGRAPH_BASE;
    let ground = PANTOGRAPH_BASE + n;
    for i in 0..=n {
        p.nodes.push(Node {
            id: PANTOGRAPH_BASE + i,
            xyz: [-5000.0, 0.0, -BAR_MM * f64::from(i)],
        });
    }
    for (i, stage) in pantograph.stages.iter().enumerate() {
        let node = PANTOGRAPH_BASE + i as u32;
        let id = PANTOGRAPH_BASE + i as u32;
        p.point_masses.push(PointMass {
            node,
            mass: kg_to_t(stage.mass_kg),
            inertia: [0.0; 3],
        });
        if let Some(matrix) = &stage.matrix {
            p.stage_matrix(i as u32, [node + 1, node], matrix);
            continue;
        }
        p.bar(
            id,
            [node, node + 1],
            n_m_to_n_mm(stage.stiffness_n_m),
            format!("pantograph_stage_{}", i + 1),
        );
        if stage.damping_n_s_m > 0.0 {
            // C_e = beta K_e on the bar: the dashpot c = beta k beside the spring.
            p.damping.push(Damping {
                alpha: 0.0,
                beta: stage.damping_n_s_m / stage.stiffness_n_m,
                elements: vec![id],
                mass_nodes: Vec::new(),
            });
        }
    }
    p.fixed_disp.push(FixedDisp {
        dofs: vec![(1, 0.0), (2, 0.0), (4, 0.0), (5, 0.0), (6, 0.0)],
        nodes: (PANTOGRAPH_BASE..ground).collect(),
    });
    p.fixed_disp.push(FixedDisp {
        dofs: (1..=6).map(|d| (d, 0.0)).collect(),
        nodes: vec![ground],
    });
    p.point_loads.push(PointLoad {
        dofs: vec![(3, pantograph.uplift_force_n)],
        nodes: vec![ground - 1],
        table: None,
    });
    p.node_sets.push(NodeSet {
        name: "pantograph".into(),
        nodes: (PANTOGRAPH_BASE..=ground).collect(),
    });
    let interior: Vec<usize> = grid.supports[1..grid.supports.len() - 1].to_vec();
    let support_nodes: Vec<NodeId> = interior.iter().map(|&i| CONTACT_BASE + i as u32).collect();
    let mut outputs = vec![OutputRequest {
        nodes: (PANTOGRAPH_BASE..ground).collect(),
        dofs: vec![3],
        quantities: vec![Quantity::Displacement, Quantity::Velocity],
        every: run_spec.output_every,
    }];
    if !support_nodes.is_empty() {
        outputs.insert(
            0,
            OutputRequest {
                nodes: support_nodes.clone(),
                dofs: vec![3],
                quantities: vec![Quantity::Displacement],
                every: run_spec.output_every,
            },
        );
    }
    let speed_mm_s = run_spec.speed_m_s() * 1e3;
    let contact = MovingContact {
        head,
        dof: 3,
        stiffness: n_m_to_n_mm(pantograph.contact_stiffness_n_m),
        speed: speed_mm_s,
        start: run_spec.start_m * 1e3,
        line: (0..grid.x.len() as u32).map(|i| CONTACT_BASE + i).collect(),
    };
    let dt = run_spec.time_step_s;
    let travel = (run_spec.end_m(length) - run_spec.start_m) * 1e3 / speed_mm_s;
    let steps = (travel / dt - 1e-9).ceil().max(1.0);
    let cases = vec![
        static_case("static state"),
        LoadCase {
            title: format!("pantograph at {} km/h", run_spec.speed_km_h),
            analysis: Analysis::Transient {
                dt,
                total_time: steps * dt,
                method: TransientMethod::Direct(Integrator::AverageAcceleration),
            },
            point_loads: Vec::new(),
        },
    ];
    let title = format!(
        "catenary {} x {} m, pantograph at {} km/h",
        catenary.spans, catenary.span_length_m, run_spec.speed_km_h
    );
    let model = model_of(parts(title, p, cases, outputs, vec![contact]))?;
    Ok(CatenaryModel {
        model,
        state,
        support_x_m: interior.iter().map(|&i| grid.x[i] * 1e-3).collect(),
        support_nodes,
        head,
        pantograph: pantograph.clone(),
        start_m: run_spec.start_m,
        speed_m_s: run_spec.speed_m_s(),
        length_m: length,
        wire_nodes: grid.x.len(),
    })
}
