//! The control space of the paper (§5.3.1) and the normalised edge length (§5.3.2): what
//! size `h` the mesh should have at a point, and how long an edge is in that metric.
//!
//! - [`SizeField`]: `h` at a point, with a location hint that the caller keeps between
//!   nearby queries (a tet id of the field's own mesh), and the normalised length of an
//!   edge, by the end-point form or piecewise along the field's tets ([`LengthMode`]).
//! - [`ConstantSize`]: one `h` everywhere.
//! - [`Background`]: sizes at the vertices of a background tet mesh, interpolated
//!   linearly (barycentric coordinates) in the tet that contains the point, found by a
//!   bounded walk from the hint. Built either from the boundary mesh T(S,F) (the
//!   paper's control space: `h = (l_min + l_max) / 2` of the boundary edges at a
//!   surface vertex, the mean of the neighbours at the other vertices) or from a user
//!   mesh with one size per vertex (Medit `.mesh` + `.sol`, paper §7).
//!
//! The lengths themselves are computed by [`crate::quality::length`] only.

mod background;

pub use background::Background;

use crate::geom::Point;
use crate::quality::length::normalized_length;
use thiserror::Error;

/// How normalised edge lengths are computed (paper §5.3.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LengthMode {
    /// From the sizes at the two end points only: `d ln(h_b / h_a) / (h_b - h_a)`
    /// (`2d / (h_a + h_b)` for close sizes). Cheap; exact when `h` is linear along the
    /// edge.
    #[default]
    EndPoints,
    /// Summed over the pieces of the edge between its crossings with the faces of the
    /// field's background tets (the paper's exact form for a piecewise-linear field).
    Piecewise,
}

/// A size map: the wanted edge length `h` at any point of space.
pub trait SizeField: Send + Sync {
    /// `h` at `p` (positive and finite). `hint` is where a location walk may start; it
    /// is updated to where it ended, so that the next query nearby is cheap. Any value
    /// is accepted (an invalid hint restarts the walk from a default tet).
    fn size(&self, p: Point, hint: &mut u32) -> f64;

    /// Normalised length of the edge `ab` with end sizes `h_a`, `h_b`, summed over the
    /// pieces where `h` is linear. The default (a field linear everywhere, or constant)
    /// is the end-point form.
    fn length_piecewise(&self, a: Point, b: Point, h_a: f64, h_b: f64, hint: &mut u32) -> f64 {
        let _ = hint;
        normalized_length(a.distance(b), h_a, h_b)
    }
}

/// Normalised length of `ab` (end sizes `h_a`, `h_b`) in the given mode.
#[inline]
pub fn edge_length(
    field: &dyn SizeField,
    mode: LengthMode,
    a: Point,
    b: Point,
    h_a: f64,
    h_b: f64,
    hint: &mut u32,
) -> f64 {
    match mode {
        LengthMode::EndPoints => normalized_length(a.distance(b), h_a, h_b),
        LengthMode::Piecewise => field.length_piecewise(a, b, h_a, h_b, hint),
    }
}

/// The same size everywhere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantSize(pub f64);

impl SizeField for ConstantSize {
    fn size(&self, _p: Point, _hint: &mut u32) -> f64 {
        self.0
    }
}

/// Why a size field cannot be built.
#[derive(Debug, Error, PartialEq)]
pub enum SizingError {
    /// A size is not positive and finite.
    #[error("size {value} at vertex {vertex} is not positive and finite")]
    BadSize {
        /// The vertex.
        vertex: usize,
        /// Its size.
        value: f64,
    },
    /// Sizes and vertices do not match.
    #[error("{sizes} sizes for {vertices} vertices")]
    Count {
        /// Number of sizes.
        sizes: usize,
        /// Number of vertices.
        vertices: usize,
    },
    /// The background mesh is unusable (no tet, bad indices, non-manifold faces).
    #[error("background mesh: {0}")]
    Mesh(String),
    /// A gradation that is not positive and finite.
    #[error("gradation {0} is not positive and finite")]
    Gradation(f64),
}

/// Checks that a constant size is usable.
pub fn constant(h: f64) -> Result<ConstantSize, SizingError> {
    if h > 0.0 && h.is_finite() {
        Ok(ConstantSize(h))
    } else {
        Err(SizingError::BadSize {
            vertex: 0,
            value: h,
        })
    }
}

#[cfg(test)]
mod tests;
