//! Sharding (issue 7): three shards of a small run, merged, give the unsharded run's
//! records (timings aside), and `harness merge` refuses shards of different corpora.
//! The fixture is generated surfaces (no corpus cache needed) and the cheap boundary-mesh
//! runners (ours-boundary, tetgen-y-boundary).

mod common;

use harness::records::{read_jsonl, Record};
use harness::shard::RunMeta;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn harness(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .output()
        .unwrap()
}

/// Six small closed surfaces of different sizes.
fn fixture(dir: &Path) -> Vec<String> {
    use mesher::surface::generate::{cube, icosphere, torus};
    let surfaces = [
        ("ball0", icosphere(0)),
        ("ball1", icosphere(1)),
        ("ball2", icosphere(2)),
        ("cube2", cube(2)),
        ("cube4", cube(4)),
        ("torus", torus(16, 8, 1.0, 0.3)),
    ];
    surfaces
        .iter()
        .map(|(name, s)| {
            let p = dir.join(format!("{name}.off"));
            mesher::io::write_surface(&p, s).unwrap();
            p.to_str().unwrap().to_string()
        })
        .collect()
}

fn run(inputs: &[String], out: &Path, shard: Option<&str>) {
    let mut args = vec!["run", "--meshers", "ours-boundary,tetgen-y-boundary"];
    args.extend(["--out", out.to_str().unwrap()]);
    if let Some(s) = shard {
        args.extend(["--shard", s]);
    }
    args.push("--input");
    args.extend(inputs.iter().map(String::as_str));
    let r = harness(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

/// A record without what differs from run to run (timings, resources, the clock).
fn timeless(mut r: Record) -> Record {
    r.wall_seconds = None;
    r.cpu_seconds = None;
    r.peak_rss_bytes = None;
    r.mesh_seconds = None;
    r.finished_at.clear();
    r
}

fn rows(dir: &Path) -> Vec<Record> {
    let rows = read_jsonl(&dir.join("results.jsonl")).unwrap();
    rows.into_iter().map(timeless).collect()
}

#[test]
fn three_shards_merged_equal_the_unsharded_run() {
    common::ensure_mesher_binary();
    let tmp = tempfile::tempdir().unwrap();
    let inputs = fixture(tmp.path());
    let whole = tmp.path().join("whole");
    run(&inputs, &whole, None);
    let ours_ok = rows(&whole)
        .iter()
        .filter(|r| r.mesher == "ours-boundary" && r.status == harness::records::Status::Ok)
        .count();
    assert!(
        ours_ok >= 4,
        "our boundary mesh runs in the fixture: {ours_ok} ok"
    );
    let shards: Vec<PathBuf> = (1..=3)
        .map(|k| {
            let dir = tmp.path().join(format!("shard{k}"));
            run(&inputs, &dir, Some(&format!("{k}/3")));
            dir
        })
        .collect();
    let sizes: Vec<usize> = shards.iter().map(|d| rows(d).len()).collect();
    assert!(
        sizes.iter().all(|&n| n > 0),
        "every shard has work: {sizes:?}"
    );
    let merged = tmp.path().join("merged");
    let mut args = vec!["merge"];
    args.extend(shards.iter().map(|d| d.to_str().unwrap()));
    args.extend(["--out", merged.to_str().unwrap()]);
    let r = harness(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(rows(&merged), rows(&whole));
    let meta = RunMeta::read(&merged).unwrap();
    assert_eq!(meta.shard, None);
    assert_eq!(
        meta.corpus_checksum,
        RunMeta::read(&whole).unwrap().corpus_checksum
    );

    // A shard of another corpus (a changed file) is refused, naming the checksum.
    std::fs::write(
        &inputs[0],
        "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
    )
    .unwrap();
    let other = tmp.path().join("other1");
    run(&inputs, &other, Some("1/3"));
    let mut args = vec!["merge", other.to_str().unwrap()];
    args.extend(shards[1..].iter().map(|d| d.to_str().unwrap()));
    let bad = tmp.path().join("bad");
    args.extend(["--out", bad.to_str().unwrap()]);
    let r = harness(&args);
    assert!(!r.status.success());
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("corpus checksum"), "{err}");
    // And an incomplete set of shards is refused too.
    let r = harness(&[
        "merge",
        shards[0].to_str().unwrap(),
        "--out",
        tmp.path().join("bad2").to_str().unwrap(),
    ]);
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("missing 2/3, 3/3"));
}
