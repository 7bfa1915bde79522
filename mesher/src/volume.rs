//! A plain, geometry-only tetrahedral mesh for exchange: what the writers write, what the
//! readers read back (ours and peers' outputs), and what [`crate::quality`] measures.
//!
//! It is deliberately not the kernel's [`crate::tetmesh::TetMesh`]: no adjacency, no
//! ghost, no free slots; indices are 0-based into `vertices`.

use crate::geom::Point;
use crate::tetmesh::{TetMesh, VertexId};

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
    /// The sum of the signed tet volumes.
    pub fn volume(&self) -> f64 {
        (0..self.tets.len())
            .map(|t| crate::quality::signed_volume(&self.tet_points(t)))
            .sum()
    }

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

/// The domain of a kernel mesh (tets whose region is not 0) as an exchange mesh, and the
/// mesh vertex of each output vertex. The vertices `first` come first, in that order
/// (the input vertices, then the boundary Steiner points), then the others in the order
/// the tets meet them; each tet keeps its region as its reference; `faces` are the
/// boundary triangles (mesh vertex ids, all on the domain).
pub fn export_domain(
    mesh: &TetMesh,
    region: &[u32],
    first: &[VertexId],
    faces: &[[VertexId; 3]],
) -> (VolumeMesh, Vec<VertexId>) {
    let mut index = vec![u32::MAX; mesh.num_vertices()];
    let mut origin: Vec<VertexId> = Vec::with_capacity(mesh.num_vertices());
    for &v in first {
        index[v.index()] = origin.len() as u32;
        origin.push(v);
    }
    let mut tets = Vec::new();
    let mut tet_refs = Vec::new();
    for t in mesh.finite_tets() {
        let r = region.get(t.index()).copied().unwrap_or(0);
        if r == 0 {
            continue;
        }
        tets.push(mesh.tet(t).map(|v| {
            if index[v.index()] == u32::MAX {
                index[v.index()] = origin.len() as u32;
                origin.push(v);
            }
            index[v.index()]
        }));
        tet_refs.push(r as i32);
    }
    let vm = VolumeMesh {
        vertices: origin.iter().map(|&v| mesh.point(v)).collect(),
        tets,
        tet_refs,
        triangles: faces.iter().map(|f| f.map(|v| index[v.index()])).collect(),
        triangle_refs: vec![1; faces.len()],
        vertex_sizes: None,
    };
    (vm, origin)
}
