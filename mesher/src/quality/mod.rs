//! Element quality (paper §6.1, §8): the one metric code path of the project.
//!
//! Every stage of the mesher and the harness measures through this module and never
//! re-implements a metric:
//! - [`tet`]: per-tet measures from four points (signed volume, `Q_K`, dihedral angles,
//!   radius ratio, edge lengths), allocation-free, plus [`TetMeasures`] in one pass;
//! - [`length`]: normalised edge length with respect to a size map (§5.3.2) and edge
//!   quality (§6.1);
//! - [`target`]: the target quality `Q_t` of a boundary surface (§8): the best `Q_K`
//!   reachable on its worst face;
//! - [`room`]: the same with each face's tet kept inside the domain (thin parts);
//! - [`summary`]: mesh-level statistics (Table 1 columns, `Q_K` and edge-length
//!   histograms), streaming through [`SummaryBuilder`];
//! - [`band`]: the share of interior edges with normalised length in `[0.6, 1.67]`;
//! - [`histogram`]: the paper's `Q_K` and edge-length bins (§8, Figs. 13-17).
//!
//! Conventions: `Q_K` is in `[1, inf)`, bigger is worse, 1 for the regular tet, infinite
//! for a flat or non-finite tet; inversion is reported by the signed volume, never by
//! `Q_K`. No function panics on degenerate geometry.

pub mod band;
pub mod histogram;
pub mod length;
pub mod room;
pub mod summary;
pub mod target;
pub mod tet;

pub use band::{edge_band, edges_off_surface, EdgeBand, BAND_HIGH, BAND_LOW};
pub use histogram::{Histogram, LENGTH_BIN_EDGES, QUALITY_BIN_EDGES};
pub use length::{
    edge_quality, normalized_length, normalized_length_piecewise, normalized_length_points,
    normalized_length_polyline, NEAR_EQUAL_RATIO_HIGH, NEAR_EQUAL_RATIO_LOW,
};
pub use room::{target_quality_in_domain, RoomQuality};
pub use summary::{
    edge_length_histogram, edge_length_stats, median, mesh_edge_length_stats, summarize,
    summarize_tets, surface_edge_length_histogram, unique_tet_edges, unique_triangle_edges,
    EdgeLengthStats, QualitySummary, SummaryBuilder,
};
pub use target::{face_best_q_k, target_quality, TargetQuality};
pub use tet::{
    circumradius, dihedral_angles, dihedral_min_max, edge_length_min_max, edge_lengths, inradius,
    max_dihedral, min_dihedral, q_k, radius_ratio, signed_volume, TetMeasures, ALPHA, TET_EDGES,
    WELL_SHAPED_Q_K,
};
