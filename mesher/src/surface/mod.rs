//! Closed triangulated surfaces: the input S of the mesher (paper §2, §4).
//!
//! A [`Surface`] is indexed (shared vertices, triangles as index triples). Readers in
//! [`crate::io`] produce it; [`Surface::check`] reports every defect that would stop the
//! boundary mesh (open, non-manifold, self-intersecting, degenerate input) in a
//! [`CheckReport`].
//!
//! Public API: [`Surface::check`] -> [`CheckReport`] (`is_clean`, `num_defects`,
//! `num_bodies`, `Display` for people, `Serialize` for machines);
//! [`Surface::reoriented`] for a closed surface whose faces disagree in orientation;
//! [`Surface::faces_intersect`] for one pair of faces; [`intersect::triangles_intersect`]
//! and [`intersect::is_collinear`] on bare points.
//!
//! Submodules: `check` (entry point, self-intersections), `topology` (indices, edges,
//! fans), [`intersect`] (exact triangle-triangle test), `bvh` (box hierarchy), `shells`
//! (components and nesting), `orient` (consistent orientation), [`report`] (the report
//! types and their display).

pub(crate) mod bvh;
mod check;
pub mod intersect;
mod orient;
pub mod report;
mod shells;
mod topology;

pub use report::CheckReport;
pub(crate) use topology::{faces_by_vertex, sorted_ids};

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
