// Driver for CGAL's Mesh_3 on a polyhedral surface, called from Rust (reference/src/mesh3.rs).
// It only uses CGAL's public API: Surface_mesh, Polyhedral_mesh_domain_with_features_3,
// Mesh_criteria_3, make_mesh_3 (sequential), and the complex's output_to_medit.
//
// Kept in its own translation unit: compiling Mesh_3 takes minutes and gigabytes, so cargo
// must be able to cache it independently of the other drivers.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/make_mesh_3.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Polyhedron = CGAL::Surface_mesh<K::Point_3>;
using Domain = CGAL::Polyhedral_mesh_domain_with_features_3<K, Polyhedron>;
// Sequential: results must not depend on thread scheduling.
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

// Status codes; keep in sync with `Mesh3Error` in reference/src/mesh3.rs.
constexpr int32_t kOk = 0;
constexpr int32_t kBadInput = 1;   // unreadable OFF, not triangles, not closed, bad size
constexpr int32_t kCgalThrew = 2;  // CGAL raised an exception while meshing
constexpr int32_t kWriteFailed = 3;

void set_error(char* err, size_t err_len, const std::string& msg) {
  if (err == nullptr || err_len == 0) return;
  std::strncpy(err, msg.c_str(), err_len - 1);
  err[err_len - 1] = '\0';
}

// Reads `path` as a closed triangle surface (one or several shells).
int32_t read_surface(const char* path, Polyhedron& sm, char* err, size_t err_len) {
  std::ifstream in(path);
  if (!in || !CGAL::IO::read_OFF(in, sm) || sm.number_of_faces() == 0) {
    set_error(err, err_len, std::string("cannot read OFF surface ") + path);
    return kBadInput;
  }
  if (!CGAL::is_triangle_mesh(sm)) {
    set_error(err, err_len, "input has non-triangular faces");
    return kBadInput;
  }
  if (!CGAL::is_closed(sm)) {
    set_error(err, err_len, "input surface is not closed (Mesh_3 needs a closed polyhedron)");
    return kBadInput;
  }
  return kOk;
}
}  // namespace

// Keep in sync with `RawResult` in reference/src/mesh3.rs.
struct RefMesh3Result {
  uint64_t vertices;     // vertices of the complex (in the written file)
  uint64_t cells;        // tetrahedra in the complex
  uint64_t facets;       // boundary triangles in the complex
  double mesh_seconds;   // wall time of domain construction + make_mesh_3
};

// Meshes the volume bounded by the OFF surface `in_off` with sizes derived from `h`
// (the mean input edge length) and writes the complex as Medit to `out_mesh`.
// Returns 0 on success, else a status code with a message in `err`.
extern "C" int32_t ref_cgal_mesh3(const char* in_off, const char* out_mesh, double h,
                                  uint32_t seed, RefMesh3Result* out, char* err,
                                  size_t err_len) {
  try {
    if (!(h > 0.0)) {
      set_error(err, err_len, "edge length must be positive");
      return kBadInput;
    }
    Polyhedron sm;
    if (int32_t rc = read_surface(in_off, sm, err, err_len); rc != kOk) return rc;

    // Determinism: Mesh_3 draws from the default generator (time-seeded otherwise)
    // and from the domain's generator for its initial points.
    CGAL::get_default_random() = CGAL::Random(seed);
    CGAL::Random domain_rng(seed);

    const auto t0 = std::chrono::steady_clock::now();
    Domain domain(sm, &domain_rng);
    domain.detect_features(60.0);
    namespace params = CGAL::parameters;
    Criteria criteria(params::edge_size = h, params::facet_angle = 25.0,
                      params::facet_size = 0.7 * h, params::facet_distance = 0.05 * h,
                      params::cell_radius_edge_ratio = 3.0, params::cell_size = h);
    // make_mesh_3 bounds sliver perturbation and exudation by the refinement's wall
    // time unless told otherwise, which makes the output depend on machine load:
    // time limit 0 means "no limit" (both stop when they can no longer improve).
    C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria,
                                        params::perturb(params::time_limit = 0.0),
                                        params::exude(params::time_limit = 0.0));
    const auto t1 = std::chrono::steady_clock::now();

    std::ofstream os(out_mesh);
    if (!os) {
      set_error(err, err_len, std::string("cannot create ") + out_mesh);
      return kWriteFailed;
    }
    os.precision(17);
    c3t3.output_to_medit(os);
    os.close();
    if (!os) {
      set_error(err, err_len, std::string("failed writing ") + out_mesh);
      return kWriteFailed;
    }

    out->vertices = static_cast<uint64_t>(c3t3.triangulation().number_of_vertices());
    out->cells = static_cast<uint64_t>(c3t3.number_of_cells_in_complex());
    out->facets = static_cast<uint64_t>(c3t3.number_of_facets_in_complex());
    out->mesh_seconds = std::chrono::duration<double>(t1 - t0).count();
    return kOk;
  } catch (const std::exception& e) {
    set_error(err, err_len, std::string("CGAL threw: ") + e.what());
    return kCgalThrew;
  } catch (...) {
    set_error(err, err_len, "CGAL threw an unknown exception");
    return kCgalThrew;
  }
}
