//! The attempts of the boundary recovery (paper §4.2): the edges in sorted order
//! first, other orders and rebuilding rounds when entities stay stuck, one level of
//! preparatory removals fewer when input edges were split. The recovery's outcome on
//! hard surfaces hangs on many small choices (Si, "TetGen, a Delaunay-based quality
//! tetrahedral mesh generator", ACM TOMS 2015, shuffles its segments for the same
//! reason); the first success that keeps the input edges whole is kept, else the best.

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
/// first success is kept (the report counts the attempts). A success that leaves split
/// points on input edges is followed by the other orders too (not the rebuilding
/// rounds, seconds on cheese), and the one with the fewest Steiner points on the input,
/// then inside, is kept: on cheese, 3 of 11 insertion orders kept split points (up to
/// 73), 2 do with the retries (1 and 6). The error of the first attempt is returned
/// when all fail.
pub fn boundary_mesh(
    surface: &Surface,
    options: &BoundaryOptions,
) -> Result<(BoundaryMesh, BoundaryReport), BoundaryError> {
    let t0 = Instant::now();
    match attempt_all(surface, options, t0) {
        // Faces listed either way round (a defect of the check) are turned to agree,
        // and the surface is tried again; the report counts them. Only after a
        // refusal: a surface that passes the check pays nothing for it.
        Err(e @ BoundaryError::Defective { .. }) => match surface.reoriented() {
            Some((turned, n)) => {
                let mut done = attempt_all(&turned, options, t0)?;
                done.1.faces_reoriented = n;
                Ok(done)
            }
            None => Err(e),
        },
        done => done,
    }
}

/// [`boundary_mesh`] on a surface whose faces agree in orientation.
fn attempt_all(
    surface: &Surface,
    options: &BoundaryOptions,
    t0: Instant,
) -> Result<(BoundaryMesh, BoundaryReport), BoundaryError> {
    let mut first_error = None;
    // The best success so far, with its options.
    let mut best: Option<(BoundaryOptions, (BoundaryMesh, BoundaryReport))> = None;
    let mut attempts = 0;
    for opts in attempt_options(options) {
        // The rebuilding rounds are the last resort of a failed recovery, too slow
        // (seconds on cheese) to only improve a success.
        if best.is_some() && !opts.incremental {
            break;
        }
        attempts += 1;
        match boundary_attempt(surface, &opts) {
            Ok(r) => {
                if best.as_ref().is_none_or(|b| score(&r.1) < score(&b.1 .1)) {
                    best = Some((opts, r));
                }
            }
            Err(e @ BoundaryError::Unrecovered { .. }) => {
                first_error.get_or_insert(e);
            }
            Err(e) => return Err(e),
        }
        // A success that split input edges for good is not the end: another order
        // often recovers them without (cheese with other insertion orders).
        if best
            .as_ref()
            .is_some_and(|b| boundary_steiner(&b.1 .1) == 0)
        {
            break;
        }
    }
    match best {
        Some((opts, r)) => Ok(kept(surface, &opts, r, attempts, t0)),
        // Every attempt ran and failed, so `first_error` is set; the default is not
        // reached.
        None => Err(first_error.unwrap_or(BoundaryError::Unrecovered {
            edges: 0,
            faces: 0,
            rounds: 0,
            first: String::new(),
        })),
    }
}

/// How good a recovery is: fewer Steiner points on the input first, then fewer inside.
fn score(r: &BoundaryReport) -> (usize, usize) {
    (boundary_steiner(r), r.steiner_interior)
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

/// Shuffled edge orders tried after a first incremental recovery failed. At 3,
/// oblong-shuffled (CGAL data) failed in the sorted order, the 3 shuffled ones and the
/// rebuilding rounds (116 input edges stuck), and so did 1 of its 11 other seeds; the
/// fifth shuffled order recovers it, and the other seed's too. The orders run only
/// while the ones before fail: a surface recovered by the first three is unchanged.
pub(super) const ORDER_RETRIES: u64 = 7;

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
