//! Recovery of the missing boundary edges and faces by flips (paper §4.2).
//!
//! A missing segment `ab` is attacked at the first simplex it crosses seen from `a` (then
//! from `b`): a crossed face by a 2-3 flip that joins `a` to the apex behind the face,
//! a crossed edge by removing it with the fan from `a` in its ring. Both shorten the
//! chain of tets the segment crosses by at least one. When the 2-3 flip is not valid
//! (the union of the two tets is not convex), the reflex edge of the face is removed
//! first, as in Si's `flipnm` (TetGen; "TetGen, a Delaunay-based quality tetrahedral
//! mesh generator", ACM TOMS 2015), one level deep; before a Steiner point, the first
//! crossings are removed with `flip_depth` levels of such preparation.
//!
//! When flips are stuck, a cone from an end point (`cone.rs`), then a Schönhardt fan
//! with one interior Steiner point (`fan.rs`).
//!
//! A missing triangle `abc` whose three edges exist is crossed near each of its edges
//! by one ring edge of that edge; removing that crossing edge with the triangle `abc`
//! forced into the ring polygon creates the face at once when the ring holds the three
//! corners, and otherwise moves the crossing outward. Every loop here has a budget;
//! running out reports the entity as stuck, never loops for ever.

use super::flips::{flip23, remove_edge, Choice, FlipCounts, Locks};
use super::local::{Local, Marks};
use crate::geom::predicates::Orientation;
use crate::geom::Point;
use crate::tetmesh::FACE_VERTICES;
use crate::{FastMap as HashMap, FastSet};

/// Largest set of tets a single search visits.
const MAX_MET: usize = 4096;
/// Largest ring for which an edge removal tries one preparatory removal per ring vertex.
/// At 10 cheese's recovery spent most of its flips on rings of ten whose removals
/// failed: 9 takes its boundary mesh from 7 Steiner rounds to 3 and 3.05 -> 2.60 G
/// instructions, with the same interior Steiner counts on the corpus but oblong's (2
/// -> 3); turbine -1 %, anchor -2 %, the other tier models within 0.3 %. At 8: turbine
/// +2 %; at 7: cheese -32 % but turbine +17 %.
const MAX_HELP_RING: usize = 9;

/// What the segment from `a` towards `b` meets first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Crossing {
    /// The segment is an edge of the mesh.
    Present,
    /// It crosses the interior of the face opposite local vertex `i` (= `a`) of `t`.
    Face(u32, usize),
    /// It crosses the interior of edge `xy`.
    Edge(u32, u32),
    /// It passes through vertex `v` (an input defect: a vertex on a segment).
    Vertex(u32),
    /// No tet at `a` holds the direction (corrupt mesh).
    Lost,
}

/// Why an entity could not be recovered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stuck {
    /// No flip makes progress.
    NoFlip,
    /// Vertex `v` lies on the entity (exactly).
    Through(u32),
}

/// The first simplex crossed by the segment from `a` to `b`.
pub(crate) fn first_crossing(l: &Local, a: u32, b: u32, star: &mut Vec<u32>) -> Crossing {
    // A walk in the star finds the tet at once. The whole star when the walk fails,
    // and when the segment leaves through an edge or a vertex: several tets hold it
    // then, and the first in the star's order names the edge's direction, which the
    // recovery's later choices follow (a change there failed turbine's planar cap).
    if let Some(t) = l.cone_walk(a, b) {
        if let Some(c @ (Crossing::Present | Crossing::Face(..))) = crossing_at(l, t, a, b) {
            return c;
        }
    }
    l.star(a, star);
    star.iter()
        .find_map(|&t| crossing_at(l, t, a, b))
        .unwrap_or(Crossing::Lost)
}

/// The crossing of `ab` at tet `t` of the star of `a`: `Present` if `t` has `b`, else
/// the simplex of `t` opposite `a` that the segment meets when `b` is in the closed cone
/// of `t` from `a`; `None` otherwise (and for ghosts).
fn crossing_at(l: &Local, t: u32, a: u32, b: u32) -> Option<Crossing> {
    if l.is_ghost(t) {
        return None;
    }
    if l.tet(t).contains(&b) {
        return Some(Crossing::Present);
    }
    // With a on the positive side of (x, y, z), the direction of b is inside the cone
    // at a over the face iff it is on the negative side of the three planes.
    let ([x, y, z], s) = l.cone_signs(t, a, b)?;
    if s.contains(&Orientation::Positive) {
        return None;
    }
    let ia = l.tet(t).iter().position(|&v| v == a)?;
    let zero = s.map(|o| o == Orientation::Zero);
    Some(match zero {
        [false, false, false] => Crossing::Face(t, ia),
        [true, false, false] => Crossing::Edge(x, y),
        [false, true, false] => Crossing::Edge(y, z),
        [false, false, true] => Crossing::Edge(z, x),
        [true, true, false] => Crossing::Vertex(y),
        [false, true, true] => Crossing::Vertex(z),
        [true, false, true] => Crossing::Vertex(x),
        [true, true, true] => Crossing::Lost,
    })
}

/// A failed recovery: the clock then, whether Steiner points were allowed, and the
/// vertices of the tets the entity met (`None`: too many to list).
pub(super) struct Failure {
    since: u32,
    steiner: bool,
    verts: Option<Vec<u32>>,
}

/// The recovery state: the mesh, the locks, counters and scratch space.
pub(crate) struct Recovery {
    pub l: Local,
    pub locks: Locks,
    pub flips: FlipCounts,
    /// Interior Steiner points inserted in Schönhardt fans.
    pub steiner: Vec<u32>,
    /// Whether Steiner points may be inserted (a second phase, after flips alone).
    pub allow_steiner: bool,
    /// Levels of preparatory removals at a stuck segment before a Steiner point
    /// ([`super::BoundaryOptions::flip_depth`]).
    pub flip_depth: usize,
    /// Edge removals that failed, with the stamps of the edge's ends then (see
    /// [`Recovery::remove_once`]); emptied when the mesh changes without stamps.
    pub(super) removal_failed: HashMap<(u32, u32, Choice), (u32, u32)>,
    /// Tets of the cone region being built ([`super::cone`]).
    pub(super) cone_tets: Marks,
    /// Vertices on the boundary of that region.
    pub(super) cone_verts: Marks,
    /// Tets taken in by the growth of a side of a Steiner point's star
    /// ([`super::suppress`]), for one apex at a time.
    pub(super) grow_marks: std::cell::RefCell<Marks>,
    pub(super) scratch: Vec<u32>,
    star: Vec<u32>,
    /// The tets of [`Recovery::met_below`] (only their number is returned).
    met: Vec<u32>,
    /// Entities whose recovery failed (an edge is `[a, b, u32::MAX]`, a triangle its
    /// sorted vertices).
    pub(super) failed: HashMap<[u32; 3], Failure>,
}

impl Recovery {
    pub fn new(l: Local) -> Self {
        Recovery {
            l,
            locks: Locks::default(),
            flips: FlipCounts::default(),
            steiner: Vec::new(),
            allow_steiner: false,
            flip_depth: 1,
            removal_failed: HashMap::default(),
            cone_tets: Marks::default(),
            cone_verts: Marks::default(),
            grow_marks: Default::default(),
            scratch: Vec::new(),
            star: Vec::new(),
            met: Vec::new(),
            failed: HashMap::default(),
        }
    }

    /// True when the recovery of `key` failed before, with the same Steiner setting,
    /// and no tet at the vertices it met has changed since: the attempt is local and
    /// deterministic, so it would fail again.
    fn failed_unchanged(&self, key: &[u32; 3]) -> bool {
        self.failed.get(key).is_some_and(|f| {
            f.steiner == self.allow_steiner
                && f.verts
                    .as_ref()
                    .is_some_and(|v| !self.l.stamps.changed_since(v, f.since))
        })
    }

    /// Remembers a failed recovery of `key`, with the tets it meets (`met`).
    fn remember_failure(&mut self, key: [u32; 3], met: Option<Vec<u32>>) {
        let verts = met.map(|m| {
            let mut v: Vec<u32> = m.iter().flat_map(|&t| self.l.tet(t)).collect();
            v.sort_unstable();
            v.dedup();
            v
        });
        let failure = Failure {
            since: self.l.stamps.clock,
            steiner: self.allow_steiner,
            verts,
        };
        self.failed.insert(key, failure);
    }

    /// [`Recovery::segment`], unless it failed before and nothing it met has changed.
    /// The flips of a failed attempt stay (each lowered the number of tets the segment
    /// meets, progress for a later attempt, as TetGen keeps them too); the failure is
    /// remembered with the clock after them.
    pub fn segment_once_per_change(&mut self, a: u32, b: u32, budget: usize) -> Result<(), Stuck> {
        let key = [a.min(b), a.max(b), u32::MAX];
        if self.failed_unchanged(&key) {
            return Err(Stuck::NoFlip);
        }
        let r = self.segment(a, b, budget);
        self.l.forget();
        if r == Err(Stuck::NoFlip) {
            let met = self.met_tets(a, b);
            self.remember_failure(key, met);
        }
        r
    }

    /// Interior Steiner candidates for a stuck segment `ab`, one where it is stuck at
    /// each end: in the first tet it meets from that end, a quarter of the way from
    /// where it leaves that tet towards the tet's centroid, and no farther from the
    /// segment than a tenth of its length (the tets at a big face can be huge, and a
    /// far point only adds edges that cross other entities). Inexact constructions;
    /// the kernel locates them exactly.
    pub fn crossing_points(&mut self, a: u32, b: u32) -> Vec<Point> {
        let (pa, pb) = (self.l.p(a), self.l.p(b));
        let len = (pb - pa).length();
        let mut out = Vec::new();
        for (f, t) in [(a, b), (b, a)] {
            let (tet, exit) = match first_crossing(&self.l, f, t, &mut self.star) {
                Crossing::Face(tt, i) => {
                    let v = self.l.tet(tt);
                    let fv = FACE_VERTICES[i].map(|k| self.l.p(v[k]));
                    (Some(tt), segment_plane(pa, pb, fv))
                }
                Crossing::Edge(x, y) => {
                    self.l.star(f, &mut self.star);
                    let tt = self.star.iter().copied().find(|&tt| {
                        let v = self.l.tet(tt);
                        !self.l.is_ghost(tt) && v.contains(&f) && v.contains(&x) && v.contains(&y)
                    });
                    let (px, py) = (self.l.p(x), self.l.p(y));
                    let at =
                        closest_parameter(pa, pb - pa, px, py).map(|(s, _)| pa + (pb - pa) * s);
                    (tt, at)
                }
                _ => (None, None),
            };
            let Some(tt) = tet else {
                continue;
            };
            let v = self.l.tet(tt);
            let centroid = v.iter().map(|&x| self.l.p(x)).sum::<Point>() / 4.0;
            let Some(exit) = exit.filter(|e| e.is_finite()) else {
                out.push(centroid);
                continue;
            };
            let mut d = (centroid - exit) * 0.25;
            if d.length() > 0.1 * len {
                d *= 0.1 * len / d.length();
            }
            out.push(exit + d);
        }
        out
    }

    /// Where to split a stuck segment `ab`: the parameter along it of the point
    /// closest to the nearest recovered (locked) edge among the tets it meets, the
    /// constraint that blocks its flips (the idea of Si's `add_steinerpt_in_segment`,
    /// TetGen); `None` when no locked edge passes beside the open segment.
    pub fn blocker_parameter(&mut self, a: u32, b: u32) -> Option<f64> {
        let met = self.met_tets(a, b)?;
        let (pa, pb) = (self.l.p(a), self.l.p(b));
        let d = pb - pa;
        let mut best: Option<(f64, f64)> = None;
        for &t in &met {
            let v = self.l.tet(t);
            for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                let (x, y) = (v[i], v[j]);
                if [x, y].iter().any(|w| *w == a || *w == b) || !self.locks.edge(x, y) {
                    continue;
                }
                let Some((tp, dist)) = closest_parameter(pa, d, self.l.p(x), self.l.p(y)) else {
                    continue;
                };
                if (0.02..=0.98).contains(&tp) && best.is_none_or(|(_, bd)| dist < bd) {
                    best = Some((tp, dist));
                }
            }
        }
        best.map(|(tp, _)| tp)
    }

    /// [`Recovery::face`], unless it failed before and nothing it crossed has changed.
    pub fn face_once_per_change(&mut self, tri: [u32; 3], budget: usize) -> Result<(), Stuck> {
        let mut key = tri;
        key.sort_unstable();
        if self.failed_unchanged(&key) {
            return Err(Stuck::NoFlip);
        }
        let r = self.face(tri, budget);
        self.l.forget();
        if r == Err(Stuck::NoFlip) {
            let met = self.crossing_tets(tri);
            self.remember_failure(key, met);
        }
        r
    }

    /// True when edge `ab` is in the mesh.
    pub fn has_edge(&mut self, a: u32, b: u32) -> bool {
        self.l.find_edge(a, b, &mut self.scratch).is_some()
    }

    /// True when face `abc` is in the mesh.
    pub fn has_face(&mut self, a: u32, b: u32, c: u32) -> bool {
        self.l.has_face(a, b, c, &mut self.scratch)
    }

    /// Recovers segment `ab` by flips within `budget` operations: first the simplex the
    /// segment meets first from either end, else any flip among the simplices it
    /// crosses that lowers the number of tets it meets (the full search).
    ///
    /// At the first crossing from an end, a 2-3 flip of the crossed face or the removal
    /// of the crossed edge by the fan from that end leaves the segment in one new tet
    /// where it crossed two or more: the chain of tets it meets gets shorter, so these
    /// need no check. Any other change (an edge of the face, the best re-triangulation,
    /// a preparatory removal) is kept only if the number of tets met strictly drops,
    /// so there are no cycles.
    pub fn segment(&mut self, a: u32, b: u32, budget: usize) -> Result<(), Stuck> {
        // Tets the segment meets, when known for the current mesh.
        let mut met: Option<usize> = None;
        for _ in 0..budget {
            let mut progressed = false;
            for (from, to) in [(a, b), (b, a)] {
                let crossing = first_crossing(&self.l, from, to, &mut self.star);
                let direct = match crossing {
                    Crossing::Present => return Ok(()),
                    Crossing::Vertex(v) => return Err(Stuck::Through(v)),
                    Crossing::Lost => return Err(Stuck::NoFlip),
                    Crossing::Face(t, i) => {
                        flip23(&mut self.l, &self.locks, t, i, &mut self.flips).is_ok()
                    }
                    // The ring of the crossed edge may hold both ends (the segment
                    // crosses that edge only): then the removal can make `ab` at once.
                    Crossing::Edge(x, y) => {
                        self.remove_once(x, y, Choice::Fan(from))
                            || self.remove_once(x, y, Choice::Chord(a, b))
                    }
                };
                if direct {
                    met = None;
                    progressed = true;
                    break;
                }
                let before = match met {
                    Some(m) => m,
                    None => self.met_below(a, b, usize::MAX).unwrap_or(usize::MAX),
                };
                met = Some(before);
                let mark = self.l.mark();
                let changed = match crossing {
                    Crossing::Face(t, i) => self.unblock_face(t, i),
                    Crossing::Edge(x, y) => self.remove(x, y, Choice::FanFrom(from)),
                    _ => false,
                };
                if !changed {
                    continue;
                }
                if self.has_edge(a, b) {
                    return Ok(());
                }
                match self.met_below(a, b, before) {
                    Some(after) => {
                        met = Some(after);
                        progressed = true;
                        break;
                    }
                    // Only a strict decrease of the tets met counts: no cycles.
                    _ => self.l.undo(mark),
                }
            }
            if !progressed {
                if !self.segment_full_search(a, b) {
                    break;
                }
                met = None;
            }
        }
        if self.has_edge(a, b) {
            return Ok(());
        }
        if self.allow_steiner && self.flip_depth > 1 && self.deep_flips(a, b, budget) {
            return Ok(());
        }
        // Flips are stuck (or cycle): a cone from an end point, else (when allowed) a
        // Schönhardt fan with a Steiner point.
        let done = [(a, b), (b, a)].iter().any(|&(p, q)| {
            self.met_tets(p, q)
                .is_some_and(|seed| self.cone(p, &seed, &[q]))
        }) || (self.allow_steiner && self.schonhardt(a, b));
        if done && self.has_edge(a, b) {
            Ok(())
        } else {
            Err(Stuck::NoFlip)
        }
    }

    /// Before a Steiner point: the first crossings from either end removed with
    /// [`Recovery::flip_depth`] levels of preparation, each change kept only when the
    /// segment meets fewer tets (no cycles).
    fn deep_flips(&mut self, a: u32, b: u32, budget: usize) -> bool {
        let depth = self.flip_depth;
        for _ in 0..budget {
            let Some(before) = self.met_below(a, b, usize::MAX) else {
                return false;
            };
            let mut progressed = false;
            for (from, to) in [(a, b), (b, a)] {
                let mark = self.l.mark();
                let changed = match first_crossing(&self.l, from, to, &mut self.star) {
                    Crossing::Present => return true,
                    Crossing::Edge(x, y) => self.remove_deep(x, y, Choice::FanFrom(from), depth),
                    Crossing::Face(t, i) => {
                        let v = self.l.tet(t);
                        let f = FACE_VERTICES[i].map(|k| v[k]);
                        (0..3).any(|k| {
                            self.remove_deep(f[k], f[(k + 1) % 3], Choice::Best, depth - 1)
                        })
                    }
                    _ => return false,
                };
                if !changed {
                    continue;
                }
                if self.has_edge(a, b) {
                    return true;
                }
                if self.met_below(a, b, before).is_some() {
                    progressed = true;
                    break;
                }
                self.l.undo(mark);
            }
            if !progressed {
                return false;
            }
        }
        self.has_edge(a, b)
    }

    /// One flip anywhere along `ab` that lowers the number of tets the segment meets.
    fn segment_full_search(&mut self, a: u32, b: u32) -> bool {
        let Some(met) = self.met_tets(a, b) else {
            return false;
        };
        let before = met.len();
        let mut faces = Vec::new();
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for &t in &met {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let f = FACE_VERTICES[i].map(|k| v[k]);
                let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                if t < u && met.contains(&u) && !f.contains(&a) && !f.contains(&b) {
                    faces.push((t, i));
                }
            }
            for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                let (x, y) = (v[i].min(v[j]), v[i].max(v[j]));
                if ![a, b].contains(&x)
                    && ![a, b].contains(&y)
                    && !edges.contains(&(x, y))
                    && self.l.orient(a, b, x, y) == Orientation::Zero
                {
                    edges.push((x, y));
                }
            }
        }
        for (t, i) in faces {
            let mark = self.l.mark();
            if flip23(&mut self.l, &self.locks, t, i, &mut self.flips).is_ok() {
                if self.met_below(a, b, before).is_some() {
                    return true;
                }
                self.l.undo(mark);
            }
        }
        for (x, y) in edges {
            let mark = self.l.mark();
            if self.remove(x, y, Choice::Best) {
                if self.has_edge(a, b) || self.met_below(a, b, before).is_some() {
                    return true;
                }
                self.l.undo(mark);
            }
        }
        false
    }

    /// The tets the open segment `ab` meets (closed tets), found by a search from the
    /// tets at `a` over the faces the line through `a` and `b` passes through; `None`
    /// past [`MAX_MET`] tets.
    pub(crate) fn met_tets(&mut self, a: u32, b: u32) -> Option<Vec<u32>> {
        let mut out = Vec::new();
        self.l
            .met_tets(a, b, MAX_MET, &mut out, &mut self.star)
            .then_some(out)
    }

    /// The number of tets the open segment `ab` meets ([`Recovery::met_tets`]) when it
    /// is below `limit`, else `None`: the search stops as soon as it reaches `limit`
    /// (most changes tried do not lower the number, and this is what tells).
    fn met_below(&mut self, a: u32, b: u32, limit: usize) -> Option<usize> {
        let max = limit.checked_sub(1)?.min(MAX_MET);
        let mut out = std::mem::take(&mut self.met);
        let n = self
            .l
            .met_tets(a, b, max, &mut out, &mut self.star)
            .then_some(out.len());
        self.met = out;
        n
    }

    /// Removes edge `xy`; if that fails, first removes one edge from `x` or `y` to a
    /// vertex of its ring (which changes the ring), undone when `xy` still cannot go:
    /// one level of Si's `flipnm`.
    fn remove(&mut self, x: u32, y: u32, choice: Choice) -> bool {
        self.remove_deep(x, y, choice, 1)
    }

    /// [`Recovery::remove`] with `depth` levels of preparatory removals (Si's `flipnm`
    /// link levels): each level removes one edge from an end of the edge to a vertex
    /// of its ring, itself with one level fewer, and undoes it when the edge still
    /// cannot go.
    pub(super) fn remove_deep(&mut self, x: u32, y: u32, choice: Choice, depth: usize) -> bool {
        if self.remove_once(x, y, choice) {
            return true;
        }
        if depth == 0 {
            return false;
        }
        let Some(ring) = self.l.ring(x, y, &mut self.scratch) else {
            return false;
        };
        if ring.len() > MAX_HELP_RING {
            return false;
        }
        let n = ring.len();
        for (k, &(_, p)) in ring.iter().enumerate() {
            if !self.may_block(x, y, ring[(k + n - 1) % n].1, p, ring[(k + 1) % n].1) {
                continue;
            }
            for z in [x, y] {
                if self.locks.edge(z, p) {
                    continue;
                }
                let mark = self.l.mark();
                if !self.remove_deep(z, p, Choice::Best, depth - 1) {
                    continue;
                }
                if self.remove_once(x, y, choice) {
                    return true;
                }
                self.l.undo(mark);
            }
        }
        false
    }

    /// Whether the ring vertex `p` of edge `xy`, between ring vertices `prev` and
    /// `next` (the ring as [`Local::ring`] lists it), may be what keeps `xy` from
    /// going: unless `p` is a convex corner of the ring seen along the edge, its ear
    /// `(prev, p, next)` having `y` on its positive and `x` on its negative side. A
    /// convex ear can be cut with both ends of the edge, so removing an edge from `p`
    /// (the preparatory step of [`Recovery::remove_deep`]) does not unblock the ring
    /// there. Skipping them makes level 2 of `flip_depth` affordable: the recovery
    /// at level 2 with this test costs fewer instructions than level 1 without it.
    pub(super) fn may_block(&self, x: u32, y: u32, prev: u32, p: u32, next: u32) -> bool {
        let ox = self.l.orient(prev, p, next, x);
        let oy = self.l.orient(prev, p, next, y);
        !(oy == Orientation::Positive && ox == Orientation::Negative)
    }

    /// [`remove_edge`], unless it failed before with the same `choice` and no tet at
    /// `x` or `y` has changed since (the ring of `xy` is then the same, and so is the
    /// outcome: most removals tried while preparing others fail, many of them
    /// again and again).
    fn remove_once(&mut self, x: u32, y: u32, choice: Choice) -> bool {
        if self.locks.edge(x, y) {
            return false;
        }
        let key = (x, y, choice);
        let now = (self.l.stamps.of(x), self.l.stamps.of(y));
        if self.removal_failed.get(&key) == Some(&now) {
            return false;
        }
        let done = remove_edge(
            &mut self.l,
            &self.locks,
            x,
            y,
            choice,
            &mut self.scratch,
            &mut self.flips,
        )
        .is_ok();
        if !done {
            self.removal_failed.insert(key, now);
        }
        done
    }

    /// Removes one edge of the face opposite vertex `i` of `t` (the reflex one first), so
    /// that a later 2-3 flip of the face can succeed (the 2-3 flip itself was refused).
    fn unblock_face(&mut self, t: u32, i: usize) -> bool {
        let v = self.l.tet(t);
        let f = FACE_VERTICES[i].map(|k| v[k]);
        let d = v[i];
        let nb = crate::tetmesh::FaceRef::from_raw(self.l.adj(t)[i]);
        if self.l.is_ghost(nb.tet().0) {
            return false;
        }
        let e = self.l.tet(nb.tet().0)[nb.facet()];
        // The edges of the face that the segment de passes on the wrong side of.
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for k in 0..3 {
            let (p, q) = (f[k], f[(k + 1) % 3]);
            if self.l.orient(p, q, d, e) != Orientation::Negative {
                edges.insert(0, (p, q));
            } else {
                edges.push((p, q));
            }
        }
        edges
            .into_iter()
            .any(|(p, q)| self.remove(p, q, Choice::Best))
    }

    /// Recovers triangle `abc` (its edges present) by flips within `budget` operations:
    /// first the edge crossing the triangle next to one of its edges, removed with the
    /// triangle forced into its ring when possible; else any crossing edge whose
    /// removal lowers the number of crossing edges (undone when it does not).
    pub fn face(&mut self, tri: [u32; 3], budget: usize) -> Result<(), Stuck> {
        for _ in 0..budget {
            if self.has_face(tri[0], tri[1], tri[2]) {
                return Ok(());
            }
            let mut progressed = false;
            for k in 0..3 {
                let (u, w, o) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                match self.crossing_edge(u, w, o) {
                    Ok(Some((p, q))) => {
                        if self.remove(p, q, Choice::With([u, w, o])) {
                            progressed = true;
                            break;
                        }
                    }
                    Ok(None) => {}
                    Err(s) => return Err(s),
                }
            }
            if progressed {
                continue;
            }
            // A cone from a corner of the triangle over the crossing tets is one
            // operation; the full search (quadratic in the crossing edges: big faces
            // such as a bounding box's are crossed by hundreds) comes after it.
            let seed = self.crossing_tets(tri).unwrap_or_default();
            let coned = (0..3).any(|k| {
                let others = [tri[(k + 1) % 3], tri[(k + 2) % 3]];
                self.cone(tri[k], &seed, &others)
            });
            if coned && self.has_face(tri[0], tri[1], tri[2]) {
                return Ok(());
            }
            if !self.face_full_search(tri) {
                return Err(Stuck::NoFlip);
            }
        }
        if self.has_face(tri[0], tri[1], tri[2]) {
            Ok(())
        } else {
            Err(Stuck::NoFlip)
        }
    }

    /// One edge removal that lowers the number of edges crossing triangle `tri`.
    fn face_full_search(&mut self, tri: [u32; 3]) -> bool {
        let Some(cross) = self.crossing_edges(tri) else {
            return false;
        };
        let before = cross.len();
        for (p, q) in cross {
            for choice in [Choice::With(tri), Choice::Best] {
                let mark = self.l.mark();
                if self.remove(p, q, choice) {
                    if self.has_face(tri[0], tri[1], tri[2])
                        || self.crossing_edges(tri).is_some_and(|c| c.len() < before)
                    {
                        return true;
                    }
                    self.l.undo(mark);
                }
            }
        }
        false
    }

    /// The mesh edges that cross the open triangle `tri` (whose edges exist).
    fn crossing_edges(&mut self, tri: [u32; 3]) -> Option<Vec<(u32, u32)>> {
        self.crossing(tri).map(|c| c.0)
    }

    /// The tets with an edge crossing the open triangle `tri`.
    fn crossing_tets(&mut self, tri: [u32; 3]) -> Option<Vec<u32>> {
        self.crossing(tri).map(|c| c.1)
    }

    /// The mesh edges that cross the open triangle `tri` (whose edges exist) and the
    /// tets that have them: a search over such tets from the rings of its edges.
    #[allow(clippy::type_complexity)]
    fn crossing(&mut self, tri: [u32; 3]) -> Option<(Vec<(u32, u32)>, Vec<u32>)> {
        let mut todo: Vec<u32> = Vec::new();
        for k in 0..3 {
            let ring = self.l.ring(tri[k], tri[(k + 1) % 3], &mut self.scratch)?;
            todo.extend(ring.iter().map(|r| r.0));
        }
        let mut seen: FastSet<u32> = todo.iter().copied().collect();
        let mut edges: Vec<(u32, u32)> = Vec::new();
        let mut tets: Vec<u32> = Vec::new();
        // Side of the triangle's plane per vertex, computed once.
        let mut side: HashMap<u32, Orientation> = HashMap::default();
        while let Some(t) = todo.pop() {
            if seen.len() > MAX_MET {
                return None;
            }
            let v = self.l.tet(t);
            let sides = v.map(|x| {
                *side
                    .entry(x)
                    .or_insert_with(|| self.l.orient(tri[0], tri[1], tri[2], x))
            });
            let mut any = false;
            for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                let (x, y) = (v[i].min(v[j]), v[i].max(v[j]));
                let (si, sj) = (sides[i], sides[j]);
                if si == Orientation::Zero || sj == Orientation::Zero || si == sj {
                    continue;
                }
                if self.crosses(tri, x, y) {
                    any = true;
                    if !edges.contains(&(x, y)) {
                        edges.push((x, y));
                    }
                }
            }
            if !any {
                continue;
            }
            tets.push(t);
            for a in self.l.adj(t) {
                let u = crate::tetmesh::FaceRef::from_raw(a).tet().0;
                if !self.l.is_ghost(u) && seen.insert(u) {
                    todo.push(u);
                }
            }
        }
        Some((edges, tets))
    }

    /// True when edge `xy` crosses the open triangle `t` at one interior point.
    fn crosses(&self, t: [u32; 3], x: u32, y: u32) -> bool {
        if t.contains(&x) || t.contains(&y) {
            return false;
        }
        let l = &self.l;
        let (sx, sy) = (l.orient(t[0], t[1], t[2], x), l.orient(t[0], t[1], t[2], y));
        if sx == Orientation::Zero || sy == Orientation::Zero || sx == sy {
            return false;
        }
        let s = [
            l.orient(x, y, t[0], t[1]),
            l.orient(x, y, t[1], t[2]),
            l.orient(x, y, t[2], t[0]),
        ];
        s[0] != Orientation::Zero && s[0] == s[1] && s[1] == s[2]
    }

    /// The ring edge of edge `uw` that triangle `uwo` passes through (`None` if the
    /// triangle leaves the ring through a face, which a later step resolves).
    fn crossing_edge(&mut self, u: u32, w: u32, o: u32) -> Result<Option<(u32, u32)>, Stuck> {
        let Some(ring) = self.l.ring(u, w, &mut self.scratch) else {
            return Ok(None);
        };
        let n = ring.len();
        for k in 0..n {
            let (p, q) = (ring[k].1, ring[(k + 1) % n].1);
            if p == o || q == o {
                return Ok(None);
            }
            let s1 = self.l.orient(u, w, p, o);
            let s2 = self.l.orient(u, w, o, q);
            if s1 == Orientation::Positive && s2 == Orientation::Positive {
                return Ok(Some((p, q)));
            }
            if s1 == Orientation::Zero && self.in_triangle(p, [u, w, o]) {
                return Err(Stuck::Through(p));
            }
        }
        Ok(None)
    }

    /// True when vertex `p`, coplanar with triangle `t`, lies in its closed interior
    /// minus the corners (the angular tests around the three edges).
    fn in_triangle(&self, p: u32, t: [u32; 3]) -> bool {
        // Project along the normal: use the sign of orient(a, b, p, apex) with an apex
        // off the plane; any tet vertex off the plane serves. A cheap exact way: p is
        // inside iff it is on the same side of each edge as the opposite corner, tested
        // with orient3d against a lifted point.
        let (a, b, c) = (self.l.p(t[0]), self.l.p(t[1]), self.l.p(t[2]));
        let n = (b - a).cross(c - a);
        let lift = a + n;
        let pp = self.l.p(p);
        use crate::geom::predicates::orient3d;
        let s = [
            orient3d(a, b, lift, pp),
            orient3d(b, c, lift, pp),
            orient3d(c, a, lift, pp),
        ];
        let r = [
            orient3d(a, b, lift, c),
            orient3d(b, c, lift, a),
            orient3d(c, a, lift, b),
        ];
        (0..3).all(|k| s[k] == r[k] || s[k] == Orientation::Zero)
    }
}

/// The closest points of the line `p + t d` and the segment `xy` (inexact): the
/// parameter `t` and the distance, or `None` for (nearly) parallel lines or when the
/// closest point of the line `xy` is outside the segment.
fn closest_parameter(p: Point, d: Point, x: Point, y: Point) -> Option<(f64, f64)> {
    let e = y - x;
    let w = p - x;
    let (a, b, c) = (d.dot(d), d.dot(e), e.dot(e));
    let (dd, ee) = (d.dot(w), e.dot(w));
    let den = a * c - b * b;
    if den <= 1e-12 * a * c {
        return None;
    }
    let t = (b * ee - c * dd) / den;
    let s = (a * ee - b * dd) / den;
    if !(0.0..=1.0).contains(&s) {
        return None;
    }
    Some((t, ((p + d * t) - (x + e * s)).length()))
}

/// Where the line through `a` and `b` meets the plane of triangle `f` (inexact), or
/// `None` when it is (nearly) parallel to it.
fn segment_plane(a: Point, b: Point, f: [Point; 3]) -> Option<Point> {
    let n = (f[1] - f[0]).cross(f[2] - f[0]);
    let den = n.dot(b - a);
    if den.abs() <= f64::EPSILON * n.length() * (b - a).length() {
        return None;
    }
    Some(a + (b - a) * (n.dot(f[0] - a) / den))
}
