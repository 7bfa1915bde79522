//! Per-tetrahedron measures: signed volume, the paper's shape quality `Q_K` (Frey,
//! Borouchaki, George 1998, §6.1), dihedral angles, the normalised radius ratio and edge
//! lengths.
//!
//! All functions take the four corners `[a, b, c, d]` of a tet by reference, allocate
//! nothing and never panic. They are inexact constructions in `f64`: in particular the
//! sign of [`signed_volume`] may be wrong for nearly flat tets; use
//! [`crate::geom::predicates::orient3d`] when the exact sign matters.
//!
//! Conventions shared by every function here:
//! - the signed volume is `det[b-a, c-a, d-a] / 6`, positive for the orientation the
//!   mesher writes (the same sign convention as `orient3d`);
//! - `Q_K = ALPHA * h_max / rho` with `ALPHA = sqrt(6)/12`, `h_max` the longest edge and
//!   `rho = 3|V| / (sum of the four face areas)` the inradius. It uses `|V|`, so an
//!   inverted tet gets the quality of its mirror image; callers flag inversion from the
//!   signed volume. A regular tet has `Q_K = 1`, every tet `Q_K >= 1`, bigger is worse;
//! - degenerate input (zero volume, or any non-finite coordinate) gives
//!   `Q_K = f64::INFINITY` and radius ratio `0`, i.e. the worst value, so that NaN never
//!   leaks into maxima or histograms.

use crate::geom::Point;

/// Normalisation factor of `Q_K`, `sqrt(6) / 12`, so that a regular tet has quality 1
/// (paper §6.1).
pub const ALPHA: f64 = 0.204_124_145_231_931_5;

/// `Q_K` below this bound is "well shaped" (paper §8, Table 1).
pub const WELL_SHAPED_Q_K: f64 = 3.0;

/// The six edges of a tet as pairs of local vertex indices; every per-edge array in this
/// module (lengths, dihedral angles) follows this order.
pub const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// For each edge of [`TET_EDGES`], the two vertices it does not contain, i.e. the two
/// faces (each named by its opposite vertex) that share the edge.
const EDGE_FACES: [[usize; 2]; 6] = [[2, 3], [1, 3], [1, 2], [0, 3], [0, 2], [0, 1]];

/// Quantities shared by all measures, computed once.
struct TetGeom {
    /// `det[b-a, c-a, d-a]` = 6 x signed volume.
    det: f64,
    /// Inward normal of the face opposite vertex `i`; its length is twice the face area.
    normals: [Point; 4],
    /// Squared edge lengths in [`TET_EDGES`] order.
    len2: [f64; 6],
}

impl TetGeom {
    #[inline]
    fn new(p: &[Point; 4]) -> TetGeom {
        let [a, b, c, d] = *p;
        let (u, v, w) = (b - a, c - a, d - a);
        let (bc, bd, cd) = (c - b, d - b, d - c);
        let n_b = v.cross(w);
        TetGeom {
            det: u.dot(n_b),
            normals: [bd.cross(bc), n_b, w.cross(u), u.cross(v)],
            len2: [
                u.length_squared(),
                v.length_squared(),
                w.length_squared(),
                bc.length_squared(),
                bd.length_squared(),
                cd.length_squared(),
            ],
        }
    }

    /// Sum of the lengths of the four normals = twice the total surface area.
    #[inline]
    fn twice_area(&self) -> f64 {
        self.normals.iter().map(|n| n.length()).sum()
    }

    #[inline]
    fn h_max(&self) -> f64 {
        self.len2.iter().copied().fold(0.0, f64::max).sqrt()
    }

    #[inline]
    fn h_min(&self) -> f64 {
        self.len2
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// `Q_K = ALPHA h_max / rho`, `rho = 3|V|/S = |det| / (2S)`.
    #[inline]
    fn q_k(&self) -> f64 {
        let q = ALPHA * self.h_max() * self.twice_area() / self.det.abs();
        if q.is_finite() {
            q
        } else {
            f64::INFINITY
        }
    }

    /// Dihedral angle at edge `e`, in degrees. With inward normals `n_k`, `n_l` of the
    /// two faces at the edge, `cos = -n_k.n_l / (|n_k||n_l|)` and
    /// `|n_k x n_l| = |det| l_e`, so `atan2` is accurate near 0 and 180 degrees.
    #[inline]
    fn dihedral(&self, e: usize) -> f64 {
        let [k, l] = EDGE_FACES[e];
        let sin = self.det.abs() * self.len2[e].sqrt();
        let cos = -self.normals[k].dot(self.normals[l]);
        sin.atan2(cos).to_degrees()
    }

    /// `3 rho / R`, in `[0, 1]`, 1 for the regular tet.
    #[inline]
    fn radius_ratio(&self) -> f64 {
        // Circumcentre - a = (|u|^2 v x w + |v|^2 w x u + |w|^2 u x v) / (2 det), so
        // R = |num| / (2|det|) and 3 rho / R = 6 det^2 / (S2 |num|), S2 = twice_area.
        let num = self.len2[0] * self.normals[1]
            + self.len2[1] * self.normals[2]
            + self.len2[2] * self.normals[3];
        let r = 6.0 * self.det * self.det / (self.twice_area() * num.length());
        if r.is_finite() {
            r.min(1.0)
        } else {
            0.0
        }
    }
}

/// A face `(a, b, c)` prepared for the tets `(a, b, c, p)` of many apexes `p` (the cone
/// of a point over a cavity's faces, scored at every candidate point): the terms of
/// [`TetGeom`] that do not depend on `p` are computed once, by the same operations, so
/// that [`ConeFace::signed_volume`] and [`ConeFace::q_k`] are bitwise those of
/// `signed_volume(&[a, b, c, p])` and `q_k(&[a, b, c, p])`.
#[derive(Clone, Copy, Debug)]
pub struct ConeFace {
    corners: [Point; 3],
    /// `b - a`, `c - a`, `c - b`.
    u: Point,
    v: Point,
    bc: Point,
    /// Squared lengths of `u`, `v`, `bc`.
    len2: [f64; 3],
    /// `u x v`, the normal opposite `p`.
    base: Point,
}

impl ConeFace {
    /// The face with corners `f`.
    #[inline]
    pub fn new(f: [Point; 3]) -> ConeFace {
        let [a, b, c] = f;
        let (u, v, bc) = (b - a, c - a, c - b);
        ConeFace {
            corners: f,
            u,
            v,
            bc,
            len2: [u.length_squared(), v.length_squared(), bc.length_squared()],
            base: u.cross(v),
        }
    }

    /// The face's corners.
    #[inline]
    pub fn corners(&self) -> [Point; 3] {
        self.corners
    }

    /// `signed_volume(&[a, b, c, p])`.
    #[inline]
    pub fn signed_volume(&self, p: Point) -> f64 {
        self.u.dot(self.v.cross(p - self.corners[0])) / 6.0
    }

    /// `q_k(&[a, b, c, p])`: [`TetGeom::new`] with the face's terms read, not computed.
    #[inline]
    pub fn q_k(&self, p: Point) -> f64 {
        let [a, b, c] = self.corners;
        let (w, bd, cd) = (p - a, p - b, p - c);
        let n_b = self.v.cross(w);
        TetGeom {
            det: self.u.dot(n_b),
            normals: [bd.cross(self.bc), n_b, w.cross(self.u), self.base],
            len2: [
                self.len2[0],
                self.len2[1],
                w.length_squared(),
                self.len2[2],
                bd.length_squared(),
                cd.length_squared(),
            ],
        }
        .q_k()
    }
}

/// Signed volume `det[b-a, c-a, d-a] / 6` (inexact construction; the sign agrees with
/// `orient3d` except for nearly flat tets). NaN if a coordinate is NaN.
#[inline]
pub fn signed_volume(p: &[Point; 4]) -> f64 {
    let [a, b, c, d] = *p;
    (b - a).dot((c - a).cross(d - a)) / 6.0
}

/// The paper's shape quality `Q_K = ALPHA h_max / rho` (§6.1): 1 for a regular tet,
/// `>= 1` otherwise, `f64::INFINITY` for a flat or non-finite tet. Orientation-blind
/// (uses `|V|`).
#[inline]
pub fn q_k(p: &[Point; 4]) -> f64 {
    TetGeom::new(p).q_k()
}

/// Inradius `3|V| / (sum of face areas)`; 0 for a flat tet, NaN for NaN input.
#[inline]
pub fn inradius(p: &[Point; 4]) -> f64 {
    let g = TetGeom::new(p);
    let r = g.det.abs() / g.twice_area();
    if r.is_nan() && p.iter().all(|x| x.is_finite()) {
        0.0
    } else {
        r
    }
}

/// Circumradius; `f64::INFINITY` for a flat tet, NaN for NaN input.
#[inline]
pub fn circumradius(p: &[Point; 4]) -> f64 {
    let g = TetGeom::new(p);
    let num = g.len2[0] * g.normals[1] + g.len2[1] * g.normals[2] + g.len2[2] * g.normals[3];
    num.length() / (2.0 * g.det.abs())
}

/// Normalised radius ratio `3 rho / R` (inradius over circumradius, times 3): 1 for the
/// regular tet, in `[0, 1]`, 0 for a flat or non-finite tet. This is the reciprocal-style
/// measure (bigger is better), unlike `Q_K`.
#[inline]
pub fn radius_ratio(p: &[Point; 4]) -> f64 {
    TetGeom::new(p).radius_ratio()
}

/// The six interior dihedral angles in degrees, in [`TET_EDGES`] order. Independent of
/// orientation. A flat tet gives angles of 0 or 180; a face of zero area gives 0 at its
/// edges; NaN input gives NaN.
#[inline]
pub fn dihedral_angles(p: &[Point; 4]) -> [f64; 6] {
    let g = TetGeom::new(p);
    std::array::from_fn(|e| g.dihedral(e))
}

/// Smallest and largest dihedral angles in degrees (NaN only if every angle is NaN).
#[inline]
pub fn dihedral_min_max(p: &[Point; 4]) -> (f64, f64) {
    min_max(&dihedral_angles(p))
}

/// Smallest dihedral angle in degrees.
#[inline]
pub fn min_dihedral(p: &[Point; 4]) -> f64 {
    dihedral_min_max(p).0
}

/// [`q_k`] and [`min_dihedral`] of one tet, the shared terms computed once (the same
/// values as the two calls).
#[inline]
pub fn q_k_and_min_dihedral(p: &[Point; 4]) -> (f64, f64) {
    let g = TetGeom::new(p);
    let angles: [f64; 6] = std::array::from_fn(|e| g.dihedral(e));
    (g.q_k(), min_max(&angles).0)
}

/// Largest dihedral angle in degrees.
#[inline]
pub fn max_dihedral(p: &[Point; 4]) -> f64 {
    dihedral_min_max(p).1
}

/// The six edge lengths in [`TET_EDGES`] order.
#[inline]
pub fn edge_lengths(p: &[Point; 4]) -> [f64; 6] {
    TET_EDGES.map(|[i, j]| p[i].distance(p[j]))
}

/// Shortest and longest edge lengths `(h_min, h_max)`.
#[inline]
pub fn edge_length_min_max(p: &[Point; 4]) -> (f64, f64) {
    let g = TetGeom::new(p);
    (g.h_min(), g.h_max())
}

fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::NAN, f64::NAN), |(lo, hi), &x| (lo.min(x), hi.max(x)))
}

/// Every measure of one tet, computed in one pass (shared cross products and lengths).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TetMeasures {
    /// Signed volume (see [`signed_volume`]); negative means inverted.
    pub volume: f64,
    /// Shape quality `Q_K` (see [`q_k`]).
    pub q_k: f64,
    /// Smallest dihedral angle, degrees.
    pub min_dihedral: f64,
    /// Largest dihedral angle, degrees.
    pub max_dihedral: f64,
    /// Normalised radius ratio `3 rho / R` (see [`radius_ratio`]).
    pub radius_ratio: f64,
    /// Shortest edge length.
    pub h_min: f64,
    /// Longest edge length.
    pub h_max: f64,
}

impl TetMeasures {
    /// Measures of the tet `p`.
    #[inline]
    pub fn new(p: &[Point; 4]) -> TetMeasures {
        let g = TetGeom::new(p);
        let angles: [f64; 6] = std::array::from_fn(|e| g.dihedral(e));
        let (min_dihedral, max_dihedral) = min_max(&angles);
        TetMeasures {
            volume: g.det / 6.0,
            q_k: g.q_k(),
            min_dihedral,
            max_dihedral,
            radius_ratio: g.radius_ratio(),
            h_min: g.h_min(),
            h_max: g.h_max(),
        }
    }

    /// Negative signed volume (inexact; see [`signed_volume`]).
    #[inline]
    pub fn is_inverted(&self) -> bool {
        self.volume < 0.0
    }

    /// Zero volume or non-finite input, i.e. `Q_K` is infinite.
    #[inline]
    pub fn is_degenerate(&self) -> bool {
        self.q_k == f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regular tet of edge 2 sqrt 2, positively oriented.
    fn regular() -> [Point; 4] {
        [
            Point::new(1.0, -1.0, -1.0),
            Point::new(1.0, 1.0, 1.0),
            Point::new(-1.0, 1.0, -1.0),
            Point::new(-1.0, -1.0, 1.0),
        ]
    }

    #[test]
    fn fused_q_k_and_angle_are_the_two_calls_bit_for_bit() {
        let mut p = regular();
        for k in 0..50 {
            p[3] += Point::new(0.13, -0.07, 0.021 * k as f64);
            let (q, a) = q_k_and_min_dihedral(&p);
            assert_eq!(q.to_bits(), q_k(&p).to_bits());
            assert_eq!(a.to_bits(), min_dihedral(&p).to_bits());
        }
    }

    #[test]
    fn cone_face_is_q_k_and_volume_bit_for_bit() {
        let mut rng = crate::delaunay::sort::SplitMix64::new(3);
        let mut u = || rng.unit() * 2.0 - 1.0;
        for k in 0..500 {
            let mut f = [0.0; 12].map(|_| u());
            // Some flat and some degenerate faces and apexes too.
            if k % 7 == 0 {
                f[11] = f[2];
                f[8] = f[2];
            }
            let t = [
                Point::new(f[0], f[1], f[2]),
                Point::new(f[3], f[4], f[5]),
                Point::new(f[6], f[7], f[8] * 1e-3),
                Point::new(f[9], f[10], f[11]),
            ];
            let face = ConeFace::new([t[0], t[1], t[2]]);
            assert_eq!(face.q_k(t[3]).to_bits(), q_k(&t).to_bits(), "{t:?}");
            assert_eq!(
                face.signed_volume(t[3]).to_bits(),
                signed_volume(&t).to_bits(),
                "{t:?}"
            );
        }
        let flat = ConeFace::new([Point::ZERO, Point::X, Point::Y]);
        assert_eq!(flat.q_k(Point::new(0.3, 0.3, 0.0)), f64::INFINITY);
        assert_eq!(flat.q_k(Point::new(f64::NAN, 0.0, 1.0)), f64::INFINITY);
    }

    #[test]
    fn alpha_is_sqrt6_over_12() {
        assert!((ALPHA - 6f64.sqrt() / 12.0).abs() < 1e-16);
    }

    #[test]
    fn regular_tet() {
        let p = regular();
        let m = TetMeasures::new(&p);
        assert!((m.q_k - 1.0).abs() < 1e-14, "{}", m.q_k);
        assert!((m.radius_ratio - 1.0).abs() < 1e-14);
        let want = (1.0f64 / 3.0).acos().to_degrees();
        for a in dihedral_angles(&p) {
            assert!((a - want).abs() < 1e-12);
        }
        let h = 8f64.sqrt();
        assert!((m.h_min - h).abs() < 1e-14 && (m.h_max - h).abs() < 1e-14);
        // Edge 2 sqrt 2: volume = h^3 / (6 sqrt 2) = 8/3; orientation positive.
        assert!((m.volume - 8.0 / 3.0).abs() < 1e-14);
        assert_eq!(m.volume, signed_volume(&p));
        assert!((inradius(&p) * 3.0 - circumradius(&p)).abs() < 1e-14);
    }

    #[test]
    fn corner_tet_values() {
        let o = Point::ZERO;
        let p = [o, Point::X, Point::Y, Point::Z];
        assert!((signed_volume(&p) - 1.0 / 6.0).abs() < 1e-16);
        // rho = 3V / S = 0.5 / (1.5 + sqrt(3)/2), h_max = sqrt 2.
        let rho = 0.5 / (1.5 + 3f64.sqrt() / 2.0);
        assert!((inradius(&p) - rho).abs() < 1e-15);
        assert!((q_k(&p) - ALPHA * 2f64.sqrt() / rho).abs() < 1e-13);
        assert!((circumradius(&p) - 3f64.sqrt() / 2.0).abs() < 1e-15);
        let a = dihedral_angles(&p);
        // Edges at the origin: right angles; the others arccos(1/sqrt 3).
        let other = (1.0 / 3f64.sqrt()).acos().to_degrees();
        for (e, want) in [90.0, 90.0, 90.0, other, other, other].iter().enumerate() {
            assert!((a[e] - want).abs() < 1e-12, "{e}: {}", a[e]);
        }
    }

    #[test]
    fn inverted_tet_keeps_quality_and_flags_volume() {
        let mut p = regular();
        let q = q_k(&p);
        p.swap(0, 1);
        let m = TetMeasures::new(&p);
        assert!(m.is_inverted() && !m.is_degenerate());
        assert!((m.q_k - q).abs() < 1e-14);
        assert!((m.min_dihedral - 70.528_779_365_509_31).abs() < 1e-10);
    }

    #[test]
    fn degenerate_and_nan_inputs() {
        let flat = [Point::ZERO, Point::X, Point::Y, Point::new(1.0, 1.0, 0.0)];
        let m = TetMeasures::new(&flat);
        assert!(m.is_degenerate() && !m.is_inverted());
        assert_eq!(m.radius_ratio, 0.0);
        assert_eq!(m.volume, 0.0);
        let same = [Point::X; 4];
        assert_eq!(q_k(&same), f64::INFINITY);
        assert_eq!(radius_ratio(&same), 0.0);
        assert_eq!(inradius(&same), 0.0);
        let nan = [
            Point::ZERO,
            Point::X,
            Point::Y,
            Point::new(f64::NAN, 0.0, 1.0),
        ];
        let m = TetMeasures::new(&nan);
        assert_eq!(m.q_k, f64::INFINITY);
        assert_eq!(m.radius_ratio, 0.0);
        assert!(m.volume.is_nan() && !m.is_inverted() && m.is_degenerate());
    }

    #[test]
    fn sliver_has_flat_angles_and_big_q() {
        // Four points nearly on a square: the classic sliver.
        let e = 1e-3;
        let p = [
            Point::new(0.0, 0.0, e),
            Point::new(1.0, 0.0, -e),
            Point::new(1.0, 1.0, e),
            Point::new(0.0, 1.0, -e),
        ];
        let m = TetMeasures::new(&p);
        assert!(m.q_k > 100.0, "{}", m.q_k);
        assert!(m.min_dihedral < 1.0 && m.max_dihedral > 179.0);
        assert!(m.radius_ratio < 0.01);
        assert!((m.h_min - (1.0f64 + 4.0 * e * e).sqrt()).abs() < 1e-12);
    }
}
