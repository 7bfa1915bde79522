//! CGAL Mesh_3 driver (C++ in `cgal/mesh3.cpp`): meshes the volume bounded by a closed
//! OFF surface (one or several shells; nested shells bound hollow regions) and writes
//! the complex as a Medit `.mesh` file.
//!
//! Sizes come from one length s: edge_size `s`, facet_size `0.7 s`, facet_distance
//! `0.05 s`, cell_size `s`, facet_angle 25°, the cell radius-edge bound of
//! [`Mesh3Options`], sharp features detected at 60°. In the default configuration s is
//! one constant `h` (the mean input edge length); in the sized one s is a field: the size
//! of the nearest of the given samples (CGAL's kd-tree), so that CGAL follows the same
//! size field as the other peers. The run is sequential and seeded, so the same input,
//! options and seed give the same mesh.

use std::ffi::{c_char, CString};
use std::path::Path;

/// Mirrors `RefMesh3Options` in `cgal/mesh3.cpp`.
#[repr(C)]
struct RawOptions {
    h: f64,
    radius_edge: f64,
    samples: *const f64,
    n_samples: u64,
    seed: u32,
}

/// How Mesh_3 is asked to mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh3Options {
    /// Constant size h (the mean input edge length); used when `samples` is empty.
    pub edge_length: f64,
    /// Bound on the cell radius-edge ratio (`cell_radius_edge_ratio`).
    pub radius_edge: f64,
    /// Size samples `[x, y, z, size]`: when not empty, every size criterion is a field
    /// whose value at p comes from the nearest sample (the sized configuration).
    pub samples: Vec<[f64; 4]>,
    /// Seed of CGAL's random generators.
    pub seed: u32,
}

/// Mirrors `RefMesh3Result` in `cgal/mesh3.cpp`.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy)]
struct RawResult {
    vertices: u64,
    cells: u64,
    facets: u64,
    mesh_seconds: f64,
}

extern "C" {
    fn ref_cgal_mesh3(
        in_off: *const c_char,
        out_mesh: *const c_char,
        opts: *const RawOptions,
        out: *mut RawResult,
        err: *mut c_char,
        err_len: usize,
    ) -> i32;
}

/// What CGAL reports after meshing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mesh3Result {
    /// Vertices of the underlying triangulation.
    pub vertices: u64,
    /// Tetrahedra in the complex (the ones written).
    pub cells: u64,
    /// Boundary triangles in the complex.
    pub facets: u64,
    /// Wall time of domain construction, feature detection and `make_mesh_3`, seconds.
    pub mesh_seconds: f64,
}

/// Why meshing failed; the status codes mirror `cgal/mesh3.cpp`.
#[derive(Debug, thiserror::Error)]
pub enum Mesh3Error {
    /// A path holds a NUL byte or is not UTF-8.
    #[error("unusable path {0}")]
    Path(String),
    /// Unreadable input, not a closed triangle surface, or a bad size.
    #[error("bad input: {0}")]
    BadInput(String),
    /// CGAL threw while meshing.
    #[error("{0}")]
    Cgal(String),
    /// The output could not be written.
    #[error("write failed: {0}")]
    Write(String),
}

fn c_path(p: &Path) -> Result<CString, Mesh3Error> {
    let s = p
        .to_str()
        .ok_or_else(|| Mesh3Error::Path(p.display().to_string()))?;
    CString::new(s).map_err(|_| Mesh3Error::Path(s.to_owned()))
}

/// Meshes the volume bounded by the OFF surface `input` with the sizes of `options` and
/// writes the Medit mesh to `output`.
pub fn mesh_3(
    input: &Path,
    output: &Path,
    options: &Mesh3Options,
) -> Result<Mesh3Result, Mesh3Error> {
    let (cin, cout) = (c_path(input)?, c_path(output)?);
    let flat: Vec<f64> = options.samples.iter().flatten().copied().collect();
    let opts = RawOptions {
        h: options.edge_length,
        radius_edge: options.radius_edge,
        samples: if flat.is_empty() {
            std::ptr::null()
        } else {
            flat.as_ptr()
        },
        n_samples: options.samples.len() as u64,
        seed: options.seed,
    };
    let mut raw = RawResult::default();
    let mut err = vec![0u8; 1024];
    // SAFETY: both paths are NUL-terminated and, like `opts` and the `flat` samples it
    // points to (4 * n_samples doubles), outlive the call; the C++ side writes only into
    // `raw` and at most `err.len()` bytes (NUL included) into `err`.
    let rc = unsafe {
        ref_cgal_mesh3(
            cin.as_ptr(),
            cout.as_ptr(),
            &opts,
            &mut raw,
            err.as_mut_ptr().cast(),
            err.len(),
        )
    };
    let end = err.iter().position(|&b| b == 0).unwrap_or(err.len());
    let msg = String::from_utf8_lossy(&err[..end]).into_owned();
    match rc {
        0 => Ok(Mesh3Result {
            vertices: raw.vertices,
            cells: raw.cells,
            facets: raw.facets,
            mesh_seconds: raw.mesh_seconds,
        }),
        1 => Err(Mesh3Error::BadInput(msg)),
        3 => Err(Mesh3Error::Write(msg)),
        _ => Err(Mesh3Error::Cgal(msg)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_surface_is_rejected_with_a_message() {
        let dir = std::env::temp_dir().join(format!("ref-mesh3-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let off = dir.join("tri.off");
        std::fs::write(&off, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        let opts = Mesh3Options {
            edge_length: 0.5,
            radius_edge: 2.0,
            samples: Vec::new(),
            seed: 0,
        };
        let err = mesh_3(&off, &dir.join("out.mesh"), &opts).unwrap_err();
        assert!(
            matches!(err, Mesh3Error::BadInput(ref m) if m.contains("not closed")),
            "{err}"
        );
        let err = mesh_3(&dir.join("missing.off"), &dir.join("out.mesh"), &opts).unwrap_err();
        assert!(matches!(err, Mesh3Error::BadInput(_)), "{err}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
