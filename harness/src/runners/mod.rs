//! Runners: one per mesher. A runner only turns typed options into the peer's invocation,
//! runs it as a measured child process, and returns the output path; the harness then
//! measures the output itself (never trusting a peer's statistics).

pub mod cgal;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

/// What a peer is, declared as data.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PeerInfo {
    /// Stable id used in records (`tetgen`, `gmsh-hxt`, ...).
    pub id: &'static str,
    /// Human name for tables.
    pub name: &'static str,
    /// True when the peer keeps the input boundary triangles exactly.
    pub keeps_boundary: bool,
}

/// One meshing job.
#[derive(Clone, Debug)]
pub struct RunRequest<'a> {
    /// Corpus model id.
    pub model: &'a str,
    /// The input surface file (as the corpus provides it).
    pub input: &'a Path,
    /// A scratch directory owned by this run.
    pub workdir: &'a Path,
    /// Per-run time limit.
    pub timeout: Duration,
    /// Target edge length for peers that need one (mean input edge length).
    pub edge_length: f64,
}

/// Resource use of a child process, measured by the harness (wait4/rusage).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProcessStats {
    /// Wall-clock seconds.
    pub wall_seconds: f64,
    /// User + system CPU seconds.
    pub cpu_seconds: f64,
    /// Peak resident set size, bytes.
    pub peak_rss_bytes: u64,
    /// Exit code, if the child exited.
    pub exit_code: Option<i32>,
    /// Signal, if the child was killed by one.
    pub signal: Option<i32>,
    /// True when the harness killed it at the time limit.
    pub timed_out: bool,
    /// Last lines of stderr.
    pub stderr_tail: String,
}

/// What a successful run produced.
#[derive(Clone, Debug)]
pub struct RunOutput {
    /// The output volume mesh, readable by `mesher::io::read_volume`.
    pub mesh: PathBuf,
    /// The peer's version as it reports it.
    pub version: String,
    /// Measured resources.
    pub stats: ProcessStats,
}

/// Why a run produced no mesh.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The peer is not installed.
    #[error("not available: {0}")]
    Missing(String),
    /// The peer ran and failed (exit code, signal or time limit in `stats`).
    #[error("{message}")]
    Failed {
        /// What happened.
        message: String,
        /// Measured resources.
        stats: ProcessStats,
    },
    /// Preparing the input or reading the output failed.
    #[error("{0}")]
    Io(String),
}

/// A mesher the harness can drive.
pub trait Runner {
    /// What the peer is.
    fn info(&self) -> PeerInfo;
    /// Runs the peer on one model.
    fn run(&self, request: &RunRequest<'_>) -> Result<RunOutput, RunError>;
}

/// Arguments of `harness run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Corpus tier to run (ci, nightly, large, dirty).
    #[arg(long, default_value = "ci")]
    pub corpus: String,
    /// Output directory for results.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `harness run`.
pub fn cli(_args: RunArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("harness run: not implemented yet")
}
