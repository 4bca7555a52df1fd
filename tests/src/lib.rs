//! coil-tests owns the end-to-end tests, the independent truth generators and their scoring.
//! It may import every library crate; its truth models use none of coil's numerics, so
//! agreement with them is evidence; nothing imports it.
//!
//! Shared helpers for the end-to-end and verification tests: models built in code
//! (no deck text), in the model's units (mm, N, t, s).

pub mod docs_tables;

use coil_solver::model::{
    Analysis, Element, ElementType, FixedDisp, Geometry, LoadCase, Material, Model, ModelParts,
    Node, NodeId, PointLoad, PointMass, RigidTie, Section,
};

/// Steel-like material constants used by several tests.
pub const STEEL_E_MPA: f64 = 210_000.0;
pub const STEEL_NU: f64 = 0.3;
/// 7850 kg/m^3 in t/mm^3.
pub const STEEL_DENSITY: f64 = 7.85e-9;

/// The paper's calibrated Young's modulus (its Table 3), MPa.
pub const PAPER_YOUNGS_MODULUS_MPA: f64 = 190_708.0;

/// The paper's spring as the mesher builds it by default (n = 14, D = 24 mm, d = 3 mm,
/// h = 6.2 mm, 24 type-98 beams per coil, steel with nu = 0.3 and 7850 kg/m^3) at the
/// paper's calibrated E: the one fixture of the end-to-end tests (each sets its own mesh,
/// weight and analyses on top).
pub fn paper_spec() -> coil_mesher::SpringSpec {
    coil_mesher::SpringSpec {
        youngs_modulus_mpa: PAPER_YOUNGS_MODULUS_MPA,
        ..coil_mesher::SpringSpec::default()
    }
}

/// How much stiffer a helix of straight beams is than the helix itself: the factor on
/// the closed-form (Castigliano) stiffness of a coil meshed with `elements_per_coil`
/// chords, from the chord geometry alone (no FE).
///
/// A chord spanning the angle `theta = 2 pi / elements_per_coil` has the length
/// `c = 2 R sin(theta / 2)` and its midpoint at `R cos(theta / 2)` from the axis. An axial
/// force `F` on the axis loads a point `s` along the chord from its midpoint with the
/// torque `F R cos(theta / 2)` about the chord and the bending moment `F s`, so the
/// chord's complementary energy per `F^2 / 2` is
/// `c (R^2 cos^2(theta / 2) / GJ + c^2 / (12 EI))`; over the arc `R theta` of the helix
/// (torsion `F R`) it is `R theta R^2 / GJ`. With `EI = (1 + nu) GJ` for a round wire the
/// ratio of compliances is
/// `sin(theta/2)/(theta/2) (cos^2(theta/2) + sin^2(theta/2) / (3 (1 + nu)))`
/// = `1 - theta^2 (1/24 + 1/4 - 1/(12 (1 + nu))) + O(theta^4)`, and this returns its
/// inverse. The pitch angle, the direct shear and the bending of the helix itself are left
/// out: for the paper's spring they change the torsion-dominated compliance by under 1 %,
/// so they change this factor's excess over 1 by under 1 % of itself.
pub fn chord_stiffening(elements_per_coil: usize, poisson: f64) -> f64 {
    let half = std::f64::consts::PI / elements_per_coil as f64;
    let compliance =
        half.sin() / half * (half.cos().powi(2) + half.sin().powi(2) / (3.0 * (1.0 + poisson)));
    1.0 / compliance
}

/// The model of `spec` written as a deck and read back, so the deck's text path (the
/// cards' writer and reader, `INITIAL VEL, QUASI STATIC`) is part of every run using it.
pub fn through_deck(spec: &coil_mesher::SpringSpec) -> Model {
    let model = spec.build().expect("valid spec");
    coil_solver::deck::read_str(&coil_solver::deck::write(&model), "spring.dat")
        .expect("the deck reads back")
}

/// A model with nothing in it but a title.
pub fn empty_model(title: &str) -> Model {
    empty_parts(title).build().expect("an empty model is valid")
}

/// The parts of a model with nothing in it but a title.
pub fn empty_parts(title: &str) -> ModelParts {
    ModelParts {
        title: title.to_string(),
        element_types: Vec::new(),
        lumped_mass: false,
        nodes: Vec::new(),
        elements: Vec::new(),
        node_sets: Vec::new(),
        element_sets: Vec::new(),
        materials: Vec::new(),
        geometries: Vec::new(),
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

/// A straight beam of `n_elements` equal elements from `start` along `direction`
/// (normalised here) with total `length`; nodes 1..=n+1, elements 1..=n.
#[derive(Debug, Clone)]
pub struct StraightBeam {
    pub kind: ElementType,
    pub n_elements: usize,
    pub length: f64,
    pub start: [f64; 3],
    pub direction: [f64; 3],
    pub orientation: [f64; 3],
    pub section: Section,
    pub youngs_modulus: f64,
    pub poisson: f64,
    pub density: f64,
}

impl StraightBeam {
    /// A beam along global x with a solid circular section, steel.
    pub fn along_x(kind: ElementType, n_elements: usize, length: f64, diameter: f64) -> Self {
        StraightBeam {
            kind,
            n_elements,
            length,
            start: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            orientation: [0.0, 1.0, 0.0],
            section: Section::SolidCircle { diameter },
            youngs_modulus: STEEL_E_MPA,
            poisson: STEEL_NU,
            density: STEEL_DENSITY,
        }
    }

    /// Id of the last node (the tip).
    pub fn tip(&self) -> NodeId {
        self.n_elements as NodeId + 1
    }

    /// The model (no supports, loads or load cases yet).
    pub fn model(&self) -> Model {
        self.parts().build().expect("a valid straight beam")
    }

    /// [`StraightBeam::model`]'s parts.
    pub fn parts(&self) -> ModelParts {
        let mut m = empty_parts("straight beam");
        let norm = self.direction.iter().map(|x| x * x).sum::<f64>().sqrt();
        let dir = self.direction.map(|x| x / norm);
        for i in 0..=self.n_elements {
            let s = self.length * i as f64 / self.n_elements as f64;
            m.nodes.push(Node {
                id: i as NodeId + 1,
                xyz: [0, 1, 2].map(|c| self.start[c] + s * dir[c]),
            });
        }
        for i in 1..=self.n_elements as u32 {
            m.elements.push(Element {
                id: i,
                kind: self.kind,
                nodes: [i, i + 1],
            });
        }
        let ids: Vec<u32> = m.elements.iter().map(|e| e.id).collect();
        m.element_types = vec![self.kind];
        m.materials.push(Material {
            name: "steel".to_string(),
            youngs_modulus: self.youngs_modulus,
            poisson: self.poisson,
            density: self.density,
            elements: ids.clone(),
        });
        m.geometries.push(Geometry {
            name: "wire".to_string(),
            section: self.section.clone(),
            orientation: self.orientation,
            elements: ids,
        });
        m
    }
}

/// Changes `model` through [`Model::edit`]; the change must leave a valid model.
pub fn edit(model: &mut Model, change: impl FnOnce(&mut ModelParts)) {
    if let Err(e) = model.edit(change) {
        panic!("the edited model is invalid: {e}");
    }
}

/// Prescribes `dofs` (1..=6) of `nodes` to zero.
pub fn fix(model: &mut Model, nodes: &[NodeId], dofs: &[u8]) {
    edit(model, |m| fix_parts(m, nodes, dofs));
}

/// [`fix`] on a model's parts.
pub fn fix_parts(model: &mut ModelParts, nodes: &[NodeId], dofs: &[u8]) {
    model.fixed_disp.push(FixedDisp {
        dofs: dofs.iter().map(|&d| (d, 0.0)).collect(),
        nodes: nodes.to_vec(),
    });
}

/// Clamps a node (all six DOFs zero).
pub fn clamp(model: &mut Model, node: NodeId) {
    fix(model, &[node], &[1, 2, 3, 4, 5, 6]);
}

/// A constant model-definition point load.
pub fn point_load(model: &mut Model, node: NodeId, dof: u8, value: f64) {
    edit(model, |m| {
        m.point_loads.push(PointLoad {
            dofs: vec![(dof, value)],
            nodes: vec![node],
            table: None,
        })
    });
}

/// Appends a static load case.
pub fn static_case(model: &mut Model, title: &str) {
    edit(model, |m| {
        m.load_cases.push(LoadCase {
            title: title.to_string(),
            analysis: Analysis::Static {
                steps: 1,
                time: 1.0,
            },
            point_loads: Vec::new(),
        })
    });
}

/// Appends a modal load case.
pub fn modal_case(model: &mut Model, title: &str, modes: u32) {
    edit(model, |m| {
        m.load_cases.push(LoadCase {
            title: title.to_string(),
            analysis: Analysis::Modal { modes },
            point_loads: Vec::new(),
        })
    });
}

/// The paper's helical spring (the paper's section 2): helix `x = R cos t, y = R sin t,
/// z = h t / 2 pi`, base wire end clamped, top wire end tied (all six DOFs, RBE2) to a
/// reference node on the axis at the top, which is guided (only u_z free) and carries
/// the weight as a point mass.
#[derive(Debug, Clone)]
pub struct Spring {
    pub coils: f64,
    pub mean_diameter: f64,
    pub wire_diameter: f64,
    pub pitch: f64,
    pub elements_per_coil: usize,
    pub kind: ElementType,
    pub youngs_modulus: f64,
    pub poisson: f64,
    pub density: f64,
    /// The weight (t) on the reference node; 0 for none.
    pub weight_mass: f64,
}

impl Spring {
    /// The paper's base spring: n = 14, D = 24 mm, d = 3 mm, h = 6.2 mm, E = 190708 MPa.
    pub fn paper(elements_per_coil: usize, kind: ElementType) -> Self {
        Spring {
            coils: 14.0,
            mean_diameter: 24.0,
            wire_diameter: 3.0,
            pitch: 6.2,
            elements_per_coil,
            kind,
            youngs_modulus: 190_708.0,
            poisson: 0.3,
            density: STEEL_DENSITY,
            weight_mass: 0.0,
        }
    }

    /// Number of beam elements.
    pub fn n_elements(&self) -> usize {
        (self.coils * self.elements_per_coil as f64).round() as usize
    }

    /// Id of the reference (weight) node.
    pub fn reference(&self) -> NodeId {
        self.n_elements() as NodeId + 2
    }

    /// Spring wire mass (t).
    pub fn wire_mass(&self) -> f64 {
        let area = std::f64::consts::PI * self.wire_diameter.powi(2) / 4.0;
        let turn = (std::f64::consts::PI * self.mean_diameter).hypot(self.pitch);
        self.density * area * turn * self.coils
    }

    /// Castigliano stiffness of the helix (N/mm) with wire torsion, bending, direct
    /// shear and axial force along the pitch angle alpha:
    /// `1/K = L_w [R^2 cos^2 a / GJ + R^2 sin^2 a / EI + cos^2 a / (kappa G A) + sin^2 a / EA]`
    /// with the wire length `L_w = n pi D / cos a` and `tan a = h / (pi D)`.
    pub fn castigliano_stiffness(&self) -> f64 {
        let pi = std::f64::consts::PI;
        let r = 0.5 * self.mean_diameter;
        let alpha = (self.pitch / (pi * self.mean_diameter)).atan();
        let (c2, s2) = (alpha.cos().powi(2), alpha.sin().powi(2));
        let e = self.youngs_modulus;
        let g = e / (2.0 * (1.0 + self.poisson));
        let area = pi * self.wire_diameter.powi(2) / 4.0;
        let i = pi * self.wire_diameter.powi(4) / 64.0;
        let kappa = 6.0 * (1.0 + self.poisson) / (7.0 + 6.0 * self.poisson);
        let wire = self.coils * pi * self.mean_diameter / alpha.cos();
        let shear = match self.kind {
            ElementType::Beam98 => c2 / (kappa * g * area),
            ElementType::Beam52 => 0.0,
        };
        1.0 / (wire * (r * r * c2 / (g * 2.0 * i) + r * r * s2 / (e * i) + shear + s2 / (e * area)))
    }

    /// The model: nodes 1..=N+1 on the helix, elements 1..=N, reference node N+2.
    pub fn model(&self) -> Model {
        let mut m = empty_parts("paper spring");
        let n = self.n_elements();
        let r = 0.5 * self.mean_diameter;
        let turns = std::f64::consts::TAU * self.coils;
        for i in 0..=n {
            let t = turns * i as f64 / n as f64;
            m.nodes.push(Node {
                id: i as NodeId + 1,
                xyz: [
                    r * t.cos(),
                    r * t.sin(),
                    self.pitch * t / std::f64::consts::TAU,
                ],
            });
        }
        let top = n as NodeId + 1;
        let reference = self.reference();
        m.nodes.push(Node {
            id: reference,
            xyz: [0.0, 0.0, self.pitch * self.coils],
        });
        let straight = StraightBeam {
            kind: self.kind,
            n_elements: n,
            length: 1.0,
            start: [0.0; 3],
            direction: [1.0, 0.0, 0.0],
            orientation: [0.0, 0.0, 1.0],
            section: Section::SolidCircle {
                diameter: self.wire_diameter,
            },
            youngs_modulus: self.youngs_modulus,
            poisson: self.poisson,
            density: self.density,
        }
        .parts();
        m.elements = straight.elements;
        m.element_types = straight.element_types;
        m.materials = straight.materials;
        m.geometries = straight.geometries;
        m.rigid_ties.push(RigidTie {
            name: "top".to_string(),
            reference,
            dofs: vec![1, 2, 3, 4, 5, 6],
            tied: vec![top],
        });
        fix_parts(&mut m, &[1], &[1, 2, 3, 4, 5, 6]);
        fix_parts(&mut m, &[reference], &[1, 2, 4, 5, 6]);
        if self.weight_mass > 0.0 {
            m.point_masses.push(PointMass {
                node: reference,
                mass: self.weight_mass,
                inertia: [0.0; 3],
            });
        }
        m.build().expect("a valid paper spring")
    }
}
pub mod real_recordings;
pub mod scoring;
pub mod silverbox;
pub mod truth;
pub mod truth_damping;
pub mod truth_forced;
pub mod truth_forced_spring;
