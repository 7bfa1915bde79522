//! Small polyhedron reconnection: an interior Steiner point that neither a cone from a
//! neighbour nor edge removals at it take out goes when its star has a
//! tetrahedralisation without it, found by a bounded depth-first search over the tets
//! of that polyhedron (paper §4.2's "remove the Steiner points"; the exhaustive
//! reconnection of Liu, Chen and Sun, "Small polyhedron reconnection for mesh
//! improvement and its implementation based on advancing front technique", IJNME 2009,
//! and Shewchuk, "Two discrete optimization algorithms for the topological improvement
//! of tetrahedral meshes", 2002). When the star has none (a twisted, Schönhardt-like
//! star), edges of its link are removed one after another, each followed by the
//! search again.
//!
//! The search keeps the faces still open (the boundary of the part not yet filled,
//! each oriented towards that part, with the vertices in front of it). It takes the
//! open face with the fewest vertices in front and tries each whose tet stays in the
//! unfilled part: no polyhedron vertex strictly inside, and no open face meeting it
//! but where they share vertices (the exact test of the surface checker, after a
//! bounding-box and a separating-plane filter). A new face that is an open face closes
//! it; the others open. Apexes that close the most faces go first, then the best
//! shaped. The result goes through the checked `replace` like every change.
//!
//! Measured (boundary mesh, interior Steiner points left / seconds): cheese 26 -> 16,
//! 0.39 -> 0.45 s; turbine 7 -> 5; anchor 21 -> 16; hinge 2 -> 1; box-with-hole stays
//! at 5 (its twisted prisms between the top face and the hole's wall need a chain of
//! flips outside the star that this does not find).

use super::flips::{self, Choice};
use super::local::GHOST;
use super::recover::Recovery;
use crate::geom::predicates::Orientation;
use crate::geom::Point;
use crate::surface::intersect::faces_intersect;
use crate::tetmesh::{FaceRef, FACE_VERTICES};
use crate::FastSet;

/// Tets tried (each one checked against the open faces) before a search gives up.
pub(super) const SEARCH_BUDGET: usize = 2000;

/// [`SEARCH_BUDGET`] for the star after each link edge removal.
const LINK_FLIP_BUDGET: usize = 100;

/// Largest polyhedron searched, in faces.
const MAX_FACES: usize = 160;

/// Link edge removals tried at a Steiner point before its removal is given up.
const MAX_LINK_FLIPS: usize = 8;

impl Recovery {
    /// Removes the interior Steiner point `s` by re-tetrahedralising its star without
    /// it, when the search finds a way within `budget` tried tets. (Searching the star
    /// with the tets across its faces too took one more point out on the corpus, on
    /// hinge, for 5 % more boundary-mesh time on turbine.)
    pub(super) fn remove_by_reconnection(&mut self, s: u32, budget: usize) -> bool {
        let mut star = Vec::new();
        self.l.star(s, &mut star);
        if star.is_empty() || star.iter().any(|&t| self.l.is_ghost(t)) {
            return false;
        }
        match self.plan(&star, s, budget) {
            // The star holds no locked edge inside (none ends at `s`).
            Some(new) => self.l.replace(&star, &new).is_ok(),
            None => false,
        }
    }

    /// Removes the interior Steiner point `s` after removing edges of its link (edges
    /// between two free faces of its star's boundary): a twisted star (a Schönhardt
    /// prism around `s`) untwists when one of its free quadrilaterals takes its other
    /// diagonal, and each removal changes the star. After each removal, the cone from
    /// a neighbour and the search are tried again. Bounded; the removals made stay
    /// (each is a checked, valid change that keeps every lock): trying each edge alone
    /// and undoing it removed fewer points on the corpus, for more time.
    pub(super) fn remove_after_link_flips(&mut self, s: u32) -> bool {
        let mut star = Vec::new();
        for _ in 0..MAX_LINK_FLIPS {
            self.l.star(s, &mut star);
            if star.iter().any(|&t| self.l.is_ghost(t)) {
                return false;
            }
            let removed = self
                .free_link_edges(s, &star)
                .into_iter()
                .any(|(x, y)| self.remove_deep(x, y, Choice::Best, 0));
            self.l.forget();
            if !removed {
                return false;
            }
            if self.remove_vertex(s) || self.remove_by_reconnection(s, LINK_FLIP_BUDGET) {
                return true;
            }
        }
        false
    }

    /// The edges of the star of `s` away from `s` between two faces of the star's
    /// boundary that are not locked, and not locked themselves.
    fn free_link_edges(&self, s: u32, star: &[u32]) -> Vec<(u32, u32)> {
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for &t in star {
            let v = self.l.tet(t);
            let Some(i) = v.iter().position(|&x| x == s) else {
                continue;
            };
            let f = FACE_VERTICES[i].map(|k| v[k]);
            if self.locks.face(f) {
                continue;
            }
            for k in 0..3 {
                let (x, y) = (f[k], f[(k + 1) % 3]);
                edges.push((x.min(y), x.max(y)));
            }
        }
        edges.sort_unstable();
        edges
            .chunk_by(|a, b| a == b)
            .filter(|c| c.len() == 2 && !self.locks.edge(c[0].0, c[0].1))
            .map(|c| c[0])
            .collect()
    }

    /// The vertices of the tets at `s`, `s` included, sorted.
    pub(super) fn neighbours(&self, s: u32) -> Vec<u32> {
        let mut star = Vec::new();
        self.l.star(s, &mut star);
        let mut out: Vec<u32> = star.iter().flat_map(|&t| self.l.tet(t)).collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// A tetrahedralisation of the union of the tets `region` (which contain `s`)
    /// with their vertices but `s`, found within `budget` tried tets; the mesh is not
    /// changed.
    fn plan(&self, region: &[u32], s: u32, budget: usize) -> Option<Vec<[u32; 4]>> {
        let set: FastSet<u32> = region.iter().copied().collect();
        let mut open: Vec<[u32; 3]> = Vec::new();
        for &t in region {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                if !set.contains(&FaceRef::from_raw(adj[i]).tet().0) {
                    open.push(FACE_VERTICES[i].map(|k| v[k]));
                }
            }
        }
        if open.len() > MAX_FACES || open.iter().any(|f| f.contains(&s) || f.contains(&GHOST)) {
            return None;
        }
        let mut verts: Vec<u32> = region.iter().flat_map(|&t| self.l.tet(t)).collect();
        verts.sort_unstable();
        verts.dedup();
        verts.retain(|&v| v != s);
        // Every vertex but `s` must stay: on a face of the region's boundary.
        if !verts.iter().all(|v| open.iter().any(|f| f.contains(v))) {
            return None;
        }
        let mut search = Search {
            rec: self,
            verts: &verts,
            budget,
            tets: Vec::new(),
            faces: Vec::new(),
            boxes: Vec::new(),
            apexes: Vec::new(),
        };
        let ids: Vec<u32> = open.iter().map(|&f| search.face(f)).collect();
        search.fill(ids).then_some(search.tets)
    }
}

/// The depth-first search of [`Recovery::plan`]. Faces live in an arena
/// (`faces`), each with the polyhedron vertices in front of it (`apexes`, computed
/// once); the open list holds arena ids.
struct Search<'a> {
    rec: &'a Recovery,
    verts: &'a [u32],
    budget: usize,
    tets: Vec<[u32; 4]>,
    faces: Vec<[u32; 3]>,
    /// Each face's bounding box (corner min, corner max).
    boxes: Vec<(Point, Point)>,
    apexes: Vec<Vec<u32>>,
}

impl Search<'_> {
    fn p(&self, v: u32) -> Point {
        self.rec.l.p(v)
    }

    fn positive(&self, f: [u32; 3], v: u32) -> bool {
        self.rec.l.orient(f[0], f[1], f[2], v) == Orientation::Positive
    }

    /// Adds face `f` to the arena; returns its id.
    fn face(&mut self, f: [u32; 3]) -> u32 {
        let apexes = self
            .verts
            .iter()
            .copied()
            .filter(|&v| !f.contains(&v) && self.positive(f, v))
            .collect();
        let fp = f.map(|x| self.p(x));
        self.boxes
            .push((fp[0].min(fp[1]).min(fp[2]), fp[0].max(fp[1]).max(fp[2])));
        self.faces.push(f);
        self.apexes.push(apexes);
        (self.faces.len() - 1) as u32
    }

    /// Fills the polyhedron bounded by `open` (faces oriented towards its inside),
    /// pushing the tets; false when the budget runs out or no tetrahedralisation
    /// exists with these vertices.
    fn fill(&mut self, open: Vec<u32>) -> bool {
        // The face with the fewest apexes in front of it.
        let Some(k) = (0..open.len()).min_by_key(|&k| self.apexes[open[k] as usize].len()) else {
            return true;
        };
        let id = open[k] as usize;
        let f = self.faces[id];
        // Every apex of the face counts as tried (the budget), but only the cheap part
        // of the test runs for all of them: the tet's faces against the open ones.
        // The dear part (no vertex inside, no open face met) runs when an apex's turn
        // comes, so the apexes after the one that completes the fill are never tested;
        // the search and its outcome are those of testing them all first.
        let n = self.apexes[id].len();
        if self.budget < n {
            self.budget = 0;
            return false;
        }
        self.budget -= n;
        let mut apexes: Vec<(usize, f64, u32)> = Vec::with_capacity(n);
        for j in 0..n {
            let v = self.apexes[id][j];
            if let Some(closed) = self.closes(&open, k, v) {
                apexes.push((
                    closed,
                    flips::tet_shape([f[0], f[1], f[2], v].map(|x| self.p(x))),
                    v,
                ));
            }
        }
        // Apexes that close the most faces first, then the best shaped.
        apexes.sort_by(|a, b| b.0.cmp(&a.0).then(b.1.total_cmp(&a.1)));
        for (_, _, v) in apexes {
            if !self.clear(&open, k, v) {
                continue;
            }
            let t = [f[0], f[1], f[2], v];
            // Room for the three faces a tet may open: no reallocation per apex.
            let mut next = Vec::with_capacity(open.len() + 3);
            next.extend_from_slice(&open);
            next.swap_remove(k);
            for fv in &FACE_VERTICES[..3] {
                let g = fv.map(|j| t[j]);
                match next
                    .iter()
                    .position(|&h| same_oriented(self.faces[h as usize], g))
                {
                    Some(j) => {
                        next.swap_remove(j);
                    }
                    None => {
                        let h = self.face([g[0], g[2], g[1]]);
                        next.push(h);
                    }
                }
            }
            self.tets.push(t);
            if self.fill(next) {
                return true;
            }
            self.tets.pop();
            if self.budget == 0 {
                return false;
            }
        }
        false
    }

    /// The tet on open face `k` with apex `v` against the open faces: how many it
    /// closes (a new face that is an open face, from the same side), or `None` when it
    /// has an open face the other way round. With [`Search::clear`], whether the tet
    /// lies in the unfilled part.
    fn closes(&self, open: &[u32], k: usize, v: u32) -> Option<usize> {
        let f = self.faces[open[k] as usize];
        let t = [f[0], f[1], f[2], v];
        let mut closed = 0;
        for (j, &hid) in open.iter().enumerate() {
            let h = self.faces[hid as usize];
            // The tet's new faces all hold `v`, and the base face `k` is not one.
            if j == k || !h.contains(&v) {
                continue;
            }
            if let Some(fv) = FACE_VERTICES[..3]
                .iter()
                .find(|fv| same_set(h, fv.map(|i| t[i])))
            {
                if !same_oriented(h, fv.map(|i| t[i])) {
                    return None;
                }
                closed += 1;
            }
        }
        Some(closed)
    }

    /// The rest of the test of the tet on open face `k` with apex `v` (after
    /// [`Search::closes`]): no polyhedron vertex strictly inside it, and no open face
    /// it does not close meets it.
    fn clear(&self, open: &[u32], k: usize, v: u32) -> bool {
        let id = open[k] as usize;
        let f = self.faces[id];
        let t = [f[0], f[1], f[2], v];
        let tp = t.map(|x| self.p(x));
        let lo = tp[1..].iter().fold(tp[0], |a, b| a.min(*b));
        let hi = tp[1..].iter().fold(tp[0], |a, b| a.max(*b));
        // No vertex strictly inside: in front of the base face (its apex list) and of
        // the three new faces.
        for &w in &self.apexes[id] {
            let wp = self.p(w);
            if w != v
                && wp.cmpge(lo).all()
                && wp.cmple(hi).all()
                && FACE_VERTICES[..3]
                    .iter()
                    .all(|fv| self.positive(fv.map(|j| t[j]), w))
            {
                return false;
            }
        }
        open.iter().enumerate().all(|(j, &hid)| {
            let h = self.faces[hid as usize];
            j == k
                || h.contains(&v)
                    && FACE_VERTICES[..3]
                        .iter()
                        .any(|fv| same_set(h, fv.map(|i| t[i])))
                || !self.meets(t, &tp, (lo, hi), hid)
        })
    }

    /// Whether every vertex of `xs` not on face `g` lies strictly behind `g`'s plane.
    fn behind(&self, g: [u32; 3], xs: &[u32]) -> bool {
        xs.iter().all(|&x| {
            g.contains(&x) || self.rec.l.orient(g[0], g[1], g[2], x) == Orientation::Negative
        })
    }

    /// Whether the arena's face `hid` meets tet `t` (points `tp`, bounding box `bb`)
    /// anywhere but where they share vertices.
    fn meets(&self, t: [u32; 4], tp: &[Point; 4], bb: (Point, Point), hid: u32) -> bool {
        let (hlo, hhi) = self.boxes[hid as usize];
        if hlo.cmpgt(bb.1).any() || hhi.cmplt(bb.0).any() {
            return false;
        }
        let h = self.faces[hid as usize];
        let hp = h.map(|x| self.p(x));
        // A separating plane: `h` outside one of the tet's face planes, or the tet
        // behind `h`'s plane (but for the vertices on it): they can only touch where
        // they share vertices.
        let separated = FACE_VERTICES
            .iter()
            .any(|fv| self.behind(fv.map(|i| t[i]), &h))
            || self.behind(h, &t);
        !separated
            && FACE_VERTICES[..3]
                .iter()
                .any(|fv| faces_intersect(&fv.map(|i| tp[i]), fv.map(|i| t[i]), &hp, h))
    }
}

fn same_set(a: [u32; 3], b: [u32; 3]) -> bool {
    a.iter().all(|x| b.contains(x))
}

/// The same face with the same orientation (a cyclic rotation).
fn same_oriented(a: [u32; 3], b: [u32; 3]) -> bool {
    (0..3).any(|r| a[0] == b[r] && a[1] == b[(r + 1) % 3] && a[2] == b[(r + 2) % 3])
}

#[cfg(test)]
mod tests {
    use super::super::{delaunay, local::Local, BoundaryOptions};
    use super::*;
    use crate::surface::generate::{icosphere, torus};

    /// The search is exhaustive: wherever a cone from a neighbour removes a vertex,
    /// the reconnection removes it too, and every result is a valid mesh.
    #[test]
    fn reconnection_removes_every_vertex_a_cone_removes() {
        for s in [icosphere(2), torus(12, 6, 2.0, 0.5)] {
            let (mesh, _, _) = delaunay(&s, &[], &BoundaryOptions::default()).unwrap();
            let (mut cones, mut reconnected) = (0, 0);
            for v in 8..mesh.num_vertices() as u32 {
                let mut a = Recovery::new(Local::new(mesh.clone()));
                let by_cone = a.remove_vertex(v);
                let mut b = Recovery::new(Local::new(mesh.clone()));
                let by_search = b.remove_by_reconnection(v, SEARCH_BUDGET);
                b.l.mesh.validate(false).unwrap();
                assert!(!by_cone || by_search, "vertex {v}");
                cones += usize::from(by_cone);
                reconnected += usize::from(by_search);
            }
            assert!(cones > 10 && reconnected >= cones, "{cones} {reconnected}");
        }
    }
}
