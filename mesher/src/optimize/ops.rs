//! The local operations of the optimiser (paper §6.2-§6.3), each accepted only when the
//! worst `Q_K` of the tets it replaces strictly improves and every new tet is exactly
//! positive (through [`Local::replace`] or an exact check of the moved ball).
//!
//! - Edge removal: the ring polygon of the edge re-triangulated by Klincsek's dynamic
//!   program maximising the worst `1/Q_K` (Shewchuk, "Two discrete optimization
//!   algorithms for the topological improvement of tetrahedral meshes", 2002); a ring
//!   of 3 is the 3-2 flip, of 4 the 4-4 flip.
//! - Face removal: the 2-3 flip, and the multi-face removal of [`faces`].
//! - Vertex smoothing (§6.3.1): the free vertex moves towards the mean of the ideal
//!   points of its ball's faces (the apex of the regular tet on each face, on the
//!   vertex's side), or towards the mean of its neighbours (Laplacian), by the longest
//!   of a few halving steps that improves the ball; as a last resort for the worst tet,
//!   a compass search for the position that minimises the ball's worst `Q_K`.
//! - Point insertion, the last resort: the cone from a new point over a small cavity
//!   (the tet with its neighbours, the tet alone, the rings of its free edges), in
//!   [`insert`].

mod faces;
mod insert;

use super::Smoothing;
use crate::boundary::flips::{best_triangulation_above, Locks, MAX_RING};
use crate::boundary::local::Local;
use crate::geom::predicates::Orientation;
use crate::geom::search::compass_below;
use crate::geom::Point;
use crate::quality::target::face_best_q_k;
use crate::quality::tet::{
    min_dihedral, q_k, q_k_and_min_dihedral, signed_volume, WELL_SHAPED_Q_K,
};
use crate::tetmesh::{FaceRef, TetId, VertexId, FACE_VERTICES};
use crate::FastMap;
use insert::cone_score_at;
use rayon::prelude::*;
use std::cell::Cell;

/// Height of the regular tet over a face of edge `h`, over `h`: sqrt(2/3).
const REGULAR_HEIGHT: f64 = 0.816_496_580_927_726;

/// Step fractions tried by the smoothing, longest first.
const STEPS: [f64; 4] = [1.0, 0.5, 0.25, 0.125];

/// The mesh being optimised and what it must keep.
pub(super) struct Ops {
    pub l: Local,
    pub locks: Locks,
    /// Region per tet slot (0 outside the domain).
    pub region: Vec<u32>,
    /// Vertices that never move (on the boundary, box corners).
    pub fixed: Vec<bool>,
    scratch: Vec<u32>,
    /// Per tet slot: the vertices it had and its `Q_K` when last computed. An entry
    /// whose vertices differ from the slot's (the slot was reused) is stale; a moved
    /// vertex clears its ball's entries ([`Self::smooth`]), and a change clears its new
    /// tets' ([`Self::claim`]): a slot freed before a vertex of its tet moved can come
    /// back with the same four vertices (a flip undone by a later flip; the free slots
    /// are a stack), and its entry then had the old position's `Q_K` (fuzz regression
    /// `mesh/stale_qk_cache.bin`). The passes rescan every tet, and most of them are
    /// unchanged since the last scan.
    qcache: Vec<Cell<([u32; 4], f64)>>,
    /// Edge removals (key: the edge as called), vertex moves (key: `(v, v)`) and edge
    /// collapses (key: `(kept, removed)`) that failed, with the clock then
    /// ([`Self::unless_failed`]).
    failed_ops: FastMap<(u32, u32, Kind), u32>,
}

/// The ball of a free vertex and where its position searches start
/// ([`Ops::free_ball`]).
struct FreeBall {
    /// Its tets.
    star: Vec<u32>,
    /// Their faces opposite the vertex.
    link: Vec<[u32; 3]>,
    /// Its position.
    old: Point,
    /// A quarter of its shortest edge.
    step: f64,
}

/// A [`Ops::qcache`] entry that matches no tet.
const STALE: ([u32; 4], f64) = ([u32::MAX; 4], 0.0);

/// Margin of the dihedral widening over what a ball's boundary faces allow
/// ([`Ops::widen_dihedral`]): where the ball's worst `Q_K` is within 2 % of the largest
/// per-face `Q_t` term of its boundary faces (the surface is the limit there, and the
/// worst tet is as good as that face allows), the widening may raise the ball's worst
/// to 1.02 times that term. part1 (netgen data): its worst tet sits on the face that
/// sets `Q_t` (55.82 against 55.69), and its smallest angle, 0.568° with the ball's
/// worst kept, could only grow to 0.577° (a random search over the ball); at 1.02 x
/// the face's term the same vertex reaches 0.88°.
const SURFACE_MARGIN: f64 = 1.02;

impl Ops {
    pub fn new(l: Local, locks: Locks, region: Vec<u32>, fixed: Vec<bool>) -> Self {
        let qcache = vec![Cell::new(STALE); l.mesh.num_slots()];
        Ops {
            l,
            locks,
            region,
            fixed,
            scratch: Vec::new(),
            qcache,
            failed_ops: FastMap::default(),
        }
    }

    /// `Q_K` of the tet in slot `t`, from the cache when the slot is unchanged.
    pub fn tet_quality(&self, t: u32) -> f64 {
        let v = self.l.tet(t);
        let Some(entry) = self.qcache.get(t as usize) else {
            return self.quality(v);
        };
        let (cached, q) = entry.get();
        if cached == v {
            // Tests run with debug assertions: any missed invalidation shows here.
            debug_assert_eq!(
                q.to_bits(),
                self.quality(v).to_bits(),
                "stale Q_K of tet {t}"
            );
            return q;
        }
        let q = self.quality(v);
        entry.set((v, q));
        q
    }

    /// Fills the `Q_K` cache for every live finite tet of the domain, computed in
    /// parallel: the first scan of a big mesh (bunny00: 1.9 M tets) reads it.
    pub fn prime_qualities(&self) {
        let (mesh, region) = (&self.l.mesh, &self.region);
        let qualities: Vec<Option<([u32; 4], f64)>> = (0..mesh.num_slots() as u32)
            .into_par_iter()
            .map(|t| {
                let id = TetId(t);
                let inside = region.get(t as usize).is_some_and(|&r| r != 0);
                let v = mesh.raw_tet(t);
                (inside && mesh.is_alive(id) && !mesh.is_ghost(id))
                    .then(|| (v, q_k(&v.map(|x| mesh.point(VertexId(x))))))
            })
            .collect();
        for (t, q) in qualities.into_iter().enumerate() {
            if let (Some(q), Some(entry)) = (q, self.qcache.get(t)) {
                entry.set(q);
            }
        }
    }

    /// `Q_K` of a tet given by its vertices.
    pub fn quality(&self, t: [u32; 4]) -> f64 {
        q_k(&t.map(|v| self.l.p(v)))
    }

    /// Smallest dihedral angle of tet `t`, in degrees.
    pub fn min_dihedral(&self, t: u32) -> f64 {
        min_dihedral(&self.l.tet(t).map(|v| self.l.p(v)))
    }

    /// Region of tet slot `t` (0 outside or unknown).
    pub fn region_of(&self, t: u32) -> u32 {
        self.region.get(t as usize).copied().unwrap_or(0)
    }

    fn worst(&self, tets: &[u32]) -> f64 {
        tets.iter()
            .map(|&t| self.tet_quality(t))
            .fold(1.0, f64::max)
    }

    /// [`Self::worst`] when it is below `bound`; otherwise some value `>= bound` (it
    /// stops at the first tet that reaches the bound: a failed move is known early).
    /// Never from the cache: smoothing calls it with the vertex at a trial position.
    fn worst_below(&self, tets: &[u32], bound: f64) -> f64 {
        max_until(tets.iter().map(|&t| self.quality(self.l.tet(t))), bound)
    }

    /// Gives the tets of the last replace the region `r` and no cached `Q_K`.
    fn claim(&mut self, r: u32) {
        let n = self.l.mesh.num_slots();
        if self.region.len() < n {
            self.region.resize(n, 0);
        }
        if self.qcache.len() < n {
            self.qcache.resize(n, Cell::new(STALE));
        }
        for &t in &self.l.created {
            self.region[t as usize] = r;
            self.qcache[t as usize].set(STALE);
        }
    }

    /// `op()`, unless the operation `key` failed and nothing at its vertices has
    /// changed since (it would fail again); a failure is remembered.
    fn unless_failed(&mut self, key: (u32, u32, Kind), op: impl FnOnce(&mut Self) -> bool) -> bool {
        if let Some(&since) = self.failed_ops.get(&key) {
            if !self.l.stamps.changed_since(&[key.0, key.1], since) {
                return false;
            }
        }
        let done = op(self);
        if !done {
            self.failed_ops.insert(key, self.l.stamps.clock);
        }
        done
    }

    /// Removes edge `xy` of tet `t` if the best re-triangulation of its ring is better.
    /// (The ring applied starts where [`Local::ring`] finds the edge: starting it
    /// elsewhere, say at the bad tet, rotates the polygon, which changes the choice
    /// among equally good triangulations and so the whole run; the ring read from `t`
    /// only rules out the removals that fail.) An edge that failed is not tried again
    /// until a tet at one of its ends has changed. The key is the edge as called: the
    /// ring's orientation and start, so rounding at a tie, follow the order.
    pub fn remove_edge(&mut self, t: u32, x: u32, y: u32) -> bool {
        // A constrained edge stays: answered before the memory of failures (which it
        // would only fill).
        if self.locks.edge(x, y) {
            return false;
        }
        self.unless_failed((x, y, Kind::Remove), |o| o.remove_edge_now(t, x, y))
    }

    fn remove_edge_now(&mut self, t: u32, x: u32, y: u32) -> bool {
        // Most removals fail, and whether one succeeds does not depend on where its ring
        // starts but through rounding (only ties among equally good triangulations do):
        // the ring read from `t` answers that without a search for the edge; only a
        // removal that will be made reads the ring as the search finds it, whose start
        // decides the ties (on the corpus, only cheese's mesh changed).
        let Some(ring) = self.l.ring_from(t, x, y) else {
            return false;
        };
        let Some(plan) = self.removal_plan(&ring, x, y) else {
            return false;
        };
        // The search's ring is the one read, and its plan the one made, when the search
        // lands on `t`.
        let Some(t0) = self.l.find_edge(x, y, &mut self.scratch) else {
            return false;
        };
        let (ring, (r, new)) = if t0 == t {
            (ring, plan)
        } else {
            let Some(ring) = self.l.ring_from(t0, x, y) else {
                return false;
            };
            let Some(plan) = self.removal_plan(&ring, x, y) else {
                return false;
            };
            (ring, plan)
        };
        let old: Vec<u32> = ring.iter().map(|e| e.0).collect();
        if self.l.replace(&old, &new).is_err() {
            return false;
        }
        self.claim(r);
        true
    }

    /// The best re-triangulation of the ring of edge `xy` (`ring` as [`Local::ring`]
    /// lists it) with its region, when it beats the ring's worst `Q_K`.
    fn removal_plan(&self, ring: &[(u32, u32)], x: u32, y: u32) -> Option<(u32, Vec<[u32; 4]>)> {
        if ring.len() < 3 || ring.len() > MAX_RING {
            return None;
        }
        // On the stack (a ring has at most MAX_RING tets): most removals are tried
        // and fail, and four small allocations were a tenth of their cost.
        let n = ring.len();
        let (mut old, mut poly, mut pts) =
            ([0u32; MAX_RING], [0u32; MAX_RING], [Point::ZERO; MAX_RING]);
        for (k, &(t, p)) in ring.iter().enumerate() {
            (old[k], poly[k], pts[k]) = (t, p, self.l.p(p));
        }
        let (old, poly) = (&old[..n], &poly[..n]);
        let r = self.region_of(old[0]);
        if r == 0 || old.iter().any(|&t| self.region_of(t) != r) {
            return None;
        }
        let before = self.worst(old);
        let (px, py) = (self.l.p(x), self.l.p(y));
        let inv = |t: [Point; 4]| {
            if signed_volume(&t) > 0.0 {
                1.0 / q_k(&t)
            } else {
                -1.0
            }
        };
        // Only a triangulation whose worst 1/Q_K beats the ring's is of use.
        let floor = 1.0 / before;
        let q = |i: usize, j: usize, k: usize| -> f64 {
            let (a, b, c) = (pts[i], pts[j], pts[k]);
            let up = inv([a, b, c, py]);
            if up <= floor {
                return up;
            }
            up.min(inv([b, a, c, px]))
        };
        let idx: [usize; MAX_RING] = std::array::from_fn(|k| k);
        let tris = best_triangulation_above(&idx[..n], &q, floor)?;
        let mut new = Vec::with_capacity(tris.len() * 2);
        for [i, j, k] in tris {
            let (a, b, c) = (poly[i], poly[j], poly[k]);
            new.push([a, b, c, y]);
            new.push([b, a, c, x]);
        }
        let after = new.iter().map(|&t| self.quality(t)).fold(1.0, f64::max);
        (after < before).then_some((r, new))
    }

    /// The 2-3 flip of the face opposite vertex `i` of tet `t`, if better.
    pub fn flip23(&mut self, t: u32, i: usize) -> bool {
        let v = self.l.tet(t);
        let f = FACE_VERTICES[i].map(|k| v[k]);
        if self.locks.face(f) {
            return false;
        }
        let nb = FaceRef::from_raw(self.l.adj(t)[i]);
        let u = nb.tet().0;
        let r = self.region_of(t);
        if self.l.is_ghost(u) || r == 0 || self.region_of(u) != r {
            return false;
        }
        let (d, e) = (v[i], self.l.tet(u)[nb.facet()]);
        let new = [[f[0], f[1], e, d], [f[1], f[2], e, d], [f[2], f[0], e, d]];
        let before = self.worst(&[t, u]);
        let after = max_until(new.iter().map(|&t| self.quality(t)), before);
        if after >= before || self.l.replace(&[t, u], &new).is_err() {
            return false;
        }
        self.claim(r);
        true
    }

    /// Moves free vertex `v` if that improves the worst tet of its ball.
    pub fn smooth(&mut self, v: u32, how: Smoothing) -> bool {
        if how == Smoothing::Off || self.fixed.get(v as usize) != Some(&false) {
            return false;
        }
        // A neighbour's move changes the tets at `v` too.
        self.unless_failed((v, v, Kind::Smooth), |o| o.smooth_now(v, how))
    }

    /// The star of `v` (all in the domain, no ghost) and its link: the faces opposite
    /// `v`, each as its tet lists it (`v` on the positive side); `None` otherwise.
    fn ball(&self, v: u32) -> Option<(Vec<u32>, Vec<[u32; 3]>)> {
        let mut star = Vec::with_capacity(STAR_CAPACITY);
        self.l.star(v, &mut star);
        if star.is_empty()
            || star
                .iter()
                .any(|&t| self.l.is_ghost(t) || self.region_of(t) == 0)
        {
            return None;
        }
        let mut link = Vec::with_capacity(star.len());
        for &t in &star {
            let tv = self.l.tet(t);
            let i = (0..4).find(|&i| tv[i] == v)?;
            link.push(FACE_VERTICES[i].map(|k| tv[k]));
        }
        Some((star, link))
    }

    fn smooth_now(&mut self, v: u32, how: Smoothing) -> bool {
        let Some((star, link)) = self.ball(v) else {
            return false;
        };
        // The optimal point first; where it does not help, the apex of the regular tet
        // on the face of the worst tet opposite the vertex (which lifts a sliver off its
        // flat direction), then the Laplacian point.
        let tries: &[Smoothing] = match how {
            Smoothing::Optimal => &[Smoothing::Optimal, Smoothing::Off, Smoothing::Laplacian],
            _ => &[how],
        };
        let old = self.l.p(v);
        let qs: Vec<f64> = star.iter().map(|&t| self.tet_quality(t)).collect();
        let before = qs.iter().copied().fold(1.0, f64::max);
        let worst_face = qs
            .iter()
            .zip(&link)
            .max_by(|a, b| a.0.total_cmp(b.0))
            .map(|w| *w.1);
        // The ball's worst tets first: a trial that fails (most do) usually fails on
        // them, and `worst_below` stops there. Its answer does not depend on the order.
        let mut by_quality: Vec<(f64, u32)> =
            qs.iter().copied().zip(star.iter().copied()).collect();
        by_quality.sort_by(|a, b| b.0.total_cmp(&a.0));
        let star: Vec<u32> = by_quality.into_iter().map(|x| x.1).collect();
        for &kind in tries {
            let target = match (kind, worst_face) {
                (Smoothing::Off, Some(f)) => self.target(&[f], v, Smoothing::Optimal),
                (Smoothing::Off, None) => None,
                _ => self.target(&link, v, kind),
            };
            let Some(target) = target else {
                continue;
            };
            for s in STEPS {
                let p = old + (target - old) * s;
                self.l.set_point(v, p);
                // The quality first (Q_K is orientation-blind, so the exact orientation
                // test is still needed, but only for the few moves that improve).
                let positive = || {
                    link.iter()
                        .all(|f| self.l.orient(f[0], f[1], f[2], v) == Orientation::Positive)
                };
                if self.worst_below(&star, before) < before && positive() {
                    self.moved(&star);
                    return true;
                }
            }
        }
        self.l.set_point(v, old);
        false
    }

    /// Moves the free vertex `v` to where its ball's worst `Q_K` is lowest: a random
    /// descent out to its shortest edge, then the compass searches from the best point
    /// found. The last resort for a worst tet with a free vertex, at a balance between
    /// several bad tets of the ball that the smoothing's targets do not reach. Accepted
    /// if the worst drops and the ball stays exactly positive.
    pub fn smooth_search(&mut self, v: u32) -> bool {
        let Some(FreeBall {
            star,
            link,
            old,
            step,
        }) = self.free_ball(v)
        else {
            return false;
        };
        let before = self.worst(&star);
        let corners = self.face_points(&link);
        let score = |q, beat| cone_score_at(&corners, q, beat);
        // The ball's worst is a maximum of several tets' Q_K: a local search from the
        // vertex can settle in a basin next to a better one (homer, CGAL data: a free
        // vertex between two tets stayed at Q_K 112 where its ball allows 78, 0.84 of
        // its shortest edge away). The random descent jumps there first; the compass
        // polishes.
        let (start, value) = random_descent_below(score, old, before, step * 4.0);
        let (after, p) = compass_below(score, start, value, step);
        after < before && self.move_checked(v, p, &star, &link)
    }

    /// Moves the free vertex `v` where its ball's smallest dihedral angle is largest
    /// (a compass search), under three conditions: no tet of the ball gets worse than
    /// the ball's bound (below), none of its well-shaped tets (`Q_K` < 3) stops being
    /// so, and every tet stays exactly positive. True when the smallest angle grew.
    ///
    /// The bound is the ball's worst `Q_K`, except where that is within
    /// [`SURFACE_MARGIN`] of what the ball's boundary faces allow (the largest of their
    /// per-face `Q_t` terms, paper §8: no apex gives a tet on such a face a lower
    /// `Q_K`): there the ball may use that margin, never above `ceiling`, and may trade
    /// well-shaped tets one for one (it keeps as many), and a random descent comes
    /// before the compass (the wider angles lie across ridges of the objective: part1
    /// 0.568° with the worst kept, 0.618° with the margin alone, 0.881° with both).
    pub fn widen_dihedral(&mut self, v: u32, ceiling: f64) -> bool {
        let Some(FreeBall {
            star,
            link,
            old,
            step,
        }) = self.free_ball(v)
        else {
            return false;
        };
        let qs: Vec<f64> = star.iter().map(|&t| self.tet_quality(t)).collect();
        let worst = qs.iter().copied().fold(1.0, f64::max);
        let bound = worst.max((self.faces_allow(&link) * SURFACE_MARGIN).min(ceiling));
        // Minimised: minus the smallest angle; infinite where a condition fails.
        // At the surface's limit, well-shaped tets may be traded one for one; elsewhere
        // each stays well-shaped.
        let at_limit = bound > worst;
        let good = qs.iter().filter(|&&q| q < WELL_SHAPED_Q_K).count();
        // The tets with the smallest angles first, each with its corners read once: a
        // trial point is mostly no better, and the score stops at the first tet that
        // shows it (`beat`: the value to beat). Part1's widening searched 2 k points
        // over a ball of 30 tets, a third of its whole run.
        let mut order: Vec<(f64, usize)> = star
            .iter()
            .enumerate()
            .map(|(k, &t)| (self.min_dihedral(t), k))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let faces: Vec<([Point; 3], f64)> = order
            .iter()
            .map(|&(_, k)| (link[k].map(|x| self.l.p(x)), qs[k]))
            .collect();
        let score = |p: Point, beat: f64| {
            let mut angle = f64::INFINITY;
            let mut lost = 0;
            for &([a, b, c], q0) in &faces {
                let t = [a, b, c, p];
                if signed_volume(&t) <= 0.0 {
                    return f64::INFINITY;
                }
                let (q, smallest) = q_k_and_min_dihedral(&t);
                let spoilt = q0 < WELL_SHAPED_Q_K && q >= WELL_SHAPED_Q_K;
                if q > bound || (spoilt && !at_limit) {
                    return f64::INFINITY;
                }
                lost += usize::from(q >= WELL_SHAPED_Q_K);
                angle = angle.min(smallest);
                if -angle >= beat {
                    return -angle;
                }
            }
            if faces.len() - lost < good {
                return f64::INFINITY;
            }
            -angle
        };
        let before = score(old, f64::INFINITY);
        if !before.is_finite() {
            return false;
        }
        let (start, value) = if at_limit {
            random_descent_below(score, old, before, step * 4.0)
        } else {
            (old, before)
        };
        let (after, p) = compass_below(score, start, value, step);
        after < before && self.move_checked(v, p, &star, &link)
    }

    /// The largest per-face `Q_t` term (paper §8) of the constrained faces among
    /// `faces` (0 when there is none): no tet on such a face has a lower `Q_K`.
    fn faces_allow(&self, faces: &[[u32; 3]]) -> f64 {
        faces
            .iter()
            .filter(|f| self.locks.face(**f))
            .map(|f| {
                let [a, b, c] = f.map(|x| self.l.p(x));
                face_best_q_k(a, b, c)
            })
            .fold(0.0, f64::max)
    }

    /// The ball of the free vertex `v` (its tets and their faces opposite `v`), its
    /// position, and the first step of the searches for a better one: a quarter of its
    /// shortest edge. `None` for a fixed vertex, a ball that leaves the domain or a
    /// degenerate step.
    fn free_ball(&self, v: u32) -> Option<FreeBall> {
        if self.fixed.get(v as usize) != Some(&false) {
            return None;
        }
        let (star, link) = self.ball(v)?;
        let old = self.l.p(v);
        let step = link
            .iter()
            .flatten()
            .map(|&x| self.l.p(x).distance(old))
            .fold(f64::INFINITY, f64::min)
            * 0.25;
        (step.is_finite() && step > 0.0).then_some(FreeBall {
            star,
            link,
            old,
            step,
        })
    }

    /// Moves `v` to `p` if every tet of its ball (`star`, faces `link`) stays exactly
    /// positive, and marks the ball changed; otherwise leaves `v` where it was.
    fn move_checked(&mut self, v: u32, p: Point, star: &[u32], link: &[[u32; 3]]) -> bool {
        let old = self.l.p(v);
        self.l.set_point(v, p);
        let positive = link
            .iter()
            .all(|f| self.l.orient(f[0], f[1], f[2], v) == Orientation::Positive);
        if !positive {
            self.l.set_point(v, old);
            return false;
        }
        self.moved(star);
        true
    }

    /// Marks the tets of a moved vertex's ball as changed.
    fn moved(&mut self, star: &[u32]) {
        for &t in star {
            if let Some(entry) = self.qcache.get(t as usize) {
                entry.set(STALE);
            }
        }
        let verts: Vec<u32> = star.iter().flat_map(|&t| self.l.tet(t)).collect();
        self.l.stamps.touch(verts);
    }

    /// Collapses the edge `xy` onto `x`: the free vertex `y` goes, and its ball becomes
    /// the cone from `x` over the faces of its link that do not have `x` (paper §6's
    /// edge collapse), if every new tet is positive and the ball's worst `Q_K` drops.
    /// `y` is interior to one region (free vertices are off the boundary), so the
    /// boundary is untouched. A collapse that failed is not tried again until a tet at
    /// `x` or `y` has changed.
    pub fn collapse(&mut self, x: u32, y: u32) -> bool {
        if self.fixed.get(y as usize) != Some(&false) {
            return false;
        }
        self.unless_failed((x, y, Kind::Collapse), |o| o.collapse_now(x, y))
    }

    fn collapse_now(&mut self, x: u32, y: u32) -> bool {
        let mut ball = Vec::with_capacity(STAR_CAPACITY);
        self.l.star(y, &mut ball);
        let Some(&first) = ball.first() else {
            return false;
        };
        let r = self.region_of(first);
        if r == 0
            || ball
                .iter()
                .any(|&t| self.l.is_ghost(t) || self.region_of(t) != r)
        {
            return false;
        }
        // The ball's link faces without `x` (each as its tet lists it: `y` on the
        // positive side), coned from `x`.
        let mut faces: Vec<[u32; 3]> = Vec::with_capacity(ball.len());
        let mut had_edge = false;
        for &t in &ball {
            let tv = self.l.tet(t);
            if tv.contains(&x) {
                had_edge = true;
            } else if let Some(i) = tv.iter().position(|&v| v == y) {
                faces.push(FACE_VERTICES[i].map(|k| tv[k]));
            }
        }
        if !had_edge {
            return false;
        }
        // The quality first (cheap, inexact), the exact orientations in `replace`.
        let before = self.worst(&ball);
        if self.cone_score(&faces, self.l.p(x), before) >= before {
            return false;
        }
        let new: Vec<[u32; 4]> = faces.iter().map(|f| [f[0], f[1], f[2], x]).collect();
        if self.l.replace(&ball, &new).is_err() {
            return false;
        }
        self.l.drop_vertex(y);
        self.claim(r);
        true
    }

    /// The apex of the regular tet on face `f` (its mean edge length), on its positive
    /// side.
    fn ideal_point(&self, f: &[u32; 3]) -> Point {
        let [a, b, c] = f.map(|u| self.l.p(u));
        let h = ((b - a).length() + (c - b).length() + (a - c).length()) / 3.0;
        let normal = (b - a).cross(c - a).normalize_or_zero();
        (a + b + c) / 3.0 + normal * (h * REGULAR_HEIGHT)
    }

    /// Where smoothing moves a vertex whose ball has the faces `link` (seen from it).
    fn target(&self, link: &[[u32; 3]], v: u32, how: Smoothing) -> Option<Point> {
        let n = link.len() as f64;
        let sum = match how {
            Smoothing::Off => return None,
            Smoothing::Laplacian => {
                let mut nb: Vec<u32> = link.iter().flatten().copied().collect();
                nb.sort_unstable();
                nb.dedup();
                let m = nb.len() as f64;
                return Some(nb.iter().map(|&u| self.l.p(u)).sum::<Point>() / m);
            }
            Smoothing::Optimal => link.iter().map(|f| self.ideal_point(f)).sum::<Point>(),
        };
        let t = sum / n;
        let same = v != u32::MAX && t == self.l.p(v);
        (t.is_finite() && !same).then_some(t)
    }
}

/// The kinds of operation whose failures are remembered.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Kind {
    Remove,
    Smooth,
    Collapse,
}

/// Room for a vertex's star from the start (most have 15-40 tets): a star grown from
/// empty took four reallocations each.
const STAR_CAPACITY: usize = 48;

/// Trials per scale of [`random_descent`].
const DESCENT_TRIALS: usize = 256;

/// Scales of [`random_descent`], relative to its `reach`.
const DESCENT_SCALES: [f64; 8] = [1.0, 0.5, 0.25, 0.1, 0.05, 0.02, 0.01, 0.005];

/// A random descent (a fixed seed): at each of [`DESCENT_SCALES`] times `reach`,
/// [`DESCENT_TRIALS`] points in the cube of that half width around the best point so
/// far, each taken when it lowers `score`. Returns the best point and its score (from
/// `p`, whose score is `value`). Unlike the compass, it jumps across the ridges of a
/// maximum of several functions into a better basin. `score` is told the value to beat
/// and may return any value at or above it once it knows a point is no better (see
/// [`compass_below`]).
pub(super) fn random_descent_below(
    score: impl Fn(Point, f64) -> f64,
    p: Point,
    value: f64,
    reach: f64,
) -> (Point, f64) {
    let mut rng = crate::delaunay::sort::SplitMix64::new(0xDE5C);
    let mut unit = || rng.unit() * 2.0 - 1.0;
    let mut best = (p, value);
    for s in DESCENT_SCALES {
        for _ in 0..DESCENT_TRIALS {
            let q = best.0 + Point::new(unit(), unit(), unit()) * (s * reach);
            let v = score(q, best.1);
            if v < best.1 {
                best = (q, v);
            }
        }
    }
    best
}

/// `values.fold(1.0, f64::max)` when that is below `bound`; otherwise the running maximum
/// at the first value that brings it to `bound` or above.
fn max_until(values: impl Iterator<Item = f64>, bound: f64) -> f64 {
    let mut m: f64 = 1.0;
    for q in values {
        m = m.max(q);
        if m >= bound {
            break;
        }
    }
    m
}
