//! TetGen 1.5 (Debian `tetgen`): `tetgen -pq1.414 in.smesh` (`tetgen`),
//! `tetgen -pYq1.414 in.smesh` (`tetgen-y`, which keeps every input triangle) and
//! `tetgen -pYq1.414m in.smesh` with `in.mtr` (`tetgen-y-sized`: the size h(P) of
//! NOTES.md §3 at every input vertex; TetGen interpolates it at the points it inserts).
//!
//! TetGen aborts without a message on OFF files with comments or blank lines, so the
//! runner writes the input itself as a comment-free `.smesh` (1-based nodes, facets, and
//! a hole list with one point inside every nested hole shell; without it TetGen would
//! also mesh the inside of inner shells), then reads `in.1.node/.ele/.face` back.
//! TetGen has no version switch (`-v` aborts): the version is the Debian package's.

use super::input::{self, Shell};
use super::process::{check_exit, run_measured};
use super::sizes;
use super::{PeerInfo, RunError, RunOutput, RunRequest, Runner};
use mesher::Surface;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// A TetGen configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct TetGen {
    /// Keep the input boundary exactly (`-Y`).
    pub keep_boundary: bool,
    /// Radius-edge ratio bound of `-q`; `None` for no quality refinement (the
    /// boundary mesh only, to compare with `mesher boundary`).
    pub radius_edge: Option<f64>,
    /// Sizes from `in.mtr` (`-m`): h(P) of NOTES.md §3 at every input vertex.
    pub sized: bool,
}

impl TetGen {
    /// `-pq1.414`: TetGen's quality refinement; may split boundary faces.
    pub fn default_switches() -> TetGen {
        TetGen {
            keep_boundary: false,
            radius_edge: Some(1.414),
            sized: false,
        }
    }

    /// `-pYq1.414`: the same, keeping every input triangle.
    pub fn keep_boundary() -> TetGen {
        TetGen {
            keep_boundary: true,
            radius_edge: Some(1.414),
            sized: false,
        }
    }

    /// `-pY`: the boundary mesh alone (input triangles kept, no refinement).
    pub fn boundary_only() -> TetGen {
        TetGen {
            keep_boundary: true,
            radius_edge: None,
            sized: false,
        }
    }

    /// The same switches plus `-m`: sizes h(P) per input vertex from `in.mtr`.
    pub fn sized(self) -> TetGen {
        TetGen {
            sized: true,
            ..self
        }
    }

    /// The switches (without the input file).
    pub fn switches(&self) -> String {
        let y = if self.keep_boundary { "Y" } else { "" };
        let m = if self.sized { "m" } else { "" };
        let q = self.radius_edge.map_or(String::new(), |r| format!("q{r}"));
        format!("-p{y}{q}{m}")
    }
}

impl Runner for TetGen {
    fn info(&self) -> PeerInfo {
        // -p without -Y may insert Steiner points on boundary faces.
        let id = match (self.keep_boundary, self.sized, self.radius_edge.is_some()) {
            (_, _, false) => "tetgen-y-boundary",
            (false, false, true) => "tetgen",
            (false, true, true) => "tetgen-sized",
            (true, false, true) => "tetgen-y",
            (true, true, true) => "tetgen-y-sized",
        };
        let sizes = if self.sized {
            ", in.mtr = h(P) per input vertex"
        } else {
            ""
        };
        PeerInfo {
            id,
            name: "TetGen",
            keeps_boundary: self.keep_boundary,
            sized: self.sized,
            slow: false,
            configuration: format!("tetgen {} in.smesh{sizes}", self.switches()),
        }
    }

    fn run(&self, req: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        let version = debian_version("tetgen")
            .ok_or_else(|| RunError::Missing("tetgen (Debian package) not installed".into()))?;
        let surface = input::load(req.input)?;
        // A dirty surface gets no hole list; TetGen then decides for itself.
        let shells = input::shells(&surface).ok();
        let smesh = req.workdir.join("in.smesh");
        write_smesh(&smesh, &surface, shells.as_deref())?;
        if self.sized {
            sizes::write_mtr(&req.workdir.join("in.mtr"), &sizes::input_sizes(&surface))?;
        }
        let mut cmd = Command::new("tetgen");
        cmd.arg(self.switches()).arg("in.smesh");
        let stats = run_measured(cmd, req.workdir, "tetgen", req.timeout)?;
        let stats = check_exit("tetgen", stats)?;
        let mesh = req.workdir.join("in.1.ele");
        if !mesh.exists() {
            return Err(RunError::Io("tetgen exited 0 but wrote no in.1.ele".into()));
        }
        Ok(RunOutput {
            mesh,
            version,
            stats,
        })
    }
}

/// Version of an installed Debian package (`dpkg-query -W`), e.g. `1.5.0-5`.
pub fn debian_version(package: &str) -> Option<String> {
    let out = Command::new("dpkg-query")
        .args(["-W", "-f=${Version}", package])
        .output()
        .ok()?;
    let v = String::from_utf8_lossy(&out.stdout).trim().to_string();
    (out.status.success() && !v.is_empty()).then_some(v)
}

/// Writes a comment-free TetGen `.smesh`: nodes (1-based), triangle facets, hole points
/// of the nested hole shells, no regions.
pub fn write_smesh(path: &Path, s: &Surface, shells: Option<&[Shell]>) -> Result<(), RunError> {
    let mut t = String::with_capacity(64 * (s.vertices.len() + s.triangles.len()));
    // `{:?}` prints the shortest text that reads back as the same double.
    let _ = writeln!(t, "{} 3 0 0", s.vertices.len());
    for (i, p) in s.vertices.iter().enumerate() {
        let _ = writeln!(t, "{} {:?} {:?} {:?}", i + 1, p.x, p.y, p.z);
    }
    let _ = writeln!(t, "{} 0", s.triangles.len());
    for f in &s.triangles {
        let _ = writeln!(t, "3 {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    let holes = shells
        .map(|sh| input::hole_points(s, sh))
        .unwrap_or_default();
    let _ = writeln!(t, "{}", holes.len());
    for (i, p) in holes.iter().enumerate() {
        let _ = writeln!(t, "{} {:?} {:?} {:?}", i + 1, p.x, p.y, p.z);
    }
    let _ = writeln!(t, "0");
    std::fs::write(path, t).map_err(|e| RunError::Io(format!("{}: {e}", path.display())))
}
