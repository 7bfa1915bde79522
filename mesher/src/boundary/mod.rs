//! The boundary mesh T(S,F) of the paper (§4): the surface points S inserted by the
//! Delaunay kernel into an enlarged bounding box (8 corners, 5 tets, §4.1), the missing
//! constrained edges and faces F recovered by flips (§4.2), interior Steiner points
//! where flips alone cannot, and the domain identified by adjacency from a box corner
//! without crossing a constrained face (§4.3).
//!
//! Steiner points (the "interior Steiner points preferred" strategy of George,
//! Borouchaki and Saltel, "'Ultimate' robustness in meshing an arbitrary polyhedron",
//! IJNME 2003): when an edge stays stuck after the flips, a point goes into the first
//! tet it meets from each end, where it is stuck (a stuck triangle gets a point off
//! each side), and those points go into the recovered mesh by the constrained Delaunay
//! kernel (`insert`; a rebuild from scratch is the fallback), then the next pass
//! recovers what is still missing. Points that end up outside the domain disappear
//! with the outside; the others are reported. Only when interior points fail is a
//! stuck edge split (`split`), at the point nearest the recovered edge that blocks it
//! (Si's rule in TetGen), exactly on it when a representable point is, which keeps
//! the boundary of T(S,F) the input surface as a point set; such points are reported
//! and taken out again where the mesh allows.
//!
//! A recovery that failed is not tried again until a tet at the vertices it met has
//! changed (`Local`'s stamps): the attempt is local and deterministic.
//!
//! Entry point: [`boundary_mesh`] -> ([`BoundaryMesh`], [`BoundaryReport`]) or a typed
//! [`BoundaryError`] that names the entity and where it is.
//!
//! Submodules: `local` (vertex-to-tet map, rings, the checked `replace`), `round` (one
//! recovery round: locks, edges, faces), `insert` (the
//! incremental Steiner rounds), `flips` (2-3,
//! edge removal by ring re-triangulation), `recover` (segment and face recovery),
//! `domain` (flood fill, regions, volumes), `split` (boundary Steiner points),
//! `attempts` (the sorted, shuffled and rebuilding attempts),
//! `suppress` (taking Steiner points out again), `reconnect` (the star of a Steiner
//! point re-tetrahedralised without it, by search).

mod attempts;
mod cone;
mod domain;
mod fan;
pub(crate) mod flips;
mod insert;
pub(crate) mod local;
mod present;
mod reconnect;
mod recover;
mod round;
mod split;
mod suppress;
#[cfg(test)]
mod tests;

use round::{recover_all, Recovered};

pub use attempts::boundary_mesh;
pub use domain::Regions;
pub use flips::FlipCounts;

use crate::delaunay::{box_mesh, sort, DelaunayError, Inserted, Kernel};
use crate::geom::{Aabb, Point};
use crate::surface::{sorted_ids, Surface};
use crate::tetmesh::{TetMesh, VertexId};
use crate::volume::VolumeMesh;
use flips::Locks;
use local::Local;
use present::{
    all_faces_present, edges_now, faces_lost, faces_now, lock_edge, FaceMarks, Here, Sweep,
};
use recover::{Recovery, Stuck};
use serde::Serialize;
use split::Refined;
use std::collections::HashMap;
use std::time::Instant;
use thiserror::Error;

/// Least distance of an interior Steiner point for a stuck edge from the planes of the
/// edge's surface triangles, relative to the edge's length (see `clear_of_faces`).
/// Anchor's runaway points were 5e-5 off. 1e-3 recovers more insertion orders of cheese
/// without split points left (9 of 11 against 8), but it moves points on turbine too,
/// whose full mesh then kept a flat tet at Q_K 1374 (test
/// `turbine_flat_tet_between_thin_walls_is_lifted`, bar 356): the downstream quality
/// swings with any change of T(S,F).
const STEINER_CLEARANCE: f64 = 1e-4;

/// Passes over the missing edges (or faces) per round: recovering one can unblock
/// another, so a pass that made progress is followed by another.
const MAX_PASSES: usize = 4;

/// Split rounds in a row that may leave as many stuck entities as the best round
/// before the recovery gives up: splitting creates new edges, and on some surfaces
/// (long thin coplanar triangles) they stay stuck as often as the old ones.
pub const STALLED_SPLIT_ROUNDS: usize = 5;

/// A split round that leaves more than [`RUNAWAY`] times the fewest stuck entities of
/// the split rounds so far, plus [`RUNAWAY_SLACK`], ends the attempt: such rounds went
/// on to hundreds of stuck edges (anchor, cheese with other insertion orders), seconds
/// of work before the stall test ended them.
const RUNAWAY: usize = 2;
/// See [`RUNAWAY`].
const RUNAWAY_SLACK: usize = 8;

/// Parameters of the boundary mesh; the defaults follow NOTES.md §1.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryOptions {
    /// Enlargement of the bounding box on each side, relative to its largest extent.
    pub box_margin: f64,
    /// Seed of the insertion order and of the order in which entities are recovered.
    pub seed: u64,
    /// Flip operations allowed per entity and attempt.
    pub flip_budget: usize,
    /// Rebuilds with more interior Steiner points before splitting edges.
    pub steiner_rounds: usize,
    /// Offset of a Steiner point from its stuck entity, relative to the entity's size.
    pub steiner_offset: f64,
    /// Check the surface (closed, manifold, no self-intersection) first.
    pub check_input: bool,
    /// Rebuilds that split the still-stuck edges (boundary Steiner points), after the
    /// interior rounds; they stop early after [`STALLED_SPLIT_ROUNDS`] rounds without
    /// fewer stuck entities than the best so far.
    pub split_rounds: usize,
    /// Insert a round's Steiner points into the mesh of the previous round by the
    /// constrained kernel (`insert`) instead of rebuilding the mesh from scratch.
    pub incremental: bool,
    /// Levels of preparatory edge removals (Si's `flipnm` link levels) tried at a
    /// stuck segment before it gets a Steiner point. Level 1 is always on. With the
    /// removals restricted to the ring vertices that may block (`may_block`), level 2
    /// costs 3-6 % more instructions than level 1 on cheese and turbine and takes fewer
    /// interior Steiner points on part1 (1 -> 0), anchor (22 -> 21) and turbine
    /// (8 -> 7), one more on box-with-hole (4 -> 5). When it leaves split edges, the
    /// recovery runs again at level 1 and keeps the result with fewer of them.
    pub flip_depth: usize,
    /// The order in which the input edges are recovered.
    pub edge_order: EdgeOrder,
}

/// The order of the edge recovery ([`BoundaryOptions::edge_order`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeOrder {
    /// By vertex ids: the surface's own numbering, usually spatially coherent, and
    /// the order that recovers every corpus model at the first attempt.
    Sorted,
    /// A shuffle of the sorted order with this seed.
    Shuffled(u64),
}

impl Default for BoundaryOptions {
    fn default() -> Self {
        BoundaryOptions {
            box_margin: 0.1,
            seed: 0x5EED,
            flip_budget: 64,
            steiner_rounds: 2,
            steiner_offset: 0.3,
            check_input: true,
            split_rounds: 16,
            incremental: true,
            flip_depth: 2,
            edge_order: EdgeOrder::Sorted,
        }
    }
}

/// The boundary mesh: the whole box mesh with a region per tet.
#[derive(Debug)]
pub struct BoundaryMesh {
    /// All tets of the box (outside ones included, region 0).
    pub mesh: TetMesh,
    /// Region of every tet slot: 0 outside the domain, 1.. the material regions.
    pub region: Vec<u32>,
    /// Mesh vertex of each input vertex.
    pub surface_vertex: Vec<VertexId>,
    /// The eight box corners.
    pub box_corners: Vec<VertexId>,
    /// Interior Steiner points (mesh vertices), inside the domain or not.
    pub steiner: Vec<VertexId>,
    /// Steiner points on input edges (mesh vertices), after the suppression.
    pub boundary_steiner: Vec<VertexId>,
    /// The boundary faces, oriented as the input: the input triangles, or their pieces
    /// where an edge was split.
    pub faces: Vec<[VertexId; 3]>,
    /// Input triangle of each face.
    pub face_parent: Vec<u32>,
    /// Constrained faces (sorted mesh vertex ids) -> input triangle index.
    pub constrained: HashMap<[u32; 3], u32>,
}

/// Counters and timings of one boundary mesh.
#[derive(Clone, Debug, Default, Serialize)]
pub struct BoundaryReport {
    /// Input vertices.
    pub surface_vertices: usize,
    /// Input triangles.
    pub surface_triangles: usize,
    /// Input edges missing from the Delaunay mesh of the surface points.
    pub missing_edges: usize,
    /// Input triangles missing from it.
    pub missing_faces: usize,
    /// Flips done (all rounds).
    pub flips: FlipCounts,
    /// Rebuilds with Steiner points.
    pub steiner_rounds: usize,
    /// Steiner points inside the domain.
    pub steiner_interior: usize,
    /// Steiner points placed that ended outside the domain (deleted with it).
    pub steiner_outside: usize,
    /// Steiner points taken out again after the recovery.
    pub steiner_removed: usize,
    /// Steiner points on input edges (splitting them), after the suppression.
    pub steiner_on_edges: usize,
    /// Steiner points on input faces (faces are never split: always 0).
    pub steiner_on_faces: usize,
    /// Steiner points on input edges taken out again after the recovery.
    pub steiner_on_edges_removed: usize,
    /// Of the Steiner points left on input edges, those only within rounding of their
    /// edge (no representable point was exactly on it): there the boundary of T(S,F)
    /// deviates from the input by rounding.
    pub steiner_on_edges_inexact: usize,
    /// Material regions (bodies, or the space between nested shells).
    pub regions: usize,
    /// Tets in the domain.
    pub tets: usize,
    /// Volume of the domain (sum of tet volumes).
    pub volume: f64,
    /// Enclosed volume of the input (signed volumes of its triangles).
    pub enclosed_volume: f64,
    /// Seconds: checking the input.
    pub time_check: f64,
    /// Seconds: Delaunay insertion (all rounds).
    pub time_delaunay: f64,
    /// Seconds: edge and face recovery (all rounds).
    pub time_recovery: f64,
    /// Seconds: domain identification.
    pub time_domain: f64,
    /// Recovery attempts: more than one when the first leaves entities stuck (other
    /// edge orders, then rebuilding rounds) or splits input edges (one level fewer of
    /// preparatory removals); the other fields describe the recovery kept.
    pub attempts: usize,
    /// Seconds of all attempts together (0 when there was one).
    pub seconds_all_attempts: f64,
    /// Input faces turned to agree in orientation with their neighbours (a closed
    /// surface listed without regard to orientation; [`Surface::reoriented`]).
    pub faces_reoriented: usize,
}

/// Why no boundary mesh was built. Every variant names the entity and where it is.
#[derive(Debug, Error)]
pub enum BoundaryError {
    /// The input surface has defects (open, non-manifold, self-intersecting, ...).
    #[error("the surface has {defects} defect(s), so no boundary mesh is built:\n{summary}")]
    Defective {
        /// Number of defects.
        defects: usize,
        /// The check report, as printed by `mesher check`.
        summary: String,
    },
    /// Fewer than four independent points, non-finite coordinates, id overflow.
    #[error(transparent)]
    Kernel(#[from] DelaunayError),
    /// Two input vertices have the same coordinates.
    #[error("input vertices {first} and {second} coincide at ({x}, {y}, {z})")]
    CoincidentVertices {
        /// The first vertex.
        first: usize,
        /// The second vertex.
        second: usize,
        /// x.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
    },
    /// An input vertex lies exactly on an input edge or triangle it is not part of.
    #[error("input vertex {vertex} at {at:?} lies on input {entity}")]
    VertexOnEntity {
        /// The vertex.
        vertex: usize,
        /// Its coordinates.
        at: [f64; 3],
        /// The edge or triangle, with its vertex ids.
        entity: String,
    },
    /// Some edges or faces could not be recovered within the budgets.
    #[error("{edges} edge(s) and {faces} face(s) not recovered after {rounds} Steiner round(s); first: {first}")]
    Unrecovered {
        /// Edges still missing.
        edges: usize,
        /// Faces still missing.
        faces: usize,
        /// Steiner rounds done.
        rounds: usize,
        /// The first missing entity, with its coordinates.
        first: String,
    },
    /// A connected part of the complement touches both sides of a constrained face.
    #[error("the domain leaks across input triangle {triangle}: the two sides are connected")]
    Leak {
        /// The triangle.
        triangle: usize,
    },
}

/// One recovery with the given options.
fn boundary_attempt(
    surface: &Surface,
    options: &BoundaryOptions,
) -> Result<(BoundaryMesh, BoundaryReport), BoundaryError> {
    let mut report = BoundaryReport {
        attempts: 1,
        surface_vertices: surface.vertices.len(),
        surface_triangles: surface.triangles.len(),
        ..BoundaryReport::default()
    };
    let t0 = Instant::now();
    let mut work = Refined::new(surface);
    // The input check and the first Delaunay mesh do not depend on each other: they
    // run side by side, and a defect found by the check still comes first.
    let timed = |f: &dyn Fn() -> _| {
        let t = Instant::now();
        let r = f();
        (r, t.elapsed().as_secs_f64())
    };
    let first = || Round::rebuild(&work.surface, &[], options);
    // The input edges come with the check, the shorter side (turbine: 31 ms with them
    // against the Delaunay mesh's 37).
    let edges = || input_edges(&work.surface, options.edge_order);
    let ((check, time_check, mut edges), (first, time_first)) = if options.check_input {
        rayon::join(
            || {
                let t = Instant::now();
                let check = surface.check();
                let time = t.elapsed().as_secs_f64();
                (Some(check), time, edges())
            },
            || timed(&first),
        )
    } else {
        ((None, 0.0, edges()), timed(&first))
    };
    if let Some(check) = check.filter(|c| !c.is_clean()) {
        return Err(BoundaryError::Defective {
            defects: check.num_defects(),
            summary: check.to_string(),
        });
    }
    report.time_check = time_check;
    report.time_delaunay = time_first;
    let mut initial = Some(first?);
    let mut steiner_points: Vec<Point> = Vec::new();
    // Steiner points chosen since the last round (for an incremental round).
    let mut fresh: Vec<Point> = Vec::new();
    let mut best: (usize, Vec<Point>, Vec<Entity>) = (usize::MAX, Vec::new(), Vec::new());
    let mut stuck = Vec::new();
    let rounds = options.steiner_rounds + options.split_rounds;
    // Fewest stuck entities seen in a split round, and rounds since it last dropped.
    let mut split_best = (usize::MAX, 0);
    let mut rounds_done = 0;
    let mut previous: Option<Round> = None;
    for round in 0..=rounds {
        rounds_done = round;
        let t1 = Instant::now();
        let (mut cur, reuse) = match initial.take() {
            Some(r) => (r, false),
            None => {
                let reuse = match previous.as_mut() {
                    Some(r) if options.incremental => r.extend(&work, &fresh),
                    _ => false,
                };
                match previous.take() {
                    Some(r) if reuse => (r, true),
                    _ => (
                        Round::rebuild(&work.surface, &steiner_points, options)?,
                        false,
                    ),
                }
            }
        };
        fresh.clear();
        report.time_delaunay += t1.elapsed().as_secs_f64();
        let t2 = Instant::now();
        let Recovered {
            stuck: left,
            bad,
            marks,
        } = recover_all(
            &mut cur.rec,
            &work.surface,
            &edges,
            &cur.sv,
            options,
            &mut report,
            round,
        )?;
        stuck = left;
        // Steiner points found exactly on an input entity are dropped; the mesh that
        // has them is not reused.
        steiner_points.retain(|p| !bad.contains(p));
        let reusable = bad.is_empty();
        report.flips = add(report.flips, std::mem::take(&mut cur.rec.flips));
        report.time_recovery += t2.elapsed().as_secs_f64();
        debug_round(round, reuse, &stuck, &work, steiner_points.len(), t0);
        if stuck.is_empty() {
            report.steiner_rounds = round;
            let t3 = Instant::now();
            let Round {
                mut rec,
                sv,
                steiner,
            } = cur;
            suppress_splits(&mut rec, &mut work, &sv, &mut report);
            let mut steiner = steiner;
            steiner.extend(rec.steiner.iter().map(|&v| VertexId(v)));
            // The domain is identified here only when there are interior Steiner
            // points to suppress (none on most clean inputs: knot2's T(S,F) 47 -> 43
            // ms); `finish` then patches it where the suppression changed the mesh.
            let mut identified = None;
            if !steiner.is_empty() {
                let (inside, before) = inside_vertices(&rec, &work, &sv)?;
                suppress(&mut rec, &mut steiner, &inside, &mut report);
                identified = Some(before);
            }
            let bm = finish(rec, &work, sv, steiner, marks, identified, &mut report)?;
            report.time_domain = t3.elapsed().as_secs_f64();
            return Ok((bm, report));
        }
        if round < options.steiner_rounds && !options.incremental {
            // Keep the Steiner set that left the fewest entities stuck; a worse round
            // is reverted and retried with points closer to the entities.
            if stuck.len() < best.0 {
                best = (stuck.len(), steiner_points.clone(), stuck.clone());
            } else {
                steiner_points = best.1.clone();
                stuck = best.2.clone();
            }
        }
        if round + 1 < options.steiner_rounds {
            let scale = options.steiner_offset / (1 << round.min(30)) as f64;
            for s in &stuck {
                match *s {
                    Entity::Edge(a, b, _) => {
                        let (ma, mb) = (cur.sv[a as usize].0, cur.sv[b as usize].0);
                        let points = cur.rec.crossing_points(ma, mb);
                        fresh.extend(clear_of_faces(&work, a, b, points));
                    }
                    Entity::Face(k) => {
                        fresh.extend(steiner_for_face(&work.surface, k, scale, round))
                    }
                }
            }
        } else if round < rounds {
            // Split rounds that run away (each split leaving more stuck pieces than it
            // fixes) do not come back: the attempt ends, the next order is tried.
            if stuck.len()
                > split_best
                    .0
                    .saturating_mul(RUNAWAY)
                    .saturating_add(RUNAWAY_SLACK)
            {
                break;
            }
            if stuck.len() < split_best.0 {
                split_best = (stuck.len(), 0);
            } else {
                split_best.1 += 1;
                if split_best.1 >= STALLED_SPLIT_ROUNDS {
                    break;
                }
            }
            // Interior points did not do it: split the stuck edges (faces get more
            // interior points, closer).
            for s in &stuck {
                match *s {
                    Entity::Edge(a, b, _) => {
                        // At the point nearest the locked edge that blocks it, with
                        // interior points where it is stuck as well.
                        let (ma, mb) = (cur.sv[a as usize].0, cur.sv[b as usize].0);
                        let t = cur.rec.blocker_parameter(ma, mb).unwrap_or(0.5);
                        let points = cur.rec.crossing_points(ma, mb);
                        fresh.extend(clear_of_faces(&work, a, b, points));
                        work.split_edge(a, b, t);
                    }
                    Entity::Face(k) => {
                        fresh.extend(steiner_for_face(&work.surface, k, 0.05, round))
                    }
                }
            }
            edges = input_edges(&work.surface, options.edge_order);
        }
        steiner_points.extend_from_slice(&fresh);
        if reusable {
            previous = Some(cur);
        }
    }
    Err(BoundaryError::Unrecovered {
        edges: stuck
            .iter()
            .filter(|s| matches!(s, Entity::Edge(..)))
            .count(),
        faces: stuck
            .iter()
            .filter(|s| matches!(s, Entity::Face(..)))
            .count(),
        rounds: rounds_done,
        first: stuck
            .first()
            .map_or_else(String::new, |e| describe(&work.surface, *e)),
    })
}

/// The mesh of one recovery round, with the mesh vertex of every refined surface
/// vertex and the interior Steiner points inserted so far.
struct Round {
    rec: Recovery,
    sv: Vec<VertexId>,
    steiner: Vec<VertexId>,
}

impl Round {
    /// A fresh Delaunay mesh of the refined surface and the Steiner points.
    fn rebuild(
        surface: &Surface,
        steiner_points: &[Point],
        options: &BoundaryOptions,
    ) -> Result<Round, BoundaryError> {
        let (mesh, sv, steiner) = delaunay(surface, steiner_points, options)?;
        Ok(Round {
            rec: Recovery::new(Local::new(mesh)),
            sv,
            steiner,
        })
    }

    /// Inserts the split points the refined surface gained since this round and the
    /// `fresh` interior Steiner points into the recovered mesh (see `insert`). False
    /// when a split point was rejected: the mesh no longer matches the refined surface
    /// and must be rebuilt.
    fn extend(&mut self, work: &Refined, fresh: &[Point]) -> bool {
        let splits = &work.surface.vertices[self.sv.len().min(work.surface.vertices.len())..];
        let mut points = splits.to_vec();
        points.extend_from_slice(fresh);
        let got = self.rec.insert_points(&points);
        let (on_edges, interior) = got.split_at(splits.len());
        if on_edges.iter().any(Option::is_none) {
            return false;
        }
        self.sv
            .extend(on_edges.iter().flatten().map(|&v| VertexId(v)));
        self.steiner
            .extend(interior.iter().flatten().map(|&v| VertexId(v)));
        true
    }
}

/// With `MESHER_DEBUG` set, one line per recovery round on stderr.
fn debug_round(
    round: usize,
    reused: bool,
    stuck: &[Entity],
    work: &Refined,
    steiner: usize,
    t0: Instant,
) {
    if std::env::var_os("MESHER_DEBUG").is_none() {
        return;
    }
    let edges = stuck
        .iter()
        .filter(|s| matches!(s, Entity::Edge(..)))
        .count();
    eprintln!(
        "boundary round {round} ({}): {} stuck ({edges} edges), {steiner} Steiner points, {} splits, {:.3} s",
        if reused { "incremental" } else { "rebuilt" },
        stuck.len(),
        work.splits.len(),
        t0.elapsed().as_secs_f64()
    );
}

/// Tries to take every split point out again, newest first (which undoes the splits of
/// the surface in reverse).
fn suppress_splits(
    rec: &mut Recovery,
    work: &mut Refined,
    sv: &[VertexId],
    report: &mut BoundaryReport,
) {
    // Newest first (an older split's star is whole again once the newer splits on it
    // are gone); passes repeat while one removes some, since removing one can free
    // another.
    for _ in 0..4 {
        let before = report.steiner_on_edges_removed;
        for k in (0..work.splits.len()).rev() {
            if work.removed[k] {
                continue;
            }
            let split = work.splits[k];
            let Some((cd, tris)) = work.star(split) else {
                continue;
            };
            let m = |i: u32| sv[i as usize].0;
            if rec.suppress_split(split.map(m), cd.map(m)) {
                work.merge(split, tris);
                work.removed[k] = true;
                report.steiner_on_edges_removed += 1;
            }
        }
        if report.steiner_on_edges_removed == before {
            break;
        }
    }
}

/// Passes of the interior Steiner point suppression.
const SUPPRESS_PASSES: usize = 4;

/// Deep removals (the search and the link flips) tried per interior Steiner point. A
/// point whose first failed is tried once more after a tet around it changed: on
/// cheese 8 of 24 such points went then, none at a third attempt, whose failures cost
/// 4 % of its boundary mesh (turbine, anchor: no third attempts).
const DEEP_ATTEMPTS: u32 = 2;

/// Tries to take every interior Steiner point out again (paper §4.2's "remove or
/// relocate"): the ones that are not needed go. Removing one can free another, so
/// passes repeat while one removes some.
fn suppress(
    rec: &mut Recovery,
    steiner: &mut Vec<VertexId>,
    inside: &[bool],
    report: &mut BoundaryReport,
) {
    let before = steiner.len();
    // Points whose deep removal failed, with the clock then, their neighbours and the
    // attempts: tried again only when a tet around them has changed, at most
    // `DEEP_ATTEMPTS` times in all.
    let mut failed: HashMap<u32, (u32, Vec<u32>, u32)> = HashMap::default();
    for _ in 0..SUPPRESS_PASSES {
        let n = steiner.len();
        steiner.retain(|v| {
            // A point outside the domain goes with the outside: no work for it.
            if !inside.get(v.index()).copied().unwrap_or(false) {
                return true;
            }
            let tried = failed.get(&v.0);
            let deep = tried.is_none_or(|(since, near, attempts)| {
                *attempts < DEEP_ATTEMPTS && rec.l.stamps.changed_since(near, *since)
            });
            if rec.remove_steiner(v.0, deep) {
                return false;
            }
            if deep {
                let attempts = tried.map_or(0, |f| f.2) + 1;
                failed.insert(v.0, (rec.l.stamps.clock, rec.neighbours(v.0), attempts));
            }
            true
        });
        if steiner.len() == n {
            break;
        }
    }
    report.steiner_removed = before - steiner.len();
}

/// The domain identified on a mesh, with the tets it was identified on (per slot, the
/// vertices; `u32::MAX` for dead slots), for [`domain::patched`].
struct Identified {
    regions: domain::Regions,
    snapshot: Vec<[u32; 4]>,
}

/// Which mesh vertices touch the domain (a tet of a material region), found by the
/// domain identification of `finish` on the mesh as it is; and that identification.
fn inside_vertices(
    rec: &Recovery,
    work: &Refined,
    sv: &[VertexId],
) -> Result<(Vec<bool>, Identified), BoundaryError> {
    let mesh_tris: Vec<[u32; 3]> = work
        .surface
        .triangles
        .iter()
        .map(|t| t.map(|i| sv[i as usize].0))
        .collect();
    let marks = rec.l.triangle_faces(&mesh_tris);
    let regions = domain::identify(&rec.l.mesh, &marks)?;
    let mesh = &rec.l.mesh;
    let mut inside = vec![false; mesh.num_vertices()];
    let mut snapshot = vec![[u32::MAX; 4]; mesh.num_slots()];
    for t in mesh.finite_tets() {
        snapshot[t.index()] = mesh.raw_tet(t.0);
        if regions.region[t.index()] != 0 {
            for v in mesh.tet(t) {
                inside[v.index()] = true;
            }
        }
    }
    Ok((inside, Identified { regions, snapshot }))
}

/// A stuck input entity (input vertex / triangle ids).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Entity {
    /// Edge with one of its triangles.
    Edge(u32, u32, u32),
    /// Triangle.
    Face(u32),
}

fn add(a: FlipCounts, b: FlipCounts) -> FlipCounts {
    FlipCounts {
        flip23: a.flip23 + b.flip23,
        flip32: a.flip32 + b.flip32,
        flip44: a.flip44 + b.flip44,
        edge_removals: a.edge_removals + b.edge_removals,
        cones: a.cones + b.cones,
        fans: a.fans + b.fans,
    }
}

/// Unique input edges `(a, b, triangle)` with `a < b`, in the given order (see
/// [`boundary_mesh`] on why the order matters).
fn input_edges(surface: &Surface, order: EdgeOrder) -> Vec<(u32, u32, u32)> {
    // A counting sort on the smaller end, then each (small) bucket sorted: the order
    // of one global sort, for a fraction of its cost (it runs at every split round).
    let ends = |t: &[u32; 3], i: usize| {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        (a.min(b), a.max(b))
    };
    let mut start = vec![0usize; surface.vertices.len() + 1];
    for t in &surface.triangles {
        for i in 0..3 {
            start[ends(t, i).0 as usize + 1] += 1;
        }
    }
    for v in 1..start.len() {
        start[v] += start[v - 1];
    }
    let mut e: Vec<(u32, u32, u32)> = vec![(0, 0, 0); 3 * surface.triangles.len()];
    let mut next = start.clone();
    for (k, t) in surface.triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = ends(t, i);
            e[next[a as usize]] = (a, b, k as u32);
            next[a as usize] += 1;
        }
    }
    for w in start.windows(2) {
        e[w[0]..w[1]].sort_unstable();
    }
    e.dedup_by_key(|x| (x.0, x.1));
    if let EdgeOrder::Shuffled(seed) = order {
        sort::shuffle(&mut e, seed);
    }
    e
}

/// The box mesh with the surface points and the Steiner points inserted.
fn delaunay(
    surface: &Surface,
    steiner_points: &[Point],
    options: &BoundaryOptions,
) -> Result<(TetMesh, Vec<VertexId>, Vec<VertexId>), BoundaryError> {
    let pts = &surface.vertices;
    if let Some(index) = pts.iter().position(|p| !p.is_finite()) {
        let p = pts[index];
        return Err(DelaunayError::NonFinite {
            index,
            x: p.x,
            y: p.y,
            z: p.z,
        }
        .into());
    }
    let bb =
        Aabb::of_points(pts.iter().chain(steiner_points)).ok_or(DelaunayError::Degenerate {
            distinct: 0,
            what: "fewer than four",
        })?;
    let ext = (bb.max - bb.min).max_element().max(f64::MIN_POSITIVE);
    let m = Point::splat(ext * options.box_margin.max(0.01));
    let (lo, hi) = (bb.min - m, bb.max + m);
    let mut mesh = box_mesh(lo, hi)?;
    mesh.reserve_vertices(pts.len() + steiner_points.len());
    let mut kernel = Kernel::new();
    kernel.set_bounds(lo, hi);
    let mut surface_vertex = vec![VertexId(0); pts.len()];
    for i in sort::brio_order(pts, options.seed) {
        match kernel.insert(&mut mesh, pts[i as usize])? {
            Inserted::New(v) => surface_vertex[i as usize] = v,
            Inserted::Duplicate(v) => {
                let first = (0..pts.len())
                    .find(|&j| pts[j] == mesh.point(v))
                    .unwrap_or(0);
                let p = pts[i as usize];
                return Err(BoundaryError::CoincidentVertices {
                    first: first.min(i as usize),
                    second: first.max(i as usize),
                    x: p.x,
                    y: p.y,
                    z: p.z,
                });
            }
        }
    }
    let mut steiner = Vec::with_capacity(steiner_points.len());
    for &p in steiner_points {
        if let Inserted::New(v) = kernel.insert(&mut mesh, p)? {
            steiner.push(v);
        }
    }
    Ok((mesh, surface_vertex, steiner))
}

/// The error for a mesh vertex found exactly on an input entity.
fn on_entity(surface: &Surface, sv: &[VertexId], v: u32, entity: &[u32]) -> BoundaryError {
    let vertex = sv.iter().position(|x| x.0 == v).unwrap_or(usize::MAX);
    let at = surface
        .vertices
        .get(vertex)
        .map_or([f64::NAN; 3], |p| p.to_array());
    let kind = if entity.len() == 2 {
        "edge"
    } else {
        "triangle"
    };
    BoundaryError::VertexOnEntity {
        vertex,
        at,
        entity: format!("{kind} {entity:?}"),
    }
}

/// A stuck entity for an error message: ids and coordinates.
fn describe(surface: &Surface, e: Entity) -> String {
    let p = |i: u32| surface.vertices[i as usize].to_array();
    match e {
        Entity::Edge(a, b, _) => format!("edge ({a}, {b}) from {:?} to {:?}", p(a), p(b)),
        Entity::Face(k) => {
            let t = surface.triangles[k as usize];
            format!(
                "triangle {k} {t:?} at {:?}, {:?}, {:?}",
                p(t[0]),
                p(t[1]),
                p(t[2])
            )
        }
    }
}

/// The crossing points of stuck edge `ab`, each moved off the planes of the edge's
/// surface triangles (along the plane's normal, on its side) to at least
/// [`STEINER_CLEARANCE`] of the edge's length. A point nearly on such a plane blocks
/// every edge of that face near it (each needs a tet with it, nearly flat), and the
/// next round's crossing points near it come out nearer still: on anchor with another
/// insertion order, points 1e-6 off a flat face made the split rounds run away (388
/// edges stuck after 9 rounds, from 13). Inexact constructions.
fn clear_of_faces(work: &Refined, a: u32, b: u32, mut points: Vec<Point>) -> Vec<Point> {
    let v = &work.surface.vertices;
    let (pa, pb) = (v[a as usize], v[b as usize]);
    let min = STEINER_CLEARANCE * (pb - pa).length();
    for k in work.triangles_at(a, &[b]) {
        let [p, q, r] = work.surface.triangles[k].map(|i| v[i as usize]);
        let n = (q - p).cross(r - p).normalize_or_zero();
        for x in &mut points {
            let d = n.dot(*x - pa);
            if d.abs() < min {
                *x += n * (min.copysign(d) - d);
            }
        }
    }
    points
}

/// Interior Steiner points for a stuck triangle `k`: off its centroid on both sides of
/// the surface, at `scale` times its smallest height (more directions in later rounds).
/// (A stuck edge gets points in the tets it meets first instead,
/// [`Recovery::crossing_points`].)
fn steiner_for_face(surface: &Surface, k: u32, scale: f64, round: usize) -> Vec<Point> {
    let [a, b, c] = surface.triangles[k as usize].map(|i| surface.vertices[i as usize]);
    let n = (b - a).cross(c - a).normalize_or_zero();
    // The smallest height: on long thin triangles a point placed at a fraction of the
    // edge length would land near unrelated parts of the surface.
    let (mid, size) = ((a + b + c) / 3.0, min_height(surface, k));
    // An irregular factor, so that points of neighbouring entities do not line up with
    // the grid-like planes of CAD models (a point exactly on a face blocks it).
    let key = k as u64 * 0x85EB_CA6B + 7;
    let jitter =
        1.0 + 0.2 * ((key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64 / (1u64 << 53) as f64);
    // A small oblique part: a purely normal offset from an axis-aligned triangle keeps
    // one coordinate, and the point can land exactly on a coplanar triangle next to it
    // (seen on cheese), which forces a rebuild.
    let oblique = Point::new(0.31, 0.27, 0.14);
    let d = (n + oblique * 0.05) * size * scale * jitter;
    let mut out = vec![mid - d, mid + d];
    if round % 2 == 1 {
        // A second pair, tilted, so that a rebuild does not meet the same tie again.
        let t = n.any_orthonormal_vector() * size * scale * 0.5;
        out.extend([mid - d + t, mid + d - t]);
    }
    out
}

/// The smallest height of triangle `k`.
fn min_height(surface: &Surface, k: u32) -> f64 {
    let [a, b, c] = surface.triangles[k as usize].map(|i| surface.vertices[i as usize]);
    let area2 = (b - a).cross(c - a).length();
    let longest = (b - a).length().max((c - b).length()).max((a - c).length());
    if longest > 0.0 {
        area2 / longest
    } else {
        0.0
    }
}

/// Domain identification and the final mesh.
fn finish(
    rec: Recovery,
    work: &Refined,
    surface_vertex: Vec<VertexId>,
    steiner: Vec<VertexId>,
    marks: Option<FaceMarks>,
    identified: Option<Identified>,
    report: &mut BoundaryReport,
) -> Result<BoundaryMesh, BoundaryError> {
    let mesh_tris: Vec<[u32; 3]> = work
        .surface
        .triangles
        .iter()
        .map(|t| t.map(|i| surface_vertex[i as usize].0))
        .collect();
    let mut constrained = HashMap::with_capacity(mesh_tris.len());
    for (t, &k) in mesh_tris.iter().zip(&work.parent) {
        constrained.insert(sorted_ids(*t), k);
    }
    // The identification before the suppression, patched where the suppression changed
    // the mesh; else from scratch.
    let patched = identified.and_then(|before| {
        domain::patched(&rec.l.mesh, &before.regions, &before.snapshot, |f| {
            constrained.contains_key(&sorted_ids(f))
        })
    });
    let regions = match patched {
        Some(r) => r,
        None => {
            let marks = match marks {
                Some(f) if f.clock == rec.l.stamps.clock => f.marks,
                _ => rec.l.triangle_faces(&mesh_tris),
            };
            domain::identify(&rec.l.mesh, &marks)?
        }
    };
    let mesh = rec.l.mesh;
    report.regions = regions.count;
    report.tets = regions.tets;
    report.volume = regions.volume;
    report.enclosed_volume = domain::enclosed_volume(&work.surface);
    let mut inside = vec![false; mesh.num_vertices()];
    for t in mesh.finite_tets() {
        if regions.region[t.index()] != 0 {
            for v in mesh.tet(t) {
                inside[v.index()] = true;
            }
        }
    }
    report.steiner_interior = steiner.iter().filter(|v| inside[v.index()]).count();
    report.steiner_outside = steiner.len() - report.steiner_interior;
    let live: Vec<usize> = (0..work.splits.len())
        .filter(|&k| !work.removed[k])
        .collect();
    let boundary_steiner: Vec<VertexId> = live
        .iter()
        .map(|&k| surface_vertex[work.splits[k][0] as usize])
        .collect();
    report.steiner_on_edges = live.len();
    report.steiner_on_edges_inexact = live.iter().filter(|&&k| !work.exact[k]).count();
    let mut surface_vertex = surface_vertex;
    surface_vertex.truncate(work.inputs);
    let bm = BoundaryMesh {
        mesh,
        region: regions.region,
        surface_vertex,
        box_corners: (0..8).map(VertexId).collect(),
        steiner,
        boundary_steiner,
        faces: mesh_tris.iter().map(|t| t.map(VertexId)).collect(),
        face_parent: work.parent.clone(),
        constrained,
    };
    Ok(bm)
}

impl BoundaryMesh {
    /// The domain as an exchange mesh: the input vertices first, in input order, then
    /// the Steiner points on input edges, then the interior ones; tets with their
    /// region; the boundary faces (the input triangles, or their pieces; the input
    /// triangle of each is in [`BoundaryMesh::face_parent`]).
    pub fn to_volume_mesh(&self) -> VolumeMesh {
        let mut first = self.surface_vertex.clone();
        first.extend_from_slice(&self.boundary_steiner);
        crate::volume::export_domain(&self.mesh, &self.region, &first, &self.faces).0
    }
}
