//! Validation against hand-made parts: each rule's error names its site.

use super::*;
use crate::model::{Element, Geometry, Material, Model, Node};

/// One type-52 element from (0,0,0) to (10,0,0) with steel and a 1 mm wire.
fn one_beam() -> ModelParts {
    ModelParts {
        element_types: vec![ElementType::Beam52],
        nodes: vec![
            Node {
                id: 2,
                xyz: [10.0, 0.0, 0.0],
            },
            Node {
                id: 1,
                xyz: [0.0; 3],
            },
        ],
        elements: vec![Element {
            id: 1,
            kind: ElementType::Beam52,
            nodes: [1, 2],
        }],
        materials: vec![Material {
            name: "steel".into(),
            youngs_modulus: 2.1e5,
            poisson: 0.3,
            density: 7.85e-9,
            elements: vec![1],
        }],
        geometries: vec![Geometry {
            name: String::new(),
            section: Section::SolidCircle { diameter: 1.0 },
            orientation: [0.0, 0.0, 1.0],
            elements: vec![1],
        }],
        ..ModelParts::default()
    }
}

#[test]
fn a_valid_model_is_normalised() {
    let m = Model::try_new(one_beam()).expect("valid");
    assert_eq!(m.nodes()[0].id, 1);
    assert_eq!(m.nodes()[1].id, 2);
}

#[test]
fn semantic_errors_name_their_site() {
    let mut p = one_beam();
    p.elements[0].nodes = [1, 3];
    let e = Model::try_new(p).unwrap_err();
    assert_eq!(e.site, Site::ElementNode(1, 1));
    assert!(e.message.contains("node 3, which does not exist"), "{e}");

    let mut p = one_beam();
    p.geometries[0].orientation = [1.0, 0.0, 0.0];
    let e = Model::try_new(p).unwrap_err();
    assert_eq!(e.site, Site::GeometryOrientation(0));

    let mut p = one_beam();
    p.materials[0].youngs_modulus = -1.0;
    assert_eq!(Model::try_new(p).unwrap_err().site, Site::Material(0));

    let mut p = one_beam();
    p.geometries.clear();
    assert!(Model::try_new(p)
        .unwrap_err()
        .message
        .contains("has no geometry"));
}

#[test]
fn deserialising_validates() {
    let good = serde_json::to_string(&Model::try_new(one_beam()).unwrap()).unwrap();
    let back: Model = serde_json::from_str(&good).expect("valid json model");
    assert_eq!(back.elements().len(), 1);
    let bad = good.replace("\"poisson\":0.3", "\"poisson\":0.7");
    assert!(serde_json::from_str::<Model>(&bad).is_err());
}
