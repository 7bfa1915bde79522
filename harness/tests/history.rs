//! The nightly history: `harness history` appends one row per mesher (a second append
//! of the same date replaces it), and `harness report --history` draws the trend plots
//! (SVG + PNG) and shows them on the page.

mod common;

use harness::report::history::{read, HistoryRow};
use std::path::Path;
use std::process::Command;

fn harness(args: &[&str]) {
    let r = Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

fn fixture_run(dir: &Path) -> String {
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    let fixture = common::repo_root().join("harness/tests/fixtures/results.jsonl");
    std::fs::copy(fixture, run.join("results.jsonl")).unwrap();
    run.to_str().unwrap().to_string()
}

#[test]
fn history_rows_per_mesher_and_trend_plots() {
    let dir = tempfile::tempdir().unwrap();
    let run = fixture_run(dir.path());
    let history = dir.path().join("history.csv");
    let h = history.to_str().unwrap();
    harness(&["history", &run, "--history", h, "--date", "2026-11-20"]);
    harness(&["history", &run, "--history", h, "--date", "2026-11-21"]);
    harness(&["history", &run, "--history", h, "--date", "2026-11-21"]);
    let rows = read(&history).unwrap();
    assert_eq!(rows.len(), 2 * 3, "3 meshers x 2 dates: {rows:#?}");
    let tetgen: Vec<&HistoryRow> = rows.iter().filter(|r| r.mesher == "tetgen-y").collect();
    assert_eq!(tetgen.len(), 2);
    assert_eq!((tetgen[0].models_ok, tetgen[0].models), (2, 2));
    assert_eq!(tetgen[0].git_commit, "a51f397");
    let gmsh = rows.iter().find(|r| r.mesher == "gmsh-hxt").unwrap();
    assert_eq!((gmsh.models_ok, gmsh.models), (1, 2));
    assert!(gmsh.tets_per_second.is_some() && gmsh.well_shaped_percent.is_some());

    let out = dir.path().join("report");
    harness(&[
        "report",
        &run,
        "--out",
        out.to_str().unwrap(),
        "--history",
        h,
    ]);
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains("Nightly trends"));
    for stem in ["trend-worst-qk", "trend-qk3", "trend-rate"] {
        for ext in ["svg", "png"] {
            let f = out.join(format!("{stem}.{ext}"));
            assert!(f.metadata().unwrap().len() > 1000, "{}", f.display());
        }
        assert!(page.contains(&format!("{stem}.svg")));
    }
}
