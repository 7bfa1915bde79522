//! Reliability (issue 8): scaled and offset copies of a model mesh as the unit copy
//! does; the same input gives byte-identical files across runs of `mesher mesh` and
//! across thread counts; the time limit returns the best valid mesh or a typed error;
//! a failed run leaves no output file.

use mesher::geom::Point;
use mesher::limit::TimeLimitAction;
use mesher::quality::summarize;
use mesher::surface::generate::{cube, icosphere, torus};
use mesher::{mesh, MeshError, Params, Surface};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Tet count and worst Q_K of `s` meshed with the default parameters; the mesh must be
/// valid with the enclosed volume.
fn tets_and_worst(name: &str, s: &Surface) -> (usize, f64) {
    let (m, r) = mesh(s, &Params::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
    m.mesh
        .validate(false)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let vm = m.to_volume_mesh();
    let volume = vm.volume();
    let enclosed = r.boundary.enclosed_volume;
    assert!(
        ((volume - enclosed) / enclosed).abs() < 1e-9,
        "{name}: volume {volume} vs enclosed {enclosed}"
    );
    (vm.tets.len(), summarize(&vm, None).worst_q_k)
}

/// `s` with its coordinates rounded to multiples of 2^-30: then the offset by 1e6 and
/// the scaling by 1e6 are exact, and the copies are the same shape as the unit copy.
fn snapped(s: &Surface) -> Surface {
    let g = 2f64.powi(30);
    transformed_with(s, |p| (p * g).round() / g)
}

/// `s` with every vertex moved radially by a pseudo-random fraction of at most 1 %.
fn jittered(s: &Surface) -> Surface {
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    let mut out = s.clone();
    for p in &mut out.vertices {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let r = (x >> 11) as f64 / (1u64 << 53) as f64;
        *p *= 1.0 + 0.02 * (r - 0.5);
    }
    out
}

/// Tolerances of copies of the same shape ([`scaled_copies_agree`]).
const EXACT: (f64, f64) = (0.0, 0.01);
/// Tolerances of copies rounded by the transformation.
const ROUNDED: (f64, f64) = (0.03, 0.05);

fn transformed_with(s: &Surface, f: impl Fn(Point) -> Point) -> Surface {
    Surface {
        vertices: s.vertices.iter().map(|&p| f(p)).collect(),
        triangles: s.triangles.clone(),
    }
}

/// The unit copy against the copy offset by 1e6, the one with diagonal 1e-4 and the one
/// scaled by 1e6, with tolerances `(tets, worst Q_K)` relative to the unit copy.
///
/// Copies of the same shape (the input snapped so that the offset and the 1e6 scaling
/// round nothing) give the same tet count, and the same worst Q_K to 1 %: the field
/// points and the smoothed positions are inexact constructions whose last bits depend
/// on the scale, and the optimiser's choices between near-equal moves follow them
/// (measured on the jittered level-2 sphere). Copies whose coordinates were rounded by
/// the transformation are slightly different surfaces, and the front's discrete choices
/// follow the last bits too (measured up to 2.5 % in tets, 4.6 % in worst Q_K: the
/// optimiser's path on a small mesh is chaotic); so those get 3 % and 5 %.
///
/// The test surfaces are jittered: on the perfectly symmetric icosphere, whole classes
/// of field points are cospherical in exact arithmetic, so the Delaunay kernel's choice
/// among them is decided by the last bits of the constructions, and any copy may
/// differ. Measured on its rounded copies: 8 % in tets at a point length of 1.1, 7 %
/// at 1.25 (the jittered sphere: within 3 % at every length from 1.0 to 1.3); it gets
/// 10 %.
fn scaled_copies_agree(name: &str, unit: &Surface, (tet_tol, q_tol): (f64, f64)) {
    let (lo, hi) = unit.vertices.iter().fold(
        (Point::splat(f64::MAX), Point::splat(f64::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let diag = lo.distance(hi);
    let (tets, worst) = tets_and_worst(name, unit);
    let mut table = format!("{name}: unit-scaled {tets} tets, worst Q_K {worst}");
    let mut ok = true;
    for (what, k, offset) in [
        ("offset by 1e6", 1.0, 1e6),
        ("diagonal 1e-4", 1e-4 / diag, 0.0),
        ("scaled by 1e6", 1e6, 0.0),
    ] {
        let label = format!("{name}, {what}");
        let copy = transformed_with(unit, |p| p * k + Point::splat(offset));
        let (t, w) = tets_and_worst(&label, &copy);
        ok &= (t as f64 - tets as f64).abs() <= tet_tol * tets as f64;
        ok &= (w - worst).abs() <= q_tol * worst;
        table += &format!("; {what}: {t} tets, worst Q_K {w}");
    }
    assert!(ok, "{table} (tolerances {tet_tol}, {q_tol})");
}

#[test]
fn scaled_copies_of_a_sphere_mesh_alike() {
    let sphere = jittered(&icosphere(2));
    scaled_copies_agree("sphere", &snapped(&sphere), EXACT);
    scaled_copies_agree("sphere, rounded copies", &sphere, ROUNDED);
    scaled_copies_agree(
        "symmetric sphere, rounded copies",
        &icosphere(2),
        (0.10, 0.05),
    );
}

#[test]
fn scaled_copies_of_a_cube_mesh_alike() {
    scaled_copies_agree("cube", &snapped(&cube(3)), EXACT);
    scaled_copies_agree("cube, rounded copies", &cube(3), ROUNDED);
}

#[test]
fn time_limit_gives_the_best_mesh_or_an_error() {
    let s = icosphere(2);
    let params = Params {
        time_limit: Some(0.0),
        ..Params::default()
    };
    let (m, r) = mesh(&s, &params).expect("the boundary mesh");
    assert_eq!(r.time_limit_hit.as_deref(), Some("boundary mesh"));
    assert!(r.optimize.is_none() && r.front.iterations.is_empty());
    m.mesh.validate(false).expect("a valid mesh");
    assert!(r.tets > 0);
    let params = Params {
        time_limit_action: TimeLimitAction::Error,
        ..params
    };
    match mesh(&s, &params) {
        Err(e @ MeshError::TimeLimit { .. }) => {
            assert!(e.to_string().contains("boundary mesh"), "{e}")
        }
        other => panic!("expected a time-limit error, got {:?}", other.map(|r| r.1)),
    }
    let generous = Params {
        time_limit: Some(1e6),
        ..params
    };
    let (_, r) = mesh(&s, &generous).expect("meshes within the limit");
    assert!(r.time_limit_hit.is_none() && r.front.converged);
}

fn mesher_cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mesher"))
        .args(args)
        .output()
        .expect("mesher runs")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("mesher-rel-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

fn write_surface(dir: &Path, name: &str, s: &Surface) -> String {
    let p = dir.join(name);
    mesher::io::write_surface(&p, s).expect("writes the surface");
    p.display().to_string()
}

#[test]
fn mesh_command_output_is_byte_identical_across_runs() {
    let d = scratch("determinism");
    let models = [
        ("sphere.off", icosphere(2)),
        ("cube.obj", cube(3)),
        ("torus.stl", torus(24, 8, 2.0, 0.5)),
    ];
    for (name, s) in &models {
        let input = write_surface(&d, name, s);
        for ext in ["mesh", "vtu", "msh"] {
            let runs: Vec<Vec<u8>> = (0..2)
                .map(|k| {
                    let out = d.join(format!("{name}.{k}.{ext}"));
                    let o = mesher_cli(&["mesh", &input, "-o", out.to_str().unwrap()]);
                    assert!(
                        o.status.success(),
                        "{name}: {}",
                        String::from_utf8_lossy(&o.stderr)
                    );
                    std::fs::read(&out).expect("the output")
                })
                .collect();
            assert!(!runs[0].is_empty());
            assert!(runs[0] == runs[1], "{name} -> .{ext}: the two runs differ");
        }
    }
    std::fs::remove_dir_all(&d).ok();
}

/// Across thread counts (issue 8): the front (optimal points, filtration) and the
/// surface check run on rayon; their results are gathered in input order, so 1, 2 and
/// 4 threads must write the same bytes. The level-4 sphere has fronts of several
/// thousand faces, so the work is split across chunks and threads.
#[test]
fn mesh_output_is_byte_identical_across_thread_counts() {
    let d = scratch("threads");
    let input = write_surface(&d, "sphere4.off", &icosphere(4));
    let runs: Vec<Vec<u8>> = ["1", "2", "4"]
        .iter()
        .map(|n| {
            let out = d.join(format!("t{n}.mesh"));
            let o = Command::new(env!("CARGO_BIN_EXE_mesher"))
                .args(["mesh", &input, "-o", out.to_str().unwrap()])
                .env("RAYON_NUM_THREADS", n)
                .output()
                .expect("mesher runs");
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            std::fs::read(&out).expect("the output")
        })
        .collect();
    assert!(!runs[0].is_empty());
    assert!(runs[0] == runs[1], "1 and 2 threads differ");
    assert!(runs[0] == runs[2], "1 and 4 threads differ");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_failed_run_leaves_no_output_file() {
    let d = scratch("failed");
    // An open surface: one triangle of a tet missing.
    let mut s = icosphere(0);
    s.triangles.pop();
    let input = write_surface(&d, "open.off", &s);
    let out = d.join("out.mesh");
    let o = mesher_cli(&["mesh", &input, "-o", out.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!out.exists(), "a failed run wrote {}", out.display());
    let left: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, vec!["open.off".to_string()]);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn time_limit_on_the_command_line() {
    let d = scratch("timelimit");
    let input = write_surface(&d, "sphere.off", &icosphere(2));
    let out = d.join("best.vtu");
    let o = mesher_cli(&[
        "mesh",
        &input,
        "-o",
        out.to_str().unwrap(),
        "--time-limit",
        "0",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("time limit passed after the boundary mesh"),
        "{err}"
    );
    let vm = mesher::io::read_volume(&out).expect("the best mesh so far");
    assert!(!vm.tets.is_empty());
    let out = d.join("none.vtu");
    let o = mesher_cli(&[
        "mesh",
        &input,
        "-o",
        out.to_str().unwrap(),
        "--time-limit",
        "0",
        "--time-limit-action",
        "error",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(err.contains("time limit"), "{err}");
    assert!(!out.exists());
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn dirty_inputs_are_refused_with_the_reason() {
    let d = scratch("dirty");
    let tet = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    let cases = [
        ("empty.off", String::new(), "empty.off"),
        (
            "nan.off",
            tet.replace("0 0 1\n3", "0 0 nan\n3"),
            "nan.off:6",
        ),
        (
            "one.off",
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".into(),
            "defect",
        ),
        (
            "open.off",
            tet.replace("3 0 3 2\n", "").replace("4 4 0", "4 3 0"),
            "defect",
        ),
        (
            "flat.off",
            "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n".into(),
            "defect",
        ),
    ];
    for (name, text, reason) in cases {
        let f = d.join(name);
        std::fs::write(&f, text).unwrap();
        let o = mesher_cli(&[
            "mesh",
            f.to_str().unwrap(),
            "-o",
            d.join("x.mesh").to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(
            err.contains("refused") && err.contains(reason),
            "{name}: {err}"
        );
        assert!(!d.join("x.mesh").exists());
    }
    std::fs::remove_dir_all(&d).ok();
}
