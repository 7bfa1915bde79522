//! Exact signs of the orientation and insphere determinants in arbitrary-precision
//! integers: the last resort of [`super::predicates`] when the coordinates span too many
//! binary orders of magnitude for `robust`'s expansions, whose products would then
//! underflow (subnormal next to normal coordinates) or overflow (found by fuzzing the
//! Delaunay kernel). Slow, allocating, and only reached on such inputs.
//!
//! Every finite double is `m * 2^e` with an integer `m`; multiplying all coordinates by
//! `2^-e_min` (the smallest exponent among them) makes them integers exactly, and a
//! determinant of degree k is then the exact one times `2^(-k e_min)`: same sign.
//!
//! Private to `predicates`, the only door to exact arithmetic.

use glam::DVec3;
use num_bigint::{BigInt, Sign};

/// `x = m * 2^e` exactly (`m` an integer of at most 53 bits); zero gives `(0, 0)`.
fn decompose(x: f64) -> (i64, i32) {
    if x == 0.0 {
        return (0, 0);
    }
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp - 1075)
    };
    (if bits >> 63 == 1 { -m } else { m }, e)
}

/// The coordinates of finite points as integers over the common scale `2^-e_min`.
fn integers<const N: usize>(p: &[DVec3; N]) -> [[BigInt; 3]; N] {
    let parts: Vec<(i64, i32)> = p
        .iter()
        .flat_map(|v| [v.x, v.y, v.z])
        .map(decompose)
        .collect();
    let e_min = parts
        .iter()
        .filter(|(m, _)| *m != 0)
        .map(|&(_, e)| e)
        .min()
        .unwrap_or(0);
    let big = |(m, e): (i64, i32)| {
        if m == 0 {
            BigInt::from(0)
        } else {
            BigInt::from(m) << ((e - e_min) as usize)
        }
    };
    std::array::from_fn(|i| std::array::from_fn(|j| big(parts[3 * i + j])))
}

/// Sign of the orientation determinant `(b - a) . ((c - a) x (d - a))` (positive for a
/// positively oriented tet in this crate's convention); `None` for non-finite input.
pub(super) fn orient3d_sign(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Option<i32> {
    if ![a, b, c, d].iter().all(|p| p.is_finite()) {
        return None;
    }
    let [a, b, c, d] = integers(&[a, b, c, d]);
    let sub = |p: &[BigInt; 3]| -> [BigInt; 3] { std::array::from_fn(|i| &p[i] - &a[i]) };
    let (ba, ca, da) = (sub(&b), sub(&c), sub(&d));
    let m1 = &ca[1] * &da[2] - &ca[2] * &da[1];
    let m2 = &ca[2] * &da[0] - &ca[0] * &da[2];
    let m3 = &ca[0] * &da[1] - &ca[1] * &da[0];
    Some(signum(&(&ba[0] * m1 + &ba[1] * m2 + &ba[2] * m3)))
}

/// Sign of Shewchuk's insphere determinant (positive: `e` inside the sphere of a tet
/// positive in his convention, i.e. outside for this crate's positive tets), the same
/// expression as `robust::insphere`; `None` for non-finite input.
pub(super) fn insphere_sign(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Option<i32> {
    if ![a, b, c, d, e].iter().all(|p| p.is_finite()) {
        return None;
    }
    let [a, b, c, d, e] = integers(&[a, b, c, d, e]);
    let sub = |p: &[BigInt; 3]| -> [BigInt; 3] { std::array::from_fn(|i| &p[i] - &e[i]) };
    let (ae, be, ce, de) = (sub(&a), sub(&b), sub(&c), sub(&d));
    let cross = |p: &[BigInt; 3], q: &[BigInt; 3]| &p[0] * &q[1] - &q[0] * &p[1];
    let (ab, bc, cd, da) = (
        cross(&ae, &be),
        cross(&be, &ce),
        cross(&ce, &de),
        cross(&de, &ae),
    );
    let (ac, bd) = (cross(&ae, &ce), cross(&be, &de));
    let abc = &ae[2] * &bc - &be[2] * &ac + &ce[2] * &ab;
    let bcd = &be[2] * &cd - &ce[2] * &bd + &de[2] * &bc;
    let cda = &ce[2] * &da + &de[2] * &ac + &ae[2] * &cd;
    let dab = &de[2] * &ab + &ae[2] * &bd + &be[2] * &da;
    let lift = |p: &[BigInt; 3]| &p[0] * &p[0] + &p[1] * &p[1] + &p[2] * &p[2];
    let det = (lift(&de) * abc - lift(&ce) * dab) + (lift(&be) * cda - lift(&ae) * bcd);
    Some(signum(&det))
}

/// -1, 0 or 1.
fn signum(x: &BigInt) -> i32 {
    match x.sign() {
        Sign::Minus => -1,
        Sign::NoSign => 0,
        Sign::Plus => 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::predicates::{insphere_robust, orient3d_robust, Orientation, Sphere};

    fn lcg(s: &mut u64) -> f64 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    #[test]
    fn agrees_with_robust_where_robust_is_exact() {
        let mut s = 7u64;
        for k in 0..2000 {
            let mut p = || DVec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s));
            // Every other set nearly degenerate: a point snapped near the plane or sphere.
            let (a, b, c, d) = (p(), p(), p(), p());
            let e = if k % 2 == 0 { p() } else { (a + b) * 0.5 };
            let o = match orient3d_sign(a, b, c, d).unwrap() {
                1 => Orientation::Positive,
                -1 => Orientation::Negative,
                _ => Orientation::Zero,
            };
            assert_eq!(o, orient3d_robust(a, b, c, d));
            let sp = match insphere_sign(a, b, c, d, e).unwrap() {
                1 => Sphere::Outside,
                -1 => Sphere::Inside,
                _ => Sphere::On,
            };
            assert_eq!(sp, insphere_robust(a, b, c, d, e));
        }
    }

    #[test]
    fn subnormal_and_normal_coordinates_together() {
        let t = 5e-324;
        let (a, b, c) = (
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        );
        assert_eq!(orient3d_sign(a, b, c, DVec3::new(0.0, 0.0, t)), Some(1));
        assert_eq!(orient3d_sign(a, b, c, DVec3::new(0.0, 0.0, -t)), Some(-1));
        assert_eq!(
            orient3d_sign(a, b, c, DVec3::new(1e300, 1e300, 0.0)),
            Some(0)
        );
    }
}
