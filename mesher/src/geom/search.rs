//! Derivative-free searches for a lower value of an inexact objective over a point
//! (the optimiser's vertex and cone positions, paper §6.3; the in-domain `Q_t`'s apex
//! search, `quality::room`).

use super::Point;

/// Halvings of the compass search's step.
const COMPASS_HALVINGS: usize = 12;

/// A compass search from `p` (value `value`) for a lower `score`: steps of `step` along
/// each axis, both ways, taken while they improve, then halved, [`COMPASS_HALVINGS`]
/// times. `score` may return any value at or above its current best when a point is no
/// better (an early exit). Returns the best value and point.
pub(crate) fn compass(
    score: impl Fn(Point) -> f64,
    p: Point,
    value: f64,
    step: f64,
) -> (f64, Point) {
    compass_below(|q, _| score(q), p, value, step)
}

/// [`compass`] with a `score` told the value to beat: it may stop and return any value
/// at or above it as soon as it knows the point is no better (the search takes only
/// lower values, so its path is the same as with a full evaluation).
pub(crate) fn compass_below(
    score: impl Fn(Point, f64) -> f64,
    mut p: Point,
    mut value: f64,
    mut step: f64,
) -> (f64, Point) {
    let dirs = [
        Point::X,
        -Point::X,
        Point::Y,
        -Point::Y,
        Point::Z,
        -Point::Z,
    ];
    for _ in 0..COMPASS_HALVINGS {
        // At most a few moves per step length: the search is a last resort, kept cheap.
        for _ in 0..4 {
            let mut moved = false;
            for d in dirs {
                let q = p + d * step;
                let s = score(q, value);
                if s < value {
                    (value, p, moved) = (s, q, true);
                }
            }
            if !moved {
                break;
            }
        }
        step *= 0.5;
    }
    (value, p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A score that stops once a point is no better than the value to beat takes the
    /// search along the same path, to the same point and value.
    #[test]
    fn a_score_told_the_value_to_beat_takes_the_same_path() {
        let terms = [(0.3, -0.2, 0.1), (-0.4, 0.5, 0.2), (0.1, 0.1, -0.6)];
        let term = |p: Point, (x, y, z): (f64, f64, f64)| p.distance(Point::new(x, y, z));
        let full = |p: Point| terms.iter().map(|&c| term(p, c)).fold(0.0, f64::max);
        let bounded = |p: Point, beat: f64| {
            let mut m: f64 = 0.0;
            for &c in &terms {
                m = m.max(term(p, c));
                if m >= beat {
                    break;
                }
            }
            m
        };
        let start = Point::new(1.0, 1.0, 1.0);
        let a = compass(full, start, full(start), 0.25);
        let b = compass_below(bounded, start, full(start), 0.25);
        assert_eq!((a.0.to_bits(), a.1), (b.0.to_bits(), b.1));
        assert!(a.0 < full(start));
    }
}
