//! The fuzzing regressions (issue 8): every input under `tests/regress/<target>/` once
//! made a fuzz target of `fuzz/` fail; each is replayed through the same checks
//! (`fuzz/src/oracle.rs`, compiled in here), so a fixed bug stays fixed. File names say
//! what failed; `tests/regress/README.md` lists them.

#[path = "../../fuzz/src/oracle.rs"]
#[allow(dead_code)]
mod oracle;

use mesher::io::SurfaceFormat;
use std::path::PathBuf;

/// The committed inputs of one target, sorted by name.
fn inputs(target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/regress")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.map(|e| e.expect("a directory entry").path()).collect())
        .unwrap_or_default();
    files.retain(|p| p.is_file() && p.file_name().is_some_and(|n| n != ".gitkeep"));
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p.display().to_string();
            (name, std::fs::read(&p).expect("a regression input"))
        })
        .collect()
}

fn replay(target: &str, check: impl Fn(&[u8])) {
    for (name, bytes) in inputs(target) {
        eprintln!("replaying {name}");
        check(&bytes);
    }
}

#[test]
fn delaunay_regressions() {
    replay("delaunay", oracle::delaunay);
}

#[test]
fn mesh_regressions() {
    replay("mesh", oracle::mesh);
}

#[test]
fn parser_regressions() {
    for (target, format) in [
        ("parse_obj", SurfaceFormat::Obj),
        ("parse_off", SurfaceFormat::Off),
        ("parse_stl", SurfaceFormat::Stl),
        ("parse_medit", SurfaceFormat::Medit),
    ] {
        replay(target, |b| oracle::parse(format, b));
    }
}

#[test]
fn kernel_refuses_a_non_finite_point() {
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ]
    .map(|[x, y, z]| mesher::Point::new(x, y, z));
    let mut mesh = mesher::delaunay::triangulate(&pts, &Default::default())
        .expect("a tet")
        .mesh;
    let mut k = mesher::delaunay::Kernel::new();
    for p in [[1e3, f64::NAN, f64::NAN], [f64::INFINITY, 0.0, 0.0]] {
        let e = k
            .insert(&mut mesh, mesher::Point::new(p[0], p[1], p[2]))
            .expect_err("refused");
        assert!(e.to_string().contains("non-finite"), "{e}");
    }
    assert_eq!(mesh.num_vertices(), 4);
    mesh.validate(true).expect("unchanged");
}
