//! Property tests of the per-tet measures (paper §6.1) and of the target quality (§8).

use glam::{DQuat, DVec3};
use mesher::quality::*;
use mesher::Point;
use proptest::prelude::*;

fn point() -> impl Strategy<Value = Point> {
    (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64).prop_map(|(x, y, z)| Point::new(x, y, z))
}

fn tet() -> impl Strategy<Value = [Point; 4]> {
    [point(), point(), point(), point()]
}

/// A rigid motion followed by a uniform scaling.
fn similarity() -> impl Strategy<Value = (DQuat, Point, f64)> {
    (point(), -3.0..3.0f64, point(), -3.0..3.0f64).prop_map(|(axis, angle, t, log_s)| {
        let axis = if axis.length() > 1e-3 {
            axis.normalize()
        } else {
            DVec3::X
        };
        (
            DQuat::from_axis_angle(axis, angle),
            t * 100.0,
            10f64.powf(log_s),
        )
    })
}

fn apply(p: Point, (r, t, s): (DQuat, Point, f64)) -> Point {
    (r * p) * s + t
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs())
}

fn regular() -> [Point; 4] {
    [
        Point::new(1.0, -1.0, -1.0),
        Point::new(1.0, 1.0, 1.0),
        Point::new(-1.0, 1.0, -1.0),
        Point::new(-1.0, -1.0, 1.0),
    ]
}

proptest! {
    #[test]
    fn q_k_is_at_least_one(p in tet()) {
        let q = q_k(&p);
        prop_assert!(q >= 1.0 - 1e-12, "{q}");
        let r = radius_ratio(&p);
        prop_assert!((0.0..=1.0).contains(&r));
        let m = TetMeasures::new(&p);
        prop_assert_eq!(m.q_k, q);
        prop_assert!(m.min_dihedral >= 0.0 && m.max_dihedral <= 180.0);
        prop_assert!(m.min_dihedral <= 70.53 + 1e-9 && m.max_dihedral >= 70.52);
    }

    #[test]
    fn measures_invariant_under_similarity(p in tet(), sim in similarity()) {
        let m = TetMeasures::new(&p);
        prop_assume!(m.q_k < 1e3);
        let moved = p.map(|x| apply(x, sim));
        let n = TetMeasures::new(&moved);
        prop_assert!(rel(m.q_k, n.q_k) < 1e-8, "{} {}", m.q_k, n.q_k);
        prop_assert!(rel(m.radius_ratio, n.radius_ratio) < 1e-7);
        prop_assert!((m.min_dihedral - n.min_dihedral).abs() < 1e-6);
        prop_assert!((m.max_dihedral - n.max_dihedral).abs() < 1e-6);
        prop_assert!(rel(m.h_max * sim.2, n.h_max) < 1e-10);
        prop_assert!(rel(m.volume * sim.2.powi(3), n.volume) < 1e-7);
    }

    #[test]
    fn orientation_only_changes_the_volume_sign(p in tet()) {
        let mut q = p;
        q.swap(2, 3);
        let (m, n) = (TetMeasures::new(&p), TetMeasures::new(&q));
        prop_assert_eq!(m.volume, -n.volume);
        prop_assert!(m.q_k == n.q_k || rel(m.q_k, n.q_k) < 1e-10);
        prop_assert!(m.is_degenerate() || m.is_inverted() != n.is_inverted());
    }

    #[test]
    fn regular_tet_dihedrals(sim in similarity()) {
        let p = regular().map(|x| apply(x, sim));
        let want = (1.0f64 / 3.0).acos().to_degrees();
        for a in dihedral_angles(&p) {
            prop_assert!((a - want).abs() < 1e-6, "{a}");
        }
        prop_assert!((q_k(&p) - 1.0).abs() < 1e-8);
        prop_assert!((radius_ratio(&p) - 1.0).abs() < 1e-8);
    }

    #[test]
    fn face_best_is_invariant(a in point(), b in point(), c in point(), sim in similarity()) {
        let q = face_best_q_k(a, b, c);
        prop_assume!(q < 1e3);
        prop_assert!(q >= 1.0 - 1e-9);
        let perms = [(b, c, a), (c, a, b), (b, a, c), (a, c, b), (c, b, a)];
        for (x, y, z) in perms {
            let r = face_best_q_k(x, y, z);
            prop_assert!(rel(q, r) < 1e-5, "{q} {r}");
        }
        let m = face_best_q_k(apply(a, sim), apply(b, sim), apply(c, sim));
        prop_assert!(rel(q, m) < 1e-5, "{q} {m}");
    }
}
