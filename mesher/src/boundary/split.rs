//! Boundary Steiner points: the last resort of the recovery (paper §4.2; Si and
//! Gärtner, "3D boundary recovery by constrained Delaunay tetrahedralization", IJNME
//! 2011, §4: a missing segment is split until its pieces are recoverable).
//!
//! When interior Steiner points do not unblock an input edge, the edge is split near its
//! middle and the triangles on the edge are split with it; every piece remembers its
//! input triangle. The pieces are recovered like any other entity, and afterwards each
//! split point is taken out again where the mesh allows (`Recovery::suppress_split`),
//! newest first, which undoes the split of the surface too.
//!
//! The split point is *exactly* on the edge when a representable point is (searched
//! among dyadic fractions, checked with the exact predicate); then the split surface is
//! the input surface as a point set. Often none is: with decimal input the coordinate
//! differences share no power of two. Then the rounded middle is used, within rounding
//! of the edge, and a split point that cannot be taken out again is reported as inexact.

use crate::geom::predicates::on_open_segment;
use crate::geom::Point;
use crate::surface::Surface;

/// Dyadic fractions tried for the split point, best first (middle, then towards it).
const FRACTIONS: [(u32, u32); 13] = [
    (1, 2),
    (3, 8),
    (5, 8),
    (7, 16),
    (9, 16),
    (1, 4),
    (3, 4),
    (5, 16),
    (11, 16),
    (13, 32),
    (19, 32),
    (15, 32),
    (17, 32),
];

/// The input surface refined by boundary Steiner points.
#[derive(Clone, Debug)]
pub(super) struct Refined {
    /// Input vertices first, then the split points.
    pub surface: Surface,
    /// Input triangle of each refined triangle.
    pub parent: Vec<u32>,
    /// Number of input vertices.
    pub inputs: usize,
    /// Each split: the point and the two ends of the edge it split.
    pub splits: Vec<[u32; 3]>,
    /// Whether each split point is exactly on its edge.
    pub exact: Vec<bool>,
    /// Whether each split was undone (its point taken out of the mesh).
    pub removed: Vec<bool>,
}

impl Refined {
    /// The input surface, not split.
    pub fn new(surface: &Surface) -> Self {
        Refined {
            surface: surface.clone(),
            parent: (0..surface.triangles.len() as u32).collect(),
            inputs: surface.vertices.len(),
            splits: Vec::new(),
            exact: Vec::new(),
            removed: Vec::new(),
        }
    }

    /// Splits the edge `(a, b)` (refined vertex ids) and the triangles on it near its
    /// middle. False when no representable point lies strictly between its ends.
    pub fn split_edge(&mut self, a: u32, b: u32) -> bool {
        let v = &self.surface.vertices;
        let Some((m, exact)) = split_point(v[a as usize], v[b as usize]) else {
            return false;
        };
        let mid = v.len() as u32;
        self.surface.vertices.push(m);
        self.splits.push([mid, a, b]);
        self.exact.push(exact);
        self.removed.push(false);
        let n = self.surface.triangles.len();
        for k in 0..n {
            let t = self.surface.triangles[k];
            // The edge in the triangle's own direction, (t[i], t[i+1]).
            let Some(i) = (0..3).find(|&i| {
                let (x, y) = (t[i], t[(i + 1) % 3]);
                (x, y) == (a, b) || (x, y) == (b, a)
            }) else {
                continue;
            };
            let (x, y, z) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
            self.surface.triangles[k] = [x, mid, z];
            self.surface.triangles.push([mid, y, z]);
            self.parent.push(self.parent[k]);
        }
        true
    }

    /// The surface star of split point `m` on edge `(u, w)` when it is still the one
    /// the split made: four triangles `(u, m, c)`, `(m, w, c)`, `(u, m, d)`,
    /// `(m, w, d)`. Returns `[c, d]` and the four triangles' indices.
    pub fn star(&self, [m, u, w]: [u32; 3]) -> Option<([u32; 2], [usize; 4])> {
        let tris: Vec<usize> = (0..self.surface.triangles.len())
            .filter(|&k| self.surface.triangles[k].contains(&m))
            .collect();
        let &[k0, k1, k2, k3] = tris.as_slice() else {
            return None;
        };
        let mut apex = Vec::with_capacity(4);
        for &k in &tris {
            let t = self.surface.triangles[k];
            let ends = t.iter().filter(|&&x| x == u || x == w).count();
            let other: Vec<u32> = t
                .iter()
                .copied()
                .filter(|&x| x != m && x != u && x != w)
                .collect();
            let &[o] = other.as_slice() else {
                return None;
            };
            if ends != 1 {
                return None;
            }
            apex.push(o);
        }
        apex.sort_unstable();
        (apex[0] == apex[1] && apex[2] == apex[3] && apex[1] != apex[2])
            .then_some(([apex[0], apex[2]], [k0, k1, k2, k3]))
    }

    /// Undoes a split in the surface: `(u, m, c)` and `(m, w, c)` become `(u, w, c)`
    /// (in the first one's orientation), on both sides. `star` must have accepted it.
    pub fn merge(&mut self, [m, u, w]: [u32; 3], tris: [usize; 4]) {
        let mut drop = Vec::with_capacity(2);
        for &k in &tris {
            let t = &mut self.surface.triangles[k];
            if t.contains(&u) {
                // (u, m, c) in some rotation: m becomes w.
                for x in t.iter_mut() {
                    if *x == m {
                        *x = w;
                    }
                }
            } else {
                drop.push(k);
            }
        }
        drop.sort_unstable();
        for k in drop.into_iter().rev() {
            self.surface.triangles.swap_remove(k);
            self.parent.swap_remove(k);
        }
    }
}

/// A point strictly inside the segment `ab` near its middle, and whether it is exactly
/// on the segment.
fn split_point(a: Point, b: Point) -> Option<(Point, bool)> {
    let d = b - a;
    let exact = FRACTIONS.iter().find_map(|&(k, n)| {
        let t = k as f64 / n as f64;
        [a + d * t, b - d * (1.0 - t), a * (1.0 - t) + b * t]
            .into_iter()
            .find(|&m| on_open_segment(a, b, m))
    });
    if let Some(m) = exact {
        return Some((m, true));
    }
    let m = a + d * 0.5;
    let between = (0..3).all(|i| m[i] >= a[i].min(b[i]) && m[i] <= a[i].max(b[i]));
    (between && m != a && m != b).then_some((m, false))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::generate;

    #[test]
    fn split_points_are_exactly_on_the_edge() {
        let pts = [
            (Point::new(0.5, 0.25, 0.125), Point::new(1.5, -0.75, 2.125)),
            (
                Point::new(0.375, 0.3125, -0.103293),
                Point::new(-0.315912, -0.177081, -0.103293),
            ),
            (Point::new(1.0, 1.0, 1.0), Point::new(1.0, 1.0, 3.0)),
        ];
        for (a, b) in pts {
            let (m, exact) = split_point(a, b).expect("a point on the segment");
            assert!(exact && on_open_segment(a, b, m));
        }
        // Adjacent floats have nothing in between.
        let a = Point::new(1.0, 1.0, 1.0);
        assert!(split_point(a, Point::new(1.0, 1.0, 1.0f64.next_up())).is_none());
        // Decimal input: no representable point is on the segment; the rounded middle.
        let (a, b) = (
            Point::new(6.205, -37.807, -199.941),
            Point::new(18.518, -36.27, -151.941),
        );
        let (m, exact) = split_point(a, b).expect("a point near the middle");
        assert!(!exact && (m - (a + b) * 0.5).length() < 1e-12);
    }

    #[test]
    fn splitting_an_edge_splits_both_triangles_and_keeps_the_surface_closed() {
        let s = generate::cube(1);
        let mut r = Refined::new(&s);
        let [a, b, _] = s.triangles[0];
        assert!(r.split_edge(a, b));
        assert_eq!(r.splits.len(), 1);
        assert_eq!(r.surface.triangles.len(), s.triangles.len() + 2);
        assert!(r.surface.check().is_clean());
        assert_eq!(r.parent.len(), r.surface.triangles.len());
        let split = r.splits[0];
        let (_, tris) = r.star(split).expect("the star of the split");
        r.merge(split, tris);
        let mut before = s.triangles.clone();
        let mut after = r.surface.triangles.clone();
        for t in before.iter_mut().chain(after.iter_mut()) {
            let k = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
            t.rotate_left(k);
        }
        before.sort_unstable();
        after.sort_unstable();
        assert_eq!(before, after);
    }
}
