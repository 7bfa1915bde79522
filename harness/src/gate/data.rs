//! The gate's inputs: the committed baseline (`reports/baseline/ci.json`, one
//! [`GateRow`] per model x runner, distilled from records) and the reviewed
//! tolerances (`reports/baseline/tolerances.toml`).

use crate::records::{Record, Status};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Why the gate could not even compare.
#[derive(Debug, thiserror::Error)]
pub enum GateError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The baseline is not valid JSON of the expected shape.
    #[error("{path}: bad baseline: {msg}")]
    Baseline {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
    /// The tolerances file is not valid.
    #[error("{path}: bad tolerances: {msg}")]
    Tolerances {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
    /// The run directory holds no record.
    #[error("{0}: no records (results.jsonl missing or empty)")]
    EmptyRun(PathBuf),
}

/// What the gate keeps of one record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GateRow {
    /// Corpus model id.
    pub model: String,
    /// Runner id.
    pub mesher: String,
    /// How the run ended.
    pub status: Status,
    /// Output tets (ok rows).
    pub tets: Option<usize>,
    /// Worst Q_K (ok rows; `null` for a degenerate tet's infinity).
    pub worst_q_k: Option<f64>,
    /// % of tets with Q_K < 3 (ok rows).
    pub well_shaped_percent: Option<f64>,
    /// No inverted tet, no face in three tets, the boundary kept where checked.
    pub valid: Option<bool>,
    /// Wall-clock seconds of the child.
    pub wall_seconds: Option<f64>,
}

impl GateRow {
    /// The gate's view of a record.
    pub fn from_record(r: &Record) -> GateRow {
        let q = r.quality.as_ref();
        GateRow {
            model: r.model.clone(),
            mesher: r.mesher.clone(),
            status: r.status,
            tets: r.tets,
            worst_q_k: q.map(|q| q.worst_q_k).filter(|w| w.is_finite()),
            well_shaped_percent: q.map(|q| q.well_shaped_percent),
            valid: r.validity.as_ref().map(|v| {
                v.inverted == 0 && v.non_manifold_faces == 0 && v.boundary_kept != Some(false)
            }),
            wall_seconds: r.wall_seconds,
        }
    }

    /// True when the model meshed.
    pub fn ok(&self) -> bool {
        self.status == Status::Ok
    }
}

/// The committed baseline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Baseline {
    /// Git revision the baseline run was made from.
    pub git_revision: String,
    /// Machine of the baseline run.
    pub machine: String,
    /// UTC time it was written.
    pub created: String,
    /// Our rows and the peers' rows the speed ratios need.
    pub rows: Vec<GateRow>,
}

impl Baseline {
    /// Reads a baseline file.
    pub fn read(path: &Path) -> Result<Baseline, GateError> {
        let text = std::fs::read_to_string(path).map_err(|source| GateError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        serde_json::from_str(&text).map_err(|e| GateError::Baseline {
            path: path.to_path_buf(),
            msg: e.to_string(),
        })
    }

    /// Writes it as pretty JSON (one reviewable diff per changed value).
    pub fn write(&self, path: &Path) -> Result<(), GateError> {
        let io = |source| GateError::Io {
            path: path.to_path_buf(),
            source,
        };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let mut text = serde_json::to_string_pretty(self).map_err(|e| GateError::Baseline {
            path: path.to_path_buf(),
            msg: e.to_string(),
        })?;
        text.push('\n');
        std::fs::write(path, text).map_err(io)
    }
}

/// Bounds on quality (see tolerances.toml).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QualityTolerance {
    /// Worst Q_K may grow by this fraction.
    pub worst_q_k_rel: f64,
    /// % Q_K < 3 may drop by this many points.
    pub well_shaped_drop: f64,
}

/// Bound on the tet count.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TetsTolerance {
    /// Relative band around the baseline count.
    pub band: f64,
}

/// Bounds on the speed ratios.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedTolerance {
    /// The ratio may drop to this fraction of the baseline's.
    pub min_ratio: f64,
    /// Below this total wall time (seconds) a side is not timed.
    pub min_seconds: f64,
    /// A model counts in the median ratio when both sides ran at least this long in the
    /// baseline (the run is compared over the same models).
    pub min_model_seconds: f64,
}

/// `reports/baseline/tolerances.toml`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    /// Quality bounds.
    pub quality: QualityTolerance,
    /// Tet count band.
    pub tets: TetsTolerance,
    /// Speed ratio bounds.
    pub speed: SpeedTolerance,
    /// Our runner id -> the peers it is timed against.
    pub peers: BTreeMap<String, Vec<String>>,
}

impl Tolerances {
    /// Reads and parses the tolerances file.
    pub fn read(path: &Path) -> Result<Tolerances, GateError> {
        let text = std::fs::read_to_string(path).map_err(|source| GateError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        toml::from_str(&text).map_err(|e| GateError::Tolerances {
            path: path.to_path_buf(),
            msg: e.to_string(),
        })
    }

    /// Every peer some runner of ours is timed against.
    pub fn all_peers(&self) -> Vec<&str> {
        let mut v: Vec<&str> = self.peers.values().flatten().map(String::as_str).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// True for the runners the gate guards.
pub fn is_ours(mesher: &str) -> bool {
    mesher.starts_with("ours")
}
