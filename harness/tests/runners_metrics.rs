//! Metrics on hand-made tets: the regular tet, a sliver, an inverted tet, a consistently
//! negative mesh (normalised), and the size field of NOTES.md §3.

use harness::metrics::{measure_input, measure_output, nearest_sizes, vertex_sizes};
use mesher::{Point, Surface, VolumeMesh};

fn regular() -> [Point; 4] {
    [
        Point::new(1.0, 1.0, 1.0),
        Point::new(1.0, -1.0, -1.0),
        Point::new(-1.0, -1.0, 1.0),
        Point::new(-1.0, 1.0, -1.0),
    ]
}

/// The boundary of tet (0,1,2,3), outward for a positive tet.
fn tet_surface(p: [Point; 4]) -> Surface {
    Surface {
        vertices: p.to_vec(),
        triangles: vec![[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]],
    }
}

fn mesh(p: &[Point], tets: Vec<[u32; 4]>) -> VolumeMesh {
    VolumeMesh {
        vertices: p.to_vec(),
        tets,
        ..VolumeMesh::default()
    }
}

#[test]
fn regular_tet_has_q_k_one_and_keeps_its_boundary() {
    let p = regular();
    assert!(mesher::quality::signed_volume(&p) > 0.0);
    let s = tet_surface(p);
    let input = measure_input(&s);
    assert!((input.q_t - 1.0).abs() < 1e-6, "q_t {}", input.q_t);
    assert_eq!(input.hard_face_fraction, 0.0);
    // Inside the tet, each face's best tet is the tet itself (apex: a surface vertex).
    let in_domain = input.q_t_domain.unwrap();
    assert!(
        (in_domain - 1.0).abs() < 1e-6,
        "q_t in the domain {in_domain}"
    );
    assert_eq!(input.hard_domain_fraction, Some(0.0));
    let m = measure_output(&input, &s, mesh(&p, vec![[0, 1, 2, 3]]), true).unwrap();
    assert!((m.quality.worst_q_k - 1.0).abs() < 1e-12);
    assert!((m.quality.min_dihedral - 70.528_779_365_509_3).abs() < 1e-9);
    assert_eq!(m.validity.inverted, 0);
    assert_eq!(m.validity.boundary_kept, Some(true));
    assert!((m.validity.volume_ratio.unwrap() - 1.0).abs() < 1e-12);
    assert!(!m.orientation_flipped);
    // Every edge has length 2*sqrt(2) = h at every vertex: normalised length 1.
    assert!((m.edge_lengths.mean - 1.0).abs() < 1e-12);
}

#[test]
fn sliver_is_bad_and_inverted_tet_is_flagged() {
    let p = regular();
    let sliver = [
        Point::new(1.0, 0.0, 0.0),
        Point::new(-1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.01),
        Point::new(0.0, -1.0, 0.01),
    ];
    let s = tet_surface(p);
    let input = measure_input(&s);
    let mut pts = p.to_vec();
    pts.extend(sliver);
    let sv = mesher::quality::signed_volume(&sliver);
    let sl = if sv > 0.0 { [4, 5, 6, 7] } else { [4, 5, 7, 6] };
    // Two positive tets (the regular one, the sliver) and the regular one inverted.
    let m = mesh(&pts, vec![[0, 1, 2, 3], sl, [0, 1, 3, 2]]);
    let out = measure_output(&input, &s, m, false).unwrap();
    assert!(!out.orientation_flipped);
    assert_eq!(out.validity.inverted, 1);
    assert_eq!(out.validity.boundary_kept, None);
    assert!(out.quality.worst_q_k > 50.0, "{}", out.quality.worst_q_k);
    assert!(
        out.quality.min_dihedral < 2.0,
        "{}",
        out.quality.min_dihedral
    );
    // The regular tet used twice: each of its faces is in two tets, none in three.
    assert_eq!(out.validity.non_manifold_faces, 0);
}

#[test]
fn consistently_negative_mesh_is_flipped() {
    let p = regular();
    let s = tet_surface(p);
    let input = measure_input(&s);
    let out = measure_output(&input, &s, mesh(&p, vec![[0, 1, 3, 2]]), true).unwrap();
    assert!(out.orientation_flipped);
    assert_eq!(out.validity.inverted, 0);
    assert!((out.validity.volume_ratio.unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(out.validity.boundary_kept, Some(true));
}

#[test]
fn face_in_three_tets_is_non_manifold() {
    let p = regular();
    let s = tet_surface(p);
    let input = measure_input(&s);
    let mut pts = p.to_vec();
    pts.push(Point::new(0.0, 0.0, 5.0));
    pts.push(Point::new(0.0, 0.0, -5.0));
    let m = mesh(&pts, vec![[0, 1, 2, 3], [0, 1, 2, 4], [0, 1, 2, 5]]);
    let out = measure_output(&input, &s, m, false).unwrap();
    assert_eq!(out.validity.non_manifold_faces, 1);
}

#[test]
fn out_of_range_tet_is_an_error_not_a_panic() {
    let s = tet_surface(regular());
    let input = measure_input(&s);
    assert!(measure_output(&input, &s, mesh(&regular(), vec![[0, 1, 2, 9]]), false).is_err());
}

#[test]
fn sizes_follow_notes_section_3() {
    // A right triangle fan: vertex 0 has edges 1 and 2, so h = 1.5 there.
    let s = Surface {
        vertices: vec![Point::ZERO, Point::X, Point::new(0.0, 2.0, 0.0)],
        triangles: vec![[0, 1, 2]],
    };
    let h = vertex_sizes(&s);
    let hyp = 5f64.sqrt();
    assert!((h[0] - 1.5).abs() < 1e-15);
    assert!((h[1] - 0.5 * (1.0 + hyp)).abs() < 1e-15);
    assert!((h[2] - 0.5 * (2.0 + hyp)).abs() < 1e-15);
    let q = [
        Point::new(0.1, 0.1, 0.0),
        Point::new(0.9, 0.0, 3.0),
        Point::new(-5.0, 9.0, 0.0),
    ];
    let n = nearest_sizes(&s, &h, &q);
    assert_eq!(n, vec![h[0], h[1], h[2]]);
}

#[test]
fn boundary_surface_drops_interior_faces_and_vertices() {
    let p = regular();
    // Split the regular tet at its centroid into 4 tets: the boundary is the 4 outer faces.
    let mut pts = p.to_vec();
    pts.push(Point::ZERO);
    let m = mesh(
        &pts,
        vec![[4, 1, 2, 3], [0, 4, 2, 3], [0, 1, 4, 3], [0, 1, 2, 4]],
    );
    let b = harness::metrics::boundary_surface(&m);
    assert_eq!(b.triangles.len(), 4);
    assert_eq!(b.vertices.len(), 4);
    assert!(b.check().is_clean());
}

#[test]
fn a_thin_slab_has_less_room_than_its_faces_alone() {
    // The unit cube of 4 x 4 squares per side, a hundredth thick: the faces alone allow
    // Q_K 41 (the side strips are needles), the big faces only ~8 inside the slab
    // where 1.2 alone.
    let mut s = mesher::surface::generate::cube(4);
    for v in &mut s.vertices {
        v.z *= 0.01;
    }
    let input = measure_input(&s);
    let in_domain = input.q_t_domain.unwrap();
    assert!(in_domain >= input.q_t, "{in_domain} < {}", input.q_t);
    // Every face: the 64 top and bottom ones are limited to Q_K > 3 now.
    let hard = input.hard_domain_fraction.unwrap();
    assert!(hard > input.hard_face_fraction + 0.3, "{hard}");
    // An open surface has no domain.
    s.triangles.pop();
    assert_eq!(measure_input(&s).q_t_domain, None);
}

/// The harness measures our output's edges in the size field `mesher mesh` itself
/// follows (the control space on T(S,F)): the band it reports is the mesher's own,
/// before and after the optimisation (which gives the vertices it moves their new size).
#[test]
fn band_of_our_mesh_is_the_meshers_own() {
    let s = mesher::surface::generate::torus(24, 12, 2.0, 0.6);
    let input = measure_input(&s);
    assert!(input.background.is_some());
    for optimize in [false, true] {
        let params = mesher::mesh::Params {
            optimize,
            ..mesher::mesh::Params::default()
        };
        let (meshed, _) = mesher::mesh::mesh(&s, &params).unwrap();
        let own = meshed.edge_band();
        let out = measure_output(&input, &s, meshed.to_volume_mesh(), true).unwrap();
        assert_eq!(out.validity.boundary_kept, Some(true));
        assert_eq!(out.edge_band.edges, own.edges);
        let (a, b) = (out.edge_band.in_band_percent, own.in_band_percent);
        assert!((a - b).abs() < 1e-9, "optimize {optimize}: {a} {b}");
        assert!((out.edge_band.mean - own.mean).abs() < 1e-9);
    }
    // Without T(S,F), the nearest input vertex's size.
    let p = s.vertices[3] * 0.999;
    let no_bg = harness::metrics::InputMeasures {
        background: None,
        ..input.clone()
    };
    let h = harness::metrics::output_sizes(&no_bg, &s, &[p]);
    assert_eq!(h, nearest_sizes(&s, &input.sizes, &[p]));
}
