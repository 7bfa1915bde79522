//! Filtration of the field points (paper §5.2): a point `Q` is dropped when a point `P`
//! already kept has `l(PQ) < delta_f` (NOTES.md §5, default `1/sqrt(2)`).
//!
//! Existing mesh vertices can be registered too ([`Grid::add_vertex`]): a point closer
//! than `delta_v` to one of them is dropped here, before the kernel builds its cavity.
//!
//! The search goes through uniform grids (a dense array of cells over the points' box,
//! or a hash map when that box has too many cells), never all pairs. Since `h` is linear along
//! `PQ`, `l(PQ) >= |PQ| / max(h_P, h_Q)`, so a close pair is closer than `delta_f`
//! times the larger size: a kept point is registered in its own cell, and a query looks
//! at the cells within that radius. The points of size up to `h_small` (the caller's
//! choice, e.g. the 99th percentile) are in cells of side `delta * h_small`, the rest in
//! cells of side `delta * h_max` ([`Grid`]); spans are clipped at [`MAX_SPAN`] cells
//! per axis, which `h_small >= h_max / MAX_SPAN` never reaches.
//!
//! Filtration by merging (not in the paper; [`Grid::keep_or_merge`], [`Clusters`]):
//! instead of being dropped, a point too close to kept points only joins the nearest
//! of them, and each kept point then moves to the mean of the points that joined it
//! (the caller gives it the field's size there and filters the moved points again,
//! measured with at most their cluster's mean size, in the same order,
//! since the means of neighbouring clusters may come closer than `delta_f`). Neighbouring
//! front faces propose points a fraction of a size apart (the optimal points of two
//! faces that share an edge, `0.58 h` apart on a regular surface); the paper keeps the
//! first along the filtration order, which lies over its own face, and the faces around
//! it get an apex off their ideal one. The mean lies between the ideal apexes of the
//! faces it serves, and the second filtration thins the layer where the first left it
//! denser than `delta_f` requires.

use crate::geom::{Aabb, Point};
use crate::quality::length::normalized_length;
use crate::FastMap;

/// Kept points checked first, most recent first (see [`Grid::try_keep`]).
const RECENT: usize = 16;

/// Cells per axis on each side of a point's own cell, at most.
pub const MAX_SPAN: i64 = 8;

/// Bits per axis of a packed cell key: cells farther apart than `2^21` along an axis
/// may share a key, which only lengthens a chain (the distances are checked anyway).
const KEY_BITS: u32 = 21;

/// Sizes within this ratio of the largest go to one level: the 8 cells of a second
/// level cost more than the few more entries per cell.
const ONE_LEVEL_RATIO: f64 = 1.25;

/// A level is a dense array of cells when it has at most this many cells per point
/// expected (or [`DENSE_MIN_CELLS`]), and a hash map otherwise (a box much larger
/// than the points' sizes).
const DENSE_CELLS_PER_POINT: usize = 16;

/// Cells a dense level may always have.
const DENSE_MIN_CELLS: usize = 1 << 16;

/// End of a chain of entries.
const NONE: u32 = u32::MAX;

/// The heads of the cells' chains: a dense array over a box of cells (cells outside
/// are clamped to its border: that only lengthens the border's chains), or a hash map.
#[derive(Debug)]
enum Heads {
    Dense {
        lo: [i64; 3],
        dims: [i64; 3],
        heads: Vec<u32>,
    },
    Hashed(FastMap<u64, u32>),
}

impl Heads {
    /// The slot of cell `c`: its index in the dense array or its packed key.
    fn slot(&self, c: [i64; 3]) -> u64 {
        match self {
            Heads::Dense { lo, dims, .. } => {
                let k: [i64; 3] = std::array::from_fn(|i| (c[i] - lo[i]).clamp(0, dims[i] - 1));
                ((k[2] * dims[1] + k[1]) * dims[0] + k[0]) as u64
            }
            Heads::Hashed(_) => {
                let m = (1u64 << KEY_BITS) - 1;
                (c[0] as u64 & m)
                    | (c[1] as u64 & m) << KEY_BITS
                    | (c[2] as u64 & m) << (2 * KEY_BITS)
            }
        }
    }

    fn get(&self, slot: u64) -> u32 {
        match self {
            Heads::Dense { heads, .. } => heads[slot as usize],
            Heads::Hashed(map) => map.get(&slot).copied().unwrap_or(NONE),
        }
    }

    /// Makes `e` the head of `slot`; returns the previous head.
    fn replace(&mut self, slot: u64, e: u32) -> u32 {
        match self {
            Heads::Dense { heads, .. } => std::mem::replace(&mut heads[slot as usize], e),
            Heads::Hashed(map) => map.insert(slot, e).unwrap_or(NONE),
        }
    }
}

/// One uniform level of the grid: cells of side `cell`, each the head of a chain of
/// entries (one array or hash lookup per cell, no allocation per cell).
#[derive(Debug)]
struct Level {
    cell: f64,
    heads: Heads,
    /// Per entry: its id and the next entry of its cell.
    links: Vec<(u32, u32)>,
}

impl Level {
    /// A level of cells of side `cell`, dense over `bounds` when that box has few
    /// enough cells for `points` entries.
    fn new(cell: f64, bounds: Option<Aabb>, points: usize) -> Level {
        let cell = cell.max(f64::MIN_POSITIVE);
        let mut level = Level {
            cell,
            heads: Heads::Hashed(FastMap::default()),
            links: Vec::new(),
        };
        if let Some(bb) = bounds {
            let lo = [bb.min.x, bb.min.y, bb.min.z].map(|c| level.key(c));
            let hi = [bb.max.x, bb.max.y, bb.max.z].map(|c| level.key(c));
            let dims: [i64; 3] = std::array::from_fn(|i| hi[i] - lo[i] + 1);
            let limit = points
                .saturating_mul(DENSE_CELLS_PER_POINT)
                .max(DENSE_MIN_CELLS);
            let cells = dims
                .iter()
                .try_fold(1usize, |n, &d| n.checked_mul(usize::try_from(d).ok()?));
            if let Some(n) = cells.filter(|&n| n <= limit) {
                level.heads = Heads::Dense {
                    lo,
                    dims,
                    heads: vec![NONE; n],
                };
            }
        }
        level
    }

    fn key(&self, x: f64) -> i64 {
        let k = (x / self.cell).floor();
        if k.is_finite() {
            k.clamp(-1e15, 1e15) as i64
        } else {
            0
        }
    }

    fn cell_of(&self, p: Point) -> [i64; 3] {
        [p.x, p.y, p.z].map(|c| self.key(c))
    }

    /// The cell range of the box of half-side `r` around `p` (2 cells per axis when
    /// `r` is at most a cell, not 3 around the point's own), clipped to [`MAX_SPAN`]
    /// cells on each side of its own.
    fn range(&self, p: Point, r: f64) -> [(i64, i64); 3] {
        [p.x, p.y, p.z].map(|c| {
            let k = self.key(c);
            let lo = self.key(c - r).clamp(k - MAX_SPAN, k);
            let hi = self.key(c + r).clamp(k, k + MAX_SPAN);
            (lo, hi)
        })
    }

    /// True when `near` holds for an entry of the cell at `slot`.
    fn any_in(&self, slot: u64, near: &impl Fn(u32) -> bool) -> bool {
        let mut e = self.heads.get(slot);
        while e != NONE {
            let (id, next) = self.links[e as usize];
            if near(id) {
                return true;
            }
            e = next;
        }
        false
    }

    /// True when `near` holds for an entry of some cell within `r` of `p` (the point's
    /// own cell first).
    fn any_within(&self, p: Point, r: f64, near: impl Fn(u32) -> bool) -> bool {
        if self.links.is_empty() {
            return false;
        }
        let own = self.heads.slot(self.cell_of(p));
        if self.any_in(own, &near) {
            return true;
        }
        let rg = self.range(p, r);
        for x in rg[0].0..=rg[0].1 {
            for y in rg[1].0..=rg[1].1 {
                for z in rg[2].0..=rg[2].1 {
                    let slot = self.heads.slot([x, y, z]);
                    if slot != own && self.any_in(slot, &near) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Calls `f` on every entry of the cells within `r` of `p`.
    fn each_within(&self, p: Point, r: f64, f: &mut impl FnMut(u32)) {
        if self.links.is_empty() {
            return;
        }
        let rg = self.range(p, r);
        for x in rg[0].0..=rg[0].1 {
            for y in rg[1].0..=rg[1].1 {
                for z in rg[2].0..=rg[2].1 {
                    let mut e = self.heads.get(self.heads.slot([x, y, z]));
                    while e != NONE {
                        let (id, next) = self.links[e as usize];
                        f(id);
                        e = next;
                    }
                }
            }
        }
    }

    fn add(&mut self, p: Point, id: u32) {
        let e = self.links.len() as u32;
        let next = self.heads.replace(self.heads.slot(self.cell_of(p)), e);
        self.links.push((id, next));
    }
}

/// Grid of the kept points and registered vertices, in two levels: entries of size at
/// most `h_small` in cells of side `D h_small`, larger ones in cells of side
/// `D h_max` (`D` the larger of the two distances). A close pair is closer than `D`
/// times the larger of its sizes, so a query looks at the small level within
/// `D max(h, h_small)` and at the large level within `D h_max`. Most points are small:
/// their cells hold a few neighbours instead of everything within the largest size.
#[derive(Debug)]
pub struct Grid {
    delta_f: f64,
    delta_v: f64,
    h_small: f64,
    h_max: f64,
    small: Level,
    big: Level,
    kept: Vec<(Point, f64)>,
    vertices: Vec<(Point, f64)>,
}

/// What [`Grid::keep_or_merge`] did with a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filtered {
    /// Kept, with this id (its index in [`Grid::kept`]).
    Kept(u32),
    /// Dropped for kept points only: the nearest of them (normalised length).
    Near(u32),
    /// Dropped for a registered vertex (or kept points, when not asked for the
    /// nearest).
    Dropped,
}

/// Bit set on a cell entry that refers to [`Grid::vertices`] rather than a kept point.
const VERTEX_BIT: u32 = 1 << 31;

impl Grid {
    /// An empty grid for points of sizes at most `h_max`, with the filtration distance
    /// `delta_f` between kept points and `delta_v` to registered vertices.
    pub fn new(h_max: f64, delta_f: f64, delta_v: f64) -> Grid {
        Grid::with_sizes(h_max, h_max, delta_f, delta_v, None)
    }

    /// [`Grid::new`] with the small level for sizes up to `h_small` (clamped to
    /// `[h_max / MAX_SPAN, h_max]`, so that no query span is ever clipped), and
    /// `bounds` the box of the points to come with their number (dense levels when
    /// that box has few enough cells; the points may still lie anywhere).
    pub fn with_sizes(
        h_small: f64,
        h_max: f64,
        delta_f: f64,
        delta_v: f64,
        bounds: Option<(Aabb, usize)>,
    ) -> Grid {
        let d = delta_f.max(delta_v);
        let h_small = if h_small * ONE_LEVEL_RATIO >= h_max {
            h_max
        } else {
            h_small.max(h_max / MAX_SPAN as f64)
        };
        Grid {
            delta_f,
            delta_v,
            h_small,
            h_max,
            small: Level::new(d * h_small, bounds.map(|b| b.0), bounds.map_or(0, |b| b.1)),
            big: Level::new(d * h_max, None, 0),
            kept: Vec::new(),
            vertices: Vec::new(),
        }
    }

    fn level_mut(&mut self, h: f64) -> &mut Level {
        if h <= self.h_small {
            &mut self.small
        } else {
            &mut self.big
        }
    }

    /// Registers an existing vertex (size `h <= h_max`): later points closer than
    /// `delta_v` to it are dropped.
    pub fn add_vertex(&mut self, p: Point, h: f64) {
        if self.vertices.len() as u32 >= VERTEX_BIT - 1 {
            return;
        }
        let id = self.vertices.len() as u32 | VERTEX_BIT;
        self.vertices.push((p, h));
        self.level_mut(h).add(p, id);
    }

    /// Keeps `p` (size `h`) unless a kept point is closer than `delta_f` or a vertex
    /// closer than `delta_v` (each at most the grid's); returns whether it was kept.
    pub fn try_keep(&mut self, p: Point, h: f64, delta_f: f64, delta_v: f64) -> bool {
        let delta_f = delta_f.min(self.delta_f);
        let delta_v = delta_v.min(self.delta_v);
        // The last points kept first: the candidates come along a space-filling curve,
        // so a close kept point is most often a recent one.
        let recent = self.kept.len().saturating_sub(RECENT);
        if self.kept[recent..]
            .iter()
            .any(|&(q, hq)| close(p, q, h, hq, delta_f))
        {
            return false;
        }
        if self.close_to_any(p, h, delta_f, delta_v) {
            return false;
        }
        self.push_kept(p, h);
        true
    }

    /// Registers `p` (size `h`) as kept; returns its id.
    fn push_kept(&mut self, p: Point, h: f64) -> u32 {
        let id = self.kept.len() as u32;
        self.kept.push((p, h));
        self.level_mut(h).add(p, id);
        id
    }

    /// [`Grid::try_keep`]; with `merge`, a point dropped for kept points only (no
    /// registered vertex closer than `delta_v`) names one of them: the nearest of the
    /// [`RECENT`] most recent kept points when one is close (the candidates come along a
    /// space-filling curve), else the nearest in reach (normalised length, then the
    /// lowest id).
    pub fn keep_or_merge(
        &mut self,
        p: Point,
        h: f64,
        delta_f: f64,
        delta_v: f64,
        merge: bool,
    ) -> Filtered {
        if !merge {
            return if self.try_keep(p, h, delta_f, delta_v) {
                Filtered::Kept(self.kept.len() as u32 - 1)
            } else {
                Filtered::Dropped
            };
        }
        let delta_f = delta_f.min(self.delta_f);
        let delta_v = delta_v.min(self.delta_v);
        if !self.vertices.is_empty() && self.vertex_close(p, h, delta_v) {
            return Filtered::Dropped;
        }
        let recent = self.kept.len().saturating_sub(RECENT) as u32..self.kept.len() as u32;
        let found = self
            .nearest_kept(p, h, delta_f, recent)
            .or_else(|| self.nearest_kept_in_reach(p, h, delta_f));
        match found {
            Some(k) => Filtered::Near(k),
            None => Filtered::Kept(self.push_kept(p, h)),
        }
    }

    /// The kept point of `ids` closer than `delta_f` to `p` and nearest (normalised
    /// length, then the lowest id).
    fn nearest_kept(
        &self,
        p: Point,
        h: f64,
        delta_f: f64,
        ids: impl IntoIterator<Item = u32>,
    ) -> Option<u32> {
        let mut best = None;
        for k in ids {
            self.consider(&mut best, p, h, delta_f, k);
        }
        best.map(|b: (f64, u32)| b.1)
    }

    /// [`Grid::nearest_kept`] over the kept points in the cells within reach of `p`.
    fn nearest_kept_in_reach(&self, p: Point, h: f64, delta_f: f64) -> Option<u32> {
        let mut best = None;
        let mut visit = |k: u32| {
            if k & VERTEX_BIT == 0 {
                self.consider(&mut best, p, h, delta_f, k);
            }
        };
        let d = self.delta_f.max(self.delta_v);
        self.small
            .each_within(p, d * h.max(self.h_small), &mut visit);
        self.big.each_within(p, d * h.max(self.h_max), &mut visit);
        best.map(|b| b.1)
    }

    /// Makes kept point `k` the `best` (length, id) when it is closer than `delta_f`
    /// to `p` and nearer than `best` (or as near with a lower id).
    fn consider(&self, best: &mut Option<(f64, u32)>, p: Point, h: f64, delta_f: f64, k: u32) {
        let (q, hq) = self.kept[k as usize];
        if close(p, q, h, hq, delta_f) {
            let l = normalized_length(p.distance(q), h, hq);
            if best.is_none_or(|b| (l, k) < b) {
                *best = Some((l, k));
            }
        }
    }

    /// True when a registered vertex is closer than `delta_v` to `p`.
    fn vertex_close(&self, p: Point, h: f64, delta_v: f64) -> bool {
        let near = |k: u32| {
            k & VERTEX_BIT != 0 && {
                let (q, hq) = self.vertices[(k & !VERTEX_BIT) as usize];
                close(p, q, h, hq, delta_v)
            }
        };
        let d = self.delta_f.max(self.delta_v);
        self.small.any_within(p, d * h.max(self.h_small), near)
            || self.big.any_within(p, d * h.max(self.h_max), near)
    }

    /// True when a kept point is closer than the grid's `delta_f` or a registered
    /// vertex closer than its `delta_v` to `p` (size `h`); nothing is kept.
    pub fn any_close(&self, p: Point, h: f64) -> bool {
        self.close_to_any(p, h, self.delta_f, self.delta_v)
    }

    /// The search of the cells within reach of `p` (the grid's larger distance).
    fn close_to_any(&self, p: Point, h: f64, delta_f: f64, delta_v: f64) -> bool {
        let near = |k: u32| {
            let ((q, hq), limit) = if k & VERTEX_BIT != 0 {
                (self.vertices[(k & !VERTEX_BIT) as usize], delta_v)
            } else {
                (self.kept[k as usize], delta_f)
            };
            close(p, q, h, hq, limit)
        };
        let d = self.delta_f.max(self.delta_v);
        self.small.any_within(p, d * h.max(self.h_small), near)
            || self.big.any_within(p, d * h.max(self.h_max), near)
    }

    /// The points kept so far, in order.
    pub fn kept(&self) -> &[(Point, f64)] {
        &self.kept
    }
}

/// `l(PQ) < limit`, the logarithm of [`normalized_length`] only when the bounds
/// `|PQ| / max(h) <= l <= |PQ| / min(h)` do not decide it.
#[inline]
pub fn close(p: Point, q: Point, hp: f64, hq: f64, limit: f64) -> bool {
    let d2 = p.distance_squared(q);
    let far = limit * hp.max(hq);
    if d2 >= far * far {
        return false;
    }
    let near = limit * hp.min(hq);
    if d2 < near * near {
        return true;
    }
    normalized_length(d2.sqrt(), hp, hq) < limit
}

/// The points merged into each kept point of a [`Grid`] ([`Filtered::Near`]): per kept
/// id, the sums of their positions and of the sizes they were filtered with, and their
/// number, its own included.
#[derive(Debug, Default)]
pub struct Clusters {
    sums: Vec<(Point, f64, u32)>,
}

impl Clusters {
    /// Records what the filtration did with `p` (size `h`); every point the grid kept
    /// must be recorded, in order.
    pub fn add(&mut self, what: Filtered, p: Point, h: f64) {
        match what {
            Filtered::Kept(k) => {
                debug_assert_eq!(k as usize, self.sums.len(), "kept points recorded in order");
                self.sums.push((p, h, 1));
            }
            Filtered::Near(k) => {
                if let Some(s) = self.sums.get_mut(k as usize) {
                    s.0 += p;
                    s.1 += h;
                    s.2 += 1;
                }
            }
            Filtered::Dropped => {}
        }
    }

    /// The kept points that moved, in id order: (id, mean position, mean size of its
    /// cluster). The means may lie closer than `delta_f` to one another: the caller
    /// filters the moved points again.
    pub fn moves(&self) -> Vec<(u32, Point, f64)> {
        let mut out = Vec::new();
        for (k, &(sum_p, sum_h, n)) in self.sums.iter().enumerate() {
            let (p, h) = (sum_p / f64::from(n), sum_h / f64::from(n));
            if n > 1 && p.is_finite() && h > 0.0 && h.is_finite() {
                out.push((k as u32, p, h));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_kept_pair_is_closer_than_delta_f() {
        let delta_f = std::f64::consts::FRAC_1_SQRT_2;
        let unit = Aabb {
            min: Point::ZERO,
            max: Point::ONE,
        };
        let half = Aabb {
            min: Point::splat(0.25),
            max: Point::splat(0.75),
        };
        // One level, and two (sizes above 0.1 in the large cells).
        for mut g in [
            Grid::new(0.2, delta_f, delta_f),
            Grid::with_sizes(0.1, 0.2, delta_f, delta_f, None),
            Grid::with_sizes(0.1, 0.2, delta_f, delta_f, Some((unit, 3000))),
            // A dense box smaller than the points' (clamped cells).
            Grid::with_sizes(0.1, 0.2, delta_f, delta_f, Some((half, 3000))),
        ] {
            // Pseudo-random points with sizes varying by a factor 4.
            let mut s = 12345u64;
            let mut rnd = || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                (s >> 11) as f64 / (1u64 << 53) as f64
            };
            let mut all = Vec::new();
            for _ in 0..3000 {
                let p = Point::new(rnd(), rnd(), rnd());
                let h = 0.05 + 0.15 * p.x;
                all.push((p, h, g.try_keep(p, h, delta_f, delta_f)));
            }
            let kept = g.kept();
            assert!(kept.len() > 50 && kept.len() < 3000);
            for i in 0..kept.len() {
                for j in i + 1..kept.len() {
                    let (p, hp) = kept[i];
                    let (q, hq) = kept[j];
                    assert!(normalized_length(p.distance(q), hp, hq) >= delta_f);
                }
            }
            // Every dropped point has a kept point closer than delta_f.
            for (p, h, k) in all {
                if !k {
                    assert!(kept
                        .iter()
                        .any(|&(q, hq)| normalized_length(p.distance(q), h, hq) < delta_f));
                }
            }
        }
    }

    #[test]
    fn registered_vertices_drop_points_within_delta_v_only() {
        let mut g = Grid::new(1.0, 0.5, 0.9);
        g.add_vertex(Point::ZERO, 1.0);
        // 0.8 from the vertex: inside delta_v = 0.9, dropped.
        assert!(!g.try_keep(Point::new(0.8, 0.0, 0.0), 1.0, 0.5, 0.9));
        // A per-point delta_v of 0.7 (a boundary face's point) keeps it.
        assert!(g.try_keep(Point::new(0.8, 0.0, 0.0), 1.0, 0.5, 0.7));
        // 0.6 from that kept point: outside delta_f = 0.5, kept; vertices are not in
        // the kept list.
        assert!(g.try_keep(Point::new(0.8, 0.6, 0.0), 1.0, 0.5, 0.5));
        assert_eq!(g.kept().len(), 2);
    }

    #[test]
    fn a_point_merges_into_the_nearest_kept_point_and_moves_it_to_the_mean() {
        let mut g = Grid::new(1.0, 0.7, 0.7);
        let mut clusters = Clusters::default();
        let mut add = |g: &mut Grid, p: Point| {
            let what = g.keep_or_merge(p, 1.0, 0.7, 0.7, true);
            clusters.add(what, p, 1.0);
            what
        };
        assert_eq!(add(&mut g, Point::ZERO), Filtered::Kept(0));
        assert_eq!(add(&mut g, Point::new(1.2, 0.0, 0.0)), Filtered::Kept(1));
        // 0.5 from the first, 0.7 from the second: merged into the first.
        assert_eq!(add(&mut g, Point::new(0.5, 0.0, 0.0)), Filtered::Near(0));
        // 0.4 from the second, 0.8 from the first.
        assert_eq!(add(&mut g, Point::new(0.8, 0.0, 0.0)), Filtered::Near(1));
        // Close to both (0.63 and 0.59): the nearer, the second.
        assert_eq!(add(&mut g, Point::new(0.62, 0.1, 0.0)), Filtered::Near(1));
        let moves = clusters.moves();
        assert_eq!(moves.len(), 2);
        assert_eq!(moves[0], (0, Point::new(0.25, 0.0, 0.0), 1.0));
        let (k, p, _) = moves[1];
        assert_eq!(k, 1);
        assert!(p.distance(Point::new(2.62 / 3.0, 0.1 / 3.0, 0.0)) < 1e-12);
        // Without merging the same point is dropped.
        assert_eq!(
            g.keep_or_merge(Point::new(0.3, 0.0, 0.0), 1.0, 0.7, 0.7, false),
            Filtered::Dropped
        );
    }

    #[test]
    fn a_point_near_a_registered_vertex_is_dropped_not_merged() {
        let mut g = Grid::new(1.0, 0.7, 0.9);
        g.add_vertex(Point::new(1.0, 0.0, 0.0), 1.0);
        assert_eq!(
            g.keep_or_merge(Point::ZERO, 1.0, 0.7, 0.9, true),
            Filtered::Kept(0)
        );
        // 0.4 from the kept point but 0.6 from the vertex (inside delta_v).
        assert_eq!(
            g.keep_or_merge(Point::new(0.4, 0.0, 0.0), 1.0, 0.7, 0.9, true),
            Filtered::Dropped
        );
    }

    /// The front's filtration with merging (`front::filtrate`): merged, moved to the
    /// means, filtered again; no two points end closer than `delta_f`.
    #[test]
    fn merged_points_filtered_again_keep_delta_f() {
        let delta_f = 0.9;
        let mut rng = crate::delaunay::sort::SplitMix64::new(777);
        let mut rnd = || rng.unit();
        let pts: Vec<(Point, f64)> = (0..2000)
            .map(|_| {
                let p = Point::new(rnd(), rnd(), rnd());
                (p, 0.05 + 0.1 * p.y)
            })
            .collect();
        let mut g = Grid::new(0.15, delta_f, delta_f);
        let mut clusters = Clusters::default();
        let mut kept = Vec::new();
        for &(p, h) in &pts {
            let what = g.keep_or_merge(p, h, delta_f, delta_f, true);
            clusters.add(what, p, h);
            if let Filtered::Kept(_) = what {
                kept.push((p, h));
            }
        }
        let moves = clusters.moves();
        assert!(!moves.is_empty(), "some points merge");
        for (k, p, h) in moves {
            kept[k as usize] = (p, h);
        }
        let mut g = Grid::new(0.15, delta_f, delta_f);
        kept.retain(|&(p, h)| g.try_keep(p, h, delta_f, delta_f));
        assert!(kept.len() > 50);
        for i in 0..kept.len() {
            for j in i + 1..kept.len() {
                let ((p, hp), (q, hq)) = (kept[i], kept[j]);
                assert!(normalized_length(p.distance(q), hp, hq) >= delta_f);
            }
        }
    }
}
