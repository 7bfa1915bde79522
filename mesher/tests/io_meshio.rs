//! Cross-checks against meshio (the reference implementation of these formats in the
//! Python world): meshio reads what we write, and we read what meshio writes.
//!
//! Python: `$MESHER_PYTHON`, else `<workspace>/.venv/bin/python`. Without it (or without
//! meshio) the tests are skipped, unless `CI` is set, where they fail.

use mesher::io::{read_volume, write_volume};
use mesher::{Point, VolumeMesh};
use std::path::{Path, PathBuf};
use std::process::Command;

const SCRIPT: &str = r#"
import json, os, sys
import numpy as np
import meshio

def dump(m):
    pts = np.ascontiguousarray(np.asarray(m.points, dtype="<f8")[:, :3])
    tets = [t for c in m.cells if c.type == "tetra" for t in c.data.tolist()]
    print(json.dumps({"points": pts.view("<i8").tolist(), "tets": tets}))

if sys.argv[1] == "read":
    fmt = sys.argv[3] if sys.argv[3] != "auto" else None
    dump(meshio.read(sys.argv[2], file_format=fmt))
else:
    m = meshio.read(sys.argv[2])
    m.cell_data = {}
    m.point_data = {}
    out = sys.argv[3]
    ones = [np.ones(len(c.data), dtype=int) for c in m.cells]
    m41 = meshio.Mesh(
        m.points, m.cells,
        point_data={"gmsh:dim_tags": np.array([[3, 1]] * len(m.points))},
        cell_data={"gmsh:physical": ones, "gmsh:geometrical": ones})
    meshio.write(os.path.join(out, "mio41.msh"), m41, file_format="gmsh", binary=False)
    for v in ["4.2", "5.1"]:
        meshio.vtk.write(os.path.join(out, "mio%s.vtk" % v[0]), m, v, binary=False)
    for name, fmt, kw in [
        ("mio.mesh", "medit", {}),
        ("mio22.msh", "gmsh22", {"binary": False}),
        ("mio22b.msh", "gmsh22", {"binary": True}),
        ("mio.vtu", "vtu", {"binary": False}),
        ("mio.node", "tetgen", {}),
    ]:
        meshio.write(os.path.join(out, name), m, file_format=fmt, **kw)
"#;

/// The Python with meshio, or `None` (test skipped) outside CI.
fn python() -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let py = std::env::var_os("MESHER_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join(".venv/bin/python"));
    let ok = Command::new(&py)
        .args(["-c", "import meshio, numpy"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if ok {
        return Some(py);
    }
    let msg = format!(
        "{} with meshio not available: run scripts/setup.sh",
        py.display()
    );
    if std::env::var_os("CI").is_some() {
        panic!("{msg}");
    }
    eprintln!("skipping meshio test: {msg}");
    None
}

/// Runs the script; returns stdout.
fn run(py: &Path, dir: &Path, args: &[&str]) -> String {
    let script = dir.join("meshio_check.py");
    std::fs::write(&script, SCRIPT).unwrap();
    let out = Command::new(py).arg(&script).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "python {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// A few tets with coordinates that need all 17 digits.
fn mesh() -> VolumeMesh {
    let v = |x: f64, y: f64, z: f64| Point::new(x, y, z);
    VolumeMesh {
        vertices: vec![
            v(0.0, 0.0, 0.0),
            v(1.0 / 3.0, 0.0, 0.0),
            v(0.0, 0.1 + 0.2, 0.0),
            v(0.0, 0.0, std::f64::consts::E),
            v(1e-7, 2.5e20, -1.0 / 7.0),
            v(-3.0, 1.0, 1.0),
        ],
        tets: vec![[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]],
        tet_refs: vec![1, 2, 2],
        triangles: vec![[0, 2, 1]],
        triangle_refs: vec![5],
        vertex_sizes: None,
    }
}

fn bits(p: &Point) -> [i64; 3] {
    p.to_array().map(|c| c.to_bits() as i64)
}

#[test]
fn meshio_reads_what_we_write() {
    let Some(py) = python() else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = mesh();
    for (file, fmt) in [
        ("o.mesh", "medit"),
        ("o.vtu", "vtu"),
        ("o.msh", "gmsh"),
        ("o.node", "tetgen"),
    ] {
        let path = dir.path().join(file);
        write_volume(&path, &m).unwrap();
        let out = run(&py, dir.path(), &["read", path.to_str().unwrap(), fmt]);
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let pts: Vec<[i64; 3]> = serde_json::from_value(v["points"].clone()).unwrap();
        let tets: Vec<[u32; 4]> = serde_json::from_value(v["tets"].clone()).unwrap();
        let want: Vec<[i64; 3]> = m.vertices.iter().map(bits).collect();
        assert_eq!(pts, want, "{file}: coordinates differ");
        assert_eq!(tets, m.tets, "{file}: tets differ");
    }
}

#[test]
fn we_read_what_meshio_writes() {
    let Some(py) = python() else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = mesh();
    let src = dir.path().join("src.mesh");
    write_volume(&src, &m).unwrap();
    run(
        &py,
        dir.path(),
        &["write", src.to_str().unwrap(), dir.path().to_str().unwrap()],
    );
    for file in [
        "mio.mesh",
        "mio22.msh",
        "mio22b.msh",
        "mio41.msh",
        "mio.vtu",
        "mio4.vtk",
        "mio5.vtk",
        "mio.node",
    ] {
        let back = read_volume(&dir.path().join(file)).unwrap_or_else(|e| panic!("{e}"));
        if file.ends_with(".vtu") {
            // meshio writes ASCII VTU floats with `{:.11e}`: 12 significant digits.
            assert_eq!(back.vertices.len(), m.vertices.len());
            for (p, q) in back.vertices.iter().zip(&m.vertices) {
                let close = |a: f64, b: f64| (a - b).abs() <= 1e-11 * b.abs();
                assert!((0..3).all(|k| close(p[k], q[k])), "{file}: {p} vs {q}");
            }
        } else {
            let got: Vec<[i64; 3]> = back.vertices.iter().map(bits).collect();
            let want: Vec<[i64; 3]> = m.vertices.iter().map(bits).collect();
            assert_eq!(got, want, "{file}: coordinates differ");
        }
        assert_eq!(back.tets, m.tets, "{file}: tets differ");
        if file != "mio.node" {
            // (meshio's TetGen writer writes no .face)
            assert_eq!(back.triangles, m.triangles, "{file}: triangles differ");
        }
    }
}
