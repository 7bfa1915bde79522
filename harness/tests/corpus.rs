//! Corpus tests: the manifest, generated models (clean, closed, deterministic, checksums
//! as declared), midpoint refinement, error messages, and the ci tier on the real cache.

mod common;

use harness::corpus::{
    self, generate, load_manifest, materialize, select, Category, CorpusError, Model, Source, Tier,
};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn manifest() -> Vec<Model> {
    load_manifest(&repo_root()).expect("corpus/manifest.toml parses")
}

#[test]
fn manifest_parses_with_unique_ids_and_every_tier() {
    let models = manifest();
    let ids: HashSet<&str> = models.iter().map(|m| m.id.as_str()).collect();
    assert_eq!(ids.len(), models.len(), "duplicate ids");
    for id in [
        "cube",
        "fandisk-in-box",
        "hinge",
        "t13-data",
        "sphere-1k",
        "man",
    ] {
        assert!(ids.contains(id), "{id} missing");
    }
    for tier in [Tier::Ci, Tier::Nightly, Tier::Large, Tier::Dirty] {
        assert!(models.iter().any(|m| m.tier == tier), "no {tier} model");
    }
    let ci = select(&models, "ci");
    let nightly = select(&models, "nightly");
    assert!(
        ci.iter().all(|m| m.triangles < 15_000),
        "ci over 15k triangles"
    );
    assert!(nightly.len() > ci.len() && nightly.iter().all(|m| m.triangles <= 110_000));
    assert_eq!(select(&models, "all").len(), models.len());
    assert!(select(&models, "bogus").is_empty());
    assert!(models.iter().all(|m| !m.licence.is_empty()));
}

/// One manifest entry.
fn entry(id: &str, src: &str, sha: &str) -> String {
    format!(
        "[[model]]\nid = \"{id}\"\nsource = \"{src}\"\nsha256 = \"{sha}\"\ntriangles = 1\n\
         tier = \"ci\"\ncategory = \"convex\"\nlicence = \"x\"\n"
    )
}

#[test]
fn manifest_errors_name_the_problem() {
    let path = Path::new("m.toml");
    let sha = "a".repeat(64);
    let parse = |text: &str| {
        corpus::manifest::parse_manifest(path, text)
            .unwrap_err()
            .to_string()
    };
    let dup = format!(
        "{}{}",
        entry("a", "cgal:x.off", &sha),
        entry("a", "cgal:y.off", &sha)
    );
    let e = parse(&dup);
    assert!(e.contains("duplicate model id \"a\""), "{e}");
    let e = parse(&entry("b", "ftp:x", &sha));
    assert!(e.contains("model b: bad source"), "{e}");
    let e = parse(&entry("c", "refine:nope@10", &sha));
    assert!(e.contains("model c: part \"nope\""), "{e}");
    let e = parse(&entry("d", "generated:blob", &sha));
    assert!(e.contains("unknown generator"), "{e}");
    let e = parse(&entry("e", "cgal:x.off", "12"));
    assert!(e.contains("model e: sha256"), "{e}");
}

#[test]
fn generated_models_are_clean_closed_deterministic_and_as_declared() {
    let root = repo_root();
    for m in manifest() {
        let Source::Generated(name) = &m.source else {
            continue;
        };
        let a = corpus::materialize::render(&root, &m).unwrap();
        let b = corpus::materialize::render(&root, &m).unwrap();
        assert!(a == b, "{}: two renders differ", m.id);
        assert_eq!(corpus::sha256_hex(&a), m.sha256, "{}: checksum", m.id);
        let s = generate::by_name(name).unwrap();
        assert_eq!(s.triangles.len(), m.triangles, "{}", m.id);
        if m.category == Category::Unreadable {
            let text = String::from_utf8_lossy(&a);
            let e = mesher::io::off::parse("f.off", &text).expect_err(&m.id);
            assert!(e.to_string().contains("f.off:"), "{}: {e}", m.id);
            continue;
        }
        let report = s.check();
        if m.tier == Tier::Dirty {
            assert!(!report.is_clean(), "{} should be defective", m.id);
            continue;
        }
        assert!(report.is_clean(), "{}: {report}", m.id);
        assert!(report.shells.iter().all(|sh| sh.closed), "{}", m.id);
        assert!(
            report.warnings.is_empty(),
            "{}: {:?}",
            m.id,
            report.warnings
        );
        assert!(report.shells[0].signed_volume > 0.0, "{}: inward", m.id);
    }
}

#[test]
fn generated_shapes_have_the_intended_topology() {
    let hole = generate::box_with_hole(&generate::HoleBox::default()).check();
    assert_eq!(hole.shells[0].genus, Some(1));
    let v = hole.shells[0].signed_volume;
    assert!(
        (v - (4.0 - std::f64::consts::PI * 0.25)).abs() < 0.01,
        "{v}"
    );
    let nested = generate::nested_spheres().check();
    assert_eq!(nested.shells.len(), 2);
    assert_eq!(nested.num_bodies(), 1);
    assert!(nested.shells[1].signed_volume < 0.0, "inner shell inward");
    assert_eq!(generate::geodesic_sphere(5, 1.0).triangles.len(), 500);
    let slab = generate::box_grid([1.0, 1.0, 0.02], [50, 50, 1]).check();
    assert!((slab.shells[0].signed_volume - 0.02).abs() < 1e-12);
}

#[test]
fn refine_multiplies_triangles_by_four_per_level_and_stays_clean() {
    for name in ["torus", "box-with-hole"] {
        let s = generate::by_name(name).unwrap();
        let n = s.triangles.len();
        let once = generate::subdivide(&s);
        assert_eq!(once.triangles.len(), 4 * n);
        // Each edge gets one midpoint: V' = V + E = V + 3F/2.
        assert_eq!(once.vertices.len(), s.vertices.len() + 3 * n / 2);
        let (r, levels) = generate::refine(&s, 10 * n);
        assert_eq!(levels, 2);
        assert_eq!(r.triangles.len(), 16 * n);
        let report = r.check();
        assert!(report.is_clean(), "{name}: {report}");
        assert_eq!(report.shells[0].genus, s.check().shells[0].genus);
        let (same, zero) = generate::refine(&s, n);
        assert_eq!((same.triangles.len(), zero), (n, 0));
    }
}

#[test]
fn missing_files_and_bad_checksums_are_errors_naming_the_model() {
    let zero = "0".repeat(64);
    let text = format!(
        "{}{}",
        entry("far", "cgal:meshes/far.off", &zero),
        entry("ball", "generated:sphere-1k", &zero)
    );
    let repo = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(repo.path().join("corpus")).unwrap();
    std::fs::write(repo.path().join("corpus/manifest.toml"), text).unwrap();
    let models = load_manifest(repo.path()).unwrap();
    let e = materialize(repo.path(), &models[0]).unwrap_err();
    assert!(matches!(e, CorpusError::Missing { .. }));
    let msg = e.to_string();
    assert!(
        msg.contains("model far") && msg.contains("run scripts/fetch-corpus.sh"),
        "{msg}"
    );
    let e = materialize(repo.path(), &models[1]).unwrap_err();
    assert!(matches!(e, CorpusError::Checksum { .. }), "{e}");
    assert!(
        e.to_string().contains("model ball: checksum mismatch"),
        "{e}"
    );
}

#[test]
fn ci_tier_resolves_and_checks_clean() {
    let root = repo_root();
    if !common::corpus_cache_present() {
        return;
    }
    let models = manifest();
    for m in select(&models, "ci") {
        let (line, ok) = corpus::check_model(&root, m).unwrap_or_else(|e| panic!("{e}"));
        assert!(ok, "{line}");
    }
}

#[test]
fn cli_list_check_and_refine() {
    let root = repo_root();
    let exe = env!("CARGO_BIN_EXE_harness");
    let run = |args: &[&str]| {
        Command::new(exe)
            .args(["corpus", "--root"])
            .arg(&root)
            .args(args)
            .output()
            .unwrap()
    };
    let out = run(&["list", "--tier", "dirty"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(text.contains("man ") && !text.contains("fandisk"), "{text}");
    let out = run(&["check", "--tier", "all", "sphere-1k", "two-cubes-edge"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("non-manifold 2"), "{text}");
    let dir = tempfile::tempdir().unwrap();
    let dest = dir.path().join("t.off");
    let dest_arg = dest.to_str().unwrap();
    let out = run(&["refine", "torus", "--triangles", "3000", "-o", dest_arg]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = mesher::io::read_surface(&dest).unwrap().surface;
    assert_eq!(s.triangles.len(), 4 * 2560);
}
