//! Local topology and local re-tetrahedralisation for boundary recovery (paper §4.2).
//!
//! [`Local`] wraps the [`TetMesh`] with a vertex-to-tet map, star and edge-ring queries,
//! and one checked primitive, [`Local::replace`]: a set of tets is replaced by another
//! set covering the same region. Every flip (2-3, 3-2, 4-4, the n-to-2n-4 edge removal)
//! and every star insertion is a `replace`, so the checks live in one place: each new
//! tet must be strictly positive (exact `orient3d`), the new faces must pair up with
//! opposite orientations, and the outer faces must be exactly the old region's outer
//! faces with the same orientation. A rejected `replace` changes nothing.

use crate::geom::predicates::{orient3d, Orientation, StaticFilter};
use crate::geom::Point;
use crate::tetmesh::{FaceRef, TetId, TetMesh, VertexId, FACE_VERTICES};
use crate::FastMap as HashMap;

mod marks;
mod stamps;
mod triangles;

pub(crate) use marks::Marks;
pub(crate) use stamps::Stamps;
use triangles::TrianglesByMin;

pub(crate) const GHOST: u32 = VertexId::GHOST.0;

/// Why a local change was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Refused {
    /// A new tet is flat or inverted.
    NotPositive,
    /// The new tets do not close up with the old region's boundary.
    Mismatch,
    /// The change touches a ghost tet (the box hull).
    Hull,
    /// Out of tet ids.
    Full,
}

/// For the positions `ia != ib` of an edge's ends `a`, `b` in a tet `v`, the other two
/// positions `[ip, iq]` ordered so that `(ia, ib, ip, iq)` is an even permutation of
/// `(0, 1, 2, 3)`: `(a, b, v[ip], v[iq])` is then positive when the tet is (test
/// `the_ring_order_keeps_the_tets_orientation`). The diagonal is unused.
const RING_ORDER: [[[u8; 2]; 4]; 4] = [
    [[0, 0], [2, 3], [3, 1], [1, 2]],
    [[3, 2], [0, 0], [0, 3], [2, 0]],
    [[1, 3], [3, 0], [0, 0], [0, 1]],
    [[2, 1], [0, 2], [1, 0], [0, 0]],
];

/// The mesh with a vertex-to-tet map, kept valid by every change made through it.
#[derive(Debug)]
pub(crate) struct Local {
    pub mesh: TetMesh,
    /// For each vertex, a live tet that has it (`u32::MAX` before it is in a tet).
    v2t: Vec<u32>,
    /// Tets created by the last successful [`Local::replace`].
    pub created: Vec<u32>,
    /// Undo log of the changes since [`Local::mark`].
    journal: Journal,
    journaling: bool,
    /// Validate the whole mesh after every change (`MESHER_VALIDATE_OPS` set; slow).
    validate_ops: bool,
    /// Per tet slot: the visit number of the last search that saw it.
    seen: std::cell::RefCell<Vec<u32>>,
    visit: std::cell::Cell<u32>,
    /// When the tets at each vertex last changed.
    pub stamps: Stamps,
    /// Scratch space of [`Local::replace`].
    pairing: Pairing,
    /// Scratch space of [`Local::undo`]: one change taken off the journal.
    undone: Undone,
    /// A static filter for [`Local::orient`] over the box of the first `filtered`
    /// vertices (rebuilt with the vertex-to-tet map; later vertices take the
    /// semi-static filter).
    filter: StaticFilter,
    filtered: u32,
}

/// Scratch space of [`Local::replace`]: a small open-addressing table of the faces
/// met (the old region's outer faces, then the new tets' faces), keyed by their sorted
/// vertices, and the links.
#[derive(Debug, Default)]
struct Pairing {
    /// Per slot: 0 when empty, else 1 + the index of its entry in `entries`.
    table: Vec<u32>,
    entries: Vec<PairEntry>,
    links: Vec<(usize, usize, Link)>,
    /// Tet slots of the change being committed.
    ids: Vec<u32>,
}

/// A face of [`Pairing`]'s table: its key, its parity, what it is, and whether it
/// has been paired.
#[derive(Clone, Copy, Debug)]
struct PairEntry {
    key: u128,
    even: bool,
    face: PairFace,
    paired: bool,
}

#[derive(Clone, Copy, Debug)]
enum PairFace {
    /// An outer face of the old region, with the tet outside it.
    Outer(FaceRef),
    /// Face `i` of new tet `k`.
    New(u32, u8),
}

impl Pairing {
    /// Empties the table, with room for `n` faces.
    fn reset(&mut self, n: usize) {
        let cap = (2 * n).next_power_of_two().max(64);
        self.table.clear();
        self.table.resize(cap, 0);
        self.entries.clear();
        self.links.clear();
    }

    /// The slot of `key`: its entry's, or the empty one where it would go.
    fn slot(&self, key: u128) -> usize {
        let mask = self.table.len() - 1;
        let h = ((key as u64) ^ ((key >> 64) as u64).rotate_left(29))
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let mut i = (h >> 40) as usize & mask;
        loop {
            match self.table[i] {
                0 => return i,
                e if self.entries[e as usize - 1].key == key => return i,
                _ => i = (i + 1) & mask,
            }
        }
    }

    fn put(&mut self, slot: usize, entry: PairEntry) {
        self.entries.push(entry);
        self.table[slot] = self.entries.len() as u32;
    }
}

/// The undo log: per journalled change, the tets it created, the tets it replaced,
/// and the stamps it overwrote (vertex, stamp), so that an undone change leaves no
/// stamp. Flat lists with one end offset per change (no allocation per change: most
/// changes are tried and undone).
#[derive(Debug, Default)]
struct Journal {
    /// Per change: the ends of its entries in `created`, `replaced` (and `adj`) and
    /// `stamps`.
    ends: Vec<(u32, u32, u32)>,
    created: Vec<u32>,
    replaced: Vec<[u32; 4]>,
    /// The neighbours of the replaced tets then (raw face handles).
    adj: Vec<[u32; 4]>,
    stamps: Vec<(u32, u32)>,
}

impl Journal {
    fn len(&self) -> usize {
        self.ends.len()
    }

    fn clear(&mut self) {
        self.ends.clear();
        self.created.clear();
        self.replaced.clear();
        self.adj.clear();
        self.stamps.clear();
    }

    /// Closes the entries pushed since the previous change as one change.
    fn seal(&mut self) {
        let n = |v: usize| v as u32;
        self.ends.push((
            n(self.created.len()),
            n(self.replaced.len()),
            n(self.stamps.len()),
        ));
    }

    /// Removes the newest change into `out`.
    fn pop_into(&mut self, out: &mut Undone) -> bool {
        if self.ends.pop().is_none() {
            return false;
        }
        let (c, r, s) = self.ends.last().copied().unwrap_or((0, 0, 0));
        out.created.clear();
        out.created.extend(self.created.drain(c as usize..));
        out.replaced.clear();
        out.replaced.extend(self.replaced.drain(r as usize..));
        out.adj.clear();
        out.adj.extend(self.adj.drain(r as usize..));
        out.stamps.clear();
        out.stamps.extend(self.stamps.drain(s as usize..));
        true
    }
}

/// One change taken off the journal: the tets it created, those it replaced, the
/// stamps it overwrote.
#[derive(Debug, Default)]
struct Undone {
    created: Vec<u32>,
    replaced: Vec<[u32; 4]>,
    adj: Vec<[u32; 4]>,
    stamps: Vec<(u32, u32)>,
}

/// Steps of the walk in a star before it falls back to the whole star.
const WALK_STEPS: usize = 512;

/// Outcome of the walk towards an edge.
enum Walk {
    Found(u32),
    Absent,
    Unsure,
}

/// A face key: sorted vertex ids (packed, smallest in the high bits: the order of the
/// sorted triples) and whether the given order is an even permutation of the
/// sorted one.
fn face_key(f: [u32; 3]) -> (u128, bool) {
    let mut s = f;
    let mut even = true;
    for i in 0..3 {
        for j in 0..2 - i {
            if s[j] > s[j + 1] {
                s.swap(j, j + 1);
                even = !even;
            }
        }
    }
    let key = (u128::from(s[0]) << 64) | (u128::from(s[1]) << 32) | u128::from(s[2]);
    (key, even)
}

impl Local {
    /// Wraps `mesh` and builds the vertex-to-tet map.
    pub fn new(mesh: TetMesh) -> Self {
        let mut l = Local {
            v2t: Vec::new(),
            mesh,
            created: Vec::new(),
            journal: Journal::default(),
            journaling: false,
            validate_ops: std::env::var_os("MESHER_VALIDATE_OPS").is_some(),
            seen: Default::default(),
            visit: Default::default(),
            stamps: Stamps::default(),
            pairing: Pairing::default(),
            undone: Default::default(),
            filter: StaticFilter::none(),
            filtered: 0,
        };
        l.rebuild_v2t();
        l
    }

    /// Rebuilds the vertex-to-tet map after the mesh was changed directly (not through
    /// [`Local::replace`]), e.g. by the Delaunay kernel. Drops the undo journal.
    pub fn refresh(&mut self) {
        self.forget();
        self.rebuild_v2t();
    }

    fn rebuild_v2t(&mut self) {
        let n = self.mesh.num_vertices();
        let (mut lo, mut hi) = (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY));
        for v in 0..n {
            let p = self.mesh.point(VertexId(v as u32));
            lo = lo.min(p);
            hi = hi.max(p);
        }
        self.filter = StaticFilter::new(lo, hi);
        self.filtered = n as u32;
        self.v2t = vec![u32::MAX; n];
        for t in self.mesh.tets() {
            for v in self.mesh.raw_tet(t.0) {
                if v != GHOST {
                    self.v2t[v as usize] = t.0;
                }
            }
        }
    }

    /// Forgets vertex `v`, which no tet has any more (an edge collapse removed it).
    pub fn drop_vertex(&mut self, v: u32) {
        if let Some(t) = self.v2t.get_mut(v as usize) {
            *t = u32::MAX;
        }
    }

    /// Coordinates of vertex `v`.
    #[inline]
    pub fn p(&self, v: u32) -> Point {
        self.mesh.point(VertexId(v))
    }

    /// Moves vertex `v` to `p`. The static filter of [`Local::orient`] holds only for
    /// points in its box: a move out of the box turns it off.
    pub fn set_point(&mut self, v: u32, p: Point) {
        if !self.filter.contains(p) {
            self.filtered = 0;
        }
        self.mesh.set_point(VertexId(v), p);
    }

    /// Exact orientation of four vertices.
    #[inline]
    pub fn orient(&self, a: u32, b: u32, c: u32, d: u32) -> Orientation {
        let (pa, pb, pc, pd) = (self.p(a), self.p(b), self.p(c), self.p(d));
        if a.max(b).max(c).max(d) < self.filtered {
            self.filter.orient3d(pa, pb, pc, pd)
        } else {
            orient3d(pa, pb, pc, pd)
        }
    }

    #[inline]
    pub fn tet(&self, t: u32) -> [u32; 4] {
        self.mesh.raw_tet(t)
    }

    #[inline]
    pub fn adj(&self, t: u32) -> [u32; 4] {
        self.mesh.raw_adj(t)
    }

    #[inline]
    pub fn is_ghost(&self, t: u32) -> bool {
        self.mesh.raw_tet(t)[3] == GHOST
    }

    /// True when vertex `v` is in a live tet (a collapsed vertex is not).
    pub fn has_vertex(&self, v: u32) -> bool {
        self.v2t.get(v as usize).is_some_and(|&t| {
            t != u32::MAX && self.mesh.is_alive(TetId(t)) && self.tet(t).contains(&v)
        })
    }

    /// The tets that have vertex `v` (ghosts included), by a walk over the faces at `v`.
    pub fn star(&self, v: u32, out: &mut Vec<u32>) {
        out.clear();
        let Some(&start) = self.v2t.get(v as usize) else {
            return;
        };
        if start == u32::MAX {
            return;
        }
        debug_assert!(self.tet(start).contains(&v), "stale v2t for {v}");
        let (mut seen, visit) = self.new_visit();
        seen[start as usize] = visit;
        out.push(start);
        let mut k = 0;
        while k < out.len() {
            let t = out[k];
            k += 1;
            let tv = self.tet(t);
            let adj = self.adj(t);
            for i in 0..4 {
                if tv[i] == v {
                    continue;
                }
                let u = FaceRef::from_raw(adj[i]).tet().0;
                if seen[u as usize] != visit {
                    seen[u as usize] = visit;
                    // Read a few steps later: its cache line loads meanwhile.
                    self.mesh.prefetch(u);
                    out.push(u);
                }
            }
        }
    }

    /// A live tet with edge `ab`, if the edge exists: a walk in the star of `a` towards
    /// `b` (a few orientation tests instead of the whole star, which is large at a box
    /// corner or a vertex of a big flat face), with the star as the fallback when the
    /// walk meets the hull or does not settle.
    pub fn find_edge(&self, a: u32, b: u32, scratch: &mut Vec<u32>) -> Option<u32> {
        match self.walk_to_edge(a, b) {
            Walk::Found(t) => Some(t),
            Walk::Absent => None,
            Walk::Unsure => {
                self.star(a, scratch);
                scratch
                    .iter()
                    .copied()
                    .find(|&t| !self.is_ghost(t) && self.tet(t).contains(&b))
            }
        }
    }

    /// The walk of [`Local::find_edge`]: from a tet at `a`, cross a face at `a` that has
    /// `b` strictly beyond it, until a tet whose cone from `a` holds `b`: it has `b` as a
    /// vertex exactly when the edge exists (else `ab` leaves through its opposite face).
    fn walk_to_edge(&self, a: u32, b: u32) -> Walk {
        // The walk stops in a tet that has `b` when the edge exists: `b` is then on
        // or behind every face at `a` of the tets around `ab`.
        match self.cone_walk(a, b) {
            Some(t) if self.tet(t).contains(&b) => Walk::Found(t),
            Some(_) => Walk::Absent,
            None => Walk::Unsure,
        }
    }

    /// A live finite tet at `a` whose closed cone from `a` (over its face opposite `a`)
    /// holds `b`: a walk in the star of `a` that crosses a face at `a` with `b`
    /// strictly beyond its plane. `None` when the walk meets the hull or does not
    /// settle (callers then scan the whole star).
    pub fn cone_walk(&self, a: u32, b: u32) -> Option<u32> {
        let &start = self.v2t.get(a as usize)?;
        if start == u32::MAX || b == GHOST {
            return None;
        }
        let mut t = start;
        let mut prev = u32::MAX;
        for step in 0..WALK_STEPS {
            if self.is_ghost(t) {
                return None;
            }
            let v = self.tet(t);
            let ia = v.iter().position(|&x| x == a)?;
            let adj = self.adj(t);
            // The face at `a` opposite local vertex i (i != ia) has `b` strictly beyond
            // its plane iff orient(face, b) is negative (the tet is positive).
            let next = (0..4).map(|k| (k + step) % 4).find(|&i| {
                i != ia && FaceRef::from_raw(adj[i]).tet().0 != prev && {
                    let f = FACE_VERTICES[i].map(|k| v[k]);
                    self.orient(f[0], f[1], f[2], b) == Orientation::Negative
                }
            });
            match next {
                Some(i) => {
                    prev = t;
                    t = FaceRef::from_raw(adj[i]).tet().0;
                }
                None => return Some(t),
            }
        }
        None
    }

    /// The vertices `[x, y, z]` of tet `t` other than `a` (in the order of
    /// `FACE_VERTICES[ia]`) and the signs of `orient(a, x, y, b)`, `orient(a, y, z, b)`,
    /// `orient(a, z, x, b)`: `b` is in the closed cone of `t` from `a` iff none is
    /// positive. `None` when `t` is a ghost or lacks `a`.
    pub fn cone_signs(&self, t: u32, a: u32, b: u32) -> Option<([u32; 3], [Orientation; 3])> {
        if self.is_ghost(t) {
            return None;
        }
        let v = self.tet(t);
        let ia = v.iter().position(|&x| x == a)?;
        let [x, y, z] = FACE_VERTICES[ia].map(|k| v[k]);
        let s = [
            self.orient(a, x, y, b),
            self.orient(a, y, z, b),
            self.orient(a, z, x, b),
        ];
        Some(([x, y, z], s))
    }

    /// The tets the open segment `ab` meets (closed tets) into `out`: first the tets
    /// at `a` whose closed cone holds `b`, then those found by a search over the faces
    /// the line through `a` and `b` passes through. False past `max` tets.
    pub fn met_tets(
        &self,
        a: u32,
        b: u32,
        max: usize,
        out: &mut Vec<u32>,
        star: &mut Vec<u32>,
    ) -> bool {
        out.clear();
        // When the walk ends in a tet whose open cone holds `b`, that tet is the only
        // one at `a` that the segment meets; else (`b` on a face plane at `a`, or `ab`
        // an edge) the tets whose closed cone holds `b`, in the star's order.
        let walked = self.cone_walk(a, b);
        let signs = walked.and_then(|t| self.cone_signs(t, a, b));
        let inside = walked.filter(|&t| {
            !self.tet(t).contains(&b)
                && signs.is_some_and(|(_, s)| s.iter().all(|&o| o == Orientation::Negative))
        });
        let closed = |t: u32| {
            self.cone_signs(t, a, b)
                .is_some_and(|(_, s)| !s.contains(&Orientation::Positive))
        };
        if let Some(t) = inside {
            out.push(t);
        } else {
            // The tets at `a` whose closed cone holds `b` are connected through their
            // faces at `a` (around the face or edge at `a` that the ray towards `b`
            // runs along): found from the walk's tet when it is one of them, then
            // listed in the star's order; else the whole star is tested.
            let near = walked
                .filter(|_| signs.is_some_and(|(_, s)| !s.contains(&Orientation::Positive)))
                .map(|t| {
                    let mut near = Vec::with_capacity(16);
                    near.push(t);
                    let mut k = 0;
                    while k < near.len() {
                        let (v, adj) = (self.tet(near[k]), self.adj(near[k]));
                        k += 1;
                        for i in 0..4 {
                            let u = FaceRef::from_raw(adj[i]).tet().0;
                            if v[i] != a && !near.contains(&u) && closed(u) {
                                near.push(u);
                            }
                        }
                    }
                    near
                });
            self.star(a, star);
            out.extend(star.iter().copied().filter(|&t| match &near {
                Some(near) => near.contains(&t),
                None => closed(t),
            }));
        }
        let (mut seen, visit) = self.new_visit();
        for &t in out.iter() {
            seen[t as usize] = visit;
        }
        let mut k = 0;
        while k < out.len() {
            if out.len() > max {
                return false;
            }
            let t = out[k];
            k += 1;
            let v = self.tet(t);
            if v.contains(&b) {
                continue;
            }
            let adj = self.adj(t);
            // The side of the line `ab` each edge of `t` passes, computed once though
            // two faces ask (an edge `ji` is `ij` the other way round).
            let mut sides: [Option<Orientation>; 16] = [None; 16];
            let mut side = |i: usize, j: usize| {
                let (lo, hi) = (i.min(j), i.max(j));
                let o = *sides[lo * 4 + hi].get_or_insert_with(|| self.orient(a, b, v[lo], v[hi]));
                if i < j {
                    o
                } else {
                    o.reversed()
                }
            };
            for i in 0..4 {
                let fv = FACE_VERTICES[i];
                let f = fv.map(|j| v[j]);
                if f.contains(&a) {
                    continue;
                }
                let u = FaceRef::from_raw(adj[i]).tet().0;
                if self.is_ghost(u) || seen[u as usize] == visit {
                    continue;
                }
                let s = [side(fv[0], fv[1]), side(fv[1], fv[2]), side(fv[2], fv[0])];
                if s.contains(&Orientation::Positive) && s.contains(&Orientation::Negative) {
                    continue;
                }
                seen[u as usize] = visit;
                out.push(u);
            }
        }
        true
    }

    /// Starts a new visit of the tets: the marks, sized for every tet slot, and the
    /// visit number (a tet is seen in this visit iff its mark equals it).
    fn new_visit(&self) -> (std::cell::RefMut<'_, Vec<u32>>, u32) {
        let mut seen = self.seen.borrow_mut();
        if seen.len() < self.mesh.num_slots() {
            seen.resize(self.mesh.num_slots() * 5 / 4 + 64, 0);
        }
        let mut visit = self.visit.get().wrapping_add(1);
        if visit == 0 {
            seen.iter_mut().for_each(|s| *s = 0);
            visit = 1;
        }
        self.visit.set(visit);
        (seen, visit)
    }

    /// The ring of edge `ab`: tets `(a, b, p_i, p_{i+1})`, each positively oriented in that
    /// vertex order, as `(tet, p_i)` in cyclic order. `None` when the edge is missing or
    /// touches the hull.
    pub fn ring(&self, a: u32, b: u32, scratch: &mut Vec<u32>) -> Option<Vec<(u32, u32)>> {
        let t0 = self.find_edge(a, b, scratch)?;
        self.ring_from(t0, a, b)
    }

    /// [`Self::ring`] from a tet `t0` known to hold the edge `ab` (no search): the same
    /// cycle, started at `t0`.
    pub fn ring_from(&self, t0: u32, a: u32, b: u32) -> Option<Vec<(u32, u32)>> {
        let mut ring = Vec::with_capacity(8);
        let mut t = t0;
        loop {
            if self.is_ghost(t) || ring.len() > 4096 {
                return None;
            }
            let v = self.tet(t);
            let ia = v.iter().position(|&x| x == a)?;
            let ib = v.iter().position(|&x| x == b)?;
            if ia == ib {
                return None;
            }
            // Every live finite tet is positive, so the orientation follows from the
            // vertex order, with no predicate (see `RING_ORDER`).
            let [ip, iq] = RING_ORDER[ia][ib].map(usize::from);
            let p = v[ip];
            debug_assert_eq!(
                self.orient(a, b, p, v[iq]),
                Orientation::Positive,
                "tet {t} is not positive"
            );
            ring.push((t, p));
            // The next tet shares face (a, b, q): across the face opposite p.
            t = FaceRef::from_raw(self.adj(t)[ip]).tet().0;
            if t == t0 {
                return Some(ring);
            }
        }
    }

    /// True when some live tet has face `{a, b, c}`: a turn around the edge `ab`.
    pub fn has_face(&self, a: u32, b: u32, c: u32, scratch: &mut Vec<u32>) -> bool {
        let Some(t0) = self.find_edge(a, b, scratch) else {
            return false;
        };
        // Walk the tets around ab through the faces at ab, both ways round (the ring may
        // meet the hull).
        let mut t = t0;
        let mut from = u32::MAX;
        for _ in 0..WALK_STEPS {
            let v = self.tet(t);
            if v.contains(&c) {
                return true;
            }
            let adj = self.adj(t);
            let next = (0..4)
                .filter(|&i| v[i] != a && v[i] != b)
                .map(|i| FaceRef::from_raw(adj[i]).tet().0)
                .find(|&u| u != from);
            match next {
                Some(u) if u != t0 && !self.is_ghost(u) => {
                    from = t;
                    t = u;
                }
                Some(u) if self.is_ghost(u) => {
                    // Finish the other way round from t0; the ghost may have c too.
                    if self.tet(u).contains(&c) {
                        return true;
                    }
                    self.star(a, scratch);
                    return scratch.iter().any(|&t| {
                        let v = self.tet(t);
                        v.contains(&b) && v.contains(&c)
                    });
                }
                _ => return false,
            }
        }
        false
    }

    /// For each triangle (mesh vertex ids), the tet faces that are that triangle: per tet
    /// slot, the triangle index on each of its four faces (`u32::MAX` for none). One
    /// sweep over the tets; the triangles are listed by their smallest vertex (a few
    /// per vertex), which costs a third of a hash lookup per tet face.
    pub fn triangle_faces(&self, tris: &[[u32; 3]]) -> Vec<[u32; 4]> {
        let by_min = TrianglesByMin::new(tris, self.mesh.num_vertices());
        let mut out = vec![[u32::MAX; 4]; self.mesh.num_slots()];
        for t in self.mesh.finite_tets() {
            let v = self.tet(t.0);
            let adj = self.adj(t.0);
            for (i, f) in FACE_VERTICES.iter().enumerate() {
                // A face shared by two finite tets is looked up once, from the lower.
                let nb = FaceRef::from_raw(adj[i]);
                let u = nb.tet().0;
                let finite = !self.is_ghost(u);
                if finite && u < t.0 {
                    continue;
                }
                if let Some(k) = by_min.find(f.map(|j| v[j])) {
                    out[t.index()][i] = k;
                    if finite {
                        out[u as usize][nb.facet()] = k;
                    }
                }
            }
        }
        out
    }

    /// Which edges (mesh vertex ids) are in the mesh: one sweep over the tets with a
    /// hash of the edges.
    pub fn edges_present(&self, edges: &[(u32, u32)]) -> Vec<bool> {
        let mut index: HashMap<(u32, u32), u32> = HashMap::default();
        index.reserve(edges.len());
        for (k, &(a, b)) in edges.iter().enumerate() {
            index.insert((a.min(b), a.max(b)), k as u32);
        }
        let mut out = vec![false; edges.len()];
        for t in self.mesh.finite_tets() {
            let v = self.tet(t.0);
            for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                if let Some(&k) = index.get(&(v[i].min(v[j]), v[i].max(v[j]))) {
                    out[k as usize] = true;
                }
            }
        }
        out
    }

    /// Replaces the tets `old` (live, finite, distinct) by tets with the vertices `new`,
    /// after checking that the new set is a positive tetrahedralisation of the same
    /// region (see the module documentation). On success [`Local::created`] lists the
    /// new tets.
    pub fn replace(&mut self, old: &[u32], new: &[[u32; 4]]) -> Result<(), Refused> {
        if old.iter().any(|&t| self.is_ghost(t)) || new.iter().any(|t| t.contains(&GHOST)) {
            return Err(Refused::Hull);
        }
        for t in new {
            if self.orient(t[0], t[1], t[2], t[3]) != Orientation::Positive {
                return Err(Refused::NotPositive);
            }
        }
        self.replace_positive(old, new)
    }

    /// [`Local::replace`] for `new` tets known to be positive (the inverse of a
    /// checked change): the faces are still matched.
    fn replace_positive(&mut self, old: &[u32], new: &[[u32; 4]]) -> Result<(), Refused> {
        let mut buf = std::mem::take(&mut self.pairing);
        let r = self.pair_faces(old, new, &mut buf);
        let r = r.and_then(|()| self.commit(old, new, &buf.links, &mut buf.ids));
        self.pairing = buf;
        r
    }

    /// The links of [`Local::replace`] into `buf.links`: each face of a new tet is
    /// either an outer face of the old region, listed with the same orientation, or
    /// shared by exactly two new tets with opposite orientations; every outer face is
    /// used once. The faces go through a small hash table (sorting them, by far the
    /// dearest part of a change, cost 38 M of turbine's 1.7 G boundary instructions).
    fn pair_faces(&self, old: &[u32], new: &[[u32; 4]], buf: &mut Pairing) -> Result<(), Refused> {
        buf.reset(4 * (old.len() + new.len()));
        let (mut seen, visit) = self.new_visit();
        for &t in old {
            seen[t as usize] = visit;
        }
        // Outer faces of the old region, with the outside neighbour and the
        // orientation as listed by the inner (old) tet.
        let mut outer = 0;
        for &t in old {
            let v = self.tet(t);
            let adj = self.adj(t);
            for i in 0..4 {
                let nb = FaceRef::from_raw(adj[i]);
                if seen[nb.tet().0 as usize] == visit {
                    continue;
                }
                let (key, even) = face_key(FACE_VERTICES[i].map(|k| v[k]));
                let slot = buf.slot(key);
                if buf.table[slot] != 0 {
                    return Err(Refused::Mismatch);
                }
                let face = PairFace::Outer(nb);
                buf.put(
                    slot,
                    PairEntry {
                        key,
                        even,
                        face,
                        paired: false,
                    },
                );
                outer += 1;
            }
        }
        drop(seen);
        let (mut used, mut open) = (0, 0);
        for (k, t) in new.iter().enumerate() {
            for (i, fv) in FACE_VERTICES.iter().enumerate() {
                let (key, even) = face_key(fv.map(|j| t[j]));
                let slot = buf.slot(key);
                if buf.table[slot] == 0 {
                    let face = PairFace::New(k as u32, i as u8);
                    buf.put(
                        slot,
                        PairEntry {
                            key,
                            even,
                            face,
                            paired: false,
                        },
                    );
                    open += 1;
                    continue;
                }
                let e = &mut buf.entries[buf.table[slot] as usize - 1];
                let link = match e.face {
                    PairFace::Outer(f) if !e.paired && e.even == even => {
                        used += 1;
                        Link::Outer(f)
                    }
                    PairFace::New(k2, i2) if !e.paired && e.even != even => {
                        open -= 1;
                        Link::Inner(k2 as usize, i2 as usize)
                    }
                    _ => return Err(Refused::Mismatch),
                };
                e.paired = true;
                buf.links.push((k, i, link));
            }
        }
        if used != outer || open != 0 {
            return Err(Refused::Mismatch);
        }
        Ok(())
    }

    /// Starts recording changes so that [`Local::undo`] can revert them; returns the
    /// position to revert to.
    pub fn mark(&mut self) -> usize {
        self.journaling = true;
        self.journal.len()
    }

    /// Reverts the changes recorded since `mark`, newest first.
    pub fn undo(&mut self, mark: usize) {
        let mut change = std::mem::take(&mut self.undone);
        while self.journal.len() > mark {
            if !self.journal.pop_into(&mut change) {
                break;
            }
            let was = std::mem::replace(&mut self.journaling, false);
            self.restore(&change.created, &change.replaced, &change.adj);
            self.stamps.restore(&change.stamps);
            self.journaling = was;
        }
        self.undone = change;
    }

    /// The inverse of a journalled change: the tets `replaced` back, with their
    /// neighbours then (`adj`), in place of the tets `created`. The free slots are a
    /// stack, so the replaced tets get their own slots back (see [`Local::commit`]),
    /// and their neighbour handles hold as they were: no face pairing, the same mesh
    /// as the checked inverse change ([`Local::replace`]) makes.
    fn restore(&mut self, created: &[u32], replaced: &[[u32; 4]], adj: &[[u32; 4]]) {
        let mut ids = std::mem::take(&mut self.pairing.ids);
        // The slots this change freed are on the free list: no new slot is needed.
        let taken = self.take_slots(created, replaced.len(), &mut ids);
        debug_assert!(taken, "undo found no free slot");
        if taken {
            self.put_tets(created, &ids, replaced);
            for (&t, n) in ids.iter().zip(adj) {
                for (i, &f) in n.iter().enumerate() {
                    self.mesh
                        .link(FaceRef::new(TetId(t), i), FaceRef::from_raw(f));
                }
            }
            self.changed(&ids, || format!("undo {created:?} -> {replaced:?}"));
        }
        self.pairing.ids = ids;
    }

    /// Stops recording and forgets the log.
    pub fn forget(&mut self) {
        self.journal.clear();
        self.journaling = false;
    }

    fn commit(
        &mut self,
        old: &[u32],
        new: &[[u32; 4]],
        links: &[(usize, usize, Link)],
        ids: &mut Vec<u32>,
    ) -> Result<(), Refused> {
        if !self.take_slots(old, new.len(), ids) {
            return Err(Refused::Full);
        }
        if self.journaling {
            // The undo stamps the old tets' vertices, the new ones' were stamped now.
            let j = &mut self.journal;
            j.created.extend_from_slice(ids);
            let first = j.replaced.len();
            j.replaced.extend(old.iter().map(|&t| self.mesh.raw_tet(t)));
            j.adj.extend(old.iter().map(|&t| self.mesh.raw_adj(t)));
            let verts = new.iter().chain(&j.replaced[first..]).flatten().copied();
            j.stamps.extend(self.stamps.read(verts));
            j.seal();
        }
        self.put_tets(old, ids, new);
        for &(k, i, link) in links {
            let me = FaceRef::new(TetId(ids[k]), i);
            match link {
                Link::Outer(f) => self.mesh.link(me, f),
                Link::Inner(k2, i2) => self.mesh.link(me, FaceRef::new(TetId(ids[k2]), i2)),
            }
        }
        self.changed(ids, || format!("replace {old:?} -> {new:?}"));
        Ok(())
    }

    /// The slots of a change from the tets `old` to `n` new ones into `ids`: the old
    /// ones first, then fresh ones. False (nothing taken) when the mesh is full.
    fn take_slots(&mut self, old: &[u32], n: usize, ids: &mut Vec<u32>) -> bool {
        ids.clear();
        ids.extend(old.iter().take(n).copied());
        while ids.len() < n {
            match self.mesh.alloc_tet() {
                Some(t) => ids.push(t),
                None => {
                    for &t in ids[old.len().min(ids.len())..].iter().rev() {
                        self.mesh.free_tet(t);
                    }
                    return false;
                }
            }
        }
        true
    }

    /// Frees the slots of `old` that `ids` does not reuse and puts the tets `new` in
    /// `ids`, with the vertex-to-tet map. Freed in reverse: the free list is a stack,
    /// so the inverse change (an undo) allocates these same slots in the same order,
    /// and frees the slots this change allocates back in the order they were taken.
    /// Slot ids then match the journal however long the chain of undone changes.
    fn put_tets(&mut self, old: &[u32], ids: &[u32], new: &[[u32; 4]]) {
        for &t in old.iter().skip(new.len()).rev() {
            self.mesh.free_tet(t);
        }
        for (&id, t) in ids.iter().zip(new) {
            self.mesh.set_tet(id, *t);
            for &v in t {
                if v as usize >= self.v2t.len() {
                    self.v2t.resize(v as usize + 1, u32::MAX);
                }
                self.v2t[v as usize] = id;
            }
        }
    }

    /// After a change that made the tets `ids` (linked): the check of every
    /// invariant when asked for (`what` names the change), the stamps, `created`.
    fn changed(&mut self, ids: &[u32], what: impl FnOnce() -> String) {
        if self.validate_ops {
            if let Err(e) = self.mesh.validate(false) {
                panic!("{} broke the mesh: {e}", what());
            }
        }
        self.stamps
            .touch(ids.iter().flat_map(|&t| self.mesh.raw_tet(t)));
        self.created.clear();
        self.created.extend_from_slice(ids);
    }
}

#[derive(Clone, Copy, Debug)]
enum Link {
    Outer(FaceRef),
    Inner(usize, usize),
}

#[cfg(test)]
mod tests;
