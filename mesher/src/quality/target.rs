//! Target quality `Q_t` of a boundary surface (paper §8, Table 1 and its footnote): the
//! quality of the best tet that can be built on the worst boundary face,
//! `Q_t = max over faces f of (min over apex P of Q_K(f, P))`.
//!
//! The inner minimum has no closed form for `Q_K` (the longest edge may be a face edge or
//! an apex edge, so the optimum is not always above the circumcentre). It is found
//! numerically, deterministically, with a derivative-free Nelder-Mead search in the
//! face's local frame: the face is translated to its centroid and scaled to unit mean
//! edge (so the answer is invariant to translation and scaling up to round-off), and
//! `P = (x, y, z)` with `z` the height along the normal. The search starts at the apex of
//! the regular tet on an equilateral face, `(0, 0, sqrt(2/3))`, and is restarted from its
//! best point until a restart no longer improves the value (Nelder-Mead can stall on the
//! kinks of `h_max`). `Q_K` is symmetric under reflection through the face's plane, so
//! one side suffices. An equilateral face gives 1 to ~1e-9.
//!
//! Cost (measured, `tests/quality_target.rs::speed_300k_triangles`, 2 cores, opt-level
//! 2): ~44 us per face, 13 s for 300k near-equilateral faces; several hundred
//! evaluations per face, mostly spent crawling along the `h_max` ridges. Too slow for
//! the target of well under a few seconds: a known open item (candidates: fewer digits,
//! a regime-wise smooth solve, or parallel faces).

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

/// Best `Q_K` of a tet `(a, b, c, P)` over every apex `P`: the quality of the best tet
/// that can be built on the face. 1 for an equilateral face, `> 1` otherwise, `inf` for
/// a degenerate (collinear, coincident or non-finite) face. Invariant to the order of
/// the vertices, rigid motions and scaling up to the search accuracy: typically 1e-9
/// relative, but a stall on an `h_max` ridge can leave ~1e-6 (property-tested at 1e-5).
pub fn face_best_q_k(a: Point, b: Point, c: Point) -> f64 {
    let Some(local) = local_face(a, b, c) else {
        return f64::INFINITY;
    };
    let face = ApexQuality::new(&local);
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
    f_best
}

/// The face in its local frame: centroid at the origin, unit mean edge, in the plane
/// `z = 0`. `None` if the face is degenerate or not finite.
fn local_face(a: Point, b: Point, c: Point) -> Option<[Point; 3]> {
    let g = (a + b + c) / 3.0;
    let (ab, ac) = (b - a, c - a);
    let mean_edge = (ab.length() + ac.length() + (c - b).length()) / 3.0;
    let normal = ab.cross(ac);
    let area2 = normal.length();
    if !(mean_edge.is_finite() && area2.is_finite() && area2 > 0.0 && mean_edge > 0.0) {
        return None;
    }
    let e1 = ab.normalize();
    let e3 = normal / area2;
    let e2 = e3.cross(e1);
    let to_local = |p: Point| {
        let q = (p - g) / mean_edge;
        Point::new(q.dot(e1), q.dot(e2), 0.0)
    };
    Some([to_local(a), to_local(b), to_local(c)])
}

/// `Q_K(a, b, c, P)` as a function of the apex `P` for a fixed face lying in the plane
/// `z = 0`: the same formula as [`q_k`] (`ALPHA h_max S / (3V)`, here `3V = A0 |z|` and
/// each side face has area `sqrt(|e|^2 z^2 + c(P)^2) / 2` with `c` the in-plane cross
/// product), with the face's share precomputed: about half the cost per evaluation.
struct ApexQuality {
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
    fn new(f: &[Point; 3]) -> ApexQuality {
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

    #[inline]
    fn q_k(&self, p: Point) -> f64 {
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
/// its triangles (paper §8).
///
/// # Panics
/// If a triangle refers to a vertex index out of range.
pub fn target_quality(vertices: &[Point], triangles: &[[u32; 3]]) -> TargetQuality {
    let mut out = TargetQuality {
        q_t: 1.0,
        worst_face: None,
    };
    for (i, t) in triangles.iter().enumerate() {
        let [a, b, c] = t.map(|k| vertices[k as usize]);
        let q = face_best_q_k(a, b, c);
        if out.worst_face.is_none() || q > out.q_t {
            out = TargetQuality {
                q_t: q,
                worst_face: Some(i),
            };
        }
    }
    out
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
}
