//! CGAL Mesh_3 runner: drives the `cgal-mesh3` binary of the `reference` crate
//! (`Polyhedral_mesh_domain_with_features_3` + `make_mesh_3`, sizes from the mean input
//! edge length h; see `reference/src/mesh3.rs`).
//!
//! The input is re-written as a clean OFF (welded, plain header) with
//! `mesher::io::write_surface`; the output is CGAL's Medit file, read back with
//! `mesher::io::read_volume`. CGAL re-meshes the boundary, so `keeps_boundary` is false.
//! Its tets come out positively oriented (checked by `harness/tests/cgal_mesh3.rs`).

use super::{PeerInfo, ProcessStats, RunError, RunOutput, RunRequest, Runner};
use std::ffi::OsString;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// Exit code of the `cgal-mesh3` stub built without CGAL headers (clap also uses 2 for
/// usage errors, so the stub is recognised by its message too).
const STUB_EXIT: i32 = 2;
const STUB_MESSAGE: &str = "built without CGAL";
/// Characters of stderr kept in records.
const STDERR_TAIL: usize = 2000;

/// CGAL Mesh_3 through the `cgal-mesh3` binary.
#[derive(Clone, Debug)]
pub struct CgalMesh3 {
    /// Path of the `cgal-mesh3` executable.
    pub binary: PathBuf,
    /// Seed of CGAL's random generators (runs are deterministic for a given seed).
    pub seed: u32,
}

impl CgalMesh3 {
    /// A runner for the given executable, seed 0.
    pub fn new(binary: impl Into<PathBuf>) -> CgalMesh3 {
        CgalMesh3 {
            binary: binary.into(),
            seed: 0,
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

    /// The command line for one run (the only place it is built).
    pub fn command_line(&self, input: &Path, output: &Path, edge_length: f64) -> Vec<OsString> {
        vec![
            input.into(),
            "-o".into(),
            output.into(),
            "--edge-length".into(),
            format!("{edge_length:e}").into(),
            "--seed".into(),
            self.seed.to_string().into(),
        ]
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
        PeerInfo {
            id: "cgal",
            name: "CGAL Mesh_3",
            keeps_boundary: false,
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

        // The child runs in the work directory: name its files relative to it, so a
        // relative work directory cannot send it looking elsewhere.
        let args = self.command_line(Path::new(INPUT_NAME), Path::new(OUTPUT_NAME), h);
        let binary = std::path::absolute(&self.binary).map_err(|e| RunError::Io(e.to_string()))?;
        let stats = run_measured(&binary, &args, request.workdir, request.timeout)?;
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

/// Maps a non-zero exit, a signal or a timeout to the matching error.
fn failure(stats: ProcessStats) -> RunError {
    if stats.exit_code == Some(STUB_EXIT) && stats.stderr_tail.contains(STUB_MESSAGE) {
        return RunError::Missing(stats.stderr_tail.trim().to_owned());
    }
    let message = if stats.timed_out {
        format!("timed out after {:.1} s", stats.wall_seconds)
    } else if let Some(sig) = stats.signal {
        format!("killed by signal {sig}")
    } else {
        let last = stats.stderr_tail.lines().last().unwrap_or("").trim();
        format!("exit code {:?}: {last}", stats.exit_code)
    };
    RunError::Failed { message, stats }
}

// TODO: switch to runners::process once it lands (wait4 rusage: CPU time and peak RSS).
/// Runs `binary args` in `workdir` with stdout/stderr in files there, killing it at
/// `timeout`. Measures wall time only: `cpu_seconds` and `peak_rss_bytes` stay 0.
fn run_measured(
    binary: &Path,
    args: &[OsString],
    workdir: &Path,
    timeout: Duration,
) -> Result<ProcessStats, RunError> {
    let io = |e: std::io::Error| RunError::Io(format!("running {}: {e}", binary.display()));
    let stdout = File::create(workdir.join("cgal.stdout")).map_err(io)?;
    let stderr_path = workdir.join("cgal.stderr");
    let stderr = File::create(&stderr_path).map_err(io)?;
    let start = Instant::now();
    let mut child = Command::new(binary)
        .args(args)
        .current_dir(workdir)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(stderr)
        .spawn()
        .map_err(io)?;
    let mut timed_out = false;
    let status = loop {
        if let Some(status) = child.try_wait().map_err(io)? {
            break status;
        }
        if start.elapsed() >= timeout {
            timed_out = true;
            // The child may exit between try_wait and kill; wait() settles either way.
            let _ = child.kill();
            break child.wait().map_err(io)?;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let wall_seconds = start.elapsed().as_secs_f64();
    let text = std::fs::read(&stderr_path).unwrap_or_default();
    Ok(ProcessStats {
        wall_seconds,
        exit_code: status.code(),
        signal: std::os::unix::process::ExitStatusExt::signal(&status),
        timed_out,
        stderr_tail: tail(&String::from_utf8_lossy(&text), STDERR_TAIL),
        ..ProcessStats::default()
    })
}

/// The last `max` characters of `s` (whole characters).
fn tail(s: &str, max: usize) -> String {
    let n = s.chars().count();
    s.chars().skip(n.saturating_sub(max)).collect()
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
                "--seed",
                "0"
            ]
        );
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

    #[test]
    fn tail_keeps_the_end() {
        assert_eq!(tail("abcdef", 3), "def");
        assert_eq!(tail("ab", 3), "ab");
    }
}
