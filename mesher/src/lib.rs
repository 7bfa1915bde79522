//! `mesher`: tetrahedral mesh generation after P.J. Frey, H. Borouchaki and P.-L. George,
//! "3D Delaunay mesh generation coupled with an advancing-front approach", Comput.
//! Methods Appl. Mech. Engrg. 157 (1998) 115-131.
//!
//! Dependency order (never backwards): [`geom`] <- [`tetmesh`] <- [`delaunay`] <- mesher
//! stages <- CLI. [`surface`], [`io`] and [`quality`] sit beside the kernel: the kernel
//! never reads files and never computes quality.

pub mod boundary;
pub mod delaunay;
pub mod front;
pub mod geom;
pub mod io;
pub mod mesh;
pub mod quality;
pub mod sizing;
pub mod surface;
pub mod tetmesh;
pub mod volume;

pub use geom::Point;
pub use mesh::{mesh, MeshError, Meshed, Params, Report, SizeSpec};
pub use surface::Surface;
pub use volume::VolumeMesh;
