//! The optimal point of a front face (paper §5.3.3): the apex of the ideal tetrahedron
//! built on the face in the control space.
//!
//! Start at the centroid plus `n * L * hbar * sqrt(2/3)` (the height of the regular tet
//! of edge `L * hbar`, `hbar` the mean size at the face's vertices, `L` the target
//! length), `n` the unit normal towards the unacceptable tet. Then relax: on each line
//! `XP` (`X` a face vertex) take the point `P_X = X + L (P - X) / l(XP)` at normalised
//! length `L` from `X`, and move `P` by `alpha` towards the mean of the `P_X`; at most
//! `steps` times (NOTES.md §6, where `L` is 1; see [`DEFAULT_POINT_LENGTH`]).
//!
//! The size at `P` is looked up at the start and once more at the end, not at every
//! step: the steps move `P` by a fraction of the size, where the size field changes
//! by less (bunny00: 24 M -> 16 M size lookups, the same tets within 0.05 %).

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
    /// Target normalised length of the apex's edges (paper: 1, the unit mesh).
    pub length: f64,
}

impl Default for PointParams {
    fn default() -> Self {
        PointParams {
            alpha: 0.1,
            steps: 5,
            mode: LengthMode::EndPoints,
            length: DEFAULT_POINT_LENGTH,
        }
    }
}

/// Default target normalised length of the optimal point's edges: 1.2, not the
/// paper's 1. Interior edges of a Delaunay mesh spread above the distance between
/// neighbouring points, so unit apex edges give a mean interior edge of 1.20, a quarter
/// of the edges below 1, and 1.34-1.66 times the tet count of Gmsh HXT on the same
/// sizes (ci tier, whose mean edge is 1.24-1.39). At 1.2 (ci tier, same run as HXT):
/// 10-15 % fewer tets than at 1, 1.17-1.29 times HXT's count on sphere-10k, fandisk,
/// elephant, torus and box-with-hole, 1.46-1.49 on the models whose first layer is
/// most of the volume (knot2, nested-spheres, sphere-1k); 92-97 % of the edges in
/// [0.6, 1.67]; worst Q_K a little higher on some fine models (fandisk 2.42 -> 2.71,
/// box-with-hole 2.99 -> 3.89, still below every peer's) and lower on hinge (149 ->
/// 74). A longer first layer too (`delta_boundary` 0.85) would bring those three to
/// 1.23-1.33, but then turbine's flat tet between thin walls stays at Q_K 1.9e5 and a
/// cube at constant size keeps only 85 % of its edges in band.
pub const DEFAULT_POINT_LENGTH: f64 = 1.2;

/// The height of the regular tetrahedron of unit edge, `sqrt(2/3)`.
pub const REGULAR_HEIGHT: f64 = 0.816_496_580_927_726;

/// Where the optimal point's relaxation starts on the face `f` of mean size `hbar`:
/// the apex of the regular tet of edge `hbar * params.length` on the side of `n`.
pub fn start(f: [Point; 3], hbar: f64, n: Point, params: &PointParams) -> Point {
    (f[0] + f[1] + f[2]) / 3.0 + n * (hbar * params.length * REGULAR_HEIGHT)
}

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
    let mut p = start(f, hbar, n, params);
    let mut hp = field.size(p, hint);
    for _ in 0..params.steps {
        let mut target = Point::ZERO;
        for k in 0..3 {
            let l = edge_length(field, params.mode, f[k], p, h[k], hp, hint);
            if !(l > 0.0 && l.is_finite()) {
                return (p, hp);
            }
            target += f[k] + (p - f[k]) * (params.length / l);
        }
        p += (target / 3.0 - p) * params.alpha;
    }
    if params.steps > 0 {
        hp = field.size(p, hint);
    }
    (p, hp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quality::tet::q_k;
    use crate::sizing::ConstantSize;

    /// The apex over an equilateral face of edge `length * h` at constant size `h`.
    fn apex_over_equilateral(h: f64, length: f64) -> ([Point; 4], f64) {
        let e = h * length;
        let a = Point::new(0.0, 0.0, 0.0);
        let b = Point::new(e, 0.0, 0.0);
        let c = Point::new(e / 2.0, e * 3f64.sqrt() / 2.0, 0.0);
        let params = PointParams {
            length,
            ..PointParams::default()
        };
        let (p, hp) = optimal_point(
            [a, b, c],
            [h; 3],
            Point::Z,
            &ConstantSize(h),
            &params,
            &mut 0,
        );
        assert_eq!(hp, h);
        ([a, b, c, p], e)
    }

    #[test]
    fn equilateral_face_at_constant_size_gives_a_regular_tet() {
        // The paper's unit target, and a longer one on a face of that length.
        for length in [1.0, 1.2] {
            let (t, e) = apex_over_equilateral(0.7, length);
            for x in &t[..3] {
                assert!(
                    (x.distance(t[3]) / e - 1.0).abs() < 0.01,
                    "{}",
                    x.distance(t[3])
                );
            }
            assert!(q_k(&t) < 1.01);
        }
    }

    #[test]
    fn relaxation_pulls_towards_the_target_length() {
        // A face smaller than the size: P moves up, its edges approach length h times
        // the target.
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
            let want = h * params.length;
            assert!((x.distance(p) - want).abs() < 0.02, "{}", x.distance(p));
        }
    }
}
