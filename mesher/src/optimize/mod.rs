//! Mesh optimisation (paper §6): the worst tets first, each improved by the first local
//! operation that lowers the worst `Q_K` around it: the collapse of one of its short
//! edges (a free end onto the other), removal of one of its edges
//! (ring re-triangulation, including the 3-2 and 4-4 flips), a 2-3 flip of one of its
//! faces, a multi-face removal (the faces between one of its vertices and the apex
//! across the opposite face replaced by the ring of the edge joining them), the
//! smoothing of one of its free vertices (§6.3.1), or, last, the insertion
//! of a point (the cone from a new point over the tet and its neighbours: slivers whose
//! four vertices lie on the boundary). Passes repeat until one improves nothing or
//! [`OptimizeOptions::max_passes`] is reached. A tet that no operation improved is not
//! tried again in those passes; polishing passes then retry, with that memory cleared,
//! the tets worse than a fraction of the current worst, and the bad tets sharing a
//! vertex with them, while the worst drops (the operations around a tet may have
//! opened a way since it failed; a flat tet between narrow walls is often freed only
//! once its neighbours have changed). Last, while it lowers the worst `Q_K` by 1 %, a
//! last resort for the worst tet: a point in a cavity grown around it when its four
//! vertices are fixed (`Ops::insert_grown_around`, then a Delaunay cavity, then the
//! wedge by one of its surface edges), else the collapse of one of its
//! free vertices onto a neighbour (`Ops::collapse`, a vertex crowded against the
//! boundary), or one point for the free vertices of a cavity grown around it
//! (`Ops::replace_grown_around`), or one point for the ring of one of its edges off the
//! surface (`Ops::split_edge_of`), or a compass search for the position of one free
//! vertex (`Ops::smooth_search`), then a polishing pass around it (the bad tets at the
//! vertices it changed).
//! Last of all, the smallest dihedral angle is widened by moving a free vertex of its
//! tet (`Ops::widen_dihedral`), as far as its ball's worst `Q_K` allows; a ball whose
//! worst is within 2 % of what its boundary faces allow (their per-face `Q_t` terms,
//! §8) may use those 2 % (and trade well-shaped tets one for one).
//!
//! Guarantees, by construction: an operation is applied only if the worst `Q_K` of the
//! tets it touches strictly drops (the widening: does not rise, except up to 1.02 times
//! the bound of the boundary faces it touches, and never above the worst `Q_K` before
//! the optimisation), so the worst `Q_K` of the mesh never rises above its value before
//! the optimisation, and the widening raises it, if at all, to at most 1.02 `Q_t`; every
//! new tet is exactly positive; constrained faces and their edges are never flipped and
//! boundary vertices never move, so the boundary and the volume are unchanged.

mod ops;

use crate::boundary::flips::Locks;
use crate::boundary::local::Local;
use crate::quality::Histogram;
use crate::tetmesh::TetMesh;
use crate::FastMap;
use ops::Ops;
use serde::Serialize;
use std::time::Instant;

/// How free vertices are moved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Smoothing {
    /// Towards the mean of the ideal points of the ball's faces (paper §6.3.1); where
    /// that does not improve the ball, towards the mean of the neighbours.
    Optimal,
    /// Towards the mean of the neighbours (for comparison).
    Laplacian,
    /// Never.
    Off,
}

/// Default bound above which a tet is worked on: 2.5. Most of the time went into the
/// tets between 2 and 2.5, which few operations improve (bunny00: 159 k tets above 2
/// after the front, 4.6 s of optimisation). Measured against 2.0 on one machine, one
/// run each: bunny00 11.4 -> 8.8 s in all, armadillo 5.7 -> 3.7 s, knot2 0.72 -> 0.34 s;
/// worst `Q_K` bunny00 2.82 -> 3.06, knot2 2.78 -> 3.01, fandisk 2.47 -> 2.90,
/// armadillo 9.40 -> 9.37 (Gmsh HXT: 5.28, 4.23, 3.64, 13.2), every fine model still
/// 100 % below 3. At 3.0 box-with-hole's worst rises to 8.7 (the tets between 2.5 and
/// 3 next to its worst one must move to free it).
pub const DEFAULT_BAD_QUALITY: f64 = 2.5;

/// Parameters of the optimisation.
#[derive(Clone, Debug, PartialEq)]
pub struct OptimizeOptions {
    /// Bound on the passes over the bad tets.
    pub max_passes: usize,
    /// Tets with `Q_K` above this are worked on (default [`DEFAULT_BAD_QUALITY`]).
    pub bad_quality: f64,
    /// Vertex smoothing variant.
    pub smoothing: Smoothing,
    /// Insert a point in a tet that no flip or move improves (the last resort).
    pub insert: bool,
    /// Bound on the polishing passes after the main ones: each retries, with a fresh
    /// memory of failures, only the tets with `Q_K` above `polish_fraction` times the
    /// current worst; they stop when the worst no longer drops.
    pub polish_passes: usize,
    /// See `polish_passes`.
    pub polish_fraction: f64,
}

impl Default for OptimizeOptions {
    fn default() -> Self {
        OptimizeOptions {
            max_passes: 8,
            bad_quality: DEFAULT_BAD_QUALITY,
            smoothing: Smoothing::Optimal,
            insert: true,
            polish_passes: 16,
            polish_fraction: 0.1,
        }
    }
}

/// What one pass did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PassStats {
    /// Tets above [`OptimizeOptions::bad_quality`] at the start of the pass.
    pub bad_tets: usize,
    /// Edges removed.
    pub edge_removals: u64,
    /// 2-3 flips.
    pub face_flips: u64,
    /// Edges collapsed.
    pub collapses: u64,
    /// Vertices moved.
    pub smoothed: u64,
    /// Points inserted.
    pub inserted: u64,
    /// Worst `Q_K` in the domain after the pass.
    pub worst: f64,
    /// Seconds.
    pub seconds: f64,
}

/// Histograms before (H1) and after (H2), and per-pass counts.
#[derive(Clone, Debug, Serialize)]
pub struct OptimizeReport {
    /// `Q_K` histogram before (H1).
    pub before: Histogram,
    /// `Q_K` histogram after (H2).
    pub after: Histogram,
    /// Worst `Q_K` before.
    pub worst_before: f64,
    /// Worst `Q_K` after.
    pub worst_after: f64,
    /// Per pass.
    pub passes: Vec<PassStats>,
    /// Seconds in all.
    pub seconds: f64,
}

/// A mesh to optimise: tets with a region each (0 = outside the domain, never touched),
/// the constrained faces (their edges are locked too) and the vertices that must not
/// move.
pub struct Domain {
    /// The mesh.
    pub mesh: TetMesh,
    /// Region per tet slot.
    pub region: Vec<u32>,
    /// Constrained faces (any vertex order).
    pub constrained: Vec<[u32; 3]>,
    /// Per vertex: true if it must not move.
    pub fixed: Vec<bool>,
}

/// Optimises the domain's tets in place; returns what it did.
pub fn optimize(domain: &mut Domain, options: &OptimizeOptions) -> OptimizeReport {
    let t0 = Instant::now();
    let locks = Locks::of_faces(&domain.constrained);
    let mesh = std::mem::take(&mut domain.mesh);
    let region = std::mem::take(&mut domain.region);
    let fixed = std::mem::take(&mut domain.fixed);
    let mut ops = Ops::new(Local::new(mesh), locks, region, fixed);
    // The Q_K of every tet, in parallel; then a scan gives the bad tets for the first
    // pass; after each pass, those at the vertices it changed are rescanned
    // (`rescan`), and a last scan gives H2.
    ops.prime_qualities();
    let (mut bad, before, worst_before) = scan(&ops, options.bad_quality);
    let mut since = ops.l.stamps.clock;
    let mut worst_after = worst_before;
    let mut passes = Vec::new();
    // Tets (sorted vertices) that no operation improved, with the clock then: not
    // tried again by the main passes, and by the polishing passes only once something
    // at their vertices has changed.
    let mut failed: FastMap<[u32; 4], u32> = FastMap::default();
    for _ in 0..options.max_passes {
        let tp = Instant::now();
        let mut stats = pass(
            &mut ops,
            options,
            options.bad_quality,
            &mut failed,
            false,
            bad.clone(),
        );
        (bad, worst_after) = rescan(&ops, bad, &mut since, options.bad_quality);
        stats.worst = worst_after;
        stats.seconds = tp.elapsed().as_secs_f64();
        let done = stats.edge_removals
            + stats.face_flips
            + stats.smoothed
            + stats.inserted
            + stats.collapses;
        passes.push(stats);
        if done == 0 {
            break;
        }
    }
    // Polishing: a tet that failed once is never retried by the main passes, though the
    // operations around it since may have opened a way (re-optimising armadillo's output
    // from scratch took its worst Q_K from 112 to 16). Retry the worst ones only, and
    // only where something changed since they failed.
    let mut worst = worst_after;
    for _ in 0..options.polish_passes {
        let tp = Instant::now();
        let bar = options.bad_quality.max(worst * options.polish_fraction);
        let mut stats = pass(&mut ops, options, bar, &mut failed, true, bad.clone());
        (bad, worst_after) = rescan(&ops, bad, &mut since, options.bad_quality);
        stats.worst = worst_after;
        stats.seconds = tp.elapsed().as_secs_f64();
        let improved = stats.worst < worst;
        worst = stats.worst;
        passes.push(stats);
        if !improved {
            break;
        }
    }
    // The last resort for the worst tet (see `last_resort`), then a polishing pass
    // around it (the bad tets at the vertices it changed), while that improves it. A
    // pass over every bad tet after each round (the bar is the bad quality whenever
    // the worst is below 25) reworked the whole mesh for one tet: couplingdown 0.70 ->
    // 0.43 s of optimisation, t13-data 0.12 -> 0.09 s, the worst Q_K the same (17.87 ->
    // 17.85, 46.09), 1.6 points fewer tets below Q_K 3 on those two (60.4 -> 58.7 %,
    // 57.2 -> 55.7 %; the best boundary-keeping peer: 44.5 %, 43.1 %).
    for _ in 0..options.polish_passes {
        let Some(&(q, t, _)) = bad
            .iter()
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
        else {
            break;
        };
        let tp = Instant::now();
        let clock = ops.l.stamps.clock;
        let Some(done) = last_resort(&mut ops, t, options) else {
            break;
        };
        ops.l.forget();
        (bad, _) = rescan(&ops, bad, &mut since, options.bad_quality);
        let around: Vec<Bad> = bad
            .iter()
            .filter(|b| ops.l.stamps.changed_since(&b.2, clock))
            .copied()
            .collect();
        let bar = options.bad_quality.max(q * options.polish_fraction);
        let mut stats = pass(&mut ops, options, bar, &mut failed, true, around);
        match done {
            LastResort::Inserted => stats.inserted += 1,
            LastResort::Moved => stats.smoothed += 1,
        }
        (bad, worst_after) = rescan(&ops, bad, &mut since, options.bad_quality);
        stats.worst = worst_after;
        stats.seconds = tp.elapsed().as_secs_f64();
        let worth = worst_after < worst * (1.0 - LAST_RESORT_GAIN);
        worst = worst_after;
        passes.push(stats);
        if !worth {
            break;
        }
    }
    let tp = Instant::now();
    // The widening never raises the mesh's worst Q_K: with the optimiser's starting
    // worst as the ceiling, anchor's ball at its face's bound took the 2 % margin, worst
    // 1411.9 (the in-domain Q_t) -> 1439.5, above Gmsh HXT's 1414.2.
    let widened = widen_smallest_angle(&mut ops, &bad, options, worst);
    let (_, after, worst_after) = scan(&ops, options.bad_quality);
    if widened > 0 {
        passes.push(PassStats {
            smoothed: widened,
            worst: worst_after,
            seconds: tp.elapsed().as_secs_f64(),
            ..PassStats::default()
        });
    }
    domain.mesh = ops.l.mesh;
    domain.region = ops.region;
    domain.fixed = ops.fixed;
    OptimizeReport {
        before,
        after,
        worst_before,
        worst_after,
        passes,
        seconds: t0.elapsed().as_secs_f64(),
    }
}

/// The last resort goes on while each round lowers the worst `Q_K` by this fraction: its
/// polishing passes add points, and on a surface-bound worst (part1: 55.83 -> 55.76,
/// Q_t 55.69) they went on for 0.1 % each and 16 % more tets.
const LAST_RESORT_GAIN: f64 = 0.01;

/// The last resort for the worst tet `t`, after the passes: a point in a cavity grown
/// around it when its four vertices are fixed (layers of face neighbours, then the
/// Delaunay cavity of a point, [`Ops::insert_delaunay_around`], then the wedge of one
/// of its surface edges, [`Ops::insert_by_surface_edge`]), else the collapse of a free vertex onto
/// a neighbour (where it lowers the ball's worst; rotor_small: a free vertex 0.003 from
/// another, in a crowd of boundary vertices, whose moves gained 0.1 % a round at Q_K
/// 2463, goes, 37.8), else a point that replaces the free vertices of a cavity grown 1-4
/// layers around it (rotor_small again, with the sizes at surface vertices corrected: a
/// free vertex nearly in the plane of four tiny boundary faces at a fold, no collapse
/// valid, 2459 -> 35.4, Q_t 32.6), else the compass search for a better position of one
/// of its free vertices. Run only on the worst tet, after the passes,
/// so that the models it does not help keep their mesh.
fn last_resort(ops: &mut Ops, t: u32, options: &OptimizeOptions) -> Option<LastResort> {
    let v = ops.l.tet(t);
    let free: Vec<u32> = v
        .into_iter()
        .filter(|&x| ops.fixed.get(x as usize) == Some(&false))
        .collect();
    if free.is_empty() {
        let done = options.insert
            && (ops.insert_grown_around(t)
                || ops.insert_delaunay_around(t)
                || ops.insert_by_surface_edge(t));
        return done.then_some(LastResort::Inserted);
    }
    // A free vertex crowded against the boundary goes, collapsed onto a neighbour, when
    // that lowers its ball's worst, or replaced with its neighbours by one new point;
    // else the search for a better position.
    let mut collapsed = || {
        free.iter().any(|&y| {
            let mut ball = Vec::new();
            ops.l.star(y, &mut ball);
            let mut nbrs: Vec<u32> = ball.iter().flat_map(|&b| ops.l.tet(b)).collect();
            nbrs.sort_unstable();
            nbrs.dedup();
            nbrs.into_iter().any(|x| x != y && ops.collapse(x, y))
        })
    };
    if collapsed()
        || (options.insert
            && (ops.replace_grown_around(t, LAST_RESORT_GAIN)
                || ops.split_edge_of(t, LAST_RESORT_GAIN)))
    {
        return Some(LastResort::Moved);
    }
    let done = options.smoothing != Smoothing::Off && free.iter().any(|&x| ops.smooth_search(x));
    done.then_some(LastResort::Moved)
}

/// Rounds of [`widen_smallest_angle`].
const WIDEN_ROUNDS: usize = 32;

/// Last of all, the smallest dihedral angle of the mesh: while one of the free vertices
/// of the tet that has it can move to widen it ([`Ops::widen_dihedral`], which keeps
/// the ball's worst `Q_K` or the 2 % margin over its boundary faces' bound, never above
/// `ceiling`, and its well-shaped tets, or at that limit their number), it moves. The
/// tet is sought among the bad tets (`Q_K` above `bad_quality`): a tet whose smallest
/// angle is `θ` has `Q_K >= α / sin(θ / 2)` (its inscribed ball lies in the wedge of
/// that angle, its centre no farther from the wedge's edge than the longest edge), so
/// every angle below `2 asin(α / bad_quality)` (9.4° at 2.5) is in a bad tet, and above
/// it the search stops. Returns the moves.
fn widen_smallest_angle(
    ops: &mut Ops,
    bad: &[Bad],
    options: &OptimizeOptions,
    ceiling: f64,
) -> u64 {
    if options.smoothing == Smoothing::Off {
        return 0;
    }
    let bar = 2.0
        * (crate::quality::ALPHA / options.bad_quality)
            .min(1.0)
            .asin();
    let bar = bar.to_degrees();
    // The bad tets, and the balls of the moved vertices (whose tets may have crossed
    // `bad_quality` without reaching 3).
    let mut angles: FastMap<u32, f64> = bad.iter().map(|b| (b.1, ops.min_dihedral(b.1))).collect();
    let mut star = Vec::new();
    let mut moves = 0;
    for _ in 0..WIDEN_ROUNDS {
        let smallest = angles
            .iter()
            .min_by(|a, b| a.1.total_cmp(b.1).then(a.0.cmp(b.0)))
            .map(|(&t, &a)| (a, t));
        let Some((angle, t)) = smallest else {
            break;
        };
        if angle.is_nan() || angle >= bar {
            break;
        }
        let Some(v) = ops
            .l
            .tet(t)
            .into_iter()
            .find(|&v| ops.widen_dihedral(v, ceiling))
        else {
            break;
        };
        ops.l.star(v, &mut star);
        for &u in &star {
            angles.insert(u, ops.min_dihedral(u));
        }
        moves += 1;
    }
    moves
}

/// What [`last_resort`] did.
enum LastResort {
    Inserted,
    Moved,
}

/// One pass over the tets above `bar`, and the bad tets (above
/// [`OptimizeOptions::bad_quality`]) that share a vertex with one, worst first. (A tet
/// far worse than the rest, say a flat one between two narrow walls, is often freed
/// only once its neighbours, bad but far less so, have changed.)
fn pass(
    ops: &mut Ops,
    options: &OptimizeOptions,
    bar: f64,
    failed: &mut FastMap<[u32; 4], u32>,
    retry_changed: bool,
    mut bad: Vec<Bad>,
) -> PassStats {
    if bar > options.bad_quality {
        let mut near = vec![false; ops.l.mesh.num_vertices()];
        for b in bad.iter().filter(|b| b.0 > bar) {
            for x in b.2 {
                near[x as usize] = true;
            }
        }
        bad.retain(|b| b.0 > bar || b.2.iter().any(|&x| near[x as usize]));
    }
    bad.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut stats = PassStats {
        bad_tets: bad.len(),
        ..PassStats::default()
    };
    for (_, t, v) in bad {
        // The tet may be gone (its slot reused) since the list was made.
        if !ops.l.mesh.is_alive(crate::tetmesh::TetId(t)) || ops.l.tet(t) != v {
            continue;
        }
        let mut key = v;
        key.sort_unstable();
        // A failed tet is skipped; with `retry_changed`, only while nothing at its
        // vertices has changed since (it would fail again: the operations are local
        // and deterministic, so skipping it changes nothing but the time).
        if let Some(&since) = failed.get(&key) {
            if !retry_changed || !ops.l.stamps.changed_since(&v, since) {
                continue;
            }
        }
        if improve(ops, t, v, options, &mut stats) {
            ops.l.forget();
        } else {
            failed.insert(key, ops.l.stamps.clock);
        }
    }
    stats
}

/// The first operation that improves the tet `t` (vertices `v`).
fn improve(
    ops: &mut Ops,
    t: u32,
    v: [u32; 4],
    options: &OptimizeOptions,
    stats: &mut PassStats,
) -> bool {
    if collapse_short_edge(ops, v) {
        stats.collapses += 1;
        return true;
    }
    for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        if ops.remove_edge(t, v[i], v[j]) {
            stats.edge_removals += 1;
            return true;
        }
    }
    for i in 0..4 {
        if ops.flip23(t, i) {
            stats.face_flips += 1;
            return true;
        }
    }
    for i in 0..4 {
        if ops.remove_faces(t, i) {
            stats.face_flips += 1;
            return true;
        }
    }
    for x in v {
        if ops.smooth(x, options.smoothing) {
            stats.smoothed += 1;
            return true;
        }
    }
    if options.insert && ops.insert_in(t) {
        stats.inserted += 1;
        return true;
    }
    false
}

/// Collapses one of the tet's short edges (shorter than [`SHORT_EDGE`] times its
/// longest), shortest first, moving a free end onto the other end.
fn collapse_short_edge(ops: &mut Ops, v: [u32; 4]) -> bool {
    let p = v.map(|x| ops.l.p(x));
    let mut edges: Vec<(f64, usize, usize)> = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
        .iter()
        .map(|&(i, j)| (p[i].distance(p[j]), i, j))
        .collect();
    let longest = edges.iter().map(|e| e.0).fold(0.0, f64::max);
    edges.retain(|e| e.0 < SHORT_EDGE * longest);
    edges.sort_by(|a, b| a.0.total_cmp(&b.0));
    edges
        .iter()
        .any(|&(_, i, j)| ops.collapse(v[i], v[j]) || ops.collapse(v[j], v[i]))
}

/// An edge of a bad tet shorter than this fraction of its longest edge is collapsed,
/// before the other operations are tried (paper §6's collapse of short edges; the
/// optimiser has no sizes, so short is relative to the tet). Against none, on one run each: couplingdown worst
/// `Q_K` 20.0 -> 17.8, fandisk-in-box 17.7 -> 15.9, box-with-hole 3.59 -> 3.32,
/// pinion 22.5 -> 22.4, the rest within 1 %, and 3-35 % fewer tets on the CAD models
/// (points the front put too close to the surface). At 0.5: cheese 170 -> 194 and
/// bunny00 2.78 -> 3.11; tried after the flips instead of first: fandisk-in-box 144.
const SHORT_EDGE: f64 = 0.3;

/// A tet worse than the bad quality: `Q_K`, slot, vertices.
type Bad = (f64, u32, [u32; 4]);

/// [`rescan`] scans the whole mesh when more than one vertex in this many was touched.
const RESCAN_SHARE: usize = 8;

/// The bad tets after the changes since the clock read `*since` (which it then reads
/// again): those of `prev` whose vertices are untouched, and the bad tets at the
/// touched vertices. The same set as [`scan`]'s, without visiting every tet (bunny00:
/// 15 scans of 1.9 M tets were a third of the optimisation). Only a full scan knows the
/// worst when no tet is bad, or when the clock has wrapped: then it scans.
fn rescan(ops: &Ops, prev: Vec<Bad>, since: &mut u32, bad_quality: f64) -> (Vec<Bad>, f64) {
    rescan_unless(ops, prev, since, bad_quality, RESCAN_SHARE)
}

/// [`rescan`], which scans the whole mesh when more than one vertex in `share` was
/// touched.
fn rescan_unless(
    ops: &Ops,
    prev: Vec<Bad>,
    since: &mut u32,
    bad_quality: f64,
    share: usize,
) -> (Vec<Bad>, f64) {
    let (clock, from) = (ops.l.stamps.clock, *since);
    *since = clock;
    if clock < from {
        let (bad, _, worst) = scan(ops, bad_quality);
        return (bad, worst);
    }
    let stamps = &ops.l.stamps;
    let changed: Vec<u32> = stamps.touched_since(from).collect();
    if changed.len() > ops.l.mesh.num_vertices() / share.max(1) {
        let (bad, _, worst) = scan(ops, bad_quality);
        return (bad, worst);
    }
    let touched = |v: &[u32; 4]| v.iter().any(|&x| stamps.of(x) > from);
    let mut bad: Vec<Bad> = prev
        .into_iter()
        .filter(|b| {
            ops.l.mesh.is_alive(crate::tetmesh::TetId(b.1))
                && ops.l.tet(b.1) == b.2
                && !touched(&b.2)
        })
        .collect();
    let mut seen = crate::FastSet::default();
    let mut star = Vec::new();
    for x in changed {
        if !ops.l.has_vertex(x) {
            continue;
        }
        ops.l.star(x, &mut star);
        for &t in &star {
            if ops.l.is_ghost(t) || ops.region_of(t) == 0 || !seen.insert(t) {
                continue;
            }
            let q = ops.tet_quality(t);
            if q > bad_quality {
                bad.push((q, t, ops.l.tet(t)));
            }
        }
    }
    if bad.is_empty() {
        let (bad, _, worst) = scan(ops, bad_quality);
        return (bad, worst);
    }
    let worst = bad.iter().map(|b| b.0).fold(1.0, f64::max);
    (bad, worst)
}

/// The domain's tets worse than `bad_quality`, the `Q_K` histogram and the worst `Q_K`.
fn scan(ops: &Ops, bad_quality: f64) -> (Vec<Bad>, Histogram, f64) {
    let mut h = Histogram::quality();
    let mut worst: f64 = 1.0;
    let mut bad = Vec::new();
    for t in ops.l.mesh.finite_tets() {
        if ops.region_of(t.0) == 0 {
            continue;
        }
        let q = ops.tet_quality(t.0);
        h.add(q);
        worst = worst.max(q);
        if q > bad_quality {
            bad.push((q, t.0, ops.l.tet(t.0)));
        }
    }
    (bad, h, worst)
}

#[cfg(test)]
mod tests;
