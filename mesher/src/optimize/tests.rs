use super::*;
use crate::boundary::{boundary_mesh, BoundaryOptions};
use crate::delaunay::{sort::SplitMix64, triangulate, DelaunayOptions};
use crate::geom::Point;
use crate::quality::tet::signed_volume;
use crate::surface::generate;
use crate::tetmesh::{TetId, FACE_VERTICES};

/// The Delaunay mesh of random points in the unit cube (corners included) as a domain
/// ([`hull_domain`]). Random Delaunay meshes have slivers, so there is work to do.
fn random_domain(n: usize, seed: u64) -> Domain {
    let mut rng = SplitMix64::new(seed);
    let mut r = || rng.unit();
    let mut pts: Vec<Point> = (0..8)
        .map(|i| Point::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64))
        .collect();
    pts.extend((0..n).map(|_| Point::new(r(), r(), r())));
    hull_domain(&pts)
}

/// The Delaunay mesh of `pts` as a domain: the hull is its constrained boundary and
/// the hull vertices are fixed.
fn hull_domain(pts: &[Point]) -> Domain {
    let tr = triangulate(pts, &DelaunayOptions::default()).expect("a triangulation");
    let mesh = tr.mesh;
    let mut region = vec![0; mesh.num_slots()];
    let mut constrained = Vec::new();
    let mut fixed = vec![false; mesh.num_vertices()];
    for t in mesh.tets() {
        if mesh.is_ghost(t) {
            let v = mesh.tet(t);
            let f = [v[0].0, v[1].0, v[2].0];
            constrained.push(f);
            for x in f {
                fixed[x as usize] = true;
            }
        } else {
            region[t.index()] = 1;
        }
    }
    Domain {
        mesh,
        region,
        constrained,
        fixed,
    }
}

/// Sorted boundary faces of the domain and its volume.
fn boundary_and_volume(d: &Domain) -> (Vec<[u32; 3]>, f64) {
    let mut faces = Vec::new();
    let mut volume = 0.0;
    for t in d.mesh.finite_tets() {
        if d.region[t.index()] == 0 {
            continue;
        }
        volume += signed_volume(&d.mesh.tet_points(t));
        for (i, fv) in FACE_VERTICES.iter().enumerate() {
            let nb = d.mesh.neighbor(t, i).tet();
            if d.mesh.is_ghost(nb) || d.region[nb.index()] == 0 {
                let v = d.mesh.tet(t);
                let mut f = fv.map(|k| v[k].0);
                f.sort_unstable();
                faces.push(f);
            }
        }
    }
    faces.sort_unstable();
    (faces, volume)
}

fn check(name: &str, d: &mut Domain, options: &OptimizeOptions) -> OptimizeReport {
    let (faces, volume) = boundary_and_volume(d);
    let fixed_points: Vec<Point> = (0..d.mesh.num_vertices())
        .filter(|&v| d.fixed[v])
        .map(|v| d.mesh.point(crate::tetmesh::VertexId(v as u32)))
        .collect();
    let r = optimize(d, options);
    d.mesh
        .validate(false)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let (faces2, volume2) = boundary_and_volume(d);
    assert_eq!(faces, faces2, "{name}: the boundary changed");
    assert!(
        (volume - volume2).abs() <= 1e-12 * volume.abs(),
        "{name}: volume {volume} -> {volume2}"
    );
    let fixed_after: Vec<Point> = (0..d.mesh.num_vertices())
        .filter(|&v| d.fixed[v])
        .map(|v| d.mesh.point(crate::tetmesh::VertexId(v as u32)))
        .collect();
    assert_eq!(fixed_points, fixed_after, "{name}: a fixed vertex moved");
    assert!(
        r.worst_after <= r.worst_before,
        "{name}: worst {} -> {}",
        r.worst_before,
        r.worst_after
    );
    for t in d.mesh.finite_tets() {
        if d.region[t.index()] != 0 {
            let v = d.mesh.tet(t);
            let p = v.map(|x| d.mesh.point(x));
            assert_eq!(
                crate::geom::predicates::orient3d(p[0], p[1], p[2], p[3]),
                crate::geom::predicates::Orientation::Positive,
                "{name}: tet {t:?} not positive"
            );
        }
    }
    r
}

#[test]
fn random_delaunay_meshes_improve_and_keep_their_boundary() {
    for seed in 0..4 {
        let mut d = random_domain(300, seed);
        let r = check("random", &mut d, &OptimizeOptions::default());
        assert!(r.worst_after < r.worst_before, "seed {seed}: {r:?}");
        // Fewer bad tets after than before.
        let bad = |h: &Histogram| h.counts.iter().skip(3).sum::<u64>();
        assert!(bad(&r.after) < bad(&r.before), "seed {seed}");
    }
}

#[test]
fn a_near_duplicate_vertex_is_collapsed() {
    // An interior point a thousandth of the spacing from another: its tets are needles
    // that only a collapse removes.
    let mut d = random_domain(200, 7);
    let pts = d.mesh.points();
    let near = pts[20] + Point::new(1e-3, 5e-4, -7e-4);
    let mut all = pts[..pts.len()].to_vec();
    all.push(near);
    let tr = triangulate(&all, &DelaunayOptions::default()).expect("a triangulation");
    let mut region = vec![0; tr.mesh.num_slots()];
    for t in tr.mesh.tets() {
        if !tr.mesh.is_ghost(t) {
            region[t.index()] = 1;
        }
    }
    let mut fixed = d.fixed.clone();
    fixed.push(false);
    d = Domain {
        mesh: tr.mesh,
        region,
        constrained: d.constrained,
        fixed,
    };
    let r = check("near duplicate", &mut d, &OptimizeOptions::default());
    assert!(
        r.passes.iter().map(|p| p.collapses).sum::<u64>() > 0,
        "{r:?}"
    );
    let used = |v: u32| {
        d.mesh
            .finite_tets()
            .any(|t| d.mesh.tet(t).iter().any(|x| x.0 == v))
    };
    assert!(
        !(used(20) && used(all.len() as u32 - 1)),
        "both ends are still there"
    );
}

#[test]
fn every_smoothing_variant_is_safe() {
    for how in [Smoothing::Optimal, Smoothing::Laplacian, Smoothing::Off] {
        let mut d = random_domain(200, 9);
        let options = OptimizeOptions {
            smoothing: how,
            ..OptimizeOptions::default()
        };
        check("variant", &mut d, &options);
    }
}

#[test]
fn boundary_meshes_keep_their_surface() {
    for (name, s) in [
        ("torus", generate::torus(24, 12, 1.0, 0.3)),
        ("sphere", generate::icosphere(2)),
    ] {
        let (bm, _) = boundary_mesh(&s, &BoundaryOptions::default()).expect("T(S,F)");
        let mut fixed = vec![false; bm.mesh.num_vertices()];
        for v in bm
            .surface_vertex
            .iter()
            .chain(&bm.boundary_steiner)
            .chain(&bm.box_corners)
        {
            fixed[v.index()] = true;
        }
        let mut d = Domain {
            constrained: bm.faces.iter().map(|f| f.map(|v| v.0)).collect(),
            mesh: bm.mesh,
            region: bm.region,
            fixed,
        };
        check(name, &mut d, &OptimizeOptions::default());
    }
}

#[test]
fn same_input_same_result() {
    let run = || {
        let mut d = random_domain(200, 3);
        optimize(&mut d, &OptimizeOptions::default());
        let tets: Vec<[u32; 4]> = d
            .mesh
            .finite_tets()
            .map(|t: TetId| d.mesh.tet(t).map(|v| v.0))
            .collect();
        (tets, d.mesh.points().to_vec())
    };
    assert_eq!(run(), run());
}

#[test]
#[ignore]
fn print_random() {
    for how in [Smoothing::Optimal, Smoothing::Laplacian, Smoothing::Off] {
        let mut d = random_domain(3000, 1);
        let r = optimize(
            &mut d,
            &OptimizeOptions {
                smoothing: how,
                max_passes: 20,
                ..OptimizeOptions::default()
            },
        );
        let pct =
            |h: &Histogram| 100.0 * h.counts[..2].iter().sum::<u64>() as f64 / h.total() as f64;
        eprintln!(
            "{how:?}: worst {:.1} -> {:.2}, %<3 {:.1} -> {:.1}, {:.3} s, passes {}",
            r.worst_before,
            r.worst_after,
            pct(&r.before),
            pct(&r.after),
            r.seconds,
            r.passes.len()
        );
        for p in &r.passes {
            eprintln!("  {p:?}");
        }
    }
}

/// A debugging aid: optimises $OPT_DEBUG_MESH (a .mesh written by `mesher mesh`) again
/// from scratch, its boundary triangles constrained and their vertices fixed, and
/// prints the worst Q_K before and after (what a second run would still gain).
#[test]
#[ignore]
fn debug_worst_tet_of_a_file() {
    let Ok(path) = std::env::var("OPT_DEBUG_MESH") else {
        return;
    };
    let vm = crate::io::read_volume(std::path::Path::new(&path)).unwrap();
    let mesh = TetMesh::from_tets(vm.vertices.clone(), &vm.tets).unwrap();
    // from_tets puts the input tets first, then the ghosts (region 0).
    let mut region = vec![1; vm.tets.len()];
    region.resize(mesh.num_slots(), 0);
    let mut fixed = vec![false; mesh.num_vertices()];
    for t in &vm.triangles {
        for &x in t {
            fixed[x as usize] = true;
        }
    }
    let mut d = Domain {
        mesh,
        region,
        constrained: vm.triangles.clone(),
        fixed,
    };
    let r = optimize(&mut d, &OptimizeOptions::default());
    eprintln!("worst {} -> {}", r.worst_before, r.worst_after);
    for p in &r.passes {
        eprintln!(
            "pass bad {} worst {} rem {} flips {} sm {} ins {} col {}",
            p.bad_tets, p.worst, p.edge_removals, p.face_flips, p.smoothed, p.inserted, p.collapses
        );
    }
}

#[test]
fn compass_search_finds_the_thin_valid_lens() {
    // Valid only within 1e-3 of the segment x in [0, 1] on the x axis, best at
    // (0.3, 4e-4, 0): from the segment's middle, with a first step a hundred times too
    // long, the search must still get there.
    let target = Point::new(0.3, 4e-4, 0.0);
    let score = |p: Point| {
        if p.y.abs() > 1e-3 || p.z.abs() > 1e-3 || !(0.0..=1.0).contains(&p.x) {
            f64::INFINITY
        } else {
            1.0 + p.distance(target)
        }
    };
    let start = Point::new(0.5, 0.0, 0.0);
    let (value, p) = crate::geom::search::compass(score, start, score(start), 0.1);
    assert!(value < 1.0 + 1e-3, "{value} at {p:?}");
}

#[test]
fn widening_a_dihedral_keeps_the_ball_worst_and_its_good_tets() {
    // A random Delaunay mesh has slivers; the free vertex whose ball has the smallest
    // angle is moved, and its ball must gain angle without losing Q_K, orientation or
    // a well-shaped tet (no boundary face in the ball: no margin).
    use crate::quality::tet::{min_dihedral, q_k, WELL_SHAPED_Q_K};
    let d = random_domain(300, 3);
    let mut ops = super::ops::Ops::new(Local::new(d.mesh), Locks::default(), d.region, d.fixed);
    let ball = |ops: &super::ops::Ops, v: u32| {
        let mut star = Vec::new();
        ops.l.star(v, &mut star);
        star.iter()
            .map(|&t| {
                let p = ops.l.tet(t).map(|x| ops.l.p(x));
                (min_dihedral(&p), q_k(&p), signed_volume(&p))
            })
            .collect::<Vec<_>>()
    };
    let free = (8..ops.l.mesh.num_vertices() as u32).filter(|&v| !ops.fixed[v as usize]);
    let smallest = |b: &[(f64, f64, f64)]| b.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
    let v = free
        .min_by(|&a, &b| smallest(&ball(&ops, a)).total_cmp(&smallest(&ball(&ops, b))))
        .expect("a free vertex");
    let before = ball(&ops, v);
    assert!(
        ops.widen_dihedral(v, f64::INFINITY),
        "the smallest angle {} stayed",
        smallest(&before)
    );
    let after = ball(&ops, v);
    assert!(smallest(&after) > smallest(&before));
    let worst = |b: &[(f64, f64, f64)]| b.iter().map(|x| x.1).fold(1.0, f64::max);
    assert!(worst(&after) <= worst(&before));
    // The star is listed in the same order (the tets stay, the vertex moves).
    for (b, a) in before.iter().zip(&after) {
        assert!(a.2 > 0.0);
        assert!(b.1 >= WELL_SHAPED_Q_K || a.1 < WELL_SHAPED_Q_K);
    }
}

#[test]
fn rescanning_the_touched_vertices_finds_what_a_full_scan_finds() {
    let d = random_domain(400, 11);
    let options = OptimizeOptions::default();
    let mut ops = super::ops::Ops::new(Local::new(d.mesh), Locks::default(), d.region, d.fixed);
    let (mut bad, _, _) = scan(&ops, options.bad_quality);
    let mut since = ops.l.stamps.clock;
    let mut failed = FastMap::default();
    let sorted = |mut b: Vec<Bad>| {
        b.sort_by_key(|x| x.1);
        b
    };
    for k in 0..3 {
        let stats = pass(
            &mut ops,
            &options,
            options.bad_quality,
            &mut failed,
            k > 0,
            bad.clone(),
        );
        assert!(
            k > 0 || stats.edge_removals + stats.smoothed > 0,
            "nothing changed"
        );
        let (full, _, worst) = scan(&ops, options.bad_quality);
        // Never the full scan's fallback (share 1: only if every vertex was touched).
        let (quick, quick_worst) = rescan_unless(&ops, bad, &mut since, options.bad_quality, 1);
        assert_eq!(sorted(quick.clone()), sorted(full), "pass {k}");
        assert_eq!(quick_worst, worst);
        bad = quick;
    }
}

#[test]
fn random_descent_jumps_to_the_better_basin() {
    // Two basins: the compass from the first one's centre stays there (1.0, behind a
    // ridge of 1.15); the better one (0.5) is 0.8 away, inside the descent's reach.
    let (a, b) = (Point::ZERO, Point::new(0.5, 0.6, 0.2));
    let score = |p: Point| (1.0 + p.distance(a)).min(0.5 + p.distance(b));
    let start = a + Point::new(0.01, 0.0, 0.0);
    let (c, _) = crate::geom::search::compass(score, start, score(start), 0.05);
    assert!(c > 0.99, "the compass left its basin: {c}");
    let (p, v) = super::ops::random_descent_below(|q, _| score(q), start, score(start), 1.0);
    assert!(v < 0.52 && p.distance(b) < 0.005, "{v} at {p:?}");
}

#[test]
#[ignore]
fn debug_ops_on_a_tet() {
    let Ok(path) = std::env::var("OPT_DEBUG_MESH") else {
        return;
    };
    let want: Vec<u32> = std::env::var("OPT_DEBUG_TET")
        .unwrap()
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let vm = crate::io::read_volume(std::path::Path::new(&path)).unwrap();
    let mesh = TetMesh::from_tets(vm.vertices.clone(), &vm.tets).unwrap();
    let mut region = vec![1; vm.tets.len()];
    region.resize(mesh.num_slots(), 0);
    let mut fixed = vec![false; mesh.num_vertices()];
    for t in &vm.triangles {
        for &x in t {
            fixed[x as usize] = true;
        }
    }
    let locks = Locks::of_faces(&vm.triangles);
    let mut ops = ops::Ops::new(Local::new(mesh), locks, region, fixed);
    let find = |ops: &ops::Ops| {
        ops.l.mesh.finite_tets().map(|t| t.0).find(|&t| {
            let mut v = ops.l.tet(t);
            v.sort_unstable();
            let mut w = want.clone();
            w.sort_unstable();
            v.to_vec() == w
        })
    };
    let t = find(&ops).expect("tet");
    let v = ops.l.tet(t);
    eprintln!("tet {t} {:?} q {}", v, ops.tet_quality(t));
    for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        let mark = ops.l.mark();
        let ok = ops.remove_edge(t, v[i], v[j]);
        eprintln!("remove_edge {} {} -> {ok}", v[i], v[j]);
        if ok {
            ops.l.undo(mark);
        }
    }
    for i in 0..4 {
        let mark = ops.l.mark();
        let ok = ops.flip23(t, i);
        eprintln!("flip23 face {i} -> {ok}");
        if ok {
            ops.l.undo(mark);
        }
    }
    let mark = ops.l.mark();
    let ok = ops.insert_in(t);
    eprintln!("insert_in -> {ok}");
    if ok {
        ops.l.undo(mark);
    }
    let ok = ops.insert_grown_around(t);
    eprintln!("insert_grown_around -> {ok}");
}

/// Checks that the mesh of `ops` is valid and still has every face of `boundary`.
fn assert_valid_with_faces(ops: &ops::Ops, boundary: &[[u32; 3]], what: &str) {
    ops.l.mesh.validate(false).expect(what);
    let mut scratch = Vec::new();
    for f in boundary {
        assert!(
            ops.l.has_face(f[0], f[1], f[2], &mut scratch),
            "{what}: boundary face {f:?} kept"
        );
    }
}

/// The mesh of `tets` over `points`, each tet turned positive.
fn positive_mesh(points: Vec<Point>, mut tets: Vec<[u32; 4]>) -> TetMesh {
    for t in &mut tets {
        let p = t.map(|x| points[x as usize]);
        if signed_volume(&p) < 0.0 {
            t.swap(0, 1);
        }
    }
    TetMesh::from_tets(points, &tets).expect("a valid test mesh")
}

/// The last resort's edge split (`Ops::split_edge_of`): a free vertex nearly in the
/// plane of a fan of small fixed triangles (a pyramid of fixed vertices, the free
/// vertex just above its base's centre) makes four flat tets around the edge from it to
/// the fan's centre; a point placed on that edge's ring lowers the ring's worst.
#[test]
fn an_edge_split_lifts_the_flat_tets_of_a_fan() {
    let c = Point::new(0.0, 0.0, 0.0);
    let ring: Vec<Point> = (0..4)
        .map(|k| {
            let a = std::f64::consts::FRAC_PI_2 * k as f64;
            Point::new(0.01 * a.cos(), 0.01 * a.sin(), 0.0)
        })
        .collect();
    let apex = Point::new(0.0, 0.0, 0.03);
    let free = Point::new(0.001, 0.0005, 0.0003);
    // 0 centre, 1-4 ring, 5 apex, 6 the free vertex.
    let mut points = vec![c];
    points.extend(&ring);
    points.push(apex);
    points.push(free);
    let mut tets = Vec::new();
    let mut boundary = Vec::new();
    for k in 0..4u32 {
        let (a, b) = (1 + k, 1 + (k + 1) % 4);
        // Bottom face (0, b, a) seen from above, side face (a, b, 5) from inside.
        boundary.push([0, b, a]);
        boundary.push([a, b, 5]);
        tets.push([0, b, a, 6]);
        tets.push([a, b, 5, 6]);
    }
    let mesh = positive_mesh(points, tets);
    let region = vec![1; mesh.num_slots()];
    let mut fixed = vec![true; mesh.num_vertices()];
    fixed[6] = false;
    let locks = Locks::of_faces(&boundary);
    let mut ops = ops::Ops::new(Local::new(mesh), locks, region, fixed);
    let worst_of = |ops: &ops::Ops| {
        ops.l
            .mesh
            .finite_tets()
            .map(|t| ops.tet_quality(t.0))
            .fold(1.0, f64::max)
    };
    let before = worst_of(&ops);
    let t = ops
        .l
        .mesh
        .finite_tets()
        .map(|t| t.0)
        .max_by(|&a, &b| ops.tet_quality(a).total_cmp(&ops.tet_quality(b)))
        .expect("tets");
    assert!(before > 10.0, "flat fan tets expected, worst {before}");
    assert!(ops.split_edge_of(t, 0.01), "the split should apply");
    let after = worst_of(&ops);
    assert!(after < 0.99 * before, "worst {before} -> {after}");
    assert_valid_with_faces(&ops, &boundary, "valid after the split");
}

/// The last resort's Delaunay cavity (`Ops::insert_delaunay_around`): a flat tet of
/// four fixed vertices under a shallow roof of two boundary faces (a ridge), over two
/// tets down to a fixed apex; the cone from one new point over the three tets' Delaunay
/// cavity lifts it.
#[test]
fn a_delaunay_cavity_lifts_a_flat_tet_under_a_ridge() {
    // 0 a, 1 b, 2 c, 3 d: the ridge a-c above the diagonal b-d; 4 the apex below.
    let points = vec![
        Point::new(-1.0, 0.0, 0.1),
        Point::new(0.0, -1.0, 0.0),
        Point::new(1.0, 0.0, 0.1),
        Point::new(0.0, 1.0, 0.0),
        Point::new(0.0, 0.0, -1.5),
    ];
    let boundary = vec![
        [0, 1, 2],
        [0, 2, 3],
        [0, 1, 4],
        [1, 2, 4],
        [2, 3, 4],
        [3, 0, 4],
    ];
    let mesh = positive_mesh(points, vec![[0, 1, 2, 3], [0, 1, 3, 4], [1, 2, 3, 4]]);
    let region = vec![1; mesh.num_slots()];
    let fixed = vec![true; mesh.num_vertices()];
    let mut ops = ops::Ops::new(Local::new(mesh), Locks::of_faces(&boundary), region, fixed);
    let qualities = |ops: &ops::Ops| -> Vec<(f64, u32)> {
        ops.l
            .mesh
            .finite_tets()
            .map(|t| (ops.tet_quality(t.0), t.0))
            .collect()
    };
    let (before, t) = qualities(&ops)
        .into_iter()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .expect("tets");
    assert!(before > 5.0, "a flat tet expected, worst {before}");
    assert!(ops.insert_delaunay_around(t), "the insertion should apply");
    let after = qualities(&ops).iter().map(|q| q.0).fold(1.0, f64::max);
    assert!(after < 0.5 * before, "worst {before} -> {after}");
    assert_valid_with_faces(&ops, &boundary, "valid after the insertion");
}

/// The last resort's wedge (`Ops::insert_by_surface_edge`) on T(S,F) of a torus,
/// whose tets all have four surface vertices: tried on every tet above `Q_K` 3, worst
/// first, it applies, each time lowers the domain's `Q_K` values sorted from the worst
/// (the tets it replaces are worse than those it makes), and keeps the mesh valid and
/// every surface face.
#[test]
fn points_by_surface_edges_keep_the_mesh_and_lower_its_worst() {
    let s = generate::torus(24, 12, 1.0, 0.3);
    let (bm, _) = boundary_mesh(&s, &BoundaryOptions::default()).expect("T(S,F)");
    let boundary: Vec<[u32; 3]> = bm.faces.iter().map(|f| f.map(|v| v.0)).collect();
    let mut fixed = vec![false; bm.mesh.num_vertices()];
    for v in bm.surface_vertex.iter().chain(&bm.box_corners) {
        fixed[v.index()] = true;
    }
    let mut ops = ops::Ops::new(
        Local::new(bm.mesh),
        Locks::of_faces(&boundary),
        bm.region,
        fixed,
    );
    // The domain's tets, worst first.
    let tets = |ops: &ops::Ops| {
        let mut all: Vec<(f64, u32, [u32; 4])> = ops
            .l
            .mesh
            .finite_tets()
            .filter(|t| ops.region[t.index()] != 0)
            .map(|t| (ops.tet_quality(t.0), t.0, ops.l.tet(t.0)))
            .collect();
        all.sort_by(|a, b| b.0.total_cmp(&a.0));
        all
    };
    let lower = |a: &[(f64, u32, [u32; 4])], b: &[(f64, u32, [u32; 4])]| {
        let first_change = a.iter().zip(b).find(|(x, y)| x.0 != y.0);
        first_change.is_some_and(|(x, y)| y.0 < x.0)
    };
    let mut before = tets(&ops);
    let bad: Vec<(f64, u32, [u32; 4])> = before.iter().copied().filter(|b| b.0 > 3.0).collect();
    let mut applied = 0;
    for (_, t, v) in bad {
        if ops.l.tet(t) != v || !ops.insert_by_surface_edge(t) {
            continue;
        }
        applied += 1;
        let after = tets(&ops);
        assert!(
            lower(&before, &after),
            "insertion {applied} did not lower the values"
        );
        before = after;
    }
    assert!(applied > 0, "no wedge insertion applied");
    assert_valid_with_faces(&ops, &boundary, "valid after the insertions");
}

/// Multi-face removal (`Ops::remove_faces`): a bipyramid over a hexagon whose four
/// faces between the apexes are a fan from one corner (eight tets, long flat ones on
/// the fan's diagonals) becomes the six tets around the axis between the apexes, when
/// one apex at least is free.
#[test]
fn multi_face_removal_turns_a_fan_into_the_ring_of_the_axis() {
    // 0-5 the hexagon, 6 the top apex, 7 the bottom one.
    let mut points: Vec<Point> = (0..6)
        .map(|k| {
            let a = std::f64::consts::FRAC_PI_3 * k as f64;
            Point::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    points.push(Point::new(0.0, 0.0, 0.8));
    points.push(Point::new(0.0, 0.0, -0.8));
    let mut tets = Vec::new();
    for i in 1..5u32 {
        tets.push([0, i, i + 1, 6]);
        tets.push([0, i + 1, i, 7]);
    }
    let boundary: Vec<[u32; 3]> = (0..6u32)
        .flat_map(|i| [[i, (i + 1) % 6, 6], [(i + 1) % 6, i, 7]])
        .collect();
    let mesh = positive_mesh(points, tets);
    let region = vec![1; mesh.num_slots()];
    // The new edge joins the apexes: refused between two fixed vertices.
    let fixed = vec![true; mesh.num_vertices()];
    let mut pinned = ops::Ops::new(
        Local::new(mesh.clone()),
        Locks::of_faces(&boundary),
        region.clone(),
        fixed.clone(),
    );
    let any = pinned.l.mesh.finite_tets().next().expect("tets").0;
    assert!(
        (0..4).all(|i| !pinned.remove_faces(any, i)),
        "both apexes fixed"
    );
    let mut fixed = fixed;
    fixed[6] = false;
    let mut ops = ops::Ops::new(Local::new(mesh), Locks::of_faces(&boundary), region, fixed);
    let worst = |ops: &ops::Ops| {
        ops.l
            .mesh
            .finite_tets()
            .map(|t| (ops.tet_quality(t.0), t.0))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .expect("tets")
    };
    let (before, t) = worst(&ops);
    let v = ops.l.tet(t);
    let apex = (0..4).find(|&i| v[i] >= 6).expect("an apex");
    assert!(ops.remove_faces(t, apex), "the removal should apply");
    let (after, _) = worst(&ops);
    assert!(after < before, "worst {before} -> {after}");
    assert_eq!(ops.l.mesh.finite_tets().count(), 6, "the ring of the axis");
    assert_valid_with_faces(&ops, &boundary, "valid after the removal");
    let mut scratch = Vec::new();
    assert!(
        ops.l.find_edge(6, 7, &mut scratch).is_some(),
        "the axis is an edge"
    );
}
