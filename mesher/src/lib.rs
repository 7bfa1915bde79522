//! `mesher`: tetrahedral mesh generation after P.J. Frey, H. Borouchaki and P.-L. George,
//! "3D Delaunay mesh generation coupled with an advancing-front approach", Comput.
//! Methods Appl. Mech. Engrg. 157 (1998) 115-131.
//!
//! Dependency order (never backwards): [`geom`] <- [`tetmesh`] <- [`delaunay`] <- mesher
//! stages <- CLI. [`surface`], [`io`] and [`quality`] sit beside the kernel: the kernel
//! never reads files and never computes quality.

// No panic in library code (issue 8): typed errors or infallible forms instead.
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

pub mod boundary;
pub mod delaunay;
pub mod front;
pub mod geom;
pub mod io;
pub mod limit;
pub mod mesh;
pub mod optimize;
pub mod quality;
pub mod sizing;
pub mod surface;
pub mod tetmesh;
pub mod volume;

pub use geom::Point;

/// Hash map and set with a fast hasher without a random seed (rustc's Fx hash), so that
/// no result can depend on a per-process seed.
pub(crate) type FastMap<K, V> = rustc_hash::FxHashMap<K, V>;
/// See [`FastMap`].
pub(crate) type FastSet<K> = rustc_hash::FxHashSet<K>;
pub use mesh::{mesh, MeshError, Meshed, Params, Report, SizeSpec};
pub use surface::Surface;
pub use volume::VolumeMesh;
