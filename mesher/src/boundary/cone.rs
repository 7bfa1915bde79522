//! Cones: a stuck region re-tetrahedralised as the cone from one of its vertices, the
//! flip-free step of the recovery between the flips and a Steiner point (paper §4.2;
//! the "star" re-tetrahedralisation of George, Borouchaki and Saltel, "'Ultimate'
//! robustness in meshing an arbitrary polyhedron", IJNME 2003). The constrained
//! entities a cone would lose are found before the change, from the region's boundary.

use super::recover::Recovery;
use crate::geom::predicates::Orientation;
use crate::tetmesh::FACE_VERTICES;

/// Growth steps of a cone region.
const MAX_GROW: usize = 32;
/// Largest cone region, in tets.
const MAX_CONE: usize = 2048;
/// Region size at which a growing cone first checks for a buried vertex (then at
/// every doubling).
const FIRST_BURIED_CHECK: usize = 32;

impl Recovery {
    /// Re-tetrahedralises a region as the cone from vertex `apex`: the region starts as
    /// `seed` and grows across every boundary face that `apex` does not see, until all
    /// are seen (then every boundary face `f` gives the tet `(f, apex)`) or a budget,
    /// the hull or a constrained face stops it. Refused if a vertex would be lost, a
    /// constrained edge or face would disappear, or a vertex of `keep` would not be on
    /// the region's boundary. The faces at `apex` stay on the boundary. (A region that
    /// also started with the whole star of `apex`, tried when Steiner points were
    /// allowed, never made a cone that the seed alone did not over the corpus and seeds
    /// 1-6, for 5 ms of turbine's T(S,F), 15 ms of fandisk-in-box's.)
    pub(super) fn cone(&mut self, apex: u32, seed: &[u32], keep: &[u32]) -> bool {
        // The region's tets are marked in `cone_tets` (epoch marks: no set to build).
        let Some(region) = self.grow_cone(apex, seed) else {
            return false;
        };
        // The region's boundary faces: those away from the apex become the new tets'
        // bases; those at the apex stay (as faces of the tets outside).
        let mut new: Vec<[u32; 4]> = Vec::with_capacity(2 * region.len() + 2);
        let mut at_apex: Vec<[u32; 3]> = Vec::with_capacity(2 * region.len() + 2);
        for &t in &region {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                if self.cone_tets.contains(u) {
                    continue;
                }
                let f = FACE_VERTICES[i].map(|k| v[k]);
                if f.contains(&apex) {
                    at_apex.push(f);
                } else {
                    new.push([f[0], f[1], f[2], apex]);
                }
            }
        }
        if new.is_empty() {
            return false;
        }
        // Every vertex of the region must stay: the apex or on a boundary face.
        self.cone_verts.clear(self.l.mesh.num_vertices());
        self.cone_verts.insert(apex);
        for &x in new
            .iter()
            .flat_map(|t| &t[..3])
            .chain(at_apex.iter().flatten())
        {
            self.cone_verts.insert(x);
        }
        if keep.iter().any(|&k| !self.cone_verts.contains(k))
            || region
                .iter()
                .any(|&t| self.l.tet(t).iter().any(|&x| !self.cone_verts.contains(x)))
            || !self.cone_keeps_locks(&region, apex, &new, &at_apex)
        {
            return false;
        }
        let locked = if cfg!(debug_assertions) {
            self.locks_in(&region)
        } else {
            (Vec::new(), Vec::new())
        };
        if self.l.replace(&region, &new).is_err() {
            return false;
        }
        debug_assert!(
            locked.0.iter().all(|&(x, y)| self.has_edge(x, y))
                && locked.1.iter().all(|f| self.has_face(f[0], f[1], f[2])),
            "a cone lost a constrained entity that cone_keeps_locks kept"
        );
        self.flips.cones += 1;
        true
    }

    /// The constrained edges and faces of the tets `region` (for a debug check).
    fn locks_in(&self, region: &[u32]) -> (Vec<(u32, u32)>, Vec<[u32; 3]>) {
        let mut edges = Vec::new();
        let mut faces = Vec::new();
        for &t in region {
            let v = self.l.tet(t);
            for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                if self.locks.edge(v[i], v[j]) {
                    edges.push((v[i], v[j]));
                }
            }
            faces.extend(
                FACE_VERTICES
                    .iter()
                    .map(|f| f.map(|k| v[k]))
                    .filter(|&f| self.locks.face(f)),
            );
        }
        (edges, faces)
    }

    /// The region of [`Recovery::cone`], its tets marked in `cone_tets`: `seed`, grown
    /// across every boundary face that `apex` does not see. `None` when a budget, the
    /// hull or a constrained face stops the growth.
    fn grow_cone(&mut self, apex: u32, seed: &[u32]) -> Option<Vec<u32>> {
        let mut region: Vec<u32> = Vec::new();
        self.cone_tets.clear(self.l.mesh.num_slots());
        for &t in seed {
            if self.cone_tets.insert(t) {
                region.push(t);
            }
        }
        // Grow: only the faces of the tets added last need a look (a face seen from the
        // apex stays seen; it stops being a boundary face only if its far side joins).
        let mut frontier = region.clone();
        let mut grow = Vec::with_capacity(4 * frontier.len());
        let mut check_at = FIRST_BURIED_CHECK;
        for _ in 0..MAX_GROW {
            if region.len() > MAX_CONE || frontier.iter().any(|&t| self.l.is_ghost(t)) {
                return None;
            }
            grow.clear();
            for &t in &frontier {
                let v = self.l.tet(t);
                let adj = self.l.adj(t);
                for i in 0..4 {
                    let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                    if self.cone_tets.contains(u) {
                        continue;
                    }
                    let f = FACE_VERTICES[i].map(|k| v[k]);
                    if f.contains(&apex)
                        || self.l.orient(f[0], f[1], f[2], apex) == Orientation::Positive
                    {
                        continue;
                    }
                    if self.locks.face(f) || self.l.is_ghost(u) {
                        return None;
                    }
                    grow.push(u);
                }
            }
            if grow.is_empty() {
                return (region.len() <= MAX_CONE).then_some(region);
            }
            frontier.clear();
            for &u in &grow {
                if self.cone_tets.insert(u) {
                    region.push(u);
                    frontier.push(u);
                }
            }
            // A vertex inside the region stays inside as it grows: the cone would
            // lose it, so stop now (checked at doubling sizes: linear in all).
            if region.len() >= check_at {
                check_at *= 2;
                if self.buries_a_vertex(apex, &region) {
                    return None;
                }
            }
        }
        (region.len() <= MAX_CONE).then_some(region)
    }

    /// True when a vertex of `region` (marked in `cone_tets`) other than `apex` is
    /// on none of its boundary faces (it is inside the region).
    fn buries_a_vertex(&mut self, apex: u32, region: &[u32]) -> bool {
        self.cone_verts.clear(self.l.mesh.num_vertices());
        self.cone_verts.insert(apex);
        for &t in region {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                if !self.cone_tets.contains(u) {
                    for k in FACE_VERTICES[i] {
                        self.cone_verts.insert(v[k]);
                    }
                }
            }
        }
        region
            .iter()
            .any(|&t| self.l.tet(t).iter().any(|&x| !self.cone_verts.contains(x)))
    }

    /// True when every constrained edge and face of the `region` survives its
    /// replacement by the cone from `apex` over the bases `new` (the region's boundary
    /// faces `at_apex` stay as faces of the tets outside; `cone_verts` marks the
    /// vertices on the boundary). Decided before the change: an edge survives iff it
    /// is an edge of a boundary face, or joins the apex to a boundary vertex; a face
    /// iff it is a boundary face, or joins the apex to an edge of a base. Only the
    /// (few) constrained entities are looked up in the boundary.
    fn cone_keeps_locks(
        &self,
        region: &[u32],
        apex: u32,
        new: &[[u32; 4]],
        at_apex: &[[u32; 3]],
    ) -> bool {
        let bases = || new.iter().map(|t| [t[0], t[1], t[2]]);
        let on_face = |f: &[u32; 3], x: u32, y: u32| f.contains(&x) && f.contains(&y);
        let edge_kept = |x: u32, y: u32| {
            if x == apex || y == apex {
                return self.cone_verts.contains(x ^ y ^ apex);
            }
            bases().any(|f| on_face(&f, x, y)) || at_apex.iter().any(|f| on_face(f, x, y))
        };
        let face_kept = |f: [u32; 3]| {
            let same = |g: &[u32; 3]| g.iter().all(|x| f.contains(x));
            if let Some(k) = f.iter().position(|&x| x == apex) {
                let (x, y) = (f[(k + 1) % 3], f[(k + 2) % 3]);
                return at_apex.iter().any(same) || bases().any(|g| on_face(&g, x, y));
            }
            bases().any(|g| same(&g))
        };
        region.iter().all(|&t| {
            let v = self.l.tet(t);
            [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
                .iter()
                .all(|&(i, j)| !self.locks.edge(v[i], v[j]) || edge_kept(v[i], v[j]))
                && FACE_VERTICES.iter().all(|f| {
                    let f = f.map(|k| v[k]);
                    !self.locks.face(f) || face_kept(f)
                })
        })
    }
}
