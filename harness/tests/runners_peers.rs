//! Peers end to end on a small generated sphere (icosphere level 2, 320 triangles):
//! TetGen (`tetgen`, `tetgen-y`) and Gmsh (HXT, Delaunay) through their runners, measured
//! by the harness metrics; and a cross-check of our Q_K and minimum dihedral angle on a
//! TetGen output against an independent numpy computation (`quality_numpy.py`).
//!
//! A peer that is not installed skips its test with a message, except when the env var
//! `CI` is set: then a missing peer fails.

mod common;

use harness::metrics::{measure_input, measure_output, OutputMeasures};
use harness::runners::gmsh::Gmsh;
use harness::runners::tetgen::TetGen;
use harness::runners::{venv_python, RunRequest, Runner};
use mesher::surface::generate::icosphere;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

fn tetgen_installed() -> bool {
    harness::runners::tetgen::debian_version("tetgen").is_some()
}

fn venv_has(module: &str) -> bool {
    Command::new(venv_python())
        .args(["-c", &format!("import {module}")])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Runs `runner` on icosphere(2) and measures the output.
fn run_on_sphere(runner: &dyn Runner, dir: &Path) -> (OutputMeasures, std::path::PathBuf) {
    let surface = icosphere(2);
    let input = dir.join("sphere.off");
    mesher::io::write_surface(&input, &surface).unwrap();
    let work = dir.join("work");
    std::fs::create_dir_all(&work).unwrap();
    let req = RunRequest {
        model: "sphere",
        input: &input,
        workdir: &work,
        timeout: Duration::from_secs(120),
        edge_length: harness::runners::input::mean_edge_length(&surface),
    };
    let out = runner
        .run(&req)
        .unwrap_or_else(|e| panic!("{}: {e}", runner.info().id));
    assert!(out.stats.wall_seconds > 0.0);
    assert!(!out.version.is_empty());
    let mesh = mesher::io::read_volume(&out.mesh).unwrap();
    let m = measure_output(
        &measure_input(&surface),
        &surface,
        mesh,
        runner.info().keeps_boundary,
    );
    (m.unwrap(), out.mesh)
}

fn assert_valid(id: &str, m: &OutputMeasures, keeps: bool) {
    assert!(m.tets > 100, "{id}: {} tets", m.tets);
    assert_eq!(m.validity.inverted, 0, "{id}");
    assert_eq!(m.validity.non_manifold_faces, 0, "{id}");
    let r = m.validity.volume_ratio.unwrap();
    assert!((r - 1.0).abs() < 1e-9, "{id}: volume ratio {r}");
    if keeps {
        assert_eq!(m.validity.boundary_kept, Some(true), "{id}");
    }
    assert!(m.quality.worst_q_k.is_finite() && m.quality.worst_q_k >= 1.0);
}

#[test]
fn tetgen_meshes_a_sphere() {
    if !common::peer_present("tetgen", tetgen_installed()) {
        return;
    }
    for t in [TetGen::default_switches(), TetGen::keep_boundary()] {
        let dir = tempfile::tempdir().unwrap();
        let (m, _) = run_on_sphere(&t, dir.path());
        assert_valid(t.info().id, &m, t.keep_boundary);
    }
}

#[test]
fn gmsh_meshes_a_sphere() {
    if !common::peer_present("gmsh (venv)", venv_has("gmsh")) {
        return;
    }
    for g in [Gmsh::hxt(), Gmsh::delaunay()] {
        let dir = tempfile::tempdir().unwrap();
        let (m, _) = run_on_sphere(&g, dir.path());
        assert_valid(g.info().id, &m, true);
    }
}

#[test]
fn quality_agrees_with_numpy_on_a_tetgen_mesh() {
    if !common::peer_present("tetgen", tetgen_installed())
        || !common::peer_present("numpy (venv)", venv_has("numpy"))
    {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (_, ele) = run_on_sphere(&TetGen::default_switches(), dir.path());
    let mesh = mesher::io::read_volume(&ele).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/quality_numpy.py");
    let base = ele.with_extension("");
    let out = Command::new(venv_python())
        .arg(&script)
        .arg(&base)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let q = v["q_k"].as_array().unwrap();
    let d = v["min_dihedral_deg"].as_array().unwrap();
    assert_eq!(q.len(), mesh.tets.len());
    for t in 0..mesh.tets.len() {
        let p = mesh.tet_points(t);
        let (ours_q, ours_d) = (mesher::quality::q_k(&p), mesher::quality::min_dihedral(&p));
        let (np_q, np_d) = (q[t].as_f64().unwrap(), d[t].as_f64().unwrap());
        assert!(
            (ours_q - np_q).abs() <= 1e-9 * np_q,
            "tet {t}: Q_K {ours_q} vs {np_q}"
        );
        assert!(
            (ours_d - np_d).abs() <= 1e-9 * np_d.max(1.0),
            "tet {t}: dihedral {ours_d} vs {np_d}"
        );
    }
}

/// Two nested spheres (radius 1 and 0.5, the inner one facing inwards): a hollow ball.
fn hollow_ball() -> mesher::Surface {
    mesher::surface::generate::hollow(&icosphere(2), &icosphere(2), 0.5)
}

#[test]
fn nested_shells_leave_the_hole_empty() {
    let surface = hollow_ball();
    let input = measure_input(&surface);
    let mut runners: Vec<Box<dyn Runner>> = Vec::new();
    if common::peer_present("tetgen", tetgen_installed()) {
        runners.push(Box::new(TetGen::keep_boundary()));
    }
    if common::peer_present("gmsh (venv)", venv_has("gmsh")) {
        runners.push(Box::new(Gmsh::hxt()));
    }
    for r in runners {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("hollow.off");
        mesher::io::write_surface(&path, &surface).unwrap();
        let req = RunRequest {
            model: "hollow",
            input: &path,
            workdir: dir.path(),
            timeout: Duration::from_secs(120),
            edge_length: 0.1,
        };
        let out = r
            .run(&req)
            .unwrap_or_else(|e| panic!("{}: {e}", r.info().id));
        let mesh = mesher::io::read_volume(&out.mesh).unwrap();
        let m = measure_output(&input, &surface, mesh, true).unwrap();
        let ratio = m.validity.volume_ratio.unwrap();
        assert!(
            (ratio - 1.0).abs() < 1e-9,
            "{}: volume ratio {ratio}",
            r.info().id
        );
        assert_eq!(m.validity.boundary_kept, Some(true), "{}", r.info().id);
    }
}
