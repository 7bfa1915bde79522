//! The tetrahedral mesh: flat arrays, typed `u32` ids, a ghost vertex for the outside.
//!
//! Layout (after Geogram and HXT, see `shared/design/fast-kernel-and-optimization.md`):
//! per tet four vertex ids (`verts`) and four packed neighbour handles (`adj`), where
//! neighbour `i` is the tet across the face opposite vertex `i` and a handle is
//! `(tet << 2) | facet`, so the back-pointer is free. The outside of the convex hull is
//! covered by *ghost* tets whose slot 3 holds [`VertexId::GHOST`]; every face of the
//! mesh therefore has exactly two tets. Deleted slots are kept on a free list and reused.
//!
//! Orientation: every finite tet `(a, b, c, d)` has positive signed volume. A ghost tet
//! `(a, b, c, GHOST)` has the hull face `(a, b, c)` oriented so that points strictly
//! outside the hull across that face see it positively (`orient3d(a, b, c, x) > 0`).
//!
//! This module knows no geometry beyond the coordinates it is handed; the only
//! predicates it evaluates are in [`TetMesh::validate`].

mod build;
mod validate;

pub use build::BuildError;
pub use validate::ValidationError;

use crate::geom::Point;
use crate::volume::VolumeMesh;

/// Id of a vertex. [`VertexId::GHOST`] is the vertex at infinity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VertexId(pub u32);

impl VertexId {
    /// The vertex at infinity, apex of every ghost tet.
    pub const GHOST: VertexId = VertexId(u32::MAX);

    /// True for the ghost vertex.
    #[inline]
    pub fn is_ghost(self) -> bool {
        self == Self::GHOST
    }

    /// The id as an index into per-vertex arrays (meaningless for the ghost).
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Id of a tet slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TetId(pub u32);

impl TetId {
    /// The id as an index into per-tet arrays.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A face seen from one of its two tets: the face opposite vertex `facet` of `tet`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FaceRef(u32);

impl FaceRef {
    /// Packs `(tet, facet)`; `facet < 4`.
    #[inline]
    pub fn new(tet: TetId, facet: usize) -> Self {
        debug_assert!(facet < 4 && tet.0 < MAX_TETS);
        FaceRef((tet.0 << 2) | facet as u32)
    }

    /// The tet.
    #[inline]
    pub fn tet(self) -> TetId {
        TetId(self.0 >> 2)
    }

    /// The packed form `(tet << 2) | facet`.
    #[inline]
    pub fn raw(self) -> u32 {
        self.0
    }

    /// From the packed form.
    #[inline]
    pub fn from_raw(r: u32) -> Self {
        FaceRef(r)
    }

    /// The local index of the vertex opposite the face.
    #[inline]
    pub fn facet(self) -> usize {
        (self.0 & 3) as usize
    }
}

/// The largest number of tet slots (ids are packed with a 2-bit facet into a `u32`).
pub const MAX_TETS: u32 = 1 << 30;

/// Vertex slot value of a deleted tet (internal).
const DEAD: u32 = u32::MAX - 1;

/// For each local facet `i`, the three other local vertices, ordered so that vertex `i`
/// lies on the positive side: `orient3d(v[F[i][0]], v[F[i][1]], v[F[i][2]], v[i]) > 0`.
/// The two tets of a face therefore list it in opposite cyclic orders.
pub const FACE_VERTICES: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];

/// The tet mesh. See the module documentation for the invariants.
#[derive(Clone, Debug, Default)]
pub struct TetMesh {
    points: Vec<Point>,
    cells: Vec<Cell>,
    free: Vec<u32>,
}

/// One tet slot: vertices and neighbour handles in one 32-byte aligned block, so a tet
/// visited by a walk or a cavity costs one cache line.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Cell {
    v: [u32; 4],
    n: [u32; 4],
}

impl TetMesh {
    /// An empty mesh with room for `vertices` vertices and `tets` tets.
    pub fn with_capacity(vertices: usize, tets: usize) -> Self {
        TetMesh {
            points: Vec::with_capacity(vertices),
            cells: Vec::with_capacity(tets),
            free: Vec::new(),
        }
    }

    /// Adds an isolated vertex (not yet part of any tet).
    pub fn push_vertex(&mut self, p: Point) -> VertexId {
        self.points.push(p);
        VertexId(self.points.len() as u32 - 1)
    }

    /// Moves vertex `v` (the caller checks that its tets stay positive).
    pub(crate) fn set_point(&mut self, v: VertexId, p: Point) {
        self.points[v.index()] = p;
    }

    /// Removes the last vertex, which no tet may use (undoing a refused Steiner point).
    pub(crate) fn pop_vertex(&mut self) {
        self.points.pop();
    }

    /// Number of vertices (ghost excluded).
    #[inline]
    pub fn num_vertices(&self) -> usize {
        self.points.len()
    }

    /// Coordinates of a finite vertex.
    #[inline]
    pub fn point(&self, v: VertexId) -> Point {
        self.points[v.index()]
    }

    /// All vertex coordinates, indexed by [`VertexId`].
    #[inline]
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// Number of tet slots, live or free.
    #[inline]
    pub fn num_slots(&self) -> usize {
        self.cells.len()
    }

    /// True when slot `t` holds a live tet.
    #[inline]
    pub fn is_alive(&self, t: TetId) -> bool {
        self.cells[t.index()].v[0] != DEAD
    }

    /// True when `t` is a ghost tet (its slot 3 is the ghost vertex).
    #[inline]
    pub fn is_ghost(&self, t: TetId) -> bool {
        self.cells[t.index()].v[3] == VertexId::GHOST.0
    }

    /// The four vertices of `t`.
    #[inline]
    pub fn tet(&self, t: TetId) -> [VertexId; 4] {
        let v = self.cells[t.index()].v;
        [
            VertexId(v[0]),
            VertexId(v[1]),
            VertexId(v[2]),
            VertexId(v[3]),
        ]
    }

    /// The tet across the face opposite vertex `i` of `t`, seen from that tet.
    #[inline]
    pub fn neighbor(&self, t: TetId, i: usize) -> FaceRef {
        FaceRef(self.cells[t.index()].n[i])
    }

    /// Live tets, ghosts included.
    pub fn tets(&self) -> impl Iterator<Item = TetId> + '_ {
        (0..self.cells.len() as u32)
            .map(TetId)
            .filter(move |&t| self.is_alive(t))
    }

    /// Live finite tets.
    pub fn finite_tets(&self) -> impl Iterator<Item = TetId> + '_ {
        self.tets().filter(move |&t| !self.is_ghost(t))
    }

    /// Number of live finite tets (a full scan).
    pub fn num_finite_tets(&self) -> usize {
        self.finite_tets().count()
    }

    /// The four corner points of a finite tet.
    #[inline]
    pub fn tet_points(&self, t: TetId) -> [Point; 4] {
        let v = self.cells[t.index()].v;
        [
            self.points[v[0] as usize],
            self.points[v[1] as usize],
            self.points[v[2] as usize],
            self.points[v[3] as usize],
        ]
    }

    /// The finite tets and all vertices as an exchange mesh (tets renumbered densely).
    pub fn to_volume_mesh(&self) -> VolumeMesh {
        let tets: Vec<[u32; 4]> = self
            .finite_tets()
            .map(|t| self.cells[t.index()].v)
            .collect();
        VolumeMesh {
            vertices: self.points.clone(),
            tets,
            ..VolumeMesh::default()
        }
    }

    // ---- raw access for the kernel and the mesher stages (crate only) ----

    /// Raw vertex slots of a tet.
    #[inline]
    pub(crate) fn raw_tet(&self, t: u32) -> [u32; 4] {
        self.cells[t as usize].v
    }

    /// Hints the processor to load tet `t` (no effect on other targets).
    #[inline]
    pub(crate) fn prefetch(&self, t: u32) {
        #[cfg(target_arch = "x86_64")]
        if let Some(c) = self.cells.get(t as usize) {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            // SAFETY: a prefetch never faults and SSE is part of the x86_64 baseline.
            unsafe { _mm_prefetch::<_MM_HINT_T0>((c as *const Cell).cast::<i8>()) };
        }
    }

    /// Hints the processor to load the four neighbours of tet `t`: a walk or a cavity
    /// visits one of them next, and its cache line loads during the tests on `t`.
    #[inline]
    pub(crate) fn prefetch_neighbors(&self, t: u32) {
        for a in self.raw_adj(t) {
            self.prefetch(a >> 2);
        }
    }

    /// Raw neighbour handles of a tet.
    #[inline]
    pub(crate) fn raw_adj(&self, t: u32) -> [u32; 4] {
        self.cells[t as usize].n
    }

    /// Overwrites the vertices of slot `t`.
    #[inline]
    pub(crate) fn set_tet(&mut self, t: u32, v: [u32; 4]) {
        self.cells[t as usize].v = v;
    }

    /// Sets the neighbour handle of face `i` of `t` (one side only).
    #[inline]
    pub(crate) fn set_adj(&mut self, t: u32, i: usize, f: FaceRef) {
        self.cells[t as usize].n[i] = f.0;
    }

    /// Makes `a` and `b` neighbours across their faces.
    #[inline]
    pub(crate) fn link(&mut self, a: FaceRef, b: FaceRef) {
        self.cells[a.tet().index()].n[a.facet()] = b.0;
        self.cells[b.tet().index()].n[b.facet()] = a.0;
    }

    /// A fresh slot (from the free list, else appended); `None` past [`MAX_TETS`].
    #[inline]
    pub(crate) fn alloc_tet(&mut self) -> Option<u32> {
        if let Some(t) = self.free.pop() {
            return Some(t);
        }
        let t = self.cells.len() as u32;
        if t >= MAX_TETS {
            return None;
        }
        self.cells.push(Cell {
            v: [DEAD; 4],
            n: [0; 4],
        });
        Some(t)
    }

    /// Marks slot `t` deleted and puts it on the free list.
    #[inline]
    pub(crate) fn free_tet(&mut self, t: u32) {
        self.cells[t as usize].v = [DEAD; 4];
        self.free.push(t);
    }

    /// Reserves room for `additional` more vertices.
    pub fn reserve_vertices(&mut self, additional: usize) {
        self.points.reserve(additional);
    }

    /// Reserves room for `additional` more tets.
    pub fn reserve_tets(&mut self, additional: usize) {
        self.cells.reserve(additional);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_ref_packs() {
        let f = FaceRef::new(TetId(12345), 3);
        assert_eq!(f.tet(), TetId(12345));
        assert_eq!(f.facet(), 3);
    }

    #[test]
    fn face_table_is_positive() {
        use crate::geom::predicates::{orient3d, Orientation};
        let v = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
            Point::new(0.0, 0.0, 1.0),
        ];
        for (i, f) in FACE_VERTICES.iter().enumerate() {
            assert_eq!(
                orient3d(v[f[0]], v[f[1]], v[f[2]], v[i]),
                Orientation::Positive,
                "facet {i}"
            );
        }
    }
}
