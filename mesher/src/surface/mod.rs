//! Closed triangulated surfaces: the input S of the mesher (paper §2, §4).
//!
//! A [`Surface`] is indexed (shared vertices, triangles as index triples). Readers in
//! [`crate::io`] produce it; `check` reports every defect that would stop the boundary
//! mesh (open, non-manifold, self-intersecting, degenerate input).

use crate::geom::Point;

/// An indexed triangulated surface.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surface {
    /// Vertex coordinates.
    pub vertices: Vec<Point>,
    /// Triangles as 0-based vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

pub mod generate;
