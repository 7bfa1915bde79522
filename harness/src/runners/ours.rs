//! Our mesher: `mesher mesh INPUT -o out.mesh --stats stats.json`. Reported as not
//! available until the `mesh` subcommand exists (`mesher mesh --help` fails). The
//! statistics file holds `{"iterations": [{"front", "proposed", "inserted"}, ...]}`,
//! which `harness run` keeps in the record for the front convergence plot.
//!
//! The binary is the `mesher` beside the running `harness` executable (same cargo target
//! directory), or `MESHER_BIN` if set.

use super::process::{check_exit, run_measured};
use super::{PeerInfo, RunError, RunOutput, RunRequest, Runner};
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// The statistics file `mesher mesh --stats` writes in the work directory.
pub const STATS_NAME: &str = "stats.json";

/// The project's own mesher: the whole pipeline (`ours`), or without the optimisation
/// (`ours-front`, `--no-optimize`: the figures issue 5 sets its targets on).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ours {
    /// Run the optimisation (paper §6) after the front.
    pub optimize: bool,
}

impl Ours {
    /// The whole pipeline, as a user runs it.
    pub fn full() -> Self {
        Ours { optimize: true }
    }

    /// Boundary mesh and front only (`--no-optimize`).
    pub fn front_only() -> Self {
        Ours { optimize: false }
    }
}

/// The project's boundary mesh alone: `mesher boundary INPUT -o out.vtu` (paper §4),
/// to compare with `tetgen -pY` (issue 4's table).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OursBoundary;

impl Runner for OursBoundary {
    fn info(&self) -> PeerInfo {
        PeerInfo {
            id: "ours-boundary",
            name: "ours (boundary mesh)",
            keeps_boundary: true,
            sized: false,
            slow: false,
            configuration: "mesher boundary INPUT -o out.vtu".into(),
        }
    }

    fn run(&self, req: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        let mesh = req.workdir.join("out.vtu");
        let mut cmd = Command::new(mesher_binary());
        cmd.arg("boundary").arg(req.input).arg("-o").arg(&mesh);
        let stats = run_measured(cmd, req.workdir, "mesher", req.timeout)?;
        let stats = check_exit("mesher boundary", stats)?;
        if !mesh.exists() {
            return Err(RunError::Io(
                "mesher boundary exited 0 but wrote no out.vtu".into(),
            ));
        }
        Ok(RunOutput {
            mesh,
            version: format!("mesher {}", env!("CARGO_PKG_VERSION")),
            stats,
        })
    }
}

/// Path of the `mesher` binary.
pub fn mesher_binary() -> PathBuf {
    if let Some(p) = std::env::var_os("MESHER_BIN") {
        return PathBuf::from(p);
    }
    std::env::current_exe()
        .ok()
        .and_then(|exe| {
            // Test binaries live in target/<profile>/deps; the CLI in target/<profile>.
            let dir = exe.parent()?;
            let dir = if dir.ends_with("deps") {
                dir.parent()?
            } else {
                dir
            };
            Some(dir.join("mesher"))
        })
        .unwrap_or_else(|| PathBuf::from("mesher"))
}

/// True when `mesher mesh --help` succeeds.
pub fn available() -> bool {
    Command::new(mesher_binary())
        .args(["mesh", "--help"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map(|s| s.success())
        .unwrap_or(false)
}

impl Runner for Ours {
    fn info(&self) -> PeerInfo {
        let (id, name, flag) = if self.optimize {
            ("ours", "ours", "")
        } else {
            ("ours-front", "ours (no optimisation)", " --no-optimize")
        };
        PeerInfo {
            id,
            name,
            keeps_boundary: true,
            sized: true,
            slow: false,
            configuration: format!("mesher mesh INPUT -o out.mesh{flag} --stats {STATS_NAME}"),
        }
    }

    fn run(&self, req: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        if !available() {
            return Err(RunError::Missing("`mesher mesh` does not exist yet".into()));
        }
        let mesh = req.workdir.join("out.mesh");
        let mut cmd = Command::new(mesher_binary());
        cmd.arg("mesh")
            .arg(req.input)
            .arg("-o")
            .arg(&mesh)
            .args(["--stats", STATS_NAME]);
        if !self.optimize {
            cmd.arg("--no-optimize");
        }
        let stats = run_measured(cmd, req.workdir, "mesher", req.timeout)?;
        let stats = check_exit("mesher mesh", stats)?;
        if !mesh.exists() {
            return Err(RunError::Io(
                "mesher mesh exited 0 but wrote no out.mesh".into(),
            ));
        }
        let version = format!("mesher {}", env!("CARGO_PKG_VERSION"));
        Ok(RunOutput {
            mesh,
            version,
            stats,
        })
    }
}
