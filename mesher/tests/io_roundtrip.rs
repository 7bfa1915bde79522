//! Write every supported format with our writers, read it back with our readers: same
//! counts, same references, bit-identical coordinates. Also reads real TetGen output
//! (skipped when `tetgen` is not on PATH).

use mesher::io::{read_surface, read_volume, write_surface, write_volume};
use mesher::{Point, Surface, VolumeMesh};
use std::path::Path;
use std::process::Command;

/// Five tets filling the unit cube, with awkward coordinates added as extra points.
fn cube_mesh() -> VolumeMesh {
    let mut vertices: Vec<Point> = (0..8)
        .map(|i| Point::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
        .collect();
    vertices[0] = Point::new(-0.0, 0.0, 0.0);
    vertices.push(Point::new(1.0 / 3.0, 0.1 + 0.2, 1e-300));
    vertices.push(Point::new(-7.25e22, 5e-324, std::f64::consts::PI));
    let tets = vec![
        [0, 1, 2, 4],
        [1, 3, 2, 7],
        [1, 2, 4, 7],
        [1, 4, 5, 7],
        [2, 4, 7, 6],
        [8, 9, 0, 1],
    ];
    let triangles = vec![[0, 2, 1], [1, 2, 3], [4, 5, 6]];
    VolumeMesh {
        tet_refs: vec![1, 1, 2, 2, -3, 1],
        triangle_refs: vec![10, 10, 11],
        vertex_sizes: Some((0..10).map(|i| 0.1 + i as f64 / 7.0).collect()),
        vertices,
        tets,
        triangles,
    }
}

fn same_bits(a: &[Point], b: &[Point]) {
    assert_eq!(a.len(), b.len(), "vertex count");
    for (i, (p, q)) in a.iter().zip(b).enumerate() {
        let pb = p.to_array().map(f64::to_bits);
        let qb = q.to_array().map(f64::to_bits);
        assert_eq!(pb, qb, "vertex {i}: {p:?} != {q:?}");
    }
}

#[test]
fn volume_formats_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let m = cube_mesh();
    for file in ["m.mesh", "m.vtu", "m.msh", "m.node"] {
        let path = dir.path().join(file);
        write_volume(&path, &m).unwrap();
        let back = read_volume(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        same_bits(&m.vertices, &back.vertices);
        assert_eq!(back.tets, m.tets, "{file}");
        assert_eq!(back.tet_refs, m.tet_refs, "{file}");
        if file != "m.vtu" {
            assert_eq!(back.triangles, m.triangles, "{file}");
            assert_eq!(back.triangle_refs, m.triangle_refs, "{file}");
        }
        if file == "m.mesh" {
            assert_eq!(back.vertex_sizes, m.vertex_sizes);
        }
    }
    // TetGen files are also found from the .ele path or the base path.
    let a = read_volume(&dir.path().join("m.ele")).unwrap();
    assert_eq!(a.tets, m.tets);
}

#[test]
fn surface_formats_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let m = cube_mesh();
    let s = Surface {
        vertices: m.vertices[..8].to_vec(),
        triangles: vec![[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6]],
    };
    let mut expected = s.clone();
    expected.vertices[0] = Point::ZERO; // -0.0 is normalised by welding
    for file in ["s.off", "s.obj", "s.stl", "s.mesh"] {
        let path = dir.path().join(file);
        write_surface(&path, &s).unwrap();
        let r = read_surface(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(r.surface.triangles.len(), 4, "{file}");
        same_bits(
            &r.surface
                .triangles
                .iter()
                .flat_map(|t| t.map(|i| r.surface.vertices[i as usize]))
                .collect::<Vec<_>>(),
            &expected
                .triangles
                .iter()
                .flat_map(|t| t.map(|i| expected.vertices[i as usize]))
                .collect::<Vec<_>>(),
        );
        assert_eq!(r.dropped_unused_vertices, 0, "{file}");
        assert_eq!(r.surface.vertices.len(), 8, "{file}");
    }
}

fn have(tool: &str) -> bool {
    Command::new(tool)
        .arg("-h")
        .output()
        .map(|_| true)
        .unwrap_or(false)
}

const CUBE_OFF: &str = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
    4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

fn run_tetgen(dir: &Path, switches: &str) -> VolumeMesh {
    let off = dir.join("cube.off");
    std::fs::write(&off, CUBE_OFF).unwrap();
    let out = Command::new("tetgen")
        .arg(switches)
        .arg(&off)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "tetgen failed: {out:?}");
    read_volume(&dir.join("cube.1.node")).unwrap()
}

fn volume(m: &VolumeMesh) -> f64 {
    (0..m.tets.len())
        .map(|t| {
            let [a, b, c, d] = m.tet_points(t);
            ((b - a).cross(c - a).dot(d - a) / 6.0).abs()
        })
        .sum()
}

#[test]
fn reads_real_tetgen_output() {
    if !have("tetgen") {
        eprintln!("skipping reads_real_tetgen_output: tetgen is not on PATH");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let m = run_tetgen(dir.path(), "-pq1.414Q");
    assert!(m.vertices.len() >= 8 && m.tets.len() >= 5, "{m:?}");
    assert!((volume(&m) - 1.0).abs() < 1e-12, "volume {}", volume(&m));
    assert!(m.tet_refs.is_empty());
    // Boundary faces cover the cube's 6 unit squares.
    let area: f64 = m
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.vertices[i as usize]);
            (b - a).cross(c - a).length() / 2.0
        })
        .sum();
    assert!((area - 6.0).abs() < 1e-12, "area {area}");
    // Regions (-A) are read as tet references.
    let dir = tempfile::tempdir().unwrap();
    let m = run_tetgen(dir.path(), "-pq1.414AQ");
    assert_eq!(m.tet_refs.len(), m.tets.len());
}
