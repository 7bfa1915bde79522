//! The whole mesher (paper §2-§5) end to end: boundary mesh, control space, field
//! points by the advancing front. Every mesh is checked: valid adjacency, every tet
//! positive, the domain's boundary faces exactly the input triangles, volume equal to
//! the enclosed volume, the front converged. Real models come from `corpus/cache`
//! (`scripts/fetch-corpus.sh`); without them those tests skip with a message, except
//! under CI where they fail.

use mesher::front::{FrontParams, Remedial};
use mesher::geom::Point;
use mesher::surface::generate::{cube, hollow, icosphere, torus};
use mesher::{mesh, Meshed, Params, Report, SizeSpec, Surface};

mod common;
use common::{boundary_faces, corpus, sorted_triangles};

/// Meshes `s` and checks every property; returns the mesh and the report.
fn check(name: &str, s: &Surface, params: &Params) -> (Meshed, Report) {
    let (m, r) = mesh(s, params).unwrap_or_else(|e| panic!("{name}: {e}"));
    m.mesh
        .validate(false)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(r.front.converged, "{name}: the front did not converge");
    let vm = m.to_volume_mesh();
    assert_eq!(&vm.vertices[..s.vertices.len()], &s.vertices[..], "{name}");
    assert_eq!(
        boundary_faces(&vm),
        sorted_triangles(&s.triangles),
        "{name}"
    );
    let volume = vm.volume();
    let enclosed = r.boundary.enclosed_volume;
    assert!(
        ((volume - enclosed) / enclosed).abs() < 1e-9,
        "{name}: volume {volume} vs enclosed {enclosed}"
    );
    assert_eq!(vm.tets.len(), r.tets, "{name}");
    if let Some(o) = &r.optimize {
        // The optimisation (paper §6) never raises the worst Q_K.
        assert!(o.worst_after <= o.worst_before, "{name}: {o:?}");
    }
    (m, r)
}

#[test]
fn generated_shapes() {
    for (name, s) in [
        ("sphere", icosphere(3)),
        ("cube", cube(4)),
        ("torus", torus(32, 12, 2.0, 0.6)),
    ] {
        let (m, r) = check(name, &s, &Params::default());
        assert!(
            r.front.iterations.len() <= 30,
            "{name}: {}",
            r.front.iterations.len()
        );
        assert!(r.vertices > s.vertices.len(), "{name}: no field point");
        let band = m.edge_band();
        assert!(band.in_band_percent >= 90.0, "{name}: {band:?}");
    }
}

/// Gradation control: a coarse outer sphere (level 1) around a fine inner one (level
/// 3) close to it; the graded sizes keep the outer vertices' size out of the gap, so
/// the mesh is finer there (more tets) and still valid, with the boundary kept.
#[test]
fn graded_sizes_fill_a_narrow_gap_more_finely() {
    let s = hollow(&icosphere(1), &icosphere(3), 0.8);
    let (_, plain) = check("gap", &s, &Params::default());
    let graded = Params {
        gradation: Some(0.3),
        ..Params::default()
    };
    let (_, r) = check("gap, graded", &s, &graded);
    assert!(
        r.tets > plain.tets,
        "{} tets graded, {} not",
        r.tets,
        plain.tets
    );
    let bad = Params {
        gradation: Some(0.0),
        ..Params::default()
    };
    let e = mesh(&s, &bad).expect_err("a zero gradation is refused");
    assert!(e.to_string().contains("gradation"), "{e}");
}

#[test]
fn nested_spheres_fill_the_shell() {
    let s = hollow(&icosphere(3), &icosphere(2), 0.5);
    let (m, _) = check("nested spheres", &s, &Params::default());
    // No field point inside the hole.
    let vm = m.to_volume_mesh();
    assert!(vm.vertices.iter().all(|p| p.length() > 0.5 - 1e-9));
}

#[test]
fn constant_size_on_a_cube_gives_unit_edges() {
    let s = cube(8);
    let params = Params {
        size: SizeSpec::Constant(0.125),
        ..Params::default()
    };
    let (m, r) = check("cube h=1/8", &s, &params);
    let band = m.edge_band();
    assert!(band.in_band_percent >= 90.0, "{band:?}");
    assert!(r.front.iterations.len() <= 30);
}

#[test]
fn background_size_map_grades_the_mesh() {
    // A background box whose size grows with x: more vertices on the fine side.
    let mut vertices = Vec::new();
    for i in 0..8 {
        vertices.push(Point::new(
            if i & 1 != 0 { 1.5 } else { -1.5 },
            if i & 2 != 0 { 1.5 } else { -1.5 },
            if i & 4 != 0 { 1.5 } else { -1.5 },
        ));
    }
    let bg = mesher::delaunay::triangulate(&vertices, &Default::default()).unwrap();
    let vm = bg.mesh.to_volume_mesh();
    let sizes: Vec<f64> = vm
        .vertices
        .iter()
        .map(|p| 0.1 + 0.1 * (p.x + 1.5))
        .collect();
    let s = icosphere(3);
    let params = Params {
        size: SizeSpec::Background { mesh: vm, sizes },
        ..Params::default()
    };
    let (m, _) = check("graded sphere", &s, &params);
    let out = m.to_volume_mesh();
    let inner = &out.vertices[s.vertices.len()..];
    let left = inner.iter().filter(|p| p.x < -0.2).count();
    let right = inner.iter().filter(|p| p.x > 0.2).count();
    assert!(left > 2 * right, "{left} {right}");
}

#[test]
fn remedial_rule_accepts_survivors() {
    // With a huge filtration distance every field point is dropped: the tets behind
    // the front survive and the remedial rule accepts them, so the front still empties
    // and the mesh is T(S,F) itself.
    let s = cube(2);
    for remedial in [Remedial::Front, Remedial::All] {
        let params = Params {
            front: FrontParams {
                delta_f: 1e3,
                delta_v: 1e3,
                remedial,
                ..FrontParams::default()
            },
            ..Params::default()
        };
        let (_, r) = check("cube, no field point", &s, &params);
        let it = &r.front.iterations;
        assert!(it.iter().all(|i| i.inserted == 0));
        assert!(it[0].remedial > 0, "{it:?}");
        assert_eq!(r.tets, r.boundary.tets);
        if remedial == Remedial::All {
            // Every tet of the domain was unacceptable and survived: one iteration.
            assert_eq!(it.len(), 1);
            assert_eq!(it[0].remedial, r.boundary.tets);
        }
    }
}

#[test]
fn piecewise_lengths_give_a_valid_mesh() {
    let s = torus(24, 10, 2.0, 0.6);
    let mut params = Params::default();
    params.front.point.mode = mesher::sizing::LengthMode::Piecewise;
    check("torus, piecewise lengths", &s, &params);
}

/// The front's departures from the paper (deeper layers, a larger delta, sparser
/// filtration) cut the iterations against the paper's parameters, and the options
/// (filtration against every unacceptable tet's vertices, a shape bound on acceptance)
/// still give a valid mesh with the boundary kept.
#[test]
fn front_defaults_take_fewer_iterations_than_the_paper_and_options_stay_valid() {
    let s = icosphere(3);
    let (_, r) = check("sphere", &s, &Params::default());
    let mut paper = Params::default();
    paper.front.layers = 1;
    paper.front.delta = std::f64::consts::SQRT_2;
    paper.front.delta_f = std::f64::consts::FRAC_1_SQRT_2;
    paper.front.delta_v = std::f64::consts::FRAC_1_SQRT_2;
    let (_, base) = check("sphere, the paper's front", &s, &paper);
    assert!(
        r.front.iterations.len() < base.front.iterations.len(),
        "{} iterations vs {}",
        r.front.iterations.len(),
        base.front.iterations.len()
    );
    let mut params = Params::default();
    params.front.filter_all_vertices = true;
    params.front.q_accept = 3.0;
    check("sphere, front options", &s, &params);
}

#[test]
fn same_input_same_bytes() {
    let s = torus(40, 8, 2.0, 0.3);
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for k in 0..2 {
        let (m, _) = mesh(&s, &Params::default()).unwrap();
        let p = dir.path().join(format!("run{k}.mesh"));
        mesher::io::write_volume(&p, &m.to_volume_mesh()).unwrap();
        files.push(std::fs::read(&p).unwrap());
    }
    assert_eq!(files[0], files[1]);
}

#[test]
fn corpus_models() {
    for rel in [
        "cgal/meshes/cube.off",
        "cgal/meshes/elephant.off",
        "cgal/meshes/knot2.off",
        "cgal/meshes/fandisk.off",
        "netgen/hinge.stl",
    ] {
        let Some(s) = corpus(rel) else { return };
        check(rel, &s, &Params::default());
    }
}

/// The optimisation lifts the slivers the front leaves on a sphere: worst Q_K from
/// unbounded to below 3 (Gmsh HXT reaches about 3.3 on such surfaces).
#[test]
fn optimisation_removes_the_slivers_of_a_sphere() {
    let s = icosphere(3);
    let (_, with) = check("sphere optimised", &s, &Params::default());
    let o = with.optimize.expect("the optimisation ran");
    assert!(o.worst_after < 3.0, "{o:?}");
    let (_, without) = check(
        "sphere raw",
        &s,
        &Params {
            optimize: false,
            ..Params::default()
        },
    );
    assert!(without.optimize.is_none());
}

/// The widening's margin over a face's own bound (1.02), with room for rounding.
const WIDENING_MARGIN: f64 = 1.02 * (1.0 + 1e-9);

/// Meshes the corpus model at `rel` (skipped when absent) with the default parameters
/// and checks that its worst Q_K after optimisation is at most `factor` Q_t.
fn worst_within(rel: &str, factor: f64) {
    let Some(s) = corpus(rel) else {
        return;
    };
    let (_, r) = check(rel, &s, &Params::default());
    assert_worst_within(rel, &s, &r, factor);
}

/// Checks that the worst Q_K after the optimisation of `s` (report `r`) is at most
/// `factor` Q_t.
fn assert_worst_within(rel: &str, s: &Surface, r: &Report, factor: f64) {
    let q_t = mesher::quality::target_quality(&s.vertices, &s.triangles).q_t;
    let o = r.optimize.as_ref().expect("the optimisation ran");
    assert!(
        o.worst_after <= factor * q_t,
        "{rel}: worst {} vs Q_t {q_t}",
        o.worst_after
    );
}

/// Regression (turbine, CGAL data): a flat tet on two coplanar boundary faces of a
/// thin blade, between neighbours almost as flat, stayed at Q_K 189,965 because the
/// polishing passes retried it alone; its neighbours must change first. The surface
/// allows Q_t = 178 there; the bar is 2 Q_t (issue 6).
#[test]
fn turbine_flat_tet_between_thin_walls_is_lifted() {
    worst_within("cgal/meshes/turbine.off", 2.0);
}

/// Regression (dino, CGAL data): a sliver of four boundary vertices with two faces on
/// a nearly flat part of the surface stayed at Q_K 47.8 (Q_t 8.97): no cavity of the
/// point insertion (the tet, its neighbours, the rings of its free edges) had a point
/// that lifts it. The cavity grown by 4 layers of face neighbours does (its kernel
/// centre, then the compass search); the worst is then 13.0, within the 2 Q_t bar of
/// issue 6.
#[test]
fn dino_sliver_under_a_flat_surface_is_lifted() {
    worst_within("cgal/meshes/dino.off", 2.0);
}

/// Regression (rotor_small, CGAL data): a free vertex 0.0026 from a cluster of boundary
/// vertices left four tets at Q_K 1097-2974 (Q_t 32.6): no smoothing target nor collapse
/// improved its ball. The last resort (a compass search for the vertex's position,
/// then a polishing pass around it) takes the worst to 80.3. Once the front's cavities
/// took in bad tets, another free vertex, 0.003 from a neighbour in a crowd of boundary
/// vertices, stayed at 2463 (its moves gained 0.1 % a round); the last resort now
/// first collapses such a vertex onto a neighbour: 37.8. With the sizes at surface
/// vertices corrected, a third, nearly in the plane of four tiny boundary faces at a
/// fold, stayed at 2459 (no collapse valid); the last resort now replaces the free
/// vertices of a cavity grown around it by one point: 35.4. The bar here is a guard
/// against the old failures (4 Q_t), not issue 6's 2 Q_t.
#[test]
fn rotor_small_vertex_crowded_by_the_boundary_is_moved() {
    worst_within("cgal/meshes/rotor_small.off", 4.0);
}

/// Regression (armadillo, CGAL data): a tet of four boundary vertices across a fold of
/// the surface (two of its faces on it) stayed at Q_K 17.8 when the front's target
/// length was 1.2: its only free edge's ring admits a cone of worst Q_K about 5, from
/// points in a lens none of the fixed candidates hit; the compass search finds one.
/// Gmsh HXT reaches 13.2 on this model (nightly tier), the bar of issue 6.
#[test]
fn armadillo_fold_tet_of_four_boundary_vertices_is_lifted() {
    let Some(s) = corpus("cgal/meshes/armadillo.off") else {
        return;
    };
    let (_, r) = check("armadillo", &s, &Params::default());
    let o = r.optimize.expect("the optimisation ran");
    assert!(o.worst_after < 13.2, "worst {}", o.worst_after);
}

/// Regression (homer, CGAL data): a free vertex between two tets at Q_K 112 (Q_t 81.3):
/// the last resort's compass search from the vertex stayed in its basin, while its ball
/// allows 78 at 0.84 of its shortest edge away. A random descent first finds it; the
/// worst is then the surface's own, Q_t, and the dihedral widening may take up to 2 %
/// of it back (82.5, for the smallest angle 0.59° -> 0.93°).
#[test]
fn homer_vertex_between_two_tets_jumps_to_a_better_basin() {
    worst_within("cgal/meshes/homer.off", WIDENING_MARGIN);
}

/// Regression (part1, Netgen data): the smallest dihedral angle, in the worst tet (on a
/// thin boundary face, Q_K 55.8 for Q_t 55.7), was 0.559°, below Gmsh HXT's 0.578°
/// (whose worst Q_K is 81.5). The last step of the optimisation moves the free vertex
/// of the tet with the smallest angle: as far as the ball's worst Q_K allows, 0.568°
/// (a random search over its ball finds no more, 0.5686°); with the 2 % margin over
/// the face's own bound that a ball at the surface's limit may use, 0.88° (0.75° on
/// later meshes). The margin stops at the mesh's worst `Q_K` now (it raised anchor's
/// worst above Gmsh HXT's): here worst 55.83, 0.64°.
#[test]
fn part1_smallest_dihedral_angle_is_widened() {
    let Some(s) = corpus("netgen/part1.stl") else {
        return;
    };
    let (m, r) = check("part1", &s, &Params::default());
    let vm = m.to_volume_mesh();
    let smallest = vm
        .tets
        .iter()
        .map(|t| mesher::quality::min_dihedral(&t.map(|v| vm.vertices[v as usize])))
        .fold(f64::INFINITY, f64::min);
    // Gmsh HXT reaches 0.578°; with the ball's worst kept, 0.568° was the most here.
    // (0.88° until the front's cavities took in bad tets, which changed the mesh
    // around that face: 0.75°; 0.64° since the margin stops at the mesh's worst.)
    assert!(smallest > 0.6, "smallest dihedral angle {smallest}°");
    // The worst tet sits on the face that sets Q_t: the widening may use 2 % of it.
    assert_worst_within("part1", &s, &r, WIDENING_MARGIN);
}

/// Seed lattices deep inside a sphere (inserted before the first front) fill the
/// interior at once: fewer iterations, less cavity work, fewer tets, the same quality.
#[test]
fn seeds_fill_the_interior_before_the_front() {
    let s = icosphere(5);
    let without = Params {
        front: FrontParams {
            seed_spacing: f64::INFINITY,
            ..FrontParams::default()
        },
        ..Params::default()
    };
    let (_, r0) = check("sphere without seeds", &s, &without);
    let (_, r1) = check("sphere with seeds", &s, &Params::default());
    assert_eq!(r0.front.seeds, 0);
    assert!(r1.front.seeds > 0);
    let its = |r: &Report| r.front.iterations.len();
    assert!(
        its(&r1) < its(&r0),
        "{} vs {} iterations",
        its(&r1),
        its(&r0)
    );
    assert!(
        r1.front.cavity_tets < r0.front.cavity_tets,
        "{} vs {}",
        r1.front.cavity_tets,
        r0.front.cavity_tets
    );
    // The lattice packs a little less densely than the front's points (sphere-10k:
    // 19 % fewer tets, closer to Gmsh HXT's count on the same sizes).
    let ratio = r1.tets as f64 / r0.tets as f64;
    assert!((0.7..1.0).contains(&ratio), "{} vs {}", r1.tets, r0.tets);
    let worst = |r: &Report| r.optimize.as_ref().unwrap().worst_after;
    assert!(
        worst(&r1) < 1.1 * worst(&r0),
        "{} vs {}",
        worst(&r1),
        worst(&r0)
    );
}

/// A torus whose quads are planar: two triangles of a quad make a flat tet in the
/// boundary mesh that no Delaunay cavity reaches (its circumball lies outside the
/// domain). The front's cavities take such tets in (`FrontParams::absorb_q_k`): before
/// optimisation none is left, where 5 % of the tets were flat without it.
#[test]
fn flat_tets_on_planar_quads_do_not_survive_the_front() {
    let s = torus(32, 12, 2.0, 0.6);
    let worst_before_opt = |absorb_q_k: f64| {
        let params = Params {
            optimize: false,
            front: FrontParams {
                absorb_q_k,
                ..FrontParams::default()
            },
            ..Params::default()
        };
        let (m, _) = check("torus", &s, &params);
        let vm = m.to_volume_mesh();
        let q = mesher::quality::summarize(&vm, None);
        (q.worst_q_k, q.well_shaped_percent)
    };
    let (worst_off, _) = worst_before_opt(f64::INFINITY);
    let (worst, well) = worst_before_opt(FrontParams::default().absorb_q_k);
    eprintln!("torus before optimisation: worst {worst_off} -> {worst}, {well} % Q_K < 3");
    assert!(worst_off > 1e3 && worst < 1e3, "{worst_off} {worst}");
    assert!(well >= 95.0, "{well}");
}
