//! Target quality `Q_t` (paper §8): known faces, agreement with a brute-force search,
//! speed.

use mesher::quality::*;
use mesher::Point;

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y, 0.0)
}

/// Brute force: a coarse grid over the apex, then a shrinking local grid.
fn brute_force(a: Point, b: Point, c: Point) -> f64 {
    let mut best = (f64::INFINITY, Point::ZERO);
    let n = 40;
    for i in 0..=n {
        for j in 0..=n {
            for k in 1..=n {
                let t = Point::new(i as f64, j as f64, k as f64) / n as f64;
                let x = Point::new(-1.0 + 3.0 * t.x, -1.0 + 4.0 * t.y, 3.0 * t.z);
                best = best.min_by_q(q_k(&[a, b, c, x]), x);
            }
        }
    }
    let mut h = 0.1;
    while h > 1e-9 {
        let centre = best.1;
        for i in -3..=3 {
            for j in -3..=3 {
                for k in -3..=3 {
                    let x = centre + Point::new(i as f64, j as f64, k as f64) * h;
                    best = best.min_by_q(q_k(&[a, b, c, x]), x);
                }
            }
        }
        if best.1 == centre {
            h *= 0.5;
        }
    }
    best.0
}

trait MinByQ {
    fn min_by_q(self, q: f64, x: Point) -> Self;
}

impl MinByQ for (f64, Point) {
    fn min_by_q(self, q: f64, x: Point) -> Self {
        if q < self.0 {
            (q, x)
        } else {
            self
        }
    }
}

#[test]
fn equilateral_face_gives_one() {
    let q = face_best_q_k(p(0.0, 0.0), p(1.0, 0.0), p(0.5, 0.75f64.sqrt()));
    assert!((q - 1.0).abs() < 1e-6, "{q}");
}

#[test]
fn right_isoceles_face() {
    let (a, b, c) = (p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0));
    let q = face_best_q_k(a, b, c);
    // Strictly worse than the regular tet, far from needle values, and no worse than
    // the apex above the circumcentre at the height of the regular tet.
    assert!(q > 1.01 && q < 1.5, "{q}");
    let naive = q_k(&[a, b, c, Point::new(0.5, 0.5, 1.0)]);
    assert!(q <= naive, "{q} {naive}");
    let bf = brute_force(a, b, c);
    assert!(q <= bf * (1.0 + 1e-7), "{q} {bf}");
    // The grid search stalls on the h_max ridges, so it only bounds from above.
    assert!((q - bf).abs() < 1e-4 * bf, "{q} {bf}");
}

#[test]
fn needle_face_is_large() {
    let q = face_best_q_k(p(0.0, 0.0), p(1.0, 0.0), p(0.5, 0.01));
    assert!(q > 30.0, "{q}");
    let bf = brute_force(p(0.0, 0.0), p(1.0, 0.0), p(0.5, 0.01));
    assert!(q <= bf * (1.0 + 1e-7), "{q} {bf}");
}

#[test]
fn agrees_with_brute_force_on_assorted_faces() {
    for c in [
        p(0.3, 0.2),
        p(0.9, 0.5),
        p(-0.4, 0.7),
        p(0.05, 0.02),
        p(0.5, 2.5),
    ] {
        let (a, b) = (p(0.0, 0.0), p(1.0, 0.0));
        let q = face_best_q_k(a, b, c);
        let bf = brute_force(a, b, c);
        assert!(q <= bf * (1.0 + 1e-7), "{c}: {q} {bf}");
        assert!((q - bf).abs() < 1e-4 * bf, "{c}: {q} {bf}");
    }
}

#[test]
fn target_is_the_worst_face() {
    let v = vec![
        p(0.0, 0.0),
        p(1.0, 0.0),
        p(0.5, 0.75f64.sqrt()),
        p(0.5, -0.05),
    ];
    let t = target_quality(&v, &[[0, 1, 2], [1, 0, 3]]);
    assert_eq!(t.worst_face, Some(1));
    assert_eq!(t.q_t, face_best_q_k(v[1], v[0], v[3]));
    let json = serde_json::to_string(&t).unwrap();
    let back: TargetQuality = serde_json::from_str(&json).unwrap();
    assert_eq!(back, t);
}

#[test]
fn fast_solver_matches_the_precise_one_on_a_grid_of_faces() {
    use mesher::quality::target::face_best_q_k_precise;
    let (a, b) = (p(0.0, 0.0), p(1.0, 0.0));
    for i in 0..=40 {
        for j in 0..=20 {
            // c over [-1, 2] x (0, 2], denser near the base (caps, needles).
            let c = p(
                -1.0 + 3.0 * i as f64 / 40.0,
                2.0 * (j as f64 / 20.0).powi(3) + 1e-4,
            );
            let (fast, precise) = (face_best_q_k(a, b, c), face_best_q_k_precise(a, b, c));
            let rel = (fast - precise) / precise;
            // Never worse than the precise search; better only where it stalled.
            assert!(rel <= 1e-9 && rel.abs() <= 1e-4, "{c}: {fast} {precise}");
        }
    }
}

/// A 300k-triangle surface: the two sides of a perturbed triangulated grid.
#[test]
#[ignore = "timing; run with --ignored --nocapture"]
fn speed_300k_triangles() {
    let n = 388usize; // 2 * 388^2 ~ 301k triangles
    let mut v = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let wobble = ((i * 7 + j * 13) % 17) as f64 / 17.0 - 0.5;
            let x = i as f64 + 0.5 * j as f64 + 0.1 * wobble;
            let y = j as f64 * 0.75f64.sqrt() + 0.1 * wobble;
            v.push(Point::new(x, y, 0.05 * wobble));
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i, j + 1)]);
            tris.push([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let t0 = std::time::Instant::now();
    let t = target_quality(&v, &tris);
    println!(
        "{} triangles: {:?}, Q_t = {}",
        tris.len(),
        t0.elapsed(),
        t.q_t
    );
}
