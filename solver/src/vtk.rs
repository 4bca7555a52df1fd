//! VTK XML unstructured-grid files (`.vtu`) of the beam model and `.pvd` collections of
//! them, for ParaView.
//!
//! Points are the nodes (coordinates in mm), cells are lines (VTK type 3): one per beam
//! element (`element_id`, `element_type` 52 or 98) and one per tied node of a rigid tie,
//! from the reference node to the tied node (`element_id` -1, `element_type` 0), so the
//! weight's reference node shows up connected. Point data: `node_id`, and for a
//! displaced or mode shape `displacement_mm` (the active vector: use ParaView's "Warp
//! By Vector") and `rotation_rad` (the small-rotation vector). Mode shapes are
//! mass-normalised, so their scale is arbitrary; warp them by a factor that suits.
//! Cell data beyond the ids are [`CellField`]s (a static case's section forces and wire
//! stresses, see [`crate::wire`]); every array name ends in its unit.
//!
//! Small grids are written as ASCII; from [`BINARY_ABOVE_VALUES`] numbers on, every
//! array is raw little-endian binary in one `AppendedData` block (a UInt64 byte count
//! before each array), which ParaView reads directly and which is about a third of the
//! ASCII size.
//!
//! A `.pvd` collection ([`collection`]) lists files with a value each (a mode's
//! frequency in Hz, a transient snapshot's time in s), so ParaView steps or animates
//! through them with that value on its time axis.
//!
//! Format: <https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>
//! (XML formats, UnstructuredGrid and Collection), version 1.0 with 64-bit headers.

use crate::model::{Model, DOFS_PER_NODE};
use std::fmt::Write as _;

/// VTK cell type of a straight line.
const VTK_LINE: u8 = 3;

/// Grids with more numbers than this are written as appended raw binary.
pub const BINARY_ABOVE_VALUES: usize = 60_000;

/// How the arrays of a `.vtu` are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// Values as text inside each `DataArray`.
    Ascii,
    /// Raw little-endian binary in an `AppendedData` block.
    Appended,
}

/// A cell array: `components` values per beam element, in `model.elements` order (the
/// rigid-tie cells get zeros). Its name should end in its unit (`torque_n_mm`).
#[derive(Debug, Clone, PartialEq)]
pub struct CellField {
    /// Array name, ending in its unit.
    pub name: String,
    /// Values per element.
    pub components: usize,
    /// `components` values per element, element after element.
    pub values: Vec<f64>,
}

/// The `.vtu` bytes of the model with an optional full DOF vector (6 per node: three
/// translations written as `displacement_mm`, three rotations as `rotation_rad`), ASCII
/// or binary by size.
pub fn unstructured_grid(model: &Model, dofs: Option<&[f64]>) -> Vec<u8> {
    grid(model, dofs, &[])
}

/// [`unstructured_grid`] with cell arrays.
pub fn grid(model: &Model, dofs: Option<&[f64]>, cell_fields: &[CellField]) -> Vec<u8> {
    let values = model.nodes.len() * if dofs.is_some() { 10 } else { 4 }
        + model.elements.len() * (6 + cell_fields.iter().map(|f| f.components).sum::<usize>());
    let encoding = if values > BINARY_ABOVE_VALUES {
        Encoding::Appended
    } else {
        Encoding::Ascii
    };
    grid_encoded(model, dofs, cell_fields, encoding)
}

/// [`grid`] in the given encoding.
pub fn grid_encoded(
    model: &Model,
    dofs: Option<&[f64]>,
    cell_fields: &[CellField],
    encoding: Encoding,
) -> Vec<u8> {
    // (connectivity, element id, element type, index into model.elements)
    let mut cells: Vec<([usize; 2], i64, i64, Option<usize>)> =
        Vec::with_capacity(model.elements.len());
    for (k, e) in model.elements.iter().enumerate() {
        if let (Some(a), Some(b)) = (model.node_index(e.nodes[0]), model.node_index(e.nodes[1])) {
            cells.push(([a, b], i64::from(e.id), i64::from(e.kind.number()), Some(k)));
        }
    }
    for tie in &model.rigid_ties {
        let Some(r) = model.node_index(tie.reference) else {
            continue;
        };
        for &s in &tie.tied {
            if let Some(s) = model.node_index(s) {
                cells.push(([r, s], -1, 0, None));
            }
        }
    }
    let n_points = model.nodes.len();
    let mut w = Writer {
        xml: String::with_capacity(200 + 120 * n_points + 60 * cells.len()),
        appended: (encoding == Encoding::Appended).then(Vec::new),
    };
    // Writing to a String cannot fail; the results are ignored deliberately.
    let _ = writeln!(w.xml, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        w.xml,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    );
    let _ = writeln!(w.xml, "  <UnstructuredGrid>");
    let _ = writeln!(
        w.xml,
        "    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{}\">",
        cells.len()
    );
    match dofs {
        Some(_) => {
            let _ = writeln!(
                w.xml,
                "      <PointData Scalars=\"node_id\" Vectors=\"displacement_mm\">"
            );
        }
        None => {
            let _ = writeln!(w.xml, "      <PointData Scalars=\"node_id\">");
        }
    }
    w.data_array("node_id", 1, model.nodes.iter().map(|n| i64::from(n.id)));
    if let Some(u) = dofs {
        for (name, offset) in [("displacement_mm", 0), ("rotation_rad", 3)] {
            let values =
                (0..n_points).flat_map(|i| (0..3).map(move |c| u[i * DOFS_PER_NODE + offset + c]));
            w.data_array(name, 3, values);
        }
    }
    let _ = writeln!(w.xml, "      </PointData>");
    let _ = writeln!(w.xml, "      <CellData Scalars=\"element_type\">");
    w.data_array("element_id", 1, cells.iter().map(|c| c.1));
    w.data_array("element_type", 1, cells.iter().map(|c| c.2));
    for field in cell_fields {
        let n = field.components;
        let values = cells.iter().flat_map(|c| {
            (0..n).map(move |j| {
                c.3.and_then(|k| field.values.get(k * n + j).copied())
                    .unwrap_or(0.0)
            })
        });
        w.data_array(&field.name, n, values);
    }
    let _ = writeln!(w.xml, "      </CellData>");
    let _ = writeln!(w.xml, "      <Points>");
    w.data_array("coordinates_mm", 3, model.nodes.iter().flat_map(|n| n.xyz));
    let _ = writeln!(w.xml, "      </Points>");
    let _ = writeln!(w.xml, "      <Cells>");
    w.data_array(
        "connectivity",
        1,
        cells.iter().flat_map(|c| c.0.map(|i| i as i64)),
    );
    w.data_array("offsets", 1, (1..=cells.len() as i64).map(|k| 2 * k));
    w.data_array("types", 1, cells.iter().map(|_| VTK_LINE));
    let _ = writeln!(w.xml, "      </Cells>");
    let _ = writeln!(w.xml, "    </Piece>");
    let _ = writeln!(w.xml, "  </UnstructuredGrid>");
    let mut bytes = w.xml.into_bytes();
    if let Some(data) = w.appended {
        bytes.extend_from_slice(b"  <AppendedData encoding=\"raw\">\n   _");
        bytes.extend_from_slice(&data);
        bytes.extend_from_slice(b"\n  </AppendedData>\n");
    }
    bytes.extend_from_slice(b"</VTKFile>\n");
    bytes
}

/// The `.pvd` text of a collection: `(value, file)` pairs, `file` relative to the
/// `.pvd`'s folder. ParaView shows `value` as the time of each entry.
pub fn collection(entries: &[(f64, String)]) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for (value, file) in entries {
        let value = if value.is_finite() { *value } else { 0.0 };
        let _ = writeln!(
            out,
            "    <DataSet timestep=\"{value:e}\" part=\"0\" file=\"{}\"/>",
            xml_escape(file)
        );
    }
    out.push_str("  </Collection>\n</VTKFile>\n");
    out
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The XML text and, for [`Encoding::Appended`], the binary block after it.
struct Writer {
    xml: String,
    appended: Option<Vec<u8>>,
}

impl Writer {
    /// A `DataArray` of numbers written straight into the output (no per-value
    /// allocation): ASCII floats in shortest round-trip scientific notation, non-finite
    /// ones (never expected) as 0 so that the file stays readable.
    fn data_array<T: Number>(
        &mut self,
        name: &str,
        components: usize,
        values: impl Iterator<Item = T>,
    ) {
        let head = format!(
            "        <DataArray type=\"{}\" Name=\"{name}\" NumberOfComponents=\"{components}\"",
            T::VTK_TYPE
        );
        self.xml.push_str(&head);
        if let Some(data) = &mut self.appended {
            let _ = writeln!(self.xml, " format=\"appended\" offset=\"{}\"/>", data.len());
            let header = data.len();
            data.extend_from_slice(&0u64.to_le_bytes());
            for v in values {
                v.write_le(data);
            }
            let bytes = (data.len() - header - 8) as u64;
            data[header..header + 8].copy_from_slice(&bytes.to_le_bytes());
            return;
        }
        self.xml.push_str(" format=\"ascii\">\n          ");
        for (k, v) in values.enumerate() {
            if k > 0 {
                self.xml.push(if k % (6 * components.max(1)) == 0 {
                    '\n'
                } else {
                    ' '
                });
            }
            v.write_to(&mut self.xml);
        }
        self.xml.push_str("\n        </DataArray>\n");
    }
}

/// Numbers a `DataArray` can hold.
trait Number: Copy {
    const VTK_TYPE: &'static str;
    fn write_to(self, out: &mut String);
    fn write_le(self, out: &mut Vec<u8>);
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
    fn write_le(self, out: &mut Vec<u8>) {
        let v = if self.is_finite() { self } else { 0.0 };
        out.extend_from_slice(&v.to_le_bytes());
    }
}

impl Number for i64 {
    const VTK_TYPE: &'static str = "Int64";
    fn write_to(self, out: &mut String) {
        let _ = write!(out, "{self}");
    }
    fn write_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Number for u8 {
    const VTK_TYPE: &'static str = "UInt8";
    fn write_to(self, out: &mut String) {
        let _ = write!(out, "{self}");
    }
    fn write_le(self, out: &mut Vec<u8>) {
        out.push(self);
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
        let text = String::from_utf8(unstructured_grid(&model, Some(&u))).unwrap();
        assert!(text.contains("NumberOfPoints=\"5\" NumberOfCells=\"4\""));
        assert!(text.contains("Name=\"displacement_mm\" NumberOfComponents=\"3\""));
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
        let plain = String::from_utf8(unstructured_grid(&model, None)).unwrap();
        assert!(!plain.contains("displacement"));
        assert_eq!(
            text.matches("<DataArray").count(),
            text.matches("</DataArray>").count()
        );
    }

    /// Reads an appended array back: the XML names its offset, the block holds a u64
    /// byte count then the little-endian values.
    fn appended_f64(bytes: &[u8], name: &str) -> Vec<f64> {
        let text = String::from_utf8_lossy(bytes);
        let start = text.find(&format!("Name=\"{name}\"")).unwrap();
        let tail = &text[start..];
        let offset: usize = tail[tail.find("offset=\"").unwrap() + 8..]
            .split('"')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        let marker = bytes.windows(2).position(|w| w == b" _").unwrap() + 2;
        let at = marker + offset;
        let n = u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize;
        bytes[at + 8..at + 8 + n]
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    #[test]
    fn appended_binary_holds_the_same_numbers() {
        let model = tied_frame();
        let u: Vec<f64> = (0..model.dof_count()).map(|i| i as f64 * 0.5).collect();
        let field = CellField {
            name: "torque_n_mm".to_string(),
            components: 1,
            values: vec![1.5, -2.0, 3.25],
        };
        let bytes = grid_encoded(&model, Some(&u), &[field], Encoding::Appended);
        assert!(bytes.ends_with(b"</AppendedData>\n</VTKFile>\n"));
        let d = appended_f64(&bytes, "displacement_mm");
        assert_eq!(d.len(), 15);
        assert_eq!(&d[9..12], &[9.0, 9.5, 10.0]);
        // Three beams then the tie cell, which gets zero.
        assert_eq!(appended_f64(&bytes, "torque_n_mm"), [1.5, -2.0, 3.25, 0.0]);
        let coords = appended_f64(&bytes, "coordinates_mm");
        let expected: Vec<f64> = model.nodes.iter().flat_map(|n| n.xyz).collect();
        assert_eq!(coords, expected);
    }

    #[test]
    fn collection_lists_files_with_their_values() {
        let text = collection(&[
            (4.3387, "case2_mode1.vtu".to_string()),
            (9.5, "a&b.vtu".to_string()),
        ]);
        assert!(
            text.contains("<DataSet timestep=\"4.3387e0\" part=\"0\" file=\"case2_mode1.vtu\"/>")
        );
        assert!(text.contains("file=\"a&amp;b.vtu\""));
        assert!(text.contains("type=\"Collection\""));
    }
}
