//! CGAL Mesh_3 driver (C++ in `cgal/mesh3.cpp`): meshes the volume bounded by a closed
//! OFF surface (one or several shells; nested shells bound hollow regions) and writes
//! the complex as a Medit `.mesh` file.
//!
//! Sizes come from one length `h`, the mean input edge length: edge_size `h`,
//! facet_size `0.7 h`, facet_distance `0.05 h`, cell_size `h`, facet_angle 25°,
//! cell radius-edge ratio 3, sharp features detected at 60°. The run is sequential and
//! seeded, so the same input, `h` and seed give the same mesh.

use std::ffi::{c_char, CString};
use std::path::Path;

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
        h: f64,
        seed: u32,
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

/// Meshes the volume bounded by the OFF surface `input` with sizes derived from
/// `edge_length` and writes the Medit mesh to `output`.
pub fn mesh_3(
    input: &Path,
    output: &Path,
    edge_length: f64,
    seed: u32,
) -> Result<Mesh3Result, Mesh3Error> {
    let (cin, cout) = (c_path(input)?, c_path(output)?);
    let mut raw = RawResult::default();
    let mut err = vec![0u8; 1024];
    // SAFETY: both paths are NUL-terminated and outlive the call; the C++ side writes
    // only into `raw` and at most `err.len()` bytes (NUL included) into `err`.
    let rc = unsafe {
        ref_cgal_mesh3(
            cin.as_ptr(),
            cout.as_ptr(),
            edge_length,
            seed,
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
        let err = mesh_3(&off, &dir.join("out.mesh"), 0.5, 0).unwrap_err();
        assert!(
            matches!(err, Mesh3Error::BadInput(ref m) if m.contains("not closed")),
            "{err}"
        );
        let err = mesh_3(&dir.join("missing.off"), &dir.join("out.mesh"), 0.5, 0).unwrap_err();
        assert!(matches!(err, Mesh3Error::BadInput(_)), "{err}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
