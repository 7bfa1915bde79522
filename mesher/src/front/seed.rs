//! Seed lattices deep inside the domain before the first front (not in the paper).
//!
//! The paper's front advances about one layer of tets per iteration, so a domain many
//! sizes deep takes as many iterations (sphere-100k: 46 with three points per face),
//! and the first fronts insert their points into T(S,F), whose interior tets join
//! boundary vertices across the whole domain (huge cavities). Here the interior is
//! seeded first with body-centred cubic (BCC) lattices, as in Labelle and Shewchuk's
//! isosurface stuffing ("Isosurface stuffing: fast tetrahedral meshes with good
//! dihedral angles", SIGGRAPH 2007): the Delaunay tets of a BCC lattice are all alike
//! (two edges of the cube side, four of `sqrt(3)/2` of it) and the lattice is not
//! cospherical, so it meshes well and fast.
//!
//! Sizes vary, so there is one lattice per level of size (ratio [`LEVEL_RATIO`]); a
//! lattice point is kept where the size field is within its level's band, inside the
//! domain (known from a coarse grid of the domain's sides, `sides`, away from the
//! boundary; located in T(S,F) near it) and farther than the clearance from the domain's
//! vertices and the points of the levels made before it. Each point is jittered a little: a partly
//! inserted lattice is cospherical. The front accepts the seeds' tets whose edges fit
//! and fills the gaps (between the surface and the lattices, and between levels).

mod sides;

use super::filter::Grid;
use super::{Candidate, FieldMesh, FrontParams};
use crate::delaunay::sort::SplitMix64;
use crate::delaunay::{Kernel, Location};
use crate::geom::predicates::StaticFilter;
use crate::geom::{Aabb, Point};
use crate::sizing::SizeField;
use crate::tetmesh::TetId;
use rayon::prelude::*;
use sides::Sides;

/// Largest number of lattice points tried per level (a finer level is skipped).
const MAX_CANDIDATES: usize = 1 << 23;

/// Largest number of lattice points tried over all levels (the coarser levels left
/// are skipped): a bound on the time of the lattices whatever the range of sizes.
const MAX_TOTAL: usize = 1 << 24;

/// Ratio between the sizes of consecutive lattice levels: a point belongs to the
/// level whose size is within a factor `sqrt(LEVEL_RATIO)` of its own.
pub const LEVEL_RATIO: f64 = 1.5;

/// Largest relative change of the size from a lattice point to its six neighbours at
/// one cube side: where sizes grade faster, the front places the points (a lattice
/// there leaves a gap the front cannot grade across: fandisk-in-box, worst Q_K 17 ->
/// 265 without this test).
const MAX_VARIATION: f64 = 0.2;

/// Percentile of the domain vertices' sizes that sets the finest lattice level.
const LOW_PERCENTILE: usize = 10;

/// The seed candidates by level (each level in lattice order): the points of
/// body-centred cubic lattices whose cube side is `params.seed_spacing` times the
/// level's size, kept where the size field is within the level's band and farther
/// than `params.seed_clearance` (normalised) from every domain vertex. At insertion
/// each seed must also keep that clearance from every vertex its cavity reaches other
/// than its own level's seeds, which drops those outside the domain and leaves a gap
/// between levels that the front fills.
pub(super) fn candidates(
    fm: &FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
) -> Vec<Vec<Candidate>> {
    if !(params.seed_spacing.is_finite() && params.seed_spacing > 0.0) {
        return Vec::new();
    }
    let Some(mut domain) = Domain::of(fm, params.seed_clearance) else {
        return Vec::new();
    };
    // Levels from the smallest vertex size to the largest.
    let lo_k = ((domain.h_min / domain.h_med).ln() / LEVEL_RATIO.ln()).round() as i32;
    let hi_k = ((domain.h_max / domain.h_med).ln() / LEVEL_RATIO.ln()).round() as i32;
    let mut levels = Vec::new();
    let mut tried = 0.0;
    let mut sizes: Option<SizeGrid> = None;
    let mut sides: Option<Option<Sides>> = None;
    for k in lo_k.max(-16)..=hi_k.min(16) {
        let h_ref = domain.h_med * LEVEL_RATIO.powi(k);
        let points = lattice_points(&domain, params.seed_spacing * h_ref);
        if points > MAX_CANDIDATES as f64 {
            continue;
        }
        tried += points;
        if tried > MAX_TOTAL as f64 {
            break;
        }
        // The size grid is no finer than the median size's lattice (the finest levels
        // are mostly near the surface and give few seeds; see `SizeGrid`).
        let spacing = params.seed_spacing * h_ref.max(domain.h_med);
        let grid = sizes.get_or_insert_with(|| SizeGrid::new(&domain, field, spacing));
        let sides = sides
            .get_or_insert_with(|| Sides::new(fm, domain.lo, domain.hi, spacing, domain.filter))
            .as_ref();
        let seeds = level(fm, &domain, field, (grid, sides), params, h_ref);
        // The next levels keep the clearance from this one's seeds too.
        for c in &seeds {
            domain.near.add_vertex(c.p, c.h);
        }
        levels.push(seeds);
    }
    levels.retain(|l: &Vec<Candidate>| !l.is_empty());
    levels
}

/// The domain's vertices, their sizes and box, and a grid of them at the clearance.
struct Domain {
    lo: Point,
    hi: Point,
    h_min: f64,
    h_med: f64,
    h_max: f64,
    hint: u32,
    near: Grid,
    /// The static filter over the box of every mesh point (the domain's and the
    /// bounding box's corners: the walks' tets reach them).
    filter: StaticFilter,
}

impl Domain {
    fn of(fm: &FieldMesh, clearance: f64) -> Option<Domain> {
        let mesh = &fm.mesh;
        let mut used = vec![false; fm.h.len()];
        let mut hint = None;
        for t in 0..mesh.num_slots() as u32 {
            if fm.cons.region[t as usize] != 0 && mesh.is_alive(TetId(t)) {
                hint.get_or_insert(t);
                for v in mesh.raw_tet(t) {
                    if let Some(u) = used.get_mut(v as usize) {
                        *u = true;
                    }
                }
            }
        }
        let verts: Vec<usize> = (0..used.len()).filter(|&v| used[v]).collect();
        let mut sizes: Vec<f64> = verts.iter().map(|&v| fm.h[v]).collect();
        if sizes.is_empty() || sizes.iter().any(|h| !(h.is_finite() && *h > 0.0)) {
            return None;
        }
        let n = sizes.len();
        let h_med = *sizes.select_nth_unstable_by(n / 2, f64::total_cmp).1;
        let h_max = sizes.iter().copied().fold(0.0, f64::max);
        // Not the smallest size: the interior sizes interpolate the boundary's, and a
        // lattice finer than a few surface triangles' size would be evaluated in vain.
        let h_min = *sizes
            .select_nth_unstable_by((n - 1) * LOW_PERCENTILE / 100, f64::total_cmp)
            .1;
        let h_small = *sizes
            .select_nth_unstable_by((n - 1) * 99 / 100, f64::total_cmp)
            .1;
        let pts = mesh.points();
        let (lo, hi) = verts.iter().fold(
            (Point::splat(f64::MAX), Point::splat(f64::MIN)),
            |(lo, hi), &v| (lo.min(pts[v]), hi.max(pts[v])),
        );
        let bounds = Aabb { min: lo, max: hi };
        let mut near = Grid::with_sizes(
            h_small,
            h_max,
            clearance,
            clearance,
            Some((bounds, verts.len())),
        );
        for &v in &verts {
            near.add_vertex(pts[v], fm.h[v]);
        }
        Some(Domain {
            lo,
            hi,
            h_min,
            h_med,
            h_max,
            hint: hint?,
            near,
            filter: StaticFilter::of_points(mesh.points()),
        })
    }
}

/// Points of the BCC lattice of cube side `step` over the domain's box (infinite for
/// an unusable step).
fn lattice_points(domain: &Domain, step: f64) -> f64 {
    if !(step > 0.0 && step.is_finite()) {
        return f64::INFINITY;
    }
    let n = ((domain.hi - domain.lo) / step).floor() + Point::ONE;
    2.0 * n.x * n.y * n.z
}

/// The candidates of the lattice level of size `h_ref` (whose [`lattice_points`] the
/// caller has bounded). The sizes at all the lattice points come first, interpolated
/// in `grid`, so that the size variation to the six neighbours is read, not looked up
/// again; a kept seed's own size is looked up in `field` (bunny00: the seed lattices
/// 2.5 s -> 1.35 s with the sizes read once, -> 1.12 s interpolated).
fn level(
    fm: &FieldMesh,
    domain: &Domain,
    field: &dyn SizeField,
    (grid, sides): (&SizeGrid, Option<&Sides>),
    params: &FrontParams,
    h_ref: f64,
) -> Vec<Candidate> {
    let extent = domain.hi - domain.lo;
    let step = params.seed_spacing * h_ref;
    let n = ((extent / step).floor() + Point::ONE).as_uvec3();
    let (nx, ny, nz) = (n.x as usize, n.y as usize, n.z as usize);
    // The lattice centred in the box; `s` picks the cube corners (0) or centres (1).
    let origin = domain.lo + (extent - (n.as_dvec3() - Point::ONE) * step) * 0.5;
    let at = |i: usize, j: usize, k: usize, s: usize| {
        let a = Point::new(i as f64, j as f64, k as f64) + 0.5 * s as f64;
        origin + (a + jitter(a)) * step
    };
    let index = |i: usize, j: usize, s: usize| (j * nx + i) * 2 + s;
    let band = LEVEL_RATIO.sqrt();
    // A point whose size cannot be in the band (every cell its jittered position may
    // fall in has all its node sizes out of it) is not interpolated: NaN stands for
    // "out of the band" (bunny00: most of the finest level's points).
    let sizes: Vec<Vec<f64>> = (0..nz)
        .into_par_iter()
        .map(|k| {
            let mut h = Vec::with_capacity(nx * ny * 2);
            for j in 0..ny {
                for i in 0..nx {
                    for s in 0..2 {
                        // A point known to be outside the domain is neither screened
                        // nor interpolated (the grid of sides answers first: bunny00's
                        // front 5.05 -> 4.90 s): NaN drops it below, and a neighbour's
                        // test that needs its size interpolates it then.
                        let p = at(i, j, k, s);
                        let out = sides.and_then(|m| m.inside(p)) == Some(false);
                        let screened = || {
                            let a = Point::new(i as f64, j as f64, k as f64) + 0.5 * s as f64;
                            let reach = Point::splat(JITTER);
                            let (lo, hi) =
                                (origin + (a - reach) * step, origin + (a + reach) * step);
                            grid.may_be_in(lo, hi, h_ref / band, h_ref * band)
                        };
                        h.push(if !out && screened() {
                            grid.at(p)
                        } else {
                            f64::NAN
                        });
                    }
                }
            }
            h
        })
        .collect();
    // The sizes of the neighbours (the uniformity test) are interpolated where the
    // screen above left them out.
    let size = |i: Option<usize>, j: Option<usize>, k: Option<usize>, s: usize| {
        let (i, j, k) = (i?, j?, k?);
        (i < nx && j < ny).then_some(())?;
        let h = sizes.get(k).map(|slice| slice[index(i, j, s)])?;
        Some(if h.is_nan() {
            grid.at(at(i, j, k, s))
        } else {
            h
        })
    };
    let slices: Vec<Vec<Candidate>> = (0..nz)
        .into_par_iter()
        .map(|k| {
            let mut out = Vec::new();
            // Slices in parallel, each with its own walks (deterministic: the slices
            // are fixed, whatever the threads).
            let mut hint = 0u32;
            let mut locator = Kernel::new();
            locator.set_filter(domain.filter);
            // Per lattice column, where the last location in it ended: the next point
            // tested in that column is a row or a few away (the last location overall
            // may be rows away).
            let mut column: Vec<Option<TetId>> = vec![None; nx * 2];
            let mut inside = |p: Point, c: usize| {
                if let Some(known) = sides.and_then(|m| m.inside(p)) {
                    return known;
                }
                if let Some(t) = column[c] {
                    locator.set_hint(t);
                }
                let at = locator.locate_next(&fm.mesh, p);
                match at {
                    Location::InTet(t) => {
                        column[c] = Some(t);
                        fm.cons.region.get(t.index()).is_some_and(|&r| r != 0)
                    }
                    _ => false,
                }
            };
            for j in 0..ny {
                for i in 0..nx {
                    for s in 0..2 {
                        let h = sizes[k][index(i, j, s)];
                        // Most points are out of the level's band: their position (its
                        // jitter) is not needed.
                        if !(h * band >= h_ref && h < h_ref * band) {
                            continue;
                        }
                        // The size at the six neighbours (none past the lattice: no seed).
                        let uniform = || {
                            let (a, b, c) = (Some(i), Some(j), Some(k));
                            [
                                size(i.checked_sub(1), b, c, s),
                                size(Some(i + 1), b, c, s),
                                size(a, j.checked_sub(1), c, s),
                                size(a, Some(j + 1), c, s),
                                size(a, b, k.checked_sub(1), s),
                                size(a, b, Some(k + 1), s),
                            ]
                            .iter()
                            .all(|x| x.is_some_and(|x| (x - h).abs() <= MAX_VARIATION * h))
                        };
                        // Cheapest first, then the most selective (bunny00: of the
                        // 1.16 M points in their band, 76 % have uniform sizes, 20 % of
                        // those are inside, and 92 % clear the vertices): the clearance
                        // search runs for 0.18 M points, not 1.16 M.
                        if !uniform() {
                            continue;
                        }
                        let p = at(i, j, k, s);
                        if !(p.is_finite() && inside(p, 2 * i + s) && !domain.near.any_close(p, h))
                        {
                            continue;
                        }
                        // The interpolated sizes smooth the field out: the tests again
                        // on the field itself (fandisk-in-box: worst Q_K 17 -> 144
                        // without).
                        let h = field.size(p, &mut hint);
                        let fits = h * band >= h_ref && h < h_ref * band;
                        let mut near = hint;
                        let mut uniform = || {
                            [Point::X, Point::Y, Point::Z].iter().all(|&e| {
                                [p + e * step, p - e * step].iter().all(|&q| {
                                    (field.size(q, &mut near) - h).abs() <= MAX_VARIATION * h
                                })
                            })
                        };
                        if fits && uniform() {
                            out.push(Candidate {
                                p,
                                h,
                                hf: h,
                                k2: domain.hint,
                                layer: 0,
                                delta_f: params.seed_clearance,
                                delta_v: params.seed_clearance,
                                exempt_from: u32::MAX,
                                hint,
                            });
                        }
                    }
                }
            }
            out
        })
        .collect();
    slices.concat()
}

/// Sizes at the nodes of a regular grid over the domain's box, one lookup each (one
/// walk per slice), read by trilinear interpolation: the lattices' tests need sizes at
/// every lattice point of every level, and most of those points are dropped. The grid
/// only screens the lattice points (a kept seed's size and its neighbours' are looked
/// up in the field itself), so its spacing is the lattice step of the median size,
/// not of the finest level (whose step made 54-58 k nodes on elephant, knot2 and
/// fandisk, for levels that gave 0, 0 and 48 seeds): the seed candidates elephant
/// 15.8 -> 10.9 ms, knot2 23 -> 17 ms, fandisk 32 -> 19 ms, bunny00 0.75 -> 0.63 s;
/// the seeds 46 -> 39, 215 -> 214, 3039 -> 3041, 132660 -> 131645, and before the
/// optimisation elephant's front takes 11 iterations instead of 8 (% Q_K < 3 95.78 ->
/// 95.66), the other models' figures within 0.3 points; after it the same worst
/// `Q_K` and smallest dihedral angle on the ci models but fandisk-in-box (whose worst
/// over nine perturbed runs is as spread as before: 14.75-18.98 against 14.75-20.49).
struct SizeGrid {
    origin: Point,
    step: f64,
    n: [usize; 3],
    h: Vec<f64>,
    /// Per cell (`n - 1` per axis, x fastest): the smallest and largest size at its
    /// eight nodes, which bound the trilinear sizes inside it.
    range: Vec<(f64, f64)>,
}

impl SizeGrid {
    fn new(domain: &Domain, field: &dyn SizeField, step: f64) -> SizeGrid {
        let extent = domain.hi - domain.lo;
        let n = ((extent / step).ceil() + Point::splat(1.0)).max(Point::splat(2.0));
        let n = [n.x as usize, n.y as usize, n.z as usize];
        let origin = domain.lo;
        let h: Vec<f64> = (0..n[2])
            .into_par_iter()
            .map(|k| {
                // Each row starts from where the row before started (its neighbour),
                // not from where it ended (a walk across the box per row).
                let mut row = 0u32;
                let mut out = Vec::with_capacity(n[0] * n[1]);
                for j in 0..n[1] {
                    let mut hint = row;
                    for i in 0..n[0] {
                        let p = origin + Point::new(i as f64, j as f64, k as f64) * step;
                        out.push(field.size(p, &mut hint));
                        if i == 0 {
                            row = hint;
                        }
                    }
                }
                out
            })
            .flatten()
            .collect();
        let range = cell_ranges(&h, n);
        SizeGrid {
            origin,
            step,
            n,
            h,
            range,
        }
    }

    /// The cell of grid coordinate `x` along an axis of `n` nodes, as [`SizeGrid::at`]
    /// picks it (clamped to the grid).
    fn cell_index(x: f64, n: usize) -> usize {
        (x.clamp(0.0, (n - 1) as f64).floor() as usize).min(n - 2)
    }

    /// False only when [`SizeGrid::at`] is below `lo_size` or above `hi_size` (both
    /// with a relative margin of 1e-9, far above the rounding of the interpolation) at
    /// every point of the box `[lo, hi]`: each cell the box meets has all its node
    /// sizes on one side of the band. A NaN node size never rules a cell out.
    fn may_be_in(&self, lo: Point, hi: Point, lo_size: f64, hi_size: f64) -> bool {
        let (a, b) = (
            (lo - self.origin) / self.step,
            (hi - self.origin) / self.step,
        );
        let [nx, ny, nz] = self.n;
        let span = |a: f64, b: f64, n: usize| Self::cell_index(a, n)..=Self::cell_index(b, n);
        let (below, above) = (lo_size * (1.0 - 1e-9), hi_size * (1.0 + 1e-9));
        span(a.z, b.z, nz).any(|k| {
            span(a.y, b.y, ny).any(|j| {
                span(a.x, b.x, nx).any(|i| {
                    let (min, max) = self.range[(k * (ny - 1) + j) * (nx - 1) + i];
                    !(max < below || min > above)
                })
            })
        })
    }

    /// The size at `p`, trilinear in its cell (clamped to the grid).
    fn at(&self, p: Point) -> f64 {
        let g = (p - self.origin) / self.step;
        let cell = |x: f64, n: usize| {
            let x = x.clamp(0.0, (n - 1) as f64);
            let i = (x.floor() as usize).min(n - 2);
            (i, x - i as f64)
        };
        let (i, u) = cell(g.x, self.n[0]);
        let (j, v) = cell(g.y, self.n[1]);
        let (k, w) = cell(g.z, self.n[2]);
        let node = |a: usize, b: usize, c: usize| {
            self.h[((k + c) * self.n[1] + j + b) * self.n[0] + i + a]
        };
        let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
        let face = |c: usize| {
            lerp(
                lerp(node(0, 0, c), node(1, 0, c), u),
                lerp(node(0, 1, c), node(1, 1, c), u),
                v,
            )
        };
        lerp(face(0), face(1), w)
    }
}

/// The smallest and largest of the eight node sizes of each cell of a grid of `n`
/// nodes per axis (x fastest); NaN when a node size is NaN.
fn cell_ranges(h: &[f64], n: [usize; 3]) -> Vec<(f64, f64)> {
    let [nx, ny, nz] = n;
    let mut out = Vec::with_capacity((nx - 1) * (ny - 1) * (nz - 1));
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let mut r = (f64::INFINITY, f64::NEG_INFINITY);
                for (a, b, c) in (0..8).map(|m| (m & 1, m >> 1 & 1, m >> 2)) {
                    let x = h[((k + c) * ny + j + b) * nx + i + a];
                    r = if x.is_nan() || r.0.is_nan() {
                        (f64::NAN, f64::NAN)
                    } else {
                        (r.0.min(x), r.1.max(x))
                    };
                }
                out.push(r);
            }
        }
    }
    out
}

/// A pseudo-random offset in `[-JITTER, JITTER]^3` for the lattice point at `at`: in a
/// partly inserted lattice the cube corners are cospherical eight at a time, where
/// the exact predicates would decide every test.
fn jitter(at: Point) -> Point {
    let key = (at.x * 2.0) as u64 ^ ((at.y * 2.0) as u64) << 21 ^ ((at.z * 2.0) as u64) << 42;
    let mut rng = SplitMix64::new(key ^ 0x9E37_79B9_7F4A_7C15);
    let mut next = || rng.unit() * 2.0 - 1.0;
    Point::new(next(), next(), next()) * JITTER
}

/// Largest offset of a seed from its lattice point, in lattice steps.
const JITTER: f64 = 0.03;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::delaunay::sort::SplitMix64;

    /// The screen of the lattice points is exact: wherever `may_be_in` rules a box out,
    /// the interpolated size at every point of the box is out of the band.
    #[test]
    fn a_box_ruled_out_holds_no_size_in_the_band() {
        let mut rng = SplitMix64::new(7);
        let mut u = || rng.unit();
        let n = [5, 4, 3];
        let h: Vec<f64> = (0..n[0] * n[1] * n[2]).map(|_| 0.5 + u()).collect();
        let range = cell_ranges(&h, n);
        let grid = SizeGrid {
            origin: Point::new(-1.0, 0.5, 2.0),
            step: 0.25,
            n,
            h,
            range,
        };
        let (mut ruled_out, mut checked) = (0, 0);
        for _ in 0..2000 {
            // Boxes inside the grid and past its ends (clamped like `at`).
            let c = grid.origin + Point::new(u() * 1.6 - 0.3, u() * 1.2 - 0.3, u() * 0.9 - 0.3);
            let r = Point::splat(u() * 0.05);
            let (lo_size, hi_size) = (0.5 + u(), 0.0);
            let hi_size = hi_size + lo_size * (1.0 + u() * 0.3);
            if grid.may_be_in(c - r, c + r, lo_size, hi_size) {
                continue;
            }
            ruled_out += 1;
            for _ in 0..20 {
                let p = c + Point::new(u() * 2.0 - 1.0, u() * 2.0 - 1.0, u() * 2.0 - 1.0) * r;
                let s = grid.at(p);
                assert!(s < lo_size || s > hi_size, "{s} in [{lo_size}, {hi_size}]");
                checked += 1;
            }
        }
        assert!(ruled_out > 100 && checked > 2000, "{ruled_out} {checked}");
    }

    /// A NaN node size never rules a cell out.
    #[test]
    fn a_nan_size_keeps_its_cells() {
        let n = [2, 2, 2];
        let mut h = vec![10.0; 8];
        h[3] = f64::NAN;
        let range = cell_ranges(&h, n);
        let grid = SizeGrid {
            origin: Point::ZERO,
            step: 1.0,
            n,
            h,
            range,
        };
        assert!(grid.may_be_in(Point::splat(0.4), Point::splat(0.6), 1.0, 2.0));
        let fine = SizeGrid {
            h: vec![10.0; 8],
            range: cell_ranges(&[10.0; 8], n),
            ..grid
        };
        assert!(!fine.may_be_in(Point::splat(0.4), Point::splat(0.6), 1.0, 2.0));
    }
}
