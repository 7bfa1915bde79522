// Driver for CGAL's 3D Delaunay triangulation, called from Rust (reference/src/cgal.rs).
// It only uses CGAL's public API: EPICK kernel, Delaunay_triangulation_3, range insertion.
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <vector>

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Dt3 = CGAL::Delaunay_triangulation_3<K>;
using Point = K::Point_3;
}  // namespace

// Keep in sync with `Dt3Result` in reference/src/cgal.rs.
struct RefDt3Result {
  uint64_t vertices;
  uint64_t finite_tets;
  double insert_seconds;
  int32_t is_valid;  // -1: not checked, 0: invalid, 1: valid
};

// Triangulates n points given as xyz[3*i .. 3*i+3].
// Returns 0 on success, 1 if CGAL threw (out is then left partly filled).
extern "C" int32_t ref_cgal_dt3(const double* xyz, size_t n, int32_t validate, RefDt3Result* out) {
  try {
    std::vector<Point> pts;
    pts.reserve(n);
    for (size_t i = 0; i < n; ++i) pts.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);

    Dt3 t;
    const auto t0 = std::chrono::steady_clock::now();
    // Range insertion: CGAL spatially sorts the points (Hilbert order) before inserting.
    t.insert(pts.begin(), pts.end());
    const auto t1 = std::chrono::steady_clock::now();

    out->insert_seconds = std::chrono::duration<double>(t1 - t0).count();
    out->vertices = static_cast<uint64_t>(t.number_of_vertices());
    out->finite_tets = static_cast<uint64_t>(t.number_of_finite_cells());
    out->is_valid = validate ? (t.is_valid() ? 1 : 0) : -1;
    return 0;
  } catch (const std::exception&) {
    return 1;
  } catch (...) {
    return 1;
  }
}
