//! CGAL Mesh_3 on CGAL's own data meshes (elephant, fandisk, fandisk inside its box):
//! slow, so ignored by default. Run with
//! `cargo test -p harness --test cgal_corpus -- --ignored --nocapture`; needs the corpus
//! cache (`scripts/fetch-corpus.sh`, or `$CGAL_MESHES` pointing at `data/meshes`).

use harness::runners::cgal::CgalMesh3;
use harness::runners::{RunRequest, Runner};
use mesher::quality::{summarize, target_quality, unique_triangle_edges};
use mesher::Surface;
use std::path::{Path, PathBuf};
use std::time::Duration;

fn meshes_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("CGAL_MESHES")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../corpus/cache/cgal/meshes")
        });
    dir.is_dir().then_some(dir)
}

fn mean_edge(s: &Surface) -> f64 {
    let edges = unique_triangle_edges(&s.triangles);
    let total: f64 = edges
        .iter()
        .map(|&[a, b]| s.vertices[a as usize].distance(s.vertices[b as usize]))
        .sum();
    total / edges.len() as f64
}

/// Concatenates the shells of several files into one surface.
fn load(dir: &Path, names: &[&str]) -> Surface {
    let mut all = Surface::default();
    for name in names {
        let s = mesher::io::read_surface(&dir.join(name)).unwrap().surface;
        let n = all.vertices.len() as u32;
        all.vertices.extend(&s.vertices);
        all.triangles
            .extend(s.triangles.iter().map(|t| t.map(|v| v + n)));
    }
    all
}

#[test]
#[ignore = "slow: about 10-60 s of CGAL per model"]
fn cgal_data_meshes() {
    let (Some(dir), Some(bin)) = (meshes_dir(), CgalMesh3::locate()) else {
        eprintln!("skipping: corpus cache or cgal-mesh3 missing");
        return;
    };
    let runner = CgalMesh3::new(bin);
    let work = std::env::temp_dir().join(format!("harness-cgal-corpus-{}", std::process::id()));
    for names in [
        &["elephant.off"][..],
        &["fandisk.off"],
        &["fandisk-box.off", "fandisk.off"],
    ] {
        let surface = load(&dir, names);
        let input = work.join("input.off");
        std::fs::create_dir_all(&work).unwrap();
        mesher::io::write_surface(&input, &surface).unwrap();
        // fandisk-box has 12 large triangles: size from the inner shell's edges.
        let h = mean_edge(&load(&dir, &names[names.len() - 1..]));
        let out = runner
            .run(&RunRequest {
                model: names[0],
                input: &input,
                workdir: &work,
                timeout: Duration::from_secs(600),
                edge_length: h,
            })
            .unwrap();
        let mesh = mesher::io::read_volume(&out.mesh).unwrap();
        let q_t = target_quality(&surface.vertices, &surface.triangles);
        let s = summarize(&mesh, None);
        eprintln!(
            "{names:?} ({} faces, h {h:.4}, Q_t {:.2}): {} verts, {} tets, wall {:.2} s, worst Q_K {:.2}, \
             median {:.2}, {:.2} % Q_K<3, dihedral {:.1}..{:.1}, inverted {}",
            surface.triangles.len(),
            q_t.q_t,
            mesh.vertices.len(),
            s.count,
            out.stats.wall_seconds,
            s.worst_q_k,
            s.median_q_k,
            s.well_shaped_percent,
            s.min_dihedral,
            s.max_dihedral,
            s.inverted
        );
        assert_eq!(s.inverted, 0);
    }
    std::fs::remove_dir_all(&work).ok();
}
