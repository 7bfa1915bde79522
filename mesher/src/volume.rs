//! A plain, geometry-only tetrahedral mesh for exchange: what the writers write, what the
//! readers read back (ours and peers' outputs), and what [`crate::quality`] measures.
//!
//! It is deliberately not the kernel's [`crate::tetmesh::TetMesh`]: no adjacency, no
//! ghost, no free slots; indices are 0-based into `vertices`.

use crate::geom::Point;

/// A tetrahedral mesh as a list of vertices and tets, with optional boundary triangles,
/// references (region / surface ids) and per-vertex sizes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VolumeMesh {
    /// Vertex coordinates.
    pub vertices: Vec<Point>,
    /// Tetrahedra as 0-based vertex indices, positively oriented when written by us.
    pub tets: Vec<[u32; 4]>,
    /// Region reference per tet (same length as `tets`, or empty).
    pub tet_refs: Vec<i32>,
    /// Boundary triangles (may be empty).
    pub triangles: Vec<[u32; 3]>,
    /// Surface reference per triangle (same length as `triangles`, or empty).
    pub triangle_refs: Vec<i32>,
    /// Target size per vertex (written as a Medit `.sol`), if any.
    pub vertex_sizes: Option<Vec<f64>>,
}

impl VolumeMesh {
    /// The four corner points of tet `t`.
    pub fn tet_points(&self, t: usize) -> [Point; 4] {
        let [a, b, c, d] = self.tets[t];
        [
            self.vertices[a as usize],
            self.vertices[b as usize],
            self.vertices[c as usize],
            self.vertices[d as usize],
        ]
    }
}
