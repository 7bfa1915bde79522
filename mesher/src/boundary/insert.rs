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

use super::flips::Locks;
use super::recover::Recovery;
use crate::delaunay::{Constraints, Kernel};
use crate::geom::Point;
use crate::tetmesh::FACE_VERTICES;

/// Region given to every finite tet while the domain is not identified yet (the
/// kernel keeps a cavity inside one region; the ghost tets are region 0).
const ANY_REGION: u32 = 1;

impl Recovery {
    /// Inserts `points` into the mesh by the constrained Delaunay kernel, the locked
    /// faces being the constraints. Returns the new vertex of each point, or `None`
    /// where the kernel rejected it. Afterwards the locks hold exactly the locked
    /// entities still present (a cavity takes an edge or face away only if all its
    /// vertices are on the cavity's boundary: only those are looked up again), so the
    /// next recovery pass needs no sweep over the whole mesh.
    pub(super) fn insert_points(&mut self, points: &[Point]) -> Vec<Option<u32>> {
        self.l.forget();
        let mut cons = self.lock_constraints();
        let mut kernel = Kernel::new();
        let mut out = Vec::with_capacity(points.len());
        let mut touched = vec![false; self.l.mesh.num_vertices() + points.len()];
        for &p in points {
            let v = match kernel.constrained_cavity(&self.l.mesh, &cons, p, None) {
                Ok(()) => {
                    for x in kernel.cavity_vertices() {
                        touched[x.index()] = true;
                    }
                    kernel
                        .commit_cavity(&mut self.l.mesh, &mut cons, p)
                        .ok()
                        .map(|v| v.0)
                }
                Err(_) => None,
            };
            out.push(v);
        }
        self.l.refresh();
        self.keep_surviving_locks(&touched);
        // The kernel changed the mesh without stamps: every entity is tried again.
        self.failed.clear();
        out
    }

    /// Drops the locks of the entities the insertions took away: of those whose
    /// vertices were all `touched` (on a cavity's boundary), the ones no longer in the
    /// mesh.
    fn keep_surviving_locks(&mut self, touched: &[bool]) {
        let hit = |x: u32| touched.get(x as usize).copied().unwrap_or(true);
        let old = std::mem::take(&mut self.locks);
        let mut locks = Locks::default();
        for (a, b) in old.edges {
            if !(hit(a) && hit(b)) || self.has_edge(a, b) {
                locks.edges.insert((a, b));
            }
        }
        for f in old.faces {
            if !f.iter().all(|&x| hit(x)) || self.has_face(f[0], f[1], f[2]) {
                locks.faces.insert(f);
            }
        }
        self.locks = locks;
    }

    /// The kernel's constraints: the locked faces masked on both sides, every finite
    /// tet in one region.
    fn lock_constraints(&self) -> Constraints {
        let mesh = &self.l.mesh;
        let n = mesh.num_slots();
        let mut cons = Constraints {
            face_mask: vec![0; n],
            region: vec![0; n],
        };
        for t in mesh.tets() {
            if mesh.is_ghost(t) {
                continue;
            }
            cons.region[t.index()] = ANY_REGION;
            let v = mesh.raw_tet(t.0);
            for (i, f) in FACE_VERTICES.iter().enumerate() {
                let mut key = [v[f[0]], v[f[1]], v[f[2]]];
                key.sort_unstable();
                if self.locks.faces.contains(&key) {
                    cons.face_mask[t.index()] |= 1 << i;
                }
            }
        }
        cons
    }
}
