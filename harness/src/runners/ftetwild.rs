//! fTetWild through `scripts/ftetwild.py` (pip `pytetwild`): absolute ideal edge length =
//! the mean input edge length (`RunRequest::edge_length`), one thread, other options at
//! their defaults. It moves the boundary within its envelope (1e-3 of the box diagonal).
//! `ftetwild-sized` also hands it the background size field of [`sizes`] (pytetwild's
//! `bg_vertices`, `bg_tets`, `bg_values`) with the mean h(P) as its edge length.
//!
//! pytetwild writes `__tracked_surface.stl` into its working directory: the script runs
//! in the run's own work directory. Its tets may be negatively oriented; the metrics
//! normalise a consistent orientation and say so in the record.

use super::input;
use super::process::run_python_script;
use super::sizes;
use super::{PeerInfo, RunError, RunOutput, RunRequest, Runner};

/// fTetWild with pytetwild's defaults and an absolute edge length.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FTetWild {
    /// Also hand it the background size field of [`sizes`] (Delaunay mesh of the input
    /// vertices carrying h(P)); its absolute edge length is then the mean h(P).
    pub sized: bool,
}

impl Runner for FTetWild {
    fn info(&self) -> PeerInfo {
        let (id, configuration) = if self.sized {
            (
                "ftetwild-sized",
                "edge_length_abs = mean h(P), background mesh = Delaunay of the input \
                 vertices carrying h(P), num_threads 1",
            )
        } else {
            (
                "ftetwild",
                "edge_length_abs = mean input edge length, num_threads 1",
            )
        };
        PeerInfo {
            id,
            name: "fTetWild",
            keeps_boundary: false,
            sized: self.sized,
            slow: true,
            configuration: configuration.into(),
        }
    }

    fn run(&self, req: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        let surface = input::load(req.input)?;
        let (h, background) = if self.sized {
            let s = sizes::input_sizes(&surface);
            (sizes::mean(&s), Some(sizes::background(&surface, &s)?))
        } else if req.edge_length > 0.0 {
            (req.edge_length, None)
        } else {
            (input::mean_edge_length(&surface), None)
        };
        input::write_domain_json(
            &req.workdir.join("domain.json"),
            &surface,
            None,
            background.as_ref(),
        )?;
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
        .chain(self.sized.then(|| "--sized".to_string()))
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
