//! The comparison harness: a corpus of real boundary meshes, runners that drive the
//! mesher and its peers (TetGen, CGAL Mesh_3, fTetWild, Gmsh), metrics computed only
//! through `mesher::quality` from each output file, records, and reports.
//!
//! Measuring (`run`) is separate from reporting (`report`): reports read records only;
//! `compare` chains the two.

pub mod compare;
pub mod corpus;
pub mod gate;
pub mod merge;
pub mod metrics;
pub mod records;
pub mod report;
pub mod run;
pub mod runners;
pub mod shard;
