//! fTetWild through `scripts/ftetwild.py` (pip `pytetwild`): absolute ideal edge length =
//! the mean input edge length (`RunRequest::edge_length`), one thread, other options at
//! their defaults. It moves the boundary within its envelope (1e-3 of the box diagonal).
//!
//! pytetwild writes `__tracked_surface.stl` into its working directory: the script runs
//! in the run's own work directory. Its tets may be negatively oriented; the metrics
//! normalise a consistent orientation and say so in the record.

use super::input;
use super::process::run_python_script;
use super::{PeerInfo, RunError, RunOutput, RunRequest, Runner};

/// fTetWild with pytetwild's defaults and an absolute edge length.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FTetWild;

impl Runner for FTetWild {
    fn info(&self) -> PeerInfo {
        PeerInfo {
            id: "ftetwild",
            name: "fTetWild",
            keeps_boundary: false,
        }
    }

    fn run(&self, req: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        let surface = input::load(req.input)?;
        input::write_domain_json(&req.workdir.join("domain.json"), &surface, None)?;
        let h = if req.edge_length > 0.0 {
            req.edge_length
        } else {
            input::mean_edge_length(&surface)
        };
        let args: Vec<String> = [
            "--input",
            "domain.json",
            "--output",
            "out.mesh",
            "--meta",
            "meta.json",
        ]
        .map(String::from)
        .into_iter()
        .chain(["--edge-length".to_string(), format!("{h:?}")])
        .collect();
        let (stats, meta) = run_python_script("ftetwild.py", &args, req.workdir, req.timeout)?;
        let mesh = req.workdir.join("out.mesh");
        if !mesh.exists() {
            return Err(RunError::Io(
                "ftetwild.py exited 0 but wrote no out.mesh".into(),
            ));
        }
        let version = meta["version"].as_str().unwrap_or("unknown").to_string();
        Ok(RunOutput {
            mesh,
            version: format!("pytetwild {version}"),
            stats,
        })
    }
}
