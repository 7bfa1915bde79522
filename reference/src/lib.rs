//! Drivers of external meshers (CGAL programs compiled by `cc`, command lines of TetGen).
//!
//! - [`node`]: reader and writer of TetGen `.node` point files.
//! - [`rng`]: a small deterministic generator for reproducible point sets.
//! - `cgal` (only when CGAL's headers were found at build time): the
//!   `Delaunay_triangulation_3` driver.
//! - `mesh3` (likewise): the Mesh_3 driver behind the `cgal-mesh3` binary.

#[cfg(has_cgal)]
pub mod cgal;
#[cfg(has_cgal)]
pub mod mesh3;
pub mod node;
pub mod rng;
