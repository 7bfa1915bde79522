//! Gmsh through `scripts/gmsh_tet.py` (pip `gmsh`): `gmsh-hxt` (`Mesh.Algorithm3D` 10)
//! and `gmsh-delaunay` (1), one thread, sizes from the boundary (Gmsh's default).
//!
//! The surface goes to the script as double-precision JSON with its shells and bodies
//! (one surface loop per shell, one volume per body, nested shells as holes), so Gmsh
//! meshes exactly the input triangles. Output: Medit `.mesh` written by the script from
//! Gmsh's API with round-trip precision (Gmsh's ASCII `.msh` 4.1 prints 16 significant
//! digits, which would move some input vertices by one ulp).

use super::input;
use super::process::run_python_script;
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
}

impl Gmsh {
    /// HXT, Gmsh's parallel Delaunay (run on one thread here).
    pub fn hxt() -> Gmsh {
        Gmsh {
            algorithm: Algorithm::Hxt,
        }
    }

    /// Gmsh's classic Delaunay.
    pub fn delaunay() -> Gmsh {
        Gmsh {
            algorithm: Algorithm::Delaunay,
        }
    }

    /// The script's arguments for this configuration.
    pub fn args(&self, input: &str, output: &str) -> Vec<String> {
        let alg = match self.algorithm {
            Algorithm::Hxt => "hxt",
            Algorithm::Delaunay => "delaunay",
        };
        [
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
        .to_vec()
    }
}

impl Runner for Gmsh {
    fn info(&self) -> PeerInfo {
        match self.algorithm {
            Algorithm::Hxt => PeerInfo {
                id: "gmsh-hxt",
                name: "Gmsh HXT",
                keeps_boundary: true,
            },
            Algorithm::Delaunay => PeerInfo {
                id: "gmsh-delaunay",
                name: "Gmsh Delaunay",
                keeps_boundary: true,
            },
        }
    }

    fn run(&self, req: &RunRequest<'_>) -> Result<RunOutput, RunError> {
        let surface = input::load(req.input)?;
        let shells = input::shells(&surface).ok();
        input::write_domain_json(
            &req.workdir.join("domain.json"),
            &surface,
            shells.as_deref(),
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
