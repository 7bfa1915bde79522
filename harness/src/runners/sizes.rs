//! The size field of the "sized" configurations: the same field for every peer, built
//! from the input surface as NOTES.md §3 says, h(P) = (shortest + longest surface edge
//! at P) / 2 at every input vertex ([`crate::metrics::vertex_sizes`]).
//!
//! Each peer takes it in the form it accepts: per input vertex (TetGen's `.mtr`), as
//! `x y z h` samples (CGAL: size of the nearest sample), or as a background mesh with
//! one value per vertex, interpolated linearly inside its tets (Gmsh's PostView field,
//! fTetWild's background mesh). The background mesh is the Delaunay tetrahedralisation
//! of the input vertices (`mesher::delaunay::triangulate`): the paper interpolates h in
//! the boundary mesh T(S,F), whose vertices are the same; before boundary recovery it
//! is this Delaunay mesh.

use super::RunError;
use mesher::Surface;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// h(P) per input vertex; a vertex on no edge gets the mean of the others.
pub fn input_sizes(surface: &Surface) -> Vec<f64> {
    let mut h = crate::metrics::vertex_sizes(surface);
    let finite: Vec<f64> = h.iter().copied().filter(|x| x.is_finite()).collect();
    let fill = mean(&finite);
    for x in h.iter_mut().filter(|x| !x.is_finite()) {
        *x = fill;
    }
    h
}

/// Arithmetic mean (0 for no value).
pub fn mean(values: &[f64]) -> f64 {
    if values.is_empty() {
        0.0
    } else {
        values.iter().sum::<f64>() / values.len() as f64
    }
}

/// A tet mesh carrying one size per vertex.
#[derive(Clone, Debug, Serialize)]
pub struct Background {
    /// Vertex coordinates.
    pub vertices: Vec<[f64; 3]>,
    /// Tets (0-based vertex indices).
    pub tets: Vec<[u32; 4]>,
    /// Size at each vertex.
    pub values: Vec<f64>,
}

/// The Delaunay tetrahedralisation of the input vertices with h(P) at each vertex.
pub fn background(surface: &Surface, sizes: &[f64]) -> Result<Background, RunError> {
    let opts = mesher::delaunay::DelaunayOptions::default();
    let tri = mesher::delaunay::triangulate(&surface.vertices, &opts)
        .map_err(|e| RunError::Io(format!("background mesh of the size field: {e}")))?;
    let mesh = tri.mesh.to_volume_mesh();
    let mut values = vec![f64::NAN; mesh.vertices.len()];
    for (i, v) in tri.vertex_of_input.iter().enumerate() {
        if let Some(slot) = values.get_mut(v.0 as usize) {
            *slot = sizes[i];
        }
    }
    let fill = mean(sizes);
    for x in values.iter_mut().filter(|x| !x.is_finite()) {
        *x = fill;
    }
    Ok(Background {
        vertices: mesh.vertices.iter().map(|p| p.to_array()).collect(),
        tets: mesh.tets,
        values,
    })
}

fn write(path: &Path, text: &str) -> Result<(), RunError> {
    std::fs::write(path, text).map_err(|e| RunError::Io(format!("{}: {e}", path.display())))
}

/// TetGen's `.mtr`: `<nodes> 1`, then one size per node, in node order.
pub fn write_mtr(path: &Path, sizes: &[f64]) -> Result<(), RunError> {
    let mut t = format!("{} 1\n", sizes.len());
    for h in sizes {
        let _ = writeln!(t, "{h:?}");
    }
    write(path, &t)
}

/// `x y z h` lines, one per input vertex (CGAL's size samples).
pub fn write_samples(path: &Path, surface: &Surface, sizes: &[f64]) -> Result<(), RunError> {
    let mut t = String::with_capacity(80 * sizes.len());
    for (p, h) in surface.vertices.iter().zip(sizes) {
        let _ = writeln!(t, "{:?} {:?} {:?} {h:?}", p.x, p.y, p.z);
    }
    write(path, &t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn background_carries_the_vertex_sizes() {
        let s = mesher::surface::generate::icosphere(1);
        let h = input_sizes(&s);
        assert!(h.iter().all(|x| x.is_finite() && *x > 0.0));
        let bg = background(&s, &h).unwrap();
        assert_eq!(bg.vertices.len(), s.vertices.len());
        assert!(!bg.tets.is_empty());
        for (p, v) in bg.vertices.iter().zip(&bg.values) {
            let i = s.vertices.iter().position(|q| q.to_array() == *p).unwrap();
            assert_eq!(*v, h[i]);
        }
    }
}
