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
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Random.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/property_map.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Polyhedron = CGAL::Surface_mesh<K::Point_3>;
using Domain = CGAL::Polyhedral_mesh_domain_with_features_3<K, Polyhedron>;
// Sequential: results must not depend on thread scheduling.
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

// Nearest-sample search (CGAL's kd-tree) over (point, size) pairs.
using Sample = std::tuple<K::Point_3, double>;
using Search_base = CGAL::Search_traits_3<K>;
using Search_traits =
    CGAL::Search_traits_adapter<Sample, CGAL::Nth_of_tuple_property_map<0, Sample>, Search_base>;
using Nearest = CGAL::Orthogonal_k_neighbor_search<Search_traits>;

// A size field for Mesh_3's criteria: `factor` times the size of the nearest sample
// (the size at the nearest input vertex, as the harness measures normalised lengths).
class Nearest_size {
 public:
  Nearest_size(const Nearest::Tree* tree, double factor) : tree_(tree), factor_(factor) {}
  template <typename Index>
  K::FT operator()(const K::Point_3& p, int, const Index&) const {
    Nearest search(*tree_, p, 1);
    return factor_ * std::get<1>(search.begin()->first);
  }

 private:
  const Nearest::Tree* tree_;
  double factor_;
};

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
// Keep in sync with `RawOptions` in reference/src/mesh3.rs.
struct RefMesh3Options {
  double h;                // constant size (the mean input edge length)
  double radius_edge;      // cell radius-edge ratio bound
  const double* samples;   // sized configuration: n_samples x (x, y, z, size); else null
  uint64_t n_samples;
  uint32_t seed;
};

struct RefMesh3Result {
  uint64_t vertices;     // vertices of the complex (in the written file)
  uint64_t cells;        // tetrahedra in the complex
  uint64_t facets;       // boundary triangles in the complex
  double mesh_seconds;   // wall time of domain construction + make_mesh_3
};

namespace {
// Sizes: edge_size s, facet_size 0.7 s, facet_distance 0.05 s, cell_size s, where s is
// the constant h, or the size of the nearest sample when samples are given.
Criteria make_criteria(const RefMesh3Options& o, const Nearest::Tree* tree) {
  namespace params = CGAL::parameters;
  if (tree == nullptr) {
    const double h = o.h;
    return Criteria(params::edge_size = h, params::facet_angle = 25.0,
                    params::facet_size = 0.7 * h, params::facet_distance = 0.05 * h,
                    params::cell_radius_edge_ratio = o.radius_edge, params::cell_size = h);
  }
  return Criteria(params::edge_size = Nearest_size(tree, 1.0), params::facet_angle = 25.0,
                  params::facet_size = Nearest_size(tree, 0.7),
                  params::facet_distance = Nearest_size(tree, 0.05),
                  params::cell_radius_edge_ratio = o.radius_edge,
                  params::cell_size = Nearest_size(tree, 1.0));
}

// Checks the options; fills `samples` from them.
int32_t check_options(const RefMesh3Options& o, std::vector<Sample>& samples, char* err,
                      size_t err_len) {
  if (!(o.h > 0.0) || !(o.radius_edge > 0.0)) {
    set_error(err, err_len, "edge length and radius-edge bound must be positive");
    return kBadInput;
  }
  for (uint64_t i = 0; o.samples != nullptr && i < o.n_samples; ++i) {
    const double* q = o.samples + 4 * i;
    if (!(q[3] > 0.0)) {
      set_error(err, err_len, "size samples must be positive");
      return kBadInput;
    }
    samples.emplace_back(K::Point_3(q[0], q[1], q[2]), q[3]);
  }
  if (o.samples != nullptr && samples.empty()) {
    set_error(err, err_len, "sized configuration without size samples");
    return kBadInput;
  }
  return kOk;
}
}  // namespace

// Meshes the volume bounded by the OFF surface `in_off` with the sizes of `opts` and
// writes the complex as Medit to `out_mesh`.
// Returns 0 on success, else a status code with a message in `err`.
extern "C" int32_t ref_cgal_mesh3(const char* in_off, const char* out_mesh,
                                  const RefMesh3Options* opts, RefMesh3Result* out, char* err,
                                  size_t err_len) {
  try {
    std::vector<Sample> samples;
    if (int32_t rc = check_options(*opts, samples, err, err_len); rc != kOk) return rc;
    Polyhedron sm;
    if (int32_t rc = read_surface(in_off, sm, err, err_len); rc != kOk) return rc;
    Nearest::Tree tree(samples.begin(), samples.end());
    if (!samples.empty()) tree.build();

    // Determinism: Mesh_3 draws from the default generator (time-seeded otherwise)
    // and from the domain's generator for its initial points.
    CGAL::get_default_random() = CGAL::Random(opts->seed);
    CGAL::Random domain_rng(opts->seed);

    const auto t0 = std::chrono::steady_clock::now();
    Domain domain(sm, &domain_rng);
    domain.detect_features(60.0);
    Criteria criteria = make_criteria(*opts, samples.empty() ? nullptr : &tree);
    namespace params = CGAL::parameters;
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
