//! One record per (model, mesher) run: what the harness measured, serialised as one JSON
//! line (`results.jsonl`) and one CSV row (`results.csv`). Reports read these only.

use mesher::quality::{EdgeBand, EdgeLengthStats, QualitySummary};
use serde::{Deserialize, Serialize};
use std::path::Path;

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
    /// Not run by choice: a slow peer outside `--limit-slow`'s smallest models.
    Skipped,
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

/// One iteration of the advancing front (ours), as `mesher mesh --stats FILE` reports
/// it: the paper's front convergence curve (NOTES.md §7).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FrontIteration {
    /// Faces in the front at the start of the iteration.
    pub front: usize,
    /// Field points proposed.
    pub proposed: usize,
    /// Field points inserted (after filtration).
    pub inserted: usize,
}

/// The statistics file of `mesher mesh --stats FILE` as far as the harness reads it.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct MesherStats {
    /// One entry per front iteration.
    #[serde(default)]
    pub iterations: Vec<FrontIteration>,
    /// Seconds of the library call (`mesher::mesh`), reading and writing excluded.
    #[serde(default)]
    pub time_total: Option<f64>,
    /// Seconds of the optimisation (paper §6) within it.
    #[serde(default)]
    pub time_optimize: Option<f64>,
}

impl MesherStats {
    /// The statistics in a `mesher mesh --stats` file; `None` when the file is absent or
    /// unreadable (the record then simply has no series and no share).
    pub fn read(path: &Path) -> Option<MesherStats> {
        let text = std::fs::read_to_string(path).ok()?;
        serde_json::from_str(&text).ok()
    }

    /// The front iterations, `None` when there are none.
    pub fn into_front(self) -> Option<Vec<FrontIteration>> {
        (!self.iterations.is_empty()).then_some(self.iterations)
    }

    /// The optimisation's share of the library call's time, in percent.
    pub fn optimize_share(&self) -> Option<f64> {
        match (self.time_optimize, self.time_total) {
            (Some(o), Some(t)) if t > 0.0 => Some(100.0 * o / t),
            _ => None,
        }
    }
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
    /// Target quality with each face's best tet kept inside the domain (an estimate,
    /// `mesher::quality::room`).
    #[serde(default)]
    pub q_t_domain: Option<f64>,
    /// Fraction of input faces whose best tet inside the domain has Q_K above 3.
    #[serde(default)]
    pub hard_domain_fraction: Option<f64>,
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
    /// The output's interior edges (off its boundary) with normalised length in
    /// `[0.6, 1.67]` (issue 5's band), same size field.
    #[serde(default)]
    pub edge_band: Option<EdgeBand>,
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
    /// True when the harness flipped every tet because the peer wrote them negatively
    /// oriented (fTetWild); `None` when no mesh was measured.
    #[serde(default)]
    pub orientation_flipped: Option<bool>,
    /// Exit code of the child, if it exited.
    #[serde(default)]
    pub exit_code: Option<i32>,
    /// Signal that ended the child, if any.
    #[serde(default)]
    pub signal: Option<i32>,
    /// Seconds the peer spent in its meshing call alone, as its driver script timed it
    /// (Python peers: without interpreter start-up and file I/O).
    #[serde(default)]
    pub mesh_seconds: Option<f64>,
    /// Mean input edge length handed to peers that need a size (fTetWild).
    #[serde(default)]
    pub edge_length: Option<f64>,
    /// The runner's configuration in one line (switches, size policy).
    #[serde(default)]
    pub configuration: Option<String>,
    /// Per-iteration front statistics (ours only).
    #[serde(default)]
    pub front: Option<Vec<FrontIteration>>,
    /// Percent of our mesher's library call (`time_total` of its statistics, the last
    /// repeat's) spent in the optimisation (ours only; issue 6 bounds it).
    #[serde(default)]
    pub optimize_share: Option<f64>,
}

impl Record {
    /// Output tets per wall-clock second.
    pub fn tets_per_second(&self) -> Option<f64> {
        match (self.tets, self.wall_seconds) {
            (Some(t), Some(w)) if w > 0.0 => Some(t as f64 / w),
            _ => None,
        }
    }

    /// Peak RSS bytes per output tet.
    pub fn bytes_per_tet(&self) -> Option<f64> {
        match (self.tets, self.peak_rss_bytes) {
            (Some(t), Some(b)) if t > 0 => Some(b as f64 / t as f64),
            _ => None,
        }
    }
}

/// Column names of `results.csv`, in order.
pub const CSV_COLUMNS: &[&str] = &[
    "model",
    "tier",
    "category",
    "mesher",
    "mesher_version",
    "keeps_boundary",
    "status",
    "message",
    "input_vertices",
    "input_faces",
    "q_t",
    "hard_face_fraction",
    "q_t_domain",
    "hard_domain_fraction",
    "vertices",
    "tets",
    "wall_seconds",
    "cpu_seconds",
    "peak_rss_bytes",
    "mesh_seconds",
    "tets_per_second",
    "bytes_per_tet",
    "worst_q_k",
    "median_q_k",
    "mean_q_k",
    "worse_than_target",
    "well_shaped",
    "well_shaped_percent",
    "min_dihedral",
    "max_dihedral",
    "min_radius_ratio",
    "degenerate",
    "edge_length_mean",
    "edge_length_mean_quality",
    "edge_length_min",
    "edge_length_max",
    "edges_in_band_percent",
    "inverted",
    "non_manifold_faces",
    "boundary_kept",
    "volume_ratio",
    "hausdorff",
    "orientation_flipped",
    "exit_code",
    "signal",
    "iterations",
    "optimize_share_percent",
    "git_revision",
    "machine",
    "finished_at",
];

fn opt<T: ToString>(v: Option<T>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

impl Record {
    /// The record as one CSV row (fields in [`CSV_COLUMNS`] order, RFC 4180 quoting).
    pub fn csv_row(&self) -> String {
        let q = self.quality.as_ref();
        let e = self.edge_lengths.as_ref();
        let v = self.validity.as_ref();
        let status = serde_json::to_value(self.status)
            .ok()
            .and_then(|s| s.as_str().map(String::from))
            .unwrap_or_default();
        let fields: Vec<String> = vec![
            self.model.clone(),
            self.tier.clone(),
            self.category.clone(),
            self.mesher.clone(),
            self.mesher_version.clone(),
            self.keeps_boundary.to_string(),
            status,
            self.message.clone().unwrap_or_default(),
            self.input_vertices.to_string(),
            self.input_faces.to_string(),
            opt(self.q_t),
            opt(self.hard_face_fraction),
            opt(self.q_t_domain),
            opt(self.hard_domain_fraction),
            opt(self.vertices),
            opt(self.tets),
            opt(self.wall_seconds),
            opt(self.cpu_seconds),
            opt(self.peak_rss_bytes),
            opt(self.mesh_seconds),
            opt(self.tets_per_second()),
            opt(self.bytes_per_tet()),
            opt(q.map(|q| q.worst_q_k)),
            opt(q.map(|q| q.median_q_k)),
            opt(q.map(|q| q.mean_q_k)),
            opt(q.and_then(|q| q.worse_than_target)),
            opt(q.map(|q| q.well_shaped)),
            opt(q.map(|q| q.well_shaped_percent)),
            opt(q.map(|q| q.min_dihedral)),
            opt(q.map(|q| q.max_dihedral)),
            opt(q.map(|q| q.min_radius_ratio)),
            opt(q.map(|q| q.degenerate)),
            opt(e.map(|e| e.mean)),
            opt(e.map(|e| e.mean_quality)),
            opt(e.map(|e| e.min)),
            opt(e.map(|e| e.max)),
            opt(self.edge_band.as_ref().map(|b| b.in_band_percent)),
            opt(v.map(|v| v.inverted)),
            opt(v.map(|v| v.non_manifold_faces)),
            opt(v.and_then(|v| v.boundary_kept)),
            opt(v.and_then(|v| v.volume_ratio)),
            opt(v.and_then(|v| v.hausdorff)),
            opt(self.orientation_flipped),
            opt(self.exit_code),
            opt(self.signal),
            opt(self.iterations),
            opt(self.optimize_share),
            self.git_revision.clone(),
            self.machine.clone(),
            self.finished_at.clone(),
        ];
        fields
            .iter()
            .map(|f| csv_field(f))
            .collect::<Vec<_>>()
            .join(",")
    }
}

/// Reads `results.jsonl` (missing file = no records; unreadable lines are skipped).
pub fn read_jsonl(path: &Path) -> std::io::Result<Vec<Record>> {
    match std::fs::read_to_string(path) {
        Ok(text) => Ok(text
            .lines()
            .filter_map(|l| serde_json::from_str(l).ok())
            .collect()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(e),
    }
}

/// Writes `dir/results.jsonl` and `dir/results.csv` with all `records`, each through a
/// temporary file renamed over the old one, so a killed run never leaves a torn file.
pub fn write_all(dir: &Path, records: &[Record]) -> std::io::Result<()> {
    let mut jsonl = String::new();
    for r in records {
        jsonl.push_str(&serde_json::to_string(r).map_err(std::io::Error::other)?);
        jsonl.push('\n');
    }
    let mut csv = CSV_COLUMNS.join(",");
    csv.push('\n');
    for r in records {
        csv.push_str(&r.csv_row());
        csv.push('\n');
    }
    write_atomic(&dir.join("results.jsonl"), &jsonl)?;
    write_atomic(&dir.join("results.csv"), &csv)
}

fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    let tmp = path.with_file_name(name);
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)
}
