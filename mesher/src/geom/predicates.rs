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
//! Degeneracies: [`insphere_perturbed`] breaks ties (`e` exactly on the sphere) by the
//! symbolic perturbation of Devillers and Teillaud ("Perturbations and vertex removal in
//! a 3D Delaunay triangulation", SODA 2003): every point is lifted by an infinitesimal
//! amount ordered lexicographically by coordinates, so the answer is never "on" for five
//! distinct points in general position of the perturbed space and the Delaunay
//! triangulation becomes unique.

use glam::DVec3;
use robust::{Coord, Coord3D};

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

/// Static filter constant for the 3x3 orientation determinant computed from
/// differences (Shewchuk's `o3derrboundA` is 7.77e-16 relative to the permanent; this
/// bound is on the permanent itself, so it is safe for any magnitude).
const O3D_ERR: f64 = 7.771_561_172_376_103e-16;
/// Shewchuk's `isperrboundA`.
const ISP_ERR: f64 = 1.776_356_839_400_253e-15;

/// Orientation of the tetrahedron `(a, b, c, d)`: the sign of `det[b-a, c-a, d-a]`,
/// exact.
#[inline]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Orientation {
    // Fast path: the determinant of the differences to `a`, with Shewchuk's error bound
    // applied to its permanent. Falls back to the adaptive exact evaluation.
    let ba = b - a;
    let ca = c - a;
    let da = d - a;
    let m1 = ca.y * da.z - ca.z * da.y;
    let m2 = ca.z * da.x - ca.x * da.z;
    let m3 = ca.x * da.y - ca.y * da.x;
    let det = ba.x * m1 + ba.y * m2 + ba.z * m3;
    let perm = ba.x.abs() * ((ca.y * da.z).abs() + (ca.z * da.y).abs())
        + ba.y.abs() * ((ca.z * da.x).abs() + (ca.x * da.z).abs())
        + ba.z.abs() * ((ca.x * da.y).abs() + (ca.y * da.x).abs());
    let bound = O3D_ERR * perm;
    if det > bound {
        return Orientation::Positive;
    }
    if -det > bound {
        return Orientation::Negative;
    }
    orient3d_exact(a, b, c, d)
}

/// Exact orientation without the fast filter (used by tests to check the filter).
#[inline(never)]
pub fn orient3d_exact(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Orientation {
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

/// Position of `e` with respect to the circumsphere of the positively oriented
/// tetrahedron `(a, b, c, d)`. Exact. The answer is meaningless if the tetrahedron is
/// flat.
#[inline]
pub fn insphere(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
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

    let aezp = ae.z.abs();
    let bezp = be.z.abs();
    let cezp = ce.z.abs();
    let dezp = de.z.abs();
    let abp = (ae.x * be.y).abs() + (be.x * ae.y).abs();
    let bcp = (be.x * ce.y).abs() + (ce.x * be.y).abs();
    let cdp = (ce.x * de.y).abs() + (de.x * ce.y).abs();
    let dap = (de.x * ae.y).abs() + (ae.x * de.y).abs();
    let acp = (ae.x * ce.y).abs() + (ce.x * ae.y).abs();
    let bdp = (be.x * de.y).abs() + (de.x * be.y).abs();
    let perm = ((cdp * bezp + bdp * cezp + bcp * dezp) * alift)
        + ((dap * cezp + acp * dezp + cdp * aezp) * blift)
        + ((abp * dezp + bdp * aezp + dap * bezp) * clift)
        + ((bcp * aezp + acp * bezp + abp * cezp) * dlift);
    let bound = ISP_ERR * perm;
    // Shewchuk's determinant is positive for "inside" when (a,b,c,d) is positive in his
    // convention, i.e. negative in ours.
    if det > bound {
        return Sphere::Outside;
    }
    if -det > bound {
        return Sphere::Inside;
    }
    insphere_exact(a, b, c, d, e)
}

/// Exact insphere without the fast filter.
#[inline(never)]
pub fn insphere_exact(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
    let v = robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e));
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
pub fn insphere_perturbed(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Sphere {
    match insphere(a, b, c, d, e) {
        Sphere::On => {}
        s => return s,
    }
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
}
