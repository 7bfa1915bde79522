//! One record per (model, mesher) run: what the harness measured, serialised as one JSON
//! line (`results.jsonl`) and one CSV row (`results.csv`). Reports read these only.

use mesher::quality::{EdgeLengthStats, QualitySummary};
use serde::{Deserialize, Serialize};

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// The mesher produced a readable, measured mesh.
    Ok,
    /// The mesher is not installed or not available yet.
    Missing,
    /// Non-zero exit code.
    Failed,
    /// Killed by a signal (crash).
    Crashed,
    /// Exceeded the per-run time limit.
    Timeout,
    /// Exited 0 but the output is missing or unreadable.
    InvalidOutput,
    /// The input was refused before meshing (dirty model), as expected.
    Refused,
}

/// Validity of an output mesh, measured by the harness.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Validity {
    /// Tets with non-positive signed volume (after the peer's orientation convention
    /// was normalised, if it writes negative tets consistently).
    pub inverted: usize,
    /// Faces shared by more than two tets.
    pub non_manifold_faces: usize,
    /// Whether every input triangle is a boundary face of the output (peers that keep
    /// the boundary), `None` when not checked.
    pub boundary_kept: Option<bool>,
    /// Sum of tet volumes / enclosed volume of the input surface.
    pub volume_ratio: Option<f64>,
    /// Hausdorff distance between the input surface and the output boundary, relative to
    /// the bounding-box diagonal (peers that move the boundary).
    pub hausdorff: Option<f64>,
}

/// One measured run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// Corpus model id.
    pub model: String,
    /// Tier of the model (ci, nightly, large, dirty).
    pub tier: String,
    /// Category of the model (convex, cad, organic, ...).
    pub category: String,
    /// Runner id (`ours`, `tetgen`, `tetgen-y`, `cgal`, `ftetwild`, `gmsh-hxt`, `gmsh-delaunay`).
    pub mesher: String,
    /// Version string of the peer as it reported it.
    pub mesher_version: String,
    /// True when the peer keeps the input boundary exactly.
    pub keeps_boundary: bool,
    /// How the run ended.
    pub status: Status,
    /// Error text or the tail of stderr when the run did not end well.
    pub message: Option<String>,
    /// Input surface vertices.
    pub input_vertices: usize,
    /// Input surface triangles.
    pub input_faces: usize,
    /// Target quality of the input surface (paper §8).
    pub q_t: Option<f64>,
    /// Fraction of input faces whose best possible Q_K exceeds 3.
    pub hard_face_fraction: Option<f64>,
    /// Output vertices.
    pub vertices: Option<usize>,
    /// Output tets.
    pub tets: Option<usize>,
    /// Wall-clock seconds of the child process.
    pub wall_seconds: Option<f64>,
    /// User + system CPU seconds of the child process.
    pub cpu_seconds: Option<f64>,
    /// Peak resident set size of the child, bytes.
    pub peak_rss_bytes: Option<u64>,
    /// Quality statistics of the output (from `mesher::quality`).
    pub quality: Option<QualitySummary>,
    /// Normalised edge lengths of the output against the input-derived size field.
    pub edge_lengths: Option<EdgeLengthStats>,
    /// Validity checks of the output.
    pub validity: Option<Validity>,
    /// Front iterations (ours only).
    pub iterations: Option<usize>,
    /// Git revision of this project.
    pub git_revision: String,
    /// Machine description (cpus, model name).
    pub machine: String,
    /// UTC time the run finished, RFC 3339.
    pub finished_at: String,
}
