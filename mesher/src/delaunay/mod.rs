//! The Delaunay kernel (paper §3).
