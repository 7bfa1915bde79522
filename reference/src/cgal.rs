//! CGAL `Delaunay_triangulation_3` driver (C++ in `cgal/dt3.cpp`).

/// Mirrors `RefDt3Result` in `cgal/dt3.cpp`.
#[repr(C)]
#[derive(Debug, Default, Clone, Copy)]
struct RawResult {
    vertices: u64,
    finite_tets: u64,
    insert_seconds: f64,
    is_valid: i32,
}

extern "C" {
    fn ref_cgal_dt3(xyz: *const f64, n: usize, validate: i32, out: *mut RawResult) -> i32;
}

/// What CGAL reports after triangulating a point set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dt3Result {
    /// Vertices of the triangulation (duplicate points are merged).
    pub vertices: u64,
    /// Finite cells (tetrahedra).
    pub finite_tets: u64,
    /// Wall time of the range insertion (spatial sort included), seconds.
    pub insert_seconds: f64,
    /// `T.is_valid()`, when asked for.
    pub is_valid: Option<bool>,
}

/// Builds the Delaunay tetrahedralisation of `pts` with CGAL (EPICK kernel,
/// range insertion). Errors if CGAL throws.
pub fn delaunay_3(pts: &[[f64; 3]], validate: bool) -> anyhow::Result<Dt3Result> {
    let mut raw = RawResult::default();
    // SAFETY: `[[f64; 3]]` is contiguous, so `pts` is 3 * len f64s; the C++
    // side reads exactly that many and writes only into `raw`.
    let rc = unsafe {
        ref_cgal_dt3(
            pts.as_ptr().cast(),
            pts.len(),
            i32::from(validate),
            &mut raw,
        )
    };
    anyhow::ensure!(rc == 0, "CGAL threw an exception while triangulating");
    Ok(Dt3Result {
        vertices: raw.vertices,
        finite_tets: raw.finite_tets,
        insert_seconds: raw.insert_seconds,
        is_valid: match raw.is_valid {
            -1 => None,
            v => Some(v == 1),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_cube_corners_and_centre() {
        let mut pts = Vec::new();
        for i in 0..8 {
            pts.push([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
        }
        pts.push([0.5, 0.5, 0.5]);
        let r = delaunay_3(&pts, true).unwrap();
        assert_eq!(r.vertices, 9);
        // The centre sees each of the 6 square faces split into 2 triangles.
        assert_eq!(r.finite_tets, 12);
        assert_eq!(r.is_valid, Some(true));
    }

    #[test]
    fn random_points_give_a_valid_triangulation() {
        let pts = crate::rng::unit_cube_points(2000, 1);
        let r = delaunay_3(&pts, true).unwrap();
        assert_eq!(r.vertices, 2000);
        assert!(r.finite_tets > 6 * 2000 - 1000);
        assert_eq!(r.is_valid, Some(true));
        assert!(r.insert_seconds >= 0.0);
    }
}
