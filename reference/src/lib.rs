//! Drivers of external meshers (CGAL programs compiled by `cc`, command lines of TetGen).
//!
//! - [`node`]: reader and writer of TetGen `.node` point files.
//! - [`rng`]: a small deterministic generator for reproducible point sets.
//! - `cgal` (only when CGAL's headers were found at build time): the
//!   `Delaunay_triangulation_3` driver.

#[cfg(has_cgal)]
pub mod cgal;
pub mod node;
pub mod rng;
