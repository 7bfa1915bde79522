//! Schönhardt fans: a segment whose every met tet shares one edge `xy` (a twisted
//! fan no flip untwists) gets the edge and one interior Steiner point (paper §4.2, the
//! last resort before a boundary Steiner point). After Si's Steiner points in
//! Schönhardt polyhedra (Si, "TetGen, a Delaunay-based quality tetrahedral mesh
//! generator", ACM TOMS 2015) and George, Borouchaki and Saltel, "'Ultimate'
//! robustness in meshing an arbitrary polyhedron", IJNME 2003.

use super::recover::Recovery;
use crate::geom::chebyshev::kernel_centre;
use crate::geom::predicates::Orientation;
use crate::geom::Point;
use crate::tetmesh::FACE_VERTICES;

impl Recovery {
    /// The Schönhardt case: every tet the segment `ab` meets has the edge `xy`, a twisted
    /// fan that no flip untwists. The fan is re-tetrahedralised with the edge `ab` and
    /// one interior Steiner point `s`: the tet `(x, y, a, b)` takes the two end faces of
    /// the fan, and the rest of the fan (its other faces and the two faces `abx`, `aby`)
    /// is the cone from `s`, placed where it sees all of them (a compass search that
    /// maximises the smallest volume). After Si's Steiner points in Schönhardt
    /// polyhedra (TetGen, TOMS 2015); checked like every change.
    pub(crate) fn schonhardt(&mut self, a: u32, b: u32) -> bool {
        let Some(met) = self.met_tets(a, b) else {
            return false;
        };
        let Some(&first) = met.first() else {
            return false;
        };
        let common: Vec<u32> = self
            .l
            .tet(first)
            .into_iter()
            .filter(|v| met.iter().all(|&t| self.l.tet(t).contains(v)))
            .collect();
        let [x, y] = common[..] else {
            return false;
        };
        if [x, y].contains(&a) || [x, y].contains(&b) {
            return false;
        }
        let t0 = match self.l.orient(x, y, a, b) {
            Orientation::Positive => [x, y, a, b],
            Orientation::Negative => [y, x, a, b],
            Orientation::Zero => return self.planar_fan(x, y, a, b),
        };
        // Faces of the rest: the fan's boundary faces other than its two end faces
        // (those with both x and y), and the faces of t0 opposite x and y, reversed.
        let mut faces: Vec<[u32; 3]> = Vec::new();
        for &t in &met {
            let v = self.l.tet(t);
            let adj = self.l.adj(t);
            for i in 0..4 {
                let u = crate::tetmesh::FaceRef::from_raw(adj[i]).tet().0;
                let f = FACE_VERTICES[i].map(|k| v[k]);
                if met.contains(&u) || (f.contains(&x) && f.contains(&y)) {
                    continue;
                }
                faces.push(f);
            }
        }
        for fv in &FACE_VERTICES[..2] {
            // Local vertices 0 and 1 of t0 are x and y; their opposite faces, reversed.
            let f = fv.map(|k| t0[k]);
            faces.push([f[0], f[2], f[1]]);
        }
        let Some(sp) = self.kernel_point(&faces) else {
            return false;
        };
        let s = self.l.mesh.num_vertices() as u32;
        self.l.mesh.push_vertex(sp);
        let mut new = vec![t0];
        new.extend(faces.iter().map(|f| [f[0], f[1], f[2], s]));
        if self.l.replace(&met, &new).is_err() {
            self.l.mesh.pop_vertex();
            return false;
        }
        self.flips.fans += 1;
        self.steiner.push(s);
        true
    }

    /// The flat case of [`Recovery::schonhardt`]: `a`, `b`, `x`, `y` are coplanar and the
    /// segment `ab` crosses the edge `xy` (a flat quad `a x b y` with the other
    /// diagonal). The ring of `xy` splits at `a` and `b` into two paths, one on each
    /// side of the plane; each side is re-tetrahedralised with the triangles `abx` and
    /// `aby` as its face on the plane: the cone from one of its own ring vertices when
    /// one sees all its faces, else from an interior Steiner point.
    ///
    /// Box-with-hole keeps 5 interior Steiner points from such sides (3-6 on eight
    /// renumberings of its vertices and faces; TetGen -pY: 0 on the file and on all
    /// eight). Each is a triangular prism between the top face and the hole's wall
    /// whose three quadrilaterals are flat: two carry input diagonals, and the free
    /// one, the prism's side towards the inside, twists it (Schönhardt's prism); its
    /// other diagonal needs the tets behind it to change, and those hang on the
    /// recovered diagonals of the wall below. Tried and not kept (interior Steiner
    /// points left: box-with-hole, cheese, turbine, anchor; TetGen: 0, 21, 24, 24):
    /// - the flip passes taking the missing edges shortest first: 0, 18, 2, 15, but
    ///   cheese's boundary mesh 0.28 -> 0.33 s (TetGen's 0.32) and 3 points more on
    ///   average over six renumberings; box-with-hole's 0 comes from lengths equal but
    ///   for the last bits (compared at 2^-20 relative: 2; renumberings 0-3);
    /// - before the Steiner point, the side untwisted by removing the edge from `x` or
    ///   `y` to a vertex of its path, with a search for a tetrahedralisation of that
    ///   edge's ring and the tets around it without the edge
    ///   (`reconnect::Search` with the edge forbidden): none keeps the recovered edges
    ///   around; letting them go and recovering them again: 6, 15, 2, 9, each boundary
    ///   mesh 30-40 % slower on cheese and turbine;
    /// - deeper preparatory removals (`flip_depth` 3 and 4), preparatory removals that
    ///   cut the ring vertex's ear, every stuck edge at full depth before any Steiner
    ///   point (TetGen's order of link levels): no change.
    fn planar_fan(&mut self, x: u32, y: u32, a: u32, b: u32) -> bool {
        let Some(ring) = self.l.ring(x, y, &mut self.scratch) else {
            return false;
        };
        let n = ring.len();
        let (Some(ia), Some(ib)) = (
            ring.iter().position(|r| r.1 == a),
            ring.iter().position(|r| r.1 == b),
        ) else {
            return false;
        };
        let old: Vec<u32> = ring.iter().map(|r| r.0).collect();
        let mut new: Vec<[u32; 4]> = Vec::new();
        let mut added = 0;
        for (from, to) in [(ia, ib), (ib, ia)] {
            // Ring tets k (between ring[k] and ring[k+1]) from `from` to `to`.
            let mut tets = Vec::new();
            let mut k = from;
            while k != to {
                tets.push(k);
                k = (k + 1) % n;
            }
            if tets.len() < 2 {
                self.pop_added(added);
                return false;
            }
            let inner = ring[(from + 1) % n].1;
            let mut faces: Vec<[u32; 3]> = Vec::new();
            for &k in &tets {
                let (p, q) = (ring[k].1, ring[(k + 1) % n].1);
                // Tet (x, y, p, q) is positive: its faces opposite y and x, seen inside.
                faces.push([x, p, q]);
                faces.push([y, q, p]);
            }
            for w in [x, y] {
                let f = if self.l.orient(a, b, w, inner) == Orientation::Positive {
                    [a, b, w]
                } else {
                    [b, a, w]
                };
                faces.push(f);
            }
            // Candidates: the path's own vertices, then a and b themselves.
            let apex = tets
                .iter()
                .skip(1)
                .map(|&k| ring[k].1)
                .chain([a, b])
                .find(|&w| {
                    faces
                        .iter()
                        .filter(|f| !f.contains(&w))
                        .all(|f| self.l.orient(f[0], f[1], f[2], w) == Orientation::Positive)
                });
            let apex = match apex {
                Some(w) => w,
                None => {
                    let Some(sp) = self.kernel_point(&faces) else {
                        self.pop_added(added);
                        return false;
                    };
                    added += 1;
                    self.l.mesh.push_vertex(sp).0
                }
            };
            new.extend(
                faces
                    .iter()
                    .filter(|f| !f.contains(&apex))
                    .map(|f| [f[0], f[1], f[2], apex]),
            );
        }
        if self.l.replace(&old, &new).is_err() {
            self.pop_added(added);
            return false;
        }
        let nv = self.l.mesh.num_vertices() as u32;
        self.steiner.extend(nv - added as u32..nv);
        self.flips.fans += 1;
        true
    }

    fn pop_added(&mut self, added: usize) {
        for _ in 0..added {
            self.l.mesh.pop_vertex();
        }
    }

    /// A point strictly on the positive side of every face (inexact search, exact
    /// check), or `None`: a compass search maximising the smallest scaled volume, then,
    /// when it stalls on a ridge of that piecewise linear function, the Chebyshev
    /// centre of the faces' half-spaces (a linear program). The fallback only, so that
    /// what the compass search finds stays as it was. Over the default order and seeds
    /// 1-10: turbine's, anchor's and cheese's orders that needed several attempts
    /// went from 2, 1 and 7 to 0, 0 and 6; cheese's orders with split points left from
    /// 3 to 1; mean time turbine 0.227 -> 0.180 s, anchor 0.207 -> 0.083 s, cheese
    /// 1.17 -> 0.95 s; the interior Steiner points, summed over the 11 orders, 92 -> 101,
    /// 199 -> 202, 322 -> 323.
    pub(super) fn kernel_point(&self, faces: &[[u32; 3]]) -> Option<Point> {
        let pts: Vec<[Point; 3]> = faces.iter().map(|f| f.map(|v| self.l.p(v))).collect();
        let n = (pts.len() * 3) as f64;
        let mut c = pts.iter().flatten().copied().sum::<Point>() / n;
        let size = pts
            .iter()
            .flatten()
            .map(|p| (*p - c).length())
            .fold(0.0, f64::max);
        if size.is_nan() || size <= 0.0 {
            return None;
        }
        let score = |q: Point| {
            pts.iter()
                .map(|[a, b, d]| (*b - *a).cross(*d - *a).dot(q - *a))
                .fold(f64::INFINITY, f64::min)
        };
        let mut best = score(c);
        let mut step = size * 0.25;
        let dirs = [
            Point::X,
            Point::NEG_X,
            Point::Y,
            Point::NEG_Y,
            Point::Z,
            Point::NEG_Z,
        ];
        for _ in 0..400 {
            let mut moved = false;
            for d in dirs {
                let q = c + d * step;
                let v = score(q);
                if v > best {
                    best = v;
                    c = q;
                    moved = true;
                }
            }
            if !moved {
                step *= 0.5;
                if step < size * 1e-6 {
                    break;
                }
            }
        }
        let sees_all = |c: Point| {
            pts.iter().all(|[a, b, d]| {
                crate::geom::predicates::orient3d(*a, *b, *d, c) == Orientation::Positive
            })
        };
        if sees_all(c) {
            return Some(c);
        }
        // The compass search stalls on the ridges of its piecewise linear objective; the
        // linear program finds the kernel's centre when there is one.
        let (centre, radius) = kernel_centre(&pts)?;
        (radius > 0.0 && sees_all(centre)).then_some(centre)
    }
}
