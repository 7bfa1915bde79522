//! Unit tests of the boundary mesh on generated surfaces.

use super::attempts::{attempt_options, ORDER_RETRIES};
use super::flips::flip23;
use super::*;
use crate::surface::generate::{cube, icosphere, torus};

fn check(surface: &Surface) -> (BoundaryMesh, BoundaryReport) {
    let (bm, r) = boundary_mesh(surface, &BoundaryOptions::default()).unwrap();
    bm.mesh.validate(false).unwrap();
    let mut s = Vec::new();
    let l = Local::new(bm.mesh.clone());
    for t in &surface.triangles {
        let f = t.map(|i| bm.surface_vertex[i as usize].0);
        assert!(
            l.has_face(f[0], f[1], f[2], &mut s),
            "triangle {t:?} missing"
        );
    }
    let rel = (r.volume - r.enclosed_volume).abs() / r.enclosed_volume.abs();
    assert!(
        rel < 1e-9,
        "volume {} vs enclosed {}",
        r.volume,
        r.enclosed_volume
    );
    (bm, r)
}

#[test]
fn sphere_cube_torus_are_recovered_with_their_volume() {
    for s in [icosphere(2), cube(3), torus(24, 12, 2.0, 0.5)] {
        let (_, r) = check(&s);
        assert_eq!(r.regions, 1);
        assert_eq!(r.steiner_on_edges + r.steiner_on_faces, 0);
    }
}

#[test]
fn thin_torus_needs_flips() {
    // A thin, coarse torus: many surface edges are not Delaunay.
    let s = torus(40, 5, 3.0, 0.2);
    let (_, r) = check(&s);
    assert!(r.missing_edges + r.missing_faces > 0, "{r:?}");
}

#[test]
fn open_surface_is_refused_with_its_defect() {
    let mut s = icosphere(1);
    s.triangles.pop();
    let e = boundary_mesh(&s, &BoundaryOptions::default()).unwrap_err();
    assert!(matches!(e, BoundaryError::Defective { .. }), "{e}");
    assert!(e.to_string().contains("open"), "{e}");
}

#[test]
fn box_delaunay_is_valid() {
    for s in [icosphere(2), cube(3)] {
        let (mesh, _, _) = delaunay(&s, &[], &BoundaryOptions::default()).unwrap();
        mesh.validate(true).unwrap();
    }
}

/// A fresh round on a surface whose every triangle is already a face (an icosphere's
/// Delaunay mesh) locks every edge and face at once and hands over face marks equal to
/// a fresh sweep; a round where some are missing takes the general path (no marks).
#[test]
fn a_round_with_every_face_present_locks_all_and_keeps_its_marks() {
    let opts = BoundaryOptions::default();
    let s = icosphere(2);
    let edges = input_edges(&s, EdgeOrder::Sorted);
    let (mesh, sv, _) = delaunay(&s, &[], &opts).unwrap();
    let mut rec = Recovery::new(Local::new(mesh));
    let mut report = BoundaryReport::default();
    let done = recover_all(&mut rec, &s, &edges, &sv, &opts, &mut report, 0).unwrap();
    assert!(done.stuck.is_empty() && done.bad.is_empty());
    assert_eq!((report.missing_edges, report.missing_faces), (0, 0));
    assert_eq!(rec.locks.faces.len(), s.triangles.len());
    assert_eq!(rec.locks.edges.len(), edges.len());
    let tris: Vec<[u32; 3]> = s
        .triangles
        .iter()
        .map(|t| t.map(|i| sv[i as usize].0))
        .collect();
    let marks = done.marks.expect("every face present: marks kept");
    assert_eq!(marks.marks, rec.l.triangle_faces(&tris));
    // Locked entities already: the general path.
    let again = recover_all(&mut rec, &s, &edges, &sv, &opts, &mut report, 0).unwrap();
    assert!(again.marks.is_none());
}

/// A developer's tool: what blocks the first stuck edges of `MODEL` (a surface file)
/// before any Steiner round. `MODEL=path cargo test -p mesher --lib debug_model --
/// --ignored --nocapture`.
#[test]
#[ignore]
fn debug_model() {
    let path = std::env::var("MODEL").unwrap();
    let s = crate::io::read_surface(std::path::Path::new(&path))
        .unwrap()
        .surface;
    let opts = BoundaryOptions {
        steiner_rounds: 0,
        ..BoundaryOptions::default()
    };
    let edges = input_edges(&s, EdgeOrder::Sorted);
    let (mesh, sv, _) = delaunay(&s, &[], &opts).unwrap();
    let mut rec = Recovery::new(Local::new(mesh));
    let mut report = BoundaryReport::default();
    let stuck = recover_all(&mut rec, &s, &edges, &sv, &opts, &mut report, 0)
        .unwrap()
        .stuck;
    eprintln!("stuck {} of missing {}", stuck.len(), report.missing_edges);
    let m = |i: u32| sv[i as usize].0;
    for e in stuck.iter().take(3) {
        let Entity::Edge(a, b, _) = *e else { continue };
        let (a, b) = (m(a), m(b));
        let met = rec.met_tets(a, b).unwrap();
        let common: Vec<u32> = rec
            .l
            .tet(met[0])
            .iter()
            .copied()
            .filter(|v| met.iter().all(|&t| rec.l.tet(t).contains(v)))
            .collect();
        eprintln!(
            "met {} tets, common vertices {common:?}: {:?}",
            met.len(),
            met.iter().map(|&t| rec.l.tet(t)).collect::<Vec<_>>()
        );
        let mut star = Vec::new();
        for (f, t) in [(a, b), (b, a)] {
            let c = recover::first_crossing(&rec.l, f, t, &mut star);
            eprintln!("edge {a}-{b} from {f}: {c:?}");
            match c {
                recover::Crossing::Edge(x, y) => {
                    let mut sc = Vec::new();
                    let ring = rec.l.ring(x, y, &mut sc).unwrap();
                    let locked = rec.locks.edge(x, y);
                    eprintln!(
                        "  ring of {x}-{y} (locked {locked}): {:?}",
                        ring.iter().map(|r| r.1).collect::<Vec<_>>()
                    );
                }
                recover::Crossing::Face(t, i) => {
                    let v = rec.l.tet(t);
                    let nb = crate::tetmesh::FaceRef::from_raw(rec.l.adj(t)[i]);
                    let e = rec.l.tet(nb.tet().0)[nb.facet()];
                    let fv = crate::tetmesh::FACE_VERTICES[i].map(|k| v[k]);
                    let sides: Vec<_> = (0..3)
                        .map(|k| rec.l.orient(fv[k], fv[(k + 1) % 3], v[i], e))
                        .collect();
                    let locked: Vec<_> = (0..3)
                        .map(|k| rec.locks.edge(fv[k], fv[(k + 1) % 3]))
                        .collect();
                    eprintln!(
                        "  face {fv:?} apex {} other {e}: sides {sides:?} locked {locked:?}",
                        v[i]
                    );
                    for k in 0..3 {
                        let mut sc = Vec::new();
                        if let Some(ring) = rec.l.ring(fv[k], fv[(k + 1) % 3], &mut sc) {
                            eprintln!(
                                "   ring of {}-{}: {:?}",
                                fv[k],
                                fv[(k + 1) % 3],
                                ring.iter().map(|r| r.1).collect::<Vec<_>>()
                            );
                        }
                    }
                }
                _ => {}
            }
        }
    }
}

/// The live tets as sorted vertex tuples, sorted.
fn tet_set(mesh: &TetMesh) -> Vec<[u32; 4]> {
    let mut out: Vec<[u32; 4]> = mesh
        .tets()
        .map(|t| {
            let mut v = mesh.raw_tet(t.0);
            v.sort_unstable();
            v
        })
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn a_long_chain_of_changes_is_undone_exactly_and_leaves_no_stamp() {
    // Flips and vertex removals (a star of many tets replaced by a smaller cone: many
    // slots freed at once, then taken again by the undo, in the same order).
    let (mesh, _, _) = delaunay(&icosphere(2), &[], &BoundaryOptions::default()).unwrap();
    let before = tet_set(&mesh);
    // Slot by slot, with the neighbours: the undo puts every tet back in its own slot
    // (it relies on that to restore the neighbour handles as they were).
    let cells = |m: &crate::tetmesh::TetMesh| -> Vec<(u32, [u32; 4], [u32; 4])> {
        (0..m.num_slots() as u32)
            .filter(|&t| m.is_alive(crate::tetmesh::TetId(t)))
            .map(|t| (t, m.raw_tet(t), m.raw_adj(t)))
            .collect()
    };
    let slots = cells(&mesh);
    let mut rec = Recovery::new(Local::new(mesh));
    let clock = rec.l.stamps.clock;
    let verts: Vec<u32> = (8..rec.l.mesh.num_vertices() as u32).collect();
    let mark = rec.l.mark();
    let mut changes = 0;
    for (k, &v) in verts.iter().enumerate() {
        if k % 3 == 0 && rec.remove_vertex(v) {
            changes += 1;
            continue;
        }
        let t = rec.l.mesh.finite_tets().nth(k * 7).map(|t| t.0);
        if let Some(t) = t {
            if flips::flip23(&mut rec.l, &rec.locks, t, k % 4, &mut rec.flips).is_ok() {
                changes += 1;
            }
        }
    }
    assert!(changes > 20, "{changes}");
    rec.l.mesh.validate(false).unwrap();
    rec.l.undo(mark);
    rec.l.forget();
    rec.l.mesh.validate(false).unwrap();
    assert_eq!(tet_set(&rec.l.mesh), before);
    assert_eq!(cells(&rec.l.mesh), slots);
    let all: Vec<u32> = (0..rec.l.mesh.num_vertices() as u32).collect();
    assert!(!rec.l.stamps.changed_since(&all, clock));
}

/// The walks of `first_crossing` and `met_tets` agree with a scan of the whole star,
/// on meshes with many degenerate (coplanar, cospherical) configurations.
#[test]
fn walks_in_the_star_agree_with_the_whole_star() {
    use crate::geom::predicates::Orientation;
    for s in [cube(3), icosphere(1), torus(12, 6, 2.0, 0.5)] {
        let (mesh, sv, _) = delaunay(&s, &[], &BoundaryOptions::default()).unwrap();
        let l = Local::new(mesh);
        let (mut star, mut out) = (Vec::new(), Vec::new());
        let n = sv.len();
        for i in 0..n {
            for j in (0..n).step_by(3) {
                let (a, b) = (sv[i].0, sv[j].0);
                if a == b {
                    continue;
                }
                // Reference: the tets of the star whose closed cone holds b, in the
                // star's order, and the crossing at the first of them.
                l.star(a, &mut star);
                let at_a: Vec<u32> = star
                    .iter()
                    .copied()
                    .filter(|&t| {
                        l.cone_signs(t, a, b)
                            .is_some_and(|(_, s)| !s.contains(&Orientation::Positive))
                    })
                    .collect();
                assert!(l.met_tets(a, b, 1 << 20, &mut out, &mut star));
                assert_eq!(out[..at_a.len()], at_a[..], "met_tets {a}-{b}");
                let c = recover::first_crossing(&l, a, b, &mut star);
                let present = at_a.iter().any(|&t| l.tet(t).contains(&b));
                match c {
                    recover::Crossing::Present => assert!(present, "{a}-{b}"),
                    recover::Crossing::Face(t, _) => assert_eq!(at_a, vec![t], "{a}-{b}"),
                    _ => assert!(!present && at_a.len() > 1, "{a}-{b}: {c:?}"),
                }
            }
        }
    }
}

#[test]
fn only_ring_vertices_that_fold_the_ring_may_block_an_edge_removal() {
    // Edge xy along z through a ring A -> R -> B -> C (counterclockwise seen from y,
    // so that the ring tets (x, y, p_i, p_i+1) are positive) in z = 0; R is pulled
    // towards the edge past the chord AB (a reflex ring vertex), B is convex.
    let pts = vec![
        Point::new(0.0, 0.0, -1.0),  // 0: x
        Point::new(0.0, 0.0, 1.0),   // 1: y
        Point::new(1.0, 1.0, 0.0),   // 2: A
        Point::new(-1.0, 1.0, 0.0),  // 3: B
        Point::new(0.0, 0.5, 0.0),   // 4: R
        Point::new(-1.0, -1.0, 0.0), // 5: C
        Point::new(0.0, 1.0, 5.0),   // 6: T, making a steep ear with A and B
    ];
    let mesh = crate::tetmesh::TetMesh::from_tets(pts, &[[0, 1, 2, 3]]).unwrap();
    let rec = Recovery::new(Local::new(mesh));
    assert!(rec.may_block(0, 1, 2, 4, 3), "reflex R");
    assert!(!rec.may_block(0, 1, 4, 3, 5), "convex B");
    // x and y on one side of the ear's plane: tried.
    assert!(rec.may_block(0, 1, 2, 6, 3), "steep ear at T");
}

#[test]
fn a_shuffled_edge_order_is_a_permutation_of_the_sorted_one() {
    let s = torus(24, 12, 2.0, 0.5);
    let sorted = input_edges(&s, EdgeOrder::Sorted);
    let mut shuffled = input_edges(&s, EdgeOrder::Shuffled(7));
    assert_ne!(shuffled, sorted);
    assert_eq!(shuffled, input_edges(&s, EdgeOrder::Shuffled(7)), "seeded");
    shuffled.sort_unstable();
    assert_eq!(shuffled, sorted);
}

#[test]
fn a_failed_recovery_is_retried_in_other_orders_then_with_rebuilds() {
    let opts = BoundaryOptions::default();
    let all = attempt_options(&opts);
    assert_eq!(all.len(), 2 + ORDER_RETRIES as usize);
    assert_eq!(all[0].edge_order, EdgeOrder::Sorted);
    assert!(all[0].check_input && all[1..].iter().all(|o| !o.check_input));
    let seeds: Vec<EdgeOrder> = all[1..=ORDER_RETRIES as usize]
        .iter()
        .map(|o| o.edge_order)
        .collect();
    assert!(seeds.iter().all(|o| matches!(o, EdgeOrder::Shuffled(_))));
    assert!(seeds.windows(2).all(|w| w[0] != w[1]));
    assert!(all[..=ORDER_RETRIES as usize].iter().all(|o| o.incremental));
    assert!(!all.last().unwrap().incremental);
    // A recovery that rebuilds already has nothing to fall back on.
    let rebuilding = BoundaryOptions {
        incremental: false,
        ..opts
    };
    assert_eq!(attempt_options(&rebuilding).len(), 1);
}

#[test]
fn input_edges_are_the_sorted_unique_edges_with_their_first_triangle() {
    let s = torus(24, 12, 2.0, 0.5);
    let mut all: Vec<(u32, u32, u32)> = Vec::new();
    for (k, t) in s.triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            all.push((a.min(b), a.max(b), k as u32));
        }
    }
    all.sort_unstable();
    all.dedup_by_key(|x| (x.0, x.1));
    assert_eq!(input_edges(&s, EdgeOrder::Sorted), all);
}

#[test]
fn crossing_points_are_kept_off_the_faces_of_their_edge() {
    let s = cube(2);
    let [a, b, _] = s.triangles[0];
    let (pa, pb) = (s.vertices[a as usize], s.vertices[b as usize]);
    let len = (pb - pa).length();
    let tris: Vec<_> = s
        .triangles
        .iter()
        .filter(|t| t.contains(&a) && t.contains(&b))
        .collect();
    assert_eq!(tris.len(), 2);
    let mid = (pa + pb) * 0.5;
    // On the edge itself (on both planes), just off it, and well clear.
    let inward = -tris
        .iter()
        .map(|t| {
            let [p, q, r] = t.map(|i| s.vertices[i as usize]);
            (q - p).cross(r - p).normalize()
        })
        .sum::<Point>()
        .normalize();
    let far = mid + inward * 0.3 * len;
    let moved = clear_of_faces(
        &super::split::Refined::new(&s),
        a,
        b,
        vec![mid, mid + inward * 1e-9, far],
    );
    for x in &moved[..2] {
        for t in &tris {
            let [p, q, r] = t.map(|i| s.vertices[i as usize]);
            let n = (q - p).cross(r - p).normalize();
            assert!(
                n.dot(*x - pa).abs() >= 0.99 * STEINER_CLEARANCE * len,
                "{x:?}"
            );
        }
    }
    assert_eq!(moved[2], far, "a point clear of the faces stays");
}

/// The domain patched after local changes ([`domain::patched`]) is the domain
/// identified from scratch; with no tet kept from before there is nothing to patch
/// from, and the caller identifies from scratch.
#[test]
fn a_patched_domain_is_the_domain_identified_again() {
    let (bm, _) = check(&torus(24, 12, 2.0, 0.5));
    let faces: Vec<[u32; 3]> = bm.faces.iter().map(|f| f.map(|v| v.0)).collect();
    let is_input = |f: [u32; 3]| bm.constrained.contains_key(&sorted_ids(f));
    let marks = Local::new(bm.mesh.clone()).triangle_faces(&faces);
    let before = domain::identify(&bm.mesh, &marks).unwrap();
    let mut snapshot = vec![[u32::MAX; 4]; bm.mesh.num_slots()];
    for t in bm.mesh.finite_tets() {
        snapshot[t.index()] = bm.mesh.raw_tet(t.0);
    }
    // 2-3 flips of free faces, inside the domain and outside it.
    let mut l = Local::new(bm.mesh.clone());
    let locks = Locks::of_faces(&faces);
    let mut counts = FlipCounts::default();
    let mut flipped = [0, 0];
    for t in bm.mesh.finite_tets() {
        for i in 0..4 {
            let inside = (before.region[t.index()] != 0) as usize;
            if flipped[inside] < 10
                && l.mesh.is_alive(t)
                && flip23(&mut l, &locks, t.0, i, &mut counts).is_ok()
            {
                flipped[inside] += 1;
            }
        }
    }
    assert_eq!(flipped, [10, 10]);
    let mesh = l.mesh;
    let marks = Local::new(mesh.clone()).triangle_faces(&faces);
    let again = domain::identify(&mesh, &marks).unwrap();
    let patched = domain::patched(&mesh, &before, &snapshot, is_input).unwrap();
    assert_eq!(patched.region, again.region);
    assert_eq!((patched.count, patched.tets), (again.count, again.tets));
    assert!((patched.volume - again.volume).abs() <= 1e-12 * again.volume.abs());
    assert!(domain::patched(&mesh, &before, &[], is_input).is_none());
}
