//! The lookup of input triangles among the faces of a mesh
//! ([`super::Local::triangle_faces`]; boundary recovery, paper §4.2).

use crate::surface::sorted_ids;

/// Triangles grouped by their smallest vertex id (compressed rows), each entry the
/// two other ids in increasing order and the triangle's index: the lookup of
/// [`super::Local::triangle_faces`].
pub(super) struct TrianglesByMin {
    /// Row `v` is `entries[start[v]..start[v + 1]]`.
    start: Vec<u32>,
    entries: Vec<(u32, u32, u32)>,
}

impl TrianglesByMin {
    pub(super) fn new(tris: &[[u32; 3]], num_vertices: usize) -> Self {
        let n = tris
            .iter()
            .flatten()
            .map(|&v| v as usize + 1)
            .max()
            .unwrap_or(0)
            .max(num_vertices);
        let mut start = vec![0u32; n + 1];
        for t in tris {
            start[sorted_ids(*t)[0] as usize + 1] += 1;
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut entries = vec![(0, 0, 0); tris.len()];
        for (k, t) in tris.iter().enumerate() {
            let [p, q, r] = sorted_ids(*t);
            let e = &mut fill[p as usize];
            entries[*e as usize] = (q, r, k as u32);
            *e += 1;
        }
        TrianglesByMin { start, entries }
    }

    /// The index of triangle `f` (any order), the last one listed if it is there twice.
    pub(super) fn find(&self, f: [u32; 3]) -> Option<u32> {
        let [p, q, r] = sorted_ids(f);
        let row = self.start.get(p as usize..p as usize + 2)?;
        self.entries[row[0] as usize..row[1] as usize]
            .iter()
            .rev()
            .find(|e| e.0 == q && e.1 == r)
            .map(|e| e.2)
    }
}
