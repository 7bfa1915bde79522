//! The point insertions of the optimiser (paper §6.3, the last of its operations): the
//! cone from a new point over a small cavity around a bad tet, the cavity's point
//! chosen among a few candidates (the mean of the ideal points of its faces, each
//! face's ideal point, the centroid) and, for the slivers of four fixed vertices, the
//! last resort's cavities grown around a tet, improved by a random descent and the
//! compass search (Kolda, Lewis and Torczon, "Optimization by direct search", SIAM
//! Review 2003): the points that lift such a tet often lie in a thin lens.

use super::{max_until, random_descent_below, Ops};
use crate::geom::predicates::{insphere, Sphere};
use crate::geom::search::compass_below;
use crate::geom::Point;
use crate::quality::tet::{ConeFace, TET_EDGES};
use crate::tetmesh::{FaceRef, FACE_VERTICES};

impl Ops {
    /// Inserts a point in tet `t` (with its neighbours across faces that are not
    /// constrained): the cone from the mean of the ideal points of the region's faces,
    /// if every new tet is positive and the region's worst `Q_K` drops. The point is
    /// free (smoothing moves it later).
    pub fn insert_in(&mut self, t: u32) -> bool {
        let r = self.region_of(t);
        if r == 0 || self.l.is_ghost(t) {
            return false;
        }
        let v = self.l.tet(t);
        let adj = self.l.adj(t);
        let mut region = vec![t];
        for (i, fv) in FACE_VERTICES.iter().enumerate() {
            let u = FaceRef::from_raw(adj[i]).tet().0;
            if !self.locks.face(fv.map(|k| v[k])) && !self.l.is_ghost(u) && self.region_of(u) == r {
                region.push(u);
            }
        }
        let mut cavities = vec![(region.clone(), None), (vec![t], None)];
        // The rings of its free edges: a flat tet on a flat part of the boundary (two
        // constrained faces) is lifted by a point above its free edge. The edge's
        // midpoint always sees the whole ring (it splits each tet of the ring in two).
        for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
            if self.locks.edge(v[i], v[j]) {
                continue;
            }
            if let Some(ring) = self.l.ring(v[i], v[j], &mut self.scratch) {
                let tets: Vec<u32> = ring.iter().map(|x| x.0).collect();
                if tets.iter().all(|&u| self.region_of(u) == r) {
                    let mid = (self.l.p(v[i]) + self.l.p(v[j])) * 0.5;
                    cavities.push((tets, Some(mid)));
                }
            }
        }
        // The compass search only for a tet of four fixed vertices (on the boundary),
        // which no move can improve (a flat tet between the thin walls of turbine, a
        // tet across a fold of armadillo's surface: the point that lifts it lies in a
        // lens a hundredth of the cavity's size). For every tet it inserts far more
        // points for small local gains: armadillo 1.5 % more vertices, turbine 10 %, and
        // turbine's share of Q_K < 3 from 92 % to 88 %.
        let search = v.iter().all(|&x| self.fixed.get(x as usize) == Some(&true));
        // The first cavity whose best candidate improves it wins. Otherwise the compass
        // search runs on the one cavity closest to an improvement (lowest ratio of the
        // new worst to the old), not on each in turn: on the CAD models, where most
        // tets have four boundary vertices, the searches were 40 % of the run.
        let mut closest: Option<(f64, usize, Cone)> = None;
        for (k, (c, mid)) in cavities.iter().enumerate() {
            let Some(cone) = self.cone_plan(c, *mid) else {
                continue;
            };
            if cone.after < cone.before {
                return self.cone_apply(c, cone, r);
            }
            let ratio = cone.after / cone.before;
            if search && ratio.is_finite() && closest.as_ref().is_none_or(|b| ratio < b.0) {
                closest = Some((ratio, k, cone));
            }
        }
        let Some((_, k, mut cone)) = closest else {
            return false;
        };
        let corners = self.face_points(&cone.faces);
        (cone.after, cone.p) = compass_below(
            |q, beat| cone_score_at(&corners, q, beat),
            cone.p,
            cone.after,
            0.125 * cone.span,
        );
        cone.after < cone.before && self.cone_apply(&cavities[k].0, cone, r)
    }

    /// The last resort for the worst tet when it has four fixed vertices: a point
    /// inserted over the tet grown by 2, 3, then [`GROWN_LAYERS`] layers of face
    /// neighbours ([`Ops::insert_grown`]). A sliver on a nearly flat part of the surface
    /// (two of its faces on it) is lifted only by a point that re-cones the tets
    /// around it too; the valid points then lie in a thin lens.
    pub fn insert_grown_around(&mut self, t: u32) -> bool {
        match self.fixed_tet_region(t) {
            Some(r) => self.insert_grown_layers(t, r, 2, false, 0.0),
            None => false,
        }
    }

    /// [`Ops::insert_grown`] with `first`, then more layers up to [`GROWN_LAYERS`],
    /// until one works. A layer that takes in no tet leaves the cavity of one layer
    /// fewer, already searched in vain, and so every layer after it: the search stops
    /// there (on fandisk-box's 10 tets the cavity is the whole mesh from the second
    /// layer on; the meshes of the corpus are unchanged).
    fn insert_grown_layers(
        &mut self,
        t: u32,
        r: u32,
        first: usize,
        free_inside: bool,
        min_gain: f64,
    ) -> bool {
        for layers in first..=GROWN_LAYERS {
            let tried = layers > first;
            match self.insert_grown(t, r, layers, free_inside, min_gain, tried) {
                Grown::Inserted => return true,
                Grown::Stalled => return false,
                Grown::Refused => {}
            }
        }
        false
    }

    /// [`Ops::insert_grown_around`] for a tet with free vertices: the cavity may hold
    /// free vertices inside, which the new point replaces (a free vertex crowded by
    /// the boundary, whose moves and collapses all fail), when that lowers the
    /// cavity's worst by the fraction `min_gain` at least (a smaller gain is left to
    /// the moves: on u, CGAL data, a replacement that gained 0.03 % ended the last
    /// resort at 693.32 where the moves reach 693.08).
    pub fn replace_grown_around(&mut self, t: u32, min_gain: f64) -> bool {
        let r = self.region_of(t);
        if r == 0 || self.l.is_ghost(t) {
            return false;
        }
        self.insert_grown_layers(t, r, 1, true, min_gain)
    }

    /// [`Ops::insert_in`] over the tet `t` grown by `layers` layers of face neighbours in
    /// region `r` (never across a constrained face), with the compass search; refused
    /// when the cavity would hold a constrained face or a vertex inside (with
    /// `free_inside`: a fixed vertex), or when the new cone does not lower the cavity's
    /// worst by the fraction `min_gain`. [`Grown::Stalled`] when the last layer took in
    /// no tet and nothing was inserted: the cavity is not searched when `tried` (the
    /// same cavity with one layer fewer was).
    fn insert_grown(
        &mut self,
        t: u32,
        r: u32,
        layers: usize,
        free_inside: bool,
        min_gain: f64,
        tried: bool,
    ) -> Grown {
        let mut cavity = vec![t];
        let mut start = 0;
        let mut stalled = false;
        for _ in 0..layers {
            let end = self.grow_layer(&mut cavity, start, r);
            stalled = cavity.len() == end;
            start = end;
            if cavity.len() > MAX_GROWN_CAVITY {
                return Grown::Refused;
            }
        }
        let failed = if stalled {
            Grown::Stalled
        } else {
            Grown::Refused
        };
        if stalled && tried {
            return failed;
        }
        if self.has_inner_lock(&cavity) {
            return failed;
        }
        let Some(cone) = self.cone_plan(&cavity, None) else {
            return failed;
        };
        if !self.keeps_vertices(&cavity, &cone, free_inside) {
            return failed;
        }
        if self.search_and_apply(&cavity, cone, r, min_gain) {
            Grown::Inserted
        } else {
            failed
        }
    }

    /// The last resort for the worst tet `t` of four fixed vertices after
    /// [`Ops::insert_grown_around`]: the Delaunay cavity of a point (the tets whose
    /// circumsphere holds it, grown from `t` across unconstrained faces in its region),
    /// for the tet's centroid and the midpoints of its free edges as points, re-coned
    /// from the point the searches of [`Ops::insert_grown`] place. The layers of face
    /// neighbours take in tets that hold a vertex, or miss some the point needs. On
    /// one front's output of elephant, a tet on two nearly coplanar surface faces was
    /// left at `Q_K` 4.45 (the cone over its 8-tet Delaunay cavity from a point by its
    /// free edge: 3.05); on the same front output as without it, rotor's worst 104.68
    /// -> 74.66, elephant's 3.18 -> 3.11, knot2's 2.73 -> 2.71.
    pub fn insert_delaunay_around(&mut self, t: u32) -> bool {
        let Some(r) = self.fixed_tet_region(t) else {
            return false;
        };
        let v = self.l.tet(t);
        let q = v.map(|x| self.l.p(x));
        let mut starts = vec![(q[0] + q[1] + q[2] + q[3]) * 0.25];
        for [i, j] in TET_EDGES {
            if !self.locks.edge(v[i], v[j]) {
                starts.push((q[i] + q[j]) * 0.5);
            }
        }
        starts.into_iter().any(|p| {
            let Some(cavity) = self.delaunay_cavity(t, r, p) else {
                return false;
            };
            let Some(cone) = self.cone_plan(&cavity, Some(p)) else {
                return false;
            };
            self.keeps_vertices(&cavity, &cone, false)
                && self.search_and_apply(&cavity, cone, r, 0.0)
        })
    }

    /// The last resort for the worst tet `t` of four fixed vertices after
    /// [`Ops::insert_delaunay_around`]: for each of its surface edges, the tets of the
    /// edge's ring in `t`'s region (the wedge between the edge's two surface triangles)
    /// and, if that fails, with their face neighbours, re-coned from a new point that
    /// starts just off the edge's midpoint, towards the wedge, placed by the searches
    /// of [`Ops::insert_grown`]. Rotor's worst tet lies on a cap (a surface triangle of
    /// edges 0.017, 0.214 and 0.231, the face that sets `Q_t`) with its apex on the
    /// surface 0.04 above: no point in the tet, its layers or its Delaunay cavity
    /// lowers it, and a point over the cap's long edge, which it shares with a nearly
    /// coplanar surface triangle, does. Rotor's worst `Q_K` with the point length
    /// perturbed by 1e-4 (nine runs): 104.68 on seven, 74.66 on two -> 74.66 on all
    /// nine; turbine's 202.35 -> 179.61 (`Q_t` 177.96); the other models' unchanged.
    pub fn insert_by_surface_edge(&mut self, t: u32) -> bool {
        let Some(r) = self.fixed_tet_region(t) else {
            return false;
        };
        let v = self.l.tet(t);
        for [i, j] in TET_EDGES {
            if !self.locks.edge(v[i], v[j]) {
                continue;
            }
            let Some(ring) = self.l.ring(v[i], v[j], &mut self.scratch) else {
                continue;
            };
            let wedge: Vec<(u32, u32)> = ring
                .into_iter()
                .filter(|&(u, _)| self.region_of(u) == r)
                .collect();
            let apexes = wedge.iter().map(|&(_, x)| self.l.p(x));
            let centre = apexes.sum::<Point>() / wedge.len().max(1) as f64;
            let mid = (self.l.p(v[i]) + self.l.p(v[j])) * 0.5;
            let start = mid + (centre - mid) * WEDGE_START;
            let mut cavity: Vec<u32> = wedge.iter().map(|&(u, _)| u).collect();
            for grown in [false, true] {
                if grown {
                    self.grow_layer(&mut cavity, 0, r);
                }
                if cavity.len() > MAX_GROWN_CAVITY || self.has_inner_lock(&cavity) {
                    break;
                }
                let Some(cone) = self.cone_plan(&cavity, Some(start)) else {
                    continue;
                };
                if self.keeps_vertices(&cavity, &cone, false)
                    && self.search_and_apply(&cavity, cone, r, 0.0)
                {
                    return true;
                }
            }
        }
        false
    }

    /// The region of `t` when it is a tet of the domain with four fixed vertices (the
    /// last resorts that only insert a point).
    fn fixed_tet_region(&self, t: u32) -> Option<u32> {
        let r = self.region_of(t);
        let fixed = self
            .l
            .tet(t)
            .iter()
            .all(|&x| self.fixed.get(x as usize) == Some(&true));
        (r != 0 && !self.l.is_ghost(t) && fixed).then_some(r)
    }

    /// The tets of region `r` whose circumsphere holds `p`, grown from `t` (which is
    /// always in) across faces that are not constrained; `None` past
    /// [`MAX_GROWN_CAVITY`] tets or when a constrained face lies between two of them.
    fn delaunay_cavity(&self, t: u32, r: u32, p: Point) -> Option<Vec<u32>> {
        let mut cavity = vec![t];
        let mut k = 0;
        while k < cavity.len() {
            let c = cavity[k];
            k += 1;
            for u in self.open_neighbours(c, r) {
                if cavity.contains(&u) {
                    continue;
                }
                let w = self.l.tet(u).map(|x| self.l.p(x));
                if insphere(w[0], w[1], w[2], w[3], p) == Sphere::Inside {
                    cavity.push(u);
                    if cavity.len() > MAX_GROWN_CAVITY {
                        return None;
                    }
                }
            }
        }
        (!self.has_inner_lock(&cavity)).then_some(cavity)
    }

    /// Adds to `cavity` the neighbours ([`Ops::open_neighbours`]) of its tets from index
    /// `from` on that it does not hold yet; returns its length before.
    fn grow_layer(&self, cavity: &mut Vec<u32>, from: usize, r: u32) -> usize {
        let end = cavity.len();
        for k in from..end {
            for u in self.open_neighbours(cavity[k], r) {
                if !cavity.contains(&u) {
                    cavity.push(u);
                }
            }
        }
        end
    }

    /// The neighbours of tet `c` in region `r` across its faces that are not
    /// constrained (ghosts left out): where a cavity grown from `c` may go.
    fn open_neighbours(&self, c: u32, r: u32) -> impl Iterator<Item = u32> + '_ {
        let v = self.l.tet(c);
        let adj = self.l.adj(c);
        FACE_VERTICES.iter().enumerate().filter_map(move |(i, fv)| {
            let u = FaceRef::from_raw(adj[i]).tet().0;
            let open =
                !self.l.is_ghost(u) && self.region_of(u) == r && !self.locks.face(fv.map(|j| v[j]));
            open.then_some(u)
        })
    }

    /// True when a constrained face lies between two tets of `cavity` (reached around
    /// it).
    fn has_inner_lock(&self, cavity: &[u32]) -> bool {
        cavity.iter().any(|&c| {
            let v = self.l.tet(c);
            let adj = self.l.adj(c);
            FACE_VERTICES.iter().enumerate().any(|(i, fv)| {
                cavity.contains(&FaceRef::from_raw(adj[i]).tet().0)
                    && self.locks.face(fv.map(|j| v[j]))
            })
        })
    }

    /// True when every vertex of `cavity` is on a face of `cone` (it stays), but with
    /// `free_inside` its free vertices (the new point replaces them).
    fn keeps_vertices(&self, cavity: &[u32], cone: &Cone, free_inside: bool) -> bool {
        let on_faces: Vec<u32> = cone.faces.iter().flatten().copied().collect();
        let stays = |x: u32| !free_inside || self.fixed.get(x as usize) != Some(&false);
        !cavity
            .iter()
            .flat_map(|&c| self.l.tet(c))
            .any(|x| !on_faces.contains(&x) && stays(x))
    }

    /// The last resort for the worst tet `t` when it has a free vertex: the ring of
    /// one of its edges that is not on the surface (longest first) replaced by the cone
    /// from a new point, placed by the searches of [`Ops::insert_grown`], when that
    /// lowers the ring's worst by the fraction `min_gain` (the edge split, with the new
    /// point where it serves the ring best). Rotor_small, with the front's output
    /// perturbed: a free vertex 0.02 from a fan of surface triangles of edges
    /// 0.003-0.01, nearly in their plane, four tets of Q_K 1500-2460 around the edge
    /// from it to the fan's centre; a point between the fan and the vertex serves both.
    pub fn split_edge_of(&mut self, t: u32, min_gain: f64) -> bool {
        let r = self.region_of(t);
        if r == 0 || self.l.is_ghost(t) {
            return false;
        }
        let v = self.l.tet(t);
        let mut edges: Vec<(f64, u32, u32)> = TET_EDGES
            .iter()
            .map(|&[i, j]| (self.l.p(v[i]).distance(self.l.p(v[j])), v[i], v[j]))
            .collect();
        edges.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, x, y) in edges {
            if self.locks.edge(x, y) {
                continue;
            }
            let Some(ring) = self.l.ring(x, y, &mut self.scratch) else {
                continue;
            };
            let tets: Vec<u32> = ring.iter().map(|e| e.0).collect();
            if tets.iter().any(|&u| self.region_of(u) != r) {
                continue;
            }
            let mid = (self.l.p(x) + self.l.p(y)) * 0.5;
            let Some(cone) = self.cone_plan(&tets, Some(mid)) else {
                continue;
            };
            if self.search_and_apply(&tets, cone, r, min_gain) {
                return true;
            }
        }
        false
    }

    /// The searches for the new point of `cone` over `cavity` (from the centre of the
    /// cavity's kernel, a random descent, then the compass search), and the cone
    /// applied when it lowers the cavity's worst by the fraction `min_gain`.
    fn search_and_apply(&mut self, cavity: &[u32], mut cone: Cone, r: u32, min_gain: f64) -> bool {
        // The centre of the cavity's kernel (the point farthest inside all its faces)
        // as a start: the valid points often lie in a thin lens that the other
        // candidates miss.
        let corners = self.face_points(&cone.faces);
        if let Some(c) = self.kernel_centre(&cone.faces) {
            let s = cone_score_at(&corners, c, cone.after);
            if s < cone.after {
                (cone.after, cone.p) = (s, c);
            }
        }
        // A random descent first: the cone's worst is a maximum over its faces, with
        // several basins (hand, CGAL data: 313 -> 189).
        let score = |q, beat| cone_score_at(&corners, q, beat);
        let (p, after) = random_descent_below(score, cone.p, cone.after, 0.25 * cone.span);
        (cone.after, cone.p) = compass_below(score, p, after, 0.125 * cone.span);
        cone.after < cone.before * (1.0 - min_gain) && self.cone_apply(cavity, cone, r)
    }

    /// The faces of `cavity`'s boundary and the best new point for the cone over them,
    /// among a few candidates: the mean of the ideal points of the faces, each face's
    /// ideal point, the centroid, `extra`. `None` for an empty cavity.
    fn cone_plan(&self, cavity: &[u32], extra: Option<Point>) -> Option<Cone> {
        let mut faces: Vec<[u32; 3]> = Vec::with_capacity(4 * cavity.len());
        for &c in cavity {
            let v = self.l.tet(c);
            let adj = self.l.adj(c);
            for (i, fv) in FACE_VERTICES.iter().enumerate() {
                if !cavity.contains(&FaceRef::from_raw(adj[i]).tet().0) {
                    faces.push(fv.map(|k| v[k]));
                }
            }
        }
        // Each face listed as its tet lists it has the cavity on its positive side, where
        // its ideal point is. Candidates: the mean of the ideal points, then each face's
        // own ideal point, then the centroid of the cavity's vertices; the best wins.
        // (The ideal points once each: the mean is their sum in the same order, a single
        // face's is its own, as `target` gives them.)
        let ideal: Vec<Point> = faces.iter().map(|f| self.ideal_point(f)).collect();
        let mut candidates: Vec<Point> = Vec::with_capacity(faces.len() + 3);
        let mean = ideal.iter().copied().sum::<Point>() / faces.len() as f64;
        candidates.extend(mean.is_finite().then_some(mean));
        candidates.extend(ideal.iter().copied().filter(|p| p.is_finite()));
        let face_corners = self.face_points(&faces);
        let corners = || face_corners.iter().flat_map(|f| f.corners());
        candidates.push(corners().sum::<Point>() / (3 * faces.len()).max(1) as f64);
        candidates.extend(extra);
        let before = self.worst(cavity);
        // The first candidate with the lowest score. Only a score below both `before`
        // and the best so far can matter, so each evaluation stops once it reaches them.
        let mut best: Option<(f64, Point)> = None;
        for p in candidates {
            let bound = best.map_or(before, |b| b.0.min(before));
            let s = cone_score_at(&face_corners, p, bound);
            if best.is_none_or(|b| s < b.0) {
                best = Some((s, p));
            }
        }
        let (after, p) = best?;
        let (lo, hi) = corners().fold((p, p), |(lo, hi), c| (lo.min(c), hi.max(c)));
        Some(Cone {
            faces,
            before,
            after,
            p,
            span: lo.distance(hi),
        })
    }

    /// The worst `Q_K` of the cone from `p` over `faces` (infinite if a tet is not
    /// positive), or some value `>= bound` once it reaches `bound`.
    pub(super) fn cone_score(&self, faces: &[[u32; 3]], p: Point, bound: f64) -> f64 {
        cone_score_at(&self.face_points(faces), p, bound)
    }

    /// `faces` read and prepared once for the many points a search scores.
    pub(super) fn face_points(&self, faces: &[[u32; 3]]) -> Vec<ConeFace> {
        faces
            .iter()
            .map(|f| ConeFace::new(f.map(|x| self.l.p(x))))
            .collect()
    }

    /// The Chebyshev centre of the half-spaces of `faces` (each with the region on its
    /// positive side), when it has a positive radius.
    fn kernel_centre(&self, faces: &[[u32; 3]]) -> Option<Point> {
        let pts: Vec<[Point; 3]> = faces.iter().map(|f| f.map(|x| self.l.p(x))).collect();
        let (centre, radius) = crate::geom::chebyshev::kernel_centre(&pts)?;
        (radius > 0.0).then_some(centre)
    }

    /// Replaces `cavity` by the cone from `cone.p` over its faces.
    fn cone_apply(&mut self, cavity: &[u32], cone: Cone, r: u32) -> bool {
        let x = self.l.mesh.push_vertex(cone.p).0;
        let new: Vec<[u32; 4]> = cone.faces.iter().map(|t| [t[0], t[1], t[2], x]).collect();
        if self.l.replace(cavity, &new).is_err() {
            self.l.mesh.pop_vertex();
            return false;
        }
        if self.fixed.len() <= x as usize {
            self.fixed.resize(x as usize + 1, false);
        }
        self.claim(r);
        true
    }
}

/// [`Ops::cone_score`] over prepared faces.
pub(super) fn cone_score_at(faces: &[ConeFace], p: Point, bound: f64) -> f64 {
    if faces.iter().any(|f| f.signed_volume(p) <= 0.0) {
        return f64::INFINITY;
    }
    max_until(faces.iter().map(|f| f.q_k(p)), bound)
}

/// A planned cone from a new point over a cavity's boundary faces.
struct Cone {
    faces: Vec<[u32; 3]>,
    /// Worst `Q_K` of the cavity's tets now.
    before: f64,
    /// Worst `Q_K` of the cone from `p`.
    after: f64,
    p: Point,
    /// Diagonal of the box of the cavity's vertices and `p`.
    span: f64,
}

/// Layers of face neighbours around a sliver of four fixed vertices for the last resort
/// (from 2). On dino (CGAL data) the worst tet, a sliver under a nearly flat part of
/// the surface at Q_K 47.8, is lifted with 4 layers (27 tets; worst then 13.0): with 2
/// or 3 the cavity's kernel is empty.
const GROWN_LAYERS: usize = 4;

/// Where [`Ops::insert_by_surface_edge`]'s point starts: this fraction of the way from
/// the edge's midpoint (on both surface triangles, where no cone is valid) to the mean
/// of the wedge's apexes.
const WEDGE_START: f64 = 0.05;

/// What [`Ops::insert_grown`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Grown {
    /// A point was inserted.
    Inserted,
    /// Nothing was inserted, and the last layer took in no tet: more layers give the
    /// same cavity.
    Stalled,
    /// Nothing was inserted.
    Refused,
}

/// Largest grown cavity, in tets.
const MAX_GROWN_CAVITY: usize = 64;
