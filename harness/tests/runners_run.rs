//! `harness run` end to end: rows for a missing peer and a real one, CSV and JSONL
//! written, `--resume` skipping finished pairs.

mod common;

use std::process::Command;

fn harness(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn run_records_rows_and_resume_skips_them() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("ball.off");
    mesher::io::write_surface(&input, &mesher::surface::generate::icosphere(1)).unwrap();
    let out = dir.path().join("out");
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
    let args = [
        "run",
        "--input",
        i,
        "--meshers",
        "ours,tetgen-y",
        "--out",
        o,
        "--timeout",
        "60",
    ];
    let r = harness(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let jsonl = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let rows: Vec<harness::records::Record> = jsonl
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows.len(), 2);
    assert!(rows
        .iter()
        .all(|r| r.model == "ball" && r.input_faces == 80));
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3);
    assert!(csv.starts_with("model,tier,category,mesher,"));
    let tg = rows.iter().find(|r| r.mesher == "tetgen-y").unwrap();
    if harness::runners::tetgen::debian_version("tetgen").is_some() {
        assert_eq!(tg.status, harness::records::Status::Ok, "{:?}", tg.message);
        assert!(tg.tets.unwrap() > 0 && tg.wall_seconds.unwrap() > 0.0);
    } else {
        assert_eq!(tg.status, harness::records::Status::Missing);
    }
    let mut again = args.to_vec();
    again.push("--resume");
    let r = harness(&again);
    assert!(r.status.success());
    let jsonl2 = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    assert_eq!(jsonl, jsonl2, "--resume re-ran a finished pair");
}

#[test]
fn unknown_mesher_is_an_error() {
    let r = harness(&["run", "--input", "x.off", "--meshers", "nope"]);
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("unknown mesher"));
}

/// `harness compare`: records in OUT/run, the report in OUT; `--limit-slow 0` turns every
/// row of a slow peer into a `skipped` row without running it.
#[test]
fn compare_runs_then_reports_and_limits_slow_peers() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("ball.off");
    mesher::io::write_surface(&input, &mesher::surface::generate::icosphere(1)).unwrap();
    let out = dir.path().join("latest");
    let r = harness(&[
        "compare",
        "--input",
        input.to_str().unwrap(),
        "--meshers",
        "tetgen-y,ftetwild",
        "--limit-slow",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let rows = harness::records::read_jsonl(&out.join("run/results.jsonl")).unwrap();
    assert_eq!(rows.len(), 2);
    let ft = rows.iter().find(|r| r.mesher == "ftetwild").unwrap();
    assert_eq!(ft.status, harness::records::Status::Skipped);
    assert!(ft.wall_seconds.is_none(), "a skipped peer must not run");
    assert!(rows.iter().all(|r| r.configuration.is_some()));
    for f in ["index.html", "table.md", "table.tex"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let md = std::fs::read_to_string(out.join("table.md")).unwrap();
    assert!(md.contains("skipped"), "{md}");
    assert!(
        md.contains("tetgen -pYq1.414 in.smesh"),
        "configuration note missing"
    );
}

#[test]
fn limit_slow_keeps_the_smallest_models_of_each_clean_tier() {
    let model = |id: &str, tier: &str, triangles| harness::run::Model {
        id: id.into(),
        path: Default::default(),
        tier: tier.into(),
        category: "convex".into(),
        triangles,
        error: None,
        sha256: String::new(),
    };
    let models = [
        model("a", "ci", 500),
        model("b", "ci", 12),
        model("c", "ci", 12),
        model("d", "ci", 46),
        model("e", "dirty", 5),
        model("f", "nightly", 20_000),
    ];
    let mut keep: Vec<String> = harness::run::slow_models(&models, Some(2))
        .into_iter()
        .collect();
    keep.sort();
    assert_eq!(keep, ["b", "c", "f"], "the dirty tier gets no slow peer");
    assert_eq!(harness::run::slow_models(&models, None).len(), 6);
}

/// Gmsh's Delaunay exits 0 with an empty mesh on an open surface (seen on the dirty
/// tier's elephant-with-holes): that is an `invalid-output` row, not `ok`.
#[test]
fn an_empty_output_is_not_ok() {
    let gmsh = std::process::Command::new(harness::runners::venv_python())
        .args(["-c", "import gmsh"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !gmsh {
        assert!(std::env::var_os("CI").is_none(), "gmsh missing and CI set");
        eprintln!("skipping: gmsh not installed (scripts/setup.sh --peers)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut open = mesher::surface::generate::icosphere(2);
    open.triangles.truncate(open.triangles.len() - 3);
    let input = dir.path().join("open.off");
    mesher::io::write_surface(&input, &open).unwrap();
    let out = dir.path().join("out");
    let r = harness(&[
        "run",
        "--input",
        input.to_str().unwrap(),
        "--meshers",
        "gmsh-delaunay",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let rows = harness::records::read_jsonl(&out.join("results.jsonl")).unwrap();
    assert_eq!(rows.len(), 1);
    assert_ne!(
        rows[0].status,
        harness::records::Status::Ok,
        "{:?}",
        rows[0]
    );
    if rows[0].exit_code == Some(0) {
        assert_eq!(rows[0].status, harness::records::Status::InvalidOutput);
    }
    eprintln!("open surface: {:?} {:?}", rows[0].status, rows[0].message);
}

/// Issue 4's comparison: our boundary mesh and TetGen's `-pY` boundary mesh, both
/// measured like any peer; ours keeps the input triangles and the volume.
#[test]
fn boundary_meshes_of_ours_and_tetgen() {
    common::ensure_mesher_binary();
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("ball.off");
    mesher::io::write_surface(&input, &mesher::surface::generate::icosphere(2)).unwrap();
    let out = dir.path().join("out");
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
    let r = harness(&[
        "run",
        "--input",
        i,
        "--meshers",
        "ours-boundary,tetgen-y-boundary",
        "--out",
        o,
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let jsonl = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    let rows: Vec<harness::records::Record> = jsonl
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let ours = rows.iter().find(|r| r.mesher == "ours-boundary").unwrap();
    assert_eq!(
        ours.status,
        harness::records::Status::Ok,
        "{:?}",
        ours.message
    );
    let v = ours.validity.as_ref().unwrap();
    assert_eq!(v.inverted, 0);
    assert_eq!(v.boundary_kept, Some(true));
    assert!((v.volume_ratio.unwrap() - 1.0).abs() < 1e-9);
    // The boundary mesh of a convex ball has no vertex but the surface's.
    assert_eq!(ours.vertices, Some(ours.input_vertices));
    let tg = rows
        .iter()
        .find(|r| r.mesher == "tetgen-y-boundary")
        .unwrap();
    if harness::runners::tetgen::debian_version("tetgen").is_some() {
        assert_eq!(tg.status, harness::records::Status::Ok, "{:?}", tg.message);
        assert_eq!(tg.vertices, Some(tg.input_vertices));
    }
}
