//! Helpers shared by the integration tests: finding (or building) `cgal-mesh3`, and
//! skipping a test whose peer is absent, except under `CI` where that fails.

#![allow(dead_code)]

use harness::runners::cgal::CgalMesh3;
use std::path::PathBuf;

/// True when the peer is there; false (after a message) to skip; panics when `CI` is set.
pub fn peer_present(name: &str, present: bool) -> bool {
    if present {
        return true;
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "{name} is missing and CI is set"
    );
    eprintln!("skipping: {name} is not installed (scripts/setup.sh --peers)");
    false
}

/// The `cgal-mesh3` binary, built if needed; `None` (after a message) to skip.
pub fn cgal_binary() -> Option<PathBuf> {
    let include = std::env::var_os("CGAL_INCLUDE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/usr/include"));
    let headers = include
        .join("CGAL/Polyhedral_mesh_domain_with_features_3.h")
        .exists();
    let bin = if headers {
        CgalMesh3::locate().or_else(build_cgal_binary)
    } else {
        None
    };
    if !peer_present("CGAL (libcgal-dev) and cgal-mesh3", bin.is_some()) {
        return None;
    }
    bin
}

/// `cargo test` builds the `reference` binaries only as unit-test executables: build
/// the real `cgal-mesh3` once (test profile, so the CGAL archive compiled for this run
/// is reused), serialised across the tests of one file.
fn build_cgal_binary() -> Option<PathBuf> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(bin) = CgalMesh3::locate() {
        return Some(bin);
    }
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = std::process::Command::new(cargo)
        .args([
            "build",
            "--quiet",
            "-p",
            "reference",
            "--bin",
            "cgal-mesh3",
            "--profile",
            "test",
        ])
        .status()
        .ok()?;
    status.success().then(CgalMesh3::locate).flatten()
}

/// The repository root (the workspace above this crate).
pub fn repo_root() -> PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("harness lives in the workspace")
        .to_path_buf()
}

/// True when the fetched part of the corpus cache is there; skips (or fails under CI)
/// if not.
pub fn corpus_cache_present() -> bool {
    let cache = repo_root().join("corpus/cache");
    let present = ["cgal/meshes", "netgen", "gmsh"]
        .iter()
        .all(|d| cache.join(d).is_dir());
    if !present {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set but corpus/cache is missing: run scripts/fetch-corpus.sh"
        );
        eprintln!("skipped: corpus/cache missing (run scripts/fetch-corpus.sh)");
    }
    present
}

/// `cargo test -p harness` does not build the `mesher` binary that the `ours` runners
/// call (only `cargo test --workspace` does): build it once (test profile, into the
/// target/debug folder where the runners look), serialised across the tests of a file.
/// Panics if it does not build: our own binary must.
pub fn ensure_mesher_binary() {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    if harness::runners::ours::mesher_binary().is_file() {
        return;
    }
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = std::process::Command::new(cargo)
        .args(["build", "--quiet", "-p", "mesher", "--bin", "mesher"])
        .args(["--profile", "test"])
        .status()
        .unwrap();
    assert!(
        status.success(),
        "cargo build -p mesher --bin mesher failed"
    );
}
