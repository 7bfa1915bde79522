//! CGAL Mesh_3 runner: drives the `cgal-mesh3` binary of the `reference` crate
//! (`Polyhedral_mesh_domain_with_features_3` + `make_mesh_3`, radius-edge bound 2, sizes
//! from the mean input edge length h (`cgal`) or, as fields, from the size h(P) of the
//! nearest input vertex (`cgal-sized`); see `reference/src/mesh3.rs`).
//!
//! The input is re-written as a clean OFF (welded, plain header) with
//! `mesher::io::write_surface`; the output is CGAL's Medit file, read back with
//! `mesher::io::read_volume`. CGAL re-meshes the boundary, so `keeps_boundary` is false.
//! Its tets come out positively oriented (checked by `harness/tests/cgal_mesh3.rs`).
//! The child is measured by [`super::process`] like every peer (wait4 rusage: wall, user
//! + system CPU, peak RSS; time limit; stderr tail).

use super::process::{check_exit, run_measured};
use super::sizes;
use super::{PeerInfo, ProcessStats, RunError, RunOutput, RunRequest, Runner};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// Exit code of the `cgal-mesh3` stub built without CGAL headers (clap also uses 2 for
/// usage errors, so the stub is recognised by its message too).
const STUB_EXIT: i32 = 2;
const STUB_MESSAGE: &str = "built without CGAL";

/// CGAL Mesh_3 through the `cgal-mesh3` binary.
#[derive(Clone, Debug)]
pub struct CgalMesh3 {
    /// Path of the `cgal-mesh3` executable.
    pub binary: PathBuf,
    /// Seed of CGAL's random generators (runs are deterministic for a given seed).
    pub seed: u32,
    /// Bound on the cells' radius-edge ratio (`cell_radius_edge_ratio`; issue 3: 2).
    pub radius_edge: f64,
    /// Size criteria as fields: the size h(P) of the nearest input vertex (see
    /// [`super::sizes`]) instead of the constant mean edge length.
    pub sized: bool,
}

impl CgalMesh3 {
    /// A runner for the given executable: seed 0, radius-edge bound 2, constant sizes.
    pub fn new(binary: impl Into<PathBuf>) -> CgalMesh3 {
        CgalMesh3 {
            binary: binary.into(),
            seed: 0,
            radius_edge: 2.0,
            sized: false,
        }
    }

    /// The same runner with sizes from the nearest input vertex (`cgal-sized`).
    pub fn sized(self) -> CgalMesh3 {
        CgalMesh3 {
            sized: true,
            ..self
        }
    }

    /// Finds `cgal-mesh3`: `$CGAL_MESH3_BIN`, else beside the running executable or one
    /// folder up (test binaries live in `target/<profile>/deps`). `None` if absent.
    pub fn locate() -> Option<PathBuf> {
        if let Some(p) = std::env::var_os("CGAL_MESH3_BIN") {
            return Some(PathBuf::from(p));
        }
        let exe = std::env::current_exe().ok()?;
        exe.ancestors()
            .skip(1)
            .take(2)
            .map(|dir| dir.join("cgal-mesh3"))
            .find(|p| p.is_file())
    }

    /// The command line for one run (the only place it is built); `--sizes SIZES_NAME`
    /// in the sized configuration.
    pub fn command_line(&self, input: &Path, output: &Path, edge_length: f64) -> Vec<OsString> {
        let mut args: Vec<OsString> = vec![
            input.into(),
            "-o".into(),
            output.into(),
            "--edge-length".into(),
            format!("{edge_length:e}").into(),
            "--radius-edge".into(),
            format!("{}", self.radius_edge).into(),
            "--seed".into(),
            self.seed.to_string().into(),
        ];
        if self.sized {
            args.extend(["--sizes".into(), SIZES_NAME.into()]);
        }
        args
    }
}

/// The installed CGAL, from `dpkg-query -W libcgal-dev` (cached; "unknown" without dpkg).
pub fn cgal_version() -> String {
    static VERSION: OnceLock<String> = OnceLock::new();
    VERSION
        .get_or_init(|| {
            Command::new("dpkg-query")
                .args(["-W", "-f=${Version}", "libcgal-dev"])
                .output()
                .ok()
                .filter(|o| o.status.success() && !o.stdout.is_empty())
                .map(|o| format!("CGAL {} (libcgal-dev)", String::from_utf8_lossy(&o.stdout)))
                .unwrap_or_else(|| "unknown".to_owned())
        })
        .clone()
}

impl Runner for CgalMesh3 {
    fn info(&self) -> PeerInfo {
        let sizes = if self.sized {
            "s = h(P) of the nearest input vertex"
        } else {
            "s = mean input edge length"
        };
        PeerInfo {
            id: if self.sized { "cgal-sized" } else { "cgal" },
            name: "CGAL Mesh_3",
            keeps_boundary: false,
            sized: self.sized,
            slow: false,
            configuration: format!(
                "edge_size s, facet_size 0.7 s, facet_distance 0.05 s, cell_size s, \
                 facet_angle 25, cell_radius_edge_ratio {}, features at 60 degrees; {sizes}",
                self.radius_edge
            ),
        }
    }

    fn run(&self, request: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        if !self.binary.is_file() {
            return Err(RunError::Missing(format!(
                "{} not found (cargo build -p reference --bin cgal-mesh3)",
                self.binary.display()
            )));
        }
        let h = request.edge_length;
        if !(h.is_finite() && h > 0.0) {
            return Err(RunError::Io(format!(
                "edge length {h} is not a positive size"
            )));
        }
        let input = request.workdir.join(INPUT_NAME);
        let output = request.workdir.join(OUTPUT_NAME);
        let read =
            mesher::io::read_surface(request.input).map_err(|e| RunError::Io(e.to_string()))?;
        mesher::io::write_surface(&input, &read.surface)
            .map_err(|e| RunError::Io(e.to_string()))?;
        if self.sized {
            let h = sizes::input_sizes(&read.surface);
            sizes::write_samples(&request.workdir.join(SIZES_NAME), &read.surface, &h)?;
        }

        // The child runs in the work directory: name its files relative to it, so a
        // relative work directory cannot send it looking elsewhere.
        let args = self.command_line(Path::new(INPUT_NAME), Path::new(OUTPUT_NAME), h);
        let binary = std::path::absolute(&self.binary).map_err(|e| RunError::Io(e.to_string()))?;
        let mut cmd = Command::new(binary);
        cmd.args(&args);
        let stats = run_measured(cmd, request.workdir, "cgal", request.timeout)?;
        if stats.exit_code != Some(0) {
            return Err(failure(stats));
        }
        // Fail early with a clear message rather than handing back an unreadable file.
        mesher::io::read_volume(&output)
            .map_err(|e| RunError::Io(format!("reading CGAL output: {e}")))?;
        Ok(RunOutput {
            mesh: output,
            version: cgal_version(),
            stats,
        })
    }
}

/// The surface handed to CGAL, in the work directory.
const INPUT_NAME: &str = "cgal-input.off";
/// CGAL's output, in the work directory.
const OUTPUT_NAME: &str = "cgal.mesh";
/// The size samples of the sized configuration (`x y z h` per input vertex).
const SIZES_NAME: &str = "cgal-sizes.txt";

/// Maps a failed run to the matching error: the stub built without CGAL is
/// [`RunError::Missing`]; anything else is [`check_exit`]'s failure (exit code, signal or
/// time limit, with the stderr tail).
fn failure(stats: ProcessStats) -> RunError {
    if stats.exit_code == Some(STUB_EXIT) && stats.stderr_tail.contains(STUB_MESSAGE) {
        return RunError::Missing(stats.stderr_tail.trim().to_owned());
    }
    match check_exit("cgal-mesh3", stats) {
        Err(e) => e,
        Ok(stats) => RunError::Failed {
            message: "cgal-mesh3: exit code 0 reported as a failure".into(),
            stats,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn info_is_cgal_and_moves_the_boundary() {
        let info = CgalMesh3::new("x").info();
        assert_eq!((info.id, info.keeps_boundary), ("cgal", false));
    }

    #[test]
    fn command_line_carries_size_and_seed() {
        let args = CgalMesh3::new("x").command_line(Path::new("a.off"), Path::new("b.mesh"), 0.25);
        let args: Vec<_> = args
            .iter()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            args,
            [
                "a.off",
                "-o",
                "b.mesh",
                "--edge-length",
                "2.5e-1",
                "--radius-edge",
                "2",
                "--seed",
                "0"
            ]
        );
        let sized = CgalMesh3::new("x").sized();
        let args = sized.command_line(Path::new("a.off"), Path::new("b.mesh"), 0.25);
        assert_eq!(args[args.len() - 2..], ["--sizes", SIZES_NAME]);
        assert_eq!(sized.info().id, "cgal-sized");
    }

    #[test]
    fn stub_exit_is_reported_as_missing() {
        let stats = ProcessStats {
            exit_code: Some(2),
            stderr_tail: "cgal-mesh3: built without CGAL (headers not found)\n".into(),
            ..ProcessStats::default()
        };
        assert!(matches!(failure(stats), RunError::Missing(_)));
        let stats = ProcessStats {
            exit_code: Some(1),
            stderr_tail: "cgal-mesh3: bad input: not closed\n".into(),
            ..ProcessStats::default()
        };
        assert!(
            matches!(failure(stats), RunError::Failed { ref message, .. } if message.contains("not closed"))
        );
    }
}
