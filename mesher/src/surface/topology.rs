//! Combinatorial checks of [`Surface::check`](crate::surface::Surface::check): index
//! validity, non-finite coordinates, zero-area and duplicate faces, the edge table (open,
//! non-manifold and inconsistently oriented edges) and pinched vertices.
//!
//! The edge table is a sorted list of directed half-edges keyed by their undirected
//! vertex pair, so each edge's faces are a contiguous run (no hashing, deterministic).
//! A vertex is pinched when its incident faces, joined whenever they share an edge
//! through the vertex, form more than one connected fan (the umbrella test for a
//! 2-manifold vertex).

use super::intersect::is_collinear;
use super::report::{CheckReport, DuplicateFaces, EdgeRef, FaceRef, PinchedVertex, VertexRef};
use super::Surface;

/// Coordinates of vertex `v`, NaN when out of range.
pub(crate) fn coords(s: &Surface, v: u32) -> [f64; 3] {
    match s.vertices.get(v as usize) {
        Some(p) => [p.x, p.y, p.z],
        None => [f64::NAN; 3],
    }
}

/// A face with its coordinates for the report.
pub(crate) fn face_ref(s: &Surface, f: u32) -> FaceRef {
    let vertices = s
        .triangles
        .get(f as usize)
        .copied()
        .unwrap_or([u32::MAX; 3]);
    FaceRef {
        face: f,
        vertices,
        coords: vertices.map(|v| coords(s, v)),
    }
}

/// A vertex with its coordinates for the report.
pub(crate) fn vertex_ref(s: &Surface, v: u32) -> VertexRef {
    VertexRef {
        vertex: v,
        coords: coords(s, v),
    }
}

/// One face's use of an undirected edge.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HalfEdge {
    /// Smaller vertex id.
    pub lo: u32,
    /// Larger vertex id.
    pub hi: u32,
    /// The face.
    pub face: u32,
    /// The face runs the edge from `lo` to `hi`.
    pub forward: bool,
}

/// Half-edges grouped by undirected edge.
pub(crate) struct EdgeTable {
    /// Sorted by `(lo, hi, face)`.
    pub half: Vec<HalfEdge>,
    /// `[start, end)` ranges in `half`, one per undirected edge.
    pub groups: Vec<(u32, u32)>,
}

/// Per-face validity found by [`scan`].
pub(crate) struct FaceStatus {
    /// Indices in range and pairwise distinct: the face takes part in the topology.
    pub index_ok: Vec<bool>,
    /// Also finite and not collinear: the face takes part in the geometry.
    pub geom_ok: Vec<bool>,
}

/// Index and coordinate validity, zero-area faces, unreferenced vertices.
pub(crate) fn scan(s: &Surface, r: &mut CheckReport) -> FaceStatus {
    let nv = s.vertices.len();
    let finite: Vec<bool> = s.vertices.iter().map(|p| p.is_finite()).collect();
    for (v, ok) in finite.iter().enumerate() {
        if !ok {
            r.non_finite_vertices.push(vertex_ref(s, v as u32));
        }
    }
    let mut used = vec![false; nv];
    let mut index_ok = vec![false; s.triangles.len()];
    let mut geom_ok = vec![false; s.triangles.len()];
    for (f, t) in s.triangles.iter().enumerate() {
        if t.iter().any(|&v| v as usize >= nv) {
            r.out_of_range_faces.push(face_ref(s, f as u32));
            continue;
        }
        for &v in t {
            used[v as usize] = true;
        }
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            r.degenerate_faces.push(face_ref(s, f as u32));
            continue;
        }
        index_ok[f] = true;
        if !t.iter().all(|&v| finite[v as usize]) {
            continue;
        }
        let [a, b, c] = t.map(|v| s.vertices[v as usize]);
        if is_collinear(a, b, c) {
            r.zero_area_faces.push(face_ref(s, f as u32));
        } else {
            geom_ok[f] = true;
        }
    }
    r.unreferenced_vertices = used.iter().filter(|u| !**u).count();
    FaceStatus { index_ok, geom_ok }
}

/// The face's ids sorted increasingly (a min/max network: it runs per tet face in the
/// boundary mesh's face lookups).
#[inline]
pub(crate) fn sorted_ids([a, b, c]: [u32; 3]) -> [u32; 3] {
    let (a, b) = (a.min(b), a.max(b));
    let (b, c) = (b.min(c), b.max(c));
    [a.min(b), a.max(b), c]
}

/// Groups of faces (with valid indices) on the same vertex set.
pub(crate) fn duplicates(s: &Surface, st: &FaceStatus) -> Vec<DuplicateFaces> {
    let mut keys: Vec<([u32; 3], u32)> = s
        .triangles
        .iter()
        .enumerate()
        .filter(|(f, _)| st.index_ok[*f])
        .map(|(f, t)| (sorted_ids(*t), f as u32))
        .collect();
    keys.sort_unstable();
    let mut out = Vec::new();
    for run in keys.chunk_by(|a, b| a.0 == b.0) {
        if run.len() > 1 {
            out.push(DuplicateFaces {
                faces: run.iter().map(|(_, f)| face_ref(s, *f)).collect(),
            });
        }
    }
    out
}

/// Builds the edge table over faces with valid indices.
pub(crate) fn edge_table(s: &Surface, st: &FaceStatus) -> EdgeTable {
    let mut half = Vec::with_capacity(3 * s.triangles.len());
    for (f, t) in s.triangles.iter().enumerate() {
        if !st.index_ok[f] {
            continue;
        }
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            half.push(HalfEdge {
                lo: a.min(b),
                hi: a.max(b),
                face: f as u32,
                forward: a < b,
            });
        }
    }
    half.sort_unstable_by_key(|h| (h.lo, h.hi, h.face));
    let mut groups = Vec::new();
    let mut start = 0usize;
    for i in 1..=half.len() {
        if i == half.len() || (half[i].lo, half[i].hi) != (half[start].lo, half[start].hi) {
            groups.push((start as u32, i as u32));
            start = i;
        }
    }
    EdgeTable { half, groups }
}

/// Open, non-manifold and inconsistently oriented edges.
pub(crate) fn classify_edges(s: &Surface, et: &EdgeTable, r: &mut CheckReport) {
    for &(a, b) in &et.groups {
        let run = &et.half[a as usize..b as usize];
        let bad = match run.len() {
            1 => Some(&mut r.open_edges),
            2 if run[0].forward == run[1].forward => Some(&mut r.inconsistent_edges),
            2 => None,
            _ => Some(&mut r.non_manifold_edges),
        };
        if let Some(list) = bad {
            let (lo, hi) = (run[0].lo, run[0].hi);
            list.push(EdgeRef {
                vertices: [lo, hi],
                coords: [coords(s, lo), coords(s, hi)],
                faces: run.iter().map(|h| h.face).collect(),
            });
        }
    }
}

/// The faces at each vertex, compressed: vertex `v`'s faces (increasing) are
/// `faces[start[v]..start[v + 1]]`. Faces `keep` refuses, and indices past the
/// vertices, are left out.
pub(crate) fn faces_by_vertex(s: &Surface, keep: impl Fn(usize) -> bool) -> (Vec<u32>, Vec<u32>) {
    let nv = s.vertices.len();
    let corners = |f: usize| {
        let t = s.triangles[f];
        let ok = keep(f);
        t.into_iter().filter(move |&v| ok && (v as usize) < nv)
    };
    let mut start = vec![0u32; nv + 1];
    for f in 0..s.triangles.len() {
        for v in corners(f) {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut faces = vec![0u32; start[nv] as usize];
    for f in 0..s.triangles.len() {
        for v in corners(f) {
            faces[fill[v as usize] as usize] = f as u32;
            fill[v as usize] += 1;
        }
    }
    (start, faces)
}

/// Vertices whose incident faces form more than one edge-connected fan.
pub(crate) fn pinched_vertices(s: &Surface, st: &FaceStatus) -> Vec<PinchedVertex> {
    let nv = s.vertices.len();
    let (start, inc) = faces_by_vertex(s, |f| st.index_ok[f]);
    let mut out = Vec::new();
    let mut link: Vec<(u32, u32)> = Vec::new();
    let mut parent: Vec<u32> = Vec::new();
    for v in 0..nv {
        let faces = &inc[start[v] as usize..start[v + 1] as usize];
        let fans = count_fans(s, v as u32, faces, &mut link, &mut parent);
        if fans > 1 {
            out.push(PinchedVertex {
                vertex: vertex_ref(s, v as u32),
                fans,
            });
        }
    }
    out
}

/// Number of groups of `faces` (all incident to `v`) connected through edges at `v`.
fn count_fans(
    s: &Surface,
    v: u32,
    faces: &[u32],
    link: &mut Vec<(u32, u32)>,
    parent: &mut Vec<u32>,
) -> usize {
    if faces.len() < 2 {
        return faces.len();
    }
    link.clear();
    for (i, &f) in faces.iter().enumerate() {
        for &w in &s.triangles[f as usize] {
            if w != v {
                link.push((w, i as u32));
            }
        }
    }
    link.sort_unstable();
    parent.clear();
    parent.extend(0..faces.len() as u32);
    let mut groups = faces.len();
    for pair in link.windows(2) {
        if pair[0].0 == pair[1].0 {
            let a = find(parent, pair[0].1);
            let b = find(parent, pair[1].1);
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
                groups -= 1;
            }
        }
    }
    groups
}

/// Union-find root with path halving.
pub(crate) fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let g = parent[parent[x as usize] as usize];
        parent[x as usize] = g;
        x = g;
    }
    x
}
