//! Building a [`TetMesh`] from a list of tets: faces are matched by their sorted vertex
//! triples, and every unmatched (hull) face gets a ghost tet.

use super::{FaceRef, TetId, TetMesh, VertexId, FACE_VERTICES};
use crate::geom::Point;
use thiserror::Error;

/// Why a list of tets is not a valid mesh.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum BuildError {
    /// A tet refers to a vertex that does not exist.
    #[error("tet {tet} refers to vertex {vertex}, but there are {count} vertices")]
    VertexOutOfRange {
        /// The tet.
        tet: usize,
        /// The vertex id.
        vertex: u32,
        /// The number of vertices.
        count: usize,
    },
    /// A tet repeats a vertex.
    #[error("tet {tet} repeats a vertex")]
    RepeatedVertex {
        /// The tet.
        tet: usize,
    },
    /// A face is shared by more than two tets.
    #[error("face {face:?} is shared by more than two tets")]
    NonManifoldFace {
        /// The sorted vertex ids of the face.
        face: [u32; 3],
    },
    /// More tets than [`super::MAX_TETS`].
    #[error("too many tets")]
    TooManyTets,
}

impl TetMesh {
    /// A mesh from vertices and positively oriented tets; hull faces get ghost tets.
    /// Orientation is the caller's duty ([`TetMesh::validate`] checks it).
    pub fn from_tets(points: Vec<Point>, tets: &[[u32; 4]]) -> Result<TetMesh, BuildError> {
        let n = points.len();
        let mut mesh = TetMesh::with_capacity(n, tets.len() * 2);
        mesh.points = points;
        for (k, t) in tets.iter().enumerate() {
            if let Some(&bad) = t.iter().find(|&&v| v as usize >= n) {
                return Err(BuildError::VertexOutOfRange {
                    tet: k,
                    vertex: bad,
                    count: n,
                });
            }
            if (0..4).any(|i| (i + 1..4).any(|j| t[i] == t[j])) {
                return Err(BuildError::RepeatedVertex { tet: k });
            }
            let s = mesh.alloc_tet().ok_or(BuildError::TooManyTets)?;
            mesh.set_tet(s, *t);
        }
        let hull = link_faces(&mut mesh, 0..tets.len() as u32, |i| i < 4)?;
        let first_ghost = mesh.num_slots() as u32;
        for f in hull {
            let v = mesh.raw_tet(f.tet().0);
            let fv = FACE_VERTICES[f.facet()];
            let g = mesh.alloc_tet().ok_or(BuildError::TooManyTets)?;
            mesh.set_tet(g, [v[fv[0]], v[fv[2]], v[fv[1]], VertexId::GHOST.0]);
            mesh.link(FaceRef::new(TetId(g), 3), f);
        }
        let end = mesh.num_slots() as u32;
        link_faces(&mut mesh, first_ghost..end, |i| i < 3)?;
        Ok(mesh)
    }
}

/// Pairs the faces (selected by `facet`) of the tets in `range` that share vertices;
/// returns the faces left unmatched.
fn link_faces(
    mesh: &mut TetMesh,
    range: std::ops::Range<u32>,
    facet: impl Fn(usize) -> bool,
) -> Result<Vec<FaceRef>, BuildError> {
    let mut faces: Vec<([u32; 3], FaceRef)> = Vec::with_capacity(range.len() * 4);
    for t in range {
        let v = mesh.raw_tet(t);
        for (i, fv) in FACE_VERTICES.iter().enumerate() {
            if !facet(i) {
                continue;
            }
            let mut key = [v[fv[0]], v[fv[1]], v[fv[2]]];
            key.sort_unstable();
            faces.push((key, FaceRef::new(TetId(t), i)));
        }
    }
    faces.sort_unstable_by_key(|f| (f.0, f.1.raw()));
    let mut unmatched = Vec::new();
    let mut k = 0;
    while k < faces.len() {
        let same = faces[k..].iter().take_while(|f| f.0 == faces[k].0).count();
        match same {
            1 => unmatched.push(faces[k].1),
            2 => mesh.link(faces[k].1, faces[k + 1].1),
            _ => return Err(BuildError::NonManifoldFace { face: faces[k].0 }),
        }
        k += same;
    }
    Ok(unmatched)
}
