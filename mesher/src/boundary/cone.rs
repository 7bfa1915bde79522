//! Cones: a stuck region re-tetrahedralised as the cone from one of its vertices, the
//! flip-free step of the recovery between the flips and a Steiner point (paper §4.2;
//! the "star" re-tetrahedralisation of George, Borouchaki and Saltel, "'Ultimate'
//! robustness in meshing an arbitrary polyhedron", IJNME 2003). The constrained
//! entities a cone would lose are found before the change, from the region's boundary.

use super::recover::Recovery;
use crate::geom::predicates::Orientation;
use crate::tetmesh::FACE_VERTICES;
use crate::FastSet;

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
    /// the region's boundary. When Steiner points are allowed (the last resort before
    /// one), the region may also start with the whole star of `apex`: that rarely
    /// succeeds where the seed alone failed (once on the corpus), and costs a fifth of
    /// the recovery time on cheese if tried at every stuck segment.
    pub(super) fn cone(&mut self, apex: u32, seed: &[u32], keep: &[u32]) -> bool {
        self.cone_region(apex, seed, keep, false)
            || (self.allow_steiner && self.cone_region(apex, seed, keep, true))
    }

    /// [`Recovery::cone`] from `seed` alone (faces at `apex` stay on the boundary) or
    /// from `seed` plus the whole star of `apex`.
    fn cone_region(&mut self, apex: u32, seed: &[u32], keep: &[u32], with_star: bool) -> bool {
        let Some((region, inside)) = self.grow_cone(apex, seed, with_star) else {
            return false;
        };
        // The region's boundary faces: those away from the apex become the new tets'
        // bases; those at the apex stay (as faces of the tets outside).
        let mut new: Vec<[u32; 4]> = Vec::new();
        let mut at_apex: Vec<[u32; 3]> = Vec::new();
        for &t in &region {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                if inside.contains(&u) {
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
        let mut on_boundary: FastSet<u32> =
            new.iter().flat_map(|t| t[..3].iter().copied()).collect();
        on_boundary.insert(apex);
        on_boundary.extend(at_apex.iter().flatten().copied());
        if keep.iter().any(|k| !on_boundary.contains(k))
            || region
                .iter()
                .any(|&t| self.l.tet(t).iter().any(|x| !on_boundary.contains(x)))
            || !self.cone_keeps_locks(&region, &new, &at_apex)
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

    /// The region of [`Recovery::cone_region`] and its set of tets: `seed` (plus the
    /// star of `apex`), grown across every boundary face that `apex` does not see.
    /// `None` when a budget, the hull or a constrained face stops the growth.
    fn grow_cone(
        &mut self,
        apex: u32,
        seed: &[u32],
        with_star: bool,
    ) -> Option<(Vec<u32>, FastSet<u32>)> {
        let mut region: Vec<u32> = Vec::new();
        if with_star {
            self.l.star(apex, &mut region);
        }
        let mut inside: FastSet<u32> = region.iter().copied().collect();
        for &t in seed {
            if inside.insert(t) {
                region.push(t);
            }
        }
        // Grow: only the faces of the tets added last need a look (a face seen from the
        // apex stays seen; it stops being a boundary face only if its far side joins).
        let mut frontier = region.clone();
        let mut check_at = FIRST_BURIED_CHECK;
        for _ in 0..MAX_GROW {
            if region.len() > MAX_CONE || frontier.iter().any(|&t| self.l.is_ghost(t)) {
                return None;
            }
            let mut grow = Vec::new();
            for &t in &frontier {
                let v = self.l.tet(t);
                let adj = self.l.adj(t);
                for i in 0..4 {
                    let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                    if inside.contains(&u) {
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
                return (region.len() <= MAX_CONE).then_some((region, inside));
            }
            frontier.clear();
            for u in grow {
                if inside.insert(u) {
                    region.push(u);
                    frontier.push(u);
                }
            }
            // A vertex inside the region stays inside as it grows: the cone would
            // lose it, so stop now (checked at doubling sizes: linear in all).
            if region.len() >= check_at {
                check_at *= 2;
                if self.buries_a_vertex(apex, &region, &inside) {
                    return None;
                }
            }
        }
        (region.len() <= MAX_CONE).then_some((region, inside))
    }

    /// True when a vertex of `region` other than `apex` is on none of its boundary
    /// faces (it is inside the region).
    fn buries_a_vertex(&self, apex: u32, region: &[u32], inside: &FastSet<u32>) -> bool {
        let mut on_boundary: FastSet<u32> = FastSet::default();
        on_boundary.insert(apex);
        for &t in region {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                if !inside.contains(&u) {
                    on_boundary.extend(FACE_VERTICES[i].map(|k| v[k]));
                }
            }
        }
        region
            .iter()
            .any(|&t| self.l.tet(t).iter().any(|x| !on_boundary.contains(x)))
    }

    /// True when every constrained edge and face of the `region` survives its
    /// replacement by the tets `new` (the region's boundary faces `at_apex` stay as
    /// faces of the tets outside). Decided before the change: an edge of the region
    /// survives iff it is an edge of a boundary face or of a new tet, a face iff it is
    /// a boundary face or a face of a new tet (the tets outside keep theirs).
    fn cone_keeps_locks(&self, region: &[u32], new: &[[u32; 4]], at_apex: &[[u32; 3]]) -> bool {
        let mut edges: FastSet<(u32, u32)> = FastSet::default();
        let mut faces: FastSet<[u32; 3]> = FastSet::default();
        let mut add_face = |f: [u32; 3], edges: &mut FastSet<(u32, u32)>| {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                edges.insert((f[i].min(f[j]), f[i].max(f[j])));
            }
            let mut s = f;
            s.sort_unstable();
            faces.insert(s);
        };
        for t in new {
            let apex = t[3];
            add_face([t[0], t[1], t[2]], &mut edges);
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                add_face([t[i], t[j], apex], &mut edges);
            }
        }
        for &f in at_apex {
            add_face(f, &mut edges);
        }
        region.iter().all(|&t| {
            let v = self.l.tet(t);
            let edges_kept =
                [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
                    .iter()
                    .all(|&(i, j)| {
                        let (x, y) = (v[i].min(v[j]), v[i].max(v[j]));
                        !self.locks.edge(x, y) || edges.contains(&(x, y))
                    });
            edges_kept
                && FACE_VERTICES.iter().all(|f| {
                    let mut f = f.map(|k| v[k]);
                    f.sort_unstable();
                    !self.locks.faces.contains(&f) || faces.contains(&f)
                })
        })
    }
}
