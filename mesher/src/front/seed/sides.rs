//! Which cells of a coarse grid over the domain's box lie wholly inside or wholly
//! outside the domain: the seed lattices' inside test without a walk in T(S,F) for
//! the points far from the boundary (not in the paper).
//!
//! A cell is *open* when no face between a tet of the domain and a tet outside it
//! (region 0, or the hull) meets it, found conservatively by the faces' bounding boxes
//! grown by a margin far above the rounding of the cell coordinates. Two open cells
//! that share a face are on the same side (a path between their points crosses no such
//! face), so one location per connected set of open cells, at a cell's centre, gives
//! the side of every point in the set. Points in cells a boundary face meets, or
//! outside the grid, are located as before. Exact: the same answers as the walks
//! (which the seeds' clearance makes unambiguous: a point on a vertex is never kept).

use crate::delaunay::{Kernel, Location};
use crate::front::FieldMesh;
use crate::geom::predicates::StaticFilter;
use crate::geom::Point;
use crate::tetmesh::{TetId, FACE_VERTICES};
use std::collections::VecDeque;

/// Largest number of cells: beyond, no grid (every point is located).
const MAX_CELLS: usize = 1 << 22;

/// Cell state: a boundary face may meet it.
const CLOSED: u32 = u32::MAX;

/// Cell state: open, not labelled yet.
const UNLABELLED: u32 = CLOSED - 1;

/// The grid and, per open cell, its connected set; per set, its side.
pub(in crate::front) struct Sides {
    origin: Point,
    step: f64,
    n: [usize; 3],
    /// Per cell (x fastest): the index of its connected set, or [`CLOSED`].
    set: Vec<u32>,
    /// Per set: inside the domain, outside, or unknown (its centre not located in a
    /// finite tet).
    inside: Vec<Option<bool>>,
}

impl Sides {
    /// The grid of cube side `step` over the box `[lo, hi]` (with half a cell of
    /// margin); `None` when the step is unusable or the cells too many.
    pub fn new(
        fm: &FieldMesh,
        lo: Point,
        hi: Point,
        step: f64,
        filter: StaticFilter,
    ) -> Option<Sides> {
        if !(step > 0.0 && step.is_finite() && lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let origin = lo - Point::splat(0.5 * step);
        let cells = ((hi - origin) / step).floor() + Point::ONE;
        if cells.x * cells.y * cells.z > MAX_CELLS as f64 {
            return None;
        }
        let n = [cells.x as usize, cells.y as usize, cells.z as usize];
        let mut sides = Sides {
            origin,
            step,
            n,
            set: vec![UNLABELLED; n[0] * n[1] * n[2]],
            inside: Vec::new(),
        };
        // Far above the rounding of `(p - origin) / step` at the box's coordinates.
        let scale = lo.abs().max(hi.abs()).max_element();
        let margin = 1e-6 * step + 1e-9 * scale;
        sides.close_boundary_cells(fm, margin);
        sides.label_sets(fm, filter);
        Some(sides)
    }

    /// Whether `p` is inside the domain, when its cell's set knows; `None` otherwise.
    pub fn inside(&self, p: Point) -> Option<bool> {
        let g = (p - self.origin) / self.step;
        let [nx, ny, nz] = self.n;
        let fits = |x: f64, n: usize| x >= 0.0 && x < n as f64;
        if !(fits(g.x, nx) && fits(g.y, ny) && fits(g.z, nz)) {
            return None;
        }
        let cell = (g.z as usize * ny + g.y as usize) * nx + g.x as usize;
        match self.set[cell] {
            CLOSED => None,
            s => self.inside[s as usize],
        }
    }

    /// Marks [`CLOSED`] every cell the box of a face between the domain and its
    /// outside meets (each face once, from its tet in the domain).
    fn close_boundary_cells(&mut self, fm: &FieldMesh, margin: f64) {
        let in_domain = |t: TetId| {
            !fm.mesh.is_ghost(t) && fm.cons.region.get(t.index()).is_some_and(|&r| r != 0)
        };
        let [nx, ny, nz] = self.n;
        let range = |a: f64, b: f64, n: usize| {
            let i = ((a - margin) / self.step).floor().max(0.0);
            let j = ((b + margin) / self.step).floor().min(n as f64 - 1.0);
            (i as usize, j as usize, i <= j)
        };
        for t in fm.mesh.finite_tets() {
            if !in_domain(t) {
                continue;
            }
            let v = fm.mesh.tet(t);
            for (i, fv) in FACE_VERTICES.iter().enumerate() {
                if in_domain(fm.mesh.neighbor(t, i).tet()) {
                    continue;
                }
                let [a, b, c] = fv.map(|k| fm.mesh.point(v[k]) - self.origin);
                let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
                let (x0, x1, ox) = range(lo.x, hi.x, nx);
                let (y0, y1, oy) = range(lo.y, hi.y, ny);
                let (z0, z1, oz) = range(lo.z, hi.z, nz);
                if !(ox && oy && oz) {
                    continue;
                }
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        let row = (z * ny + y) * nx;
                        self.set[row + x0..=row + x1].fill(CLOSED);
                    }
                }
            }
        }
    }

    /// Labels the connected sets of open cells (face neighbours) and locates one centre
    /// per set.
    fn label_sets(&mut self, fm: &FieldMesh, filter: StaticFilter) {
        let [nx, ny, nz] = self.n;
        let mut locator = Kernel::new();
        locator.set_filter(filter);
        let mut queue = VecDeque::new();
        for start in 0..self.set.len() {
            if self.set[start] != UNLABELLED {
                continue;
            }
            let id = self.inside.len() as u32;
            self.set[start] = id;
            queue.push_back(start);
            while let Some(c) = queue.pop_front() {
                let (x, y, z) = (c % nx, (c / nx) % ny, c / (nx * ny));
                let nbrs = [
                    (x > 0).then(|| c - 1),
                    (x + 1 < nx).then(|| c + 1),
                    (y > 0).then(|| c - nx),
                    (y + 1 < ny).then(|| c + nx),
                    (z > 0).then(|| c - nx * ny),
                    (z + 1 < nz).then(|| c + nx * ny),
                ];
                for d in nbrs.into_iter().flatten() {
                    if self.set[d] == UNLABELLED {
                        self.set[d] = id;
                        queue.push_back(d);
                    }
                }
            }
            let (x, y, z) = (start % nx, (start / nx) % ny, start / (nx * ny));
            let centre = self.origin + (Point::new(x as f64, y as f64, z as f64) + 0.5) * self.step;
            let side = match locator.locate_next(&fm.mesh, centre) {
                Location::InTet(t) => Some(fm.cons.region.get(t.index()).is_some_and(|&r| r != 0)),
                _ => None,
            };
            self.inside.push(side);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::{boundary_mesh, BoundaryOptions};
    use crate::delaunay::sort::SplitMix64;
    use crate::delaunay::Constraints;
    use crate::surface::generate::{hollow, icosphere, torus};
    use crate::surface::Surface;

    /// The front's mesh of T(S,F) (no sizes: the sides do not read them).
    fn field_mesh(s: &Surface) -> FieldMesh {
        let (bm, _) = boundary_mesh(s, &BoundaryOptions::default()).expect("T(S,F)");
        let n = bm.mesh.num_slots();
        FieldMesh {
            cons: Constraints {
                face_mask: vec![0; n],
                region: bm.region,
            },
            mesh: bm.mesh,
            h: Vec::new(),
            hint: Vec::new(),
        }
    }

    /// Wherever the grid answers, it answers as the walk does, at random points of the
    /// domain's box; and it answers for most of them.
    fn agrees_with_the_walks(s: &Surface, step: f64) {
        let fm = field_mesh(s);
        let (lo, hi) = s.vertices.iter().fold(
            (Point::splat(f64::MAX), Point::splat(f64::MIN)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let filter = StaticFilter::of_points(fm.mesh.points());
        let sides = Sides::new(&fm, lo, hi, step, filter).expect("a grid");
        let mut locator = Kernel::new();
        locator.set_filter(filter);
        let mut rng = SplitMix64::new(11);
        let (mut answered, mut inside) = (0, 0);
        for _ in 0..4000 {
            let p = lo + (hi - lo) * Point::new(rng.unit(), rng.unit(), rng.unit());
            let Some(known) = sides.inside(p) else {
                continue;
            };
            let walked = match locator.locate_next(&fm.mesh, p) {
                Location::InTet(t) => fm.cons.region[t.index()] != 0,
                _ => false,
            };
            assert_eq!(known, walked, "at {p}");
            answered += 1;
            inside += usize::from(known);
        }
        assert!(answered > 2000 && inside > 200, "{answered} {inside}");
    }

    #[test]
    fn a_torus_and_its_hole() {
        agrees_with_the_walks(&torus(48, 24, 1.0, 0.4), 0.1);
    }

    #[test]
    fn the_shell_between_nested_spheres() {
        agrees_with_the_walks(&hollow(&icosphere(3), &icosphere(2), 0.5), 0.08);
    }

    /// No grid for an unusable step or too many cells.
    #[test]
    fn no_grid_when_the_step_is_unusable() {
        let fm = field_mesh(&icosphere(1));
        let filter = StaticFilter::of_points(fm.mesh.points());
        let (lo, hi) = (Point::splat(-1.0), Point::splat(1.0));
        for step in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-4] {
            assert!(Sides::new(&fm, lo, hi, step, filter).is_none(), "{step}");
        }
    }
}
