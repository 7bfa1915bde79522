//! The regression gate (issue 7): it passes on the committed baseline itself and fails
//! on an injected regression, both through the library on `reports/baseline/ci.json`
//! and through `harness gate` on a doctored run directory.

mod common;

use harness::gate::{compare, count, Baseline, GateRow, Tolerances, Verdict};
use harness::records::{self, Status};
use std::path::PathBuf;
use std::process::Command;

fn baseline_dir() -> PathBuf {
    common::repo_root().join("reports").join("baseline")
}

fn committed() -> (Baseline, Tolerances) {
    let dir = baseline_dir();
    let b = Baseline::read(&dir.join("ci.json")).unwrap();
    let t = Tolerances::read(&dir.join("tolerances.toml")).unwrap();
    (b, t)
}

/// The first ok row of ours-boundary in the committed baseline, as an index.
fn ok_ours(rows: &[GateRow]) -> usize {
    rows.iter()
        .position(|r| r.mesher == "ours-boundary" && r.ok() && r.worst_q_k.is_some())
        .expect("the baseline has an ok ours-boundary row with a finite worst Q_K")
}

#[test]
fn the_committed_baseline_passes_against_itself() {
    let (b, t) = committed();
    let f = compare(&b.rows, &b.rows, &t);
    assert_eq!(count(&f, Verdict::Regressed), 0, "{f:#?}");
    assert!(count(&f, Verdict::Pass) > 20);
}

#[test]
fn each_injected_regression_fails_the_gate() {
    let (b, t) = committed();
    let i = ok_ours(&b.rows);
    type Doctor = fn(&mut GateRow);
    let doctors: [(&str, Doctor); 5] = [
        ("meshes", |r| r.status = Status::Failed),
        ("worst Q_K", |r| r.worst_q_k = r.worst_q_k.map(|w| w * 2.0)),
        ("% Q_K<3", |r| {
            r.well_shaped_percent = r.well_shaped_percent.map(|p| p - 5.0)
        }),
        ("tets", |r| r.tets = r.tets.map(|n| n * 2)),
        ("valid", |r| r.valid = Some(false)),
    ];
    for (check, doctor) in doctors {
        let mut now = b.rows.clone();
        doctor(&mut now[i]);
        let f = compare(&b.rows, &now, &t);
        let bad: Vec<_> = f
            .iter()
            .filter(|f| f.verdict == Verdict::Regressed)
            .collect();
        assert_eq!(bad.len(), 1, "{check}: {bad:#?}");
        assert_eq!(bad[0].check, check);
        assert_eq!(bad[0].subject, b.rows[i].model);
    }
}

#[test]
fn a_baseline_failure_that_still_fails_is_no_regression_and_a_fix_is_an_improvement() {
    let (b, t) = committed();
    let mut base = b.rows.clone();
    let i = ok_ours(&base);
    base[i].status = Status::Failed;
    assert_eq!(count(&compare(&base, &base, &t), Verdict::Regressed), 0);
    let f = compare(&base, &b.rows, &t);
    assert_eq!(count(&f, Verdict::Regressed), 0);
    assert_eq!(count(&f, Verdict::Improved), 1);
}

#[test]
fn absent_runners_are_not_compared_and_new_ones_not_gated() {
    let (b, t) = committed();
    let mut now = b.rows.clone();
    let mut extra = now[ok_ours(&now)].clone();
    extra.mesher = "ours-next".into();
    now.push(extra);
    let f = compare(&b.rows, &now, &t);
    assert_eq!(count(&f, Verdict::Regressed), 0);
    assert_eq!(count(&f, Verdict::New), 1);
}

#[test]
fn a_model_crossing_the_time_floor_does_not_change_the_speed_median() {
    let (b, t) = committed();
    let floor = t.speed.min_model_seconds;
    let wall = |rows: &[GateRow], who: &str, m: &str| {
        rows.iter()
            .find(|r| r.mesher == who && r.model == m)
            .and_then(|r| r.wall_seconds)
    };
    // A model both sides timed in the baseline, run ten times faster on both sides (the
    // same ratio) and so under the floor: it still counts, the median stays.
    let model = b
        .rows
        .iter()
        .filter(|r| r.mesher == "ours" && r.ok())
        .map(|r| r.model.clone())
        .find(|m| {
            let both = [wall(&b.rows, "ours", m), wall(&b.rows, "gmsh-hxt", m)];
            both.iter()
                .all(|w| w.is_some_and(|w| w >= floor && w < 10.0 * floor))
        })
        .expect("a model both sides ran just above the floor");
    let mut now = b.rows.clone();
    for r in now
        .iter_mut()
        .filter(|r| r.model == model && (r.mesher == "ours" || r.mesher == "gmsh-hxt"))
    {
        r.wall_seconds = r.wall_seconds.map(|w| w / 10.0);
    }
    let f = compare(&b.rows, &now, &t);
    let speed = |f: &[harness::gate::Finding]| {
        f.iter()
            .find(|x| x.check == "tets/s ratio" && x.subject.ends_with("gmsh-hxt"))
            .map(|x| (x.subject.clone(), x.baseline.clone(), x.now.clone()))
            .expect("a speed row against gmsh-hxt")
    };
    let (subject, base, now_ratio) = speed(&f);
    let (subject0, _, _) = speed(&compare(&b.rows, &b.rows, &t));
    assert_eq!(subject, subject0, "{model}");
    assert_eq!(base, now_ratio, "{model}");
    assert_eq!(count(&f, Verdict::Regressed), 0);
}

/// A run directory from the fixture records, tetgen-y playing `ours` (timed against
/// gmsh-hxt, as tolerances.toml declares for `ours`).
fn fixture_run(dir: &std::path::Path) -> PathBuf {
    let fixture = common::repo_root().join("harness/tests/fixtures/results.jsonl");
    let mut rows = records::read_jsonl(&fixture).unwrap();
    for r in rows.iter_mut().filter(|r| r.mesher == "tetgen-y") {
        r.mesher = "ours".into();
    }
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    records::write_all(&run, &rows).unwrap();
    run
}

fn gate(run: &std::path::Path, baseline: &std::path::Path, update: bool) -> (i32, String) {
    let tol = baseline_dir().join("tolerances.toml");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_harness"));
    cmd.arg("gate").arg(run).arg("--baseline").arg(baseline);
    cmd.arg("--tolerances").arg(tol);
    if update {
        cmd.arg("--update");
    }
    let out = cmd.output().unwrap();
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code().unwrap_or(-1), text)
}

#[test]
fn harness_gate_exits_1_with_a_table_on_a_doctored_run() {
    let dir = tempfile::tempdir().unwrap();
    let run = fixture_run(dir.path());
    let baseline = dir.path().join("baseline.json");
    assert_eq!(gate(&run, &baseline, true).0, 0);
    let (code, text) = gate(&run, &baseline, false);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("0 regressed"), "{text}");

    let mut rows = records::read_jsonl(&run.join("results.jsonl")).unwrap();
    for r in rows.iter_mut().filter(|r| r.mesher == "ours") {
        match r.model.as_str() {
            "sphere1k" => r.wall_seconds = r.wall_seconds.map(|w| w * 10.0),
            _ => r.status = Status::Failed,
        }
    }
    records::write_all(&run, &rows).unwrap();
    let (code, text) = gate(&run, &baseline, false);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("2 regressed"), "{text}");
    let table: Vec<&str> = text.lines().filter(|l| l.contains("REGRESSED")).collect();
    assert!(
        table
            .iter()
            .any(|l| l.contains("anchor") && l.contains("meshes")),
        "{text}"
    );
    assert!(
        table
            .iter()
            .any(|l| l.contains("tets/s ratio") && l.contains("gmsh-hxt")),
        "{text}"
    );
}
