//! Seed points deep inside the domain before the first front (not in the paper).
//!
//! The first front inserts its points into T(S,F), whose interior tets join boundary
//! vertices across the whole domain. On a smooth convex surface these vertices are
//! nearly cospherical, and so are the first layer's points: each new point lies inside
//! the circumspheres of a large share of the tets across the void, and its cavity
//! re-triangulates that share (sphere-100k: 370 cavity tets per attempt in the first
//! iteration against about 20 later, 10.5 s of a 30 s front). A sparse lattice of
//! points far from the surface, inserted first, breaks the void into tets a few sizes
//! across; the front then meets these points as it meets any vertex (its points are
//! filtered against them).

use super::{Candidate, FieldMesh, FrontParams};
use crate::delaunay::sort::SplitMix64;
use crate::geom::Point;
use crate::sizing::SizeField;
use crate::tetmesh::TetId;

/// Largest number of lattice points tried (the spacing grows to stay below it).
const MAX_CANDIDATES: usize = 1 << 20;

/// The seed candidates: the points of a cubic lattice of spacing
/// `params.seed_spacing` times the median size at the domain's vertices, over the
/// domain's bounding box, in lattice order. Each must keep `params.seed_clearance`
/// (normalised) from every vertex its cavity reaches, which drops those near the
/// surface and outside the domain when they are inserted.
pub(super) fn candidates(
    fm: &FieldMesh,
    field: &dyn SizeField,
    params: &FrontParams,
) -> Vec<Candidate> {
    if !(params.seed_spacing.is_finite() && params.seed_spacing > 0.0) {
        return Vec::new();
    }
    let mesh = &fm.mesh;
    let mut used = vec![false; fm.h.len()];
    let mut hint_tet = None;
    for t in 0..mesh.num_slots() as u32 {
        if fm.cons.region[t as usize] != 0 && mesh.is_alive(TetId(t)) {
            hint_tet.get_or_insert(t);
            for v in mesh.raw_tet(t) {
                if let Some(u) = used.get_mut(v as usize) {
                    *u = true;
                }
            }
        }
    }
    let Some(hint) = hint_tet else {
        return Vec::new();
    };
    let verts: Vec<usize> = (0..used.len()).filter(|&v| used[v]).collect();
    let mut sizes: Vec<f64> = verts.iter().map(|&v| fm.h[v]).collect();
    if sizes.is_empty() {
        return Vec::new();
    }
    let mid = sizes.len() / 2;
    let h_med = *sizes.select_nth_unstable_by(mid, f64::total_cmp).1;
    let pts = mesh.points();
    let (lo, hi) = verts.iter().fold(
        (Point::splat(f64::MAX), Point::splat(f64::MIN)),
        |(lo, hi), &v| (lo.min(pts[v]), hi.max(pts[v])),
    );
    let extent = hi - lo;
    let mut step = params.seed_spacing * h_med;
    let count = |s: f64| {
        let n = (extent / s).floor() + Point::ONE;
        n.x * n.y * n.z
    };
    if !(step > 0.0 && step.is_finite()) {
        return Vec::new();
    }
    while count(step) > MAX_CANDIDATES as f64 {
        step *= 1.25;
    }
    let n = ((extent / step).floor() + Point::ONE).as_uvec3();
    // The lattice centred in the box.
    let origin = lo + (extent - (n.as_dvec3() - Point::ONE) * step) * 0.5;
    let mut out = Vec::new();
    let mut hint_size = 0u32;
    for k in 0..n.z {
        for j in 0..n.y {
            for i in 0..n.x {
                let p =
                    origin + (Point::new(i as f64, j as f64, k as f64) + jitter(i, j, k)) * step;
                let h = field.size(p, &mut hint_size);
                if p.is_finite() && h.is_finite() && h > 0.0 {
                    out.push(Candidate {
                        p,
                        h,
                        k2: hint,
                        layer: 0,
                        delta_f: params.seed_clearance,
                        delta_v: params.seed_clearance,
                    });
                }
            }
        }
    }
    out
}

/// A pseudo-random offset in `[-JITTER, JITTER]^3` for lattice point `(i, j, k)`: a
/// regular lattice is cospherical eight points at a time, and the kernel's choices
/// among near-cospherical points make needlessly large cavities.
fn jitter(i: u32, j: u32, k: u32) -> Point {
    let key = (i as u64) << 42 ^ (j as u64) << 21 ^ k as u64;
    let mut rng = SplitMix64::new(key ^ 0x9E37_79B9_7F4A_7C15);
    let mut next = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
    Point::new(next(), next(), next()) * JITTER
}

/// Largest offset of a seed from its lattice point, in lattice steps.
const JITTER: f64 = 0.25;
