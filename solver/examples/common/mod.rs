//! The paper's spring built in code for the benchmarks (the solver cannot depend on the
//! mesher): n = 14 coils, D = 24 mm, d = 3 mm, pitch 6.2 mm, type 98, E = 190708 MPa,
//! nu = 0.3, 7850 kg/m^3, with coil-mesh's numbering (node 1 = the weight's reference on
//! the axis, nodes 2.. = the helix from the clamped base); the top wire end is tied by
//! RBE2 to node 1, which is guided (only u_z free) and carries `weight_t` and a 10 N
//! compressive load in one static load case. Callers replace the load cases, damping,
//! initial velocities and outputs they need.

use coil_solver::model::*;

/// Node id of the weight's reference node.
pub const WEIGHT: NodeId = 1;

#[allow(dead_code)] // not every benchmark builds it unchanged
pub fn paper_spring(elements_per_coil: usize, weight_t: f64, lumped_mass: bool) -> Model {
    paper_spring_parts(elements_per_coil, weight_t, lumped_mass)
        .build()
        .expect("the paper spring is a valid model")
}

/// [`paper_spring`]'s parts, to change before building.
pub fn paper_spring_parts(
    elements_per_coil: usize,
    weight_t: f64,
    lumped_mass: bool,
) -> ModelParts {
    let (coils, d_mean, d_wire, pitch) = (14.0, 24.0, 3.0, 6.2);
    let n = (coils * elements_per_coil as f64) as usize;
    let r = 0.5 * d_mean;
    let mut nodes = vec![Node {
        id: WEIGHT,
        xyz: [0.0, 0.0, pitch * coils],
    }];
    nodes.extend((0..=n).map(|i| {
        let t = std::f64::consts::TAU * coils * i as f64 / n as f64;
        Node {
            id: i as NodeId + 2,
            xyz: [r * t.cos(), r * t.sin(), pitch * t / std::f64::consts::TAU],
        }
    }));
    let ids: Vec<ElementId> = (1..=n as ElementId).collect();
    ModelParts {
        title: format!("paper spring, {elements_per_coil} elements per coil"),
        element_types: vec![ElementType::Beam98],
        lumped_mass,
        nodes,
        elements: ids
            .iter()
            .map(|&id| Element {
                id,
                kind: ElementType::Beam98,
                nodes: [id + 1, id + 2],
            })
            .collect(),
        node_sets: Vec::new(),
        element_sets: Vec::new(),
        materials: vec![Material {
            name: "steel".to_string(),
            youngs_modulus: 190_708.0,
            poisson: 0.3,
            density: units::density_from_si(7850.0),
            elements: ids.clone(),
        }],
        geometries: vec![Geometry {
            name: "wire".to_string(),
            section: Section::SolidCircle { diameter: d_wire },
            orientation: [0.0, 0.0, 1.0],
            elements: ids,
        }],
        damping: Vec::new(),
        point_masses: vec![PointMass {
            node: WEIGHT,
            mass: weight_t,
            inertia: [0.0; 3],
        }],
        rigid_ties: vec![RigidTie {
            name: "top".to_string(),
            reference: WEIGHT,
            dofs: vec![1, 2, 3, 4, 5, 6],
            tied: vec![n as NodeId + 2],
        }],
        fixed_disp: vec![
            FixedDisp {
                dofs: (1..=6).map(|d| (d, 0.0)).collect(),
                nodes: vec![2],
            },
            FixedDisp {
                dofs: vec![(1, 0.0), (2, 0.0), (4, 0.0), (5, 0.0), (6, 0.0)],
                nodes: vec![WEIGHT],
            },
        ],
        point_loads: Vec::new(),
        tables: Vec::new(),
        initial_velocities: Vec::new(),
        outputs: Vec::new(),
        load_cases: vec![LoadCase {
            title: "static".to_string(),
            analysis: Analysis::Static {
                steps: 1,
                time: 1.0,
            },
            point_loads: vec![PointLoad {
                dofs: vec![(3, -10.0)],
                nodes: vec![WEIGHT],
                table: None,
            }],
        }],
        point_laws: Vec::new(),
        dashpots: Vec::new(),
        modal_damping: Default::default(),
        beam_tensions: Vec::new(),
        tension_links: Vec::new(),
        moving_contacts: Vec::new(),
        matrix_elements: Vec::new(),
    }
}

/// Rayleigh damping alpha M + beta K on all of the wire's elements (not the weight).
#[allow(dead_code)] // not every benchmark damps
pub fn damp_wire(model: &mut ModelParts, alpha: f64, beta: f64) {
    let elements = model.elements.iter().map(|e| e.id).collect();
    model.damping = vec![Damping {
        alpha,
        beta,
        elements,
        mass_nodes: Vec::new(),
    }];
}

/// The weight (t) that puts `probe`'s axial period near `period_s`: `K (T / 2 pi)^2`, `K`
/// the static stiffness at the weight from the probe's first (static) load case.
#[allow(dead_code)] // not every benchmark sizes its weight
pub fn weight_for_period(probe: &Model, period_s: f64) -> Result<f64, Box<dyn std::error::Error>> {
    use coil_solver::analysis::{static_analysis, System};
    let system = System::new(probe)?;
    let factor = system.factor_stiffness()?;
    let stiffness = static_analysis::solve(&system, &factor, &probe.load_cases()[0], 1.0)?
        .stiffness_n_mm
        .ok_or("no stiffness")?;
    Ok(stiffness * (period_s / std::f64::consts::TAU).powi(2))
}
