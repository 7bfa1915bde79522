//! The CGAL Mesh_3 runner end to end: `cgal-mesh3` on an icosphere and on two nested
//! spheres, read back and measured with `mesher::quality`.
//!
//! Needs the `cgal-mesh3` binary (`cargo build -p reference --bin cgal-mesh3`, or
//! `$CGAL_MESH3_BIN`). Without CGAL headers or without the binary the tests are skipped
//! with a message, except when `CI` is set: then they fail.

use harness::runners::cgal::CgalMesh3;
use harness::runners::{RunError, RunOutput, RunRequest, Runner};
use mesher::quality::{signed_volume, unique_triangle_edges};
use mesher::surface::generate::icosphere;
use mesher::{Point, Surface, VolumeMesh};
use std::path::{Path, PathBuf};
use std::time::Duration;

mod common;

/// The runner, or `None` (after saying why) when the test must be skipped; fails
/// under `CI` instead of skipping.
fn runner() -> Option<CgalMesh3> {
    common::cgal_binary().map(CgalMesh3::new)
}

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("harness-cgal-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn mean_edge(s: &Surface) -> f64 {
    let edges = unique_triangle_edges(&s.triangles);
    let total: f64 = edges
        .iter()
        .map(|&[a, b]| s.vertices[a as usize].distance(s.vertices[b as usize]))
        .sum();
    total / edges.len() as f64
}

/// Volume enclosed by a closed outward surface (tets from the origin).
fn enclosed_volume(s: &Surface) -> f64 {
    s.triangles
        .iter()
        .map(|t| {
            signed_volume(&[
                Point::ZERO,
                s.vertices[t[0] as usize],
                s.vertices[t[1] as usize],
                s.vertices[t[2] as usize],
            ])
        })
        .sum()
}

fn run(runner: &CgalMesh3, dir: &Path, surface: &Surface) -> Result<RunOutput, RunError> {
    let input = dir.join("input.off");
    mesher::io::write_surface(&input, surface).unwrap();
    runner.run(&RunRequest {
        model: "test",
        input: &input,
        workdir: dir,
        timeout: Duration::from_secs(120),
        edge_length: mean_edge(surface),
    })
}

/// Reads the output, checks every tet is positively oriented, returns the total volume.
fn checked_volume(out: &RunOutput) -> (VolumeMesh, f64) {
    let mesh = mesher::io::read_volume(&out.mesh).unwrap();
    assert!(!mesh.tets.is_empty());
    let vols: Vec<f64> = (0..mesh.tets.len())
        .map(|t| signed_volume(&mesh.tet_points(t)))
        .collect();
    let inverted = vols.iter().filter(|&&v| v <= 0.0).count();
    assert_eq!(
        inverted,
        0,
        "{inverted} of {} tets not positively oriented",
        vols.len()
    );
    (mesh, vols.iter().sum())
}

#[test]
fn icosphere_is_meshed_with_positive_tets_and_its_volume() {
    let Some(runner) = runner() else { return };
    let dir = scratch("sphere");
    let sphere = icosphere(2);
    let out = run(&runner, &dir, &sphere).unwrap();
    let (mesh, volume) = checked_volume(&out);
    let expected = enclosed_volume(&sphere);
    let err = (volume - expected).abs() / expected;
    assert!(
        err < 0.05,
        "volume {volume} vs {expected} ({:.2} %)",
        100.0 * err
    );
    assert!(out.stats.exit_code == Some(0) && out.stats.wall_seconds > 0.0);
    assert!(out.version.starts_with("CGAL"), "version {}", out.version);
    eprintln!(
        "icosphere(2): {} tets, volume error {:.3} %",
        mesh.tets.len(),
        100.0 * err
    );

    // Same input, same seed: the same file.
    let first = std::fs::read(&out.mesh).unwrap();
    let again = run(&runner, &dir, &sphere).unwrap();
    assert!(
        first == std::fs::read(&again.mesh).unwrap(),
        "CGAL run is not deterministic"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn nested_spheres_bound_a_hollow_domain() {
    let Some(runner) = runner() else { return };
    let dir = scratch("nested");
    // The inner shell faces into the cavity (inward normals), as a hole's boundary does.
    let both = mesher::surface::generate::hollow(&icosphere(2), &icosphere(2), 0.5);
    let out = run(&runner, &dir, &both).unwrap();
    let (_, volume) = checked_volume(&out);
    let expected = enclosed_volume(&both);
    let err = (volume - expected).abs() / expected;
    assert!(
        err < 0.05,
        "volume {volume} vs shell {expected} ({:.2} %)",
        100.0 * err
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn open_surface_is_a_failed_row_not_a_panic() {
    let Some(runner) = runner() else { return };
    let dir = scratch("open");
    let mut open = icosphere(1);
    open.triangles.pop();
    match run(&runner, &dir, &open) {
        Err(RunError::Failed { message, stats }) => {
            assert!(message.contains("not closed"), "{message}");
            assert_eq!(stats.exit_code, Some(1));
        }
        other => panic!("expected a failure, got {other:?}"),
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn missing_binary_is_reported_as_missing() {
    let dir = scratch("missing");
    let runner = CgalMesh3::new(dir.join("no-such-binary"));
    assert!(matches!(
        run(&runner, &dir, &icosphere(0)),
        Err(RunError::Missing(_))
    ));
    std::fs::remove_dir_all(&dir).ok();
}

/// Regression: `harness run --out reports/runs/x` (a relative directory) made CGAL look
/// for its input relative to its own work directory and fail on every model.
#[test]
fn relative_work_directory_works() {
    let Some(runner) = runner() else { return };
    let rel = PathBuf::from(format!("cgal-rel-test-{}", std::process::id()));
    std::fs::create_dir_all(&rel).unwrap();
    let out = run(&runner, &rel, &mesher::surface::generate::icosphere(2));
    std::fs::remove_dir_all(&rel).ok();
    let out = out.expect("CGAL runs from a relative work directory");
    assert!(out.stats.exit_code == Some(0));
}
