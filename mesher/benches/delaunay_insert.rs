//! Criterion bench of the Delaunay kernel: uniform random points (10^4, 10^5, 10^6), the
//! 10k vertices of the level-5 icosphere (nearly cospherical: every insphere among
//! neighbours needs the exact stages) and the vertices of a real surface when one is
//! available; plus the exact insphere stages alone on nearly cospherical points (the
//! fixed-point stage against `robust`).
//!
//! `cargo bench -p mesher --bench delaunay_insert`. The surface case uses CGAL's
//! armadillo from the corpus cache (`scripts/fetch-corpus.sh`) or `MESHER_BENCH_SURFACE`;
//! `MESHER_BENCH_MAX=100000` skips the 10^6 case.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use mesher::delaunay::{sort::SplitMix64, triangulate, DelaunayOptions};
use mesher::Point;
use std::time::Duration;

fn uniform(n: usize, seed: u64) -> Vec<Point> {
    let mut r = SplitMix64::new(seed);
    let mut u = || r.unit();
    (0..n).map(|_| Point::new(u(), u(), u())).collect()
}

fn bench_uniform(c: &mut Criterion) {
    let max: usize = std::env::var("MESHER_BENCH_MAX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let mut g = c.benchmark_group("delaunay_insert");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for n in [10_000usize, 100_000, 1_000_000] {
        if n > max {
            continue;
        }
        let pts = uniform(n, 1);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("uniform", n), &pts, |b, pts| {
            b.iter(|| triangulate(pts, &DelaunayOptions::default()).map(|t| t.mesh.num_slots()))
        });
    }
    let sphere = mesher::surface::generate::icosphere(5).vertices;
    g.throughput(Throughput::Elements(sphere.len() as u64));
    g.bench_with_input(BenchmarkId::new("icosphere", 5), &sphere, |b, pts| {
        b.iter(|| triangulate(pts, &DelaunayOptions::default()).map(|t| t.mesh.num_slots()))
    });
    let default_surface = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../corpus/cache/cgal/meshes/armadillo.off"
    );
    let path = std::env::var("MESHER_BENCH_SURFACE").unwrap_or_else(|_| default_surface.into());
    if std::path::Path::new(&path).is_file() {
        match mesher::io::read_surface(std::path::Path::new(&path)) {
            Ok(s) => {
                let pts = s.surface.vertices;
                let name = std::path::Path::new(&path)
                    .file_stem()
                    .map_or_else(|| path.clone(), |s| s.to_string_lossy().into_owned());
                g.throughput(Throughput::Elements(pts.len() as u64));
                g.bench_with_input(BenchmarkId::new("surface", name), &pts, |b, pts| {
                    b.iter(|| {
                        triangulate(pts, &DelaunayOptions::default()).map(|t| t.mesh.num_slots())
                    })
                });
            }
            Err(e) => eprintln!("{path}: {e}"),
        }
    } else {
        eprintln!("no surface for the surface case: run scripts/fetch-corpus.sh");
    }
    g.finish();
}

/// Nearly cospherical 5-tuples: neighbouring icosphere vertices, which the floating-point
/// filter cannot decide.
fn bench_insphere_exact(c: &mut Criterion) {
    use mesher::geom::predicates::{insphere_exact, insphere_robust};
    let s = mesher::surface::generate::icosphere(5);
    let tuples: Vec<[Point; 5]> = s
        .triangles
        .windows(2)
        .step_by(7)
        .take(1000)
        .filter_map(|w| {
            let mut v: Vec<u32> = w.iter().flatten().copied().collect();
            v.sort_unstable();
            v.dedup();
            (v.len() >= 5).then(|| std::array::from_fn(|i| s.vertices[v[i] as usize]))
        })
        .collect();
    let mut g = c.benchmark_group("insphere_cospherical");
    g.throughput(Throughput::Elements(tuples.len() as u64));
    g.bench_function("fixed", |b| {
        b.iter(|| {
            tuples
                .iter()
                .map(|p| insphere_exact(p[0], p[1], p[2], p[3], p[4]) as u32)
                .sum::<u32>()
        })
    });
    g.bench_function("robust", |b| {
        b.iter(|| {
            tuples
                .iter()
                .map(|p| insphere_robust(p[0], p[1], p[2], p[3], p[4]) as u32)
                .sum::<u32>()
        })
    });
    g.finish();
}

criterion_group!(benches, bench_uniform, bench_insphere_exact);
criterion_main!(benches);
