//! Small models for the unit tests of the engine's modules.

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
        dashpots: Vec::new(),
        modal_damping: Default::default(),
        beam_tensions: Vec::new(),
        tension_links: Vec::new(),
        moving_contacts: Vec::new(),
        matrix_elements: Vec::new(),
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
