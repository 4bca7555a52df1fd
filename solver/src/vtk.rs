//! VTK XML unstructured-grid files (`.vtu`, ASCII) of the beam model, for ParaView.
//!
//! Points are the nodes (coordinates in mm), cells are lines (VTK type 3): one per beam
//! element (`element_id`, `element_type` 52 or 98) and one per tied node of a rigid tie,
//! from the reference node to the tied node (`element_id` -1, `element_type` 0), so the
//! weight's reference node shows up connected. Point data: `node_id`, and for a
//! displaced or mode shape `displacement` (mm, the active vector: use ParaView's "Warp
//! By Vector") and `rotation` (rad, the small-rotation vector). Mode shapes are
//! mass-normalised, so their scale is arbitrary; warp them by a factor that suits.
//!
//! Format: <https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>
//! (XML formats, UnstructuredGrid), version 1.0 with 64-bit headers.

use crate::model::{Model, DOFS_PER_NODE};
use std::fmt::Write as _;

/// VTK cell type of a straight line.
const VTK_LINE: u8 = 3;

/// The `.vtu` text of the model with an optional full DOF vector (6 per node: three
/// translations written as `displacement`, three rotations as `rotation`).
pub fn unstructured_grid(model: &Model, dofs: Option<&[f64]>) -> String {
    let mut cells: Vec<([usize; 2], i64, i64)> = Vec::with_capacity(model.elements.len());
    for e in &model.elements {
        if let (Some(a), Some(b)) = (model.node_index(e.nodes[0]), model.node_index(e.nodes[1])) {
            cells.push(([a, b], i64::from(e.id), i64::from(e.kind.number())));
        }
    }
    for tie in &model.rigid_ties {
        let Some(r) = model.node_index(tie.reference) else {
            continue;
        };
        for &s in &tie.tied {
            if let Some(s) = model.node_index(s) {
                cells.push(([r, s], -1, 0));
            }
        }
    }
    let n_points = model.nodes.len();
    let mut out = String::with_capacity(200 + 120 * n_points + 60 * cells.len());
    // Writing to a String cannot fail; the results are ignored deliberately.
    let _ = writeln!(out, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        out,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    );
    let _ = writeln!(out, "  <UnstructuredGrid>");
    let _ = writeln!(
        out,
        "    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{}\">",
        cells.len()
    );
    match dofs {
        Some(_) => {
            let _ = writeln!(
                out,
                "      <PointData Scalars=\"node_id\" Vectors=\"displacement\">"
            );
        }
        None => {
            let _ = writeln!(out, "      <PointData Scalars=\"node_id\">");
        }
    }
    data_array(
        &mut out,
        "node_id",
        1,
        model.nodes.iter().map(|n| i64::from(n.id)),
    );
    if let Some(u) = dofs {
        for (name, offset) in [("displacement", 0), ("rotation", 3)] {
            let values =
                (0..n_points).flat_map(|i| (0..3).map(move |c| u[i * DOFS_PER_NODE + offset + c]));
            data_array(&mut out, name, 3, values);
        }
    }
    let _ = writeln!(out, "      </PointData>");
    let _ = writeln!(out, "      <CellData Scalars=\"element_type\">");
    data_array(&mut out, "element_id", 1, cells.iter().map(|c| c.1));
    data_array(&mut out, "element_type", 1, cells.iter().map(|c| c.2));
    let _ = writeln!(out, "      </CellData>");
    let _ = writeln!(out, "      <Points>");
    data_array(
        &mut out,
        "coordinates",
        3,
        model.nodes.iter().flat_map(|n| n.xyz),
    );
    let _ = writeln!(out, "      </Points>");
    let _ = writeln!(out, "      <Cells>");
    data_array(
        &mut out,
        "connectivity",
        1,
        cells.iter().flat_map(|c| c.0.map(|i| i as i64)),
    );
    data_array(
        &mut out,
        "offsets",
        1,
        (1..=cells.len() as i64).map(|k| 2 * k),
    );
    data_array(&mut out, "types", 1, cells.iter().map(|_| VTK_LINE));
    let _ = writeln!(out, "      </Cells>");
    let _ = writeln!(out, "    </Piece>");
    let _ = writeln!(out, "  </UnstructuredGrid>");
    let _ = writeln!(out, "</VTKFile>");
    out
}

/// A `DataArray` of numbers written straight into `out` (no per-value allocation):
/// floats in shortest round-trip scientific notation, non-finite ones (never expected)
/// as 0 so that the file stays readable.
fn data_array<T: Number>(
    out: &mut String,
    name: &str,
    components: usize,
    values: impl Iterator<Item = T>,
) {
    let _ = write!(
        out,
        "        <DataArray type=\"{}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">\n          ",
        T::VTK_TYPE
    );
    for (k, v) in values.enumerate() {
        if k > 0 {
            out.push(if k % (6 * components.max(1)) == 0 {
                '\n'
            } else {
                ' '
            });
        }
        v.write_to(out);
    }
    out.push_str("\n        </DataArray>\n");
}

/// Numbers a `DataArray` can hold.
trait Number: Copy {
    const VTK_TYPE: &'static str;
    fn write_to(self, out: &mut String);
}

impl Number for f64 {
    const VTK_TYPE: &'static str = "Float64";
    fn write_to(self, out: &mut String) {
        if self.is_finite() {
            let _ = write!(out, "{self:e}");
        } else {
            out.push('0');
        }
    }
}

impl Number for i64 {
    const VTK_TYPE: &'static str = "Int64";
    fn write_to(self, out: &mut String) {
        let _ = write!(out, "{self}");
    }
}

impl Number for u8 {
    const VTK_TYPE: &'static str = "UInt8";
    fn write_to(self, out: &mut String) {
        let _ = write!(out, "{self}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::test_support::tied_frame;

    #[test]
    fn grid_has_points_cells_and_fields() {
        let model = tied_frame();
        let u: Vec<f64> = (0..model.dof_count()).map(|i| i as f64 * 0.5).collect();
        let text = unstructured_grid(&model, Some(&u));
        assert!(text.contains("NumberOfPoints=\"5\" NumberOfCells=\"4\""));
        assert!(text.contains("Name=\"displacement\" NumberOfComponents=\"3\""));
        // Node 4 (index 3): u_x is DOF 18 -> 9, rotation x is DOF 21 -> 10.5.
        assert!(text.contains("9e0 9.5e0 1e1"));
        assert!(text.contains("1.05e1 1.1e1 1.15e1"));
        // Three beams and one tie line from the reference (index 4) to node 4 (index 3).
        let array = |name: &str| -> Vec<String> {
            let start = text.find(&format!("Name=\"{name}\"")).unwrap();
            let body = &text[start..];
            let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
            body.split_whitespace().map(str::to_string).collect()
        };
        assert_eq!(
            array("connectivity"),
            ["0", "1", "1", "2", "2", "3", "4", "3"]
        );
        assert_eq!(array("offsets"), ["2", "4", "6", "8"]);
        assert_eq!(array("element_type"), ["98", "98", "98", "0"]);
        let plain = unstructured_grid(&model, None);
        assert!(!plain.contains("displacement"));
        assert_eq!(
            text.matches("<DataArray").count(),
            text.matches("</DataArray>").count()
        );
    }
}
