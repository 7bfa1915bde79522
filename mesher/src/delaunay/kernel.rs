//! Point insertion: the Delaunay kernel `T = T - C(P) + B(P)` of the paper (§3), with
//! the Bowyer-Watson cavity grown by adjacency.
//!
//! - Location: visibility walk with a randomised order of the faces tried (Devillers,
//!   Pion, Teillaud, "Walking in a triangulation", IJFCS 2002), started from the last
//!   created tet; bounded, with an exhaustive scan as the fallback.
//! - Cavity `C(P)`: breadth-first over neighbours, each tet marked in/out once per
//!   insertion (the marks are cleared from the cavity and boundary lists afterwards).
//!   A finite tet is in conflict when `P` is inside its circumsphere (perturbed predicate: ties never occur); a ghost tet
//!   `(a, b, c, GHOST)` when `P` is strictly beyond the hull face `(a, b, c)`, or on its
//!   plane and in conflict with the finite tet behind it (whose circumsphere cuts that
//!   plane in the circumcircle of the face).
//! - Ball `B(P)`: each cavity boundary face makes a new tet by putting `P` in place of the
//!   cavity tet's vertex opposite that face, which keeps the orientation because the
//!   cavity is star-shaped. Inner adjacencies are paired through a small matrix indexed
//!   by per-insertion local vertex ids (HXT's scheme), with a hash map for huge cavities;
//!   the local ids sit in a per-vertex table tagged by insertion, so nothing is cleared
//!   between insertions (against a hash table cleared per insertion: uniform points
//!   -11 to -13 %, the 10k icosphere -16 %, armadillo's vertices -6 %, criterion).

use super::DelaunayError;
use crate::geom::predicates::{orient3d, Orientation, Sphere, StaticFilter};
use crate::geom::Point;
use crate::tetmesh::{FaceRef, TetId, TetMesh, VertexId, FACE_VERTICES};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

mod constrained;
pub use constrained::{Constraints, Rejection};

const GHOST: u32 = VertexId::GHOST.0;
/// Local ids available in the pairing matrix (id 0 is the ghost vertex). Points on the
/// flat parts of a CAD surface make cavities of a hundred tets or more (fandisk's
/// Delaunay mesh of its 6475 vertices: 322 cavities past 63 boundary vertices, paired
/// through the hash map after a failed first try): at 128 its T(S,F) Delaunay step
/// takes 0.059 -> 0.046 s (medians of 7), the same meshes.
const LOCAL_IDS: usize = 128;
/// Bits of a local id in the per-vertex table (`LOCAL_IDS == 1 << LOCAL_BITS`).
const LOCAL_BITS: u32 = 7;
/// Entries of the pairing matrix.
const PAIRS: usize = LOCAL_IDS * LOCAL_IDS;
/// Mark of a tet in the cavity.
const IN: u8 = 1;
/// Mark of a tet tested and found outside the cavity.
const OUT: u8 = 2;

/// Where a point lies in the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// In the closed finite tet.
    InTet(TetId),
    /// Outside the hull, strictly beyond the hull face of this ghost tet.
    Outside(TetId),
    /// Exactly on an existing vertex.
    OnVertex(VertexId),
}

/// One face of the cavity boundary and the tet it will produce.
#[derive(Clone, Copy, Debug)]
struct BoundaryFace {
    /// The new tet's vertices (the cavity tet's with the new point at `slot`).
    verts: [u32; 4],
    /// Slot of the new point.
    slot: u8,
    /// The tet outside the cavity across this face.
    outer: FaceRef,
}

/// Counters of the kernel, cheap enough to keep always on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KernelStats {
    /// Points inserted.
    pub inserted: u64,
    /// Points found on an existing vertex.
    pub duplicates: u64,
    /// Tets visited by walks.
    pub walk_steps: u64,
    /// Walks that hit the step bound and fell back to a scan.
    pub walk_fallbacks: u64,
    /// Tets removed by cavities.
    pub cavity_tets: u64,
    /// Cavities too large for the pairing matrix.
    pub large_cavities: u64,
}

/// The insertion engine: per-tet marks and scratch buffers reused by every insertion,
/// so an insertion allocates nothing.
#[derive(Debug, Default)]
pub struct Kernel {
    /// Per tet slot: [`IN`], [`OUT`] or 0; non-zero only during an insertion.
    marks: Vec<u8>,
    /// Per vertex: the stamp of the last insertion whose cavity boundary held it (high
    /// bits) and its local id there (low [`LOCAL_BITS`]).
    vertex_local: Vec<u32>,
    local_stamp: u32,
    stack: Vec<u32>,
    cavity: Vec<u32>,
    boundary: Vec<BoundaryFace>,
    new_tets: Vec<u32>,
    locals: Vec<[u8; 4]>,
    pairs: Vec<u32>,
    big_pairs: HashMap<(u32, u32), FaceRef, BuildHasherDefault<EdgeHasher>>,
    /// Tets refused by a constrained cavity (marks to clear).
    touched: Vec<u32>,
    /// Mask bits of the outer faces of a constrained cavity.
    outer_bits: Vec<u8>,
    /// Per-vertex stamps of the constrained cavity checks, and their epoch.
    vstamp: Vec<u32>,
    epoch: u32,
    /// Distinct vertices of the constrained cavity's boundary (stamped with `epoch`),
    /// counted as [`Kernel::boundary`] is filled.
    boundary_vertices: usize,
    rng: u64,
    last: u32,
    /// Static filter for the box every vertex lies in ([`StaticFilter::none`] when
    /// unknown); points outside it are tested with the generic filter.
    filter: StaticFilter,
    /// Counters since the kernel was made.
    pub stats: KernelStats,
}

impl Kernel {
    /// A kernel for `mesh`.
    pub fn new() -> Self {
        Kernel {
            pairs: vec![0; PAIRS],
            rng: 0x2545_F491_4F6C_DD1D,
            filter: StaticFilter::none(),
            ..Kernel::default()
        }
    }

    /// Declares that every vertex of the mesh lies in `[min, max]`: enables the static
    /// filter. Inserting a point outside the box is allowed and switches the filter
    /// off for good. The caller must not declare a box that misses a mesh vertex.
    pub fn set_bounds(&mut self, min: Point, max: Point) {
        self.filter = StaticFilter::new(min, max);
    }

    /// [`Kernel::set_bounds`] with a filter made already (e.g.
    /// [`StaticFilter::of_points`] of the mesh's points).
    pub fn set_filter(&mut self, filter: StaticFilter) {
        self.filter = filter;
    }

    /// The static filter if `p` lies in its box, else the generic one (`locate` may be
    /// called for points outside the box without inserting them).
    #[inline]
    fn filter_for(&self, p: Point) -> StaticFilter {
        self.filter.for_point(p)
    }

    /// Sets the tet where the next walk starts.
    pub fn set_hint(&mut self, t: TetId) {
        self.last = t.0;
    }

    #[inline]
    fn next_rand(&mut self) -> u32 {
        // xorshift64: only used to vary the order of faces tried by the walk.
        self.rng ^= self.rng << 13;
        self.rng ^= self.rng >> 7;
        self.rng ^= self.rng << 17;
        (self.rng >> 32) as u32
    }

    /// Locates `p`, walking from the hint.
    pub fn locate(&mut self, mesh: &TetMesh, p: Point) -> Location {
        let mut t = self.last;
        if t as usize >= mesh.num_slots() || !mesh.is_alive(TetId(t)) {
            t = mesh.tets().next().map_or(0, |t| t.0);
        }
        if mesh.is_ghost(TetId(t)) {
            t = FaceRef::from_raw(mesh.raw_adj(t)[3]).tet().0;
        }
        let bound = 64 + 4 * mesh.num_slots() as u64;
        let filter = self.filter_for(p);
        let mut came = 4usize;
        let mut steps = 0u64;
        'walk: while steps < bound {
            steps += 1;
            let v = mesh.raw_tet(t);
            mesh.prefetch_neighbors(t);
            let q = [
                pt(mesh, v[0]),
                pt(mesh, v[1]),
                pt(mesh, v[2]),
                pt(mesh, v[3]),
            ];
            let r = self.next_rand() as usize;
            for k in 0..4 {
                let i = (r + k) & 3;
                if i == came {
                    continue;
                }
                // Vertex i is on the positive side of its face: crossing when p is on
                // the negative side.
                let f = FACE_VERTICES[i];
                if filter.orient3d(q[f[0]], q[f[1]], q[f[2]], p) == Orientation::Negative {
                    let f = FaceRef::from_raw(mesh.raw_adj(t)[i]);
                    t = f.tet().0;
                    came = f.facet();
                    if mesh.is_ghost(TetId(t)) {
                        self.stats.walk_steps += steps;
                        return Location::Outside(TetId(t));
                    }
                    continue 'walk;
                }
            }
            self.stats.walk_steps += steps;
            return on_vertex(&q, &v, p).unwrap_or(Location::InTet(TetId(t)));
        }
        self.stats.walk_steps += steps;
        self.stats.walk_fallbacks += 1;
        locate_by_scan(mesh, p)
    }

    /// [`Kernel::locate`], and the next walk starts where this one ended (a sequence of
    /// nearby queries, each a few steps).
    pub fn locate_next(&mut self, mesh: &TetMesh, p: Point) -> Location {
        let at = self.locate(mesh, p);
        if let Location::InTet(t) | Location::Outside(t) = at {
            self.last = t.0;
        }
        at
    }

    /// Inserts `p`: a new vertex, or the existing vertex at the same coordinates. A
    /// non-finite point or one beyond [`super::MAX_COORDINATE`] is refused (its index in
    /// the error is the vertex it would have been), leaving the mesh unchanged.
    pub fn insert(&mut self, mesh: &mut TetMesh, p: Point) -> Result<Inserted, DelaunayError> {
        super::check_point(mesh.num_vertices(), p)?;
        if !self.filter.contains(p) {
            // A vertex outside the declared box voids the static bounds for good.
            self.filter = StaticFilter::none();
        }
        let start = match self.locate(mesh, p) {
            Location::OnVertex(v) => {
                self.stats.duplicates += 1;
                return Ok(Inserted::Duplicate(v));
            }
            Location::InTet(t) | Location::Outside(t) => t.0,
        };
        self.grow_cavity(mesh, p, start);
        let v = mesh.push_vertex(p);
        self.fill_cavity(mesh, v.0)?;
        self.stats.inserted += 1;
        Ok(Inserted::New(v))
    }

    fn ensure_marks(&mut self, mesh: &TetMesh) {
        if self.marks.len() < mesh.num_slots() {
            self.marks.resize(mesh.num_slots().max(1024) * 5 / 4, 0);
        }
    }

    /// Collects the conflict region of `p` from `start` (which must be in conflict) and
    /// its boundary faces.
    fn grow_cavity(&mut self, mesh: &TetMesh, p: Point, start: u32) {
        self.ensure_marks(mesh);
        let filter = self.filter_for(p);
        self.cavity.clear();
        self.boundary.clear();
        self.stack.clear();
        self.marks[start as usize] = IN;
        self.stack.push(start);
        self.cavity.push(start);
        while let Some(c) = self.stack.pop() {
            let adj = mesh.raw_adj(c);
            for (i, &a) in adj.iter().enumerate() {
                let f = FaceRef::from_raw(a);
                let u = f.tet().0;
                let s = self.marks[u as usize];
                if s == IN {
                    continue;
                }
                if s != OUT && in_conflict(mesh, &filter, u, p) {
                    mesh.prefetch_neighbors(u);
                    self.marks[u as usize] = IN;
                    self.stack.push(u);
                    self.cavity.push(u);
                    continue;
                }
                self.marks[u as usize] = OUT;
                let mut verts = mesh.raw_tet(c);
                verts[i] = u32::MAX - 2; // placeholder for the new vertex
                self.boundary.push(BoundaryFace {
                    verts,
                    slot: i as u8,
                    outer: f,
                });
            }
        }
        self.stats.cavity_tets += self.cavity.len() as u64;
    }

    /// Replaces the cavity by the ball of vertex `v`.
    fn fill_cavity(&mut self, mesh: &mut TetMesh, v: u32) -> Result<(), DelaunayError> {
        let nb = self.boundary.len();
        let nc = self.cavity.len();
        self.new_tets.clear();
        self.new_tets.extend_from_slice(&self.cavity[..nc.min(nb)]);
        for &t in &self.cavity[nb.min(nc)..] {
            mesh.free_tet(t);
        }
        while self.new_tets.len() < nb {
            let t = mesh.alloc_tet().ok_or(DelaunayError::TooManyTets)?;
            self.new_tets.push(t);
        }
        for &c in &self.cavity {
            self.marks[c as usize] = 0;
        }
        for b in &self.boundary {
            self.marks[b.outer.tet().index()] = 0;
        }
        for k in 0..nb {
            let b = &mut self.boundary[k];
            b.verts[b.slot as usize] = v;
            let t = self.new_tets[k];
            mesh.set_tet(t, b.verts);
            mesh.link(FaceRef::new(TetId(t), b.slot as usize), b.outer);
        }
        self.pair_inner_faces(mesh, v);
        self.last = self.new_tets[0];
        Ok(())
    }

    /// Links the new tets to each other: two new tets share a face `(v, x, y)` exactly
    /// when one lists the directed edge `x -> y` after `v` and the other `y -> x`.
    fn pair_inner_faces(&mut self, mesh: &mut TetMesh, v: u32) {
        let ok = self.assign_local_ids(v);
        let pairs = <&mut [u32; PAIRS]>::try_from(&mut self.pairs[..]);
        let (true, Ok(pairs)) = (ok, pairs) else {
            self.stats.large_cavities += 1;
            self.pair_by_map(mesh, v);
            return;
        };
        // The local ids are below `LOCAL_IDS`: the masks only spare the bound checks.
        let at = |x: u8, y: u8| (x as usize * LOCAL_IDS + y as usize) & (PAIRS - 1);
        for (k, b) in self.boundary.iter().enumerate() {
            let loc = self.locals[k];
            let t = self.new_tets[k];
            for &(j, pa, pb) in &INNER_FACES[b.slot as usize] {
                pairs[at(loc[pa], loc[pb])] = FaceRef::new(TetId(t), j).raw();
            }
        }
        for (k, b) in self.boundary.iter().enumerate() {
            let loc = self.locals[k];
            let t = self.new_tets[k];
            for &(j, pa, pb) in &INNER_FACES[b.slot as usize] {
                let other = pairs[at(loc[pb], loc[pa])];
                mesh.set_adj(t, j, FaceRef::from_raw(other));
            }
        }
    }

    /// Gives every vertex of the cavity boundary a local id (0 for the ghost) and
    /// records them per boundary face in `locals`; false when there are too many. The
    /// ids live in a per-vertex table tagged with the insertion's stamp, so nothing is
    /// cleared between insertions.
    fn assign_local_ids(&mut self, v: u32) -> bool {
        self.local_stamp += 1;
        if self.local_stamp >= 1 << (32 - LOCAL_BITS) {
            self.vertex_local.fill(0);
            self.local_stamp = 1;
        }
        let tag = self.local_stamp << LOCAL_BITS;
        let mask = (1u32 << LOCAL_BITS) - 1;
        self.locals.clear();
        let mut next_local = 1u32;
        for b in &self.boundary {
            let mut loc = [0u8; 4];
            for (s, &x) in b.verts.iter().enumerate() {
                if x == v || x == GHOST {
                    continue;
                }
                let i = x as usize;
                if i >= self.vertex_local.len() {
                    self.vertex_local.resize((i + 1).max(1024) * 5 / 4, 0);
                }
                let e = &mut self.vertex_local[i];
                if *e & !mask != tag {
                    if next_local as usize >= LOCAL_IDS {
                        return false;
                    }
                    *e = tag | next_local;
                    next_local += 1;
                }
                loc[s] = (*e & mask) as u8;
            }
            self.locals.push(loc);
        }
        true
    }

    /// The pairing of [`Self::pair_inner_faces`] through a hash map, for cavities with
    /// more boundary vertices than local ids.
    fn pair_by_map(&mut self, mesh: &mut TetMesh, v: u32) {
        self.big_pairs.clear();
        for k in 0..self.boundary.len() {
            let b = self.boundary[k];
            let t = self.new_tets[k];
            for (j, after) in EDGE_AFTER.iter().enumerate() {
                if j == b.slot as usize {
                    continue;
                }
                let (pa, pb) = after[b.slot as usize];
                let (x, y) = (b.verts[pa], b.verts[pb]);
                debug_assert!(x != v && y != v);
                let here = FaceRef::new(TetId(t), j);
                if let Some(other) = self.big_pairs.remove(&(y, x)) {
                    mesh.link(here, other);
                } else {
                    self.big_pairs.insert((x, y), here);
                }
            }
        }
    }
}

/// What [`Kernel::insert`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Inserted {
    /// A new vertex.
    New(VertexId),
    /// The point coincides with this existing vertex; nothing changed.
    Duplicate(VertexId),
}

impl Inserted {
    /// The vertex at the point.
    pub fn vertex(self) -> VertexId {
        match self {
            Inserted::New(v) | Inserted::Duplicate(v) => v,
        }
    }
}

/// A multiplicative hash for the directed-edge keys of [`Kernel::pair_by_map`] (only
/// lookups and removals: no iteration order is ever used). Huge cavities, such as the
/// first field points' in T(S,F), spent most of their pairing time in SipHash.
#[derive(Default)]
struct EdgeHasher(u64);

impl Hasher for EdgeHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u32(b as u32);
        }
    }
    fn write_u32(&mut self, x: u32) {
        self.0 = (self.0.rotate_left(26) ^ x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

/// `INNER_FACES[s]`: for a new tet whose new vertex is at position `s`, its three
/// faces through that vertex, each as (the position opposite the face, then the
/// positions of the directed edge that follows `s` in the face).
const INNER_FACES: [[(usize, usize, usize); 3]; 4] = inner_faces_table();

const fn inner_faces_table() -> [[(usize, usize, usize); 3]; 4] {
    let after = edge_after_table();
    let mut t = [[(0, 0, 0); 3]; 4];
    let mut s = 0;
    while s < 4 {
        let mut k = 0;
        let mut j = 0;
        while j < 4 {
            if j != s {
                t[s][k] = (j, after[j][s].0, after[j][s].1);
                k += 1;
            }
            j += 1;
        }
        s += 1;
    }
    t
}

/// `EDGE_AFTER[j][s]`: in the oriented face opposite local vertex `j`, the positions of
/// the directed edge that follows position `s` (`s != j`).
const EDGE_AFTER: [[(usize, usize); 4]; 4] = edge_after_table();

const fn edge_after_table() -> [[(usize, usize); 4]; 4] {
    let mut t = [[(0, 0); 4]; 4];
    let mut j = 0;
    while j < 4 {
        let f = FACE_VERTICES[j];
        t[j][f[0]] = (f[1], f[2]);
        t[j][f[1]] = (f[2], f[0]);
        t[j][f[2]] = (f[0], f[1]);
        j += 1;
    }
    t
}

#[inline]
fn pt(mesh: &TetMesh, v: u32) -> Point {
    mesh.point(VertexId(v))
}

/// Is tet `t` in conflict with `p` (see the module doc)? `f` must be valid for `p` and
/// every vertex of the mesh.
#[inline]
fn in_conflict(mesh: &TetMesh, f: &StaticFilter, t: u32, p: Point) -> bool {
    let v = mesh.raw_tet(t);
    if v[3] == GHOST {
        match f.orient3d(pt(mesh, v[0]), pt(mesh, v[1]), pt(mesh, v[2]), p) {
            Orientation::Positive => true,
            Orientation::Negative => false,
            Orientation::Zero => {
                let behind = FaceRef::from_raw(mesh.raw_adj(t)[3]).tet().0;
                in_conflict(mesh, f, behind, p)
            }
        }
    } else {
        let q = [
            pt(mesh, v[0]),
            pt(mesh, v[1]),
            pt(mesh, v[2]),
            pt(mesh, v[3]),
        ];
        f.insphere_perturbed(q[0], q[1], q[2], q[3], p) == Sphere::Inside
    }
}

#[inline]
fn on_vertex(q: &[Point; 4], v: &[u32; 4], p: Point) -> Option<Location> {
    (0..4)
        .find(|&i| q[i] == p)
        .map(|i| Location::OnVertex(VertexId(v[i])))
}

/// Exhaustive location, used only when a walk exceeds its bound.
fn locate_by_scan(mesh: &TetMesh, p: Point) -> Location {
    let mut outside = None;
    for t in mesh.tets() {
        let v = mesh.raw_tet(t.0);
        if v[3] == GHOST {
            let o = orient3d(pt(mesh, v[0]), pt(mesh, v[1]), pt(mesh, v[2]), p);
            if o == Orientation::Positive && outside.is_none() {
                outside = Some(t);
            }
            continue;
        }
        let q = [
            pt(mesh, v[0]),
            pt(mesh, v[1]),
            pt(mesh, v[2]),
            pt(mesh, v[3]),
        ];
        let inside = (0..4).all(|i| {
            let mut s = q;
            s[i] = p;
            orient3d(s[0], s[1], s[2], s[3]) != Orientation::Negative
        });
        if inside {
            return on_vertex(&q, &v, p).unwrap_or(Location::InTet(t));
        }
    }
    // A point is either in a finite tet or beyond some hull face.
    Location::Outside(outside.unwrap_or(TetId(0)))
}
