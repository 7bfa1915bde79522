//! The optimal point of a front face (paper §5.3.3): the apex of the ideal tetrahedron
//! built on the face in the control space.
//!
//! Start at the centroid plus `n * hbar * sqrt(2/3)` (the height of the regular tet of
//! edge `hbar`, the mean size at the face's vertices), `n` the unit normal towards the
//! unacceptable tet. Then relax: on each line `XP` (`X` a face vertex) take the point
//! `P_X = X + (P - X) / l(XP)` at unit normalised length from `X`, and move `P` by
//! `alpha` towards the mean of the `P_X`; at most `steps` times (NOTES.md §6).

use crate::geom::Point;
use crate::sizing::{edge_length, LengthMode, SizeField};

/// Parameters of the optimal point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointParams {
    /// Relaxation factor (paper: 0.1).
    pub alpha: f64,
    /// Relaxation steps (paper: at most 5).
    pub steps: usize,
    /// How normalised lengths are computed.
    pub mode: LengthMode,
}

impl Default for PointParams {
    fn default() -> Self {
        PointParams {
            alpha: 0.1,
            steps: 5,
            mode: LengthMode::EndPoints,
        }
    }
}

/// The height of the regular tetrahedron of unit edge, `sqrt(2/3)`.
pub const REGULAR_HEIGHT: f64 = 0.816_496_580_927_726;

/// The optimal point on the face `f` with sizes `h` at its vertices, on the side of the
/// unit normal `n`, and the size there. Inexact construction.
pub fn optimal_point(
    f: [Point; 3],
    h: [f64; 3],
    n: Point,
    field: &dyn SizeField,
    params: &PointParams,
    hint: &mut u32,
) -> (Point, f64) {
    let hbar = (h[0] + h[1] + h[2]) / 3.0;
    let centroid = (f[0] + f[1] + f[2]) / 3.0;
    let mut p = centroid + n * (hbar * REGULAR_HEIGHT);
    let mut hp = field.size(p, hint);
    for _ in 0..params.steps {
        let mut target = Point::ZERO;
        for k in 0..3 {
            let l = edge_length(field, params.mode, f[k], p, h[k], hp, hint);
            if !(l > 0.0 && l.is_finite()) {
                return (p, hp);
            }
            target += f[k] + (p - f[k]) / l;
        }
        p += (target / 3.0 - p) * params.alpha;
        hp = field.size(p, hint);
    }
    (p, hp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quality::tet::q_k;
    use crate::sizing::ConstantSize;

    #[test]
    fn equilateral_face_at_constant_size_gives_a_regular_tet() {
        let h = 0.7;
        let a = Point::new(0.0, 0.0, 0.0);
        let b = Point::new(h, 0.0, 0.0);
        let c = Point::new(h / 2.0, h * 3f64.sqrt() / 2.0, 0.0);
        let (p, hp) = optimal_point(
            [a, b, c],
            [h; 3],
            Point::Z,
            &ConstantSize(h),
            &PointParams::default(),
            &mut 0,
        );
        assert_eq!(hp, h);
        for x in [a, b, c] {
            assert!((x.distance(p) / h - 1.0).abs() < 0.01, "{}", x.distance(p));
        }
        assert!(q_k(&[a, b, c, p]) < 1.01);
    }

    #[test]
    fn relaxation_pulls_towards_unit_edges() {
        // A face smaller than the size: P moves up, its edges approach length h.
        let h = 1.0;
        let f = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(0.5, 0.0, 0.0),
            Point::new(0.25, 0.43, 0.0),
        ];
        let params = PointParams {
            steps: 50,
            alpha: 0.5,
            ..PointParams::default()
        };
        let (p, _) = optimal_point(f, [h; 3], Point::Z, &ConstantSize(h), &params, &mut 0);
        for x in f {
            assert!((x.distance(p) - h).abs() < 0.02, "{}", x.distance(p));
        }
    }
}
