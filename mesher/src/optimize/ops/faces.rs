//! Multi-face removal (Shewchuk, "Two discrete optimization algorithms for the
//! topological improvement of tetrahedral meshes", 2002), the inverse of edge removal:
//! the faces sandwiched between two vertices `u` and `w` (each face `f` with the tets
//! `(u, f)` and `(w, f)`) form a triangulated polygon; removing `k` of them, a disc
//! with no vertex inside, replaces their `2k` tets by the ring of the new edge `uw`,
//! one tet per edge of the disc's border. The 2-3 flip is the one-face case.

use super::{max_until, Ops};
use crate::tetmesh::{FaceRef, FACE_VERTICES};

/// Faces of a sandwich gathered at most (the discs tried are its first faces in the
/// order they were reached, two to all).
const MAX_SANDWICH: usize = 8;

/// A face of the sandwich: its vertices as the tet on `u`'s side lists them (`u` on
/// the positive side), that tet and the tet on `w`'s side.
#[derive(Clone, Copy)]
struct Layer {
    face: [u32; 3],
    upper: u32,
    lower: u32,
}

impl Ops {
    /// Multi-face removal around the face of tet `t` opposite its vertex `i`: `u` is
    /// that vertex, `w` the apex across the face. The sandwich grows from the face
    /// across its edges (breadth first, at most [`MAX_SANDWICH`] faces); each of its
    /// first `k >= 2` faces that form a disc with every vertex on its border is tried,
    /// and the best of those whose new tets are all positive replaces its tets when it
    /// lowers their worst `Q_K`. Constrained faces and tets of another region are
    /// never part of a sandwich, and `u` or `w` must be free.
    pub fn remove_faces(&mut self, t: u32, i: usize) -> bool {
        let r = self.region_of(t);
        if r == 0 || self.l.is_ghost(t) {
            return false;
        }
        let v = self.l.tet(t);
        let u = v[i];
        let Some(first) = self.layer(t, i, r) else {
            return false;
        };
        let w = self.apex_below(&first);
        // A new edge between two fixed vertices makes tets that no move improves
        // later (rotor_small: two tets of four surface vertices on a fold, Q_K 235,
        // where the moves reach 34 without that edge).
        let fixed = |x: u32| self.fixed.get(x as usize) != Some(&false);
        if fixed(u) && fixed(w) {
            return false;
        }
        let sandwich = self.sandwich(first, u, w, r);
        let mut best: Option<(f64, usize, Vec<[u32; 4]>)> = None;
        for k in 2..=sandwich.len() {
            let Some((border, inner)) = disc(&sandwich[..k]) else {
                continue;
            };
            // The inner edges go, with the faces through them on either side.
            let locked = inner.iter().any(|&(x, y)| {
                self.locks.edge(x, y) || self.locks.face([u, x, y]) || self.locks.face([w, x, y])
            });
            if locked {
                continue;
            }
            let new: Vec<[u32; 4]> = border.iter().map(|&(x, y)| [x, y, w, u]).collect();
            // Only a disc better than the best so far matters: its worst stops there.
            let bound = best.as_ref().map_or(f64::INFINITY, |b| b.0);
            let after = max_until(new.iter().map(|&n| self.quality(n)), bound);
            if best.as_ref().is_none_or(|b| after < b.0) {
                best = Some((after, k, new));
            }
        }
        let Some((after, k, new)) = best else {
            return false;
        };
        let old: Vec<u32> = sandwich[..k]
            .iter()
            .flat_map(|l| [l.upper, l.lower])
            .collect();
        if after >= self.worst(&old) || self.l.replace(&old, &new).is_err() {
            return false;
        }
        self.claim(r);
        true
    }

    /// The face of `t` opposite its vertex `i` as a sandwich layer, when it is not
    /// constrained and the tet across it is in region `r`.
    fn layer(&self, t: u32, i: usize, r: u32) -> Option<Layer> {
        let v = self.l.tet(t);
        let face = FACE_VERTICES[i].map(|k| v[k]);
        if self.locks.face(face) {
            return None;
        }
        let lower = FaceRef::from_raw(self.l.adj(t)[i]).tet().0;
        (!self.l.is_ghost(lower) && self.region_of(lower) == r).then_some(Layer {
            face,
            upper: t,
            lower,
        })
    }

    /// The vertex of the layer's lower tet that is not on its face.
    fn apex_below(&self, layer: &Layer) -> u32 {
        let low = self.l.tet(layer.lower);
        low.into_iter()
            .find(|x| !layer.face.contains(x))
            .unwrap_or(u32::MAX)
    }

    /// The faces between `u` and `w` reached from `first` across their edges: for an
    /// edge of a layer, the next tet around it on `u`'s side, whose face opposite `u`
    /// is a layer when the tet across that face has `w` for apex.
    fn sandwich(&self, first: Layer, u: u32, w: u32, r: u32) -> Vec<Layer> {
        let mut layers = vec![first];
        let mut k = 0;
        while k < layers.len() && layers.len() < MAX_SANDWICH {
            let upper = layers[k].upper;
            k += 1;
            let tv = self.l.tet(upper);
            let adj = self.l.adj(upper);
            // The faces of the upper tet through `u` lead to its neighbours around
            // the layer's edges.
            for (j, &x) in tv.iter().enumerate() {
                if x == u || layers.len() >= MAX_SANDWICH {
                    continue;
                }
                let next = FaceRef::from_raw(adj[j]).tet().0;
                if self.l.is_ghost(next)
                    || self.region_of(next) != r
                    || layers.iter().any(|l| l.upper == next)
                    || self.locks.face(FACE_VERTICES[j].map(|m| tv[m]))
                {
                    continue;
                }
                let nv = self.l.tet(next);
                let Some(iu) = nv.iter().position(|&y| y == u) else {
                    continue;
                };
                let Some(layer) = self.layer(next, iu, r) else {
                    continue;
                };
                if self.apex_below(&layer) == w {
                    layers.push(layer);
                }
            }
        }
        layers
    }
}

/// Edges as vertex pairs.
type Edges = Vec<(u32, u32)>;

/// The border of the faces `layers` as directed edges `(x, y)`, each as its face lists
/// it, and their inner edges (once each), when they form a disc with every vertex on
/// the border (a triangulated polygon: `k` faces, `k + 2` border edges and vertices,
/// each vertex on two border edges); `None` otherwise.
fn disc(layers: &[Layer]) -> Option<(Edges, Edges)> {
    let all: Edges = layers
        .iter()
        .flat_map(|l| {
            let [a, b, c] = l.face;
            [(a, b), (b, c), (c, a)]
        })
        .collect();
    // An inner edge is listed once each way; the border's once.
    let (inner, border): (Edges, Edges) = all.iter().partition(|&&(x, y)| all.contains(&(y, x)));
    if border.len() != layers.len() + 2 {
        return None;
    }
    let mut verts: Vec<u32> = layers.iter().flat_map(|l| l.face).collect();
    verts.sort_unstable();
    verts.dedup();
    let single_cycle = verts.len() == border.len()
        && verts.iter().all(|&x| {
            border.iter().filter(|e| e.0 == x).count() == 1
                && border.iter().filter(|e| e.1 == x).count() == 1
        });
    let inner = inner.into_iter().filter(|&(x, y)| x < y).collect();
    single_cycle.then_some((border, inner))
}
