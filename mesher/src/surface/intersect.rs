//! Exact triangle-triangle intersection for the self-intersection check of
//! [`Surface::check`](crate::surface::Surface::check).
//!
//! Everything is decided with the exact [`orient3d`] and [`orient2d`] of
//! [`crate::geom::predicates`]; no intersection point is ever constructed.
//!
//! * Segment against triangle (closed sets): if the segment crosses the triangle's plane
//!   (its endpoints are not strictly on one side), the crossing point lies in the
//!   triangle iff the three Plücker signs `orient3d(a, b, t_i, t_j)` over the triangle's
//!   edges are not strictly opposite (the classic line-triangle side test). If the
//!   segment lies in the plane the test is done in 2D.
//! * 2D projections: a coplanar configuration is projected by dropping one coordinate
//!   axis. Dropping a coordinate is exact (no arithmetic), and the projection is an affine
//!   bijection of the plane as soon as the projected triangle is not flat, which we check
//!   exactly with `orient2d`: the three projections are tried in order and the first
//!   non-degenerate one is used. A triangle flat in all three is collinear
//!   ([`is_collinear`]: the zero-area test of the checker).
//! * Two closed triangles meet iff an edge of one meets the other: their intersection is
//!   a convex set whose extreme points lie on the boundary of one of them.
//! * Faces that share vertices (by index) are allowed to touch there. Sharing one vertex
//!   `v`: the intersection is convex and contains `v`; if it contains another point, the
//!   farthest point from `v` along that direction lies on the edge opposite to `v` of one
//!   face, so the faces meet improperly iff the edge of one opposite `v` meets the other
//!   face. Sharing an edge `uv`: improper iff both faces are coplanar and lie on the same
//!   side of `uv` (they fold onto each other).
//!
//! Degenerate (collinear) triangles are reported separately by the checker and are
//! never considered to intersect anything here.

use crate::geom::predicates::{orient2d, orient3d, Orientation, StaticFilter};
use crate::geom::Point;
use Orientation::{Negative, Positive, Zero};

/// The 2D projection dropping coordinate `axis` (keeping the other two in cyclic order,
/// so the sign of `orient2d` is the sign of the normal's `axis` component).
#[inline]
fn proj(p: Point, axis: usize) -> [f64; 2] {
    match axis {
        0 => [p.y, p.z],
        1 => [p.z, p.x],
        _ => [p.x, p.y],
    }
}

/// The first axis whose dropping leaves the triangle non-flat, `None` if collinear.
pub(crate) fn projection_axis(t: &[Point; 3]) -> Option<usize> {
    (0..3).find(|&ax| orient2d(proj(t[0], ax), proj(t[1], ax), proj(t[2], ax)) != Zero)
}

/// Whether the three points are exactly collinear (zero-area triangle).
pub fn is_collinear(a: Point, b: Point, c: Point) -> bool {
    projection_axis(&[a, b, c]).is_none()
}

/// `r` lies within the bounding box of `p`, `q` (used for collinear points only).
#[inline]
fn in_box_2d(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> bool {
    (0..2).all(|k| r[k] >= p[k].min(q[k]) && r[k] <= p[k].max(q[k]))
}

/// Closed segments `[a, b]` and `[c, d]` of the plane meet.
fn segments_meet_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let d1 = orient2d(c, d, a);
    let d2 = orient2d(c, d, b);
    let d3 = orient2d(a, b, c);
    let d4 = orient2d(a, b, d);
    if d1 != Zero && d2 != Zero && d1 != d2 && d3 != Zero && d4 != Zero && d3 != d4 {
        return true;
    }
    (d1 == Zero && in_box_2d(c, d, a))
        || (d2 == Zero && in_box_2d(c, d, b))
        || (d3 == Zero && in_box_2d(a, b, c))
        || (d4 == Zero && in_box_2d(a, b, d))
}

/// `p` lies in the closed triangle `t` of orientation `o` (not `Zero`).
fn point_in_triangle_2d(p: [f64; 2], t: &[[f64; 2]; 3], o: Orientation) -> bool {
    let bad = o.reversed();
    (0..3).all(|i| orient2d(t[i], t[(i + 1) % 3], p) != bad)
}

/// Closed segment `[a, b]` meets the closed non-flat triangle `t` of the plane.
fn segment_triangle_2d(a: [f64; 2], b: [f64; 2], t: &[[f64; 2]; 3]) -> bool {
    let o = orient2d(t[0], t[1], t[2]);
    if o == Zero {
        return false;
    }
    point_in_triangle_2d(a, t, o)
        || point_in_triangle_2d(b, t, o)
        || (0..3).any(|i| segments_meet_2d(a, b, t[i], t[(i + 1) % 3]))
}

/// Closed segment `[a, b]` meets closed triangle `t`, given the exact sides `sa`, `sb`
/// of `a` and `b` with respect to the plane of `t` (`orient3d(t0, t1, t2, .)`).
fn segment_triangle(
    f: &StaticFilter,
    a: Point,
    b: Point,
    sa: Orientation,
    sb: Orientation,
    t: &[Point; 3],
) -> bool {
    match (sa, sb) {
        (Zero, Zero) => match projection_axis(t) {
            Some(ax) => segment_triangle_2d(
                proj(a, ax),
                proj(b, ax),
                &[proj(t[0], ax), proj(t[1], ax), proj(t[2], ax)],
            ),
            None => false,
        },
        _ if sa == sb => false,
        _ => {
            // The line ab meets the plane in a single point of [a, b].
            let mut pos = false;
            let mut neg = false;
            for i in 0..3 {
                match f.orient3d(a, b, t[i], t[(i + 1) % 3]) {
                    Positive => pos = true,
                    Negative => neg = true,
                    Zero => {}
                }
            }
            !(pos && neg)
        }
    }
}

/// Exact sides of the three points of `q` with respect to the plane of `p`.
#[inline]
fn sides(f: &StaticFilter, p: &[Point; 3], q: &[Point; 3]) -> [Orientation; 3] {
    [
        f.orient3d(p[0], p[1], p[2], q[0]),
        f.orient3d(p[0], p[1], p[2], q[1]),
        f.orient3d(p[0], p[1], p[2], q[2]),
    ]
}

/// All three sides strictly equal: the triangle is strictly on one side of the plane.
#[inline]
fn strictly_one_side(s: &[Orientation; 3]) -> bool {
    s[0] != Zero && s[0] == s[1] && s[1] == s[2]
}

/// Whether the closed triangles `p` and `q` have a common point. Collinear triangles
/// never intersect (see the module docs).
pub fn triangles_intersect(p: &[Point; 3], q: &[Point; 3]) -> bool {
    triangles_intersect_in(&StaticFilter::none(), p, q)
}

/// [`triangles_intersect`] with the static filter `f`, valid for every point given.
fn triangles_intersect_in(f: &StaticFilter, p: &[Point; 3], q: &[Point; 3]) -> bool {
    if projection_axis(p).is_none() || projection_axis(q).is_none() {
        return false;
    }
    let sq = sides(f, p, q);
    if strictly_one_side(&sq) {
        return false;
    }
    let sp = sides(f, q, p);
    if strictly_one_side(&sp) {
        return false;
    }
    (0..3).any(|i| {
        let j = (i + 1) % 3;
        segment_triangle(f, q[i], q[j], sq[i], sq[j], p)
            || segment_triangle(f, p[i], p[j], sp[i], sp[j], q)
    })
}

/// Whether faces `p` (vertex ids `ip`) and `q` (ids `iq`) intersect improperly: anywhere
/// except along the vertices or edge they share by index. Faces with a repeated index or
/// collinear points never intersect here; faces with the same three ids always do.
pub fn faces_intersect(p: &[Point; 3], ip: [u32; 3], q: &[Point; 3], iq: [u32; 3]) -> bool {
    faces_intersect_in(&StaticFilter::none(), p, ip, q, iq)
}

/// [`faces_intersect`] with the static filter `f`, valid for every point given (the
/// surface check's: its vertices' box).
pub(crate) fn faces_intersect_in(
    f: &StaticFilter,
    p: &[Point; 3],
    ip: [u32; 3],
    q: &[Point; 3],
    iq: [u32; 3],
) -> bool {
    if ip[0] == ip[1] || ip[1] == ip[2] || ip[0] == ip[2] {
        return false;
    }
    if iq[0] == iq[1] || iq[1] == iq[2] || iq[0] == iq[2] {
        return false;
    }
    if projection_axis(p).is_none() || projection_axis(q).is_none() {
        return false;
    }
    // shared[i] = position in q of p's vertex i.
    let shared: [Option<usize>; 3] = [0, 1, 2].map(|i| iq.iter().position(|&x| x == ip[i]));
    match shared.iter().filter(|s| s.is_some()).count() {
        0 => triangles_intersect_in(f, p, q),
        1 => {
            let i = shared.iter().position(|s| s.is_some()).unwrap_or(0);
            let j = shared[i].unwrap_or(0);
            opposite_edge_meets(f, p, i, q) || opposite_edge_meets(f, q, j, p)
        }
        2 => {
            let k = shared.iter().position(|s| s.is_none()).unwrap_or(0);
            let m = (0..3).find(|&m| !ip.contains(&iq[m])).unwrap_or(0);
            folded_on_shared_edge(f, p, k, q[m])
        }
        _ => true,
    }
}

/// The edge of `p` opposite to its vertex `i` meets triangle `q`.
fn opposite_edge_meets(f: &StaticFilter, p: &[Point; 3], i: usize, q: &[Point; 3]) -> bool {
    let a = p[(i + 1) % 3];
    let b = p[(i + 2) % 3];
    let sa = f.orient3d(q[0], q[1], q[2], a);
    let sb = f.orient3d(q[0], q[1], q[2], b);
    segment_triangle(f, a, b, sa, sb, q)
}

/// Face `p` and the face made of `p`'s edge opposite to vertex `k` plus apex `b` overlap
/// beyond that edge: coplanar and `b` on the same side as `p[k]`.
fn folded_on_shared_edge(f: &StaticFilter, p: &[Point; 3], k: usize, b: Point) -> bool {
    let u = p[(k + 1) % 3];
    let v = p[(k + 2) % 3];
    let a = p[k];
    if f.orient3d(u, v, a, b) != Zero {
        return false;
    }
    match projection_axis(p) {
        Some(ax) => {
            let sa = orient2d(proj(u, ax), proj(v, ax), proj(a, ax));
            let sb = orient2d(proj(u, ax), proj(v, ax), proj(b, ax));
            sa == sb
        }
        None => false,
    }
}

/// How a segment `[p, q]` meets a triangle, for ray parity (see
/// [`super::shells`](crate::surface::shells)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Crossing {
    /// No common point.
    Miss,
    /// The open segment crosses the open triangle transversally.
    Proper,
    /// `p` lies on the triangle.
    AtStart,
    /// Any other contact (through an edge or vertex, in the plane, or at `q`).
    Degenerate,
}

/// Classifies how segment `[p, q]` meets the non-flat triangle `t`.
pub(crate) fn segment_crossing(p: Point, q: Point, t: &[Point; 3]) -> Crossing {
    let sp = orient3d(t[0], t[1], t[2], p);
    let sq = orient3d(t[0], t[1], t[2], q);
    if sp == Zero && sq == Zero {
        return if segment_triangle(&StaticFilter::none(), p, q, sp, sq, t) {
            Crossing::Degenerate
        } else {
            Crossing::Miss
        };
    }
    if sp == sq {
        return Crossing::Miss;
    }
    let mut pos = false;
    let mut neg = false;
    let mut zero = false;
    for i in 0..3 {
        match orient3d(p, q, t[i], t[(i + 1) % 3]) {
            Positive => pos = true,
            Negative => neg = true,
            Zero => zero = true,
        }
    }
    if pos && neg {
        Crossing::Miss
    } else if sp == Zero {
        Crossing::AtStart
    } else if zero || sq == Zero {
        Crossing::Degenerate
    } else {
        Crossing::Proper
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Point {
        Point::new(x, y, z)
    }

    #[test]
    fn crossing_and_separate() {
        let p = [v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 2.0, 0.0)];
        let q = [v(0.5, 0.5, -1.0), v(0.5, 0.5, 1.0), v(3.0, 3.0, 0.0)];
        assert!(triangles_intersect(&p, &q));
        let r = [v(0.5, 0.5, 1.0), v(0.5, 0.7, 1.0), v(3.0, 3.0, 1.0)];
        assert!(!triangles_intersect(&p, &r));
        // Touching at a single point counts for unrelated faces.
        let s = [v(0.0, 0.0, 0.0), v(-1.0, 0.0, 1.0), v(0.0, -1.0, 1.0)];
        assert!(triangles_intersect(&p, &s));
        assert!(!faces_intersect(&p, [0, 1, 2], &s, [0, 3, 4]));
    }

    #[test]
    fn shared_edge_cases() {
        let p = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
        // Opposite side, coplanar: fine.
        let q = [v(1.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(0.0, -1.0, 0.0)];
        assert!(!faces_intersect(&p, [0, 1, 2], &q, [1, 0, 3]));
        // Same side, coplanar: folded.
        let r = [v(1.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(0.2, 0.2, 0.0)];
        assert!(faces_intersect(&p, [0, 1, 2], &r, [1, 0, 3]));
        // Dihedral angle: fine.
        let s = [v(1.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(0.2, 0.2, 1.0)];
        assert!(!faces_intersect(&p, [0, 1, 2], &s, [1, 0, 3]));
    }

    #[test]
    fn segment_crossing_cases() {
        let t = [v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(0.0, 2.0, 0.0)];
        let c = |p: Point, q: Point| segment_crossing(p, q, &t);
        assert_eq!(c(v(0.5, 0.5, -1.0), v(0.5, 0.5, 1.0)), Crossing::Proper);
        assert_eq!(c(v(3.0, 3.0, -1.0), v(3.0, 3.0, 1.0)), Crossing::Miss);
        assert_eq!(c(v(0.5, 0.5, 1.0), v(0.5, 0.5, 2.0)), Crossing::Miss);
        assert_eq!(c(v(0.5, 0.5, 0.0), v(0.5, 0.5, 2.0)), Crossing::AtStart);
        assert_eq!(c(v(3.0, 3.0, 0.0), v(3.0, 3.0, 2.0)), Crossing::Miss);
        // Through an edge, through a vertex, ending on the face, lying in the plane.
        assert_eq!(c(v(1.0, 0.0, -1.0), v(1.0, 0.0, 1.0)), Crossing::Degenerate);
        assert_eq!(c(v(0.0, 0.0, -1.0), v(0.0, 0.0, 1.0)), Crossing::Degenerate);
        assert_eq!(c(v(0.5, 0.5, -1.0), v(0.5, 0.5, 0.0)), Crossing::Degenerate);
        assert_eq!(c(v(-1.0, 0.5, 0.0), v(3.0, 0.5, 0.0)), Crossing::Degenerate);
        assert_eq!(c(v(-1.0, 5.0, 0.0), v(3.0, 5.0, 0.0)), Crossing::Miss);
    }

    #[test]
    fn collinear() {
        assert!(is_collinear(
            v(0.0, 0.0, 0.0),
            v(1.0, 1.0, 1.0),
            v(3.0, 3.0, 3.0)
        ));
        assert!(!is_collinear(
            v(0.0, 0.0, 0.0),
            v(1.0, 1.0, 1.0),
            v(3.0, 3.0, 3.5)
        ));
    }
}
