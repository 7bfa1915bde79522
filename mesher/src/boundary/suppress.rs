//! Steiner point suppression after the recovery (paper §4.2: Steiner points are removed
//! or relocated where the mesh allows; George, Borouchaki and Saltel, "'Ultimate'
//! robustness in meshing an arbitrary polyhedron", IJNME 2003, §5).
//!
//! - An interior Steiner point goes when its star can be re-tetrahedralised as the cone
//!   from one of its neighbours.
//! - A split point `m` on an input edge `(u, w)` goes when its star can be rebuilt with
//!   the two unsplit triangles `(u, w, c)` and `(u, w, d)` as faces: they cut the star
//!   into two parts (one on each side of the surface), and each part is the cone from
//!   one of its own vertices that sees all its faces, or else from a new point in its
//!   kernel, an interior Steiner point (outside the domain, on the outer side, it
//!   disappears with the outside). When no point sees a part (the split point is off
//!   its edge by rounding on a flat part of the surface, so that part is slivers that
//!   vanish), the part grows outside the star, across the faces a candidate apex does
//!   not see, until a vertex sees it all: the cone of the segment recovery, applied to
//!   a side. The surface is then unsplit there.

use super::flips::Choice;
use super::local::{Marks, GHOST};
use super::reconnect;
use super::recover::Recovery;

/// Edge removals at a Steiner point before its removal is given up.
const MAX_DEGREE_FLIPS: usize = 8;

/// The grown cone ([`Recovery::remove_grown`]: each of up to hundreds of apexes grows
/// a region) is tried at every `GROWN_EVERY`-th degree of a Steiner point on the way
/// down, and at the last; the cone from a neighbour ([`Recovery::remove_vertex`]) at
/// every degree. On turbine 164 of the 220 grown cones failed (25 ms of the 35 ms
/// suppression); at every second degree its T(S,F) takes 0.230 -> 0.217 s, with the
/// same interior Steiner points on every model and over seeds 1-6 (summed: anchor 94,
/// cheese 98, turbine 37, box-with-hole 27); at every third, anchor 95 and cheese 100.
const GROWN_EVERY: usize = 2;

/// Levels of preparatory removals (`Recovery::remove_deep`) for an edge at a Steiner
/// point being taken out. Level 1 leaves fewer interior Steiner points on cheese
/// (26 -> 23) and anchor (22 -> 21) for 0.02 s more on cheese; level 2 takes one more
/// on turbine and hinge for 0.05 s more on cheese, level 3 nothing more.
const SUPPRESS_FLIP_DEPTH: usize = 1;

/// Tets a side of a point's star may take in from outside the star. Every success
/// seen over the corpus takes at most 75 (on average 9-13), while most apexes tried
/// fail, many only at this bound: 256 -> 128 takes a third of the growth's
/// instructions on turbine and cheese (3 % of their boundary mesh), with the same
/// meshes on every model of the boundary sweep (96 costs oblong a Steiner point).
const MAX_SIDE_GROWTH: usize = 128;

/// A face of a side passes "through" its split point when it is this close to it,
/// relative to the nearest vertex ([`Recovery::near_point`]).
const NEAR_FACE: f64 = 1e-6;

/// Perceptron steps that turn the direction off a split point into every face near it.
const PERCEPTRON_STEPS: usize = 64;
use crate::geom::predicates::{orient3d, Orientation};
use crate::geom::Point;
use crate::surface::sorted_ids;
use crate::tetmesh::{FaceRef, FACE_VERTICES};
use crate::FastSet;

impl Recovery {
    /// Removes vertex `s` (a Steiner point, on no constrained entity): its star is
    /// re-tetrahedralised as the cone from one of its neighbours that sees every face of
    /// the star's boundary (tried in id order). Constrained edges and faces are never on
    /// the inside of the star (they do not touch `s`), so they all stay.
    pub fn remove_vertex(&mut self, s: u32) -> bool {
        let mut star = Vec::new();
        self.l.star(s, &mut star);
        if star.is_empty() || star.iter().any(|&t| self.l.is_ghost(t)) {
            return false;
        }
        let Some(link) = self.link(s, &star) else {
            return false;
        };
        let mut nbrs: Vec<u32> = link.iter().flatten().copied().collect();
        nbrs.sort_unstable();
        nbrs.dedup();
        for u in nbrs {
            // Checked before anything is built: most neighbours fail on an early face.
            let sees_all = link
                .iter()
                .filter(|f| !f.contains(&u))
                .all(|f| self.l.orient(f[0], f[1], f[2], u) == Orientation::Positive);
            if !sees_all {
                continue;
            }
            let new: Vec<[u32; 4]> = link
                .iter()
                .filter(|f| !f.contains(&u))
                .map(|f| [f[0], f[1], f[2], u])
                .collect();
            if self.l.replace(&star, &new).is_ok() {
                return true;
            }
        }
        false
    }

    /// Removes the interior Steiner point `s`: the cone from a neighbour, or from a
    /// vertex near it over its grown star (at every [`GROWN_EVERY`]-th degree), else
    /// edge removals at `s` (each lowers its degree) until a cone works; bounded. With
    /// `deep`, then a search for any tetrahedralisation of its star without it, and
    /// again after removals of edges of its link
    /// ([`Recovery::remove_by_reconnection`]). The flips made on a failed attempt
    /// stay: each is a checked, valid change that keeps every lock (the undo journal
    /// cannot replay a chain of flips that re-use tet slots).
    pub fn remove_steiner(&mut self, s: u32, deep: bool) -> bool {
        // Whether the grown cone was tried at the star as it is now.
        let mut grown = false;
        self.with_fewer_edges(s, |rec, at| match at {
            Degree::Step(k) => {
                grown = k % GROWN_EVERY == 0;
                rec.remove_vertex(s) || (grown && rec.remove_grown(s))
            }
            Degree::Last => !grown && rec.remove_grown(s),
        }) || (deep
            && (self.remove_by_reconnection(s, reconnect::SEARCH_BUDGET)
                || self.remove_after_link_flips(s)))
    }

    /// `remove()`, and if it fails, again after each edge removal at `s` (each lowers
    /// its degree, which may make its star easier to re-tetrahedralise), and once more
    /// as [`Degree::Last`] when the removals end; bounded. The flips made on a failed
    /// attempt stay: each is a checked, valid change that keeps every lock.
    fn with_fewer_edges(
        &mut self,
        s: u32,
        mut remove: impl FnMut(&mut Self, Degree) -> bool,
    ) -> bool {
        if remove(self, Degree::Step(0)) {
            return true;
        }
        self.l.forget();
        for step in 1..=MAX_DEGREE_FLIPS {
            let mut star = Vec::new();
            self.l.star(s, &mut star);
            let mut nbrs: Vec<u32> = star
                .iter()
                .flat_map(|&t| self.l.tet(t))
                .filter(|&x| x != s && x != GHOST)
                .collect();
            nbrs.sort_unstable();
            nbrs.dedup();
            let removed = nbrs
                .into_iter()
                .any(|x| self.remove_deep(s, x, Choice::Best, SUPPRESS_FLIP_DEPTH));
            if !removed {
                break;
            }
            if remove(self, Degree::Step(step)) {
                self.l.forget();
                return true;
            }
        }
        let done = remove(self, Degree::Last);
        self.l.forget();
        done
    }

    /// Removes vertex `s` by the cone from a vertex near it over its star grown across
    /// the faces that vertex does not see (see [`Recovery::grown_side`]).
    fn remove_grown(&mut self, s: u32) -> bool {
        let mut star = Vec::new();
        self.l.star(s, &mut star);
        if star.is_empty() || star.iter().any(|&t| self.l.is_ghost(t)) {
            return false;
        }
        let Some((extra, cone)) = self.grown_side(s, &star, &[]) else {
            return false;
        };
        let mut old = star;
        old.extend(extra);
        let locked = self.locked_in(&old, s);
        let mark = self.l.mark();
        let done = self.l.replace(&old, &cone).is_ok();
        if done && !locked.iter().all(|&(x, y)| self.has_edge(x, y)) {
            self.l.undo(mark);
            self.l.forget();
            return false;
        }
        self.l.forget();
        done
    }

    /// The faces of the star of `s` opposite `s`, seen from inside the star.
    fn link(&self, s: u32, star: &[u32]) -> Option<Vec<[u32; 3]>> {
        star.iter()
            .map(|&t| {
                let v = self.l.tet(t);
                let i = (0..4).find(|&i| v[i] == s)?;
                Some(FACE_VERTICES[i].map(|k| v[k]))
            })
            .collect()
    }

    /// Removes the split point `m` of input edge `(u, w)`, whose surface star is the
    /// triangles `(u, m, c)`, `(m, w, c)`, `(u, m, d)`, `(m, w, d)`; on success the
    /// mesh has the faces `(u, w, c)` and `(u, w, d)` and the locks follow.
    pub fn suppress_split(&mut self, split: [u32; 3], cd: [u32; 2]) -> bool {
        self.with_fewer_edges(split[0], |rec, at| {
            matches!(at, Degree::Step(_)) && rec.suppress_split_once(split, cd)
        })
    }

    /// [`Recovery::suppress_split`] on the star as it is.
    fn suppress_split_once(&mut self, [m, u, w]: [u32; 3], [c, d]: [u32; 2]) -> bool {
        let mut star = Vec::new();
        self.l.star(m, &mut star);
        if star.is_empty() || star.iter().any(|&t| self.l.is_ghost(t)) {
            return false;
        }
        let cut = [[u, m, c], [m, w, c], [u, m, d], [m, w, d]].map(sorted_ids);
        let Some(sides) = self.sides(m, &star, &cut) else {
            return false;
        };
        let mut new: Vec<[u32; 4]> = Vec::new();
        let mut old = star.clone();
        let mut added = Vec::new();
        for side in &sides {
            let Some(mut faces) = self.link(m, side) else {
                return self.give_up(&added);
            };
            // The unsplit triangles, seen from this side: a tet of the side on
            // (u, m, c) tells which side of the plane it is. Its far vertex is tested
            // against the unsplit triangle itself: in a thin fold of the surface the
            // other triangle's vertex is that far vertex, and a split point off its
            // edge by rounding can put it on the other side of (u, m, c). Only when
            // it is in the unsplit triangle's plane (a flat part) does the split
            // triangle decide.
            for x in [c, d] {
                let Some(q) = side.iter().find_map(|&t| {
                    let v = self.l.tet(t);
                    let has = [u, m, x].iter().all(|y| v.contains(y));
                    has.then(|| v.into_iter().find(|y| ![u, m, x].contains(y)))
                        .flatten()
                }) else {
                    return self.give_up(&added);
                };
                let side_of = match self.l.orient(u, w, x, q) {
                    Orientation::Zero => self.l.orient(u, m, x, q),
                    o => o,
                };
                faces.push(if side_of == Orientation::Positive {
                    [u, w, x]
                } else {
                    [w, u, x]
                });
            }
            let n = faces.len();
            let apex = match self.apex(&faces) {
                Some(a) => a,
                None => match self
                    .near_point(m, &faces[n - 2..], &faces)
                    .or_else(|| self.kernel_point(&faces))
                {
                    Some(p) => {
                        let v = self.l.mesh.push_vertex(p).0;
                        added.push(v);
                        v
                    }
                    None => {
                        // No point sees the side (a split point off its edge by
                        // rounding, on a flat part of the surface): the side grows
                        // outside the star until one of its vertices sees it all.
                        let Some((extra, cone)) = self.grown_side(m, side, &faces[n - 2..]) else {
                            return self.give_up(&added);
                        };
                        old.extend(extra);
                        new.extend(cone);
                        continue;
                    }
                },
            };
            new.extend(
                faces
                    .iter()
                    .filter(|f| !f.contains(&apex))
                    .map(|f| [f[0], f[1], f[2], apex]),
            );
        }
        let locked = self.locked_in(&old, m);
        let mark = self.l.mark();
        if self.l.replace(&old, &new).is_err() {
            self.l.forget();
            return self.give_up(&added);
        }
        if !locked.iter().all(|&(x, y)| self.has_edge(x, y)) {
            self.l.undo(mark);
            self.l.forget();
            return self.give_up(&added);
        }
        self.l.forget();
        self.steiner.extend(&added);
        for f in cut {
            self.locks.faces.remove(&f);
        }
        for x in [u, w, c, d] {
            self.locks.edges.remove(&(m.min(x), m.max(x)));
        }
        self.locks.edges.insert((u.min(w), u.max(w)));
        self.locks.faces.insert(sorted_ids([u, w, c]));
        self.locks.faces.insert(sorted_ids([u, w, d]));
        true
    }

    /// One side of the star of split point `m` grown outside the star: starting from
    /// the side's tets, every boundary face that the candidate apex does not see brings
    /// in the tet behind it (never across a locked face or into the hull), as in the
    /// cone of the segment recovery. The apex is tried among the vertices of the tets
    /// next to the side. Returns the tets added and the cone (with the `cut` faces, the
    /// unsplit triangles seen from this side).
    fn grown_side(
        &self,
        m: u32,
        side: &[u32],
        cut: &[[u32; 3]],
    ) -> Option<(Vec<u32>, Vec<[u32; 4]>)> {
        let mut candidates: Vec<u32> = Vec::new();
        let in_side: FastSet<u32> = side.iter().copied().collect();
        // The side's boundary faces away from `m` with the tet behind each, in the
        // order the growth meets them: every apex starts there (hundreds are tried).
        let mut rim: Vec<([u32; 3], u32)> = Vec::new();
        for &t in side {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let u = FaceRef::from_raw(adj[i]).tet().0;
                if !in_side.contains(&u) {
                    if !self.l.is_ghost(u) {
                        candidates.extend(self.l.tet(u));
                    }
                    let f = FACE_VERTICES[i].map(|j| v[j]);
                    if !f.contains(&m) {
                        rim.push((f, u));
                    }
                }
            }
        }
        candidates.retain(|&v| v != m && v != GHOST);
        candidates.sort_unstable();
        candidates.dedup();
        let walls: Vec<[u32; 3]> = rim
            .iter()
            .filter(|&&(f, u)| self.locks.face(f) || self.l.is_ghost(u) || side_of_star(self, u, m))
            .map(|&(f, _)| f)
            .collect();
        let side = Side {
            m,
            tets: side,
            set: &in_side,
            rim: &rim,
            walls: &walls,
            cut,
        };
        candidates
            .into_iter()
            .find_map(|apex| self.grow_from(&side, apex))
    }

    /// [`Recovery::grown_side`] for one apex.
    fn grow_from(&self, side: &Side, apex: u32) -> Option<(Vec<u32>, Vec<[u32; 4]>)> {
        let m = side.m;
        // The cut faces must be seen, and so must the walls: the growth cannot cross
        // them (and a region that took in the tet behind a locked face by another way
        // would lose that face).
        if side.cut.iter().chain(side.walls).any(|f| {
            !f.contains(&apex) && self.l.orient(f[0], f[1], f[2], apex) != Orientation::Positive
        }) {
            return None;
        }
        // This apex's additions, in order (the side's set is shared by every apex).
        let mut marks = self.grow_marks.borrow_mut();
        marks.clear(self.l.mesh.num_slots());
        let mut added = Added {
            list: Vec::with_capacity(MAX_SIDE_GROWTH + 1),
            marks,
        };
        // The side's rim first, then the faces of the tets added, in order.
        let mut k = 0;
        let mut rim = side.rim.iter();
        loop {
            let (f, u) = match rim.next() {
                Some(&(f, u)) => (f, u),
                None => {
                    let Some(&t) = added.list.get(k / 4) else {
                        break;
                    };
                    let i = k % 4;
                    k += 1;
                    let f = FACE_VERTICES[i].map(|j| self.l.tet(t)[j]);
                    let u = FaceRef::from_raw(self.l.adj(t)[i]).tet().0;
                    if f.contains(&m) || side.set.contains(&u) {
                        continue;
                    }
                    (f, u)
                }
            };
            if f.contains(&apex) || added.contains(u) {
                continue;
            }
            if self.l.orient(f[0], f[1], f[2], apex) == Orientation::Positive {
                continue;
            }
            if self.locks.face(f) || self.l.is_ghost(u) || side_of_star(self, u, m) {
                return None;
            }
            added.push(u);
            if added.list.len() > MAX_SIDE_GROWTH {
                return None;
            }
        }
        let member = |u: u32| side.set.contains(&u) || added.contains(u);
        let mut cone: Vec<[u32; 4]> = Vec::new();
        for &t in side.tets.iter().chain(&added.list) {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let f = FACE_VERTICES[i].map(|j| v[j]);
                let u = FaceRef::from_raw(adj[i]).tet().0;
                if !f.contains(&m) && !f.contains(&apex) && !member(u) {
                    cone.push([f[0], f[1], f[2], apex]);
                }
            }
        }
        cone.extend(
            side.cut
                .iter()
                .filter(|f| !f.contains(&apex))
                .map(|f| [f[0], f[1], f[2], apex]),
        );
        // Every vertex of the region but `m` stays: the apex or on a face of the cone.
        let on_cone: FastSet<u32> = cone.iter().flat_map(|c| c[..3].iter().copied()).collect();
        let kept = side
            .tets
            .iter()
            .chain(&added.list)
            .flat_map(|&t| self.l.tet(t))
            .all(|x| x == m || x == apex || on_cone.contains(&x));
        kept.then_some((added.list, cone))
    }

    /// Locked edges of the tets `region` that do not end at `m`.
    fn locked_in(&self, region: &[u32], m: u32) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for &t in region {
            let v = self.l.tet(t);
            for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                let (x, y) = (v[i], v[j]);
                if x != m && y != m && self.locks.edge(x, y) {
                    out.push((x, y));
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The star of `m` split in two by the faces `cut`: the tets reachable from the
    /// first without crossing them, and the rest. `None` unless both are non-empty and
    /// connected.
    fn sides(&self, m: u32, star: &[u32], cut: &[[u32; 3]; 4]) -> Option<[Vec<u32>; 2]> {
        let mut side = vec![u8::MAX; star.len()];
        let pos = |t: u32| star.iter().position(|&s| s == t);
        for label in [0u8, 1] {
            let start = side.iter().position(|&s| s == u8::MAX)?;
            side[start] = label;
            let mut stack = vec![start];
            while let Some(k) = stack.pop() {
                let t = star[k];
                let v = self.l.tet(t);
                let adj = self.l.adj(t);
                for i in 0..4 {
                    if v[i] == m {
                        continue;
                    }
                    let f = sorted_ids(FACE_VERTICES[i].map(|j| v[j]));
                    if cut.contains(&f) {
                        continue;
                    }
                    let nb = FaceRef::from_raw(adj[i]).tet().0;
                    if let Some(j) = pos(nb) {
                        if side[j] == u8::MAX {
                            side[j] = label;
                            stack.push(j);
                        }
                    }
                }
            }
        }
        if side.contains(&u8::MAX) {
            return None;
        }
        let part = |l: u8| -> Vec<u32> {
            (0..star.len())
                .filter(|&k| side[k] == l)
                .map(|k| star[k])
                .collect()
        };
        Some([part(0), part(1)])
    }

    /// A vertex of `faces` from which every face it is not on is seen positively.
    fn apex(&self, faces: &[[u32; 3]]) -> Option<u32> {
        let mut verts: Vec<u32> = faces.iter().flatten().copied().collect();
        verts.sort_unstable();
        verts.dedup();
        verts.into_iter().find(|&x| {
            faces
                .iter()
                .filter(|f| !f.contains(&x))
                .all(|f| self.l.orient(f[0], f[1], f[2], x) == Orientation::Positive)
        })
    }

    /// A point near `m` strictly inside every face of `faces`: off `m` along the
    /// bisector of the two `cut` faces (a part of the star of `m` sees every link face
    /// from points close enough to `m`, and the cut faces from inside their wedge).
    /// Faces that pass within rounding of `m` (slivers of its star, a split point off
    /// its edge by rounding) turn the direction until it points inside them all
    /// (perceptron steps over their normals), as far as they allow.
    fn near_point(&self, m: u32, cut: &[[u32; 3]], faces: &[[u32; 3]]) -> Option<Point> {
        let pm = self.l.p(m);
        let normal = |f: &[u32; 3]| {
            let [a, b, c] = f.map(|v| self.l.p(v));
            (b - a).cross(c - a).normalize_or_zero()
        };
        let bisector = cut.iter().map(normal).sum::<Point>().normalize_or_zero();
        let size = faces
            .iter()
            .flatten()
            .map(|&v| (self.l.p(v) - pm).length())
            .fold(f64::INFINITY, f64::min);
        if bisector == Point::ZERO || !size.is_finite() {
            return None;
        }
        let inside_all = |dir: Point| {
            (1..48).find_map(|k| {
                let p = pm + dir * (size * 0.5f64.powi(k));
                faces
                    .iter()
                    .all(|f| {
                        let [a, b, c] = f.map(|v| self.l.p(v));
                        orient3d(a, b, c, p) == Orientation::Positive
                    })
                    .then_some(p)
            })
        };
        if let Some(p) = inside_all(bisector) {
            return Some(p);
        }
        let mut dir = bisector;
        let close: Vec<Point> = faces
            .iter()
            .filter(|f| {
                let p0 = self.l.p(f[0]);
                normal(f).dot(pm - p0).abs() <= NEAR_FACE * size
            })
            .map(normal)
            .collect();
        for _ in 0..PERCEPTRON_STEPS {
            let Some(n) = close.iter().find(|n| n.dot(dir) <= 0.0) else {
                break;
            };
            dir = (dir + *n).normalize_or_zero();
            if dir == Point::ZERO {
                return None;
            }
        }
        inside_all(dir)
    }

    /// Takes back the points added by a failed suppression (the newest vertices).
    fn give_up(&mut self, added: &[u32]) -> bool {
        for _ in added {
            self.l.mesh.pop_vertex();
        }
        false
    }
}

/// Which attempt [`Recovery::with_fewer_edges`] makes.
#[derive(Clone, Copy, Debug)]
enum Degree {
    /// After this many edge removals at the point.
    Step(usize),
    /// When the edge removals end (none more possible, or the bound reached): the star
    /// is the one of the last step.
    Last,
}

/// One side of a point's star to grow (see [`Recovery::grown_side`]): the point, the
/// side's tets (also as a set), its rim (boundary faces away from `m`, with the tet
/// behind each) and the cut faces the cone must also see.
struct Side<'a> {
    m: u32,
    tets: &'a [u32],
    set: &'a FastSet<u32>,
    rim: &'a [([u32; 3], u32)],
    /// The rim faces the growth cannot cross (see [`Recovery::grown_side`]).
    walls: &'a [[u32; 3]],
    cut: &'a [[u32; 3]],
}

/// Tets added to a side for one apex: a list, and epoch marks of the tets for the
/// membership test (a list scanned while short, then a hash set, cost 45 M of the 187 M
/// instructions of the growths on turbine).
struct Added<'a> {
    list: Vec<u32>,
    marks: std::cell::RefMut<'a, Marks>,
}

impl Added<'_> {
    fn contains(&self, u: u32) -> bool {
        self.marks.contains(u)
    }

    fn push(&mut self, u: u32) {
        self.list.push(u);
        self.marks.insert(u);
    }
}

/// True when tet `t` has vertex `m` (it is in the star of `m`, on the other side).
fn side_of_star(r: &Recovery, t: u32, m: u32) -> bool {
    r.l.tet(t).contains(&m)
}
