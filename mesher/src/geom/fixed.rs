//! Exact signs of the orientation and insphere determinants in fixed-point integer
//! arithmetic: the intermediate stage of [`super::predicates`] between the floating-point
//! filters and Shewchuk's adaptive expansions (`robust`).
//!
//! A finite double is `m * 2^e` with an odd integer `m` of at most 53 bits. When the
//! values a determinant is built from (the coordinate differences, or failing that the
//! coordinates) all become integers of at most [`BITS`] bits once multiplied by the same
//! power of two `2^s`, the determinant of those integers is the exact determinant times
//! `2^(k s)` (k = 3 or 5, a positive factor), so its sign is the exact sign.
//! Integers of 62 bits keep every intermediate product within a few 64-bit limbs:
//! 2x2 minors fit in `i128`, 3x3 minors in 192 bits and the insphere determinant in 320.
//!
//! Points that are close to each other (the near-degenerate calls of a Delaunay kernel:
//! nearly cospherical or coplanar neighbours) have exact floating-point differences
//! whose bits span far fewer than 62 positions, so this stage decides them at the cost
//! of a few dozen integer multiplications, with no allocation and no zeroed buffers.
//! Inputs it cannot represent (exponents too spread, NaN, infinities) return `None` and
//! the caller uses `robust`.
//!
//! This module is private to `predicates`, the only door to exact arithmetic.

use glam::DVec3;

/// Largest magnitude, in bits, of a scaled input: every scaled value is `< 2^BITS`.
const BITS: u32 = 62;
/// Coordinates are subtracted after scaling, so they get one bit less.
const COORD_BITS: u32 = BITS - 1;

/// `2^k` for `-1022 <= k <= 1023`.
#[inline(always)]
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// The values scaled by a common power of two to integers of fewer than `bits` bits
/// (magnitude `< 2^bits`), or `None` when some value is not finite or the bits of the
/// values span more than `bits` positions.
///
/// The scale puts the largest magnitude in `[2^(bits-1), 2^bits)`; the scaled values are
/// then integers exactly when no bit of any value lies below the scale's unit. Scaling
/// up is exact; scaling down can only round values that become subnormal (below 1, so
/// not integers) or zero, hence the check that non-zero values stay non-zero.
#[inline]
fn to_fixed<const N: usize>(v: [f64; N], bits: u32) -> Option<[i64; N]> {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == f64::INFINITY || v.iter().any(|x| x.is_nan()) {
        return None;
    }
    if m == 0.0 {
        return Some([0; N]);
    }
    // m < 2^top, with top - 1 <= log2(m).
    let b = m.to_bits();
    let biased = (b >> 52) as i32;
    let top = if biased == 0 {
        -1010 - b.leading_zeros() as i32
    } else {
        biased - 1022
    };
    let k = bits as i32 - top;
    let scale = |x: f64| {
        if k > 1023 {
            x * pow2(1023) * pow2(k - 1023)
        } else {
            x * pow2(k)
        }
    };
    let mut out = [0i64; N];
    for i in 0..N {
        let y = scale(v[i]);
        if y != y.trunc() || (y == 0.0 && v[i] != 0.0) {
            return None;
        }
        out[i] = y as i64;
    }
    Some(out)
}

/// `a - b` when it is exact in floating point (Knuth's two-difference with a zero tail).
#[inline]
fn exact_diff(a: f64, b: f64) -> Option<f64> {
    let x = a - b;
    let bvirt = a - x;
    let avirt = x + bvirt;
    let bround = bvirt - b;
    let around = a - avirt;
    (around + bround == 0.0 && x.is_finite()).then_some(x)
}

/// The 3 * K coordinates of `p - o` for each `p` in `pts`, as integers of fewer than
/// [`BITS`] bits sharing one scale: from the floating-point differences when they are
/// exact, else from the coordinates themselves, subtracted in integers.
#[inline]
fn scaled_diffs<const K: usize, const N: usize>(o: DVec3, pts: [DVec3; K]) -> Option<[i64; N]> {
    debug_assert_eq!(N, 3 * K);
    let mut d = [0.0; N];
    let mut exact = true;
    'all: for (k, p) in pts.iter().enumerate() {
        for j in 0..3 {
            match exact_diff(p[j], o[j]) {
                Some(x) => d[3 * k + j] = x,
                None => {
                    exact = false;
                    break 'all;
                }
            }
        }
    }
    if exact {
        if let Some(f) = to_fixed(d, BITS) {
            return Some(f);
        }
    }
    // The coordinates themselves: one value per coordinate plus the origin's three.
    let mut c = [[0.0; 3]; 5];
    c[0] = o.to_array();
    for (k, p) in pts.iter().enumerate() {
        c[k + 1] = p.to_array();
    }
    let flat: [f64; 15] = std::array::from_fn(|i| if i / 3 <= K { c[i / 3][i % 3] } else { 0.0 });
    let f = to_fixed(flat, COORD_BITS)?;
    Some(std::array::from_fn(|i| f[3 + i] - f[i % 3]))
}

/// An unsigned integer of `L` 64-bit limbs, least significant first.
type Mag<const L: usize> = [u64; L];

/// `a * b` for magnitudes whose product fits in `L` limbs.
#[inline(always)]
fn mul<const A: usize, const B: usize, const L: usize>(a: &Mag<A>, b: &Mag<B>) -> Mag<L> {
    let mut r = [0u64; L];
    for i in 0..A {
        let mut carry = 0u128;
        for j in 0..B {
            if i + j >= L {
                debug_assert!(a[i] == 0 || b[j] == 0);
                continue;
            }
            let t = a[i] as u128 * b[j] as u128 + r[i + j] as u128 + carry;
            r[i + j] = t as u64;
            carry = t >> 64;
        }
        if i + B < L {
            r[i + B] = carry as u64;
        } else {
            debug_assert_eq!(carry, 0);
        }
    }
    r
}

/// `a + b`, which must not overflow.
#[inline(always)]
fn add<const L: usize>(a: &Mag<L>, b: &Mag<L>) -> Mag<L> {
    let mut r = [0u64; L];
    let mut carry = false;
    for i in 0..L {
        let (s1, c1) = a[i].overflowing_add(b[i]);
        let (s2, c2) = s1.overflowing_add(carry as u64);
        r[i] = s2;
        carry = c1 || c2;
    }
    debug_assert!(!carry);
    r
}

/// `a - b` for `a >= b`.
#[inline(always)]
fn sub<const L: usize>(a: &Mag<L>, b: &Mag<L>) -> Mag<L> {
    let mut r = [0u64; L];
    let mut borrow = false;
    for i in 0..L {
        let (s1, b1) = a[i].overflowing_sub(b[i]);
        let (s2, b2) = s1.overflowing_sub(borrow as u64);
        r[i] = s2;
        borrow = b1 || b2;
    }
    debug_assert!(!borrow);
    r
}

/// Compares magnitudes.
#[inline(always)]
fn cmp<const L: usize>(a: &Mag<L>, b: &Mag<L>) -> std::cmp::Ordering {
    for i in (0..L).rev() {
        match a[i].cmp(&b[i]) {
            std::cmp::Ordering::Equal => {}
            o => return o,
        }
    }
    std::cmp::Ordering::Equal
}

/// A signed integer accumulated as the difference of two magnitudes.
#[derive(Clone, Copy)]
struct Acc<const L: usize> {
    pos: Mag<L>,
    neg: Mag<L>,
}

impl<const L: usize> Acc<L> {
    fn new() -> Self {
        Acc {
            pos: [0; L],
            neg: [0; L],
        }
    }

    #[inline(always)]
    fn push(&mut self, negative: bool, m: &Mag<L>) {
        if negative {
            self.neg = add(&self.neg, m);
        } else {
            self.pos = add(&self.pos, m);
        }
    }

    /// The value as (negative, magnitude).
    #[inline(always)]
    fn signed(&self) -> (bool, Mag<L>) {
        if cmp(&self.pos, &self.neg) == std::cmp::Ordering::Less {
            (true, sub(&self.neg, &self.pos))
        } else {
            (false, sub(&self.pos, &self.neg))
        }
    }

    #[inline(always)]
    fn sign(&self) -> i32 {
        match cmp(&self.pos, &self.neg) {
            std::cmp::Ordering::Less => -1,
            std::cmp::Ordering::Equal => 0,
            std::cmp::Ordering::Greater => 1,
        }
    }
}

#[inline(always)]
fn mag1(x: i64) -> Mag<1> {
    [x.unsigned_abs()]
}

#[inline(always)]
fn mag2(x: u128) -> Mag<2> {
    [x as u64, (x >> 64) as u64]
}

/// The 2x2 minor `p0 q1 - q0 p1` (`< 2^125` in magnitude for inputs `< 2^62`).
#[inline(always)]
fn minor2(p0: i64, p1: i64, q0: i64, q1: i64) -> i128 {
    p0 as i128 * q1 as i128 - q0 as i128 * p1 as i128
}

/// `sum_k s_k z_k m_k` for three signed 62-bit `z` and 125-bit `m`: a 3x3 minor,
/// `< 2^189` in magnitude, as (negative, magnitude).
#[inline(always)]
fn minor3(terms: [(i64, i128); 3]) -> (bool, Mag<3>) {
    let mut acc = Acc::<3>::new();
    for (z, m) in terms {
        let p: Mag<3> = mul(&mag1(z), &mag2(m.unsigned_abs()));
        acc.push((z < 0) != (m < 0), &p);
    }
    acc.signed()
}

/// Exact sign of `det[b-a, c-a, d-a]` (the sign of [`super::orient3d`]): 1, 0 or -1,
/// or `None` when the inputs are out of this stage's range.
#[inline]
pub(super) fn orient3d_sign(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Option<i32> {
    let v: [i64; 9] = scaled_diffs(a, [b, c, d])?;
    let (b, c, d) = (&v[0..3], &v[3..6], &v[6..9]);
    let m1 = minor2(c[1], c[2], d[1], d[2]);
    let m2 = minor2(c[2], c[0], d[2], d[0]);
    let m3 = minor2(c[0], c[1], d[0], d[1]);
    let (neg, mag) = minor3([(b[0], m1), (b[1], m2), (b[2], m3)]);
    Some(if mag == [0; 3] {
        0
    } else if neg {
        -1
    } else {
        1
    })
}

/// Exact sign of Shewchuk's insphere determinant of `(a, b, c, d, e)` (the sign of
/// `robust::insphere`: positive when `e` is outside the sphere of a tetrahedron that is
/// positive in our convention): 1, 0 or -1, or `None` when the inputs are out of this
/// stage's range.
#[inline]
pub(super) fn insphere_sign(a: DVec3, b: DVec3, c: DVec3, d: DVec3, e: DVec3) -> Option<i32> {
    let v: [i64; 12] = scaled_diffs(e, [a, b, c, d])?;
    let p = |k: usize| [v[3 * k], v[3 * k + 1], v[3 * k + 2]];
    let (ae, be, ce, de) = (p(0), p(1), p(2), p(3));
    // The same expression as the floating-point filter, in integers.
    let ab = minor2(ae[0], ae[1], be[0], be[1]);
    let bc = minor2(be[0], be[1], ce[0], ce[1]);
    let cd = minor2(ce[0], ce[1], de[0], de[1]);
    let da = minor2(de[0], de[1], ae[0], ae[1]);
    let ac = minor2(ae[0], ae[1], ce[0], ce[1]);
    let bd = minor2(be[0], be[1], de[0], de[1]);
    let abc = minor3([(ae[2], bc), (-be[2], ac), (ce[2], ab)]);
    let bcd = minor3([(be[2], cd), (-ce[2], bd), (de[2], bc)]);
    let cda = minor3([(ce[2], da), (de[2], ac), (ae[2], cd)]);
    let dab = minor3([(de[2], ab), (ae[2], bd), (be[2], da)]);
    let lift = |q: [i64; 3]| -> Mag<2> {
        // Each square is < 2^124, the sum < 2^126.
        let s = q.iter().map(|&x| x as i128 * x as i128).sum::<i128>();
        mag2(s as u128)
    };
    // det = (dlift abc - clift dab) + (blift cda - alift bcd); each product < 2^315.
    let mut acc = Acc::<5>::new();
    for (l, (neg, m3), minus) in [
        (lift(de), abc, false),
        (lift(ce), dab, true),
        (lift(be), cda, false),
        (lift(ae), bcd, true),
    ] {
        let prod: Mag<5> = mul(&l, &m3);
        acc.push(neg != minus, &prod);
    }
    Some(acc.sign())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `x = m * 2^e` with `m` odd (or `(0, i32::MAX)` for zero). `x` must be finite.
    #[inline]
    fn decompose(x: f64) -> (i64, i32) {
        if x == 0.0 {
            return (0, i32::MAX);
        }
        let bits = x.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i32;
        let frac = bits & ((1u64 << 52) - 1);
        let (mant, e) = if biased == 0 {
            (frac, -1074)
        } else {
            (frac | (1u64 << 52), biased - 1075)
        };
        let tz = mant.trailing_zeros();
        let m = (mant >> tz) as i64;
        (if x < 0.0 { -m } else { m }, e + tz as i32)
    }

    /// The values scaled by a common power of two to integers of fewer than `bits` bits
    /// (magnitude `< 2^bits`), or `None` when some value is not finite or the bits of the
    /// values span more than `bits` positions.
    fn to_fixed_reference<const N: usize>(v: [f64; N], bits: u32) -> Option<[i64; N]> {
        let mut m = [0i64; N];
        let mut e = [i32::MAX; N];
        let mut emin = i32::MAX;
        for i in 0..N {
            if !v[i].is_finite() {
                return None;
            }
            (m[i], e[i]) = decompose(v[i]);
            emin = emin.min(e[i]);
        }
        for i in 0..N {
            if m[i] == 0 {
                continue;
            }
            let shift = (e[i] - emin) as u32;
            let len = 64 - m[i].unsigned_abs().leading_zeros();
            if shift >= bits || shift + len > bits {
                return None;
            }
            m[i] <<= shift;
        }
        Some(m)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(5000))]
        /// The floating-point scaling agrees with the bit-level reference.
        #[test]
        fn to_fixed_matches_reference(
            m in proptest::array::uniform6(proptest::prelude::any::<i64>()),
            e in proptest::array::uniform6(-80i32..80),
            base in proptest::prop_oneof![
                proptest::strategy::Just(0i32), -1100i32..1000, proptest::strategy::Just(-1074)
            ],
            zero in proptest::array::uniform6(0u8..5),
        ) {
            let v: [f64; 6] = std::array::from_fn(|i| {
                if zero[i] == 0 {
                    0.0
                } else {
                    // A 1..53-bit mantissa at exponent base + e.
                    let bits = (m[i] as u64 >> 11) >> (m[i] as u64 % 53);
                    let x = ldexp(bits as f64, base + e[i]);
                    if m[i] < 0 { -x } else { x }
                }
            });
            for bits in [BITS, COORD_BITS] {
                let (a, r) = (to_fixed(v, bits), to_fixed_reference(v, bits));
                proptest::prop_assert_eq!(a.is_some(), r.is_some());
                if let (Some(a), Some(r)) = (a, r) {
                    // The same values up to the common power of two, the largest in
                    // [2^(bits-1), 2^bits).
                    let j = (0..6).max_by_key(|&i| r[i].unsigned_abs()).unwrap();
                    for i in 0..6 {
                        proptest::prop_assert_eq!(
                            a[i] as i128 * r[j] as i128,
                            a[j] as i128 * r[i] as i128
                        );
                    }
                    if r[j] != 0 {
                        proptest::prop_assert!(a[j].unsigned_abs() >> (bits - 1) == 1);
                    }
                }
            }
        }
    }

    #[test]
    fn decompose_round_trips() {
        for x in [
            1.0,
            -1.0,
            0.75,
            3.0e-310,
            -f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            1e150,
            -1e-150,
            0.1,
        ] {
            let (m, e) = decompose(x);
            assert!(m % 2 != 0, "{x}");
            // m * 2^e, computed in two steps to stay in range.
            let h = e / 2;
            let y = m as f64 * 2f64.powi(h) * 2f64.powi(e - h);
            assert_eq!(x, y, "{x}");
        }
    }

    #[test]
    fn to_fixed_rejects_spread_and_non_finite() {
        assert_eq!(to_fixed([1.0, 0.5, 0.0], BITS), Some([1 << 61, 1 << 60, 0]));
        assert_eq!(to_fixed([1.0, 2f64.powi(-61)], BITS), Some([1 << 61, 1]));
        assert_eq!(to_fixed([1.0, 2f64.powi(-62)], BITS), None);
        assert_eq!(to_fixed([-0.75, 5e-324], BITS), None);
        assert_eq!(
            to_fixed([5e-324, -1e-323], BITS),
            Some([1 << 60, -(1 << 61)])
        );
        assert_eq!(
            to_fixed([f64::MAX, 0.0], BITS),
            Some([((1 << 53) - 1) << 9, 0])
        );
        assert_eq!(to_fixed([f64::INFINITY, 0.0], BITS), None);
        assert_eq!(to_fixed([1.0, f64::NAN], BITS), None);
        assert_eq!(to_fixed([0.0, -0.0], BITS), Some([0, 0]));
    }

    #[test]
    fn multiplication_matches_u128() {
        let a = [u64::MAX];
        let b = [u64::MAX, 0];
        let r: Mag<3> = mul(&a, &b);
        let x = u64::MAX as u128 * u64::MAX as u128;
        assert_eq!(r, [x as u64, (x >> 64) as u64, 0]);
        let big: Mag<4> = mul(&[u64::MAX, u64::MAX], &[u64::MAX, u64::MAX]);
        // (2^128 - 1)^2 = 2^256 - 2^129 + 1
        assert_eq!(big, [1, 0, u64::MAX - 1, u64::MAX]);
    }

    #[test]
    fn neighbours_on_a_sphere_take_the_fixed_stage() {
        // Five nearby points of the unit sphere, rounded: the filter cannot decide, and
        // neither the differences nor the determinant need `robust`.
        let p = [
            (0.6, 0.8, 0.0),
            (0.61, 0.79, 0.05),
            (0.59, 0.8, 0.04),
            (0.62, 0.77, -0.03),
            (0.6, 0.78, 0.02),
        ]
        .map(|(x, y, z)| DVec3::new(x, y, z).normalize());
        assert!(insphere_sign(p[0], p[1], p[2], p[3], p[4]).is_some());
        assert!(orient3d_sign(p[0], p[1], p[2], p[3]).is_some());
        // Exactly cospherical integers: a zero determinant.
        let q = [
            (3, 4, 12),
            (4, 3, 12),
            (-3, 4, 12),
            (12, 4, 3),
            (3, -4, -12),
        ]
        .map(|(x, y, z)| DVec3::new(x as f64, y as f64, z as f64));
        assert_eq!(insphere_sign(q[0], q[1], q[2], q[3], q[4]), Some(0));
    }

    // Property tests: every fast path against `robust` on adversarial inputs.
    //
    // The reference is `robust` on the input scaled by a power of two that brings its
    // largest coordinate near 1, whenever that scaling is exact: the sign of the
    // determinant is unchanged, and `robust` (like any floating-point expansion method)
    // is only exact when its products neither overflow nor underflow, which fails for
    // degree-5 products of coordinates near 1e150 or 1e-150 without the rescaling.
    use super::super::{
        insphere, insphere_exact, orient3d, orient3d_exact, Orientation, Sphere, StaticFilter,
    };
    use proptest::prelude::*;

    /// `x * 2^k`, exact when the result is normal (or `x` subnormal and `k >= 0`).
    fn ldexp(mut x: f64, mut k: i32) -> f64 {
        while k != 0 {
            let step = k.clamp(-1000, 1000);
            x *= 2f64.powi(step);
            k -= step;
        }
        x
    }

    /// The points scaled by a power of two so that the largest coordinate is in
    /// [0.5, 1), when that is exact; else the points unchanged.
    fn normalised<const N: usize>(p: [DVec3; N]) -> [DVec3; N] {
        let m = p.iter().map(|q| q.abs().max_element()).fold(0.0, f64::max);
        if m == 0.0 || !m.is_finite() {
            return p;
        }
        let (_, e) = decompose(m);
        let top = e + (64 - decompose(m).0.unsigned_abs().leading_zeros()) as i32;
        let q = p.map(|v| DVec3::new(ldexp(v.x, -top), ldexp(v.y, -top), ldexp(v.z, -top)));
        let back = q.map(|v| DVec3::new(ldexp(v.x, top), ldexp(v.y, top), ldexp(v.z, top)));
        if back == p {
            q
        } else {
            p
        }
    }

    fn c3(p: DVec3) -> robust::Coord3D<f64> {
        robust::Coord3D {
            x: p.x,
            y: p.y,
            z: p.z,
        }
    }

    fn ref_insphere(p: [DVec3; 5]) -> Sphere {
        let q = normalised(p);
        let v = robust::insphere(c3(q[0]), c3(q[1]), c3(q[2]), c3(q[3]), c3(q[4]));
        super::super::sphere_from_shewchuk(v)
    }

    fn ref_orient3d(p: [DVec3; 4]) -> Orientation {
        let q = normalised(p);
        let v = -robust::orient3d(c3(q[0]), c3(q[1]), c3(q[2]), c3(q[3]));
        Orientation::from_f64(v)
    }

    /// Checks every path on the five points (and the four-point subsets for orient3d).
    fn check(p: [DVec3; 5]) -> Result<(), TestCaseError> {
        let r = ref_insphere(p);
        prop_assert_eq!(insphere_exact(p[0], p[1], p[2], p[3], p[4]), r);
        prop_assert_eq!(insphere(p[0], p[1], p[2], p[3], p[4]), r);
        if let Some(s) = insphere_sign(p[0], p[1], p[2], p[3], p[4]) {
            prop_assert_eq!(super::super::sphere_from_shewchuk(s as f64), r);
        }
        let lo = p.iter().fold(DVec3::INFINITY, |m, q| m.min(*q));
        let hi = p.iter().fold(DVec3::NEG_INFINITY, |m, q| m.max(*q));
        let f = StaticFilter::new(lo, hi);
        for skip in 0..5 {
            let mut q = [DVec3::ZERO; 4];
            let mut k = 0;
            for (i, x) in p.iter().enumerate() {
                if i != skip {
                    q[k] = *x;
                    k += 1;
                }
            }
            let r = ref_orient3d(q);
            prop_assert_eq!(orient3d_exact(q[0], q[1], q[2], q[3]), r);
            prop_assert_eq!(orient3d(q[0], q[1], q[2], q[3]), r);
            prop_assert_eq!(f.orient3d(q[0], q[1], q[2], q[3]), r);
            if let Some(s) = orient3d_sign(q[0], q[1], q[2], q[3]) {
                prop_assert_eq!(Orientation::from_f64(s as f64), r);
            }
        }
        Ok(())
    }

    /// A Pythagorean quadruple `(x, y, z)` with `x^2 + y^2 + z^2 = d^2`.
    fn quadruple(m: i64, n: i64, p: i64, q: i64) -> [i64; 3] {
        [
            m * m + n * n - p * p - q * q,
            2 * (m * q + n * p),
            2 * (n * q - m * p),
        ]
    }

    /// A signed permutation of `v` (48 of them, all on the same sphere).
    fn signed_perm(v: [i64; 3], k: u8) -> [i64; 3] {
        const P: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let p = P[(k % 6) as usize];
        let s = k / 6;
        std::array::from_fn(|i| if s >> i & 1 == 1 { -v[p[i]] } else { v[p[i]] })
    }

    fn pt(v: [i64; 3], centre: [i64; 3], scale: f64) -> DVec3 {
        DVec3::new(
            (v[0] + centre[0]) as f64 * scale,
            (v[1] + centre[1]) as f64 * scale,
            (v[2] + centre[2]) as f64 * scale,
        )
    }

    /// `x` moved by `k` units in the last place.
    fn ulps(x: f64, k: i64) -> f64 {
        let mut y = x;
        for _ in 0..k.unsigned_abs() {
            y = if k > 0 { y.next_up() } else { y.next_down() };
        }
        y
    }

    fn scale() -> impl Strategy<Value = f64> {
        prop_oneof![
            Just(1.0),
            (-1074i32..1000).prop_map(|k| ldexp(1.0, k)),
            Just(1e-150),
            Just(1e150),
            Just(0.1),
            Just(3.7e-300),
        ]
    }

    fn unit() -> impl Strategy<Value = DVec3> {
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
            .prop_filter("non-zero", |(x, y, z)| x * x + y * y + z * z > 1e-6)
            .prop_map(|(x, y, z)| DVec3::new(x, y, z).normalize())
    }

    /// A coordinate with a random mantissa and an exponent near `base`.
    fn spread_coord(base: i32) -> impl Strategy<Value = f64> {
        (any::<bool>(), 1u64..(1 << 53), 0i32..90).prop_map(move |(neg, m, de)| {
            let x = ldexp(m as f64, base + de - 53);
            if neg {
                -x
            } else {
                x
            }
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        /// Exactly cospherical integer points (signed permutations of Pythagorean
        /// quadruples, so every insphere is exactly zero before scaling), translated
        /// and scaled, including by powers of two into subnormals and near overflow.
        #[test]
        fn cospherical_integer_points(
            mnpq in (-12i64..12, -12i64..12, -12i64..12, -12i64..12),
            perms in prop::array::uniform5(0u8..48),
            centre in prop::array::uniform3(-1000i64..1000),
            s in scale(),
        ) {
            let v = quadruple(mnpq.0, mnpq.1, mnpq.2, mnpq.3);
            let p = perms.map(|k| pt(signed_perm(v, k), centre, s));
            check(p)?;
        }

        /// Points on a sphere rounded to doubles, then moved by up to 2 ulps per
        /// coordinate: nearly cospherical, like the geodesic sphere's vertices.
        #[test]
        fn sphere_points_perturbed_by_ulps(
            dirs in prop::array::uniform5(unit()),
            nudges in prop::array::uniform5(prop::array::uniform3(-2i64..=2)),
            centre in prop::array::uniform3(-4.0f64..4.0),
            radius in prop_oneof![Just(1.0), 1e-3f64..1e3],
            s in scale(),
        ) {
            let c = DVec3::from_array(centre);
            let p: [DVec3; 5] = std::array::from_fn(|i| {
                let q = (c + dirs[i] * radius) * s;
                DVec3::new(
                    ulps(q.x, nudges[i][0]),
                    ulps(q.y, nudges[i][1]),
                    ulps(q.z, nudges[i][2]),
                )
            });
            check(p)?;
        }

        /// Close neighbours on a small cap of a sphere (the kernel's cavities), with
        /// the exact tie of the unperturbed points half of the time.
        #[test]
        fn sphere_cap_neighbours(
            dirs in prop::array::uniform5((-1.0f64..1.0, -1.0f64..1.0)),
            nudge in prop::array::uniform5(prop::array::uniform3(-1i64..=1)),
            width in prop_oneof![Just(0.03), Just(1e-6), 1e-9f64..0.5],
            at in unit(),
            s in scale(),
        ) {
            let t1 = at.any_orthonormal_vector();
            let t2 = at.cross(t1);
            let p: [DVec3; 5] = std::array::from_fn(|i| {
                let (u, v) = dirs[i];
                let q = (at + (t1 * u + t2 * v) * width).normalize() * s;
                DVec3::new(ulps(q.x, nudge[i][0]), ulps(q.y, nudge[i][1]), ulps(q.z, nudge[i][2]))
            });
            check(p)?;
        }

        /// Coordinates whose exponents span up to 90 binades around a base anywhere in
        /// the double range: some within the fixed-point stage's reach, some not.
        #[test]
        fn coordinates_spanning_exponents(
            base in prop_oneof![Just(0i32), -1000i32..900, Just(-1020), Just(900)],
            c in prop::array::uniform5(prop::array::uniform3(spread_coord(0))),
        ) {
            let p = c.map(|q| DVec3::new(ldexp(q[0], base), ldexp(q[1], base), ldexp(q[2], base)));
            check(p)?;
        }

        /// Subnormal coordinates: small integer multiples of the smallest double, near
        /// cospherical and near coplanar configurations included.
        #[test]
        fn subnormal_coordinates(
            c in prop::array::uniform5(prop::array::uniform3(-(1i64 << 20)..(1 << 20))),
            flat in any::<bool>(),
        ) {
            let mut p = c.map(|q| pt(q, [0; 3], f64::from_bits(1)));
            if flat {
                // Five coplanar points: z = 0.
                for q in &mut p {
                    q.z = 0.0;
                }
            }
            check(p)?;
        }

        /// Cube corners and nearby lattice points at tiny and huge scales (1e-150,
        /// 1e150): exact ties and near ties far from 1.
        #[test]
        fn tiny_and_huge_lattices(
            c in prop::array::uniform5(prop::array::uniform3(0i64..3)),
            scale in prop_oneof![Just(1e-150), Just(1e150), Just(1e-300), Just(1e300), Just(7e-310)],
            shift in prop_oneof![Just(0.0), Just(1.0), Just(-0.5)],
        ) {
            let p = c.map(|q| {
                DVec3::new(q[0] as f64 + shift, q[1] as f64, q[2] as f64 - shift) * scale
            });
            check(p)?;
        }
    }
}
