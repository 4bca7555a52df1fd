//! Beam elements and their local frames, as pure functions.
//!
//! [`beam`] computes the local 12x12 stiffness and mass of Marc types 52 and 98;
//! [`frame`] builds the local axes from the two nodes and the orientation vector.
//! This module only resolves an element's material, section and nodes from the
//! [`Model`] and rotates the local matrices to global axes.
//!
//! DOF order per node: `u_x, u_y, u_z, theta_x, theta_y, theta_z` (node 1 then node 2),
//! global axes after [`global_matrices`]. Units: mm, N, t, s.

pub mod beam;
pub mod frame;

pub use beam::BeamProperties;
pub use frame::{Frame, FrameError, Matrix12};

use crate::model::{Element, Model, NodeId};

/// Why an element's matrices cannot be formed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// The element has no material.
    #[error("no material (ISOTROPIC) is assigned")]
    NoMaterial,
    /// The element has no geometry.
    #[error("no GEOMETRY is assigned")]
    NoGeometry,
    /// The element names a node that does not exist.
    #[error("node {0} does not exist")]
    UnknownNode(NodeId),
    /// A material or section value out of range.
    #[error("{what} must be {requirement}, got {value}")]
    BadProperty {
        /// The property.
        what: &'static str,
        /// What it must be.
        requirement: &'static str,
        /// Its value.
        value: f64,
    },
    /// The local frame cannot be built.
    #[error(transparent)]
    Frame(#[from] FrameError),
}

fn require(
    what: &'static str,
    value: f64,
    ok: bool,
    requirement: &'static str,
) -> Result<(), ElementError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(ElementError::BadProperty {
            what,
            requirement,
            value,
        })
    }
}

/// The element's properties and local frame, checked for admissible values.
pub fn properties(
    model: &Model,
    element: &Element,
) -> Result<(BeamProperties, Frame), ElementError> {
    let material = model
        .material_of(element.id)
        .ok_or(ElementError::NoMaterial)?;
    let geometry = model
        .geometry_of(element.id)
        .ok_or(ElementError::NoGeometry)?;
    let xyz = |id: NodeId| {
        model
            .node_index(id)
            .map(|i| model.nodes[i].xyz)
            .ok_or(ElementError::UnknownNode(id))
    };
    let frame = frame::local_frame(
        xyz(element.nodes[0])?,
        xyz(element.nodes[1])?,
        geometry.orientation,
    )?;
    let e = material.youngs_modulus;
    let nu = material.poisson;
    require("Young's modulus (MPa)", e, e > 0.0, "positive")?;
    require(
        "Poisson's ratio",
        nu,
        nu > -1.0 && nu <= 0.5,
        "in (-1, 0.5]",
    )?;
    require(
        "density (t/mm^3)",
        material.density,
        material.density >= 0.0,
        "non-negative",
    )?;
    let section = geometry.section.properties(nu);
    require(
        "section area (mm^2)",
        section.area,
        section.area > 0.0,
        "positive",
    )?;
    require("I_yy (mm^4)", section.iyy, section.iyy > 0.0, "positive")?;
    require("I_zz (mm^4)", section.izz, section.izz > 0.0, "positive")?;
    require(
        "torsion constant J (mm^4)",
        section.torsion,
        section.torsion > 0.0,
        "positive",
    )?;
    if element.kind == crate::model::ElementType::Beam98 {
        let k = section.shear_coefficient;
        require("shear coefficient", k, k > 0.0, "positive for type 98")?;
    }
    Ok((
        BeamProperties {
            kind: element.kind,
            length: frame.length,
            youngs_modulus: e,
            shear_modulus: material.shear_modulus(),
            density: material.density,
            section,
        },
        frame,
    ))
}

/// Global stiffness (with the geometric stiffness of the element's `BEAM TENSION`, if
/// any) and mass (consistent, or HRZ-lumped when `lumped`) of one element, written into
/// `k` and `m`.
pub fn global_matrices(
    model: &Model,
    element: &Element,
    lumped: bool,
    k: &mut Matrix12,
    m: &mut Matrix12,
) -> Result<(), ElementError> {
    let (props, frame) = properties(model, element)?;
    beam::local_stiffness(&props, k);
    let tension = model.tension_of(element.id);
    if tension != 0.0 {
        beam::add_local_geometric_stiffness(props.length, tension, k);
    }
    if lumped {
        let mut consistent = Matrix12::zeros();
        beam::local_consistent_mass(&props, &mut consistent);
        beam::hrz_lump(&consistent, m);
    } else {
        beam::local_consistent_mass(&props, m);
    }
    frame::to_global(&frame.rotation, k);
    frame::to_global(&frame.rotation, m);
    Ok(())
}
