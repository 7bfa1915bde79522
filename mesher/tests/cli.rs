//! End-to-end tests of the `mesher` command line: exit codes, messages, outputs.

use std::path::PathBuf;
use std::process::{Command, Output};

fn mesher(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mesher"))
        .args(args)
        .output()
        .expect("mesher runs")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("mesher-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn generate_check_delaunay_round_trip() {
    let d = scratch("roundtrip");
    let s = d.join("sphere.off");
    let o = mesher(&[
        "generate",
        "sphere",
        "--level",
        "2",
        "-o",
        s.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));

    let o = mesher(&["check", s.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stdout));
    assert!(text(&o.stdout).contains("clean"));

    let out = d.join("dt.vtu");
    let o = mesher(&[
        "delaunay",
        s.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--stats",
        "--validate",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stats: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON stats");
    assert_eq!(stats["points"], 162);
    let tets = stats["tets"].as_u64().unwrap();
    let back = mesher::io::read_volume(&out).expect("readable output");
    assert_eq!(back.tets.len() as u64, tets);
    assert_eq!(back.vertices.len(), 162);
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn check_reports_defects_with_exit_code_1() {
    let d = scratch("open");
    let f = d.join("open.off");
    // A tetrahedron with one face missing: three open edges.
    std::fs::write(
        &f,
        "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n",
    )
    .unwrap();
    let o = mesher(&["check", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stdout).contains("open edges"),
        "{}",
        text(&o.stdout)
    );
    let o = mesher(&["check", f.to_str().unwrap(), "--json"]);
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON report");
    assert_eq!(r["open_edges"].as_array().map(Vec::len), Some(3));
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn bad_input_names_file_and_line_with_exit_code_2() {
    let d = scratch("bad");
    let f = d.join("bad.off");
    std::fs::write(&f, "OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n").unwrap();
    let o = mesher(&["check", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = text(&o.stderr);
    assert!(err.contains("bad.off:4"), "{err}");

    let n = d.join("flat.node");
    std::fs::write(&n, "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n").unwrap();
    let o = mesher(&["delaunay", n.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("coplanar"), "{}", text(&o.stderr));

    let o = mesher(&["check", d.join("missing.off").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("missing.off"));
    std::fs::remove_dir_all(d).ok();
}
