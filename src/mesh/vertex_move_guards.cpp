// Vertex moves undone where they fold the mesh (a triangle turned past 60 degrees) or push it
// through itself (a moved triangle that intersects another).

#include "mesh/vertex_move_guards.hpp"

#include <clustersurf/mesh/mesh_check.hpp>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace clustersurf::detail {

namespace {

/// A triangle the moves turn by more than 60 degrees has folded; its corners stay.
constexpr double kMaxTurnCos = 0.5;

}  // namespace

void undo_folds(TriangleMesh& mesh, const Points& before, std::vector<double>& moves) {
  const auto normal = [](const Points& x, const Eigen::RowVector3i& t) {
    return Eigen::Vector3d((x.row(t(1)) - x.row(t(0))).cross(x.row(t(2)) - x.row(t(0))).transpose());
  };
  std::vector<std::uint8_t> turned(static_cast<std::size_t>(mesh.triangles.rows()));
  for (;;) {
    // Each triangle tested in parallel; the corners of those turned put back after.
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh.triangles.rows(), 4096), [&](const auto& range) {
      for (Eigen::Index t = range.begin(); t != range.end(); ++t) {
        const Eigen::RowVector3i tri = mesh.triangles.row(t);
        turned[static_cast<std::size_t>(t)] = 0;
        if (moves[static_cast<std::size_t>(tri(0))] == 0 && moves[static_cast<std::size_t>(tri(1))] == 0 &&
            moves[static_cast<std::size_t>(tri(2))] == 0)
          continue;
        const Eigen::Vector3d was = normal(before, tri), is = normal(mesh.vertices, tri);
        turned[static_cast<std::size_t>(t)] = !(is.dot(was) > kMaxTurnCos * is.norm() * was.norm());
      }
    });
    bool any = false;
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
      if (turned[static_cast<std::size_t>(t)] == 0) continue;
      any = true;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Index v = mesh.triangles(t, k);
        mesh.vertices.row(v) = before.row(v);
        moves[static_cast<std::size_t>(v)] = 0;
      }
    }
    if (!any) return;
  }
}

void undo_crossings(TriangleMesh& mesh, const Points& before, std::vector<double>& moves, double least) {
  const auto nt = static_cast<std::size_t>(mesh.triangles.rows());
  const auto moved = [&](std::size_t t) {
    const auto tri = mesh.triangles.row(static_cast<Eigen::Index>(t));
    return moves[static_cast<std::size_t>(tri(0))] != 0 || moves[static_cast<std::size_t>(tri(1))] != 0 ||
           moves[static_cast<std::size_t>(tri(2))] != 0;
  };
  // First the triangles with a corner moved more than `least`, then those an undo changed that
  // still have a moved corner.
  std::vector<std::uint8_t> suspect(nt), undone(static_cast<std::size_t>(mesh.vertices.rows()), 0);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto tri = mesh.triangles.row(static_cast<Eigen::Index>(t));
    suspect[t] = std::abs(moves[static_cast<std::size_t>(tri(0))]) > least ||
                 std::abs(moves[static_cast<std::size_t>(tri(1))]) > least ||
                 std::abs(moves[static_cast<std::size_t>(tri(2))]) > least;
  }
  MeshCheckOptions all;
  all.max_pairs = std::numeric_limits<std::size_t>::max();
  for (;;) {
    const SelfIntersections found = find_self_intersections(mesh, suspect, all);
    std::fill(undone.begin(), undone.end(), 0);
    bool any = false;
    for (const auto& pair : found.pairs)
      for (const std::int32_t t : pair) {
        if (!moved(static_cast<std::size_t>(t))) continue;
        any = true;
        for (int k = 0; k < 3; ++k) {
          const Eigen::Index v = mesh.triangles(t, k);
          mesh.vertices.row(v) = before.row(v);
          moves[static_cast<std::size_t>(v)] = 0;
          undone[static_cast<std::size_t>(v)] = 1;
        }
      }
    if (!any) return;
    for (std::size_t t = 0; t < nt; ++t) {
      const auto tri = mesh.triangles.row(static_cast<Eigen::Index>(t));
      suspect[t] = (undone[static_cast<std::size_t>(tri(0))] != 0 || undone[static_cast<std::size_t>(tri(1))] != 0 ||
                    undone[static_cast<std::size_t>(tri(2))] != 0) &&
                   moved(t);
    }
  }
}

}  // namespace clustersurf::detail
