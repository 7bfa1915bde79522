//! Flips for boundary recovery (paper §4.2): the 2-3 flip of a face and the removal of
//! an edge by re-triangulating the polygon of its ring (n tets -> 2n-4 tets; n = 3 is
//! the 3-2 flip, n = 4 the 4-4 flip).
//!
//! The polygon triangulation is chosen by the dynamic program of Klincsek (1980), as
//! used for edge removal by Shewchuk ("Two discrete optimization algorithms for the
//! topological improvement of tetrahedral meshes", 2002): the valid triangulation with
//! the best worst tet, optionally forced to contain one triangle. Every change goes
//! through [`Local::replace`], which checks it exactly.

use super::local::{Local, Refused};
use crate::geom::Point;
use crate::tetmesh::{FaceRef, FACE_VERTICES};
use crate::FastSet as HashSet;

/// Largest ring an edge removal tries (the dynamic program is cubic in it).
pub(crate) const MAX_RING: usize = 16;

/// Constrained (locked) entities: never removed by a flip.
#[derive(Debug, Default)]
pub(crate) struct Locks {
    pub edges: HashSet<(u32, u32)>,
    pub faces: HashSet<[u32; 3]>,
    /// Per vertex, whether a locked face has it ([`Locks::of_faces`] only; empty:
    /// not known, every question goes to the sets).
    on: Vec<bool>,
}

impl Locks {
    /// The faces locked, and their edges. The sets must not grow afterwards: an edge
    /// or face with a vertex on none of these faces is answered "not locked" without
    /// a look-up (most of those the optimiser asks about have a free vertex).
    pub fn of_faces(faces: &[[u32; 3]]) -> Locks {
        let mut locks = Locks::default();
        for f in faces {
            let s = crate::surface::sorted_ids(*f);
            locks.faces.insert(s);
            for (a, b) in [(s[0], s[1]), (s[1], s[2]), (s[0], s[2])] {
                locks.edges.insert((a, b));
            }
            if let Some(&top) = s.last() {
                if locks.on.len() <= top as usize {
                    locks.on.resize(top as usize + 1, false);
                }
            }
            for v in s {
                locks.on[v as usize] = true;
            }
        }
        locks
    }

    /// True when `v` is known to be on no locked face.
    #[inline]
    fn off(&self, v: u32) -> bool {
        !self.on.is_empty() && !self.on.get(v as usize).copied().unwrap_or(false)
    }

    pub fn edge(&self, a: u32, b: u32) -> bool {
        if self.off(a) || self.off(b) {
            return false;
        }
        self.edges.contains(&(a.min(b), a.max(b)))
    }
    pub fn face(&self, f: [u32; 3]) -> bool {
        if f.iter().any(|&v| self.off(v)) {
            return false;
        }
        let mut s = f;
        s.sort_unstable();
        self.faces.contains(&s)
    }
}

/// Counters of the flips done.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct FlipCounts {
    /// 2-3 flips.
    pub flip23: u64,
    /// 3-2 flips (edge removals with a ring of 3).
    pub flip32: u64,
    /// 4-4 flips (edge removals with a ring of 4).
    pub flip44: u64,
    /// Edge removals with a ring of 5 or more.
    pub edge_removals: u64,
    /// Regions re-tetrahedralised as a cone from one of their vertices.
    pub cones: u64,
    /// Schönhardt fans re-tetrahedralised with one interior Steiner point.
    pub fans: u64,
}

/// The 2-3 flip of the face opposite local vertex `i` of tet `t`.
pub(crate) fn flip23(
    l: &mut Local,
    locks: &Locks,
    t: u32,
    i: usize,
    n: &mut FlipCounts,
) -> Result<(), Refused> {
    let v = l.tet(t);
    let f = FACE_VERTICES[i].map(|k| v[k]);
    if locks.face(f) {
        return Err(Refused::Mismatch);
    }
    let nb = FaceRef::from_raw(l.adj(t)[i]);
    let u = nb.tet().0;
    if l.is_ghost(u) {
        return Err(Refused::Hull);
    }
    let (d, e) = (v[i], l.tet(u)[nb.facet()]);
    let new = [[f[0], f[1], e, d], [f[1], f[2], e, d], [f[2], f[0], e, d]];
    l.replace(&[t, u], &new)?;
    n.flip23 += 1;
    Ok(())
}

/// Which triangulation of the ring polygon an edge removal uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Choice {
    /// The best valid one.
    Best,
    /// The best one with this triangle (ring vertices) in it.
    With([u32; 3]),
    /// The fan from this ring vertex, else the best.
    FanFrom(u32),
    /// The fan from this ring vertex only.
    Fan(u32),
    /// The best one with the diagonal between these two ring vertices.
    Chord(u32, u32),
}

/// Removes edge `xy` by re-triangulating its ring.
pub(crate) fn remove_edge(
    l: &mut Local,
    locks: &Locks,
    x: u32,
    y: u32,
    choice: Choice,
    scratch: &mut Vec<u32>,
    n: &mut FlipCounts,
) -> Result<(), Refused> {
    if locks.edge(x, y) {
        return Err(Refused::Mismatch);
    }
    let ring = l.ring(x, y, scratch).ok_or(Refused::Hull)?;
    if ring.len() > MAX_RING || ring.len() < 3 {
        return Err(Refused::Mismatch);
    }
    let len = ring.len();
    let mut poly = [0u32; MAX_RING];
    let mut pts = [Point::ZERO; MAX_RING];
    for (k, r) in ring.iter().enumerate() {
        poly[k] = r.1;
        pts[k] = l.p(r.1);
    }
    let poly = &poly[..len];
    let all: [usize; MAX_RING] = std::array::from_fn(|k| k);
    let all = &all[..len];
    let (px, py) = (l.p(x), l.p(y));
    // Ring is counter-clockwise seen from y: tets [pi, pj, pk, y] and [pj, pi, pk, x].
    let valid = |i: usize, j: usize, k: usize| -> f64 {
        let (a, b, c) = (pts[i], pts[j], pts[k]);
        // The signs first: most triangles of a ring fail one, and the shape is dearer.
        let (v1, v2) = (volume6(a, b, c, py), volume6(b, a, c, px));
        if v1 <= 0.0 || v2 <= 0.0 {
            return -1.0;
        }
        let q1 = shape_of(v1, a, b, c, py);
        let q2 = shape_of(v2, b, a, c, px);
        if q1 > 0.0 && q2 > 0.0 {
            q1.min(q2)
        } else {
            -1.0
        }
    };
    let pos = |v: u32| poly.iter().position(|&p| p == v);
    let tris = match choice {
        Choice::Best => best_triangulation(all, &valid),
        Choice::With(t) => match (pos(t[0]), pos(t[1]), pos(t[2])) {
            (Some(i), Some(j), Some(k)) => forced(poly.len(), [i, j, k], &valid),
            _ => None,
        },
        Choice::Fan(v) => pos(v).and_then(|s| fan(poly.len(), s, &valid)),
        Choice::Chord(p, q) => match (pos(p), pos(q)) {
            (Some(i), Some(j)) => chord(poly.len(), i.min(j), i.max(j), &valid),
            _ => None,
        },
        Choice::FanFrom(v) => pos(v)
            .and_then(|s| fan(poly.len(), s, &valid))
            .or_else(|| best_triangulation(all, &valid)),
    }
    .ok_or(Refused::NotPositive)?;
    let mut new = Vec::with_capacity(tris.len() * 2);
    for [i, j, k] in tris {
        let (a, b, c) = (poly[i], poly[j], poly[k]);
        new.push([a, b, c, y]);
        new.push([b, a, c, x]);
    }
    let old: Vec<u32> = ring.iter().map(|r| r.0).collect();
    l.replace(&old, &new)?;
    match ring.len() {
        3 => n.flip32 += 1,
        4 => n.flip44 += 1,
        _ => n.edge_removals += 1,
    }
    Ok(())
}

/// [`shape_of`] of the tet with corners `p` (inexact; it only ranks).
pub(super) fn tet_shape(p: [Point; 4]) -> f64 {
    shape_of(volume6(p[0], p[1], p[2], p[3]), p[0], p[1], p[2], p[3])
}

/// Six times the signed volume of tet `abcd` (inexact).
#[inline]
fn volume6(a: Point, b: Point, c: Point, d: Point) -> f64 {
    (b - a).dot((c - a).cross(d - a))
}

/// A scale-free shape measure of tet `abcd`, from six times its volume `v6`: positive
/// iff its volume (inexact) is, 1 for the regular tet. Exact validity is checked by
/// `replace`; this only ranks.
#[inline]
fn shape_of(v6: f64, a: Point, b: Point, c: Point, d: Point) -> f64 {
    let v = v6 / 6.0;
    let s = [b - a, c - a, d - a, c - b, d - b, d - c]
        .iter()
        .map(|e| e.length_squared())
        .sum::<f64>()
        / 6.0;
    if s <= 0.0 {
        return -1.0;
    }
    // Regular tet of edge l: V = l^3 / (6 sqrt 2).
    v * 6.0 * std::f64::consts::SQRT_2 / (s * s.sqrt())
}

/// The fan of triangles from polygon vertex `s`, if all are valid.
fn fan(n: usize, s: usize, q: &impl Fn(usize, usize, usize) -> f64) -> Option<Vec<[usize; 3]>> {
    let idx: Vec<usize> = (0..n).map(|k| (s + k) % n).collect();
    let tris: Vec<[usize; 3]> = (1..n - 1).map(|k| [idx[0], idx[k], idx[k + 1]]).collect();
    tris.iter()
        .all(|t| q(t[0], t[1], t[2]) > 0.0)
        .then_some(tris)
}

/// The best triangulation containing the diagonal `ij` (polygon indices, `i < j`):
/// the best of each of the two polygons it cuts off.
fn chord(
    n: usize,
    i: usize,
    j: usize,
    q: &impl Fn(usize, usize, usize) -> f64,
) -> Option<Vec<[usize; 3]>> {
    if j - i < 2 || n - (j - i) < 2 {
        return None;
    }
    let first: Vec<usize> = (i..=j).collect();
    let second: Vec<usize> = (j..n).chain(0..=i).collect();
    let mut out = best_triangulation(&first, q)?;
    out.extend(best_triangulation(&second, q)?);
    Some(out)
}

/// The best triangulation containing triangle `t` (polygon indices).
fn forced(
    n: usize,
    t: [usize; 3],
    q: &impl Fn(usize, usize, usize) -> f64,
) -> Option<Vec<[usize; 3]>> {
    let mut t = t;
    t.sort_unstable();
    if q(t[0], t[1], t[2]) <= 0.0 {
        return None;
    }
    let mut out = vec![[t[0], t[1], t[2]]];
    let chains = [
        (t[0]..=t[1]).collect::<Vec<_>>(),
        (t[1]..=t[2]).collect::<Vec<_>>(),
        (t[2]..n).chain(0..=t[0]).collect::<Vec<_>>(),
    ];
    for c in chains {
        if c.len() >= 3 {
            out.extend(best_triangulation(&c, q)?);
        }
    }
    Some(out)
}

/// Klincsek's dynamic program over the polygon `idx` (indices in cyclic order): the
/// triangulation maximising the smallest `q`, or `None` if every one has a `q <= 0`.
pub(crate) fn best_triangulation(
    idx: &[usize],
    q: &impl Fn(usize, usize, usize) -> f64,
) -> Option<Vec<[usize; 3]>> {
    best_triangulation_above(idx, q, 0.0)
}

/// [`best_triangulation`], `None` unless the best smallest `q` is above `floor`
/// (`floor >= 0`). A triangle is evaluated only when it could raise its sub-polygon's
/// value above both the best found so far and `floor`; the choice among the
/// triangulations above `floor` (ties included) is the unpruned one.
pub(crate) fn best_triangulation_above(
    idx: &[usize],
    q: &impl Fn(usize, usize, usize) -> f64,
    floor: f64,
) -> Option<Vec<[usize; 3]>> {
    let m = idx.len();
    if m < 3 {
        return Some(Vec::new());
    }
    // The tables on the stack for rings up to MAX_RING (every caller's: most calls
    // are tried and fail, and two allocations per call were a tenth of their cost),
    // in small tables for the small rings most calls have (the big ones cost a 4 kB
    // fill each).
    const SMALL: usize = 8;
    if m <= SMALL {
        let (mut best, mut arg) = ([f64::NEG_INFINITY; SMALL * SMALL], [0usize; SMALL * SMALL]);
        return triangulation_dp(idx, q, floor, &mut best[..m * m], &mut arg[..m * m]);
    }
    const STACK: usize = MAX_RING * MAX_RING;
    if m <= MAX_RING {
        let (mut best, mut arg) = ([f64::NEG_INFINITY; STACK], [0usize; STACK]);
        return triangulation_dp(idx, q, floor, &mut best[..m * m], &mut arg[..m * m]);
    }
    let (mut best, mut arg) = (vec![f64::NEG_INFINITY; m * m], vec![0usize; m * m]);
    triangulation_dp(idx, q, floor, &mut best, &mut arg)
}

/// The dynamic program of [`best_triangulation_above`] in the `m x m` tables `best`
/// (filled with `-inf`) and `arg`.
fn triangulation_dp(
    idx: &[usize],
    q: &impl Fn(usize, usize, usize) -> f64,
    floor: f64,
    best: &mut [f64],
    arg: &mut [usize],
) -> Option<Vec<[usize; 3]>> {
    let m = idx.len();
    for i in 0..m - 1 {
        best[i * m + i + 1] = f64::INFINITY;
    }
    for len in 2..m {
        for i in 0..m - len {
            let j = i + len;
            for k in i + 1..j {
                let sides = best[i * m + k].min(best[k * m + j]);
                if sides <= best[i * m + j] || sides <= floor {
                    continue;
                }
                let v = sides.min(q(idx[i], idx[k], idx[j]));
                if v > best[i * m + j] {
                    best[i * m + j] = v;
                    arg[i * m + j] = k;
                }
            }
        }
    }
    let top = best[m - 1];
    if top.is_nan() || top <= floor.max(0.0) {
        return None;
    }
    let mut out = Vec::with_capacity(m - 2);
    // Each pop pushes two intervals inside the popped one: never more than `m` wait.
    let mut stack = Vec::with_capacity(m);
    stack.push((0, m - 1));
    while let Some((i, j)) = stack.pop() {
        if j - i < 2 {
            continue;
        }
        let k = arg[i * m + j];
        out.push([idx[i], idx[k], idx[j]]);
        stack.push((i, k));
        stack.push((k, j));
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vertex marks of `of_faces` change no answer: every edge and face over a
    /// set of vertices, some on locked faces, some on none, and some past the marks.
    #[test]
    fn locks_answer_as_their_sets() {
        let faces = [[0, 1, 2], [2, 1, 3], [5, 7, 6]];
        let locks = Locks::of_faces(&faces);
        let sets = Locks {
            edges: locks.edges.clone(),
            faces: locks.faces.clone(),
            on: Vec::new(),
        };
        let n = 10;
        for a in 0..n {
            for b in 0..n {
                assert_eq!(locks.edge(a, b), sets.edge(a, b), "{a} {b}");
                for c in 0..n {
                    assert_eq!(locks.face([a, b, c]), sets.face([a, b, c]), "{a} {b} {c}");
                }
            }
        }
        assert!(locks.face([3, 2, 1]) && locks.edge(7, 5) && !locks.face([0, 1, 3]));
        assert!(!locks.edge(4, 0) && !locks.edge(9, 2));
    }

    #[test]
    fn dp_triangulates_a_convex_polygon_and_forces_a_triangle() {
        let q = |_: usize, _: usize, _: usize| 1.0;
        let t = best_triangulation(&[0, 1, 2, 3, 4, 5], &q).unwrap();
        assert_eq!(t.len(), 4);
        let f = forced(6, [4, 0, 2], &q).unwrap();
        assert_eq!(f.len(), 4);
        assert!(f.contains(&[0, 2, 4]));
        let bad = |i: usize, _: usize, _: usize| if i == 0 { -1.0 } else { 1.0 };
        assert!(best_triangulation(&[0, 1, 2], &bad).is_none());
    }

    /// The unpruned program, as a reference: (best value, triangles).
    fn reference(m: usize, q: &impl Fn(usize, usize, usize) -> f64) -> (f64, Vec<[usize; 3]>) {
        let mut best = vec![f64::NEG_INFINITY; m * m];
        let mut arg = vec![0usize; m * m];
        for i in 0..m - 1 {
            best[i * m + i + 1] = f64::INFINITY;
        }
        for len in 2..m {
            for i in 0..m - len {
                let j = i + len;
                for k in i + 1..j {
                    let v = best[i * m + k].min(best[k * m + j]).min(q(i, k, j));
                    if v > best[i * m + j] {
                        best[i * m + j] = v;
                        arg[i * m + j] = k;
                    }
                }
            }
        }
        let mut out = Vec::new();
        // Each pop pushes two intervals inside the popped one: never more than `m` wait.
        let mut stack = Vec::with_capacity(m);
        stack.push((0, m - 1));
        while let Some((i, j)) = stack.pop() {
            if j - i >= 2 {
                let k = arg[i * m + j];
                out.push([i, k, j]);
                stack.push((i, k));
                stack.push((k, j));
            }
        }
        (best[m - 1], out)
    }

    #[test]
    fn pruning_keeps_the_unpruned_choice_above_the_floor() {
        let mut s = 7u64;
        for m in 3..11 {
            for round in 0..200 {
                // Few distinct values, so ties are common.
                let salt = s;
                let q = move |i: usize, j: usize, k: usize| {
                    let h = (i * 131 + j * 31 + k * 7) as u64 ^ salt;
                    let h = h.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 59;
                    h as f64 / 8.0 - 0.5
                };
                s = s.wrapping_mul(6364136223846793005).wrapping_add(round);
                let (value, tris) = reference(m, &q);
                let idx: Vec<usize> = (0..m).collect();
                for floor in [0.0, 0.25, 0.75, 1.5] {
                    let got = best_triangulation_above(&idx, &q, floor);
                    if value > floor {
                        assert_eq!(got.as_ref(), Some(&tris), "m {m} floor {floor}");
                    } else {
                        assert!(got.is_none(), "m {m} floor {floor}");
                    }
                }
            }
        }
    }
}
