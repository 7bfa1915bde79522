//! Incremental Steiner rounds (paper §4.2; the constrained Delaunay kernel of §5.3.4).
//!
//! A Steiner round used to rebuild the boundary mesh from scratch with the new points
//! among the Delaunay vertices, then recover every missing entity again. Instead the
//! new points (interior Steiner points near the stuck entities, and the split points of
//! stuck edges) go into the mesh as it is after the previous round, by the constrained
//! Delaunay kernel: the cavity of a point never crosses a recovered (locked) face, so
//! what was recovered stays, flips included. Entities a cavity took away are simply
//! missing again and recovered by the next pass.
//!
//! A split point the kernel rejects leaves the refined surface and the mesh out of
//! step; the caller then rebuilds from scratch, which stays the fallback.

use super::recover::Recovery;
use crate::delaunay::{Constraints, Kernel, Location};
use crate::geom::predicates::Orientation;
use crate::geom::Point;
use crate::tetmesh::{FaceRef, FACE_VERTICES};

/// Region given to every finite tet while the domain is not identified yet (the
/// kernel keeps a cavity inside one region; the ghost tets are region 0).
const ANY_REGION: u32 = 1;

/// Largest number of tets around the simplex a rejected point splits.
const MAX_SPLIT_STAR: usize = 256;

impl Recovery {
    /// Inserts `points` into the mesh by the constrained Delaunay kernel, the locked
    /// faces being the constraints. Returns the new vertex of each point, or `None`
    /// where the kernel rejected it. Afterwards the locks hold exactly the locked
    /// entities still present (a cavity takes an edge or face away only if all its
    /// vertices are on the cavity's boundary: only those are looked up again), so the
    /// next recovery pass needs no sweep over the whole mesh.
    pub(super) fn insert_points(&mut self, points: &[Point]) -> Vec<Option<u32>> {
        self.l.forget();
        let mut cons = self.region_constraints();
        // Face masks are learnt lazily, for the tets a cavity can reach (a scan of
        // every face of the mesh per round was most of a late round on turbine).
        let mut known = vec![false; cons.face_mask.len()];
        let mut reach: Vec<u32> = Vec::new();
        let mut kernel = Kernel::new();
        // The static filter over the box of every vertex, old and new.
        let all = self.l.mesh.points().iter().chain(points);
        kernel.set_filter(crate::geom::predicates::StaticFilter::of_points(all));
        let mut out = Vec::with_capacity(points.len());
        let mut touched = vec![false; self.l.mesh.num_vertices() + points.len()];
        for &p in points {
            // With the masks known so far (fewer constraints), the conflict region
            // grows over every tet the true one can: its tets and their neighbours
            // are all the kernel reads.
            reach.clear();
            let mut record = |t| {
                reach.push(t);
                false
            };
            let never = &mut |_| false;
            let _ =
                kernel.constrained_cavity_with(&self.l.mesh, &cons, p, None, &mut record, never);
            self.learn_masks(&reach, &mut cons, &mut known);
            let v = match kernel.constrained_cavity(&self.l.mesh, &cons, p, None) {
                Ok(()) => {
                    for x in kernel.cavity_vertices() {
                        touched[x.index()] = true;
                    }
                    let v = kernel.commit_cavity(&mut self.l.mesh, &mut cons, p).ok();
                    known.resize(cons.face_mask.len(), false);
                    for &t in kernel.new_tets() {
                        known[t as usize] = true;
                    }
                    v.map(|v| v.0)
                }
                Err(_) => None,
            };
            out.push(v);
        }
        self.l.refresh();
        // A point the kernel rejects (a cavity emptied by constrained faces coplanar
        // with it, seen on turbine's flat parts) splits the simplex it lies in instead:
        // the recovery needs a valid mesh, not a Delaunay one.
        for (k, &p) in points.iter().enumerate() {
            if out[k].is_none() {
                out[k] = self.split_simplex_at(p, &mut kernel, &mut touched);
            }
        }
        self.keep_surviving_locks(&touched);
        // The kernel changed the mesh without stamps: every entity is tried again.
        self.failed.clear();
        self.removal_failed.clear();
        out
    }

    /// Inserts `p` by splitting the smallest simplex that holds it (a tet, face or
    /// edge, found by the kernel's walk): every tet around that simplex becomes the
    /// tets joining `p` to its faces that do not hold `p`. Refused (nothing changed)
    /// at the hull, on a vertex, inside a constrained edge or face, or when a new tet
    /// would not be positive. The vertices of the replaced tets are marked `touched`.
    fn split_simplex_at(
        &mut self,
        p: Point,
        kernel: &mut Kernel,
        touched: &mut Vec<bool>,
    ) -> Option<u32> {
        let Location::InTet(t0) = kernel.locate(&self.l.mesh, p) else {
            return None;
        };
        let s = self.l.mesh.push_vertex(p).0;
        let done = self.split_around(s, t0.0);
        if done.is_none() {
            self.l.mesh.pop_vertex();
            return None;
        }
        for t in done? {
            for x in t {
                if touched.len() <= x as usize {
                    touched.resize(x as usize + 1, true);
                }
                touched[x as usize] = true;
            }
        }
        Some(s)
    }

    /// [`Recovery::split_simplex_at`] for the new vertex `s` in the closed tet `t0`;
    /// the vertices of the tets replaced.
    fn split_around(&mut self, s: u32, t0: u32) -> Option<Vec<[u32; 4]>> {
        // The tets whose closure holds `s`: across every face that holds it.
        let mut old = vec![t0];
        let mut k = 0;
        while k < old.len() {
            let t = old[k];
            k += 1;
            if self.l.is_ghost(t) || old.len() > MAX_SPLIT_STAR {
                return None;
            }
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for (i, f) in FACE_VERTICES.iter().enumerate() {
                let f = f.map(|j| v[j]);
                if self.l.orient(f[0], f[1], f[2], s) != Orientation::Zero {
                    continue;
                }
                if self.locks.face(f) {
                    return None;
                }
                let u = FaceRef::from_raw(adj[i]).tet().0;
                if !old.contains(&u) {
                    old.push(u);
                }
            }
        }
        let mut new = Vec::new();
        let mut verts = Vec::with_capacity(old.len());
        for &t in &old {
            let v = self.l.tet(t);
            for (i, f) in FACE_VERTICES.iter().enumerate() {
                let f = f.map(|j| v[j]);
                if self.l.orient(f[0], f[1], f[2], s) != Orientation::Zero {
                    let mut n = v;
                    n[i] = s;
                    new.push(n);
                }
            }
            verts.push(v);
        }
        // On a vertex every face through it holds `s`: nothing is split.
        let on_locked_edge = verts.iter().any(|v| {
            [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
                .iter()
                .any(|&(i, j)| {
                    self.locks.edge(v[i], v[j])
                        && new
                            .iter()
                            .all(|n| !(n.contains(&v[i]) && n.contains(&v[j])))
                })
        });
        if new.len() < 4 || on_locked_edge || self.l.replace(&old, &new).is_err() {
            return None;
        }
        self.l.forget();
        Some(verts)
    }

    /// Drops the locks of the entities the insertions took away: of those whose
    /// vertices were all `touched` (on a cavity's boundary), the ones no longer in the
    /// mesh.
    fn keep_surviving_locks(&mut self, touched: &[bool]) {
        let hit = |x: u32| touched.get(x as usize).copied().unwrap_or(true);
        // Filtered in place (the sets are large, the entities that go few).
        let mut locks = std::mem::take(&mut self.locks);
        locks
            .edges
            .retain(|&(a, b)| !(hit(a) && hit(b)) || self.has_edge(a, b));
        locks
            .faces
            .retain(|f| !f.iter().all(|&x| hit(x)) || self.has_face(f[0], f[1], f[2]));
        self.locks = locks;
    }

    /// The kernel's constraints before any face mask is known: every finite tet in
    /// one region.
    fn region_constraints(&self) -> Constraints {
        let mesh = &self.l.mesh;
        let n = mesh.num_slots();
        let mut cons = Constraints {
            face_mask: vec![0; n],
            region: vec![0; n],
        };
        for t in mesh.tets() {
            if !mesh.is_ghost(t) {
                cons.region[t.index()] = ANY_REGION;
            }
        }
        cons
    }

    /// Sets the face masks (locked faces) of the tets `reach` and of their
    /// neighbours, where not `known` yet.
    fn learn_masks(&self, reach: &[u32], cons: &mut Constraints, known: &mut [bool]) {
        let mesh = &self.l.mesh;
        for &t in reach {
            let adj = mesh.raw_adj(t);
            for u in std::iter::once(t).chain(adj.iter().map(|&a| a >> 2)) {
                if known[u as usize] {
                    continue;
                }
                known[u as usize] = true;
                if self.l.is_ghost(u) {
                    continue;
                }
                let v = mesh.raw_tet(u);
                for (i, f) in FACE_VERTICES.iter().enumerate() {
                    if self.locks.face([v[f[0]], v[f[1]], v[f[2]]]) {
                        cons.face_mask[u as usize] |= 1 << i;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::local::Local;
    use crate::delaunay::box_mesh;
    use crate::tetmesh::TetId;

    /// A small Delaunay mesh in a box, as a recovery sees it.
    fn recovery() -> Recovery {
        let mut mesh = box_mesh(Point::splat(-2.0), Point::splat(2.0)).unwrap();
        let mut kernel = Kernel::new();
        for p in [
            // Dyadic coordinates: the points built below are exactly on their face
            // or edge.
            Point::new(0.125, 0.25, 0.375),
            Point::new(-0.75, 0.5, 0.125),
            Point::new(0.5, -0.625, -0.25),
            Point::new(0.25, 0.875, -0.875),
            Point::new(-0.375, -0.5, 0.75),
        ] {
            kernel.insert(&mut mesh, p).unwrap();
        }
        Recovery::new(Local::new(mesh))
    }

    /// A point exactly inside triangle `abc` (exact for dyadic coordinates).
    fn on_face(a: Point, b: Point, c: Point) -> Point {
        a + (b - a) * 0.25 + (c - a) * 0.25
    }

    fn finite_tet(rec: &Recovery) -> [Point; 4] {
        let t = rec.l.mesh.finite_tets().next().unwrap();
        rec.l.mesh.tet(t).map(|v| rec.l.mesh.point(v))
    }

    /// Splits at `p`; the mesh stays valid and the new vertex is in it. Returns the
    /// number of tets gained.
    fn split_ok(rec: &mut Recovery, p: Point) -> usize {
        let mut touched = Vec::new();
        let tets = rec.l.mesh.finite_tets().count();
        let s = rec.split_simplex_at(p, &mut Kernel::new(), &mut touched);
        let s = s.unwrap_or_else(|| panic!("no split at {p:?}"));
        rec.l.mesh.validate(false).unwrap();
        assert_eq!(rec.l.mesh.point(crate::tetmesh::VertexId(s)), p);
        assert!(touched.iter().any(|&x| x));
        rec.l.mesh.finite_tets().count() - tets
    }

    #[test]
    fn a_rejected_point_splits_the_tet_face_or_edge_it_lies_in() {
        let mut rec = recovery();
        let q = finite_tet(&rec);
        // 1 tet into 4, 2 into 6, the ring of an edge (n tets) into 2n.
        assert_eq!(split_ok(&mut rec, (q[0] + q[1] + q[2] + q[3]) / 4.0), 3);
        let q = finite_tet(&rec);
        assert_eq!(split_ok(&mut rec, on_face(q[0], q[1], q[2])), 4);
        let q = finite_tet(&rec);
        assert!(split_ok(&mut rec, (q[0] + q[1]) * 0.5) >= 3);
    }

    #[test]
    fn a_split_inside_a_locked_face_or_on_a_vertex_is_refused_and_changes_nothing() {
        let mut rec = recovery();
        let t = rec.l.mesh.finite_tets().next().unwrap();
        let v = rec.l.mesh.tet(t).map(|v| v.0);
        let mut f = [v[0], v[1], v[2]];
        f.sort_unstable();
        rec.locks.faces.insert(f);
        let before: Vec<TetId> = rec.l.mesh.tets().collect();
        let n = rec.l.mesh.num_vertices();
        let q = f.map(|x| rec.l.p(x));
        let mut touched = Vec::new();
        let mut kernel = Kernel::new();
        for p in [on_face(q[0], q[1], q[2]), q[0]] {
            assert_eq!(rec.split_simplex_at(p, &mut kernel, &mut touched), None);
        }
        assert_eq!(rec.l.mesh.num_vertices(), n);
        assert_eq!(rec.l.mesh.tets().collect::<Vec<_>>(), before);
        rec.l.mesh.validate(false).unwrap();
    }
}
