//! Gmsh through `scripts/gmsh_tet.py` (pip `gmsh`): `gmsh-hxt` (`Mesh.Algorithm3D` 10)
//! and `gmsh-delaunay` (1), one thread, sizes from the boundary (Gmsh's default); the
//! `-sized` configurations take their sizes from the background field of [`sizes`]
//! (a PostView field on the Delaunay mesh of the input vertices carrying h(P)).
//!
//! The surface goes to the script as double-precision JSON with its shells and bodies
//! (one surface loop per shell, one volume per body, nested shells as holes), so Gmsh
//! meshes exactly the input triangles. Output: Medit `.mesh` written by the script from
//! Gmsh's API with round-trip precision (Gmsh's ASCII `.msh` 4.1 prints 16 significant
//! digits, which would move some input vertices by one ulp).

use super::input;
use super::process::run_python_script;
use super::sizes;
use super::{PeerInfo, RunError, RunOutput, RunRequest, Runner};

/// Gmsh's 3D algorithm.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Algorithm {
    /// HXT (`Mesh.Algorithm3D` = 10).
    Hxt,
    /// Delaunay (`Mesh.Algorithm3D` = 1).
    Delaunay,
}

/// A Gmsh configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Gmsh {
    /// The 3D algorithm.
    pub algorithm: Algorithm,
    /// Sizes from the background field of [`sizes`] (Delaunay mesh of the input
    /// vertices carrying h(P)) instead of Gmsh's own extension from the boundary.
    pub sized: bool,
}

impl Gmsh {
    /// HXT, Gmsh's parallel Delaunay (run on one thread here).
    pub fn hxt() -> Gmsh {
        Gmsh {
            algorithm: Algorithm::Hxt,
            sized: false,
        }
    }

    /// Gmsh's classic Delaunay.
    pub fn delaunay() -> Gmsh {
        Gmsh {
            algorithm: Algorithm::Delaunay,
            sized: false,
        }
    }

    /// The same algorithm following the size field of [`sizes`].
    pub fn sized(self) -> Gmsh {
        Gmsh {
            sized: true,
            ..self
        }
    }

    /// The script's arguments for this configuration.
    pub fn args(&self, input: &str, output: &str) -> Vec<String> {
        let alg = match self.algorithm {
            Algorithm::Hxt => "hxt",
            Algorithm::Delaunay => "delaunay",
        };
        let mut args = [
            "--input",
            input,
            "--output",
            output,
            "--meta",
            "meta.json",
            "--algorithm",
            alg,
        ]
        .map(String::from)
        .to_vec();
        if self.sized {
            args.push("--sized".into());
        }
        args
    }
}

impl Runner for Gmsh {
    fn info(&self) -> PeerInfo {
        let (id, name, number) = match (self.algorithm, self.sized) {
            (Algorithm::Hxt, false) => ("gmsh-hxt", "Gmsh HXT", 10),
            (Algorithm::Hxt, true) => ("gmsh-hxt-sized", "Gmsh HXT", 10),
            (Algorithm::Delaunay, false) => ("gmsh-delaunay", "Gmsh Delaunay", 1),
            (Algorithm::Delaunay, true) => ("gmsh-delaunay-sized", "Gmsh Delaunay", 1),
        };
        let sizes = if self.sized {
            "PostView background field = h(P) on the Delaunay mesh of the input vertices, \
             no size from boundary/points/curvature"
        } else {
            "sizes extended from the boundary (Gmsh default)"
        };
        PeerInfo {
            id,
            name,
            keeps_boundary: true,
            sized: self.sized,
            slow: false,
            configuration: format!("Mesh.Algorithm3D {number}, General.NumThreads 1, {sizes}"),
        }
    }

    fn run(&self, req: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        let surface = input::load(req.input)?;
        let shells = input::shells(&surface).ok();
        let background = match self.sized {
            true => Some(sizes::background(&surface, &sizes::input_sizes(&surface))?),
            false => None,
        };
        input::write_domain_json(
            &req.workdir.join("domain.json"),
            &surface,
            shells.as_deref(),
            background.as_ref(),
        )?;
        let args = self.args("domain.json", "out.mesh");
        let (stats, meta) = run_python_script("gmsh_tet.py", &args, req.workdir, req.timeout)?;
        let mesh = req.workdir.join("out.mesh");
        if !mesh.exists() {
            return Err(RunError::Io(
                "gmsh_tet.py exited 0 but wrote no out.mesh".into(),
            ));
        }
        let version = meta["version"].as_str().unwrap_or("unknown").to_string();
        Ok(RunOutput {
            mesh,
            version: format!("gmsh {version}"),
            stats,
        })
    }
}
