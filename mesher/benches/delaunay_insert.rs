//! Criterion bench of the Delaunay kernel: uniform random points (10^4, 10^5, 10^6) and
//! the vertices of a real surface when one is available.
//!
//! `cargo bench -p mesher --bench delaunay_insert`; set `MESHER_BENCH_SURFACE=path.off`
//! to add a surface's vertices, `MESHER_BENCH_MAX=100000` to skip the 10^6 case.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use mesher::delaunay::{sort::SplitMix64, triangulate, DelaunayOptions};
use mesher::Point;
use std::time::Duration;

fn uniform(n: usize, seed: u64) -> Vec<Point> {
    let mut r = SplitMix64::new(seed);
    let mut u = || (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
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
    if let Ok(path) = std::env::var("MESHER_BENCH_SURFACE") {
        match mesher::io::read_surface(std::path::Path::new(&path)) {
            Ok(s) => {
                let pts = s.surface.vertices;
                g.throughput(Throughput::Elements(pts.len() as u64));
                g.bench_with_input(BenchmarkId::new("surface", &path), &pts, |b, pts| {
                    b.iter(|| {
                        triangulate(pts, &DelaunayOptions::default()).map(|t| t.mesh.num_slots())
                    })
                });
            }
            Err(e) => eprintln!("MESHER_BENCH_SURFACE: {e}"),
        }
    }
    g.finish();
}

criterion_group!(benches, bench_uniform);
criterion_main!(benches);
