//! Normalised edge length with respect to a size map (paper §5.3.2) and edge quality
//! (paper §6.1).
//!
//! With `h` varying linearly from `h_a` to `h_b` along an edge of Euclidean length `d`,
//! `l = d * integral_0^1 dt / h(t) = d ln(h_b / h_a) / (h_b - h_a)`. When the two sizes are
//! close (`0.9 < h_a / h_b < 1.1`, the paper's band, [`NEAR_EQUAL_RATIO_LOW`] and
//! [`NEAR_EQUAL_RATIO_HIGH`]) the paper replaces it by `2 d / (h_a + h_b)`, which also
//! avoids the `0/0` of the log form at `h_a = h_b`. The two forms differ by less than
//! 0.1 % at the band's edges. When the edge crosses background tets, the formula is
//! summed over the pieces between consecutive crossing points.
//!
//! Sizes must be positive and finite; otherwise the result is NaN (never a panic).

use crate::geom::Point;

/// Lower end (exclusive) of the size-ratio band `h_a / h_b` in which the near-equal form
/// `2d / (h_a + h_b)` is used (paper §5.3.2).
pub const NEAR_EQUAL_RATIO_LOW: f64 = 0.9;
/// Upper end (exclusive) of the near-equal band (paper §5.3.2).
pub const NEAR_EQUAL_RATIO_HIGH: f64 = 1.1;

/// Normalised length of an edge of Euclidean length `d` whose end sizes are `h_a`, `h_b`
/// (size linear along the edge). Symmetric in `h_a`, `h_b`; `d / h` for a constant size.
/// NaN if a size is not positive and finite or `d` is NaN.
#[inline]
pub fn normalized_length(d: f64, h_a: f64, h_b: f64) -> f64 {
    let valid = |h: f64| h > 0.0 && h.is_finite();
    if !(valid(h_a) && valid(h_b)) {
        return f64::NAN;
    }
    let r = h_a / h_b;
    if r > NEAR_EQUAL_RATIO_LOW && r < NEAR_EQUAL_RATIO_HIGH {
        2.0 * d / (h_a + h_b)
    } else {
        d * (h_b / h_a).ln() / (h_b - h_a)
    }
}

/// Normalised length of the edge between the points `a` and `b` with sizes `h_a`, `h_b`.
#[inline]
pub fn normalized_length_points(a: Point, b: Point, h_a: f64, h_b: f64) -> f64 {
    normalized_length(a.distance(b), h_a, h_b)
}

/// Piecewise normalised length of an edge of Euclidean length `d`, given the size at a
/// sequence of parameters `(t, h)` along it, `t` in `[0, 1]` increasing from one end
/// (`t = 0`, included by the caller) to the other (`t = 1`, included): the sum of
/// [`normalized_length`] over consecutive pieces (paper §5.3.2). Fewer than two samples
/// give 0.
pub fn normalized_length_piecewise(d: f64, samples: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    let mut it = samples.into_iter();
    let Some((mut t0, mut h0)) = it.next() else {
        return 0.0;
    };
    let mut sum = 0.0;
    for (t1, h1) in it {
        sum += normalized_length((t1 - t0).abs() * d, h0, h1);
        (t0, h0) = (t1, h1);
    }
    sum
}

/// Piecewise normalised length along a polyline of `(point, size)` samples, e.g. an
/// edge's end points and its crossings with background faces, in order along the edge.
/// Fewer than two samples give 0.
pub fn normalized_length_polyline(samples: impl IntoIterator<Item = (Point, f64)>) -> f64 {
    let mut it = samples.into_iter();
    let Some((mut p0, mut h0)) = it.next() else {
        return 0.0;
    };
    let mut sum = 0.0;
    for (p1, h1) in it {
        sum += normalized_length(p0.distance(p1), h0, h1);
        (p0, h0) = (p1, h1);
    }
    sum
}

/// Edge quality (paper §6.1): `l` if `l <= 1`, else `1 / l`; in `[0, 1]`, 1 for a unit
/// edge. NaN stays NaN.
#[inline]
pub fn edge_quality(l: f64) -> f64 {
    if l <= 1.0 {
        l
    } else {
        1.0 / l
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The log form, without the band.
    fn log_form(d: f64, a: f64, b: f64) -> f64 {
        d * (b / a).ln() / (b - a)
    }

    #[test]
    fn constant_size_gives_d_over_h() {
        assert_eq!(normalized_length(3.0, 1.5, 1.5), 2.0);
        assert!((normalized_length(0.7, 0.2, 0.2) - 3.5).abs() < 1e-15);
    }

    #[test]
    fn log_and_near_equal_forms_agree_near_equal_sizes() {
        for &r in &[0.95, 0.99, 0.999, 1.001, 1.01, 1.05] {
            let (d, a) = (2.0, 0.5);
            let b = a / r;
            let exact = log_form(d, a, b);
            let near = normalized_length(d, a, b);
            // Second-order agreement: relative error ~ (1 - r)^2 / 12.
            let bound = (1.0 - r).powi(2) / 10.0 + 1e-12;
            assert!(((exact - near) / exact).abs() < bound, "r={r}");
        }
    }

    #[test]
    fn continuity_across_the_band_edges() {
        for edge in [NEAR_EQUAL_RATIO_LOW, NEAR_EQUAL_RATIO_HIGH] {
            let below = normalized_length(1.0, edge * (1.0 - 1e-12), 1.0);
            let above = normalized_length(1.0, edge * (1.0 + 1e-12), 1.0);
            assert!(((below - above) / below).abs() < 1e-3, "{below} {above}");
        }
        // Inside the band and outside, small steps in h give small steps in l.
        let mut prev = normalized_length(1.0, 0.5, 1.0);
        for i in 1..=2000 {
            let h = 0.5 + i as f64 * 1e-3;
            let l = normalized_length(1.0, h, 1.0);
            assert!((l - prev).abs() < 2e-3, "h={h}");
            prev = l;
        }
    }

    #[test]
    fn symmetric_and_between_the_end_values() {
        let l = normalized_length(1.0, 0.1, 2.0);
        assert!((l - normalized_length(1.0, 2.0, 0.1)).abs() < 1e-15);
        assert!(l < 1.0 / 0.1 && l > 1.0 / 2.0);
    }

    #[test]
    fn invalid_sizes_give_nan() {
        assert!(normalized_length(1.0, 0.0, 1.0).is_nan());
        assert!(normalized_length(1.0, -1.0, 1.0).is_nan());
        assert!(normalized_length(1.0, f64::NAN, 1.0).is_nan());
        assert!(normalized_length(1.0, 1.0, f64::INFINITY).is_nan());
        assert_eq!(normalized_length(0.0, 1.0, 3.0), 0.0);
    }

    #[test]
    fn piecewise_one_piece_equals_direct() {
        let direct = normalized_length(2.5, 0.3, 1.7);
        let pw = normalized_length_piecewise(2.5, [(0.0, 0.3), (1.0, 1.7)]);
        assert_eq!(direct, pw);
        let (a, b) = (Point::new(1.0, 2.0, 3.0), Point::new(-1.0, 0.5, 2.0));
        let poly = normalized_length_polyline([(a, 0.3), (b, 1.7)]);
        assert!((poly - normalized_length_points(a, b, 0.3, 1.7)).abs() < 1e-15);
        assert_eq!(normalized_length_piecewise(1.0, []), 0.0);
        assert_eq!(normalized_length_polyline([(a, 1.0)]), 0.0);
    }

    #[test]
    fn piecewise_of_linear_size_matches_single_piece() {
        // Splitting an edge at points where the linear size is sampled exactly gives
        // the same integral (up to the near-equal approximation, off here: big ratios).
        let (d, ha, hb) = (3.0, 0.1, 10.0);
        let h = |t: f64| ha + (hb - ha) * t;
        let direct = normalized_length(d, ha, hb);
        let ts = [0.0, 0.05, 0.3, 1.0];
        let pw = normalized_length_piecewise(d, ts.iter().map(|&t| (t, h(t))));
        assert!(((pw - direct) / direct).abs() < 1e-12, "{pw} {direct}");
    }

    #[test]
    fn edge_quality_folds_at_one() {
        assert_eq!(edge_quality(0.5), 0.5);
        assert_eq!(edge_quality(1.0), 1.0);
        assert_eq!(edge_quality(4.0), 0.25);
        assert!(edge_quality(f64::NAN).is_nan());
    }
}
