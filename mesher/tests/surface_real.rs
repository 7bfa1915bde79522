//! The checker on real meshes: CGAL's data set (Debian package `libcgal-demo`), fetched
//! by `scripts/fetch-corpus.sh` into `corpus/cache/cgal/meshes` (or `MESHER_CGAL_DATA`).
//! Without the files the tests are skipped with a message, except under CI where they
//! fail: `scripts/test.sh` fetches them.

use mesher::io::read_surface;
use mesher::surface::report::CheckReport;
use std::path::PathBuf;

fn dir() -> Option<PathBuf> {
    let d = std::env::var_os("MESHER_CGAL_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../corpus/cache/cgal/meshes")
        });
    if d.join("fandisk.off").is_file() {
        return Some(d);
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "CGAL data meshes missing in {}: run scripts/fetch-corpus.sh",
        d.display()
    );
    eprintln!(
        "skipped: no CGAL data meshes in {} (run scripts/fetch-corpus.sh)",
        d.display()
    );
    None
}

fn check(name: &str) -> Option<CheckReport> {
    let path = dir()?.join(format!("{name}.off"));
    let read = read_surface(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    Some(read.surface.check())
}

#[test]
fn clean_models_pass() {
    for (name, bodies) in [
        ("cube", 1),
        ("3torus", 1),
        ("anchor", 1),
        ("rotor", 1),
        ("pinion", 1),
        ("couplingdown", 1),
        ("elephant", 1),
        ("fandisk", 1),
        ("fandisk-box", 1),
        ("knot2", 2),
        ("cheese", 1),
        ("turbine", 1),
        ("armadillo", 1),
        ("bunny00", 1),
    ] {
        let Some(r) = check(name) else { return };
        assert!(r.is_clean(), "{name} should be clean:\n{r}");
        assert_eq!(r.num_bodies(), bodies, "{name}:\n{r}");
    }
    let r = check("cheese").expect("checked above");
    assert_eq!(r.shells[0].genus, Some(133));
}

#[test]
fn dirty_models_name_their_defect() {
    let Some(r) = check("mushroom") else { return };
    assert!(!r.is_clean() && !r.open_edges.is_empty(), "mushroom:\n{r}");
    assert!(r.to_string().contains("open edges"));

    let r = check("elephant-with-holes").expect("data present");
    assert!(
        !r.open_edges.is_empty() && !r.pinched_vertices.is_empty(),
        "{r}"
    );

    let r = check("man").expect("data present");
    assert!(r.self_intersections.count > 0, "man:\n{r}");
    assert!(r.to_string().contains("self-intersecting"));

    let r = check("tetra_intersected_by_triangle").expect("data present");
    assert_eq!(r.self_intersections.count, 1, "{r}");
}

#[test]
fn every_cgal_mesh_reads_or_fails_cleanly_and_checks_without_panic() {
    let Some(d) = dir() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&d)
        .expect("readable data dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "off" || e == "stl"))
        .collect();
    files.sort();
    assert!(files.len() > 100);
    for f in files {
        if let Ok(read) = read_surface(&f) {
            let r = read.surface.check();
            // The text report must render for every input.
            assert!(!r.to_string().is_empty());
        }
    }
}
