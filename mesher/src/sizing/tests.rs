use super::*;
use crate::boundary::{boundary_mesh, BoundaryOptions};
use crate::delaunay::{triangulate, DelaunayOptions};
use crate::surface::generate::cube;

/// A background on a jittered grid of the unit cube with `h = h(p)` at the vertices.
fn grid_background(h: impl Fn(Point) -> f64) -> Background {
    let n = 6;
    let mut pts = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            for k in 0..=n {
                let jit = ((i * 7 + j * 13 + k * 29) % 11) as f64 * 1e-3;
                pts.push(Point::new(i as f64, j as f64, k as f64) / n as f64 + jit);
            }
        }
    }
    let tr = triangulate(&pts, &DelaunayOptions::default()).unwrap();
    let hs = tr.mesh.points().iter().map(|&p| h(p)).collect();
    Background::new(tr.mesh, hs).unwrap()
}

#[test]
fn constant_size_length_is_d_over_h() {
    let f = ConstantSize(0.5);
    let (a, b) = (Point::ZERO, Point::new(1.0, 1.0, 0.0));
    let mut hint = 0;
    for mode in [LengthMode::EndPoints, LengthMode::Piecewise] {
        let l = edge_length(&f, mode, a, b, 0.5, 0.5, &mut hint);
        assert!((l - 2f64.sqrt() / 0.5).abs() < 1e-12);
    }
    assert!(constant(0.0).is_err() && constant(f64::NAN).is_err());
}

#[test]
fn linear_field_is_interpolated_exactly() {
    let bg = grid_background(|p| 0.1 + 0.3 * p.x + 0.2 * p.z);
    let mut hint = 0;
    for p in [
        Point::new(0.5, 0.5, 0.5),
        Point::new(0.11, 0.93, 0.42),
        Point::new(0.8, 0.2, 0.05),
    ] {
        let h = bg.size(p, &mut hint);
        assert!((h - (0.1 + 0.3 * p.x + 0.2 * p.z)).abs() < 1e-12, "{p} {h}");
    }
}

#[test]
fn piecewise_length_matches_the_closed_form_for_a_linear_field() {
    // h linear along the edge: the paper's closed form d ln(hb/ha) / (hb - ha).
    let h = |p: Point| 0.05 + 0.5 * p.x;
    let bg = grid_background(h);
    let (a, b) = (Point::new(0.1, 0.3, 0.4), Point::new(0.95, 0.6, 0.5));
    let (ha, hb) = (h(a), h(b));
    let closed = a.distance(b) * (hb / ha).ln() / (hb - ha);
    let mut hint = 0;
    let pw = edge_length(&bg, LengthMode::Piecewise, a, b, ha, hb, &mut hint);
    let ep = edge_length(&bg, LengthMode::EndPoints, a, b, ha, hb, &mut hint);
    // Short pieces fall in the near-equal band of the length formula (error ~1e-4).
    assert!(((pw - closed) / closed).abs() < 1e-3, "{pw} {closed}");
    assert!(((ep - closed) / closed).abs() < 1e-12, "{ep} {closed}");
}

#[test]
fn piecewise_length_follows_a_nonlinear_field() {
    // h = 0.02 + x^2 sampled at the vertices: along x the piecewise length is the sum
    // over the grid cells, far from the end-point form (which sees only h(a), h(b)).
    let bg = grid_background(|p| 0.02 + p.x * p.x);
    let (a, b) = (Point::new(0.02, 0.5, 0.5), Point::new(0.98, 0.5, 0.5));
    let mut hint = 0;
    let (ha, hb) = (bg.size(a, &mut hint), bg.size(b, &mut hint));
    let pw = bg.length_piecewise(a, b, ha, hb, &mut hint);
    // Reference: many pieces, each with the interpolated sizes at its ends.
    let n = 4000;
    let mut reference = 0.0;
    for k in 0..n {
        let (p, q) = (
            a + (b - a) * (k as f64 / n as f64),
            a + (b - a) * ((k + 1) as f64 / n as f64),
        );
        let (hp, hq) = (bg.size(p, &mut hint), bg.size(q, &mut hint));
        reference += normalized_length(p.distance(q), hp, hq);
    }
    let ep = normalized_length(a.distance(b), ha, hb);
    assert!(
        ((pw - reference) / reference).abs() < 1e-3,
        "{pw} {reference}"
    );
    assert!(
        ((ep - reference) / reference).abs() > 0.1,
        "{ep} {reference}"
    );
}

#[test]
fn control_space_on_the_boundary_mesh() {
    let s = cube(3);
    let (bm, _) = boundary_mesh(&s, &BoundaryOptions::default()).unwrap();
    let bg = Background::from_boundary(&bm, &s).unwrap();
    // Surface vertex sizes are (l_min + l_max) / 2 of its input edges.
    for (i, v) in bm.surface_vertex.iter().enumerate() {
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for t in &s.triangles {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                if a == i || b == i {
                    let d = s.vertices[a].distance(s.vertices[b]);
                    lo = lo.min(d);
                    hi = hi.max(d);
                }
            }
        }
        assert!((bg.vertex_sizes()[v.index()] - 0.5 * (lo + hi)).abs() < 1e-15);
    }
    assert!(bg.vertex_sizes().iter().all(|h| *h > 0.0 && h.is_finite()));
    // Inside, the size is between the extremes of the surface sizes.
    let mut hint = 0;
    let h = bg.size(Point::splat(0.5), &mut hint);
    let (lo, hi) = bg
        .vertex_sizes()
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(h >= lo && h <= hi, "{h}");
}

#[test]
fn bad_sizes_are_refused() {
    let tr = triangulate(
        &[Point::ZERO, Point::X, Point::Y, Point::Z],
        &DelaunayOptions::default(),
    )
    .unwrap();
    assert!(matches!(
        Background::new(tr.mesh.clone(), vec![1.0; 3]),
        Err(SizingError::Count { .. })
    ));
    assert!(matches!(
        Background::new(tr.mesh, vec![1.0, 0.0, 1.0, 1.0]),
        Err(SizingError::BadSize { vertex: 1, .. })
    ));
}
