//! ParaView output (`outputs.vtk: true`), written with the vtkio crate as VTK XML
//! (`.vtu`, unstructured grids, binary base64 data) and, for growth, a `.pvd` collection
//! that steps through the snapshots.
//!
//! Entry points: [`point_cloud`] (nodes or sample points as vertex cells with point data:
//! PD nodes, interior grids, growth snapshots), [`segments`] (BEM elements or crack paths
//! as line cells with cell data), [`pvd`] (the time series). 2-D vectors are written with
//! a zero z component; a plane stress state as the three components (xx, yy, xy).

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

/// Values attached to points or cells.
#[derive(Debug, Clone, PartialEq)]
pub enum Field {
    /// One number each.
    Scalars(Vec<f64>),
    /// A 2-D vector each (written with z = 0).
    Vectors(Vec<[f64; 2]>),
    /// Three components each (a plane stress as xx, yy, xy).
    Triples(Vec<[f64; 3]>),
}

impl Field {
    fn attribute(self, name: &str) -> Attribute {
        let (num_comp, data): (u32, Vec<f64>) = match self {
            Field::Scalars(v) => (1, v),
            Field::Vectors(v) => (3, v.iter().flat_map(|a| [a[0], a[1], 0.0]).collect()),
            Field::Triples(v) => (3, v.iter().flat_map(|a| *a).collect()),
        };
        let elem = if num_comp == 1 {
            ElementType::Scalars {
                num_comp,
                lookup_table: None,
            }
        } else {
            ElementType::Generic(num_comp)
        };
        Attribute::DataArray(DataArray {
            name: name.to_string(),
            elem,
            data: IOBuffer::F64(data),
        })
    }
}

/// A `.vtu` of `points` as vertex cells with the given point data.
pub fn point_cloud(points: &[[f64; 2]], data: Vec<(&str, Field)>) -> Result<Vec<u8>, String> {
    let n = points.len() as u64;
    let cells = Cells {
        cell_verts: VertexNumbers::XML {
            connectivity: (0..n).collect(),
            offsets: (1..=n).collect(),
        },
        types: vec![CellType::Vertex; points.len()],
    };
    let attributes = Attributes {
        point: data.into_iter().map(|(k, f)| f.attribute(k)).collect(),
        cell: Vec::new(),
    };
    to_bytes(flat(points), cells, attributes)
}

/// A `.vtu` of straight segments `(a, b)` as line cells with the given cell data.
pub fn segments(
    ends: &[([f64; 2], [f64; 2])],
    data: Vec<(&str, Field)>,
) -> Result<Vec<u8>, String> {
    let n = ends.len() as u64;
    let points: Vec<[f64; 2]> = ends.iter().flat_map(|(a, b)| [*a, *b]).collect();
    let cells = Cells {
        cell_verts: VertexNumbers::XML {
            connectivity: (0..2 * n).collect(),
            offsets: (1..=n).map(|k| 2 * k).collect(),
        },
        types: vec![CellType::Line; ends.len()],
    };
    let attributes = Attributes {
        point: Vec::new(),
        cell: data.into_iter().map(|(k, f)| f.attribute(k)).collect(),
    };
    to_bytes(flat(&points), cells, attributes)
}

fn flat(points: &[[f64; 2]]) -> Vec<f64> {
    points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect()
}

fn to_bytes(points: Vec<f64>, cells: Cells, data: Attributes) -> Result<Vec<u8>, String> {
    let vtk = Vtk {
        version: Version::new((1, 0)),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(points),
            cells,
            data,
        }),
    };
    let mut out = Vec::new();
    vtk.write_xml(&mut out).map_err(|e| e.to_string())?;
    Ok(out)
}

/// A ParaView collection (`.pvd`) of `(time, file)` entries, files relative to the
/// collection. vtkio writes no collections; the format is four XML elements.
pub fn pvd(entries: &[(f64, String)]) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for (t, f) in entries {
        let f = f
            .replace('&', "&amp;")
            .replace('"', "&quot;")
            .replace('<', "&lt;");
        s.push_str(&format!(
            "    <DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{f}\"/>\n"
        ));
    }
    s.push_str("  </Collection>\n</VTKFile>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_cloud_reads_back() {
        let bytes = point_cloud(
            &[[0.0, 0.0], [1.0, 2.0]],
            vec![
                ("damage", Field::Scalars(vec![0.0, 0.5])),
                ("displacement", Field::Vectors(vec![[1.0, 2.0], [3.0, 4.0]])),
            ],
        )
        .expect("writes");
        let back = Vtk::parse_xml(std::io::BufReader::new(&bytes[..])).expect("reads");
        let DataSet::UnstructuredGrid { pieces, .. } = back.data else {
            panic!("not an unstructured grid")
        };
        let piece = pieces[0].load_piece_data(None).expect("inline piece");
        assert_eq!(
            piece.points.cast_into::<f64>(),
            Some(vec![0.0, 0.0, 0.0, 1.0, 2.0, 0.0])
        );
        let Attribute::DataArray(d) = &piece.data.point[1] else {
            panic!("field")
        };
        assert_eq!(d.name, "displacement");
        assert_eq!(
            d.data.clone().cast_into::<f64>(),
            Some(vec![1.0, 2.0, 0.0, 3.0, 4.0, 0.0])
        );
    }

    #[test]
    fn a_collection_lists_its_files() {
        let p = pvd(&[(0.0, "a.vtu".into()), (1.0, "b.vtu".into())]);
        assert!(
            p.contains("timestep=\"1\"") && p.contains("file=\"b.vtu\""),
            "{p}"
        );
    }
}
