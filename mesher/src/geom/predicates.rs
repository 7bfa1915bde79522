//! Exact geometric predicates: the only door to `robust` in the project.
//!
//! The Delaunay kernel of the paper (Frey, Borouchaki, George 1998, §3) needs two
//! predicates: the orientation of four points and the position of a point with respect
//! to the circumsphere of a tetrahedron. Both are evaluated exactly with Shewchuk's
//! adaptive arithmetic ("Adaptive precision floating-point arithmetic and fast robust
//! geometric predicates", 1997) through the `robust` crate, after a cheap static
//! floating-point filter. Everything else in the crate calls these functions and never
//! `robust` itself.
//!
//! Sign conventions (ours, not Shewchuk's): [`orient3d`] is `Positive` when the
//! tetrahedron `(a, b, c, d)` has positive signed volume `det[b-a, c-a, d-a] / 6`.
//! [`insphere`] takes a positively oriented tetrahedron and answers `Inside` when `e` is
//! strictly inside its circumsphere.
//!
//! Exact stages, cheapest first: a semi-static floating-point filter (and the static
//! [`StaticFilter`] of the kernel); for [`orient3d`], exact zeros read from comparisons
//! (a coordinate shared by the four points, a repeated point, two differences parallel
//! to one axis: nearly all the undecided calls on CAD surfaces); then, for the calls the
//! filter cannot decide (nearly coplanar or cospherical points), the determinant in
//! fixed-point integers (module
//! `fixed`: exact whenever the coordinate differences share a bounded exponent range,
//! which is the case for neighbouring points); only the rest (wildly spread exponents,
//! non-finite input) reach `robust`'s adaptive expansions, whose zero-initialised
//! buffers and expansion sums cost microseconds per call.
//!
//! Degeneracies: [`insphere_perturbed`] breaks ties (`e` exactly on the sphere) by the
//! symbolic perturbation of Devillers and Teillaud ("Perturbations and vertex removal in
//! a 3D Delaunay triangulation", SODA 2003): every point is lifted by an infinitesimal
//! amount ordered lexicographically by coordinates, so the answer is never "on" for five
//! distinct points in general position of the perturbed space and the Delaunay
//! triangulation becomes unique.

use glam::DVec3;
use robust::{Coord, Coord3D};

#[path = "big.rs"]
mod big;
#[path = "fixed.rs"]
mod fixed;

/// Sign of an orientation determinant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Orientation {
    /// Negative signed volume (or clockwise in 2D).
    Negative,
    /// The points are coplanar (collinear in 2D).
    Zero,
    /// Positive signed volume (or counter-clockwise in 2D).
    Positive,
}

impl Orientation {
    #[inline]
    fn from_f64(v: f64) -> Self {
        if v > 0.0 {
            Orientation::Positive
        } else if v < 0.0 {
            Orientation::Negative
        } else {
            Orientation::Zero
        }
    }

    /// The opposite sign.
    #[inline]
    pub fn reversed(self) -> Self {
        match self {
            Orientation::Negative => Orientation::Positive,
            Orientation::Zero => Orientation::Zero,
            Orientation::Positive => Orientation::Negative,
        }
    }
}

/// Position of a point with respect to a sphere (or circle).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sphere {
    /// Strictly inside.
    Inside,
    /// Exactly on the sphere.
    On,
    /// Strictly outside.
    Outside,
}

#[inline]
fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

/// Semi-static filter of [`orient3d`]: with `M_k` the largest absolute coordinate
/// difference (to `a`) along axis `k`, the rounding error of the determinant evaluated
/// below is at most `O3D_SEMI * M_x * M_y * M_z`. Derived from Shewchuk's bound
/// `o3derrboundA = 7 eps` times the permanent, which is at most `6 M_x M_y M_z`
/// (4.66e-15), rounded up; CGAL's filter uses 5.11e-15 for the same determinant.
const O3D_SEMI: f64 = 5.2e-15;
/// Semi-static filter of [`insphere`]: the error is at most `ISP_SEMI * M_x * M_y * M_z *
/// M_max^2`, from `isperrboundA = 16 eps` times the permanent, which is at most `72 M_x
/// M_y M_z M_max^2` (1.279e-13), rounded up.
const ISP_SEMI: f64 = 1.3e-13;
/// Outside `[FILTER_MIN, FILTER_MAX]` the products of the bounds may underflow or
/// overflow: go straight to the exact evaluation.
const FILTER_MIN: f64 = 1e-58;
const FILTER_MAX: f64 = 1e58;

/// Orientation of the tetrahedron `(a, b, c, d)`: the sign of `det[b-a, c-a, d-a]`,
/// exact.
#[inline]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Orientation {
    // Fast path: the determinant of the differences to `a`, with a semi-static error
    // bound. Falls back to the adaptive exact evaluation.
    let (det, ba, ca, da) = orient3d_det(a, b, c, d);
    orient3d_semi(det, [ba, ca, da], [a, b, c, d])
}

/// [`orient3d`] from its determinant `det` and the differences `b - a`, `c - a`,
/// `d - a` ([`orient3d_det`]), as a caller whose own filter failed has them.
#[inline]
fn orient3d_semi(det: f64, [ba, ca, da]: [DVec3; 3], [a, b, c, d]: [DVec3; 4]) -> Orientation {
    let mx = ba.x.abs().max(ca.x.abs()).max(da.x.abs());
    let my = ba.y.abs().max(ca.y.abs()).max(da.y.abs());
    let mz = ba.z.abs().max(ca.z.abs()).max(da.z.abs());
    let lo = mx.min(my).min(mz);
    let hi = mx.max(my).max(mz);
    if lo > FILTER_MIN && hi < FILTER_MAX {
        let bound = O3D_SEMI * mx * my * mz;
        if det > bound {
            return Orientation::Positive;
        }
        if -det > bound {
            return Orientation::Negative;
        }
    }
    // Four points with one coordinate in common (the differences are exact zeros
    // then): a flat tet in an axis-aligned plane, common on CAD surfaces (cheese,
    // turbine); or a point given twice (the recovery asks that of a vertex and a face
    // that holds it). Both are answered without the exact stages.
    if lo == 0.0 || a == b || a == c || a == d || b == c || b == d || c == d {
        return Orientation::Zero;
    }
    if two_parallel_to_an_axis([a, b, c, d]) {
        return Orientation::Zero;
    }
    orient3d_exact(a, b, c, d)
}

/// Whether two of the six differences between the four points are parallel to the same
/// coordinate axis (their ends equal in the two other coordinates): the four points are
/// then coplanar, exactly. Walls of prismatic holes (cheese) give many such flat tets.
#[inline(never)]
fn two_parallel_to_an_axis(p: [DVec3; 4]) -> bool {
    let mut seen = [false; 3];
    for i in 0..4 {
        for j in i + 1..4 {
            let (u, w) = (p[i], p[j]);
            let axis = match (u.x == w.x, u.y == w.y, u.z == w.z) {
                (false, true, true) => 0,
                (true, false, true) => 1,
                (true, true, false) => 2,
                _ => continue,
            };
            if seen[axis] {
                return true;
            }
            seen[axis] = true;
        }
    }
    false
}

/// The orientation determinant in floating point, and the differences it used.
#[inline(always)]
fn orient3d_det(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> (f64, DVec3, DVec3, DVec3) {
    let ba = b - a;
    let ca = c - a;
    let da = d - a;
    let m1 = ca.y * da.z - ca.z * da.y;
    let m2 = ca.z * da.x - ca.x * da.z;
    let m3 = ca.x * da.y - ca.y * da.x;
    (ba.x * m1 + ba.y * m2 + ba.z * m3, ba, ca, da)
}

/// Exact orientation without the floating-point filter: the fixed-point stage, then
/// `robust` for inputs out of its range.
#[inline(never)]
pub fn orient3d_exact(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Orientation {
    match fixed::orient3d_sign(a, b, c, d) {
        Some(s) => Orientation::from_f64(s as f64),
        None => {
            let q = rescaled([a, b, c, d]);
            if robust_exact(&q) {
                orient3d_robust(q[0], q[1], q[2], q[3])
            } else {
                big::orient3d_sign(a, b, c, d)
                    .map_or(Orientation::Zero, |s| Orientation::from_f64(s as f64))
            }
        }
    }
}

/// Exact orientation by `robust` alone: the reference the faster stages are tested and
/// benchmarked against.
#[inline(never)]
pub fn orient3d_robust(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Orientation {
    // robust's orient3d is positive when d is below the plane of (a, b, c) seen
    // counter-clockwise, which is our negative signed volume.
    Orientation::from_f64(-robust::orient3d(c3(a), c3(b), c3(c), c3(d)))
}

/// Orientation of the triangle `(a, b, c)` in the plane: `Positive` when
/// counter-clockwise. Exact.
#[inline]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Orientation {
    Orientation::from_f64(robust::orient2d(
        Coord { x: a[0], y: a[1] },
        Coord { x: b[0], y: b[1] },
        Coord { x: c[0], y: c[1] },
    ))
}

/// Whether `p` lies on the open segment `(a, b)`, decided exactly: collinear in the
/// three coordinate projections and strictly between the end points.
pub fn on_open_segment(a: DVec3, b: DVec3, p: DVec3) -> bool {
    let proj = |v: DVec3, i: usize, j: usize| [v[i], v[j]];
    let collinear = [(0, 1), (1, 2), (2, 0)]
        .iter()
        .all(|&(i, j)| orient2d(proj(a, i, j), proj(b, i, j), proj(p, i, j)) == Orientation::Zero);
    // On the line, `p` is strictly between iff it is on a coordinate where `a` and `b`
    // differ (exact comparisons).
    collinear
        && (0..3).any(|i| a[i] != b[i])
        && (0..3).all(|i| {
            let (lo, hi) = (a[i].min(b[i]), a[i].max(b[i]));
            if lo == hi {
                p[i] == lo
            } else {
                lo < p[i] && p[i] < hi
            }
        })
}

/// Position of `e` with respect to the circumsphere of the positively oriented
/// tetrahedron `(a, b, c, d)`. Exact. The answer is meaningless if the tetrahedron is
/// flat.
#[inline]
pub fn insphere(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
    let (det, diffs) = insphere_det(a, b, c, d, e);
    insphere_semi(det, diffs, [a, b, c, d, e])
}

/// [`insphere`] from its determinant `det` and the differences to `e`
/// ([`insphere_det`]), as a caller whose own filter failed has them.
#[inline]
fn insphere_semi(det: f64, [ae, be, ce, de]: [DVec3; 4], [a, b, c, d, e]: [DVec3; 5]) -> Sphere {
    let mx = ae.x.abs().max(be.x.abs()).max(ce.x.abs()).max(de.x.abs());
    let my = ae.y.abs().max(be.y.abs()).max(ce.y.abs()).max(de.y.abs());
    let mz = ae.z.abs().max(be.z.abs()).max(ce.z.abs()).max(de.z.abs());
    let lo = mx.min(my).min(mz);
    let hi = mx.max(my).max(mz);
    if !(lo > FILTER_MIN && hi < FILTER_MAX) {
        return insphere_exact(a, b, c, d, e);
    }
    let bound = ISP_SEMI * mx * my * mz * hi * hi;
    // Shewchuk's determinant is positive for "inside" when (a,b,c,d) is positive in his
    // convention, i.e. negative in ours.
    if det > bound {
        return Sphere::Outside;
    }
    if -det > bound {
        return Sphere::Inside;
    }
    insphere_dynamic(det, [ae, be, ce, de], [a, b, c, d, e])
}

/// The calls the semi-static filter leaves (out of line, so the inlined fast path stays
/// small): a dynamic filter, Shewchuk's first error bound, `ISP_DYN` times the permanent
/// (the determinant with every term replaced by its absolute value), valid for the same
/// expression evaluated in the same order without underflow (guaranteed by the caller's
/// range check); then the exact stages.
#[inline(never)]
fn insphere_dynamic(det: f64, diffs: [DVec3; 4], [a, b, c, d, e]: [DVec3; 5]) -> Sphere {
    // The caller's range check bounds the largest difference per axis only; a smaller
    // non-zero one can still make products underflow, and then the relative bound does
    // not hold (fuzzing found a wrong sign with differences near 1e-178 beside 1e-35).
    let no_underflow = diffs.iter().all(|v| {
        v.to_array()
            .iter()
            .all(|&x| x == 0.0 || x.abs() > FILTER_MIN)
    });
    if no_underflow {
        let perm = insphere_permanent(diffs);
        if det > ISP_DYN * perm {
            return Sphere::Outside;
        }
        if -det > ISP_DYN * perm {
            return Sphere::Inside;
        }
    }
    insphere_exact(a, b, c, d, e)
}

/// Shewchuk's `isperrboundA = (16 + 224 eps) eps`, with `eps = 2^-53`.
const ISP_DYN: f64 = (16.0 + 224.0 * f64::EPSILON / 2.0) * f64::EPSILON / 2.0;

/// The permanent of the insphere determinant of the differences (Shewchuk 1997, §4.3).
#[inline(always)]
fn insphere_permanent([ae, be, ce, de]: [DVec3; 4]) -> f64 {
    let m = |p: DVec3, q: DVec3| (p.x * q.y).abs() + (q.x * p.y).abs();
    let (ab, bc, cd, da, ac, bd) = (
        m(ae, be),
        m(be, ce),
        m(ce, de),
        m(de, ae),
        m(ae, ce),
        m(be, de),
    );
    let (az, bz, cz, dz) = (ae.z.abs(), be.z.abs(), ce.z.abs(), de.z.abs());
    (cd * bz + bd * cz + bc * dz) * ae.length_squared()
        + (da * cz + ac * dz + cd * az) * be.length_squared()
        + (ab * dz + bd * az + da * bz) * ce.length_squared()
        + (bc * az + ac * bz + ab * cz) * de.length_squared()
}

/// The insphere determinant in floating point (Shewchuk's expression: positive when `e`
/// is outside for our positive tets), and the differences it used.
#[inline(always)]
fn insphere_det(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> (f64, [DVec3; 4]) {
    let ae = a - e;
    let be = b - e;
    let ce = c - e;
    let de = d - e;
    let ab = ae.x * be.y - be.x * ae.y;
    let bc = be.x * ce.y - ce.x * be.y;
    let cd = ce.x * de.y - de.x * ce.y;
    let da = de.x * ae.y - ae.x * de.y;
    let ac = ae.x * ce.y - ce.x * ae.y;
    let bd = be.x * de.y - de.x * be.y;
    let abc = ae.z * bc - be.z * ac + ce.z * ab;
    let bcd = be.z * cd - ce.z * bd + de.z * bc;
    let cda = ce.z * da + de.z * ac + ae.z * cd;
    let dab = de.z * ab + ae.z * bd + be.z * da;
    let alift = ae.length_squared();
    let blift = be.length_squared();
    let clift = ce.length_squared();
    let dlift = de.length_squared();
    let det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
    (det, [ae, be, ce, de])
}

/// A static filter for points known to lie in a box (Shewchuk's, TetGen's and HXT's
/// idea): the error bounds of the semi-static filters, evaluated once with the box
/// extents as the coordinate differences. One comparison decides most calls; the rest
/// go through the semi-static filter, then the exact predicate.
///
/// Only valid when every point passed lies in the box given to [`StaticFilter::new`]:
/// callers check [`StaticFilter::contains`] for points that may lie outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticFilter {
    min: DVec3,
    max: DVec3,
    o3d: f64,
    isp: f64,
}

impl StaticFilter {
    /// A filter for points in the box `[min, max]`.
    pub fn new(min: DVec3, max: DVec3) -> Self {
        let m = max - min;
        let ok = m.is_finite() && m.min_element() > FILTER_MIN && m.max_element() < FILTER_MAX;
        let hi = m.max_element();
        let (o3d, isp) = if ok {
            // Rounded up a little: the bounds themselves are computed in floating point.
            let prod = m.x * m.y * m.z * (1.0 + 1e-12);
            (O3D_SEMI * prod, ISP_SEMI * prod * hi * hi * (1.0 + 1e-12))
        } else {
            (f64::INFINITY, f64::INFINITY)
        };
        StaticFilter { min, max, o3d, isp }
    }

    /// A filter for the box of `points` ([`StaticFilter::none`] when there are none).
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a DVec3>) -> Self {
        super::Aabb::of_points(points).map_or_else(Self::none, |b| Self::new(b.min, b.max))
    }

    /// This filter when `p` lies in its box, else the generic one (for a query point
    /// that may lie outside the box of the points it is tested with).
    #[inline]
    pub fn for_point(&self, p: DVec3) -> Self {
        if self.contains(p) {
            *self
        } else {
            Self::none()
        }
    }

    /// A filter that never decides alone (every call takes the semi-static path).
    pub fn none() -> Self {
        StaticFilter {
            min: DVec3::INFINITY,
            max: DVec3::NEG_INFINITY,
            o3d: f64::INFINITY,
            isp: f64::INFINITY,
        }
    }

    /// True when `p` lies in the filter's box.
    #[inline]
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// [`orient3d`] for points in the box.
    #[inline]
    pub fn orient3d(&self, a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Orientation {
        let (det, ba, ca, da) = orient3d_det(a, b, c, d);
        if det > self.o3d {
            Orientation::Positive
        } else if -det > self.o3d {
            Orientation::Negative
        } else {
            // The same determinant: the semi-static filter goes on from it.
            orient3d_semi(det, [ba, ca, da], [a, b, c, d])
        }
    }

    /// [`insphere_perturbed`] for points in the box.
    #[inline]
    pub fn insphere_perturbed(&self, a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
        let (det, diffs) = insphere_det(a, b, c, d, e);
        if det > self.isp {
            Sphere::Outside
        } else if -det > self.isp {
            Sphere::Inside
        } else {
            // The same determinant: the semi-static filter goes on from it.
            match insphere_semi(det, diffs, [a, b, c, d, e]) {
                Sphere::On => insphere_tie_break(a, b, c, d, e),
                s => s,
            }
        }
    }
}

impl Default for StaticFilter {
    fn default() -> Self {
        StaticFilter::none()
    }
}

/// Exact insphere without the floating-point filter: the fixed-point stage, then
/// `robust` for inputs out of its range.
#[inline(never)]
pub fn insphere_exact(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
    match fixed::insphere_sign(a, b, c, d, e) {
        Some(s) => sphere_from_shewchuk(s as f64),
        None => {
            let q = rescaled([a, b, c, d, e]);
            if robust_exact(&q) {
                insphere_robust(q[0], q[1], q[2], q[3], q[4])
            } else {
                big::insphere_sign(a, b, c, d, e)
                    .map_or(Sphere::On, |s| sphere_from_shewchuk(s as f64))
            }
        }
    }
}

/// `2^k` for `-1022 <= k <= 1023`.
#[inline]
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// The points multiplied by the power of two that brings their largest coordinate into
/// `[0.5, 1)`, when that is exact; else the points unchanged. Every determinant keeps its
/// sign, and `robust`, whose expansions are exact only while no product overflows or
/// underflows, then stays exact for points of comparable magnitude far from 1 (degree-5
/// products of coordinates near 1e±70 already leave the double range).
fn rescaled<const N: usize>(p: [DVec3; N]) -> [DVec3; N] {
    let m = p.iter().fold(0.0f64, |m, q| m.max(q.abs().max_element()));
    if m == 0.0 || !m.is_finite() || !p.iter().all(|q| q.is_finite()) {
        return p;
    }
    // m < 2^top with top - 1 <= log2(m); subnormals have biased exponent 0.
    let biased = ((m.to_bits() >> 52) & 0x7ff) as i32;
    let top = if biased == 0 {
        -1022 - m.to_bits().leading_zeros() as i32 + 12
    } else {
        biased - 1022
    };
    let scale = |x: f64, k: i32| {
        let mut x = x;
        let mut k = k;
        while k != 0 {
            let step = k.clamp(-1000, 1000);
            x *= pow2(step);
            k -= step;
        }
        x
    };
    let q = p.map(|v| DVec3::new(scale(v.x, -top), scale(v.y, -top), scale(v.z, -top)));
    let back = q.map(|v| DVec3::new(scale(v.x, top), scale(v.y, top), scale(v.z, top)));
    if back == p {
        q
    } else {
        p
    }
}

/// Whether `robust` is exact on the (rescaled) points: every coordinate zero or of
/// magnitude in `[2^-150, 4]`. Then every value its expansions form from degree-5
/// products is a multiple of `2^(-5 * (150 + 53))`, above the smallest normal double,
/// and below the largest; else [`big`] decides (NaN and infinities stay with `robust`).
fn robust_exact<const N: usize>(q: &[DVec3; N]) -> bool {
    const LO: f64 = 7.006_492_321_624_085e-46; // 2^-150
    q.iter().all(|v| {
        !v.is_finite()
            || v.to_array()
                .iter()
                .all(|&x| x == 0.0 || (LO..=4.0).contains(&x.abs()))
    })
}

/// Exact insphere by `robust` alone: the reference the faster stages are tested and
/// benchmarked against.
#[inline(never)]
pub fn insphere_robust(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
    sphere_from_shewchuk(robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e)))
}

/// Shewchuk's insphere sign (positive: outside for our positive tets) as a [`Sphere`].
#[inline]
fn sphere_from_shewchuk(v: f64) -> Sphere {
    if v < 0.0 {
        Sphere::Inside
    } else if v > 0.0 {
        Sphere::Outside
    } else {
        Sphere::On
    }
}

/// Lexicographic order of points by (x, y, z): the order of the symbolic perturbation.
#[inline]
fn lex_less(p: DVec3, q: DVec3) -> bool {
    (p.x, p.y, p.z) < (q.x, q.y, q.z)
}

/// [`insphere`] with ties broken by symbolic perturbation: never answers `On` for five
/// distinct points when `(a, b, c, d)` is a proper positive tetrahedron.
///
/// The perturbation lifts each point on the paraboloid by an infinitesimal that is
/// larger for lexicographically larger points. When the exact determinant is zero the
/// sign is read from the coefficient of the largest perturbation whose cofactor (an
/// orientation of the four other points) is not zero.
#[inline]
pub fn insphere_perturbed(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
    match insphere(a, b, c, d, e) {
        Sphere::On => insphere_tie_break(a, b, c, d, e),
        s => s,
    }
}

/// The symbolic perturbation of [`insphere_perturbed`] for an exact tie.
#[cold]
#[inline(never)]
fn insphere_tie_break(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
    let mut pts = [(a, 0usize), (b, 1), (c, 2), (d, 3), (e, 4)];
    // Sort descending: the largest point carries the dominant perturbation.
    pts.sort_by(|p, q| {
        if lex_less(p.0, q.0) {
            std::cmp::Ordering::Greater
        } else if lex_less(q.0, p.0) {
            std::cmp::Ordering::Less
        } else {
            std::cmp::Ordering::Equal
        }
    });
    for &(_, which) in &pts {
        // The cofactor of point `which` is the orientation of the other four with `e`
        // put in its place; raising that point pushes `e` outside when positive.
        let o = match which {
            4 => return Sphere::Outside,
            0 => orient3d(e, b, c, d),
            1 => orient3d(a, e, c, d),
            2 => orient3d(a, b, e, d),
            _ => orient3d(a, b, c, e),
        };
        match o {
            Orientation::Positive => return Sphere::Inside,
            Orientation::Negative => return Sphere::Outside,
            Orientation::Zero => {}
        }
    }
    Sphere::On
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn on_open_segment_is_exact() {
        let (a, b) = (v(0.0, 0.0, 0.0), v(1.0, 2.0, 4.0));
        assert!(on_open_segment(a, b, v(0.5, 1.0, 2.0)));
        assert!(!on_open_segment(a, b, a));
        assert!(!on_open_segment(a, b, v(2.0, 4.0, 8.0)));
        // One unit in the last place off the line.
        assert!(!on_open_segment(a, b, v(0.5, 1.0, 2.0f64.next_up())));
        // Symmetric end points: the origin is exactly between them.
        let c = v(0.1, 0.7, 0.3);
        assert!(on_open_segment(-c, c, v(0.0, 0.0, 0.0)));
    }

    #[test]
    fn orientation_convention() {
        let o = v(0.0, 0.0, 0.0);
        let x = v(1.0, 0.0, 0.0);
        let y = v(0.0, 1.0, 0.0);
        let z = v(0.0, 0.0, 1.0);
        assert_eq!(orient3d(o, x, y, z), Orientation::Positive);
        assert_eq!(orient3d(o, y, x, z), Orientation::Negative);
        assert_eq!(orient3d(o, x, y, v(1.0, 1.0, 0.0)), Orientation::Zero);
        assert_eq!(orient3d_exact(o, x, y, z), Orientation::Positive);
        assert_eq!(
            orient2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]),
            Orientation::Positive
        );
    }

    #[test]
    fn shared_coordinates_and_repeated_points_are_coplanar_as_the_exact_stages_say() {
        // Arbitrary values in one axis-aligned plane, and one point a unit in the last
        // place off it: the shortcut must answer only the first.
        let p = [
            v(0.0666403, 0.0828129999041748, -0.42323825299072265),
            v(0.0666403, 0.08306436188423155, -0.42323210280609136),
            v(0.0666403, -1e-3, 7.25),
            v(0.0666403, 3.0e5, -2.5e-7),
        ];
        for k in 0..3 {
            let q: Vec<DVec3> = p
                .iter()
                .map(|x| {
                    let mut a = x.to_array();
                    a.swap(0, k);
                    DVec3::from_array(a)
                })
                .collect();
            assert_eq!(orient3d(q[0], q[1], q[2], q[3]), Orientation::Zero);
            assert_eq!(orient3d_exact(q[0], q[1], q[2], q[3]), Orientation::Zero);
            let mut off = q[3].to_array();
            off[k] = off[k].next_up();
            let off = DVec3::from_array(off);
            assert_eq!(
                orient3d(q[0], q[1], q[2], off),
                orient3d_exact(q[0], q[1], q[2], off)
            );
            assert_ne!(orient3d(q[0], q[1], q[2], off), Orientation::Zero);
        }
        // Two differences parallel to one axis: the walls of a prismatic hole.
        let (a, b) = (
            v(-0.0436300002, 0.0362810008, 0.0063700001),
            v(-0.0381130017, 0.0312799998, -0.0062799999),
        );
        let (c, d) = (v(b.x, b.y, 0.0062799999), v(a.x, a.y, -0.0063700001));
        assert_eq!(orient3d(a, b, c, d), Orientation::Zero);
        assert_eq!(orient3d_exact(a, b, c, d), Orientation::Zero);
        let d_off = v(a.x.next_up(), a.y, -0.0063700001);
        assert_eq!(orient3d(a, b, c, d_off), orient3d_exact(a, b, c, d_off));
        assert_ne!(orient3d(a, b, c, d_off), Orientation::Zero);
        // A point given twice.
        let (x, y, z) = (v(0.1, 0.7, 0.3), v(-2.5, 1e-3, 4.0), v(3.0, 3.5, -1.25));
        for t in [[x, y, z, x], [x, y, y, z], [z, x, y, z]] {
            assert_eq!(orient3d(t[0], t[1], t[2], t[3]), Orientation::Zero);
            assert_eq!(orient3d_exact(t[0], t[1], t[2], t[3]), Orientation::Zero);
        }
    }

    #[test]
    fn insphere_convention() {
        let o = v(0.0, 0.0, 0.0);
        let x = v(1.0, 0.0, 0.0);
        let y = v(0.0, 1.0, 0.0);
        let z = v(0.0, 0.0, 1.0);
        assert_eq!(insphere(o, x, y, z, v(0.2, 0.2, 0.2)), Sphere::Inside);
        assert_eq!(insphere(o, x, y, z, v(2.0, 2.0, 2.0)), Sphere::Outside);
        // (1,1,1) is on the circumsphere (centre (.5,.5,.5)).
        assert_eq!(insphere(o, x, y, z, v(1.0, 1.0, 1.0)), Sphere::On);
        assert_eq!(insphere_exact(o, x, y, z, v(0.2, 0.2, 0.2)), Sphere::Inside);
        assert_ne!(insphere_perturbed(o, x, y, z, v(1.0, 1.0, 1.0)), Sphere::On);
    }

    #[test]
    fn perturbation_is_consistent_on_cube() {
        // The eight cube corners are cospherical: for the two tetrahedra sharing a face,
        // the perturbed answers must not both claim the opposite vertex.
        let c: Vec<DVec3> = (0..8)
            .map(|i| v((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        let t = [c[0], c[1], c[2], c[4]];
        assert_eq!(orient3d(t[0], t[1], t[2], t[3]), Orientation::Positive);
        let s = insphere_perturbed(t[0], t[1], t[2], t[3], c[7]);
        assert_ne!(s, Sphere::On);
    }

    #[test]
    fn filter_agrees_with_exact_near_degenerate() {
        let a = v(0.1, 0.1, 0.1);
        let b = v(0.3, 0.1, 0.1);
        let c = v(0.1, 0.3, 0.1);
        for i in 0..200 {
            let d = v(0.2, 0.2, 0.1 + (i as f64 - 100.0) * 1e-17);
            assert_eq!(orient3d(a, b, c, d), orient3d_exact(a, b, c, d));
        }
    }

    use proptest::prelude::*;

    fn near(base: f64) -> impl Strategy<Value = f64> {
        prop_oneof![
            Just(base),
            (-1000i64..1000)
                .prop_map(move |k| base + k as f64 * f64::EPSILON * base.abs().max(1.0)),
            (-1.0f64..1.0).prop_map(move |t| base + t * 1e-12),
        ]
    }

    fn pt_near(x: f64, y: f64, z: f64) -> impl Strategy<Value = DVec3> {
        (near(x), near(y), near(z)).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// The filters never disagree with the exact predicates, on nearly coplanar and
        /// nearly cospherical inputs at several scales.
        #[test]
        fn filters_agree_with_exact(
            a in pt_near(0.0, 0.0, 0.0),
            b in pt_near(1.0, 0.0, 0.0),
            c in pt_near(0.0, 1.0, 0.0),
            d in pt_near(1.0, 1.0, 0.0),
            e in pt_near(1.0, 1.0, 1.0),
            z in pt_near(0.0, 0.0, 1.0),
            scale in prop_oneof![Just(1.0), Just(1e-9), Just(3.7e6), Just(1e-40)],
            shift in prop_oneof![Just(0.0), Just(1e3), Just(-12.5)],
        ) {
            let f = |p: DVec3| p * scale + DVec3::splat(shift * scale);
            let (a, b, c, d, e, z) = (f(a), f(b), f(c), f(d), f(e), f(z));
            prop_assert_eq!(orient3d(a, b, c, d), orient3d_exact(a, b, c, d));
            prop_assert_eq!(orient3d(a, b, c, z), orient3d_exact(a, b, c, z));
            prop_assert_eq!(insphere(a, b, c, z, e), insphere_exact(a, b, c, z, e));
            prop_assert_eq!(insphere(a, b, c, z, d), insphere_exact(a, b, c, z, d));
            // The exact stages agree with `robust` alone (no product leaves the double
            // range at these scales).
            prop_assert_eq!(orient3d_exact(a, b, c, d), orient3d_robust(a, b, c, d));
            prop_assert_eq!(insphere_exact(a, b, c, z, e), insphere_robust(a, b, c, z, e));
            prop_assert_eq!(insphere_exact(a, b, c, z, d), insphere_robust(a, b, c, z, d));
            // The static filter over the points' box agrees too.
            let pts = [a, b, c, d, e, z];
            let lo = pts.iter().fold(DVec3::INFINITY, |m, p| m.min(*p));
            let hi = pts.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p));
            let f = StaticFilter::new(lo, hi);
            prop_assert!(pts.iter().all(|p| f.contains(*p)));
            prop_assert_eq!(f.orient3d(a, b, c, d), orient3d_exact(a, b, c, d));
            prop_assert_eq!(f.orient3d(a, b, c, z), orient3d_exact(a, b, c, z));
            if orient3d_exact(a, b, c, z) == Orientation::Positive {
                prop_assert_eq!(
                    f.insphere_perturbed(a, b, c, z, e),
                    insphere_perturbed(a, b, c, z, e)
                );
            }
        }
    }
}
