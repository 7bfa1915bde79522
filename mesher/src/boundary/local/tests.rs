use super::triangles::TrianglesByMin;
use super::*;
use crate::surface::sorted_ids;

#[test]
fn triangles_are_found_by_their_smallest_vertex_in_any_order() {
    for t in [
        [0, 1, 2],
        [2, 0, 1],
        [1, 2, 0],
        [2, 1, 0],
        [0, 2, 1],
        [1, 0, 2],
    ] {
        assert_eq!(sorted_ids(t), [0, 1, 2]);
    }
    let tris = [[3, 1, 2], [1, 4, 3], [5, 3, 4], [2, 3, 1]];
    let by_min = TrianglesByMin::new(&tris, 4);
    assert_eq!(by_min.find([4, 3, 1]), Some(1));
    assert_eq!(by_min.find([3, 4, 5]), Some(2));
    // Listed twice (the same three vertices): the last one, as a hash map keeps.
    assert_eq!(by_min.find([1, 2, 3]), Some(3));
    assert_eq!(by_min.find([1, 2, 4]), None);
    // Vertices beyond any listed triangle (or the mesh) are not there.
    assert_eq!(by_min.find([7, 8, 9]), None);
    assert_eq!(by_min.find([0, 1, 2]), None);
}

fn two_tets() -> Local {
    // Tets (p, q, r, d) and (q, p, r, e) sharing face pqr, with de through it.
    let pts = vec![
        Point::new(1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
        Point::new(-1.0, -1.0, 0.0),
        Point::new(0.0, 0.0, 1.0),
        Point::new(0.0, 0.0, -1.0),
    ];
    let mesh = TetMesh::from_tets(pts, &[[0, 1, 2, 3], [1, 0, 2, 4]]).unwrap();
    mesh.validate(false).unwrap();
    Local::new(mesh)
}

#[test]
fn flip23_then_32_restores_two_tets() {
    let mut l = two_tets();
    let old: Vec<u32> = l.mesh.finite_tets().map(|t| t.0).collect();
    let new = [[0, 1, 4, 3], [1, 2, 4, 3], [2, 0, 4, 3]];
    l.replace(&old, &new).unwrap();
    l.mesh.validate(false).unwrap();
    assert_eq!(l.mesh.num_finite_tets(), 3);
    let mut s = Vec::new();
    let ring = l.ring(3, 4, &mut s).unwrap();
    assert_eq!(ring.len(), 3);
    let old: Vec<u32> = ring.iter().map(|r| r.0).collect();
    l.replace(&old, &[[0, 1, 2, 3], [1, 0, 2, 4]]).unwrap();
    l.mesh.validate(false).unwrap();
    assert!(l.has_face(0, 1, 2, &mut s));
}

#[test]
fn inverted_or_mismatched_sets_are_refused_and_nothing_changes() {
    let mut l = two_tets();
    let old: Vec<u32> = l.mesh.finite_tets().map(|t| t.0).collect();
    assert_eq!(
        l.replace(&old, &[[1, 0, 4, 3], [1, 2, 4, 3], [2, 0, 4, 3]]),
        Err(Refused::NotPositive)
    );
    assert_eq!(
        l.replace(&old, &[[0, 1, 4, 3], [1, 2, 4, 3]]),
        Err(Refused::Mismatch)
    );
    l.mesh.validate(false).unwrap();
    assert_eq!(l.mesh.num_finite_tets(), 2);
}

#[test]
fn a_move_out_of_the_box_turns_the_static_filter_off() {
    let mut l = two_tets();
    assert_eq!(l.filtered, 5);
    l.set_point(3, Point::new(0.0, 0.0, 0.5));
    assert_eq!(l.filtered, 5, "a move inside the box keeps it");
    l.set_point(3, Point::new(1e9, 1e9, 1e-12));
    assert_eq!(l.filtered, 0);
    assert_eq!(l.orient(0, 1, 2, 3), Orientation::Positive);
}

#[test]
fn a_face_listed_more_than_twice_is_refused() {
    let mut l = two_tets();
    let old: Vec<u32> = l.mesh.finite_tets().map(|t| t.0).collect();
    // The 2-3 flip with its first tet twice: its faces are then listed two or
    // three times, never as one pair of opposite orientations.
    let t = [[0, 1, 4, 3], [1, 2, 4, 3], [2, 0, 4, 3]];
    let doubled = [t[0], t[1], t[2], t[0]];
    assert_eq!(l.replace(&old, &doubled), Err(Refused::Mismatch));
    l.mesh.validate(false).unwrap();
    assert_eq!(l.replace(&old, &t), Ok(()));
    l.mesh.validate(false).unwrap();
}

/// `RING_ORDER` orders the two other vertices of a positive tet so that the edge's
/// ends and them are positive, for every ordered pair of positions.
#[test]
fn the_ring_order_keeps_the_tets_orientation() {
    use crate::geom::predicates::{orient3d, Orientation};
    let p = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
        Point::new(0.0, 0.0, 1.0),
    ];
    assert_eq!(orient3d(p[0], p[1], p[2], p[3]), Orientation::Positive);
    // Every even permutation of a positive tet is positive too.
    for perm in [
        [0, 1, 2, 3],
        [1, 0, 3, 2],
        [2, 3, 0, 1],
        [3, 2, 1, 0],
        [1, 2, 0, 3],
    ] {
        let q = perm.map(|k| p[k]);
        for ia in 0..4 {
            for ib in (0..4).filter(|&ib| ib != ia) {
                let [ip, iq] = RING_ORDER[ia][ib].map(usize::from);
                let mut seen = [ia, ib, ip, iq];
                seen.sort_unstable();
                assert_eq!(seen, [0, 1, 2, 3]);
                assert_eq!(
                    orient3d(q[ia], q[ib], q[ip], q[iq]),
                    Orientation::Positive,
                    "{perm:?} {ia} {ib}"
                );
            }
        }
    }
}
