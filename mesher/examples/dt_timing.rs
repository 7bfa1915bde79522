use mesher::delaunay::{sort::SplitMix64, triangulate, DelaunayOptions};
use mesher::Point;
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let mut r = SplitMix64::new(42);
    let mut u = || (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let pts: Vec<Point> = (0..n).map(|_| Point::new(u(), u(), u())).collect();
    let t0 = std::time::Instant::now();
    let tr = triangulate(&pts, &DelaunayOptions::default()).unwrap();
    let dt = t0.elapsed().as_secs_f64();
    println!(
        "n={n} tets={} time={dt:.3}s  {:?}",
        tr.mesh.num_finite_tets(),
        tr.stats
    );
    if std::env::args().any(|a| a == "--validate") {
        let t1 = std::time::Instant::now();
        tr.mesh.validate(true).unwrap();
        println!("validate {:.2}s", t1.elapsed().as_secs_f64());
    }
}
