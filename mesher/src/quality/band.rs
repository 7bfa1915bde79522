//! The share of interior edges whose normalised length (paper §5.3.2, NOTES.md §4) lies
//! in the band `[0.6, 1.67]` that a mesh following its size map should fill (the
//! paper's L2 histograms, Figs. 13-15, concentrate there; issue 5 asks 90 %).
//!
//! Interior edges are the tet edges not on the mesh's boundary (a face used by one tet):
//! the surface edges are the input's, the same for every mesher, and say nothing of how
//! the volume was filled.

use crate::geom::Point;
use crate::quality::histogram::nonfinite;
use crate::quality::length::normalized_length;
use crate::quality::summary::{unique_tet_edges, unique_triangle_edges};
use crate::volume::VolumeMesh;
use serde::{Deserialize, Serialize};

/// Lower end of the band (normalised length).
pub const BAND_LOW: f64 = 0.6;
/// Upper end of the band.
pub const BAND_HIGH: f64 = 1.67;

/// Normalised lengths of the interior edges of a mesh, end-point form.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EdgeBand {
    /// Interior edges.
    pub edges: usize,
    /// Percentage with `0.6 <= l <= 1.67`.
    #[serde(with = "nonfinite")]
    pub in_band_percent: f64,
    /// Percentage below the band (too short).
    #[serde(with = "nonfinite")]
    pub below_percent: f64,
    /// Percentage above the band (too long).
    #[serde(with = "nonfinite")]
    pub above_percent: f64,
    /// Mean normalised length.
    #[serde(with = "nonfinite")]
    pub mean: f64,
}

/// The band of `edges` (pairs of indices into `vertices` and `sizes`). Lengths that are
/// not a number (a size that is not positive and finite) count above the band.
///
/// # Panics
/// If an edge index is out of range of `vertices` or `sizes`.
pub fn edge_band(vertices: &[Point], edges: &[[u32; 2]], sizes: &[f64]) -> EdgeBand {
    let (mut inside, mut below, mut sum) = (0usize, 0usize, 0.0);
    for &[a, b] in edges {
        let (a, b) = (a as usize, b as usize);
        let l = normalized_length(vertices[a].distance(vertices[b]), sizes[a], sizes[b]);
        sum += l;
        if (BAND_LOW..=BAND_HIGH).contains(&l) {
            inside += 1;
        } else if l < BAND_LOW {
            below += 1;
        }
    }
    let n = edges.len();
    let pct = |k: usize| {
        if n == 0 {
            f64::NAN
        } else {
            100.0 * k as f64 / n as f64
        }
    };
    EdgeBand {
        edges: n,
        in_band_percent: pct(inside),
        below_percent: pct(below),
        above_percent: pct(n - inside - below),
        mean: if n == 0 { f64::NAN } else { sum / n as f64 },
    }
}

impl EdgeBand {
    /// The edges of `vm`'s tets that are not on its triangles, with `sizes` at its
    /// vertices.
    pub fn of(vm: &VolumeMesh, sizes: &[f64]) -> EdgeBand {
        edge_band(
            &vm.vertices,
            &edges_off_surface(unique_tet_edges(&vm.tets), &vm.triangles),
            sizes,
        )
    }
}

/// The edges of `edges` (sorted unique pairs, as [`unique_tet_edges`] gives them) that
/// are not an edge of `surface`.
pub fn edges_off_surface(mut edges: Vec<[u32; 2]>, surface: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let on = unique_triangle_edges(surface);
    edges.retain(|e| on.binary_search(e).is_err());
    edges
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three tets around the edge (0, 1), bounded by their six other faces: that edge
    /// is the one off the surface.
    #[test]
    fn edges_off_the_surface_of_a_ring() {
        let tets = [[0, 1, 2, 3], [0, 1, 3, 4], [0, 1, 4, 2]];
        let surface = [
            [1, 2, 3],
            [0, 3, 2],
            [1, 3, 4],
            [0, 4, 3],
            [1, 4, 2],
            [0, 2, 4],
        ];
        assert_eq!(
            edges_off_surface(unique_tet_edges(&tets), &surface),
            vec![[0, 1]]
        );
    }

    #[test]
    fn band_counts_each_side() {
        let v = [
            Point::ZERO,
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.5, 0.0, 0.0),
            Point::new(2.0, 0.0, 0.0),
        ];
        let sizes = [1.0; 4];
        // Lengths 1 (in), 0.5 (below), 2 (above).
        let band = edge_band(&v, &[[0, 1], [0, 2], [0, 3]], &sizes);
        assert_eq!(band.edges, 3);
        let third = 100.0 / 3.0;
        assert!((band.in_band_percent - third).abs() < 1e-12);
        assert!((band.below_percent - third).abs() < 1e-12);
        assert!((band.above_percent - third).abs() < 1e-12);
        assert!((band.mean - 3.5 / 3.0).abs() < 1e-12);
        let empty = edge_band(&v, &[], &sizes);
        assert_eq!(empty.edges, 0);
        assert!(empty.in_band_percent.is_nan());
        // A record of a mesh without interior edges reads back (JSON has no NaN).
        let back: EdgeBand = serde_json::from_str(&serde_json::to_string(&empty).unwrap()).unwrap();
        assert_eq!(back.edges, 0);
        assert!(back.in_band_percent.is_nan() && back.mean.is_nan());
    }
}
