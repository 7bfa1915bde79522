//! Inexact construction: the Chebyshev centre of a bounded intersection of half-spaces
//! (the centre of the largest ball inside it), by a small dense simplex method on the
//! dual linear program (Dantzig's method with Bland's rule, which cannot cycle; Chvátal,
//! "Linear Programming", 1983, ch. 3). The boundary recovery (paper §4.2) uses it to
//! place an interior Steiner point that sees every face of a region: such a point
//! exists exactly when the region's kernel has an interior, and the ball's centre is as
//! far as possible from every face.
//!
//! The primal: maximise `t` over `(x, t)` subject to `n_i · x - t >= d_i` for unit
//! normals `n_i`. Its dual: minimise `-Σ d_i λ_i` subject to `Σ λ_i n_i = 0`,
//! `Σ λ_i = 1`, `λ >= 0`, four equality rows, solved in two phases from artificial
//! variables; the primal optimum is read off the final tableau as the simplex
//! multipliers. Every loop is bounded; any numerical trouble gives `None`.

use super::Point;

/// Pivots allowed per phase, per column.
const PIVOTS_PER_COLUMN: usize = 8;

/// Zero, for data scaled to unit size.
const EPS: f64 = 1e-11;

/// Smallest pivot: smaller ones would magnify the rounding of the tableau (a centre
/// off its planes by 1e-3 was seen with 1e-11).
const MIN_PIVOT: f64 = 1e-9;

/// A half-space `{x : normal · x >= offset}` (any non-zero `normal`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace {
    pub normal: Point,
    pub offset: f64,
}

/// The centre and radius of the largest ball inside the half-spaces and the box
/// `[lo, hi]` (which keeps the program bounded). The radius is negative or zero when
/// the intersection has no interior; it is measured at the centre returned (the
/// distance to its nearest plane), so rounding in the simplex method cannot overstate
/// it. `None` when the simplex method gives up (bound on
/// pivots, or a degenerate normal).
pub fn chebyshev_centre(halves: &[HalfSpace], lo: Point, hi: Point) -> Option<(Point, f64)> {
    // Scale to the box: centre at the origin, half diagonal 1.
    let centre = (lo + hi) * 0.5;
    let scale = ((hi - lo).length() * 0.5).max(f64::MIN_POSITIVE);
    let mut rows: Vec<(Point, f64)> = Vec::with_capacity(halves.len() + 6);
    for h in halves {
        let len = h.normal.length();
        if !(len.is_finite() && len > 0.0) {
            return None;
        }
        let n = h.normal / len;
        // n · (centre + scale y) >= offset / len.
        rows.push((n, (h.offset / len - n.dot(centre)) / scale));
    }
    for axis in [Point::X, Point::Y, Point::Z] {
        let half = (hi - lo).dot(axis) * 0.5 / scale;
        rows.push((axis, -half));
        rows.push((-axis, -half));
    }
    if rows.iter().any(|r| !r.1.is_finite()) {
        return None;
    }
    let (y, _) = solve_dual(&rows)?;
    // The radius the centre really has (the tableau's optimum carries its rounding).
    let t = rows
        .iter()
        .map(|(n, d)| n.dot(y) - d)
        .fold(f64::INFINITY, f64::min);
    Some((centre + y * scale, t * scale))
}

/// [`chebyshev_centre`] of the positive sides of triangles (`orient3d(a, b, c, p) > 0`
/// for `p` inside: the kernel of a region whose boundary faces they are), bounded by
/// their box; `None` for no triangle or when the simplex method gives up.
pub fn kernel_centre(triangles: &[[Point; 3]]) -> Option<(Point, f64)> {
    let halves: Vec<HalfSpace> = triangles
        .iter()
        .map(|[a, b, c]| {
            let normal = (*b - *a).cross(*c - *a);
            HalfSpace {
                normal,
                offset: normal.dot(*a),
            }
        })
        .collect();
    let bounds = super::Aabb::of_points(triangles.iter().flatten())?;
    chebyshev_centre(&halves, bounds.min, bounds.max)
}

/// The tableau of the dual: 4 rows, `m` columns of `λ` then 4 artificials, and the
/// right-hand side.
struct Tableau {
    a: Vec<[f64; 4]>,
    rhs: [f64; 4],
    basis: [usize; 4],
}

impl Tableau {
    fn pivot(&mut self, row: usize, col: usize) {
        let p = self.a[col][row];
        for c in self.a.iter_mut() {
            c[row] /= p;
        }
        self.rhs[row] /= p;
        for r in 0..4 {
            if r == row {
                continue;
            }
            let f = self.a[col][r];
            if f == 0.0 {
                continue;
            }
            for c in self.a.iter_mut() {
                c[r] -= f * c[row];
            }
            self.rhs[r] -= f * self.rhs[row];
        }
        self.basis[row] = col;
    }

    /// Minimises `cost` over the columns `< allowed` (the basis may hold others);
    /// false when the pivot bound is reached or the program is unbounded.
    fn minimise(&mut self, cost: &[f64], allowed: usize) -> bool {
        for _ in 0..PIVOTS_PER_COLUMN * (self.a.len() + 4) {
            // Bland: the first column with a negative reduced cost enters.
            let entering = (0..allowed).find(|&j| {
                let r = cost[j]
                    - (0..4)
                        .map(|i| cost[self.basis[i]] * self.a[j][i])
                        .sum::<f64>();
                r < -EPS
            });
            let Some(j) = entering else {
                return true;
            };
            // Ratio test; ties to the smallest basic index.
            let mut leave: Option<(f64, usize, usize)> = None;
            for i in 0..4 {
                let x = self.a[j][i];
                if x > MIN_PIVOT {
                    let ratio = self.rhs[i] / x;
                    let better = leave.is_none_or(|(r, _, b)| {
                        ratio < r - EPS || (ratio <= r + EPS && self.basis[i] < b)
                    });
                    if better {
                        leave = Some((ratio, i, self.basis[i]));
                    }
                }
            }
            // Unbounded: the dual has no minimum, so the primal is infeasible (cannot
            // happen with the box), or rounding.
            let Some((_, row, _)) = leave else {
                return false;
            };
            self.pivot(row, j);
        }
        false
    }
}

/// Solves the dual for rows `(n_i, d_i)` (unit `n_i`); returns the primal `(x, t)`.
fn solve_dual(rows: &[(Point, f64)]) -> Option<(Point, f64)> {
    let m = rows.len();
    let mut a: Vec<[f64; 4]> = rows.iter().map(|(n, _)| [n.x, n.y, n.z, 1.0]).collect();
    for k in 0..4 {
        let mut e = [0.0; 4];
        e[k] = 1.0;
        a.push(e);
    }
    let mut tab = Tableau {
        a,
        rhs: [0.0, 0.0, 0.0, 1.0],
        basis: [m, m + 1, m + 2, m + 3],
    };
    // Phase 1: the artificials out.
    let mut cost = vec![0.0; m + 4];
    cost[m..].fill(1.0);
    if !tab.minimise(&cost, m) {
        return None;
    }
    let infeasibility: f64 = (0..4)
        .filter(|&i| tab.basis[i] >= m)
        .map(|i| tab.rhs[i])
        .sum();
    if infeasibility > 1e-9 {
        return None;
    }
    // Phase 2: minimise -Σ d_i λ_i, the artificials kept out.
    for (c, r) in cost.iter_mut().zip(rows) {
        *c = -r.1;
    }
    cost[m..].fill(0.0);
    if !tab.minimise(&cost, m) {
        return None;
    }
    // The simplex multipliers: the primal solution.
    let y: Vec<f64> = (0..4)
        .map(|k| {
            (0..4)
                .map(|i| cost[tab.basis[i]] * tab.a[m + k][i])
                .sum::<f64>()
        })
        .collect();
    // The program solved is the dual of: maximise y_t subject to
    // n_i · y_x + y_t <= -d_i, that is the primal with x = -y_x and t = y_t.
    let (x, t) = (-Point::new(y[0], y[1], y[2]), y[3]);
    // The four planes of the final basis are tight at the optimum: solved again from
    // the data, the centre loses the tableau's accumulated rounding.
    let tight = tab.basis.map(|j| rows.get(j).copied());
    let (x, t) = match tight {
        [Some(a), Some(b), Some(c), Some(d)] => {
            let rows = [a, b, c, d].map(|(n, d)| ([n.x, n.y, n.z, -1.0], d));
            match solve4(rows) {
                Some(v) => (Point::new(v[0], v[1], v[2]), v[3]),
                None => (x, t),
            }
        }
        _ => (x, t),
    };
    (x.is_finite() && t.is_finite()).then_some((x, t))
}

/// The solution of four linear equations (Gaussian elimination with partial
/// pivoting), or `None` when they are (nearly) singular.
fn solve4(mut rows: [([f64; 4], f64); 4]) -> Option<[f64; 4]> {
    for col in 0..4 {
        let p = (col..4).max_by(|&i, &j| rows[i].0[col].abs().total_cmp(&rows[j].0[col].abs()))?;
        if rows[p].0[col].abs() < MIN_PIVOT {
            return None;
        }
        rows.swap(col, p);
        for r in col + 1..4 {
            let f = rows[r].0[col] / rows[col].0[col];
            for k in col..4 {
                rows[r].0[k] -= f * rows[col].0[k];
            }
            rows[r].1 -= f * rows[col].1;
        }
    }
    let mut v = [0.0; 4];
    for col in (0..4).rev() {
        let s: f64 = (col + 1..4).map(|k| rows[col].0[k] * v[k]).sum();
        v[col] = (rows[col].1 - s) / rows[col].0[col];
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_halves() -> Vec<HalfSpace> {
        // The cube [0, 1]^3.
        let mut h = Vec::new();
        for axis in [Point::X, Point::Y, Point::Z] {
            h.push(HalfSpace {
                normal: axis,
                offset: 0.0,
            });
            h.push(HalfSpace {
                normal: -axis,
                offset: -1.0,
            });
        }
        h
    }

    #[test]
    fn the_centre_of_a_cube_is_its_centre() {
        let (c, r) =
            chebyshev_centre(&cube_halves(), Point::splat(-5.0), Point::splat(5.0)).unwrap();
        assert!((c - Point::splat(0.5)).length() < 1e-9, "{c}");
        assert!((r - 0.5).abs() < 1e-9, "{r}");
    }

    #[test]
    fn a_thin_slab_gives_its_half_thickness() {
        let mut h = cube_halves();
        // 0.1 <= z <= 0.12 inside the cube.
        h.push(HalfSpace {
            normal: Point::Z,
            offset: 0.1,
        });
        h.push(HalfSpace {
            normal: -Point::Z * 3.0,
            offset: -0.36,
        });
        let (c, r) = chebyshev_centre(&h, Point::splat(-1.0), Point::splat(2.0)).unwrap();
        assert!((r - 0.01).abs() < 1e-9, "{r}");
        assert!((c.z - 0.11).abs() < 1e-9, "{c}");
    }

    /// A needle along the cube's diagonal, 2e-3 thick: where an axis-aligned compass
    /// search stalls (every axis move leaves the needle).
    #[test]
    fn a_thin_needle_off_the_axes_is_found() {
        let mut h = cube_halves();
        for n in [Point::new(1.0, -1.0, 0.0), Point::new(0.0, 1.0, -1.0)] {
            h.push(HalfSpace {
                normal: n,
                offset: -1e-3,
            });
            h.push(HalfSpace {
                normal: -n,
                offset: -1e-3,
            });
        }
        let (c, r) = chebyshev_centre(&h, Point::splat(-1.0), Point::splat(2.0)).unwrap();
        assert!(r > 1e-4, "{r}");
        assert!(h.iter().all(|s| s.normal.dot(c) > s.offset), "{c}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// Half-spaces around a point `c`, each `r_i` from it: the centre returned is at
        /// least `min r_i` (up to rounding) inside every half-space, the radius it
        /// reports is its true clearance, and no larger than the box allows.
        #[test]
        fn the_centre_is_as_deep_as_a_known_interior_point(
            c in proptest::array::uniform3(-1.0f64..1.0),
            planes in proptest::collection::vec(
                (proptest::array::uniform3(-1.0f64..1.0), 0.01f64..1.0),
                1..40,
            ),
        ) {
            let c = Point::from(c);
            let halves: Vec<HalfSpace> = planes
                .iter()
                .filter_map(|&(n, r)| {
                    let n = Point::from(n);
                    (n.length() > 1e-3).then(|| {
                        let n = n.normalize();
                        HalfSpace { normal: n, offset: n.dot(c) - r }
                    })
                })
                .collect();
            let depth = planes.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
            let (x, radius) =
                chebyshev_centre(&halves, Point::splat(-3.0), Point::splat(3.0)).unwrap();
            proptest::prop_assert!(radius >= depth - 1e-9, "{radius} < {depth}");
            for h in &halves {
                proptest::prop_assert!(h.normal.dot(x) - h.offset >= radius - 1e-9);
            }
            proptest::prop_assert!(radius <= 3.0 + 1e-9);
        }
    }

    #[test]
    fn an_empty_intersection_has_no_positive_radius() {
        let h = [
            HalfSpace {
                normal: Point::X,
                offset: 1.0,
            },
            HalfSpace {
                normal: -Point::X,
                offset: 0.0,
            },
        ];
        let (_, r) = chebyshev_centre(&h, Point::splat(-2.0), Point::splat(2.0)).unwrap();
        assert!(r <= 0.0, "{r}");
    }
}
