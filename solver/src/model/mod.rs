//! The validated, immutable finite-element model.
//!
//! Everything downstream of the deck reader (elements, assembly, analyses, the deck
//! writer, the mesher) sees only this type; no numerical code sees deck text.
//!
//! # Units
//! The model is in Marc's consistent unit system: length in mm, force in N, mass in
//! tonne (1 t = 1000 kg), time in s. Hence stress and Young's modulus in MPa (N/mm^2),
//! density in t/mm^3 (7850 kg/m^3 = 7.85e-9 t/mm^3), rotary inertia in t mm^2,
//! velocity in mm/s, acceleration in mm/s^2. Conversion to SI happens only at the
//! edges (result files, the mesher's flags); see [`units`].
//!
//! # Degrees of freedom
//! Every node carries six DOFs, numbered 1..=6 in the deck as in Marc:
//! 1 = u_x, 2 = u_y, 3 = u_z, 4 = theta_x, 5 = theta_y, 6 = theta_z (global axes,
//! right-handed, rotations in radians). Internally a DOF is `node_index * 6 + (dof - 1)`.
//!
//! # Identity
//! Nodes and elements keep their user numbers (`id`); vectors are sorted by id so that
//! look-ups are binary searches. Sets are resolved to sorted, de-duplicated id lists
//! when the model is built; the named sets are kept only so that a written deck reads
//! back to an equal model.

pub mod check;
mod error;
pub mod line;
mod parts;
pub mod units;

pub use error::{ModelError, Site};
pub use parts::*;

impl Model {
    /// Validates `parts` and makes them a model: ids and references resolved, values in
    /// range, constraints consistent (see [`check`] for the full list). Id lists are
    /// sorted and de-duplicated, nodes and elements sorted by id.
    pub fn try_new(parts: ModelParts) -> Result<Model, ModelError> {
        let p = check::check(parts)?;
        Ok(Model {
            title: p.title,
            element_types: p.element_types,
            lumped_mass: p.lumped_mass,
            nodes: p.nodes,
            elements: p.elements,
            node_sets: p.node_sets,
            element_sets: p.element_sets,
            materials: p.materials,
            geometries: p.geometries,
            damping: p.damping,
            point_masses: p.point_masses,
            rigid_ties: p.rigid_ties,
            fixed_disp: p.fixed_disp,
            point_loads: p.point_loads,
            tables: p.tables,
            initial_velocities: p.initial_velocities,
            outputs: p.outputs,
            load_cases: p.load_cases,
            point_laws: p.point_laws,
            dashpots: p.dashpots,
            modal_damping: p.modal_damping,
            beam_tensions: p.beam_tensions,
            tension_links: p.tension_links,
            moving_contacts: p.moving_contacts,
            matrix_elements: p.matrix_elements,
        })
    }

    /// Changes the model through its parts and validates the result: on an error the
    /// model is left as it was. `model.edit(|p| p.lumped_mass = true)?`.
    pub fn edit(&mut self, change: impl FnOnce(&mut ModelParts)) -> Result<(), ModelError> {
        let mut parts = self.clone().into_parts();
        change(&mut parts);
        *self = Model::try_new(parts)?;
        Ok(())
    }

    /// The model's pieces, to change and build again with [`Model::try_new`].
    pub fn into_parts(self) -> ModelParts {
        ModelParts {
            title: self.title,
            element_types: self.element_types,
            lumped_mass: self.lumped_mass,
            nodes: self.nodes,
            elements: self.elements,
            node_sets: self.node_sets,
            element_sets: self.element_sets,
            materials: self.materials,
            geometries: self.geometries,
            damping: self.damping,
            point_masses: self.point_masses,
            rigid_ties: self.rigid_ties,
            fixed_disp: self.fixed_disp,
            point_loads: self.point_loads,
            tables: self.tables,
            initial_velocities: self.initial_velocities,
            outputs: self.outputs,
            load_cases: self.load_cases,
            point_laws: self.point_laws,
            dashpots: self.dashpots,
            modal_damping: self.modal_damping,
            beam_tensions: self.beam_tensions,
            tension_links: self.tension_links,
            moving_contacts: self.moving_contacts,
            matrix_elements: self.matrix_elements,
        }
    }

    /// The model's title (`TITLE`).
    pub fn title(&self) -> &str {
        &self.title
    }

    /// Element types declared in the parameter section (`ELEMENTS`).
    pub fn element_types(&self) -> &[ElementType] {
        &self.element_types
    }

    /// Lumped instead of consistent mass (parameter `LUMP`); never a silent default.
    pub fn lumped_mass(&self) -> bool {
        self.lumped_mass
    }

    /// The nodes, sorted by id, each id once.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The beam elements, sorted by id, each id once.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Named node sets (kept so that a written deck reads back equal).
    pub fn node_sets(&self) -> &[NodeSet] {
        &self.node_sets
    }

    /// Named element sets (kept so that a written deck reads back equal).
    pub fn element_sets(&self) -> &[ElementSet] {
        &self.element_sets
    }

    /// Materials; every element has one (the last listing it wins).
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Beam geometries; every element has one (the last listing it wins).
    pub fn geometries(&self) -> &[Geometry] {
        &self.geometries
    }

    /// Rayleigh damping groups.
    pub fn damping(&self) -> &[Damping] {
        &self.damping
    }

    /// Point masses, at most one per node.
    pub fn point_masses(&self) -> &[PointMass] {
        &self.point_masses
    }

    /// Rigid ties; they neither overlap nor chain.
    pub fn rigid_ties(&self) -> &[RigidTie] {
        &self.rigid_ties
    }

    /// Prescribed displacements; each (node, DOF) once.
    pub fn fixed_disp(&self) -> &[FixedDisp] {
        &self.fixed_disp
    }

    /// Model-definition point loads (active in every load case).
    pub fn point_loads(&self) -> &[PointLoad] {
        &self.point_loads
    }

    /// Load-factor tables against time.
    pub fn tables(&self) -> &[Table] {
        &self.tables
    }

    /// Initial velocities of transients; each (node, DOF) once.
    pub fn initial_velocities(&self) -> &[InitialVelocity] {
        &self.initial_velocities
    }

    /// History output requests.
    pub fn outputs(&self) -> &[OutputRequest] {
        &self.outputs
    }

    /// The load cases, in order.
    pub fn load_cases(&self) -> &[LoadCase] {
        &self.load_cases
    }

    /// Nonlinear point elements (`FRICTION`, `QUADRATIC DAMPER`, `CUBIC SPRING`): one entry per (node, DOF), the cards on it combined, sorted by (node, DOF), on free DOFs.
    pub fn point_laws(&self) -> &[PointElement] {
        &self.point_laws
    }

    /// Linear dashpots to ground (`DASHPOT`), sorted by (node, DOF), on free DOFs.
    pub fn dashpots(&self) -> &[Dashpot] {
        &self.dashpots
    }

    /// Modal damping (`LOSS FACTOR`, `MODAL DAMPING`).
    pub fn modal_damping(&self) -> &ModalDamping {
        &self.modal_damping
    }
}

impl ModelParts {
    /// [`Model::try_new`] of these parts.
    pub fn build(self) -> Result<Model, ModelError> {
        Model::try_new(self)
    }
}

impl TryFrom<ModelParts> for Model {
    type Error = ModelError;
    fn try_from(parts: ModelParts) -> Result<Model, ModelError> {
        Model::try_new(parts)
    }
}

impl From<Model> for ModelParts {
    fn from(model: Model) -> ModelParts {
        model.into_parts()
    }
}

impl Model {
    /// Index of a node id in `nodes`.
    pub fn node_index(&self, id: NodeId) -> Option<usize> {
        self.nodes.binary_search_by_key(&id, |n| n.id).ok()
    }

    /// Index of an element id in `elements`.
    pub fn element_index(&self, id: ElementId) -> Option<usize> {
        self.elements.binary_search_by_key(&id, |e| e.id).ok()
    }

    /// Total number of DOFs before constraints (6 per node).
    pub fn dof_count(&self) -> usize {
        self.nodes.len() * DOFS_PER_NODE
    }

    /// The material of an element, if one is assigned.
    pub fn material_of(&self, id: ElementId) -> Option<&Material> {
        self.materials
            .iter()
            .rev()
            .find(|m| m.elements.binary_search(&id).is_ok())
    }

    /// Tensioned beams (`BEAM TENSION`).
    pub fn beam_tensions(&self) -> &[BeamTension] {
        &self.beam_tensions
    }

    /// Tension-only links (`TENSION LINK`).
    pub fn tension_links(&self) -> &[TensionLink] {
        &self.tension_links
    }

    /// Moving contacts (`MOVING CONTACT`).
    pub fn moving_contacts(&self) -> &[MovingContact] {
        &self.moving_contacts
    }

    /// Matrix elements (`DMIG`).
    pub fn matrix_elements(&self) -> &[MatrixElement] {
        &self.matrix_elements
    }

    /// The given axial force of an element (`BEAM TENSION`; N), zero when none is given.
    pub fn tension_of(&self, id: ElementId) -> f64 {
        self.beam_tensions
            .iter()
            .find(|t| t.elements.binary_search(&id).is_ok())
            .map_or(0.0, |t| t.force)
    }

    /// The geometry of an element, if one is assigned.
    pub fn geometry_of(&self, id: ElementId) -> Option<&Geometry> {
        self.geometries
            .iter()
            .rev()
            .find(|g| g.elements.binary_search(&id).is_ok())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solid_circle_properties() {
        let p = Section::SolidCircle { diameter: 3.0 }.properties(0.3);
        let pi = std::f64::consts::PI;
        assert!((p.area - pi * 2.25).abs() < 1e-12);
        assert!((p.iyy - pi * 81.0 / 64.0).abs() < 1e-12);
        assert!((p.torsion - pi * 81.0 / 32.0).abs() < 1e-12);
        assert!((p.shear_coefficient - 7.8 / 8.8).abs() < 1e-12);
    }
}
