//! Properties of the exact face-face intersection test: symmetric, invariant under
//! rotation and reversal of either face's vertices, independent of the checker's
//! acceleration structure (the BVH finds exactly the brute-force pairs), and equal to
//! independent separating-axis oracles evaluated exactly on integer coordinates (for
//! faces sharing ids, on the face minus a thin sliver around what it shares).

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

/// Separating-axis oracle, exact for small integer coordinates (every product fits in
/// an f64 mantissa): closed triangles are disjoint iff their projections on one of the
/// candidate axes (both normals, edge-edge cross products, in-plane edge normals) are
/// strictly separated.
fn sat_intersect(a: &[Point; 3], b: &[Point; 3]) -> bool {
    let ea = [a[1] - a[0], a[2] - a[1], a[0] - a[2]];
    let eb = [b[1] - b[0], b[2] - b[1], b[0] - b[2]];
    let na = ea[0].cross(ea[1]);
    let nb = eb[0].cross(eb[1]);
    let mut axes = vec![na, nb];
    for x in ea {
        for y in eb {
            axes.push(x.cross(y));
        }
        axes.push(na.cross(x));
    }
    for y in eb {
        axes.push(nb.cross(y));
    }
    !axes.iter().any(|ax| {
        if *ax == Point::ZERO {
            return false;
        }
        let pa = a.map(|p| ax.dot(p));
        let pb = b.map(|p| ax.dot(p));
        let (amin, amax) = (pa[0].min(pa[1]).min(pa[2]), pa[0].max(pa[1]).max(pa[2]));
        let (bmin, bmax) = (pb[0].min(pb[1]).min(pb[2]), pb[0].max(pb[1]).max(pb[2]));
        amax < bmin || bmax < amin
    })
}

fn grid_triangle() -> impl Strategy<Value = [Point; 3]> {
    let pt = (-3i32..=3, -3i32..=3, -2i32..=2)
        .prop_map(|(x, y, z)| Point::new(x as f64, y as f64, z as f64));
    [pt.clone(), pt.clone(), pt]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20000))]

    #[test]
    fn plain_test_matches_separating_axes(a in grid_triangle(), b in grid_triangle()) {
        let flat = |t: &[Point; 3]| (t[1] - t[0]).cross(t[2] - t[0]) == Point::ZERO;
        if flat(&a) || flat(&b) {
            return Ok(());
        }
        prop_assert_eq!(triangles_intersect(&a, &b), sat_intersect(&a, &b));
    }

    #[test]
    fn plain_test_matches_separating_axes_coplanar(a in flat_triangle(), b in flat_triangle()) {
        let flat = |t: &[Point; 3]| (t[1] - t[0]).cross(t[2] - t[0]) == Point::ZERO;
        if flat(&a) || flat(&b) {
            return Ok(());
        }
        prop_assert_eq!(triangles_intersect(&a, &b), sat_intersect(&a, &b));
    }
}

/// Triangles of the plane x + y + 2z = 0... sampled on its integer lattice: coplanar
/// pairs, in a plane that no coordinate projection is aligned with.
fn flat_triangle() -> impl Strategy<Value = [Point; 3]> {
    let pt = (-3i32..=3, -3i32..=3).prop_map(|(u, v)| {
        // u * (1, 1, -1) + v * (2, 0, -1) lies on x + y + 2z = 0.
        Point::new((u + 2 * v) as f64, u as f64, (-u - v) as f64)
    });
    [pt.clone(), pt.clone(), pt]
}

type I3 = [i128; 3];

fn isub(a: I3, b: I3) -> I3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn icross(a: I3, b: I3) -> I3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn idot(a: I3, b: I3) -> i128 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Exact separating-axis test for two convex planar polygons with integer corners.
fn sat_polygons(a: &[I3], b: &[I3]) -> bool {
    let edges = |p: &[I3]| -> Vec<I3> {
        (0..p.len())
            .map(|i| isub(p[(i + 1) % p.len()], p[i]))
            .collect()
    };
    let (ea, eb) = (edges(a), edges(b));
    let na = icross(ea[0], ea[1]);
    let nb = icross(eb[0], eb[1]);
    let mut axes = vec![na, nb];
    for &x in &ea {
        axes.extend(eb.iter().map(|&y| icross(x, y)));
        axes.push(icross(na, x));
    }
    axes.extend(eb.iter().map(|&y| icross(nb, y)));
    !axes.iter().any(|&ax| {
        if ax == [0, 0, 0] {
            return false;
        }
        let pa: Vec<i128> = a.iter().map(|&p| idot(ax, p)).collect();
        let pb: Vec<i128> = b.iter().map(|&p| idot(ax, p)).collect();
        let (amin, amax) = (*pa.iter().min().unwrap(), *pa.iter().max().unwrap());
        let (bmin, bmax) = (*pb.iter().min().unwrap(), *pb.iter().max().unwrap());
        amax < bmin || bmax < amin
    })
}

/// Oracle for faces sharing vertex ids: face `f` minus a sliver of relative width 2^-24
/// around what it shares with `g` (scaled by 2^24 to stay integral) meets `g`. With
/// corners in [-2, 2]^3 every vertex of the intersection other than the shared part
/// has barycentric weights with denominators far below 2^24, so the sliver is thin
/// enough.
fn shared_oracle(pts: &[Point], f: [u32; 3], g: [u32; 3]) -> bool {
    const S: i128 = 1 << 24;
    let sc = |v: u32| -> I3 {
        let p = pts[v as usize];
        [p.x as i128 * S, p.y as i128 * S, p.z as i128 * S]
    };
    // Point at relative distance 2^-24 from `from` towards `to`, scaled by S.
    let step = |from: u32, to: u32| -> I3 {
        let (a, b) = (sc(from), sc(to));
        [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) / S)
    };
    let shared: Vec<usize> = (0..3).filter(|&i| g.contains(&f[i])).collect();
    let cut: Vec<I3> = match shared.len() {
        0 => f.iter().map(|&v| sc(v)).collect(),
        1 => {
            let i = shared[0];
            let (v, a, b) = (f[i], f[(i + 1) % 3], f[(i + 2) % 3]);
            vec![step(v, a), sc(a), sc(b), step(v, b)]
        }
        _ => {
            let k = (0..3).find(|i| !shared.contains(i)).unwrap();
            let (a, u, v) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
            vec![step(u, a), step(v, a), sc(a)]
        }
    };
    let gt: Vec<I3> = g.iter().map(|&v| sc(v)).collect();
    sat_polygons(&cut, &gt)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20000))]

    #[test]
    fn shared_faces_match_the_sliver_oracle((pts, f, g) in config()) {
        let flat = |t: [u32; 3]| {
            let p = t.map(|v| pts[v as usize]);
            (p[1] - p[0]).cross(p[2] - p[0]) == Point::ZERO
        };
        let nshared = f.iter().filter(|v| g.contains(v)).count();
        if flat(f) || flat(g) || nshared == 3 {
            return Ok(());
        }
        let got = surface(&pts, f, g).faces_intersect(0, 1);
        prop_assert_eq!(got, shared_oracle(&pts, f, g), "shared {}", nshared);
    }
}
