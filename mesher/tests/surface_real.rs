//! The checker on real meshes from CGAL's data set (Debian package `libcgal-demo`,
//! `data.tar.gz`). Ignored by default: the files are not in the repository. Run with
//! `MESHER_CGAL_DATA=/path/to/data/meshes cargo test --release -p mesher --test
//! surface_real -- --ignored --nocapture` (default path `/tmp/cgal-data/data/meshes`).

use mesher::io::{read_surface, read_surface_unwelded};
use std::path::PathBuf;
use std::time::Instant;

fn dir() -> PathBuf {
    std::env::var_os("MESHER_CGAL_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/tmp/cgal-data/data/meshes"))
}

#[test]
#[ignore = "needs CGAL's data meshes on disk"]
fn cgal_meshes() {
    let names = std::env::var("MESHER_CGAL_FILES").unwrap_or_else(|_| {
        "elephant fandisk knot2 cheese bunny00 armadillo mushroom elephant-with-holes man"
            .to_string()
    });
    for name in names.split_whitespace() {
        let path = dir().join(format!("{name}.off"));
        let read = match read_surface(&path) {
            Ok(r) => r,
            Err(e) => {
                println!("== {name}: unreadable: {e}");
                continue;
            }
        };
        let t = Instant::now();
        let r = read.surface.check();
        println!(
            "== {name} (welded {}, dropped {}) checked in {:.3} s, {} candidate pairs\n{r}",
            read.welded_vertices,
            read.dropped_unused_vertices,
            t.elapsed().as_secs_f64(),
            r.self_intersections.candidates
        );
        if read.welded_vertices > 0 {
            if let Ok(raw) = read_surface_unwelded(&path) {
                println!("-- {name} without welding:\n{}", raw.check());
            }
        }
    }
}
