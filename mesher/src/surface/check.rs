//! [`Surface::check`]: runs every test of the surface checker and gathers a
//! [`CheckReport`].
//!
//! Order: index and coordinate validity and zero-area faces ([`topology::scan`]),
//! duplicate faces, the edge table (open / non-manifold / inconsistently oriented
//! edges), pinched vertices, self-intersections, then shells and their nesting
//! ([`shells`]).
//!
//! Self-intersections: every face with finite, non-collinear corners gets its exact
//! bounding box in a [`Bvh`]; each face, taken in the tree's leaf order (spatially
//! coherent, so consecutive queries reuse cached nodes), queries the tree for the
//! overlapping faces later in that order, and each such pair is tested with the exact
//! [`faces_intersect`], which lets faces touch at the vertices or edge they share by
//! index. Faces on the same three vertex ids are
//! reported as duplicates and not as intersections. The face ranges are processed in
//! parallel with rayon; the result is the same for any thread count (the lowest
//! [`MAX_PAIRS`] pairs are kept and the count is a sum), unless the
//! [`PAIR_BUDGET`] is exhausted.

use super::bvh::{Box3, Bvh};
use super::intersect::{faces_intersect, faces_intersect_in};
use super::report::{CheckReport, IntersectingPair, SelfIntersections, MAX_PAIRS, PAIR_BUDGET};
use super::topology::{self, face_ref, sorted_ids, FaceStatus};
use super::{shells, Surface};
use crate::geom::predicates::StaticFilter;
use crate::geom::Point;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

impl Surface {
    /// Checks the surface for every defect that would stop the boundary mesh: invalid
    /// indices or coordinates, degenerate and duplicate faces, open and non-manifold
    /// edges, pinched vertices, inconsistent orientation and self-intersections; also
    /// describes its shells and how they nest. Never panics.
    pub fn check(&self) -> CheckReport {
        let mut r = CheckReport {
            num_vertices: self.vertices.len(),
            num_triangles: self.triangles.len(),
            ..CheckReport::default()
        };
        let st = topology::scan(self, &mut r);
        r.duplicate_faces = topology::duplicates(self, &st);
        let et = topology::edge_table(self, &st);
        topology::classify_edges(self, &et, &mut r);
        r.pinched_vertices = topology::pinched_vertices(self, &st);
        r.self_intersections = self_intersections(self, &st);
        shells::shells(self, &st, &et, &mut r);
        // Faces listed either way round on an otherwise sound surface: still a defect
        // here, but the boundary mesh repairs it (`Surface::reoriented`); say so.
        if !r.inconsistent_edges.is_empty() {
            if let Some((_, turned)) = self.reoriented() {
                let faces = if turned == 1 { "face" } else { "faces" };
                r.warnings.push(format!(
                    "the inconsistently oriented edges are mended by `mesher mesh` and \
                     `mesher boundary`: {turned} {faces} turned to agree"
                ));
            }
        }
        r
    }

    /// Whether faces `f` and `g` intersect improperly (anywhere but at the vertices or
    /// edge they share by index), exactly. `false` for out-of-range faces or indices,
    /// faces with a repeated index, or collinear faces.
    pub fn faces_intersect(&self, f: usize, g: usize) -> bool {
        let (Some(tf), Some(tg)) = (self.corners(f), self.corners(g)) else {
            return false;
        };
        faces_intersect(&tf, self.triangles[f], &tg, self.triangles[g])
    }

    /// Corner points of face `f`, if its indices are in range.
    fn corners(&self, f: usize) -> Option<[Point; 3]> {
        let t = self.triangles.get(f)?;
        let mut p = [Point::ZERO; 3];
        for k in 0..3 {
            p[k] = *self.vertices.get(t[k] as usize)?;
        }
        Some(p)
    }
}

/// What one range of faces found.
#[derive(Default)]
struct Partial {
    count: usize,
    pairs: Vec<(u32, u32)>,
    candidates: u64,
}

impl Partial {
    /// Keeps only the lowest [`MAX_PAIRS`] pairs.
    fn trim(&mut self) {
        self.pairs.sort_unstable();
        self.pairs.truncate(MAX_PAIRS);
    }

    fn merge(mut self, mut o: Partial) -> Partial {
        self.count += o.count;
        self.candidates += o.candidates;
        self.pairs.append(&mut o.pairs);
        self.trim();
        self
    }
}

/// Faces per parallel task.
const CHUNK: usize = 2048;

/// Exact self-intersection test over a BVH of face boxes.
fn self_intersections(s: &Surface, st: &FaceStatus) -> SelfIntersections {
    let mut items = Vec::new();
    for (f, t) in s.triangles.iter().enumerate() {
        if st.geom_ok[f] {
            let p = t.map(|v| s.vertices[v as usize]);
            let lo = p[0].min(p[1]).min(p[2]);
            let hi = p[0].max(p[1]).max(p[2]);
            let b = Box3 {
                min: lo.to_array(),
                max: hi.to_array(),
            };
            items.push((f as u32, b));
        }
    }
    // Every corner tested lies in the box of the faces tested: a static filter holds.
    let corners = items
        .iter()
        .flat_map(|&(f, _)| s.triangles[f as usize].map(|v| &s.vertices[v as usize]));
    let filter = StaticFilter::of_points(corners);
    let bvh = Bvh::build(items);
    let used = AtomicU64::new(0);
    let stop = AtomicBool::new(false);
    let n = bvh.len();
    let range = |c: usize| c * CHUNK..n.min((c + 1) * CHUNK);
    let total = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| scan_faces(s, &bvh, &filter, range(c), &used, &stop))
        .reduce(Partial::default, Partial::merge);
    SelfIntersections {
        count: total.count,
        pairs: total
            .pairs
            .iter()
            .map(|&(a, b)| IntersectingPair {
                a: face_ref(s, a),
                b: face_ref(s, b),
            })
            .collect(),
        candidates: total.candidates,
        truncated: stop.load(Ordering::Relaxed),
    }
}

/// Tests the faces at leaf-order positions `range` against the overlapping faces later
/// in leaf order.
fn scan_faces(
    s: &Surface,
    bvh: &Bvh,
    filter: &StaticFilter,
    range: std::ops::Range<usize>,
    used: &AtomicU64,
    stop: &AtomicBool,
) -> Partial {
    let mut part = Partial::default();
    for pos in range {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let (f, bf) = bvh.item(pos);
        let tf = s.triangles[f as usize];
        let pf = tf.map(|v| s.vertices[v as usize]);
        let kf = sorted_ids(tf);
        let mut tested = 0u64;
        bvh.query_after(pos + 1, &bf, |g| {
            tested += 1;
            let tg = s.triangles[g as usize];
            if sorted_ids(tg) == kf {
                return;
            }
            let pg = tg.map(|v| s.vertices[v as usize]);
            if faces_intersect_in(filter, &pf, tf, &pg, tg) {
                part.count += 1;
                part.pairs.push((f.min(g), f.max(g)));
            }
        });
        part.candidates += tested;
        if part.pairs.len() > 2 * MAX_PAIRS {
            part.trim();
        }
        if used.fetch_add(tested, Ordering::Relaxed) + tested > PAIR_BUDGET {
            stop.store(true, Ordering::Relaxed);
        }
    }
    part.trim();
    part
}
