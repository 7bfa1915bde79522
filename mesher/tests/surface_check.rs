//! Hand-built surfaces for every defect kind of `Surface::check`, plus an ignored
//! timing test on a large icosphere.

use mesher::{Point, Surface};

fn p(x: f64, y: f64, z: f64) -> Point {
    Point::new(x, y, z)
}

/// Unit corner tetrahedron, outward oriented, translated by `o`.
fn tet(o: Point) -> Surface {
    Surface {
        vertices: vec![
            o,
            o + p(1.0, 0.0, 0.0),
            o + p(0.0, 1.0, 0.0),
            o + p(0.0, 0.0, 1.0),
        ],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    }
}

/// Axis-aligned cube `[lo, lo + size]^3` from 12 triangles, outward unless `inward`.
fn cube(lo: Point, size: f64, inward: bool) -> Surface {
    let vertices = (0..8)
        .map(|i| lo + size * p((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
        .collect();
    let mut triangles = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    if inward {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    Surface {
        vertices,
        triangles,
    }
}

/// Disjoint union of surfaces.
fn union(parts: &[Surface]) -> Surface {
    let mut s = Surface::default();
    for part in parts {
        let off = s.vertices.len() as u32;
        s.vertices.extend_from_slice(&part.vertices);
        s.triangles
            .extend(part.triangles.iter().map(|t| t.map(|v| v + off)));
    }
    s
}

/// Torus with `n` x `m` quads split in two, outward oriented.
fn torus(n: u32, m: u32) -> Surface {
    let (big, small) = (2.0, 0.7);
    let mut s = Surface::default();
    for i in 0..n {
        let u = std::f64::consts::TAU * i as f64 / n as f64;
        for j in 0..m {
            let v = std::f64::consts::TAU * j as f64 / m as f64;
            let r = big + small * v.cos();
            s.vertices
                .push(p(r * u.cos(), r * u.sin(), small * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            s.triangles.push([a, b, c]);
            s.triangles.push([a, c, d]);
        }
    }
    s
}

/// Icosphere: the icosahedron subdivided `level` times (20 * 4^level faces), outward.
pub fn icosphere(level: u32) -> Surface {
    mesher::surface::generate::icosphere(level)
}

#[test]
fn tetrahedron_is_clean() {
    let r = tet(Point::ZERO).check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells.len(), 1);
    let s = &r.shells[0];
    assert!(s.closed);
    assert_eq!(s.genus, Some(0));
    assert!((s.signed_volume - 1.0 / 6.0).abs() < 1e-12);
    assert_eq!(s.depth, Some(0));
    assert!(r.warnings.is_empty(), "{r}");
}

#[test]
fn cube_is_clean() {
    let r = cube(p(-0.5, 0.25, 3.0), 2.0, false).check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells[0].genus, Some(0));
    assert!((r.shells[0].signed_volume - 8.0).abs() < 1e-9);
    assert_eq!(r.num_bodies(), 1);
    assert!(r.warnings.is_empty());
}

#[test]
fn inside_out_cube_warns_but_is_clean() {
    let r = cube(Point::ZERO, 1.0, true).check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.warnings.len(), 1, "{r}");
}

#[test]
fn cube_with_a_missing_face_is_open() {
    let mut s = cube(Point::ZERO, 1.0, false);
    s.triangles.remove(3);
    let r = s.check();
    assert!(!r.is_clean());
    assert_eq!(r.open_edges.len(), 3, "{r}");
    assert!(!r.shells[0].closed);
    assert_eq!(r.shells[0].genus, None);
    assert!(r.self_intersections.count == 0);
    assert!(r.to_string().contains("open edges: 3"));
}

#[test]
fn tets_sharing_an_edge_are_non_manifold() {
    let a = tet(Point::ZERO);
    // The half-turn about the x axis keeps the orientation and the edge 0-1.
    let mut s = a.clone();
    s.vertices.push(p(0.0, -1.0, 0.0));
    s.vertices.push(p(0.0, 0.0, -1.0));
    for t in &a.triangles {
        s.triangles.push(t.map(|v| match v {
            2 => 4,
            3 => 5,
            v => v,
        }));
    }
    let r = s.check();
    assert_eq!(r.non_manifold_edges.len(), 1, "{r}");
    assert_eq!(r.non_manifold_edges[0].vertices, [0, 1]);
    assert_eq!(r.non_manifold_edges[0].faces.len(), 4);
    assert!(r.pinched_vertices.is_empty(), "{r}");
    assert_eq!(r.self_intersections.count, 0, "{r}");
    assert!(r.open_edges.is_empty() && r.inconsistent_edges.is_empty());
}

#[test]
fn tets_sharing_a_vertex_pinch_it() {
    let a = tet(Point::ZERO);
    let mut s = a.clone();
    // Point reflection through the origin flips orientation: reverse the faces.
    for k in 1..4 {
        s.vertices.push(-a.vertices[k]);
    }
    for t in &a.triangles {
        let m = t.map(|v| if v == 0 { 0 } else { v + 3 });
        s.triangles.push([m[0], m[2], m[1]]);
    }
    let r = s.check();
    assert_eq!(r.pinched_vertices.len(), 1, "{r}");
    assert_eq!(r.pinched_vertices[0].vertex.vertex, 0);
    assert_eq!(r.pinched_vertices[0].fans, 2);
    assert_eq!(r.self_intersections.count, 0, "{r}");
    assert!(r.non_manifold_edges.is_empty() && r.open_edges.is_empty());
    assert_eq!(r.shells.len(), 2);
}

#[test]
fn flipped_triangle_is_inconsistent() {
    let mut s = cube(Point::ZERO, 1.0, false);
    s.triangles[5].swap(0, 1);
    let r = s.check();
    assert_eq!(r.inconsistent_edges.len(), 3, "{r}");
    assert!(r.open_edges.is_empty());
    assert!(!r.shells[0].closed);
    // Still a defect, but the boundary mesh mends it: the report says so.
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("1 face turned to agree")),
        "{r}"
    );
}

#[test]
fn duplicate_face_is_reported() {
    let mut s = tet(Point::ZERO);
    s.triangles.push([2, 1, 0]);
    let r = s.check();
    assert_eq!(r.duplicate_faces.len(), 1, "{r}");
    let ids: Vec<u32> = r.duplicate_faces[0].faces.iter().map(|f| f.face).collect();
    assert_eq!(ids, vec![0, 4]);
    assert_eq!(
        r.self_intersections.count, 0,
        "duplicates are not intersections"
    );
}

#[test]
fn zero_area_face_is_reported() {
    let mut s = cube(Point::ZERO, 1.0, false);
    // Split face [0, 2, 3] at the midpoint m of its edge 0-3 into [0, 2, m] and
    // [m, 2, 3], and close the crack with the zero-area face [0, m, 3].
    s.vertices.push(p(0.5, 0.5, 0.0));
    let m = 8;
    s.triangles[0] = [0, 2, m];
    s.triangles.push([m, 2, 3]);
    s.triangles.push([0, m, 3]);
    let r = s.check();
    assert_eq!(r.zero_area_faces.len(), 1, "{r}");
    assert_eq!(r.zero_area_faces[0].face, 13);
    // The sliver hides a T-junction: faces 0 and 12 touch face 1 along segments of its
    // edge 0-3, beyond their shared vertices, which is a real contact.
    assert_eq!(r.self_intersections.count, 2, "{r}");
    assert!(r.shells[0].closed);
}

#[test]
fn nan_and_bad_indices_never_panic() {
    let mut s = tet(Point::ZERO);
    s.vertices[3] = p(f64::NAN, 0.0, f64::INFINITY);
    s.triangles.push([0, 1, 99]);
    s.triangles.push([1, 1, 2]);
    let r = s.check();
    assert_eq!(r.non_finite_vertices.len(), 1);
    assert_eq!(r.non_finite_vertices[0].vertex, 3);
    assert_eq!(r.out_of_range_faces.len(), 1);
    assert_eq!(r.degenerate_faces.len(), 1);
    assert!(!r.is_clean());
    let text = r.to_string();
    assert!(text.contains("non-finite vertices: 1"), "{text}");
    assert!(serde_json::to_string(&r).is_ok());
    assert!(!s.faces_intersect(0, 4));
    assert!(!s.faces_intersect(0, 1000));
}

#[test]
fn empty_surface() {
    let r = Surface::default().check();
    assert!(r.is_clean());
    assert!(r.shells.is_empty());
}

#[test]
fn interpenetrating_tets_intersect() {
    let s = union(&[tet(Point::ZERO), tet(p(0.25, 0.25, 0.25))]);
    let r = s.check();
    assert!(r.self_intersections.count > 0, "{r}");
    let first = &r.self_intersections.pairs[0];
    assert!(first.a.face < 4 && first.b.face >= 4);
    assert!(r.to_string().contains("self-intersecting face pairs"));
}

#[test]
fn triangle_through_a_tet() {
    let mut s = tet(Point::ZERO);
    s.vertices
        .extend([p(0.2, 0.2, -1.0), p(0.25, 0.2, 2.0), p(-1.0, -1.0, 0.5)]);
    s.triangles.push([4, 5, 6]);
    let r = s.check();
    assert!(r.self_intersections.count >= 2, "{r}");
    assert!(r.self_intersections.pairs.iter().all(|q| q.b.face == 4));
    assert!(s.faces_intersect(0, 4) && s.faces_intersect(4, 0));
}

#[test]
fn coplanar_overlapping_triangles() {
    let s = Surface {
        vertices: vec![
            p(0.0, 0.0, 0.0),
            p(2.0, 0.0, 0.0),
            p(0.0, 2.0, 0.0),
            p(0.5, 0.5, 0.0),
            p(3.0, 0.5, 0.0),
            p(0.5, 3.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [3, 4, 5]],
    };
    let r = s.check();
    assert_eq!(r.self_intersections.count, 1, "{r}");
    // Folded neighbours: coplanar on the same side of their shared edge.
    let f = Surface {
        vertices: vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.3, 0.3, 0.0),
        ],
        triangles: vec![[0, 1, 2], [1, 0, 3]],
    };
    assert_eq!(f.check().self_intersections.count, 1);
}

#[test]
fn nested_cubes_form_a_domain_with_a_cavity() {
    let s = union(&[
        cube(Point::ZERO, 3.0, false),
        cube(p(1.0, 1.0, 1.0), 1.0, true),
    ]);
    let r = s.check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells.len(), 2);
    assert_eq!(r.shells[0].depth, Some(0));
    assert_eq!(r.shells[1].depth, Some(1));
    assert_eq!(r.shells[1].parent, Some(0));
    assert!(r.warnings.is_empty(), "{r}");
    assert_eq!(r.num_bodies(), 1);
    assert!(r.to_string().contains("inside shell 0"));
    // Same orientation for the inner cube: still clean, but warned.
    let s2 = union(&[
        cube(Point::ZERO, 3.0, false),
        cube(p(1.0, 1.0, 1.0), 1.0, false),
    ]);
    let r2 = s2.check();
    assert!(r2.is_clean());
    assert_eq!(r2.warnings.len(), 1, "{r2}");
}

#[test]
fn three_level_nesting() {
    let s = union(&[
        cube(p(2.0, 2.0, 2.0), 1.0, false),
        cube(Point::ZERO, 5.0, false),
        cube(p(1.0, 1.0, 1.0), 3.0, true),
    ]);
    let r = s.check();
    assert!(r.is_clean(), "{r}");
    let d: Vec<_> = r.shells.iter().map(|s| (s.depth, s.parent)).collect();
    assert_eq!(
        d,
        vec![(Some(2), Some(2)), (Some(0), None), (Some(1), Some(1))]
    );
    assert!(r.warnings.is_empty(), "{r}");
}

#[test]
fn disjoint_cubes_are_two_bodies() {
    let s = union(&[
        cube(Point::ZERO, 1.0, false),
        cube(p(2.0, 0.0, 0.0), 1.0, false),
    ]);
    let r = s.check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells.len(), 2);
    assert_eq!(r.num_bodies(), 2);
    assert!(r
        .shells
        .iter()
        .all(|s| s.parent.is_none() && s.depth == Some(0)));
}

#[test]
fn touching_cubes_intersect() {
    // Sharing a face geometrically but not by index: the faces overlap.
    let s = union(&[
        cube(Point::ZERO, 1.0, false),
        cube(p(1.0, 0.0, 0.0), 1.0, false),
    ]);
    let r = s.check();
    assert!(r.self_intersections.count > 0, "{r}");
}

#[test]
fn torus_has_genus_one() {
    let r = torus(24, 12).check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells.len(), 1);
    assert_eq!(r.shells[0].euler_characteristic, 0);
    assert_eq!(r.shells[0].genus, Some(1));
    assert!(r.shells[0].signed_volume > 0.0);
}

#[test]
fn icosphere_is_clean() {
    let s = icosphere(3);
    let r = s.check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells[0].genus, Some(0));
    assert!(r.shells[0].signed_volume > 0.0);
}

#[test]
fn report_lists_are_capped() {
    let mut s = icosphere(2);
    s.triangles.truncate(100);
    let r = s.check();
    let text = r.to_string();
    assert!(text.contains("... and"), "{text}");
    assert!(text.lines().count() < 200);
}

#[test]
#[ignore = "timing: run with --release -- --ignored --nocapture"]
fn timing_icosphere_327k() {
    let s = icosphere(7);
    let t = std::time::Instant::now();
    let r = s.check();
    let dt = t.elapsed();
    println!(
        "check of {} triangles: {:.3} s ({} candidate pairs)",
        s.triangles.len(),
        dt.as_secs_f64(),
        r.self_intersections.candidates
    );
    assert!(r.is_clean(), "{r}");
}

#[test]
fn many_bodies_side_by_side() {
    let parts: Vec<Surface> = (0..2000)
        .map(|i| tet(p((i % 50) as f64 * 2.0, (i / 50) as f64 * 2.0, 0.0)))
        .collect();
    let r = union(&parts).check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells.len(), 2000);
    assert_eq!(r.num_bodies(), 2000);
}

#[test]
fn box_in_box_in_torus_hole_is_not_nested() {
    // A cube in the hole of a torus: inside its bounding box but outside the solid.
    let s = union(&[torus(32, 16), cube(p(-0.3, -0.3, -0.3), 0.6, false)]);
    let r = s.check();
    assert!(r.is_clean(), "{r}");
    assert_eq!(r.shells[1].depth, Some(0));
    assert_eq!(r.num_bodies(), 2);
}

#[test]
fn deep_nesting_with_shared_planes_and_alternating_orientation() {
    // Five cubes nested around off-centre points; several share coordinate planes with
    // their container's vertices, so axis-aligned rays would hit edges.
    let parts: Vec<Surface> = (0..5)
        .map(|i| {
            let lo = i as f64 * 0.5;
            let size = 10.0 - i as f64 * 1.5;
            cube(p(lo, lo * 0.5, lo), size, i % 2 == 1)
        })
        .rev()
        .collect();
    let r = union(&parts).check();
    assert!(r.is_clean(), "{r}");
    // Shell k is parts[k], i.e. cube 4 - k.
    for (k, sh) in r.shells.iter().enumerate() {
        let level = 4 - k;
        assert_eq!(sh.depth, Some(level), "{r}");
        let parent = (level > 0).then(|| k + 1);
        assert_eq!(sh.parent, parent, "{r}");
    }
    assert!(r.warnings.is_empty(), "{r}");
}
