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

use crate::geom::predicates::{on_open_segment, orient3d};
use crate::geom::Point;
use crate::surface::{faces_by_vertex, Surface};

/// Denominator of the dyadic fractions tried near the wanted split parameter, nearest
/// first.
const SPLIT_DENOMINATOR: u32 = 64;
/// Farthest a split point near the wanted parameter may be from it.
const SPLIT_SLACK: f64 = 0.1;
/// Simple dyadic fractions tried after those: an exact split point matters more than
/// its place (a point off its edge by rounding is hard to take out again on a flat
/// part of the surface).
const SIMPLE_FRACTIONS: [f64; 7] = [0.5, 0.25, 0.75, 0.375, 0.625, 0.125, 0.875];

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
    /// The input triangles at each input vertex (`at[start[v]..start[v + 1]]`), and
    /// the triangles the splits and merges wrote or moved since: together they hold
    /// every triangle at a vertex ([`Refined::triangles_at`]), without a sweep.
    start: Vec<u32>,
    at: Vec<u32>,
    changed: Vec<u32>,
}

impl Refined {
    /// The input surface, not split.
    pub fn new(surface: &Surface) -> Self {
        let n = surface.vertices.len();
        let (start, at) = faces_by_vertex(surface, |_| true);
        Refined {
            surface: surface.clone(),
            parent: (0..surface.triangles.len() as u32).collect(),
            inputs: n,
            splits: Vec::new(),
            exact: Vec::new(),
            removed: Vec::new(),
            start,
            at,
            changed: Vec::new(),
        }
    }

    /// The indices of the triangles that hold vertex `v` and every vertex of `also`,
    /// increasing (what a sweep over the triangles finds).
    pub fn triangles_at(&self, v: u32, also: &[u32]) -> Vec<usize> {
        let tris = &self.surface.triangles;
        let row = match (self.start.get(v as usize), self.start.get(v as usize + 1)) {
            (Some(&a), Some(&b)) => &self.at[a as usize..b as usize],
            _ => &[],
        };
        let mut out: Vec<usize> = row
            .iter()
            .chain(&self.changed)
            .map(|&k| k as usize)
            .filter(|&k| {
                tris.get(k)
                    .is_some_and(|t| t.contains(&v) && also.iter().all(|x| t.contains(x)))
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Splits the edge `(a, b)` (refined vertex ids) and the triangles on it near the
    /// parameter `t` (0 at `a`, 1 at `b`). False when no representable point lies
    /// strictly between its ends.
    pub fn split_edge(&mut self, a: u32, b: u32, t: f64) -> bool {
        let v = &self.surface.vertices;
        let (pa, pb) = (v[a as usize], v[b as usize]);
        // The triangles on the edge, with their apexes.
        let on_edge = self.triangles_at(a, &[b]);
        let apexes: Vec<Point> = on_edge
            .iter()
            .filter_map(|&k| {
                let t = &self.surface.triangles[k];
                t.iter().find(|&&x| x != a && x != b)
            })
            .map(|&x| v[x as usize])
            .collect();
        let keeps_fold = |m: Point| folds_alike(pa, pb, m, &apexes);
        let Some((m, exact)) = split_point(pa, pb, t, keeps_fold) else {
            return false;
        };
        let mid = v.len() as u32;
        self.surface.vertices.push(m);
        self.splits.push([mid, a, b]);
        self.exact.push(exact);
        self.removed.push(false);
        for k in on_edge {
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
            self.changed.push(k as u32);
            self.changed.push(self.surface.triangles.len() as u32);
            self.surface.triangles.push([mid, y, z]);
            self.parent.push(self.parent[k]);
        }
        true
    }

    /// The surface star of split point `m` on edge `(u, w)` when it is still the one
    /// the split made: four triangles `(u, m, c)`, `(m, w, c)`, `(u, m, d)`,
    /// `(m, w, d)`. Returns `[c, d]` and the four triangles' indices.
    pub fn star(&self, [m, u, w]: [u32; 3]) -> Option<([u32; 2], [usize; 4])> {
        let tris = self.triangles_at(m, &[]);
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
            self.changed.push(k as u32);
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
            // The last triangle moved into slot `k`.
            self.changed.push(k as u32);
        }
    }
}

/// A point strictly inside the segment `ab` near parameter `t`, and whether it is
/// exactly on the segment: the nearest dyadic fraction `k / 64` (within
/// [`SPLIT_SLACK`]) whose point is exactly on it, else the first of
/// [`SIMPLE_FRACTIONS`] that is. When none is, a point within rounding of the segment
/// for which `usable` holds (the rounded fractions and their neighbouring floats), else
/// the rounded point at `t`.
fn split_point(
    a: Point,
    b: Point,
    t: f64,
    usable: impl Fn(Point) -> bool,
) -> Option<(Point, bool)> {
    let d = b - a;
    let t = if t.is_finite() {
        t.clamp(0.05, 0.95)
    } else {
        0.5
    };
    let mut fractions: Vec<f64> = (1..SPLIT_DENOMINATOR)
        .map(|k| k as f64 / SPLIT_DENOMINATOR as f64)
        .filter(|f| (f - t).abs() <= SPLIT_SLACK)
        .collect();
    fractions.sort_by(|x, y| (x - t).abs().total_cmp(&(y - t).abs()).then(x.total_cmp(y)));
    fractions.extend(SIMPLE_FRACTIONS);
    let candidates = |f: f64| [a + d * f, b - d * (1.0 - f), a * (1.0 - f) + b * f];
    let exact = fractions.iter().find_map(|&f| {
        candidates(f)
            .into_iter()
            .find(|&m| on_open_segment(a, b, m))
    });
    if let Some(m) = exact {
        return Some((m, true));
    }
    let between = |m: Point| {
        (0..3).all(|i| m[i] >= a[i].min(b[i]) && m[i] <= a[i].max(b[i])) && m != a && m != b
    };
    let nudged = fractions.iter().find_map(|&f| {
        candidates(f)
            .into_iter()
            .flat_map(neighbours)
            .find(|&m| between(m) && usable(m))
    });
    if let Some(m) = nudged {
        return Some((m, false));
    }
    let m = a + d * t;
    between(m).then_some((m, false))
}

/// `p` and the points one float away from it in any coordinates (27 in all).
fn neighbours(p: Point) -> impl Iterator<Item = Point> {
    let step = |x: f64, k: usize| match k {
        0 => x,
        1 => x.next_down(),
        _ => x.next_up(),
    };
    (0..27).map(move |k| Point::new(step(p.x, k % 3), step(p.y, k / 3 % 3), step(p.z, k / 9)))
}

/// True when a point `m` off the edge `ab` by rounding splits the triangles on it
/// (apexes `apexes`) without changing how they fold: each half of one triangle puts
/// the other triangle's apex on the same side as the whole triangle does (exactly
/// coplanar on a flat part). A point that inverts a thin fold cannot be taken out
/// again.
fn folds_alike(a: Point, b: Point, m: Point, apexes: &[Point]) -> bool {
    apexes.iter().all(|&c| {
        apexes.iter().filter(|&&d| d != c).all(|&d| {
            let whole = orient3d(a, b, c, d);
            orient3d(a, m, c, d) == whole && orient3d(m, b, c, d) == whole
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::predicates::Orientation;
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
            let (m, exact) = split_point(a, b, 0.5, |_| true).expect("a point on the segment");
            assert!(exact && on_open_segment(a, b, m));
        }
        // Adjacent floats have nothing in between.
        let a = Point::new(1.0, 1.0, 1.0);
        assert!(split_point(a, Point::new(1.0, 1.0, 1.0f64.next_up()), 0.5, |_| true).is_none());
        // Decimal input: no representable point is on the segment; the rounded middle.
        let (a, b) = (
            Point::new(6.205, -37.807, -199.941),
            Point::new(18.518, -36.27, -151.941),
        );
        let (m, exact) = split_point(a, b, 0.5, |_| true).expect("a point near the middle");
        assert!(!exact && (m - (a + b) * 0.5).length() < 1e-12);
    }

    #[test]
    fn a_rounded_split_point_keeps_a_thin_fold_folded() {
        // From cheese (an edge of a previous split, so no representable point on it):
        // two triangles on the edge folded almost flat onto each other. Rounded points
        // on the edge can put the other apex on the wrong side of a half triangle (the
        // split could then never be taken out again); the chosen point never does.
        let a = Point::new(-0.0473389998, 0.0063570002, 0.0363470018);
        let b = Point::new(-0.04755556370625, 0.00648168760625, 0.034399875275);
        let c = Point::new(-0.04744006295625, 0.00641518765625, 0.034681876025);
        let d = Point::new(-0.047562782503125, 0.006485843853124999, 0.0350914377875);
        assert_ne!(orient3d(a, b, c, d), Orientation::Zero);
        let ok = |m: Point| folds_alike(a, b, m, &[c, d]);
        let mut inverted_by_rounding = 0;
        for k in 4..60 {
            let t = k as f64 / 64.0;
            if !ok(a + (b - a) * t) {
                inverted_by_rounding += 1;
            }
            let (m, exact) = split_point(a, b, t, ok).expect("a split point");
            assert!(exact || ok(m), "t = {t}");
        }
        assert!(inverted_by_rounding > 0);
    }

    /// The index finds what a sweep over the triangles finds, through splits (of
    /// pieces too) and merges in any order.
    #[test]
    fn triangles_at_a_vertex_match_a_sweep_through_splits_and_merges() {
        let s = generate::icosphere(1);
        let mut r = Refined::new(&s);
        let check = |r: &Refined| {
            for v in 0..r.surface.vertices.len() as u32 {
                for also in [vec![], vec![(v + 1) % 7]] {
                    let sweep: Vec<usize> = (0..r.surface.triangles.len())
                        .filter(|&k| {
                            let t = r.surface.triangles[k];
                            t.contains(&v) && also.iter().all(|x| t.contains(x))
                        })
                        .collect();
                    assert_eq!(r.triangles_at(v, &also), sweep, "vertex {v}");
                }
            }
        };
        for k in [0, 5, 9, 3] {
            let [a, b, _] = r.surface.triangles[k];
            assert!(r.split_edge(a, b, 0.5));
            check(&r);
        }
        // A piece of a split edge split again.
        let [m, a, _] = r.splits[0];
        assert!(r.split_edge(m, a, 0.5));
        check(&r);
        for i in [4, 1, 2, 0, 3] {
            let split = r.splits[i];
            let (_, tris) = r.star(split).expect("the star of the split");
            r.merge(split, tris);
            check(&r);
        }
    }

    #[test]
    fn splitting_an_edge_splits_both_triangles_and_keeps_the_surface_closed() {
        let s = generate::cube(1);
        let mut r = Refined::new(&s);
        let [a, b, _] = s.triangles[0];
        assert!(r.split_edge(a, b, 0.5));
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
