//! CI runs the whole ci tier with TetGen (`tetgen-y`) and CGAL Mesh_3 (`cgal`) through
//! `harness run`: one row per model and mesher, every row `ok` (the ci tier is clean),
//! and every mesh valid: no inverted tet, no face in three tets; TetGen keeps the input
//! triangles and the enclosed volume; CGAL, which re-meshes the surface, stays within
//! 10 % of the volume and 5 % of the box diagonal (Hausdorff, when pymeshlab is there):
//! sanity bounds that catch a lost body or a wild surface (the worst ci model, rotor,
//! a coarse CAD surface, is at 5.3 % and 1.9 %).
//!
//! With `HARNESS_CI_RUN=DIR` (set by `scripts/test.sh`) it checks the rows of that run
//! instead of running the tier itself.
//!
//! Needs the corpus cache (`scripts/fetch-corpus.sh`), TetGen and `cgal-mesh3`: skipped
//! with a message when one is missing, a failure when `CI` is set.

mod common;

use harness::records::{Record, Status};
use std::process::Command;

fn ci_model_count() -> usize {
    let models = harness::corpus::load_manifest(&common::repo_root()).unwrap();
    harness::corpus::select(&models, "ci").len()
}

fn check_row(r: &Record) {
    let what = format!("{} / {}", r.model, r.mesher);
    assert_eq!(r.status, Status::Ok, "{what}: {:?}", r.message);
    let v = r.validity.as_ref().unwrap();
    assert_eq!(v.inverted, 0, "{what}");
    assert_eq!(v.non_manifold_faces, 0, "{what}");
    assert!(
        r.tets.unwrap() > 0 && r.cpu_seconds.unwrap() > 0.0,
        "{what}"
    );
    assert!(r.peak_rss_bytes.unwrap() > 0, "{what}");
    let ratio = v.volume_ratio.unwrap();
    if r.mesher == "tetgen-y" {
        assert_eq!(v.boundary_kept, Some(true), "{what}");
        assert!((ratio - 1.0).abs() < 1e-6, "{what}: volume ratio {ratio}");
    } else {
        assert!((ratio - 1.0).abs() < 0.1, "{what}: volume ratio {ratio}");
        if let Some(h) = v.hausdorff {
            assert!(h < 0.05, "{what}: Hausdorff {h} of the diagonal");
        }
    }
}

/// The ci-tier run `scripts/test.sh` already made for the regression gate, if any: its
/// rows of TetGen and CGAL (the tier is not run twice in CI).
fn shared_run() -> Option<Vec<Record>> {
    let dir = std::path::PathBuf::from(std::env::var_os("HARNESS_CI_RUN")?);
    let rows = harness::records::read_jsonl(&dir.join("results.jsonl")).unwrap();
    Some(
        rows.into_iter()
            .filter(|r| r.mesher == "tetgen-y" || r.mesher == "cgal")
            .collect(),
    )
}

#[test]
fn ci_tier_with_tetgen_and_cgal() {
    if let Some(rows) = shared_run() {
        assert_eq!(rows.len(), 2 * ci_model_count());
        rows.iter().for_each(check_row);
        return;
    }
    let tetgen = harness::runners::tetgen::debian_version("tetgen").is_some();
    if !common::corpus_cache_present() || !common::peer_present("tetgen", tetgen) {
        return;
    }
    let Some(cgal) = common::cgal_binary() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let r = Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(["run", "--corpus", "ci", "--meshers", "tetgen-y,cgal"])
        .arg("--out")
        .arg(&out)
        .env("CGAL_MESH3_BIN", &cgal)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let rows = harness::records::read_jsonl(&out.join("results.jsonl")).unwrap();
    assert_eq!(rows.len(), 2 * ci_model_count());
    rows.iter().for_each(check_row);
}
