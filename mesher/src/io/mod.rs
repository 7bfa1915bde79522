//! File formats: surface readers and volume-mesh writers and readers. All file IO of the
//! library lives here.

pub mod points;
