//! The attempts of the boundary recovery (paper §4.2): the edges in sorted order
//! first, other orders and rebuilding rounds when entities stay stuck, one level of
//! preparatory removals fewer when input edges were split. The recovery's outcome on
//! hard surfaces hangs on many small choices (Si, "TetGen, a Delaunay-based quality
//! tetrahedral mesh generator", ACM TOMS 2015, shuffles its segments for the same
//! reason); the first success is kept.

use super::EdgeOrder;
use super::{boundary_attempt, BoundaryError, BoundaryMesh, BoundaryOptions, BoundaryReport};
use crate::surface::Surface;
use std::time::Instant;

/// Builds T(S,F) for a closed surface.
///
/// The recovery's outcome on hard surfaces (long thin coplanar triangles) hangs on many
/// small choices, the order of the edges among them: recovering them in a random order
/// instead of the sorted one left entities stuck on anchor, cheese or turbine for a
/// quarter to a half of the seeds tried, most of which another order recovers. So when
/// the incremental rounds leave entities stuck, the recovery runs again in
/// [`ORDER_RETRIES`] shuffled orders, then once with the rebuilding rounds, and the
/// first success is kept (the report counts the attempts). The error of the first
/// attempt is returned when all fail.
pub fn boundary_mesh(
    surface: &Surface,
    options: &BoundaryOptions,
) -> Result<(BoundaryMesh, BoundaryReport), BoundaryError> {
    let t0 = Instant::now();
    let first = match boundary_attempt(surface, options) {
        Ok(r) => return Ok(kept(surface, options, r, 1, t0)),
        Err(e @ BoundaryError::Unrecovered { .. }) => e,
        Err(e) => return Err(e),
    };
    // The first of `attempt_options` is `options` itself, done above.
    for (k, opts) in attempt_options(options).iter().enumerate().skip(1) {
        match boundary_attempt(surface, opts) {
            Ok(r) => return Ok(kept(surface, opts, r, k + 1, t0)),
            Err(BoundaryError::Unrecovered { .. }) => {}
            Err(e) => return Err(e),
        }
    }
    Err(first)
}

/// The successful recovery `r`, the `attempts`-th, after the one more attempt of
/// [`shallower_if_better`] when it split input edges; the report counts the attempts.
fn kept(
    surface: &Surface,
    options: &BoundaryOptions,
    mut r: (BoundaryMesh, BoundaryReport),
    mut attempts: usize,
    t0: Instant,
) -> (BoundaryMesh, BoundaryReport) {
    if options.flip_depth > 1 && boundary_steiner(&r.1) > 0 {
        attempts += 1;
        r = shallower_if_better(surface, options, r);
    }
    if attempts > 1 {
        r.1.attempts = attempts;
        r.1.seconds_all_attempts = t0.elapsed().as_secs_f64();
    }
    r
}

/// Shuffled edge orders tried after a first incremental recovery failed.
pub(super) const ORDER_RETRIES: u64 = 3;

/// The options of the successive attempts of [`boundary_mesh`]: `options`, then (for
/// an incremental recovery) the same in [`ORDER_RETRIES`] shuffled edge orders, then
/// with the rebuilding rounds. The input is checked by the first only.
pub(super) fn attempt_options(options: &BoundaryOptions) -> Vec<BoundaryOptions> {
    let mut out = vec![options.clone()];
    if !options.incremental {
        return out;
    }
    let base = match options.edge_order {
        EdgeOrder::Sorted => options.seed,
        EdgeOrder::Shuffled(k) => k,
    };
    for k in 1..=ORDER_RETRIES {
        out.push(BoundaryOptions {
            edge_order: EdgeOrder::Shuffled(base.wrapping_add(k.wrapping_mul(GOLDEN))),
            check_input: false,
            ..options.clone()
        });
    }
    out.push(BoundaryOptions {
        incremental: false,
        check_input: false,
        ..options.clone()
    });
    out
}

/// The 64-bit golden ratio: seeds of the retried orders spread apart.
const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// Steiner points left on input edges and faces.
fn boundary_steiner(r: &BoundaryReport) -> usize {
    r.steiner_on_edges + r.steiner_on_faces
}

/// `deep` (a recovery with boundary Steiner points) or, when it has fewer of them,
/// the recovery with one level of preparatory removals.
fn shallower_if_better(
    surface: &Surface,
    options: &BoundaryOptions,
    deep: (BoundaryMesh, BoundaryReport),
) -> (BoundaryMesh, BoundaryReport) {
    let shallow = BoundaryOptions {
        flip_depth: 1,
        check_input: false,
        ..options.clone()
    };
    match boundary_attempt(surface, &shallow) {
        Ok(r) if boundary_steiner(&r.1) < boundary_steiner(&deep.1) => r,
        _ => deep,
    }
}
