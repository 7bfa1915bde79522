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
                let s = score(q);
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
