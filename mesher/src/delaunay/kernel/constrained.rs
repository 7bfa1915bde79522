//! The constrained Delaunay kernel of the paper (§5.3.4, with the correction of §3):
//! inserting a field point into a mesh whose tets carry a region and whose faces may be
//! constrained (the input surface).
//!
//! - The cavity `C(P)` grows by adjacency from the tet containing `P` over tets in
//!   conflict with `P`, but never across a constrained face and never into another
//!   region (region 0 is the outside of the domain, so the cavity stays inside).
//! - Correction: while a cavity boundary face does not see `P` strictly on its inner
//!   side (a new tet would not be positive, exact `orient3d`), the cavity tet behind that
//!   face leaves the cavity, and so does any part no longer connected to the start; a
//!   vertex of the cavity that is on no boundary face (it would disappear) makes one of
//!   its tets leave. The point is rejected when the start tet itself has to leave.
//! - The result is checked to be a topological ball (Euler: `V - F/2 = 2` on the
//!   boundary) before anything changes.
//!
//! The insertion is two-phase: [`Kernel::constrained_cavity`] computes the cavity
//! without changing the mesh, the caller may inspect [`Kernel::cavity_vertices`] (e.g.
//! reject a point too close to a vertex it would connect to), then
//! [`Kernel::commit_cavity`] replaces the cavity by the ball of the new vertex. The
//! per-tet [`Constraints`] (face mask, region) are kept in sync: a new tet inherits the
//! cavity's region, and the mask bit of its outer face from the tet across it.

use super::{in_conflict, BoundaryFace, Kernel, GHOST, IN, OUT};
use crate::delaunay::DelaunayError;
use crate::geom::predicates::Orientation;
use crate::geom::Point;
use crate::tetmesh::{FaceRef, TetId, TetMesh, VertexId, FACE_VERTICES};

/// Per-tet-slot attributes of a constrained mesh, kept in sync by
/// [`Kernel::commit_cavity`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Constraints {
    /// Bit `i` set when face `i` of the tet (opposite vertex `i`) is constrained.
    pub face_mask: Vec<u8>,
    /// Region of the tet: 0 outside the domain, 1.. material regions.
    pub region: Vec<u32>,
}

impl Constraints {
    /// Grows the arrays to `slots` entries (new entries: no constraint, region 0).
    pub fn resize(&mut self, slots: usize) {
        if self.face_mask.len() < slots {
            self.face_mask.resize(slots, 0);
            self.region.resize(slots, 0);
        }
    }

    /// True when face `i` of `t` is constrained.
    #[inline]
    pub fn is_constrained(&self, t: u32, i: usize) -> bool {
        self.face_mask[t as usize] >> i & 1 != 0
    }
}

/// Why a point was not inserted by the constrained kernel (non-fatal outcomes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rejection {
    /// The point is outside the domain (in a region-0 or ghost tet).
    Outside,
    /// The point coincides with a vertex.
    OnVertex,
    /// The cavity correction emptied the cavity (the start tet had to leave).
    Emptied,
    /// The corrected cavity is not a topological ball.
    NotBall,
    /// The caller's veto refused a tet of the cavity
    /// ([`Kernel::constrained_cavity_with`]).
    Vetoed,
}

/// Bound on the correction rounds, relative to the cavity size.
const CORRECTION_ROUNDS_PER_TET: usize = 2;

impl Kernel {
    /// Locates `p` from `hint` (or the last created tet) and computes its corrected
    /// constrained cavity; the mesh is not changed. On success the cavity is kept for
    /// [`Self::commit_cavity`].
    pub fn constrained_cavity(
        &mut self,
        mesh: &TetMesh,
        cons: &Constraints,
        p: Point,
        hint: Option<TetId>,
    ) -> Result<(), Rejection> {
        self.constrained_cavity_with(mesh, cons, p, hint, &mut |_| false, &mut |_| false)
    }

    /// [`Self::constrained_cavity`], rejecting the point ([`Rejection::Vetoed`]) as soon
    /// as `veto` is true for a tet that enters the conflict region (before the
    /// correction, which may remove tets again: the veto is the stricter for it). A
    /// caller that would refuse a point for a vertex or a face of its cavity learns it
    /// here at the first such tet, not after the whole cavity is built.
    ///
    /// The cavity also takes in the tets it borders without being in conflict with them
    /// for which `absorb` is true (without growing further from them). The Delaunay
    /// cavity never reaches a bad tet whose circumball holds no new point (a flat tet
    /// made of two nearly coplanar surface triangles, whose circumball lies outside the
    /// domain; a sliver between points of the first layers): a caller can let the
    /// cavities take such tets in. Enlarging the cavity is George and Borouchaki's
    /// generalised kernel (the cavity changed for the elements' sake; the mesh is no
    /// longer Delaunay there): the correction keeps it star-shaped, so the mesh stays
    /// valid. Whether a tet taken in is star-shaped from the point alone is not asked:
    /// bad tets side by side often are together.
    pub fn constrained_cavity_with(
        &mut self,
        mesh: &TetMesh,
        cons: &Constraints,
        p: Point,
        hint: Option<TetId>,
        veto: &mut dyn FnMut(u32) -> bool,
        absorb: &mut dyn FnMut(u32) -> bool,
    ) -> Result<(), Rejection> {
        if crate::delaunay::check_point(0, p).is_err() {
            // A point with a NaN, infinite or out-of-range coordinate is in no tet of
            // the domain.
            return Err(Rejection::Outside);
        }
        if let Some(h) = hint {
            if h.index() < mesh.num_slots() && mesh.is_alive(h) {
                self.last = h.0;
            }
        }
        let start = match self.locate(mesh, p) {
            super::Location::OnVertex(_) => return Err(Rejection::OnVertex),
            super::Location::Outside(_) => return Err(Rejection::Outside),
            super::Location::InTet(t) => t.0,
        };
        if cons.region.get(start as usize).copied().unwrap_or(0) == 0 {
            return Err(Rejection::Outside);
        }
        let r = if self.grow_constrained(mesh, cons, p, start, veto, absorb) {
            self.correct_cavity(mesh, cons, p, start)
        } else {
            Err(Rejection::Vetoed)
        };
        for &t in self.cavity.iter().chain(&self.touched) {
            self.marks[t as usize] = 0;
        }
        self.touched.clear();
        if r.is_err() {
            self.cavity.clear();
            self.boundary.clear();
        }
        r
    }

    /// The vertices of the current cavity's boundary (with repetitions).
    pub fn cavity_vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        self.boundary.iter().flat_map(|b| {
            (0..4)
                .filter(move |&s| s != b.slot as usize)
                .map(move |s| VertexId(b.verts[s]))
        })
    }

    /// The tets of the current cavity.
    pub fn cavity_tets(&self) -> &[u32] {
        &self.cavity
    }

    /// The tets made by the last insertion (valid until the next one).
    pub fn new_tets(&self) -> &[u32] {
        &self.new_tets
    }

    /// Replaces the cavity computed by [`Self::constrained_cavity`] by the ball of a new
    /// vertex at `p`, keeping `cons` in sync.
    pub fn commit_cavity(
        &mut self,
        mesh: &mut TetMesh,
        cons: &mut Constraints,
        p: Point,
    ) -> Result<VertexId, DelaunayError> {
        let region = self.cavity.first().map_or(0, |&c| cons.region[c as usize]);
        let v = mesh.push_vertex(p);
        // Outer masks are read before any slot is reused.
        self.outer_bits.clear();
        for b in &self.boundary {
            let o = b.outer;
            self.outer_bits
                .push(cons.face_mask[o.tet().index()] >> o.facet() & 1);
        }
        self.fill_cavity(mesh, v.0)?;
        cons.resize(mesh.num_slots());
        for (k, b) in self.boundary.iter().enumerate() {
            let t = self.new_tets[k] as usize;
            cons.face_mask[t] = self.outer_bits[k] << b.slot;
            cons.region[t] = region;
        }
        self.cavity.clear();
        self.stats.inserted += 1;
        Ok(v)
    }

    /// Grows the conflict region of `p` from `start` without crossing a constrained
    /// face or leaving the start's region; tets tested and refused go to `touched`.
    /// Returns false, the cavity partial, at the first tet `veto` refuses.
    fn grow_constrained(
        &mut self,
        mesh: &TetMesh,
        cons: &Constraints,
        p: Point,
        start: u32,
        veto: &mut dyn FnMut(u32) -> bool,
        absorb: &mut dyn FnMut(u32) -> bool,
    ) -> bool {
        self.ensure_marks(mesh);
        let filter = self.filter_for(p);
        let region = cons.region[start as usize];
        self.cavity.clear();
        self.stack.clear();
        self.touched.clear();
        self.marks[start as usize] = IN;
        self.cavity.push(start);
        if veto(start) {
            return false;
        }
        mesh.prefetch_neighbors(start);
        self.stack.push(start);
        while let Some(c) = self.stack.pop() {
            let adj = mesh.raw_adj(c);
            let mask = cons.face_mask[c as usize];
            for (i, &a) in adj.iter().enumerate() {
                if mask >> i & 1 != 0 {
                    continue;
                }
                let u = a >> 2;
                if self.marks[u as usize] != 0 {
                    continue;
                }
                // Regions are separated by constrained faces, so the region test is
                // only a safety net, paid for the (fewer) tets in conflict.
                let same = mesh.raw_tet(u)[3] != GHOST && cons.region[u as usize] == region;
                let conflict = same && in_conflict(mesh, &filter, u, p);
                if conflict || (same && absorb(u)) {
                    if conflict {
                        mesh.prefetch_neighbors(u);
                    }
                    self.marks[u as usize] = IN;
                    self.cavity.push(u);
                    if veto(u) {
                        self.stats.cavity_tets += self.cavity.len() as u64;
                        return false;
                    }
                    // A tet taken in does not grow the cavity further.
                    if conflict {
                        self.stack.push(u);
                    }
                } else {
                    self.marks[u as usize] = OUT;
                    self.touched.push(u);
                }
            }
        }
        self.stats.cavity_tets += self.cavity.len() as u64;
        true
    }

    /// Shrinks the cavity until it is star-shaped with respect to `p` and loses no
    /// vertex, and fills `boundary`.
    fn correct_cavity(
        &mut self,
        mesh: &TetMesh,
        cons: &Constraints,
        p: Point,
        start: u32,
    ) -> Result<(), Rejection> {
        let rounds = CORRECTION_ROUNDS_PER_TET * self.cavity.len() + 2;
        for _ in 0..rounds {
            let bad = match self.cavity_boundary(mesh, cons, p, start) {
                Some(c) => Some(c),
                None => self.lost_vertex_tet(mesh, start),
            };
            let Some(c) = bad else {
                return self.check_ball();
            };
            if c == start {
                return Err(Rejection::Emptied);
            }
            self.marks[c as usize] = OUT;
            self.touched.push(c);
            self.keep_connected(mesh, cons, start);
        }
        Err(Rejection::Emptied)
    }

    /// Fills `boundary` from the cavity; returns a cavity tet that must leave (a face
    /// that does not see `p` strictly inside, or a constrained face inside the cavity).
    fn cavity_boundary(
        &mut self,
        mesh: &TetMesh,
        cons: &Constraints,
        p: Point,
        start: u32,
    ) -> Option<u32> {
        let filter = self.filter_for(p);
        self.boundary.clear();
        // The boundary's vertices are stamped and counted on the way, for the checks
        // that follow (a vertex lost, the Euler characteristic) when no tet leaves.
        self.next_epoch(mesh);
        let epoch = self.epoch;
        let mut count = 0;
        for &c in &self.cavity {
            let adj = mesh.raw_adj(c);
            let verts = mesh.raw_tet(c);
            for (i, &a) in adj.iter().enumerate() {
                let inner = self.marks[(a >> 2) as usize] == IN;
                let f = FACE_VERTICES[i];
                let q = |k: usize| mesh.point(VertexId(verts[f[k]]));
                if inner {
                    if cons.is_constrained(c, i) {
                        // The cavity went round the constrained face (an unrecovered
                        // surface does not close it off): the tet on the far side of
                        // the face from `p` leaves, never the start tet.
                        let u = a >> 2;
                        let p_on_c_side =
                            filter.orient3d(q(0), q(1), q(2), p) == Orientation::Positive;
                        return Some(if c == start || (p_on_c_side && u != start) {
                            u
                        } else {
                            c
                        });
                    }
                    continue;
                }
                if filter.orient3d(q(0), q(1), q(2), p) != Orientation::Positive {
                    return Some(c);
                }
                for &k in &f {
                    let x = verts[k] as usize;
                    if self.vstamp[x] != epoch {
                        self.vstamp[x] = epoch;
                        count += 1;
                    }
                }
                let mut nv = verts;
                nv[i] = u32::MAX - 2;
                self.boundary.push(BoundaryFace {
                    verts: nv,
                    slot: i as u8,
                    outer: FaceRef::from_raw(a),
                });
            }
        }
        self.boundary_vertices = count;
        None
    }

    /// A new epoch for the vertex stamps, sized for every vertex of `mesh`.
    fn next_epoch(&mut self, mesh: &TetMesh) {
        if self.vstamp.len() < mesh.num_vertices() + 1 {
            self.vstamp.resize(mesh.num_vertices() + 1024, 0);
        }
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.vstamp.fill(0);
            self.epoch = 1;
        }
    }

    /// A cavity tet holding a vertex that is on no boundary face (it would vanish);
    /// prefers a tet other than `start`. The boundary's vertices carry the current
    /// epoch's stamp ([`Kernel::cavity_boundary`]).
    fn lost_vertex_tet(&mut self, mesh: &TetMesh, start: u32) -> Option<u32> {
        let lost = self.cavity.iter().find_map(|&c| {
            mesh.raw_tet(c)
                .into_iter()
                .find(|&x| self.vstamp[x as usize] != self.epoch)
        })?;
        let holder = |c: &&u32| mesh.raw_tet(**c).contains(&lost);
        let other = self.cavity.iter().filter(holder).find(|&&c| c != start);
        Some(other.copied().unwrap_or(start))
    }

    /// Keeps in the cavity only the tets reachable from `start` through unconstrained
    /// faces between cavity tets (after a tet left, the rest may have split).
    fn keep_connected(&mut self, mesh: &TetMesh, cons: &Constraints, start: u32) {
        // Reachable tets are re-marked IN through a temporary third state.
        const REACHED: u8 = 3;
        self.stack.clear();
        self.stack.push(start);
        self.marks[start as usize] = REACHED;
        while let Some(c) = self.stack.pop() {
            for (i, &a) in mesh.raw_adj(c).iter().enumerate() {
                let u = (a >> 2) as usize;
                if self.marks[u] == IN && !cons.is_constrained(c, i) {
                    self.marks[u] = REACHED;
                    self.stack.push(u as u32);
                }
            }
        }
        let marks = &mut self.marks;
        let touched = &mut self.touched;
        self.cavity.retain(|&c| {
            if marks[c as usize] == REACHED {
                marks[c as usize] = IN;
                true
            } else {
                marks[c as usize] = OUT;
                touched.push(c);
                false
            }
        });
    }

    /// Euler check of the cavity boundary: a closed surface of genus 0 has
    /// `V - E + F = 2`, with `E = 3F / 2` (`V` counted by [`Kernel::cavity_boundary`]).
    fn check_ball(&self) -> Result<(), Rejection> {
        let v = self.boundary_vertices;
        let f = self.boundary.len();
        if f & 1 == 0 && v + 2 == f / 2 + 4 {
            Ok(())
        } else {
            Err(Rejection::NotBall)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::delaunay::{triangulate, DelaunayOptions};
    use crate::geom::predicates::StaticFilter;

    /// A Delaunay mesh of a jittered 4x4x4 grid, every finite tet in region 1.
    fn grid() -> (TetMesh, Constraints) {
        let mut pts = Vec::new();
        for i in 0..4 {
            for j in 0..4 {
                for k in 0..4 {
                    let jit = ((i * 7 + j * 13 + k * 29) % 11) as f64 * 1e-3;
                    pts.push(Point::new(i as f64, j as f64, k as f64) + jit);
                }
            }
        }
        let mesh = triangulate(&pts, &DelaunayOptions::default()).unwrap().mesh;
        let n = mesh.num_slots();
        let region = (0..n as u32)
            .map(|t| u32::from(mesh.is_alive(TetId(t)) && !mesh.is_ghost(TetId(t))))
            .collect();
        let cons = Constraints {
            face_mask: vec![0; n],
            region,
        };
        (mesh, cons)
    }

    /// The constrained triangles (sorted vertex ids), from the masks of live tets.
    fn constrained_faces(mesh: &TetMesh, cons: &Constraints) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        for t in mesh.tets() {
            let v = mesh.raw_tet(t.0);
            for (i, f) in FACE_VERTICES.iter().enumerate() {
                if cons.is_constrained(t.0, i) {
                    let mut k = [v[f[0]], v[f[1]], v[f[2]]];
                    k.sort_unstable();
                    out.push(k);
                }
            }
        }
        out.sort_unstable();
        out
    }

    #[test]
    fn a_fully_constrained_tet_is_split_alone() {
        let (mut mesh, mut cons) = grid();
        let t = mesh.finite_tets().nth(10).unwrap();
        // Constrain the four faces of t on both sides.
        cons.face_mask[t.index()] = 0b1111;
        for i in 0..4 {
            let f = mesh.neighbor(t, i);
            cons.face_mask[f.tet().index()] |= 1 << f.facet();
        }
        let before = constrained_faces(&mesh, &cons);
        let q = mesh.tet_points(t);
        let p = (q[0] + q[1] + q[2] + q[3]) / 4.0;
        let mut k = Kernel::new();
        k.constrained_cavity(&mesh, &cons, p, Some(t)).unwrap();
        assert_eq!(k.cavity_tets(), &[t.0]);
        k.commit_cavity(&mut mesh, &mut cons, p).unwrap();
        assert_eq!(k.new_tets().len(), 4);
        mesh.validate(false).unwrap();
        // Each constrained face is listed from both sides, before and after.
        assert_eq!(constrained_faces(&mesh, &cons), before);
        assert!(k.new_tets().iter().all(|&n| cons.region[n as usize] == 1));
    }

    #[test]
    fn a_cavity_round_a_lone_constrained_face_keeps_its_start() {
        // One constrained face that closes off nothing (a surface not recovered yet):
        // the cavity of a point next to it reaches the tet behind it the long way
        // round. That tet leaves the cavity, not the one holding the point.
        let (mut mesh, mut cons) = grid();
        let mut done = 0;
        for t in mesh
            .finite_tets()
            .collect::<Vec<_>>()
            .into_iter()
            .step_by(7)
        {
            let (mut m2, mut c2) = (mesh.clone(), cons.clone());
            let nb = m2.neighbor(t, 0);
            if m2.is_ghost(nb.tet()) {
                continue;
            }
            c2.face_mask[t.index()] |= 1;
            c2.face_mask[nb.tet().index()] |= 1 << nb.facet();
            let q = m2.tet_points(t);
            let face = (q[1] + q[2] + q[3]) / 3.0;
            let p = face + ((q[0] + q[1] + q[2] + q[3]) / 4.0 - face) * 0.05;
            let before = constrained_faces(&m2, &c2);
            let mut k = Kernel::new();
            k.constrained_cavity(&m2, &c2, p, Some(t))
                .expect("the point goes in");
            assert!(k.cavity_tets().contains(&t.0));
            assert!(!k.cavity_tets().contains(&nb.tet().0));
            k.commit_cavity(&mut m2, &mut c2, p).unwrap();
            m2.validate(false).unwrap();
            assert_eq!(constrained_faces(&m2, &c2), before);
            done += 1;
            (mesh, cons) = (m2, c2);
            if done == 5 {
                break;
            }
        }
        assert_eq!(done, 5);
    }

    #[test]
    fn a_veto_refuses_the_point_and_leaves_the_kernel_usable() {
        let (mut mesh, mut cons) = grid();
        let mut k = Kernel::new();
        let p = mesh.finite_tets().find_map(|t| {
            let q = mesh.tet_points(t);
            (cons.region[t.index()] != 0).then(|| (q[0] + q[1] + q[2] + q[3]) / 4.0)
        });
        let p = p.expect("a domain tet");
        let mut seen = 0;
        let mut veto = |_t: u32| {
            seen += 1;
            true
        };
        let r = k.constrained_cavity_with(&mesh, &cons, p, None, &mut veto, &mut |_| false);
        assert_eq!(r, Err(Rejection::Vetoed));
        assert_eq!(seen, 1, "the growth stops at the first refused tet");
        // Marks were reset: the same point goes in without a veto.
        k.constrained_cavity(&mesh, &cons, p, None).unwrap();
        k.commit_cavity(&mut mesh, &mut cons, p).unwrap();
        mesh.validate(false).unwrap();
    }

    #[test]
    fn points_outside_or_on_a_vertex_are_rejected() {
        let (mesh, cons) = grid();
        let mut k = Kernel::new();
        let out = k.constrained_cavity(&mesh, &cons, Point::splat(10.0), None);
        assert_eq!(out, Err(Rejection::Outside));
        let v = mesh.point(VertexId(5));
        let on = k.constrained_cavity(&mesh, &cons, v, None);
        assert_eq!(on, Err(Rejection::OnVertex));
    }

    /// Cavities that take in every tet they border (the most the correction can be
    /// asked to repair) keep the mesh valid, and do take some in.
    #[test]
    fn absorbing_cavities_keep_the_mesh_valid() {
        let (mut mesh, mut cons) = grid();
        let volume = |m: &TetMesh| -> f64 {
            m.finite_tets()
                .map(|t| {
                    crate::quality::signed_volume(&m.raw_tet(t.0).map(|v| m.point(VertexId(v))))
                })
                .sum()
        };
        let before = volume(&mesh);
        let mut k = Kernel::new();
        let (mut inserted, mut absorbed) = (0, 0);
        for i in 0..200u32 {
            let f = |s: u32| ((i.wrapping_mul(s) % 997) as f64 / 997.0) * 2.8 + 0.1;
            let p = Point::new(f(31), f(57), f(83));
            let ok =
                k.constrained_cavity_with(&mesh, &cons, p, None, &mut |_| false, &mut |_| true);
            if ok.is_ok() {
                let filter = StaticFilter::none();
                absorbed += k
                    .cavity_tets()
                    .iter()
                    .filter(|&&t| !in_conflict(&mesh, &filter, t, p))
                    .count();
                k.commit_cavity(&mut mesh, &mut cons, p).unwrap();
                inserted += 1;
            }
        }
        assert!(inserted > 100 && absorbed > 100, "{inserted} {absorbed}");
        mesh.validate(false).unwrap();
        assert!((volume(&mesh) - before).abs() < 1e-9 * before);
    }

    #[test]
    fn many_insertions_keep_the_mesh_valid() {
        let (mut mesh, mut cons) = grid();
        let mut k = Kernel::new();
        let mut inserted = 0;
        for i in 0..200u32 {
            let f = |s: u32| ((i.wrapping_mul(s) % 997) as f64 / 997.0) * 2.8 + 0.1;
            let p = Point::new(f(31), f(57), f(83));
            if k.constrained_cavity(&mesh, &cons, p, None).is_ok() {
                k.commit_cavity(&mut mesh, &mut cons, p).unwrap();
                inserted += 1;
            }
        }
        assert!(inserted > 100, "{inserted}");
        mesh.validate(false).unwrap();
        // Without constraints the result is Delaunay.
        mesh.validate(true).unwrap();
    }
}
