//! Properties of the exact face-face intersection test: symmetric, invariant under
//! rotation and reversal of either face's vertices, and independent of the checker's
//! acceleration structure (the BVH finds exactly the brute-force pairs).

use mesher::surface::intersect::triangles_intersect;
use mesher::{Point, Surface};
use proptest::prelude::*;

/// A pool of 7 points on a small integer grid (many coplanar and collinear cases) and
/// two faces drawn from it, sharing vertices often.
fn config() -> impl Strategy<Value = (Vec<Point>, [u32; 3], [u32; 3])> {
    let pt = (-2i32..=2, -2i32..=2, -2i32..=2)
        .prop_map(|(x, y, z)| Point::new(x as f64, y as f64, z as f64));
    let face = proptest::sample::subsequence((0u32..7).collect::<Vec<_>>(), 3)
        .prop_flat_map(|ids| Just([ids[0], ids[1], ids[2]]).prop_shuffle())
        .prop_map(|v| [v[0], v[1], v[2]]);
    (proptest::collection::vec(pt, 7), face.clone(), face)
}

fn surface(pts: &[Point], f: [u32; 3], g: [u32; 3]) -> Surface {
    Surface {
        vertices: pts.to_vec(),
        triangles: vec![f, g],
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    #[test]
    fn symmetric_and_rotation_invariant((pts, f, g) in config()) {
        let base = surface(&pts, f, g).faces_intersect(0, 1);
        prop_assert_eq!(surface(&pts, g, f).faces_intersect(0, 1), base);
        for k in 1..3 {
            let fr = [f[k], f[(k + 1) % 3], f[(k + 2) % 3]];
            let gr = [g[(k + 1) % 3], g[(k + 2) % 3], g[k]];
            prop_assert_eq!(surface(&pts, fr, g).faces_intersect(0, 1), base);
            prop_assert_eq!(surface(&pts, f, gr).faces_intersect(0, 1), base);
            prop_assert_eq!(surface(&pts, gr, fr).faces_intersect(0, 1), base);
        }
        let frev = [f[0], f[2], f[1]];
        prop_assert_eq!(surface(&pts, frev, g).faces_intersect(0, 1), base);
    }

    #[test]
    fn unshared_faces_match_the_plain_test((pts, _, _) in config()) {
        let (f, g) = ([0, 1, 2], [3, 4, 5]);
        let s = surface(&pts, f, g);
        let tf = f.map(|v| pts[v as usize]);
        let tg = g.map(|v| pts[v as usize]);
        prop_assert_eq!(s.faces_intersect(0, 1), triangles_intersect(&tf, &tg));
        prop_assert_eq!(triangles_intersect(&tg, &tf), triangles_intersect(&tf, &tg));
    }

    #[test]
    fn sharing_only_ids_never_adds_contacts((pts, f, g) in config()) {
        // Faces that share ids can only intersect if the plain closed triangles do.
        let s = surface(&pts, f, g);
        let tf = f.map(|v| pts[v as usize]);
        let tg = g.map(|v| pts[v as usize]);
        if s.faces_intersect(0, 1) {
            prop_assert!(triangles_intersect(&tf, &tg));
        }
    }

    #[test]
    fn checker_counts_match_brute_force(
        pts in proptest::collection::vec((-3i32..=3, -3i32..=3, -3i32..=3), 12),
        faces in proptest::collection::vec((0u32..12, 0u32..12, 0u32..12), 1..14),
    ) {
        let s = Surface {
            vertices: pts.iter().map(|&(x, y, z)| Point::new(x as f64, y as f64, z as f64)).collect(),
            triangles: faces.iter().map(|&(a, b, c)| [a, b, c]).collect(),
        };
        let r = s.check();
        let n = s.triangles.len();
        let mut want = 0;
        for i in 0..n {
            for j in i + 1..n {
                let mut a = s.triangles[i];
                let mut b = s.triangles[j];
                a.sort_unstable();
                b.sort_unstable();
                if a != b && s.faces_intersect(i, j) {
                    want += 1;
                }
            }
        }
        prop_assert_eq!(r.self_intersections.count, want);
    }
}
