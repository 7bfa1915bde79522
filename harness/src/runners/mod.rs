//! Runners: one per mesher. A runner only turns typed options into the peer's invocation,
//! runs it as a measured child process, and returns the output path; the harness then
//! measures the output itself (never trusting a peer's statistics).
//!
//! Submodules: [`process`] (the measured child), one module per peer ([`tetgen`],
//! [`gmsh`], [`ftetwild`], [`cgal`], [`ours`]), [`input`] (the input surface as each
//! peer is handed it: shells, nesting, hole points) and [`sizes`] (the size field of the
//! sized configurations).
//! [`registry`] lists every runner; `harness run` is in [`crate::run`].

pub mod cgal;
pub mod ftetwild;
pub mod gmsh;
pub mod input;
pub mod ours;
pub mod process;
pub mod sizes;
pub mod tetgen;

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
    /// True for a configuration that follows the size field of NOTES.md §3
    /// ([`sizes`]) instead of the peer's own size policy.
    pub sized: bool,
    /// True for a peer that takes minutes per model (`--limit-slow` applies to it).
    pub slow: bool,
    /// The configuration in one line (switches, options), for reports.
    pub configuration: String,
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

/// Every runner, in table order: each peer's default configuration, then its sized one.
pub fn registry() -> Vec<Box<dyn Runner>> {
    vec![
        Box::new(ours::Ours::full()),
        Box::new(ours::Ours::front_only()),
        Box::new(ours::OursBoundary),
        Box::new(tetgen::TetGen::boundary_only()),
        Box::new(tetgen::TetGen::default_switches()),
        Box::new(tetgen::TetGen::keep_boundary()),
        Box::new(tetgen::TetGen::keep_boundary().sized()),
        Box::new(gmsh::Gmsh::hxt()),
        Box::new(gmsh::Gmsh::hxt().sized()),
        Box::new(gmsh::Gmsh::delaunay()),
        Box::new(gmsh::Gmsh::delaunay().sized()),
        Box::new(ftetwild::FTetWild::default()),
        Box::new(ftetwild::FTetWild { sized: true }),
        Box::new(cgal::CgalMesh3::new(cgal_binary())),
        Box::new(cgal::CgalMesh3::new(cgal_binary()).sized()),
    ]
}

fn cgal_binary() -> PathBuf {
    cgal::CgalMesh3::locate().unwrap_or_else(|| PathBuf::from("cgal-mesh3"))
}

/// The project root (scripts/, .venv/): `HARNESS_ROOT` if set, else the workspace this
/// crate was built from.
pub fn project_root() -> PathBuf {
    match std::env::var_os("HARNESS_ROOT") {
        Some(r) => PathBuf::from(r),
        None => Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from(".")),
    }
}

/// The venv's Python (`MESHER_VENV` or `<root>/.venv`), as `scripts/setup.sh` makes it.
pub fn venv_python() -> PathBuf {
    let venv = std::env::var_os("MESHER_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| project_root().join(".venv"));
    venv.join("bin").join("python")
}

/// Arguments of `harness run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Corpus tier selections to run, comma-separated (ci, nightly, large, dirty, all).
    #[arg(long, value_delimiter = ',', default_value = "ci")]
    pub corpus: Vec<String>,
    /// Output directory for results (default `reports/runs/<UTC stamp>`; for `harness
    /// compare`: the report folder, default `reports/latest`, with the records in `run/`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Comma-separated runner ids (default: every registered runner).
    #[arg(long, value_delimiter = ',')]
    pub meshers: Vec<String>,
    /// Comma-separated model ids to keep (default: every model of the tier).
    #[arg(long, value_delimiter = ',')]
    pub models: Vec<String>,
    /// Skip (model, mesher) pairs already recorded in `OUT/results.jsonl`.
    #[arg(long)]
    pub resume: bool,
    /// Per-run time limit, seconds.
    #[arg(long, default_value_t = 600.0)]
    pub timeout: f64,
    /// Explicit surface files to run instead of corpus models (model id = file stem).
    #[arg(long, num_args = 1..)]
    pub input: Vec<PathBuf>,
    /// Keep each run's work directory (output meshes, logs) under `OUT/work`.
    #[arg(long)]
    pub keep_meshes: bool,
    /// Run the slow peers (fTetWild) only on the N smallest models (by input triangles)
    /// of each clean tier, and on no dirty model; their other rows are `skipped`.
    #[arg(long, value_name = "N")]
    pub limit_slow: Option<usize>,
    /// Run only shard K of N (1-based): a deterministic slice of the models, balanced by
    /// input size; combine the shards with `harness merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<crate::shard::Shard>,
    /// Run each (model, mesher) that finishes within 10 s up to N times in all and keep
    /// the fastest run's time, CPU time and memory (noise on a shared machine only adds
    /// time); the mesh measured is the last run's (every mesher here is deterministic).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub repeat: usize,
}

/// `harness run`.
pub fn cli(args: RunArgs) -> anyhow::Result<ExitCode> {
    crate::run::cli(args)
}
