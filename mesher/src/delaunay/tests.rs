//! Kernel tests: validity, empty spheres, hull, degeneracies.

use super::*;
use crate::geom::predicates::{orient3d, Orientation};
use crate::tetmesh::TetId;
use proptest::prelude::*;

fn rand_points(n: usize, seed: u64) -> Vec<Point> {
    let mut r = sort::SplitMix64::new(seed);
    let mut u = || r.unit();
    (0..n).map(|_| Point::new(u(), u(), u())).collect()
}

fn grid(n: usize) -> Vec<Point> {
    let mut v = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                v.push(Point::new(i as f64, j as f64, k as f64));
            }
        }
    }
    v
}

fn tet_volume(p: [Point; 4]) -> f64 {
    (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) / 6.0
}

/// Checks validity, Delaunay, that every input point is a vertex at its coordinates,
/// that every hull face supports all points, and that the tets fill the hull volume.
pub(crate) fn check_triangulation(points: &[Point], tr: &Triangulation) {
    let m = &tr.mesh;
    m.validate(true).expect("valid Delaunay mesh");
    for (i, p) in points.iter().enumerate() {
        assert_eq!(m.point(tr.vertex_of_input[i]), *p, "input point {i}");
    }
    let mut hull_volume = 0.0;
    let mut tet_sum = 0.0;
    for t in m.tets() {
        let v = m.tet(t);
        if m.is_ghost(t) {
            let (a, b, c) = (m.point(v[0]), m.point(v[1]), m.point(v[2]));
            for q in points {
                assert_ne!(orient3d(a, b, c, *q), Orientation::Positive, "hull face");
            }
            // The hull face (a, b, c) is oriented outward: divergence theorem.
            hull_volume += a.dot(b.cross(c)) / 6.0;
        } else {
            tet_sum += tet_volume(m.tet_points(t));
        }
    }
    let scale = tet_sum.abs().max(1e-300);
    assert!(
        ((hull_volume - tet_sum) / scale).abs() < 1e-9,
        "hull {hull_volume} vs tets {tet_sum}"
    );
}

#[test]
fn random_points() {
    let pts = rand_points(3000, 1);
    let tr = triangulate(&pts, &DelaunayOptions::default()).unwrap();
    check_triangulation(&pts, &tr);
    assert_eq!(tr.duplicates, 0);
}

#[test]
fn all_orders_agree_on_tet_count() {
    let pts = rand_points(500, 2);
    let counts: Vec<usize> = [
        InsertionOrder::Brio,
        InsertionOrder::Hilbert,
        InsertionOrder::Input,
    ]
    .iter()
    .map(|&order| {
        let tr = triangulate(&pts, &DelaunayOptions { order, seed: 3 }).unwrap();
        check_triangulation(&pts, &tr);
        tr.mesh.num_finite_tets()
    })
    .collect();
    assert!(counts.windows(2).all(|w| w[0] == w[1]), "{counts:?}");
}

#[test]
fn cubic_grid_cospherical() {
    for n in [2, 3, 6] {
        let pts = grid(n);
        let tr = triangulate(&pts, &DelaunayOptions::default()).unwrap();
        check_triangulation(&pts, &tr);
        let vol: f64 = tr
            .mesh
            .finite_tets()
            .map(|t| tet_volume(tr.mesh.tet_points(t)))
            .sum();
        let side = (n - 1) as f64;
        assert!((vol - side * side * side).abs() < 1e-9);
    }
}

#[test]
fn grid_in_input_order_and_hilbert() {
    let pts = grid(5);
    for order in [InsertionOrder::Input, InsertionOrder::Hilbert] {
        let tr = triangulate(&pts, &DelaunayOptions { order, seed: 1 }).unwrap();
        check_triangulation(&pts, &tr);
    }
}

#[test]
fn points_on_a_sphere() {
    // Many cospherical points plus the centre.
    let mut pts = Vec::new();
    for i in 0..12 {
        for j in 1..12 {
            let (t, f) = (i as f64 * 0.52, j as f64 * 0.26);
            pts.push(Point::new(f.sin() * t.cos(), f.sin() * t.sin(), f.cos()));
        }
    }
    pts.push(Point::new(0.0, 0.0, 1.0));
    pts.push(Point::new(0.0, 0.0, -1.0));
    pts.push(Point::ZERO);
    let tr = triangulate(&pts, &DelaunayOptions::default()).unwrap();
    check_triangulation(&pts, &tr);
}

#[test]
fn duplicates_are_merged() {
    let mut pts = rand_points(200, 4);
    pts.extend_from_within(0..50);
    let tr = triangulate(&pts, &DelaunayOptions::default()).unwrap();
    check_triangulation(&pts, &tr);
    assert_eq!(tr.duplicates, 50);
    assert_eq!(tr.mesh.num_vertices(), 200);
}

#[test]
fn degenerate_inputs_are_errors() {
    let p = |x: f64, y: f64, z: f64| Point::new(x, y, z);
    let cases = [
        vec![],
        vec![p(0.0, 0.0, 0.0); 5],
        vec![p(0.0, 0.0, 0.0), p(1.0, 1.0, 1.0), p(2.0, 2.0, 2.0)],
        vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(1.0, 1.0, 0.0),
        ],
    ];
    for c in cases {
        assert!(matches!(
            triangulate(&c, &DelaunayOptions::default()),
            Err(DelaunayError::Degenerate { .. })
        ));
    }
    let nan = vec![p(0.0, 0.0, 0.0), p(f64::NAN, 0.0, 0.0)];
    assert!(matches!(
        triangulate(&nan, &DelaunayOptions::default()),
        Err(DelaunayError::NonFinite { index: 1, .. })
    ));
}

#[test]
fn coplanar_subsets_and_points_on_hull_faces() {
    // A square grid in a plane plus two apexes: many points on hull faces and edges.
    let mut pts = Vec::new();
    for i in 0..7 {
        for j in 0..7 {
            pts.push(Point::new(i as f64, j as f64, 0.0));
        }
    }
    pts.push(Point::new(3.0, 3.0, 5.0));
    pts.push(Point::new(1.0, 2.0, -4.0));
    for order in [InsertionOrder::Input, InsertionOrder::Brio] {
        let tr = triangulate(&pts, &DelaunayOptions { order, seed: 9 }).unwrap();
        check_triangulation(&pts, &tr);
    }
}

#[test]
fn box_mesh_is_valid_and_accepts_points() {
    let mut m = box_mesh(Point::splat(-1.0), Point::splat(2.0)).unwrap();
    m.validate(true).unwrap();
    assert!((5..=6).contains(&m.num_finite_tets()));
    let corner = |i: usize| m.point(crate::tetmesh::VertexId(i as u32));
    assert_eq!(corner(0), Point::splat(-1.0));
    assert_eq!(corner(7), Point::splat(2.0));
    assert_eq!(corner(1), Point::new(2.0, -1.0, -1.0));
    let mut k = Kernel::new();
    k.set_hint(TetId(0));
    for p in rand_points(500, 5) {
        k.insert(&mut m, p).unwrap();
    }
    for p in grid(4) {
        k.insert(&mut m, p * 0.25).unwrap();
    }
    m.validate(true).unwrap();
    let vol: f64 = m.finite_tets().map(|t| tet_volume(m.tet_points(t))).sum();
    assert!((vol - 27.0).abs() < 1e-9);
}

fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        (-4i32..4).prop_map(|v| v as f64),
        (-1.0f64..1.0),
        (-4i32..4).prop_map(|v| v as f64 * 0.5),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn prop_random_sets_with_degeneracies(
        raw in prop::collection::vec((coord(), coord(), coord()), 4..60),
        dup in 0usize..10,
        seed in 0u64..1000,
        order in prop_oneof![Just(InsertionOrder::Brio), Just(InsertionOrder::Input)],
    ) {
        let mut pts: Vec<Point> = raw.iter().map(|&(x, y, z)| Point::new(x, y, z)).collect();
        let k = dup.min(pts.len());
        pts.extend_from_within(0..k);
        match triangulate(&pts, &DelaunayOptions { order, seed }) {
            Ok(tr) => check_triangulation(&pts, &tr),
            Err(DelaunayError::Degenerate { .. }) => {}
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn prop_cospherical_subsets(
        n in 4usize..40,
        seed in 0u64..1000,
    ) {
        // Points on a sphere of radius 5 with integer coordinates (Pythagorean
        // quadruples) plus random interior points: many exact cospherical quintuples.
        let sphere: Vec<Point> = [
            (5, 0, 0), (-5, 0, 0), (0, 5, 0), (0, -5, 0), (0, 0, 5), (0, 0, -5),
            (3, 4, 0), (-3, 4, 0), (3, -4, 0), (-3, -4, 0), (4, 0, 3), (4, 0, -3),
            (-4, 0, 3), (0, 3, 4), (0, -3, 4), (0, 4, -3), (3, 0, -4), (-4, 3, 0),
        ].iter().map(|&(x, y, z)| Point::new(x as f64, y as f64, z as f64)).collect();
        let mut pts: Vec<Point> = sphere.iter().cycle().skip(seed as usize % 18).take(n.min(18)).copied().collect();
        pts.extend(rand_points(n / 3, seed).into_iter().map(|p| p * 4.0 - Point::splat(2.0)));
        if let Ok(tr) = triangulate(&pts, &DelaunayOptions { order: InsertionOrder::Brio, seed }) {
            check_triangulation(&pts, &tr);
        }
    }
}

#[test]
fn huge_cavity_uses_the_map_pairing() {
    // 200 points on a sphere then its centre: the centre's cavity holds every tet.
    let mut pts = Vec::new();
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for i in 0..200 {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / 200.0;
        let r = (1.0 - z * z).sqrt();
        let t = golden * i as f64;
        pts.push(Point::new(r * t.cos(), r * t.sin(), z));
    }
    pts.push(Point::ZERO);
    let tr = triangulate(
        &pts,
        &DelaunayOptions {
            order: InsertionOrder::Input,
            seed: 0,
        },
    )
    .unwrap();
    check_triangulation(&pts, &tr);
    assert!(tr.stats.large_cavities >= 1);
}

#[test]
fn static_filter_bounds_with_points_outside() {
    // Bounds declared for the unit cube; some points fall outside and take the
    // generic filter: the result must still be a valid Delaunay mesh.
    let mut m = box_mesh(Point::splat(-0.5), Point::splat(1.5)).unwrap();
    let mut k = Kernel::new();
    k.set_bounds(Point::splat(-0.5), Point::splat(1.5));
    for p in rand_points(2000, 11) {
        k.insert(&mut m, p).unwrap();
    }
    for p in rand_points(200, 12) {
        k.insert(&mut m, p * 4.0 - Point::splat(1.5)).unwrap();
    }
    for p in rand_points(500, 13) {
        k.insert(&mut m, p).unwrap();
    }
    m.validate(true).unwrap();
}
