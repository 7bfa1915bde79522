//! `harness corpus import DIR`: a user's surfaces go to the local manifest with their
//! checksum and `Surface::check()` tier (clean -> `local`, defects -> `dirty`), unreadable
//! files are listed and left out, a second import replaces the entries of the same
//! files, and `harness run --corpus local` runs the clean ones.

mod common;

use harness::corpus::{import::load_local, Tier};
use std::path::Path;
use std::process::Command;

fn harness(root: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .current_dir(root)
        .output()
        .unwrap()
}

#[test]
fn import_then_run_the_local_tier() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path().join("repo");
    std::fs::create_dir_all(root.join("corpus")).unwrap();
    let manifest = common::repo_root().join("corpus/manifest.toml");
    std::fs::copy(manifest, root.join("corpus/manifest.toml")).unwrap();
    let mine = tmp.path().join("mine");
    std::fs::create_dir_all(mine.join("sub")).unwrap();
    let ball = mesher::surface::generate::icosphere(1);
    mesher::io::write_surface(&mine.join("ball.off"), &ball).unwrap();
    let mut open = ball.clone();
    open.triangles.pop();
    mesher::io::write_surface(&mine.join("sub/cube.off"), &open).unwrap();
    std::fs::write(mine.join("broken.stl"), "not a mesh").unwrap();
    std::fs::write(mine.join("notes.txt"), "ignored").unwrap();

    let dir = mine.to_str().unwrap();
    for _ in 0..2 {
        let r = harness(&root, &["corpus", "import", dir]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    }
    let models = load_local(&root.join("corpus/local.toml")).unwrap();
    assert_eq!(models.len(), 2, "{models:#?}");
    let ball_m = models.iter().find(|m| m.id == "ball").unwrap();
    assert_eq!(ball_m.tier, Tier::Local);
    assert_eq!(ball_m.triangles, ball.triangles.len());
    let bytes = std::fs::read(mine.join("ball.off")).unwrap();
    assert_eq!(ball_m.sha256, harness::corpus::sha256_hex(&bytes));
    // "cube" is a corpus id already: the user's model gets a prefixed one.
    let open_m = models.iter().find(|m| m.id == "local-cube").unwrap();
    assert_eq!(open_m.tier, Tier::Dirty);

    let out = tmp.path().join("run");
    let r = harness(
        &root,
        &[
            "run",
            "--corpus",
            "local",
            "--meshers",
            "tetgen-y-boundary",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let rows = harness::records::read_jsonl(&out.join("results.jsonl")).unwrap();
    assert_eq!(rows.len(), 1);
    assert_eq!(
        (rows[0].model.as_str(), rows[0].tier.as_str()),
        ("ball", "local")
    );
}
