//! Consistent orientation of a closed surface whose faces are listed either way round
//! ([`Surface::reoriented`]): a triangle soup written without regard to orientation
//! (CGAL's `cube-shuffled.off`, `blobby-shuffled.off`) bounds the same solid, and
//! TetGen meshes it. Each connected component is first turned to agree with its lowest
//! face, by a breadth-first walk across its edges; then each closed shell is turned
//! whole, if need be, so that the solid lies on its inner side: outwards for the
//! outermost shells, inwards for the cavities inside them, and so on by nesting depth
//! (then the signed volumes of the faces sum to the enclosed volume). The boundary mesh
//! does not need this (its domain is a flood fill stopped by the constrained faces,
//! paper §4.3), its report and output faces do.

use super::report::CheckReport;
use super::topology::{edge_table, scan};
use super::{shells, Surface};
use std::collections::VecDeque;

impl Surface {
    /// The surface with faces turned so that each edge is run once each way and the
    /// solid lies on the inner side of each shell (see the module doc), with the number
    /// of faces turned, when it is closed and 2-manifold (every edge in exactly two
    /// faces with valid indices), orientable, and some of its faces disagree. `None`
    /// otherwise: faces that agree are left as they are (an inward surface too, which
    /// bounds the same solid), and [`Surface::check`] reports the defects of the
    /// others.
    pub fn reoriented(&self) -> Option<(Surface, usize)> {
        let mut turn = self.turns()?;
        let mut out = self.turned(&turn);
        // Whole shells turned by nesting depth (the solid inside the outermost ones).
        let mut report = CheckReport::default();
        let status = scan(&out, &mut report);
        let table = edge_table(&out, &status);
        shells::shells(&out, &status, &table, &mut report);
        let volume = shell_volumes(&out, &report);
        let whole: Vec<bool> = report
            .shells
            .iter()
            .map(|sh| {
                sh.depth
                    .is_some_and(|d| (volume[sh.id] > 0.0) != (d % 2 == 0))
            })
            .collect();
        for ((t, flip), &sh) in out
            .triangles
            .iter_mut()
            .zip(&mut turn)
            .zip(&report.face_shell)
        {
            if whole.get(sh as usize) == Some(&true) {
                t.swap(1, 2);
                *flip = !*flip;
            }
        }
        let turned = turn.iter().filter(|&&t| t).count();
        (turned > 0).then_some((out, turned))
    }

    /// The surface with the faces `turn` marks reversed.
    fn turned(&self, turn: &[bool]) -> Surface {
        let mut out = self.clone();
        for (t, &flip) in out.triangles.iter_mut().zip(turn) {
            if flip {
                t.swap(1, 2);
            }
        }
        out
    }

    /// Which faces turn so that each component agrees with its lowest face (`None` for
    /// a surface that is not closed, 2-manifold and orientable, or whose faces agree
    /// already: those are left as they are, inward shells too).
    fn turns(&self) -> Option<Vec<bool>> {
        let mut report = CheckReport::default();
        let status = scan(self, &mut report);
        if status.index_ok.iter().any(|ok| !ok) {
            return None;
        }
        let table = edge_table(self, &status);
        // Per face, its neighbours across its edges, and whether the two run the
        // shared edge the same way (then one of them must turn relative to the other).
        let n = self.triangles.len();
        let mut across: Vec<Vec<(u32, bool)>> = vec![Vec::with_capacity(3); n];
        let mut consistent = true;
        for &(a, b) in &table.groups {
            let [h, k] = table.half[a as usize..b as usize] else {
                return None;
            };
            let same = h.forward == k.forward;
            consistent &= !same;
            across[h.face as usize].push((k.face, same));
            across[k.face as usize].push((h.face, same));
        }
        if consistent {
            return None;
        }
        let mut turn = vec![false; n];
        let mut seen = vec![false; n];
        let mut queue = VecDeque::new();
        for root in 0..n {
            if seen[root] {
                continue;
            }
            seen[root] = true;
            queue.push_back(root);
            while let Some(f) = queue.pop_front() {
                for &(g, same) in &across[f] {
                    let want = turn[f] ^ same;
                    let g = g as usize;
                    if !seen[g] {
                        seen[g] = true;
                        turn[g] = want;
                        queue.push_back(g);
                    } else if turn[g] != want {
                        // A Moebius-like band: no consistent orientation exists.
                        return None;
                    }
                }
            }
        }
        Some(turn)
    }
}

/// Per shell of `report`, the signed volume it encloses, summed from a vertex of its
/// own: about the origin, a tiny shell far from it (volume 2e-18, a fuzzed input) got
/// the wrong sign from rounding.
fn shell_volumes(s: &Surface, report: &CheckReport) -> Vec<f64> {
    let origin: Vec<_> = report
        .shells
        .iter()
        .map(|sh| s.vertices[s.triangles[sh.first_face as usize][0] as usize])
        .collect();
    let mut volume = vec![0.0; report.shells.len()];
    for (t, &sh) in s.triangles.iter().zip(&report.face_shell) {
        let Some(&o) = origin.get(sh as usize) else {
            continue;
        };
        let [a, b, c] = t.map(|v| s.vertices[v as usize] - o);
        volume[sh as usize] += a.dot(b.cross(c)) / 6.0;
    }
    volume
}

#[cfg(test)]
mod tests {
    use crate::geom::Point;
    use crate::surface::Surface;

    /// The unit cube, two outward triangles per side.
    fn cube() -> Surface {
        crate::surface::generate::cube(1)
    }

    #[test]
    fn faces_that_agree_are_left_as_they_are() {
        let s = cube();
        assert!(s.check().is_clean(), "{}", s.check());
        assert!(s.reoriented().is_none());
        // Every face turned: they agree (inward), and bound the same solid.
        let mut inward = s.clone();
        inward.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        assert!(inward.reoriented().is_none());
        // One face turned too: the whole turns outward.
        inward.triangles[3].swap(1, 2);
        let (back, turned) = inward.reoriented().expect("disagreeing faces");
        assert_eq!((back, turned), (s, 11));
    }

    #[test]
    fn a_cavity_faces_into_itself() {
        // A cube inside a larger cube, both outward, one face of the outer one turned:
        // that face and the inner cube turn (the solid is between them), and the faces'
        // signed volumes then sum to the solid's volume.
        let outer = cube();
        let mut s = outer.clone();
        let n = s.vertices.len() as u32;
        s.vertices
            .extend(outer.vertices.iter().map(|p| *p * 0.5 + Point::splat(0.25)));
        s.triangles
            .extend(outer.triangles.iter().map(|t| t.map(|v| v + n)));
        s.triangles[5].swap(0, 2);
        let (fixed, turned) = s.reoriented().expect("disagreeing faces");
        assert_eq!(turned, 13);
        let volume: f64 = fixed
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| fixed.vertices[v as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        assert!((volume - (1.0 - 0.125)).abs() < 1e-12, "{volume}");
    }

    #[test]
    fn faces_turned_at_random_are_turned_back_to_agree_with_the_lowest() {
        let s = cube();
        let mut shuffled = s.clone();
        for f in [1, 4, 5, 9, 11] {
            shuffled.triangles[f].swap(0, 1);
        }
        assert!(!shuffled.check().is_clean());
        let (fixed, turned) = shuffled.reoriented().expect("orientable and closed");
        assert_eq!(turned, 5);
        assert!(fixed.check().is_clean(), "{}", fixed.check());
        // Outward again: the whole cube is as it was (up to rotation of each face's
        // indices).
        for (a, b) in fixed.triangles.iter().zip(&s.triangles) {
            let mut r = *a;
            let turns = (0..3).any(|_| {
                r.rotate_left(1);
                r == *b
            });
            assert!(turns, "{a:?} against {b:?}");
        }
    }

    #[test]
    fn an_open_surface_is_left_to_the_check() {
        let mut s = cube();
        s.triangles.pop();
        s.triangles[0].swap(0, 1);
        assert!(s.reoriented().is_none());
        assert!(!s.check().is_clean());
    }
}
