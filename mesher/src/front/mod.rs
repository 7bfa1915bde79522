//! Field points by the advancing front coupled with the Delaunay kernel (paper §5):
//! a loop of front identification, optimal points, filtration and constrained insertion
//! until the front is empty.
//!
//! - Classification (§5.2): a tet is acceptable iff every edge has normalised length
//!   `<= delta` (NOTES.md §5, default `sqrt(2)`); at the start the tets outside the
//!   domain are acceptable and those inside are not, so the first front is the boundary.
//! - Front: the faces between an acceptable and an unacceptable tet (a constrained face
//!   of an unacceptable tet counts too: the other side belongs to another region).
//! - One optimal point per front face ([`point`]), kept only if strictly inside the
//!   circumsphere of the unacceptable tet `K2` (exact `insphere`), and points of deeper
//!   layers along the face normal, inside that circumsphere too (not in the paper: fewer
//!   iterations on deep domains, see [`DEFAULT_LAYERS`]). All are filtered ([`filter`]) against the kept points
//!   (`delta_f`) and the vertices of `K2` (`delta_v`; optionally those of every
//!   unacceptable tet).
//! - Insertion by the constrained kernel ([`crate::delaunay::Kernel::constrained_cavity`]):
//!   the cavity never crosses the surface nor leaves the region; a point outside the
//!   domain, whose cavity the correction empties, or that would be joined to a vertex
//!   closer than `delta_f`, is dropped. The cavity also takes in the tets it borders
//!   whose edges all fit and whose `Q_K` is above `absorb_q_k` (not in the paper: the
//!   generalised kernel of George and Borouchaki, the cavity enlarged for the
//!   elements' sake while it stays star-shaped), so that flat tets on the surface and
//!   slivers of the first layers, which no Delaunay cavity reaches, go.
//! - Seeds ([`seed`], not in the paper): body-centred cubic lattices of points at the
//!   local size, kept at a clearance from the surface, inserted before the first front;
//!   their tets whose edges fit are accepted at once, so the fronts start from the
//!   surface and from the lattice and fill the gap between them.
//! - Remedial rule (§5.2): an unacceptable tet that survives an iteration becomes
//!   acceptable ([`Remedial`] chooses which ones; one with an edge over twice `delta`
//!   only after three tries), which guarantees convergence; the loop is also bounded by
//!   `max_iterations`.

pub mod filter;
pub mod point;
mod seed;

use crate::delaunay::{Constraints, DelaunayError, Kernel, Rejection};
use crate::geom::predicates::{insphere, Sphere, StaticFilter};
use crate::geom::{Aabb, Point};
use crate::quality::normalized_length;
use crate::quality::tet::{q_k, TET_EDGES};
use crate::sizing::{edge_length, LengthMode, SizeField};
use crate::tetmesh::{TetId, TetMesh, FACE_VERTICES};
use filter::{Clusters, Filtered, Grid};
use point::{optimal_point, PointParams, REGULAR_HEIGHT};
use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;
use thiserror::Error;

/// Which surviving unacceptable tets the remedial rule makes acceptable.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum Remedial {
    /// Those that were behind a front face this iteration (a point was tried for them).
    #[default]
    Front,
    /// All of them (the paper's literal `U_i ∩ U_{i+1}`).
    All,
}

/// Default acceptance bound `delta`: 1.6, not NOTES.md's `sqrt(2)`. A tet with an
/// edge between 1.41 and 1.6 is in band ([0.6, 1.67]) already; refining it costs
/// iterations and points for nothing (with three layers, sphere-10k: 12 iterations at
/// `sqrt(2)`, 10 at 1.6, same tet count and quality).
pub const DEFAULT_DELTA: f64 = 1.6;

/// Default points per front face: the optimal point and two deeper ones (not in the
/// paper). A front advances about one layer of tets per iteration, so with one point
/// per face the iterations grow with the depth of the domain in units of the size:
/// sphere-10k 35, armadillo 52, bunny00 and sphere-100k past the bound of 60. With
/// three layers and the seed lattices ([`seed`]): sphere-10k 5, armadillo 11, bunny00
/// 25, sphere-100k 7. Deeper points whose cavity reaches the surface are dropped (the
/// boundary faces place that layer).
pub const DEFAULT_LAYERS: usize = 3;

/// A boundary face's optimal point is filtered (and kept from vertices) at a size of at
/// most this many times its face's largest vertex size; its own size stays the field's.
/// Where T(S,F)'s tets join a fine surface to much coarser vertices, the size
/// interpolated a height above the surface is many times the face's (fandisk-in-box:
/// about 3.5 times, from the box corners of size 1.3), the first layer's points were
/// filtered at that size (91 % of them dropped), and fans of tets from fandisk faces to
/// a box corner were left that the optimisation broke or not by chance: worst `Q_K`
/// after it 14.6-143.7 over nine runs with the point length perturbed by 1e-4 (twice
/// the in-domain `Q_t`: 17.68), 15.1-16.8 with the bound. Before the optimisation
/// there: 81.4 -> 84.7 % of the edges in band, 75.3 -> 76.4 % `Q_K < 3`, 2 % fewer
/// tets. No other corpus model changes. Bounding the point's own size too (its vertex
/// size) refined around it: fandisk-in-box 14 % more tets.
pub const BOUNDARY_FILTER_SCALE: f64 = 2.0;

/// Default layers whose points the filtration merges ([`FrontParams::merge_layers`]):
/// the optimal points and the first deeper layer (module [`filter`]). Measured before
/// the optimisation against none (0), ci and nightly tiers (with
/// [`BOUNDARY_FILTER_SCALE`]): tets 0.3-11 % fewer on the fine models (knot2 34 225 ->
/// 30 573, 1.43 -> 1.28 times Gmsh HXT's; sphere-1k 1.44 -> 1.29, elephant 1.31 ->
/// 1.23, box-with-hole 1.31 -> 1.24, torus 1.33 -> 1.26, armadillo 1.32 -> 1.29,
/// bunny00 1.18 -> 1.15; CAD models -5 to +8 %), edges in band within 1.3 points on the
/// fine models (bunny00 89.8 -> 90.8 %), `Q_K < 3` up on them but sphere-1k (97.65 ->
/// 97.06) and sphere-10k (99.23 -> 99.09): elephant 95.20 -> 95.78, knot2 93.43 ->
/// 93.68, box-with-hole 92.70 -> 93.90, torus 95.40 -> 95.77. The front 3 % slower on
/// bunny00 (median of 5), the whole run as fast (a faster optimisation). With the
/// optimal points only (1): the same figures within a point, but a small torus (32 x
/// 12 segments, the tests' `generated_shapes`) keeps 89.8 % of its edges in band after
/// the optimisation (2: 94.1 %, none: 96.6 %). Merging into the nearest kept point in
/// reach every time (not the nearest recent one first) cost the front 8 % on bunny00
/// for the same figures.
pub const DEFAULT_MERGE_LAYERS: usize = 2;

/// Default filtration distances `delta_f` and `delta_v` (normalised): 0.9, not
/// NOTES.md's `1/sqrt(2)`, for the interior points; the boundary faces' points keep
/// `1/sqrt(2)` ([`FrontParams::delta_boundary`]). At `1/sqrt(2)` the mean interior edge
/// is 1.08 and the tet count 1.6-2.2 times Gmsh HXT's (whose mean edge is 1.24-1.39
/// against the same sizes, and only ~80 % of its edges in [0.6, 1.67] on sphere-10k).
/// At 0.9: mean 1.12-1.24, 95-97 % in band, 1.34-1.56 times HXT's count on the fine
/// models. At 1.0 fewer than 90 % of the edges stay in band (sphere-10k 84 %).
pub const DEFAULT_DELTA_F: f64 = 0.9;

/// Default cube side of the seed lattices, in their level's size (see [`seed`]): 1.45.
/// A level keeps the lattice points whose size is within a factor `sqrt(1.5)` of its
/// own, so a cube side of `s h` has normalised lengths from `s / 1.22` to `1.22 s`
/// (its diagonals 0.87 times that): at 1.5 the sides reach 1.84, past the band's 1.67
/// where the local size is in the lower part of the level's range, and bunny00 (whose
/// sizes vary) kept 10.6 % of its interior edges above the band (89.4 % in band). At
/// 1.45: 90.6 %, tets +3 % (sphere-10k +6 %, all within 1.12 times Gmsh HXT's), the same
/// time (fewer front iterations), worst Q_K knot2 2.96 -> 2.68, fandisk 2.71 -> 2.51,
/// armadillo 9.31 -> 9.26, the others unchanged. Earlier, against no lattices (one run
/// each, sphere-100k and bunny00): the fronts took 46 and 36 iterations without seeds,
/// 7 and 18 with them, and the whole run 31 s -> 12 s and 18 s -> 15 s.
pub const DEFAULT_SEED_SPACING: f64 = 1.45;

/// Default clearance of a seed from the domain's vertices and from other levels'
/// seeds (normalised): the front fills that gap. At 3 instead of 2: one more iteration
/// and 1-3 % more tets on sphere-10k and sphere-100k.
pub const DEFAULT_SEED_CLEARANCE: f64 = 2.0;

/// Parameters of the front (defaults: NOTES.md §5-§6, except [`DEFAULT_DELTA`],
/// [`DEFAULT_DELTA_F`] and the deeper layers, [`DEFAULT_LAYERS`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrontParams {
    /// Acceptance bound on normalised edge lengths.
    pub delta: f64,
    /// Filtration distance (normalised).
    pub delta_f: f64,
    /// Smallest normalised distance from a field point to an existing vertex (the
    /// vertices of `K2` and of the cavity); NOTES.md §5's "too close to existing
    /// vertices", default `delta_f`.
    pub delta_v: f64,
    /// `delta_f` and `delta_v` for the optimal points of boundary faces (constrained
    /// front faces): the first layer on the surface, next to vertices that never move.
    pub delta_boundary: f64,
    /// The optimal point's relaxation and the length mode.
    pub point: PointParams,
    /// Shape bound of acceptance: a tet with `Q_K` above it is unacceptable whatever
    /// its edges (so that the front puts a point in a flat tet between boundary faces).
    pub q_accept: f64,
    /// Tets whose edges all fit the size (no point goes in them: `l <= delta`,
    /// end-point form) and whose `Q_K` is above this join the cavity of a point next
    /// to them ([`Kernel::constrained_cavity_with`]); infinity: never. The flat
    /// tets two nearly coplanar surface triangles make, and the slivers of the first
    /// layers, are otherwise left to the optimisation. Measured before optimisation
    /// (`Q_K < 3`): torus 89.3 -> 95.4 %, nested-spheres 94.8 -> 97.0, elephant 94.4
    /// -> 95.2, knot2 92.0 -> 93.4, box-with-hole 91.8 -> 92.7, turbine 84.9 -> 89.4;
    /// front time up to +15 % on the small models, bunny00 +3 %. The seed lattices'
    /// insertions take in only tets with two surface faces. With 3: about the same
    /// before optimisation, and after it rotor's worst 105 -> 75 but homer's 82.9 ->
    /// 91.7 (Q_t 81.3). Absorbing every bad tet, the big boundary-mesh tets not yet
    /// refined included, made bunny00 worse (97.4 -> 96.6 %) and 60 % slower.
    pub absorb_q_k: f64,
    /// Bound on the iterations. The largest models need more than the paper's dozen:
    /// sphere-100k converges in 64 (bunny00 47, armadillo 32); the late iterations
    /// have small fronts and cost little.
    pub max_iterations: usize,
    /// The remedial rule's scope.
    pub remedial: Remedial,
    /// Filtration also against the vertices of every unacceptable tet (not only those
    /// of the point's own `K2`): fewer points rejected at insertion after their cavity
    /// was built, and a better first layer on knot2 (worst Q_K 4.55 -> 2.96) and
    /// box-with-hole (7.80 -> 3.90) with the paper's parameters; off by default: it
    /// moves the tet count of scaled copies of the level-2 sphere by 2 %. Measured
    /// again with today's defaults (ci + nightly): edges in band +1 to +1.5 points
    /// (bunny00 89.8 -> 91.2 %), `Q_K < 3` before optimisation within 0.5 points, tets
    /// +1-3 %, same time; but after the optimisation cheese's worst goes 170 -> 19002
    /// (a flat tet with two boundary faces on a needle triangle, four fixed vertices,
    /// that no operation lifts) and box-with-hole's 2.92 -> 3.83.
    pub filter_all_vertices: bool,
    /// Points proposed per front face: the optimal point, then up to `layers - 1` more
    /// along the face's normal, one regular-tet height apart, while inside `K2`'s
    /// circumsphere (deeper layers).
    pub layers: usize,
    /// Points of the first `merge_layers` layers (the optimal points first) that the
    /// filtration drops for kept points only are merged into the nearest of them
    /// ([`filter::Clusters`]); 0: the paper's filtration (dropped).
    pub merge_layers: usize,
    /// Cube side of the seed lattices ([`seed`]) in their level's size; infinite for
    /// none (the paper's front alone).
    pub seed_spacing: f64,
    /// Smallest normalised distance from a seed to a domain vertex or another level's
    /// seed.
    pub seed_clearance: f64,
}

impl Default for FrontParams {
    fn default() -> Self {
        FrontParams {
            delta: DEFAULT_DELTA,
            delta_f: DEFAULT_DELTA_F,
            delta_v: DEFAULT_DELTA_F,
            delta_boundary: std::f64::consts::FRAC_1_SQRT_2,
            point: PointParams::default(),
            q_accept: f64::INFINITY,
            absorb_q_k: 4.0,
            max_iterations: 100,
            remedial: Remedial::default(),
            layers: DEFAULT_LAYERS,
            merge_layers: DEFAULT_MERGE_LAYERS,
            filter_all_vertices: false,
            seed_spacing: DEFAULT_SEED_SPACING,
            seed_clearance: DEFAULT_SEED_CLEARANCE,
        }
    }
}

impl FrontParams {
    /// The normalised-length mode.
    pub fn mode(&self) -> LengthMode {
        self.point.mode
    }
}

/// One iteration of the front (the paper's convergence curve).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Iteration {
    /// Front faces at the start.
    pub front: usize,
    /// Optimal points strictly inside the circumsphere of their `K2`.
    pub proposed: usize,
    /// Points dropped by the filtration (kept points and `K2`'s vertices).
    pub filtered: usize,
    /// Points dropped at insertion (outside, emptied cavity, too close to a vertex).
    pub rejected: usize,
    /// Points inserted.
    pub inserted: usize,
    /// Tets made acceptable by the remedial rule.
    pub remedial: usize,
    /// Tets in the domain at the end.
    pub tets: usize,
    /// Seconds spent in the iteration.
    pub seconds: f64,
    /// Of which: front identification and optimal points.
    pub seconds_propose: f64,
    /// Of which: filtration and insertion.
    pub seconds_insert: f64,
}

/// The outcome of [`advance`].
#[derive(Clone, Debug, Default, Serialize)]
pub struct FrontReport {
    /// Per iteration.
    pub iterations: Vec<Iteration>,
    /// True when the front emptied within the bound.
    pub converged: bool,
    /// Points rejected at insertion, by reason: outside, emptied, not a ball, too close
    /// (to a vertex, or a deeper-layer point whose cavity reaches the surface).
    pub rejections: [usize; 4],
    /// Tets removed by the cavities (all tried insertions).
    pub cavity_tets: u64,
    /// Tets visited by the location walks.
    pub walk_steps: u64,
    /// Seed points inserted before the first front ([`seed`]).
    pub seeds: usize,
}

/// A fatal failure of the front (non-fatal outcomes are counted in the report).
#[derive(Debug, Error)]
pub enum FrontError {
    /// The kernel ran out of tet ids.
    #[error(transparent)]
    Kernel(#[from] DelaunayError),
}

/// The mesh the front works on: tets with their constraints and regions, and the size
/// at every vertex.
#[derive(Clone, Debug)]
pub struct FieldMesh {
    /// The mesh (the whole box, ghosts included).
    pub mesh: TetMesh,
    /// Constrained faces and regions per tet slot.
    pub cons: Constraints,
    /// `h` at every vertex.
    pub h: Vec<f64>,
    /// At every vertex, the size field's hint after its size lookup: walks for the
    /// points near a vertex start there (bunny00: 3.4 background steps per lookup
    /// from the previous face's hint).
    pub hint: Vec<u32>,
}

/// A field point waiting for insertion.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    p: Point,
    h: f64,
    /// The size its distances to other points and vertices are measured with
    /// (filtration, `delta_v`): `h`, or less on a boundary face.
    hf: f64,
    /// The unacceptable tet behind its face.
    k2: u32,
    /// 0 for the optimal point, k for the k-th deeper layer.
    layer: u8,
    /// The smallest normalised distance to a kept point for this point.
    delta_f: f64,
    /// The smallest normalised distance to an existing vertex for this point.
    delta_v: f64,
    /// Vertices from this id on are exempt from `delta_v` (the seeds' own lattice).
    exempt_from: u32,
    /// The size field's hint after the lookup of `h`.
    hint: u32,
}

/// A tet with an edge longer than this many times `delta` is grossly unacceptable:
/// the remedial rule accepts it only after [`GROSS_TRIES`] iterations behind a front
/// face. Accepted at once, such a tet stays (fandisk-in-box: a tet from the fandisk's
/// top face to a box corner, Q_K 265, when the deeper-layer points had to lie in `K2`'s
/// circumsphere; 16.4 with three tries).
const GROSS_FACTOR: f64 = 2.0;

/// Iterations a grossly unacceptable tet is tried before the remedial rule applies.
const GROSS_TRIES: u8 = 3;

/// Front faces handled per parallel task (fixed, so results do not depend on threads).
const CHUNK: usize = 256;

/// An interior front face whose `K2` apex (the vertex opposite it) is closer than this
/// fraction of `delta_v` (normalised) to where its optimal point starts
/// ([`point::start`]) proposes nothing: its ideal point is there already, and the
/// point would be dropped next to its own `K2`. On bunny00, 216 k of the 319 k points
/// of the second iteration were so dropped after their optimal points were computed;
/// the screen at 0.85 catches 162 k of them before, and would have caught 165 that
/// were not dropped (at 1.0: 208 k and 5.7 k). Over its front the points proposed 2.08
/// M -> 1.14 M, the proposals' time 1.21 -> 0.80 s, the front 5.33 -> 4.93 s; the same %
/// `Q_K` < 3 and tets within 0.02 %. Boundary faces (the first layer) are not screened:
/// screened too, their points shift on the CAD models, whose small meshes then end
/// another way after the optimisation (rotor 34.3 -> 32.7 % `Q_K` < 3, part1 18.5 ->
/// 16.7 %, the smallest dihedral 1.03 -> 0.68 degrees).
const APEX_SCREEN: f64 = 0.85;

/// The domain tets not yet accepted, as a list that may also hold stale entries (dead
/// or accepted since; [`Active::refresh`] drops them): an iteration then costs what its
/// front costs, not a scan of the whole mesh.
#[derive(Default)]
struct Active {
    list: Vec<u32>,
    listed: Vec<bool>,
}

impl Active {
    fn push(&mut self, t: u32) {
        let i = t as usize;
        if self.listed.len() <= i {
            self.listed
                .resize((i + 1).max(self.listed.len() * 5 / 4), false);
        }
        // A reused slot may still be listed: its entry stands for the new tet.
        if !self.listed[i] {
            self.listed[i] = true;
            self.list.push(t);
        }
    }

    /// Keeps the live unaccepted domain tets, in increasing slot order (the order of a
    /// scan, on which the candidates' order and so the mesh depend).
    fn refresh(&mut self, fm: &FieldMesh, accept: &[bool]) {
        let listed = &mut self.listed;
        self.list.retain(|&t| {
            let keep = fm.mesh.is_alive(TetId(t))
                && fm.cons.region[t as usize] != 0
                && !accept[t as usize];
            listed[t as usize] = keep;
            keep
        });
        self.list.sort_unstable();
    }
}

/// Runs the front to convergence (or `max_iterations`), calling `progress` after each
/// iteration.
pub fn advance(
    fm: &mut FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
    progress: &mut dyn FnMut(&Iteration),
) -> Result<FrontReport, FrontError> {
    let slots = fm.mesh.num_slots();
    fm.cons.resize(slots);
    let mut accept: Vec<bool> = (0..slots).map(|t| fm.cons.region[t] == 0).collect();
    let mut active = Active::default();
    let mut tets = 0usize;
    for t in 0..slots as u32 {
        if fm.cons.region[t as usize] != 0 && fm.mesh.is_alive(TetId(t)) {
            active.push(t);
            tets += 1;
        }
    }
    let mut ages = Ages {
        born: vec![0u32; slots],
        tried: vec![0u32; slots],
        tries: vec![0u8; slots],
    };
    let mut kernel = Kernel::new();
    kernel.set_filter(StaticFilter::of_points(fm.mesh.points()));
    let mut report = FrontReport::default();
    let mut absorbable: Vec<u8> = Vec::new();
    let mut last = None;
    let first_seed = fm.h.len() as u32;
    for level in seed::candidates(fm, field, params) {
        // A level's seeds keep the clearance from every vertex but their own level's.
        let own = fm.h.len() as u32;
        for mut c in reorder(&level, 0x5EED) {
            c.exempt_from = own;
            if let Some(t) = last {
                c.k2 = t;
            }
            // Seeds take in only flat tets on the surface: the lattice's own tets are
            // the front's to refine (taking them in too made bunny00 slower, 6.4 ->
            // 6.9 s, and worse, 97.5 -> 97.2 % Q_K < 3 before optimisation).
            if let Ok(removed) = insert(&mut kernel, fm, c, params, &mut absorbable, true)? {
                report.seeds += 1;
                tets = tets + kernel.new_tets().len() - removed;
                let slots = fm.mesh.num_slots();
                admit(&kernel, &mut accept, &mut ages, &mut active, slots, 0);
                last = kernel.new_tets().first().copied();
            }
        }
    }
    if report.seeds > 0 {
        accept_lattice(fm, field, params, first_seed, &active.list, &mut accept);
    }
    for it in 1..=params.max_iterations as u32 {
        let t0 = Instant::now();
        active.refresh(fm, &accept);
        let faces = front_faces(fm, &accept, &active.list);
        if faces.is_empty() {
            report.converged = true;
            break;
        }
        let mut rec = Iteration {
            front: faces.len(),
            ..Iteration::default()
        };
        for &(t, _) in &faces {
            if ages.tried[t as usize] != it {
                ages.tries[t as usize] = ages.tries[t as usize].saturating_add(1);
            }
            ages.tried[t as usize] = it;
        }
        let proposed = propose(fm, field, params, &faces);
        let cands = proposed.cands;
        rec.seconds_propose = t0.elapsed().as_secs_f64();
        rec.proposed = proposed.count;
        // Filtration along a Hilbert curve (neighbours in turn: a regular packing),
        // insertion in BRIO order (random rounds, Hilbert inside each): the first big
        // cavities are broken up early, and neighbouring insertions touch neighbouring
        // tets.
        let ordered = by_layer_then_hilbert(&cands, proposed.bounds);
        let kept = filtrate(fm, field, params, &active.list, &ordered);
        rec.filtered = proposed.count - kept.len();
        let kept = reorder(&kept, 0x5EED ^ it as u64);
        for c in kept {
            match insert(&mut kernel, fm, c, params, &mut absorbable, false)? {
                Ok(removed) => {
                    rec.inserted += 1;
                    tets = tets + kernel.new_tets().len() - removed;
                    let slots = fm.mesh.num_slots();
                    admit(&kernel, &mut accept, &mut ages, &mut active, slots, it);
                }
                Err(r) => {
                    rec.rejected += 1;
                    report.rejections[r] += 1;
                }
            }
        }
        rec.seconds_insert = t0.elapsed().as_secs_f64() - rec.seconds_propose;
        let remedial = classify(fm, field, params, it, &ages, &active.list, &mut accept);
        rec.tets = tets;
        rec.remedial = remedial;
        rec.seconds = t0.elapsed().as_secs_f64();
        progress(&rec);
        report.iterations.push(rec);
    }
    if !report.converged {
        active.refresh(fm, &accept);
        report.converged = front_faces(fm, &accept, &active.list).is_empty();
    }
    report.cavity_tets = kernel.stats.cavity_tets;
    report.walk_steps = kernel.stats.walk_steps;
    Ok(report)
}

/// The candidates in BRIO order.
fn reorder(cands: &[Candidate], seed: u64) -> Vec<Candidate> {
    let pts: Vec<Point> = cands.iter().map(|c| c.p).collect();
    let order = crate::delaunay::sort::brio_order(&pts, seed);
    order.into_iter().map(|i| cands[i as usize]).collect()
}

/// The candidates by layer (the optimal points first), each layer along the Hilbert
/// curve over `bounds`.
fn by_layer_then_hilbert(cands: &[Candidate], bounds: Option<Aabb>) -> Vec<Candidate> {
    let pts: Vec<Point> = cands.iter().map(|c| c.p).collect();
    let order = crate::delaunay::sort::hilbert_order_by_in(&pts, bounds, |i| cands[i].layer);
    order.into_iter().map(|i| cands[i as usize]).collect()
}

/// Per tet slot: the iteration that made the tet, the last one in which it was
/// behind a front face, and in how many iterations it was.
struct Ages {
    born: Vec<u32>,
    tried: Vec<u32>,
    tries: Vec<u8>,
}

fn grow(accept: &mut Vec<bool>, ages: &mut Ages, n: usize) {
    if accept.len() < n {
        accept.resize(n, false);
        ages.born.resize(n, 0);
        ages.tried.resize(n, 0);
        ages.tries.resize(n, 0);
    }
}

/// Registers the tets of the kernel's last insertion (`slots` tet slots now): born in
/// iteration `it` (0 before the first), unaccepted, active.
fn admit(
    kernel: &Kernel,
    accept: &mut Vec<bool>,
    ages: &mut Ages,
    active: &mut Active,
    slots: usize,
    it: u32,
) {
    grow(accept, ages, slots);
    for &t in kernel.new_tets() {
        ages.born[t as usize] = it;
        ages.tries[t as usize] = 0;
        accept[t as usize] = false;
        active.push(t);
    }
}

/// The front faces `(K2, facet)`, in slot order (the active list's, in chunks on the
/// threads).
fn front_faces(fm: &FieldMesh, accept: &[bool], active: &[u32]) -> Vec<(u32, u8)> {
    active
        .par_chunks(4 * CHUNK)
        .map(|chunk| {
            let mut out = Vec::new();
            for &t in chunk {
                let adj = fm.mesh.raw_adj(t);
                for (i, &a) in adj.iter().enumerate() {
                    if accept[(a >> 2) as usize] || fm.cons.is_constrained(t, i) {
                        out.push((t, i as u8));
                    }
                }
            }
            out
        })
        .flatten()
        .collect()
}

/// The points proposed in one iteration ([`propose`]).
struct Proposed {
    /// Those left for the filtration, in face order.
    cands: Vec<Candidate>,
    /// All points proposed, those dropped next to their `K2` included (a face screened
    /// out by [`APEX_SCREEN`] proposes none).
    count: usize,
    /// The box of all the points proposed: the filtration's order (along the Hilbert
    /// curve over this box) is then the order the points had among all of them.
    bounds: Option<Aabb>,
}

/// Optimal points of the front faces, kept when strictly inside `K2`'s circumsphere;
/// none for a face whose `K2` apex is where its point would start ([`APEX_SCREEN`]).
/// Without [`FrontParams::filter_all_vertices`], a point closer than its `delta_v` to
/// a vertex of its own `K2` is dropped here (the filtration's first test, done in
/// parallel: on bunny00 1.29 M of the 2.07 M points proposed went no further, and
/// were sorted and copied in vain).
fn propose(
    fm: &FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
    faces: &[(u32, u8)],
) -> Proposed {
    let chunks: Vec<(Vec<Candidate>, usize, Option<Aabb>)> = faces
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut out = Vec::with_capacity(chunk.len());
            for &(t, i) in chunk {
                let v = fm.mesh.raw_tet(t);
                let q = fm.mesh.tet_points(TetId(t));
                let f = FACE_VERTICES[i as usize];
                let mut hint = fm.hint[v[f[0]] as usize];
                let tri = [q[f[0]], q[f[1]], q[f[2]]];
                let h = [f[0], f[1], f[2]].map(|k| fm.h[v[k] as usize]);
                // The face's orientation makes vertex i (inside K2) positive.
                let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
                if n == Point::ZERO {
                    continue;
                }
                // A boundary face's own point: the first layer on the surface.
                let bound = if fm.cons.is_constrained(t, i as usize) {
                    params.delta_boundary
                } else if apex_at_start(fm, v[i as usize], tri, h, n, params) {
                    continue;
                } else {
                    f64::INFINITY
                };
                let (p, hp) = optimal_point(tri, h, n, field, &params.point, &mut hint);
                let ok = p.is_finite()
                    && hp > 0.0
                    && hp.is_finite()
                    && insphere(q[0], q[1], q[2], q[3], p) == Sphere::Inside;
                if !ok {
                    continue;
                }
                let hf = if bound.is_finite() {
                    hp.min(BOUNDARY_FILTER_SCALE * h[0].max(h[1]).max(h[2]))
                } else {
                    hp
                };
                out.push(Candidate {
                    p,
                    h: hp,
                    hf,
                    k2: t,
                    layer: 0,
                    delta_f: params.delta_f.min(bound),
                    delta_v: params.delta_v.min(bound),
                    exempt_from: u32::MAX,
                    hint,
                });
                let k2 = q;
                let mut prev = (p, hp);
                for layer in 1..params.layers.min(16) as u8 {
                    let q = prev.0 + n * (prev.1 * params.point.length * REGULAR_HEIGHT);
                    // Like the optimal point, strictly inside K2's circumsphere: beyond
                    // it the mesh is refined already, and the kernel would refuse the
                    // point after building its cavity (bunny00: 18.1 s -> 13.4 s).
                    // Tested before the size lookup, which is then not needed.
                    if !q.is_finite() || insphere(k2[0], k2[1], k2[2], k2[3], q) != Sphere::Inside {
                        break;
                    }
                    let hq = field.size(q, &mut hint);
                    if !(hq > 0.0 && hq.is_finite()) {
                        break;
                    }
                    out.push(Candidate {
                        p: q,
                        h: hq,
                        hf: hq,
                        k2: t,
                        layer,
                        delta_f: params.delta_f,
                        delta_v: params.delta_v,
                        exempt_from: u32::MAX,
                        hint,
                    });
                    prev = (q, hq);
                }
            }
            let count = out.len();
            let bounds = Aabb::of_points(out.iter().map(|c| &c.p));
            if !params.filter_all_vertices {
                out.retain(|c| !near_own_k2(fm, c));
            }
            (out, count, bounds)
        })
        .collect();
    Proposed {
        count: chunks.iter().map(|c| c.1).sum(),
        bounds: Aabb::of_points(
            chunks
                .iter()
                .filter_map(|c| c.2.as_ref())
                .flat_map(|b| [&b.min, &b.max]),
        ),
        cands: chunks.into_iter().flat_map(|c| c.0).collect(),
    }
}

/// True when `apex`, the vertex of `K2` opposite an interior front face `f` (sizes `h`,
/// unit normal `n` towards `apex`), is where the face's optimal point would start
/// ([`APEX_SCREEN`]).
fn apex_at_start(
    fm: &FieldMesh,
    apex: u32,
    f: [Point; 3],
    h: [f64; 3],
    n: Point,
    params: &FrontParams,
) -> bool {
    let hbar = (h[0] + h[1] + h[2]) / 3.0;
    let start = point::start(f, hbar, n, &params.point);
    let (q, hq) = (fm.mesh.points()[apex as usize], fm.h[apex as usize]);
    filter::close(start, q, hbar, hq, params.delta_v * APEX_SCREEN)
}

/// True when `c` is closer than its `delta_v` to a vertex of its own `K2`.
fn near_own_k2(fm: &FieldMesh, c: &Candidate) -> bool {
    fm.mesh.raw_tet(c.k2).iter().any(|&x| {
        let (q, hq) = (fm.mesh.points()[x as usize], fm.h[x as usize]);
        filter::close(c.p, q, c.hf, hq, c.delta_v)
    })
}

/// The candidates that survive the filtration, in order. With
/// [`FrontParams::filter_all_vertices`], the vertices of the unacceptable domain tets
/// (the front's and those ahead of it) are registered in the grid first, so that a
/// point too close to one of them is dropped before the kernel builds its cavity;
/// otherwise [`propose`] has dropped those too close to a vertex of their own `K2`.
fn filtrate(
    fm: &FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
    active: &[u32],
    cands: &[Candidate],
) -> Vec<Candidate> {
    let all = params.filter_all_vertices;
    let verts = if all {
        unacceptable_vertices(fm, active)
    } else {
        Vec::new()
    };
    let h_max = cands
        .iter()
        .map(|c| c.hf)
        .chain(verts.iter().map(|&v| fm.h[v]))
        .fold(0.0, f64::max);
    // The small level of the grid holds 99 % of the points (sizes vary by a factor of
    // 5 or more across a front, and cells sized for the largest hold far too many).
    let mut sizes: Vec<f64> = cands.iter().map(|c| c.hf).collect();
    let h_small = if sizes.is_empty() {
        h_max
    } else {
        let k = (sizes.len() - 1) * 99 / 100;
        *sizes.select_nth_unstable_by(k, f64::total_cmp).1
    };
    let pts = fm.mesh.points();
    let bounds = Aabb::of_points(
        cands
            .iter()
            .map(|c| &c.p)
            .chain(verts.iter().map(|&v| &pts[v])),
    );
    let new_grid = |points: usize| {
        let mut grid = Grid::with_sizes(
            h_small,
            h_max,
            params.delta_f,
            params.delta_v,
            bounds.map(|b| (b, points + verts.len())),
        );
        for &v in &verts {
            grid.add_vertex(pts[v], fm.h[v]);
        }
        grid
    };
    let mut grid = new_grid(cands.len());
    let mut out = Vec::with_capacity(cands.len());
    let mut clusters = Clusters::default();
    for c in cands {
        let merge = usize::from(c.layer) < params.merge_layers;
        let what = grid.keep_or_merge(c.p, c.hf, c.delta_f, c.delta_v, merge);
        clusters.add(what, c.p, c.hf);
        if let Filtered::Kept(_) = what {
            out.push(*c);
        }
    }
    let moves = clusters.moves();
    if moves.is_empty() {
        return out;
    }
    // A moved point takes the field's size where it now is (its vertex's size), and is
    // filtered at no more than that.
    for (k, p, hf) in moves {
        let c = &mut out[k as usize];
        let size = field.size(p, &mut c.hint);
        if size > 0.0 && size.is_finite() {
            (c.p, c.h, c.hf) = (p, size, hf.min(size));
        }
    }
    // The means of neighbouring clusters may have come closer than `delta_f`: the
    // same filtration again, in the same order, on the moved points.
    let mut grid = new_grid(out.len());
    out.retain(|c| grid.try_keep(c.p, c.hf, c.delta_f, c.delta_v));
    out
}

/// The vertices of the unacceptable domain tets (`active`, refreshed: in increasing
/// slot order), each once.
fn unacceptable_vertices(fm: &FieldMesh, active: &[u32]) -> Vec<usize> {
    let mut seen = vec![false; fm.h.len()];
    let mut verts = Vec::new();
    for &t in active {
        for v in fm.mesh.raw_tet(t).map(|v| v as usize) {
            if v < seen.len() && !seen[v] {
                seen[v] = true;
                verts.push(v);
            }
        }
    }
    verts
}

/// Inserts one field point; the inner result is the number of tets its cavity removed,
/// or why it was dropped (an index into [`FrontReport::rejections`]).
fn insert(
    kernel: &mut Kernel,
    fm: &mut FieldMesh,
    c: Candidate,
    params: &FrontParams,
    absorbable: &mut Vec<u8>,
    surface_only: bool,
) -> Result<Result<usize, usize>, FrontError> {
    let hint = fm.mesh.is_alive(TetId(c.k2)).then_some(TetId(c.k2));
    let (mesh, cons, h) = (&fm.mesh, &fm.cons, &fm.h);
    // Refused as soon as the conflict region reaches a vertex too close to the point
    // (most refusals: known at the first such tet, not after the whole cavity).
    let mut veto = |t: u32| {
        mesh.raw_tet(t).iter().any(|&v| {
            if v >= c.exempt_from {
                return false;
            }
            let (q, hq) = (mesh.points()[v as usize], h[v as usize]);
            filter::close(c.p, q, c.hf, hq, c.delta_v)
        })
    };
    // Tets whose edges all fit the size (the front puts no point in them) and whose
    // Q_K is above `absorb_q_k` join the cavities they border. A tet's answer holds
    // while it lives: kept per slot (0 unknown, 1 no, 2 yes), reset when the slot is
    // reused.
    if absorbable.len() < mesh.num_slots() {
        absorbable.resize(mesh.num_slots(), 0);
    }
    let mut absorb = |t: u32| {
        if surface_only && cons.face_mask[t as usize].count_ones() < 2 {
            return false;
        }
        let known = absorbable[t as usize];
        if known != 0 {
            return known == 2;
        }
        let v = mesh.raw_tet(t);
        let p = v.map(|x| mesh.points()[x as usize]);
        let yes = cons.region[t as usize] != 0
            && q_k(&p) > params.absorb_q_k
            && TET_EDGES.iter().all(|&[i, j]| {
                let l = p[i].distance(p[j]);
                normalized_length(l, h[v[i] as usize], h[v[j] as usize]) <= params.delta
            });
        absorbable[t as usize] = 1 + u8::from(yes);
        yes
    };
    if let Err(r) = kernel.constrained_cavity_with(mesh, cons, c.p, hint, &mut veto, &mut absorb) {
        return Ok(Err(match r {
            Rejection::Outside => 0,
            Rejection::Emptied => 1,
            Rejection::NotBall => 2,
            Rejection::OnVertex | Rejection::Vetoed => 3,
        }));
    }
    // A deeper-layer point whose cavity reaches the surface is near it (in a thin part,
    // or past a curved front): the boundary faces' own points place that layer, and a
    // deep point there makes flat tets on faces whose vertices never move.
    let at_surface = || {
        kernel
            .cavity_tets()
            .iter()
            .any(|&t| (0..4).any(|i| fm.cons.is_constrained(t, i)))
    };
    if c.layer > 0 && at_surface() {
        return Ok(Err(3));
    }
    let removed = kernel.cavity_tets().len();
    kernel.commit_cavity(&mut fm.mesh, &mut fm.cons, c.p)?;
    for &t in kernel.new_tets() {
        if let Some(a) = absorbable.get_mut(t as usize) {
            *a = 0;
        }
    }
    fm.h.push(c.h);
    fm.hint.push(c.hint);
    Ok(Ok(removed))
}

/// Classifies the `active` tets born in iteration `it` by their edges and applies the
/// remedial rule to the unacceptable survivors; returns how many the remedial rule
/// accepted.
fn classify(
    fm: &FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
    it: u32,
    ages: &Ages,
    active: &[u32],
    accept: &mut [bool],
) -> usize {
    let results = over_unaccepted(fm, active, accept, |t, hint| {
        let tu = t as usize;
        let ok = if ages.born[tu] == it {
            acceptable(fm, field, params, t, hint)
        } else {
            // A grossly unacceptable tet gets a few tries before the remedial rule
            // accepts it: the points around it may make room meanwhile.
            let mut gross = || {
                let wide = FrontParams {
                    delta: params.delta * GROSS_FACTOR,
                    ..*params
                };
                ages.tries[tu] < GROSS_TRIES && !acceptable(fm, field, &wide, t, hint)
            };
            (params.remedial == Remedial::All || ages.tried[tu] == it) && !gross()
        };
        Some((t, ok))
    });
    let mut remedial = 0;
    for &(t, ok) in &results {
        if ok {
            if ages.born[t as usize] != it {
                remedial += 1;
            }
            accept[t as usize] = true;
        }
    }
    remedial
}

/// Accepts the tets of the seed lattice (a vertex from `first_seed` on) whose edges
/// all fit: the front then starts from the lattice's border as from the surface.
fn accept_lattice(
    fm: &FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
    first_seed: u32,
    active: &[u32],
    accept: &mut [bool],
) {
    let ok = over_unaccepted(fm, active, accept, |t, hint| {
        let lattice = fm.mesh.raw_tet(t).iter().all(|&v| v >= first_seed);
        (lattice && acceptable(fm, field, params, t, hint)).then_some(t)
    });
    for t in ok {
        accept[t as usize] = true;
    }
}

/// `f(t, hint)` for the live domain tets of `active` not accepted yet, in chunks on the
/// threads (a size-field hint per chunk), the results in the list's order.
fn over_unaccepted<T: Send>(
    fm: &FieldMesh,
    active: &[u32],
    accept: &[bool],
    f: impl Fn(u32, &mut u32) -> Option<T> + Sync,
) -> Vec<T> {
    active
        .par_chunks(4 * CHUNK)
        .map(|chunk| {
            let mut hint = 0u32;
            chunk
                .iter()
                .filter(|&&t| {
                    let tu = t as usize;
                    !accept[tu] && fm.cons.region[tu] != 0 && fm.mesh.is_alive(TetId(t))
                })
                .filter_map(|&t| f(t, &mut hint))
                .collect::<Vec<T>>()
        })
        .flatten()
        .collect()
}

/// True when every edge of `t` has normalised length `<= delta`.
fn acceptable(
    fm: &FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
    t: u32,
    hint: &mut u32,
) -> bool {
    let v = fm.mesh.raw_tet(t);
    let pts = fm.mesh.points();
    if params.q_accept.is_finite() {
        // A NaN quality (degenerate) is unacceptable too.
        let q = q_k(&v.map(|x| pts[x as usize]));
        if q.is_nan() || q > params.q_accept {
            return false;
        }
    }
    TET_EDGES.iter().all(|&[i, j]| {
        let (a, b) = (v[i] as usize, v[j] as usize);
        let l = edge_length(field, params.mode(), pts[a], pts[b], fm.h[a], fm.h[b], hint);
        l <= params.delta
    })
}
