// CGAL's surface reconstruction as a peer in bench/compare.
//
//     cgal_reconstruct --version
//     cgal_reconstruct poisson IN.ply OUT.ply [--estimate-normals]
//     cgal_reconstruct advancing-front IN.ply OUT.ply
//
// poisson: CGAL::poisson_surface_reconstruction_delaunay with the parameters of CGAL's
// documentation example (poisson_reconstruction_example.cpp): spacing = average distance to the
// 6 nearest neighbours, sm_angle 20°, sm_radius 30 × spacing, sm_distance 0.375 × spacing.
// It needs oriented normals: an input without normals (or --estimate-normals) gets them as in
// CGAL's reconstruction tutorial, jet_estimate_normals and mst_orient_normals over 24
// neighbours, and the points whose normal could not be oriented are dropped.
//
// advancing-front: CGAL::advancing_front_surface_reconstruction with its default radius ratio
// bound (5) and beta (0.52 rad), as in CGAL's examples. It ignores normals and interpolates the
// points. The algorithm does not know inside from outside, so each connected component is
// flipped if most of its vertices' input normals disagree with it or, without normals, if its
// signed volume is negative.
//
// Parallel: average spacing and jet normal estimation use CGAL::Parallel_if_available_tag (TBB);
// the Poisson solve, the surface mesher, MST orientation and advancing front are sequential in
// CGAL 5.5. Progress and stage times go to stderr. Exit codes: 2 usage, 3 unreadable or empty
// input, 4 reconstruction failed, 5 output not writable.

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Point_set_3.h>
#include <CGAL/Point_set_3/IO.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/version.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/info.h>
#endif

#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using PointSet = CGAL::Point_set_3<Point, Vector>;
using Mesh = CGAL::Surface_mesh<Point>;

constexpr int kSpacingNeighbours = 6;  // CGAL's Poisson example
constexpr int kNormalNeighbours = 24;  // CGAL's reconstruction tutorial

// Seconds since `start`, for the stage log.
double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Number of worker threads CGAL's parallel algorithms may use (1 without TBB).
int thread_count() {
#ifdef CGAL_LINKED_WITH_TBB
  return tbb::info::default_concurrency();
#else
  return 1;
#endif
}

// Prints the usage to stderr and returns the usage exit code.
int usage() {
  std::fprintf(stderr,
               "usage: cgal_reconstruct --version\n"
               "       cgal_reconstruct poisson IN.ply OUT.ply [--estimate-normals]\n"
               "       cgal_reconstruct advancing-front IN.ply OUT.ply\n");
  return 2;
}

// Reads a point cloud (PLY, with or without nx/ny/nz); false with a message when unreadable or empty.
bool read_points(const std::string& path, PointSet& points) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "error: %s: cannot open\n", path.c_str());
    return false;
  }
  if (!CGAL::IO::read_PLY(in, points)) {
    std::fprintf(stderr, "error: %s: not a readable PLY point cloud\n", path.c_str());
    return false;
  }
  if (points.empty()) {
    std::fprintf(stderr, "error: %s: no points\n", path.c_str());
    return false;
  }
  return true;
}

// Writes the mesh as binary PLY; false with a message when it cannot.
bool write_mesh(const std::string& path, const Mesh& mesh) {
  std::ofstream out(path, std::ios::binary);
  if (!out || !CGAL::IO::write_PLY(out, mesh, CGAL::parameters::use_binary_mode(true)) || !out.flush()) {
    std::fprintf(stderr, "error: %s: cannot write\n", path.c_str());
    return false;
  }
  return true;
}

// Gives every point an oriented normal (jet fit + MST, CGAL's tutorial pipeline) and drops the
// points MST could not orient; returns the number dropped.
std::size_t estimate_normals(PointSet& points) {
  points.add_normal_map();
  CGAL::jet_estimate_normals<CGAL::Parallel_if_available_tag>(points, kNormalNeighbours);
  const auto unoriented = CGAL::mst_orient_normals(points, kNormalNeighbours);
  const std::size_t dropped = static_cast<std::size_t>(std::distance(unoriented, points.end()));
  points.remove(unoriented, points.end());
  points.collect_garbage();
  return dropped;
}

// Poisson reconstruction of `points` into `mesh` with CGAL's example parameters; false on failure.
bool run_poisson(PointSet& points, bool force_estimate, Mesh& mesh) {
  const auto t0 = std::chrono::steady_clock::now();
  if (force_estimate || !points.has_normal_map()) {
    const std::size_t dropped = estimate_normals(points);
    std::fprintf(stderr, "normals: estimated (jet + MST, %d neighbours), %zu unoriented points dropped, %.2f s\n",
                 kNormalNeighbours, dropped, seconds_since(t0));
    if (points.empty()) {
      std::fprintf(stderr, "error: no point has an oriented normal\n");
      return false;
    }
  } else {
    std::fprintf(stderr, "normals: from the input\n");
  }
  const auto t1 = std::chrono::steady_clock::now();
  const double spacing = CGAL::compute_average_spacing<CGAL::Parallel_if_available_tag>(points, kSpacingNeighbours);
  std::fprintf(stderr, "average spacing: %g (%.2f s)\n", spacing, seconds_since(t1));
  const auto t2 = std::chrono::steady_clock::now();
  const bool ok = CGAL::poisson_surface_reconstruction_delaunay(points.begin(), points.end(), points.point_map(),
                                                                points.normal_map(), mesh, spacing,
                                                                /*sm_angle=*/20.0, /*sm_radius=*/30.0,
                                                                /*sm_distance=*/0.375);
  std::fprintf(stderr, "poisson: %s, %zu faces (%.2f s)\n", ok ? "ok" : "failed",
               static_cast<std::size_t>(mesh.number_of_faces()), seconds_since(t2));
  return ok && mesh.number_of_faces() > 0;
}

// Orients each connected component (facets sharing a vertex) of the facets, which index the
// points of `points`: with input normals, so that most facets agree with their vertices' normals;
// without, so that the component's signed volume is positive (outward if it encloses a volume).
void orient_components(std::vector<std::array<std::size_t, 3>>& facets, const PointSet& points) {
  std::vector<std::size_t> parent(points.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto find = [&parent](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const auto& f : facets) {
    parent[find(f[1])] = find(f[0]);
    parent[find(f[2])] = find(f[0]);
  }
  const auto index = [&points](std::size_t i) { return *(points.begin() + static_cast<std::ptrdiff_t>(i)); };
  const bool normals = points.has_normal_map();
  std::vector<double> score(points.size(), 0.0);
  for (const auto& f : facets) {
    const Point& a = points.point(index(f[0]));
    const Point& b = points.point(index(f[1]));
    const Point& c = points.point(index(f[2]));
    const Vector cross = CGAL::cross_product(b - a, c - a);
    if (normals) {
      const Vector n = points.normal(index(f[0])) + points.normal(index(f[1])) + points.normal(index(f[2]));
      score[find(f[0])] += cross * n > 0 ? 1.0 : -1.0;
    } else {
      score[find(f[0])] += (a - CGAL::ORIGIN) * cross;  // 6 × the signed volume of the tetrahedron (0, a, b, c)
    }
  }
  std::size_t flipped = 0;
  for (auto& f : facets)
    if (score[find(f[0])] < 0) {
      std::swap(f[1], f[2]);
      ++flipped;
    }
  std::fprintf(stderr, "orientation: %zu of %zu facets flipped (%s)\n", flipped, facets.size(),
               normals ? "to follow the input normals" : "to give each component a positive volume");
}

// Advancing-front reconstruction of `points` into `mesh` with CGAL's defaults; false on failure.
bool run_advancing_front(const PointSet& points, Mesh& mesh) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::array<std::size_t, 3>> facets;
  CGAL::advancing_front_surface_reconstruction(points.points().begin(), points.points().end(),
                                               std::back_inserter(facets));
  std::fprintf(stderr, "advancing front: %zu facets (%.2f s)\n", facets.size(), seconds_since(t0));
  if (facets.empty()) return false;
  orient_components(facets, points);
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (!PMP::is_polygon_soup_a_polygon_mesh(facets)) {
    std::fprintf(stderr, "error: advancing front returned facets that do not form an oriented manifold\n");
    return false;
  }
  const std::vector<Point> vertices(points.points().begin(), points.points().end());
  PMP::polygon_soup_to_polygon_mesh(vertices, facets, mesh);
  return mesh.number_of_faces() > 0;
}

}  // namespace

// Parses the command line, reconstructs, writes the mesh; see the header comment for exit codes.
int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 1 && args[0] == "--version") {
    std::printf("cgal %s\n", CGAL_VERSION_STR);
    return 0;
  }
  if (args.size() < 3 || args.size() > 4) return usage();
  const std::string& method = args[0];
  bool force_estimate = false;
  if (args.size() == 4) {
    if (method != "poisson" || args[3] != "--estimate-normals") return usage();
    force_estimate = true;
  }
  if (method != "poisson" && method != "advancing-front") return usage();

  PointSet points;
  if (!read_points(args[1], points)) return 3;
  std::fprintf(stderr, "cgal %s, %zu points%s, %d thread(s) for the parallel stages\n", CGAL_VERSION_STR, points.size(),
               points.has_normal_map() ? " with normals" : "", thread_count());
  Mesh mesh;
  const bool ok = method == "poisson" ? run_poisson(points, force_estimate, mesh) : run_advancing_front(points, mesh);
  if (!ok) {
    std::fprintf(stderr, "error: %s reconstruction failed\n", method.c_str());
    return 4;
  }
  return write_mesh(args[2], mesh) ? 0 : 5;
}
