//! What the domain leaves room for: the target quality `Q_t` of paper §8 with the apex
//! of each face's best tet kept inside the domain.
//!
//! `Q_t` takes, per boundary face, the best `Q_K` of a tet on it over every apex
//! ([`super::target`]). A mesh that keeps the boundary has one tet on each face, on the
//! domain's side, lying in the domain: where the domain is thinner than the face's best
//! tet is tall (a gap between two walls, a thin tube, a needle face across a slot), no
//! mesher reaches the per-face term. Here the term is the best `Q_K` over the apexes
//! whose tet meets the surface only along the face: each face's best apex first (when
//! its tet fits, the term is `Q_t`'s), else a search over lower and shifted apexes.
//!
//! The tet fits when none of its three other faces meets a surface triangle (other than
//! along the vertices or edge they share by index, exact predicates of
//! [`crate::surface::intersect`]) and no surface vertex lies strictly inside it. The
//! domain's side of each face comes from its shell's orientation and nesting depth
//! (the domain is inside the shells of even depth).
//!
//! Where the best apex's tet does not fit, a search: apexes lower in its column and the
//! centroid's (heights down to `2^-30` of its own), random apexes over the half ball of
//! the longest edge on the domain's side, compass searches from the best three (every
//! step kept only if its tet fits), and the surface's own vertices near the face (a tet
//! of four surface vertices: on CAD models often the best), nearest first. The term is
//! the value at an actual apex: an estimate from above of the true constrained minimum,
//! which a better search could only lower, so a lower bound of the worst `Q_K` of a
//! boundary-keeping mesh only up to the search's accuracy. Measured against our own
//! meshes (the tet each keeps on a face must not beat the face's term): none does by
//! more than 5e-5 relative on the CAD models of the ci tier and turbine; on cheese 8
//! faces of 17 786 do, by up to 16 % (interior apexes the search missed). The reports call it
//! an estimate.

use super::target::{face_best_apex, face_best_q_k, local_face_frame, ApexQuality};
use crate::geom::predicates::{orient3d, Orientation};
use crate::geom::search::compass;
use crate::geom::Point;
use crate::surface::bvh::{Box3, Bvh};
use crate::surface::intersect::faces_intersect;
use crate::surface::report::CheckReport;
use crate::surface::Surface;
use rayon::prelude::*;

/// Result of [`target_quality_in_domain`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RoomQuality {
    /// The largest in-domain term over the faces (>= `Q_t`).
    #[serde(with = "crate::quality::histogram::nonfinite")]
    pub q_t: f64,
    /// The face reaching it (the first one on ties).
    pub worst_face: Option<usize>,
    /// Faces whose best tet does not fit in the domain (their term exceeds `Q_t`'s).
    pub limited_faces: usize,
    /// Faces whose in-domain term is above [`super::WELL_SHAPED_Q_K`].
    pub hard_faces: usize,
}

/// Apex id of the tested tet: no surface vertex has it.
const APEX: u32 = u32::MAX;

/// Height factors tried below the best apex: `HEIGHT_RATIO^k`, `k = 1..=HEIGHT_STEPS`.
const HEIGHT_RATIO: f64 = 0.5;
const HEIGHT_STEPS: i32 = 30;

/// Surface vertices within this many longest edges of a limited face's centroid are
/// tried as apexes.
const VERTEX_REACH: f64 = 2.0;

/// At most this many vertex apexes (the nearest first) are tested per limited face.
const MAX_VERTEX_APEXES: usize = 128;

/// Random apexes tried per limited face, and the best of them (with the column's
/// best) from which compass searches start.
const RANDOM_STARTS: usize = 32;
const COMPASS_STARTS: usize = 3;

/// The in-domain target quality of a clean, closed surface, `report` its
/// [`Surface::check`] (`None` when the report is not clean: the domain's side of a face
/// is then undefined). Deterministic; parallel over the faces.
pub fn target_quality_in_domain(surface: &Surface, report: &CheckReport) -> Option<RoomQuality> {
    let side = domain_sides(report)?;
    let room = Room::new(surface);
    let terms: Vec<(f64, bool)> = (0..surface.triangles.len())
        .into_par_iter()
        .with_min_len(256)
        .map(|f| room.face_term(f, side[f]))
        .collect();
    let mut out = RoomQuality {
        q_t: 1.0,
        worst_face: None,
        limited_faces: 0,
        hard_faces: 0,
    };
    for (f, &(q, limited)) in terms.iter().enumerate() {
        if out.worst_face.is_none() || q > out.q_t {
            (out.q_t, out.worst_face) = (q, Some(f));
        }
        out.limited_faces += usize::from(limited);
        out.hard_faces += usize::from(q > super::WELL_SHAPED_Q_K);
    }
    Some(out)
}

/// Per face, the sign of its normal `(b - a) x (c - a)` that points into the domain:
/// inwards on a shell of even nesting depth, outwards on one of odd depth (a cavity),
/// whichever way the shell's faces turn.
fn domain_sides(report: &CheckReport) -> Option<Vec<f64>> {
    if !report.is_clean() {
        return None;
    }
    let shell_side: Vec<Option<f64>> = report
        .shells
        .iter()
        .map(|s| {
            let outward = if s.signed_volume > 0.0 { 1.0 } else { -1.0 };
            let inside = if s.depth? % 2 == 0 { 1.0 } else { -1.0 };
            Some(-outward * inside)
        })
        .collect();
    report
        .face_shell
        .iter()
        .map(|&sh| shell_side.get(sh as usize).copied().flatten())
        .collect()
}

/// The surface with a hierarchy over its triangles.
struct Room<'a> {
    surface: &'a Surface,
    bvh: Bvh,
}

impl<'a> Room<'a> {
    fn new(surface: &'a Surface) -> Self {
        let items = surface
            .triangles
            .iter()
            .enumerate()
            .map(|(k, t)| (k as u32, bounds(&t.map(|i| surface.vertices[i as usize]))))
            .collect();
        Room {
            surface,
            bvh: Bvh::build(items),
        }
    }

    /// The in-domain term of face `f` with the domain on `side` of its normal, and
    /// whether its best tet did not fit.
    fn face_term(&self, f: usize, side: f64) -> (f64, bool) {
        let ids = self.surface.triangles[f];
        let [a, b, c] = ids.map(|i| self.surface.vertices[i as usize]);
        let (Some((apex, free)), Some((local, frame))) =
            (face_best_apex(a, b, c, side), local_face_frame(a, b, c))
        else {
            return (face_best_q_k(a, b, c), false);
        };
        if self.fits(f, apex) {
            return (free, false);
        }
        let quality = ApexQuality::new(&local);
        let value = |p: Point| {
            if p.z.is_nan() || p.z <= 0.0 {
                return f64::INFINITY;
            }
            let q = quality.q_k(p);
            if q.is_finite() && self.fits(f, frame.to_world(p, side)) {
                q
            } else {
                f64::INFINITY
            }
        };
        let l = (0..3)
            .map(|i| local[i].distance(local[(i + 1) % 3]))
            .fold(0.0, f64::max);
        let starts = search_starts(&value, frame.to_local(apex, side), l, f as u64);
        let searched = starts
            .iter()
            .take(COMPASS_STARTS)
            .map(|&(v, p)| compass(value, p, v, 0.5 * p.z.max(1e-3)).0)
            .fold(f64::INFINITY, f64::min);
        // The surface's own vertices near the face are apexes too (a tet of four
        // surface vertices, its side faces on the surface: on CAD models the best one).
        (
            searched
                .min(self.vertex_apexes(f, side, searched))
                .max(free),
            true,
        )
    }

    /// The best `Q_K` below `below` over the surface vertices within [`VERTEX_REACH`]
    /// longest edges of face `f`'s centroid, on the domain's side, whose tet fits
    /// (infinite if none).
    fn vertex_apexes(&self, f: usize, side: f64, below: f64) -> f64 {
        let s = self.surface;
        let ids = s.triangles[f];
        let [a, b, c] = ids.map(|i| s.vertices[i as usize]);
        let reach = VERTEX_REACH * a.distance(b).max(b.distance(c)).max(c.distance(a));
        let g = (a + b + c) / 3.0;
        let around = Box3 {
            min: (g - Point::splat(reach)).to_array(),
            max: (g + Point::splat(reach)).to_array(),
        };
        let mut near: Vec<u32> = Vec::new();
        self.bvh
            .query(&around, |k| near.extend(s.triangles[k as usize]));
        near.sort_unstable();
        near.dedup();
        let normal = (b - a).cross(c - a) * side;
        // Nearest first (the far ones are mostly behind a wall), each tested only if
        // it would beat the best so far.
        let mut cand: Vec<(f64, f64, u32)> = near
            .iter()
            .filter(|v| !ids.contains(v))
            .filter_map(|&v| {
                let p = s.vertices[v as usize];
                let q = super::q_k(&[a, b, c, p]);
                let inward = normal.dot(p - a) > 0.0;
                (inward && q < below).then_some((p.distance(g), q, v))
            })
            .collect();
        cand.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.2.cmp(&y.2)));
        let mut best = f64::INFINITY;
        let mut tests = 0;
        for (_, q, v) in cand {
            if q >= best {
                continue;
            }
            if tests == MAX_VERTEX_APEXES {
                break;
            }
            tests += 1;
            if self.fits_apex(f, s.vertices[v as usize], v) {
                best = q;
            }
        }
        best
    }

    /// Whether the tet on face `f` with apex `p` meets the surface only along `f`.
    fn fits(&self, f: usize, p: Point) -> bool {
        self.fits_apex(f, p, APEX)
    }

    /// [`Room::fits`] for an apex with vertex id `apex` ([`APEX`] for a new point).
    fn fits_apex(&self, f: usize, p: Point, apex: u32) -> bool {
        let s = self.surface;
        let ids = s.triangles[f];
        let [a, b, c] = ids.map(|i| s.vertices[i as usize]);
        let tet = [a, b, c, p];
        let sides = [
            ([a, b, p], [ids[0], ids[1], apex]),
            ([b, c, p], [ids[1], ids[2], apex]),
            ([c, a, p], [ids[2], ids[0], apex]),
        ];
        let mut fits = true;
        self.bvh.query(&bounds(&tet), |k| {
            if !fits || k as usize == f {
                return;
            }
            let t = s.triangles[k as usize];
            let q = t.map(|i| s.vertices[i as usize]);
            // A side face that is this surface triangle lies on the boundary: the tet
            // touches it from inside (two of its faces on the surface).
            let same = |xi: &[u32; 3]| xi.iter().all(|v| t.contains(v));
            fits = !sides
                .iter()
                .any(|(x, xi)| !same(xi) && faces_intersect(x, *xi, &q, t))
                && !t.iter().any(|&v| {
                    v != apex && !ids.contains(&v) && strictly_inside(&tet, s.vertices[v as usize])
                });
        });
        fits
    }
}

/// Starts of the compass searches for a face whose best apex `top` (local frame) does
/// not fit, best first: the best fitting apex below `top` or the centroid (heights
/// halved down to `2^-HEIGHT_STEPS`), then [`RANDOM_STARTS`] random apexes over the
/// half box of side `l` (the longest edge) on the domain's side, seeded by `seed`
/// (the feasible set can lie away from the column: a slot beside the face). Only
/// fitting ones (finite value) are kept.
fn search_starts(
    value: &impl Fn(Point) -> f64,
    top: Point,
    l: f64,
    seed: u64,
) -> Vec<(f64, Point)> {
    let mut best = (f64::INFINITY, top);
    for k in 1..=HEIGHT_STEPS {
        let z = top.z * HEIGHT_RATIO.powi(k);
        for p in [Point::new(top.x, top.y, z), Point::new(0.0, 0.0, z)] {
            let v = value(p);
            if v < best.0 {
                best = (v, p);
            }
        }
        if best.0.is_finite() && k > 2 && best.1.z > 2.0 * z {
            break;
        }
    }
    let mut rng = crate::delaunay::sort::SplitMix64::new(seed ^ 0x5EED_0000);
    let mut unit = || rng.unit();
    let mut starts: Vec<(f64, Point)> = vec![best];
    for _ in 0..RANDOM_STARTS {
        let p = Point::new(
            (2.0 * unit() - 1.0) * l,
            (2.0 * unit() - 1.0) * l,
            unit() * l,
        );
        let v = value(p);
        if v.is_finite() {
            starts.push((v, p));
        }
    }
    starts.retain(|s| s.0.is_finite());
    starts.sort_by(|x, y| x.0.total_cmp(&y.0));
    starts
}

/// Whether `v` lies strictly inside the tet `t` (exact orientations).
fn strictly_inside(t: &[Point; 4], v: Point) -> bool {
    let faces = [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)];
    faces.iter().all(|&(i, j, k, m)| {
        let inner = orient3d(t[i], t[j], t[k], t[m]);
        inner != Orientation::Zero && orient3d(t[i], t[j], t[k], v) == inner
    })
}

/// Bounding box of points.
fn bounds(p: &[Point]) -> Box3 {
    let mut b = Box3::EMPTY;
    for q in p {
        b = b.union(&Box3 {
            min: [q.x, q.y, q.z],
            max: [q.x, q.y, q.z],
        });
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::generate;

    fn scaled(mut s: Surface, k: Point) -> Surface {
        for v in &mut s.vertices {
            *v *= k;
        }
        s
    }

    #[test]
    fn a_round_body_leaves_room_for_every_best_tet() {
        for s in [generate::icosphere(2), generate::torus(24, 12, 2.0, 0.7)] {
            let free = super::super::target_quality(&s.vertices, &s.triangles).q_t;
            let r = target_quality_in_domain(&s, &s.check()).unwrap();
            assert_eq!(r.limited_faces, 0);
            assert_eq!(r.q_t, free);
        }
    }

    #[test]
    fn a_thin_slab_limits_its_big_faces() {
        // A unit cube of 4 x 4 squares per side, flattened to a hundredth: the best tet
        // on a top square's half stands 0.2 high, the slab is 0.01 thick.
        let s = scaled(generate::cube(4), Point::new(1.0, 1.0, 0.01));
        let free = super::super::target_quality(&s.vertices, &s.triangles).q_t;
        let r = target_quality_in_domain(&s, &s.check()).unwrap();
        assert!(r.limited_faces >= 64, "{r:?}");
        assert!(r.q_t >= free && r.q_t.is_finite());
        // Each top and bottom face: about 8 in the slab against 1.2 in free space.
        let (room, sides) = (Room::new(&s), domain_sides(&s.check()).unwrap());
        for (f, t) in s.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| s.vertices[i as usize]);
            if (b - a).cross(c - a).normalize().z.abs() > 0.99 {
                let (term, limited) = room.face_term(f, sides[f]);
                let alone = face_best_q_k(a, b, c);
                assert!(
                    limited && term > 5.0 * alone,
                    "face {f}: {term} against {alone}"
                );
            }
        }
        // The same slab turned inside out (a cavity in space) is the same domain's
        // complement: the faces then have room on the other side.
        let mut inside_out = s.clone();
        for t in &mut inside_out.triangles {
            t.swap(1, 2);
        }
        let r2 = target_quality_in_domain(&inside_out, &inside_out.check()).unwrap();
        assert_eq!(
            r2.q_t, r.q_t,
            "orientation decides nothing: the nesting does"
        );
    }

    #[test]
    fn an_open_surface_has_no_domain() {
        let mut s = generate::cube(2);
        s.triangles.pop();
        assert!(target_quality_in_domain(&s, &s.check()).is_none());
    }

    /// Prints `Q_t` and the in-domain `Q_t` of the surfaces in `ROOM_FILES` (commas).
    #[test]
    #[ignore]
    fn print_room_of_files() {
        let Ok(list) = std::env::var("ROOM_FILES") else {
            return;
        };
        for path in list.split(',') {
            let s = crate::io::read_surface(std::path::Path::new(path))
                .unwrap()
                .surface;
            let t0 = std::time::Instant::now();
            let q = super::super::target_quality(&s.vertices, &s.triangles);
            let r = target_quality_in_domain(&s, &s.check()).unwrap();
            if let Ok(out) = std::env::var("ROOM_TERMS") {
                let (room, sides) = (Room::new(&s), domain_sides(&s.check()).unwrap());
                let terms: Vec<String> = (0..s.triangles.len())
                    .map(|f| format!("{}", room.face_term(f, sides[f]).0))
                    .collect();
                std::fs::write(out, terms.join("\n")).unwrap();
            }
            eprintln!(
                "{path}: Q_t {:.3} (face {:?}) in domain {:.3} (face {:?}), limited {} hard {} of {}; {:.3} s",
                q.q_t,
                q.worst_face,
                r.q_t,
                r.worst_face,
                r.limited_faces,
                r.hard_faces,
                s.triangles.len(),
                t0.elapsed().as_secs_f64()
            );
        }
    }
}
