//! Domain identification (paper §4.3): the tets are split into connected components by
//! the constrained faces; the component of the box corners is the outside; the
//! components are then ranked by their nesting depth (distance from the outside across
//! constrained faces). Odd depth is material (a body, or the space between a box and
//! the object inside it), even depth is void (the outside, a cavity in a body). A
//! constrained face with the same component on both sides, or two components of the
//! same parity side by side, is a leak and an error.

use super::BoundaryError;
use crate::surface::Surface;
use crate::tetmesh::{FaceRef, TetId, TetMesh, VertexId};
use std::collections::VecDeque;

const NONE: u32 = u32::MAX;

/// The regions of a boundary mesh.
#[derive(Clone, Debug)]
pub struct Regions {
    /// Region of each tet slot: 0 outside the domain, 1.. material regions.
    pub region: Vec<u32>,
    /// Number of material regions.
    pub count: usize,
    /// Tets in the domain.
    pub tets: usize,
    /// Volume of the domain.
    pub volume: f64,
}

/// Labels the components and the regions.
pub(crate) fn identify(mesh: &TetMesh, marks: &[[u32; 4]]) -> Result<Regions, BoundaryError> {
    let n = mesh.num_slots();
    let mut comp = vec![NONE; n];
    let mut ncomp = 0u32;
    // Component 0 starts at a tet with box corner 0; then every other unlabelled tet.
    let start = mesh
        .finite_tets()
        .find(|&t| mesh.tet(t).contains(&VertexId(0)));
    let order = start.into_iter().chain(mesh.finite_tets());
    let mut queue = VecDeque::new();
    let mut graph: Vec<(u32, u32, u32)> = Vec::new();
    for s in order {
        if comp[s.index()] != NONE {
            continue;
        }
        comp[s.index()] = ncomp;
        queue.push_back(s.0);
        while let Some(t) = queue.pop_front() {
            let adj = mesh.raw_adj(t);
            for (i, &a) in adj.iter().enumerate() {
                let u = FaceRef::from_raw(a).tet();
                if mesh.is_ghost(u) {
                    continue;
                }
                let tri = marks.get(t as usize).map_or(u32::MAX, |m| m[i]);
                if tri != u32::MAX {
                    graph.push((ncomp, u.0, tri));
                    continue;
                }
                if comp[u.index()] == NONE {
                    comp[u.index()] = ncomp;
                    queue.push_back(u.0);
                }
            }
        }
        ncomp += 1;
    }
    let depth = depths(&comp, &graph, ncomp)?;
    // Material components, numbered in order of first appearance.
    let mut id = vec![0u32; ncomp as usize];
    let mut count = 0;
    for c in 0..ncomp as usize {
        if depth[c] % 2 == 1 {
            count += 1;
            id[c] = count;
        }
    }
    let mut region = vec![0u32; n];
    let (mut tets, mut volume) = (0, 0.0);
    for t in mesh.finite_tets() {
        let r = id[comp[t.index()] as usize];
        region[t.index()] = r;
        if r != 0 {
            tets += 1;
            volume += tet_volume(mesh, t);
        }
    }
    Ok(Regions {
        region,
        count: count as usize,
        tets,
        volume,
    })
}

/// The regions of a mesh that has changed since `before` was identified on it (tets
/// `snapshot`, per slot, the vertices then; `u32::MAX` for dead slots): a tet with the
/// same vertices in its slot keeps its region, every other takes the region of its
/// neighbours across faces that are not input triangles (`constrained`). `None` when
/// that is not consistent (a new tet between two regions, an input triangle with
/// material on both sides or on neither, a new tet reached by no neighbour): the
/// caller then identifies the domain from scratch, which names the leak. The interior
/// Steiner points' suppression changes a few stars of a finished mesh: this spares a
/// second identification (turbine: the input triangles looked up again and the flood
/// fill, 8 of the boundary mesh's 270 ms).
pub(crate) fn patched(
    mesh: &TetMesh,
    before: &Regions,
    snapshot: &[[u32; 4]],
    constrained: impl Fn([u32; 3]) -> bool,
) -> Option<Regions> {
    let n = mesh.num_slots();
    let mut region = vec![NONE; n];
    let mut fresh: Vec<u32> = Vec::new();
    for t in mesh.finite_tets() {
        let k = t.index();
        if snapshot.get(k) == Some(&mesh.raw_tet(t.0)) {
            region[k] = before.region[k];
        } else {
            fresh.push(t.0);
        }
    }
    let face = |t: u32, i: usize| {
        let v = mesh.raw_tet(t);
        crate::tetmesh::FACE_VERTICES[i].map(|k| v[k])
    };
    // Passes over the new tets, each labelling those next to a labelled one; a pass
    // that labels nothing ends it.
    let mut pending = fresh.clone();
    while !pending.is_empty() {
        let mut left = Vec::new();
        for &t in &pending {
            let adj = mesh.raw_adj(t);
            let from = (0..4).find_map(|i| {
                let u = FaceRef::from_raw(adj[i]).tet();
                let r = region[u.index()];
                (!mesh.is_ghost(u) && r != NONE && !constrained(face(t, i))).then_some(r)
            });
            match from {
                Some(r) => region[t as usize] = r,
                None => left.push(t),
            }
        }
        if left.len() == pending.len() {
            return None;
        }
        pending = left;
    }
    // Every face of a new tet: the same region across a free face, material on exactly
    // one side of an input triangle (the hull's faces are free, outside the domain).
    for &t in &fresh {
        let adj = mesh.raw_adj(t);
        let r = region[t as usize];
        for (i, &a) in adj.iter().enumerate() {
            let u = FaceRef::from_raw(a).tet();
            let ru = if mesh.is_ghost(u) {
                0
            } else {
                region[u.index()]
            };
            let ok = if constrained(face(t, i)) {
                (r == 0) != (ru == 0)
            } else {
                r == ru
            };
            if !ok {
                return None;
            }
        }
    }
    let (mut tets, mut volume) = (0, 0.0);
    for t in mesh.finite_tets() {
        if region[t.index()] != 0 {
            tets += 1;
            volume += tet_volume(mesh, t);
        }
    }
    for r in region.iter_mut().filter(|r| **r == NONE) {
        *r = 0;
    }
    Some(Regions {
        region,
        count: before.count,
        tets,
        volume,
    })
}

/// Nesting depth of each component by breadth-first search from component 0 over the
/// constrained faces; a face whose two sides are at the same depth is a leak.
fn depths(comp: &[u32], graph: &[(u32, u32, u32)], ncomp: u32) -> Result<Vec<u32>, BoundaryError> {
    let mut adj: Vec<Vec<(u32, u32)>> = vec![Vec::new(); ncomp as usize];
    for &(c, t, tri) in graph {
        let d = comp[t as usize];
        if d == c {
            return Err(BoundaryError::Leak {
                triangle: tri as usize,
            });
        }
        adj[c as usize].push((d, tri));
    }
    let mut depth = vec![NONE; ncomp as usize];
    let mut queue = VecDeque::new();
    for s in 0..ncomp {
        if depth[s as usize] != NONE {
            continue;
        }
        // Component 0 is the outside; an unreached component (impossible for closed
        // shells inside the box) starts at depth 0 as well.
        depth[s as usize] = 0;
        queue.push_back(s);
        while let Some(c) = queue.pop_front() {
            for &(d, tri) in &adj[c as usize] {
                if depth[d as usize] == NONE {
                    depth[d as usize] = depth[c as usize] + 1;
                    queue.push_back(d);
                } else if depth[d as usize] % 2 == depth[c as usize] % 2 {
                    return Err(BoundaryError::Leak {
                        triangle: tri as usize,
                    });
                }
            }
        }
    }
    Ok(depth)
}

fn tet_volume(mesh: &TetMesh, t: TetId) -> f64 {
    let [a, b, c, d] = mesh.tet_points(t);
    (b - a).dot((c - a).cross(d - a)) / 6.0
}

/// The volume enclosed by the surface: the sum of the signed volumes of the cones from
/// the centroid of its vertices to its triangles (exact for closed shells up to
/// rounding; positive for outward-oriented shells).
pub fn enclosed_volume(surface: &Surface) -> f64 {
    let n = surface.vertices.len().max(1) as f64;
    let o = surface.vertices.iter().copied().sum::<crate::geom::Point>() / n;
    surface
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| surface.vertices[i as usize] - o);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}
