//! Target quality `Q_t` of a boundary surface (paper §8, Table 1 and its footnote): the
//! quality of the best tet that can be built on the worst boundary face,
//! `Q_t = max over faces f of (min over apex P of Q_K(f, P))`.
//!
//! The inner minimum has no closed form for `Q_K`. Work in the face's local frame (the
//! face translated to its centroid and scaled to unit mean edge, so the answer is
//! invariant to translation and scaling up to round-off), with the apex
//! `P = (x, y, z)`, `z` the height; `Q_K` is symmetric under reflection through the
//! face's plane, so `z > 0` suffices. Structure used by [`face_best_q_k`]:
//! - at the optimum the longest edge is the longest *face* edge `L` (observed on every
//!   test face, never `h_max > L`): the apex lies in the lens `|P - v_j| <= L`;
//! - there `Q_K = ALPHA L S / (3V)` and `S / z` decreases with `z` for a fixed `(x, y)`,
//!   so the apex is on the top of the lens, `z = sqrt(L^2 - R(x, y)^2)` with `R` the
//!   distance to the farthest vertex. In the coordinates `(x, y, 1) / z` both `S / z`
//!   and the lens are convex, so every local minimum is global;
//! - the minimum lies on the farthest-point Voronoi diagram of the vertices: at its
//!   vertex, the circumcentre (all apex edges = `L`; well-shaped faces), or on one of
//!   its three edges (two apex edges = `L`; the bisector of a face edge). Again
//!   observed on every test face, never inside a cell.
//!
//! So the search is one-dimensional: for each Voronoi edge (a piece of a bisector, cut
//! to the lens), evaluate its ends and, unless the function rises from them, run a
//! golden-section search (28 steps, ~1e-12 relative on the value). A safeguard steps off
//! the best edge on both sides and falls back to the precise search if that improves
//! (never triggered in tests). An equilateral face gives 1 to round-off.
//!
//! [`face_best_q_k_precise`] keeps the former solver, a derivative-free Nelder-Mead
//! search over `P` from the regular tet's apex, restarted until it stops improving
//! (it can stall on the kinks of `h_max`, leaving ~1e-6). The tests compare the two on
//! thousands of random and adversarial faces (needles, caps down to height 1e-5,
//! near-equilateral, near right isoceles, largest angle ~150°, random placements): the
//! fast value is never above the precise one by more than 1e-9 relative and is below it
//! on ~10 % of the faces, by at most ~2e-6 (the precise search's stalls).
//!
//! Cost (measured, `tests/quality_target.rs::speed_300k_triangles`, release, on the
//! 2-core machine while it was also running other builds, load ~3-4): 0.10-0.17 s for
//! 300k near-equilateral faces (~0.4 us per face), with 2 or 1 (`RAYON_NUM_THREADS=1`)
//! rayon threads alike at that load; the former solver took ~44 us per face, 13 s. A
//! mix of random and adversarial faces, most needing an edge search, averages ~1 us.

use crate::geom::Point;
#[cfg(test)]
use crate::quality::tet::q_k;
use crate::quality::tet::ALPHA;

/// Result of [`target_quality`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TargetQuality {
    /// `Q_t`, the largest best-reachable `Q_K` over the faces; 1 (the best possible) for
    /// an empty surface, `inf` if a face is degenerate.
    #[serde(with = "crate::quality::histogram::nonfinite")]
    pub q_t: f64,
    /// Index of the face reaching `q_t` (the first one on ties); `None` when empty.
    pub worst_face: Option<usize>,
}

/// Relative tolerance on the value at which a Nelder-Mead run and the restarts stop.
const F_TOL: f64 = 1e-9;
/// Simplex size (in units of the mean edge) below which a run stops.
const X_TOL: f64 = 1e-7;
/// Budget of objective evaluations per face (a safety net; typical use is ~200-400).
const MAX_EVALS: usize = 3000;
/// Initial simplex size of the first run and of the restarts, in mean-edge units.
const STEP_FIRST: f64 = 0.2;
const STEP_RESTART: f64 = 0.02;
const MAX_RESTARTS: usize = 12;

/// Reference solver for [`face_best_q_k`]: the same minimum by a slow, careful
/// Nelder-Mead search with restarts (~44 us per face), typically accurate to 1e-9
/// relative (a stall on an `h_max` ridge can leave ~1e-6). Kept to check the fast solver.
#[doc(hidden)]
pub fn face_best_q_k_precise(a: Point, b: Point, c: Point) -> f64 {
    match local_face(a, b, c) {
        Some(local) => precise_search(&ApexQuality::new(&local)).1,
        None => f64::INFINITY,
    }
}

/// The precise search in the local frame: best apex and its value.
fn precise_search(face: &ApexQuality) -> (Point, f64) {
    let f = |p: Point| face.q_k(p);
    let mut best = Point::new(0.0, 0.0, (2.0f64 / 3.0).sqrt());
    let mut f_best = f(best);
    let mut evals = 1;
    let mut stale = 0;
    for restart in 0..=MAX_RESTARTS {
        let step = if restart == 0 {
            STEP_FIRST
        } else {
            STEP_RESTART
        };
        let budget = MAX_EVALS.saturating_sub(evals);
        let (p, fp, n) = nelder_mead(&f, best, step, restart % 2 == 1, budget);
        evals += n;
        let improved = fp < f_best * (1.0 - F_TOL);
        if fp < f_best {
            (best, f_best) = (p, fp);
        }
        // Two restarts in a row without progress (with differently oriented simplices,
        // so that a stall on a ridge of h_max is not mistaken for the optimum).
        stale = if improved { 0 } else { stale + 1 };
        if stale == 2 || evals >= MAX_EVALS {
            break;
        }
    }
    (best, f_best)
}

/// Best `Q_K` of a tet `(a, b, c, P)` over every apex `P`: the quality of the best tet
/// that can be built on the face. 1 for an equilateral face, `> 1` otherwise, `inf` for
/// a degenerate (collinear, coincident or non-finite) face. It is the value at an
/// actual apex, so an upper bound of the true minimum, found to ~1e-12 relative (see
/// the module doc); invariant to the order of the vertices, rigid motions and scaling
/// up to that accuracy. About 1 us per face.
pub fn face_best_q_k(a: Point, b: Point, c: Point) -> f64 {
    match local_face(a, b, c) {
        Some(local) => {
            let face = ApexQuality::new(&local);
            let best = face.fast_min();
            if face.off_edge_is_better(best) {
                best.0.min(precise_search(&face).1)
            } else {
                best.0
            }
        }
        None => f64::INFINITY,
    }
}

/// The best apex of [`face_best_q_k`] in world coordinates, on the side of the face's
/// normal `(b - a) x (c - a)` when `side > 0` (its mirror image otherwise: `Q_K` is
/// symmetric through the face's plane), with its value; `None` for a degenerate face.
pub(crate) fn face_best_apex(a: Point, b: Point, c: Point, side: f64) -> Option<(Point, f64)> {
    let (local, frame) = local_face_frame(a, b, c)?;
    let face = ApexQuality::new(&local);
    let best = face.fast_min();
    let [x, y] = best.1;
    let r2 = face
        .v
        .iter()
        .map(|v| (x - v[0]).powi(2) + (y - v[1]).powi(2))
        .fold(0.0, f64::max);
    let mut apex = Point::new(x, y, (face.l2 - r2).max(0.0).sqrt());
    let mut value = best.0;
    if face.off_edge_is_better(best) {
        let (p, v) = precise_search(&face);
        if v < value {
            (apex, value) = (Point::new(p.x, p.y, p.z.abs()), v);
        }
    }
    Some((frame.to_world(apex, side), value))
}

/// The local frame of a face: centroid, mean edge and orthonormal axes (the third the
/// unit normal of `(b - a) x (c - a)`).
pub(crate) struct Frame {
    g: Point,
    scale: f64,
    axes: [Point; 3],
}

impl Frame {
    /// The world point of local `(x, y, z)`, `z` taken along the normal times `side`'s
    /// sign.
    pub(crate) fn to_world(&self, p: Point, side: f64) -> Point {
        let [e1, e2, e3] = self.axes;
        self.g + (e1 * p.x + e2 * p.y + e3 * (p.z * side.signum())) * self.scale
    }

    /// The inverse of [`Frame::to_world`].
    pub(crate) fn to_local(&self, p: Point, side: f64) -> Point {
        let [e1, e2, e3] = self.axes;
        let q = (p - self.g) / self.scale;
        Point::new(q.dot(e1), q.dot(e2), q.dot(e3) * side.signum())
    }
}

/// [`local_face`] with its frame.
pub(crate) fn local_face_frame(a: Point, b: Point, c: Point) -> Option<([Point; 3], Frame)> {
    let g = (a + b + c) / 3.0;
    let (ab, ac) = (b - a, c - a);
    let scale = (ab.length() + ac.length() + (c - b).length()) / 3.0;
    let normal = ab.cross(ac);
    let area2 = normal.length();
    if !(scale.is_finite() && area2.is_finite() && area2 > 0.0 && scale > 0.0) {
        return None;
    }
    let e1 = ab.normalize();
    let e3 = normal / area2;
    let e2 = e3.cross(e1);
    let frame = Frame {
        g,
        scale,
        axes: [e1, e2, e3],
    };
    let flat = |p: Point| {
        let q = frame.to_local(p, 1.0);
        Point::new(q.x, q.y, 0.0)
    };
    Some(([flat(a), flat(b), flat(c)], frame))
}

/// Golden-section iterations on each Voronoi edge: the bracket shrinks by
/// `0.618^GOLDEN_ITERS` (~2e-6 of the edge's length; the value, at a smooth minimum,
/// to ~1e-12 relative).
const GOLDEN_ITERS: usize = 28;
const INV_PHI: f64 = 0.618_033_988_749_894_9;
/// Relative step along an edge used to test whether the function rises from its end.
const RISE_STEP: f64 = 1e-7;
/// Step (mean-edge units) off the best Voronoi edge used by the safeguard.
const SAFEGUARD_STEP: f64 = 1e-3;

/// The face in its local frame: centroid at the origin, unit mean edge, in the plane
/// `z = 0`. `None` if the face is degenerate or not finite.
fn local_face(a: Point, b: Point, c: Point) -> Option<[Point; 3]> {
    local_face_frame(a, b, c).map(|(local, _)| local)
}

/// `Q_K(a, b, c, P)` as a function of the apex `P` for a fixed face lying in the plane
/// `z = 0`: the same formula as [`q_k`] (`ALPHA h_max S / (3V)`, here `3V = A0 |z|` and
/// each side face has area `sqrt(|e|^2 z^2 + c(P)^2) / 2` with `c` the in-plane cross
/// product), with the face's share precomputed: about half the cost per evaluation.
pub(crate) struct ApexQuality {
    /// Face vertices (x, y).
    v: [[f64; 2]; 3],
    /// Edge vectors `v[i+1] - v[i]`.
    e: [[f64; 2]; 3],
    /// Squared edge lengths.
    e2: [f64; 3],
    /// Squared longest face edge.
    l2: f64,
    /// Face area.
    area: f64,
}

impl ApexQuality {
    pub(crate) fn new(f: &[Point; 3]) -> ApexQuality {
        let v = f.map(|p| [p.x, p.y]);
        let e: [[f64; 2]; 3] =
            std::array::from_fn(|i| [v[(i + 1) % 3][0] - v[i][0], v[(i + 1) % 3][1] - v[i][1]]);
        let e2 = e.map(|d| d[0] * d[0] + d[1] * d[1]);
        let area = 0.5 * (e[0][0] * e[1][1] - e[0][1] * e[1][0]).abs();
        ApexQuality {
            v,
            e,
            e2,
            l2: e2[0].max(e2[1]).max(e2[2]),
            area,
        }
    }

    /// `Q_K` with the apex on the top of the lens `max_j |P - v_j| = L` above the
    /// in-plane point `(x, y)`; infinite outside the lens.
    #[inline]
    fn on_lens(&self, x: f64, y: f64) -> f64 {
        let mut r2: f64 = 0.0;
        for v in &self.v {
            let (dx, dy) = (x - v[0], y - v[1]);
            r2 = r2.max(dx * dx + dy * dy);
        }
        let z2 = self.l2 - r2;
        if z2 > 0.0 {
            self.q_k(Point::new(x, y, z2.sqrt()))
        } else {
            f64::INFINITY
        }
    }

    /// The fast minimum (see the module doc): the best apex over the three
    /// farthest-point Voronoi edges on the top of the lens, each searched by golden
    /// section (their common end, the circumcentre, and the other ends are evaluated
    /// exactly). Returns the value and, for the safeguard, the best in-plane point and
    /// the unit direction of its edge.
    fn fast_min(&self) -> (f64, [f64; 2], [f64; 2]) {
        let mut best = (f64::INFINITY, [0.0; 2], [1.0, 0.0]);
        for i in 0..3 {
            let (vi, vj, vm) = (self.v[i], self.v[(i + 1) % 3], self.v[(i + 2) % 3]);
            let mid = [0.5 * (vi[0] + vj[0]), 0.5 * (vi[1] + vj[1])];
            let len = self.e2[i].sqrt();
            let n = [-self.e[i][1] / len, self.e[i][0] / len];
            // Points `mid + s n` of the bisector of edge i are in the lens for
            // |s| < s_max, and have v_i, v_j (not v_m) farthest where
            // k s <= r (|P - v_i|^2 = e2/4 + s^2 against |P - v_m|^2).
            let s_max = (self.l2 - 0.25 * self.e2[i]).max(0.0).sqrt();
            let (mut lo, mut hi) = (-s_max, s_max);
            let dm = [mid[0] - vm[0], mid[1] - vm[1]];
            let k = 2.0 * (n[0] * dm[0] + n[1] * dm[1]);
            let r = 0.25 * self.e2[i] - (dm[0] * dm[0] + dm[1] * dm[1]);
            if k > 0.0 {
                hi = hi.min(r / k);
            } else if k < 0.0 {
                lo = lo.max(r / k);
            } else if r < 0.0 {
                continue;
            }
            if lo >= hi {
                continue;
            }
            let at = |s: f64| [mid[0] + s * n[0], mid[1] + s * n[1]];
            let g = |s: f64| {
                let [x, y] = at(s);
                self.on_lens(x, y)
            };
            let mut keep = |f: f64, s: f64| {
                if f < best.0 {
                    best = (f, at(s), n);
                }
            };
            let (g_lo, g_hi) = (g(lo), g(hi));
            keep(g_lo, lo);
            keep(g_hi, hi);
            // Early exit: the function along the edge is unimodal (every local minimum
            // of the problem is global, module doc), so if it rises when leaving an
            // end, that end is the edge's minimum. The common case for well-shaped
            // faces: the optimum is at the circumcentre and no edge is searched.
            let eps = RISE_STEP * (hi - lo);
            if (g_lo.is_finite() && g(lo + eps) >= g_lo)
                || (g_hi.is_finite() && g(hi - eps) >= g_hi)
            {
                continue;
            }
            let (mut a, mut b) = (lo, hi);
            let mut c = b - INV_PHI * (b - a);
            let mut d = a + INV_PHI * (b - a);
            let (mut fc, mut fd) = (g(c), g(d));
            for _ in 0..GOLDEN_ITERS {
                if fc <= fd {
                    b = d;
                    (d, fd) = (c, fc);
                    c = b - INV_PHI * (b - a);
                    fc = g(c);
                } else {
                    a = c;
                    (c, fc) = (d, fd);
                    d = a + INV_PHI * (b - a);
                    fd = g(d);
                }
            }
            keep(fc, c);
            keep(fd, d);
        }
        best
    }

    /// True when stepping off the best Voronoi edge by `SAFEGUARD_STEP`, into either
    /// neighbouring cell, improves on it: the optimum would then lie inside a cell, a
    /// case the fast search does not cover (never seen in tests).
    fn off_edge_is_better(&self, (f, p, n): (f64, [f64; 2], [f64; 2])) -> bool {
        let t = [n[1] * SAFEGUARD_STEP, -n[0] * SAFEGUARD_STEP];
        let side = |sign: f64| self.on_lens(p[0] + sign * t[0], p[1] + sign * t[1]);
        f.is_finite() && (side(1.0) < f || side(-1.0) < f)
    }

    #[inline]
    pub(crate) fn q_k(&self, p: Point) -> f64 {
        let z2 = p.z * p.z;
        let mut h2 = self.l2;
        let mut sides = 0.0;
        for i in 0..3 {
            let (dx, dy) = (p.x - self.v[i][0], p.y - self.v[i][1]);
            h2 = h2.max(dx * dx + dy * dy + z2);
            let c = self.e[i][0] * dy - self.e[i][1] * dx;
            sides += (self.e2[i] * z2 + c * c).sqrt();
        }
        let q = ALPHA * h2.sqrt() * (self.area + 0.5 * sides) / (self.area * p.z.abs());
        if q.is_finite() {
            q
        } else {
            f64::INFINITY
        }
    }
}

/// Nelder-Mead minimisation in 3D (standard coefficients 1, 2, 1/2, 1/2) from `x0` with
/// an initial simplex of size `step`, axis-aligned or (if `skew`) rotated off the axes;
/// at most `budget` evaluations.
/// Returns the best point, its value and the number of evaluations.
fn nelder_mead(
    f: &impl Fn(Point) -> f64,
    x0: Point,
    step: f64,
    skew: bool,
    budget: usize,
) -> (Point, f64, usize) {
    let dirs = if skew {
        // Vertices of a regular tet centred on x0 (a simplex with no axis-aligned edge).
        [
            Point::new(1.0, 1.0, 1.0),
            Point::new(1.0, -1.0, -1.0),
            Point::new(-1.0, 1.0, -1.0),
            Point::new(-1.0, -1.0, 1.0),
        ]
        .map(|d| d * (0.5 * step))
    } else {
        [
            Point::ZERO,
            Point::X * step,
            Point::Y * step,
            Point::Z * step,
        ]
    };
    let mut x = dirs.map(|d| x0 + d);
    let mut v = x.map(f);
    let mut evals = 4;
    while evals + 2 <= budget {
        sort_simplex(&mut x, &mut v);
        let size = (1..4).map(|i| x[i].distance(x[0])).fold(0.0, f64::max);
        if (v[3] - v[0] <= F_TOL * v[0] && size <= X_TOL) || size <= X_TOL * 1e-3 {
            break;
        }
        let centre = (x[0] + x[1] + x[2]) / 3.0;
        let xr = centre + (centre - x[3]);
        let fr = f(xr);
        evals += 1;
        if fr < v[0] {
            let xe = centre + 2.0 * (centre - x[3]);
            let fe = f(xe);
            evals += 1;
            (x[3], v[3]) = if fe < fr { (xe, fe) } else { (xr, fr) };
        } else if fr < v[2] {
            (x[3], v[3]) = (xr, fr);
        } else {
            // Outside contraction when the reflection beats the worst, inside otherwise.
            let (xc, limit) = if fr < v[3] {
                (centre + 0.5 * (xr - centre), fr)
            } else {
                (centre + 0.5 * (x[3] - centre), v[3])
            };
            let fc = f(xc);
            evals += 1;
            if fc < limit {
                (x[3], v[3]) = (xc, fc);
            } else {
                for i in 1..4 {
                    x[i] = x[0] + 0.5 * (x[i] - x[0]);
                    v[i] = f(x[i]);
                }
                evals += 3;
            }
        }
    }
    sort_simplex(&mut x, &mut v);
    (x[0], v[0], evals)
}

/// Insertion sort of the simplex by value (stable, so deterministic on ties; NaN never
/// occurs because `q_k` maps it to infinity).
fn sort_simplex(x: &mut [Point; 4], v: &mut [f64; 4]) {
    for i in 1..4 {
        let mut j = i;
        while j > 0 && v[j] < v[j - 1] {
            v.swap(j, j - 1);
            x.swap(j, j - 1);
            j -= 1;
        }
    }
}

/// Target quality `Q_t` of a triangulated surface: the maximum of [`face_best_q_k`] over
/// its triangles (paper §8), computed in parallel over the faces (rayon). Deterministic:
/// the result does not depend on the number of threads, and ties go to the lowest face
/// index.
///
/// # Panics
/// If a triangle refers to a vertex index out of range.
pub fn target_quality(vertices: &[Point], triangles: &[[u32; 3]]) -> TargetQuality {
    use rayon::prelude::*;
    // Faces per rayon task: a face costs ~1 us, so this keeps the scheduling overhead
    // negligible while leaving enough tasks to balance.
    const CHUNK: usize = 1024;
    let worst = triangles
        .par_iter()
        .with_min_len(CHUNK)
        .enumerate()
        .map(|(i, t)| {
            let [a, b, c] = t.map(|k| vertices[k as usize]);
            (face_best_q_k(a, b, c), i)
        })
        // Larger value wins, then lower index: associative and commutative, hence
        // independent of how rayon splits the work. (Values are never NaN.)
        .reduce_with(|x, y| {
            if y.0 > x.0 || (y.0 == x.0 && y.1 < x.1) {
                y
            } else {
                x
            }
        });
    match worst {
        Some((q_t, i)) => TargetQuality {
            q_t,
            worst_face: Some(i),
        },
        None => TargetQuality {
            q_t: 1.0,
            worst_face: None,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn equilateral() -> [Point; 3] {
        [
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.5, 0.75f64.sqrt(), 0.0),
        ]
    }

    #[test]
    fn equilateral_face_reaches_one() {
        let [a, b, c] = equilateral();
        let q = face_best_q_k(a, b, c);
        println!("equilateral: {q}");
        assert!((q - 1.0).abs() < 1e-6, "{q}");
        assert!(q >= 1.0 - 1e-12);
    }

    #[test]
    fn degenerate_faces_are_infinite() {
        let (o, x) = (Point::ZERO, Point::X);
        assert_eq!(face_best_q_k(o, x, 2.0 * x), f64::INFINITY);
        assert_eq!(face_best_q_k(o, o, x), f64::INFINITY);
        let nan = Point::new(f64::NAN, 0.0, 0.0);
        assert_eq!(face_best_q_k(o, x, nan), f64::INFINITY);
    }

    #[test]
    fn apex_quality_matches_q_k() {
        let local = local_face(
            Point::new(0.3, 0.1, 2.0),
            Point::new(1.7, -0.4, 2.5),
            Point::new(0.9, 1.1, 1.0),
        )
        .unwrap();
        let face = ApexQuality::new(&local);
        for p in [
            Point::new(0.0, 0.0, 0.8),
            Point::new(0.4, -2.0, 0.01),
            Point::new(-3.0, 1.0, -5.0),
            Point::new(0.1, 0.2, 0.0),
        ] {
            let (want, got) = (q_k(&[local[0], local[1], local[2], p]), face.q_k(p));
            assert!(
                got == want || ((got - want) / want).abs() < 1e-12,
                "{got} {want}"
            );
        }
    }

    #[test]
    fn empty_surface() {
        let t = target_quality(&[], &[]);
        assert_eq!((t.q_t, t.worst_face), (1.0, None));
    }

    /// Deterministic xorshift in [0, 1).
    fn rng(mut s: u64) -> impl FnMut() -> f64 {
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Random and adversarial faces, `(0,0)`, `(1,0)`, `c`, then placed at a random
    /// position, orientation and scale in space.
    fn test_faces(n: usize) -> Vec<[Point; 3]> {
        let mut rnd = rng(0x9e37_79b9_7f4a_7c15);
        let mut out = vec![
            equilateral(),
            [Point::ZERO, Point::X, Point::Y],
            [Point::ZERO, Point::X, Point::new(0.5, 1e-6, 0.0)],
            [Point::ZERO, Point::X, Point::new(0.0, 1e-6, 0.0)],
            [Point::ZERO, Point::X, Point::new(0.5, 0.5, 0.0)],
            [Point::ZERO, Point::X, Point::new(0.5, 50.0, 0.0)],
        ];
        for i in 0..n {
            let (x, y) = match i % 6 {
                // Anything.
                0 => (rnd() * 1.6 - 0.3, rnd() * 1.2 + 0.01),
                // Caps and obtuse faces, down to nearly flat ones.
                1 => (rnd() * 3.0 - 1.0, 10f64.powf(-5.0 * rnd())),
                // Needles: a short edge at (0,0), long ones to c.
                2 => (rnd() * 0.02 - 0.01, 10f64.powf(2.0 * rnd() - 1.0)),
                // Near-equilateral.
                3 => (0.5 + 0.1 * (rnd() - 0.5), 0.866 + 0.1 * (rnd() - 0.5)),
                // Near right isoceles (both orientations of the right angle).
                4 => {
                    let d = 1e-3 * (rnd() - 0.5);
                    if rnd() < 0.5 {
                        (d, 1.0 + d)
                    } else {
                        (0.5 + d, 0.5 + d)
                    }
                }
                // Near the circumcentre-outside-the-lens limit (largest angle ~150°).
                _ => (0.5 + 0.02 * (rnd() - 0.5), 0.134 + 0.02 * (rnd() - 0.5)),
            };
            let scale = 10f64.powf(4.0 * rnd() - 2.0);
            let axis = Point::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            let (sin, cos) = (6.0 * rnd()).sin_cos();
            let shift = Point::new(rnd(), rnd(), rnd()) * 100.0;
            let place = |p: Point| {
                // Rodrigues rotation, then scale and shift.
                let r = p * cos + axis.cross(p) * sin + axis * axis.dot(p) * (1.0 - cos);
                r * scale + shift
            };
            out.push([Point::ZERO, Point::X, Point::new(x, y, 0.0)].map(place));
        }
        out
    }

    #[test]
    fn fast_agrees_with_precise() {
        let (mut worst, mut better, mut fallbacks) = (0.0f64, 0, 0);
        for [a, b, c] in test_faces(6000) {
            let local = local_face(a, b, c).unwrap();
            let face = ApexQuality::new(&local);
            let best = face.fast_min();
            fallbacks += face.off_edge_is_better(best) as usize;
            let (fast, precise) = (face_best_q_k(a, b, c), face_best_q_k_precise(a, b, c));
            let rel = (fast - precise) / precise;
            assert!(fast >= 1.0 - 1e-12, "{a} {b} {c}: {fast}");
            // Never worse than the precise search beyond round-off ...
            assert!(rel <= 1e-9, "{a} {b} {c}: fast {fast} precise {precise}");
            // ... and, where better (the precise search stalled on a ridge), close.
            assert!(
                rel.abs() <= 1e-4,
                "{a} {b} {c}: fast {fast} precise {precise}"
            );
            worst = worst.max(rel.abs());
            better += (rel < -1e-9) as usize;
        }
        println!("fast vs precise: worst |rel| {worst:.2e}, fast better on {better} faces");
        assert_eq!(fallbacks, 0);
        // Measured: worst |rel| ~7e-6, all of it the precise search stalling.
        assert!(worst < 1e-5, "{worst} {better}");
    }

    #[test]
    fn target_quality_is_deterministic_on_ties() {
        // Many copies of the same worst face: the lowest index wins for any split.
        let v = [equilateral().to_vec(), vec![Point::new(0.5, -0.05, 0.0)]].concat();
        let mut tris = vec![[0u32, 1, 2]; 5000];
        for i in [1234, 2000, 4999] {
            tris[i] = [1, 0, 3];
        }
        let t = target_quality(&v, &tris);
        assert_eq!(t.worst_face, Some(1234));
        assert_eq!(t.q_t, face_best_q_k(v[1], v[0], v[3]));
    }
}
