//! The Delaunay kernel of the paper (§3): incremental insertion `T = T - C(P) + B(P)`
//! with exact, symbolically perturbed predicates, and bulk triangulation of a point set
//! in BRIO/Hilbert order.
//!
//! [`triangulate`] builds the Delaunay tetrahedralisation of any point set with at least
//! four affinely independent points (duplicates are merged and reported). [`box_mesh`]
//! gives the paper's starting mesh: the 8 corners of an enlarged bounding box split into
//! 5 tets (§4.1).

mod kernel;
pub mod sort;

pub use kernel::{Constraints, Inserted, Kernel, KernelStats, Location, Rejection};

use crate::geom::predicates::{orient2d, orient3d, Orientation, StaticFilter};
use crate::geom::Point;
use crate::tetmesh::{TetMesh, VertexId};
use thiserror::Error;

/// Why a point set cannot be triangulated.
#[derive(Debug, Error, PartialEq)]
pub enum DelaunayError {
    /// A coordinate is NaN or infinite.
    #[error("point {index} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite {
        /// Index of the point in the input.
        index: usize,
        /// x.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
    },
    /// Fewer than four affinely independent points: no tet exists.
    #[error("the {distinct} distinct points are {what}: no tetrahedron can be built")]
    Degenerate {
        /// How many distinct points were seen.
        distinct: usize,
        /// "coincident", "collinear" or "coplanar".
        what: &'static str,
    },
    /// More tets than the id space holds.
    #[error("too many tets for 32-bit ids")]
    TooManyTets,
    /// A coordinate is beyond [`MAX_COORDINATE`] in magnitude.
    #[error("point {index} at ({x}, {y}, {z}) is beyond 2^64 in magnitude (the supported range)")]
    OutOfRange {
        /// Index of the point in the input (for [`Kernel::insert`], the vertex it would
        /// have been).
        index: usize,
        /// x.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
    },
}

/// The largest coordinate magnitude the kernel accepts, 2^64 (about 1.8e19). The exact
/// predicates decide any finite input, but the constructions of the later stages
/// (circumcentres, volumes, sizes) overflow near 1e300 (fuzzing fed such points).
pub const MAX_COORDINATE: f64 = 18_446_744_073_709_551_616.0;

/// Checks that `p` (point `index`) is finite and within [`MAX_COORDINATE`].
pub(crate) fn check_point(index: usize, p: Point) -> Result<(), DelaunayError> {
    let (x, y, z) = (p.x, p.y, p.z);
    if !p.is_finite() {
        return Err(DelaunayError::NonFinite { index, x, y, z });
    }
    if p.abs().max_element() > MAX_COORDINATE {
        return Err(DelaunayError::OutOfRange { index, x, y, z });
    }
    Ok(())
}

/// How the points are ordered before insertion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum InsertionOrder {
    /// Biased randomized insertion order with Hilbert-sorted rounds (default).
    #[default]
    Brio,
    /// One Hilbert sort of all points.
    Hilbert,
    /// The input order.
    Input,
}

/// Options of [`triangulate`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DelaunayOptions {
    /// Insertion order.
    pub order: InsertionOrder,
    /// Seed of the BRIO shuffle (output is deterministic for a given seed).
    pub seed: u64,
}

impl Default for DelaunayOptions {
    fn default() -> Self {
        DelaunayOptions {
            order: InsertionOrder::Brio,
            seed: 0x5EED,
        }
    }
}

/// The result of [`triangulate`].
#[derive(Debug)]
pub struct Triangulation {
    /// The mesh; its vertices are stored in insertion order.
    pub mesh: TetMesh,
    /// For each input point, its vertex (duplicates share one).
    pub vertex_of_input: Vec<VertexId>,
    /// Number of input points merged into an earlier identical point.
    pub duplicates: usize,
    /// Kernel counters.
    pub stats: KernelStats,
}

/// The Delaunay tetrahedralisation of `points`.
pub fn triangulate(
    points: &[Point],
    options: &DelaunayOptions,
) -> Result<Triangulation, DelaunayError> {
    for (index, &p) in points.iter().enumerate() {
        check_point(index, p)?;
    }
    let order: Vec<u32> = match options.order {
        InsertionOrder::Brio => sort::brio_order(points, options.seed),
        InsertionOrder::Hilbert => sort::hilbert_order(points),
        InsertionOrder::Input => (0..points.len() as u32).collect(),
    };
    let simplex = initial_simplex(points, &order)?;
    let mut vertex_of_input = vec![VertexId(0); points.len()];
    for (k, &i) in simplex.iter().enumerate() {
        vertex_of_input[i as usize] = VertexId(k as u32);
    }
    let seed: Vec<Point> = simplex.iter().map(|&i| points[i as usize]).collect();
    let mut mesh =
        TetMesh::from_tets(seed, &[[0, 1, 2, 3]]).map_err(|_| DelaunayError::TooManyTets)?;
    mesh.reserve_vertices(points.len());
    mesh.reserve_tets(points.len() * 7);
    let mut kernel = Kernel::new();
    kernel.set_filter(StaticFilter::of_points(points));
    let mut duplicates = 0;
    // Gather the points in insertion order first: independent loads that the processor
    // overlaps, instead of one cache miss per insertion inside the dependent loop.
    let ordered: Vec<Point> = order.iter().map(|&i| points[i as usize]).collect();
    let mut inserted = Vec::with_capacity(order.len());
    for (&i, &p) in order.iter().zip(&ordered) {
        if simplex.contains(&i) {
            inserted.push(vertex_of_input[i as usize]);
            continue;
        }
        let ins = kernel.insert(&mut mesh, p)?;
        if matches!(ins, Inserted::Duplicate(_)) {
            duplicates += 1;
        }
        inserted.push(ins.vertex());
    }
    for (&i, &v) in order.iter().zip(&inserted) {
        vertex_of_input[i as usize] = v;
    }
    Ok(Triangulation {
        mesh,
        vertex_of_input,
        duplicates,
        stats: kernel.stats,
    })
}

/// Four affinely independent input points, the first found along `order`, listed so
/// that they form a positive tet.
fn initial_simplex(points: &[Point], order: &[u32]) -> Result<[u32; 4], DelaunayError> {
    let p = |i: u32| points[i as usize];
    let Some(&a) = order.first() else {
        return Err(DelaunayError::Degenerate {
            distinct: 0,
            what: "fewer than four",
        });
    };
    let b = order.iter().copied().find(|&i| p(i) != p(a));
    let Some(b) = b else {
        return Err(DelaunayError::Degenerate {
            distinct: 1,
            what: "coincident",
        });
    };
    let c = order
        .iter()
        .copied()
        .find(|&i| !collinear(p(a), p(b), p(i)));
    let Some(c) = c else {
        return Err(DelaunayError::Degenerate {
            distinct: 2,
            what: "collinear",
        });
    };
    let mut d_or = Orientation::Zero;
    let d = order.iter().copied().find(|&i| {
        d_or = orient3d(p(a), p(b), p(c), p(i));
        d_or != Orientation::Zero
    });
    let Some(d) = d else {
        return Err(DelaunayError::Degenerate {
            distinct: 3,
            what: "coplanar",
        });
    };
    Ok(if d_or == Orientation::Positive {
        [a, b, c, d]
    } else {
        [b, a, c, d]
    })
}

/// Exact collinearity: the three points are collinear iff every axis-aligned projection
/// of the triangle is degenerate.
fn collinear(a: Point, b: Point, c: Point) -> bool {
    let z = |i: usize, j: usize| {
        orient2d([a[i], a[j]], [b[i], b[j]], [c[i], c[j]]) == Orientation::Zero
    };
    z(0, 1) && z(1, 2) && z(0, 2)
}

/// The paper's starting mesh (§4.1): the 8 corners of the box `[min, max]` and tets
/// filling it, with ghosts outside. Corner `i` is vertex `i`, at `(x, y, z)` with x from
/// bit 0, y from bit 1, z from bit 2 of `i`.
///
/// The 8 corners are cospherical, so which split of the box is "Delaunay" is decided by
/// the symbolic perturbation; the split must be the one the perturbed predicates agree
/// with (the paper's fixed 5-tet split is not always), or a later cavity may not be
/// star-shaped. So the corners are triangulated by the kernel itself: 5 or 6 tets.
pub fn box_mesh(min: Point, max: Point) -> Result<TetMesh, DelaunayError> {
    if !(min.is_finite() && max.is_finite()) || min.cmpge(max).any() {
        return Err(DelaunayError::Degenerate {
            distinct: 0,
            what: "an empty box",
        });
    }
    let corners: Vec<Point> = (0..8)
        .map(|i| {
            Point::new(
                if i & 1 != 0 { max.x } else { min.x },
                if i & 2 != 0 { max.y } else { min.y },
                if i & 4 != 0 { max.z } else { min.z },
            )
        })
        .collect();
    let options = DelaunayOptions {
        order: InsertionOrder::Input,
        seed: 0,
    };
    let tr = triangulate(&corners, &options)?;
    // Back to corner numbering: mesh vertex k is the corner inserted k-th.
    let mut corner_of = [0u32; 8];
    for (i, v) in tr.vertex_of_input.iter().enumerate() {
        corner_of[v.index()] = i as u32;
    }
    let tets: Vec<[u32; 4]> = tr
        .mesh
        .finite_tets()
        .map(|t| tr.mesh.tet(t).map(|v| corner_of[v.index()]))
        .collect();
    TetMesh::from_tets(corners, &tets).map_err(|_| DelaunayError::TooManyTets)
}

#[cfg(test)]
mod tests;
