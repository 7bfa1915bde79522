//! `harness report` on a fixture run (2 models x 3 meshers, with a missing and a failed
//! row and one model whose surface is the limit): files, numbers, notes, SVGs, HTML, and
//! the page rendered by headless Chromium.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use harness::report::{load_records, write_report, ReportError};

fn fixture_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn report_into(out: &Path) -> Vec<PathBuf> {
    let files = write_report(&fixture_dir(), out).expect("report");
    assert!(files.warnings.is_empty(), "{:?}", files.warnings);
    files.files
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn fixture_parses_as_current_records() {
    let loaded = load_records(&fixture_dir().join("results.jsonl")).unwrap();
    assert_eq!(loaded.records.len(), 6);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

#[test]
fn writes_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let files = report_into(dir.path());
    for name in [
        "table.md",
        "table.tex",
        "index.html",
        "qk-sphere1k.svg",
        "edges-sphere1k.svg",
        "qk-anchor.svg",
        "edges-anchor.svg",
        "rate.svg",
    ] {
        let p = dir.path().join(name);
        assert!(p.is_file(), "{name} missing");
        assert!(files.contains(&p), "{name} not listed");
    }
}

#[test]
fn markdown_has_table1_numbers_statuses_and_notes() {
    let dir = tempfile::tempdir().unwrap();
    report_into(dir.path());
    let md = read(&dir.path().join("table.md"));
    for expected in [
        "|  | sphere1k | anchor‡ |",
        "| **tetgen-y** |  |  |",
        "| **cgal†** |  |  |",
        "| boundary faces | 1280 | 1050 |",
        "| tets | 4321 | 2500 |",
        "| CPU s | 0.48 | 0.09 |",
        "| Q_t | 1.31 | 1.41e3 |",
        "| worst Q_K | 9.15 | 9.80e3 |",
        "| # Q_K > Q_t | 321 | 0 |",
        "| # Q_K<3 | 4100 | 243 |",
        "| % Q_K<3 | 94.89 | 9.72 |",
        "| % Q_K<3 | 99.50 | missing |",
        "| % Q_K<3 | 99.10 | failed |",
        "| tetgen-y | ok 2 | 9.15 | 9.80e3 | 63.67 | 11.4k | 20 |",
        "| gmsh-hxt | ok 1, failed 1 | 3.33 | 3.33 | 99.10 | 13.8k | 60 |",
        "| cgal† | ok 1, missing 1 | 5.33 | 5.33 | 99.50 | 1.8k | 150 |",
        "anchor: the surface is the limit: no mesher can reach good worst-case quality on this surface (Q_t = 1.41e3",
        "† cgal moves the input boundary",
    ] {
        assert!(md.contains(expected), "table.md lacks {expected:?}:\n{md}");
    }
    assert!(!md.contains("sphere1k: the surface is the limit"));
}

/// Every plot also exists as a PNG of the plot's size that decodes and is not blank: a
/// good share of white background, some pixels of the first mesher's colour (bars or
/// points) and dark pixels (text and axes, so the font was found).
#[test]
fn pngs_decode_and_are_not_blank() {
    let dir = tempfile::tempdir().unwrap();
    let files = report_into(dir.path());
    let pngs: Vec<&PathBuf> = files
        .iter()
        .filter(|p| p.extension().is_some_and(|x| x == "png"))
        .collect();
    let svgs = files
        .iter()
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .count();
    assert_eq!(pngs.len(), svgs, "one PNG per SVG");
    for png in pngs {
        assert!(png.with_extension("svg").is_file(), "{}", png.display());
        let pixels = decode_rgb(png);
        assert_eq!(pixels.len(), 760 * 420, "{}", png.display());
        let white = share_of(&pixels, [255, 255, 255]);
        let series = share_of(&pixels, [31, 119, 180]);
        let dark = pixels.iter().filter(|p| p.iter().all(|&c| c < 80)).count();
        assert!(
            white > 0.3 && white < 0.999,
            "{}: white {white}",
            png.display()
        );
        assert!(series > 0.0005, "{}: series colour {series}", png.display());
        assert!(
            dark > 200,
            "{}: {dark} dark pixels (no text?)",
            png.display()
        );
    }
}

/// A record with a front series (ours, once `mesher mesh --stats` exists) gets a front
/// convergence plot in its model's section.
#[test]
fn front_series_is_plotted() {
    let dir = tempfile::tempdir().unwrap();
    let text = read(&fixture_dir().join("results.jsonl"));
    let first = text.lines().next().unwrap();
    let mut rec: harness::records::Record = serde_json::from_str(first).unwrap();
    rec.mesher = "ours".into();
    rec.front = Some(
        [
            (2560, 2400, 2100),
            (3900, 3500, 2900),
            (1200, 900, 700),
            (80, 40, 30),
        ]
        .map(
            |(front, proposed, inserted)| harness::records::FrontIteration {
                front,
                proposed,
                inserted,
            },
        )
        .to_vec(),
    );
    let jsonl = format!("{text}{}\n", serde_json::to_string(&rec).unwrap());
    std::fs::write(dir.path().join("results.jsonl"), jsonl).unwrap();
    let out = dir.path().join("report");
    write_report(dir.path(), &out).unwrap();
    let stem = format!("front-{}-ours", rec.model);
    for ext in ["svg", "png"] {
        assert!(out.join(format!("{stem}.{ext}")).is_file(), "{stem}.{ext}");
    }
    assert!(read(&out.join("index.html")).contains(&format!("{stem}.svg")));
    let none = tempfile::tempdir().unwrap();
    write_report(&fixture_dir(), none.path()).unwrap();
    let fronts = std::fs::read_dir(none.path())
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .starts_with("front-")
        })
        .count();
    assert_eq!(fronts, 0, "no series, no front plot");
}

#[test]
fn latex_is_escaped() {
    let dir = tempfile::tempdir().unwrap();
    report_into(dir.path());
    let tex = read(&dir.path().join("table.tex"));
    assert!(tex.contains("\\begin{tabular}{lrr}"));
    assert!(tex.contains("\\multicolumn{3}{l}{\\textbf{cgal$^\\dagger$}}"));
    assert!(tex.contains("\\% $Q_K$$<$3 & 94.89 & 9.72 \\\\"));
    assert!(tex.contains("no mesher can reach good worst-case quality"));
    assert_eq!(
        tex.matches("\\begin{tabular}").count(),
        tex.matches("\\end{tabular}").count()
    );
}

#[test]
fn svgs_are_well_formed_and_html_references_them() {
    let dir = tempfile::tempdir().unwrap();
    report_into(dir.path());
    let html = read(&dir.path().join("index.html"));
    let mut n = 0;
    for e in std::fs::read_dir(dir.path()).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "svg") {
            let svg = read(&p);
            let head = svg.trim_start();
            assert!(
                head.starts_with("<svg") || head.starts_with("<?xml"),
                "{}",
                p.display()
            );
            assert!(svg.trim_end().ends_with("</svg>"), "{}", p.display());
            let name = p.file_name().unwrap().to_str().unwrap();
            assert!(
                html.contains(&format!("src=\"{name}\"")),
                "index.html lacks {name}"
            );
            n += 1;
        }
    }
    assert_eq!(n, 5);
    for expected in [
        "a51f397",
        "2 x Test CPU @ 2.0GHz",
        "2026-11-22T04:00:01Z",
        "METHODOLOGY.md",
        "no mesher can reach good worst-case quality on this surface",
        "corrupted size vs. prev_size",
        "<style>",
    ] {
        assert!(html.contains(expected), "index.html lacks {expected:?}");
    }
}

#[test]
fn bad_lines_are_skipped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = read(&fixture_dir().join("results.jsonl"));
    text.push_str("not json\n\n{\"model\":\"x\"}\n");
    std::fs::write(dir.path().join("results.jsonl"), text).unwrap();
    let report = write_report(dir.path(), dir.path()).unwrap();
    assert_eq!(report.warnings.len(), 2, "{:?}", report.warnings);
    assert!(report.warnings[0].contains("results.jsonl:7:"));
    assert!(report.warnings[1].contains("results.jsonl:9:"));
    assert!(dir.path().join("index.html").is_file());
}

#[test]
fn no_records_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    assert!(matches!(
        write_report(dir.path(), dir.path()),
        Err(ReportError::Io { .. })
    ));
    std::fs::write(dir.path().join("results.jsonl"), "garbage\n").unwrap();
    assert!(matches!(
        write_report(dir.path(), dir.path()),
        Err(ReportError::NoRecords(_))
    ));
}

#[test]
fn cli_writes_into_out() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_harness"))
        .arg("report")
        .arg(fixture_dir())
        .arg("--out")
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("index.html"));
    assert!(dir.path().join("table.md").is_file());
    let bad = Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(["report", "/nonexistent-run-dir"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
}

fn find_chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|c| {
            Command::new(c)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        })
}

/// Runs `cmd`, killing it after `limit`.
fn run_with_timeout(cmd: &mut Command, limit: Duration) -> bool {
    let mut child = cmd.spawn().expect("spawn chromium");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status.success();
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return false;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// RGB pixels of a PNG.
fn decode_rgb(path: &Path) -> Vec<[u8; 3]> {
    let mut reader = png::Decoder::new(std::fs::File::open(path).unwrap())
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let bpp = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        c => panic!("unexpected PNG colour type {c:?}"),
    };
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf[..info.buffer_size()]
        .chunks_exact(bpp)
        .map(|p| [p[0], p[1], p[2]])
        .collect()
}

fn share_of(pixels: &[[u8; 3]], rgb: [u8; 3]) -> f64 {
    let near = |p: &[u8; 3]| (0..3).all(|i| p[i].abs_diff(rgb[i]) <= 4);
    pixels.iter().filter(|p| near(p)).count() as f64 / pixels.len() as f64
}

#[test]
fn chromium_renders_tables_and_plots() {
    let Some(chromium) = find_chromium() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "chromium is missing on CI: scripts/setup.sh installs it"
        );
        eprintln!("skipped: chromium not installed (scripts/setup.sh installs it)");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    report_into(dir.path());
    let profile = tempfile::tempdir().unwrap();
    let shot = dir.path().join("shot.png");
    let ok = run_with_timeout(
        Command::new(chromium)
            .args(["--headless", "--no-sandbox", "--disable-gpu"])
            .args([
                "--disable-background-networking",
                "--disable-component-update",
            ])
            .args([
                "--disable-sync",
                "--no-first-run",
                "--window-size=1280,2000",
            ])
            .arg(format!("--user-data-dir={}", profile.path().display()))
            .arg(format!("--screenshot={}", shot.display()))
            .arg(format!(
                "file://{}",
                dir.path().join("index.html").display()
            ))
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null()),
        Duration::from_secs(120),
    );
    assert!(ok && shot.is_file(), "chromium wrote no screenshot");
    let pixels = decode_rgb(&shot);
    assert_eq!(pixels.len(), 1280 * 2000);
    let white = share_of(&pixels, [255, 255, 255]);
    assert!(
        white < 0.97,
        "page is nearly blank ({:.1} % white)",
        100.0 * white
    );
    // Table header background (#eef) and the first series colour of the plots.
    let header = share_of(&pixels, [0xee, 0xee, 0xff]);
    assert!(header > 0.001, "no table header rendered ({header})");
    let bars = share_of(&pixels, [31, 119, 180]);
    assert!(bars > 0.001, "no plot rendered ({bars})");
}
