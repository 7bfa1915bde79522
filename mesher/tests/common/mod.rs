//! Helpers shared by the integration tests: the corpus cache and the boundary of an
//! exchange mesh.
#![allow(dead_code)] // each test binary uses a part

use mesher::io::read_surface;
use mesher::{Surface, VolumeMesh};
use std::collections::HashMap;
use std::path::PathBuf;

/// A model of the corpus cache (`corpus/cache/<rel>`), or `None` (with a note) when it
/// is not downloaded; under CI a missing model fails the test.
pub fn corpus(rel: &str) -> Option<Surface> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../corpus/cache")
        .join(rel);
    if !p.is_file() {
        assert!(
            std::env::var_os("CI").is_none(),
            "{} missing: run scripts/fetch-corpus.sh",
            p.display()
        );
        eprintln!(
            "skipped: {} missing (run scripts/fetch-corpus.sh)",
            p.display()
        );
        return None;
    }
    Some(
        read_surface(&p)
            .unwrap_or_else(|e| panic!("{rel}: {e}"))
            .surface,
    )
}

/// A triangle with its vertices sorted.
pub fn sorted(mut f: [u32; 3]) -> [u32; 3] {
    f.sort_unstable();
    f
}

/// Triangles with their vertices sorted, in sorted order.
pub fn sorted_triangles(t: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut v: Vec<[u32; 3]> = t.iter().map(|t| sorted(*t)).collect();
    v.sort_unstable();
    v
}

/// The faces of exactly one tet (the boundary of the tets' union), sorted.
pub fn boundary_faces(vm: &VolumeMesh) -> Vec<[u32; 3]> {
    let mut count: HashMap<[u32; 3], u32> = HashMap::new();
    for t in &vm.tets {
        for f in [
            [t[1], t[2], t[3]],
            [t[0], t[2], t[3]],
            [t[0], t[1], t[3]],
            [t[0], t[1], t[2]],
        ] {
            *count.entry(sorted(f)).or_default() += 1;
        }
    }
    let mut b: Vec<[u32; 3]> = count
        .into_iter()
        .filter(|e| e.1 == 1)
        .map(|e| e.0)
        .collect();
    b.sort_unstable();
    b
}
