//! Consistency check of a [`TetMesh`]: every adjacency and orientation invariant, and
//! optionally the empty-sphere (Delaunay) property. Tests and fuzz targets call it.

use super::{FaceRef, TetId, TetMesh, VertexId, DEAD};
use crate::geom::predicates::{insphere, orient3d, Orientation, Sphere};
use thiserror::Error;

/// The first broken invariant found by [`TetMesh::validate`].
#[derive(Debug, Error, PartialEq)]
pub enum ValidationError {
    /// A vertex id is neither a vertex nor the ghost, or the ghost is not in slot 3.
    #[error("tet {tet}: bad vertex slot {slot} ({vertex})")]
    BadVertex {
        /// The tet.
        tet: u32,
        /// The slot.
        slot: usize,
        /// The raw vertex id.
        vertex: u32,
    },
    /// A tet repeats a vertex.
    #[error("tet {tet}: repeated vertex")]
    RepeatedVertex {
        /// The tet.
        tet: u32,
    },
    /// A neighbour handle points to a dead slot or out of range.
    #[error("tet {tet} facet {facet}: neighbour {neighbor} is not a live tet")]
    DeadNeighbor {
        /// The tet.
        tet: u32,
        /// The facet.
        facet: usize,
        /// The neighbour tet.
        neighbor: u32,
    },
    /// `adj(adj(t, i)) != (t, i)` or the two tets do not share the face's vertices.
    #[error("tet {tet} facet {facet}: adjacency not symmetric or faces differ")]
    Asymmetric {
        /// The tet.
        tet: u32,
        /// The facet.
        facet: usize,
    },
    /// A finite tet is not positively oriented.
    #[error("tet {tet}: orientation {orientation:?}, expected positive")]
    NotPositive {
        /// The tet.
        tet: u32,
        /// What was found.
        orientation: Orientation,
    },
    /// The hull is not convex at a ghost tet.
    #[error("ghost tet {tet}: hull not convex across facet {facet}")]
    NotConvex {
        /// The ghost tet.
        tet: u32,
        /// The facet towards the other ghost.
        facet: usize,
    },
    /// A vertex of a neighbour lies strictly inside the circumsphere of a tet.
    #[error("tet {tet} facet {facet}: opposite vertex inside the circumsphere")]
    NotDelaunay {
        /// The tet.
        tet: u32,
        /// The facet.
        facet: usize,
    },
}

impl TetMesh {
    /// Checks every invariant of the module doc; with `delaunay`, also that no
    /// neighbour's opposite vertex lies strictly inside a tet's circumsphere (local
    /// Delaunay, which implies global Delaunay) and that the hull is convex.
    pub fn validate(&self, delaunay: bool) -> Result<(), ValidationError> {
        for t in 0..self.cells.len() as u32 {
            if self.cells[t as usize].v[0] == DEAD {
                continue;
            }
            self.check_vertices(t)?;
            self.check_adjacency(t)?;
            self.check_orientation(t)?;
            if delaunay {
                self.check_delaunay(t)?;
            }
        }
        Ok(())
    }

    fn check_vertices(&self, t: u32) -> Result<(), ValidationError> {
        let v = self.cells[t as usize].v;
        let n = self.points.len() as u32;
        for (slot, &x) in v.iter().enumerate() {
            let ok = x < n || (slot == 3 && x == VertexId::GHOST.0);
            if !ok {
                return Err(ValidationError::BadVertex {
                    tet: t,
                    slot,
                    vertex: x,
                });
            }
        }
        for i in 0..4 {
            for j in i + 1..4 {
                if v[i] == v[j] {
                    return Err(ValidationError::RepeatedVertex { tet: t });
                }
            }
        }
        Ok(())
    }

    fn check_adjacency(&self, t: u32) -> Result<(), ValidationError> {
        let v = self.cells[t as usize].v;
        for i in 0..4 {
            let f = FaceRef(self.cells[t as usize].n[i]);
            let n = f.tet().0;
            if n as usize >= self.cells.len() || self.cells[n as usize].v[0] == DEAD {
                return Err(ValidationError::DeadNeighbor {
                    tet: t,
                    facet: i,
                    neighbor: n,
                });
            }
            let back = FaceRef(self.cells[n as usize].n[f.facet()]);
            let w = self.cells[n as usize].v;
            let mut mine: Vec<u32> = (0..4).filter(|&k| k != i).map(|k| v[k]).collect();
            let mut theirs: Vec<u32> = (0..4).filter(|&k| k != f.facet()).map(|k| w[k]).collect();
            mine.sort_unstable();
            theirs.sort_unstable();
            if back != FaceRef::new(TetId(t), i) || mine != theirs || v[i] == w[f.facet()] {
                return Err(ValidationError::Asymmetric { tet: t, facet: i });
            }
        }
        Ok(())
    }

    fn check_orientation(&self, t: u32) -> Result<(), ValidationError> {
        if self.is_ghost(TetId(t)) {
            return self.check_convex(t);
        }
        let [a, b, c, d] = self.tet_points(TetId(t));
        match orient3d(a, b, c, d) {
            Orientation::Positive => Ok(()),
            o => Err(ValidationError::NotPositive {
                tet: t,
                orientation: o,
            }),
        }
    }

    /// A ghost's hull face must not see the far vertex of a neighbouring ghost, and its
    /// finite neighbour's apex must lie behind it.
    fn check_convex(&self, t: u32) -> Result<(), ValidationError> {
        let v = self.cells[t as usize].v;
        let p = |x: u32| self.points[x as usize];
        for i in 0..4 {
            let f = FaceRef(self.cells[t as usize].n[i]);
            let w = self.cells[f.tet().index()].v;
            let apex = w[f.facet()];
            if apex == VertexId::GHOST.0 {
                continue;
            }
            let o = orient3d(p(v[0]), p(v[1]), p(v[2]), p(apex));
            let bad = if i == 3 {
                o != Orientation::Negative
            } else {
                o == Orientation::Positive
            };
            if bad {
                return Err(ValidationError::NotConvex { tet: t, facet: i });
            }
        }
        Ok(())
    }

    fn check_delaunay(&self, t: u32) -> Result<(), ValidationError> {
        if self.is_ghost(TetId(t)) {
            return Ok(());
        }
        let [a, b, c, d] = self.tet_points(TetId(t));
        for i in 0..4 {
            let f = FaceRef(self.cells[t as usize].n[i]);
            let apex = self.cells[f.tet().index()].v[f.facet()];
            if apex == VertexId::GHOST.0 {
                continue;
            }
            if insphere(a, b, c, d, self.points[apex as usize]) == Sphere::Inside {
                return Err(ValidationError::NotDelaunay { tet: t, facet: i });
            }
        }
        Ok(())
    }
}
